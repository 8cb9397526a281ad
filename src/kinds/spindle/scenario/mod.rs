//! The `[spindle]` section: an ISO 230-7 test of an axis of rotation by a virtual spindle error
//! analyser.
//!
//! ```toml
//! [spindle]
//! axis = "S"                        # the spindle (default), or a rotary axis C, A, B
//! sensing = "fixed"                 # probes on the stator, artefact turning (default); or
//!                                   # "rotating": probes turning with the axis, artefact fixed
//! speeds_rpm = [2000, 6000, 12000]  # ISO 230-7: three speeds for a spindle; negative: reverse
//!                                   # (default: 2000, 6000, 12000 for S, 10 for a table axis)
//! revolutions = 20                  # recorded per speed (ISO 230-7: at least 20)
//! samples_per_revolution = 1024     # on the index
//! setups = ["normal"]               # or ["normal", "reversed"] (Donaldson), "turned_<deg>"
//! settle_s = 0.002                  # not recorded before each speed, in whole revolutions
//!                                   # (default: ten time constants of the slowest filter)
//! x_mm = 380.0                      # where the other axes stand (linear: mid-travel,
//! s_deg = 0.0                       # rotary: 0); x_mm, y_mm, z_mm, a_deg, b_deg, c_deg, s_deg
//! noise_nm = 2.0                    # defaults of every probe (each may set its own)
//! resolution_nm = 0.1
//! bandwidth_hz = 10000.0            # first-order low-pass; inf: none
//! range_um = 50.0                   # ± measuring range
//!
//! [spindle.artefact]
//! kind = "cylinder"                 # "sphere", "two_spheres" or "cylinder" (default)
//! diameter_mm = 25.0
//! length_mm = 80.0                  # cylinder: probed length (default 80)
//! separation_mm = 80.0              # two_spheres: centre to centre (default 80)
//! stickout_mm = 0.0                 # reference point below the rotor's end frame (S: the
//!                                   # tool tip; a table: its surface, default 100 mm)
//! eccentricity_um = [1.5, -0.8]     # set-up, x y of the carrier's axis frame
//! tilt_urad = [0.0, 5.0]            # set-up, about x y of the carrier's axis frame
//! form = [{ per_revolution = 5, amplitude_nm = 30, phase_deg = 10 }]   # outward, a·sin(kψ + φ)
//!
//! [[spindle.probe]]                 # none given: the five-probe nest of ISO 230-7 Fig 12
//! name = "x1"                       # lower-case letters, digits and _
//! kind = "radial"                   # "radial" (azimuth_deg, height_mm), "axial", "face"
//! azimuth_deg = 0.0                 # (radius_mm, azimuth_deg: on a cylinder's end face)
//! height_mm = 0.0
//! gain_error = 0.001                # and noise_nm, resolution_nm, bandwidth_hz, range_um
//! ```
//!
//! The default nest: `x1` (azimuth 0°) and `y1` (90°) at height 0, `x2` and `y2` at the second
//! station (the second sphere, or the cylinder's far end), `z` on the axis; on a single sphere
//! only `x1`, `y1` and `z`. Frames, signs and the reading: [`super::instrument`].
//!
//! | file | reads |
//! |---|---|
//! | here | the section, [`SpindleTest`], and the number checks every part uses |
//! | `axis` | the axis under test, its speeds, the set-ups, where the other axes stand |
//! | `artefact` | `[spindle.artefact]` |
//! | `probes` | the instrument defaults, `[[spindle.probe]]` and the default nest |

mod artefact;
mod axis;
mod probes;

use super::instrument::{Artefact, ProbeSpec};
use super::program::Setup;
use super::record::Sensing;
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::Real;
use crate::scenario::{Checker, Context, ScenarioError};
use serde::Deserialize;
use toml::Spanned;

/// Metres per nanometre.
const M_PER_NM: Real = 1e-9;

/// The most samples (all set-ups, speeds and settling) one test may take: 4 million, twenty
/// times ISO 230-7's 20 revolutions × 1024 samples at five speeds and two set-ups, so that the
/// largest test a scenario may ask for runs in about ten seconds and 0.6 GB (5.6 M samples took
/// 13.6 s and 0.8 GB on the 2-core machine of the README's figures).
pub const MAX_SAMPLES: usize = 4_000_000;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSpindle {
    axis: Option<Spanned<String>>,
    sensing: Option<Spanned<String>>,
    speeds_rpm: Option<Spanned<Vec<Real>>>,
    revolutions: Option<Spanned<i64>>,
    samples_per_revolution: Option<Spanned<i64>>,
    setups: Option<Spanned<Vec<String>>>,
    settle_s: Option<Spanned<Real>>,
    noise_nm: Option<Spanned<Real>>,
    resolution_nm: Option<Spanned<Real>>,
    bandwidth_hz: Option<Spanned<Real>>,
    range_um: Option<Spanned<Real>>,
    x_mm: Option<Spanned<Real>>,
    y_mm: Option<Spanned<Real>>,
    z_mm: Option<Spanned<Real>>,
    a_deg: Option<Spanned<Real>>,
    b_deg: Option<Spanned<Real>>,
    c_deg: Option<Spanned<Real>>,
    s_deg: Option<Spanned<Real>>,
    artefact: Option<Spanned<artefact::RawArtefact>>,
    #[serde(default)]
    probe: Vec<Spanned<probes::RawProbe>>,
}

/// A spindle test: the axis, the programme and the analyser.
#[derive(Clone, Debug, PartialEq)]
pub struct SpindleTest {
    /// The axis of rotation measured.
    pub axis: Axis,
    /// Fixed or rotating sensitive direction.
    pub sensing: Sensing,
    /// The speeds (rad/s, signed), in order.
    pub speeds: Vec<Real>,
    /// Recorded revolutions per speed.
    pub revolutions: usize,
    /// Samples per revolution, on the index.
    pub samples_per_revolution: usize,
    /// Settling time before each record (s), rounded up to whole revolutions.
    pub settle: Real,
    /// Where the other axes stand (the measured axis's value is 0).
    pub parked: AxisValues,
    /// The set-ups, in order.
    pub setups: Vec<Setup>,
    /// The artefact.
    pub artefact: Artefact,
    /// The probes, in column order.
    pub probes: Vec<ProbeSpec>,
    /// The machine's name.
    pub machine: String,
}

impl SpindleTest {
    /// One line for `mtwin check`.
    pub fn describe(&self) -> Vec<String> {
        let speeds: Vec<String> = self
            .speeds
            .iter()
            .map(|w| crate::math::trimmed(w * 60.0 / std::f64::consts::TAU, 3))
            .collect();
        vec![format!(
            "spindle {}: {} sensing, {} at {} rpm, {} revolutions of {} samples, set-ups {}, probes {}",
            self.axis,
            match self.sensing {
                Sensing::Fixed => "fixed",
                Sensing::Rotating => "rotating",
            },
            self.artefact.describe(),
            speeds.join("/"),
            self.revolutions,
            self.samples_per_revolution,
            self.setups
                .iter()
                .map(|s| s.name())
                .collect::<Vec<_>>()
                .join(", "),
            self.probes
                .iter()
                .map(|p| p.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        )]
    }

    /// Total samples taken, settling included.
    pub fn sample_count(&self) -> usize {
        self.blocks().iter().map(|b| b.sample_count()).sum()
    }

    /// The records of the programme.
    pub fn blocks(&self) -> Vec<super::program::Block> {
        super::program::schedule(
            self.setups.len(),
            &self.speeds,
            self.revolutions,
            self.samples_per_revolution,
            self.settle,
        )
    }
}

/// The spindle test of a `[spindle]` section on `machine`.
pub(crate) fn spindle_test(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawSpindle>,
) -> Result<SpindleTest, ScenarioError> {
    let s = raw.get_ref();
    let check = Checker::new(context, raw.span(), "spindle");
    let axis = axis::axis_under_test(&check, machine, &s.axis)?;
    let sensing = match s.sensing.as_ref().map(|v| (v.get_ref().as_str(), v.span())) {
        None | Some(("fixed", _)) => Sensing::Fixed,
        Some(("rotating", _)) => Sensing::Rotating,
        Some((other, span)) => {
            return Err(check.fail(
                Some(span),
                "sensing",
                format!("expected \"fixed\" or \"rotating\", got \"{other}\""),
            ));
        }
    };
    let speeds = axis::speeds(&check, axis, &s.speeds_rpm)?;
    let revolutions = count(&check, &s.revolutions, "revolutions", 20, (1, 100_000))?;
    let samples_per_revolution = count(
        &check,
        &s.samples_per_revolution,
        "samples_per_revolution",
        1024,
        (8, 1 << 20),
    )?;
    let setups = axis::setups(&check, &s.setups)?;
    let parked = axis::parked(&check, machine, axis, s)?;
    let artefact = artefact::artefact(&check, axis, s.artefact.as_ref())?;
    let probes = probes::probes(&check, s, &artefact)?;
    // A probe whose filter cuts below once per revolution of the fastest speed cannot see
    // the error motion it is there for (ISO 230-7 §4.3 and Annex H: the bandwidth must cover
    // the undulations per revolution of interest at the speed).
    let fastest_hz = speeds.iter().fold(0.0, |f: Real, w| f.max(w.abs())) / std::f64::consts::TAU;
    if let Some(p) = probes
        .iter()
        .find(|p| p.bandwidth.is_some_and(|b| b < fastest_hz))
    {
        let given = s.bandwidth_hz.as_ref().map(|v| v.span());
        return Err(check.fail(
            given,
            "bandwidth_hz",
            format!(
                "probe \"{}\" filters at {} Hz, below once per revolution at the fastest speed ({} Hz): it cannot see the error motion",
                p.name,
                crate::math::readable(p.bandwidth.unwrap_or(0.0)),
                crate::math::trimmed(fastest_hz, 3)
            ),
        ));
    }
    // Ten time constants of the slowest filter: its transient is then below 5e-5 of a step.
    let slowest = probes
        .iter()
        .filter_map(|p| p.bandwidth)
        .fold(Real::INFINITY, Real::min);
    let default_settle = if slowest.is_finite() {
        10.0 / (std::f64::consts::TAU * slowest)
    } else {
        0.0
    };
    let settle = number(
        &check,
        &s.settle_s,
        "settle_s",
        default_settle,
        (0.0, false, 3600.0),
    )?;

    let test = SpindleTest {
        axis,
        sensing,
        speeds,
        revolutions,
        samples_per_revolution,
        settle,
        parked,
        setups,
        artefact,
        probes,
        machine: machine.name().to_string(),
    };
    let total = test.sample_count();
    if total > MAX_SAMPLES {
        return Err(check.fail(
            s.revolutions
                .as_ref()
                .map(|v| v.span())
                .or(s.samples_per_revolution.as_ref().map(|v| v.span())),
            "revolutions",
            format!(
                "the test takes {total} samples (set-ups × speeds × (settling + revolutions) × samples_per_revolution), more than {MAX_SAMPLES}: fewer revolutions or samples"
            ),
        ));
    }
    Ok(test)
}

/// A finite number in `[min, max]` (`min` excluded when `open`), or its default.
fn number(
    check: &Checker<'_>,
    value: &Option<Spanned<Real>>,
    key: &str,
    default: Real,
    (min, open, max): (Real, bool, Real),
) -> Result<Real, ScenarioError> {
    check.value(value, key, default, |x| {
        let above = if open { x > min } else { x >= min };
        if x.is_finite() && above && x <= max {
            Ok(x)
        } else {
            let low = if open { "above" } else { "at least" };
            Err(format!(
                "expected a finite number {low} {min} and at most {max}, got {x}"
            ))
        }
    })
}

/// A whole number in `[min, max]`, or its default.
fn count(
    check: &Checker<'_>,
    value: &Option<Spanned<i64>>,
    key: &str,
    default: usize,
    (min, max): (i64, i64),
) -> Result<usize, ScenarioError> {
    check.value(value, key, default, |n| {
        if (min..=max).contains(&n) {
            Ok(n as usize)
        } else {
            Err(format!(
                "expected a whole number from {min} to {max}, got {n}"
            ))
        }
    })
}

/// A bandwidth: positive, `inf` for none.
fn bandwidth(
    check: &Checker<'_>,
    value: &Option<Spanned<Real>>,
    key: &str,
    default: Option<Real>,
) -> Result<Option<Real>, ScenarioError> {
    check.value(value, key, default, |f| {
        if f == Real::INFINITY {
            Ok(None)
        } else if f.is_finite() && (1.0..=1e6).contains(&f) {
            Ok(Some(f))
        } else {
            Err(format!(
                "expected 1 … 1000000 Hz (probe amplifiers), or inf for no filter, got {}",
                crate::math::readable(f)
            ))
        }
    })
}
