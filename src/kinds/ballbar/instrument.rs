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
//! nominal length and `δ_cal` the bar's calibration error (reported − true length). The angle
//! is the programmed angle at the sampling instant, in [0°, 360°), as ball-bar software assigns
//! it from the programmed path.
//!
//! Simplified: rigid bar and balls (no sphericity error, no bar sag or thermal growth of the
//! bar), no tool-cup offset from the tool tip.

use crate::kinds::ballbar::program::{CircularInterpolation, run_circle};
use crate::kinds::ballbar::table::{BallbarReading, BallbarTable, Sense, TestConditions};
use crate::machine::{MachineState, Workspace};
use crate::math::{Real, Vector, quantise, standard_normal};
use crate::program::Servo;
use crate::twin::Twin;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;

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
        let mut readings = Vec::with_capacity(samples.len());
        for sample in samples.iter().filter(|s| circle.in_data(s.command.angle)) {
            let tool = errors
                .workpiece_from_tool(machine, &mut workspace, &sample.state)
                .translation;
            let reading = (tool - centre).length() - self.length
                + self.calibration_error
                + self.noise * standard_normal(rng);
            readings.push(BallbarReading {
                sense: sample.command.sense,
                angle: sample.command.angle.rem_euclid(TAU),
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
            },
        }
    }
}
