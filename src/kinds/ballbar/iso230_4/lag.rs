//! Where a trace places an axis's reversal, and how well ([`CircleData::locate_lag`]): the
//! confidence set of the reversal lag, a change point, joined over the backlash's two
//! mechanisms.

use super::blocks::Blocks;
use super::normal::Fitter;
use super::profile::LagProfile;
use super::{CircleData, ModelFit, Shape, Term};
use crate::math::Real;

/// Bisections of the flat interval's edges, each from the best lag to a range end (at most
/// 400 ms): 2⁻²⁵ of that is 12 ns, far below the 1 µs the lag is printed to.
const EDGE_BISECTIONS: usize = 25;
/// Bound on Δχ² of the 95 % confidence set of a reversal lag: the lag is where a step lies in
/// the trace, a threshold (change point), and the likelihood ratio of a threshold does not
/// follow χ²₁ but P(LR ≤ x) = (1 − e^(−x/2))² (Hansen 2000, *Econometrica* 68, 575–603,
/// Theorem 2 and Table I), so x = −2·ln(1 − √0.95) = 7.352 (χ²₁ would give 3.841).
const STEP_LR_95: Real = 7.352_276_694_155_739;
/// Bound on the residual sum of squares of the backlash's other mechanism (a step, or a gap
/// taken up), in σ̂² above the chosen one's, within which the data are not taken to have told
/// the mechanisms apart. Each mechanism's fit is a minimum over its own change point (and
/// spike decay), so their difference is one of two such minima, not a χ² statistic: twice
/// [`STEP_LR_95`]. Measured on two simulators written apart from the fit (a step; a dead band
/// behind a first-order servo), 0.3 µm of noise, seeds 1–40: the wrong mechanism won by up to
/// 19·σ̂² (that one a sample on the reversal, a tie of the step simulator's, since removed),
/// and with real play at the bound of one change point alone 5 of 480 lags were more than 3 u
/// off (5 again on seeds 41–80); at this bound none of 480 is beyond 2 u on either seed set,
/// the 95th percentile of |error|/u 1.74–1.90 for the step and 1.55–1.66 for the play, the
/// median u 0.43 ms for a 1 µm step (`reversal_lag_coverage_at_low_signal_to_noise`,
/// `reversal_lag_coverage_with_real_play`).
const MECHANISM_BOUND: Real = 2.0 * STEP_LR_95;
/// The reversal lag's confidence set in words, for the notes that say a trace does not place
/// the reversal (the analysis's and discovery's).
pub const LAG_SET: &str = "within the 95 % confidence set of a change point, Δχ² ≤ 7.35";
/// Coverage factor of a normal distribution at 95 %: the lag's standard uncertainty is half
/// the 95 % set's width over it, so that ±2u is the set.
const COVERAGE_95: Real = 1.959_963_984_540_054;

/// What a trace says of an axis's reversal lag ([`CircleData::locate_lag`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LagLocation {
    /// The fitted lag (s) and its standard uncertainty: the distance from the fitted lag to
    /// the farther edge of the 95 % confidence set over 1.96. The set is the hull of the lags
    /// where the residual sum of squares, the other reversal terms refitted, is at most 7.35·σ̂²
    /// above its value at the fitted lag (a change point's likelihood-ratio bound), joined with
    /// the same set of the backlash's other mechanism when its fit is within twice that bound
    /// ([`ModelFit::mechanisms`]). For a step the set holds at least the lags between the
    /// readings on either side of it, where the fit cannot tell one from another, so ±2u spans
    /// them.
    Located {
        /// The fitted lag (s).
        lag: Real,
        /// Its standard uncertainty (s).
        u: Real,
    },
    /// The residual sum of squares stays within 7.35·σ̂² of its value at the fitted lag from
    /// `from` to `to` (s), and that interval reaches an end of the searched range: the trace
    /// does not place the reversal, and the fitted lag is not a measurement. Lateral play alone
    /// does this: its column σ·|sin θ| is continuous at the axis's reversal, so moving the
    /// reversal by δ changes it by at most about 2·(v·δ/R)·l/2 over an arc of v·δ (a few
    /// nanometres for 30 ms at 1000 mm/min on a 150 mm bar).
    NotLocated {
        /// The interval's start (s).
        from: Real,
        /// The interval's end (s).
        to: Real,
    },
}

impl CircleData {
    /// Where `axis`'s reversal is, as the fit `fit` places it, located by its reversal terms
    /// `locating` (the axis's others left out of the model: a term that is not significant
    /// fits noise wherever the lag puts it, and must not lend the lag a precision it does not
    /// have). The profile of the residual sum of squares over the lag, the other terms' columns
    /// refitted at each lag, is searched for the hull of the lags where it is at most 7.35 times
    /// `variance` (σ̂²) above its value at the fitted lag (`confidence_hull`: the 95 %
    /// confidence set of a change point), joined with that of the backlash's other mechanism
    /// when its fit is within twice that bound: [`LagLocation::Located`] when that hull lies
    /// inside the searched range, [`LagLocation::NotLocated`] when it reaches an end.
    pub fn locate_lag(
        &self,
        axis: usize,
        fit: &ModelFit,
        locating: &[Term],
        variance: Real,
    ) -> LagLocation {
        let blocks = Blocks::training(self, &vec![true; self.len()]);
        let fitter = Fitter::new(self, &blocks, vec![true, false]);
        let fixed: Vec<Term> = fit
            .terms
            .iter()
            .copied()
            .filter(|t| t.reversal_axis() != Some(axis))
            .collect();
        let moving: Vec<Term> = locating
            .iter()
            .copied()
            .filter(|t| t.reversal_axis() == Some(axis) && fit.terms.contains(t))
            .collect();
        let (low, high) = self.ranges.lag;
        if moving.is_empty() {
            return LagLocation::NotLocated {
                from: low,
                to: high,
            };
        }
        let every = fit
            .terms
            .iter()
            .filter(|t| t.reversal_axis() == Some(axis))
            .all(|t| moving.contains(t));
        let bound = STEP_LR_95 * variance;
        // The hull of the lags where the profile at `shape` (the other terms' columns
        // refitted at each lag) is within `slack` of its value at the lag that shape's fit
        // found, and that lag.
        let hull = |shape: &Shape, slack: Real| {
            let columns = fitter.columns(&fixed, shape);
            let profile = LagProfile::new(&fitter, axis, &moving, &columns, shape);
            // The fitted lag is this profile's minimum when every reversal term of the axis
            // locates it; otherwise the lag is searched again without the others.
            let best = if every {
                shape.lag[axis]
            } else {
                fitter.search_lag(&profile)
            };
            let (from, to) = confidence_hull(|g| profile.rss(g), best, slack, low, high);
            (best, from, to)
        };
        let (best, mut from, mut to) = hull(&fit.shape, bound);
        // The backlash's other mechanism: a gap taken up after the reversal lasts about
        // √(2b/(R·ω²)) (30 ms for 1 µm at 1000 mm/min on a 150 mm bar), so a gap from one lag
        // reads like a step that much later. Where the fit of the other mechanism is within
        // MECHANISM_BOUND·σ̂² of the chosen one, its own confidence set joins the chosen one's.
        for (shape, _) in rival_mechanisms(fit, axis, variance) {
            let (_, other_from, other_to) = hull(shape, bound);
            from = from.min(other_from);
            to = to.max(other_to);
        }
        if from <= low || to >= high {
            LagLocation::NotLocated { from, to }
        } else {
            // The set need not be centred on the fitted lag: its farther edge sets u.
            LagLocation::Located {
                lag: best,
                u: (best - from).max(to - best) / COVERAGE_95,
            }
        }
    }
}

/// The backlash mechanisms of `fit` ([`ModelFit::mechanisms`]) that take `axis`'s lost motion
/// the other way (a step where the fit took a gap, or a gap where it took a step) and fit within
/// [`MECHANISM_BOUND`]·`variance` of the chosen one, each with its residual sum of squares above
/// the chosen one's in units of `variance`: the trace does not tell those from the chosen one.
pub(super) fn rival_mechanisms(
    fit: &ModelFit,
    axis: usize,
    variance: Real,
) -> impl Iterator<Item = (&Shape, Real)> {
    let chosen = fit
        .mechanisms
        .iter()
        .find(|(shape, _)| *shape == fit.shape)
        .map(|&(_, rss)| rss);
    fit.mechanisms.iter().filter_map(move |(shape, rss)| {
        let above = (rss - chosen?) / variance;
        (shape.play[axis] != fit.shape.play[axis] && above <= MECHANISM_BOUND)
            .then_some((shape, above))
    })
}

/// Points of the scan [`confidence_hull`] makes of the whole lag range (every 0.2 ms over
/// ±200 ms: a twentieth of the 4 ms sampling interval of the bundled tests, between two of
/// whose readings the lag profile is smooth).
const HULL_SCAN: usize = 2001;

/// The smallest interval that holds every lag in `low..high` where `f` is at most `variance`
/// above its value at the fitted lag `best`: the hull of the profile-likelihood confidence set
/// (Δχ² = 1 when `variance` is σ̂²; [`CircleData::locate_lag`] gives it [`STEP_LR_95`]·σ̂²),
/// which holds any lower valley the search missed too.
///
/// The residual sum of squares over the lag has a kink wherever a reading crosses the
/// reversal, and it can have a second minimum within `variance` of the first, a sampling
/// interval or more away (measured on `vmc3_ballbar_xy`'s discovery: 2.6 % of the lag
/// searches ended more than Δχ² = 1 above the lowest point of a fine scan). Bisection from
/// `best` alone ([`interval`]) finds the edge of one valley and would report a `u` that does
/// not see the other, so the range is also scanned at [`HULL_SCAN`] points and each outermost
/// point within `variance` is refined by bisection against its outer neighbour.
fn confidence_hull(
    f: impl Fn(Real) -> Real,
    best: Real,
    variance: Real,
    low: Real,
    high: Real,
) -> (Real, Real) {
    let target = f(best) + variance;
    let (mut from, mut to) = interval(&f, best, target, low, high);
    let at = |k: usize| low + (high - low) * k as Real / (HULL_SCAN - 1) as Real;
    let inside = (0..HULL_SCAN).filter(|&k| f(at(k)) <= target);
    let ends = inside.fold(None, |ends, k| {
        Some(ends.map_or((k, k), |(first, _)| (first, k)))
    });
    let edge = |inside: Real, outside: Real| crossing(&f, inside, outside, target);
    if let Some((first, last)) = ends {
        if at(first) < from {
            from = if first == 0 {
                low
            } else {
                edge(at(first), at(first - 1))
            };
        }
        if at(last) > to {
            to = if last == HULL_SCAN - 1 {
                high
            } else {
                edge(at(last), at(last + 1))
            };
        }
    }
    (from, to)
}

/// The interval around `best` (inside low..high) where `f` stays at or below `target`:
/// each edge by [`EDGE_BISECTIONS`] bisections between `best` and the bound (the bound
/// itself when `f` is below `target` there).
pub(super) fn interval(
    f: &impl Fn(Real) -> Real,
    best: Real,
    target: Real,
    low: Real,
    high: Real,
) -> (Real, Real) {
    let edge = |bound: Real| {
        if f(bound) <= target {
            bound
        } else {
            crossing(f, best, bound, target)
        }
    };
    (edge(low), edge(high))
}

/// Where `f` crosses `target` between `inside` (at or below it) and `outside` (above it), by
/// [`EDGE_BISECTIONS`] bisections.
fn crossing(f: &impl Fn(Real) -> Real, inside: Real, outside: Real, target: Real) -> Real {
    let (mut inside, mut outside) = (inside, outside);
    for _ in 0..EDGE_BISECTIONS {
        let middle = (inside + outside) / 2.0;
        if f(middle) <= target {
            inside = middle;
        } else {
            outside = middle;
        }
    }
    (inside + outside) / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_change_point_bound_is_hansens_95_percent_point() {
        // Hansen (2000), Table I: the asymptotic critical values of the threshold's likelihood
        // ratio are 5.94 (90 %), 7.35 (95 %) and 10.59 (99 %); P(LR ≤ x) = (1 − e^(−x/2))².
        let level = |x: Real| (1.0 - (-x / 2.0).exp()).powi(2);
        for (x, p) in [(5.94, 0.90), (7.35, 0.95), (10.59, 0.99)] {
            assert!((level(x) - p).abs() < 5e-4, "{x}: {}", level(x));
        }
        assert!((level(STEP_LR_95) - 0.95).abs() < 1e-12);
        // The normal's 97.5 % point: Φ(1.96) = 0.975002 (Abramowitz & Stegun, Table 26.1).
        assert!((COVERAGE_95 - 1.96).abs() < 4e-5);
    }

    #[test]
    fn the_hull_holds_a_second_valley_within_the_variance() {
        // Two valleys: (x + 1)² and (x − 3)² + 0.2 (lags in arbitrary units over −10..10).
        // At most 0.5 above the value 0 at the fitted x = −1: |x + 1| ≤ √0.5 and
        // |x − 3| ≤ √0.3, so the hull is [−1 − √0.5, 3 + √0.3]; the first valley's interval
        // alone is [−1 − √0.5, −1 + √0.5].
        let f = |x: Real| ((x + 1.0) * (x + 1.0)).min((x - 3.0) * (x - 3.0) + 0.2);
        let (from, to) = confidence_hull(f, -1.0, 0.5, -10.0, 10.0);
        assert!((from - (-1.0 - 0.5_f64.sqrt())).abs() < 1e-6, "{from}");
        assert!((to - (3.0 + 0.3_f64.sqrt())).abs() < 1e-6, "{to}");
        let (_, local) = interval(&f, -1.0, 0.5, -10.0, 10.0);
        assert!((local - (-1.0 + 0.5_f64.sqrt())).abs() < 1e-6, "{local}");
        // The second valley 0.6 above the first is outside the set: the hull is one valley's.
        let g = |x: Real| ((x + 1.0) * (x + 1.0)).min((x - 3.0) * (x - 3.0) + 0.6);
        let (from, to) = confidence_hull(g, -1.0, 0.5, -10.0, 10.0);
        assert!((to - (-1.0 + 0.5_f64.sqrt())).abs() < 1e-6, "{from} {to}");
        // A search that stopped in the upper valley (best = 3, value 0.6): the lower valley,
        // below it, is in the hull, up to 1.1: [−1 − √1.1, 3 + √0.5].
        let (from, to) = confidence_hull(g, 3.0, 0.5, -10.0, 10.0);
        assert!((from - (-1.0 - 1.1_f64.sqrt())).abs() < 1e-6, "{from}");
        assert!((to - (3.0 + 0.5_f64.sqrt())).abs() < 1e-6, "{to}");
    }
}
