//! The searched parameters of the joint fit, each on the joint residual sum of squares: an
//! axis's reversal lag (a profile over the lag, `reversal.rs`) and its uncertainty, the spike
//! decays, the cyclic periods and the lobe count (periodograms); and the significance a
//! searched amplitude must reach. Every trial is scored against the fit of the other columns
//! from cross products alone: the readings a spike lives on, the cyclic columns' moments
//! about a grid frequency, the lobe columns' sums (`spectral.rs`).

use super::columns::{Column, Dense};
use super::lag::interval;
use super::linalg::Projection;
use super::model::SPIKE_DECAYS;
use super::moments::{ORDER, offset_series};
use super::normal::{Fitter, NormalFit};
use super::profile::LagProfile;
use super::reversal::Reversal;
use super::statics::Y;
use super::{CircleData, Shape, Term};
use crate::math::{Real, brent_minimum, golden_minimum};
use nalgebra::DMatrix;
use rustfft::num_complex::Complex;
use std::f64::consts::TAU;

/// Grid points of the reversal-lag search (every 5 ms over ±200 ms).
const LAG_GRID: usize = 81;
/// Grid points of the decay search (log-spaced).
const DECAY_GRID: usize = 16;
/// Golden-section iterations of the lag search between the best grid point's neighbours
/// (0.618²⁰ of 10 ms: 0.7 µs). The lag profile is smooth only between two readings (a
/// reading crossing the reversal is a kink, a step with backlash), so parabolic steps would
/// gain little there, and golden section keeps to its bracket's shrinking by a fixed ratio.
const GOLDEN_ITERATIONS: usize = 20;
/// The decay and period searches refine their grid's best point by Brent's method between
/// the point's neighbours (their residual sums of squares are smooth in ln τ and in the
/// frequency), to this fraction of the bracket (two grid steps): of 0.43 in ln τ for a decay
/// (0.001 % of τ), of two frequency steps for a period; each far below the parameter's
/// uncertainty.
const REFINE_TOLERANCE: Real = 2.5e-5;
/// At most this many evaluations per refinement (golden section alone needs about 22).
const REFINE_EVALUATIONS: usize = 40;

/// The least significance level: a linear amplitude counts as significant at this many
/// standard uncertainties.
const SIGNIFICANCE: Real = 2.0;
/// The false-alarm probability a searched amplitude's threshold allows over its search.
const FALSE_ALARM: Real = 0.05;

impl Fitter<'_> {
    /// Searches `axis`'s reversal lag (s): a grid of [`LAG_GRID`] points over the range,
    /// golden section between the best point's neighbours, then the middle of the interval
    /// where the residual sum of squares stays at that minimum. A sampled trace cannot tell
    /// where between two samples an axis reversed (a step, or a spike's onset, reads the
    /// same): the middle is the unbiased choice.
    pub(super) fn search_lag(&self, profile: &LagProfile<'_>) -> Real {
        let (low, high) = self.data.ranges.lag;
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
        let (from, to) = interval(&|g| profile.rss(g), lag, flat, low, high);
        if std::env::var("MTWIN_DEBUG").is_ok() {
            eprintln!(
                "lag search: best grid {} ({:.12e}), refined {:.9e} {:.12e}, chosen {lag:.9e} {value:.12e}, interval {from:.9e} {to:.9e} fixed {:.12e}",
                grid[best],
                values[best],
                refined,
                profile.rss(refined),
                profile.fixed.rss
            );
            if std::env::var("MTWIN_DEBUG").unwrap() == "grid" {
                for k in 0..61 {
                    let g = -3e-3 + 1e-4 * k as Real;
                    eprintln!("  {g:.5} {:.15e}", profile.rss(g) - value);
                }
            }
        }
        (from + to) / 2.0
    }

    /// Searches `term`'s shape parameter on the joint residual sum of squares with `fixed`
    /// (the other columns); `refine` only polishes the current value.
    pub(super) fn search(&self, term: Term, fixed: &[Column], shape: &mut Shape, refine: bool) {
        let fit = self.project(fixed);
        match term {
            Term::ReversalSpikeP | Term::ReversalSpikeQ => {
                let axis = usize::from(term == Term::ReversalSpikeQ);
                self.search_decay(axis, fixed, &fit, shape);
            }
            Term::CyclicP | Term::CyclicQ => {
                let axis = usize::from(term == Term::CyclicQ);
                self.search_period(axis, fixed, &fit, shape, refine);
            }
            Term::Lobes => self.search_lobes(fixed, &fit, shape, refine),
            _ => {}
        }
    }

    /// The spike decay of `axis`: a log grid of [`DECAY_GRID`] decays, then Brent's method
    /// between the best one's neighbours. The column is zero but within the longest decay's
    /// window after a crossed reversal: only those readings are evaluated.
    fn search_decay(&self, axis: usize, fixed: &[Column], fit: &NormalFit, shape: &mut Shape) {
        let ranges = self.data.ranges;
        let reversal = Reversal::new(axis, shape, &self.data.test);
        let window = reversal.spike_window(self.data, self.blocks, &self.included, ranges.decay.1);
        let rows: Vec<usize> = window.iter().map(|w| w.0).collect();
        let k = fixed.len();
        let values = self.values_at(fixed, &rows);
        let at = |tau: Real| {
            let mut fb = DMatrix::zeros(k, 1);
            let (mut bb, mut by) = (0.0, 0.0);
            let column = fb.as_mut_slice();
            for ((_, weight, dt), row) in window.iter().zip(values.chunks(k + 1)) {
                if *dt >= SPIKE_DECAYS * tau {
                    break;
                }
                let v = weight * (-dt / tau).exp();
                for (f, x) in column.iter_mut().zip(row) {
                    *f += v * x;
                }
                by += v * row[k];
                bb += v * v;
            }
            fit.rss_from(&fb, &DMatrix::from_element(1, 1, bb), &[by])
        };
        let (low, high) = (ranges.decay.0.ln(), ranges.decay.1.ln());
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
        let (refined, value) = brent(|g| at(g.exp()), a, b);
        shape.decay[axis] = if value < values[best] {
            refined.exp()
        } else {
            grid[best].exp()
        };
    }

    /// The cyclic period of `axis`: the periodogram's peak of the fixed fit's residual on the
    /// first pass (the current period on the next), then Brent's method within a grid step
    /// either side. Trials are scored from the columns' moments about the grid frequency
    /// nearest to the middle of that interval.
    fn search_period(
        &self,
        axis: usize,
        fixed: &[Column],
        fit: &NormalFit,
        shape: &mut Shape,
        refine: bool,
    ) {
        let grid = self.data.frequency_grid();
        let peak = if refine {
            1.0 / shape.period[axis]
        } else {
            1.0 / self
                .fit_periodogram(axis, fixed, &fit.coefficients, fit.rss)
                .0
        };
        let (from, to) = (
            (peak - grid.step).max(grid.low),
            (peak + grid.step).min(grid.high),
        );
        let at = self.cyclic_trials(axis, fixed, fit, (from + to) / 2.0);
        let (refined, value) = brent(&at, from, to);
        shape.period[axis] = if value < at(peak) {
            1.0 / refined
        } else {
            1.0 / peak
        };
    }

    /// The residual sum of squares of `fit` (of `fixed`) with `axis`'s cyclic columns at a
    /// trial frequency (1/m) near `middle`: from moments about the grid frequency nearest to
    /// it, or column by column when `middle` is off the grid's reach.
    fn cyclic_trials<'b>(
        &'b self,
        axis: usize,
        fixed: &'b [Column],
        fit: &'b NormalFit,
        middle: Real,
    ) -> Box<dyn Fn(Real) -> Real + 'b> {
        let column = move |f: Real, index: usize| {
            Column::dense(Dense::Cyclic {
                axis,
                period: 1.0 / f,
                index,
            })
        };
        let Some(k) = self.centre_of(middle) else {
            return Box::new(move |f| {
                let extra = [column(f, 0), column(f, 1)];
                self.rss_with(fit, fixed, &extra)
            });
        };
        let moments = self.combined(axis, k);
        let centre = moments.frequency;
        // Every fixed column's moments: its static part's from the blocks' sums, the rest
        // reading by reading.
        let rows: Vec<Vec<Complex<Real>>> = fixed
            .iter()
            .map(|c| {
                let mut m = match &c.dense {
                    Dense::Zero | Dense::Static(_) | Dense::Mix(_) => {
                        vec![Complex::new(0.0, 0.0); ORDER]
                    }
                    Dense::Lobe { k: count, index } => self.lobe_moments(axis, k, *count, *index),
                    dense => {
                        let values = self.dense_values(dense);
                        self.moments_of(axis, &moments, self.rows.iter().map(|&i| (i, values[i])))
                    }
                };
                let sparse = self.moments_of(
                    axis,
                    &moments,
                    c.sparse
                        .rows
                        .iter()
                        .zip(&c.sparse.values)
                        .map(|(&i, &v)| (i as usize, v)),
                );
                for (a, b) in m.iter_mut().zip(sparse) {
                    *a += b;
                }
                m
            })
            .collect();
        let statics: Vec<Vec<(usize, Real)>> = fixed
            .iter()
            .map(|c| match &c.dense {
                Dense::Static(j) => vec![(*j, 1.0)],
                Dense::Mix(mix) => mix.to_vec(),
                _ => Vec::new(),
            })
            .collect();
        let radius = self.data.test.radius;
        Box::new(move |f: Real| {
            let (series, double) = offset_series(radius, f - centre);
            let n = fixed.len();
            let mut fb = DMatrix::zeros(n, 2);
            for i in 0..n {
                let sum: Complex<Real> = rows[i].iter().zip(&series).map(|(m, e)| m * e).sum();
                let (mut sin, mut cos) = (sum.im, sum.re);
                for &(j, w) in &statics[i] {
                    let (s, c) = moments.with_table(j, &series);
                    sin += w * s;
                    cos += w * c;
                }
                fb[(i, 0)] = sin;
                fb[(i, 1)] = cos;
            }
            let (ys, yc) = moments.with_table(Y, &series);
            let (ss, cc, sc) = moments.own(&double);
            let bb = DMatrix::from_row_slice(2, 2, &[ss, sc, sc, cc]);
            fit.rss_from(&fb, &bb, &[ys, yc])
        })
    }

    /// The residual sum of squares of `fit` (of `fixed`) with `extra` columns added, their
    /// cross products taken column by column.
    fn rss_with(&self, fit: &NormalFit, fixed: &[Column], extra: &[Column]) -> Real {
        let (k, m) = (fixed.len(), extra.len());
        let fb = DMatrix::from_fn(k, m, |i, j| self.cross(&fixed[i], &extra[j]));
        let bb = DMatrix::from_fn(m, m, |i, j| self.cross(&extra[i], &extra[j]));
        let by: Vec<Real> = extra.iter().map(|c| self.cross_y(c)).collect();
        fit.rss_from(&fb, &bb, &by)
    }

    /// The lobe count: every count on the first pass, two either side of the current one
    /// after.
    fn search_lobes(&self, fixed: &[Column], fit: &NormalFit, shape: &mut Shape, refine: bool) {
        let ranges = self.data.ranges;
        let (low, high) = if refine {
            (
                shape.lobes.saturating_sub(2).max(ranges.lobes.0),
                (shape.lobes + 2).min(ranges.lobes.1),
            )
        } else {
            ranges.lobes
        };
        if low > high {
            return;
        }
        let counts = (high - low + 1) as usize;
        let k = fixed.len();
        // Per count, the fixed columns' cross products with sin kθ and cos kθ beyond what
        // the blocks' lobe sums hold (their dense parts other than static ones, their sparse
        // changes), reading by reading with the phasors advanced by recurrence.
        let mut extra = vec![0.0; counts * k * 2];
        let dense: Vec<(usize, std::rc::Rc<Vec<Real>>)> = fixed
            .iter()
            .enumerate()
            .filter(|(_, c)| c.dense.statics().is_none())
            .map(|(j, c)| (j, self.dense_values(&c.dense)))
            .collect();
        let mut sparse: std::collections::BTreeMap<usize, Vec<(usize, Real)>> = Default::default();
        for (j, c) in fixed.iter().enumerate() {
            for (&i, &v) in c.sparse.rows.iter().zip(&c.sparse.values) {
                if self.fitted(i as usize) {
                    sparse.entry(i as usize).or_default().push((j, v));
                }
            }
        }
        // Dense columns (cyclic ones) by a transform over the angles when every count is
        // wanted; the rest reading by reading.
        let transformed = !refine && !dense.is_empty();
        if transformed {
            for (j, values) in &dense {
                for (n, (s, c)) in self.lobe_products(values).into_iter().enumerate() {
                    extra[(n * k + j) * 2] += s;
                    extra[(n * k + j) * 2 + 1] += c;
                }
            }
        }
        let rows: Vec<usize> = if dense.is_empty() || transformed {
            sparse.keys().copied().collect()
        } else {
            self.rows.clone()
        };
        let mut weights: Vec<(usize, Real)> = Vec::with_capacity(k);
        for i in rows {
            weights.clear();
            if !transformed {
                weights.extend(dense.iter().map(|(j, values)| (*j, values[i])));
            }
            if let Some(entries) = sparse.get(&i) {
                weights.extend_from_slice(entries);
            }
            let point = &self.data.points[i];
            let (ds, dc) = point.sin_cos;
            let (mut s, mut co) = (Real::from(low) * point.angle).sin_cos();
            for n in 0..counts {
                let out = &mut extra[n * k * 2..(n + 1) * k * 2];
                for &(j, v) in &weights {
                    out[2 * j] += v * s;
                    out[2 * j + 1] += v * co;
                }
                (s, co) = (s * dc + co * ds, co * dc - s * ds);
            }
        }
        let mut best = (low, Real::INFINITY);
        for (n, count) in (low..=high).enumerate() {
            let lobe = |index: usize| Column::dense(Dense::Lobe { k: count, index });
            let columns = [lobe(0), lobe(1)];
            let value = match (self.lobe_self(count, 0, 0), self.lobe_self(count, 1, 1)) {
                (Some(ss), Some(cc)) => {
                    let sc = self.lobe_self(count, 0, 1).unwrap_or(0.0);
                    let mut fb = DMatrix::zeros(k, 2);
                    for (j, c) in fixed.iter().enumerate() {
                        for index in 0..2 {
                            let held: Real = match &c.dense {
                                Dense::Static(t) => self.lobe_with(count, index, *t).unwrap_or(0.0),
                                Dense::Mix(mix) => mix
                                    .iter()
                                    .map(|(t, w)| {
                                        w * self.lobe_with(count, index, *t).unwrap_or(0.0)
                                    })
                                    .sum(),
                                _ => 0.0,
                            };
                            fb[(j, index)] = held + extra[(n * k + j) * 2 + index];
                        }
                    }
                    let by = [
                        self.lobe_with(count, 0, Y).unwrap_or(0.0),
                        self.lobe_with(count, 1, Y).unwrap_or(0.0),
                    ];
                    let bb = DMatrix::from_row_slice(2, 2, &[ss, sc, sc, cc]);
                    fit.rss_from(&fb, &bb, &by)
                }
                _ => self.rss_with(fit, fixed, &columns),
            };
            if value < best.1 {
                best = (count, value);
            }
        }
        shape.lobes = best.0;
    }
}

impl CircleData {
    /// Why `term`'s searched shape in `shape` is not a measurement, when it lies at an end of
    /// its searched range (within 0.1 % of a decay, in logarithm, or of a grid step of the
    /// frequency: the searches end within 3e-5 and 2e-4 of a bound their minimum runs into;
    /// a lobe count at the most searched): the residual still falls toward the end, so the
    /// trace's feature lies beyond what the term can take, and its height is that of the wrong
    /// shape. `None` for the other terms and for shapes inside their ranges.
    pub fn shape_at_range_end(&self, term: Term, shape: &Shape) -> Option<String> {
        match term {
            Term::ReversalSpikeP | Term::ReversalSpikeQ => {
                let decay = shape.decay[usize::from(term == Term::ReversalSpikeQ)];
                let (shortest, longest) = self.ranges.decay;
                if (decay / longest).ln().abs() < 1e-3 {
                    Some(format!(
                        "its decay reaches the longest searched ({:.1} ms): the trace's feature decays more slowly than a reversal spike the fit can follow, so neither its height nor its decay is measured",
                        longest * 1e3
                    ))
                } else if (decay / shortest).ln().abs() < 1e-3 {
                    Some(format!(
                        "its decay reaches the shortest searched ({:.1} ms, two sampling intervals): the spike dies out faster than the trace is sampled, so its height at the reversal cannot be read",
                        shortest * 1e3
                    ))
                } else {
                    None
                }
            }
            Term::CyclicP | Term::CyclicQ => {
                let frequency = 1.0 / shape.period[usize::from(term == Term::CyclicQ)];
                let grid = self.frequency_grid();
                if (frequency - grid.low).abs() < 1e-3 * grid.step {
                    Some(format!(
                        "its period reaches the longest searched ({:.1} mm, half the radius): the trace's feature is of longer wavelength than a cyclic error the fit can take, so neither its amplitude nor its period is measured",
                        1e3 / grid.low
                    ))
                } else if (frequency - grid.high).abs() < 1e-3 * grid.step {
                    Some(format!(
                        "its period reaches the shortest searched ({:.2} mm, four sample spacings): shorter than the trace resolves (it may be aliased), so neither its amplitude nor its period is measured",
                        1e3 / grid.high
                    ))
                } else {
                    None
                }
            }
            // Fewer than 3 lobes are the centre offset and the ovals of squareness and scale,
            // in the model as their own terms: only the most lobes is an end. On a whole turn
            // (short of one lobe at the most) more lobes are orthogonal to every count
            // searched, so the most is a count like any other; on an arc they are not.
            Term::Lobes if shape.lobes >= self.ranges.lobes.1 => {
                let most = self.ranges.lobes.1;
                let whole = TAU * (1.0 - 1.0 / Real::from(most));
                let arc = self.spans.iter().flatten().copied().fold(TAU, Real::min);
                (arc < whole).then(|| format!(
                    "its count reaches the most searched ({most} per turn) on an arc of {:.0}°, where more lobes than that are not orthogonal to the counts searched: the trace's feature may have more lobes than the fit can take, so neither its count nor its amplitude is measured",
                    arc.to_degrees()
                ))
            }
            _ => None,
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
            Term::CyclicP | Term::CyclicQ => self.frequency_grid().count,
            Term::ReversalSpikeP | Term::ReversalSpikeQ => LAG_GRID * DECAY_GRID,
            _ => return SIGNIFICANCE,
        };
        (2.0 * (tested as Real / FALSE_ALARM).ln())
            .sqrt()
            .max(SIGNIFICANCE)
    }

    /// The period (m) of `term` (cyclic p or q) whose two columns alone remove the largest
    /// fraction of `residual` (over `rows`, `residual[j]` at `rows[j]`), and that fraction: a
    /// periodogram over the frequency grid, phasors advanced by recurrence. (Fits use the same
    /// periodogram by a non-uniform Fourier transform, `spectral.rs`.)
    pub fn cyclic_periodogram(
        &self,
        term: Term,
        rows: &[usize],
        residual: &[Real],
    ) -> (Real, Real) {
        let grid = self.frequency_grid();
        let (f_low, step, count) = (grid.low, grid.step, grid.count);
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

/// The minimum of `f` between `low` and `high` (a grid point's neighbours) by Brent's method
/// to [`REFINE_TOLERANCE`] of the bracket.
pub(super) fn brent(f: impl Fn(Real) -> Real, low: Real, high: Real) -> (Real, Real) {
    let tolerance = REFINE_TOLERANCE * (high - low).abs();
    brent_minimum(f, low, high, tolerance, REFINE_EVALUATIONS)
}
