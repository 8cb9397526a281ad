//! The searched (nonlinear) parameters: the time constants of `thermal_lag` and
//! `second_heat_source` (log grid, then golden section) and the period of `periodic`
//! (periodogram, then golden section).

use super::fit::Searched;
use super::problem::Reference;
use super::{PositioningEffect, PositioningProblem, TAU_GRID};
use crate::math::Real;
use crate::math::golden_minimum;
use std::f64::consts::TAU;

impl PositioningProblem {
    /// The time span of the file (s), for the time-constant search range.
    pub(super) fn time_span(&self) -> Real {
        let time = self
            .time
            .as_ref()
            .expect("only searched with a time column");
        let (first, last) = (self.order[0], self.order[self.order.len() - 1]);
        (time[last] - time[first]).max(60.0)
    }

    /// The shortest heating time constant (s) the training readings `train` can tell from a
    /// step: a third of the time from the file's first reading to the first training reading.
    /// Shorter, the response `1 − e^(−(t − t₀)/τ)` changes by less than e^(−3) = 5 % over the
    /// training readings: a constant the profile already holds, whose coefficient (against the
    /// profile's) the fit cannot bound, and which it would extrapolate to a held-out cold
    /// first run by metres (1 µm of noise over a 10⁻⁵ difference of columns).
    pub(super) fn shortest_heating_tau(&self, train: &[bool]) -> Real {
        let time = self
            .time
            .as_ref()
            .expect("only searched with a time column");
        let start = time[self.order[0]];
        let first_trained = self
            .order
            .iter()
            .find(|&&i| train[i])
            .map_or(start, |&i| time[i]);
        (first_trained - start) / 3.0
    }

    /// Searches a time constant (s) on a log grid from `shortest` (at least 1 min) to twice the
    /// file's span, then refines by golden section between the best point's neighbours.
    pub(super) fn search_tau(&self, shortest: Real, sse: impl Fn(Real) -> Real) -> Real {
        let high = (2.0 * self.time_span()).max(120.0);
        let (low, high) = (shortest.clamp(60.0, 0.5 * high).ln(), high.ln());
        let grid: Vec<Real> = (0..TAU_GRID)
            .map(|k| low + (high - low) * k as Real / (TAU_GRID - 1) as Real)
            .collect();
        let values: Vec<Real> = grid.iter().map(|&g| sse(g.exp())).collect();
        let best = (0..TAU_GRID)
            .min_by(|&a, &b| values[a].total_cmp(&values[b]))
            .unwrap_or(0);
        let (a, b) = (
            grid[best.saturating_sub(1)],
            grid[(best + 1).min(TAU_GRID - 1)],
        );
        let (refined, value) = golden_minimum(|g| sse(g.exp()), a, b, 16);
        if value < values[best] {
            refined.exp()
        } else {
            grid[best].exp()
        }
    }

    /// Searches the period (m): a periodogram of the residual of the model without the cyclic
    /// term over frequencies from 1/(span) to 1/min_period (4 points per 1/span), then a
    /// golden-section refinement of the full fit around the peak.
    pub(super) fn search_period(
        &self,
        effects: &[PositioningEffect],
        train: &[bool],
        reference: &Reference,
        searched: &Searched,
    ) -> Real {
        let without: Vec<PositioningEffect> = effects
            .iter()
            .copied()
            .filter(|&e| e != PositioningEffect::Periodic)
            .collect();
        let (_, residuals, _, _) = self.solve(&without, train, reference, searched);
        let rows: Vec<usize> = (0..self.x.len()).filter(|&i| train[i]).collect();
        let x: Vec<Real> = rows.iter().map(|&i| self.x[i]).collect();
        let r: Vec<Real> = rows.iter().map(|&i| residuals[i]).collect();
        let (step, f_low) = self.frequency_grid();
        let (peak, _) = self.periodogram_peak(&x, &r);
        let sse = |f: Real| {
            let trial = Searched {
                period: Some(1.0 / f),
                ..*searched
            };
            self.solve(effects, train, reference, &trial).2
        };
        let (low, high) = ((peak - step).max(f_low / 2.0), peak + step);
        let (refined, value) = golden_minimum(sse, low, high, 16);
        if value < sse(peak) {
            1.0 / refined
        } else {
            1.0 / peak
        }
    }

    /// The periodogram's frequency step and lowest frequency (1/m): from 1/travel to
    /// 1/min_period, 4 points per 1/travel.
    fn frequency_grid(&self) -> (Real, Real) {
        let span = (2.0 * self.half_range).max(self.options.min_period);
        (1.0 / (4.0 * span), 1.0 / span)
    }

    /// The frequency (1/m) whose sinusoid removes the largest fraction of `r`'s sum of squares
    /// over positions `x`, and that fraction.
    ///
    /// Readings at one position share their sine and cosine, so the sums of every trial
    /// frequency are taken over the distinct positions (a laser file reads a few dozen targets
    /// many times), each weighted by its readings: the same normal equations, a tenth of the
    /// work. The sinusoids of consecutive frequencies are stepped by a rotation (restarted
    /// from the exact value every [`RESTART`] frequencies, so rounding stays near 1e-14).
    pub(super) fn periodogram_peak(&self, x: &[Real], r: &[Real]) -> (Real, Real) {
        let (step, f_low) = self.frequency_grid();
        let count = ((1.0 / self.options.min_period - f_low) / step).ceil() as usize + 1;
        let groups = Groups::new(x, r);
        let mut phase = vec![(0.0, 0.0); groups.x.len()];
        let rotation: Vec<(Real, Real)> = groups
            .x
            .iter()
            .map(|&x| (TAU * step * x).sin_cos())
            .collect();
        // The last of equal maxima, as `Iterator::max_by` takes it.
        let mut best = (f_low, Real::NEG_INFINITY);
        for k in 0..count {
            let f = f_low + step * k as Real;
            if k % RESTART == 0 {
                for (p, &x) in phase.iter_mut().zip(&groups.x) {
                    *p = (TAU * f * x).sin_cos();
                }
            } else {
                for (p, &(rs, rc)) in phase.iter_mut().zip(&rotation) {
                    // sin(a + b), cos(a + b).
                    *p = (p.0 * rc + p.1 * rs, p.1 * rc - p.0 * rs);
                }
            }
            let fraction = groups.reduction(&phase);
            if fraction >= best.1 {
                best = (f, fraction);
            }
        }
        if best.1 == Real::NEG_INFINITY {
            (f_low, 0.0)
        } else {
            best
        }
    }
}

/// Frequencies between exact restarts of the periodogram's rotation.
const RESTART: usize = 64;

/// Residuals summed by position: each distinct position, its number of readings and their sum;
/// and the total sum of squares.
struct Groups {
    x: Vec<Real>,
    count: Vec<Real>,
    sum: Vec<Real>,
    total: Real,
}

impl Groups {
    fn new(x: &[Real], r: &[Real]) -> Groups {
        let mut order: Vec<usize> = (0..x.len()).collect();
        order.sort_by(|&a, &b| x[a].total_cmp(&x[b]).then(a.cmp(&b)));
        let mut groups = Groups {
            x: Vec::new(),
            count: Vec::new(),
            sum: Vec::new(),
            total: r.iter().map(|v| v * v).sum(),
        };
        for i in order {
            if groups.x.last() == Some(&x[i]) {
                *groups.count.last_mut().expect("a group") += 1.0;
                *groups.sum.last_mut().expect("a group") += r[i];
            } else {
                groups.x.push(x[i]);
                groups.count.push(1.0);
                groups.sum.push(r[i]);
            }
        }
        groups
    }

    /// The fraction of the sum of squares removed by fitting `a·sin + b·cos + c`, the sines
    /// and cosines at each position given (normal equations of the three columns).
    fn reduction(&self, phase: &[(Real, Real)]) -> Real {
        let mut normal = nalgebra::Matrix3::<Real>::zeros();
        let mut right = nalgebra::Vector3::<Real>::zeros();
        for ((&(sin, cos), &w), &sum) in phase.iter().zip(&self.count).zip(&self.sum) {
            let row = nalgebra::Vector3::new(sin, cos, 1.0);
            normal += row * row.transpose() * w;
            right += row * sum;
        }
        let Some(c) = normal.cholesky().map(|c| c.solve(&right)) else {
            return 0.0;
        };
        // Residual sum of squares = total − cᵀ·(Aᵀr) at the least-squares solution.
        if self.total > 0.0 {
            (c.dot(&right) / self.total).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}
