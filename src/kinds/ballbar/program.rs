//! Circular interpolation (G03 then G02) for a circular test (ISO 230-4), as a CNC's
//! interpolator commands it: along an arc of the test plane at a programmed feed, with a
//! trapezoidal speed profile (acceleration ramps) inside overshoot arcs that lie outside the
//! data arc, counter-clockwise first, then, after a dwell, clockwise back.

use super::table::Sense;
use crate::machine::{AxisValues, Plane};
use crate::machine::{Direction, MachineState};
use crate::math::Real;
use crate::program::servo::{Sampling, sample_loops};
use crate::program::{AxisLoop, Servo};

/// One circular test on one plane: the commanded path (SI: m, rad, m/s, m/s², s).
#[derive(Clone, Debug, PartialEq)]
pub struct CircularInterpolation {
    /// The plane of the circle.
    pub plane: Plane,
    /// Axis positions at the circle centre; the axes off the plane (and every rotary axis)
    /// stay there throughout.
    pub centre: AxisValues,
    /// Radius (m).
    pub radius: Real,
    /// Programmed path speed (m/s).
    pub feed: Real,
    /// Where the data arc starts (rad, from the plane's first axis toward its second).
    pub data_start: Real,
    /// Length of the data arc (rad; 2π for a full circle).
    pub data_arc: Real,
    /// Overshoot arc before and after the data arc (rad): the ramps and servo transients
    /// happen there, outside the data.
    pub overshoot: Real,
    /// Path acceleration and deceleration of the ramps (m/s²).
    pub acceleration: Real,
    /// Standstill between the two senses (s).
    pub dwell: Real,
}

/// Where the interpolator is at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CommandPoint {
    /// The sense of the run under way (during the dwell: the run just finished).
    pub sense: Sense,
    /// Programmed angle (rad, unwrapped: the data arc is `data_start ..= data_start + data_arc`).
    pub angle: Real,
    /// Programmed path speed (m/s, ≥ 0).
    pub speed: Real,
}

impl CircularInterpolation {
    /// Path length of one run, overshoots included (m).
    pub fn run_length(&self) -> Real {
        self.radius * (self.data_arc + 2.0 * self.overshoot)
    }

    /// Path length of one acceleration (or deceleration) ramp (m).
    pub fn ramp_length(&self) -> Real {
        self.feed * self.feed / (2.0 * self.acceleration)
    }

    /// Duration of one run (s).
    pub fn run_duration(&self) -> Real {
        let ramp_time = self.feed / self.acceleration;
        2.0 * ramp_time + (self.run_length() - 2.0 * self.ramp_length()) / self.feed
    }

    /// Duration of the whole test: both runs and the dwell between them (s).
    pub fn duration(&self) -> Real {
        2.0 * self.run_duration() + self.dwell
    }

    /// When the command enters `sense`'s data arc (s from the start of the test): after its
    /// overshoot arc, run at the feed once the ramp is done (the ramp fits in the overshoot).
    pub fn entry_time(&self, sense: Sense) -> Real {
        let ramp_time = self.feed / self.acceleration;
        let into_run = ramp_time + (self.radius * self.overshoot - self.ramp_length()) / self.feed;
        match sense {
            Sense::Ccw => into_run,
            Sense::Cw => self.run_duration() + self.dwell + into_run,
        }
    }

    /// Why this path cannot be run as a test, if it cannot: every value must be finite and
    /// positive (overshoot and dwell may be zero), the data arc at most a full turn, and the
    /// ramps must fit inside the overshoot arcs so that the data arc is run at the feed.
    pub fn problem(&self) -> Option<String> {
        let positive = [
            ("radius", self.radius),
            ("feed", self.feed),
            ("data arc", self.data_arc),
            ("acceleration", self.acceleration),
        ];
        if let Some((name, value)) = positive.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
            return Some(format!("{name} must be a positive number, got {value}"));
        }
        if !(self.overshoot.is_finite() && self.overshoot >= 0.0) {
            return Some(format!("overshoot must be ≥ 0, got {}", self.overshoot));
        }
        if !(self.dwell.is_finite() && self.dwell >= 0.0) {
            return Some(format!("dwell must be ≥ 0, got {}", self.dwell));
        }
        if !self.data_start.is_finite() {
            return Some("the data arc's start must be a finite angle".into());
        }
        if self.data_arc > std::f64::consts::TAU + 1e-12 {
            return Some("the data arc is more than a full circle".into());
        }
        if self.ramp_length() > self.radius * self.overshoot {
            return Some(format!(
                "the acceleration ramp ({:.3} mm at this feed and acceleration) is longer than the overshoot arc ({:.3} mm): the data arc would not run at the feed",
                self.ramp_length() * 1e3,
                self.radius * self.overshoot * 1e3
            ));
        }
        None
    }

    /// Distance along the path (m) and path speed (m/s) `t` seconds into a run.
    fn along(&self, t: Real) -> (Real, Real) {
        let (v, a) = (self.feed, self.acceleration);
        let ramp_time = v / a;
        let total = self.run_duration();
        let t = t.clamp(0.0, total);
        if t < ramp_time {
            (a * t * t / 2.0, a * t)
        } else if t <= total - ramp_time {
            (self.ramp_length() + v * (t - ramp_time), v)
        } else {
            let left = total - t;
            (self.run_length() - a * left * left / 2.0, a * left)
        }
    }

    /// The interpolator's state at time `t` (s) from the start of the test.
    pub fn command(&self, t: Real) -> CommandPoint {
        let run = self.run_duration();
        let (sense, into_run) = if t < run {
            (Sense::Ccw, t)
        } else if t < run + self.dwell {
            (Sense::Ccw, run)
        } else {
            (Sense::Cw, t - run - self.dwell)
        };
        let (s, speed) = self.along(into_run);
        let first = self.data_start - self.overshoot;
        let last = self.data_start + self.data_arc + self.overshoot;
        let angle = match sense {
            Sense::Ccw => first + s / self.radius,
            Sense::Cw => last - s / self.radius,
        };
        CommandPoint {
            sense,
            angle,
            speed,
        }
    }

    /// Commanded axis positions at a programmed angle (rad).
    pub fn position(&self, angle: Real) -> AxisValues {
        let mut position = self.centre;
        position[self.plane.first()] += self.radius * angle.cos();
        position[self.plane.second()] += self.radius * angle.sin();
        position
    }

    /// Whether a programmed angle (unwrapped, as [`CommandPoint::angle`]) is on the data arc.
    pub fn in_data(&self, angle: Real) -> bool {
        let tolerance = 1e-12;
        angle >= self.data_start - tolerance && angle <= self.data_start + self.data_arc + tolerance
    }
}

/// The machine at one sampling instant of a circular test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ServoSample {
    /// Time from the start of the test (s).
    pub time: Real,
    /// The interpolator's state (programmed angle, sense, speed).
    pub command: CommandPoint,
    /// Actual axis positions and directions of travel, for the twin.
    pub state: MachineState,
}

/// Runs a circular test through the controller and samples it every `sample_period` seconds
/// from t = 0 to the end of the test: the interpolator's state and the actual axis positions
/// (with each axis's direction of travel) at each sample.
///
/// The loops start at rest on the first command point; each axis's direction of travel starts
/// as that of its first commanded motion. Allocates the returned samples only.
pub fn run_circle(
    circle: &CircularInterpolation,
    servo: &Servo,
    sample_period: Real,
) -> Vec<ServoSample> {
    assert!(
        sample_period > 0.0 && servo.ipo_period > 0.0,
        "sampling and interpolation periods must be positive"
    );
    let axes = [circle.plane.first(), circle.plane.second()];
    let first_angle = circle.command(0.0).angle;
    let start = circle.position(first_angle);
    // A thousandth of a radian into the first (counter-clockwise) run.
    let early = circle.position(first_angle + 1e-3);
    let mut loops = axes.map(|axis| {
        let direction = if early[axis] >= start[axis] {
            Direction::Positive
        } else {
            Direction::Negative
        };
        AxisLoop::new(*servo.axis(axis), axis, start[axis], direction)
    });
    let duration = circle.duration();
    let mut out = Vec::with_capacity((duration / sample_period).floor() as usize + 1);
    let never: Result<(), std::convert::Infallible> = sample_loops(
        &mut loops,
        &start,
        Sampling {
            ipo_period: servo.ipo_period,
            duration,
            sample_period,
        },
        MachineState::at(circle.centre),
        |t1| Ok(circle.position(circle.command(t1).angle)),
        |t, state| {
            out.push(ServoSample {
                time: t,
                command: circle.command(t),
                state: *state,
            });
            Ok(())
        },
    );
    let Ok(()) = never;
    out
}
