//! What the machine does over time. So far: the ISO 230-2 linear test cycle (targets approached
//! in both directions with an overrun, runs repeated), with the time of every reading from the
//! feed and the dwell. Continuous programmes (warm-up cycles, circular interpolation, spindle
//! programmes) and the servo model come with the thermal and ball-bar work.

use crate::io::Approach;
use crate::machine::{Axis, AxisValues, Direction, MachineState};
use crate::math::Real;
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

/// One reading of the cycle: where the machine stands, how it got there, and when.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Visit {
    /// Run index (from 0).
    pub run: usize,
    /// Target index (from 0, increasing position).
    pub target: usize,
    /// Direction of approach.
    pub approach: Approach,
    /// Time since the start of the test (s).
    pub time: Real,
    /// Commanded positions and directions of travel.
    pub state: MachineState,
}

impl LinearCycle {
    /// Every reading of the test in order, timed: moves at the feed between consecutive points
    /// (overruns included), then the dwell, then the reading.
    pub fn visits(&self) -> Vec<Visit> {
        let mut visits = Vec::with_capacity(2 * self.runs * self.targets.len());
        let (Some(&first), Some(&last)) = (self.targets.first(), self.targets.last()) else {
            return visits;
        };
        let mut time = 0.0;
        let mut here = first - self.overrun;
        let mut go = |to: Real, time: &mut Real| {
            *time += (to - here).abs() / self.feed;
            here = to;
        };
        for run in 0..self.runs {
            for (approach, direction, start) in [
                (Approach::Up, Direction::Positive, first - self.overrun),
                (Approach::Down, Direction::Negative, last + self.overrun),
            ] {
                go(start, &mut time);
                let order: Vec<usize> = match approach {
                    Approach::Up => (0..self.targets.len()).collect(),
                    Approach::Down => (0..self.targets.len()).rev().collect(),
                };
                for target in order {
                    go(self.targets[target], &mut time);
                    time += self.dwell;
                    let mut state = MachineState::at(self.rest);
                    state.position[self.axis] = self.targets[target];
                    state.direction[self.axis.index()] = direction;
                    visits.push(Visit {
                        run,
                        target,
                        approach,
                        time,
                        state,
                    });
                }
            }
        }
        visits
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
