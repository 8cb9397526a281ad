//! A virtual telescopic ball-bar for circular tests (ISO 230-4).
//!
//! One ball sits in a cup on the table (the centre ball), the other in a cup on the spindle
//! (the tool ball, at the tool tip); the bar between them reads the change of their distance.
//! The machine runs a circle of the bar's nominal length about the centre ball, counter-
//! clockwise then clockwise ([`CircularInterpolation`]), through its controller
//! ([`crate::program::servo`]) and the twin (geometric errors at the actual axis positions,
//! with each axis's direction of travel). Each reading, at a fixed sampling rate over the data
//! arc (the overshoot arcs are not recorded), is
//!
//! ```text
//! deviation = quantise(|p_tool − p_centre| − L + δ_cal + noise)
//! ```
//!
//! with `p_tool` the actual tool-tip position in the workpiece frame, `p_centre` the centre
//! ball: where the machine actually put the tool tip when commanded to the circle centre (the
//! centre cup is set from the machine, as with a setting ball) plus the set-up offset, `L` the
//! nominal length and `δ_cal` the bar's calibration error (reported − true length).
//!
//! The angle of a reading is assigned as ball-bar software assigns it: from the time since the
//! start of the data arc it detected in the machine's motion, at the programmed feed. The
//! software sees the machine, not its controller, so the start it detects is where the axes
//! actually arrive, a servo lag after the command ([`detected_delay`]); the angle of a reading
//! taken at `t` is the programmed angle at `t − delay`, in [0°, 360°). At the feed, through a
//! position loop, that is where the axes actually are: the common lag of the two axes is not
//! in the angles (their difference is, as the servo mismatch), and an axis reverses at
//! 0°/90°/… plus its own lag less the common one. Assigning the programmed angle at `t`
//! instead would turn every shape of the trace by the common lag (v·τ/R, 0.57° at 2000 mm/min
//! on a 100 mm bar with K_v = 33 s⁻¹), against the sense of travel: the squareness's ellipse
//! then differs between the senses by a σ·cos 2θ term that the diagnostics would read as
//! lateral play.
//!
//! Simplified: rigid bar and balls (no sphericity error, no bar sag or thermal growth of the
//! bar), no tool-cup offset from the tool tip.

use crate::kinds::ballbar::program::{CircularInterpolation, ServoSample, run_circle};
use crate::kinds::ballbar::table::{BallbarReading, BallbarTable, Sense, TestConditions};
use crate::machine::{MachineState, Workspace};
use crate::math::{Real, Vector, quantise, standard_normal};
use crate::program::Servo;
use crate::twin::Twin;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};

/// The bar lengths a ball-bar kit offers (m): the bar and its extensions.
pub const BALLBAR_LENGTHS: [Real; 4] = [0.05, 0.1, 0.15, 0.3];

/// A ball-bar and how it is set up.
#[derive(Clone, Debug, PartialEq)]
pub struct Ballbar {
    /// Nominal length (m), one of [`BALLBAR_LENGTHS`]: the radius of the test.
    pub length: Real,
    /// Centre ball relative to where the machine puts the tool tip at the circle centre,
    /// workpiece frame (m).
    pub setup_offset: Vector,
    /// Calibration error: reported − true length (m).
    pub calibration_error: Real,
    /// Resolution (m).
    pub resolution: Real,
    /// White noise on each reading, 1σ (m).
    pub noise: Real,
    /// Sampling rate (Hz).
    pub sample_rate: Real,
}

impl Ballbar {
    /// Runs `circle` on `twin` through `servo` and reads the bar at every sample on the data
    /// arc, both senses. `rng` draws the noise.
    pub fn measure(
        &self,
        twin: &Twin,
        circle: &CircularInterpolation,
        servo: &Servo,
        rng: &mut ChaCha8Rng,
    ) -> BallbarTable {
        assert!(
            (circle.radius - self.length).abs() < 1e-12,
            "the circle's radius is the bar's length"
        );
        let (machine, errors) = (&twin.machine, &twin.errors);
        let mut workspace = Workspace::new(machine);
        let centre = errors
            .workpiece_from_tool(machine, &mut workspace, &MachineState::at(circle.centre))
            .translation
            + self.setup_offset;
        let samples = run_circle(circle, servo, 1.0 / self.sample_rate);
        let delays = [Sense::Ccw, Sense::Cw].map(|sense| detected_delay(circle, &samples, sense));
        let mut readings = Vec::with_capacity(samples.len());
        for sample in &samples {
            let sense = sample.command.sense;
            let assigned = circle.command(sample.time - delays[usize::from(sense == Sense::Cw)]);
            if assigned.sense != sense || !circle.in_data(assigned.angle) {
                continue;
            }
            // On the circle's clock (the sample's state carries its time; the centre was set
            // at the start).
            let tool = errors
                .workpiece_from_tool(machine, &mut workspace, &sample.state)
                .translation;
            let reading = (tool - centre).length() - self.length
                + self.calibration_error
                + self.noise * standard_normal(rng);
            readings.push(BallbarReading {
                sense,
                angle: assigned.angle.rem_euclid(TAU),
                deviation: quantise(reading, self.resolution),
                time: Some(sample.time),
            });
        }
        BallbarTable {
            readings,
            conditions: TestConditions {
                plane: Some(circle.plane),
                radius: Some(circle.radius),
                feed: Some(circle.feed),
                sample_rate: Some(self.sample_rate),
                first: Some(Sense::Ccw),
                centre: Some(circle.centre),
            },
            machine: Some(machine.name().to_string()),
            columns_not_read: Vec::new(),
        }
    }
}

/// How long after the command the axes actually reach the start of `sense`'s data arc (s),
/// the start ball-bar software detects: the first crossing of the entry angle by the actual
/// axis positions' polar angle about the circle centre (unwrapped along the run from the
/// programmed start) during the run of that sense, timed by linear interpolation between
/// `samples`, less the time the command crosses it. 0 when the run's first sample is already
/// at or past the entry (a test without an overshoot arc).
pub fn detected_delay(
    circle: &CircularInterpolation,
    samples: &[ServoSample],
    sense: Sense,
) -> Real {
    let sigma = sense.sign();
    let entry = match sense {
        Sense::Ccw => circle.data_start,
        Sense::Cw => circle.data_start + circle.data_arc,
    };
    let (p, q) = (circle.plane.first(), circle.plane.second());
    let polar = |s: &ServoSample| {
        (s.state.position[q] - circle.centre[q]).atan2(s.state.position[p] - circle.centre[p])
    };
    let wrap = |angle: Real| (angle + PI).rem_euclid(TAU) - PI;
    let mut run = samples.iter().filter(|s| s.command.sense == sense);
    let Some(first) = run.next() else {
        return 0.0;
    };
    // σ × the actual angle past the entry, the angle unwrapped from the programmed start.
    let mut raw = polar(first);
    let mut unwrapped = first.command.angle + wrap(raw - first.command.angle);
    let mut previous = (first.time, sigma * (unwrapped - entry));
    if previous.1 >= 0.0 {
        return 0.0;
    }
    for sample in run {
        let angle = polar(sample);
        unwrapped += wrap(angle - raw);
        raw = angle;
        let past = sigma * (unwrapped - entry);
        if past >= 0.0 {
            let (t0, d0) = previous;
            let crossing = t0 + (sample.time - t0) * (-d0) / (past - d0);
            return crossing - circle.entry_time(sense);
        }
        previous = (sample.time, past);
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::{AxisValues, Plane};
    use crate::program::AxisServo;

    fn circle(data_start: Real, overshoot: Real) -> CircularInterpolation {
        CircularInterpolation {
            plane: Plane::XY,
            centre: AxisValues::default(),
            radius: 0.1,
            feed: 2.0 / 60.0,
            data_start,
            data_arc: TAU,
            overshoot,
            acceleration: 1.0,
            dwell: 0.5,
        }
    }

    fn servo(kv: [Real; 2], feed_forward: Real) -> Servo {
        let mut servo = Servo::default();
        for (axis, kv) in servo.axes.iter_mut().zip(kv) {
            *axis = AxisServo {
                kv,
                feed_forward,
                ..AxisServo::DEFAULT
            };
        }
        servo
    }

    #[test]
    fn the_detected_start_lags_the_command_by_the_loops_phase_lag() {
        // Both axes with ẋ = Kv·(c − x) + f·ċ follow a circle at ω = v/R with the phase lag
        // arg H(jω), H(s) = (Kv + f·s)/(Kv + s), once the start-up transient (e^(−Kv·t),
        // e^(−66) by the data arc) is gone: the actual path is the circle turned back by
        // (atan(ω/Kv) − atan(f·ω/Kv)), reached that many radians later. Kv = 33.3 s⁻¹,
        // ω = 1/3 s⁻¹: 29.9990 ms without feed-forward, 14.9996 ms with half of it. The
        // interpolator's 1 ms chords move the crossing by far less than 1 µs. A 180° overshoot
        // starts each run opposite its entry.
        for (feed_forward, data_start, overshoot_deg) in [
            (0.0, 0.0, 45.0),
            (0.5, 1.0, 45.0),
            (0.0, 4.0, 45.0),
            (0.0, 0.0, 180.0),
        ] {
            let circle = circle(data_start, overshoot_deg * std::f64::consts::PI / 180.0);
            let kv = 100.0 / 3.0;
            let samples = run_circle(&circle, &servo([kv; 2], feed_forward), 0.01);
            let omega = circle.feed / circle.radius;
            let expected = ((omega / kv).atan() - (feed_forward * omega / kv).atan()) / omega;
            for sense in [Sense::Ccw, Sense::Cw] {
                let delay = detected_delay(&circle, &samples, sense);
                assert!(
                    (delay - expected).abs() < 1e-6,
                    "f {feed_forward}, {sense:?}: {delay} s, expected {expected} s"
                );
            }
        }
    }

    #[test]
    fn with_unequal_gains_the_start_is_timed_by_the_axis_across_the_entry() {
        // At the entry angle 0° the polar angle of (p, q) crosses 0 when q does: the delay is
        // q's phase lag, whatever p's gain (and p's at 90°).
        let (kv_p, kv_q) = (25.0, 100.0 / 3.0);
        let omega = (2.0 / 60.0) / 0.1;
        for (data_start, kv) in [(0.0, kv_q), (std::f64::consts::FRAC_PI_2, kv_p)] {
            let circle = circle(data_start, 45.0 * std::f64::consts::PI / 180.0);
            let samples = run_circle(&circle, &servo([kv_p, kv_q], 0.0), 0.01);
            let delay = detected_delay(&circle, &samples, Sense::Ccw);
            let expected = (omega / kv).atan() / omega;
            assert!((delay - expected).abs() < 1e-6, "{delay} vs {expected}");
        }
    }

    #[test]
    fn without_an_overshoot_arc_the_start_is_the_commands() {
        // The run starts at rest on the entry: nothing to detect, no delay.
        let mut circle = circle(0.0, 0.0);
        circle.acceleration = Real::INFINITY;
        let samples = run_circle(&circle, &Servo::default(), 0.01);
        assert_eq!(detected_delay(&circle, &samples, Sense::Ccw), 0.0);
    }
}
