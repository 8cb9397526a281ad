//! The searched parameters of the joint fit, each on the joint residual sum of squares: an
//! axis's reversal lag (a windowed profile, [`LagProfile`]) and its uncertainty, the spike
//! decays, the cyclic periods and the lobe count (periodograms); and the significance a
//! searched amplitude must reach.

use super::linalg::{Projection, dot};
use super::model::{SPIKE_DECAYS, spike, take_up_arc};
use super::{CircleData, ModelFit, Shape, Term, arc_since_reversal};
use crate::math::{Real, golden_minimum};
use nalgebra::DMatrix;
use std::f64::consts::{PI, TAU};

/// Grid points of the reversal-lag search (every 5 ms over ±200 ms).
const LAG_GRID: usize = 81;
/// Grid points of the decay search (log-spaced) and golden-section iterations.
const DECAY_GRID: usize = 16;
const GOLDEN_ITERATIONS: usize = 20;

/// The least significance level: a linear amplitude counts as significant at this many
/// standard uncertainties.
const SIGNIFICANCE: Real = 2.0;
/// The false-alarm probability a searched amplitude's threshold allows over its search.
const FALSE_ALARM: Real = 0.05;

impl CircleData {
    /// The fit of every term of `terms` but `axis`'s reversal terms (over `rows`), and those
    /// reversal terms.
    pub(super) fn split_reversal(
        &self,
        axis: usize,
        terms: &[Term],
        shape: &Shape,
        rows: &[usize],
        y: &[Real],
    ) -> (Projection, Vec<Term>) {
        let (moving, fixed): (Vec<Term>, Vec<Term>) = terms
            .iter()
            .copied()
            .partition(|t| t.reversal_axis() == Some(axis));
        (
            Projection::new(self.columns_on(&fixed, shape, rows), y),
            moving,
        )
    }

    /// The joint residual sum of squares of `axis`'s reversal terms `moving` against `fixed`
    /// as a function of the axis's lag. A lag moves these columns only on the rows within
    /// the longest lag (and the spike's window) after a programmed reversal or the most
    /// negative lag before one: the sums over the other rows are taken once.
    pub(super) fn lag_profile<'a>(
        &'a self,
        axis: usize,
        moving: &'a [Term],
        fixed: &'a Projection,
        rows: &'a [usize],
        shape: &Shape,
    ) -> LagProfile<'a> {
        let unlagged = Shape {
            lag: [0.0; 2],
            ..*shape
        };
        let rate = self.test.feed / self.test.radius;
        let spike = if moving.iter().any(|t| t.searched()) {
            SPIKE_DECAYS * shape.decay[axis]
        } else {
            0.0
        };
        // With play the backlash column takes the gap up (and the spike starts) over the
        // take-up arc after the reversal: those rows move with the lag too.
        let after = rate * (self.ranges.lag.1.max(0.0) + spike)
            + take_up_arc(shape.play[axis], self.test.radius);
        let before = rate * (-self.ranges.lag.0).max(0.0);
        let (near, far): (Vec<usize>, Vec<usize>) = (0..rows.len()).partition(|&j| {
            let arc = arc_since_reversal(axis, &self.points[rows[j]], &self.test, &unlagged);
            arc <= after || arc >= PI - before
        });
        let far_rows: Vec<usize> = far.iter().map(|&j| rows[j]).collect();
        let columns = self.columns_on(moving, shape, &far_rows);
        let (k, m) = (fixed.columns.len(), columns.len());
        let fb = DMatrix::from_fn(k, m, |i, c| {
            far.iter()
                .zip(&columns[c])
                .map(|(&j, v)| fixed.columns[i][j] * v)
                .sum()
        });
        let bb = DMatrix::from_fn(m, m, |a, b| dot(&columns[a], &columns[b]));
        let br = (0..m)
            .map(|c| {
                far.iter()
                    .zip(&columns[c])
                    .map(|(&j, v)| fixed.residual[j] * v)
                    .sum()
            })
            .collect();
        LagProfile {
            data: self,
            axis,
            moving,
            fixed,
            rows,
            shape: *shape,
            near,
            far: (fb, bb, br),
        }
    }

    /// Searches `axis`'s reversal lag (s): a grid of [`LAG_GRID`] points over the range,
    /// golden section between the best point's neighbours, then the middle of the interval
    /// where the residual sum of squares stays at that minimum. A sampled trace cannot tell
    /// where between two samples an axis reversed (a step, or a spike's onset, reads the
    /// same): the middle is the unbiased choice.
    pub(super) fn search_lag(&self, profile: &LagProfile<'_>) -> Real {
        let (low, high) = self.ranges.lag;
        let grid: Vec<Real> = (0..LAG_GRID)
            .map(|k| low + (high - low) * k as Real / (LAG_GRID - 1) as Real)
            .collect();
        let values: Vec<Real> = grid.iter().map(|&g| profile.rss(g)).collect();
        let best = (0..LAG_GRID)
            .min_by(|&a, &b| values[a].total_cmp(&values[b]))
            .unwrap_or(0);
        let (a, b) = (
            grid[best.saturating_sub(1)],
            grid[(best + 1).min(LAG_GRID - 1)],
        );
        let (refined, value) = golden_minimum(|g| profile.rss(g), a, b, GOLDEN_ITERATIONS);
        let (lag, value) = if value < values[best] {
            (refined, value)
        } else {
            (grid[best], values[best])
        };
        let flat = value + 1e-9 * profile.fixed.rss;
        let (from, to) = interval(|g| profile.rss(g), lag, flat, low, high);
        (from + to) / 2.0
    }

    /// The standard uncertainty of `axis`'s reversal lag in `fit` (s): half the width of the
    /// profile-likelihood interval where the residual sum of squares stays within `variance`
    /// (σ̂²) of its minimum (Δχ² = 1), each side found by bisection. For a step sampled every
    /// Δt it is at least about Δt/2: the data cannot place the step better.
    pub(super) fn lag_uncertainty(&self, axis: usize, fit: &ModelFit, variance: Real) -> Real {
        let rows: Vec<usize> = (0..self.len()).collect();
        let (fixed, moving) =
            self.split_reversal(axis, &fit.terms, &fit.shape, &rows, &self.deviation);
        let profile = self.lag_profile(axis, &moving, &fixed, &rows, &fit.shape);
        let best = fit.shape.lag[axis];
        let target = profile.rss(best) + variance;
        let (low, high) = self.ranges.lag;
        let (from, to) = interval(|g| profile.rss(g), best, target, low, high);
        (to - from) / 2.0
    }

    /// Searches `term`'s shape parameter on the joint residual sum of squares with `fixed`
    /// (the other columns); `refine` only polishes the current value.
    pub(super) fn search(
        &self,
        term: Term,
        fixed: &Projection,
        rows: &[usize],
        shape: &mut Shape,
        refine: bool,
    ) {
        let rss = |trial: &Shape| -> Real {
            let columns: Vec<Vec<Real>> = (0..term.columns())
                .map(|k| self.column_on(term, k, trial, rows))
                .collect();
            let views: Vec<&[Real]> = columns.iter().map(Vec::as_slice).collect();
            fixed.rss_with(&views)
        };
        match term {
            Term::ReversalSpikeP | Term::ReversalSpikeQ => {
                let axis = usize::from(term == Term::ReversalSpikeQ);
                // The column is zero but within the longest decay's window after a crossed
                // reversal: only those rows are evaluated.
                let longest = Shape {
                    decay: [self.ranges.decay.1; 2],
                    ..*shape
                };
                let window: Vec<usize> = (0..rows.len())
                    .filter(|&j| spike(axis, &self.points[rows[j]], &self.test, &longest).is_some())
                    .collect();
                let window_rows: Vec<usize> = window.iter().map(|&j| rows[j]).collect();
                let at = |tau: Real| {
                    let mut trial = *shape;
                    trial.decay[axis] = tau;
                    let column = self.column_on(term, 0, &trial, &window_rows);
                    fixed.rss_with_sparse(&window, &column)
                };
                let (low, high) = (self.ranges.decay.0.ln(), self.ranges.decay.1.ln());
                let grid: Vec<Real> = (0..DECAY_GRID)
                    .map(|k| low + (high - low) * k as Real / (DECAY_GRID - 1) as Real)
                    .collect();
                let values: Vec<Real> = grid.iter().map(|g| at(g.exp())).collect();
                let best = (0..DECAY_GRID)
                    .min_by(|&a, &b| values[a].total_cmp(&values[b]))
                    .unwrap_or(0);
                let (a, b) = (
                    grid[best.saturating_sub(1)],
                    grid[(best + 1).min(DECAY_GRID - 1)],
                );
                let (refined, value) = golden_minimum(|g| at(g.exp()), a, b, GOLDEN_ITERATIONS);
                shape.decay[axis] = if value < values[best] {
                    refined.exp()
                } else {
                    grid[best].exp()
                };
            }
            Term::CyclicP | Term::CyclicQ => {
                let axis = usize::from(term == Term::CyclicQ);
                let (f_low, f_high, step, _) = self.frequency_grid();
                let peak = if refine {
                    1.0 / shape.period[axis]
                } else {
                    1.0 / self.cyclic_periodogram(term, rows, &fixed.residual).0
                };
                let at = |f: Real| {
                    let mut trial = *shape;
                    trial.period[axis] = 1.0 / f;
                    rss(&trial)
                };
                let (refined, value) = golden_minimum(
                    at,
                    (peak - step).max(f_low),
                    (peak + step).min(f_high),
                    GOLDEN_ITERATIONS,
                );
                shape.period[axis] = if value < at(peak) {
                    1.0 / refined
                } else {
                    1.0 / peak
                };
            }
            Term::Lobes => {
                // All counts on the first pass; two either side of the current one after.
                let (low, high) = if refine {
                    (
                        shape.lobes.saturating_sub(2).max(self.ranges.lobes.0),
                        (shape.lobes + 2).min(self.ranges.lobes.1),
                    )
                } else {
                    self.ranges.lobes
                };
                let mut best = (low, Real::INFINITY);
                self.each_lobe_count(rows, low, high, |k, sin, cos| {
                    let value = fixed.rss_with(&[sin, cos]);
                    if value < best.1 {
                        best = (k, value);
                    }
                });
                shape.lobes = best.0;
            }
            _ => {}
        }
    }

    /// How many standard uncertainties a searched amplitude must reach to be significant: the
    /// level √(2·ln(M/0.05)) that noise alone exceeds at any of the M shapes the search tests
    /// with probability at most 5 % (Bonferroni; for a cyclic term A/u is Rayleigh-distributed,
    /// P(A/u > x) = e^(−x²/2), and for a spike's one coefficient P(|z| > x) is below that),
    /// and at least 2. A cyclic term tests M periods; a spike M = 81 lags × 16 decays, its
    /// onset free to sit wherever the noise is largest (4.51 u): at 2 u, noise alone made a
    /// spike of an axis without backlash significant in most traces.
    pub fn significance(&self, term: Term) -> Real {
        let tested = match term {
            Term::CyclicP | Term::CyclicQ => self.frequency_grid().3,
            Term::ReversalSpikeP | Term::ReversalSpikeQ => LAG_GRID * DECAY_GRID,
            _ => return SIGNIFICANCE,
        };
        (2.0 * (tested as Real / FALSE_ALARM).ln())
            .sqrt()
            .max(SIGNIFICANCE)
    }

    /// The cyclic search's frequencies (1/m): lowest, highest, step (4 per 1/(2R), the
    /// resolution over the diameter) and how many.
    fn frequency_grid(&self) -> (Real, Real, Real, usize) {
        let (low, high) = self.ranges.period;
        let (f_low, f_high) = (1.0 / high, 1.0 / low);
        let step = 1.0 / (8.0 * self.test.radius);
        let count = ((f_high - f_low) / step * (1.0 + 1e-12)).floor().max(0.0) as usize + 1;
        (f_low, f_high, step, count)
    }

    /// The period (m) of `term` (cyclic p or q) whose two columns alone remove the largest
    /// fraction of `residual` (over `rows`), and that fraction: a periodogram over the
    /// frequency grid, phasors advanced by recurrence.
    pub fn cyclic_periodogram(
        &self,
        term: Term,
        rows: &[usize],
        residual: &[Real],
    ) -> (Real, Real) {
        let (f_low, _, step, count) = self.frequency_grid();
        let m = rows.len();
        let (mut zr, mut zi, mut wr, mut wi) =
            (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        let (mut rc, mut cc) = (vec![0.0; m], vec![0.0; m]);
        let total: Real = residual.iter().map(|r| r * r).sum();
        for (j, &i) in rows.iter().enumerate() {
            let (sin, cos) = self.points[i].sin_cos;
            let c = if term == Term::CyclicP { cos } else { sin };
            let x = TAU * self.test.radius * c;
            (zi[j], zr[j]) = (x * f_low).sin_cos();
            (wi[j], wr[j]) = (x * step).sin_cos();
            rc[j] = residual[j] * c;
            cc[j] = c * c;
        }
        let mut best = (f_low, 0.0);
        for k in 0..count {
            let (mut s1, mut s2, mut a11, mut a22, mut a12) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for j in 0..m {
                let (s, c) = (zi[j], zr[j]);
                s1 += rc[j] * s;
                s2 += rc[j] * c;
                a11 += cc[j] * s * s;
                a22 += cc[j] * c * c;
                a12 += cc[j] * s * c;
                let (nr, ni) = (c * wr[j] - s * wi[j], c * wi[j] + s * wr[j]);
                zr[j] = nr;
                zi[j] = ni;
            }
            let det = a11 * a22 - a12 * a12;
            if det > 0.0 && total > 0.0 {
                let reduction = (s1 * s1 * a22 - 2.0 * s1 * s2 * a12 + s2 * s2 * a11) / det;
                let fraction = (reduction / total).clamp(0.0, 1.0);
                if fraction > best.1 {
                    best = (f_low + step * k as Real, fraction);
                }
            }
        }
        (1.0 / best.0, best.1)
    }

    /// The number of lobes k (in the searched range) whose sin kθ, cos kθ alone remove the
    /// largest fraction of `residual` (over `rows`), and that fraction.
    pub fn lobes_periodogram(&self, rows: &[usize], residual: &[Real]) -> (u32, Real) {
        let (low, high) = self.ranges.lobes;
        let mut best = (low, 0.0);
        let total: Real = residual.iter().map(|r| r * r).sum();
        if total <= 0.0 {
            return best;
        }
        self.each_lobe_count(rows, low, high, |k, sin, cos| {
            let fraction =
                Projection::new(vec![sin.to_vec(), cos.to_vec()], residual).explained / total;
            if fraction > best.1 {
                best = (k, fraction);
            }
        });
        best
    }

    /// Calls `f(k, sin kθ, cos kθ)` over `rows` for every lobe count k from `low` to `high`,
    /// the phasors e^(ikθ) advanced by recurrence.
    fn each_lobe_count(
        &self,
        rows: &[usize],
        low: u32,
        high: u32,
        mut f: impl FnMut(u32, &[Real], &[Real]),
    ) {
        let step: Vec<(Real, Real)> = rows.iter().map(|&i| self.points[i].sin_cos).collect();
        let (mut sin, mut cos): (Vec<Real>, Vec<Real>) = rows
            .iter()
            .map(|&i| (Real::from(low) * self.points[i].angle).sin_cos())
            .unzip();
        for k in low..=high {
            f(k, &sin, &cos);
            for ((s, c), (ds, dc)) in sin.iter_mut().zip(cos.iter_mut()).zip(&step) {
                (*s, *c) = (*s * dc + *c * ds, *c * dc - *s * ds);
            }
        }
    }
}

/// The interval around `best` (inside low..high) where `f` stays at or below `target`:
/// each edge by bisection between `best` and the bound (the bound itself when `f` is below
/// `target` there).
fn interval(
    f: impl Fn(Real) -> Real,
    best: Real,
    target: Real,
    low: Real,
    high: Real,
) -> (Real, Real) {
    let edge = |bound: Real| {
        if f(bound) <= target {
            return bound;
        }
        let (mut inside, mut outside) = (best, bound);
        for _ in 0..40 {
            let middle = (inside + outside) / 2.0;
            if f(middle) <= target {
                inside = middle;
            } else {
                outside = middle;
            }
        }
        (inside + outside) / 2.0
    };
    (edge(low), edge(high))
}

/// The residual sum of squares as a function of one axis's reversal lag
/// ([`CircleData::lag_profile`]).
pub(super) struct LagProfile<'a> {
    data: &'a CircleData,
    axis: usize,
    moving: &'a [Term],
    fixed: &'a Projection,
    rows: &'a [usize],
    shape: Shape,
    /// Positions in `rows` near the reversals, where the lag moves the columns.
    near: Vec<usize>,
    /// Fᵀ·B, Bᵀ·B and Bᵀ·r over the other rows.
    far: (DMatrix<Real>, DMatrix<Real>, Vec<Real>),
}

impl LagProfile<'_> {
    /// The residual sum of squares at `lag` (s).
    fn rss(&self, lag: Real) -> Real {
        let mut trial = self.shape;
        trial.lag[self.axis] = lag;
        let near_rows: Vec<usize> = self.near.iter().map(|&j| self.rows[j]).collect();
        let columns = self.data.columns_on(self.moving, &trial, &near_rows);
        let (fb, bb, br) = &self.far;
        let fixed = self.fixed;
        let fb = fb
            + DMatrix::from_fn(fb.nrows(), fb.ncols(), |i, c| {
                self.near
                    .iter()
                    .zip(&columns[c])
                    .map(|(&j, v)| fixed.columns[i][j] * v)
                    .sum::<Real>()
            });
        let bb =
            bb + DMatrix::from_fn(bb.nrows(), bb.ncols(), |a, b| dot(&columns[a], &columns[b]));
        let br: Vec<Real> = br
            .iter()
            .zip(&columns)
            .map(|(far, column)| {
                far + self
                    .near
                    .iter()
                    .zip(column)
                    .map(|(&j, v)| fixed.residual[j] * v)
                    .sum::<Real>()
            })
            .collect();
        fixed.rss_from(&fb, &bb, &br)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::ballbar::iso230_4::{BasisPoint, CircularTest, diagnostic_column};
    use crate::kinds::ballbar::table::BallbarTable;
    use crate::machine::Plane;

    #[test]
    fn the_windowed_lag_profile_equals_a_full_refit() {
        // A circle with backlash and a spike of p at a ±25 ms lag, plus a wobble the model
        // lacks: the windowed residual sum of squares at every trial lag equals the one of
        // the full columns.
        let test = CircularTest {
            plane: Plane::XY,
            radius: 0.1,
            feed: 0.01,
        };
        // Lagging (25 ms after the programmed reversal) and leading (25 ms before it).
        for truth_lag in [0.025, -0.025] {
            let truth = Shape {
                lag: [truth_lag, 0.0],
                ..Shape::default()
            };
            let n = 4000;
            let mut readings = Vec::new();
            for (sense, sign) in [
                (crate::kinds::ballbar::table::Sense::Ccw, 1.0),
                (crate::kinds::ballbar::table::Sense::Cw, -1.0),
            ] {
                for k in 0..n {
                    let angle = (sign * TAU * (k as Real + 0.5) / n as Real).rem_euclid(TAU);
                    let at = BasisPoint::new(angle, sign, 0.0, [true; 2]);
                    let deviation = 2e-6
                        * diagnostic_column(Term::BacklashP, 0, &at, &test, &truth)
                        + 3e-6 * diagnostic_column(Term::ReversalSpikeP, 0, &at, &test, &truth)
                        + 1e-7 * (7.0 * angle).sin();
                    readings.push(crate::kinds::ballbar::table::BallbarReading {
                        sense,
                        angle,
                        deviation,
                        time: None,
                    });
                }
            }
            let data = CircleData::new(
                &BallbarTable {
                    readings,
                    ..Default::default()
                },
                &test,
            )
            .unwrap();
            let terms = [Term::Radius, Term::BacklashP, Term::ReversalSpikeP];
            let rows: Vec<usize> = (0..data.len()).collect();
            let shape = Shape::default();
            let (fixed, moving) = data.split_reversal(0, &terms, &shape, &rows, &data.deviation);
            let profile = data.lag_profile(0, &moving, &fixed, &rows, &shape);
            for lag in [-0.2, -0.0371, -0.004, 0.0, 0.004, 0.025, 0.0371, 0.2] {
                let trial = Shape {
                    lag: [lag, 0.0],
                    ..shape
                };
                let columns = data.columns_on(&moving, &trial, &rows);
                let views: Vec<&[Real]> = columns.iter().map(Vec::as_slice).collect();
                let full = fixed.rss_with(&views);
                assert!(
                    (profile.rss(lag) - full).abs() <= 1e-9 * full,
                    "{lag}: {} vs {full}",
                    profile.rss(lag)
                );
            }
            // And the search finds the lag the data were made with (to the 1/4000-turn sampling).
            let found = data.search_lag(&profile);
            assert!(
                (found - truth_lag).abs() < 0.1 * TAU / 4000.0 / 0.01,
                "{found}"
            );
        }
    }
}
