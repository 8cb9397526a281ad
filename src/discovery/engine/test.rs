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

/// The in-sample route in words, for the reports of files with at most [`IN_SAMPLE_FOLDS`]
/// folds (see [`InSample`]).
pub const IN_SAMPLE_RULE: &str = "with at most 3 folds, where a fold's training data may not fix a time \
     constant, conditions (2) and (3) may be met in-sample instead: the fit to all readings lowers the sum of \
     squares by more than noise can, its F statistic for the added parameters (the noise variance from the \
     candidate's residuals, widened by their lag-one correlation) as a normal z reaching the quantile of \
     1 - 0.025/(C G), G the grid points the candidate's new searched values were chosen among, with and without \
     the fold that gains most; condition (1) still asks the held-out RMS to drop by 5 %";

/// Files with at most this many folds may meet the held-out conditions in-sample
/// ([`InSample`]).
pub const IN_SAMPLE_FOLDS: usize = 3;
/// The least residual degrees of freedom of an in-sample test.
const MIN_IN_SAMPLE_DOF: usize = 10;

/// The in-sample route of a [`Test`], on files of at most [`IN_SAMPLE_FOLDS`] folds.
///
/// With three runs, leave-one-run-out trains each fold on two: a time constant (a heat
/// source's, a lag's) that two runs cannot fix extrapolates badly to the third, and a cause
/// whose fit to all three runs is overwhelming fails the held-out z (the unseen heat source
/// of three X runs: base model 5.5 µm in-sample, held-out 8.0; with the lost motion and the
/// heat source 6.4 held out, z 2.1 against 2.5). The fit to all readings then speaks: with
/// `SS₀` and `SS₁` the residual sums of squares of the current model and of the candidate
/// (`p₀` and `p₁` free parameters, linear and searched, [`Problem::parameters`]) over `n`
/// readings, `F = ((SS₀ − SS₁)/(p₁ − p₀)) / s²` with `s² = SS₁/(n − p₁)·(1 + ρ)/(1 − ρ)`, ρ the
/// lag-one correlation of the candidate's residuals in the order taken (a correlated residual
/// widens the noise a smooth column can pick up, as for an AR(1) series's mean). Under the
/// null F follows F(p₁ − p₀, n − p₁) for linear terms; a searched value is the best of the G
/// grid points it was chosen among, so the level is divided by G (Bonferroni; conservative,
/// neighbouring grid points being alike). F becomes a normal z by Paulson's approximation
/// ([`f_as_normal`]) and must reach `Φ⁻¹(1 − 0.025/(C·G))`, and so must the same F without the
/// gain of the fold that gains most (the evidence replicates, as condition (3) asks of the
/// held-out z). Condition (1) is unchanged: the candidate must still predict the runs held out
/// 5 % better, so that in-sample evidence never takes in a term that extrapolates worse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InSample {
    /// The in-sample F statistic as a standard normal z.
    pub z: Real,
    /// The same without the gain of the fold that gains most.
    pub rest_z: Real,
    /// The z demanded: `Φ⁻¹(1 − 0.025/(C·G))`.
    pub threshold: Real,
    /// G, the grid points the candidate's new searched values were chosen among.
    pub grid: Real,
}

impl InSample {
    /// The in-sample test of `candidate` against `current` on `folds` among `candidates`, when
    /// the file has at most [`IN_SAMPLE_FOLDS`] folds, both fits count their parameters, the
    /// candidate adds some, and at least [`MIN_IN_SAMPLE_DOF`] degrees of freedom are left.
    fn new(current: &Score, candidate: &Score, folds: &Folds, candidates: usize) -> Option<Self> {
        if folds.count > IN_SAMPLE_FOLDS
            || current.fold_ss.len() != folds.count
            || candidate.fold_ss.len() != folds.count
        {
            return None;
        }
        let (p0, p1) = (current.parameters?, candidate.parameters?);
        let added = p1.count.checked_sub(p0.count).filter(|&d| d > 0)?;
        let dof = folds
            .of_sample
            .len()
            .checked_sub(p1.count)
            .filter(|&d| d >= MIN_IN_SAMPLE_DOF)?;
        let (ss0, ss1): (Real, Real) =
            (current.fold_ss.iter().sum(), candidate.fold_ss.iter().sum());
        if !(ss1 > 0.0 && ss0.is_finite()) {
            return None;
        }
        let rho = (candidate.fold_lag_one.iter().sum::<Real>() / ss1).clamp(0.0, 0.999);
        let variance = ss1 / dof as Real * (1.0 + rho) / (1.0 - rho);
        let z_of = |gain: Real| f_as_normal(gain / added as Real / variance, added, dof);
        let gains: Vec<Real> = current
            .fold_ss
            .iter()
            .zip(&candidate.fold_ss)
            .map(|(a, b)| a - b)
            .collect();
        let most = gains.iter().copied().fold(Real::NEG_INFINITY, Real::max);
        let grid = (p1.grid / p0.grid).max(1.0);
        Some(InSample {
            z: z_of(ss0 - ss1),
            rest_z: z_of(ss0 - ss1 - most),
            threshold: threshold_of(candidates as Real * grid),
            grid,
        })
    }

    /// Whether the in-sample gain is beyond noise, with and without the fold that gains most.
    pub fn significant(&self) -> bool {
        self.z >= self.threshold && self.rest_z >= self.threshold
    }
}

/// An F(d1, d2) statistic as the standard normal deviate of the same upper tail, by
/// Paulson's approximation (1942, after Wilson and Hilferty's cube root of χ²):
/// `z = ((1 − b)·F^(1/3) − (1 − a)) / √(a + b·F^(2/3))` with `a = 2/(9·d1)`, `b = 2/(9·d2)`.
/// Within 0.04 of the exact deviate up to z = 3.1 for d2 ≥ 60, erring low (against
/// acceptance) for one degree of freedom.
pub fn f_as_normal(f: Real, d1: usize, d2: usize) -> Real {
    let (a, b) = (2.0 / (9.0 * d1 as Real), 2.0 / (9.0 * d2 as Real));
    let c = f.cbrt();
    ((1.0 - b) * c - (1.0 - a)) / (a + b * c * c).sqrt()
}

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
    /// The in-sample route, on files of at most [`IN_SAMPLE_FOLDS`] folds.
    pub in_sample: Option<InSample>,
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
            in_sample: InSample::new(current, candidate, folds, candidates),
        }
    }

    /// Whether the candidate passes all three conditions.
    pub fn passes(&self) -> bool {
        self.gain >= MIN_RELATIVE_GAIN && self.significant()
    }

    /// Whether the gains are beyond noise: conditions (2) and (3) hold, whatever the pooled
    /// gain, held out or (on files of few folds) in-sample.
    pub fn significant(&self) -> bool {
        self.held_out_significant() || self.in_sample.is_some_and(|s| s.significant())
    }

    /// Whether the held-out gains alone are beyond noise.
    pub fn held_out_significant(&self) -> bool {
        self.z >= self.threshold && self.rest_z >= self.threshold
    }

    /// The evidence a significant test rests on: `held-out`, or `in-sample` when only the
    /// in-sample route ([`InSample`]) is significant; `None` when neither is.
    pub fn evidence(&self) -> Option<&'static str> {
        if self.held_out_significant() {
            Some("held-out")
        } else if self.significant() {
            Some("in-sample")
        } else {
            None
        }
    }

    /// The first condition of [`RULE`] the candidate fails, by its number there, looked at in
    /// the order 2 (the combined z is within noise on every route), 3 (the z rests on one
    /// fold), 1 (the pooled held-out RMS drops by less than [`MIN_RELATIVE_GAIN`]); `None`
    /// when it passes. A NaN fails the condition it is in.
    pub fn failed_condition(&self) -> Option<u8> {
        let combined = |z: Real, threshold: Real| !z.is_nan() && z >= threshold;
        let in_sample_combined = self.in_sample.is_some_and(|s| combined(s.z, s.threshold));
        if self.passes() {
            None
        } else if !combined(self.z, self.threshold) && !in_sample_combined {
            Some(2)
        } else if !self.significant() {
            Some(3)
        } else {
            Some(1)
        }
    }

    /// The same test among `candidates` candidates: only the thresholds change.
    pub fn among(self, candidates: usize) -> Test {
        Test {
            threshold: threshold(candidates),
            in_sample: self.in_sample.map(|s| InSample {
                threshold: threshold_of(candidates as Real * s.grid),
                ..s
            }),
            ..self
        }
    }
}

/// The z a round of `candidates` candidates demands: `Φ⁻¹(1 − 0.025/C)` (Bonferroni).
fn threshold(candidates: usize) -> Real {
    threshold_of(candidates as Real)
}

/// [`threshold`] for a number of tests that need not be whole (C·G).
fn threshold_of(tests: Real) -> Real {
    normal_quantile(1.0 - ROUND_ALPHA / tests.max(1.0))
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
