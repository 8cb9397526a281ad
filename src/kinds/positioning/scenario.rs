//! The `[iso230_2]` and `[laser]` sections: a linear positioning test measured by a laser
//! interferometer.
//!
//! ```toml
//! [iso230_2]
//! axis = "X"
//! targets_mm = { from = 10.0, to = 750.0, count = 9 }   # irregular spacing, seeded
//! runs = 5
//! overrun_mm = 5.0
//! feed_mm_per_min = 2000.0
//! dwell_s = 2.0
//! y_mm = 205.0                  # where the other axes stand (default: mid-travel, rotary 0)
//!
//! [laser]
//! beam_offset_mm = [0.0, 0.0, 60.0]   # reflector from the tool tip, tool frame (Abbe offset)
//! misalignment_urad = [0.0, 0.0]      # beam tilt towards the two other axes, ISO order (cosine error)
//! resolution_nm = 1.0
//! noise_nm = 10.0
//! compensation = "sensors"            # or "off": standard air assumed
//! air = { temperature_degc = 20.0, pressure_hpa = 1013.25, humidity_pct = 50.0 }
//! sensor_offsets = { temperature_degc = 0.0, pressure_hpa = 0.0, humidity_pct = 0.0 }
//! material = { expansion_ppm_per_degc = 11.7, temperature_degc = 20.0 }   # NDE, optional
//! dead_path_mm = 100.0                # beam length at the zero (matters when the air changes)
//! zero = "each_run"                   # or "once" (drift tests)
//! interferometer_on = "workpiece"     # or "tool" (the reverse set-up)
//! ```

use crate::kinds::positioning::Air;
use crate::kinds::positioning::laser::{
    AirCompensation, Laser, MaterialCompensation, Mounting, Zeroing,
};
use crate::kinds::positioning::{LinearCycle, irregular_targets};
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::{M_PER_MM, RAD_PER_DEG, RAD_PER_URAD, Real, Vector, seeded_rng};
use crate::program::Event;
use crate::program::Program;
use crate::scenario::thermal::{RawThermal, thermal_setup};
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind, ThermalSetup};
use serde::Deserialize;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawIso230_2 {
    axis: Spanned<String>,
    targets_mm: Spanned<RawTargets>,
    #[serde(default = "default_runs")]
    runs: Spanned<usize>,
    #[serde(default = "default_overrun")]
    overrun_mm: Spanned<Real>,
    #[serde(default = "default_feed")]
    feed_mm_per_min: Spanned<Real>,
    #[serde(default = "default_dwell")]
    dwell_s: Spanned<Real>,
    x_mm: Option<Spanned<Real>>,
    y_mm: Option<Spanned<Real>>,
    z_mm: Option<Spanned<Real>>,
    a_deg: Option<Spanned<Real>>,
    b_deg: Option<Spanned<Real>>,
    c_deg: Option<Spanned<Real>>,
}

fn default_runs() -> Spanned<usize> {
    Spanned::new(0..0, 5)
}
fn default_overrun() -> Spanned<Real> {
    Spanned::new(0..0, 5.0)
}
fn default_feed() -> Spanned<Real> {
    Spanned::new(0..0, 2000.0)
}
fn default_dwell() -> Spanned<Real> {
    Spanned::new(0..0, 2.0)
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct RawTargets {
    from: Real,
    to: Real,
    count: usize,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLaser {
    #[serde(default)]
    beam_offset_mm: Option<Spanned<[Real; 3]>>,
    #[serde(default)]
    misalignment_urad: Option<Spanned<[Real; 2]>>,
    #[serde(default = "default_resolution")]
    resolution_nm: Spanned<Real>,
    #[serde(default)]
    noise_nm: Option<Spanned<Real>>,
    #[serde(default)]
    compensation: Option<Spanned<String>>,
    #[serde(default)]
    air: Option<Spanned<RawAir>>,
    #[serde(default)]
    sensor_offsets: Option<Spanned<RawAir>>,
    #[serde(default)]
    material: Option<Spanned<RawMaterial>>,
    /// `each_run` (default) or `once`.
    #[serde(default)]
    zero: Option<Spanned<String>>,
    #[serde(default)]
    dead_path_mm: Option<Spanned<Real>>,
    /// `workpiece` (default) or `tool`.
    #[serde(default)]
    interferometer_on: Option<Spanned<String>>,
}

fn default_resolution() -> Spanned<Real> {
    Spanned::new(0..0, 1.0)
}

#[derive(Deserialize, Clone, Copy, Default)]
#[serde(deny_unknown_fields)]
struct RawAir {
    temperature_degc: Option<Real>,
    pressure_hpa: Option<Real>,
    humidity_pct: Option<Real>,
}

#[derive(Deserialize, Clone)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    expansion_ppm_per_degc: Real,
    /// A fixed material temperature…
    temperature_degc: Option<Real>,
    /// …or a sensor on a node of the thermal model, with its offset.
    node: Option<String>,
    #[serde(default)]
    offset_degc: Real,
}

/// A linear positioning test and the laser that measures it.
#[derive(Clone, Debug, PartialEq)]
pub struct LaserTest {
    /// Target positions along the laser's axis (m), indexed by the programme's measure points.
    pub targets: Vec<Real>,
    /// Number of runs.
    pub runs: usize,
    /// Everything the machine does during the test (for a warm-up experiment, the idle
    /// running between runs too).
    pub program: Program,
    /// The instrument.
    pub laser: Laser,
    /// The material sensor of NDE compensation, when it sits on a node of the thermal model:
    /// (node name, sensor offset °C).
    pub material_sensor: Option<(String, Real)>,
}

pub(crate) fn laser_test(
    context: &Context<'_>,
    machine: &Machine,
    seed: u64,
    test: &Spanned<RawIso230_2>,
    laser: Option<&Spanned<RawLaser>>,
) -> Result<LaserTest, ScenarioError> {
    let t = test.get_ref();
    let fail = |span: std::ops::Range<usize>, key: &str, message: String| {
        let span = if span.is_empty() { test.span() } else { span };
        context.error(
            Some(span),
            ScenarioErrorKind::Value,
            format!("{key}: {message}"),
        )
    };
    let axis = super::thermal_tests::linear_axis(t.axis.get_ref()).ok_or_else(|| {
        fail(
            t.axis.span(),
            "iso230_2.axis",
            format!("\"{}\": expected \"X\", \"Y\" or \"Z\"", t.axis.get_ref()),
        )
    })?;
    let info = machine.axis(axis).expect("every machine has X, Y, Z");
    let (lower, upper) = info.limits.expect("linear axes have limits");
    let RawTargets { from, to, count } = *t.targets_mm.get_ref();
    let targets_span = t.targets_mm.span();
    if !(from.is_finite() && to.is_finite() && from < to) {
        return Err(fail(
            targets_span,
            "iso230_2.targets_mm",
            "from and to must be finite with from < to".into(),
        ));
    }
    if !(2..=10_000).contains(&count) {
        return Err(fail(
            targets_span,
            "iso230_2.targets_mm",
            format!("count must be 2 to 10000, got {count}"),
        ));
    }
    let positive =
        |value: &Spanned<Real>, key: &str, allow_zero: bool| -> Result<Real, ScenarioError> {
            let v = *value.get_ref();
            let ok = v.is_finite() && (v > 0.0 || (allow_zero && v == 0.0));
            if ok {
                Ok(v)
            } else {
                Err(fail(
                    value.span(),
                    key,
                    format!(
                        "expected a {} number, got {v}",
                        if allow_zero {
                            "non-negative"
                        } else {
                            "positive"
                        }
                    ),
                ))
            }
        };
    let overrun = positive(&t.overrun_mm, "iso230_2.overrun_mm", true)? * M_PER_MM;
    let feed = positive(&t.feed_mm_per_min, "iso230_2.feed_mm_per_min", false)? * M_PER_MM / 60.0;
    let dwell = positive(&t.dwell_s, "iso230_2.dwell_s", true)?;
    let runs = *t.runs.get_ref();
    if !(2..=1000).contains(&runs) {
        return Err(fail(
            t.runs.span(),
            "iso230_2.runs",
            format!("repeatability needs 2 to 1000 runs (ISO 230-2: 5), got {runs}"),
        ));
    }
    let (start, end) = (from * M_PER_MM - overrun, to * M_PER_MM + overrun);
    if !(info.within_travel(start) && info.within_travel(end)) {
        return Err(fail(
            targets_span,
            "iso230_2.targets_mm",
            format!(
                "the targets with their {} mm overrun span {} .. {} mm, beyond the travel of {axis} ({} .. {} mm)",
                overrun / M_PER_MM,
                start / M_PER_MM,
                end / M_PER_MM,
                lower / M_PER_MM,
                upper / M_PER_MM
            ),
        ));
    }
    let targets = irregular_targets(
        from * M_PER_MM,
        to * M_PER_MM,
        count,
        &mut seeded_rng(seed, "iso230_2 targets"),
    );

    // Where the other axes stand: as given, else mid-travel (rotary axes at zero).
    let mut rest = AxisValues::ZERO;
    let given = [
        (Axis::X, "x_mm", &t.x_mm),
        (Axis::Y, "y_mm", &t.y_mm),
        (Axis::Z, "z_mm", &t.z_mm),
        (Axis::A, "a_deg", &t.a_deg),
        (Axis::B, "b_deg", &t.b_deg),
        (Axis::C, "c_deg", &t.c_deg),
    ];
    for (other, key, value) in given {
        let key = format!("iso230_2.{key}");
        match (machine.axis(other), value) {
            (_, Some(v)) if other == axis => {
                return Err(fail(
                    v.span(),
                    &key,
                    format!("{axis} is the axis under test; its positions are the targets"),
                ));
            }
            (None, Some(v)) => {
                return Err(fail(
                    v.span(),
                    &key,
                    format!("machine \"{}\" has no axis {other}", machine.name()),
                ));
            }
            (None, None) => {}
            (Some(info), value) => {
                let scale = if other.is_linear() {
                    M_PER_MM
                } else {
                    RAD_PER_DEG
                };
                let position = match (value, info.limits) {
                    (Some(v), _) => *v.get_ref() * scale,
                    (None, Some((lo, hi))) if other.is_linear() => (lo + hi) / 2.0,
                    (None, _) => 0.0,
                };
                if !info.within_travel(position) {
                    let span = value.as_ref().map_or(0..0, |v| v.span());
                    return Err(fail(
                        span,
                        &key,
                        format!("{} is outside the travel of {other}", position / scale),
                    ));
                }
                rest[other] = position;
            }
        }
    }
    let cycle = LinearCycle {
        axis,
        targets,
        runs,
        overrun,
        feed,
        dwell,
        rest,
    };
    let given_zero = zero_given(laser);
    let (mut laser, material_sensor) = laser_for(context, axis, laser)?;
    if !given_zero {
        laser.zero = Zeroing::Once; // ISO 230-2 practice: one datum for the whole test
    }
    Ok(LaserTest {
        program: cycle.program(),
        runs: cycle.runs,
        targets: cycle.targets,
        laser,
        material_sensor,
    })
}

/// The first key of `[laser]` that a drift test (ISO 230-3 §7.2.5: air compensation on, NDE
/// off, zeroed once at the start) cannot honour, with its span and why.
pub(crate) fn drift_conflict(raw: &Spanned<RawLaser>) -> Option<(std::ops::Range<usize>, String)> {
    let l = raw.get_ref();
    if let Some(c) = l.compensation.as_ref().filter(|c| c.get_ref() == "off") {
        return Some((
            c.span(),
            "laser.compensation: a drift test uses the air compensation (ISO 230-3 §7.2.5)".into(),
        ));
    }
    if let Some(m) = &l.material {
        return Some((m.span(), "laser.material: a drift test does not use NDE, which would hide the scale's expansion (ISO 230-3 §7.2.5)".into()));
    }
    if let Some(z) = l.zero.as_ref().filter(|z| z.get_ref() != "once") {
        return Some((
            z.span(),
            "laser.zero: a drift test is zeroed once, at the start".into(),
        ));
    }
    None
}

/// The span of `[laser] air.temperature_degc`, when given.
pub(crate) fn air_temperature_given(raw: &Spanned<RawLaser>) -> Option<std::ops::Range<usize>> {
    let l = raw.get_ref();
    l.air
        .as_ref()
        .filter(|a| a.get_ref().temperature_degc.is_some())
        .map(|a| a.span())
}

/// Whether `[laser]` says when to zero.
fn zero_given(raw: Option<&Spanned<RawLaser>>) -> bool {
    raw.is_some_and(|r| r.get_ref().zero.is_some())
}

/// The laser of the `[laser]` section on `axis` with its material sensor's node, or an ideal
/// laser (1 nm resolution, no noise, exact air compensation, reflector at the tool tip) without
/// the section.
pub(crate) fn laser_for(
    context: &Context<'_>,
    axis: Axis,
    raw: Option<&Spanned<RawLaser>>,
) -> Result<(Laser, Option<(String, Real)>), ScenarioError> {
    match raw {
        Some(raw) => laser_spec(context, axis, raw),
        None => Ok((
            Laser {
                axis,
                beam_offset: Vector::ZERO,
                misalignment: [0.0, 0.0],
                resolution: 1e-9,
                noise: 0.0,
                air: Air::STANDARD,
                compensation: AirCompensation::Sensors {
                    temperature_offset: 0.0,
                    pressure_offset: 0.0,
                    humidity_offset: 0.0,
                },
                material: None,
                dead_path: 0.0,
                zero: Zeroing::EachRun,
                mounting: Mounting::InterferometerOnWorkpiece,
            },
            None,
        )),
    }
}

fn laser_spec(
    context: &Context<'_>,
    axis: Axis,
    raw: &Spanned<RawLaser>,
) -> Result<(Laser, Option<(String, Real)>), ScenarioError> {
    let l = raw.get_ref();
    let fail = |span: std::ops::Range<usize>, key: &str, message: String| {
        let span = if span.is_empty() { raw.span() } else { span };
        context.error(
            Some(span),
            ScenarioErrorKind::Value,
            format!("laser.{key}: {message}"),
        )
    };
    let finite =
        |values: &[Real], span: std::ops::Range<usize>, key: &str| -> Result<(), ScenarioError> {
            match values.iter().all(|v| v.is_finite()) {
                true => Ok(()),
                false => Err(fail(span, key, "expected finite numbers".into())),
            }
        };
    let beam_offset = match &l.beam_offset_mm {
        Some(v) => {
            finite(v.get_ref(), v.span(), "beam_offset_mm")?;
            Vector::from_array(*v.get_ref()) * M_PER_MM
        }
        None => Vector::ZERO,
    };
    let misalignment = match &l.misalignment_urad {
        Some(v) => {
            finite(v.get_ref(), v.span(), "misalignment_urad")?;
            v.get_ref().map(|m| m * RAD_PER_URAD)
        }
        None => [0.0, 0.0],
    };
    let non_negative =
        |v: Real, span: std::ops::Range<usize>, key: &str| -> Result<Real, ScenarioError> {
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(fail(
                    span,
                    key,
                    format!("expected a non-negative number, got {v}"),
                ))
            }
        };
    let resolution = non_negative(
        *l.resolution_nm.get_ref(),
        l.resolution_nm.span(),
        "resolution_nm",
    )? * 1e-9;
    let noise = match &l.noise_nm {
        Some(v) => non_negative(*v.get_ref(), v.span(), "noise_nm")? * 1e-9,
        None => 0.0,
    };
    let air_raw = l.air.as_ref().map(|a| *a.get_ref()).unwrap_or_default();
    let air = Air {
        temperature: air_raw
            .temperature_degc
            .unwrap_or(Air::STANDARD.temperature),
        pressure: air_raw
            .pressure_hpa
            .map_or(Air::STANDARD.pressure, |p| p * 100.0),
        humidity: air_raw.humidity_pct.unwrap_or(Air::STANDARD.humidity),
    };
    let air_span = l.air.as_ref().map_or(0..0, |a| a.span());
    let plausible_air = (-10.0..=60.0).contains(&air.temperature)
        && (50_000.0..=120_000.0).contains(&air.pressure)
        && (0.0..=100.0).contains(&air.humidity);
    if !plausible_air {
        return Err(fail(
            air_span,
            "air",
            "expected -10..60 °C, 500..1200 hPa, 0..100 %RH".into(),
        ));
    }
    let offsets = l
        .sensor_offsets
        .as_ref()
        .map(|a| *a.get_ref())
        .unwrap_or_default();
    let offset_values = [
        offsets.temperature_degc,
        offsets.pressure_hpa,
        offsets.humidity_pct,
    ]
    .map(|v| v.unwrap_or(0.0));
    finite(
        &offset_values,
        l.sensor_offsets.as_ref().map_or(0..0, |a| a.span()),
        "sensor_offsets",
    )?;
    let assumed = Air {
        temperature: air.temperature + offset_values[0],
        pressure: air.pressure + offset_values[1] * 100.0,
        humidity: air.humidity + offset_values[2],
    };
    let plausible_assumed = (-10.0..=60.0).contains(&assumed.temperature)
        && (50_000.0..=120_000.0).contains(&assumed.pressure)
        && (0.0..=100.0).contains(&assumed.humidity);
    if !plausible_assumed {
        let span = l.sensor_offsets.as_ref().map_or(0..0, |a| a.span());
        return Err(fail(
            span,
            "sensor_offsets",
            "the sensors would read beyond -10..60 °C, 500..1200 hPa or 0..100 %RH".into(),
        ));
    }
    let compensation = match l.compensation.as_ref().map(|c| c.get_ref().as_str()) {
        None | Some("sensors") => AirCompensation::Sensors {
            temperature_offset: offset_values[0],
            pressure_offset: offset_values[1] * 100.0,
            humidity_offset: offset_values[2],
        },
        Some("off") => AirCompensation::Off,
        Some(other) => {
            let span = l.compensation.as_ref().map_or(0..0, |c| c.span());
            return Err(fail(
                span,
                "compensation",
                format!("\"{other}\": expected \"sensors\" or \"off\""),
            ));
        }
    };
    let (material, material_sensor) = match &l.material {
        Some(m) => {
            let RawMaterial {
                expansion_ppm_per_degc,
                temperature_degc,
                node,
                offset_degc,
            } = m.get_ref().clone();
            finite(&[expansion_ppm_per_degc, offset_degc], m.span(), "material")?;
            let sensor = match (temperature_degc, node) {
                (Some(t), None) if t.is_finite() => None,
                (None, Some(node)) => Some((node, offset_degc)),
                _ => {
                    return Err(fail(
                        m.span(),
                        "material",
                        "give either temperature_degc or node (a thermal-model node)".into(),
                    ));
                }
            };
            let fixed = temperature_degc.unwrap_or(20.0);
            (
                Some(MaterialCompensation {
                    expansion: expansion_ppm_per_degc * 1e-6,
                    measured_temperature: fixed,
                }),
                sensor,
            )
        }
        None => (None, None),
    };
    let dead_path = match &l.dead_path_mm {
        Some(v) => non_negative(*v.get_ref(), v.span(), "dead_path_mm")? * M_PER_MM,
        None => 0.0,
    };
    let zero = match l.zero.as_ref().map(|z| z.get_ref().as_str()) {
        None | Some("each_run") => Zeroing::EachRun,
        Some("once") => Zeroing::Once,
        Some(other) => {
            let span = l.zero.as_ref().map_or(0..0, |z| z.span());
            return Err(fail(
                span,
                "zero",
                format!("\"{other}\": expected \"each_run\" or \"once\""),
            ));
        }
    };
    let mounting = match l.interferometer_on.as_ref().map(|m| m.get_ref().as_str()) {
        None | Some("workpiece") => Mounting::InterferometerOnWorkpiece,
        Some("tool") => Mounting::InterferometerOnTool,
        Some(other) => {
            let span = l.interferometer_on.as_ref().map_or(0..0, |m| m.span());
            return Err(fail(
                span,
                "interferometer_on",
                format!("\"{other}\": expected \"workpiece\" or \"tool\""),
            ));
        }
    };
    let laser = Laser {
        axis,
        beam_offset,
        misalignment,
        resolution,
        noise,
        air,
        compensation,
        material,
        dead_path,
        zero,
        mounting,
    };
    Ok((laser, material_sensor))
}

/// The sections a laser test may be given by, as read (each optional).
pub(crate) struct RawSections<'a> {
    /// `[iso230_2]`.
    pub iso230_2: Option<&'a Spanned<RawIso230_2>>,
    /// `[warmup]`.
    pub warmup: Option<&'a Spanned<super::thermal_tests::RawWarmup>>,
    /// `[iso230_3_linear]`.
    pub iso230_3_linear: Option<&'a Spanned<super::thermal_tests::RawLinearMotion>>,
    /// `[laser]`.
    pub laser: Option<&'a Spanned<RawLaser>>,
    /// `[thermal]`, which a laser test runs through and nothing else uses.
    pub thermal: Option<&'a Spanned<RawThermal>>,
}

/// The laser test of a scenario, if it has one, with the thermal model it runs through: at
/// most one of `[iso230_2]`, `[warmup]`, `[iso230_3_linear]`, the `[laser]` that measures
/// it, and `[thermal]` (needed by the thermal tests, used by nothing else).
pub(crate) fn sections(
    context: &Context<'_>,
    machine: &Machine,
    seed: u64,
    raw: RawSections<'_>,
) -> Result<(Option<ThermalSetup>, Option<LaserTest>), ScenarioError> {
    let tests = [
        raw.iso230_2.map(|t| t.span()),
        raw.warmup.map(|t| t.span()),
        raw.iso230_3_linear.map(|t| t.span()),
    ];
    let given: Vec<_> = tests.iter().flatten().collect();
    if let (true, Some(laser)) = (given.is_empty(), raw.laser) {
        return Err(context.error(
            Some(laser.span()),
            ScenarioErrorKind::Nothing,
            "laser: a laser needs a test to measure; add an [iso230_2], [warmup] or [iso230_3_linear] section",
        ));
    }
    if given.len() > 1 {
        return Err(context.error(
            Some(given[1].clone()),
            ScenarioErrorKind::Value,
            "one laser test per scenario: [iso230_2], [warmup] or [iso230_3_linear]",
        ));
    }
    let thermal = raw
        .thermal
        .as_ref()
        .map(|t| thermal_setup(context, machine, t))
        .transpose()?;
    if let (Some(span), None) = (tests[1].clone().or(tests[2].clone()), &thermal) {
        return Err(context.error(
            Some(span),
            ScenarioErrorKind::Value,
            "warmup and iso230_3_linear are thermal tests: add a [thermal] section with the machine's thermal model",
        ));
    }
    let laser = raw.laser;
    let laser_test = if let Some(test) = raw.iso230_2 {
        Some(laser_test(context, machine, seed, test, laser)?)
    } else if let Some(warmup) = raw.warmup {
        Some(super::thermal_tests::warmup_test(
            context, machine, warmup, laser,
        )?)
    } else if let Some(linear) = raw.iso230_3_linear {
        Some(super::thermal_tests::linear_motion_test(
            context, machine, linear, laser,
        )?)
    } else {
        None
    };
    if let (Some(setup), Some(test)) = (&thermal, &laser_test) {
        let duration: Real = test
            .program
            .timeline(Real::INFINITY)
            .iter()
            .map(|e| match e {
                Event::Interval(i) => i.duration,
                Event::Measure(_) => 0.0,
            })
            .sum();
        if duration / setup.max_interval > 5e6 {
            return Err(context.error(
                raw.thermal.map(|t| t.span()),
                ScenarioErrorKind::Value,
                format!(
                    "thermal.max_interval_s: {:.1} h in steps of {} s is more than five million steps",
                    duration / 3600.0,
                    setup.max_interval
                ),
            ));
        }
    }
    if let (Some(_), Some(span)) = (&thermal, raw.laser.and_then(air_temperature_given)) {
        return Err(context.error(
            Some(span),
            ScenarioErrorKind::Value,
            "laser.air.temperature_degc: with [thermal] the laser's air is the machine's air (its ambient); set it there",
        ));
    }
    if let (Some(section), None) = (raw.thermal, &laser_test) {
        return Err(context.error(
            Some(section.span()),
            ScenarioErrorKind::Nothing,
            "thermal: nothing in this scenario uses the thermal model; add a laser test ([iso230_2], [warmup] or [iso230_3_linear])",
        ));
    }
    if let Some((node, _)) = laser_test.as_ref().and_then(|t| t.material_sensor.as_ref()) {
        let known = thermal
            .as_ref()
            .is_some_and(|t| t.thermal.network.node(node).is_some());
        if !known {
            let span = raw.laser.map(|l| l.span());
            return Err(context.error(
                span,
                ScenarioErrorKind::Value,
                format!("laser.material.node: \"{node}\" is not a node of the [thermal] model (a material sensor on a node needs one)"),
            ));
        }
    }
    Ok((thermal, laser_test))
}
