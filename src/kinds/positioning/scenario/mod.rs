//! The sections of a laser test: `[iso230_2]` (here), the `[laser]` that measures it
//! ([`laser`]), and the thermal tests `[warmup]` and `[iso230_3_linear]` ([`thermal_tests`]).
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
//! ```

pub mod laser;
pub mod thermal_tests;

pub(crate) use laser::{RawLaser, air_temperature_given, laser_for, zero_given};

use crate::kinds::positioning::conditions::{PositioningConditions, PositioningTest};
use crate::kinds::positioning::laser::{Laser, Zeroing};
use crate::kinds::positioning::program::{LinearCycle, irregular_targets};
use crate::machine::{Axis, Machine};
use crate::math::{M_PER_MM, Real, seeded_rng};
use crate::program::Program;
use crate::scenario::bounds::{self, Bound};
use crate::scenario::parked::{self, Why};
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

/// A linear positioning test and the laser that measures it.
#[derive(Clone, Debug, PartialEq)]
pub struct LaserTest {
    /// Which test it is.
    pub test: PositioningTest,
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

impl LaserTest {
    /// The conditions its table carries in its preamble.
    pub fn conditions(&self) -> PositioningConditions {
        PositioningConditions {
            test: Some(self.test),
            axis: Some(self.laser.axis),
            runs: Some(self.runs),
            targets: Some(self.targets.clone()),
            compensation: Some(self.laser.compensation_name().to_string()),
            ..Default::default()
        }
    }

    /// `laser: X, 9 targets × 5 runs, 7.9 min of programme`, as `mtwin check` lists it.
    pub fn describe(&self) -> String {
        let duration = self.program.duration();
        let duration = if duration < 7200.0 {
            format!("{:.1} min", duration / 60.0)
        } else {
            format!("{:.1} h", duration / 3600.0)
        };
        format!(
            "laser: {}, {} targets × {} runs, {duration} of programme",
            self.laser.axis,
            self.targets.len(),
            self.runs,
        )
    }
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
    let axis = thermal_tests::linear_axis(t.axis.get_ref()).ok_or_else(|| {
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
    let bounded = |value: &Spanned<Real>, key: &str, bound: Bound| -> Result<Real, ScenarioError> {
        bound
            .check(*value.get_ref())
            .map_err(|message| fail(value.span(), key, message))
    };
    let feed = bounded(
        &t.feed_mm_per_min,
        "iso230_2.feed_mm_per_min",
        bounds::FEED_MM_PER_MIN,
    )? * M_PER_MM
        / 60.0;
    let dwell = bounded(&t.dwell_s, "iso230_2.dwell_s", bounds::DWELL_S)?;
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
    let given = [
        (Axis::X, "x_mm", &t.x_mm),
        (Axis::Y, "y_mm", &t.y_mm),
        (Axis::Z, "z_mm", &t.z_mm),
        (Axis::A, "a_deg", &t.a_deg),
        (Axis::B, "b_deg", &t.b_deg),
        (Axis::C, "c_deg", &t.c_deg),
    ];
    let rest = parked::parked(machine, axis, &given).map_err(|refused| {
        let other = refused.axis;
        let message = match refused.why {
            Why::UnderTest => {
                format!("{axis} is the axis under test; its positions are the targets")
            }
            Why::NoAxis => format!("machine \"{}\" has no axis {other}", machine.name()),
            Why::OutsideTravel { position, .. } => {
                format!("{position} is outside the travel of {other}")
            }
        };
        fail(
            refused.span.unwrap_or(0..0),
            &format!("iso230_2.{}", refused.key),
            message,
        )
    })?;
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
        test: PositioningTest::Iso230_2,
        program: cycle.program(),
        runs: cycle.runs,
        targets: cycle.targets,
        laser,
        material_sensor,
    })
}

/// The sections a laser test may be given by, as read (each optional).
pub(crate) struct RawSections<'a> {
    /// `[iso230_2]`.
    pub iso230_2: Option<&'a Spanned<RawIso230_2>>,
    /// `[warmup]`.
    pub warmup: Option<&'a Spanned<thermal_tests::RawWarmup>>,
    /// `[iso230_3_linear]`.
    pub iso230_3_linear: Option<&'a Spanned<thermal_tests::RawLinearMotion>>,
    /// `[laser]`.
    pub laser: Option<&'a Spanned<RawLaser>>,
    /// The scenario's `[thermal]` model, if it has one, and where its section is.
    pub thermal: Option<(&'a ThermalSetup, std::ops::Range<usize>)>,
}

/// The laser test of a scenario, if it has one: at most one of `[iso230_2]`, `[warmup]`,
/// `[iso230_3_linear]`, and the `[laser]` that measures it. The thermal tests need the
/// scenario's `[thermal]` model; any test runs through it when there is one.
pub(crate) fn sections(
    context: &Context<'_>,
    machine: &Machine,
    seed: u64,
    raw: RawSections<'_>,
) -> Result<Option<LaserTest>, ScenarioError> {
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
    let thermal = raw.thermal.as_ref().map(|(setup, _)| *setup);
    if let (Some(span), None) = (tests[1].clone().or(tests[2].clone()), thermal) {
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
        Some(thermal_tests::warmup_test(context, machine, warmup, laser)?)
    } else if let Some(linear) = raw.iso230_3_linear {
        Some(thermal_tests::linear_motion_test(
            context, machine, linear, laser,
        )?)
    } else {
        None
    };
    if let (Some((setup, span)), Some(test)) = (&raw.thermal, &laser_test) {
        setup.check_steps(context, span.clone(), test.program.duration())?;
    }
    if let (Some(_), Some(span)) = (thermal, raw.laser.and_then(air_temperature_given)) {
        return Err(context.error(
            Some(span),
            ScenarioErrorKind::Value,
            "laser.air.temperature_degc: with [thermal] the laser's air is the machine's air (its ambient); set it there",
        ));
    }
    if let Some((node, _)) = laser_test.as_ref().and_then(|t| t.material_sensor.as_ref()) {
        let known = thermal.is_some_and(|t| t.thermal.network.node(node).is_some());
        if !known {
            let span = raw.laser.map(|l| l.span());
            return Err(context.error(
                span,
                ScenarioErrorKind::Value,
                format!("laser.material.node: \"{node}\" is not a node of the [thermal] model (a material sensor on a node needs one)"),
            ));
        }
    }
    Ok(laser_test)
}
