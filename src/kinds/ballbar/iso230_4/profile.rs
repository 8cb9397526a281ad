//! The residual sum of squares of a fit as a function of one axis's reversal lag
//! ([`LagProfile`]), for the lag search's few hundred trials.
//!
//! The axis's reversal terms (backlash, lateral play, spike) move against the fit of all the
//! other columns. With s a reading's arc from the nearest programmed reversal and φ = v·δ/R
//! the trial lag as an arc (see `reversal.rs`), a trial changes their cross products from the
//! unlagged static columns' in three ways, each taken from sums over the readings near the
//! reversals in increasing s:
//!
//! - **flips**: the backlash and lateral play columns change sign on the readings between the
//!   programmed and the actual reversal (s in [0, φ) for a positive lag, [φ, 0) for a negative
//!   one): prefix sums of −2 × their unlagged values times the fixed columns and the deviation;
//!   their own products do not change;
//! - **the spike** lives on the readings with s − φ in [g, g + 10·a) after the take-up arc g,
//!   a = v·τ/R the arc of one decay, where it is w·e^(−(s − φ − g)/a) = e^((φ − s₀)/a) ×
//!   w·e^(−(s − g − s₀)/a): the same column for every trial up to a factor, so suffix sums of
//!   its products over the readings from each s serve every trial (the readings beyond the
//!   window hold less than e^(−10) of it, so the difference of two suffix sums loses no
//!   precision);
//! - **the take-up arc** g (with play) after the actual reversal, where the backlash column is
//!   its unlagged value times ±(κ·sin²((s − φ)/2) − 1), κ = 4R/gap: with
//!   sin((s − φ)/2) = sin(s/2)·cos(φ/2) − cos(s/2)·sin(φ/2) that is a combination of
//!   sin²(s/2), sin(s/2)·cos(s/2) and cos²(s/2) with the trial's weights, so prefix sums of
//!   those (and of their products, for the column's own products) serve every trial.
//!
//! The readings at the programmed reversal (where the arc and the sign of travel the columns
//! take may disagree to a hair, and the unlagged columns may be 0 where the lagged ones are
//! not) are evaluated one by one.

use super::columns::{Column, Dense};
use super::model::SPIKE_DECAYS;
use super::normal::{Fitter, NormalFit};
use super::reversal::{EDGE, Reading, Reversal};
use super::statics::static_index;
use super::{Shape, Term};
use crate::math::Real;
use nalgebra::DMatrix;

/// The residual sum of squares as a function of one axis's reversal lag.
pub(super) struct LagProfile<'a> {
    fitter: &'a Fitter<'a>,
    reversal: Reversal,
    /// The moving columns' slots (backlash 0, lateral play 1, spike 2), in column order.
    slots: Vec<usize>,
    /// The fit of the fixed columns.
    pub(super) fixed: NormalFit,
    /// The number of fixed columns.
    k: usize,
    /// Fᵀ·B, Bᵀ·B and Bᵀ·y of the unlagged moving columns without play (spikes zero).
    base: (DMatrix<Real>, DMatrix<Real>, Vec<Real>),
    /// The fitted readings near the reversals, in increasing arc: their readings, arcs,
    /// fixed columns' values then deviation (`k + 1` each), and moving columns' unlagged
    /// values (0 for a spike).
    rows: Vec<usize>,
    arcs: Vec<Real>,
    values: Vec<Real>,
    bases: Vec<Real>,
    /// Where the non-negative arcs start.
    zero: usize,
    /// Readings (positions in `rows`) at the programmed reversal, and whether each is one.
    degenerate: Vec<usize>,
    singular: Vec<bool>,
    /// Prefix sums of the flips (`(k + 1)·m` each): from the zero arc upward, and downward.
    after: Vec<Real>,
    before: Vec<Real>,
    /// The spike's suffix sums, when it moves.
    spike: Option<SpikeSums>,
    /// The take-up arc's prefix sums, with play.
    take_up: Option<TakeUpSums>,
    /// sin and cos of half of each reading's arc, for the take-up arc.
    halves: Vec<(Real, Real)>,
    scratch: std::cell::RefCell<Scratch>,
}

/// Prefix sums over the readings the take-up arc can cover (see the module documentation),
/// with h₁ = sin(s/2), h₂ = cos(s/2), b the backlash column's unlagged value and l the lateral
/// play's (0 when not moving), v the fixed columns' values and the deviation: per position,
/// the sums over the readings before it of b·(h₁², h₁h₂, h₂², 1)·v, l·v (`k + 1` each), then
/// b²·(h₁⁴, h₁³h₂, h₁²h₂², h₁h₂³, h₂⁴, h₁², h₁h₂, h₂²) and b·l·(h₁², h₁h₂, h₂², 1).
struct TakeUpSums {
    /// The first position covered.
    first: usize,
    sums: Vec<Real>,
    width: usize,
    /// The backlash's and the lateral play's places among the moving columns.
    backlash: Option<usize>,
    lateral: Option<usize>,
    /// κ = 4R/gap.
    kappa: Real,
}

/// Suffix sums of the spike's column up to a factor (see the module documentation).
struct SpikeSums {
    /// The spike's position among the moving columns.
    column: usize,
    /// s₀: the arc the factor is taken from.
    reference: Real,
    /// Per position, the sums over the readings from it on: w·e^(−(s − g − s₀)/a) times the
    /// fixed columns and the deviation (`k + 1`), its square, and its products with the
    /// moving columns' unlagged values (`m`).
    sums: Vec<Real>,
    width: usize,
    /// Per position, w·e^(−(s − g − s₀)/a) (0 where there is no spike).
    g: Vec<Real>,
}

impl<'a> LagProfile<'a> {
    /// The profile of `axis`'s reversal terms `moving` (in `terms`' order) against the
    /// other columns `fixed_columns`, at `shape` (its play and decay kept).
    pub(super) fn new(
        fitter: &'a Fitter<'a>,
        axis: usize,
        moving: &[Term],
        fixed_columns: &[Column],
        shape: &Shape,
    ) -> LagProfile<'a> {
        let data = fitter.data;
        let fixed = fitter.project(fixed_columns);
        let slots: Vec<usize> = moving.iter().map(|&t| Reversal::slot(t)).collect();
        let reversal = Reversal::new(axis, shape, &data.test);
        let statics: Vec<Column> = moving
            .iter()
            .map(|&t| {
                Column::dense(static_index(t, &Shape::default()).map_or(Dense::Zero, Dense::Static))
            })
            .collect();
        let (k, m) = (fixed_columns.len(), moving.len());
        let fb = DMatrix::from_fn(k, m, |i, j| fitter.cross(&fixed_columns[i], &statics[j]));
        let bb = DMatrix::from_fn(m, m, |i, j| fitter.cross(&statics[i], &statics[j]));
        let by = statics.iter().map(|c| fitter.cross_y(c)).collect();
        // Every reading a lag in the searched range can move, with the take-up arc and the
        // spike's window after it.
        let (low, high) = data.ranges.lag;
        let spike = slots.contains(&2);
        let lowest = reversal.at_lag(low).zone(spike);
        let highest = reversal.at_lag(high).zone(spike);
        let axis_rows = &fitter.blocks.axes[axis];
        let rows: Vec<usize> = axis_rows
            .within(lowest.0.min(highest.0), lowest.1.max(highest.1))
            .iter()
            .map(|&i| i as usize)
            .filter(|&i| fitter.fitted(i))
            .collect();
        let arcs: Vec<Real> = rows.iter().map(|&i| axis_rows.arc[i]).collect();
        let values = fitter.values_at(fixed_columns, &rows);
        let mut bases = Vec::with_capacity(rows.len() * m);
        let unlagged = Reversal::new(axis, &Shape::default(), &data.test);
        let mut degenerate = Vec::new();
        for (position, &i) in rows.iter().enumerate() {
            let table = fitter.blocks.row(i);
            bases.extend(statics.iter().map(|c| match c.dense {
                Dense::Static(j) => table[j],
                _ => 0.0,
            }));
            // At the programmed reversal (to a hair, where the arc and the sign of travel
            // the columns take may disagree) the columns are evaluated one by one.
            if arcs[position].abs() <= EDGE || unlagged.travel(&data.points[i]) == 0.0 {
                degenerate.push(position);
            }
        }
        let zero = arcs.partition_point(|&a| a < 0.0);
        let mut singular = vec![false; rows.len()];
        for &p in &degenerate {
            singular[p] = true;
        }
        let stride = (k + 1) * m;
        let flips = |positions: &mut dyn Iterator<Item = usize>| -> Vec<Real> {
            let mut sums = vec![0.0; stride];
            let mut last = vec![0.0; stride];
            for p in positions {
                if singular[p] {
                    sums.extend_from_slice(&last);
                    continue;
                }
                for (j, &b) in bases[p * m..(p + 1) * m].iter().enumerate() {
                    for (i, v) in values[p * (k + 1)..(p + 1) * (k + 1)].iter().enumerate() {
                        last[j * (k + 1) + i] -= 2.0 * b * v;
                    }
                }
                sums.extend_from_slice(&last);
            }
            sums
        };
        let after = flips(&mut (zero..rows.len()));
        let before = flips(&mut (0..zero).rev());
        let spike = slots.iter().position(|&s| s == 2).map(|column| {
            let reference = reversal.at_lag(low).shift();
            let (take_up, decay) = (reversal.take_up(), reversal.decay_arc());
            let width = k + 2 + m;
            let mut sums = vec![0.0; (rows.len() + 1) * width];
            let mut gs = vec![0.0; rows.len()];
            for p in (0..rows.len()).rev() {
                let (head, tail) = sums.split_at_mut((p + 1) * width);
                let (out, next) = (&mut head[p * width..], &tail[..width]);
                out.copy_from_slice(next);
                if singular[p] {
                    continue;
                }
                let at = &data.points[rows[p]];
                let crossed = if arcs[p] < 0.0 {
                    at.crossed_next[axis]
                } else {
                    at.crossed[axis]
                };
                if !crossed {
                    continue;
                }
                let (sin, cos) = at.sin_cos;
                let weight = if axis == 0 { cos.abs() } else { sin.abs() };
                let g = weight * (-(arcs[p] - take_up - reference) / decay).exp();
                gs[p] = g;
                for (o, v) in out.iter_mut().zip(&values[p * (k + 1)..(p + 1) * (k + 1)]) {
                    *o += g * v;
                }
                out[k + 1] += g * g;
                for (o, b) in out[k + 2..].iter_mut().zip(&bases[p * m..(p + 1) * m]) {
                    *o += g * b;
                }
            }
            SpikeSums {
                column,
                reference,
                sums,
                width,
                g: gs,
            }
        });
        let halves: Vec<(Real, Real)> = arcs.iter().map(|a| (a / 2.0).sin_cos()).collect();
        let take_up = (reversal.take_up() > 0.0).then(|| {
            let backlash = slots.iter().position(|&s| s == 0);
            let lateral = slots.iter().position(|&s| s == 1);
            // The readings some trial's take-up arc covers.
            let first = arcs.partition_point(|&a| a < reversal.at_lag(low).shift());
            let last =
                arcs.partition_point(|&a| a < reversal.at_lag(high).shift() + reversal.take_up());
            let w = k + 1;
            let width = 5 * w + 12;
            let mut sums = vec![0.0; width];
            let mut running = vec![0.0; width];
            for p in first..last.max(first) {
                if !singular[p] {
                    let b = backlash.map_or(0.0, |j| bases[p * m + j]);
                    let l = lateral.map_or(0.0, |j| bases[p * m + j]);
                    let (h1, h2) = halves[p];
                    let weights = [b * h1 * h1, b * h1 * h2, b * h2 * h2, b, l];
                    let v = &values[p * w..(p + 1) * w];
                    for (block, weight) in weights.iter().enumerate() {
                        for (o, x) in running[block * w..(block + 1) * w].iter_mut().zip(v) {
                            *o += weight * x;
                        }
                    }
                    let (s1, s2) = (h1 * h1, h2 * h2);
                    let own = [
                        s1 * s1,
                        s1 * h1 * h2,
                        s1 * s2,
                        h1 * h2 * s2,
                        s2 * s2,
                        s1,
                        h1 * h2,
                        s2,
                    ];
                    for (o, x) in running[5 * w..5 * w + 8].iter_mut().zip(own) {
                        *o += b * b * x;
                    }
                    for (o, x) in running[5 * w + 8..].iter_mut().zip([s1, h1 * h2, s2, 1.0]) {
                        *o += b * l * x;
                    }
                }
                sums.extend_from_slice(&running);
            }
            TakeUpSums {
                first,
                sums,
                width,
                backlash,
                lateral,
                kappa: 4.0 * data.test.radius / shape.play[axis],
            }
        });
        let scratch = std::cell::RefCell::new(Scratch {
            fb: fb.clone(),
            bb: bb.clone(),
            by: vec![0.0; m],
            actual: vec![0.0; m],
            held: vec![0.0; m],
        });
        LagProfile {
            fitter,
            reversal,
            slots,
            fixed,
            k,
            take_up,
            halves,
            scratch,
            base: (fb, bb, by),
            rows,
            arcs,
            values,
            bases,
            zero,
            degenerate,
            singular,
            after,
            before,
            spike,
        }
    }

    /// The residual sum of squares at `lag` (s).
    pub(super) fn rss(&self, lag: Real) -> Real {
        let mut scratch = self.scratch.borrow_mut();
        let Scratch {
            fb,
            bb,
            by,
            actual,
            held,
        } = &mut *scratch;
        let reversal = self.reversal.at_lag(lag);
        let (phi, take_up) = (reversal.shift(), reversal.take_up());
        let (k, m) = (self.k, self.slots.len());
        fb.copy_from(&self.base.0);
        bb.copy_from(&self.base.1);
        by.copy_from_slice(&self.base.2);
        let stride = (k + 1) * m;
        // Flips: a positive lag flips the arcs in [0, φ); a negative one those in [φ, 0),
        // less the take-up arc after φ (evaluated one by one below).
        let flipped = if phi >= 0.0 {
            (
                self.zero,
                self.zero + self.arcs[self.zero..].partition_point(|&a| a < phi),
            )
        } else {
            let start = self.arcs[..self.zero].partition_point(|&a| a < phi + take_up);
            (start.min(self.zero), self.zero)
        };
        let count = flipped.1 - flipped.0;
        let sums = if phi >= 0.0 {
            &self.after[count * stride..(count + 1) * stride]
        } else {
            &self.before[count * stride..(count + 1) * stride]
        };
        for j in 0..m {
            for i in 0..k {
                fb[(i, j)] += sums[j * (k + 1) + i];
            }
            by[j] += sums[j * (k + 1) + k];
        }
        // The spike over its window, from the suffix sums.
        let mut window = (0, 0, 0.0);
        if let Some(spike) = &self.spike {
            let decay = reversal.decay_arc();
            let from = phi + take_up;
            let lo = self.arcs.partition_point(|&a| a < from);
            let hi = lo + self.arcs[lo..].partition_point(|&a| a < from + SPIKE_DECAYS * decay);
            let factor = ((phi - spike.reference) / decay).exp();
            window = (lo, hi, factor);
            let (w, s) = (spike.width, &spike.sums);
            let range = |j: usize, a: usize, b: usize| s[a * w + j] - s[b * w + j];
            let c = spike.column;
            for i in 0..k {
                fb[(i, c)] += factor * range(i, lo, hi);
            }
            by[c] += factor * range(k, lo, hi);
            bb[(c, c)] += factor * factor * range(k + 1, lo, hi);
            // Its products with the other moving columns, flipped on the window's negative
            // arcs (a negative lag).
            let split = self.zero.clamp(lo, hi);
            for j in 0..m {
                if j == c {
                    continue;
                }
                let all = range(k + 2 + j, lo, hi);
                let negative = range(k + 2 + j, lo, split);
                let product = factor * (all - 2.0 * negative);
                bb[(j, c)] += product;
                bb[(c, j)] += product;
            }
        }
        // The take-up arc [φ, φ + g): from its prefix sums.
        if let Some(sums) = &self.take_up {
            self.add_take_up(sums, phi, take_up, fb, bb, by);
        }
        // The readings at the programmed reversal, one by one.
        let half = (phi / 2.0).sin_cos();
        for &p in &self.degenerate {
            let reading = Reading {
                at: &self.fitter.data.points[self.rows[p]],
                arc: self.arcs[p],
            };
            let all = reversal.values_near(&reading, self.halves[p], half);
            // What the sums hold: the unlagged values, flipped in the flipped range; nothing
            // of the readings at the programmed reversal beyond their unlagged values.
            let sign = if !self.singular[p] && (flipped.0..flipped.1).contains(&p) {
                -1.0
            } else {
                1.0
            };
            for (j, &slot) in self.slots.iter().enumerate() {
                actual[j] = all[slot];
                held[j] = if slot == 2 {
                    match &self.spike {
                        Some(spike) if (window.0..window.1).contains(&p) => window.2 * spike.g[p],
                        _ => 0.0,
                    }
                } else {
                    sign * self.bases[p * m + j]
                };
            }
            if actual == held {
                continue;
            }
            let values = &self.values[p * (k + 1)..(p + 1) * (k + 1)];
            for j in 0..m {
                let change = actual[j] - held[j];
                if change != 0.0 {
                    for i in 0..k {
                        fb[(i, j)] += change * values[i];
                    }
                    by[j] += change * values[k];
                }
                for l in 0..m {
                    bb[(j, l)] += actual[j] * actual[l] - held[j] * held[l];
                }
            }
        }
        self.fixed.rss_from(fb, bb, by)
    }
}

impl LagProfile<'_> {
    /// Adds the take-up arc's change at a trial shift `phi` (take-up arc `take_up`) to the
    /// moving columns' sums: the backlash ±(κ·q − 1) times its unlagged value,
    /// q = sin²((s − φ)/2), and the lateral play's flip, on the readings with arcs in
    /// [φ, φ + g) (flipped where the arc is negative).
    fn add_take_up(
        &self,
        sums: &TakeUpSums,
        phi: Real,
        take_up: Real,
        fb: &mut DMatrix<Real>,
        bb: &mut DMatrix<Real>,
        by: &mut [Real],
    ) {
        let (k, w) = (self.k, self.k + 1);
        let last = sums.first + sums.sums.len() / sums.width - 1;
        let start = self
            .arcs
            .partition_point(|&a| a < phi)
            .clamp(sums.first, last);
        let end = self
            .arcs
            .partition_point(|&a| a < phi + take_up)
            .clamp(start, last);
        let (s, c) = (phi / 2.0).sin_cos();
        let (cc, cs, ss) = (c * c, c * s, s * s);
        let kappa = sums.kappa;
        let parts = [
            (start, end.min(self.zero).max(start), -1.0),
            (start.max(self.zero).min(end), end, 1.0),
        ];
        for (from, to, sign) in parts {
            if from >= to {
                continue;
            }
            let range = |j: usize| {
                sums.sums[(to - sums.first) * sums.width + j]
                    - sums.sums[(from - sums.first) * sums.width + j]
            };
            if let Some(b) = sums.backlash {
                for i in 0..w {
                    let q = cc * range(i) - 2.0 * cs * range(w + i) + ss * range(2 * w + i);
                    let change = sign * kappa * q - (sign + 1.0) * range(3 * w + i);
                    if i < k {
                        fb[(i, b)] += change;
                    } else {
                        by[b] += change;
                    }
                }
                let e = |n: usize| range(5 * w + n);
                let q4 = cc * cc * e(0) - 4.0 * cc * cs * e(1) + 6.0 * cc * ss * e(2)
                    - 4.0 * cs * ss * e(3)
                    + ss * ss * e(4);
                let q2 = cc * e(5) - 2.0 * cs * e(6) + ss * e(7);
                bb[(b, b)] += kappa * kappa * q4 - 2.0 * kappa * q2;
                if let Some(l) = sums.lateral {
                    let g = |n: usize| range(5 * w + 8 + n);
                    let cross = kappa * (cc * g(0) - 2.0 * cs * g(1) + ss * g(2)) - 2.0 * g(3);
                    bb[(b, l)] += cross;
                    bb[(l, b)] += cross;
                }
            }
            if let (Some(l), true) = (sums.lateral, sign < 0.0) {
                for i in 0..w {
                    let change = -2.0 * range(4 * w + i);
                    if i < k {
                        fb[(i, l)] += change;
                    } else {
                        by[l] += change;
                    }
                }
            }
        }
    }
}

/// Work space of [`LagProfile::rss`].
struct Scratch {
    fb: DMatrix<Real>,
    bb: DMatrix<Real>,
    by: Vec<Real>,
    actual: Vec<Real>,
    held: Vec<Real>,
}
