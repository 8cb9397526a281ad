//! ISO 230-4 circular tests of a ball-bar table: the standard's figures and the diagnostics a
//! service engineer reads from the trace.
//!
//! **Frame and signs.** The plane's axes are p (its first) and q (its second), see [`Plane`]:
//! XY → p = X, q = Y; YZ → p = Y, q = Z; ZX → p = Z, q = X. θ runs from +p toward +q; σ = +1
//! counter-clockwise (θ increasing), −1 clockwise. A reading is d = measured distance between
//! the balls − nominal radius R (actual − nominal, + outward). v is the feed (path speed),
//! sgn the sign function. SI inside (m, rad, s).
//!
//! # ISO 230-4 figures
//!
//! The offset of the machine's circle from the centre ball is removed by least squares to
//! first order, d ≈ r₀ + c_p·cos θ + c_q·sin θ; the first-order removal leaves at most a
//! residual of amplitude e²/(4R) for an offset e (0.025 µm for e = 0.1 mm at R = 100 mm).
//!
//! - `G_ccw`, `G_cw` circular deviation: max − min of the residuals of each sense's own fit;
//! - `G` bidirectional circular deviation G(b): max − min of both senses' residuals from one
//!   common fit (r₀, c_p, c_q);
//! - `H` circular hysteresis: max over θ of |d_ccw(θ) − d_cw(θ)| after the common centre
//!   removal, the cw trace linearly interpolated in θ at the ccw angles where both traces cover
//!   (across 0°/360° too);
//! - `F_max`, `F_min`: max and min of d − c_p·cos θ − c_q·sin θ (common fit): radial deviation
//!   from the nominal radius with the centre offset removed, r₀ kept.
//!
//! # Diagnostics
//!
//! One joint linear least-squares fit over both senses of d(θ, σ) = the sum of the columns
//! below ([`Term`], [`diagnostic_column`]); reversal lags, decay times and periods are
//! searched on the joint residual sum of squares.
//!
//! The angle of a reading is the programmed one (ball-bar software assigns it from the
//! programmed path), but an axis reverses when it actually does: a servo lag δ (1/K_v for a
//! position loop without feed-forward) after its programmed reversal. Backlash, lateral play
//! and the spike of p act at θ_p = θ − σ·v·δ_p/R crossing 0° or 180°, those of q at
//! θ_q = θ − σ·v·δ_q/R crossing 90° or 270°; δ_p, δ_q are searched from 0 to min(200 ms, the
//! time for 30° of arc) whenever the model has a reversal term of the axis. With δ = 0 the
//! terms read as in the table (sgn(sin θ_p)·sin θ = |sin θ|, …).
//!
//! | key | parameter | radial term |
//! |---|---|---|
//! | `radius_deviation_um` | c₀: bar length error, mean scale | c₀ |
//! | `centre_offset_p_um`, `_q_um` | centre of the machine's circle relative to the centre ball | c_p·cos θ + c_q·sin θ |
//! | `squareness_um_per_m` | s (rad), + when the angle between +p and +q travel is < 90° | (R·s/2)·sin 2θ |
//! | `scale_mismatch_ppm` | Δk = k_p − k_q | (R·Δk/2)·cos 2θ |
//! | `servo_mismatch_ms` | Δτ = τ_p − τ_q (lag = 1/K_v), + when p lags more | σ·(v·Δτ/2)·sin 2θ |
//! | `backlash_p_um` | b_p: p lags the command by b_p/2 against its travel, sgn ṗ = −σ·sgn(sin θ_p) | +σ·sgn(sin θ_p)·cos θ·b_p/2 |
//! | `backlash_q_um` | b_q, sgn q̇ = σ·sgn(cos θ_q) | −σ·sgn(cos θ_q)·sin θ·b_q/2 |
//! | `lateral_play_p_um` | l_p: the p carriage shifts along q by −sgn(ṗ)·l_p/2 | +σ·sgn(sin θ_p)·sin θ·l_p/2 (= +σ·\|sin θ\|·l_p/2 at δ_p = 0) |
//! | `lateral_play_q_um` | l_q: the q carriage shifts along p by −sgn(q̇)·l_q/2 | −σ·sgn(cos θ_q)·cos θ·l_q/2 (= −σ·\|cos θ\|·l_q/2) |
//! | `reversal_lag_p_ms`, `_q_ms` | δ_p, δ_q: time from the programmed to the actual reversal of the axis, reported when one of its reversal terms is significant (u from the profile likelihood, Δ RSS = σ̂²) | (locates the reversal terms) |
//! | `straightness_p_um` | S_p: bow of p along q, E_q = S_p·(1 − (p/R)²), middle toward +q | S_p·sin³θ |
//! | `straightness_q_um` | S_q: E_p = S_q·(1 − (q/R)²) | S_q·cos³θ |
//! | `reversal_spike_p_um`, `_decay_ms` | h_p, τ_p: after p reverses (θ_p = 0°, 180°) it sticks and lags in its new direction by h_p·e^(−Δt/τ_p), Δt = R·\|θ_p − θ_r\|/v | +h_p·\|cos θ\|·e^(−Δt/τ_p) |
//! | `reversal_spike_q_um`, `_decay_ms` | the same for q at 90°, 270° | +h_q·\|sin θ\|·e^(−Δt/τ_q) |
//! | `cyclic_p_um`, `_period_mm`, `_phase_deg` | periodic error A·sin(2π·p/P + φ) of p, p = R·cos θ from the circle centre | cos θ·[α·sin(2πp/P) + β·cos(2πp/P)], A = √(α² + β²), φ = atan2(β, α) |
//! | `cyclic_q_um`, … | the same for q, q = R·sin θ | sin θ·[α·sin(2πq/P) + β·cos(2πq/P)] |
//!
//! A spike counts only after a reversal the trace crossed: the same sense has readings within
//! 3° before it (a full circle counts as crossed at its start: tests run in with a lead-in
//! arc). Decays are searched from max(1 ms, two sampling intervals) to min(200 ms, the time
//! for 30° of arc): a shorter spike lies in one or two readings and cannot be told from noise.
//! A spike's height is read back to the instant the axis reversed, which a trace sampled
//! every Δt places only within a sample interval: the height is known to a factor
//! e^(±Δt/(2τ)), and its uncertainty includes h·u_δ/τ. Periods are searched from max(1 mm,
//! 4 sample spacings) to R/2. A spike amplitude below twice its uncertainty is reported with
//! a null decay. A cyclic amplitude needs more, as its
//! period is the best of the M periods searched (4 per 1/(2R) in frequency): noise alone
//! passes 2u at one of them nearly always, so the threshold is √(2·ln(M/0.05)) u (4.5 u for
//! R = 150 mm, M = 1185), which the largest of M noise amplitudes exceeds at most 5 % of the
//! time; below it the period is null ([`CircleData::significance`]).
//!
//! **Uncertainties** are standard uncertainties σ̂·√((JᵀJ)⁻¹)ⱼⱼ, σ̂² = RSS/(n − k), J the fit's
//! columns plus the derivatives in the decays and periods of significant terms. They assume
//! independent residuals; a real trace's residuals are serially correlated, so they are
//! optimistic.
//!
//! **Identifiability.** A term the data cannot tell from the others is reported null with the
//! reason, never as a number: terms needing both senses when one is missing (servo mismatch is
//! then squareness, lateral play is radius and scale), spikes with no crossed reversal, and
//! any term whose variance the others inflate more than [`MAX_VARIANCE_INFLATION`] times (the
//! least important goes first; order of [`Term::DIAGNOSTICS`]).

use crate::kinds::ballbar::BallbarTable;
use crate::machine::Plane;
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, fixed, golden_minimum};
use nalgebra::DMatrix;
use serde_json::{Value, json};
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::fmt::Write;

/// The fewest readings a sense present in the table may have.
pub const MIN_READINGS: usize = 20;
/// The smallest angular span (°) a sense may cover for a circle fit.
pub const MIN_SPAN_DEG: Real = 90.0;
/// The fewest readings for the diagnostic fit (about 20 columns).
pub const MIN_DIAGNOSTIC_READINGS: usize = 200;
/// A term whose variance the other terms inflate more than this is unidentifiable (its
/// uncertainty would be more than √1000 ≈ 32 times that of an orthogonal design).
pub const MAX_VARIANCE_INFLATION: Real = 1000.0;
/// A reversal counts as crossed when the sense has readings this close before it (rad).
const CROSSING_WINDOW: Real = 3.0 * RAD_PER_DEG;
/// A spike column is cut after this many decay times.
const SPIKE_DECAYS: Real = 10.0;
/// A spike needs at least this many readings within 3 decays (at the longest) of its reversals.
const MIN_SPIKE_READINGS: usize = 10;
/// Decay search bounds (s) and the arc (rad) whose duration also bounds it.
const DECAY_MIN: Real = 1e-3;
const DECAY_MAX: Real = 0.2;
const DECAY_ARC: Real = 30.0 * RAD_PER_DEG;
/// Shortest cyclic period searched (m).
const PERIOD_MIN: Real = 1e-3;
/// The most lobes searched.
const LOBES_MAX: u32 = 60;
/// Grid points of the reversal-lag search (every 5 ms over 0–200 ms).
const LAG_GRID: usize = 41;
/// Grid points of the decay search (log-spaced) and golden-section iterations.
const DECAY_GRID: usize = 16;
const GOLDEN_ITERATIONS: usize = 20;
/// Eigenvalues of the column-scaled Gram matrix below this fraction of the largest are zero.
const EIGEN_TOLERANCE: Real = 1e-13;
/// A spike amplitude counts as significant at this many standard uncertainties.
const SIGNIFICANCE: Real = 2.0;
/// The false-alarm probability a cyclic amplitude's threshold allows over its period search.
const CYCLIC_FALSE_ALARM: Real = 0.05;

/// The conditions of a circular test, which the table does not hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircularTest {
    /// The plane of the circle.
    pub plane: Plane,
    /// Nominal radius (m).
    pub radius: Real,
    /// Path speed (m/s).
    pub feed: Real,
}

/// Why a ball-bar table cannot be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BallbarError {
    /// The radius is not a finite positive length.
    #[error("radius {0} mm: expected a finite positive length")]
    Radius(Real),
    /// The feed is not a finite positive speed.
    #[error("feed {0} mm/min: expected a finite positive speed")]
    Feed(Real),
    /// The table has no readings.
    #[error("the table has no readings")]
    Empty,
    /// A reading holds a value that is not a finite number.
    #[error("reading {0}: the angle or the deviation is not a finite number")]
    NotFinite(usize),
    /// A sense with too few readings.
    #[error(
        "the {sense} trace has {n} reading(s): a circular test needs at least {MIN_READINGS} in each sense present"
    )]
    TooFewReadings {
        /// `ccw` or `cw`.
        sense: &'static str,
        /// How many it has.
        n: usize,
    },
    /// A sense covers too small an arc to fit a circle to.
    #[error(
        "the {sense} trace covers only {span_deg:.1}° of arc: fitting the centre needs at least {MIN_SPAN_DEG}°"
    )]
    SpanTooSmall {
        /// `ccw` or `cw`.
        sense: &'static str,
        /// Its span (°).
        span_deg: Real,
    },
}

/// A term of the radial deviation model; see the module docs for each one's convention.
/// `Lobes`, `RadiusDrift` and `SenseRadius` are not ISO diagnostics; discovery uses them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Term {
    /// c₀ (m): 1.
    Radius,
    /// c_p (m): cos θ.
    CentreP,
    /// c_q (m): sin θ.
    CentreQ,
    /// s (rad): (R/2)·sin 2θ.
    Squareness,
    /// Δk = k_p − k_q: (R/2)·cos 2θ.
    ScaleMismatch,
    /// Δτ = τ_p − τ_q (s): σ·(v/2)·sin 2θ.
    ServoMismatch,
    /// b_p (m): σ·sgn(sin θ_p)·cos θ/2, θ_p = θ − σ·v·δ_p/R.
    BacklashP,
    /// b_q (m): −σ·sgn(cos θ_q)·sin θ/2, θ_q = θ − σ·v·δ_q/R.
    BacklashQ,
    /// l_p (m): σ·sgn(sin θ_p)·sin θ/2 (σ·|sin θ|/2 at δ_p = 0).
    LateralPlayP,
    /// l_q (m): −σ·sgn(cos θ_q)·cos θ/2 (−σ·|cos θ|/2 at δ_q = 0).
    LateralPlayQ,
    /// S_p (m): sin³θ.
    StraightnessP,
    /// S_q (m): cos³θ.
    StraightnessQ,
    /// h_p (m): |cos θ|·e^(−Δt/τ_p) after a crossed (actual) reversal of p; decay searched.
    ReversalSpikeP,
    /// h_q (m): |sin θ|·e^(−Δt/τ_q) after a crossed (actual) reversal of q; decay searched.
    ReversalSpikeQ,
    /// α, β (m): cos θ·sin(2πp/P), cos θ·cos(2πp/P), p = R·cos θ; period searched.
    CyclicP,
    /// α, β (m): sin θ·sin(2πq/P), sin θ·cos(2πq/P), q = R·sin θ; period searched.
    CyclicQ,
    /// a, b (m): sin kθ, cos kθ, k ≥ 3 lobes searched.
    Lobes,
    /// Rate (m/s): time since the first reading.
    RadiusDrift,
    /// ccw − cw radius (m): σ/2.
    SenseRadius,
}

impl Term {
    /// The ISO diagnostics in order of importance (an unidentifiable group loses its last).
    pub const DIAGNOSTICS: [Term; 16] = [
        Term::Radius,
        Term::CentreP,
        Term::CentreQ,
        Term::Squareness,
        Term::ScaleMismatch,
        Term::ServoMismatch,
        Term::BacklashP,
        Term::BacklashQ,
        Term::LateralPlayP,
        Term::LateralPlayQ,
        Term::StraightnessP,
        Term::StraightnessQ,
        Term::ReversalSpikeP,
        Term::ReversalSpikeQ,
        Term::CyclicP,
        Term::CyclicQ,
    ];

    /// The number of linear coefficients (columns).
    pub fn columns(self) -> usize {
        match self {
            Term::CyclicP | Term::CyclicQ | Term::Lobes => 2,
            _ => 1,
        }
    }

    /// Whether the term has a searched shape parameter (decay, period, lobes).
    pub fn searched(self) -> bool {
        matches!(
            self,
            Term::ReversalSpikeP
                | Term::ReversalSpikeQ
                | Term::CyclicP
                | Term::CyclicQ
                | Term::Lobes
        )
    }

    /// The axis (0 = p, 1 = q) whose actual reversal the term acts at: backlash, lateral play
    /// and spike, located with the axis's reversal lag.
    pub fn reversal_axis(self) -> Option<usize> {
        match self {
            Term::BacklashP | Term::LateralPlayP | Term::ReversalSpikeP => Some(0),
            Term::BacklashQ | Term::LateralPlayQ | Term::ReversalSpikeQ => Some(1),
            _ => None,
        }
    }

    /// Whether the term changes sign with the sense (needs both senses).
    pub fn sense_dependent(self) -> bool {
        matches!(
            self,
            Term::ServoMismatch | Term::LateralPlayP | Term::LateralPlayQ | Term::SenseRadius
        )
    }

    /// The name with the plane's axis letters, without unit (`backlash_x`).
    pub fn name(self, plane: Plane) -> String {
        let p = plane.first().letter().to_ascii_lowercase();
        let q = plane.second().letter().to_ascii_lowercase();
        match self {
            Term::Radius => "radius_deviation".into(),
            Term::CentreP => format!("centre_offset_{p}"),
            Term::CentreQ => format!("centre_offset_{q}"),
            Term::Squareness => "squareness".into(),
            Term::ScaleMismatch => "scale_mismatch".into(),
            Term::ServoMismatch => "servo_mismatch".into(),
            Term::BacklashP => format!("backlash_{p}"),
            Term::BacklashQ => format!("backlash_{q}"),
            Term::LateralPlayP => format!("lateral_play_{p}"),
            Term::LateralPlayQ => format!("lateral_play_{q}"),
            Term::StraightnessP => format!("straightness_{p}"),
            Term::StraightnessQ => format!("straightness_{q}"),
            Term::ReversalSpikeP => format!("reversal_spike_{p}"),
            Term::ReversalSpikeQ => format!("reversal_spike_{q}"),
            Term::CyclicP => format!("cyclic_{p}"),
            Term::CyclicQ => format!("cyclic_{q}"),
            Term::Lobes => "lobes".into(),
            Term::RadiusDrift => "radius_drift".into(),
            Term::SenseRadius => "sense_radius".into(),
        }
    }

    /// The file unit's suffix and the factor from SI to it.
    pub fn unit(self) -> (&'static str, Real) {
        match self {
            Term::Squareness => ("um_per_m", 1e6),
            Term::ScaleMismatch => ("ppm", 1e6),
            Term::ServoMismatch => ("ms", 1e3),
            Term::RadiusDrift => ("um_per_min", 60e6),
            _ => ("um", 1e6),
        }
    }

    /// The report key: name and unit (`backlash_x_um`).
    pub fn key(self, plane: Plane) -> String {
        format!("{}_{}", self.name(plane), self.unit().0)
    }

    /// What the parameter means, in p/q terms (the legend).
    pub fn convention(self) -> &'static str {
        match self {
            Term::Radius => "constant radial deviation c0 (bar length error, mean scale)",
            Term::CentreP => "centre of the machine's circle relative to the centre ball, along p",
            Term::CentreQ => "centre of the machine's circle relative to the centre ball, along q",
            Term::Squareness => {
                "squareness s, + when the angle between +p and +q travel is less than 90°: (R·s/2)·sin 2θ"
            }
            Term::ScaleMismatch => "scale mismatch Δk = kp − kq: (R·Δk/2)·cos 2θ",
            Term::ServoMismatch => {
                "servo mismatch Δτ = τp − τq (lag times 1/Kv), + when p lags more: σ·(v·Δτ/2)·sin 2θ"
            }
            Term::BacklashP => {
                "backlash bp: p lags the command by bp/2 against its travel; steps where p actually reverses, 0°/180° + its reversal lag: +σ·sgn(sin θ)·cos θ·bp/2"
            }
            Term::BacklashQ => {
                "backlash bq: q lags the command by bq/2 against its travel; steps where q actually reverses, 90°/270° + its reversal lag: −σ·sgn(cos θ)·sin θ·bq/2"
            }
            Term::LateralPlayP => {
                "lateral play lp: the p carriage shifts along q by −sgn(ṗ)·lp/2: +σ·|sin θ|·lp/2"
            }
            Term::LateralPlayQ => {
                "lateral play lq: the q carriage shifts along p by −sgn(q̇)·lq/2: −σ·|cos θ|·lq/2"
            }
            Term::StraightnessP => {
                "straightness Sp of p along q, a bow (peak-to-valley over the diameter, middle toward +q): Sp·sin³θ"
            }
            Term::StraightnessQ => {
                "straightness Sq of q along p, a bow (middle toward +p): Sq·cos³θ"
            }
            Term::ReversalSpikeP => {
                "reversal spike hp of p (+ outward), decaying with τp after each crossed reversal (0°/180° + its reversal lag): hp·|cos θ|·exp(−Δt/τp)"
            }
            Term::ReversalSpikeQ => {
                "reversal spike hq of q (+ outward), decaying with τq after each crossed reversal (90°/270° + its reversal lag): hq·|sin θ|·exp(−Δt/τq)"
            }
            Term::CyclicP => {
                "cyclic error of p, A·sin(2π·p/P + φ) along p, p = R·cos θ from the circle centre"
            }
            Term::CyclicQ => {
                "cyclic error of q, A·sin(2π·q/P + φ) along q, q = R·sin θ from the circle centre"
            }
            Term::Lobes => "k lobes per turn at fixed angles: A·sin(kθ + φ)",
            Term::RadiusDrift => "radius changing linearly with time since the first reading",
            Term::SenseRadius => "radius of the ccw trace minus that of the cw trace: σ·Δ/2",
        }
    }
}

/// The searched shape parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Reversal lags δ_p, δ_q (s): from the programmed reversal of the axis to its actual
    /// one, where its backlash, lateral play and spike act.
    pub lag: [Real; 2],
    /// Spike decay times τ_p, τ_q (s).
    pub decay: [Real; 2],
    /// Cyclic periods P_p, P_q (m).
    pub period: [Real; 2],
    /// Number of lobes per turn.
    pub lobes: u32,
}

impl Default for Shape {
    fn default() -> Shape {
        Shape {
            lag: [0.0; 2],
            decay: [0.02; 2],
            period: [0.01; 2],
            lobes: 3,
        }
    }
}

/// A reading's place on the circle, as the diagnostic columns need it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasisPoint {
    /// θ (rad, in [0, 2π)).
    pub angle: Real,
    /// σ: +1 ccw, −1 cw.
    pub sense: Real,
    /// Time since the first reading (s): the table's, else spread over the readings in file
    /// order at the feed.
    pub time: Real,
    /// Whether the trace crossed the last reversal of p (index 0) and of q (index 1) before
    /// this reading; spike columns are zero where it did not.
    pub crossed: [bool; 2],
    /// sin θ and cos θ, computed once (every column needs them).
    sin_cos: (Real, Real),
}

impl BasisPoint {
    /// A reading at `angle` (rad) in sense `sense` (±1), `time` (s) into the test.
    pub fn new(angle: Real, sense: Real, time: Real, crossed: [bool; 2]) -> BasisPoint {
        BasisPoint {
            angle,
            sense,
            time,
            crossed,
            sin_cos: angle.sin_cos(),
        }
    }
}

/// The arc (rad) travelled since the last actual reversal of p (`axis` 0, programmed at 0°
/// and 180°) or of q (1, at 90° and 270°), in the sense of travel, in [0, π): the programmed
/// reversal delayed by the axis's lag `shape.lag[axis]`.
pub fn arc_since_reversal(
    axis: usize,
    at: &BasisPoint,
    test: &CircularTest,
    shape: &Shape,
) -> Real {
    let offset = if axis == 0 { 0.0 } else { FRAC_PI_2 };
    (at.sense * (at.angle - offset) - test.feed * shape.lag[axis] / test.radius).rem_euclid(PI)
}

/// sgn(sin θ_p) for `axis` 0, sgn(cos θ_q) for 1, with θ_a = θ − σ·v·δ_a/R the angle the axis
/// has actually reached (δ_a its reversal lag): ∓σ times the axis's direction of travel.
fn travel(axis: usize, at: &BasisPoint, test: &CircularTest, shape: &Shape) -> Real {
    let angle = at.angle - at.sense * test.feed * shape.lag[axis] / test.radius;
    signum(if axis == 0 { angle.sin() } else { angle.cos() })
}

/// Column `index` of `term` at `at` (radial deviation per unit of the term's SI parameter).
pub fn diagnostic_column(
    term: Term,
    index: usize,
    at: &BasisPoint,
    test: &CircularTest,
    shape: &Shape,
) -> Real {
    let (sin, cos) = at.sin_cos;
    let sigma = at.sense;
    let r = test.radius;
    match term {
        Term::Radius => 1.0,
        Term::CentreP => cos,
        Term::CentreQ => sin,
        Term::Squareness => r * sin * cos,
        Term::ScaleMismatch => r / 2.0 * (cos * cos - sin * sin),
        Term::ServoMismatch => sigma * test.feed * sin * cos,
        Term::BacklashP => sigma * travel(0, at, test, shape) * cos / 2.0,
        Term::BacklashQ => -sigma * travel(1, at, test, shape) * sin / 2.0,
        Term::LateralPlayP => sigma * travel(0, at, test, shape) * sin / 2.0,
        Term::LateralPlayQ => -sigma * travel(1, at, test, shape) * cos / 2.0,
        Term::StraightnessP => sin * sin * sin,
        Term::StraightnessQ => cos * cos * cos,
        Term::ReversalSpikeP | Term::ReversalSpikeQ => {
            let axis = usize::from(term == Term::ReversalSpikeQ);
            spike(axis, at, test, shape).map_or(0.0, |(value, _)| value)
        }
        Term::CyclicP | Term::CyclicQ => {
            let c = if term == Term::CyclicP { cos } else { sin };
            let phase = TAU * r * c / shape.period[usize::from(term == Term::CyclicQ)];
            c * if index == 0 { phase.sin() } else { phase.cos() }
        }
        Term::Lobes => {
            let phase = Real::from(shape.lobes) * at.angle;
            if index == 0 { phase.sin() } else { phase.cos() }
        }
        Term::RadiusDrift => at.time,
        Term::SenseRadius => sigma / 2.0,
    }
}

/// The sign function, 0 at 0.
fn signum(x: Real) -> Real {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The spike column of `axis` at `at` and the time since the actual reversal (s), when the
/// reversal was crossed and is less than [`SPIKE_DECAYS`] decays ago.
fn spike(axis: usize, at: &BasisPoint, test: &CircularTest, shape: &Shape) -> Option<(Real, Real)> {
    if !at.crossed[axis] {
        return None;
    }
    let tau = shape.decay[axis];
    let dt = test.radius * arc_since_reversal(axis, at, test, shape) / test.feed;
    (dt < SPIKE_DECAYS * tau).then(|| {
        let (sin, cos) = at.sin_cos;
        let weight = if axis == 0 { cos.abs() } else { sin.abs() };
        (weight * (-dt / tau).exp(), dt)
    })
}

/// The searched parameters' ranges for a table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchRanges {
    /// Reversal lag (s): shortest (0) and longest.
    pub lag: (Real, Real),
    /// Spike decay (s): shortest and longest.
    pub decay: (Real, Real),
    /// Cyclic period (m): shortest and longest.
    pub period: (Real, Real),
    /// Lobes per turn: fewest and most.
    pub lobes: (u32, u32),
}

/// A table prepared for fitting: its readings as basis points and deviations.
#[derive(Clone, Debug, PartialEq)]
pub struct CircleData {
    /// The test conditions.
    pub test: CircularTest,
    /// Every reading's place on the circle, in file order.
    pub points: Vec<BasisPoint>,
    /// Every reading's deviation (m).
    pub deviation: Vec<Real>,
    /// The searched parameters' ranges.
    pub ranges: SearchRanges,
    /// Readings per sense (ccw, cw).
    pub counts: [usize; 2],
    /// Angular span per sense (rad), when present.
    pub spans: [Option<Real>; 2],
}

/// Index of a sense: ccw 0, cw 1.
fn sense_index(sense: Real) -> usize {
    usize::from(sense < 0.0)
}

const SENSE_NAMES: [&str; 2] = ["ccw", "cw"];

/// The arc that angles in [0, 2π) cover (rad): where it starts (the angle after the largest
/// gap, the wrap at 360° included) and its span (2π less that gap). Empty input: (0, 0).
pub fn covered_arc(angles: &[Real]) -> (Real, Real) {
    let mut sorted = angles.to_vec();
    sorted.sort_by(Real::total_cmp);
    let (Some(&first), Some(&last)) = (sorted.first(), sorted.last()) else {
        return (0.0, 0.0);
    };
    let (mut largest, mut start) = (first + TAU - last, first);
    for pair in sorted.windows(2) {
        if pair[1] - pair[0] > largest {
            largest = pair[1] - pair[0];
            start = pair[1];
        }
    }
    (start, TAU - largest)
}

impl CircleData {
    /// Checks `table` and `test` and prepares the readings.
    pub fn new(table: &BallbarTable, test: &CircularTest) -> Result<CircleData, BallbarError> {
        if !(test.radius.is_finite() && test.radius > 0.0) {
            return Err(BallbarError::Radius(test.radius / M_PER_MM));
        }
        if !(test.feed.is_finite() && test.feed > 0.0) {
            return Err(BallbarError::Feed(test.feed / M_PER_MM * 60.0));
        }
        if table.readings.is_empty() {
            return Err(BallbarError::Empty);
        }
        if let Some(k) = table.readings.iter().position(|r| {
            !(r.angle.is_finite()
                && r.deviation.is_finite()
                && r.time.is_none_or(|t| t.is_finite()))
        }) {
            return Err(BallbarError::NotFinite(k + 1));
        }
        let n = table.readings.len();
        let sense: Vec<Real> = table.readings.iter().map(|r| r.sense.sign()).collect();
        let angle: Vec<Real> = table
            .readings
            .iter()
            .map(|r| r.angle.rem_euclid(TAU) % TAU)
            .collect();
        let mut counts = [0; 2];
        let mut spans = [None; 2];
        let mut test_time = 0.0;
        for s in 0..2 {
            let angles: Vec<Real> = (0..n)
                .filter(|&i| sense_index(sense[i]) == s)
                .map(|i| angle[i])
                .collect();
            counts[s] = angles.len();
            if angles.is_empty() {
                continue;
            }
            if angles.len() < MIN_READINGS {
                return Err(BallbarError::TooFewReadings {
                    sense: SENSE_NAMES[s],
                    n: angles.len(),
                });
            }
            let (_, span) = covered_arc(&angles);
            if span < MIN_SPAN_DEG * RAD_PER_DEG {
                return Err(BallbarError::SpanTooSmall {
                    sense: SENSE_NAMES[s],
                    span_deg: span / RAD_PER_DEG,
                });
            }
            spans[s] = Some(span);
            test_time += span * test.radius / test.feed;
        }
        let timed = table.readings.iter().all(|r| r.time.is_some());
        let time: Vec<Real> = if timed {
            let start = table
                .readings
                .iter()
                .filter_map(|r| r.time)
                .fold(Real::INFINITY, Real::min);
            table
                .readings
                .iter()
                .map(|r| r.time.unwrap_or(start) - start)
                .collect()
        } else {
            (0..n).map(|i| test_time * i as Real / n as Real).collect()
        };
        // crossed[sense][reversal k at k·90°]: readings of the sense just before it.
        let mut crossed = [[false; 4]; 2];
        for i in 0..n {
            let s = sense_index(sense[i]);
            for (k, flag) in crossed[s].iter_mut().enumerate() {
                let before = (sense[i] * (k as Real * FRAC_PI_2 - angle[i])).rem_euclid(TAU);
                if before > 0.0 && before <= CROSSING_WINDOW {
                    *flag = true;
                }
            }
        }
        let unlagged = Shape::default();
        let points: Vec<BasisPoint> = (0..n)
            .map(|i| {
                let mut point = BasisPoint::new(angle[i], sense[i], time[i], [false; 2]);
                for axis in 0..2 {
                    let reversal = (angle[i]
                        - sense[i] * arc_since_reversal(axis, &point, test, &unlagged))
                    .rem_euclid(TAU);
                    let k = (reversal / FRAC_PI_2).round() as usize % 4;
                    point.crossed[axis] = crossed[sense_index(sense[i])][k];
                }
                point
            })
            .collect();
        let ranges = Self::ranges(&points, test, n);
        Ok(CircleData {
            test: *test,
            points,
            deviation: table.readings.iter().map(|r| r.deviation).collect(),
            ranges,
            counts,
            spans,
        })
    }

    /// The searched parameters' ranges: reversal lags from 0 and decays from max(1 ms, two
    /// sampling intervals), both to min(200 ms, time for 30° of arc); periods from max(1 mm,
    /// 4 sample spacings) to R/2; lobes from 3 to min(60, a quarter of the readings per turn).
    fn ranges(points: &[BasisPoint], test: &CircularTest, n: usize) -> SearchRanges {
        let mut steps: Vec<Real> = points
            .windows(2)
            .filter(|w| w[0].sense == w[1].sense)
            .map(|w| w[1].time - w[0].time)
            .filter(|dt| *dt > 0.0)
            .collect();
        steps.sort_by(Real::total_cmp);
        let interval = steps.get(steps.len() / 2).copied().unwrap_or(0.0);
        let spacing = interval * test.feed;
        let per_turn = (n as Real / 2.0).max(1.0);
        let longest = DECAY_MAX.min(DECAY_ARC * test.radius / test.feed);
        SearchRanges {
            lag: (0.0, longest),
            decay: (DECAY_MIN.max(2.0 * interval), longest),
            period: (PERIOD_MIN.max(4.0 * spacing), test.radius / 2.0),
            lobes: (3, LOBES_MAX.min((per_turn / 4.0) as u32)),
        }
    }

    /// The number of readings.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether there are no readings.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Whether both senses are present.
    pub fn both_senses(&self) -> bool {
        self.counts[0] > 0 && self.counts[1] > 0
    }

    /// Why `term` cannot be fitted to these data at all, if it cannot (both senses needed, no
    /// crossed reversal, sampling too coarse for the searched range).
    pub fn structural(&self, term: Term) -> Option<String> {
        let plane = self.test.plane;
        if term.sense_dependent() && !self.both_senses() {
            let like = match term {
                Term::ServoMismatch => "squareness",
                Term::SenseRadius => "the radius",
                _ => "the radius and the scale mismatch",
            };
            return Some(format!(
                "needs both senses: in one sense it cannot be told from {like}"
            ));
        }
        match term {
            Term::ReversalSpikeP | Term::ReversalSpikeQ => {
                let axis = usize::from(term == Term::ReversalSpikeQ);
                let letter = if axis == 0 {
                    plane.first()
                } else {
                    plane.second()
                };
                let (low, high) = self.ranges.decay;
                if low >= high {
                    return Some(format!(
                        "the readings are {:.1} ms apart: too coarse for decays up to {:.1} ms",
                        low * 1e3,
                        high * 1e3
                    ));
                }
                let near = self
                    .points
                    .iter()
                    .filter(|p| {
                        p.crossed[axis]
                            && self.test.radius
                                * arc_since_reversal(axis, p, &self.test, &Shape::default())
                                / self.test.feed
                                < 3.0 * high
                    })
                    .count();
                (near < MIN_SPIKE_READINGS).then(|| {
                    format!(
                        "{near} reading(s) follow a crossed reversal of {letter} within {:.0} ms (at least {MIN_SPIKE_READINGS} needed)",
                        3e3 * high
                    )
                })
            }
            Term::CyclicP | Term::CyclicQ => {
                let (low, high) = self.ranges.period;
                (low >= high).then(|| {
                    format!(
                        "the readings are too far apart for periods up to {:.1} mm",
                        high / M_PER_MM
                    )
                })
            }
            Term::Lobes => {
                let (low, high) = self.ranges.lobes;
                (low > high).then(|| "too few readings per turn for 3 or more lobes".into())
            }
            _ => None,
        }
    }

    /// The terms of `terms` (in order of importance) these data cannot tell from the others,
    /// with the reason: a column whose variance the others inflate more than
    /// [`MAX_VARIANCE_INFLATION`] times costs its near-collinear group its least important
    /// member. Shapes of searched terms as in `shape`.
    pub fn unidentifiable(&self, terms: &[Term], shape: &Shape) -> Vec<(Term, String)> {
        screen(self, terms, shape)
    }

    /// Column `index` of `term` over `rows`.
    fn column_on(&self, term: Term, index: usize, shape: &Shape, rows: &[usize]) -> Vec<Real> {
        rows.iter()
            .map(|&i| diagnostic_column(term, index, &self.points[i], &self.test, shape))
            .collect()
    }

    /// Every column of `terms`, in order, over `rows`.
    fn columns_on(&self, terms: &[Term], shape: &Shape, rows: &[usize]) -> Vec<Vec<Real>> {
        terms
            .iter()
            .flat_map(|&t| (0..t.columns()).map(move |k| (t, k)))
            .map(|(t, k)| self.column_on(t, k, shape, rows))
            .collect()
    }

    /// Fits `terms` to the readings where `train` is true: every searched parameter (the
    /// reversal lag of each axis with a reversal term, then the searched terms' shapes in the
    /// order of `terms`; twice over when there are several, each with the others held), then
    /// the linear coefficients. Residuals are given for every reading.
    pub fn fit(&self, terms: &[Term], train: &[bool]) -> ModelFit {
        let rows: Vec<usize> = (0..self.len()).filter(|&i| train[i]).collect();
        let y: Vec<Real> = rows.iter().map(|&i| self.deviation[i]).collect();
        let mut shape = Shape::default();
        let mut searches: Vec<Search> = (0..2)
            .filter(|&a| terms.iter().any(|t| t.reversal_axis() == Some(a)))
            .map(Search::Lag)
            .collect();
        searches.extend(
            terms
                .iter()
                .copied()
                .filter(|t| t.searched())
                .map(Search::Shape),
        );
        let linear: Vec<Term> = terms.iter().copied().filter(|t| !t.searched()).collect();
        let mut done: Vec<Term> = Vec::new();
        let passes = if searches.len() > 1 { 2 } else { 1 };
        for pass in 0..passes {
            for &search in &searches {
                match search {
                    Search::Lag(axis) => {
                        let (fixed, moving) = self.split_reversal(axis, terms, &shape, &rows, &y);
                        let profile = self.lag_profile(axis, &moving, &fixed, &rows, &shape);
                        shape.lag[axis] = self.search_lag(&profile);
                    }
                    Search::Shape(term) => {
                        let fixed_terms: Vec<Term> = linear
                            .iter()
                            .chain(done.iter().filter(|&&t| t != term))
                            .copied()
                            .collect();
                        let fixed =
                            Projection::new(self.columns_on(&fixed_terms, &shape, &rows), &y);
                        self.search(term, &fixed, &rows, &mut shape, pass > 0);
                        if !done.contains(&term) {
                            done.push(term);
                        }
                    }
                }
            }
        }
        let all: Vec<usize> = (0..self.len()).collect();
        let columns = self.columns_on(terms, &shape, &all);
        let training: Vec<Vec<Real>> = columns
            .iter()
            .map(|c| rows.iter().map(|&i| c[i]).collect())
            .collect();
        let coefficients = Projection::new(training, &y).coefficients;
        let residuals = (0..self.len())
            .map(|i| {
                self.deviation[i]
                    - columns
                        .iter()
                        .zip(&coefficients)
                        .map(|(c, k)| c[i] * k)
                        .sum::<Real>()
            })
            .collect();
        ModelFit {
            terms: terms.to_vec(),
            shape,
            coefficients,
            residuals,
        }
    }

    /// The fit of every term of `terms` but `axis`'s reversal terms (over `rows`), and those
    /// reversal terms.
    fn split_reversal(
        &self,
        axis: usize,
        terms: &[Term],
        shape: &Shape,
        rows: &[usize],
        y: &[Real],
    ) -> (Projection, Vec<Term>) {
        let (moving, fixed): (Vec<Term>, Vec<Term>) = terms
            .iter()
            .copied()
            .partition(|t| t.reversal_axis() == Some(axis));
        (
            Projection::new(self.columns_on(&fixed, shape, rows), y),
            moving,
        )
    }

    /// The joint residual sum of squares of `axis`'s reversal terms `moving` against `fixed`
    /// as a function of the axis's lag. A lag moves these columns only on the rows within
    /// the longest lag (and the spike's window) after a programmed reversal: the sums over
    /// the other rows are taken once.
    fn lag_profile<'a>(
        &'a self,
        axis: usize,
        moving: &'a [Term],
        fixed: &'a Projection,
        rows: &'a [usize],
        shape: &Shape,
    ) -> LagProfile<'a> {
        let unlagged = Shape {
            lag: [0.0; 2],
            ..*shape
        };
        let reach = self.test.feed / self.test.radius
            * (self.ranges.lag.1
                + if moving.iter().any(|t| t.searched()) {
                    SPIKE_DECAYS * shape.decay[axis]
                } else {
                    0.0
                });
        let (near, far): (Vec<usize>, Vec<usize>) = (0..rows.len()).partition(|&j| {
            arc_since_reversal(axis, &self.points[rows[j]], &self.test, &unlagged) <= reach
        });
        let far_rows: Vec<usize> = far.iter().map(|&j| rows[j]).collect();
        let columns = self.columns_on(moving, shape, &far_rows);
        let (k, m) = (fixed.columns.len(), columns.len());
        let fb = DMatrix::from_fn(k, m, |i, c| {
            far.iter()
                .zip(&columns[c])
                .map(|(&j, v)| fixed.columns[i][j] * v)
                .sum()
        });
        let bb = DMatrix::from_fn(m, m, |a, b| dot(&columns[a], &columns[b]));
        let br = (0..m)
            .map(|c| {
                far.iter()
                    .zip(&columns[c])
                    .map(|(&j, v)| fixed.residual[j] * v)
                    .sum()
            })
            .collect();
        LagProfile {
            data: self,
            axis,
            moving,
            fixed,
            rows,
            shape: *shape,
            near,
            far: (fb, bb, br),
        }
    }

    /// Searches `axis`'s reversal lag (s): a grid of [`LAG_GRID`] points over the range,
    /// golden section between the best point's neighbours, then the middle of the interval
    /// where the residual sum of squares stays at that minimum. A sampled trace cannot tell
    /// where between two samples an axis reversed (a step, or a spike's onset, reads the
    /// same): the middle is the unbiased choice.
    fn search_lag(&self, profile: &LagProfile<'_>) -> Real {
        let (low, high) = self.ranges.lag;
        let grid: Vec<Real> = (0..LAG_GRID)
            .map(|k| low + (high - low) * k as Real / (LAG_GRID - 1) as Real)
            .collect();
        let values: Vec<Real> = grid.iter().map(|&g| profile.rss(g)).collect();
        let best = (0..LAG_GRID)
            .min_by(|&a, &b| values[a].total_cmp(&values[b]))
            .unwrap_or(0);
        let (a, b) = (
            grid[best.saturating_sub(1)],
            grid[(best + 1).min(LAG_GRID - 1)],
        );
        let (refined, value) = golden_minimum(|g| profile.rss(g), a, b, GOLDEN_ITERATIONS);
        let (lag, value) = if value < values[best] {
            (refined, value)
        } else {
            (grid[best], values[best])
        };
        let flat = value + 1e-9 * profile.fixed.rss;
        let (from, to) = interval(|g| profile.rss(g), lag, flat, low, high);
        (from + to) / 2.0
    }

    /// The standard uncertainty of `axis`'s reversal lag in `fit` (s): half the width of the
    /// profile-likelihood interval where the residual sum of squares stays within `variance`
    /// (σ̂²) of its minimum (Δχ² = 1), each side found by bisection. For a step sampled every
    /// Δt it is at least about Δt/2: the data cannot place the step better.
    fn lag_uncertainty(&self, axis: usize, fit: &ModelFit, variance: Real) -> Real {
        let rows: Vec<usize> = (0..self.len()).collect();
        let (fixed, moving) =
            self.split_reversal(axis, &fit.terms, &fit.shape, &rows, &self.deviation);
        let profile = self.lag_profile(axis, &moving, &fixed, &rows, &fit.shape);
        let best = fit.shape.lag[axis];
        let target = profile.rss(best) + variance;
        let (low, high) = self.ranges.lag;
        let (from, to) = interval(|g| profile.rss(g), best, target, low, high);
        (to - from) / 2.0
    }

    /// Searches `term`'s shape parameter on the joint residual sum of squares with `fixed`
    /// (the other columns); `refine` only polishes the current value.
    fn search(
        &self,
        term: Term,
        fixed: &Projection,
        rows: &[usize],
        shape: &mut Shape,
        refine: bool,
    ) {
        let rss = |trial: &Shape| -> Real {
            let columns: Vec<Vec<Real>> = (0..term.columns())
                .map(|k| self.column_on(term, k, trial, rows))
                .collect();
            let views: Vec<&[Real]> = columns.iter().map(Vec::as_slice).collect();
            fixed.rss_with(&views)
        };
        match term {
            Term::ReversalSpikeP | Term::ReversalSpikeQ => {
                let axis = usize::from(term == Term::ReversalSpikeQ);
                // The column is zero but within the longest decay's window after a crossed
                // reversal: only those rows are evaluated.
                let longest = Shape {
                    decay: [self.ranges.decay.1; 2],
                    ..*shape
                };
                let window: Vec<usize> = (0..rows.len())
                    .filter(|&j| spike(axis, &self.points[rows[j]], &self.test, &longest).is_some())
                    .collect();
                let window_rows: Vec<usize> = window.iter().map(|&j| rows[j]).collect();
                let at = |tau: Real| {
                    let mut trial = *shape;
                    trial.decay[axis] = tau;
                    let column = self.column_on(term, 0, &trial, &window_rows);
                    fixed.rss_with_sparse(&window, &column)
                };
                let (low, high) = (self.ranges.decay.0.ln(), self.ranges.decay.1.ln());
                let grid: Vec<Real> = (0..DECAY_GRID)
                    .map(|k| low + (high - low) * k as Real / (DECAY_GRID - 1) as Real)
                    .collect();
                let values: Vec<Real> = grid.iter().map(|g| at(g.exp())).collect();
                let best = (0..DECAY_GRID)
                    .min_by(|&a, &b| values[a].total_cmp(&values[b]))
                    .unwrap_or(0);
                let (a, b) = (
                    grid[best.saturating_sub(1)],
                    grid[(best + 1).min(DECAY_GRID - 1)],
                );
                let (refined, value) = golden_minimum(|g| at(g.exp()), a, b, GOLDEN_ITERATIONS);
                shape.decay[axis] = if value < values[best] {
                    refined.exp()
                } else {
                    grid[best].exp()
                };
            }
            Term::CyclicP | Term::CyclicQ => {
                let axis = usize::from(term == Term::CyclicQ);
                let (f_low, f_high, step, _) = self.frequency_grid();
                let peak = if refine {
                    1.0 / shape.period[axis]
                } else {
                    1.0 / self.cyclic_periodogram(term, rows, &fixed.residual).0
                };
                let at = |f: Real| {
                    let mut trial = *shape;
                    trial.period[axis] = 1.0 / f;
                    rss(&trial)
                };
                let (refined, value) = golden_minimum(
                    at,
                    (peak - step).max(f_low),
                    (peak + step).min(f_high),
                    GOLDEN_ITERATIONS,
                );
                shape.period[axis] = if value < at(peak) {
                    1.0 / refined
                } else {
                    1.0 / peak
                };
            }
            Term::Lobes => {
                // All counts on the first pass; two either side of the current one after.
                let (low, high) = if refine {
                    (
                        shape.lobes.saturating_sub(2).max(self.ranges.lobes.0),
                        (shape.lobes + 2).min(self.ranges.lobes.1),
                    )
                } else {
                    self.ranges.lobes
                };
                let mut best = (low, Real::INFINITY);
                self.each_lobe_count(rows, low, high, |k, sin, cos| {
                    let value = fixed.rss_with(&[sin, cos]);
                    if value < best.1 {
                        best = (k, value);
                    }
                });
                shape.lobes = best.0;
            }
            _ => {}
        }
    }

    /// How many standard uncertainties a searched amplitude must reach to be significant: 2
    /// for a spike; for a cyclic term, whose period is the best of the M periods the search
    /// tests, the level √(2·ln(M/0.05)) that a noise-only amplitude (A/u Rayleigh-distributed,
    /// P(A/u > x) = e^(−x²/2)) exceeds at any of them with probability at most 5 %
    /// (Bonferroni), and at least 2.
    pub fn significance(&self, term: Term) -> Real {
        match term {
            Term::CyclicP | Term::CyclicQ => {
                let tested = self.frequency_grid().3 as Real;
                (2.0 * (tested / CYCLIC_FALSE_ALARM).ln())
                    .sqrt()
                    .max(SIGNIFICANCE)
            }
            _ => SIGNIFICANCE,
        }
    }

    /// The cyclic search's frequencies (1/m): lowest, highest, step (4 per 1/(2R), the
    /// resolution over the diameter) and how many.
    fn frequency_grid(&self) -> (Real, Real, Real, usize) {
        let (low, high) = self.ranges.period;
        let (f_low, f_high) = (1.0 / high, 1.0 / low);
        let step = 1.0 / (8.0 * self.test.radius);
        let count = ((f_high - f_low) / step * (1.0 + 1e-12)).floor().max(0.0) as usize + 1;
        (f_low, f_high, step, count)
    }

    /// The period (m) of `term` (cyclic p or q) whose two columns alone remove the largest
    /// fraction of `residual` (over `rows`), and that fraction: a periodogram over the
    /// frequency grid, phasors advanced by recurrence.
    pub fn cyclic_periodogram(
        &self,
        term: Term,
        rows: &[usize],
        residual: &[Real],
    ) -> (Real, Real) {
        let (f_low, _, step, count) = self.frequency_grid();
        let m = rows.len();
        let (mut zr, mut zi, mut wr, mut wi) =
            (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        let (mut rc, mut cc) = (vec![0.0; m], vec![0.0; m]);
        let total: Real = residual.iter().map(|r| r * r).sum();
        for (j, &i) in rows.iter().enumerate() {
            let (sin, cos) = self.points[i].sin_cos;
            let c = if term == Term::CyclicP { cos } else { sin };
            let x = TAU * self.test.radius * c;
            (zi[j], zr[j]) = (x * f_low).sin_cos();
            (wi[j], wr[j]) = (x * step).sin_cos();
            rc[j] = residual[j] * c;
            cc[j] = c * c;
        }
        let mut best = (f_low, 0.0);
        for k in 0..count {
            let (mut s1, mut s2, mut a11, mut a22, mut a12) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for j in 0..m {
                let (s, c) = (zi[j], zr[j]);
                s1 += rc[j] * s;
                s2 += rc[j] * c;
                a11 += cc[j] * s * s;
                a22 += cc[j] * c * c;
                a12 += cc[j] * s * c;
                let (nr, ni) = (c * wr[j] - s * wi[j], c * wi[j] + s * wr[j]);
                zr[j] = nr;
                zi[j] = ni;
            }
            let det = a11 * a22 - a12 * a12;
            if det > 0.0 && total > 0.0 {
                let reduction = (s1 * s1 * a22 - 2.0 * s1 * s2 * a12 + s2 * s2 * a11) / det;
                let fraction = (reduction / total).clamp(0.0, 1.0);
                if fraction > best.1 {
                    best = (f_low + step * k as Real, fraction);
                }
            }
        }
        (1.0 / best.0, best.1)
    }

    /// The number of lobes k (in the searched range) whose sin kθ, cos kθ alone remove the
    /// largest fraction of `residual` (over `rows`), and that fraction.
    pub fn lobes_periodogram(&self, rows: &[usize], residual: &[Real]) -> (u32, Real) {
        let (low, high) = self.ranges.lobes;
        let mut best = (low, 0.0);
        let total: Real = residual.iter().map(|r| r * r).sum();
        if total <= 0.0 {
            return best;
        }
        self.each_lobe_count(rows, low, high, |k, sin, cos| {
            let fraction =
                Projection::new(vec![sin.to_vec(), cos.to_vec()], residual).explained / total;
            if fraction > best.1 {
                best = (k, fraction);
            }
        });
        best
    }

    /// Calls `f(k, sin kθ, cos kθ)` over `rows` for every lobe count k from `low` to `high`,
    /// the phasors e^(ikθ) advanced by recurrence.
    fn each_lobe_count(
        &self,
        rows: &[usize],
        low: u32,
        high: u32,
        mut f: impl FnMut(u32, &[Real], &[Real]),
    ) {
        let step: Vec<(Real, Real)> = rows.iter().map(|&i| self.points[i].sin_cos).collect();
        let (mut sin, mut cos): (Vec<Real>, Vec<Real>) = rows
            .iter()
            .map(|&i| (Real::from(low) * self.points[i].angle).sin_cos())
            .unzip();
        for k in low..=high {
            f(k, &sin, &cos);
            for ((s, c), (ds, dc)) in sin.iter_mut().zip(cos.iter_mut()).zip(&step) {
                (*s, *c) = (*s * dc + *c * ds, *c * dc - *s * ds);
            }
        }
    }
}

/// The interval around `best` (inside low..high) where `f` stays at or below `target`:
/// each edge by bisection between `best` and the bound (the bound itself when `f` is below
/// `target` there).
fn interval(
    f: impl Fn(Real) -> Real,
    best: Real,
    target: Real,
    low: Real,
    high: Real,
) -> (Real, Real) {
    let edge = |bound: Real| {
        if f(bound) <= target {
            return bound;
        }
        let (mut inside, mut outside) = (best, bound);
        for _ in 0..40 {
            let middle = (inside + outside) / 2.0;
            if f(middle) <= target {
                inside = middle;
            } else {
                outside = middle;
            }
        }
        (inside + outside) / 2.0
    };
    (edge(low), edge(high))
}

/// A searched parameter of a fit: an axis's reversal lag or a searched term's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Search {
    Lag(usize),
    Shape(Term),
}

/// The residual sum of squares as a function of one axis's reversal lag
/// ([`CircleData::lag_profile`]).
struct LagProfile<'a> {
    data: &'a CircleData,
    axis: usize,
    moving: &'a [Term],
    fixed: &'a Projection,
    rows: &'a [usize],
    shape: Shape,
    /// Positions in `rows` near the reversals, where the lag moves the columns.
    near: Vec<usize>,
    /// Fᵀ·B, Bᵀ·B and Bᵀ·r over the other rows.
    far: (DMatrix<Real>, DMatrix<Real>, Vec<Real>),
}

impl LagProfile<'_> {
    /// The residual sum of squares at `lag` (s).
    fn rss(&self, lag: Real) -> Real {
        let mut trial = self.shape;
        trial.lag[self.axis] = lag;
        let near_rows: Vec<usize> = self.near.iter().map(|&j| self.rows[j]).collect();
        let columns = self.data.columns_on(self.moving, &trial, &near_rows);
        let (fb, bb, br) = &self.far;
        let fixed = self.fixed;
        let fb = fb
            + DMatrix::from_fn(fb.nrows(), fb.ncols(), |i, c| {
                self.near
                    .iter()
                    .zip(&columns[c])
                    .map(|(&j, v)| fixed.columns[i][j] * v)
                    .sum::<Real>()
            });
        let bb =
            bb + DMatrix::from_fn(bb.nrows(), bb.ncols(), |a, b| dot(&columns[a], &columns[b]));
        let br: Vec<Real> = br
            .iter()
            .zip(&columns)
            .map(|(far, column)| {
                far + self
                    .near
                    .iter()
                    .zip(column)
                    .map(|(&j, v)| fixed.residual[j] * v)
                    .sum::<Real>()
            })
            .collect();
        fixed.rss_from(&fb, &bb, &br)
    }
}

/// A fitted model of the radial deviation.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelFit {
    /// The terms, in column order.
    pub terms: Vec<Term>,
    /// The searched parameters (meaningful for the searched terms present).
    pub shape: Shape,
    /// Every column's coefficient (SI), terms in order.
    pub coefficients: Vec<Real>,
    /// Measured − predicted for every reading (m).
    pub residuals: Vec<Real>,
}

impl ModelFit {
    /// The radial deviation `term` accounts for at each point of `data` (m), if it is in the
    /// fit: its columns times its coefficients. Over every term of the fit these and the
    /// residuals add up to the measured deviations.
    pub fn contribution(&self, term: Term, data: &CircleData) -> Option<Vec<Real>> {
        let coefficients = self.coefficients_of(term)?;
        Some(
            data.points
                .iter()
                .map(|at| {
                    coefficients
                        .iter()
                        .enumerate()
                        .map(|(k, c)| c * diagnostic_column(term, k, at, &data.test, &self.shape))
                        .sum()
                })
                .collect(),
        )
    }

    /// The coefficients of `term`, if it is in the fit.
    pub fn coefficients_of(&self, term: Term) -> Option<&[Real]> {
        let mut start = 0;
        for &t in &self.terms {
            let end = start + t.columns();
            if t == term {
                return Some(&self.coefficients[start..end]);
            }
            start = end;
        }
        None
    }
}

/// Dot product.
fn dot(a: &[Real], b: &[Real]) -> Real {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The Gram matrix AᵀA of columns over the same rows.
fn gram(columns: &[&[Real]]) -> DMatrix<Real> {
    let k = columns.len();
    let mut g = DMatrix::zeros(k, k);
    for i in 0..k {
        for j in i..k {
            let v = dot(columns[i], columns[j]);
            g[(i, j)] = v;
            g[(j, i)] = v;
        }
    }
    g
}

/// The eigen-decomposition of the Gram matrix with columns scaled to unit norm: scales,
/// eigenvalues, eigenvectors.
fn scaled_eigen(g: &DMatrix<Real>) -> (Vec<Real>, Vec<Real>, DMatrix<Real>) {
    let k = g.nrows();
    let d: Vec<Real> = (0..k)
        .map(|j| {
            let v = g[(j, j)];
            if v > 0.0 { 1.0 / v.sqrt() } else { 0.0 }
        })
        .collect();
    let scaled = DMatrix::from_fn(k, k, |i, j| g[(i, j)] * d[i] * d[j]);
    let eigen = scaled.symmetric_eigen();
    (
        d,
        eigen.eigenvalues.iter().copied().collect(),
        eigen.eigenvectors,
    )
}

/// The pseudo-inverse (AᵀA)⁺ from the Gram matrix, eigenvalues of the column-scaled matrix
/// below [`EIGEN_TOLERANCE`] of the largest treated as zero (zero columns get zero).
fn gram_pinv(g: &DMatrix<Real>) -> DMatrix<Real> {
    let k = g.nrows();
    if k == 0 {
        return DMatrix::zeros(0, 0);
    }
    let (d, values, vectors) = scaled_eigen(g);
    let largest = values.iter().copied().fold(0.0, Real::max);
    DMatrix::from_fn(k, k, |i, j| {
        let sum: Real = values
            .iter()
            .enumerate()
            .filter(|(_, l)| **l > largest * EIGEN_TOLERANCE)
            .map(|(m, l)| vectors[(i, m)] * vectors[(j, m)] / l)
            .sum();
        sum * d[i] * d[j]
    })
}

/// The variance inflation of every column: the diagonal of the inverse of the column-scaled
/// Gram matrix (1 for a column orthogonal to the others; +∞ for one inside their span).
fn variance_inflation(g: &DMatrix<Real>) -> Vec<Real> {
    let k = g.nrows();
    if k == 0 {
        return Vec::new();
    }
    let (d, values, vectors) = scaled_eigen(g);
    let largest = values.iter().copied().fold(0.0, Real::max);
    (0..k)
        .map(|j| {
            if d[j] == 0.0 {
                return Real::INFINITY;
            }
            values
                .iter()
                .enumerate()
                .map(|(m, l)| {
                    let weight = vectors[(j, m)].powi(2);
                    if *l > largest * EIGEN_TOLERANCE {
                        weight / l
                    } else if weight > 1e-6 {
                        Real::INFINITY
                    } else {
                        0.0
                    }
                })
                .sum()
        })
        .collect()
}

/// A least-squares fit of fixed columns, ready to score extra columns quickly.
struct Projection {
    columns: Vec<Vec<Real>>,
    pinv: DMatrix<Real>,
    coefficients: Vec<Real>,
    residual: Vec<Real>,
    rss: Real,
    /// The sum of squares the columns explain (m²).
    explained: Real,
}

impl Projection {
    fn new(columns: Vec<Vec<Real>>, y: &[Real]) -> Projection {
        let views: Vec<&[Real]> = columns.iter().map(Vec::as_slice).collect();
        let pinv = gram_pinv(&gram(&views));
        let b: Vec<Real> = views.iter().map(|c| dot(c, y)).collect();
        let coefficients: Vec<Real> = (0..b.len())
            .map(|i| (0..b.len()).map(|j| pinv[(i, j)] * b[j]).sum())
            .collect();
        let mut residual = y.to_vec();
        for (c, k) in views.iter().zip(&coefficients) {
            for (r, v) in residual.iter_mut().zip(c.iter()) {
                *r -= k * v;
            }
        }
        let rss = dot(&residual, &residual);
        Projection {
            explained: dot(y, y) - rss,
            columns,
            pinv,
            coefficients,
            residual,
            rss,
        }
    }

    /// The residual sum of squares with `extra` columns added: the fixed fit's, less what the
    /// extras' parts orthogonal to the fixed columns explain of its residual.
    fn rss_with(&self, extra: &[&[Real]]) -> Real {
        let (k, m) = (self.columns.len(), extra.len());
        let fb = DMatrix::from_fn(k, m, |i, j| dot(&self.columns[i], extra[j]));
        let bb = DMatrix::from_fn(m, m, |i, j| dot(extra[i], extra[j]));
        let br: Vec<Real> = extra.iter().map(|c| dot(c, &self.residual)).collect();
        self.rss_from(&fb, &bb, &br)
    }

    /// [`Projection::rss_with`] for one extra column that is zero but at `positions` (of the
    /// projection's rows), where it is `values`.
    fn rss_with_sparse(&self, positions: &[usize], values: &[Real]) -> Real {
        let sum =
            |of: &[Real]| -> Real { positions.iter().zip(values).map(|(&j, v)| of[j] * v).sum() };
        let fb = DMatrix::from_fn(self.columns.len(), 1, |i, _| sum(&self.columns[i]));
        let bb = DMatrix::from_element(1, 1, dot(values, values));
        self.rss_from(&fb, &bb, &[sum(&self.residual)])
    }

    /// [`Projection::rss_with`] from the extras' sums: Fᵀ·B (fixed × extra), Bᵀ·B and Bᵀ·r.
    fn rss_from(&self, fb: &DMatrix<Real>, bb: &DMatrix<Real>, br: &[Real]) -> Real {
        let m = br.len();
        let reduced = bb - fb.transpose() * &self.pinv * fb;
        let inverse = gram_pinv(&reduced);
        let explained: Real = (0..m)
            .map(|i| {
                (0..m)
                    .map(|j| br[i] * inverse[(i, j)] * br[j])
                    .sum::<Real>()
            })
            .sum();
        (self.rss - explained).max(0.0)
    }
}

/// One diagnostic's estimate, in the term's SI unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TermEstimate {
    /// The value (the amplitude for a cyclic term).
    pub value: Real,
    /// Its standard uncertainty.
    pub u: Real,
    /// A spike's decay (s) or a cyclic term's period (m) and its uncertainty, when the
    /// amplitude is significant (above twice its uncertainty).
    pub shape: Option<(Real, Real)>,
    /// A cyclic term's phase φ (rad) and its uncertainty, when significant.
    pub phase: Option<(Real, Real)>,
}

/// The diagnostic fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostics {
    /// Every identifiable diagnostic, in the order of [`Term::DIAGNOSTICS`].
    pub estimates: Vec<(Term, TermEstimate)>,
    /// The reversal lag of p and q (s) and its standard uncertainty, when some reversal term
    /// of the axis (backlash, lateral play, spike) is significant.
    pub reversal_lag: [Option<(Real, Real)>; 2],
    /// The diagnostics the data cannot give, with the reason.
    pub unidentifiable: Vec<(Term, String)>,
    /// Remarks (amplitudes that are not significant).
    pub notes: Vec<String>,
    /// RMS of the residual (m).
    pub rms: Real,
    /// n − fitted parameters.
    pub dof: usize,
    /// The fit itself.
    pub fit: ModelFit,
}

impl Diagnostics {
    /// The estimate of `term`, if identifiable.
    pub fn get(&self, term: Term) -> Option<&TermEstimate> {
        self.estimates
            .iter()
            .find(|(t, _)| *t == term)
            .map(|(_, e)| e)
    }
}

/// The ISO 230-4 evaluation and the diagnostics of a ball-bar table.
#[derive(Clone, Debug, PartialEq)]
pub struct BallbarEvaluation {
    /// The test conditions.
    pub test: CircularTest,
    /// Readings per sense (ccw, cw).
    pub counts: [usize; 2],
    /// Angular span per sense (rad).
    pub spans: [Option<Real>; 2],
    /// Circular deviation G of the ccw and cw traces (m).
    pub circular_deviation: [Option<Real>; 2],
    /// Bidirectional circular deviation G(b) (m), with both senses.
    pub bidirectional_deviation: Option<Real>,
    /// Circular hysteresis H (m), with both senses overlapping.
    pub hysteresis: Option<Real>,
    /// Largest and smallest radial deviation F_max, F_min (m), centre removed.
    pub radial_max: Real,
    /// See `radial_max`.
    pub radial_min: Real,
    /// Centre offset of the common first-order fit along p and q (m).
    pub centre_offset: [Real; 2],
    /// Mean radial deviation r₀ of the common fit (m).
    pub mean_radial_deviation: Real,
    /// The diagnostics, or why they were not computed.
    pub diagnostics: Result<Diagnostics, String>,
}

/// Evaluates a ball-bar table to ISO 230-4 and fits the diagnostics.
pub fn evaluate(
    table: &BallbarTable,
    test: &CircularTest,
) -> Result<BallbarEvaluation, BallbarError> {
    let data = CircleData::new(table, test)?;
    let n = data.len();
    let circle = [Term::Radius, Term::CentreP, Term::CentreQ];
    let shape = Shape::default();
    let fit_rows = |rows: &[usize]| -> Projection {
        let y: Vec<Real> = rows.iter().map(|&i| data.deviation[i]).collect();
        Projection::new(data.columns_on(&circle, &shape, rows), &y)
    };
    let spread = |values: &[Real]| {
        let (low, high) = values
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        high - low
    };
    let mut circular_deviation = [None; 2];
    for (s, g) in circular_deviation.iter_mut().enumerate() {
        let rows: Vec<usize> = (0..n)
            .filter(|&i| sense_index(data.points[i].sense) == s)
            .collect();
        if !rows.is_empty() {
            *g = Some(spread(&fit_rows(&rows).residual));
        }
    }
    let all: Vec<usize> = (0..n).collect();
    let common = fit_rows(&all);
    let both = data.both_senses();
    let radial: Vec<Real> = common
        .residual
        .iter()
        .map(|r| r + common.coefficients[0])
        .collect();
    let (radial_min, radial_max) = radial
        .iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    Ok(BallbarEvaluation {
        test: *test,
        counts: data.counts,
        spans: data.spans,
        circular_deviation,
        bidirectional_deviation: both.then(|| spread(&common.residual)),
        hysteresis: if both {
            hysteresis(&data.points, &common.residual)
        } else {
            None
        },
        radial_max,
        radial_min,
        centre_offset: [common.coefficients[1], common.coefficients[2]],
        mean_radial_deviation: common.coefficients[0],
        diagnostics: diagnose(&data),
    })
}

/// H: the largest |e_ccw(θ) − e_cw(θ)| with the cw residual interpolated linearly at the ccw
/// angles, only inside cw gaps no wider than 3 median gaps (the wrap at 360° included).
fn hysteresis(points: &[BasisPoint], residual: &[Real]) -> Option<Real> {
    let mut cw: Vec<(Real, Real)> = points
        .iter()
        .zip(residual)
        .filter(|(p, _)| p.sense < 0.0)
        .map(|(p, r)| (p.angle, *r))
        .collect();
    cw.sort_by(|a, b| a.0.total_cmp(&b.0));
    let m = cw.len();
    let gap = |k: usize| {
        if k + 1 < m {
            cw[k + 1].0 - cw[k].0
        } else {
            cw[0].0 + TAU - cw[m - 1].0
        }
    };
    let mut gaps: Vec<Real> = (0..m).map(gap).filter(|g| *g > 0.0).collect();
    gaps.sort_by(Real::total_cmp);
    let limit = 3.0 * *gaps.get(gaps.len() / 2)?;
    let mut largest: Option<Real> = None;
    for (p, r) in points.iter().zip(residual).filter(|(p, _)| p.sense > 0.0) {
        // The cw reading at or before θ (circularly) and the one after it.
        let after = cw.partition_point(|c| c.0 <= p.angle);
        let before = (after + m - 1) % m;
        let width = gap(before);
        if width > limit {
            continue;
        }
        let (a, b) = (cw[before], cw[(before + 1) % m]);
        let offset = (p.angle - a.0).rem_euclid(TAU);
        let value = if width > 0.0 {
            a.1 + (b.1 - a.1) * offset / width
        } else {
            a.1
        };
        let difference = (r - value).abs();
        largest = Some(largest.map_or(difference, |l: Real| l.max(difference)));
    }
    largest
}

/// The joint diagnostic fit with identifiability checks and uncertainties.
fn diagnose(data: &CircleData) -> Result<Diagnostics, String> {
    let n = data.len();
    if n < MIN_DIAGNOSTIC_READINGS {
        return Err(format!(
            "{n} readings: the diagnostic fit needs at least {MIN_DIAGNOSTIC_READINGS}"
        ));
    }
    let plane = data.test.plane;
    let mut unidentifiable: Vec<(Term, String)> = Vec::new();
    let mut terms: Vec<Term> = Vec::new();
    for term in Term::DIAGNOSTICS {
        match data.structural(term) {
            Some(reason) => unidentifiable.push((term, reason)),
            None => terms.push(term),
        }
    }
    let all_rows: Vec<usize> = (0..n).collect();
    let everything = vec![true; n];
    // The linear terms first (their columns do not depend on the searched shapes), then
    // everything at the searched shapes, until nothing more is dropped.
    let linear: Vec<Term> = terms.iter().copied().filter(|t| !t.searched()).collect();
    for (term, reason) in data.unidentifiable(&linear, &Shape::default()) {
        terms.retain(|&t| t != term);
        unidentifiable.push((term, reason));
    }
    let fit = loop {
        let fit = data.fit(&terms, &everything);
        let dropped = data.unidentifiable(&terms, &fit.shape);
        if dropped.is_empty() {
            break fit;
        }
        for (term, reason) in dropped {
            terms.retain(|&t| t != term);
            unidentifiable.push((term, reason));
        }
    };
    unidentifiable.sort_by_key(|(t, _)| *t);
    let rss: Real = fit.residuals.iter().map(|r| r * r).sum();
    let searched_count = terms.iter().filter(|t| t.searched()).count();
    let lags = (0..2)
        .filter(|&a| terms.iter().any(|t| t.reversal_axis() == Some(a)))
        .count();
    let k = fit.coefficients.len() + searched_count + lags;
    let dof = n.saturating_sub(k).max(1);
    let variance = rss / dof as Real;
    let columns = data.columns_on(&terms, &fit.shape, &all_rows);
    let covariance = |extra: &[Vec<Real>]| -> DMatrix<Real> {
        let views: Vec<&[Real]> = columns.iter().chain(extra).map(Vec::as_slice).collect();
        gram_pinv(&gram(&views)) * variance
    };
    let linear_covariance = covariance(&[]);
    // Offsets of each term's coefficients.
    let mut offsets = Vec::with_capacity(terms.len());
    let mut start = 0;
    for &t in &terms {
        offsets.push(start);
        start += t.columns();
    }
    let amplitude = |t: usize, cov: &DMatrix<Real>| -> (Real, Real) {
        let j = offsets[t];
        let c = &fit.coefficients[j..j + terms[t].columns()];
        if c.len() == 1 {
            return (c[0], cov[(j, j)].max(0.0).sqrt());
        }
        let a = c[0].hypot(c[1]);
        let var = if a > 0.0 {
            (c[0] * c[0] * cov[(j, j)]
                + 2.0 * c[0] * c[1] * cov[(j, j + 1)]
                + c[1] * c[1] * cov[(j + 1, j + 1)])
                / (a * a)
        } else {
            cov[(j, j)].max(cov[(j + 1, j + 1)])
        };
        (a, var.max(0.0).sqrt())
    };
    // Significant searched terms get derivative columns in their shape parameter.
    let mut notes = Vec::new();
    let mut derivatives: Vec<Vec<Real>> = Vec::new();
    let mut shape_column: Vec<Option<usize>> = vec![None; terms.len()];
    for (t, &term) in terms.iter().enumerate() {
        if !term.searched() {
            continue;
        }
        let (value, u) = amplitude(t, &linear_covariance);
        let threshold = data.significance(term);
        if value.abs() >= threshold * u && u > 0.0 {
            let c = fit.coefficients_of(term).unwrap_or(&[]);
            shape_column[t] = Some(columns.len() + derivatives.len());
            derivatives.push(
                all_rows
                    .iter()
                    .map(|&i| shape_derivative(term, c, &data.points[i], &data.test, &fit.shape))
                    .collect(),
            );
        } else {
            let what = if matches!(term, Term::CyclicP | Term::CyclicQ) {
                "period"
            } else {
                "decay"
            };
            notes.push(format!(
                "{}: amplitude {:.3} µm within {threshold:.1} × its uncertainty ({:.3} µm): not significant, {what} not reported",
                term.key(plane),
                value / M_PER_UM,
                u / M_PER_UM
            ));
        }
    }
    // A lag is reported when the axis has a significant reversal term to be located by.
    let mut reversal_lag = [None; 2];
    for (axis, lag) in reversal_lag.iter_mut().enumerate() {
        let members: Vec<usize> = (0..terms.len())
            .filter(|&t| terms[t].reversal_axis() == Some(axis))
            .collect();
        if members.is_empty() {
            continue;
        }
        let significant = members.iter().any(|&t| {
            let (value, u) = amplitude(t, &linear_covariance);
            u > 0.0 && value.abs() >= data.significance(terms[t]) * u
        });
        if significant {
            *lag = Some((
                fit.shape.lag[axis],
                data.lag_uncertainty(axis, &fit, variance),
            ));
        } else {
            notes.push(format!(
                "{}: no significant backlash, lateral play or spike of {} to time the reversal by: not reported",
                lag_key(plane, axis),
                if axis == 0 { plane.first() } else { plane.second() }
            ));
        }
    }
    let full_covariance = covariance(&derivatives);
    let estimates = terms
        .iter()
        .enumerate()
        .map(|(t, &term)| {
            let (value, mut u) = amplitude(t, &full_covariance);
            // A spike's height is read back to the reversal instant: h ∝ e^(δ/τ) for the data
            // after it, so the lag's uncertainty adds h·u_δ/τ.
            if matches!(term, Term::ReversalSpikeP | Term::ReversalSpikeQ) {
                let axis = usize::from(term == Term::ReversalSpikeQ);
                if let Some((_, u_lag)) = reversal_lag[axis] {
                    u = u.hypot(value * u_lag / fit.shape.decay[axis]);
                }
            }
            let mut estimate = TermEstimate {
                value,
                u,
                shape: None,
                phase: None,
            };
            if let Some(d) = shape_column[t] {
                let u_shape = full_covariance[(d, d)].max(0.0).sqrt();
                let axis = usize::from(matches!(term, Term::ReversalSpikeQ | Term::CyclicQ));
                estimate.shape = Some(match term {
                    Term::CyclicP | Term::CyclicQ => (fit.shape.period[axis], u_shape),
                    _ => (fit.shape.decay[axis], u_shape),
                });
                if matches!(term, Term::CyclicP | Term::CyclicQ) {
                    let j = offsets[t];
                    let (a, b) = (fit.coefficients[j], fit.coefficients[j + 1]);
                    let cov = &full_covariance;
                    let var = (b * b * cov[(j, j)] - 2.0 * a * b * cov[(j, j + 1)]
                        + a * a * cov[(j + 1, j + 1)])
                        / (a * a + b * b).powi(2);
                    estimate.phase = Some((b.atan2(a), var.max(0.0).sqrt()));
                }
            }
            (term, estimate)
        })
        .collect();
    Ok(Diagnostics {
        estimates,
        reversal_lag,
        unidentifiable,
        notes,
        rms: (rss / n as Real).sqrt(),
        dof,
        fit,
    })
}

/// The derivative of a searched term's contribution (coefficients `c`) in its decay (m/s)
/// or period (m/m) at `at`.
fn shape_derivative(
    term: Term,
    c: &[Real],
    at: &BasisPoint,
    test: &CircularTest,
    shape: &Shape,
) -> Real {
    match term {
        Term::ReversalSpikeP | Term::ReversalSpikeQ => {
            let axis = usize::from(term == Term::ReversalSpikeQ);
            let tau = shape.decay[axis];
            spike(axis, at, test, shape).map_or(0.0, |(value, dt)| c[0] * value * dt / (tau * tau))
        }
        Term::CyclicP | Term::CyclicQ => {
            let axis = usize::from(term == Term::CyclicQ);
            let (sin, cos) = at.angle.sin_cos();
            let w = if axis == 0 { cos } else { sin };
            let period = shape.period[axis];
            let x = test.radius * w;
            let (s, k) = (TAU * x / period).sin_cos();
            w * (-TAU * x / (period * period)) * (c[0] * k - c[1] * s)
        }
        _ => 0.0,
    }
}

/// The terms of `terms` the data cannot tell from the others, with the reason. While some
/// column's variance inflation exceeds [`MAX_VARIANCE_INFLATION`], the near-collinear group
/// (the terms weighing in the eigenvector of the smallest eigenvalue of the column-scaled Gram
/// matrix) loses its least important member (`terms` is in order of importance).
fn screen(data: &CircleData, terms: &[Term], shape: &Shape) -> Vec<(Term, String)> {
    let plane = data.test.plane;
    let rows: Vec<usize> = (0..data.len()).collect();
    let mut kept: Vec<Term> = terms.to_vec();
    let mut dropped = Vec::new();
    let columns: Vec<(Term, Vec<Real>)> = terms
        .iter()
        .flat_map(|&t| (0..t.columns()).map(move |k| (t, k)))
        .map(|(t, k)| (t, data.column_on(t, k, shape, &rows)))
        .collect();
    loop {
        let active: Vec<&(Term, Vec<Real>)> =
            columns.iter().filter(|(t, _)| kept.contains(t)).collect();
        let views: Vec<&[Real]> = active.iter().map(|(_, c)| c.as_slice()).collect();
        let g = gram(&views);
        let inflation = variance_inflation(&g);
        if inflation.iter().all(|v| *v <= MAX_VARIANCE_INFLATION) {
            return dropped;
        }
        let (_, values, vectors) = scaled_eigen(&g);
        let smallest = (0..values.len())
            .min_by(|&a, &b| values[a].total_cmp(&values[b]))
            .unwrap_or(0);
        let weight = |j: usize| vectors[(j, smallest)].abs();
        let heaviest = (0..active.len()).map(weight).fold(0.0, Real::max);
        let Some(victim) = kept
            .iter()
            .rev()
            .copied()
            .find(|&t| (0..active.len()).any(|j| active[j].0 == t && weight(j) >= 0.2 * heaviest))
            .or_else(|| kept.last().copied())
        else {
            return dropped;
        };
        let vif = (0..active.len())
            .filter(|&j| active[j].0 == victim)
            .map(|j| inflation[j])
            .fold(0.0, Real::max);
        // Which of the others make it up: regress its first column on them.
        let j = active
            .iter()
            .position(|(t, _)| *t == victim)
            .unwrap_or_default();
        let others: Vec<usize> = (0..active.len())
            .filter(|&i| active[i].0 != victim)
            .collect();
        let sub = DMatrix::from_fn(others.len(), others.len(), |a, b| g[(others[a], others[b])]);
        let pinv = gram_pinv(&sub);
        let norm = g[(j, j)].sqrt();
        let mut share: Vec<(Term, Real)> = Vec::new();
        for (a, &i) in others.iter().enumerate() {
            let coefficient: Real = (0..others.len())
                .map(|b| pinv[(a, b)] * g[(others[b], j)])
                .sum();
            let size = coefficient.abs() * g[(i, i)].sqrt() / norm.max(Real::MIN_POSITIVE);
            match share.iter_mut().find(|(t, _)| *t == active[i].0) {
                Some(entry) => entry.1 = entry.1.max(size),
                None => share.push((active[i].0, size)),
            }
        }
        share.sort_by(|a, b| b.1.total_cmp(&a.1));
        let top = share.first().map_or(0.0, |s| s.1);
        let names: Vec<String> = share
            .iter()
            .take(3)
            .filter(|(_, s)| *s >= 0.25 * top && *s > 0.0)
            .map(|(t, _)| t.key(plane))
            .collect();
        let inflation_text = if vif.is_finite() {
            format!("variance inflation {vif:.3e}, limit {MAX_VARIANCE_INFLATION}")
        } else {
            "exactly collinear".to_string()
        };
        dropped.push((
            victim,
            if names.is_empty() || norm == 0.0 {
                "no signal in these data (its column is zero)".to_string()
            } else {
                format!(
                    "cannot be told from {} with these data ({inflation_text})",
                    names.join(", ")
                )
            },
        ));
        kept.retain(|&t| t != victim);
    }
}

/// The report key of `axis`'s reversal lag (`reversal_lag_x_ms`).
fn lag_key(plane: Plane, axis: usize) -> String {
    let letter = if axis == 0 {
        plane.first()
    } else {
        plane.second()
    };
    format!("reversal_lag_{}_ms", letter.letter().to_ascii_lowercase())
}

/// What a reversal lag is, for the legend.
const LAG_CONVENTION: &str = "reversal lag δ of the axis: time from its programmed reversal (p: 0°/180°, q: 90°/270°) to its actual one, where its backlash, lateral play and spike act (≈ 1/Kv for a position loop without feed-forward)";

/// Rounds for reports: 4 decimals, no −0.
fn round(value: Real) -> Value {
    json!(fixed(value, 4).parse::<Real>().unwrap_or(value))
}

/// Metres to µm, rounded.
fn um(value: Real) -> Value {
    round(value / M_PER_UM)
}

impl BallbarEvaluation {
    /// The report with stable keys (lengths in µm, the plane's axis letters in the names).
    pub fn to_json(&self) -> Value {
        let plane = self.test.plane;
        let p = plane.first().letter().to_ascii_lowercase();
        let q = plane.second().letter().to_ascii_lowercase();
        let option = |v: Option<Real>| v.map_or(Value::Null, um);
        let mut report = json!({
            "kind": "ballbar",
            "standard": "ISO 230-4",
            "plane": plane.to_string(),
            "radius_mm": round(self.test.radius / M_PER_MM),
            "feed_mm_per_min": round(self.test.feed / M_PER_MM * 60.0),
            "n_readings": self.counts[0] + self.counts[1],
            "n_ccw": self.counts[0],
            "n_cw": self.counts[1],
            "span_ccw_deg": self.spans[0].map(|s| round(s / RAD_PER_DEG)),
            "span_cw_deg": self.spans[1].map(|s| round(s / RAD_PER_DEG)),
            "G_ccw_um": option(self.circular_deviation[0]),
            "G_cw_um": option(self.circular_deviation[1]),
            "G_um": option(self.bidirectional_deviation),
            "H_um": option(self.hysteresis),
            "F_max_um": um(self.radial_max),
            "F_min_um": um(self.radial_min),
            format!("centre_offset_{p}_um"): um(self.centre_offset[0]),
            format!("centre_offset_{q}_um"): um(self.centre_offset[1]),
            "mean_radial_deviation_um": um(self.mean_radial_deviation),
        });
        match &self.diagnostics {
            Err(reason) => {
                report["diagnostics"] = Value::Null;
                report["diagnostics_skipped"] = json!(reason);
            }
            Ok(d) => {
                let mut values = serde_json::Map::new();
                let mut conventions = serde_json::Map::new();
                for term in Term::DIAGNOSTICS {
                    let (_, scale) = term.unit();
                    let estimate = d.get(term);
                    values.insert(
                        term.key(plane),
                        estimate.map_or(
                            Value::Null,
                            |e| json!({"value": round(e.value * scale), "u": round(e.u * scale)}),
                        ),
                    );
                    conventions.insert(term.key(plane), json!(term.convention()));
                    let pair = |v: Option<(Real, Real)>, scale: Real| {
                        v.map_or(
                            Value::Null,
                            |(v, u)| json!({"value": round(v * scale), "u": round(u * scale)}),
                        )
                    };
                    match term {
                        Term::ReversalSpikeP | Term::ReversalSpikeQ => {
                            values.insert(
                                format!("{}_decay_ms", term.name(plane)),
                                pair(estimate.and_then(|e| e.shape), 1e3),
                            );
                        }
                        Term::CyclicP | Term::CyclicQ => {
                            values.insert(
                                format!("{}_period_mm", term.name(plane)),
                                pair(estimate.and_then(|e| e.shape), 1.0 / M_PER_MM),
                            );
                            values.insert(
                                format!("{}_phase_deg", term.name(plane)),
                                pair(estimate.and_then(|e| e.phase), 1.0 / RAD_PER_DEG),
                            );
                        }
                        _ => {}
                    }
                }
                for axis in 0..2 {
                    values.insert(
                        lag_key(plane, axis),
                        d.reversal_lag[axis].map_or(
                            Value::Null,
                            |(v, u)| json!({"value": round(v * 1e3), "u": round(u * 1e3)}),
                        ),
                    );
                    conventions.insert(lag_key(plane, axis), json!(LAG_CONVENTION));
                }
                report["diagnostics"] = Value::Object(values);
                report["unidentifiable"] = d
                    .unidentifiable
                    .iter()
                    .map(|(t, why)| json!({"term": t.key(plane), "reason": why}))
                    .collect();
                report["notes"] = json!(d.notes);
                report["residual_rms_um"] = um(d.rms);
                report["dof"] = json!(d.dof);
                report["conventions"] = json!({
                    "axes": format!("p = {}, q = {}; θ from +p toward +q; σ = +1 ccw, −1 cw; deviation = measured − nominal radius, + outward", plane.first(), plane.second()),
                    "uncertainty": "standard uncertainty σ̂·√((JᵀJ)⁻¹)ⱼⱼ, σ̂² = RSS/(n − k); optimistic when the residuals are serially correlated",
                    "terms": Value::Object(conventions),
                });
            }
        }
        report
    }

    /// The report for people.
    pub fn to_text(&self) -> String {
        let plane = self.test.plane;
        let mut out = String::new();
        let cell =
            |v: Option<Real>| v.map_or_else(|| "-".to_string(), |v| format!("{:.3}", v / M_PER_UM));
        let _ = writeln!(
            out,
            "ISO 230-4 circular test, plane {plane} (p = {}, q = {}): radius {} mm, feed {} mm/min",
            plane.first(),
            plane.second(),
            fixed(self.test.radius / M_PER_MM, 3),
            fixed(self.test.feed / M_PER_MM * 60.0, 1)
        );
        for (s, name) in SENSE_NAMES.iter().enumerate() {
            if let Some(span) = self.spans[s] {
                let _ = writeln!(
                    out,
                    "  {name}: {} readings over {:.1}°",
                    self.counts[s],
                    span / RAD_PER_DEG
                );
            }
        }
        let _ = writeln!(out);
        let line = |out: &mut String, name: &str, v: Option<Real>| {
            let _ = writeln!(out, "  {name:<44}{:>10} µm", cell(v));
        };
        line(
            &mut out,
            "circular deviation G ccw",
            self.circular_deviation[0],
        );
        line(
            &mut out,
            "circular deviation G cw",
            self.circular_deviation[1],
        );
        line(
            &mut out,
            "bidirectional circular deviation G(b)",
            self.bidirectional_deviation,
        );
        line(&mut out, "circular hysteresis H", self.hysteresis);
        line(
            &mut out,
            "largest radial deviation F_max",
            Some(self.radial_max),
        );
        line(
            &mut out,
            "smallest radial deviation F_min",
            Some(self.radial_min),
        );
        line(
            &mut out,
            &format!("centre offset {}", plane.first()),
            Some(self.centre_offset[0]),
        );
        line(
            &mut out,
            &format!("centre offset {}", plane.second()),
            Some(self.centre_offset[1]),
        );
        line(
            &mut out,
            "mean radial deviation",
            Some(self.mean_radial_deviation),
        );
        let _ = writeln!(
            out,
            "  (centre offset removed by a first-order least-squares circle; F relative to the nominal radius)"
        );
        match &self.diagnostics {
            Err(reason) => {
                let _ = writeln!(out, "\nDiagnostics not computed: {reason}");
            }
            Ok(d) => {
                let _ = writeln!(
                    out,
                    "\nDiagnostics (joint least-squares fit, value ± standard uncertainty; residual RMS {:.3} µm, {} dof):",
                    d.rms / M_PER_UM,
                    d.dof
                );
                for (term, e) in &d.estimates {
                    let (unit, scale) = term.unit();
                    let unit = unit.replace("um", "µm").replace("_per_", "/");
                    let _ = write!(
                        out,
                        "  {:<24}{:>10.3} ± {:<8.3} {unit}",
                        term.name(plane),
                        e.value * scale,
                        e.u * scale
                    );
                    if let Some((v, u)) = e.shape {
                        let _ = match term {
                            Term::CyclicP | Term::CyclicQ => write!(
                                out,
                                "   period {:.3} ± {:.3} mm",
                                v / M_PER_MM,
                                u / M_PER_MM
                            ),
                            _ => write!(out, "   decay {:.2} ± {:.2} ms", v * 1e3, u * 1e3),
                        };
                    }
                    if let Some((v, u)) = e.phase {
                        let _ = write!(
                            out,
                            ", phase {:.1} ± {:.1}°",
                            v / RAD_PER_DEG,
                            u / RAD_PER_DEG
                        );
                    }
                    let _ = writeln!(out);
                }
                for (axis, lag) in d.reversal_lag.iter().enumerate() {
                    if let Some((v, u)) = lag {
                        let name = lag_key(plane, axis);
                        let _ = writeln!(
                            out,
                            "  {:<24}{:>10.3} ± {:<8.3} ms",
                            &name[..name.len() - 3],
                            v * 1e3,
                            u * 1e3
                        );
                    }
                }
                if !d.unidentifiable.is_empty() {
                    let _ = writeln!(out, "\nNot identifiable from these data:");
                    for (term, why) in &d.unidentifiable {
                        let _ = writeln!(out, "  {:<24}{why}", term.name(plane));
                    }
                }
                for note in &d.notes {
                    let _ = writeln!(out, "  note: {note}");
                }
                let _ = writeln!(
                    out,
                    "\nConventions: p = {}, q = {}; θ from +p toward +q; σ = +1 ccw, −1 cw; deviation = measured − nominal radius (+ outward).",
                    plane.first(),
                    plane.second()
                );
                for term in Term::DIAGNOSTICS {
                    let _ = writeln!(out, "  {:<24}{}", term.name(plane), term.convention());
                }
                let _ = writeln!(out, "  {:<24}{LAG_CONVENTION}", "reversal_lag");
                let _ = writeln!(
                    out,
                    "Uncertainties assume independent residuals and are optimistic for a real (serially correlated) trace."
                );
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variance_inflation_is_one_for_orthogonal_columns_and_infinite_for_collinear_ones() {
        let a = [1.0, 1.0, 1.0, 1.0];
        let b = [1.0, -1.0, 1.0, -1.0];
        let v = variance_inflation(&gram(&[&a, &b]));
        assert!((v[0] - 1.0).abs() < 1e-12 && (v[1] - 1.0).abs() < 1e-12);
        let c = [2.0, 0.0, 2.0, 0.0]; // a + b
        let v = variance_inflation(&gram(&[&a, &b, &c]));
        assert!(v.iter().all(|x| *x > 1e12), "{v:?}");
        // Two columns with correlation ρ: VIF = 1/(1 − ρ²). ρ = 1/√2 here: VIF = 2.
        let d = [1.0, 0.0, 1.0, 0.0];
        let v = variance_inflation(&gram(&[&a, &d]));
        assert!((v[0] - 2.0).abs() < 1e-12, "{v:?}");
    }

    #[test]
    fn projection_scores_an_extra_column_as_a_full_refit_would() {
        let x: Vec<Real> = (0..50).map(|i| i as Real / 10.0).collect();
        let one = vec![1.0; 50];
        let y: Vec<Real> = x.iter().map(|x| 1.0 + x.sin() + 0.1 * x * x).collect();
        let square: Vec<Real> = x.iter().map(|x| x * x).collect();
        let fixed = Projection::new(vec![one.clone(), x.clone()], &y);
        let full = Projection::new(vec![one, x, square.clone()], &y);
        assert!((fixed.rss_with(&[&square]) - full.rss).abs() < 1e-10 * fixed.rss);
    }

    #[test]
    fn arc_since_reversal_runs_in_the_sense_of_travel() {
        let test = CircularTest {
            plane: Plane::XY,
            radius: 0.1,
            feed: 0.01,
        };
        let at = |deg: Real, sense: Real| BasisPoint::new(deg * RAD_PER_DEG, sense, 0.0, [true; 2]);
        let arc = |axis: usize, deg: Real, sense: Real, lag: Real| {
            let shape = Shape {
                lag: [lag; 2],
                ..Shape::default()
            };
            arc_since_reversal(axis, &at(deg, sense), &test, &shape) / RAD_PER_DEG
        };
        // ccw at 10°: 10° after p reversed at 0°; cw at 10°: 170° after p reversed at 180°.
        assert!((arc(0, 10.0, 1.0, 0.0) - 10.0).abs() < 1e-9);
        assert!((arc(0, 10.0, -1.0, 0.0) - 170.0).abs() < 1e-9);
        // cw at 350°: 10° after p reversed at 360°; q: ccw at 100° is 10° after 90°.
        assert!((arc(0, 350.0, -1.0, 0.0) - 10.0).abs() < 1e-9);
        assert!((arc(1, 100.0, 1.0, 0.0) - 10.0).abs() < 1e-9);
        assert!((arc(1, 80.0, -1.0, 0.0) - 10.0).abs() < 1e-9);
        // A lag of 0.1·(4°·π/180)/0.01 s = 0.698 s puts the actual reversal 4° later: ccw at
        // 10° is 6° after it, cw at 350° 6° after it.
        let lag = 0.1 * 4.0 * RAD_PER_DEG / 0.01;
        assert!((arc(0, 10.0, 1.0, lag) - 6.0).abs() < 1e-9);
        assert!((arc(0, 350.0, -1.0, lag) - 6.0).abs() < 1e-9);
    }

    #[test]
    fn the_windowed_lag_profile_equals_a_full_refit() {
        // A circle with backlash and a spike of p at a 25 ms lag, plus a wobble the model
        // lacks: the windowed residual sum of squares at every trial lag equals the one of
        // the full columns.
        let test = CircularTest {
            plane: Plane::XY,
            radius: 0.1,
            feed: 0.01,
        };
        let truth = Shape {
            lag: [0.025, 0.0],
            ..Shape::default()
        };
        let n = 4000;
        let mut readings = Vec::new();
        for (sense, sign) in [
            (crate::kinds::ballbar::Sense::Ccw, 1.0),
            (crate::kinds::ballbar::Sense::Cw, -1.0),
        ] {
            for k in 0..n {
                let angle = (sign * TAU * (k as Real + 0.5) / n as Real).rem_euclid(TAU);
                let at = BasisPoint::new(angle, sign, 0.0, [true; 2]);
                let deviation = 2e-6 * diagnostic_column(Term::BacklashP, 0, &at, &test, &truth)
                    + 3e-6 * diagnostic_column(Term::ReversalSpikeP, 0, &at, &test, &truth)
                    + 1e-7 * (7.0 * angle).sin();
                readings.push(crate::kinds::ballbar::BallbarReading {
                    sense,
                    angle,
                    deviation,
                    time: None,
                });
            }
        }
        let data = CircleData::new(&BallbarTable { readings }, &test).unwrap();
        let terms = [Term::Radius, Term::BacklashP, Term::ReversalSpikeP];
        let rows: Vec<usize> = (0..data.len()).collect();
        let shape = Shape::default();
        let (fixed, moving) = data.split_reversal(0, &terms, &shape, &rows, &data.deviation);
        let profile = data.lag_profile(0, &moving, &fixed, &rows, &shape);
        for lag in [0.0, 0.004, 0.025, 0.0371, 0.2] {
            let trial = Shape {
                lag: [lag, 0.0],
                ..shape
            };
            let columns = data.columns_on(&moving, &trial, &rows);
            let views: Vec<&[Real]> = columns.iter().map(Vec::as_slice).collect();
            let full = fixed.rss_with(&views);
            assert!(
                (profile.rss(lag) - full).abs() <= 1e-9 * full,
                "{lag}: {} vs {full}",
                profile.rss(lag)
            );
        }
        // And the search finds the lag the data were made with (to the 1/4000-turn sampling).
        let found = data.search_lag(&profile);
        assert!((found - 0.025).abs() < 0.1 * TAU / 4000.0 / 0.01, "{found}");
    }
}
