//! The `[iso230_3_etve]` section: the ISO 230-3 §5 environmental temperature variation error
//! (ETVE) test. The axes hold still, the spindle is stopped, and a nest of five displacement
//! sensors on the table reads a mandrel in the spindle while the air around the machine
//! changes. It runs through the scenario's `[thermal]` model.
//!
//! ```toml
//! [iso230_3_etve]
//! hold_mm = { x = 380.0, y = 205.0, z = 200.0 }   # where the axes stand (others at zero)
//! duration_min = 480.0                            # "as long as possible" (ISO 230-3 §5.2)
//! sample_min = 1.0                                # at most 5 min (§5.2)
//! control = "hold"                                # "hold" or "off", as the report states it (§5.4 k)
//! nest = { first_mm = 20.0, spacing_mm = 100.0, noise_um = 0.02, resolution_um = 0.01 }
//! air = { noise_degc = 0.02, resolution_degc = 0.01 }   # the ambient thermometer
//! ```
//!
//! The nest: X1 and Y1 read the mandrel `first_mm` above the tool point (along the tool
//! frame's z, the spindle axis of the bundled machines), X2 and Y2 `spacing_mm` (the
//! standard's l) further up towards the spindle nose, and Z reads the mandrel's end at the
//! tool point. The air thermometer reads the ambient without lag; the machine-structure
//! thermometer the standard asks for is one of `[thermal]`'s sensors (e.g. on
//! `spindle_housing`).

use crate::machine::{Axis, AxisValues, Machine};
use crate::math::{M_PER_MM, M_PER_UM, Real};
use crate::program::{Approach, MeasurePoint, Program, Step};
use crate::scenario::bounds::{self, Bound};
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind, ThermalSetup};
use crate::thermal::SensorSpec;
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawEtve {
    #[serde(default)]
    hold_mm: BTreeMap<String, Real>,
    duration_min: Real,
    #[serde(default = "one")]
    sample_min: Real,
    #[serde(default = "hold")]
    control: String,
    nest: RawNest,
    #[serde(default)]
    air: RawAir,
}

fn one() -> Real {
    1.0
}
fn hold() -> String {
    "hold".into()
}

/// The nest of a drift test as written (shared by the ETVE and the spindle test).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawNest {
    first_mm: Real,
    spacing_mm: Real,
    #[serde(default)]
    noise_um: Real,
    #[serde(default)]
    resolution_um: Real,
}

/// The ambient thermometer of a drift test as written (shared by the ETVE and the spindle test).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawAir {
    #[serde(default = "air_noise")]
    noise_degc: Real,
    #[serde(default = "air_resolution")]
    resolution_degc: Real,
}

impl Default for RawAir {
    fn default() -> RawAir {
        RawAir {
            noise_degc: air_noise(),
            resolution_degc: air_resolution(),
        }
    }
}

fn air_noise() -> Real {
    0.02
}
fn air_resolution() -> Real {
    0.01
}

/// Whether the machine's axes are powered in hold or the machine is switched off (ISO 230-3
/// §5.1). The twin's thermal model has no heat from holding, so both run alike; the table and
/// the report state which was asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ControlMode {
    /// Axes powered, in hold.
    Hold,
    /// Machine switched off.
    Off,
}

impl ControlMode {
    /// `hold` or `off`.
    pub fn name(self) -> &'static str {
        match self {
            ControlMode::Hold => "hold",
            ControlMode::Off => "off",
        }
    }
}

/// The nest of five displacement sensors (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nest {
    /// Height of the X1, Y1 pair above the tool point, along the tool frame's z (m).
    pub first: Real,
    /// Distance from X1, Y1 to X2, Y2 towards the spindle nose: the standard's l (m).
    pub spacing: Real,
    /// White noise on each reading, 1σ (m).
    pub noise: Real,
    /// Resolution (m).
    pub resolution: Real,
}

/// The ISO 230-3 §5 ETVE test.
#[derive(Clone, Debug, PartialEq)]
pub struct EtveTest {
    /// The machine holding still, read every sample.
    pub program: Program,
    /// Where the axes hold (SI).
    pub hold: AxisValues,
    /// Time between samples (s).
    pub sample: Real,
    /// Hold or off.
    pub control: ControlMode,
    /// The displacement sensors.
    pub nest: Nest,
    /// The ambient thermometer (named `air`; no lag).
    pub air: SensorSpec,
}

impl EtveTest {
    /// `ETVE test (ISO 230-3 §5): 8.0 h in hold, read every 1 min`, as `mtwin check` lists it.
    pub fn describe(&self) -> String {
        format!(
            "ETVE test (ISO 230-3 §5): {:.1} h in {}, read every {} min, nest l = {} mm",
            self.program.duration() / 3600.0,
            self.control.name(),
            crate::math::trimmed(self.sample / 60.0, 3),
            crate::math::trimmed(self.nest.spacing / M_PER_MM, 3),
        )
    }
}

/// The ETVE test of a scenario, if it has one; it needs the scenario's `[thermal]` model
/// (`thermal`, with its section's span).
pub(crate) fn sections(
    context: &Context<'_>,
    machine: &Machine,
    raw: Option<&Spanned<RawEtve>>,
    thermal: Option<(&ThermalSetup, std::ops::Range<usize>)>,
) -> Result<Option<EtveTest>, ScenarioError> {
    thermal_test(context, "iso230_3_etve", raw, thermal, |raw, setup| {
        let test = etve_test(context, machine, raw, setup)?;
        let duration = test.program.duration();
        Ok((test, duration))
    })
}

/// A thermal test section `name` of a scenario, if given, built by `build` on the scenario's
/// `[thermal]` model (`thermal`, with its section's span), which it needs; the thermal model's
/// steps are checked against the programme's duration that `build` returns with the test.
pub(crate) fn thermal_test<R, T>(
    context: &Context<'_>,
    name: &str,
    raw: Option<&Spanned<R>>,
    thermal: Option<(&ThermalSetup, std::ops::Range<usize>)>,
    build: impl FnOnce(&Spanned<R>, &ThermalSetup) -> Result<(T, Real), ScenarioError>,
) -> Result<Option<T>, ScenarioError> {
    let Some(raw) = raw else {
        return Ok(None);
    };
    let Some((setup, thermal_span)) = thermal else {
        return Err(context.error(
            Some(raw.span()),
            ScenarioErrorKind::Value,
            format!(
                "{name} is a thermal test: add a [thermal] section with the machine's thermal model (and its air)"
            ),
        ));
    };
    let (test, duration) = build(raw, setup)?;
    setup.check_steps(context, thermal_span, duration)?;
    Ok(Some(test))
}

fn etve_test(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawEtve>,
    setup: &ThermalSetup,
) -> Result<EtveTest, ScenarioError> {
    let e = raw.get_ref();
    let fail = |message: String| {
        context.section_error(
            raw.span(),
            ScenarioErrorKind::Value,
            "iso230_3_etve.",
            message,
        )
    };
    let hold = hold_position(machine, &e.hold_mm, &fail)?;
    // An hour at least: the report's first-hour range and an ETVE value need it (the analysis
    // cautions a shorter record); "as long as possible" (ISO 230-3 §5.2), at most a week here.
    if !(e.duration_min.is_finite()
        && e.duration_min >= 60.0
        && e.duration_min <= 7.0 * 24.0 * 60.0)
    {
        return Err(fail(format!(
            "duration_min: {} min; expected at least 60 (the first-hour range; hours written as minutes?) and at most a week",
            e.duration_min
        )));
    }
    // ISO 230-3 §5.2: readings at least every 5 min.
    if !(e.sample_min.is_finite() && e.sample_min > 0.0 && e.sample_min <= 5.0) {
        return Err(fail(format!(
            "sample_min: {} min; ISO 230-3 §5.2 asks for a reading at least every 5 min (0 < sample_min ≤ 5)",
            e.sample_min
        )));
    }
    let samples = (e.duration_min / e.sample_min + 1e-9).floor() as usize;
    if !(2..=200_000).contains(&samples) {
        return Err(fail(format!(
            "sample_min: {samples} samples over duration_min; expected 2 to 200000"
        )));
    }
    let control = match e.control.as_str() {
        "hold" => ControlMode::Hold,
        "off" => ControlMode::Off,
        other => {
            return Err(fail(format!(
                "control: \"{other}\": expected \"hold\" or \"off\""
            )));
        }
    };
    let nest = nest(&e.nest, &fail)?;
    let air = air_thermometer(&e.air, setup, "the ETVE's", &fail)?;
    let sample = e.sample_min * 60.0;
    let mut steps = vec![Step::Spindle(0.0)];
    for index in 0..=samples {
        if index > 0 {
            steps.push(Step::Dwell(sample));
        }
        steps.push(Step::Measure(MeasurePoint {
            run: index,
            target: 0,
            approach: Approach::Up,
        }));
    }
    Ok(EtveTest {
        program: Program { start: hold, steps },
        hold,
        sample,
        control,
        nest,
        air,
    })
}

/// Where the linear axes hold (SI) from `hold_mm` (`x`, `y`, `z` in mm; the others at zero),
/// each within its travel; `fail` words an error about a key of the section.
pub(crate) fn hold_position(
    machine: &Machine,
    hold_mm: &BTreeMap<String, Real>,
    fail: &dyn Fn(String) -> ScenarioError,
) -> Result<AxisValues, ScenarioError> {
    let mut hold = AxisValues::ZERO;
    for (key, value) in hold_mm {
        let axis = match key.as_str() {
            "x" => Axis::X,
            "y" => Axis::Y,
            "z" => Axis::Z,
            other => {
                return Err(fail(format!(
                    "hold_mm.{other}: expected x, y or z (rotary axes hold at zero)"
                )));
            }
        };
        let info = machine
            .axis(axis)
            .ok_or_else(|| fail(format!("hold_mm.{key}: the machine has no {axis} axis")))?;
        if !info.within_travel(value * M_PER_MM) {
            return Err(fail(format!(
                "hold_mm.{key}: {value} mm is outside the travel of {axis}"
            )));
        }
        hold[axis] = value * M_PER_MM;
    }
    for info in machine.axes() {
        if !info.within_travel(hold[info.axis]) {
            return Err(fail(format!(
                "hold_mm: {} cannot hold at 0 (outside its travel); give hold_mm.{}",
                info.axis,
                info.axis.letter().to_ascii_lowercase()
            )));
        }
    }
    Ok(hold)
}

/// The nest (SI) from its section; `fail` words an error about a key of the section.
pub(crate) fn nest(
    n: &RawNest,
    fail: &dyn Fn(String) -> ScenarioError,
) -> Result<Nest, ScenarioError> {
    let reach = Bound {
        lo: 0.0,
        hi: 1000.0,
        why: "a test mandrel is at most a metre long",
    };
    let sensor = Bound {
        hi: 10.0,
        ..bounds::NOISE_NM
    };
    let checks = [
        ("first_mm", n.first_mm, reach),
        ("spacing_mm", n.spacing_mm, Bound { lo: 1.0, ..reach }),
        ("noise_um", n.noise_um, sensor),
        ("resolution_um", n.resolution_um, sensor),
    ];
    for (key, value, bound) in checks {
        bound
            .check(value)
            .map_err(|message| fail(format!("nest.{key}: {message}")))?;
    }
    Ok(Nest {
        first: n.first_mm * M_PER_MM,
        spacing: n.spacing_mm * M_PER_MM,
        noise: n.noise_um * M_PER_UM,
        resolution: n.resolution_um * M_PER_UM,
    })
}

/// The ambient thermometer `air` (no lag) from its section, its name free among `setup`'s
/// sensors; `whose` names the test in the message (`the ETVE's`).
pub(crate) fn air_thermometer(
    raw: &RawAir,
    setup: &ThermalSetup,
    whose: &str,
    fail: &dyn Fn(String) -> ScenarioError,
) -> Result<SensorSpec, ScenarioError> {
    for (key, value) in [
        ("noise_degc", raw.noise_degc),
        ("resolution_degc", raw.resolution_degc),
    ] {
        bounds::THERMOMETER_DEGC
            .check(value)
            .map_err(|message| fail(format!("air.{key}: {message}")))?;
    }
    if setup.sensors.iter().any(|(_, s)| s.name == "air") {
        return Err(fail(format!(
            "air: a [thermal] sensor is named \"air\", the name of {whose} ambient thermometer; rename it"
        )));
    }
    Ok(SensorSpec {
        name: "air".into(),
        offset: 0.0,
        noise: raw.noise_degc,
        resolution: raw.resolution_degc,
        time_constant: 0.0,
    })
}
