//! Polar-plot centres and the values about them (ISO 230-7 §3.7, §3.8), computed exactly.
//!
//! **What it models.** A profile `p[m]` (m) at angles `θ_m` (rad) is a polar plot of
//! displacement versus rotation angle. The plot's radius `r0` is only a drawing scale, so every
//! value is computed in the linearised ("limaçon") model: moving the centre by `c = (cx, cy)`
//! changes the radial deviation at `θ` by `−(cx cosθ + cy sinθ)`, the residual about `c` is
//!
//! ```text
//! ρ_c[m] = p[m] − cx·cosθ_m − cy·sinθ_m
//! ```
//!
//! and the value about `c` is `max ρ_c − min ρ_c`, the separation of the two concentric circles
//! about `c` that just enclose the plot. The five centres of ISO 230-7 are:
//!
//! | centre | offset `c` |
//! |---|---|
//! | PC  | `(0, 0)`, the sensor zero |
//! | LSC | least-squares fit of `a0 + cx cosθ + cy sinθ` to `p` (3×3 normal equations; `2/M Σ p cosθ`, `2/M Σ p sinθ` for equally spaced full-circle angles) |
//! | MRS | minimises `max ρ_c − min ρ_c`: the LP `min u − l` s.t. `l ≤ ρ_c[m] ≤ u` |
//! | MIC | maximises `min ρ_c` (largest inscribed circle): the LP `max l` s.t. `ρ_c[m] ≥ l` |
//! | MCC | minimises `max ρ_c` (smallest circumscribed circle): the LP `min u` s.t. `ρ_c[m] ≤ u` |
//!
//! **The solver.** MRS, MIC and MCC are linear programmes in 3–4 unknowns with one or two
//! constraints per point. They are solved exactly by a small primal simplex on their duals
//! (3–4 equality rows, one column per constraint), which is the classical exchange (Stiefel)
//! algorithm: the basis is the set of 3 (MIC, MCC) or 4 (MRS) contact points, each iteration
//! brings in the point that violates the current circles most (Dantzig's rule, switching to
//! Bland's rule after repeated non-improving steps so degenerate profiles cannot cycle) and the
//! ratio test keeps the multipliers non-negative. The basis is re-factorised from scratch each
//! step (a 3×3 or 4×4 elimination), pricing is one pass over the points without allocation.
//! At the end the solver checks its certificate: every point inside the circles to
//! 1e-13 × max|p| (primal feasibility) and non-negative multipliers that balance the objective
//! (dual feasibility), and it returns the contact points. A general LP crate was not used:
//! `microlp` would bring `sprs` and `ndarray` for a 4-variable problem.
//!
//! **Ties.** MRS has a unique value; with distinct angles its centre is unique as well (1, cos,
//! sin is a Haar system on the circle). The smallest circumscribed (or largest inscribed)
//! circle of a sampled plot can be reached by a whole segment of centres, e.g. a pure 2-UPR
//! ellipse sampled at its vertices, and the range about them differs. The MCC (MIC) centre is
//! therefore the lexicographic optimum: among the centres with the smallest maximum (largest
//! minimum), the one with the largest minimum (smallest maximum), i.e. the smallest value.
//! This happens only when the optimum is degenerate (a multiplier of the contacts vanishes:
//! two antipodal contacts); the second LP is then solved by the same simplex, with the first
//! optimum relaxed by the pricing tolerance. Otherwise the three contacts fix the centre.
//!
//! **Partial arcs.** LSC and MRS are well defined for any angles with at least 3 (LSC) or 4
//! (MRS) distinct directions, e.g. the arc of a swivel table, though their offsets grow
//! sensitive as the arc shrinks. MIC and MCC are bounded only when the directions surround the
//! centre: they need every gap between neighbouring angles below [`MAX_ANGLE_GAP`] (179°),
//! otherwise [`PolarError::NotSurrounded`].
//!
//! **Left out.** The exact geometric circle fits on the drawn plot (they tend to the limaçon
//! result as `r0` grows, with a deviation about offset²/r0); constrained fits for partial arcs;
//! which centre a test must use (ISO 230-7 Table 1) and which data the centre is taken from
//! (the synchronous plot, §3.7 Note 1): that is the caller's business, see
//! [`range_about`] to evaluate other data about a given centre.

use std::f64::consts::TAU;
use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::math::{RAD_PER_DEG, Real};

/// The largest gap (rad) between neighbouring angles for which MIC and MCC are computed: 179°.
///
/// With a gap of `π − δ` the directions surround the centre only by `sin(δ/2)`, and profile
/// noise reaches the offset amplified by about `1/sin(δ/2)`: 115 at this limit, unbounded at
/// 180°.
pub const MAX_ANGLE_GAP: Real = 179.0 * RAD_PER_DEG;

/// Pricing tolerance of the simplex, relative to the profile's scale `max |p|`: a point is
/// inside the circles if it is outside by at most this. Rounding of the residuals is about
/// 1e-16 of the scale, so this stops degenerate pivots on noise, and it bounds the error of a
/// value by 2e-13 of the scale.
const PRICING_TOL: Real = 1e-13;

/// Consecutive pivots without progress of the objective after which the simplex uses Bland's
/// rule (smallest index) to leave a degenerate vertex without cycling.
const STALL_LIMIT: usize = 8;

/// A multiplier of the MIC/MCC optimum (they sum to 1) at or below which the optimum is
/// treated as degenerate and the tie-break LP is solved.
const TIE_MULTIPLIER: Real = 1e-9;

/// A polar-plot centre of ISO 230-7 §3.7.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Centre {
    /// Polar chart centre: the sensor zero, offset `(0, 0)` (§3.7.2).
    #[serde(rename = "PC")]
    Pc,
    /// Least-squares circle centre (§3.7.4).
    #[serde(rename = "LSC")]
    Lsc,
    /// Minimum radial separation centre (§3.7.5).
    #[serde(rename = "MRS")]
    Mrs,
    /// Maximum inscribed circle centre (§3.7.6).
    #[serde(rename = "MIC")]
    Mic,
    /// Minimum circumscribed circle centre (§3.7.7).
    #[serde(rename = "MCC")]
    Mcc,
}

impl Centre {
    /// The five centres, in the order of ISO 230-7 §3.7.
    pub const ALL: [Centre; 5] = [
        Centre::Pc,
        Centre::Lsc,
        Centre::Mrs,
        Centre::Mic,
        Centre::Mcc,
    ];

    /// The abbreviation of ISO 230-7: "PC", "LSC", "MRS", "MIC" or "MCC".
    pub fn name(self) -> &'static str {
        match self {
            Centre::Pc => "PC",
            Centre::Lsc => "LSC",
            Centre::Mrs => "MRS",
            Centre::Mic => "MIC",
            Centre::Mcc => "MCC",
        }
    }
}

impl fmt::Display for Centre {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is none of PC, LSC, MRS, MIC, MCC.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown polar-plot centre \"{0}\" (expected PC, LSC, MRS, MIC or MCC)")]
pub struct UnknownCentre(pub String);

impl FromStr for Centre {
    type Err = UnknownCentre;

    /// The abbreviation, in any case ("lsc", "MRS", "Mcc").
    fn from_str(s: &str) -> Result<Centre, UnknownCentre> {
        Centre::ALL
            .into_iter()
            .find(|c| c.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| UnknownCentre(s.to_string()))
    }
}

/// A profile evaluated about one centre.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CentreFit {
    /// Which centre.
    pub centre: Centre,
    /// The centre's offset `(cx, cy)` from the polar chart centre (m), in the limaçon model.
    pub offset: [Real; 2],
    /// `min ρ_c` (m): the inner circle's radius minus `r0`.
    pub low: Real,
    /// `max ρ_c` (m): the outer circle's radius minus `r0`.
    pub high: Real,
    /// The points (indices, ascending) that fix the circles. PC, LSC: where the lowest and the
    /// highest residual are. MRS: the optimal basis, alternately on the outer and the inner
    /// circle. MCC (MIC): the outer (inner) contacts that certify the smallest maximum (largest
    /// minimum) and the points that fix the centre among equals. Each contact lies on the
    /// inner or the outer circle to within 2e-13 × max|p|.
    pub contacts: Vec<usize>,
}

impl CentreFit {
    /// The value about this centre, `high − low` (m): the difference in radii of the two
    /// concentric circles that just enclose the plot.
    pub fn value(&self) -> Real {
        self.high - self.low
    }
}

/// Why a profile cannot be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PolarError {
    /// Fewer than 3 points.
    #[error("a polar profile needs at least 3 points, got {0}")]
    TooFew(usize),
    /// The number of values is not the number of angles.
    #[error("{values} values do not match {angles} angles")]
    LengthMismatch {
        /// Number of values.
        values: usize,
        /// Number of angles.
        angles: usize,
    },
    /// A value, angle or offset is NaN or infinite.
    #[error("{what} {index} is not finite")]
    NonFinite {
        /// "value", "angle" or "offset".
        what: &'static str,
        /// Its index.
        index: usize,
    },
    /// Too few distinct directions for the centre (3 for LSC, 4 for MRS).
    #[error("the {centre} centre needs at least {needed} distinct angles")]
    TooFewDirections {
        /// The centre asked for.
        centre: Centre,
        /// Distinct directions it needs.
        needed: usize,
    },
    /// The angles do not surround the centre (a partial arc): the MIC or MCC is unbounded or
    /// ill-conditioned.
    #[error(
        "the angles leave a gap of {gap_deg:.1}° (more than {:.0}°): they do not surround the centre, so the {centre} centre is unbounded or ill-conditioned; use PC, LSC or MRS",
        MAX_ANGLE_GAP / RAD_PER_DEG
    )]
    NotSurrounded {
        /// The centre asked for.
        centre: Centre,
        /// The largest gap between neighbouring angles (degrees).
        gap_deg: Real,
    },
    /// The simplex could not certify its optimum (a numerical failure; should not happen).
    #[error("the {centre} solver could not certify its optimum: {reason}")]
    NotCertified {
        /// The centre asked for.
        centre: Centre,
        /// What failed.
        reason: &'static str,
    },
}

/// The angles of a profile, with their directions computed once so that many profiles
/// (revolutions, probes, inner and outer contours) can be evaluated at the same angles.
#[derive(Clone, Debug)]
pub struct Angles {
    /// `(cos θ, sin θ)` per angle.
    directions: Vec<[Real; 2]>,
    /// The largest gap between neighbouring directions (rad, in `(0, 2π]`).
    largest_gap: Real,
}

impl Angles {
    /// The directions of these angles (rad, any values, any order, repeats allowed).
    ///
    /// Errors: fewer than 3 angles, or one not finite.
    pub fn new(angles: &[Real]) -> Result<Angles, PolarError> {
        if angles.len() < 3 {
            return Err(PolarError::TooFew(angles.len()));
        }
        if let Some(index) = angles.iter().position(|a| !a.is_finite()) {
            return Err(PolarError::NonFinite {
                what: "angle",
                index,
            });
        }
        let directions = angles
            .iter()
            .map(|&a| {
                let (s, c) = a.sin_cos();
                [c, s]
            })
            .collect();
        Ok(Angles {
            directions,
            largest_gap: largest_gap(angles),
        })
    }

    /// `count` angles equally spaced over one revolution, `θ_m = 2π m / count`.
    pub fn equally_spaced(count: usize) -> Result<Angles, PolarError> {
        if count < 3 {
            return Err(PolarError::TooFew(count));
        }
        let directions = (0..count)
            .map(|m| {
                let (s, c) = (TAU * m as Real / count as Real).sin_cos();
                [c, s]
            })
            .collect();
        Ok(Angles {
            directions,
            largest_gap: TAU / count as Real,
        })
    }

    /// Number of angles.
    pub fn len(&self) -> usize {
        self.directions.len()
    }

    /// `[cos θ, sin θ]` of each angle, in the order given.
    pub fn directions(&self) -> &[[Real; 2]] {
        &self.directions
    }

    /// Never true (an `Angles` holds at least 3); here for the `len` convention.
    pub fn is_empty(&self) -> bool {
        self.directions.is_empty()
    }

    /// The largest gap between neighbouring angles around the circle (rad): `2π/M` for `M`
    /// equally spaced angles, `2π − arc` for a partial arc.
    pub fn largest_gap(&self) -> Real {
        self.largest_gap
    }

    /// Whether the angles surround the centre well enough for MIC and MCC
    /// (largest gap ≤ [`MAX_ANGLE_GAP`]).
    pub fn surround_centre(&self) -> bool {
        self.largest_gap <= MAX_ANGLE_GAP
    }

    /// The profile `p` (one value per angle, m) evaluated about a centre.
    ///
    /// Errors: length mismatch, a value not finite, too few distinct directions (LSC, MRS),
    /// angles that do not surround the centre (MIC, MCC), and — not expected — a simplex that
    /// cannot certify its optimum.
    pub fn fit(&self, profile: &[Real], centre: Centre) -> Result<CentreFit, PolarError> {
        self.check_values(profile)?;
        let dirs = &self.directions;
        let (offset, contacts) = match centre {
            Centre::Pc => ([0.0, 0.0], None),
            Centre::Lsc => (least_squares(dirs, profile)?, None),
            Centre::Mrs => {
                let (offset, contacts) = minimum_zone(dirs, profile)?;
                (offset, Some(contacts))
            }
            Centre::Mic | Centre::Mcc => {
                if !self.surround_centre() {
                    return Err(PolarError::NotSurrounded {
                        centre,
                        gap_deg: self.largest_gap / RAD_PER_DEG,
                    });
                }
                let sigma = if centre == Centre::Mcc { 1.0 } else { -1.0 };
                let (offset, contacts) = one_sided(dirs, profile, sigma, centre)?;
                (offset, Some(contacts))
            }
        };
        let (low, high, arg_low, arg_high) = extremes(dirs, profile, offset);
        let contacts = contacts.unwrap_or_else(|| {
            let mut c = vec![arg_low, arg_high];
            c.sort_unstable();
            c.dedup();
            c
        });
        Ok(CentreFit {
            centre,
            offset,
            low,
            high,
            contacts,
        })
    }

    /// `(min ρ_c, max ρ_c)` of other data about a given offset (m): e.g. all revolutions
    /// pooled, or the inner and outer contours, about the centre of the synchronous profile.
    ///
    /// Value `i` is at angle `i mod len()`, so `values` may hold several revolutions end to
    /// end, each at these angles (the last one may be partial). Never fails: a value or offset
    /// that is not finite, or no values at all, gives `(NaN, NaN)`.
    pub fn range_about(&self, values: &[Real], offset: [Real; 2]) -> (Real, Real) {
        if values.is_empty() || !offset.iter().chain(values).all(|v| v.is_finite()) {
            return (Real::NAN, Real::NAN);
        }
        let mut low = Real::INFINITY;
        let mut high = Real::NEG_INFINITY;
        for revolution in values.chunks(self.len()) {
            let (l, h) = range_of(&self.directions, revolution, offset);
            low = low.min(l);
            high = high.max(h);
        }
        (low, high)
    }

    /// One value per angle, each finite.
    fn check_values(&self, values: &[Real]) -> Result<(), PolarError> {
        if values.len() != self.len() {
            return Err(PolarError::LengthMismatch {
                values: values.len(),
                angles: self.len(),
            });
        }
        match values.iter().position(|v| !v.is_finite()) {
            Some(index) => Err(PolarError::NonFinite {
                what: "value",
                index,
            }),
            None => Ok(()),
        }
    }
}

/// The profile `p` at `angles` (rad) evaluated about a centre; see [`Angles::fit`].
///
/// Use [`Angles`] directly to evaluate many profiles at the same angles without recomputing
/// the directions.
pub fn fit(profile: &[Real], angles: &[Real], centre: Centre) -> Result<CentreFit, PolarError> {
    if profile.len() != angles.len() {
        return Err(PolarError::LengthMismatch {
            values: profile.len(),
            angles: angles.len(),
        });
    }
    Angles::new(angles)?.fit(profile, centre)
}

/// `(min ρ_c, max ρ_c)` of `values` about `offset` (m), value `i` at `angles[i mod len]` (so
/// `values` may hold several revolutions end to end). Never fails: no values or angles, or a
/// value, angle or offset that is not finite, give `(NaN, NaN)`.
///
/// This computes `cos θ` and `sin θ` of the angles at every call (about 15 ns per angle, the
/// bulk of the cost for one revolution); to evaluate many data sets at the same angles, build
/// an [`Angles`] once and use [`Angles::range_about`].
pub fn range_about(values: &[Real], angles: &[Real], offset: [Real; 2]) -> (Real, Real) {
    if values.is_empty()
        || angles.is_empty()
        || !offset
            .iter()
            .chain(values)
            .chain(angles)
            .all(|v| v.is_finite())
    {
        return (Real::NAN, Real::NAN);
    }
    // Each direction once (the angles actually used), then the revolutions over them.
    let directions: Vec<[Real; 2]> = angles
        .iter()
        .take(values.len())
        .map(|a| {
            let (s, c) = a.sin_cos();
            [c, s]
        })
        .collect();
    let (mut low, mut high) = (Real::INFINITY, Real::NEG_INFINITY);
    for revolution in values.chunks(directions.len()) {
        let (l, h) = range_of(&directions, revolution, offset);
        low = low.min(l);
        high = high.max(h);
    }
    (low, high)
}

/// `(min ρ, max ρ, argmin, argmax)` of `p` about `offset` (the first index of each on ties).
fn extremes(dirs: &[[Real; 2]], p: &[Real], offset: [Real; 2]) -> (Real, Real, usize, usize) {
    let [cx, cy] = offset;
    // Two passes of one key each run faster than one pass keeping both.
    let (arg_high, high) = first_max(dirs, p, |[c, s], v| v - cx * c - cy * s);
    let (arg_low, minus_low) = first_max(dirs, p, |[c, s], v| -(v - cx * c - cy * s));
    (-minus_low, high, arg_low, arg_high)
}

/// `(min ρ, max ρ)` of `p` about `offset`: [`extremes`] without the indices, in lanes of
/// `min` and `max` that the compiler turns into vector instructions.
fn range_of(dirs: &[[Real; 2]], p: &[Real], offset: [Real; 2]) -> (Real, Real) {
    let [cx, cy] = offset;
    let mut low = [Real::INFINITY; LANES];
    let mut high = [Real::NEG_INFINITY; LANES];
    let rho = |[c, s]: [Real; 2], v: Real| v - cx * c - cy * s;
    let len = dirs.len().min(p.len());
    let whole = len - len % LANES;
    let chunks = dirs[..whole]
        .chunks_exact(LANES)
        .zip(p[..whole].chunks_exact(LANES));
    for (d, v) in chunks {
        for lane in 0..LANES {
            let r = rho(d[lane], v[lane]);
            low[lane] = low[lane].min(r);
            high[lane] = high[lane].max(r);
        }
    }
    for m in whole..len {
        let r = rho(dirs[m], p[m]);
        low[0] = low[0].min(r);
        high[0] = high[0].max(r);
    }
    let low = low.into_iter().fold(Real::INFINITY, Real::min);
    let high = high.into_iter().fold(Real::NEG_INFINITY, Real::max);
    (low, high)
}

/// Interleaved lanes of [`first_max`] and [`range_of`]: independent running extremes that the
/// processor overlaps, instead of one chain of compare-and-select through every point.
const LANES: usize = 4;

/// The largest `key(direction, value)` over the points and its first index (the one a plain
/// scan with a strict `>` keeps); `(0, −∞)` for no points. The pricing of the simplex and the
/// extremes of every centre fit go through here, so it is written for speed: the points are
/// scanned in [`LANES`] interleaved lanes, each keeping the first index of its own largest
/// key, and the lanes are merged at the end (largest key, then smallest index): the same index
/// and key as the plain scan.
#[inline(always)]
fn first_max(
    dirs: &[[Real; 2]],
    p: &[Real],
    key: impl Fn([Real; 2], Real) -> Real,
) -> (usize, Real) {
    let len = dirs.len().min(p.len());
    let whole = len - len % LANES;
    let mut best = [Real::NEG_INFINITY; LANES];
    let mut at = [0usize; LANES];
    let chunks = dirs[..whole]
        .chunks_exact(LANES)
        .zip(p[..whole].chunks_exact(LANES));
    for (chunk, (d, v)) in chunks.enumerate() {
        for lane in 0..LANES {
            let k = key(d[lane], v[lane]);
            if k > best[lane] {
                best[lane] = k;
                at[lane] = chunk * LANES + lane;
            }
        }
    }
    for m in whole..len {
        let k = key(dirs[m], p[m]);
        let lane = m - whole;
        if k > best[lane] {
            best[lane] = k;
            at[lane] = m;
        }
    }
    let mut pick = 0;
    for lane in 1..LANES {
        if best[lane] > best[pick] || (best[lane] == best[pick] && at[lane] < at[pick]) {
            pick = lane;
        }
    }
    (at[pick], best[pick])
}

/// The largest gap between neighbouring angles around the circle, in O(M) by buckets: with `M`
/// buckets of width `2π/M`, a gap inside a bucket is shorter than the mean gap, so the largest
/// gap lies between the highest angle of one occupied bucket and the lowest of the next.
fn largest_gap(angles: &[Real]) -> Real {
    let n = angles.len();
    let per_radian = n as Real / TAU;
    let mut buckets = vec![[Real::INFINITY, Real::NEG_INFINITY]; n]; // [lowest, highest]
    for &a in angles {
        // a mod 2π in [0, 2π), without the cost of fmod.
        let mut phi = a - TAU * (a / TAU).floor();
        if phi < 0.0 {
            phi += TAU;
        }
        if phi >= TAU {
            phi -= TAU;
        }
        let bucket = &mut buckets[((phi * per_radian) as usize).min(n - 1)];
        if phi < bucket[0] {
            bucket[0] = phi;
        }
        if phi > bucket[1] {
            bucket[1] = phi;
        }
    }
    let mut first_low = None;
    let mut previous_high: Real = 0.0;
    let mut gap: Real = 0.0;
    for &[low, high] in &buckets {
        if low > high {
            continue; // empty bucket
        }
        match first_low {
            None => first_low = Some(low),
            Some(_) => gap = gap.max(low - previous_high),
        }
        previous_high = high;
    }
    let first = first_low.unwrap_or(0.0);
    gap.max(first + TAU - previous_high)
}

/// The LSC offset: least squares of `a0 + cx cosθ + cy sinθ` on `p`, from the normal
/// equations of the centred regressors (for equally spaced full-circle angles the cross terms
/// vanish and this is `2/M Σ p cosθ`, `2/M Σ p sinθ`).
fn least_squares(dirs: &[[Real; 2]], p: &[Real]) -> Result<[Real; 2], PolarError> {
    let n = dirs.len() as Real;
    let (mut mc, mut ms, mut mp) = (0.0, 0.0, 0.0);
    for (&[c, s], &v) in dirs.iter().zip(p) {
        mc += c;
        ms += s;
        mp += v;
    }
    (mc, ms, mp) = (mc / n, ms / n, mp / n);
    let (mut scc, mut sss, mut scs, mut scp, mut ssp) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (&[c, s], &v) in dirs.iter().zip(p) {
        let (c, s, v) = (c - mc, s - ms, v - mp);
        scc += c * c;
        sss += s * s;
        scs += c * s;
        scp += c * v;
        ssp += s * v;
    }
    let det = scc * sss - scs * scs;
    // Fewer than 3 distinct directions make cos and sin affinely dependent (det = 0).
    if det.is_nan() || det <= 1e-12 * (scc + sss) * (scc + sss) {
        return Err(PolarError::TooFewDirections {
            centre: Centre::Lsc,
            needed: 3,
        });
    }
    Ok([(sss * scp - scs * ssp) / det, (scc * ssp - scs * scp) / det])
}

/// The profile's scale for the tolerances: `max |p|`.
fn scale_of(p: &[Real]) -> Real {
    p.iter().fold(0.0, |m: Real, v| m.max(v.abs()))
}

/// The MRS offset and contacts: the Chebyshev fit `min_{a0,c} max_m |ρ_c[m] − a0|` (the MRS
/// value is twice its optimum), an LP in `y = (t, a0, cx, cy)`.
fn minimum_zone(dirs: &[[Real; 2]], p: &[Real]) -> Result<([Real; 2], Vec<usize>), PolarError> {
    const CENTRE: Centre = Centre::Mrs;
    // Four well-spread directions (farthest-point sampling).
    let mut chosen = [0usize; 4];
    let mut nearest = vec![Real::INFINITY; dirs.len()];
    for slot in 1..4 {
        let last = dirs[chosen[slot - 1]];
        let (mut best, mut best_d) = (0, -1.0);
        for (m, (d, near)) in dirs.iter().zip(nearest.iter_mut()).enumerate() {
            let chord2 = (d[0] - last[0]).powi(2) + (d[1] - last[1]).powi(2);
            *near = near.min(chord2);
            if *near > best_d {
                (best, best_d) = (m, *near);
            }
        }
        // A chord below 1e-6 (1e-6 rad) is the same direction.
        if best_d < 1e-12 {
            return Err(PolarError::TooFewDirections {
                centre: CENTRE,
                needed: 4,
            });
        }
        chosen[slot] = best;
    }
    // The null vector μ of the 3×4 matrix [(1, cosθ_i, sinθ_i)] with μ_3 = 1. Its signs give a
    // feasible dual start: λ_i = |μ_i| / Σ|μ| on the constraint of side sign(μ_i).
    let column = |m: usize| [1.0, dirs[m][0], dirs[m][1]];
    let mut a = [[0.0; 3]; 3];
    for (j, &m) in chosen[..3].iter().enumerate() {
        for (row, v) in column(m).into_iter().enumerate() {
            a[row][j] = v;
        }
    }
    let rhs = column(chosen[3]).map(|v| -v);
    let mu3 = solve(a, rhs).ok_or(PolarError::NotCertified {
        centre: CENTRE,
        reason: "singular starting reference",
    })?;
    let mu = [mu3[0], mu3[1], mu3[2], 1.0];
    let total: Real = mu.iter().map(|v| v.abs()).sum();
    if mu.iter().any(|v| v.abs() <= 1e-12 * total) {
        return Err(PolarError::NotCertified {
            centre: CENTRE,
            reason: "degenerate starting reference",
        });
    }
    let basis = std::array::from_fn(|i| 2 * chosen[i] + usize::from(mu[i] < 0.0));
    let family = Band { dirs, p };
    let tol = PRICING_TOL * scale_of(p);
    let vertex = simplex(&family, [1.0, 0.0, 0.0, 0.0], basis, tol, CENTRE)?;
    let mut contacts: Vec<usize> = vertex.basis.iter().map(|k| k / 2).collect();
    contacts.sort_unstable();
    contacts.dedup();
    Ok(([vertex.y[2], vertex.y[3]], contacts))
}

/// The MCC (`sigma = 1`) or MIC (`sigma = −1`) offset and contacts: phase 1 minimises
/// `t = max σρ_c`; if its optimum is degenerate, phase 2 maximises `min σρ_c` among the
/// centres with `max σρ_c ≤ t* + tol`.
/// The caller has checked that the directions surround the centre.
fn one_sided(
    dirs: &[[Real; 2]],
    p: &[Real],
    sigma: Real,
    centre: Centre,
) -> Result<([Real; 2], Vec<usize>), PolarError> {
    // Start: a triangle of directions around the centre, from the highest point i: j the
    // farthest direction counter-clockwise within (0, π), k the farthest clockwise within
    // (0, π]. With no gap ≥ π, the arcs i→j, j→k, k→i are all ≤ π.
    let mut i = 0;
    for (m, &v) in p.iter().enumerate() {
        if sigma * v > sigma * p[i] {
            i = m;
        }
    }
    let ui = dirs[i];
    let (mut j, mut k) = (None, None);
    let (mut dot_j, mut dot_k) = (Real::INFINITY, Real::INFINITY);
    for (m, u) in dirs.iter().enumerate() {
        let cross = ui[0] * u[1] - ui[1] * u[0];
        let dot = ui[0] * u[0] + ui[1] * u[1];
        if cross > 0.0 {
            if dot < dot_j {
                (j, dot_j) = (Some(m), dot);
            }
        } else if (cross < 0.0 || dot < 0.0) && dot < dot_k {
            (k, dot_k) = (Some(m), dot);
        }
    }
    let (Some(j), Some(k)) = (j, k) else {
        return Err(PolarError::NotCertified {
            centre,
            reason: "no starting triangle around the centre",
        });
    };
    let tol = PRICING_TOL * scale_of(p);
    let upper = Upper { dirs, p, sigma };
    let first = simplex(&upper, [1.0, 0.0, 0.0], [i, j, k], tol, centre)?;
    // With every multiplier positive, the three contacts are tight at every optimum
    // (complementary slackness) and fix the centre: it is unique, no tie to break.
    let mut contacts: Vec<usize> = first
        .basis
        .iter()
        .zip(first.lambda)
        .filter(|&(_, l)| l > TIE_MULTIPLIER)
        .map(|(&m, _)| m)
        .collect();
    let offset = if contacts.len() == 3 {
        [first.y[1], first.y[2]]
    } else {
        // A degenerate optimum (two antipodal contacts): a segment of centres reaches t*.
        // Among them, the largest min σρ_c; the contacts with a positive multiplier stay on
        // the outer circle, the phase-2 basis is tight at the final centre.
        let capped = Capped {
            dirs,
            p,
            sigma,
            cap: first.y[0] + tol,
        };
        let second = simplex(
            &capped,
            [-1.0, 0.0, 0.0],
            [2 * i, 2 * j, 2 * k],
            tol,
            centre,
        )?;
        contacts.extend(second.basis.iter().map(|k| k / 2));
        [second.y[1], second.y[2]]
    };
    contacts.sort_unstable();
    contacts.dedup();
    Ok((offset, contacts))
}

/// The constraints `a_k · y ≥ h_k` of a primal `min b · y`, i.e. the columns of its dual
/// `max h · λ` s.t. `Σ λ_k a_k = b`, `λ ≥ 0`. The violation of constraint `k` at `y` is
/// `h_k − a_k · y` (the reduced cost of its column).
trait Family<const N: usize> {
    /// Number of constraints.
    fn count(&self) -> usize;
    /// `(a_k, h_k)`.
    fn column(&self, k: usize) -> ([Real; N], Real);
    /// The most violated constraint and its violation (Dantzig's rule).
    fn most_violated(&self, y: &[Real; N]) -> (usize, Real);
    /// The first constraint (smallest `k`) violated by more than `tol` (Bland's rule).
    fn first_violated(&self, y: &[Real; N], tol: Real) -> Option<usize>;
}

/// MCC/MIC phase 1, `y = (t, cx, cy)`: `t ≥ σρ_c[m]`, i.e. `t + σ u_m·c ≥ σ p_m`.
struct Upper<'a> {
    dirs: &'a [[Real; 2]],
    p: &'a [Real],
    sigma: Real,
}

impl Family<3> for Upper<'_> {
    fn count(&self) -> usize {
        self.p.len()
    }

    fn column(&self, k: usize) -> ([Real; 3], Real) {
        let [c, s] = self.dirs[k];
        let g = self.sigma;
        ([1.0, g * c, g * s], g * self.p[k])
    }

    fn most_violated(&self, y: &[Real; 3]) -> (usize, Real) {
        let [t, cx, cy] = *y;
        let g = self.sigma;
        let (best, best_d) = first_max(self.dirs, self.p, |[c, s], v| g * (v - cx * c - cy * s));
        (best, best_d - t)
    }

    fn first_violated(&self, y: &[Real; 3], tol: Real) -> Option<usize> {
        let [t, cx, cy] = *y;
        let g = self.sigma;
        self.dirs
            .iter()
            .zip(self.p)
            .position(|(&[c, s], &v)| g * (v - cx * c - cy * s) - t > tol)
    }
}

/// MRS, `y = (t, a0, cx, cy)`: `t ≥ ±(ρ_c[m] − a0)`; constraint `2m` is the `+` side (outer
/// circle), `2m + 1` the `−` side (inner circle).
struct Band<'a> {
    dirs: &'a [[Real; 2]],
    p: &'a [Real],
}

impl Family<4> for Band<'_> {
    fn count(&self) -> usize {
        2 * self.p.len()
    }

    fn column(&self, k: usize) -> ([Real; 4], Real) {
        let m = k / 2;
        let g = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
        let [c, s] = self.dirs[m];
        ([1.0, g, g * c, g * s], g * self.p[m])
    }

    fn most_violated(&self, y: &[Real; 4]) -> (usize, Real) {
        let [t, a0, cx, cy] = *y;
        let residual = |[c, s]: [Real; 2], v: Real| v - a0 - cx * c - cy * s;
        let (best, _) = first_max(self.dirs, self.p, |d, v| residual(d, v).abs());
        let best_r = residual(self.dirs[best], self.p[best]);
        (2 * best + usize::from(best_r < 0.0), best_r.abs() - t)
    }

    fn first_violated(&self, y: &[Real; 4], tol: Real) -> Option<usize> {
        let [t, a0, cx, cy] = *y;
        for (m, (&[c, s], &v)) in self.dirs.iter().zip(self.p).enumerate() {
            let r = v - a0 - cx * c - cy * s;
            if r - t > tol {
                return Some(2 * m);
            }
            if -r - t > tol {
                return Some(2 * m + 1);
            }
        }
        None
    }
}

/// MCC/MIC phase 2, `y = (l, cx, cy)`, maximise `l`: constraint `2m` is `σρ_c[m] ≥ l`
/// (`−l − σu_m·c ≥ −σp_m`), `2m + 1` is `σρ_c[m] ≤ cap` (`σu_m·c ≥ σp_m − cap`).
struct Capped<'a> {
    dirs: &'a [[Real; 2]],
    p: &'a [Real],
    sigma: Real,
    cap: Real,
}

impl Family<3> for Capped<'_> {
    fn count(&self) -> usize {
        2 * self.p.len()
    }

    fn column(&self, k: usize) -> ([Real; 3], Real) {
        let m = k / 2;
        let [c, s] = self.dirs[m];
        let g = self.sigma;
        if k.is_multiple_of(2) {
            ([-1.0, -g * c, -g * s], -g * self.p[m])
        } else {
            ([0.0, g * c, g * s], g * self.p[m] - self.cap)
        }
    }

    fn most_violated(&self, y: &[Real; 3]) -> (usize, Real) {
        let [l, cx, cy] = *y;
        let g = self.sigma;
        let (mut low, mut low_rho) = (0, Real::INFINITY);
        let (mut high, mut high_rho) = (0, Real::NEG_INFINITY);
        for (m, (&[c, s], &v)) in self.dirs.iter().zip(self.p).enumerate() {
            let rho = g * (v - cx * c - cy * s);
            if rho < low_rho {
                (low, low_rho) = (m, rho);
            }
            if rho > high_rho {
                (high, high_rho) = (m, rho);
            }
        }
        let (below, above) = (l - low_rho, high_rho - self.cap);
        if below >= above {
            (2 * low, below)
        } else {
            (2 * high + 1, above)
        }
    }

    fn first_violated(&self, y: &[Real; 3], tol: Real) -> Option<usize> {
        let [l, cx, cy] = *y;
        let g = self.sigma;
        for (m, (&[c, s], &v)) in self.dirs.iter().zip(self.p).enumerate() {
            let rho = g * (v - cx * c - cy * s);
            if l - rho > tol {
                return Some(2 * m);
            }
            if rho - self.cap > tol {
                return Some(2 * m + 1);
            }
        }
        None
    }
}

/// An optimal vertex: the primal `y`, the basis (constraint indices) and the dual multipliers.
struct Vertex<const N: usize> {
    y: [Real; N],
    basis: [usize; N],
    lambda: [Real; N],
}

/// Primal simplex on the dual `max h·λ` s.t. `Σ λ_k a_k = b`, `λ ≥ 0`, from a feasible basis.
/// Stops when no constraint is violated by more than `tol`, after checking the certificate.
fn simplex<const N: usize, F: Family<N>>(
    family: &F,
    b: [Real; N],
    mut basis: [usize; N],
    tol: Real,
    centre: Centre,
) -> Result<Vertex<N>, PolarError> {
    let fail = |reason| PolarError::NotCertified { centre, reason };
    let max_iterations = 1000 + 4 * family.count();
    let mut bland = false;
    let mut stalls = 0;
    let mut best = Real::NEG_INFINITY;
    for _ in 0..max_iterations {
        let mut matrix = [[0.0; N]; N]; // matrix[row][i] = a_{basis[i]}[row]
        let mut transposed = [[0.0; N]; N];
        let mut h = [0.0; N];
        for (i, &k) in basis.iter().enumerate() {
            let (a, hk) = family.column(k);
            for (row, v) in a.into_iter().enumerate() {
                matrix[row][i] = v;
            }
            transposed[i] = a;
            h[i] = hk;
        }
        let lambda = solve(matrix, b).ok_or_else(|| fail("singular basis"))?;
        let y = solve(transposed, h).ok_or_else(|| fail("singular basis"))?;
        let objective: Real = b.iter().zip(&y).map(|(u, v)| u * v).sum();
        if objective > best + 0.01 * tol {
            best = objective;
            stalls = 0;
        } else {
            stalls += 1;
            bland |= stalls > STALL_LIMIT;
        }
        let entering = if bland {
            family.first_violated(&y, tol)
        } else {
            Some(family.most_violated(&y))
                .filter(|&(_, d)| d > tol)
                .map(|(k, _)| k)
        };
        let Some(q) = entering else {
            certify(&matrix, &b, &lambda).map_err(fail)?;
            return Ok(Vertex { y, basis, lambda });
        };
        let w = solve(matrix, family.column(q).0).ok_or_else(|| fail("singular basis"))?;
        let w_max = w.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
        let mut leaving: Option<(usize, Real)> = None;
        for i in 0..N {
            if w[i] <= 1e-12 * w_max {
                continue;
            }
            let ratio = lambda[i].max(0.0) / w[i];
            leaving = match leaving {
                None => Some((i, ratio)),
                Some((r, best_ratio)) => {
                    let tie = (ratio - best_ratio).abs() <= 1e-12;
                    let better = if tie {
                        if bland {
                            basis[i] < basis[r]
                        } else {
                            w[i] > w[r]
                        }
                    } else {
                        ratio < best_ratio
                    };
                    if better {
                        Some((i, ratio))
                    } else {
                        Some((r, best_ratio))
                    }
                }
            };
        }
        let Some((r, _)) = leaving else {
            return Err(fail("unbounded dual ray"));
        };
        basis[r] = q;
    }
    Err(fail("no convergence within the iteration limit"))
}

/// Dual feasibility of the final basis: `λ ≥ 0` and `B λ = b`, both to 1e-9 relative.
fn certify<const N: usize>(
    matrix: &[[Real; N]; N],
    b: &[Real; N],
    lambda: &[Real; N],
) -> Result<(), &'static str> {
    let size: Real = lambda.iter().map(|v| v.abs()).sum::<Real>() + 1.0;
    if lambda.iter().any(|&l| l < -1e-9 * size) {
        return Err("negative multiplier");
    }
    for (row, &bv) in matrix.iter().zip(b) {
        let residual: Real = row.iter().zip(lambda).map(|(a, l)| a * l).sum::<Real>() - bv;
        if residual.abs() > 1e-9 * size {
            return Err("multipliers do not balance the objective");
        }
    }
    Ok(())
}

/// `a x = b` by Gaussian elimination with partial pivoting; `None` if a pivot is below 1e-13
/// of the largest entry.
fn solve<const N: usize>(mut a: [[Real; N]; N], mut b: [Real; N]) -> Option<[Real; N]> {
    let norm = a.iter().flatten().fold(0.0, |m: Real, v| m.max(v.abs()));
    if norm.is_nan() || norm == 0.0 {
        return None;
    }
    for col in 0..N {
        let mut pivot = col;
        for row in col + 1..N {
            if a[row][col].abs() > a[pivot][col].abs() {
                pivot = row;
            }
        }
        if a[pivot][col].abs() <= 1e-13 * norm {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let head = a[col];
        for row in col + 1..N {
            let f = a[row][col] / head[col];
            for (x, h) in a[row][col..].iter_mut().zip(&head[col..]) {
                *x -= f * h;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; N];
    for col in (0..N).rev() {
        let tail: Real = (col + 1..N).map(|k| a[col][k] * x[k]).sum();
        x[col] = (b[col] - tail) / a[col][col];
    }
    Some(x)
}
