//! The measurement-independent part of discovery: held-out scoring, forward selection and the
//! stepwise search that can back out of a wrong step.
//!
//! A [`Problem`] knows its samples, its base model and its library of effects; the engine
//! scores any set of effects by cross-validation (every fit inside a fold sees only that
//! fold's training samples). [`forward_selection`] adds effects one at a time (a pair when no
//! single one passes) while the held-out gain is larger than noise can explain ([`Test`]).
//! [`stepwise_selection`] moves by the same test but can also add a block of up to three
//! effects, remove an effect that no longer helps and exchange one for another, and reports
//! the exchanges the data cannot rule out ([`Alternative`]).

use crate::math::Real;

/// How samples are split for cross-validation.
#[derive(Clone, Debug, PartialEq)]
pub struct Folds {
    /// What the split is, for reports (e.g. `leave-one-run-out`).
    pub scheme: String,
    /// The fold of every sample.
    pub of_sample: Vec<usize>,
    /// The number of folds.
    pub count: usize,
    /// Every sample in the order it was taken: neighbours in it that share a fold are where
    /// the acceptance test looks for correlated residuals ([`Test`]).
    pub sequence: Vec<usize>,
}

impl Folds {
    /// Folds given by the fold of every sample, the samples taken in the table's order.
    pub fn new(scheme: String, of_sample: Vec<usize>, count: usize) -> Folds {
        let sequence = (0..of_sample.len()).collect();
        Folds {
            scheme,
            of_sample,
            count,
            sequence,
        }
    }

    /// One fold per group (e.g. per run), the samples taken in the table's order.
    pub fn leave_one_group_out(groups: &[usize], scheme: &str) -> Folds {
        Folds::new(
            scheme.into(),
            groups.to_vec(),
            groups.iter().max().map_or(0, |g| g + 1),
        )
    }

    /// `k` contiguous blocks of `order` (sample indices in the order they were taken), as
    /// equal as possible.
    pub fn contiguous(order: &[usize], k: usize) -> Folds {
        let n = order.len();
        let k = k.min(n).max(1);
        let mut of_sample = vec![0; n];
        for (position, &sample) in order.iter().enumerate() {
            of_sample[sample] = position * k / n;
        }
        Folds {
            scheme: format!("contiguous {k}-fold"),
            of_sample,
            count: k,
            sequence: order.to_vec(),
        }
    }

    /// The training mask of fold `k` (every sample not in it).
    pub fn training(&self, k: usize) -> Vec<bool> {
        self.of_sample.iter().map(|&f| f != k).collect()
    }
}

/// A measurement whose model can be extended by effects.
pub trait Problem {
    /// An effect of the library.
    type Effect: Copy + Eq + std::fmt::Debug;
    /// A fitted model.
    type Fit: Clone;

    /// The effect's stable identifier (for progress messages).
    fn id(&self, effect: Self::Effect) -> &'static str;
    /// The number of samples.
    fn n_samples(&self) -> usize;
    /// The cross-validation split.
    fn folds(&self) -> &Folds;
    /// Fits the base model plus `effects` on the samples where `train` is true (every free
    /// parameter, linear or searched, from those samples only).
    fn fit(&self, effects: &[Self::Effect], train: &[bool]) -> Self::Fit;
    /// Measured − predicted for every sample (in the problem's unit).
    fn residuals(&self, fit: &Self::Fit) -> Vec<Real>;
    /// The effects to score next: every effect the data can test that is not yet in the model
    /// (a report must not hide a candidate), each with the evidence from the residual
    /// diagnostics that points to it, in the order worth trying.
    fn proposals(&self, effects: &[Self::Effect], fit: &Self::Fit) -> Vec<(Self::Effect, String)>;
}

/// How well a set of effects predicts the data.
#[derive(Clone, Debug, PartialEq)]
pub struct Score {
    /// RMS residual of the fit to all samples.
    pub rms: Real,
    /// RMS of the held-out residuals over all folds.
    pub cv_rms: Real,
    /// Mean squared held-out residual of each fold.
    pub fold_mse: Vec<Real>,
    /// Every sample's held-out residual (measured − predicted by the fit that did not see it).
    pub held_out: Vec<Real>,
}

/// Scores `effects` on `problem`: the fit to all data and the held-out residuals. The fits
/// (all data, then each fold's training set) run in parallel; their results are gathered in
/// fold order, so the score does not depend on the thread count.
pub fn score<P: Problem + Sync>(problem: &P, effects: &[P::Effect]) -> (Score, P::Fit)
where
    P::Effect: Sync,
    P::Fit: Send,
{
    use rayon::prelude::*;
    let n = problem.n_samples();
    let folds = problem.folds();
    let mut fits: Vec<P::Fit> = (0..=folds.count)
        .into_par_iter()
        .map(|k| {
            let train = if k == 0 {
                vec![true; n]
            } else {
                folds.training(k - 1)
            };
            problem.fit(effects, &train)
        })
        .collect();
    let full = fits.remove(0);
    let rms = rms(&problem.residuals(&full));
    let mut sum = vec![0.0; folds.count];
    let mut count = vec![0usize; folds.count];
    let mut held_out = vec![0.0; n];
    for (k, fit) in fits.iter().enumerate() {
        let residuals = problem.residuals(fit);
        for (i, r) in residuals.iter().enumerate() {
            if folds.of_sample[i] == k {
                sum[k] += r * r;
                count[k] += 1;
                held_out[i] = *r;
            }
        }
    }
    let total: Real = sum.iter().sum();
    let cv_rms = (total / n.max(1) as Real).sqrt();
    let fold_mse = sum
        .iter()
        .zip(&count)
        .map(|(s, &c)| if c > 0 { s / c as Real } else { 0.0 })
        .collect();
    (
        Score {
            rms,
            cv_rms,
            fold_mse,
            held_out,
        },
        full,
    )
}

/// Root mean square.
pub fn rms(values: &[Real]) -> Real {
    if values.is_empty() {
        return 0.0;
    }
    (values.iter().map(|v| v * v).sum::<Real>() / values.len() as Real).sqrt()
}

/// The evidence of a candidate no residual diagnostic points to: it is scored all the same.
pub const NO_DIAGNOSTIC: &str = "no residual diagnostic points to it; scored all the same";

/// The smallest held-out gain accepted, relative to the current held-out RMS.
pub const MIN_RELATIVE_GAIN: Real = 0.05;
/// The family-wise false-acceptance probability of one round (all its candidates together).
pub const ROUND_ALPHA: Real = 0.025;
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
            threshold: normal_quantile(1.0 - ROUND_ALPHA / candidates.max(1) as Real),
            rest_z,
        }
    }

    /// Whether the candidate passes all three conditions.
    pub fn passes(&self) -> bool {
        self.gain >= MIN_RELATIVE_GAIN && self.z >= self.threshold && self.rest_z >= self.threshold
    }
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

/// The model after one step of discovery and what it leaves.
#[derive(Clone, Debug, PartialEq)]
pub struct ResidualStep<'a> {
    /// The model, named as the report names it (`base + effect + …`).
    pub model: String,
    /// Its held-out RMS (m).
    pub cv_rms: Real,
    /// Measured − model at every reading of the table, in the table's order (m).
    pub residuals: &'a [Real],
}

/// One accepted effect.
#[derive(Clone, Debug)]
pub struct Accepted<E, F> {
    /// The effect.
    pub effect: E,
    /// What in the residual proposed it.
    pub evidence: String,
    /// The model's score with it.
    pub score: Score,
    /// The model fitted to all data with it (and every effect before it).
    pub fit: F,
    /// The effect it was accepted with, when neither passed alone but the pair did (for a
    /// block of three: the first of the others; [`Accepted::together`] has them all).
    pub together_with: Option<E>,
    /// Every effect it entered with (its block without it; empty when it entered alone).
    pub together: Vec<E>,
    /// Its acceptance test against the model before it (for a block: the block's, on each of
    /// its effects).
    pub test: Test,
}

/// A candidate of the last round that did not pass.
#[derive(Clone, Debug, PartialEq)]
pub struct Rejected<E> {
    /// The effect.
    pub effect: E,
    /// The held-out RMS of the model with it.
    pub cv_rms: Real,
    /// Its acceptance test.
    pub test: Test,
}

/// What one move of a search did to the model.
#[derive(Clone, Debug, PartialEq)]
pub enum Action<E> {
    /// Effects added: one (a forward step) or a block that entered together.
    Add(Vec<E>),
    /// An effect removed: it no longer lowers the held-out RMS by [`MIN_RELATIVE_GAIN`].
    Remove(E),
    /// An effect of the model exchanged for one candidate or two.
    Swap {
        /// The effect that left.
        removed: E,
        /// The candidates that took its place.
        added: Vec<E>,
    },
}

/// One move of a search, in the order made.
#[derive(Clone, Debug, PartialEq)]
pub struct Move<E> {
    /// What it did.
    pub action: Action<E>,
    /// The held-out RMS of the model before the move.
    pub cv_rms_before: Real,
    /// The held-out RMS of the model after it.
    pub cv_rms: Real,
    /// The test behind it. For an addition or a swap: the new model against the one before,
    /// with the threshold of its round (it passed). For a removal: the model with the effect
    /// against the model without it, at one test's threshold (it did not pass: the effect's
    /// held-out gain was below [`MIN_RELATIVE_GAIN`]).
    pub test: Test,
}

/// A model the held-out data cannot rule out beside the final one: one effect of the final
/// model exchanged for another candidate (see [`stepwise_selection`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Alternative<E> {
    /// The final model's effect that is exchanged.
    pub removed: E,
    /// The candidate that takes its place.
    pub added: E,
    /// The exchanged model's held-out RMS.
    pub cv_rms: Real,
    /// The final model tested against the exchanged one at one test's threshold (C = 1): it
    /// does not pass, so the data do not show the final model is the better of the two.
    pub test: Test,
}

/// The outcome of a selection ([`forward_selection`] or [`stepwise_selection`]).
#[derive(Clone, Debug)]
pub struct Selection<E, F> {
    /// The base model's score and fit.
    pub baseline: (Score, F),
    /// The final model's effects in the order they entered, each scored with the effects
    /// before it: step `k` is the model up to its effect (a prefix of the final model, also
    /// when the search removed or exchanged effects on the way; [`Selection::moves`] has the
    /// path), its test that prefix against the one before its effect (or block).
    pub steps: Vec<Accepted<E, F>>,
    /// The candidates of the last round, none of which passed, with their scores.
    pub rejected: Vec<Rejected<E>>,
    /// Every move of the search in order: additions, and for [`stepwise_selection`] the
    /// removals and exchanges that backed out of earlier steps.
    pub moves: Vec<Move<E>>,
    /// Exchanges of one effect of the final model for another candidate that the data cannot
    /// rule out, lowest held-out RMS first (empty for [`forward_selection`]).
    pub alternatives: Vec<Alternative<E>>,
}

impl<E: Copy, F> Selection<E, F> {
    /// The accepted effects in order.
    pub fn effects(&self) -> Vec<E> {
        self.steps.iter().map(|s| s.effect).collect()
    }

    /// Each step's held-out gain over the model before it: (drop of the held-out RMS, the
    /// same in % of the RMS before).
    pub fn gains(&self) -> Vec<(Real, Real)> {
        let mut before = self.baseline.0.cv_rms;
        self.steps
            .iter()
            .map(|step| {
                let gain = before - step.score.cv_rms;
                let pct = 100.0 * gain / before;
                before = step.score.cv_rms;
                (gain, pct)
            })
            .collect()
    }

    /// The score and fit after the first `k` accepted effects (`k = 0`: the base model).
    pub fn after(&self, k: usize) -> (&Score, &F) {
        match k {
            0 => (&self.baseline.0, &self.baseline.1),
            k => (&self.steps[k - 1].score, &self.steps[k - 1].fit),
        }
    }

    /// The base model and each accepted effect in turn, named by `model_name(k)` (after `k`
    /// effects), with the residual of its fit.
    pub fn residual_steps<'a>(
        &'a self,
        model_name: impl Fn(usize) -> String,
        residuals: impl Fn(&'a F) -> &'a [Real],
    ) -> Vec<ResidualStep<'a>> {
        (0..=self.steps.len())
            .map(|k| {
                let (score, fit) = self.after(k);
                ResidualStep {
                    model: model_name(k),
                    cv_rms: score.cv_rms,
                    residuals: residuals(fit),
                }
            })
            .collect()
    }

    /// Each accepted step as JSON: the kind's own keys (`effect`, `cause`, `params`, …) from
    /// `keys`, and the scores every kind reports — `evidence`, `rms_um`, `cv_rms_um`,
    /// `fold_cv_rms_um` ([`folds_json`]) and the gain over the step before, `gain_um` and
    /// `gain_pct` — rounded by [`round_json`].
    pub fn steps_json(
        &self,
        keys: impl Fn(&Accepted<E, F>) -> serde_json::Map<String, serde_json::Value>,
    ) -> Vec<serde_json::Value> {
        let um = |v: Real| round_json(v / crate::math::M_PER_UM);
        self.steps
            .iter()
            .zip(self.gains())
            .map(|(step, (gain, pct))| {
                let mut object = keys(step);
                object.insert("evidence".into(), step.evidence.clone().into());
                object.insert("rms_um".into(), um(step.score.rms));
                object.insert("cv_rms_um".into(), um(step.score.cv_rms));
                object.insert("fold_cv_rms_um".into(), folds_json(&step.score));
                object.insert("gain_um".into(), um(gain));
                object.insert("gain_pct".into(), round_json(pct));
                test_keys(&mut object, &step.test);
                serde_json::Value::Object(object)
            })
            .collect()
    }

    /// The final model's score and fit.
    pub fn last(&self) -> (&Score, &F) {
        match self.steps.last() {
            Some(step) => (&step.score, &step.fit),
            None => (&self.baseline.0, &self.baseline.1),
        }
    }

    /// Whether the search backed out of an earlier step: some move removed or exchanged an
    /// effect, so the path ([`Selection::moves`]) differs from the final model's steps.
    pub fn backed_out(&self) -> bool {
        self.moves
            .iter()
            .any(|m| !matches!(m.action, Action::Add(_)))
    }

    /// The moves as JSON, in order: `action` (`add`, `remove` or `swap`), `added` and
    /// `removed` (effect ids from `id`, lists), `cv_rms_before_um`, `cv_rms_um`, `change_pct`
    /// (of the held-out RMS, negative when it dropped) and the move's test (`gain_z`, `rest_z`,
    /// `z_needed`; for a removal the removed effect's test against the model without it, at
    /// one test's threshold), rounded by [`round_json`].
    pub fn moves_json(&self, id: impl Fn(E) -> String) -> Vec<serde_json::Value> {
        let um = |v: Real| round_json(v / crate::math::M_PER_UM);
        let ids = |effects: &[E]| -> serde_json::Value {
            effects
                .iter()
                .map(|&e| serde_json::Value::from(id(e)))
                .collect()
        };
        self.moves
            .iter()
            .map(|m| {
                let (action, added, removed) = match &m.action {
                    Action::Add(effects) => ("add", effects.clone(), Vec::new()),
                    Action::Remove(effect) => ("remove", Vec::new(), vec![*effect]),
                    Action::Swap { removed, added } => ("swap", added.clone(), vec![*removed]),
                };
                let mut object = serde_json::Map::new();
                object.insert("action".into(), action.into());
                object.insert("added".into(), ids(&added));
                object.insert("removed".into(), ids(&removed));
                object.insert("cv_rms_before_um".into(), um(m.cv_rms_before));
                object.insert("cv_rms_um".into(), um(m.cv_rms));
                object.insert(
                    "change_pct".into(),
                    round_json(change_pct(m.cv_rms_before, m.cv_rms)),
                );
                test_keys(&mut object, &m.test);
                serde_json::Value::Object(object)
            })
            .collect()
    }

    /// The moves for people, numbered, with the held-out RMS before and after each and the test
    /// behind it, held-out RMS to `decimals` µm; empty unless the search backed out
    /// ([`Selection::backed_out`]): otherwise the accepted steps are the path.
    pub fn moves_text(&self, id: impl Fn(E) -> String, decimals: usize) -> String {
        if !self.backed_out() {
            return String::new();
        }
        let um = |v: Real| crate::math::fixed(v / crate::math::M_PER_UM, decimals);
        let list = |effects: &[E]| {
            effects
                .iter()
                .map(|&e| id(e))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut out = String::from(
            "\nThe search backed out of earlier steps; its moves in order (held-out RMS before → after):\n",
        );
        for (k, m) in self.moves.iter().enumerate() {
            let what = match &m.action {
                Action::Add(effects) => format!("added {}", list(effects)),
                Action::Remove(effect) => format!("removed {}", id(*effect)),
                Action::Swap { removed, added } => {
                    format!("exchanged {} for {}", id(*removed), list(added))
                }
            };
            let why = match &m.action {
                Action::Remove(_) => format!(
                    "no longer worth a term: its held-out gain {:+.1} % (5 % needed), z {:.1}, without the best fold {:.1}",
                    100.0 * m.test.gain,
                    m.test.z,
                    m.test.rest_z
                ),
                _ => test_text(&m.test),
            };
            out.push_str(&format!(
                "  {}. {what}: {} → {} µm ({why})\n",
                k + 1,
                um(m.cv_rms_before),
                um(m.cv_rms)
            ));
        }
        out.push_str("The accepted effects below are the final model's, in the order they entered, each scored with those before it.\n");
        out
    }

    /// The alternatives as JSON, lowest held-out RMS first: `effect` (the candidate that comes
    /// in, from `id`), `instead_of` (the final model's effect it replaces), `cv_rms_um`,
    /// `change_pct` (its held-out RMS against the final model's, in %) and the final model's
    /// test against it (`gain_z`, `rest_z`, `z_needed`), rounded by [`round_json`].
    pub fn alternatives_json(&self, id: impl Fn(E) -> String) -> Vec<serde_json::Value> {
        let last = self.last().0.cv_rms;
        self.alternatives
            .iter()
            .map(|a| {
                let mut object = serde_json::Map::new();
                object.insert("effect".into(), id(a.added).into());
                object.insert("instead_of".into(), id(a.removed).into());
                object.insert(
                    "cv_rms_um".into(),
                    round_json(a.cv_rms / crate::math::M_PER_UM),
                );
                object.insert("change_pct".into(), round_json(change_pct(last, a.cv_rms)));
                test_keys(&mut object, &a.test);
                serde_json::Value::Object(object)
            })
            .collect()
    }

    /// The alternatives for people, one per line (held-out RMS to `decimals` µm), or a line
    /// saying there is none when the final model has effects. For a selection from
    /// [`stepwise_selection`] (forward selection does not look for alternatives).
    pub fn alternatives_text(&self, id: impl Fn(E) -> String, decimals: usize) -> String {
        if self.steps.is_empty() {
            return String::new();
        }
        if self.alternatives.is_empty() {
            return "\nNo alternative: exchanging any effect of the final model for another candidate either does nothing or gives a model the final one beats by the held-out rule.\n".into();
        }
        let last = self.last().0.cv_rms;
        let mut out = String::from(
            "\nAlternatives the held-out data cannot rule out (one effect of the final model exchanged for another candidate; the final model does not beat them by the rule at one test's threshold — two causes this file cannot separate):\n",
        );
        for a in &self.alternatives {
            out.push_str(&format!(
                "  {} instead of {}: held-out RMS {} µm ({:+.1} % on the final model's); the final model's z {:.1}, without the best fold {:.1}, ≥ {:.2}\n",
                id(a.added),
                id(a.removed),
                crate::math::fixed(a.cv_rms / crate::math::M_PER_UM, decimals),
                change_pct(last, a.cv_rms),
                a.test.z,
                a.test.rest_z,
                a.test.threshold
            ));
        }
        out
    }
}

/// The change of a held-out RMS from `before` to `after`, in % of `before`.
fn change_pct(before: Real, after: Real) -> Real {
    if before > 0.0 {
        100.0 * (after / before - 1.0)
    } else {
        0.0
    }
}

/// Forward selection: from the base model, score every proposed effect by held-out RMS and
/// accept the best one that passes its [`Test`]; when none does, accept the best pair of
/// proposed effects that passes (two terms that only together explain the residual, e.g. a
/// sensor that warms both sooner and more than the screw); repeat until nothing passes.
/// `progress` hears about each test.
pub fn forward_selection<P: Problem + Sync>(
    problem: &P,
    mut progress: impl FnMut(&str),
) -> Selection<P::Effect, P::Fit>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let baseline = score(problem, &[]);
    let folds = problem.folds();
    let mut steps: Vec<Accepted<P::Effect, P::Fit>> = Vec::new();
    let mut effects: Vec<P::Effect> = Vec::new();
    let mut moves: Vec<Move<P::Effect>> = Vec::new();
    loop {
        let (current, current_fit) = match steps.last() {
            Some(step) => (&step.score, &step.fit),
            None => (&baseline.0, &baseline.1),
        };
        let proposals = problem.proposals(&effects, current_fit);
        let mut tested: Tested<P> = Vec::new();
        for (effect, evidence) in proposals {
            progress(&format!("testing {}", problem.id(effect)));
            let mut trial = effects.clone();
            trial.push(effect);
            let (candidate, fit) = score(problem, &trial);
            tested.push((effect, evidence, candidate, fit));
        }
        let tests: Vec<Test> = tested
            .iter()
            .map(|(_, _, candidate, _)| Test::new(current, candidate, folds, tested.len()))
            .collect();
        let best = (0..tested.len())
            .filter(|&i| tests[i].passes())
            .min_by(|&a, &b| tested[a].2.cv_rms.total_cmp(&tested[b].2.cv_rms));
        if let Some(i) = best {
            let (effect, evidence, score, fit) = tested.swap_remove(i);
            effects.push(effect);
            moves.push(Move {
                action: Action::Add(vec![effect]),
                cv_rms_before: current.cv_rms,
                cv_rms: score.cv_rms,
                test: tests[i],
            });
            steps.push(Accepted {
                effect,
                evidence,
                score,
                fit,
                together_with: None,
                together: Vec::new(),
                test: tests[i],
            });
            continue;
        }
        if let Some((first, second, score, fit, test)) =
            best_pair(problem, &effects, current, &tested, &mut progress)
        {
            // Both enter: the first with its own score (what it does alone), the second with
            // the pair's, so each step reads "the model up to here".
            let (a, b) = (tested[first].0, tested[second].0);
            let take = |i: usize| tested[i].clone();
            let (_, evidence_a, score_a, fit_a) = take(first);
            let (_, evidence_b, _, _) = take(second);
            effects.extend([a, b]);
            moves.push(Move {
                action: Action::Add(vec![a, b]),
                cv_rms_before: current.cv_rms,
                cv_rms: score.cv_rms,
                test,
            });
            steps.push(Accepted {
                effect: a,
                evidence: evidence_a,
                score: score_a,
                fit: fit_a,
                together_with: Some(b),
                together: vec![b],
                test,
            });
            steps.push(Accepted {
                effect: b,
                evidence: evidence_b,
                score,
                fit,
                together_with: Some(a),
                together: vec![a],
                test,
            });
            continue;
        }
        let rejected = tested
            .into_iter()
            .zip(tests)
            .map(|((effect, _, score, _), test)| Rejected {
                effect,
                cv_rms: score.cv_rms,
                test,
            })
            .collect();
        return Selection {
            baseline,
            steps,
            rejected,
            moves,
            alternatives: Vec::new(),
        };
    }
}

/// Tested candidates: effect, evidence, score, fit.
type Tested<P> = Vec<(<P as Problem>::Effect, String, Score, <P as Problem>::Fit)>;

/// The best pair of `tested` that passes its [`Test`] against `current` (among all pairs of
/// the round): the indices (the better of the two alone first), the pair's score, fit and test.
fn best_pair<P: Problem + Sync>(
    problem: &P,
    effects: &[P::Effect],
    current: &Score,
    tested: &Tested<P>,
    progress: &mut impl FnMut(&str),
) -> Option<(usize, usize, Score, P::Fit, Test)>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let pairs = tested.len() * tested.len().saturating_sub(1) / 2;
    let mut best: Option<(usize, usize, Score, P::Fit, Test)> = None;
    for i in 0..tested.len() {
        for j in i + 1..tested.len() {
            let (a, b) = if tested[i].2.cv_rms <= tested[j].2.cv_rms {
                (i, j)
            } else {
                (j, i)
            };
            progress(&format!(
                "testing {} with {}",
                problem.id(tested[a].0),
                problem.id(tested[b].0)
            ));
            let (pair, fit) = score(problem, &[effects, &[tested[a].0, tested[b].0]].concat());
            let test = Test::new(current, &pair, problem.folds(), pairs);
            if test.passes()
                && best
                    .as_ref()
                    .is_none_or(|(_, _, s, _, _)| pair.cv_rms < s.cv_rms)
            {
                best = Some((a, b, pair, fit, test));
            }
        }
    }
    best
}

/// The most effects one addition of [`stepwise_selection`] brings in together (a block).
pub const LARGEST_BLOCK: usize = 3;

/// The stepwise search in words, for reports (each move's test is the one [`RULE`] describes).
pub const STEPWISE_RULE: &str = "a search by held-out RMS in moves, each judged by one test: a candidate passes when \
     it (1) lowers the pooled held-out RMS by at least 5 %, (2) has held-out gains sum(r0^2 - r1^2) whose per-fold z \
     (the gain over its standard error under noise with the fold's variance and lag-one correlation, from the \
     candidate's held-out residuals), combined by Stouffer with each fold weighted by the z it would have if the \
     candidate were true, reach the normal quantile of 1 - 0.025/C for the C candidates of its kind (Bonferroni), and \
     (3) still reaches it without the fold that contributes most. ADD the best passing single effect (C the singles), \
     or a block of two or three that passes (C all the blocks of its size; every pair is scored, and the \
     best-scoring pair with each other candidate) with every effect earning its place (passing added to the rest of \
     the block at the singles' threshold; when no single effect passes, lowering the block's held-out RMS by 5 %) \
     when no single passes or its held-out RMS is 5 % lower than the best single's. REMOVE, after every addition or \
     swap, while the model without one of its effects has a held-out RMS less than 5 % higher (the effect is no \
     longer worth a term), the effect whose removal leaves the lowest. SWAP, when nothing can be added, one effect of \
     the model for one candidate or two (each of two lowering the held-out RMS by 5 %): the exchange with the lowest \
     held-out RMS among those that pass against the model (C the exchanges). Never back to a model already visited; \
     stop when nothing moves. Alternatives: the exchanges of one effect of the final model for one candidate that \
     the final model does not beat by (1)-(3) with C = 1";

/// Every model a search has scored: its effects (in the order they were fitted), its score
/// and its fit. A model is found again by its set of effects.
struct Book<'a, P: Problem> {
    problem: &'a P,
    models: Vec<(Vec<P::Effect>, Score, P::Fit)>,
    /// The models the search has been at (indices into `models`): it never moves back to one.
    visited: Vec<usize>,
}

impl<'a, P: Problem + Sync> Book<'a, P>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    fn new(problem: &'a P) -> Self {
        Book {
            problem,
            models: Vec::new(),
            visited: Vec::new(),
        }
    }

    /// Whether the search has been at the model with `effects`.
    fn visited(&self, effects: &[P::Effect]) -> bool {
        self.find(effects)
            .is_some_and(|i| self.visited.contains(&i))
    }

    /// Where the model with `effects` (in any order) is, if it has been scored.
    fn find(&self, effects: &[P::Effect]) -> Option<usize> {
        self.models.iter().position(|(scored, _, _)| {
            scored.len() == effects.len() && effects.iter().all(|e| scored.contains(e))
        })
    }

    /// Where each model of `models` is, scoring (and naming to `progress`) those not scored
    /// yet. They are scored in parallel and gathered in the order given, so the book does not
    /// depend on the thread count.
    fn score_all(
        &mut self,
        models: &[Vec<P::Effect>],
        progress: &mut dyn FnMut(&str),
    ) -> Vec<usize> {
        use rayon::prelude::*;
        let mut missing: Vec<Vec<P::Effect>> = Vec::new();
        for model in models {
            let known = self.find(model).is_some()
                || missing
                    .iter()
                    .any(|m| m.len() == model.len() && model.iter().all(|e| m.contains(e)));
            if !known {
                progress(&format!("testing {}", self.name(model)));
                missing.push(model.clone());
            }
        }
        let problem = self.problem;
        let scored: Vec<(Score, P::Fit)> = missing
            .par_iter()
            .map(|model| score(problem, model))
            .collect();
        for (model, (score, fit)) in missing.into_iter().zip(scored) {
            self.models.push((model, score, fit));
        }
        models
            .iter()
            .map(|model| self.find(model).expect("scored above"))
            .collect()
    }

    /// Where one model is, scoring it if needed.
    fn at(&mut self, effects: &[P::Effect], progress: &mut dyn FnMut(&str)) -> usize {
        self.score_all(&[effects.to_vec()], progress)[0]
    }

    fn score(&self, i: usize) -> &Score {
        &self.models[i].1
    }

    fn fit(&self, i: usize) -> &P::Fit {
        &self.models[i].2
    }

    /// A model's effects for progress messages: `base + a + b`.
    fn name(&self, effects: &[P::Effect]) -> String {
        let mut name = String::from("base");
        for &e in effects {
            name.push_str(" + ");
            name.push_str(self.problem.id(e));
        }
        name
    }
}

/// An effect of the model during a search: what pointed to it, the move that brought it in
/// and the number of candidates of that move's family (its test's C).
struct Member<E> {
    effect: E,
    evidence: String,
    entered: usize,
    family: usize,
}

/// The number of `k`-subsets of `n` things.
fn subsets(n: usize, k: usize) -> usize {
    if k > n {
        return 0;
    }
    (0..k).fold(1, |c, i| c * (n - i) / (i + 1))
}

/// Stepwise selection: forward steps by the held-out rule ([`Test`]), with blocks, removals
/// and exchanges, so that a term taken early that mimics a combination of others can leave.
///
/// From the base model, each round:
///
/// 1. **Add.** Every proposed effect is scored added to the model (C = the proposals), every
///    pair of proposals, and the best-scoring pair with each other proposal (triples, up to
///    [`LARGEST_BLOCK`]); a block is tested against the model with C = all the blocks of its
///    size (Bonferroni over the whole family, so scoring only some triples is conservative).
///    A block must also have every one of its effects earn its place: when some single
///    effect passes, each effect of the block must pass its [`Test`] added to the rest of the
///    block at the singles' threshold (no effect rides on another); when none passes — the
///    residual needs several effects at once, the case [`forward_selection`] meets with a
///    pair — each must lower the block's held-out RMS by at least [`MIN_RELATIVE_GAIN`]
///    (forward selection takes a pair without asking). The best single that passes enters,
///    unless the best block that passes has a held-out RMS at least [`MIN_RELATIVE_GAIN`]
///    lower (its extra effects must be worth their terms): a block that explains what the
///    best single only mimics then enters instead; with no single passing, the best block.
/// 2. **Remove**, after every addition or swap: while the model without one of its effects
///    has a held-out RMS less than [`MIN_RELATIVE_GAIN`] higher than the model's, that effect
///    is no longer worth a term by the rule's own measure (others now explain what it
///    absorbed); the one whose removal leaves the lowest held-out RMS leaves, and the check
///    repeats. Entering asks a significant gain of 5 % or more, staying only the 5 %: as in
///    classical stepwise regression, the bar to leave is lower than the bar to enter, so an
///    effect that just entered does not leave at once.
/// 3. **Swap**, when nothing can be added: every effect of the model exchanged for every
///    proposal and for every pair of proposals (a term that mimics two others gives way to
///    them; each of a pair must lower the exchanged model's held-out RMS by
///    [`MIN_RELATIVE_GAIN`]); the exchange with the lowest held-out RMS among those that pass
///    their [`Test`] against the model (C = the exchanges) is made, then step 2.
///
/// It stops when nothing moves. Every addition and swap passes the rule's condition (1) and
/// so lowers the held-out RMS by at least [`MIN_RELATIVE_GAIN`]; a removal raises it by less
/// than that and shrinks the model. The search keeps the models it has been at and never
/// moves to one of them again (an effect that left cannot come straight back anyway: its
/// gain is below the 5 % an addition needs), so it visits each of the finitely many models at
/// most once and ends.
///
/// On a file with no effect in it the first round is the only one: the singles and pairs that
/// [`forward_selection`] tests, and the triples, whose family adds at most 2.5 % to the bound
/// on a false acceptance (removal and swaps only act on a model that has effects).
///
/// The returned [`Selection`] has the final model's effects as `steps` (each a prefix scored
/// again), the path as `moves`, the last round's single candidates as `rejected`, and as
/// `alternatives` the exchanges of one final effect for one candidate (scored in the last
/// swap round) that the final model does not beat by the rule at one test's threshold
/// (C = 1), in which the incoming effect does something (the exchanged model has a lower
/// held-out RMS than the final model without the outgoing effect): two causes the file cannot
/// separate. Every scored model is kept (score and fit) and found again by its effects, so no
/// model is fitted twice; models are scored in parallel and gathered in order, so the result
/// does not depend on the thread count. `progress` hears about each model scored.
pub fn stepwise_selection<P: Problem + Sync>(
    problem: &P,
    mut progress: impl FnMut(&str),
) -> Selection<P::Effect, P::Fit>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let progress: &mut dyn FnMut(&str) = &mut progress;
    let folds = problem.folds();
    let mut book = Book::new(problem);
    let mut model: Vec<Member<P::Effect>> = Vec::new();
    let mut moves: Vec<Move<P::Effect>> = Vec::new();
    loop {
        let effects: Vec<P::Effect> = model.iter().map(|m| m.effect).collect();
        let here = book.at(&effects, progress);
        if !book.visited.contains(&here) {
            book.visited.push(here);
        }
        let current = book.score(here).clone();
        let proposals = problem.proposals(&effects, book.fit(here));
        let with = |extra: &[P::Effect]| [effects.as_slice(), extra].concat();
        // Singles, then the proposals ranked by what each does alone (a block lists its
        // effects in that order, the better alone first).
        let singles: Vec<Vec<P::Effect>> = proposals.iter().map(|(e, _)| with(&[*e])).collect();
        let single_at = book.score_all(&singles, progress);
        let single_tests: Vec<Test> = single_at
            .iter()
            .map(|&i| Test::new(&current, book.score(i), folds, proposals.len()))
            .collect();
        let best_single = (0..proposals.len())
            .filter(|&i| single_tests[i].passes() && !book.visited(&singles[i]))
            .min_by(|&a, &b| {
                book.score(single_at[a])
                    .cv_rms
                    .total_cmp(&book.score(single_at[b]).cv_rms)
            });
        let mut ranked: Vec<usize> = (0..proposals.len()).collect();
        ranked.sort_by(|&a, &b| {
            book.score(single_at[a])
                .cv_rms
                .total_cmp(&book.score(single_at[b]).cv_rms)
        });
        // A block competes with the best single: when a single passes, each of the block's
        // effects must pass as a single added to the rest of the block.
        let block = best_block(
            &mut book,
            &effects,
            &current,
            &proposals,
            &ranked,
            &single_at,
            best_single.map(|_| proposals.len()),
            progress,
        );
        let single = best_single.map(|i| (vec![i], single_at[i], single_tests[i], proposals.len()));
        // A block wins over a passing single only when its extra effects are worth their
        // terms: its held-out RMS at least MIN_RELATIVE_GAIN below the single's.
        let addition = match (single, block) {
            (Some(single), Some(block))
                if Test::new(book.score(single.1), book.score(block.1), folds, 1).gain
                    >= MIN_RELATIVE_GAIN =>
            {
                Some(block)
            }
            (Some(single), _) => Some(single),
            (None, block) => block,
        };
        if let Some((block, at, test, family)) = addition {
            let added: Vec<P::Effect> = block.iter().map(|&i| proposals[i].0).collect();
            for &i in &block {
                model.push(Member {
                    effect: proposals[i].0,
                    evidence: proposals[i].1.clone(),
                    entered: moves.len(),
                    family,
                });
            }
            moves.push(Move {
                action: Action::Add(added),
                cv_rms_before: current.cv_rms,
                cv_rms: book.score(at).cv_rms,
                test,
            });
            remove_idle(&mut book, &mut model, &mut moves, progress);
            continue;
        }
        if model.is_empty() {
            return finish(
                &mut book,
                model,
                single_at,
                single_tests,
                &proposals,
                moves,
                Vec::new(),
                progress,
            );
        }
        // Exchanges of one effect for one proposal, then for two (a term that mimics a
        // combination of two others gives way to them).
        let n = proposals.len();
        let mut exchanges: Vec<(usize, Vec<usize>, Vec<P::Effect>)> = Vec::new();
        for size in 1..=2 {
            for j in 0..model.len() {
                let incoming: Vec<Vec<usize>> = if size == 1 {
                    ranked.iter().map(|&i| vec![i]).collect()
                } else {
                    (0..n)
                        .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
                        .map(|(a, b)| vec![ranked[a], ranked[b]])
                        .collect()
                };
                for added in incoming {
                    let mut swapped: Vec<P::Effect> = effects.clone();
                    swapped.remove(j);
                    swapped.extend(added.iter().map(|&i| proposals[i].0));
                    exchanges.push((j, added, swapped));
                }
            }
        }
        let models: Vec<Vec<P::Effect>> = exchanges.iter().map(|(_, _, m)| m.clone()).collect();
        let at = book.score_all(&models, progress);
        let family = exchanges.len();
        let tests: Vec<Test> = at
            .iter()
            .map(|&i| Test::new(&current, book.score(i), folds, family))
            .collect();
        // Two incoming effects must each be worth a term in the exchanged model: without
        // either, the model (the one-for-one exchange) is at least MIN_RELATIVE_GAIN worse.
        let worth = |k: usize| {
            let (j, added, _) = &exchanges[k];
            added.len() == 1
                || added.iter().all(|&leaving| {
                    exchanges
                        .iter()
                        .position(|(jj, other, _)| {
                            jj == j
                                && other.len() == 1
                                && added.contains(&other[0])
                                && other[0] != leaving
                        })
                        .is_some_and(|w| {
                            Test::new(book.score(at[w]), book.score(at[k]), folds, 1).gain
                                >= MIN_RELATIVE_GAIN
                        })
                })
        };
        let best = (0..family)
            .filter(|&k| tests[k].passes() && worth(k) && !book.visited.contains(&at[k]))
            .min_by(|&a, &b| {
                book.score(at[a])
                    .cv_rms
                    .total_cmp(&book.score(at[b]).cv_rms)
            });
        if let Some(k) = best {
            let (j, added, _) = &exchanges[k];
            let removed = model.remove(*j).effect;
            for &i in added {
                model.push(Member {
                    effect: proposals[i].0,
                    evidence: proposals[i].1.clone(),
                    entered: moves.len(),
                    family,
                });
            }
            moves.push(Move {
                action: Action::Swap {
                    removed,
                    added: added.iter().map(|&i| proposals[i].0).collect(),
                },
                cv_rms_before: current.cv_rms,
                cv_rms: book.score(at[k]).cv_rms,
                test: tests[k],
            });
            remove_idle(&mut book, &mut model, &mut moves, progress);
            continue;
        }
        // The final model: the one-for-one exchanges it does not beat, whose incoming effect
        // does something.
        let mut alternatives: Vec<Alternative<P::Effect>> = Vec::new();
        for (k, (j, added, _)) in exchanges.iter().enumerate() {
            if added.len() != 1 {
                continue;
            }
            let mut without: Vec<P::Effect> = effects.clone();
            without.remove(*j);
            let without = book.at(&without, progress);
            let exchanged = book.score(at[k]);
            let test = Test::new(exchanged, &current, folds, 1);
            if !test.passes() && exchanged.cv_rms < book.score(without).cv_rms {
                alternatives.push(Alternative {
                    removed: effects[*j],
                    added: proposals[added[0]].0,
                    cv_rms: book.score(at[k]).cv_rms,
                    test,
                });
            }
        }
        alternatives.sort_by(|a, b| a.cv_rms.total_cmp(&b.cv_rms));
        return finish(
            &mut book,
            model,
            single_at,
            single_tests,
            &proposals,
            moves,
            alternatives,
            progress,
        );
    }
}

/// The admissible block of proposals with the lowest held-out RMS (indices into `proposals`,
/// in the order of `ranked`): its book entry, test and family size (see
/// [`stepwise_selection`]). With `singles` (the round's number of single candidates, when one
/// of them passes) each effect of a block must pass its [`Test`] added to the rest of the
/// block at that round's threshold; without, it must lower the block's held-out RMS by
/// [`MIN_RELATIVE_GAIN`].
#[allow(clippy::too_many_arguments)]
fn best_block<P: Problem + Sync>(
    book: &mut Book<'_, P>,
    effects: &[P::Effect],
    current: &Score,
    proposals: &[(P::Effect, String)],
    ranked: &[usize],
    single_at: &[usize],
    singles: Option<usize>,
    progress: &mut dyn FnMut(&str),
) -> Option<(Vec<usize>, usize, Test, usize)>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let n = ranked.len();
    let folds = book.problem.folds();
    let model = |block: &[usize]| -> Vec<P::Effect> {
        effects
            .iter()
            .copied()
            .chain(block.iter().map(|&i| proposals[i].0))
            .collect()
    };
    // Every pair, its effects in ranked order.
    let pairs: Vec<Vec<usize>> = (0..n)
        .flat_map(|a| (a + 1..n).map(move |b| vec![ranked[a], ranked[b]]))
        .collect();
    let pair_at = book.score_all(
        &pairs.iter().map(|p| model(p)).collect::<Vec<_>>(),
        progress,
    );
    // The best-scoring pair with each other proposal.
    let rank_of = |i: usize| ranked.iter().position(|&r| r == i).unwrap_or(0);
    let mut triples: Vec<Vec<usize>> = Vec::new();
    if LARGEST_BLOCK >= 3
        && let Some(best) = (0..pairs.len()).min_by(|&a, &b| {
            book.score(pair_at[a])
                .cv_rms
                .total_cmp(&book.score(pair_at[b]).cv_rms)
        })
    {
        for &other in ranked.iter().filter(|i| !pairs[best].contains(i)) {
            let mut triple = [pairs[best].clone(), vec![other]].concat();
            triple.sort_by_key(|&i| rank_of(i));
            triples.push(triple);
        }
    }
    let triple_at = book.score_all(
        &triples.iter().map(|t| model(t)).collect::<Vec<_>>(),
        progress,
    );
    let mut best: Option<(Vec<usize>, usize, Test, usize)> = None;
    let families = [
        (pairs, pair_at, subsets(n, 2)),
        (triples, triple_at, subsets(n, 3)),
    ];
    for (blocks, at, family) in &families {
        for (block, &i) in blocks.iter().zip(at) {
            let score = book.score(i);
            let test = Test::new(current, score, folds, *family);
            if !test.passes()
                || book.visited.contains(&i)
                || best
                    .as_ref()
                    .is_some_and(|(_, b, _, _)| book.score(*b).cv_rms <= score.cv_rms)
            {
                continue;
            }
            // Every effect earns its place in the block (the block without it was scored with
            // the smaller blocks).
            let worth = block.iter().all(|&leaving| {
                let rest: Vec<usize> = block.iter().copied().filter(|&k| k != leaving).collect();
                let without = if rest.len() == 1 {
                    Some(single_at[rest[0]])
                } else {
                    book.find(&model(&rest))
                };
                without.is_some_and(|w| match singles {
                    Some(c) => Test::new(book.score(w), score, folds, c).passes(),
                    None => Test::new(book.score(w), score, folds, 1).gain >= MIN_RELATIVE_GAIN,
                })
            });
            if worth {
                best = Some((block.clone(), i, test, *family));
            }
        }
    }
    best
}

/// Removes, one at a time, an effect that is no longer worth a term: the model without it
/// has a held-out RMS less than [`MIN_RELATIVE_GAIN`] higher (the one whose removal leaves
/// the lowest held-out RMS first; never back to a model the search has been at). See
/// [`stepwise_selection`].
fn remove_idle<P: Problem + Sync>(
    book: &mut Book<'_, P>,
    model: &mut Vec<Member<P::Effect>>,
    moves: &mut Vec<Move<P::Effect>>,
    progress: &mut dyn FnMut(&str),
) where
    P::Effect: Sync,
    P::Fit: Send,
{
    let folds = book.problem.folds();
    while !model.is_empty() {
        let effects: Vec<P::Effect> = model.iter().map(|m| m.effect).collect();
        let here = book.at(&effects, progress);
        if !book.visited.contains(&here) {
            book.visited.push(here);
        }
        let without: Vec<Vec<P::Effect>> = (0..effects.len())
            .map(|j| {
                let mut fewer = effects.clone();
                fewer.remove(j);
                fewer
            })
            .collect();
        let at = book.score_all(&without, progress);
        let tests: Vec<Test> = at
            .iter()
            .map(|&i| Test::new(book.score(i), book.score(here), folds, 1))
            .collect();
        let Some(j) = (0..effects.len())
            .filter(|&j| tests[j].gain < MIN_RELATIVE_GAIN && !book.visited.contains(&at[j]))
            .min_by(|&a, &b| {
                book.score(at[a])
                    .cv_rms
                    .total_cmp(&book.score(at[b]).cv_rms)
            })
        else {
            return;
        };
        moves.push(Move {
            action: Action::Remove(effects[j]),
            cv_rms_before: book.score(here).cv_rms,
            cv_rms: book.score(at[j]).cv_rms,
            test: tests[j],
        });
        model.remove(j);
    }
}

/// The selection from the final model: its prefixes scored as steps (a block's test on each
/// of its effects, with the C of the move that brought it in), the last round's singles as
/// rejected candidates.
#[allow(clippy::too_many_arguments)]
fn finish<P: Problem + Sync>(
    book: &mut Book<'_, P>,
    model: Vec<Member<P::Effect>>,
    single_at: Vec<usize>,
    single_tests: Vec<Test>,
    proposals: &[(P::Effect, String)],
    moves: Vec<Move<P::Effect>>,
    alternatives: Vec<Alternative<P::Effect>>,
    progress: &mut dyn FnMut(&str),
) -> Selection<P::Effect, P::Fit>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    let folds = book.problem.folds();
    let rejected = proposals
        .iter()
        .zip(single_at.iter().zip(single_tests))
        .map(|((effect, _), (&i, test))| Rejected {
            effect: *effect,
            cv_rms: book.score(i).cv_rms,
            test,
        })
        .collect();
    let effects: Vec<P::Effect> = model.iter().map(|m| m.effect).collect();
    let prefixes: Vec<Vec<P::Effect>> =
        (0..=effects.len()).map(|k| effects[..k].to_vec()).collect();
    let at = book.score_all(&prefixes, progress);
    // Each step fitted with its effects in the order they entered (the book may hold the
    // same set fitted in another order: equal up to rounding, but the step's fit lists its
    // effects as the model's name does).
    let stale: Vec<usize> = (0..prefixes.len())
        .filter(|&k| book.models[at[k]].0 != prefixes[k])
        .collect();
    let refits: Vec<(Score, P::Fit)> = {
        use rayon::prelude::*;
        let problem = book.problem;
        stale
            .par_iter()
            .map(|&k| score(problem, &prefixes[k]))
            .collect()
    };
    let mut prefix: Vec<(Score, P::Fit)> = at
        .iter()
        .map(|&i| (book.score(i).clone(), book.fit(i).clone()))
        .collect();
    for (k, refit) in stale.into_iter().zip(refits) {
        prefix[k] = refit;
    }
    let mut steps = Vec::new();
    let mut start = 0;
    while start < model.len() {
        let end = start
            + model[start..]
                .iter()
                .take_while(|m| m.entered == model[start].entered)
                .count();
        let test = Test::new(&prefix[start].0, &prefix[end].0, folds, model[start].family);
        for (k, member) in model.iter().enumerate().take(end).skip(start) {
            let together: Vec<P::Effect> = effects[start..end]
                .iter()
                .copied()
                .filter(|&e| e != member.effect)
                .collect();
            steps.push(Accepted {
                effect: member.effect,
                evidence: member.evidence.clone(),
                score: prefix[k + 1].0.clone(),
                fit: prefix[k + 1].1.clone(),
                together_with: together.first().copied(),
                together,
                test,
            });
        }
        start = end;
    }
    Selection {
        baseline: prefix.swap_remove(0),
        steps,
        rejected,
        moves,
        alternatives,
    }
}

/// The rejected candidates as JSON: `effect` (from `id`), `cv_rms_um`, and their test
/// (`gain_z`, `rest_z`, `z_needed`).
pub fn rejected_json<E: Copy>(
    rejected: &[Rejected<E>],
    id: impl Fn(E) -> String,
) -> Vec<serde_json::Value> {
    rejected
        .iter()
        .map(|r| {
            let mut object = serde_json::Map::new();
            object.insert("effect".into(), id(r.effect).into());
            object.insert(
                "cv_rms_um".into(),
                round_json(r.cv_rms / crate::math::M_PER_UM),
            );
            test_keys(&mut object, &r.test);
            serde_json::Value::Object(object)
        })
        .collect()
}

/// A test's keys in a JSON object: `gain_z`, `z_needed`, `rest_z`.
fn test_keys(object: &mut serde_json::Map<String, serde_json::Value>, test: &Test) {
    object.insert("gain_z".into(), round_json(test.z));
    object.insert("z_needed".into(), round_json(test.threshold));
    object.insert("rest_z".into(), round_json(test.rest_z));
}

/// An accepted step's test for people: `z 12.3, without the best fold 8.1, ≥ 2.58`.
pub(crate) fn test_text(test: &Test) -> String {
    format!(
        "z {:.1}, without the best fold {:.1}, ≥ {:.2}",
        test.z, test.rest_z, test.threshold
    )
}

/// The rejected candidates for people, one per line: held-out RMS and why it failed.
pub(crate) fn rejected_text<E: Copy>(
    rejected: &[Rejected<E>],
    id: impl Fn(E) -> String,
    decimals: usize,
) -> String {
    let mut out = String::new();
    if rejected.is_empty() {
        return out;
    }
    out.push_str("\nTested and rejected (held-out RMS; held-out gain; its z, and without the fold that contributes most, against the z needed):\n");
    for r in rejected {
        out.push_str(&format!(
            "  {:<20} {} µm; {:+.1} %; z {:.1}, {:.1} / {:.2}\n",
            id(r.effect),
            crate::math::fixed(r.cv_rms / crate::math::M_PER_UM, decimals),
            100.0 * r.test.gain,
            r.test.z,
            r.test.rest_z,
            r.test.threshold,
        ));
    }
    out
}

/// Rounds a reported number to 4 decimals (0.1 nm in µm), without −0.
pub fn round_json(value: Real) -> serde_json::Value {
    serde_json::json!(
        crate::math::fixed(value, 4)
            .parse::<Real>()
            .unwrap_or(value)
    )
}

/// Each fold's held-out RMS in µm (from its mean square, rounded by [`round_json`]): the JSON's
/// `fold_cv_rms_um`, so a user sees which folds a gain comes from.
pub fn folds_json(score: &Score) -> serde_json::Value {
    serde_json::Value::Array(
        score
            .fold_mse
            .iter()
            .map(|m| round_json(m.sqrt() / crate::math::M_PER_UM))
            .collect(),
    )
}

/// Each fold's held-out RMS for people: `folds: 0.412 0.398 … µm` to `decimals`.
pub(crate) fn folds_text(score: &Score, decimals: usize) -> String {
    let values: Vec<String> = score
        .fold_mse
        .iter()
        .map(|m| crate::math::fixed(m.sqrt() / crate::math::M_PER_UM, decimals))
        .collect();
    format!("folds: {} µm", values.join(" "))
}

/// An effect's parameters for people: `key = value, …` to 3 decimals (the JSON gives 4).
pub(crate) fn params_text(params: &std::collections::BTreeMap<&'static str, Real>) -> String {
    params
        .iter()
        .map(|(k, v)| format!("{k} = {v:.3}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The heading of the final model's values in a report for people: they are the refit on all
/// data with every accepted effect, the values of `--json`'s `final`, which differ from each
/// step's values at acceptance.
pub(crate) const FINAL_VALUES: &str =
    "  values refit with every accepted effect (the --json `final`):";

/// An effect's parameters as a JSON object, rounded by [`round_json`].
pub(crate) fn params_json(
    params: &std::collections::BTreeMap<&'static str, Real>,
) -> serde_json::Value {
    serde_json::Value::Object(
        params
            .iter()
            .map(|(k, v)| (k.to_string(), round_json(*v)))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contiguous_folds_are_blocks_in_time_order() {
        // Samples taken in the order 2, 0, 1, 3, 4, 5 into 3 folds of 2.
        let folds = Folds::contiguous(&[2, 0, 1, 3, 4, 5], 3);
        assert_eq!(folds.of_sample, vec![0, 1, 0, 1, 2, 2]);
        assert_eq!(
            folds.training(1),
            vec![true, false, true, false, true, true]
        );
    }

    #[test]
    fn normal_quantile_matches_the_tables() {
        // Standard normal tables: 0.975 → 1.959964, 0.995 → 2.575829, 0.9975 → 2.807034,
        // 0.999 → 3.090232, 0.025 → −1.959964.
        for (p, z) in [
            (0.975, 1.959964),
            (0.995, 2.575829),
            (0.9975, 2.807034),
            (0.999, 3.090232),
            (0.025, -1.959964),
            (0.5, 0.0),
        ] {
            assert!((normal_quantile(p) - z).abs() < 2e-6, "{p}");
        }
    }

    /// Two folds of three readings: the gain, z and rest gain by hand.
    #[test]
    fn the_test_matches_a_hand_computation() {
        let folds = Folds::new("two".into(), vec![0, 0, 0, 1, 1, 1], 2);
        let score = |held_out: Vec<Real>| {
            let n = held_out.len() as Real;
            Score {
                rms: 0.0,
                cv_rms: (held_out.iter().map(|r| r * r).sum::<Real>() / n).sqrt(),
                fold_mse: vec![],
                held_out,
            }
        };
        let current = score(vec![2.0, -1.0, 3.0, 1.0, 2.0, -2.0]);
        let candidate = score(vec![1.0, 1.0, -1.0, 1.0, 1.0, 1.0]);
        let test = Test::new(&current, &candidate, &folds, 1);
        // Fold 0: r1 = (1, 1, −1), σ² = 1, lag-one (1 − 1)/3 = 0: ρ = 0, δ = (1, −2, 4),
        // δᵀδ = 21. Fold 1: r1 = (1, 1, 1), σ² = 1, ρ = 2/3, δ = (0, 1, −3):
        // Σδ² + 2ρ(δ1δ2 + δ2δ3) + 2ρ²δ1δ3 = 10 − 4 = 6. Gains: 14 − 3 = 11 and 9 − 3 = 6.
        let rho: Real = 2.0 / 3.0;
        let second = 10.0 + 2.0 * rho * (0.0 - 3.0);
        // Weights Σδ²/(2√(δᵀRδ)) with Σδ² = 21 and 10, σ² = 1 in both folds.
        let (d0, d1) = (2.0 * 21.0_f64.sqrt(), 2.0 * second.sqrt());
        let (z0, z1) = (11.0 / d0, 6.0 / d1);
        let (w0, w1) = (21.0 / d0, 10.0 / d1);
        let z = (w0 * z0 + w1 * z1) / (w0 * w0 + w1 * w1).sqrt();
        assert!((test.z - z).abs() < 1e-12, "{} {z}", test.z);
        // Without the fold that contributes most, the other alone (its own z).
        let rest = if w0 * z0 >= w1 * z1 { z1 } else { z0 };
        assert!((test.rest_z - rest).abs() < 1e-12);
        assert!((test.gain - (1.0 - 1.0 / (23.0_f64 / 6.0).sqrt())).abs() < 1e-12);
        assert!((test.threshold - 1.959964).abs() < 2e-6);
    }

    /// The derivation's claim: when the candidate's term is not in the data (δ fixed by the
    /// training folds, the held-out residual noise independent of it), z exceeds Φ⁻¹(0.975)
    /// at most 2.5 % of the time — for white noise, and for first-order correlated noise
    /// (ρ = 0.8) that a white-noise standard error would under-state. 4000 draws of 5 folds of
    /// 30 readings; the binomial standard deviation of a 2.5 % rate is 0.25 %.
    #[test]
    fn on_noise_z_rarely_passes_even_with_correlated_residuals() {
        use crate::math::{seeded_rng, standard_normal};
        let folds = Folds::new("five".into(), (0..150).map(|i| i / 30).collect(), 5);
        for rho in [0.0, 0.8] {
            let mut rng = seeded_rng(7, "engine null");
            let mut passes = 0;
            let draws = 4000;
            for _ in 0..draws {
                // A smooth spurious prediction change per fold and correlated noise.
                let slope = 0.05 * standard_normal(&mut rng);
                let mut noise = 0.0;
                let (mut r0, mut r1) = (Vec::new(), Vec::new());
                for i in 0..150 {
                    let fresh = standard_normal(&mut rng);
                    noise = if i % 30 == 0 {
                        fresh
                    } else {
                        rho * noise + (1.0 - rho * rho).sqrt() * fresh
                    };
                    let delta = slope * ((i % 30) as Real - 14.5) / 15.0;
                    r0.push(noise);
                    r1.push(noise - delta);
                }
                let score = |held_out: Vec<Real>| Score {
                    rms: 0.0,
                    cv_rms: 1.0,
                    fold_mse: vec![],
                    held_out,
                };
                if Test::new(&score(r0), &score(r1), &folds, 1).z >= normal_quantile(0.975) {
                    passes += 1;
                }
            }
            let rate = passes as Real / draws as Real;
            println!("ρ = {rho}: z ≥ 1.96 in {:.2} %", 100.0 * rate);
            assert!(rate <= 0.025 + 3.0 * 0.0025, "ρ = {rho}: {rate}");
        }
    }

    /// A linear problem with known truth: every effect is one column (a smooth shape of the
    /// sample index), the base model an intercept, five contiguous folds of 40 samples.
    struct Linear {
        names: Vec<&'static str>,
        columns: Vec<Vec<Real>>,
        y: Vec<Real>,
        folds: Folds,
    }

    const SAMPLES: usize = 200;

    /// A smooth shape over the samples: `sin(2π·cycles·t + phase)`, t in [0, 1).
    fn shape(cycles: Real, phase: Real) -> Vec<Real> {
        (0..SAMPLES)
            .map(|i| (std::f64::consts::TAU * cycles * i as Real / SAMPLES as Real + phase).sin())
            .collect()
    }

    impl Linear {
        /// The effects `names` with their `columns`, and data `truth` plus noise of `sigma`.
        fn new(
            names: &[&'static str],
            columns: Vec<Vec<Real>>,
            truth: &[Real],
            sigma: Real,
            seed: u64,
        ) -> Linear {
            use crate::math::{seeded_rng, standard_normal};
            let mut rng = seeded_rng(seed, "linear problem");
            let y = truth
                .iter()
                .map(|t| t + sigma * standard_normal(&mut rng))
                .collect();
            Linear {
                names: names.to_vec(),
                columns,
                y,
                folds: Folds::new(
                    "contiguous".into(),
                    (0..SAMPLES).map(|i| i / 40).collect(),
                    5,
                ),
            }
        }
    }

    impl Problem for Linear {
        type Effect = usize;
        type Fit = Vec<Real>;

        fn id(&self, effect: usize) -> &'static str {
            self.names[effect]
        }

        fn n_samples(&self) -> usize {
            SAMPLES
        }

        fn folds(&self) -> &Folds {
            &self.folds
        }

        fn fit(&self, effects: &[usize], train: &[bool]) -> Vec<Real> {
            let rows: Vec<usize> = (0..SAMPLES).filter(|&i| train[i]).collect();
            let mut design = crate::discovery::least_squares::Design::new(rows.len());
            design.push(vec![1.0; rows.len()]);
            for &e in effects {
                design.push(rows.iter().map(|&i| self.columns[e][i]).collect());
            }
            let c = design.solve(&rows.iter().map(|&i| self.y[i]).collect::<Vec<_>>());
            (0..SAMPLES)
                .map(|i| {
                    let predicted: Real = c[0]
                        + effects
                            .iter()
                            .zip(&c[1..])
                            .map(|(&e, k)| self.columns[e][i] * k)
                            .sum::<Real>();
                    self.y[i] - predicted
                })
                .collect()
        }

        fn residuals(&self, fit: &Vec<Real>) -> Vec<Real> {
            fit.clone()
        }

        fn proposals(&self, effects: &[usize], _fit: &Vec<Real>) -> Vec<(usize, String)> {
            (0..self.names.len())
                .filter(|e| !effects.contains(e))
                .map(|e| (e, NO_DIAGNOSTIC.to_string()))
                .collect()
        }
    }

    fn sorted(mut effects: Vec<usize>) -> Vec<usize> {
        effects.sort();
        effects
    }

    /// The moves of a selection, without their numbers.
    fn actions(selection: &Selection<usize, Vec<Real>>) -> Vec<Action<usize>> {
        selection.moves.iter().map(|m| m.action.clone()).collect()
    }

    /// The data are a + b. The library also has m = a + b + 0.3·d (d not in the library),
    /// which alone explains most of it: forward selection takes m first, then no single
    /// effect passes and the pair a, b enters, and it stops with m still in (three terms for
    /// two). The stepwise search scores the pair a, b in the first round beside m: each of a
    /// and b passes added to the other, and the pair predicts the held-out data better than
    /// m, so it enters instead, and m never does.
    #[test]
    fn a_first_term_that_mimics_two_true_ones_gives_way_to_them() {
        let (a, b, d) = (shape(1.3, 0.2), shape(2.1, 1.1), shape(0.6, 2.0));
        let m: Vec<Real> = (0..SAMPLES).map(|i| a[i] + b[i] + 0.3 * d[i]).collect();
        let truth: Vec<Real> = (0..SAMPLES).map(|i| a[i] + b[i]).collect();
        let names = ["m", "a", "b", "j1", "j2"];
        let columns = vec![m, a, b, shape(3.7, 0.4), shape(5.3, 2.9)];
        for seed in 1..=5 {
            let problem = Linear::new(&names, columns.clone(), &truth, 0.05, seed);
            let forward = forward_selection(&problem, |_| {});
            assert_eq!(
                actions(&forward),
                [Action::Add(vec![0]), Action::Add(vec![2, 1])],
                "seed {seed}"
            );
            let stepwise = stepwise_selection(&problem, |_| {});
            assert_eq!(actions(&stepwise), [Action::Add(vec![2, 1])], "seed {seed}");
            assert_eq!(stepwise.steps[0].together, vec![1]);
            // The final model explains the data to the noise, and the steps are its prefixes.
            let last = stepwise.last().0.cv_rms;
            assert!(last < 1.2 * 0.05, "seed {seed}: held-out RMS {last}");
            assert!(last < forward.last().0.cv_rms, "seed {seed}");
            assert_eq!(stepwise.steps[0].score, score(&problem, &[2]).0);
        }
    }

    /// The data are 3·c + a + b, with m = a + b + 0.3·d as above. The first round takes c
    /// with m (each passes added to the other; a, b and c together are not among the blocks
    /// scored, which extend the best pair). Then no single effect passes and the pair a, b
    /// enters; m now explains nothing the others do not, and the search removes it, ending on
    /// the true set with the path saying so. Forward selection keeps m.
    #[test]
    fn a_term_that_others_explain_is_removed() {
        let (a, b, c, d) = (
            shape(1.3, 0.2),
            shape(2.1, 1.1),
            shape(0.8, 0.5),
            shape(0.6, 2.0),
        );
        let m: Vec<Real> = (0..SAMPLES).map(|i| a[i] + b[i] + 0.3 * d[i]).collect();
        let truth: Vec<Real> = (0..SAMPLES).map(|i| 3.0 * c[i] + a[i] + b[i]).collect();
        let names = ["m", "a", "b", "c", "j1", "j2"];
        let columns = vec![m, a, b, c, shape(3.7, 0.4), shape(5.3, 2.9)];
        for seed in 1..=5 {
            let problem = Linear::new(&names, columns.clone(), &truth, 0.05, seed);
            let forward = forward_selection(&problem, |_| {});
            assert!(
                forward.effects().contains(&0),
                "seed {seed}: {:?}",
                forward.moves
            );
            let stepwise = stepwise_selection(&problem, |_| {});
            assert!(stepwise.backed_out());
            assert!(
                actions(&stepwise).contains(&Action::Remove(0)),
                "seed {seed}"
            );
            assert_eq!(sorted(stepwise.effects()), vec![1, 2, 3], "seed {seed}");
            assert!(stepwise.last().0.cv_rms < 1.2 * 0.05, "seed {seed}");
            // The steps are the final model's prefixes, in the order its effects entered.
            let effects = stepwise.effects();
            for (k, step) in stepwise.steps.iter().enumerate() {
                assert_eq!(step.score, score(&problem, &effects[..=k]).0);
            }
        }
    }

    /// Two effects with the same column on the data (x and x2): the final model takes one, and
    /// the exchange for the other is reported as an alternative with the same held-out RMS.
    #[test]
    fn exactly_collinear_effects_are_alternatives() {
        let (x, c) = (shape(1.0, 0.3), shape(2.6, 1.7));
        let truth: Vec<Real> = (0..SAMPLES).map(|i| 2.0 * x[i] + 1.5 * c[i]).collect();
        let names = ["x", "x2", "c", "j1", "j2"];
        let columns = vec![x.clone(), x, c, shape(3.7, 0.4), shape(5.3, 2.9)];
        for seed in 1..=5 {
            let problem = Linear::new(&names, columns.clone(), &truth, 0.05, seed);
            let selection = stepwise_selection(&problem, |_| {});
            let effects = sorted(selection.effects());
            assert!(
                effects == vec![0, 2] || effects == vec![1, 2],
                "seed {seed}: {effects:?}"
            );
            let kept = if effects[0] == 0 { 0 } else { 1 };
            let alternative = selection
                .alternatives
                .iter()
                .find(|a| a.removed == kept)
                .unwrap_or_else(|| panic!("seed {seed}: {:?}", selection.alternatives));
            assert_eq!(alternative.added, 1 - kept);
            assert!((alternative.cv_rms - selection.last().0.cv_rms).abs() < 1e-12);
            assert!(!alternative.test.passes());
            // c has no stand-in: exchanging it loses what it explains.
            assert!(
                selection.alternatives.iter().all(|a| a.removed != 2),
                "{:?}",
                selection.alternatives
            );
        }
    }

    /// Problems where many sets of effects can explain the data: seven effects, each a sparse
    /// mixture of five smooth shapes (the weights drawn once, rounded), the data e0 + e1 +
    /// 0.7·e2 and noise of 0.3, eight noise draws; and twelve random problems of eight effects.
    fn tangled_problems() -> Vec<Linear> {
        use crate::math::{seeded_rng, standard_normal};
        let base = [
            shape(0.883, 1.224),
            shape(1.880, -0.323),
            shape(2.489, -0.188),
            shape(3.525, -0.058),
            shape(4.174, -0.904),
        ];
        let weights: [[Real; 5]; 7] = [
            [1.41, 0.0, 0.0, 0.0, 0.0],
            [0.0, -1.35, -0.83, 0.0, 0.0],
            [0.0, -1.40, 0.0, 0.84, 1.08],
            [1.75, -1.09, 0.0, 1.17, 0.0],
            [-1.18, 0.0, 0.0, 2.49, -2.0],
            [0.0, 0.0, 0.0, -0.92, -1.51],
            [-0.98, 0.0, 0.0, 0.0, -0.96],
        ];
        let mixed: Vec<Vec<Real>> = weights
            .iter()
            .map(|w| {
                (0..SAMPLES)
                    .map(|i| (0..5).map(|k| w[k] * base[k][i]).sum())
                    .collect()
            })
            .collect();
        let truth: Vec<Real> = (0..SAMPLES)
            .map(|i| mixed[0][i] + mixed[1][i] + 0.7 * mixed[2][i])
            .collect();
        let names = ["e0", "e1", "e2", "e3", "e4", "e5", "e6", "e7"];
        let mut problems: Vec<Linear> = (1..=8)
            .map(|seed| Linear::new(&names[..7], mixed.clone(), &truth, 0.3, seed))
            .collect();
        for seed in 1..=12 {
            let mut rng = seeded_rng(seed, "random problem");
            let mut draw = || standard_normal(&mut rng);
            let columns: Vec<Vec<Real>> = (0..8)
                .map(|_| {
                    let (a, b, c) = (draw(), draw(), draw());
                    let (f, g) = (shape(1.0 + 3.0 * a.abs(), b), shape(0.5 + 2.0 * c.abs(), a));
                    (0..SAMPLES).map(|i| f[i] + 0.5 * c * g[i]).collect()
                })
                .collect();
            let weights = [draw(), draw(), draw()];
            let truth: Vec<Real> = (0..SAMPLES)
                .map(|i| (0..3).map(|k| weights[k] * columns[k][i]).sum())
                .collect();
            problems.push(Linear::new(&names, columns, &truth, 0.1, seed));
        }
        problems
    }

    /// On [`tangled_problems`] every move keeps the search's invariants — an addition or swap
    /// lowers the held-out RMS by at least 5 %, a removal takes an effect worth less than that,
    /// no model is visited twice — and the moves lead to the final model; the steps are its
    /// prefixes; the result is the same on one thread as on several. The problems make the
    /// search back out: removals and swaps (one effect for two) both happen among them.
    #[test]
    fn every_move_keeps_the_invariants_and_threads_do_not_change_the_result() {
        let (mut removals, mut swaps) = (0, 0);
        for (seed, problem) in tangled_problems().into_iter().enumerate() {
            let selection = stepwise_selection(&problem, |_| {});
            let mut model: Vec<usize> = Vec::new();
            let mut visited = vec![model.clone()];
            for m in &selection.moves {
                match &m.action {
                    Action::Remove(e) => {
                        assert!(m.test.gain < MIN_RELATIVE_GAIN, "{m:?}");
                        model.retain(|x| x != e);
                        removals += 1;
                    }
                    Action::Add(added) => {
                        assert!(
                            m.cv_rms <= (1.0 - MIN_RELATIVE_GAIN) * m.cv_rms_before,
                            "{m:?}"
                        );
                        model.extend(added);
                    }
                    Action::Swap { removed, added } => {
                        swaps += 1;
                        assert!(
                            m.cv_rms <= (1.0 - MIN_RELATIVE_GAIN) * m.cv_rms_before,
                            "{m:?}"
                        );
                        model.retain(|x| x != removed);
                        model.extend(added);
                    }
                }
                let set = sorted(model.clone());
                assert!(!visited.contains(&set), "seed {seed}: back to {set:?}");
                visited.push(set);
            }
            assert_eq!(sorted(model), sorted(selection.effects()));
            let effects = selection.effects();
            for (k, step) in selection.steps.iter().enumerate() {
                assert_eq!(step.score, score(&problem, &effects[..=k]).0);
            }
            let one = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap();
            let again = one.install(|| stepwise_selection(&problem, |_| {}));
            assert_eq!(again.effects(), effects);
            assert_eq!(again.moves, selection.moves);
            assert_eq!(again.alternatives, selection.alternatives);
            assert_eq!(again.last().0, selection.last().0);
        }
        println!("{removals} removals, {swaps} swaps");
        assert!(removals > 0 && swaps > 0);
    }
}
