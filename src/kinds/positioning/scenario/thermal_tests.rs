//! The thermal tests measured by the laser: the `[warmup]` experiment (Lu 2012 Ch. 5: runs over
//! the axis between idle-running warm-up intervals, the nut temperature recorded at each run)
//! and the ISO 230-3 §7 linear-motion test (`[iso230_3_linear]`). Both need the machine's
//! `[thermal]` model ([`crate::scenario::thermal`]).
//!
//! ```toml
//! [warmup]
//! axis = "X"
//! targets_mm = { from = 0.0, to = 750.0, step = 50.0 }
//! runs = 7
//! overrun_mm = 5.0
//! feed_mm_per_min = 2000.0
//! dwell_s = 2.0
//! idle = { from_mm = 0.0, to_mm = 750.0, feed_mm_per_min = 4800.0, minutes = 45.0 }   # between runs
//! ```

use super::{LaserTest, RawLaser, laser_for};
use crate::kinds::positioning::conditions::PositioningTest;
use crate::kinds::positioning::program::LinearCycle;
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::{M_PER_MM, Real};
use crate::program::{Program, Step};
use crate::scenario::bounds;
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind};
use serde::Deserialize;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawWarmup {
    axis: Spanned<String>,
    targets_mm: Spanned<RawTargets>,
    #[serde(default = "seven")]
    runs: usize,
    #[serde(default = "five")]
    overrun_mm: Real,
    #[serde(default = "two_thousand")]
    feed_mm_per_min: Real,
    #[serde(default = "two")]
    dwell_s: Real,
    idle: Spanned<RawIdle>,
    y_mm: Option<Real>,
    z_mm: Option<Real>,
    x_mm: Option<Real>,
}

fn seven() -> usize {
    7
}
fn five() -> Real {
    5.0
}
fn two_thousand() -> Real {
    2000.0
}
fn two() -> Real {
    2.0
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct RawTargets {
    from: Real,
    to: Real,
    step: Real,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct RawIdle {
    from_mm: Real,
    to_mm: Real,
    feed_mm_per_min: Real,
    minutes: Real,
}

/// The `[warmup]` experiment as a laser test: laser runs between idle-running intervals.
pub(crate) fn warmup_test(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawWarmup>,
    laser: Option<&Spanned<RawLaser>>,
) -> Result<LaserTest, ScenarioError> {
    let w = raw.get_ref();
    let fail = |span: std::ops::Range<usize>, message: String| {
        context.section_error(span, ScenarioErrorKind::Value, "warmup.", message)
    };
    let axis = linear_axis(w.axis.get_ref()).ok_or_else(|| {
        fail(
            w.axis.span(),
            format!(
                "axis: \"{}\": expected \"X\", \"Y\" or \"Z\"",
                w.axis.get_ref()
            ),
        )
    })?;
    let info = machine.axis(axis).expect("every machine has X, Y, Z");
    let RawTargets { from, to, step } = *w.targets_mm.get_ref();
    let span = w.targets_mm.span();
    if !(from.is_finite() && to.is_finite() && step.is_finite() && step > 0.0 && from < to) {
        return Err(fail(
            span,
            "targets_mm: finite from < to and a positive step".into(),
        ));
    }
    // Counted in f64 first: (to − from)/step of 1e300 is no usize.
    let intervals = ((to - from) / step + 1e-9).floor();
    if !(1.0..=9_999.0).contains(&intervals) {
        return Err(fail(
            span,
            format!(
                "targets_mm: {} targets; expected 2 to 10000",
                crate::math::readable(intervals + 1.0)
            ),
        ));
    }
    let count = intervals as usize + 1;
    let targets: Vec<Real> = (0..count)
        .map(|i| (from + step * i as Real) * M_PER_MM)
        .collect();
    let overrun = w.overrun_mm * M_PER_MM;
    let ends = [targets[0] - overrun, targets[count - 1] + overrun];
    let overrun_ok = w.overrun_mm.is_finite() && w.overrun_mm >= 0.0;
    if !(overrun_ok && ends.iter().all(|e| info.within_travel(*e))) {
        return Err(fail(
            span,
            format!(
                "targets_mm: with the {} mm overrun they leave the travel of {axis}",
                w.overrun_mm
            ),
        ));
    }
    let timing = [
        (
            "feed_mm_per_min",
            w.feed_mm_per_min,
            bounds::FEED_MM_PER_MIN,
        ),
        ("dwell_s", w.dwell_s, bounds::DWELL_S),
    ];
    for (key, value, bound) in timing {
        bound
            .check(value)
            .map_err(|message| fail(raw.span(), format!("{key}: {message}")))?;
    }
    if !(2..=1000).contains(&w.runs) {
        return Err(fail(raw.span(), format!("runs: 2 to 1000, got {}", w.runs)));
    }
    let idle = *w.idle.get_ref();
    let (lower, upper) = info.limits.expect("linear axes have limits");
    let travel = format!(
        "a position within the travel of {axis} ({} .. {} mm)",
        lower / M_PER_MM,
        upper / M_PER_MM
    );
    let problem = [
        (
            "from_mm",
            idle.from_mm,
            info.within_travel(idle.from_mm * M_PER_MM),
            travel.as_str(),
        ),
        (
            "to_mm",
            idle.to_mm,
            info.within_travel(idle.to_mm * M_PER_MM),
            travel.as_str(),
        ),
        (
            "feed_mm_per_min",
            idle.feed_mm_per_min,
            bounds::FEED_MM_PER_MIN.check(idle.feed_mm_per_min).is_ok(),
            "0.1 … 200000 mm/min",
        ),
        (
            "minutes",
            idle.minutes,
            (0.0..=14_400.0).contains(&idle.minutes),
            "0 to 14400 minutes",
        ),
    ]
    .into_iter()
    .find(|(_, value, ok, _)| !(value.is_finite() && *ok));
    if let Some((key, value, _, expected)) = problem {
        return Err(fail(
            w.idle.span(),
            format!("idle.{key}: {value}; expected {expected}"),
        ));
    }
    let rest = rest_positions(
        machine,
        axis,
        [(Axis::X, w.x_mm), (Axis::Y, w.y_mm), (Axis::Z, w.z_mm)],
    )
    .map_err(|message| fail(raw.span(), message))?;
    let cycle = LinearCycle {
        axis,
        targets,
        runs: 1,
        overrun,
        feed: w.feed_mm_per_min * M_PER_MM / 60.0,
        dwell: w.dwell_s,
        rest,
    };
    let mut steps = Vec::new();
    for run in 0..w.runs {
        if run > 0 {
            steps.push(Step::WarmUp {
                axis,
                from: idle.from_mm * M_PER_MM,
                to: idle.to_mm * M_PER_MM,
                feed: idle.feed_mm_per_min * M_PER_MM / 60.0,
                duration: idle.minutes * 60.0,
            });
        }
        steps.push(Step::Move {
            to: vec![(axis, ends[0])],
            feed: cycle.feed,
        });
        steps.extend(cycle.run_steps(run));
    }
    let mut start = rest;
    start[axis] = ends[0];
    let (laser, material_sensor) = laser_for(context, axis, laser)?;
    Ok(LaserTest {
        test: PositioningTest::Warmup,
        program: Program { start, steps },
        targets: cycle.targets,
        runs: w.runs,
        laser,
        material_sensor,
    })
}

/// `[iso230_3_linear]`: the ISO 230-3 §7 linear-motion test.
///
/// ```toml
/// [iso230_3_linear]
/// axis = "X"
/// targets_mm = [20.0, 740.0]      # P1, P2: near the ends of travel
/// feed_mm_per_min = 10000.0       # a share of the fastest programmable feed
/// dwell_s = 2.0
/// cycling_min = 240.0
/// read_every = 5                  # bidirectional cycles between readings
/// cooldown_min = 60.0
/// visit_every_min = 5.0
/// ```
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLinearMotion {
    axis: Spanned<String>,
    targets_mm: Spanned<[Real; 2]>,
    #[serde(default = "ten_thousand")]
    feed_mm_per_min: Real,
    #[serde(default = "two")]
    dwell_s: Real,
    #[serde(default = "two_forty")]
    cycling_min: Real,
    #[serde(default = "five_cycles")]
    read_every: usize,
    #[serde(default = "sixty_min")]
    cooldown_min: Real,
    #[serde(default = "five")]
    visit_every_min: Real,
    x_mm: Option<Real>,
    y_mm: Option<Real>,
    z_mm: Option<Real>,
}

fn ten_thousand() -> Real {
    10_000.0
}
fn two_forty() -> Real {
    240.0
}
fn five_cycles() -> usize {
    5
}
fn sixty_min() -> Real {
    60.0
}

/// The `[iso230_3_linear]` test as a laser test. ISO 230-3 §7.2.5: air compensation on, NDE off,
/// all readings zeroed once at the start; `[laser]` keys that say otherwise are refused.
pub(crate) fn linear_motion_test(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawLinearMotion>,
    laser: Option<&Spanned<RawLaser>>,
) -> Result<LaserTest, ScenarioError> {
    let m = raw.get_ref();
    let fail = |span: std::ops::Range<usize>, message: String| {
        context.section_error(span, ScenarioErrorKind::Value, "iso230_3_linear.", message)
    };
    let axis = linear_axis(m.axis.get_ref()).ok_or_else(|| {
        fail(
            m.axis.span(),
            format!(
                "axis: \"{}\": expected \"X\", \"Y\" or \"Z\"",
                m.axis.get_ref()
            ),
        )
    })?;
    let info = machine.axis(axis).expect("every machine has X, Y, Z");
    let [p1, p2] = m.targets_mm.get_ref().map(|t| t * M_PER_MM);
    if !(p1.is_finite()
        && p2.is_finite()
        && p1 < p2
        && info.within_travel(p1)
        && info.within_travel(p2))
    {
        return Err(fail(
            m.targets_mm.span(),
            format!("targets_mm: two positions P1 < P2 within the travel of {axis}"),
        ));
    }
    let numbers = [
        m.feed_mm_per_min,
        m.dwell_s,
        m.cycling_min,
        m.cooldown_min,
        m.visit_every_min,
    ];
    let valid = numbers.iter().all(|v| v.is_finite())
        && bounds::FEED_MM_PER_MIN.check(m.feed_mm_per_min).is_ok()
        && (0.0..=3600.0).contains(&m.dwell_s)
        && m.cycling_min > 0.0
        && m.cycling_min <= 14_400.0
        && (0.0..=14_400.0).contains(&m.cooldown_min)
        && m.visit_every_min > 0.0
        && m.read_every >= 1;
    if !valid {
        return Err(fail(raw.span(), "feed 0.1 to 200000 mm/min; cycling (at most 14400 min) and visit interval positive; dwell 0 to 3600 s; cool-down 0 to 14400 min; read_every ≥ 1".into()));
    }
    if m.cooldown_min / m.visit_every_min > 1e6 {
        return Err(fail(
            raw.span(),
            format!(
                "visit_every_min: {} visits in the cool-down; at most a million",
                crate::math::readable((m.cooldown_min / m.visit_every_min).floor())
            ),
        ));
    }
    let rest = rest_positions(
        machine,
        axis,
        [(Axis::X, m.x_mm), (Axis::Y, m.y_mm), (Axis::Z, m.z_mm)],
    )
    .map_err(|message| fail(raw.span(), message))?;
    let cycle_s = 2.0 * ((p2 - p1) / (m.feed_mm_per_min * M_PER_MM / 60.0) + m.dwell_s);
    if m.cycling_min * 60.0 / cycle_s > 1e6 {
        return Err(fail(
            raw.span(),
            format!(
                "cycling_min: {:.0} cycles of {cycle_s:.3} s; at most a million",
                m.cycling_min * 60.0 / cycle_s
            ),
        ));
    }
    // A cool-down visit goes from mid-travel to P1, to P2 and back: it must fit its interval,
    // and the cool-down must hold at least one.
    let visit_s = 2.0 * (p2 - p1) / (m.feed_mm_per_min * M_PER_MM / 60.0) + 2.0 * m.dwell_s;
    if m.cooldown_min > 0.0
        && (m.visit_every_min * 60.0 < visit_s || m.visit_every_min > m.cooldown_min)
    {
        return Err(fail(
            raw.span(),
            format!(
                "visit_every_min: a cool-down visit takes {:.2} min; visit_every_min must be at least that and at most cooldown_min",
                visit_s / 60.0
            ),
        ));
    }
    let test = crate::kinds::positioning::program::LinearMotionTest {
        axis,
        targets: [p1, p2],
        feed: m.feed_mm_per_min * M_PER_MM / 60.0,
        dwell: m.dwell_s,
        cycling: m.cycling_min * 60.0,
        read_every: m.read_every,
        cooldown: m.cooldown_min * 60.0,
        visit_interval: m.visit_every_min * 60.0,
        rest,
    };
    let program = test.program();
    let runs = crate::program::visits(&program.timeline(Real::INFINITY)).len() / 2;
    if let Some((span, message)) = laser.and_then(super::laser::drift_conflict) {
        return Err(context.error(Some(span), ScenarioErrorKind::Value, message));
    }
    let (mut laser, _) = laser_for(context, axis, laser)?;
    laser.zero = crate::kinds::positioning::setup::Zeroing::Once;
    Ok(LaserTest {
        test: PositioningTest::Iso230_3Linear,
        program,
        targets: vec![p1, p2],
        runs,
        laser,
        material_sensor: None,
    })
}

/// Where the linear axes other than `axis` stand during a test: as given (mm), else at
/// mid-travel. A position for the axis under test is refused (its positions are the test's).
fn rest_positions(
    machine: &Machine,
    axis: Axis,
    given: [(Axis, Option<Real>); 3],
) -> Result<AxisValues, String> {
    let mut rest = AxisValues::ZERO;
    for (other, value) in given {
        let key = format!("{}_mm", other.letter().to_ascii_lowercase());
        if other == axis {
            if value.is_some() {
                return Err(format!(
                    "{key}: {axis} is the axis under test; its positions come from the test"
                ));
            }
            continue;
        }
        let info = machine.axis(other).expect("every machine has X, Y, Z");
        let (lower, upper) = info.limits.expect("linear axes have limits");
        let position = value.map_or((lower + upper) / 2.0, |v| v * M_PER_MM);
        if !info.within_travel(position) {
            return Err(format!(
                "{key}: {} mm is outside the travel of {other}",
                position / M_PER_MM
            ));
        }
        rest[other] = position;
    }
    Ok(rest)
}

/// The linear axis named `X`, `Y` or `Z`.
pub(crate) fn linear_axis(name: &str) -> Option<Axis> {
    match name {
        "X" => Some(Axis::X),
        "Y" => Some(Axis::Y),
        "Z" => Some(Axis::Z),
        _ => None,
    }
}
