//! What the machine does over time: a programme of steps (moves at a feed, dwells, warm-up
//! cycles, spindle speed changes, measurement points) turned into a timeline of intervals
//! (for the thermal model: how fast each axis moved and how fast the spindle turned) and
//! measurement events (for the instruments: where the machine stood and how it got there).
//!
//! Simplified: the steps of a [`Program`] move axes at constant speed along straight lines,
//! starting and stopping instantly (no acceleration, no servo lag), which is what the thermal
//! model needs. Circular tests have their own interpolator ([`crate::kinds::ballbar::CircularInterpolation`]: ramps,
//! overshoot arcs) and controller model ([`servo`]: position loops, feed-forward, reversal
//! spikes, vibration), which turn commands into actual axis positions.

pub mod servo;

pub use servo::{AxisLoop, AxisServo, Servo};

use crate::machine::{Axis, AxisValues, Direction, MachineState};
use crate::math::Real;

/// Direction of approach to a target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Approach {
    /// Reached while travelling in the positive direction (↑).
    Up,
    /// Reached while travelling in the negative direction (↓).
    Down,
}

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
    /// How long the programme runs (s): the sum of its timeline's intervals.
    pub fn duration(&self) -> Real {
        self.timeline(Real::INFINITY)
            .iter()
            .map(|e| match e {
                Event::Interval(i) => i.duration,
                Event::Measure(_) => 0.0,
            })
            .sum()
    }

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
                // Measured at rest, the spindle turning at its commanded speed.
                Step::Measure(point) => events.push(Event::Measure(Visit {
                    point: *point,
                    time,
                    state: MachineState {
                        time,
                        velocity: AxisValues::ZERO.with(Axis::S, spindle),
                        ..state
                    },
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
