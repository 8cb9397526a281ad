//! The programmes of the laser tests: the ISO 230-2 linear cycle with its irregular targets,
//! and the ISO 230-3 §7 linear-motion test (the warm-up experiment is built from
//! [`LinearCycle`] runs in [`super::scenario::thermal_tests`]).

use crate::machine::{Axis, AxisValues};
use crate::math::Real;
use crate::program::{Approach, MeasurePoint, Program, Step, Visit, visits};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// The ISO 230-2 test cycle on one linear axis: in each run, from an overrun below the first
/// target, every target is approached in the positive direction; then from an overrun beyond
/// the last, every target in the negative direction (the standard's linear cycle).
#[derive(Clone, Debug, PartialEq)]
pub struct LinearCycle {
    /// The axis under test.
    pub axis: Axis,
    /// Target positions (m), increasing.
    pub targets: Vec<Real>,
    /// Number of bidirectional runs.
    pub runs: usize,
    /// Overrun beyond the first and last targets (m), so each approach starts from the same side.
    pub overrun: Real,
    /// Feed between points (m/s).
    pub feed: Real,
    /// Dwell at each target before the reading (s).
    pub dwell: Real,
    /// Positions of the other axes during the test (SI).
    pub rest: AxisValues,
}

impl LinearCycle {
    /// The steps of one run (index `run`): overrun below, targets upwards, overrun above,
    /// targets downwards, each target followed by the dwell and a measurement.
    pub fn run_steps(&self, run: usize) -> Vec<Step> {
        let mut steps = Vec::with_capacity(6 * self.targets.len() + 2);
        let (Some(&first), Some(&last)) = (self.targets.first(), self.targets.last()) else {
            return steps;
        };
        let go = |to: Real| Step::Move {
            to: vec![(self.axis, to)],
            feed: self.feed,
        };
        for (approach, start) in [
            (Approach::Up, first - self.overrun),
            (Approach::Down, last + self.overrun),
        ] {
            steps.push(go(start));
            let order: Vec<usize> = match approach {
                Approach::Up => (0..self.targets.len()).collect(),
                Approach::Down => (0..self.targets.len()).rev().collect(),
            };
            for target in order {
                steps.push(go(self.targets[target]));
                steps.push(Step::Dwell(self.dwell));
                steps.push(Step::Measure(MeasurePoint {
                    run,
                    target,
                    approach,
                }));
            }
        }
        steps
    }

    /// The whole test as a programme, starting at the first overrun position.
    pub fn program(&self) -> Program {
        let mut start = self.rest;
        start[self.axis] = self.targets.first().map_or(0.0, |t| t - self.overrun);
        Program {
            start,
            steps: (0..self.runs).flat_map(|run| self.run_steps(run)).collect(),
        }
    }

    /// Every reading of the test in order, timed.
    pub fn visits(&self) -> Vec<Visit> {
        visits(&self.program().timeline(Real::INFINITY))
    }
}

/// The ISO 230-3 §7 linear-motion test on one axis: cycling between two targets near the ends of
/// travel (each approached only from the other, so reversal is included), readings every
/// `read_every` bidirectional cycles; then a cool-down parked at mid-travel, visiting both
/// targets every `visit_interval`. Target 0 (P1, the lower) is always approached downwards,
/// target 1 (P2) upwards; run k is the k-th pair of readings. It starts at P2 and reads
/// P1 then P2 before cycling.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearMotionTest {
    /// The axis.
    pub axis: Axis,
    /// P1 < P2 (m).
    pub targets: [Real; 2],
    /// Traverse rate (m/s).
    pub feed: Real,
    /// Dwell at each target (s).
    pub dwell: Real,
    /// Length of the cycling period (s).
    pub cycling: Real,
    /// Read every this many bidirectional cycles (≥ 1).
    pub read_every: usize,
    /// Length of the cool-down (s).
    pub cooldown: Real,
    /// Interval between cool-down visits (s).
    pub visit_interval: Real,
    /// Positions of the other axes (SI).
    pub rest: AxisValues,
}

impl LinearMotionTest {
    /// The whole test as a programme.
    pub fn program(&self) -> Program {
        let [p1, p2] = self.targets;
        let go = |to: Real| Step::Move {
            to: vec![(self.axis, to)],
            feed: self.feed,
        };
        let read = |run: usize, steps: &mut Vec<Step>| {
            steps.push(go(p1));
            steps.push(Step::Dwell(self.dwell));
            steps.push(Step::Measure(MeasurePoint {
                run,
                target: 0,
                approach: Approach::Down,
            }));
            steps.push(go(p2));
            steps.push(Step::Dwell(self.dwell));
            steps.push(Step::Measure(MeasurePoint {
                run,
                target: 1,
                approach: Approach::Up,
            }));
        };
        let mut steps = Vec::new();
        let mut run = 0;
        read(run, &mut steps);
        let cycle_time = 2.0 * ((p2 - p1).abs() / self.feed + self.dwell);
        let cycles = (self.cycling / cycle_time).floor() as usize;
        for cycle in 1..=cycles {
            if cycle % self.read_every.max(1) == 0 {
                run += 1;
                read(run, &mut steps);
            } else {
                steps.extend([
                    go(p1),
                    Step::Dwell(self.dwell),
                    go(p2),
                    Step::Dwell(self.dwell),
                ]);
            }
        }
        // Cool-down: park at mid-travel; every `visit_interval`, read both targets and return.
        let middle = (p1 + p2) / 2.0;
        let to_middle = (p2 - middle).abs() / self.feed;
        let visit_time = (middle - p1).abs() / self.feed
            + (p2 - p1).abs() / self.feed
            + 2.0 * self.dwell
            + to_middle;
        steps.push(go(middle));
        let visits = (self.cooldown / self.visit_interval).floor() as usize;
        for visit in 0..visits {
            let wait = self.visit_interval - if visit == 0 { to_middle } else { visit_time };
            steps.push(Step::Dwell(wait.max(0.0)));
            run += 1;
            read(run, &mut steps);
            steps.push(go(middle));
        }
        let mut start = self.rest;
        start[self.axis] = p2;
        Program { start, steps }
    }
}

/// `count` targets from `start` to `end` (m) at the irregular spacing ISO 230-2 asks for, so
/// that a periodic error does not hide between them: the interior targets move from the even
/// spacing p by a seeded random amount within ±p/4. The first and last stay put.
pub fn irregular_targets(start: Real, end: Real, count: usize, rng: &mut ChaCha8Rng) -> Vec<Real> {
    let spacing = (end - start) / (count.max(2) - 1) as Real;
    (0..count)
        .map(|i| {
            let even = start + spacing * i as Real;
            if i == 0 || i + 1 == count {
                even
            } else {
                even + spacing * (rng.random::<Real>() - 0.5) / 2.0
            }
        })
        .collect()
}
