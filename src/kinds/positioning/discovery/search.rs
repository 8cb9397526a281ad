//! The searched (nonlinear) parameters: the time constants of `thermal_lag` and
//! `second_heat_source` (log grid, then golden section) and the period of `periodic`
//! (periodogram, then golden section).

use super::fit::Searched;
use super::problem::Reference;
use super::profile::FREQUENCY_PROBES;
use super::{PositioningEffect, PositioningProblem, TAU_GRID};
use crate::discovery::least_squares::RANK_TOLERANCE;
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
    /// term (from the profile, no fit of its own) over frequencies from 1/(span) to
    /// 1/min_period (4 points per 1/span), then a
    /// golden-section refinement of the full fit's sum of squares around the peak (through
    /// [`PositioningProblem::sse_profile`]: only the sine and cosine change with the period).
    pub(super) fn search_period(
        &self,
        effects: &[PositioningEffect],
        train: &[bool],
        reference: &Reference,
        searched: &Searched,
    ) -> Real {
        let held = *searched;
        let (sse, without) =
            self.sse_profile(effects, train, reference, FREQUENCY_PROBES, move |f| {
                Searched {
                    period: Some(1.0 / f),
                    ..held
                }
            });
        // The residual of the model without the cyclic term on the training rows: the
        // profile's target off the columns the period does not change.
        let r = without.expect("a period changes no known part");
        let x: Vec<Real> = (0..self.x.len())
            .filter(|&i| train[i])
            .map(|i| self.x[i])
            .collect();
        let (step, f_low) = self.frequency_grid();
        let (peak, _) = self.periodogram_peak(&x, &r);
        let (low, high) = ((peak - step).max(f_low / 2.0), peak + step);
        let (refined, value) = golden_minimum(&sse, low, high, 16);
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
        let g = groups.x.len();
        let (mut sin, mut cos) = (vec![0.0; g], vec![0.0; g]);
        let (rotation_sin, rotation_cos): (Vec<Real>, Vec<Real>) =
            groups.x.iter().map(|&x| (TAU * step * x).sin_cos()).unzip();
        // The last of equal maxima, as `Iterator::max_by` takes it.
        let mut best = (f_low, Real::NEG_INFINITY);
        for k in 0..count {
            let f = f_low + step * k as Real;
            if k % RESTART == 0 {
                for ((s, c), &x) in sin.iter_mut().zip(cos.iter_mut()).zip(&groups.x) {
                    (*s, *c) = (TAU * f * x).sin_cos();
                }
            } else {
                let rotations = rotation_sin.iter().zip(&rotation_cos);
                for ((s, c), (&rs, &rc)) in sin.iter_mut().zip(cos.iter_mut()).zip(rotations) {
                    // sin(a + b), cos(a + b).
                    (*s, *c) = (*s * rc + *c * rs, *c * rc - *s * rs);
                }
            }
            let fraction = groups.reduction(&sin, &cos);
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

/// Interleaved partial sums of the periodogram's normal equations.
const LANES: usize = 2;

/// Residuals summed by position: each distinct position, its number of readings and their sum;
/// the total sum of squares, the number of readings and the sum of the residuals.
struct Groups {
    x: Vec<Real>,
    count: Vec<Real>,
    sum: Vec<Real>,
    total: Real,
    readings: Real,
    residual_sum: Real,
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
            readings: x.len() as Real,
            residual_sum: 0.0,
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
        groups.residual_sum = groups.sum.iter().sum();
        groups
    }

    /// The fraction of the sum of squares removed by fitting `a·sin + b·cos + c`, the sines
    /// and cosines at each position given: the normal equations of the three columns, of
    /// which only the seven sums that depend on the frequency are accumulated (the readings'
    /// count and the residuals' sum do not), in [`LANES`] interleaved partial sums that the
    /// compiler can keep in vector registers.
    fn reduction(&self, sin: &[Real], cos: &[Real]) -> Real {
        let mut lanes = [[0.0; LANES]; 7];
        let chunks = sin
            .chunks_exact(LANES)
            .zip(cos.chunks_exact(LANES))
            .zip(self.count.chunks_exact(LANES))
            .zip(self.sum.chunks_exact(LANES));
        for (((s, c), w), r) in chunks {
            for l in 0..LANES {
                let (ws, wc) = (w[l] * s[l], w[l] * c[l]);
                lanes[0][l] += ws * s[l];
                lanes[1][l] += ws * c[l];
                lanes[2][l] += wc * c[l];
                lanes[3][l] += ws;
                lanes[4][l] += wc;
                lanes[5][l] += s[l] * r[l];
                lanes[6][l] += c[l] * r[l];
            }
        }
        let mut sums = lanes.map(|lane| lane.iter().sum::<Real>());
        let tail = sin.len() - sin.len() % LANES;
        for j in tail..sin.len() {
            let (s, c, w, r) = (sin[j], cos[j], self.count[j], self.sum[j]);
            let (ws, wc) = (w * s, w * c);
            for (sum, term) in sums
                .iter_mut()
                .zip([ws * s, ws * c, wc * c, ws, wc, s * r, c * r])
            {
                *sum += term;
            }
        }
        let [ss, sc, cc, s1, c1, sr, cr] = sums;
        // The constant's equation eliminated: the centred 2 × 2 system M·k = w of the sine
        // and the cosine. What the three columns remove (total − residual sum of squares) is
        // wᵀ·M⁺·w plus the mean's share; M⁺ by M's eigenvalues, cut as the least squares cut
        // singular values: [`RANK_TOLERANCE`] of the constant column's norm √n, squared here
        // (sin² + cos² = 1 at every reading, so n is the sinusoid's scale too). At a frequency
        // that puts every position on a whole number of cycles, the sine is round-off and the
        // cosine the constant: only the mean removes anything.
        let (n, r1) = (self.readings, self.residual_sum);
        if n <= 0.0 || self.total <= 0.0 {
            return 0.0;
        }
        let (a, b, d) = (ss - s1 * s1 / n, sc - s1 * c1 / n, cc - c1 * c1 / n);
        let w = (sr - s1 * r1 / n, cr - c1 * r1 / n);
        let (half_trace, radius) = (0.5 * (a + d), (0.25 * (a - d) * (a - d) + b * b).sqrt());
        let largest = half_trace + radius;
        let cut = n * RANK_TOLERANCE * RANK_TOLERANCE;
        let mut removed = r1 * r1 / n;
        if largest > cut {
            // The largest eigenvalue's unit eigenvector (the better conditioned of the two
            // forms), and the other's at right angles.
            let (p, q) = if a >= d {
                (largest - d, b)
            } else {
                (b, largest - a)
            };
            let norm = (p * p + q * q).sqrt();
            let e = if norm > 0.0 {
                (p / norm, q / norm)
            } else {
                (1.0, 0.0)
            };
            for (lambda, (x, y)) in [(largest, e), (half_trace - radius, (-e.1, e.0))] {
                if lambda > cut {
                    removed += (x * w.0 + y * w.1).powi(2) / lambda;
                }
            }
        }
        (removed / self.total).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discovery::least_squares::Design;

    #[test]
    fn grouped_reduction_equals_a_least_squares_on_every_reading() {
        // Positions read two to four times each (whole millimetres), a 25 mm sinusoid, an
        // offset and deterministic scatter.
        let mut x = Vec::new();
        let mut r = Vec::new();
        for k in 0..41_usize {
            let position = (5 + 17 * k) as Real * 1e-3;
            for repeat in 0..(2 + k % 3) {
                x.push(position);
                r.push(
                    1.3e-6 * (TAU * position / 0.025).sin() + 0.1e-6
                        - 0.2e-6 * (TAU * position / 0.025).cos()
                        + 0.05e-6 * (((k * 7 + repeat * 3) % 11) as Real / 11.0 - 0.5),
                );
            }
        }
        let groups = Groups::new(&x, &r);
        // 41 positions: ten chunks of the partial sums and one left over.
        assert_eq!(groups.x.len(), 41);
        let total: Real = r.iter().map(|v| v * v).sum();
        for period_mm in [3.7, 25.0, 61.0, 400.0] {
            let w = TAU / (period_mm * 1e-3);
            let (sin, cos): (Vec<Real>, Vec<Real>) =
                groups.x.iter().map(|&p| (w * p).sin_cos()).unzip();
            let mut design = Design::new(x.len());
            design.push(x.iter().map(|&p| (w * p).sin()).collect());
            design.push(x.iter().map(|&p| (w * p).cos()).collect());
            design.push(vec![1.0; x.len()]);
            let fitted = design.times(&design.solve(&r));
            let sse: Real = r.iter().zip(&fitted).map(|(r, f)| (r - f).powi(2)).sum();
            let direct = 1.0 - sse / total;
            let grouped = groups.reduction(&sin, &cos);
            assert!(
                (grouped - direct).abs() < 1e-10,
                "period {period_mm} mm: {grouped} against {direct}"
            );
        }
    }

    #[test]
    fn on_a_whole_number_of_cycles_only_the_mean_is_removed() {
        // Positions on a 5 mm grid and a 5 mm period: the sine is round-off (about 1e-13)
        // and the cosine is 1 everywhere, so the sinusoid adds nothing to the constant and
        // the fraction removed is the mean's, (Σr)²/n over Σr², not a fit of round-off.
        let x: Vec<Real> = (1..=30).map(|k| (5 * k) as Real * 1e-3).collect();
        let r: Vec<Real> = (0..30)
            .map(|k| 1e-6 * (0.3 + ((k * 7) % 11) as Real / 11.0))
            .collect();
        let groups = Groups::new(&x, &r);
        let w = TAU / 5e-3;
        let (sin, cos): (Vec<Real>, Vec<Real>) = x.iter().map(|&p| (w * p).sin_cos()).unzip();
        let total: Real = r.iter().map(|v| v * v).sum();
        let mean_share = r.iter().sum::<Real>().powi(2) / 30.0 / total;
        let fraction = groups.reduction(&sin, &cos);
        assert!(
            (fraction - mean_share).abs() < 1e-12,
            "{fraction} against {mean_share}"
        );
    }
}
