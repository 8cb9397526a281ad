//! The measurement uncertainty of each test's values: ISO 230-7 Annex F (ISO/TR 230-9 style,
//! coverage factor k = 2).
//!
//! # The budget
//!
//! Annex F combines a device term and an environment term per plot, and widens a plot's
//! uncertainty to a value's (F.4–F.7):
//!
//! ```text
//! U_DEVICE = U_CALIBRATION (F.1)  or  0.6·R_DEVICE (F.2)
//! U_EVE    = 0.6·E_VE (F.3)                   E_VE: range of a drift test with the axis stopped
//! U(single plot)       = √(U_DEVICE² + U_EVE²)        total, asynchronous, inner, outer (F.4)
//! U(synchronous plot)  = √(U_DEVICE² + U_EVE²/n)      n revolutions averaged (F.5)
//! U(value) = 1.4·U(plot)                              (F.6, F.7)
//! ```
//!
//! What the record cannot say is taken from [`Budget`] (the preamble's `device_uncertainty_um`,
//! `device_range_um`, `drift_um`, `artefact_roundness_um`, or `mtwin analyze spindle`'s flags).
//! What it can say is read from it:
//!
//! - **resolution** of the readings (the preamble's `resolution_nm`, or the step the readings
//!   are rounded to): `U = 2·q/√12`, part of the device term when no device term is stated
//!   (ISO/TR 230-9 C.3 counts it inside a stated one);
//! - **drift seen in the record** when no drift test is stated: `E_VE` is taken as the range
//!   of the test's revolution means over the segment. It also holds sub-synchronous motion, so
//!   it is an upper bound of the environment's drift; it is labelled so;
//! - **centring** (the limaçon model): a sphere of radius `R` off centre by `e` reads
//!   `e cos θ − e²/4R + (e²/4R) cos 2θ` to second order, a 2-UPR error of range `e²/2R` that
//!   every centre keeps; `e` is the largest 1-UPR amplitude among the test's radial probes'
//!   readings and `R` their distance from the axis (unknown, and left out, when the table puts
//!   a probe on the axis).
//!   `U = 0.6·e²/2R` (a range, as F.2);
//! - the **artefact's roundness**, when stated, enters radial synchronous values unseparated:
//!   `U = 0.6·roundness`.
//!
//! A test's signal combines its probes linearly; the device term is scaled by the largest norm
//! of the weights (`√2/L` for a tilt over a separation `L`, 1 for two orthogonal probes in a
//! rotating or fixed direction, more for probes closer than 90°); the environment term too,
//! as each probe drifts on its own.
//!
//! # Left out
//!
//! Sensor-to-surface alignment, the separation distance's own uncertainty (tilt), thermal
//! drift of the artefact mount, bandwidth (Annex H: a probe too slow for the lobes at a speed
//! loses them, which no budget repairs) and the correlation of one probe's gain error across
//! tests. Without a stated device term the budget is **incomplete**: it says so
//! ([`TestUncertainty::missing`]) and its U is a lower bound.

use super::Test;
use crate::kinds::spindle::analysis::motion::{self, Direction, Revolutions};
use crate::kinds::spindle::analysis::spectrum;
use crate::kinds::spindle::record::SpindleProbe;
use crate::math::Real;

/// Coverage-factor widening of a plot's uncertainty to a value's (F.6, F.7).
const PLOT_TO_VALUE: Real = 1.4;

/// A range `R` of a rectangular distribution as an expanded uncertainty (k = 2), F.2: `0.6·R`.
const RANGE_TO_U: Real = 0.6;

/// What the record cannot say about its own uncertainty (m, k = 2 where an uncertainty).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Budget {
    /// `U_CALIBRATION` of one probe channel (F.1).
    pub device: Option<Real>,
    /// The manufacturer's error range `R_DEVICE` of one channel (F.2), used when `device` is
    /// not given.
    pub device_range: Option<Real>,
    /// `E_VE`, the range of a drift test with the axis stopped (F.3).
    pub drift: Option<Real>,
    /// The artefact's roundness (peak to valley).
    pub roundness: Option<Real>,
    /// The readings' resolution (the preamble's `resolution_nm`), else inferred from them.
    pub resolution: Option<Real>,
}

/// One contribution to a test's budget.
#[derive(Clone, Debug, PartialEq)]
pub struct Contribution {
    /// What it is, and where its number came from.
    pub source: String,
    /// Its expanded uncertainty (k = 2) in the test's unit, on the single plot.
    pub u: Real,
    /// Whether it enters the synchronous plot divided by √n (the environment's drift).
    pub averages: bool,
}

/// A test's uncertainty (k = 2), in its unit (m, or rad for tilt).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TestUncertainty {
    /// U of the synchronous, fundamental and residual values (F.7).
    pub synchronous: Real,
    /// U of the total, asynchronous, inner and outer values (F.6).
    pub single: Real,
    /// The contributions, on the plot.
    pub contributions: Vec<Contribution>,
    /// What the budget lacks (empty when complete): its U is then a lower bound.
    pub missing: Vec<String>,
}

/// Student's t for a two-sided 95 % interval with `dof` degrees of freedom (tabulated at
/// 1–10, 12, 15, 20, 30, 60; linear in 1/ν between, 1.96 in the limit): the coverage factor
/// of an estimate from few degrees of freedom (GUM G.3).
pub fn student_t95(dof: Real) -> Real {
    const TABLE: [(Real, Real); 16] = [
        (1.0, 12.706),
        (2.0, 4.303),
        (3.0, 3.182),
        (4.0, 2.776),
        (5.0, 2.571),
        (6.0, 2.447),
        (7.0, 2.365),
        (8.0, 2.306),
        (9.0, 2.262),
        (10.0, 2.228),
        (12.0, 2.179),
        (15.0, 2.131),
        (20.0, 2.086),
        (30.0, 2.042),
        (60.0, 2.000),
        (Real::INFINITY, 1.960),
    ];
    if dof.is_nan() || dof <= 1.0 {
        return TABLE[0].1;
    }
    for pair in TABLE.windows(2) {
        let [(n0, t0), (n1, t1)] = [pair[0], pair[1]];
        if dof <= n1 {
            // Linear in 1/ν (1/∞ = 0).
            let f = (1.0 / n0 - 1.0 / dof) / (1.0 / n0 - 1.0 / n1);
            return t0 + f * (t1 - t0);
        }
    }
    1.960
}

/// The step the readings (m) are rounded to: the largest power of ten from 1 µm down to
/// 1 fm that divides every reading to within a thousandth of the step (a decimal reading
/// converted to metres is off its grid by far less); `None` when there is none (unrounded
/// floats).
pub fn rounding_step(readings: &[Vec<Real>]) -> Option<Real> {
    let values: Vec<Real> = readings.iter().flatten().copied().collect();
    if values.is_empty() {
        return None;
    }
    const STEPS: [Real; 10] = [
        1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15,
    ];
    crate::io::plausible::coarsest_grid(&values, &STEPS, 1e-3)
}

/// The largest norm, over the revolution, of the weights by which the test combines its
/// probes' readings (module docs).
fn weight_norm(test: &Test, probes: &[&SpindleProbe], length: Option<Real>) -> Real {
    match (test.direction, probes) {
        (Direction::Tilt, _) => {
            // (upper − lower)/L, each of the stations itself a combination.
            let per_station = if probes.len() == 4 {
                pair_norm(probes[0], probes[1])
            } else {
                1.0
            };
            per_station * std::f64::consts::SQRT_2 / length.unwrap_or(Real::NAN)
        }
        (_, [a, b]) => pair_norm(a, b),
        _ => 1.0,
    }
}

/// The largest norm over directions `u` of the weights solving `E·u` from two radial probes:
/// `|u·D⁻¹|`, whose largest value is the largest singular value of `D⁻¹`.
fn pair_norm(a: &SpindleProbe, b: &SpindleProbe) -> Real {
    let (da, db) = (a.direction, b.direction);
    let det = da[0] * db[1] - da[1] * db[0];
    // D = [da; db] (rows); σ_max(D⁻¹) = 1/σ_min(D).
    let (p, q, r, s) = (da[0], da[1], db[0], db[1]);
    let sum = p * p + q * q + r * r + s * s;
    let root = (sum * sum - 4.0 * det * det).max(0.0).sqrt();
    let sigma_min = ((sum - root) / 2.0).max(0.0).sqrt();
    1.0 / sigma_min
}

/// The artefact's centring a radial probe's record reads (m): the amplitude of its
/// synchronous profile's first harmonic, `e` of the limaçon model (module docs).
pub(super) fn centring(signal: &Revolutions) -> Real {
    let [a, b] = spectrum::harmonics(&motion::synchronous(signal), 1)[0];
    a.hypot(b)
}

/// The budget of one test (module docs). `probes` are the test's probes, `length` the
/// separation of a tilt's stations, `centring` the largest 1-UPR amplitude of its radial
/// probes' readings (m).
pub(super) fn test_uncertainty(
    test: &Test,
    probes: &[&SpindleProbe],
    length: Option<Real>,
    centring: Real,
    budget: &Budget,
) -> TestUncertainty {
    let weight = weight_norm(test, probes, length);
    let mut contributions = Vec::new();
    let mut missing = Vec::new();
    match (budget.device, budget.device_range) {
        (Some(u), _) => contributions.push(Contribution {
            source: "device: stated calibration uncertainty (F.1)".into(),
            u: weight * u,
            averages: false,
        }),
        (None, Some(range)) => contributions.push(Contribution {
            source: "device: 0.6 × stated error range (F.2)".into(),
            u: weight * RANGE_TO_U * range,
            averages: false,
        }),
        (None, None) => {
            missing.push("device uncertainty or error range (F.1, F.2) not stated".into());
            if let Some(q) = budget.resolution {
                contributions.push(Contribution {
                    source: format!("resolution {:.3} nm: 2q/√12", q * 1e9),
                    u: weight * 2.0 * q / 12f64.sqrt(),
                    averages: false,
                });
            }
        }
    }
    let revolutions = test.signal.count();
    match budget.drift {
        Some(e) => contributions.push(Contribution {
            source: "environment: 0.6 × stated drift test range (F.3)".into(),
            u: weight * RANGE_TO_U * e,
            averages: true,
        }),
        None => {
            let m = test.signal.samples_per_revolution();
            let means: Vec<Real> = (0..revolutions)
                .map(|k| test.signal.revolution(k).iter().sum::<Real>() / m as Real)
                .collect();
            let range = means.iter().copied().fold(Real::NEG_INFINITY, Real::max)
                - means.iter().copied().fold(Real::INFINITY, Real::min);
            missing.push("no drift test stated (F.3)".into());
            if revolutions >= 2 {
                contributions.push(Contribution {
                    source: "environment: 0.6 × range of the revolution means in the record (an upper bound of drift)".into(),
                    u: RANGE_TO_U * range,
                    averages: true,
                });
            }
        }
    }
    if test.direction == Direction::Radial {
        let radius = probes
            .iter()
            .map(|p| p.position[0].hypot(p.position[1]))
            .fold(Real::INFINITY, Real::min);
        let e = centring;
        if radius > 0.0 && radius.is_finite() {
            contributions.push(Contribution {
                source: format!(
                    "centring: 0.6 × e²/2R, e = {:.4} µm, R = {:.3} mm",
                    e * 1e6,
                    radius * 1e3
                ),
                u: RANGE_TO_U * e * e / (2.0 * radius),
                averages: false,
            });
        }
        if let Some(roundness) = budget.roundness {
            contributions.push(Contribution {
                source: "artefact roundness: 0.6 × stated peak to valley".into(),
                u: RANGE_TO_U * roundness,
                averages: false,
            });
        }
    }
    TestUncertainty::combine(contributions, missing, revolutions)
}

impl TestUncertainty {
    /// F.4–F.7 from the contributions on the plot, `revolutions` averaged in the synchronous
    /// plot.
    pub fn combine(
        contributions: Vec<Contribution>,
        missing: Vec<String>,
        revolutions: usize,
    ) -> TestUncertainty {
        let n = revolutions.max(1) as Real;
        let (mut fixed, mut averaged) = (0.0, 0.0);
        for c in &contributions {
            if c.averages {
                averaged += c.u * c.u;
            } else {
                fixed += c.u * c.u;
            }
        }
        TestUncertainty {
            synchronous: PLOT_TO_VALUE * (fixed + averaged / n).sqrt(),
            single: PLOT_TO_VALUE * (fixed + averaged).sqrt(),
            contributions,
            missing,
        }
    }
}
