//! The measurement-independent part of discovery: held-out scoring and forward selection.
//!
//! A [`Problem`] knows its samples, its base model and its library of effects; the engine
//! scores any set of effects by cross-validation (every fit inside a fold sees only that
//! fold's training samples) and adds effects one at a time while the held-out gain is larger
//! than noise can explain ([`Test`]).

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
    /// The effect it was accepted with, when neither passed alone but the pair did.
    pub together_with: Option<E>,
    /// Its acceptance test against the model before it (for a pair: the pair's, on both).
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

/// The outcome of forward selection.
#[derive(Clone, Debug)]
pub struct Selection<E, F> {
    /// The base model's score and fit.
    pub baseline: (Score, F),
    /// Accepted effects, in order of acceptance.
    pub steps: Vec<Accepted<E, F>>,
    /// The candidates of the last round, none of which passed, with their scores.
    pub rejected: Vec<Rejected<E>>,
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
            steps.push(Accepted {
                effect,
                evidence,
                score,
                fit,
                together_with: None,
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
            steps.push(Accepted {
                effect: a,
                evidence: evidence_a,
                score: score_a,
                fit: fit_a,
                together_with: Some(b),
                test,
            });
            steps.push(Accepted {
                effect: b,
                evidence: evidence_b,
                score,
                fit,
                together_with: Some(a),
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
}
