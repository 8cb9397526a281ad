//! The held-out test that judges every move of a search ([`Test`]).

use super::*;

/// The acceptance rule in words, for reports.
pub const RULE: &str = "accept the candidate with the lowest held-out RMS among those that (1) lower the pooled held-out \
     RMS by at least 5 %, (2) have held-out gains sum(r0^2 - r1^2) whose per-fold z (the gain over its standard error \
     under noise with the fold's variance and lag-one correlation, from the candidate's held-out residuals), combined \
     by Stouffer with each fold weighted by the z it would have if the candidate were true, reach the normal quantile \
     of 1 - 0.025/C for the C candidates of the round (Bonferroni), and (3) still reach it without the fold that \
     contributes most; when no single effect passes, the best passing pair (C the pairs tested); stop when nothing \
     passes";

/// The acceptance test of a candidate against the current model (see [`RULE`]).
///
/// With `r0` and `r1` the held-out residuals of the current model and of the candidate, the
/// candidate moves every held-out prediction by `δ = r0 − r1`, and fold `k` gains
/// `G_k = Σ (r0² − r1²) = 2 Σ δ·r0 − Σ δ²`. If the candidate's extra term were not in the
/// data, `r0` would be noise independent of `δ` (`δ` comes from the training folds only), so
/// `E[G_k] = −Σ δ² ≤ 0` and `Var G_k = 4 σ_k² δ_kᵀR_kδ_k`, with σ_k² the noise variance in the
/// fold and `R_k` its correlation between the fold's readings: taken as first order (lag-one
/// coefficient `ρ_k` between neighbours in the order the readings were taken, `ρ_k^|i−j|`
/// further apart). σ_k² and ρ_k are estimated from the candidate's held-out residuals in the
/// fold — the noise left once the term is in, and no smaller than the current model's when the
/// term is spurious. Each fold gives `z_k = G_k / √Var G_k`, at most a standard normal under
/// the null and independent across folds (each fold's noise is its own). They combine by
/// Stouffer's weighted sum `z = Σ w_k z_k / √(Σ w_k²)`, still a standard normal under the
/// null, with `w_k = Σ δ_k² / √Var G_k` the z the fold would give if the candidate's change
/// were the truth — how much the candidate can act in the fold, the weights that make the sum
/// most powerful. A fold where it cannot act (a cold run, an interpolated middle run: δ ≈ 0)
/// weighs nothing instead of vetoing; one where it changes the prediction and gains nothing
/// counts against it; a within-run correlated residual (a slow drift the model misses) widens
/// the null as it should. Across the C candidates of a round the threshold is Bonferroni's
/// `Φ⁻¹(1 − 0.025/C)`. Two more conditions: the held-out RMS drops by at least
/// [`MIN_RELATIVE_GAIN`] (a gain worth a term), and the evidence replicates: without the fold
/// that contributes most (the largest `w_k z_k`), the rest still reaches the same threshold,
/// so that one run the base model happens to fit badly (a held-out reference run, a disturbed
/// run) cannot carry a term alone. (Asking only 1.96 of the rest, as for a single test, let
/// noise-only tables through: 3 of 100 five-run and 3 of 60 seven-run tables accepted a
/// thermal lag that smooths the sensor's noise, paired with another term.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Test {
    /// Relative drop of the pooled held-out RMS, `1 − after/before`.
    pub gain: Real,
    /// The folds' held-out gains in standard errors of noise, combined (weighted Stouffer).
    pub z: Real,
    /// The z the round demands.
    pub threshold: Real,
    /// The same z without the fold that contributes most.
    pub rest_z: Real,
}

impl Test {
    /// Tests `candidate` against `current` on `folds`, among `candidates` candidates in the
    /// round.
    pub fn new(current: &Score, candidate: &Score, folds: &Folds, candidates: usize) -> Test {
        let (r0, r1) = (&current.held_out, &candidate.held_out);
        let gain = if current.cv_rms > 0.0 {
            1.0 - candidate.cv_rms / current.cv_rms
        } else {
            0.0
        };
        // The noise left with the candidate in each fold (runs differ in their noise, and
        // a held-out reference run in its interpolation error): variance and lag-one
        // correlation along the fold's readings in the order they were taken.
        let count = folds.count;
        let mut previous: Vec<Option<usize>> = vec![None; count];
        let (mut lag_zero, mut lag_one, mut readings) =
            (vec![0.0; count], vec![0.0; count], vec![0usize; count]);
        for &i in &folds.sequence {
            let k = folds.of_sample[i];
            lag_zero[k] += r1[i] * r1[i];
            readings[k] += 1;
            if let Some(j) = previous[k] {
                lag_one[k] += r1[i] * r1[j];
            }
            previous[k] = Some(i);
        }
        let rho: Vec<Real> = (0..count)
            .map(|k| {
                if lag_zero[k] > 0.0 {
                    (lag_one[k] / lag_zero[k]).clamp(0.0, 0.999)
                } else {
                    0.0
                }
            })
            .collect();
        // Σ_k σ_k²·δ_kᵀR(ρ_k)δ_k, each quadratic form by the first-order recursion
        // S_i = δ_i + ρ_k·S_(i−1) along the fold.
        let mut running = vec![0.0; count];
        let mut quadratic = vec![0.0; count];
        let mut fold_gain = vec![0.0; count];
        for &i in &folds.sequence {
            let k = folds.of_sample[i];
            let delta = r0[i] - r1[i];
            running[k] = delta + rho[k] * running[k];
            quadratic[k] += delta * (2.0 * running[k] - delta);
            fold_gain[k] += r0[i] * r0[i] - r1[i] * r1[i];
        }
        // Each fold's z (its gain over its standard error) and its weight, the z it would
        // have if the candidate's change were the truth (G_k = Σδ²): how much the candidate
        // can act in the fold. Folds where it does not change the prediction weigh nothing.
        let mut delta_squared = vec![0.0; count];
        for &i in &folds.sequence {
            let delta = r0[i] - r1[i];
            delta_squared[folds.of_sample[i]] += delta * delta;
        }
        let weighted: Vec<(Real, Real)> = (0..count)
            .filter(|&k| readings[k] > 0 && quadratic[k] > 0.0 && lag_zero[k] > 0.0)
            .map(|k| {
                let deviation = 2.0 * (lag_zero[k] / readings[k] as Real * quadratic[k]).sqrt();
                (fold_gain[k] / deviation, delta_squared[k] / deviation)
            })
            .collect();
        let stouffer = |values: &[(Real, Real)]| {
            let norm = values.iter().map(|(_, w)| w * w).sum::<Real>().sqrt();
            if norm > 0.0 {
                values.iter().map(|(z, w)| w * z).sum::<Real>() / norm
            } else {
                0.0
            }
        };
        let z = stouffer(&weighted);
        let mut rest = weighted.clone();
        let contribution = |&(z, w): &(Real, Real)| z * w;
        if let Some(best) = (0..rest.len())
            .max_by(|&a, &b| contribution(&rest[a]).total_cmp(&contribution(&rest[b])))
        {
            rest.swap_remove(best);
        }
        let rest_z = stouffer(&rest);
        Test {
            gain,
            z,
            threshold: threshold(candidates),
            rest_z,
        }
    }

    /// Whether the candidate passes all three conditions.
    pub fn passes(&self) -> bool {
        self.gain >= MIN_RELATIVE_GAIN && self.significant()
    }

    /// Whether the held-out gains are beyond noise: conditions (2) and (3) hold, whatever the
    /// pooled gain.
    pub fn significant(&self) -> bool {
        self.z >= self.threshold && self.rest_z >= self.threshold
    }

    /// The first condition of [`RULE`] the candidate fails, by its number there, looked at in
    /// the order 2 (the combined z is within noise), 3 (the z rests on one fold), 1 (the pooled
    /// held-out RMS drops by less than [`MIN_RELATIVE_GAIN`]); `None` when it passes. A NaN
    /// fails the condition it is in.
    pub fn failed_condition(&self) -> Option<u8> {
        if self.passes() {
            None
        } else if self.z.is_nan() || self.z < self.threshold {
            Some(2)
        } else if self.rest_z.is_nan() || self.rest_z < self.threshold {
            Some(3)
        } else {
            Some(1)
        }
    }

    /// The same test among `candidates` candidates: only the threshold changes.
    pub fn among(self, candidates: usize) -> Test {
        Test {
            threshold: threshold(candidates),
            ..self
        }
    }
}

/// The z a round of `candidates` candidates demands: `Φ⁻¹(1 − 0.025/C)` (Bonferroni).
fn threshold(candidates: usize) -> Real {
    normal_quantile(1.0 - ROUND_ALPHA / candidates.max(1) as Real)
}

/// The standard normal quantile `Φ⁻¹(p)` for `0 < p < 1`, by Acklam's rational approximation
/// (relative error below 1.2·10⁻⁹, far finer than a threshold needs). The coefficients are
/// the published ones, digit for digit.
#[allow(clippy::excessive_precision)]
pub fn normal_quantile(p: Real) -> Real {
    const A: [Real; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.383577518672690e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [Real; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [Real; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [Real; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    let tail = |q: Real| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    const LOW: Real = 0.02425;
    if p <= 0.0 {
        Real::NEG_INFINITY
    } else if p >= 1.0 {
        Real::INFINITY
    } else if p < LOW {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - LOW {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}
