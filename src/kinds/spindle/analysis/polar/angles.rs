//! A profile's angles with their directions ([`Angles`]), the fit of a profile about a centre
//! ([`fit`], [`Angles::fit`]) and the range of values about an offset ([`range_about`]).

use std::f64::consts::TAU;

use super::centre::{Centre, CentreFit, MAX_ANGLE_GAP, PolarError};
use super::extremes::{extremes, range_of};
use super::simplex::{minimum_zone, one_sided};
use crate::math::{RAD_PER_DEG, Real};

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
