//! The `[rtest]` section: the sphere on the table, the nest in the spindle and the K-tests.
//!
//! ```toml
//! [rtest]
//! sphere_mm = [100.0, 0.0, 150.0]   # sphere centre in the workpiece frame (on the C table)
//! sphere_diameter_mm = 25.4
//! sphere_setup_um = [0.0, 0.0, 0.0] # where the sphere really is relative to sphere_mm: the
//!                                   # controller follows sphere_mm (the operator's preset), the
//!                                   # sphere sits this far off it (a set-up error; ±1000 µm)
//! probes = 3                        # 3, or 4 with one along the tool axis
//! tip = "flat"                      # "flat" (linear) or "point" (cross-talk u²/2R)
//! tip_radius_mm = 0.0               # point tips: the tip ball's radius (0: non-contact)
//! range_mm = 2.0                    # each probe's measuring range (±)
//! noise_um = 0.2
//! resolution_um = 0.01
//! gain_error = [0.0, 0.0, 0.0]      # per probe, relative (0.001 = 0.1 %)
//! direction_error_mrad = [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]   # per probe: elevation, azimuth
//!                                   # (the fourth, axial probe: tilts about the nest's x and y)
//! calibration = "six_point"         # or "nominal" (the software trusts the nominal axes)
//! calibration_step_mm = 0.5
//! zero = "each_test"                # the software zeroes at each test's first pose, or
//!                                   # "first_pose": once, at the first test's first pose (a datum
//!                                   # for the whole sequence; the nest follows the sphere between tests)
//! mode = "static"                   # or "dynamic" (continuous, through the position loops)
//! dwell_s = 1.0                     # static: time between poses
//! rotary_feed_deg_per_min = 1800.0  # dynamic: speed of the swept axis
//! sample_rate_hz = 100.0            # dynamic: the nest's sampling
//! ipo_period_ms = 1.0               # dynamic: the interpolator
//! kv_per_s = { X = 33.3, C = 25.0 } # dynamic: position-loop gains (default 33.3 each)
//!
//! [[rtest.test]]
//! name = "CK1 A0"                   # unique; names the rows of the table
//! from_deg = { A = 0.0, C = 0.0 }   # rotary angles at the start (absent axes: 0)
//! to_deg = { C = 360.0 }            # at the end (absent axes: as at the start)
//! points = 25                       # static poses, ends included
//! back = false                      # true: then back to the start along the same path (each
//!                                   # pose approached both ways; 2·points − 1 poses)
//! ```

use super::instrument::{Calibration, Nest, Probe, Tip, probe_axis};
use super::program::{Dynamic, FollowError, KTest, SETTLE, follow};
use crate::collision::{Mount, Scene, Solid};
use crate::machine::{Axis, AxisValues, Machine, Workspace};
use crate::math::{M_PER_MM, M_PER_UM, Pose, RAD_PER_DEG, Real, Rotation, Vector};
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind};
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRtest {
    sphere_mm: Spanned<[Real; 3]>,
    sphere_diameter_mm: Option<Spanned<Real>>,
    sphere_setup_um: Option<Spanned<[Real; 3]>>,
    probes: Option<Spanned<i64>>,
    tip: Option<Spanned<String>>,
    tip_radius_mm: Option<Spanned<Real>>,
    range_mm: Option<Spanned<Real>>,
    noise_um: Option<Spanned<Real>>,
    resolution_um: Option<Spanned<Real>>,
    gain_error: Option<Spanned<Vec<Real>>>,
    direction_error_mrad: Option<Spanned<Vec<[Real; 2]>>>,
    calibration: Option<Spanned<String>>,
    calibration_step_mm: Option<Spanned<Real>>,
    zero: Option<Spanned<String>>,
    mode: Option<Spanned<String>>,
    dwell_s: Option<Spanned<Real>>,
    rotary_feed_deg_per_min: Option<Spanned<Real>>,
    sample_rate_hz: Option<Spanned<Real>>,
    ipo_period_ms: Option<Spanned<Real>>,
    kv_per_s: Option<Spanned<BTreeMap<String, Real>>>,
    test: Spanned<Vec<Spanned<RawKTest>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawKTest {
    name: Spanned<String>,
    from_deg: Option<Spanned<BTreeMap<String, Real>>>,
    to_deg: Option<Spanned<BTreeMap<String, Real>>>,
    points: Option<Spanned<i64>>,
    back: Option<bool>,
}

/// How the tests run.
#[derive(Clone, Debug, PartialEq)]
pub enum Mode {
    /// Stop at each pose, `dwell` seconds apart.
    Static {
        /// Time between poses (s).
        dwell: Real,
    },
    /// Continuous motion through the position loops.
    Dynamic(Dynamic),
}

/// An R-test: the sphere, the nest and the tests.
#[derive(Clone, Debug, PartialEq)]
pub struct RTest {
    /// Sphere centre in the workpiece frame (m), as the controller and the table state it.
    pub sphere: Vector,
    /// Where the sphere really is relative to [`RTest::sphere`] (m): the preset's error.
    pub sphere_setup: Vector,
    /// The instrument.
    pub nest: Nest,
    /// The tests, in the order given.
    pub tests: Vec<KTest>,
    /// How they run.
    pub mode: Mode,
    /// Where the software zeroes the probes.
    pub zero: Zero,
}

/// Where the R-test software zeroes the probes: the readings are changes since then.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Zero {
    /// At each test's first pose (each K-test evaluated on its own, as ISO 10791-6 does).
    EachTest,
    /// Once, at the first test's first pose: one datum for the sequence, so that tests at
    /// other tilts are read against it (what identifies the tilting axis's line from C circles).
    FirstPose,
}

impl Zero {
    /// Its name in scenarios and table preambles.
    pub fn name(self) -> &'static str {
        match self {
            Zero::EachTest => "each_test",
            Zero::FirstPose => "first_pose",
        }
    }
}

impl RTest {
    /// One line per test, for `mtwin check`.
    pub fn describe(&self) -> Vec<String> {
        self.tests
            .iter()
            .map(|t| format!("R-test \"{}\": {} poses", t.name, t.pose_count()))
            .collect()
    }
}

pub(crate) fn rtest(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawRtest>,
) -> Result<RTest, ScenarioError> {
    let r = raw.get_ref();
    let fail = |span: std::ops::Range<usize>, key: &str, message: String| {
        let span = if span.is_empty() { raw.span() } else { span };
        context.error(
            Some(span),
            ScenarioErrorKind::Value,
            format!("rtest.{key}: {message}"),
        )
    };
    let number = |v: &Option<Spanned<Real>>, key: &str, default: Real, zero_ok: bool| {
        let Some(v) = v else { return Ok(default) };
        let x = *v.get_ref();
        if x.is_finite() && (x > 0.0 || (zero_ok && x == 0.0)) {
            Ok(x)
        } else {
            let expected = if zero_ok { "≥ 0" } else { "positive" };
            Err(fail(
                v.span(),
                key,
                format!("expected a finite {expected} number, got {x}"),
            ))
        }
    };
    // A value with a physical range: refused outside it, with the reason.
    let bounded = |v: &Option<Spanned<Real>>,
                   key: &str,
                   default: Real,
                   (low, high): (Real, Real),
                   why: &str| {
        let Some(v) = v else { return Ok(default) };
        let x = *v.get_ref();
        if x.is_finite() && (low..=high).contains(&x) {
            Ok(x)
        } else {
            Err(fail(
                v.span(),
                key,
                format!(
                    "expected {} … {} ({why}), got {}",
                    crate::math::readable(low),
                    crate::math::readable(high),
                    crate::math::readable(x)
                ),
            ))
        }
    };
    if machine.rotary_axes().count() == 0 {
        return Err(fail(
            raw.span(),
            "sphere_mm",
            format!(
                "machine \"{}\" has no rotary axis: the R-test checks rotary axes",
                machine.name()
            ),
        ));
    }
    let sphere_values = *r.sphere_mm.get_ref();
    if !sphere_values.iter().all(|v| v.is_finite()) {
        return Err(fail(
            r.sphere_mm.span(),
            "sphere_mm",
            "expected three finite numbers".into(),
        ));
    }
    let sphere = Vector::from_array(sphere_values) * M_PER_MM;
    let sphere_setup = match &r.sphere_setup_um {
        None => Vector::ZERO,
        Some(v) => {
            let bound = crate::scenario::Bound::symmetric(
                1000.0,
                "a sphere preset with a dial indicator is within micrometres; a millimetre is no preset",
            );
            bound
                .check_each(v.get_ref())
                .map_err(|message| fail(v.span(), "sphere_setup_um", message))?;
            Vector::from_array(*v.get_ref()) * crate::math::M_PER_UM
        }
    };
    let sphere_radius = bounded(
        &r.sphere_diameter_mm,
        "sphere_diameter_mm",
        25.4,
        (5.0, 100.0),
        "R-test spheres are about 10 to 50 mm",
    )? / 2.0
        * M_PER_MM;
    let count = match &r.probes {
        None => 3,
        Some(p) if matches!(*p.get_ref(), 3 | 4) => *p.get_ref() as usize,
        Some(p) => {
            return Err(fail(
                p.span(),
                "probes",
                format!("expected 3 or 4, got {}", p.get_ref()),
            ));
        }
    };
    let tip_radius = bounded(
        &r.tip_radius_mm,
        "tip_radius_mm",
        0.0,
        (0.0, 10.0),
        "a probe tip is a few mm at most",
    )? * M_PER_MM;
    let tip = match r.tip.as_ref().map(|t| (t.get_ref().as_str(), t.span())) {
        None | Some(("flat", _)) => {
            if let Some(t) = &r.tip_radius_mm {
                return Err(fail(
                    t.span(),
                    "tip_radius_mm",
                    "flat tips have no radius: set tip = \"point\" or drop the key".into(),
                ));
            }
            Tip::Flat
        }
        Some(("point", _)) => Tip::Point { radius: tip_radius },
        Some((other, span)) => {
            return Err(fail(
                span,
                "tip",
                format!("expected \"flat\" or \"point\", got \"{other}\""),
            ));
        }
    };
    let range = bounded(
        &r.range_mm,
        "range_mm",
        2.0,
        (0.1, 10.0),
        "an R-test's probes travel a few mm",
    )? * M_PER_MM;
    let noise = bounded(
        &r.noise_um,
        "noise_um",
        0.2,
        (0.0, 10.0),
        "a displacement probe's noise is well under a micrometre",
    )? * M_PER_UM;
    let resolution = bounded(
        &r.resolution_um,
        "resolution_um",
        0.01,
        (0.0, 10.0),
        "a displacement probe resolves well under a micrometre",
    )? * M_PER_UM;
    let per_probe_len = |len: usize, span: std::ops::Range<usize>, key: &str| {
        if len == count {
            Ok(())
        } else {
            Err(fail(
                span,
                key,
                format!("expected one entry per probe ({count}), got {len}"),
            ))
        }
    };
    let gains = match &r.gain_error {
        None => vec![0.0; count],
        Some(g) => {
            per_probe_len(g.get_ref().len(), g.span(), "gain_error")?;
            if let Some(bad) = g
                .get_ref()
                .iter()
                .find(|x| !(x.is_finite() && x.abs() < 0.5))
            {
                return Err(fail(
                    g.span(),
                    "gain_error",
                    format!("{bad}: expected a relative error within ±0.5"),
                ));
            }
            g.get_ref().clone()
        }
    };
    let directions = match &r.direction_error_mrad {
        None => vec![[0.0; 2]; count],
        Some(d) => {
            per_probe_len(d.get_ref().len(), d.span(), "direction_error_mrad")?;
            if d.get_ref()
                .iter()
                .flatten()
                .any(|x| !(x.is_finite() && x.abs() <= 100.0))
            {
                return Err(fail(
                    d.span(),
                    "direction_error_mrad",
                    "expected [elevation, azimuth] pairs within ±100 mrad".into(),
                ));
            }
            d.get_ref().clone()
        }
    };
    let probes = Nest::nominal_axes(count)
        .into_iter()
        .zip(gains.iter().zip(&directions))
        .map(|(nominal, (&gain_error, error))| {
            // The axial probe has no azimuth: its pair is a tilt about the nest's x, then y.
            let axis = if nominal == Vector::Z {
                Rotation::from_rotation_y(error[1] * 1e-3)
                    * Rotation::from_rotation_x(error[0] * 1e-3)
                    * Vector::Z
            } else {
                let elevation = nominal.z.asin() + error[0] * 1e-3;
                let azimuth = nominal.y.atan2(nominal.x) + error[1] * 1e-3;
                probe_axis(azimuth, elevation)
            };
            Probe {
                nominal_axis: nominal,
                axis,
                gain_error,
            }
        })
        .collect();
    let step = number(&r.calibration_step_mm, "calibration_step_mm", 0.5, false)? * M_PER_MM;
    let calibration = match r
        .calibration
        .as_ref()
        .map(|c| (c.get_ref().as_str(), c.span()))
    {
        None | Some(("six_point", _)) => Calibration::SixPoint { step },
        Some(("nominal", _)) => Calibration::Nominal,
        Some((other, span)) => {
            return Err(fail(
                span,
                "calibration",
                format!("expected \"six_point\" or \"nominal\", got \"{other}\""),
            ));
        }
    };
    if step >= range {
        return Err(fail(
            r.calibration_step_mm
                .as_ref()
                .map_or(raw.span(), |s| s.span()),
            "calibration_step_mm",
            "the calibration step must lie inside the probes' range".into(),
        ));
    }
    let zero = match r.zero.as_ref().map(|z| (z.get_ref().as_str(), z.span())) {
        None | Some(("each_test", _)) => Zero::EachTest,
        Some(("first_pose", _)) => Zero::FirstPose,
        Some((other, span)) => {
            return Err(fail(
                span,
                "zero",
                format!("expected \"each_test\" or \"first_pose\", got \"{other}\""),
            ));
        }
    };
    let mode = match r.mode.as_ref().map(|m| (m.get_ref().as_str(), m.span())) {
        None | Some(("static", _)) => Mode::Static {
            dwell: bounded(
                &r.dwell_s,
                "dwell_s",
                1.0,
                (1e-3, 3600.0),
                "a pose held longer than an hour measures drift, not the axis",
            )?,
        },
        Some(("dynamic", _)) => {
            let mut kv = [100.0 / 3.0; 7];
            if let Some(map) = &r.kv_per_s {
                for (letter, &value) in map.get_ref() {
                    let axis = single_axis(letter)
                        .filter(|a| machine.has_axis(*a) && *a != Axis::S)
                        .ok_or_else(|| {
                            fail(
                                map.span(),
                                "kv_per_s",
                                format!("{letter}: not a feed axis of the machine"),
                            )
                        })?;
                    if !(value.is_finite() && (1.0..=1000.0).contains(&value)) {
                        return Err(fail(
                            map.span(),
                            "kv_per_s",
                            format!(
                                "{letter} = {}: expected a gain of 1 … 1000 /s (position loops run at tens of 1/s)",
                                crate::math::readable(value)
                            ),
                        ));
                    }
                    kv[axis.index()] = value;
                }
            }
            Mode::Dynamic(Dynamic {
                rate: bounded(
                    &r.rotary_feed_deg_per_min,
                    "rotary_feed_deg_per_min",
                    1800.0,
                    (1.0, 72_000.0),
                    "72 000 °/min is 200 rpm, beyond any rotary table's feed",
                )? * RAD_PER_DEG
                    / 60.0,
                sample_rate: bounded(
                    &r.sample_rate_hz,
                    "sample_rate_hz",
                    100.0,
                    (1.0, 1e5),
                    "an R-test's probes are read at up to some kHz",
                )?,
                ipo_period: bounded(
                    &r.ipo_period_ms,
                    "ipo_period_ms",
                    1.0,
                    (0.05, 100.0),
                    "CNC interpolation cycles run from about 0.1 ms to a few ms",
                )? * 1e-3,
                kv,
            })
        }
        Some((other, span)) => {
            return Err(fail(
                span,
                "mode",
                format!("expected \"static\" or \"dynamic\", got \"{other}\""),
            ));
        }
    };
    let nest = Nest {
        probes,
        tip,
        sphere_radius,
        range,
        noise,
        resolution,
        calibration,
    };

    if sphere.z < sphere_radius {
        return Err(fail(
            r.sphere_mm.span(),
            "sphere_mm",
            format!(
                "the sphere's centre must stand at least its radius ({} mm) above the table surface",
                sphere_radius / M_PER_MM
            ),
        ));
    }
    let scene = collision_scene(machine, sphere, sphere_radius);
    let mut tests: Vec<KTest> = Vec::new();
    let mut workspace = Workspace::new(machine);
    if r.test.get_ref().is_empty() {
        return Err(fail(r.test.span(), "test", "give at least one test".into()));
    }
    for t in r.test.get_ref() {
        let raw_test = t.get_ref();
        let name = raw_test.name.get_ref().trim().to_string();
        let key = format!("test \"{name}\"");
        if name.is_empty() || name.contains(',') || name.contains('"') {
            return Err(fail(
                raw_test.name.span(),
                "test.name",
                "expected a non-empty name without commas or quotes".into(),
            ));
        }
        if tests.iter().any(|other| other.name == name) {
            return Err(fail(
                raw_test.name.span(),
                "test.name",
                format!("\"{name}\" is given twice"),
            ));
        }
        let angles = |map: &Option<Spanned<BTreeMap<String, Real>>>,
                      base: AxisValues,
                      field: &str|
         -> Result<AxisValues, ScenarioError> {
            let mut out = base;
            let Some(map) = map else { return Ok(out) };
            for (letter, &value) in map.get_ref() {
                let Some(info) = single_axis(letter)
                    .filter(|a| a.is_rotary())
                    .and_then(|a| machine.axis(a))
                else {
                    return Err(fail(
                        map.span(),
                        &format!("test.{field}"),
                        format!(
                            "{key}: {letter} is not a rotary axis of machine \"{}\"",
                            machine.name()
                        ),
                    ));
                };
                let v = value * RAD_PER_DEG;
                if !info.within_travel(v) {
                    return Err(fail(
                        map.span(),
                        &format!("test.{field}"),
                        format!(
                            "{key}: {letter} = {value}° is outside its travel, {}",
                            info.scenario_travel_text()
                        ),
                    ));
                }
                out[info.axis] = v;
            }
            Ok(out)
        };
        let from = angles(&raw_test.from_deg, AxisValues::ZERO, "from_deg")?;
        let to = angles(&raw_test.to_deg, from, "to_deg")?;
        let points = match &raw_test.points {
            None => 25,
            // Three poses at least: the analysis fits a circle or a line through each test and
            // refuses fewer.
            Some(p) if (3..=100_000).contains(p.get_ref()) => *p.get_ref() as usize,
            Some(p) => {
                return Err(fail(
                    p.span(),
                    "test.points",
                    format!(
                        "{key}: expected 3 … 100000 poses (a test's circle or line needs three), got {}",
                        p.get_ref()
                    ),
                ));
            }
        };
        let test = KTest {
            name,
            from,
            to,
            points,
            back: raw_test.back.unwrap_or(false),
        };
        // Every pose must be reachable, and the path free of collisions: check it finely.
        // The times the table will carry: static poses `dwell` apart; in dynamic mode the
        // motion starts after the loops have settled.
        let (start_time, move_time) = match &mode {
            Mode::Static { dwell } => (0.0, (test.pose_count() - 1) as Real * dwell),
            Mode::Dynamic(d) => (SETTLE, test.rotary_travel(machine) / d.rate),
        };
        if let Mode::Dynamic(d) = &mode {
            // The work of a dynamic sweep: one sample per reading, one servo step per
            // interpolation period (about 10 s at these limits on a 2-core machine).
            let duration = move_time + 2.0 * SETTLE;
            let (samples, steps) = (duration * d.sample_rate, duration / d.ipo_period);
            if samples > MAX_DYNAMIC_SAMPLES || steps > MAX_SERVO_STEPS {
                return Err(fail(
                    t.span(),
                    "test",
                    format!(
                        "{key}: a dynamic sweep of {} s is {} readings and {} servo steps; at most {} and {}: a faster feed or a lower sample rate",
                        crate::math::trimmed(duration, 1),
                        crate::math::readable(samples.ceil()),
                        crate::math::readable(steps.ceil()),
                        MAX_DYNAMIC_SAMPLES,
                        MAX_SERVO_STEPS
                    ),
                ));
            }
        }
        let checks = (test.rotary_travel(machine).to_degrees().ceil() as usize).clamp(2, 3600);
        let mut path = Vec::with_capacity(checks + 1);
        for k in 0..=checks {
            let lambda = k as Real / checks as Real;
            let angles = test.angles_at(machine, lambda);
            let position = follow(machine, &mut workspace, &angles, sphere)
                .map_err(|e: FollowError| fail(t.span(), "test", format!("{key}: {e}")))?;
            path.push((start_time + lambda * move_time, position));
        }
        if let Err(hit) = scene.sweep(machine, &path) {
            return Err(fail(
                t.span(),
                "test",
                format!(
                    "{key}: the {} (tool side) would touch the {} (workpiece side) {:.2} s into the test, at {}",
                    hit.tool_body,
                    hit.workpiece_body,
                    hit.time,
                    hit.describe(machine)
                ),
            ));
        }
        tests.push(test);
    }
    Ok(RTest {
        sphere,
        sphere_setup,
        nest,
        tests,
        mode,
        zero,
    })
}

/// The most readings one dynamic R-test sweep may take (the ball-bar's limit).
pub const MAX_DYNAMIC_SAMPLES: Real = 5e6;
/// The most interpolation periods one dynamic sweep may simulate.
pub const MAX_SERVO_STEPS: Real = 5e7;

/// The nest's holder: a cylinder of this radius (m) around the tool axis, from [`NEST_GAP`]
/// above the sphere's top to the spindle nose, 150 mm above the tip. The probes that reach
/// down around the sphere are not modelled.
pub const NEST_RADIUS: Real = 0.040;
/// The gap (m) between the sphere's top and the nest's holder when the readings are zero.
pub const NEST_GAP: Real = 0.010;
/// The radius (m) of the post the sphere stands on, from the table surface up to the sphere.
pub const POST_RADIUS: Real = 0.008;

/// The machine (its `tool` link replaced by the nest) with the sphere on its post.
fn collision_scene(machine: &Machine, sphere: Vector, radius: Real) -> Scene {
    let mut scene = Scene::of_machine(machine, &["tool"]);
    let (bottom, top) = (radius + NEST_GAP, 0.150_f64.max(radius + NEST_GAP + 0.01));
    scene.attach(
        "nest",
        Mount::Tool,
        Pose::from_translation(Vector::new(0.0, 0.0, (bottom + top) / 2.0)),
        Solid::Cylinder(NEST_RADIUS, top - bottom),
    );
    scene.attach(
        "sphere",
        Mount::Workpiece,
        Pose::from_translation(sphere),
        Solid::Sphere(radius),
    );
    let post = sphere.z - radius;
    if post > 1e-6 {
        scene.attach(
            "post",
            Mount::Workpiece,
            Pose::from_translation(Vector::new(sphere.x, sphere.y, post / 2.0)),
            Solid::Cylinder(POST_RADIUS, post),
        );
    }
    scene
}

/// The axis of a one-letter key (`A`, `c`).
fn single_axis(letter: &str) -> Option<Axis> {
    let mut chars = letter.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) => Axis::from_letter(c.to_ascii_uppercase()),
        _ => None,
    }
}
