//! What the machine does over time: a programme of steps (moves at a feed, dwells, warm-up
//! cycles, spindle speed changes, measurement points) turned into a timeline of intervals
//! (for the thermal model: how fast each axis moved and how fast the spindle turned) and
//! measurement events (for the instruments: where the machine stood and how it got there).
//!
//! Simplified: the steps of a [`Program`] move axes at constant speed along straight lines,
//! starting and stopping instantly (no acceleration, no servo lag), which is what the thermal
//! model needs. Circular tests have their own interpolator ([`CircularInterpolation`]: ramps,
//! overshoot arcs) and controller model ([`servo`]: position loops, feed-forward, reversal
//! spikes, vibration), which turn commands into actual axis positions.

mod circle;
pub mod servo;

pub use circle::{CircularInterpolation, CommandPoint};
pub use servo::{AxisServo, Servo, ServoSample, run_circle};

use crate::io::Approach;
use crate::machine::{Axis, AxisValues, Direction, MachineState};
use crate::math::Real;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// What a measurement event is about, for the instrument that takes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeasurePoint {
    /// Run index (from 0).
    pub run: usize,
    /// Target index.
    pub target: usize,
    /// Direction of approach.
    pub approach: Approach,
}

/// One step of a programme (SI: m, m/s, s, rad/s).
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Move the named axes (the others stay) along a straight line at `feed` (path speed).
    Move {
        /// Where to.
        to: Vec<(Axis, Real)>,
        /// Path speed (m/s), > 0.
        feed: Real,
    },
    /// Stand still.
    Dwell(Real),
    /// Run one axis back and forth between two positions at `feed` for `duration`, then return
    /// to where it started.
    WarmUp {
        /// The axis.
        axis: Axis,
        /// One end of the stroke.
        from: Real,
        /// The other end.
        to: Real,
        /// Speed (m/s).
        feed: Real,
        /// How long (s).
        duration: Real,
    },
    /// Set the spindle speed (rad/s; 0 stops it).
    Spindle(Real),
    /// A measurement point.
    Measure(MeasurePoint),
}

/// An interval of the timeline, during which the heat inputs are taken as constant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Its length (s).
    pub duration: Real,
    /// Mean speed of each axis over it (m/s or rad/s, ≥ 0).
    pub speed: AxisValues,
    /// Spindle speed (rad/s).
    pub spindle: Real,
}

/// One reading of an instrument: where the machine stands, how it got there, and when.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Visit {
    /// What is being measured.
    pub point: MeasurePoint,
    /// Time since the start of the programme (s).
    pub time: Real,
    /// Commanded positions and directions of travel.
    pub state: MachineState,
}

/// An event of the timeline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Event {
    /// Time passes.
    Interval(Interval),
    /// An instrument reads.
    Measure(Visit),
}

/// A programme: where the machine starts and its steps.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    /// Starting positions (SI).
    pub start: AxisValues,
    /// The steps, in order.
    pub steps: Vec<Step>,
}

impl Program {
    /// The timeline, with no interval longer than `max_interval` seconds.
    pub fn timeline(&self, max_interval: Real) -> Vec<Event> {
        assert!(max_interval > 0.0, "intervals need a positive length");
        let mut events = Vec::new();
        let mut state = MachineState::at(self.start);
        let mut time = 0.0;
        let mut spindle = 0.0;
        let pass = |duration: Real,
                    speed: AxisValues,
                    spindle: Real,
                    time: &mut Real,
                    events: &mut Vec<Event>| {
            let pieces = (duration / max_interval).ceil().max(1.0) as usize;
            for _ in 0..pieces {
                events.push(Event::Interval(Interval {
                    duration: duration / pieces as Real,
                    speed,
                    spindle,
                }));
            }
            *time += duration;
        };
        for step in &self.steps {
            match step {
                Step::Move { to, feed } => {
                    let mut end = state.position;
                    for &(axis, value) in to {
                        end[axis] = value;
                    }
                    let delta: Vec<Real> = (0..7).map(|i| end.0[i] - state.position.0[i]).collect();
                    let length = delta.iter().map(|d| d * d).sum::<Real>().sqrt();
                    if length > 0.0 {
                        let duration = length / feed;
                        let mut speed = AxisValues::ZERO;
                        for (i, d) in delta.iter().enumerate() {
                            speed.0[i] = d.abs() / duration;
                            if *d != 0.0 {
                                state.direction[i] = if *d > 0.0 {
                                    Direction::Positive
                                } else {
                                    Direction::Negative
                                };
                            }
                        }
                        pass(duration, speed, spindle, &mut time, &mut events);
                        state.position = end;
                    }
                }
                Step::Dwell(duration) => {
                    pass(*duration, AxisValues::ZERO, spindle, &mut time, &mut events)
                }
                Step::WarmUp {
                    axis,
                    from,
                    to,
                    feed,
                    duration,
                } => {
                    // To `from`, back and forth over the stroke for `duration`, then home: the
                    // axis moves at the feed throughout, so that is its mean speed.
                    let (axis, home) = (*axis, state.position[*axis]);
                    let stroke = (to - from).abs();
                    let travelled = feed * duration;
                    let phase = if stroke > 0.0 {
                        travelled % (2.0 * stroke)
                    } else {
                        0.0
                    };
                    let (end, heading_to) = if phase <= stroke {
                        (from + (to - from).signum() * phase, *to)
                    } else {
                        (to - (to - from).signum() * (phase - stroke), *from)
                    };
                    let lead_in = (from - home).abs();
                    let back = (home - end).abs();
                    let mut speed = AxisValues::ZERO;
                    speed[axis] = *feed;
                    pass(
                        (lead_in + back) / feed + duration,
                        speed,
                        spindle,
                        &mut time,
                        &mut events,
                    );
                    // The last motion decides the direction of travel.
                    let last_move = if back > 0.0 {
                        home - end
                    } else {
                        heading_to - end
                    };
                    if last_move != 0.0 {
                        state.direction[axis.index()] = if last_move > 0.0 {
                            Direction::Positive
                        } else {
                            Direction::Negative
                        };
                    }
                }
                Step::Spindle(speed) => spindle = *speed,
                Step::Measure(point) => events.push(Event::Measure(Visit {
                    point: *point,
                    time,
                    state,
                })),
            }
        }
        events
    }
}

/// A stretch of the commanded path: a straight line, or a warm-up stroke going back and forth.
enum Piece {
    /// From `start` to `end` at constant speed.
    Line {
        start: AxisValues,
        end: AxisValues,
        duration: Real,
    },
    /// `axis` from `from` toward `to` and back at `feed`, the other axes at `base`.
    Stroke {
        base: AxisValues,
        axis: Axis,
        from: Real,
        to: Real,
        feed: Real,
        duration: Real,
    },
}

impl Piece {
    fn duration(&self) -> Real {
        match self {
            Piece::Line { duration, .. } | Piece::Stroke { duration, .. } => *duration,
        }
    }

    /// The position `s` seconds into the piece.
    fn at(&self, s: Real) -> AxisValues {
        match *self {
            Piece::Line {
                start,
                end,
                duration,
            } => {
                let f = if duration > 0.0 { s / duration } else { 1.0 };
                let mut p = start;
                for i in 0..7 {
                    p.0[i] += (end.0[i] - start.0[i]) * f;
                }
                p
            }
            Piece::Stroke {
                base,
                axis,
                from,
                to,
                feed,
                ..
            } => {
                let stroke = (to - from).abs();
                let phase = if stroke > 0.0 {
                    (feed * s) % (2.0 * stroke)
                } else {
                    0.0
                };
                let mut p = base;
                p[axis] = if phase <= stroke {
                    from + (to - from).signum() * phase
                } else {
                    to - (to - from).signum() * (phase - stroke)
                };
                p
            }
        }
    }
}

impl Program {
    /// The commanded positions over time, for drawing the machine: `(time s, position)` every
    /// `period` seconds and at the start and end of every motion, along the same straight lines
    /// and warm-up strokes (at the same feeds, no acceleration) as [`Program::timeline`], so a
    /// measurement event at time `t` finds the path at its position.
    pub fn path(&self, period: Real) -> Vec<(Real, AxisValues)> {
        assert!(period > 0.0, "sampling needs a positive period");
        let mut pieces = Vec::new();
        let mut position = self.start;
        let line = |start: AxisValues, end: AxisValues, feed: Real| {
            let length = (0..7)
                .map(|i| (end.0[i] - start.0[i]).powi(2))
                .sum::<Real>()
                .sqrt();
            Piece::Line {
                start,
                end,
                duration: length / feed,
            }
        };
        for step in &self.steps {
            match step {
                Step::Move { to, feed } => {
                    let mut end = position;
                    for &(axis, value) in to {
                        end[axis] = value;
                    }
                    pieces.push(line(position, end, *feed));
                    position = end;
                }
                Step::Dwell(duration) => pieces.push(Piece::Line {
                    start: position,
                    end: position,
                    duration: *duration,
                }),
                Step::WarmUp {
                    axis,
                    from,
                    to,
                    feed,
                    duration,
                } => {
                    let home = position;
                    let mut start = position;
                    start[*axis] = *from;
                    pieces.push(line(position, start, *feed));
                    let stroke = Piece::Stroke {
                        base: start,
                        axis: *axis,
                        from: *from,
                        to: *to,
                        feed: *feed,
                        duration: *duration,
                    };
                    let end = stroke.at(*duration);
                    pieces.push(stroke);
                    pieces.push(line(end, home, *feed));
                }
                Step::Spindle(_) | Step::Measure(_) => {}
            }
        }
        let mut samples = vec![(0.0, self.start)];
        let mut time: Real = 0.0;
        for piece in pieces.iter().filter(|p| p.duration() > 0.0) {
            let end = time + piece.duration();
            let mut k = (time / period).floor() + 1.0;
            while k * period < end {
                samples.push((k * period, piece.at(k * period - time)));
                k += 1.0;
            }
            samples.push((end, piece.at(piece.duration())));
            time = end;
        }
        samples
    }
}

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

/// The measurement events of a timeline.
pub fn visits(timeline: &[Event]) -> Vec<Visit> {
    timeline
        .iter()
        .filter_map(|e| match e {
            Event::Measure(visit) => Some(*visit),
            Event::Interval(_) => None,
        })
        .collect()
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
