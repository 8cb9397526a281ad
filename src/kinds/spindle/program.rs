//! What the axis does during a spindle test: for each set-up, for each speed, whole settling
//! revolutions (not recorded: the probes' filters settle) and then `revolutions` revolutions
//! sampled on the index.
//!
//! Sample `m` of revolution `k` of a record at speed `ω` (rotation frequency `f = |ω|/2π`) with
//! `M` samples per revolution is taken at
//!
//! ```text
//! θ_m = ±2πm/M (within [0, 2π), minus for a negative speed)
//! t   = t_start + (k + m/M)/f
//! ```
//!
//! with the axis turning at `ω` and the other axes parked. Time runs on without a break through
//! the whole programme (one record's settling starts where the previous record ended; the
//! change of speed or set-up is taken as instantaneous), and so does the axis's unwrapped angle,
//! which asynchronous content per revolution follows. The first settling starts at `t = 0`
//! with the axis at 0.

use crate::math::Real;
use std::f64::consts::{PI, TAU};

/// A set-up of the artefact and probes (ISO 230-7 Annex B and its multi-step extension).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Setup {
    /// As given.
    Normal,
    /// Donaldson reversal: the artefact turned 180° on its carrier and the radial probes moved
    /// to the opposite side of the axis (azimuth + 180°); axial and face probes stay.
    Reversed,
    /// The artefact turned by this angle (rad) on its carrier, the probes unchanged (one step
    /// of a multi-step separation).
    Turned(Real),
}

impl Setup {
    /// Its name in scenarios and in the table's `setup` column: `normal`, `reversed`,
    /// `turned_<deg>`.
    pub fn name(self) -> String {
        match self {
            Setup::Normal => "normal".into(),
            Setup::Reversed => "reversed".into(),
            Setup::Turned(angle) => {
                format!("turned_{}", crate::math::trimmed(angle.to_degrees(), 6))
            }
        }
    }

    /// The set-up named `text`; `None` when it is none of them.
    pub fn parse(text: &str) -> Option<Setup> {
        match text {
            "normal" => Some(Setup::Normal),
            "reversed" => Some(Setup::Reversed),
            _ => {
                let degrees: Real = text.strip_prefix("turned_")?.parse().ok()?;
                (degrees.is_finite() && degrees > 0.0 && degrees < 360.0)
                    .then(|| Setup::Turned(degrees.to_radians()))
            }
        }
    }

    /// The angle the artefact is turned by on its carrier (rad).
    pub fn artefact_turn(self) -> Real {
        match self {
            Setup::Normal => 0.0,
            Setup::Reversed => PI,
            Setup::Turned(angle) => angle,
        }
    }

    /// Whether the radial probes sit on the opposite side of the axis.
    pub fn probes_opposite(self) -> bool {
        self == Setup::Reversed
    }
}

/// One record: one set-up at one speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Block {
    /// Index of the set-up in the test's list.
    pub setup: usize,
    /// Index of the speed in the test's list.
    pub speed_index: usize,
    /// The speed (rad/s, signed).
    pub speed: Real,
    /// Settling revolutions before the record.
    pub settle_revolutions: usize,
    /// Recorded revolutions.
    pub revolutions: usize,
    /// Samples per revolution.
    pub samples_per_revolution: usize,
    /// Time at the start of the settling (s).
    pub start_time: Real,
    /// The axis's unwrapped angle at that time (rad): a whole number of turns.
    pub start_angle: Real,
}

/// One sample of a block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Time (s).
    pub time: Real,
    /// The axis's unwrapped angle (rad).
    pub position: Real,
    /// Index of the angle on the grid `2πi/M`: `θ = 2π·angle_index/M`.
    pub angle_index: usize,
    /// The recorded revolution, `None` while settling.
    pub revolution: Option<usize>,
}

impl Block {
    /// Rotation frequency (revolutions per second).
    pub fn frequency(&self) -> Real {
        self.speed.abs() / TAU
    }

    /// Sample interval (s).
    pub fn interval(&self) -> Real {
        1.0 / (self.samples_per_revolution as Real * self.frequency())
    }

    /// Samples from the start of the settling to the end of the record.
    pub fn sample_count(&self) -> usize {
        (self.settle_revolutions + self.revolutions) * self.samples_per_revolution
    }

    /// Time at the first recorded sample (the index mark after the settling).
    pub fn record_start(&self) -> Real {
        self.start_time + self.settle_revolutions as Real / self.frequency()
    }

    /// Time at the end of the block (where the next one starts).
    pub fn end_time(&self) -> Real {
        self.start_time + (self.settle_revolutions + self.revolutions) as Real / self.frequency()
    }

    /// The unwrapped angle at the end of the block.
    pub fn end_angle(&self) -> Real {
        self.start_angle
            + self.speed.signum() * TAU * (self.settle_revolutions + self.revolutions) as Real
    }

    /// Sample `j` from the start of the settling (`0 ≤ j < sample_count`).
    pub fn sample(&self, j: usize) -> Sample {
        let per_rev = self.samples_per_revolution;
        let turns = j as Real / per_rev as Real;
        let m = j % per_rev;
        let forward = self.speed > 0.0;
        let recorded_from = self.settle_revolutions * per_rev;
        Sample {
            time: self.start_time + turns / self.frequency(),
            position: self.start_angle + self.speed.signum() * TAU * turns,
            angle_index: if forward { m } else { (per_rev - m) % per_rev },
            revolution: (j >= recorded_from).then(|| (j - recorded_from) / per_rev),
        }
    }
}

/// The records of a test in order: each set-up, each speed; times and angles continuous.
pub fn schedule(
    setups: usize,
    speeds: &[Real],
    revolutions: usize,
    samples_per_revolution: usize,
    settle: Real,
) -> Vec<Block> {
    let mut blocks = Vec::with_capacity(setups * speeds.len());
    let (mut time, mut angle) = (0.0, 0.0);
    for setup in 0..setups {
        for (speed_index, &speed) in speeds.iter().enumerate() {
            let frequency = speed.abs() / TAU;
            let block = Block {
                setup,
                speed_index,
                speed,
                settle_revolutions: (settle * frequency).ceil() as usize,
                revolutions,
                samples_per_revolution,
                start_time: time,
                start_angle: angle,
            };
            time = block.end_time();
            angle = block.end_angle();
            blocks.push(block);
        }
    }
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_fall_on_the_index_grid_and_time_runs_on() {
        // 600 rpm = 10 rev/s, 8 samples a revolution, 0.15 s of settling = 2 whole revolutions.
        let blocks = schedule(2, &[20.0 * PI, -20.0 * PI], 3, 8, 0.15);
        assert_eq!(blocks.len(), 4);
        let b = blocks[0];
        assert_eq!(b.settle_revolutions, 2);
        assert_eq!(b.sample_count(), 40);
        let first = b.sample(16);
        assert_eq!(first.revolution, Some(0));
        assert_eq!(first.angle_index, 0);
        assert!((first.time - 0.2).abs() < 1e-15);
        let s = b.sample(16 + 8 + 3);
        assert_eq!((s.revolution, s.angle_index), (Some(1), 3));
        assert!((s.time - (0.2 + (1.0 + 3.0 / 8.0) / 10.0)).abs() < 1e-15);
        assert!((s.position - TAU * (3.0 + 3.0 / 8.0)).abs() < 1e-12);
        // The next block starts where this one ends, turning backwards.
        let n = blocks[1];
        assert!((n.start_time - 0.5).abs() < 1e-15);
        let back = n.sample(1);
        assert_eq!(back.angle_index, 7);
        assert!((back.position - (TAU * 5.0 - TAU / 8.0)).abs() < 1e-12);
        assert_eq!(blocks[2].setup, 1);
    }

    #[test]
    fn set_up_names_read_back() {
        for setup in [
            Setup::Normal,
            Setup::Reversed,
            Setup::Turned(72f64.to_radians()),
        ] {
            assert_eq!(Setup::parse(&setup.name()), Some(setup));
        }
        assert_eq!(Setup::parse("turned_0"), None);
        assert_eq!(Setup::parse("upside_down"), None);
    }
}
