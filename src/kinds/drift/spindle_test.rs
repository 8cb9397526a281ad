//! The `[iso230_3_spindle]` section: the ISO 230-3 §6 test of the thermal distortion caused by
//! a rotating spindle. The set-up is the ETVE test's (§6.2: a mandrel in the spindle, the nest
//! of five displacement sensors on the table, a thermometer near the front spindle bearing and
//! one in the air), the axes hold still, and the spindle runs a speed programme — a constant
//! speed for up to 4 h (§6.2, §6.3) or a variable speed spectrum — then stands for at least
//! 1 h while the readings go on. It runs through the scenario's `[thermal]` model, whose
//! `spindle_bearing` node the spindle speed heats ([`crate::thermal::HeatDriver::Spindle`]) and
//! whose spindle growth and column tilt move the tool.
//!
//! ```toml
//! [iso230_3_spindle]
//! hold_mm = { x = 380.0, y = 205.0, z = 260.0 }   # where the axes stand (others at zero)
//! constant = { speed_rpm = 6000.0, run_min = 240.0, stop_min = 60.0 }   # §6.3
//! # or the variable speed spectrum (§6.2, Fig. 6), then stop_min stopped (default 60):
//! # spectrum = [{ speed_rpm = 3000.0, duration_min = 20.0 }, { speed_rpm = 0.0, duration_min = 5.0 }]
//! # stop_min = 60.0
//! sample_min = 1.0                                # at most 5 min (§6.2)
//! nest = { first_mm = 20.0, spacing_mm = 100.0, noise_um = 0.02, resolution_um = 0.01 }
//! air = { noise_degc = 0.02, resolution_degc = 0.01 }   # the ambient thermometer
//! ```
//!
//! `constant`: `speed_rpm` (> 0), `run_min` (default 240, the standard's 4 h) and `stop_min`
//! (default 60). `spectrum`: one `{ speed_rpm, duration_min }` per step in order (0 rpm for the
//! periodic stops), and `stop_min` beside it. The running period t of the standard is the whole
//! constant run or the whole spectrum; the cool-down follows, at least 60 min (§6.2: "stopped
//! for at least 1 h"). The nest and the air thermometer are the ETVE's
//! ([`super::scenario`]), the structure's thermometers `[thermal]`'s sensors.
//!
//! The readings: one at the start (the spindle still at rest, the zero of every channel), then
//! every `sample_min`, plus one at the end of the running period and one at the end if those
//! fall between samples. A reading at the instant the speed changes is taken before the
//! change, so the reading at the end of the running period belongs to it. The nest reads the
//! mandrel's mean position over a revolution (§6.2 footnote 5: runout removed by low-pass
//! filtering or synchronous sampling), so starting and stopping give no runout offsets.
//!
//! The table is the `drift` table ([`DriftTable`]): X1, Y1, X2, Y2, Z, `temp_air_degc` and the
//! `[thermal]` sensors, with the conditions `test = iso230_3_spindle`, `ambient_sensor`,
//! `spacing_mm`, `control = hold`, `hold_mm`, `first_mm`, `programme` (`constant` or
//! `spectrum`), `speed_rpm` or `spectrum` (`3000 rpm for 20 min, 0 rpm for 5 min`), `run_min`
//! (the end of the running period) and `stop_min`. `mtwin analyze drift` evaluates it: the
//! drift over the first 60 min and the whole record, the tilts A and B from the pairs, the
//! 15 % stop criterion.

use super::iso230_3::{drift_ranges, signed_range, stop_time, tilts};
use super::run::{hold_condition, read_nest};
use super::scenario::{
    ControlMode, Nest, RawAir, RawNest, air_thermometer, hold_position, nest, thermal_test,
};
use super::table::{DriftChannel, DriftConditions, DriftTable};
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::{M_PER_MM, Real, trimmed};
use crate::program::{Approach, MeasurePoint, Program, Step};
use crate::scenario::thermal::{RawThermal, thermal_setup};
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind, ThermalSetup};
use crate::thermal::SensorSpec;
use crate::twin::{ThermalRecord, Twin};
use serde::Deserialize;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::f64::consts::TAU;
use toml::Spanned;

/// The section's name, as the scenario and the table's conditions spell it.
pub const SECTION: &str = "iso230_3_spindle";

/// rad/s per min⁻¹.
const RAD_PER_S_PER_RPM: Real = TAU / 60.0;

/// `speed` rad/s in min⁻¹ as written in a file: to 1e-6 min⁻¹, so 6000 reads back as 6000.
fn rpm(speed: Real) -> Real {
    (speed / RAD_PER_S_PER_RPM * 1e6).round() / 1e6
}

/// The highest spindle speed a section may ask for (min⁻¹).
const MAX_RPM: Real = 200_000.0;

/// A week (min): the longest period a section may ask for.
const WEEK_MIN: Real = 7.0 * 24.0 * 60.0;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSpindleTest {
    #[serde(default)]
    hold_mm: BTreeMap<String, Real>,
    constant: Option<Spanned<RawConstant>>,
    spectrum: Option<Spanned<Vec<Spanned<RawSpeedStep>>>>,
    stop_min: Option<Spanned<Real>>,
    #[serde(default = "one")]
    sample_min: Real,
    nest: RawNest,
    #[serde(default)]
    air: RawAir,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConstant {
    speed_rpm: Real,
    #[serde(default = "four_hours")]
    run_min: Real,
    #[serde(default = "one_hour")]
    stop_min: Real,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSpeedStep {
    speed_rpm: Real,
    duration_min: Real,
}

fn one() -> Real {
    1.0
}
fn four_hours() -> Real {
    240.0
}
fn one_hour() -> Real {
    60.0
}

/// The spindle speed programme of the running period (SI: rad/s, s).
#[derive(Clone, Debug, PartialEq)]
pub enum SpeedProgramme {
    /// One speed for the whole running period (ISO 230-3 §6.3).
    Constant {
        /// Spindle speed (rad/s), > 0.
        speed: Real,
        /// The running period (s).
        run: Real,
    },
    /// The variable speed spectrum (§6.2, Fig. 6): `(speed rad/s, duration s)` in order, 0 for
    /// the periodic stops.
    Spectrum(Vec<(Real, Real)>),
}

impl SpeedProgramme {
    /// The running period t of the standard (s): the constant run or the whole spectrum.
    pub fn run_period(&self) -> Real {
        match self {
            SpeedProgramme::Constant { run, .. } => *run,
            SpeedProgramme::Spectrum(steps) => steps.iter().map(|(_, d)| d).sum(),
        }
    }

    /// When the speed is set and to what: `(time s, speed rad/s)` from the start, in order,
    /// ending with the stop (speed 0) at [`SpeedProgramme::run_period`].
    pub fn changes(&self) -> Vec<(Real, Real)> {
        let mut changes = Vec::new();
        match self {
            SpeedProgramme::Constant { speed, .. } => changes.push((0.0, *speed)),
            SpeedProgramme::Spectrum(steps) => {
                let mut time = 0.0;
                for (speed, duration) in steps {
                    changes.push((time, *speed));
                    time += duration;
                }
            }
        }
        changes.push((self.run_period(), 0.0));
        changes
    }

    /// The speed over `[t − dt, t)` for a small dt (rad/s): what turned the spindle up to a
    /// reading at `t` (0 before the start).
    pub fn speed_before(&self, t: Real) -> Real {
        self.changes()
            .iter()
            .take_while(|(at, _)| *at < t - 1e-6)
            .last()
            .map_or(0.0, |(_, speed)| *speed)
    }

    /// `constant` or `spectrum`.
    pub fn name(&self) -> &'static str {
        match self {
            SpeedProgramme::Constant { .. } => "constant",
            SpeedProgramme::Spectrum(_) => "spectrum",
        }
    }

    /// `6000 rpm for 240 min`, or `3000 rpm for 20 min, 0 rpm for 5 min, …`.
    pub fn describe(&self) -> String {
        let step = |speed: Real, duration: Real| {
            format!(
                "{} rpm for {} min",
                trimmed(rpm(speed), 3),
                trimmed(duration / 60.0, 3)
            )
        };
        match self {
            SpeedProgramme::Constant { speed, run } => step(*speed, *run),
            SpeedProgramme::Spectrum(steps) => steps
                .iter()
                .map(|(s, d)| step(*s, *d))
                .collect::<Vec<_>>()
                .join(", "),
        }
    }
}

/// The ISO 230-3 §6 spindle thermal test.
#[derive(Clone, Debug, PartialEq)]
pub struct SpindleThermalTest {
    /// The machine holding still, the spindle running the programme, read every sample.
    pub program: Program,
    /// Where the axes hold (SI).
    pub hold: AxisValues,
    /// Time between samples (s).
    pub sample: Real,
    /// The spindle speeds of the running period.
    pub speeds: SpeedProgramme,
    /// How long the spindle stands after the running period, read on (s).
    pub stop: Real,
    /// The displacement sensors.
    pub nest: Nest,
    /// The ambient thermometer (named `air`; no lag).
    pub air: SensorSpec,
}

impl SpindleThermalTest {
    /// `spindle thermal test (ISO 230-3 §6): 6000 rpm for 240 min, then stopped 60 min, read
    /// every 1 min, nest l = 100 mm`, as `mtwin check` lists it.
    pub fn describe(&self) -> String {
        format!(
            "spindle thermal test (ISO 230-3 §6): {}, then stopped {} min, read every {} min, nest l = {} mm",
            self.speeds.describe(),
            trimmed(self.stop / 60.0, 3),
            trimmed(self.sample / 60.0, 3),
            trimmed(self.nest.spacing / M_PER_MM, 3),
        )
    }

    /// The whole test: the running period and the stop (s).
    pub fn duration(&self) -> Real {
        self.speeds.run_period() + self.stop
    }
}

/// The spindle thermal test of a scenario, if it has one; it needs the scenario's `[thermal]`
/// model (`thermal`, with its section's span).
pub(crate) fn sections(
    context: &Context<'_>,
    machine: &Machine,
    raw: Option<&Spanned<RawSpindleTest>>,
    thermal: Option<(&ThermalSetup, std::ops::Range<usize>)>,
) -> Result<Option<SpindleThermalTest>, ScenarioError> {
    thermal_test(context, "iso230_3_spindle", raw, thermal, |raw, setup| {
        let test = spindle_test(context, machine, raw, setup)?;
        let duration = test.program.duration();
        Ok((test, duration))
    })
}

/// The `[thermal]` and `[iso230_3_spindle]` sections of a scenario's `text` (the file `file`;
/// every other key is left alone) for `machine`: the test and the thermal model it runs
/// through, `None` without the section. Errors name the file, line and key as
/// [`crate::app::Scenario::load`]'s do. This runs the section on its own, e.g. for a test or
/// beside a scenario loaded without it.
pub fn parse_sections(
    file: &str,
    text: &str,
    machine: &Machine,
) -> Result<Option<(SpindleThermalTest, ThermalSetup)>, ScenarioError> {
    #[derive(Deserialize)]
    struct RawSections {
        thermal: Option<Spanned<RawThermal>>,
        iso230_3_spindle: Option<Spanned<RawSpindleTest>>,
    }
    let context = Context::new(file.to_string(), text);
    let raw: RawSections = toml::from_str(text).map_err(|e| {
        let message = e.message().trim().to_string();
        let kind = if message.starts_with("unknown field") {
            ScenarioErrorKind::UnknownKey
        } else {
            ScenarioErrorKind::Syntax
        };
        context.error(e.span(), kind, message)
    })?;
    let thermal = raw
        .thermal
        .as_ref()
        .map(|t| thermal_setup(&context, machine, t))
        .transpose()?;
    let with_span = thermal.as_ref().zip(raw.thermal.as_ref().map(|t| t.span()));
    let test = sections(&context, machine, raw.iso230_3_spindle.as_ref(), with_span)?;
    Ok(test.zip(thermal))
}

fn spindle_test(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawSpindleTest>,
    setup: &ThermalSetup,
) -> Result<SpindleThermalTest, ScenarioError> {
    let e = raw.get_ref();
    let prefix = format!("{SECTION}.");
    let fail = |message: String| {
        context.section_error(raw.span(), ScenarioErrorKind::Value, &prefix, message)
    };
    let hold = hold_position(machine, &e.hold_mm, &fail)?;
    let speed_ok = |rpm: Real| rpm.is_finite() && (0.0..=MAX_RPM).contains(&rpm);
    let period_ok = |min: Real| min.is_finite() && min > 0.0 && min <= WEEK_MIN;
    let (speeds, stop_min) = match (&e.constant, &e.spectrum) {
        (None, None) => {
            return Err(fail(
                "constant or spectrum: give the spindle speed programme, e.g. constant = { speed_rpm = 6000.0, run_min = 240.0, stop_min = 60.0 } (ISO 230-3 §6.3) or spectrum = [{ speed_rpm = 3000.0, duration_min = 20.0 }, …] (§6.2)".into(),
            ));
        }
        (Some(_), Some(spectrum)) => {
            return Err(context.error(
                Some(spectrum.span()),
                ScenarioErrorKind::Value,
                format!(
                    "{prefix}spectrum: give constant or spectrum, not both (one speed programme per test)"
                ),
            ));
        }
        (Some(constant), None) => {
            let c = constant.get_ref();
            if let Some(stop) = &e.stop_min {
                return Err(context.error(
                    Some(stop.span()),
                    ScenarioErrorKind::Value,
                    format!("{prefix}stop_min: with constant, give the stop inside it: constant = {{ speed_rpm = …, run_min = …, stop_min = … }}"),
                ));
            }
            if !(speed_ok(c.speed_rpm) && c.speed_rpm > 0.0) {
                return Err(fail(format!(
                    "constant.speed_rpm: {} rpm; expected a spindle speed above 0 and at most {MAX_RPM}",
                    c.speed_rpm
                )));
            }
            if !period_ok(c.run_min) {
                return Err(fail(format!(
                    "constant.run_min: {} min; expected more than 0 and at most a week (ISO 230-3 §6.2: 4 h, 240 min)",
                    c.run_min
                )));
            }
            let programme = SpeedProgramme::Constant {
                speed: c.speed_rpm * RAD_PER_S_PER_RPM,
                run: c.run_min * 60.0,
            };
            (programme, ("constant.stop_min", c.stop_min, None))
        }
        (None, Some(spectrum)) => {
            let entries = spectrum.get_ref();
            if entries.is_empty() {
                return Err(context.error(
                    Some(spectrum.span()),
                    ScenarioErrorKind::Value,
                    format!(
                        "{prefix}spectrum: empty; expected one {{ speed_rpm, duration_min }} per step of the spectrum"
                    ),
                ));
            }
            let mut steps = Vec::with_capacity(entries.len());
            for (index, entry) in entries.iter().enumerate() {
                let s = entry.get_ref();
                let at_entry = |message: String| {
                    context.error(
                        Some(entry.span()),
                        ScenarioErrorKind::Value,
                        format!("{prefix}spectrum[{index}].{message}"),
                    )
                };
                if !speed_ok(s.speed_rpm) {
                    return Err(at_entry(format!(
                        "speed_rpm: {} rpm; expected 0 (a stop) to {MAX_RPM}",
                        s.speed_rpm
                    )));
                }
                if !period_ok(s.duration_min) {
                    return Err(at_entry(format!(
                        "duration_min: {} min; expected more than 0 and at most a week",
                        s.duration_min
                    )));
                }
                steps.push((s.speed_rpm * RAD_PER_S_PER_RPM, s.duration_min * 60.0));
            }
            if steps.iter().all(|(speed, _)| *speed == 0.0) {
                return Err(context.error(
                    Some(spectrum.span()),
                    ScenarioErrorKind::Value,
                    format!("{prefix}spectrum: every step is a stop (0 rpm); the spindle must run"),
                ));
            }
            let programme = SpeedProgramme::Spectrum(steps);
            if programme.run_period() > WEEK_MIN * 60.0 {
                return Err(context.error(
                    Some(spectrum.span()),
                    ScenarioErrorKind::Value,
                    format!("{prefix}spectrum: longer than a week"),
                ));
            }
            let stop = e.stop_min.as_ref();
            let stop_min = stop.map_or_else(one_hour, |s| *s.get_ref());
            (programme, ("stop_min", stop_min, stop.map(|s| s.span())))
        }
    };
    let (stop_key, stop_min, stop_span) = stop_min;
    // ISO 230-3 §6.2: "the spindle shall be stopped for at least 1 h" while monitoring goes on.
    if !(stop_min.is_finite() && (60.0..=WEEK_MIN).contains(&stop_min)) {
        let message = format!(
            "{stop_key}: {stop_min} min; ISO 230-3 §6.2 stops the spindle for at least 1 h (60 ≤ stop_min ≤ a week)"
        );
        return Err(match stop_span {
            Some(span) => context.error(
                Some(span),
                ScenarioErrorKind::Value,
                format!("{prefix}{message}"),
            ),
            None => fail(message),
        });
    }
    // ISO 230-3 §6.2 (as §5.2): readings at least every 5 min.
    if !(e.sample_min.is_finite() && e.sample_min > 0.0 && e.sample_min <= 5.0) {
        return Err(fail(format!(
            "sample_min: {} min; ISO 230-3 §6.2 asks for a reading at least every 5 min (0 < sample_min ≤ 5)",
            e.sample_min
        )));
    }
    let stop = stop_min * 60.0;
    let total = speeds.run_period() + stop;
    let sample = e.sample_min * 60.0;
    let samples = (total / sample + 1e-9).floor() as usize;
    if samples > 200_000 {
        return Err(fail(format!(
            "sample_min: {samples} samples over the test; expected at most 200000"
        )));
    }
    let nest = nest(&e.nest, &fail)?;
    let air = air_thermometer(&e.air, setup, "the spindle test's", &fail)?;
    Ok(SpindleThermalTest {
        program: program(hold, sample, samples, &speeds, total),
        hold,
        sample,
        speeds,
        stop,
        nest,
        air,
    })
}

/// The programme: hold at `hold`; a reading at every multiple of `sample` up to `samples`, at
/// the end of the running period and at `total` (each once); the speed set at each change of
/// `speeds`, after a reading at the same instant.
fn program(
    hold: AxisValues,
    sample: Real,
    samples: usize,
    speeds: &SpeedProgramme,
    total: Real,
) -> Program {
    // Instants closer than this are one (s): sums of minutes are not exact multiples.
    const SAME: Real = 1e-6;
    let mut readings: Vec<Real> = (0..=samples).map(|k| k as Real * sample).collect();
    readings.extend([speeds.run_period(), total]);
    readings.sort_by(Real::total_cmp);
    readings.dedup_by(|later, earlier| *later - *earlier <= SAME);
    let changes = speeds.changes();
    // Every instant, with what happens there: (time, reading?, new speed).
    let mut instants: Vec<(Real, bool, Option<Real>)> =
        readings.iter().map(|t| (*t, true, None)).collect();
    for &(at, speed) in &changes {
        match instants
            .iter_mut()
            .find(|(t, _, _)| (*t - at).abs() <= SAME)
        {
            Some(instant) => instant.2 = Some(speed),
            None => instants.push((at, false, Some(speed))),
        }
    }
    instants.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut steps = vec![Step::Spindle(0.0)];
    let (mut time, mut run) = (0.0, 0);
    for (at, reading, speed) in instants {
        if at > time {
            steps.push(Step::Dwell(at - time));
            time = at;
        }
        if reading {
            steps.push(Step::Measure(MeasurePoint {
                run,
                target: 0,
                approach: Approach::Up,
            }));
            run += 1;
        }
        if let Some(speed) = speed {
            steps.push(Step::Spindle(speed));
        }
    }
    Program { start: hold, steps }
}

/// A simulated spindle thermal test: the table and what the twin knew at each reading.
#[derive(Clone, Debug)]
pub struct SpindleThermalRun {
    /// The instrument's table.
    pub table: DriftTable,
    /// The true displacement of each channel, zeroed at the start (m), without noise or
    /// resolution: the truth the table's channels measure.
    pub true_channels: Vec<DriftChannel>,
    /// The thermal twin at each reading.
    pub records: Vec<ThermalRecord>,
    /// The spindle speed that turned up to each reading (rad/s).
    pub speeds: Vec<Real>,
    /// The end of the running period (s).
    pub run_period: Real,
}

/// Simulates `test` on `twin` through `setup`, the random streams seeded from `seed`.
pub fn simulate(
    twin: &Twin,
    test: &SpindleThermalTest,
    setup: &ThermalSetup,
    seed: u64,
) -> SpindleThermalRun {
    let readings = read_nest(
        twin,
        setup,
        &test.program,
        &test.nest,
        &test.air,
        seed,
        "spindle test",
    );
    let times: Vec<Real> = readings.records.iter().map(|r| r.visit.time).collect();
    let (speed_rpm, spectrum) = match &test.speeds {
        SpeedProgramme::Constant { speed, .. } => (Some(rpm(*speed)), None),
        SpeedProgramme::Spectrum(_) => (None, Some(test.speeds.describe())),
    };
    let table = DriftTable {
        conditions: DriftConditions {
            test: Some(SECTION.into()),
            ambient_sensor: Some(test.air.name.clone()),
            spacing: Some(test.nest.spacing),
            control: Some(ControlMode::Hold),
            hold: Some(hold_condition(twin, &test.hold)),
            first: Some(test.nest.first),
            programme: Some(test.speeds.name().into()),
            speed_rpm,
            spectrum,
            run_period: Some(test.speeds.run_period()),
            stop: Some(test.stop),
            other: Vec::new(),
        },
        times: times.clone(),
        channels: readings.channels,
        temperatures: readings.temperatures,
        columns_not_read: Vec::new(),
    };
    SpindleThermalRun {
        table,
        true_channels: readings.true_channels,
        records: readings.records,
        speeds: times.iter().map(|t| test.speeds.speed_before(*t)).collect(),
        run_period: test.speeds.run_period(),
    }
}

/// The ranges of a drift record (file units, ×1e6: µm or µrad) as the standard reports them:
/// over the first 60 min, over the running period (ending at `run_period` s), over the whole
/// record, the stop criterion and the last value.
fn ranges(record: &[(Real, Real)], run_period: Real, unit: &str) -> serde_json::Map<String, Value> {
    let scale = |v: Real| v * 1e6;
    let whole = drift_ranges(record);
    let start = record.first().map_or(0.0, |(t, _)| *t);
    let mut entry = serde_json::Map::new();
    entry.insert(format!("range_60_{unit}"), json!(whole.map(|r| scale(r.0))));
    entry.insert(
        format!("range_run_{unit}"),
        json!(signed_range(record, start, start + run_period).map(scale)),
    );
    entry.insert(format!("range_{unit}"), json!(whole.map(|r| scale(r.1))));
    entry.insert(
        "stop_min".into(),
        json!(stop_time(record).map(|t| t / 60.0)),
    );
    entry.insert(
        format!("final_{unit}"),
        json!(record.last().map(|(_, v)| scale(*v))),
    );
    entry
}

fn record_of(times: &[Real], channel: &DriftChannel) -> Vec<(Real, Real)> {
    times
        .iter()
        .copied()
        .zip(channel.values.iter().copied())
        .collect()
}

/// The test as injected and, per true channel and true tilt (from the noise-free pairs), the
/// drift the standard reports (file units), for `truth.json`: `range_60_<unit>` (first 60 min),
/// `range_run_<unit>` (the running period, ISO 230-3 Table 1's d(·)_t), `range_<unit>` (the
/// whole record, cool-down included), `stop_min` (15 % criterion), `final_<unit>`; and the
/// speed that turned up to each reading.
pub fn truth(test: &SpindleThermalTest, run: &SpindleThermalRun) -> Value {
    let times = &run.table.times;
    let noise_free = DriftTable {
        times: times.clone(),
        channels: run.true_channels.clone(),
        temperatures: Vec::new(),
        conditions: DriftConditions::default(),
        columns_not_read: Vec::new(),
    };
    let derived = tilts(&noise_free, test.nest.spacing);
    let channels: Vec<Value> = run
        .true_channels
        .iter()
        .chain(&derived)
        .map(|c| {
            let unit = if c.angular { "urad" } else { "um" };
            let mut entry = ranges(&record_of(times, c), run.run_period, unit);
            entry.insert("name".into(), json!(c.name));
            entry.insert("unit".into(), json!(unit));
            Value::Object(entry)
        })
        .collect();
    let programme = match &test.speeds {
        SpeedProgramme::Constant { speed, run } => json!({
            "kind": "constant",
            "speed_rpm": rpm(*speed),
            "run_min": run / 60.0,
        }),
        SpeedProgramme::Spectrum(steps) => json!({
            "kind": "spectrum",
            "steps": steps.iter().map(|(s, d)| json!({
                "speed_rpm": rpm(*s), "duration_min": d / 60.0,
            })).collect::<Vec<_>>(),
            "run_min": test.speeds.run_period() / 60.0,
        }),
    };
    let hold: serde_json::Map<String, Value> = [Axis::X, Axis::Y, Axis::Z]
        .map(|a| {
            (
                a.letter().to_ascii_lowercase().to_string(),
                json!(test.hold[a] / M_PER_MM),
            )
        })
        .into_iter()
        .collect();
    json!({
        "test": SECTION,
        "hold_mm": hold,
        "programme": programme,
        "stop_min": test.stop / 60.0,
        "sample_min": test.sample / 60.0,
        "nest": {
            "first_mm": test.nest.first / M_PER_MM,
            "spacing_mm": test.nest.spacing / M_PER_MM,
            "noise_um": test.nest.noise * 1e6,
            "resolution_um": test.nest.resolution * 1e6,
        },
        "air_thermometer": { "noise_degc": test.air.noise, "resolution_degc": test.air.resolution },
        "speed_rpm_at_readings": run.speeds.iter().map(|s| rpm(*s)).collect::<Vec<_>>(),
        "true_channels": channels,
    })
}

impl SpindleThermalRun {
    /// One line for people: the Z drift over the running period and its first 60 min, and when
    /// the 15 % criterion would have let the running period stop, from the table.
    pub fn summary(&self) -> String {
        let hours = self.table.times.last().copied().unwrap_or(0.0) / 3600.0;
        let Some(z) = self.table.channels.iter().find(|c| c.name == "z") else {
            return format!("spindle thermal test: {hours:.1} h");
        };
        let record = record_of(&self.table.times, z);
        let start = record.first().map_or(0.0, |(t, _)| *t);
        let first = drift_ranges(&record).map(|r| r.0);
        let running = signed_range(&record, start, start + self.run_period);
        let um = |v: Option<Real>| v.map_or_else(|| "-".into(), |v| format!("{:.3} µm", v * 1e6));
        let stop = stop_time(&record).filter(|t| *t <= start + self.run_period);
        format!(
            "spindle thermal test: {hours:.1} h, Z drift {} over the {:.0} min running period ({} in the first 60 min){}",
            um(running),
            self.run_period / 60.0,
            um(first),
            stop.map_or_else(
                || ", the 15 % stop criterion not met while running".into(),
                |t| format!(", 15 % stop criterion met at {:.0} min", t / 60.0)
            ),
        )
    }
}
