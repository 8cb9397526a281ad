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

use super::instrument::{Artefact, ArtefactKind, FormHarmonic, ProbeKind, ProbeSpec};
use super::program::Setup;
use super::record::Sensing;
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, RAD_PER_URAD, Real};
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind};
use serde::Deserialize;
use std::ops::Range;
use toml::Spanned;

/// Metres per nanometre.
const M_PER_NM: Real = 1e-9;

/// The most samples (all set-ups, speeds and settling) one test may take: beyond, memory and
/// time run away (20 M samples of 5 probes are about 1 GB of table).
pub const MAX_SAMPLES: usize = 20_000_000;

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
    artefact: Option<Spanned<RawArtefact>>,
    #[serde(default)]
    probe: Vec<Spanned<RawProbe>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawArtefact {
    kind: Option<Spanned<String>>,
    diameter_mm: Option<Spanned<Real>>,
    length_mm: Option<Spanned<Real>>,
    separation_mm: Option<Spanned<Real>>,
    stickout_mm: Option<Spanned<Real>>,
    eccentricity_um: Option<Spanned<[Real; 2]>>,
    tilt_urad: Option<Spanned<[Real; 2]>>,
    form: Option<Spanned<Vec<Spanned<RawForm>>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawForm {
    per_revolution: i64,
    amplitude_nm: Real,
    #[serde(default)]
    phase_deg: Real,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProbe {
    name: Spanned<String>,
    kind: Spanned<String>,
    azimuth_deg: Option<Spanned<Real>>,
    height_mm: Option<Spanned<Real>>,
    radius_mm: Option<Spanned<Real>>,
    gain_error: Option<Spanned<Real>>,
    noise_nm: Option<Spanned<Real>>,
    resolution_nm: Option<Spanned<Real>>,
    bandwidth_hz: Option<Spanned<Real>>,
    range_um: Option<Spanned<Real>>,
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

/// The located checks of the section.
struct Checker<'a> {
    context: &'a Context<'a>,
    section: Range<usize>,
}

impl Checker<'_> {
    fn fail(
        &self,
        span: Option<Range<usize>>,
        key: &str,
        message: impl std::fmt::Display,
    ) -> ScenarioError {
        let span = span
            .filter(|s| !s.is_empty())
            .unwrap_or(self.section.clone());
        self.context.error(
            Some(span),
            ScenarioErrorKind::Value,
            format!("spindle.{key}: {message}"),
        )
    }

    /// A finite number in `[min, max]` (`min` excluded when `open`), or its default.
    fn number(
        &self,
        value: &Option<Spanned<Real>>,
        key: &str,
        default: Real,
        (min, open, max): (Real, bool, Real),
    ) -> Result<Real, ScenarioError> {
        let Some(v) = value else { return Ok(default) };
        let x = *v.get_ref();
        let above = if open { x > min } else { x >= min };
        if x.is_finite() && above && x <= max {
            Ok(x)
        } else {
            let low = if open { "above" } else { "at least" };
            Err(self.fail(
                Some(v.span()),
                key,
                format!("expected a finite number {low} {min} and at most {max}, got {x}"),
            ))
        }
    }

    /// A whole number in `[min, max]`, or its default.
    fn count(
        &self,
        value: &Option<Spanned<i64>>,
        key: &str,
        default: usize,
        (min, max): (i64, i64),
    ) -> Result<usize, ScenarioError> {
        let Some(v) = value else { return Ok(default) };
        let n = *v.get_ref();
        if (min..=max).contains(&n) {
            Ok(n as usize)
        } else {
            Err(self.fail(
                Some(v.span()),
                key,
                format!("expected a whole number from {min} to {max}, got {n}"),
            ))
        }
    }

    /// A bandwidth: positive, `inf` for none.
    fn bandwidth(
        &self,
        value: &Option<Spanned<Real>>,
        key: &str,
        default: Option<Real>,
    ) -> Result<Option<Real>, ScenarioError> {
        let Some(v) = value else { return Ok(default) };
        let f = *v.get_ref();
        if f == Real::INFINITY {
            Ok(None)
        } else if f.is_finite() && f > 0.0 {
            Ok(Some(f))
        } else {
            Err(self.fail(
                Some(v.span()),
                key,
                format!("expected a positive frequency, or inf for no filter, got {f}"),
            ))
        }
    }
}

/// The instrument defaults of the section, which each probe may override.
struct ProbeDefaults {
    noise: Real,
    resolution: Real,
    bandwidth: Option<Real>,
    range: Real,
}

/// The spindle test of a `[spindle]` section on `machine`.
pub(crate) fn spindle_test(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawSpindle>,
) -> Result<SpindleTest, ScenarioError> {
    let s = raw.get_ref();
    let check = Checker {
        context,
        section: raw.span(),
    };
    let axis = match &s.axis {
        None => Axis::S,
        Some(a) => {
            let text = a.get_ref().trim();
            let mut letters = text.chars();
            let letter = match (letters.next(), letters.next()) {
                (Some(c), None) => Axis::from_letter(c.to_ascii_uppercase()),
                _ => None,
            };
            match letter {
                Some(axis) if !axis.is_linear() => axis,
                _ => {
                    return Err(check.fail(
                        Some(a.span()),
                        "axis",
                        format!("expected an axis of rotation, S, C, A or B, got \"{text}\""),
                    ));
                }
            }
        }
    };
    match machine.axis(axis) {
        None => {
            return Err(check.fail(
                s.axis.as_ref().map(|a| a.span()),
                "axis",
                format!("machine \"{}\" has no axis {axis}", machine.name()),
            ));
        }
        Some(info) if !info.is_continuous() => {
            return Err(check.fail(
                s.axis.as_ref().map(|a| a.span()),
                "axis",
                format!(
                    "{axis} has a limited travel: the test turns the axis through whole revolutions (a swivelling axis needs a partial-arc test, ISO 230-7 §6, which this analyser does not run)"
                ),
            ));
        }
        Some(_) => {}
    }
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
    let speeds_rpm = match &s.speeds_rpm {
        None if axis == Axis::S => vec![2000.0, 6000.0, 12000.0],
        None => vec![10.0],
        Some(v) => {
            if v.get_ref().is_empty() {
                return Err(check.fail(Some(v.span()), "speeds_rpm", "give at least one speed"));
            }
            if let Some(bad) = v
                .get_ref()
                .iter()
                .find(|w| !(w.is_finite() && **w != 0.0 && w.abs() <= 200_000.0))
            {
                return Err(check.fail(
                    Some(v.span()),
                    "speeds_rpm",
                    format!(
                        "{bad}: expected speeds other than 0 within ±200000 rpm (negative: the axis turns backwards)"
                    ),
                ));
            }
            v.get_ref().clone()
        }
    };
    let speeds: Vec<Real> = speeds_rpm
        .iter()
        .map(|w| w * std::f64::consts::TAU / 60.0)
        .collect();
    let revolutions = check.count(&s.revolutions, "revolutions", 20, (1, 100_000))?;
    let samples_per_revolution = check.count(
        &s.samples_per_revolution,
        "samples_per_revolution",
        1024,
        (8, 1 << 20),
    )?;
    let setups = match &s.setups {
        None => vec![Setup::Normal],
        Some(v) => {
            if v.get_ref().is_empty() {
                return Err(check.fail(Some(v.span()), "setups", "give at least one set-up"));
            }
            let mut setups = Vec::new();
            for text in v.get_ref() {
                let setup = Setup::parse(text.trim()).ok_or_else(|| {
                    check.fail(
                        Some(v.span()),
                        "setups",
                        format!(
                            "\"{text}\": expected \"normal\", \"reversed\" or \"turned_<deg>\" (0 < deg < 360)"
                        ),
                    )
                })?;
                if setups.iter().any(|s: &Setup| s.name() == setup.name()) {
                    return Err(check.fail(
                        Some(v.span()),
                        "setups",
                        format!("\"{text}\" is given twice"),
                    ));
                }
                setups.push(setup);
            }
            setups
        }
    };

    // Where the other axes stand.
    let mut parked = AxisValues::ZERO;
    let given = [
        (Axis::X, "x_mm", &s.x_mm),
        (Axis::Y, "y_mm", &s.y_mm),
        (Axis::Z, "z_mm", &s.z_mm),
        (Axis::A, "a_deg", &s.a_deg),
        (Axis::B, "b_deg", &s.b_deg),
        (Axis::C, "c_deg", &s.c_deg),
        (Axis::S, "s_deg", &s.s_deg),
    ];
    for (other, key, value) in given {
        match (machine.axis(other), value) {
            (_, Some(v)) if other == axis => {
                return Err(check.fail(
                    Some(v.span()),
                    key,
                    format!("{axis} is the axis under test: it turns through the whole test"),
                ));
            }
            (None, Some(v)) => {
                return Err(check.fail(
                    Some(v.span()),
                    key,
                    format!("machine \"{}\" has no axis {other}", machine.name()),
                ));
            }
            (None, None) => {}
            (Some(info), value) => {
                let scale = crate::machine::axis_unit_to_si(other);
                let position = match (value, info.limits) {
                    (Some(v), _) => *v.get_ref() * scale,
                    (None, Some((lo, hi))) if other.is_linear() => (lo + hi) / 2.0,
                    (None, _) => 0.0,
                };
                if !info.within_travel(position) {
                    let (lo, hi) = info.limits.unwrap_or((Real::NAN, Real::NAN));
                    return Err(check.fail(
                        value.as_ref().map(|v| v.span()),
                        key,
                        format!(
                            "{} is outside the travel of {other} ({} … {})",
                            position / scale,
                            lo / scale,
                            hi / scale
                        ),
                    ));
                }
                parked[other] = position;
            }
        }
    }

    let artefact = artefact(&check, axis, s.artefact.as_ref())?;
    let defaults = ProbeDefaults {
        noise: check.number(&s.noise_nm, "noise_nm", 2.0, (0.0, false, 1e6))? * M_PER_NM,
        resolution: check.number(&s.resolution_nm, "resolution_nm", 0.1, (0.0, false, 1e6))?
            * M_PER_NM,
        bandwidth: check.bandwidth(&s.bandwidth_hz, "bandwidth_hz", Some(10_000.0))?,
        range: check.number(&s.range_um, "range_um", 50.0, (0.0, true, 1e4))? * M_PER_UM,
    };
    let probes = if s.probe.is_empty() {
        default_nest(&artefact, &defaults)
    } else {
        let mut probes: Vec<ProbeSpec> = Vec::new();
        for (index, p) in s.probe.iter().enumerate() {
            let probe = probe(&check, index, p, &artefact, &defaults)?;
            if probes.iter().any(|other| other.name == probe.name) {
                return Err(check.fail(
                    Some(p.get_ref().name.span()),
                    &format!("probe[{index}].name"),
                    format!("\"{}\" is given twice", probe.name),
                ));
            }
            probes.push(probe);
        }
        probes
    };
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
    let settle = check.number(
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

/// The `[spindle.artefact]` table.
fn artefact(
    check: &Checker<'_>,
    axis: Axis,
    raw: Option<&Spanned<RawArtefact>>,
) -> Result<Artefact, ScenarioError> {
    let empty = RawArtefact {
        kind: None,
        diameter_mm: None,
        length_mm: None,
        separation_mm: None,
        stickout_mm: None,
        eccentricity_um: None,
        tilt_urad: None,
        form: None,
    };
    let a = raw.map_or(&empty, |r| r.get_ref());
    let kind_name = a.kind.as_ref().map(|k| (k.get_ref().as_str(), k.span()));
    let kind = kind_name.as_ref().map_or("cylinder", |(k, _)| k);
    let radius = check.number(
        &a.diameter_mm,
        "artefact.diameter_mm",
        25.0,
        (0.0, true, 1000.0),
    )? / 2.0
        * M_PER_MM;
    let only = |value: &Option<Spanned<Real>>, key: &str, kind_needed: &str| match value {
        Some(v) if kind != kind_needed => Err(check.fail(
            Some(v.span()),
            key,
            format!("only a {kind_needed} has it (this artefact is a {kind})"),
        )),
        _ => Ok(()),
    };
    only(&a.length_mm, "artefact.length_mm", "cylinder")?;
    only(&a.separation_mm, "artefact.separation_mm", "two_spheres")?;
    let kind = match kind {
        "sphere" => ArtefactKind::Sphere,
        "two_spheres" => {
            let separation = check.number(
                &a.separation_mm,
                "artefact.separation_mm",
                80.0,
                (0.0, true, 2000.0),
            )? * M_PER_MM;
            if separation <= 2.0 * radius {
                return Err(check.fail(
                    a.separation_mm.as_ref().map(|v| v.span()),
                    "artefact.separation_mm",
                    format!(
                        "the spheres ({} mm) would overlap: their centres must be more than a diameter apart",
                        2.0 * radius / M_PER_MM
                    ),
                ));
            }
            ArtefactKind::TwoSpheres { separation }
        }
        "cylinder" => ArtefactKind::Cylinder {
            length: check.number(
                &a.length_mm,
                "artefact.length_mm",
                80.0,
                (0.0, true, 2000.0),
            )? * M_PER_MM,
        },
        other => {
            return Err(check.fail(
                kind_name.map(|(_, span)| span),
                "artefact.kind",
                format!("expected \"sphere\", \"two_spheres\" or \"cylinder\", got \"{other}\""),
            ));
        }
    };
    let table_axis = axis != Axis::S;
    let stickout = check.number(
        &a.stickout_mm,
        "artefact.stickout_mm",
        if table_axis { 100.0 } else { 0.0 },
        (-2000.0, false, 2000.0),
    )? * M_PER_MM;
    let pair = |value: &Option<Spanned<[Real; 2]>>, key: &str, scale: Real, limit: Real| {
        let Some(v) = value else {
            return Ok([0.0; 2]);
        };
        let [x, y] = *v.get_ref();
        if x.is_finite() && y.is_finite() && x.hypot(y) <= limit {
            Ok([x * scale, y * scale])
        } else {
            Err(check.fail(
                Some(v.span()),
                key,
                format!("expected two finite numbers, at most {limit} together, got [{x}, {y}]"),
            ))
        }
    };
    let eccentricity = pair(
        &a.eccentricity_um,
        "artefact.eccentricity_um",
        M_PER_UM,
        1000.0,
    )?;
    let tilt = pair(&a.tilt_urad, "artefact.tilt_urad", RAD_PER_URAD, 10_000.0)?;
    let mut form = Vec::new();
    if let Some(list) = &a.form {
        for (i, h) in list.get_ref().iter().enumerate() {
            let f = h.get_ref();
            let key = format!("artefact.form[{i}]");
            if !(2..=10_000).contains(&f.per_revolution) {
                let why = if f.per_revolution == 1 {
                    "1 undulation per revolution is the artefact's eccentricity: give it as eccentricity_um"
                } else {
                    "expected a whole number of undulations per revolution from 2 to 10000"
                };
                return Err(check.fail(
                    Some(h.span()),
                    &format!("{key}.per_revolution"),
                    format!("{}: {why}", f.per_revolution),
                ));
            }
            if !(f.amplitude_nm.is_finite() && f.amplitude_nm.abs() <= 1e6) {
                return Err(check.fail(
                    Some(h.span()),
                    &format!("{key}.amplitude_nm"),
                    format!(
                        "expected a finite amplitude within ±1e6 nm, got {}",
                        f.amplitude_nm
                    ),
                ));
            }
            if !f.phase_deg.is_finite() {
                return Err(check.fail(
                    Some(h.span()),
                    &format!("{key}.phase_deg"),
                    "expected a finite phase",
                ));
            }
            form.push(FormHarmonic {
                per_revolution: f.per_revolution as u32,
                amplitude: f.amplitude_nm * M_PER_NM,
                phase: f.phase_deg * RAD_PER_DEG,
            });
        }
    }
    Ok(Artefact {
        kind,
        radius,
        stickout,
        eccentricity,
        tilt,
        form,
    })
}

/// The five-probe nest of ISO 230-7 Fig 12 (three probes on a single sphere).
fn default_nest(artefact: &Artefact, d: &ProbeDefaults) -> Vec<ProbeSpec> {
    let second = match artefact.kind {
        ArtefactKind::Sphere => None,
        ArtefactKind::TwoSpheres { separation } => Some(separation),
        ArtefactKind::Cylinder { length } => Some(length),
    };
    let spec = |name: &str, kind| ProbeSpec {
        name: name.into(),
        kind,
        gain_error: 0.0,
        noise: d.noise,
        resolution: d.resolution,
        bandwidth: d.bandwidth,
        range: d.range,
    };
    let radial = |azimuth_deg: Real, height| ProbeKind::Radial {
        azimuth: azimuth_deg * RAD_PER_DEG,
        height,
    };
    let mut probes = vec![spec("x1", radial(0.0, 0.0)), spec("y1", radial(90.0, 0.0))];
    if let Some(h) = second {
        probes.push(spec("x2", radial(0.0, h)));
        probes.push(spec("y2", radial(90.0, h)));
    }
    probes.push(spec("z", ProbeKind::Axial));
    probes
}

/// One `[[spindle.probe]]` entry.
fn probe(
    check: &Checker<'_>,
    index: usize,
    raw: &Spanned<RawProbe>,
    artefact: &Artefact,
    d: &ProbeDefaults,
) -> Result<ProbeSpec, ScenarioError> {
    let p = raw.get_ref();
    let key = |field: &str| format!("probe[{index}].{field}");
    let name = p.name.get_ref().trim().to_string();
    let valid = name.starts_with(|c: char| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !valid {
        return Err(check.fail(
            Some(p.name.span()),
            &key("name"),
            format!(
                "\"{name}\": expected lower-case letters, digits and _, starting with a letter (it names the column NAME_um)"
            ),
        ));
    }
    let kind_name = p.kind.get_ref().as_str();
    let unused = |value: &Option<Spanned<Real>>, field: &str| match value {
        Some(v) => Err(check.fail(
            Some(v.span()),
            &key(field),
            format!(
                "{} {kind_name} probe has no {field}",
                if kind_name.starts_with(['a', 'e', 'i', 'o', 'u']) {
                    "an"
                } else {
                    "a"
                }
            ),
        )),
        None => Ok(()),
    };
    let azimuth = check.number(
        &p.azimuth_deg,
        &key("azimuth_deg"),
        0.0,
        (-360.0, false, 360.0),
    )? * RAD_PER_DEG;
    let kind = match kind_name {
        "radial" => {
            unused(&p.radius_mm, "radius_mm")?;
            let height = check.number(
                &p.height_mm,
                &key("height_mm"),
                0.0,
                (-2000.0, false, 2000.0),
            )? * M_PER_MM;
            let tolerance = 1e-9;
            let (ok, expected) = match artefact.kind {
                ArtefactKind::Sphere => (
                    height.abs() <= tolerance,
                    "0 (the sphere's equator)".to_string(),
                ),
                ArtefactKind::TwoSpheres { separation } => (
                    height.abs() <= tolerance || (height - separation).abs() <= tolerance,
                    format!(
                        "0 or {} (the spheres' equators)",
                        crate::math::trimmed(separation / M_PER_MM, 6)
                    ),
                ),
                ArtefactKind::Cylinder { length } => (
                    (-tolerance..=length + tolerance).contains(&height),
                    format!(
                        "from 0 to {} (along the cylinder)",
                        crate::math::trimmed(length / M_PER_MM, 6)
                    ),
                ),
            };
            if !ok {
                return Err(check.fail(
                    p.height_mm.as_ref().map(|v| v.span()),
                    &key("height_mm"),
                    format!(
                        "{} mm: a radial probe on a {} senses at a height of {expected} mm",
                        height / M_PER_MM,
                        artefact.kind.name()
                    ),
                ));
            }
            ProbeKind::Radial { azimuth, height }
        }
        "axial" => {
            unused(&p.radius_mm, "radius_mm")?;
            unused(&p.height_mm, "height_mm")?;
            unused(&p.azimuth_deg, "azimuth_deg")?;
            ProbeKind::Axial
        }
        "face" => {
            unused(&p.height_mm, "height_mm")?;
            if !matches!(artefact.kind, ArtefactKind::Cylinder { .. }) {
                return Err(check.fail(
                    Some(p.kind.span()),
                    &key("kind"),
                    format!(
                        "a face probe needs a flat end face: the artefact is a {}; use kind = \"cylinder\"",
                        artefact.kind.name()
                    ),
                ));
            }
            let radius = check.number(
                &p.radius_mm,
                &key("radius_mm"),
                Real::NAN,
                (0.0, true, 2000.0),
            )? * M_PER_MM;
            if radius.is_nan() {
                return Err(check.fail(
                    Some(raw.span()),
                    &key("radius_mm"),
                    "a face probe needs its radius_mm",
                ));
            }
            if radius >= artefact.radius {
                return Err(check.fail(
                    p.radius_mm.as_ref().map(|v| v.span()),
                    &key("radius_mm"),
                    format!(
                        "{} mm is off the end face (radius {} mm)",
                        radius / M_PER_MM,
                        artefact.radius / M_PER_MM
                    ),
                ));
            }
            ProbeKind::Face { radius, azimuth }
        }
        other => {
            return Err(check.fail(
                Some(p.kind.span()),
                &key("kind"),
                format!("expected \"radial\", \"axial\" or \"face\", got \"{other}\""),
            ));
        }
    };
    let gain_error = check.number(&p.gain_error, &key("gain_error"), 0.0, (-0.5, false, 0.5))?;
    Ok(ProbeSpec {
        name,
        kind,
        gain_error,
        noise: check.number(
            &p.noise_nm,
            &key("noise_nm"),
            d.noise / M_PER_NM,
            (0.0, false, 1e6),
        )? * M_PER_NM,
        resolution: check.number(
            &p.resolution_nm,
            &key("resolution_nm"),
            d.resolution / M_PER_NM,
            (0.0, false, 1e6),
        )? * M_PER_NM,
        bandwidth: check.bandwidth(&p.bandwidth_hz, &key("bandwidth_hz"), d.bandwidth)?,
        range: check.number(
            &p.range_um,
            &key("range_um"),
            d.range / M_PER_UM,
            (0.0, true, 1e4),
        )? * M_PER_UM,
    })
}
