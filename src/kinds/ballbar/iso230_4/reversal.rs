//! The reversal terms of an axis (backlash, lateral play, spike) at a shape, computed from
//! each reading's arc to the nearest programmed reversal ([`Reversal`]).
//!
//! With s a reading's arc from the nearest programmed reversal (negative before it) and
//! φ = v·δ/R the lag as an arc, the reading is s − φ from the actual reversal. A lag changes
//! the backlash and lateral play columns only on the readings between the programmed and the
//! actual reversal, where the axis's direction of travel flips (the column's sign flips), and
//! over the take-up arc after the actual reversal (play); a spike lives on the readings after
//! it, over [`SPIKE_DECAYS`] decays. A column at a shape is therefore its unlagged static
//! column plus a change on the readings near the reversals.

use super::blocks::Blocks;
use super::columns::{Column, Dense, Sparse};
use super::model::{SPIKE_DECAYS, signum, take_up_arc};
use super::statics::static_index;
use super::{BasisPoint, CircleData, CircularTest, Shape, Term};
use crate::math::Real;
use std::f64::consts::PI;
use std::rc::Rc;

/// Readings this close to an edge of a zone (rad) are evaluated with it.
pub(super) const EDGE: Real = 1e-9;

/// An axis's reversal at a shape.
#[derive(Clone, Copy, Debug)]
pub(super) struct Reversal {
    axis: usize,
    radius: Real,
    feed: Real,
    /// The lag as an arc, φ = v·δ/R.
    shift: Real,
    /// cos φ, sin φ.
    rotation: (Real, Real),
    /// The play (m) and its take-up arc.
    gap: Real,
    take_up: Real,
    /// The spike's decay (s) and the arc of its window after the take-up.
    decay: Real,
    window: Real,
}

/// What a reading needs for the reversal columns of an axis.
pub(super) struct Reading<'a> {
    pub(super) at: &'a BasisPoint,
    /// Arc from the nearest programmed reversal.
    pub(super) arc: Real,
}

impl Reversal {
    /// The reversal of `axis` at `shape` in `test`.
    pub(super) fn new(axis: usize, shape: &Shape, test: &CircularTest) -> Reversal {
        let shift = test.feed * shape.lag[axis] / test.radius;
        let gap = shape.play[axis];
        Reversal {
            axis,
            radius: test.radius,
            feed: test.feed,
            shift,
            rotation: (shift.cos(), shift.sin()),
            gap,
            take_up: take_up_arc(gap, test.radius),
            decay: shape.decay[axis],
            window: SPIKE_DECAYS * shape.decay[axis] * test.feed / test.radius,
        }
    }

    /// The same reversal at another lag.
    pub(super) fn at_lag(&self, lag: Real) -> Reversal {
        let shift = self.feed * lag / self.radius;
        Reversal {
            shift,
            rotation: (shift.cos(), shift.sin()),
            ..*self
        }
    }

    /// The arcs (from the nearest programmed reversal) of the readings whose backlash or
    /// lateral play column differs from the unlagged one without play, or whose spike is not
    /// zero: between the programmed and the actual reversal, then over the take-up arc and
    /// the spike's window.
    pub(super) fn zone(&self, spike: bool) -> (Real, Real) {
        let window = if spike { self.window } else { 0.0 };
        (
            self.shift.min(0.0) - EDGE,
            self.shift.max(0.0) + 2.0 * self.take_up + window + EDGE,
        )
    }

    /// Sign of the axis's direction of travel at the lagged angle relative to the sign
    /// function the columns use (sgn sin θ_p for p, sgn cos θ_q for q).
    pub(super) fn travel(&self, at: &BasisPoint) -> Real {
        let (sin, cos) = at.sin_cos;
        let (c, s) = self.rotation;
        let s = at.sense * s;
        // sin(θ − σφ) and cos(θ − σφ).
        signum(if self.axis == 0 {
            sin * c - cos * s
        } else {
            cos * c + sin * s
        })
    }

    /// The arc since the actual reversal, in [0, π), and whether that reversal is the next
    /// programmed one (a negative lag).
    fn since(&self, reading: &Reading<'_>) -> (Real, bool) {
        let a = reading.arc - self.shift;
        if a < 0.0 {
            (a + PI, false)
        } else {
            (a, self.shift < 0.0 && reading.arc < 0.0)
        }
    }

    /// The backlash column's fraction of its half-step (see [`super::take_up`]).
    fn take_up_fraction(&self, since: Real) -> Real {
        if self.gap <= 0.0 {
            return 1.0;
        }
        let back = 2.0 * self.radius * (since / 2.0).sin().powi(2);
        2.0 * (back / self.gap).min(1.0) - 1.0
    }

    /// Backlash, lateral play and spike columns at a reading.
    pub(super) fn values(&self, reading: &Reading<'_>) -> [Real; 3] {
        let (since, next) = self.since(reading);
        let fraction = self.take_up_fraction(since);
        self.columns_at(reading.at, since, next, fraction)
    }

    /// The three columns at `at`, `since` after the actual reversal (`next`: the next
    /// programmed one), the backlash's take-up `fraction`.
    fn columns_at(&self, at: &BasisPoint, since: Real, next: bool, fraction: Real) -> [Real; 3] {
        let (sin, cos) = at.sin_cos;
        let travel = self.travel(at);
        let (backlash, lateral) = if self.axis == 0 {
            (
                at.sense * travel * cos / 2.0 * fraction,
                at.sense * travel * sin / 2.0,
            )
        } else {
            (
                -at.sense * travel * sin / 2.0 * fraction,
                -at.sense * travel * cos / 2.0,
            )
        };
        let spike = self
            .spike_parts(at, since, next)
            .filter(|(_, dt)| *dt < SPIKE_DECAYS * self.decay)
            .map_or(0.0, |(weight, dt)| weight * (-dt / self.decay).exp());
        [backlash, lateral, spike]
    }

    /// [`Reversal::values`] with the take-up arc's sine from `half` (sin and cos of half the
    /// reading's arc) and `shift` (of half the lag's arc): sin((s − φ)/2) by the difference
    /// formula, without a sine per reading.
    pub(super) fn values_near(
        &self,
        reading: &Reading<'_>,
        half: (Real, Real),
        shift: (Real, Real),
    ) -> [Real; 3] {
        let (since, next) = self.since(reading);
        let fraction = if self.gap <= 0.0 || since > PI / 2.0 {
            self.take_up_fraction(since)
        } else {
            let sine = half.0 * shift.1 - half.1 * shift.0;
            let back = 2.0 * self.radius * sine * sine;
            2.0 * (back / self.gap).min(1.0) - 1.0
        };
        self.columns_at(reading.at, since, next, fraction)
    }

    /// A spike's weight (|cos θ| for p, |sin θ| for q) and time since its onset (s) at a
    /// reading `since` after the actual reversal, `next` whether that is the next
    /// programmed one: when the trace crossed it and the take-up arc is behind.
    fn spike_parts(&self, at: &BasisPoint, since: Real, next: bool) -> Option<(Real, Real)> {
        let crossed = if next {
            at.crossed_next[self.axis]
        } else {
            at.crossed[self.axis]
        };
        (crossed && since >= self.take_up).then(|| {
            let (sin, cos) = at.sin_cos;
            let weight = if self.axis == 0 { cos.abs() } else { sin.abs() };
            (weight, self.radius * (since - self.take_up) / self.feed)
        })
    }

    /// Which of [`Reversal::values`] a term is.
    pub(super) fn slot(term: Term) -> usize {
        match term {
            Term::BacklashP | Term::BacklashQ => 0,
            Term::LateralPlayP | Term::LateralPlayQ => 1,
            _ => 2,
        }
    }

    /// The column of `term` (a reversal term of this axis) for the readings of the
    /// `included` blocks of `blocks` (made from `data`): the static unlagged column plus its
    /// change near the reversals, or a spike's values there.
    pub(super) fn column(
        &self,
        data: &CircleData,
        blocks: &Blocks,
        included: &[bool],
        term: Term,
    ) -> Column {
        let slot = Reversal::slot(term);
        let static_index = static_index(term, &Shape::default());
        let rows = &blocks.axes[self.axis];
        let (from, to) = self.zone(slot == 2);
        let mut entries = Vec::new();
        for &i in rows.within(from, to) {
            let reading = Reading {
                at: &data.points[i as usize],
                arc: rows.arc[i as usize],
            };
            let value = self.values(&reading)[slot];
            let change = match static_index {
                Some(j) => value - blocks.row(i as usize)[j],
                None => value,
            };
            if change != 0.0 {
                entries.push((i, change));
            }
        }
        let sparse = Rc::new(Sparse::new(blocks, included, entries));
        Column {
            dense: static_index.map_or(Dense::Zero, Dense::Static),
            sparse,
        }
    }

    /// The readings of the `included` blocks of `blocks` (made from `data`) within the
    /// spike's window at its longest decay `longest` (s), with their spike weights and times
    /// since the onset, in increasing time.
    pub(super) fn spike_window(
        &self,
        data: &CircleData,
        blocks: &Blocks,
        included: &[bool],
        longest: Real,
    ) -> Vec<(usize, Real, Real)> {
        let widest = Reversal {
            decay: longest,
            window: SPIKE_DECAYS * longest * self.feed / self.radius,
            ..*self
        };
        let (from, to) = widest.zone(true);
        let rows = &blocks.axes[self.axis];
        let mut window: Vec<(usize, Real, Real)> = rows
            .within(from, to)
            .iter()
            .map(|&i| i as usize)
            .filter(|&i| blocks.fitted(included, i))
            .filter_map(|i| {
                let reading = Reading {
                    at: &data.points[i],
                    arc: rows.arc[i],
                };
                let (since, next) = self.since(&reading);
                self.spike_parts(reading.at, since, next)
                    .filter(|(weight, dt)| *weight != 0.0 && *dt < SPIKE_DECAYS * longest)
                    .map(|(weight, dt)| (i, weight, dt))
            })
            .collect();
        window.sort_by(|a, b| a.2.total_cmp(&b.2));
        window
    }

    /// The lag as an arc, φ = v·δ/R.
    pub(super) fn shift(&self) -> Real {
        self.shift
    }

    /// The take-up arc of the play (0 without).
    pub(super) fn take_up(&self) -> Real {
        self.take_up
    }

    /// The arc of one spike decay, v·τ/R.
    pub(super) fn decay_arc(&self) -> Real {
        self.window / SPIKE_DECAYS
    }
}
