//! The diagnostic model: the terms of the radial deviation ([`Term`]), their searched shape
//! parameters ([`Shape`]), a reading's place on the circle ([`BasisPoint`]), and the column
//! each term contributes there ([`diagnostic_column`]), reversal spikes and the arc since an
//! axis's actual reversal included.

use super::CircularTest;
use crate::machine::Plane;
use crate::math::Real;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// A spike column is cut after this many decay times.
pub(super) const SPIKE_DECAYS: Real = 10.0;

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
    /// b_p (m): σ·sgn(sin θ_p)·cos θ/2, θ_p = θ − σ·v·δ_p/R; as play times [`take_up`].
    BacklashP,
    /// b_q (m): −σ·sgn(cos θ_q)·sin θ/2, θ_q = θ − σ·v·δ_q/R; as play times [`take_up`].
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

    /// Whether the term can place its axis's reversal: backlash steps there (or starts taking
    /// up its play), a spike starts there. Lateral play cannot: its radial share σ·|sin θ|·l/2
    /// (p; |cos θ| for q) is continuous at the axis's reversal, where sin θ (cos θ) is zero,
    /// so moving the reversal changes it only in second order, by less than the noise of any
    /// real trace, and a lag fitted to it follows the noise.
    pub fn locates_reversal(self) -> bool {
        self.reversal_axis().is_some() && !matches!(self, Term::LateralPlayP | Term::LateralPlayQ)
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
    /// Play g_p, g_q (m) the backlash columns take up: 0 for lost motion as an instantaneous
    /// step at the reversal, else the gap the motor crosses while the carriage stands still
    /// (see [`take_up`]). The fit sets it to the fitted backlash when that fits better.
    pub play: [Real; 2],
    /// Angle lag ℓ (s) of the position-dependent terms: the trace's angles lead the direction
    /// the axes actually reach by σ·v·ℓ/R (ℓ ≈ 1/K_v for angles assigned from the command at the
    /// sampling time, 0 for ball-bar software that times its trace from the machine's motion);
    /// the centre offset, squareness and scale mismatch columns (the tool's actual position
    /// projected on its actual direction) are taken at θ_a = θ − σ·v·ℓ/R. Straightness and
    /// cyclic columns stay at θ: a bow moves by S·2·v·ℓ/R (0.04 µm for 2 µm at 2000 mm/min on
    /// 100 mm), and where a cyclic error is drawn (at the commanded or the actual position)
    /// is the data's convention, not settled by the trace.
    pub angle_lag: Real,
}

impl Default for Shape {
    fn default() -> Shape {
        Shape {
            lag: [0.0; 2],
            decay: [0.02; 2],
            period: [0.01; 2],
            lobes: 3,
            play: [0.0; 2],
            angle_lag: 0.0,
        }
    }
}

/// The arc (rad) over which the motor crosses a gap `gap` after it reverses at a quadrant
/// (`radius` the circle's): the axis position is R·cos φ from the reversal, so the motor has
/// come back R·(1 − cos φ) = gap after φ = arccos(1 − gap/R) (≈ √(2·gap/R): 0.41° for 4 µm on
/// 150 mm). 0 without play.
pub fn take_up_arc(gap: Real, radius: Real) -> Real {
    if gap > 0.0 {
        (1.0 - (gap / radius).min(2.0)).acos()
    } else {
        0.0
    }
}

/// The fraction w of its half-step the backlash of `axis` shows at `at` (−1 … 1), with the
/// play `shape.play[axis]` = g.
///
/// Derivation: the carriage follows the motor through a dead band of width b, carriage =
/// motor − (b/2)·d, d the last direction the motor pushed it. Before a reversal it lags by
/// b/2 against the old direction, i.e. leads by b/2 in the new one; the motor runs the circle
/// (its lag is in the reversal lag δ, its gain on the circle differs from 1 by (ωτ)²/2, a few
/// 10⁻⁵), so φ after its reversal it has come back u = R·(1 − cos φ), and the carriage, still
/// standing, leads it by b/2 − u in the new direction until u = b, then lags by b/2. In units
/// of the steady lag −(b/2)·d_new that is w = 2·min(u/b, 1) − 1: −1 at the reversal (the trace
/// continues as before it), +1 once the gap is crossed (the half-step's level), a parabola
/// in φ between (u ≈ R·φ²/2). Radially the backlash column is the half-step column times w,
/// linear in b for the fixed g the column is drawn with; the fit takes g = |b|. The shape does
/// not depend on the feed: the motor's travel, not time, sets the take-up. As g → 0 the
/// take-up arc vanishes and w = 1: today's instantaneous step.
pub fn take_up(axis: usize, at: &BasisPoint, test: &CircularTest, shape: &Shape) -> Real {
    let gap = shape.play[axis];
    if gap <= 0.0 {
        return 1.0;
    }
    let arc = arc_since_reversal(axis, at, test, shape);
    let back = 2.0 * test.radius * (arc / 2.0).sin().powi(2);
    2.0 * (back / gap).min(1.0) - 1.0
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
    /// Whether the trace crossed the last programmed reversal of p (index 0) and of q
    /// (index 1) before this reading; spike columns are zero where it did not.
    pub crossed: [bool; 2],
    /// The same for the next programmed reversal after this reading: an axis with a negative
    /// lag has actually reversed there already.
    pub crossed_next: [bool; 2],
    /// sin θ and cos θ, computed once (every column needs them).
    pub(super) sin_cos: (Real, Real),
}

impl BasisPoint {
    /// A reading at `angle` (rad) in sense `sense` (±1), `time` (s) into the test.
    pub fn new(angle: Real, sense: Real, time: Real, crossed: [bool; 2]) -> BasisPoint {
        BasisPoint {
            angle,
            sense,
            time,
            crossed,
            crossed_next: crossed,
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
    // The direction the axes actually reach, for the position-dependent terms.
    let (sin_a, cos_a) = if shape.angle_lag == 0.0 {
        at.sin_cos
    } else {
        (at.angle - sigma * test.feed * shape.angle_lag / r).sin_cos()
    };
    match term {
        Term::Radius => 1.0,
        Term::CentreP => cos_a,
        Term::CentreQ => sin_a,
        Term::Squareness => r * sin_a * cos_a,
        Term::ScaleMismatch => r / 2.0 * (cos_a * cos_a - sin_a * sin_a),
        Term::ServoMismatch => sigma * test.feed * sin * cos,
        Term::BacklashP => {
            sigma * travel(0, at, test, shape) * cos / 2.0 * take_up(0, at, test, shape)
        }
        Term::BacklashQ => {
            -sigma * travel(1, at, test, shape) * sin / 2.0 * take_up(1, at, test, shape)
        }
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
pub(super) fn signum(x: Real) -> Real {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The spike column of `axis` at `at` and the time since the actual reversal (s), when the
/// reversal was crossed and is less than [`SPIKE_DECAYS`] decays ago. With play
/// (`shape.play[axis]` > 0) the spike starts where the carriage reverses, the take-up arc
/// ([`take_up_arc`]) after the motor.
pub(super) fn spike(
    axis: usize,
    at: &BasisPoint,
    test: &CircularTest,
    shape: &Shape,
) -> Option<(Real, Real)> {
    let arc = arc_since_reversal(axis, at, test, shape);
    // The actual reversal is the next programmed one when a negative lag wrapped the arc.
    let unlagged = Shape {
        lag: [0.0; 2],
        ..*shape
    };
    let next = shape.lag[axis] < 0.0 && arc < arc_since_reversal(axis, at, test, &unlagged);
    let crossed = if next {
        at.crossed_next[axis]
    } else {
        at.crossed[axis]
    };
    if !crossed {
        return None;
    }
    // With play the carriage reverses (and sticks) once the motor has crossed the gap.
    let onset = take_up_arc(shape.play[axis], test.radius);
    if arc < onset {
        return None;
    }
    let tau = shape.decay[axis];
    let dt = test.radius * (arc - onset) / test.feed;
    (dt < SPIKE_DECAYS * tau).then(|| {
        let (sin, cos) = at.sin_cos;
        let weight = if axis == 0 { cos.abs() } else { sin.abs() };
        (weight * (-dt / tau).exp(), dt)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::RAD_PER_DEG;

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
}
