//! The searched (nonlinear) parameters: the time constants of `thermal_lag` and
//! `second_heat_source` (log grid, then golden section) and the period of `periodic`
//! (periodogram, then Brent's method).

use super::fit::Searched;
use super::problem::Reference;
use super::profile::FREQUENCY_PROBES;
use super::{PositioningEffect, PositioningProblem, TAU_GRID};
use crate::math::{M_PER_MM, Real, brent_minimum, golden_minimum};

/// The period's refinement about the periodogram's peak ends within this fraction of its
/// bracket (two frequency steps of 1/(4·span)) of the minimum, far below the period's
/// uncertainty. Golden section took 16 steps (0.618¹⁶ = 4.6·10⁻⁴ of the bracket); Brent's
/// parabolic steps need 6–12 on this smooth sum of squares. (The time constants keep golden
/// section: with Brent's steps, an exactly aliased pair of effects on a two-target file,
/// `thermal_scale` and `reversal_thermal` on `vmc3_iso230_3_linear`, swapped places on
/// rounding; see the book's performance chapter.)
const REFINE_TOLERANCE: Real = 1e-4;
/// At most this many evaluations per refinement.
const REFINE_EVALUATIONS: usize = 40;

/// The minimum of `f` between `low` and `high` by Brent's method to [`REFINE_TOLERANCE`].
fn refine(f: impl Fn(Real) -> Real, low: Real, high: Real) -> (Real, Real) {
    brent_minimum(
        f,
        low,
        high,
        REFINE_TOLERANCE * (high - low).abs(),
        REFINE_EVALUATIONS,
    )
}

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

    /// The range (s) a time constant is searched over: from `shortest` (at least 1 min) to
    /// twice the file's span.
    pub(super) fn tau_range(&self, shortest: Real) -> (Real, Real) {
        let high = (2.0 * self.time_span()).max(120.0);
        (shortest.clamp(60.0, 0.5 * high), high)
    }

    /// Why the time constant `tau` (s), searched from `shortest` ([`Self::search_tau`]), is not
    /// a measurement, when it lies at an end of its range (within 0.1 % in logarithm; the
    /// search ends within 2e-4 of a bound its minimum runs into): the residual still falls
    /// toward the end, so the file holds no time constant the search can take.
    pub(super) fn tau_at_range_end(&self, tau: Real, shortest: Real) -> Option<String> {
        let (low, high) = self.tau_range(shortest);
        if (tau / high).ln().abs() < 1e-3 {
            Some("is the end of the range searched (twice the file's span): the file shows no end to the response, so the time constant is not measured (it is at least this long), nor the size of what it scales; these are the model's values, which --write-model writes".to_string())
        } else if (tau / low).ln().abs() < 1e-3 {
            Some("is the shortest searched: the response is faster than the file resolves, so the time constant is not measured (it is at most this long); these are the model's values, which --write-model writes".to_string())
        } else {
            None
        }
    }

    /// Why the period `period` (m), searched by [`Self::search_period`], is not a measurement,
    /// when it lies at an end of the range: as long as the travel read or longer (the search
    /// refines down to half the lowest frequency), the file holds at most one cycle, so a
    /// sinusoid is one smooth shape among many (a bow, a scale error) and neither its period nor
    /// its amplitude is measured; at the shortest searched (within 0.1 %), the period is at most
    /// that.
    pub(super) fn period_at_range_end(&self, period: Real) -> Option<String> {
        let (_, f_low) = self.frequency_grid();
        if period * f_low >= 1.0 - 1e-3 {
            Some(format!(
                "is at least the travel read ({:.1} mm): the file holds at most one cycle of it, so the period is not measured, nor the amplitude (over one cycle a sinusoid is one smooth shape among many: a bow, a scale error); these are the model's values, which --write-model writes",
                1.0 / f_low / M_PER_MM
            ))
        } else if (period / self.options.min_period).ln().abs() < 1e-3 {
            Some(format!(
                "is the shortest searched ({:.1} mm): the period is not measured (it is at most this long), nor the amplitude; these are the model's values, which --write-model writes",
                self.options.min_period / M_PER_MM
            ))
        } else {
            None
        }
    }

    /// Searches a time constant (s) on a log grid from `shortest` (at least 1 min) to twice the
    /// file's span, then refines by golden section (16 steps) between the best point's
    /// neighbours.
    pub(super) fn search_tau(&self, shortest: Real, sse: impl Fn(Real) -> Real) -> Real {
        let (low, high) = self.tau_range(shortest);
        let (low, high) = (low.ln(), high.ln());
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
    /// 1/min_period (4 points per 1/span), then a refinement by Brent's method of the full
    /// fit's sum of squares around the peak (through
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
        let (step, f_low) = self.frequency_grid();
        let r = without.expect("a period changes no known part");
        let (peak, _) = self.periodogram_peak(train, &r);
        let (low, high) = ((peak - step).max(f_low / 2.0), peak + step);
        let (refined, value) = refine(&sse, low, high);
        if value < sse(peak) {
            1.0 / refined
        } else {
            1.0 / peak
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::positioning::{PositioningOptions, PositioningTable};

    #[test]
    fn a_period_from_the_travel_up_or_at_the_shortest_is_not_a_measurement() {
        // Two bidirectional runs over targets 5 to 695 mm: 690 mm of travel read, periods
        // searched from 2 mm (the default shortest) up.
        let mut text = String::from("axis,run,direction,target_mm,deviation_um\n");
        for run in 1..=2 {
            for direction in ["+", "-"] {
                for j in 0..7 {
                    let x = 5.0 + 115.0 * j as f64;
                    text.push_str(&format!("X,{run},{direction},{x},{}\n", 0.1 * j as f64));
                }
            }
        }
        let table = PositioningTable::parse(text.as_bytes(), "periods.csv").unwrap();
        let problem = PositioningProblem::new(&table, PositioningOptions::default()).unwrap();
        let mm = |v: Real| v * M_PER_MM;
        for period in [690.0, 1000.0, 1380.0, 2.0] {
            let why = problem.period_at_range_end(mm(period));
            assert!(why.is_some(), "{period} mm");
        }
        assert!(
            problem
                .period_at_range_end(mm(690.0))
                .unwrap()
                .contains("690.0 mm")
        );
        for period in [2.01, 25.0, 680.0] {
            assert_eq!(problem.period_at_range_end(mm(period)), None, "{period} mm");
        }
    }
}
