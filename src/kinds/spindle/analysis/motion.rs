//! One error-motion signal laid out as revolutions × angles, its ISO 230-7 decomposition by
//! rotational frequency, and the error motion values.
//!
//! # What it models
//!
//! A test signal `s[k, m]` (m for radial, axial and face; rad for tilt) sampled at the index
//! grid `θ_m = 2πm/M`, `m = 0..M`, for `K` complete revolutions `k = 0..K`. From it
//! ([`decompose`], ISO 230-7 §3.5, §3.6; digest §2.5):
//!
//! ```text
//! synchronous   S[m]    = (1/K) Σ_k s[k,m]                      (§3.5.2 Note 1)
//! asynchronous  A[k,m]  = s[k,m] − S[m]                         (§3.5.5 Note 1)
//! inner, outer  I[m]    = min_k s[k,m],  O[m] = max_k s[k,m]     (§3.6.7, §3.6.8)
//! fundamental   a1 = (2/M) Σ_m S[m] cos θ_m,  b1 = (2/M) Σ_m S[m] sin θ_m   (§3.5.3)
//! residual      R[m]    = S[m] − mean(S) − a1 cos θ_m − b1 sin θ_m            (§3.5.4)
//! ```
//!
//! and the values ([`values`], §3.8; digest §2.8), with the centre `c` found on the
//! **synchronous** plot (§3.7.7 Note 1) and that same centre used for the total, inner and
//! outer plots. In the small-deviation (limaçon) model a centre offset `c` changes the radial
//! deviation at `θ` by `−(cx cos θ + cy sin θ)`, and a value is the range of what remains:
//!
//! - total (§3.8.2): range about `c` of all revolutions pooled; and, "specified otherwise"
//!   (§3.7.7 Note 1), about the total plot's own centre of the same kind: PC and LSC are the
//!   same centres (the least-squares fit to every revolution is the fit to their mean `S`),
//!   MRS, MIC and MCC are fitted to the whole cloud, whose extremes at each angle are `O` and
//!   `I`, so the fit to `O` and `I` pooled is exact;
//! - synchronous (§3.8.3): range of `S` about `c`;
//! - asynchronous (§3.8.4): `max_m (O[m] − I[m])`, the widest band at a single angle, the one
//!   value not based on concentric circles (and independent of the centre in the limaçon model);
//! - fundamental (§3.8.5): `2·√(a1² + b1²)`, twice the distance from PC to the LSC of `S`;
//! - residual (§3.8.6): the residual plot `R` evaluated about its own centre of each kind.
//!   About PC it is the range of `R`; about LSC, MRS, MIC and MCC it equals the synchronous
//!   value about that centre, since `R` differs from `S` by a constant and a 1-UPR term, which a
//!   fitted centre absorbs (the §2.7 invariant of the digest). The centre of `S` is not used on
//!   `R`: it would put the fundamental back with its sign reversed;
//! - inner and outer (§3.8.7, §3.8.8): ranges of `I` and `O` about `c`.
//!
//! The preferred centre per direction is ISO 230-7 Tab 1 ([`Direction::preferred_centre`]):
//! LSC for radial and tilt, which removes the fundamental (the radial fundamental is normally
//! the artefact's radial throw, §3.5.3 Notes 2–3, and the fundamental tilt is the direction of
//! the axis average line, A.7.6); PC for axial and face, which keeps it (§5.3.4.3 "fundamental
//! error motion should not be removed analytically"; the fundamental axial error motion is
//! evaluated, A.7.6). [`values`] takes the centre explicitly, so a caller can also ask for any
//! other centre; the direction only labels the result and states the convention.
//!
//! **The one ambiguity** (digest §2.8): for axial error motion §5.3.4.3 calls the asynchronous
//! value "the maximum range of the displacement over a sufficient number of revolutions", which
//! could be read as the range of the whole record. This module reads it as the §3.8.4
//! definition used for every other direction: the maximum per-angle band width `max_m (O − I)`.
//! The other reading is the PC total value, which [`values`] reports as `total` when asked for
//! [`Centre::Pc`].
//!
//! Also here: the combinations ISO 230-7 uses to build one signal from probe readings
//! ([`rotating_radial`] formula (1), [`fixed_direction`] formula (4), [`tilt`] formula (5)), and
//! [`resample`] for records whose samples do not fall on the index grid.
//!
//! # What it leaves out
//!
//! Sign conventions and probe geometry (the caller builds the signal), artefact form
//! separation (`separation`), the centre fits themselves (`polar`), speed-dependent summaries
//! (the caller evaluates each speed on its own), CW/CCW pooling, partial-arc records (rotary
//! axes with less than a full turn), drift removal and uncertainty (ISO 230-7 Annex F). Values
//! are in the limaçon model, independent of the cosmetic plot radius `r0`.

use super::polar::{Angles, Centre, PolarError};
use crate::math::Real;
use serde::Serialize;
use std::f64::consts::TAU;

/// The fewest angle bins per revolution: below three the 1-UPR cosine and sine cannot be told
/// apart from the mean (at `M = 2` the sine is zero at every bin).
pub const MIN_SAMPLES_PER_REVOLUTION: usize = 3;

/// The most values [`resample`] produces (2³⁰ values, 8 GiB): a guard against an angle that
/// spans far more revolutions than the record has samples.
pub const MAX_RESAMPLED: usize = 1 << 30;

/// Why a record cannot be laid out or evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    /// Fewer than [`MIN_SAMPLES_PER_REVOLUTION`] angle bins per revolution.
    #[error("{0} samples per revolution; at least 3 are needed")]
    TooFewSamplesPerRevolution(usize),
    /// No sample at all.
    #[error("the record holds no sample")]
    Empty,
    /// The number of values is not a whole number of revolutions.
    #[error("{len} values are not a whole number of revolutions of {per_revolution} samples")]
    PartialRevolution {
        /// Number of values given.
        len: usize,
        /// Samples per revolution asked for.
        per_revolution: usize,
    },
    /// A value or an angle is NaN or infinite.
    #[error("sample {0} is not finite")]
    NonFinite(usize),
    /// The angle and the signal have different lengths.
    #[error("{angles} angles but {values} signal values")]
    LengthMismatch {
        /// Number of angles.
        angles: usize,
        /// Number of signal values.
        values: usize,
    },
    /// The unwrapped angle does not strictly increase at this sample.
    #[error("the angle does not increase at sample {0}")]
    NonMonotoneAngle(usize),
    /// The angle covers no complete revolution of the index grid.
    #[error("the angle covers no complete revolution")]
    NoCompleteRevolution,
    /// The resampled record would exceed [`MAX_RESAMPLED`] values.
    #[error("the angle spans {0:e} grid samples, more than the limit")]
    TooLong(Real),
    /// The centre could not be fitted to the synchronous plot.
    #[error("centre fit: {0}")]
    Centre(#[from] PolarError),
}

/// One error-motion signal: `K` complete revolutions of `M` samples at the index grid
/// `θ_m = 2πm/M`, stored revolution by revolution (row-major `K × M`).
#[derive(Clone, Debug, PartialEq)]
pub struct Revolutions {
    samples_per_revolution: usize,
    values: Vec<Real>,
}

impl Revolutions {
    /// Lays `values` out as revolutions of `samples_per_revolution` samples each: value
    /// `k·M + m` is revolution `k` at angle `θ_m = 2πm/M`.
    ///
    /// Errors: fewer than [`MIN_SAMPLES_PER_REVOLUTION`] samples per revolution, no value, a
    /// length that is not a whole number of revolutions, a non-finite value.
    pub fn new(samples_per_revolution: usize, values: Vec<Real>) -> Result<Self, MotionError> {
        if samples_per_revolution < MIN_SAMPLES_PER_REVOLUTION {
            return Err(MotionError::TooFewSamplesPerRevolution(
                samples_per_revolution,
            ));
        }
        if values.is_empty() {
            return Err(MotionError::Empty);
        }
        if !values.len().is_multiple_of(samples_per_revolution) {
            return Err(MotionError::PartialRevolution {
                len: values.len(),
                per_revolution: samples_per_revolution,
            });
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(MotionError::NonFinite(i));
        }
        Ok(Self {
            samples_per_revolution,
            values,
        })
    }

    /// Number of samples per revolution `M`.
    pub fn samples_per_revolution(&self) -> usize {
        self.samples_per_revolution
    }

    /// Number of revolutions `K` (at least 1).
    pub fn count(&self) -> usize {
        self.values.len() / self.samples_per_revolution
    }

    /// The index-grid angles `θ_m = 2πm/M` (rad), `M` of them.
    pub fn angles(&self) -> Vec<Real> {
        grid(self.samples_per_revolution)
    }

    /// Revolution `k`'s `M` samples. Panics if `k ≥ count()`, like slice indexing.
    pub fn revolution(&self, k: usize) -> &[Real] {
        let m = self.samples_per_revolution;
        &self.values[k * m..(k + 1) * m]
    }

    /// All `K·M` samples, revolution by revolution.
    pub fn values(&self) -> &[Real] {
        &self.values
    }
}

/// `θ_m = 2πm/M`.
fn grid(m: usize) -> Vec<Real> {
    (0..m).map(|i| TAU * i as Real / m as Real).collect()
}

/// The index grid `θ_m = 2πm/M` of `M` samples per revolution with the direction
/// `(cos θ_m, sin θ_m)` of every angle computed once: build it once per record and pass it to
/// [`values_about_on`] for each of the record's signals.
#[derive(Clone, Debug)]
pub struct Grid {
    angles: Angles,
    /// The grid's angles twice over: the outer contour's then the inner one's, for the total
    /// plot's own centre.
    pooled: Angles,
}

impl Grid {
    /// The grid of `samples_per_revolution` angles.
    ///
    /// Errors: fewer than [`MIN_SAMPLES_PER_REVOLUTION`].
    pub fn new(samples_per_revolution: usize) -> Result<Grid, MotionError> {
        if samples_per_revolution < MIN_SAMPLES_PER_REVOLUTION {
            return Err(MotionError::TooFewSamplesPerRevolution(
                samples_per_revolution,
            ));
        }
        let angles = Angles::equally_spaced(samples_per_revolution)
            .expect("at least MIN_SAMPLES_PER_REVOLUTION = 3 angles");
        let twice: Vec<Real> = (0..2 * samples_per_revolution)
            .map(|m| TAU * (m % samples_per_revolution) as Real / samples_per_revolution as Real)
            .collect();
        let pooled = Angles::new(&twice).expect("at least 6 finite angles");
        Ok(Grid { angles, pooled })
    }

    /// Number of samples per revolution `M`.
    pub fn samples_per_revolution(&self) -> usize {
        self.angles.len()
    }

    /// The grid's angles, for the centre fits and ranges of [`super::polar`].
    pub fn angles(&self) -> &Angles {
        &self.angles
    }
}

/// The decomposition of one signal by rotational frequency (ISO 230-7 §3.5, §3.6).
#[derive(Clone, Debug, PartialEq)]
pub struct Decomposition {
    /// `S[m]`, the mean over the revolutions at each angle (`M` values).
    pub synchronous: Vec<Real>,
    /// `A[k, m] = s[k, m] − S[m]` (`K × M`, row-major like [`Revolutions::values`]).
    pub asynchronous: Vec<Real>,
    /// `I[m]`, the smallest value over the revolutions at each angle (`M`).
    pub inner: Vec<Real>,
    /// `O[m]`, the largest value over the revolutions at each angle (`M`).
    pub outer: Vec<Real>,
    /// `[a1, b1]`: the 1-UPR cosine and sine coefficients of `S`, so the fundamental is
    /// `a1 cos θ + b1 sin θ`.
    pub fundamental: [Real; 2],
    /// `S − mean(S) − (a1 cos θ + b1 sin θ)` (`M`).
    pub residual: Vec<Real>,
}

/// Splits a signal into its synchronous, asynchronous, inner, outer, fundamental and residual
/// parts (formulas in the module docs).
pub fn decompose(r: &Revolutions) -> Decomposition {
    let grid = Grid::new(r.samples_per_revolution).expect("a laid-out signal has M ≥ 3");
    let contours = Contours::new(r);
    let mut asynchronous = Vec::with_capacity(r.values.len());
    for k in 0..r.count() {
        asynchronous.extend(
            r.revolution(k)
                .iter()
                .zip(&contours.synchronous)
                .map(|(v, s)| v - s),
        );
    }
    let (fundamental, residual) = fundamental(&contours.synchronous, &grid);
    Decomposition {
        synchronous: contours.synchronous,
        asynchronous,
        inner: contours.inner,
        outer: contours.outer,
        fundamental,
        residual,
    }
}

/// The synchronous profile `S` of a signal alone (as in [`decompose`], without the other
/// parts).
pub fn synchronous(r: &Revolutions) -> Vec<Real> {
    Contours::new(r).synchronous
}

/// The per-angle parts of a signal: `S`, `I` and `O`, in one pass over the record.
struct Contours {
    synchronous: Vec<Real>,
    inner: Vec<Real>,
    outer: Vec<Real>,
}

impl Contours {
    fn new(r: &Revolutions) -> Contours {
        let m_count = r.samples_per_revolution;
        let mut synchronous = vec![0.0; m_count];
        let mut inner = vec![Real::INFINITY; m_count];
        let mut outer = vec![Real::NEG_INFINITY; m_count];
        for revolution in r.values.chunks_exact(m_count) {
            for (((s, lo), hi), &v) in synchronous
                .iter_mut()
                .zip(inner.iter_mut())
                .zip(outer.iter_mut())
                .zip(revolution)
            {
                *s += v;
                *lo = lo.min(v);
                *hi = hi.max(v);
            }
        }
        let inv_k = 1.0 / r.count() as Real;
        for s in &mut synchronous {
            *s *= inv_k;
        }
        Contours {
            synchronous,
            inner,
            outer,
        }
    }
}

/// `[a1, b1]` of the synchronous profile and its residual (formulas in the module docs), on
/// the grid's directions.
fn fundamental(synchronous: &[Real], grid: &Grid) -> ([Real; 2], Vec<Real>) {
    let m_count = synchronous.len();
    let directions = grid.angles().directions();
    let (mut a1, mut b1, mut mean) = (0.0, 0.0, 0.0);
    for (&s, &[cos, sin]) in synchronous.iter().zip(directions) {
        a1 += s * cos;
        b1 += s * sin;
        mean += s;
    }
    let scale = 2.0 / m_count as Real;
    a1 *= scale;
    b1 *= scale;
    mean /= m_count as Real;
    let residual = synchronous
        .iter()
        .zip(directions)
        .map(|(&s, &[cos, sin])| s - mean - a1 * cos - b1 * sin)
        .collect();
    ([a1, b1], residual)
}

/// The direction of an error motion (ISO 230-7 §3.4), which sets the preferred centre and
/// whether the fundamental is removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// Radial error motion, at a stated axial location (§3.4.1); m.
    Radial,
    /// Axial error motion (§3.4.4); m.
    Axial,
    /// Tilt error motion (§3.4.3); rad.
    Tilt,
    /// Face error motion, at a stated radius (§3.4.5); m.
    Face,
}

impl Direction {
    /// All four, in declaration order.
    pub const ALL: [Direction; 4] = [
        Direction::Radial,
        Direction::Axial,
        Direction::Tilt,
        Direction::Face,
    ];

    /// Lower-case name: `radial`, `axial`, `tilt`, `face`.
    pub fn name(self) -> &'static str {
        match self {
            Direction::Radial => "radial",
            Direction::Axial => "axial",
            Direction::Tilt => "tilt",
            Direction::Face => "face",
        }
    }

    /// The preferred centre of ISO 230-7 Tab 1: LSC for radial and tilt, PC for axial and face.
    pub fn preferred_centre(self) -> Centre {
        match self {
            Direction::Radial | Direction::Tilt => Centre::Lsc,
            Direction::Axial | Direction::Face => Centre::Pc,
        }
    }

    /// Whether the fundamental (1 UPR) is removed from the synchronous value: yes for radial
    /// and tilt, where the LSC centre removes it (§3.5.3 Note 2, A.7.6); no for axial and face,
    /// where it is evaluated (§5.3.4.3, §3.8.5) and PC keeps it.
    pub fn removes_fundamental(self) -> bool {
        matches!(self, Direction::Radial | Direction::Tilt)
    }
}

impl std::fmt::Display for Direction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The error motion values of one signal about one centre (ISO 230-7 §3.8), in the signal's
/// unit (m, or rad for tilt).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ErrorMotionValues {
    /// The direction the signal measures.
    pub direction: Direction,
    /// The centre used, fitted to the synchronous plot.
    pub centre: Centre,
    /// Its offset `[cx, cy]` from PC, in the signal's unit.
    pub offset: [Real; 2],
    /// Total value (§3.8.2): range about the centre of all revolutions pooled.
    pub total: Real,
    /// Total value about the total plot's own centre of this kind (§3.7.7 Note 1 "unless
    /// specified otherwise"): the same as `total` for PC and LSC.
    pub total_own_centre: Real,
    /// That centre's offset `[cx, cy]` from PC.
    pub total_own_offset: [Real; 2],
    /// Synchronous value (§3.8.3): range of `S` about the centre.
    pub synchronous: Real,
    /// Asynchronous value (§3.8.4): the widest band `max_m (O[m] − I[m])`.
    pub asynchronous: Real,
    /// Fundamental value (§3.8.5): `2·√(a1² + b1²)`.
    pub fundamental: Real,
    /// Residual synchronous value (§3.8.6): the residual plot about its own centre of this
    /// kind (about PC its range; about the others the synchronous value, module docs).
    pub residual: Real,
    /// Inner value (§3.8.7): range of `I` about the centre.
    pub inner: Real,
    /// Outer value (§3.8.8): range of `O` about the centre.
    pub outer: Real,
}

/// The error motion values of `r` about `centre`, fitted to the synchronous plot (§3.7.7
/// Note 1). Pass `direction.preferred_centre()` for the ISO 230-7 Tab 1 default.
///
/// Errors: the centre fit fails ([`MotionError::Centre`]).
pub fn values(
    r: &Revolutions,
    direction: Direction,
    centre: Centre,
) -> Result<ErrorMotionValues, MotionError> {
    Ok(values_about(r, direction, &[centre])?.remove(0))
}

/// [`values`] about each of `centres`, in that order, from one decomposition of `r`.
///
/// The total value about a centre is taken from the outer and inner contours: at each angle
/// the centre shifts every revolution's sample by the same amount, so the pooled extremes
/// about it are the extremes of `O − c·u` and `I − c·u` (exactly; no revolution is revisited).
///
/// Errors: a centre fit fails ([`MotionError::Centre`]).
pub fn values_about(
    r: &Revolutions,
    direction: Direction,
    centres: &[Centre],
) -> Result<Vec<ErrorMotionValues>, MotionError> {
    values_about_on(r, direction, centres, &Grid::new(r.samples_per_revolution)?)
}

/// [`values_about`] on a grid built once for many signals of the same samples per revolution
/// (the same values; the directions are not recomputed).
///
/// Errors: a centre fit fails ([`MotionError::Centre`]), or the grid has another number of
/// samples per revolution than `r` (`MotionError::Centre` of a length mismatch).
pub fn values_about_on(
    r: &Revolutions,
    direction: Direction,
    centres: &[Centre],
    grid: &Grid,
) -> Result<Vec<ErrorMotionValues>, MotionError> {
    if grid.samples_per_revolution() != r.samples_per_revolution {
        return Err(MotionError::Centre(PolarError::LengthMismatch {
            values: r.samples_per_revolution,
            angles: grid.samples_per_revolution(),
        }));
    }
    // S, I and O only: the asynchronous record of `decompose` is not needed for the values.
    let contours = Contours::new(r);
    let ([a1, b1], residual) = fundamental(&contours.synchronous, grid);
    let angles = grid.angles();
    let asynchronous = contours
        .outer
        .iter()
        .zip(&contours.inner)
        .map(|(o, i)| o - i)
        .fold(0.0, Real::max);
    // The total plot's extremes at each angle, for its own MRS, MIC and MCC.
    let pooled = [contours.outer.as_slice(), &contours.inner].concat();
    centres
        .iter()
        .map(|&centre| {
            // The fit's low and high are those of S about its centre: the synchronous range.
            let fit = angles.fit(&contours.synchronous, centre)?;
            let offset = fit.offset;
            let (outer_low, outer_high) = angles.range_about(&contours.outer, offset);
            let (inner_low, inner_high) = angles.range_about(&contours.inner, offset);
            let total = outer_high - inner_low;
            let (total_own_offset, total_own_centre) = match centre {
                Centre::Pc | Centre::Lsc => (offset, total),
                Centre::Mrs | Centre::Mic | Centre::Mcc => {
                    let own = grid.pooled.fit(&pooled, centre)?;
                    (own.offset, own.value())
                }
            };
            Ok(ErrorMotionValues {
                direction,
                centre,
                offset,
                total,
                total_own_centre,
                total_own_offset,
                synchronous: fit.value(),
                asynchronous,
                fundamental: 2.0 * a1.hypot(b1),
                residual: angles.fit(&residual, centre)?.value(),
                inner: inner_high - inner_low,
                outer: outer_high - outer_low,
            })
        })
        .collect()
}

/// ISO 230-7 formula (1), rotating sensitive direction: `out[i] = ΔX[i] cos θ[i] + ΔY[i] sin θ[i]`
/// (the radial error motion `r(θ) − r0` along the direction at angle `θ` from X).
///
/// Writes `out[i]` for every `i` below the shortest of the four lengths (pass equal lengths);
/// it does not allocate.
pub fn rotating_radial(dx: &[Real], dy: &[Real], angles: &[Real], out: &mut [Real]) {
    for (((o, &x), &y), &t) in out.iter_mut().zip(dx).zip(dy).zip(angles) {
        let (sin, cos) = t.sin_cos();
        *o = x * cos + y * sin;
    }
}

/// ISO 230-7 formula (4), fixed sensitive direction at `theta_f` (rad) from X:
/// `out[i] = ΔX[i] cos θ_f + ΔY[i] sin θ_f`.
///
/// Writes `out[i]` for every `i` below the shortest of the three lengths (pass equal lengths).
pub fn fixed_direction(dx: &[Real], dy: &[Real], theta_f: Real, out: &mut [Real]) {
    let (sin, cos) = theta_f.sin_cos();
    for ((o, &x), &y) in out.iter_mut().zip(dx).zip(dy) {
        *o = x * cos + y * sin;
    }
}

/// ISO 230-7 formula (5) (reconstructed, digest §2.14): tilt from two radial stations
/// `separation` (m) apart along the axis, `out[i] = (upper[i] − lower[i]) / separation` (rad).
/// "Upper" is the station at the larger axial coordinate, so a tilt that moves it further along
/// the sensitive direction is positive (ISO 230-7 A.2: `E_X|z2 = E_X|z1 + L·E_B`).
///
/// Writes `out[i]` for every `i` below the shortest of the three lengths (pass equal lengths);
/// a zero separation gives IEEE infinities or NaN, not a panic.
pub fn tilt(lower: &[Real], upper: &[Real], separation: Real, out: &mut [Real]) {
    let inv = 1.0 / separation;
    for ((o, &l), &u) in out.iter_mut().zip(lower).zip(upper) {
        *o = (u - l) * inv;
    }
}

/// Resamples a record whose samples do not fall on the index grid: `signal[i]` taken at the
/// unwrapped angle `angle[i]` (rad, strictly increasing, angle 0 at the index mark; negate the
/// angle of an axis turning the negative way) is linearly interpolated onto
/// `2π(k + m/M)`, `m = 0..M`, for every whole revolution `k` whose `M` grid points all lie in
/// `[angle[0], angle[last]]`. Revolution 0 of the result is the first such `k`; partial
/// revolutions at either end are dropped.
///
/// Linear interpolation errs by at most `h²/8 · max|s''|` for sample spacing `h`; it also
/// low-passes content near the sampling rate, so sample well above the highest UPR of interest.
///
/// Errors: lengths differ, fewer than [`MIN_SAMPLES_PER_REVOLUTION`] samples per revolution, no
/// sample, a non-finite angle or value, an angle that does not strictly increase, no complete
/// revolution, more than [`MAX_RESAMPLED`] grid values.
pub fn resample(
    angle: &[Real],
    signal: &[Real],
    samples_per_revolution: usize,
) -> Result<Revolutions, MotionError> {
    if angle.len() != signal.len() {
        return Err(MotionError::LengthMismatch {
            angles: angle.len(),
            values: signal.len(),
        });
    }
    let m_count = samples_per_revolution;
    if m_count < MIN_SAMPLES_PER_REVOLUTION {
        return Err(MotionError::TooFewSamplesPerRevolution(m_count));
    }
    if angle.is_empty() {
        return Err(MotionError::Empty);
    }
    for (i, (a, s)) in angle.iter().zip(signal).enumerate() {
        if !a.is_finite() || !s.is_finite() {
            return Err(MotionError::NonFinite(i));
        }
        if i > 0 && *a <= angle[i - 1] {
            return Err(MotionError::NonMonotoneAngle(i));
        }
    }
    let first = angle[0];
    let last = angle[angle.len() - 1];
    // Grid points within a few rounding units of the ends count as inside (an angle built as
    // 2π·x may miss the exact grid value by an ulp); the interpolation clamps to the end value.
    let slack = 8.0 * Real::EPSILON * first.abs().max(last.abs()).max(TAU);
    let k_first = ((first - slack) / TAU).ceil();
    let span_in_revolution = TAU * (m_count - 1) as Real / m_count as Real;
    let k_last = ((last + slack - span_in_revolution) / TAU).floor();
    if k_last < k_first {
        return Err(MotionError::NoCompleteRevolution);
    }
    let grid_len = (k_last - k_first + 1.0) * m_count as Real;
    if grid_len > MAX_RESAMPLED as Real {
        return Err(MotionError::TooLong(grid_len));
    }
    let k_count = (k_last - k_first) as usize + 1;
    let mut values = Vec::with_capacity(k_count * m_count);
    let mut j = 0usize; // angle[j] ≤ target < angle[j + 1], advanced monotonically
    let step = TAU / m_count as Real;
    for k in 0..k_count {
        let base = TAU * (k_first + k as Real);
        for m in 0..m_count {
            let target = base + step * m as Real;
            while j + 2 < angle.len() && angle[j + 1] < target {
                j += 1;
            }
            let (a0, a1) = if angle.len() == 1 {
                (angle[0], angle[0])
            } else {
                (angle[j], angle[j + 1])
            };
            let v = if a1 > a0 {
                let t = ((target - a0) / (a1 - a0)).clamp(0.0, 1.0);
                signal[j] + t * (signal[j + 1] - signal[j])
            } else {
                signal[j]
            };
            values.push(v);
        }
    }
    Revolutions::new(m_count, values)
}
