//! The `[ballbar]` and `[servo]` sections: circular tests (ISO 230-4) measured by a ball-bar,
//! run through the controller model.
//!
//! ```toml
//! [ballbar]
//! planes = ["XY"]                 # any of "XY", "YZ", "ZX": one table each (ballbar_xy.csv, …)
//! length_mm = 150.0               # 50, 100, 150 or 300: the radius of the test
//! feed_mm_per_min = 1000.0
//! centre_mm = { x = 380.0, y = 205.0, z = 300.0 }   # circle centre (default: mid-travel)
//! a_deg = 0.0                     # rotary axes held (default 0)
//! arc_deg = 360.0                 # data arc (default: 360 in XY, 180 in YZ and ZX)
//! overshoot_deg = 180.0           # before and after the data arc (default: 180 full, 20 partial)
//! sample_rate_hz = 250.0
//! acceleration_mm_per_s2 = 2000.0 # interpolator ramps
//! dwell_s = 1.0                   # between the counter-clockwise and the clockwise run
//! setup_offset_um = [20.0, -10.0, 0.0]   # centre ball vs the machine's circle centre, workpiece frame
//! calibration_um = 0.0            # bar calibration error: reported − true length
//! noise_um = 0.1
//! resolution_um = 0.1
//!
//! [servo]
//! ipo_period_ms = 1.0
//! X = { kv_per_s = 33.3, feed_forward = 0.0, spike_um = 0.0, spike_decay_ms = 10.0, vibration_um = 0.0, vibration_hz = 0.0, play_um = 0.0 }
//! Y = { kv_per_s = 30.0 }         # unset keys take these defaults
//! ```
//!
//! `play_um` is real play between motor and carriage (a dead band of that width, ≥ 0, see
//! [`crate::program::servo`]): the carriage stands still while the motor crosses the gap after
//! a reversal. Lost motion as an instantaneous half-step at each reversal is the error model's
//! reversal term instead (e.g. `EXX = { reversal_um = 4.0 }`).
//!
//! A partial arc (less than 360°) keeps to the upper half of a vertical plane (the +Z side of
//! the centre, where the bar clears the table), centred on it: a 180° data arc runs from 0 to
//! 180° in YZ and from 270° through 0 to 90° in ZX; with the 20° overshoots that is the 220°
//! partial arc of ball-bar practice.

use crate::kinds::ballbar::instrument::{BALLBAR_LENGTHS, Ballbar};
use crate::kinds::ballbar::program::CircularInterpolation;
use crate::machine::{Axis, AxisValues, Machine, Plane};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, Vector};
use crate::program::{AxisServo, Servo};
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind};
use serde::Deserialize;
use std::f64::consts::TAU;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawBallbar {
    #[serde(default)]
    planes: Option<Spanned<Vec<String>>>,
    length_mm: Spanned<Real>,
    #[serde(default)]
    feed_mm_per_min: Option<Spanned<Real>>,
    #[serde(default)]
    centre_mm: Option<Spanned<RawCentre>>,
    a_deg: Option<Spanned<Real>>,
    b_deg: Option<Spanned<Real>>,
    c_deg: Option<Spanned<Real>>,
    arc_deg: Option<Spanned<Real>>,
    overshoot_deg: Option<Spanned<Real>>,
    sample_rate_hz: Option<Spanned<Real>>,
    acceleration_mm_per_s2: Option<Spanned<Real>>,
    dwell_s: Option<Spanned<Real>>,
    setup_offset_um: Option<Spanned<[Real; 3]>>,
    calibration_um: Option<Spanned<Real>>,
    noise_um: Option<Spanned<Real>>,
    resolution_um: Option<Spanned<Real>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct RawCentre {
    x: Option<Real>,
    y: Option<Real>,
    z: Option<Real>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawServo {
    ipo_period_ms: Option<Spanned<Real>>,
    #[serde(rename = "X")]
    x: Option<Spanned<RawAxisServo>>,
    #[serde(rename = "Y")]
    y: Option<Spanned<RawAxisServo>>,
    #[serde(rename = "Z")]
    z: Option<Spanned<RawAxisServo>>,
}

#[derive(Deserialize, Clone)]
#[serde(deny_unknown_fields)]
struct RawAxisServo {
    kv_per_s: Option<Real>,
    feed_forward: Option<Real>,
    spike_um: Option<Real>,
    spike_decay_ms: Option<Real>,
    vibration_um: Option<Real>,
    vibration_hz: Option<Real>,
    play_um: Option<Spanned<Real>>,
}

/// Circular tests, the ball-bar that measures them and the controller that runs them.
#[derive(Clone, Debug, PartialEq)]
pub struct BallbarTest {
    /// One circle per plane, in the order given.
    pub circles: Vec<CircularInterpolation>,
    /// The instrument.
    pub ballbar: Ballbar,
    /// The controller.
    pub servo: Servo,
}

/// The largest value a scenario may give each ball-bar quantity, with the reason; every one
/// is far beyond a real test, so that only typos and overflows are refused.
pub const LIMITS: [(&str, Real, &str); 9] = [
    ("arc_deg", 360.0, "a full circle"),
    (
        "overshoot_deg",
        360.0,
        "a turn before and after the data arc",
    ),
    (
        "calibration_um",
        1000.0,
        "a ball-bar's transducer reads ±1 mm about its calibrated length",
    ),
    (
        "feed_mm_per_min",
        120_000.0,
        "2 m/s, beyond the rapid traverse of machining centres",
    ),
    (
        "sample_rate_hz",
        100_000.0,
        "a hundred times a ball-bar's usual 1 kHz; the samples of a circle grow with it",
    ),
    (
        "acceleration_mm_per_s2",
        100_000.0,
        "10 g, beyond any machining centre's axes",
    ),
    ("dwell_s", 3600.0, "an hour at each end of a circle"),
    (
        "noise_um",
        1000.0,
        "the transducer's ±1 mm range: more is no ball-bar reading",
    ),
    (
        "resolution_um",
        1.0,
        "a ball-bar resolves 0.1 µm (Renishaw QC20) and the ISO 230-4 figures are a few µm: a \
         coarser step quantises them away",
    ),
];

/// The limit of `key` and its reason, from [`LIMITS`].
fn limit(key: &str) -> (Real, &'static str) {
    LIMITS
        .iter()
        .find(|(k, _, _)| *k == key)
        .map(|(_, max, why)| (*max, *why))
        .expect("every ball-bar quantity has a limit")
}

pub(crate) fn ballbar_test(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawBallbar>,
    servo: Option<&Spanned<RawServo>>,
) -> Result<BallbarTest, ScenarioError> {
    let b = raw.get_ref();
    let fail = |span: Option<std::ops::Range<usize>>, key: &str, message: String| {
        let span = span.filter(|s| !s.is_empty()).unwrap_or(raw.span());
        context.error(
            Some(span),
            ScenarioErrorKind::Value,
            format!("ballbar.{key}: {message}"),
        )
    };
    // A value that must be positive (or ≥ 0) and at most `max` ([`LIMITS`] says why), with
    // its default.
    let value = |v: &Option<Spanned<Real>>,
                 key: &str,
                 default: Real,
                 allow_zero: bool|
     -> Result<Real, ScenarioError> {
        let Some(v) = v else { return Ok(default) };
        let x = *v.get_ref();
        let (max, why) = limit(key);
        if x.is_finite() && (x > 0.0 || (allow_zero && x == 0.0)) && x <= max {
            Ok(x)
        } else {
            let expected = if allow_zero { "≥ 0" } else { "positive" };
            Err(fail(
                Some(v.span()),
                key,
                format!(
                    "expected a {expected} number up to {max} ({why}), got {}",
                    crate::math::readable(x)
                ),
            ))
        }
    };

    let planes: Vec<Plane> = match &b.planes {
        None => vec![Plane::XY],
        Some(list) => {
            let mut planes = Vec::new();
            for name in list.get_ref() {
                let plane: Plane = name
                    .parse()
                    .map_err(|m: String| fail(Some(list.span()), "planes", m))?;
                if planes.contains(&plane) {
                    return Err(fail(
                        Some(list.span()),
                        "planes",
                        format!("{plane} is listed twice"),
                    ));
                }
                planes.push(plane);
            }
            if planes.is_empty() {
                return Err(fail(
                    Some(list.span()),
                    "planes",
                    "give at least one plane".into(),
                ));
            }
            planes
        }
    };
    let length_mm = *b.length_mm.get_ref();
    let length = length_mm * M_PER_MM;
    if !BALLBAR_LENGTHS.iter().any(|l| (l - length).abs() < 1e-12) {
        return Err(fail(
            Some(b.length_mm.span()),
            "length_mm",
            format!("{length_mm} mm is not a ball-bar length; expected 50, 100, 150 or 300"),
        ));
    }
    let feed = value(&b.feed_mm_per_min, "feed_mm_per_min", 1000.0, false)? * M_PER_MM / 60.0;
    let sample_rate = value(&b.sample_rate_hz, "sample_rate_hz", 250.0, false)?;
    let acceleration = value(
        &b.acceleration_mm_per_s2,
        "acceleration_mm_per_s2",
        2000.0,
        false,
    )? * M_PER_MM;
    let dwell = value(&b.dwell_s, "dwell_s", 1.0, true)?;
    let calibration = b.calibration_um.as_ref().map_or(Ok(0.0), |c| {
        let v = *c.get_ref();
        let (max, why) = limit("calibration_um");
        if v.is_finite() && v.abs() <= max {
            Ok(v * M_PER_UM)
        } else {
            Err(fail(
                Some(c.span()),
                "calibration_um",
                format!(
                    "expected a number within ±{max} ({why}), got {}",
                    crate::math::readable(v)
                ),
            ))
        }
    })?;
    let noise = value(&b.noise_um, "noise_um", 0.1, true)? * M_PER_UM;
    let resolution = value(&b.resolution_um, "resolution_um", 0.1, true)? * M_PER_UM;
    let setup_offset = match &b.setup_offset_um {
        None => Vector::ZERO,
        Some(v) if v.get_ref().iter().all(|x| x.is_finite()) => {
            Vector::from_array(*v.get_ref()) * M_PER_UM
        }
        Some(v) => {
            return Err(fail(
                Some(v.span()),
                "setup_offset_um",
                "expected three finite numbers".into(),
            ));
        }
    };
    if setup_offset.length() > 0.01 * length {
        return Err(fail(
            b.setup_offset_um.as_ref().map(|v| v.span()),
            "setup_offset_um",
            format!(
                "{:.0} µm is more than 1 % of the bar's length: the bar would not seat",
                setup_offset.length() / M_PER_UM
            ),
        ));
    }
    // Where the circle centre and the held axes stand: as given, else mid-travel, rotary 0.
    let centre_given = b.centre_mm.as_ref().map(|c| *c.get_ref());
    let mut centre = AxisValues::ZERO;
    let held = [
        (Axis::X, "centre_mm.x", centre_given.and_then(|c| c.x), None),
        (Axis::Y, "centre_mm.y", centre_given.and_then(|c| c.y), None),
        (Axis::Z, "centre_mm.z", centre_given.and_then(|c| c.z), None),
        (
            Axis::A,
            "a_deg",
            b.a_deg.as_ref().map(|v| *v.get_ref()),
            b.a_deg.as_ref(),
        ),
        (
            Axis::B,
            "b_deg",
            b.b_deg.as_ref().map(|v| *v.get_ref()),
            b.b_deg.as_ref(),
        ),
        (
            Axis::C,
            "c_deg",
            b.c_deg.as_ref().map(|v| *v.get_ref()),
            b.c_deg.as_ref(),
        ),
    ];
    let centre_span = b.centre_mm.as_ref().map(|c| c.span());
    for (axis, key, given, spanned) in held {
        let span = spanned.map(|s| s.span()).or(centre_span.clone());
        let Some(info) = machine.axis(axis) else {
            if given.is_some() {
                return Err(fail(
                    span,
                    key,
                    format!("machine \"{}\" has no axis {axis}", machine.name()),
                ));
            }
            continue;
        };
        let scale = if axis.is_linear() {
            M_PER_MM
        } else {
            RAD_PER_DEG
        };
        let position = match (given, info.limits) {
            (Some(v), _) => v * scale,
            (None, Some((lower, upper))) if axis.is_linear() => (lower + upper) / 2.0,
            (None, _) => 0.0,
        };
        if !info.within_travel(position) {
            return Err(fail(
                span,
                key,
                format!(
                    "{} is outside the travel of {axis}, {}",
                    position / scale,
                    info.scenario_travel_text()
                ),
            ));
        }
        centre[axis] = position;
    }

    let mut circles = Vec::new();
    for plane in planes {
        let full = plane == Plane::XY;
        let arc_deg = value(
            &b.arc_deg,
            "arc_deg",
            if full { 360.0 } else { 180.0 },
            false,
        )?;
        let partial = arc_deg < 360.0;
        let overshoot_deg = value(
            &b.overshoot_deg,
            "overshoot_deg",
            if partial { 20.0 } else { 180.0 },
            true,
        )?;
        let data_arc = arc_deg * RAD_PER_DEG;
        let data_start = if partial {
            plane.upper_half_start() + (std::f64::consts::PI - data_arc) / 2.0
        } else {
            0.0
        };
        let circle = CircularInterpolation {
            plane,
            centre,
            radius: length,
            feed,
            data_start,
            data_arc,
            overshoot: overshoot_deg * RAD_PER_DEG,
            acceleration,
            dwell,
        };
        if let Some(problem) = circle.problem() {
            return Err(fail(None, &format!("{plane}"), problem));
        }
        if circle.duration() * sample_rate > 5e6 {
            return Err(fail(
                b.sample_rate_hz.as_ref().map(|v| v.span()),
                "sample_rate_hz",
                format!(
                    "{:.0} s at {sample_rate} Hz is more than five million readings",
                    circle.duration()
                ),
            ));
        }
        // Every commanded point within the travel (checked every 0.5° of the path).
        let (first, last) = (
            data_start - circle.overshoot,
            data_start + data_arc + circle.overshoot,
        );
        let steps = ((last - first) / (0.5 * RAD_PER_DEG)).ceil().max(1.0) as usize;
        for i in 0..=steps {
            let angle = first + (last - first) * i as Real / steps as Real;
            let position = circle.position(angle);
            if let Err((axis, v, (lower, upper))) = machine.check_limits(&position) {
                return Err(fail(
                    centre_span.clone(),
                    "centre_mm",
                    format!(
                        "the {plane} circle of radius {length_mm} mm about this centre takes {axis} to {:.1} mm at {:.1}°, outside its travel {:.1} .. {:.1} mm",
                        v / M_PER_MM,
                        angle.rem_euclid(TAU) / RAD_PER_DEG,
                        lower / M_PER_MM,
                        upper / M_PER_MM
                    ),
                ));
            }
        }
        circles.push(circle);
    }
    let servo = servo_spec(context, servo)?;
    Ok(BallbarTest {
        circles,
        ballbar: Ballbar {
            length,
            setup_offset,
            calibration_error: calibration,
            resolution,
            noise,
            sample_rate,
        },
        servo,
    })
}

fn servo_spec(
    context: &Context<'_>,
    raw: Option<&Spanned<RawServo>>,
) -> Result<Servo, ScenarioError> {
    match raw {
        Some(raw) => servo_over(context, raw, Servo::default()),
        None => Ok(Servo::default()),
    }
}

/// The servo `raw` states over `servo`: each key given replaces that axis's value, the others
/// keep theirs (the defaults in a full scenario, the base's in an extension).
pub(crate) fn servo_over(
    context: &Context<'_>,
    raw: &Spanned<RawServo>,
    mut servo: Servo,
) -> Result<Servo, ScenarioError> {
    let s = raw.get_ref();
    if let Some(period) = &s.ipo_period_ms {
        let ms = *period.get_ref();
        // CNC interpolation cycles run from about 0.1 ms to a few ms; the simulation takes a
        // step per period, so a period far below that is hours of work for nothing.
        if !(ms.is_finite() && (0.05..=100.0).contains(&ms)) {
            return Err(context.error(
                Some(period.span()),
                ScenarioErrorKind::Value,
                format!(
                    "servo.ipo_period_ms: expected 0.05 … 100 ms (CNC interpolation cycles run from about 0.1 ms to a few ms), got {}",
                    crate::math::readable(ms)
                ),
            ));
        }
        servo.ipo_period = ms * 1e-3;
    }
    for (axis, given) in [(Axis::X, &s.x), (Axis::Y, &s.y), (Axis::Z, &s.z)] {
        let Some(given) = given else { continue };
        let g = given.get_ref();
        let d = servo.axes[axis.index()];
        let play = match &g.play_um {
            None => d.play,
            Some(v) => {
                let um = *v.get_ref();
                if !(um.is_finite() && um >= 0.0) {
                    let span = Some(v.span()).filter(|s| !s.is_empty());
                    return Err(context.error(
                        span.or(Some(given.span())),
                        ScenarioErrorKind::Value,
                        format!("servo.{axis}.play_um: expected a finite width ≥ 0 µm, got {um}"),
                    ));
                }
                um * M_PER_UM
            }
        };
        let spec = AxisServo {
            kv: g.kv_per_s.unwrap_or(d.kv),
            feed_forward: g.feed_forward.unwrap_or(d.feed_forward),
            spike_height: g.spike_um.map_or(d.spike_height, |v| v * M_PER_UM),
            spike_decay: g.spike_decay_ms.map_or(d.spike_decay, |v| v * 1e-3),
            vibration_amplitude: g
                .vibration_um
                .map_or(d.vibration_amplitude, |v| v * M_PER_UM),
            vibration_frequency: g.vibration_hz.unwrap_or(d.vibration_frequency),
            play,
        };
        if let Some(problem) = spec.problem() {
            return Err(context.error(
                Some(given.span()),
                ScenarioErrorKind::Value,
                format!("servo.{axis}: {problem}"),
            ));
        }
        servo.axes[axis.index()] = spec;
    }
    Ok(servo)
}

/// The ball-bar test of a scenario, if it has a `[ballbar]` section; a `[servo]` without one
/// is refused (nothing else uses it).
pub(crate) fn sections(
    context: &Context<'_>,
    machine: &Machine,
    ballbar: Option<&Spanned<RawBallbar>>,
    servo: Option<&Spanned<RawServo>>,
) -> Result<Option<BallbarTest>, ScenarioError> {
    let test = ballbar
        .map(|b| ballbar_test(context, machine, b, servo))
        .transpose()?;
    if let (Some(servo), None) = (servo, &test) {
        return Err(context.error(
            Some(servo.span()),
            ScenarioErrorKind::Nothing,
            "servo: nothing in this scenario uses the servo model; add a [ballbar] test",
        ));
    }
    Ok(test)
}

impl BallbarTest {
    /// One line per circle (plane, radius, feed, data arc, duration), as `mtwin check` lists
    /// them.
    pub fn describe(&self) -> Vec<String> {
        self.circles
            .iter()
            .map(|circle| {
                format!(
                    "ball-bar: {} plane, {:.0} mm at {:.0} mm/min, {:.0}° data arc, {:.0} s",
                    circle.plane,
                    circle.radius * 1e3,
                    circle.feed * 6e4,
                    circle.data_arc.to_degrees(),
                    circle.duration()
                )
            })
            .collect()
    }
}
