//! The measurement-independent part of discovery: held-out scoring and forward selection.
//!
//! A [`Problem`] knows its samples, its base model and its library of effects; the engine
//! scores any set of effects by cross-validation (every fit inside a fold sees only that
//! fold's training samples) and adds effects one at a time while the held-out gain is larger
//! than noise can explain ([`passes`]).

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
}

impl Folds {
    /// One fold per group (e.g. per run).
    pub fn leave_one_group_out(groups: &[usize], scheme: &str) -> Folds {
        Folds {
            scheme: scheme.into(),
            of_sample: groups.to_vec(),
            count: groups.iter().max().map_or(0, |g| g + 1),
        }
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
    /// The effects worth testing next, each with the evidence from the residual diagnostics
    /// that proposes it (effects already in the model are not proposed).
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
}

/// Scores `effects` on `problem`: the fit to all data and the held-out residuals.
pub fn score<P: Problem>(problem: &P, effects: &[P::Effect]) -> (Score, P::Fit) {
    let n = problem.n_samples();
    let full = problem.fit(effects, &vec![true; n]);
    let rms = rms(&problem.residuals(&full));
    let folds = problem.folds();
    let mut sum = vec![0.0; folds.count];
    let mut count = vec![0usize; folds.count];
    for k in 0..folds.count {
        let fit = problem.fit(effects, &folds.training(k));
        let residuals = problem.residuals(&fit);
        for (i, r) in residuals.iter().enumerate() {
            if folds.of_sample[i] == k {
                sum[k] += r * r;
                count[k] += 1;
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

/// The smallest held-out gain accepted, relative to the current held-out RMS.
pub const MIN_RELATIVE_GAIN: Real = 0.05;
/// The acceptance rule in words, for reports.
pub const RULE: &str = "accept the candidate with the lowest held-out RMS if it lowers the held-out RMS by at least 5 % \
     and the per-fold log ratio of held-out mean squares (before/after) has a paired t statistic above \
     the one-sided 97.5 % Student quantile (folds − 1 degrees of freedom); when no single effect passes, the best passing pair; \
     stop when nothing passes";

/// One-sided 97.5 % quantiles of Student's t for 1 to 30 degrees of freedom.
const T_975: [Real; 30] = [
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
    2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
    2.052, 2.048, 2.045, 2.042,
];

/// The paired t statistic over folds must reach the one-sided 97.5 % quantile of Student's t
/// with (folds − 1) degrees of freedom ([`min_fold_t`]); the statistic is the mean over folds
/// of ln(held-out mean square before / after) divided by its standard error. The logarithm
/// makes folds comparable when an effect shows more in some runs than in others (a warm-up
/// hardly shows in the cold run); the quantile makes few folds demand more consistency.
/// Beyond 30 degrees of freedom, the normal quantile 1.960.
pub fn min_fold_t(folds: usize) -> Real {
    match folds {
        0 | 1 => Real::INFINITY,
        k if k - 1 <= T_975.len() => T_975[k - 2],
        _ => 1.960,
    }
}

/// Whether `candidate` improves on `current` by more than noise can explain (see [`RULE`]).
pub fn passes(current: &Score, candidate: &Score) -> bool {
    if current.cv_rms <= 0.0 || candidate.cv_rms > current.cv_rms * (1.0 - MIN_RELATIVE_GAIN) {
        return false;
    }
    let log =
        |v: &[Real]| -> Vec<Real> { v.iter().map(|m| m.max(Real::MIN_POSITIVE).ln()).collect() };
    paired_t(&log(&current.fold_mse), &log(&candidate.fold_mse))
        >= min_fold_t(current.fold_mse.len())
}

/// The paired t statistic of `before − after` over folds (+∞ when every fold drops by the
/// same positive amount).
pub fn paired_t(before: &[Real], after: &[Real]) -> Real {
    let d: Vec<Real> = before.iter().zip(after).map(|(b, a)| b - a).collect();
    let k = d.len() as Real;
    if d.len() < 2 {
        return 0.0;
    }
    let mean = d.iter().sum::<Real>() / k;
    let variance = d.iter().map(|x| (x - mean).powi(2)).sum::<Real>() / (k - 1.0);
    let standard_error = (variance / k).sqrt();
    if standard_error > 0.0 {
        mean / standard_error
    } else if mean > 0.0 {
        Real::INFINITY
    } else {
        0.0
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
}

/// The outcome of forward selection.
#[derive(Clone, Debug)]
pub struct Selection<E, F> {
    /// The base model's score and fit.
    pub baseline: (Score, F),
    /// Accepted effects, in order of acceptance.
    pub steps: Vec<Accepted<E, F>>,
    /// The candidates of the last round, none of which passed, with their held-out RMS.
    pub rejected: Vec<(E, Real)>,
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

/// Forward selection: from the base model, test every proposed effect by held-out RMS, accept
/// the best one that [`passes`]; when none does, accept the best pair of proposed effects that
/// passes (two terms that only together explain the residual, e.g. a sensor that warms both
/// sooner and more than the screw); repeat until nothing passes. `progress` hears about each
/// test.
pub fn forward_selection<P: Problem>(
    problem: &P,
    mut progress: impl FnMut(&str),
) -> Selection<P::Effect, P::Fit> {
    let baseline = score(problem, &[]);
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
        let best = tested
            .iter()
            .enumerate()
            .filter(|(_, (_, _, s, _))| passes(current, s))
            .min_by(|a, b| a.1.2.cv_rms.total_cmp(&b.1.2.cv_rms))
            .map(|(i, _)| i);
        match best {
            Some(i) => {
                let (effect, evidence, score, fit) = tested.swap_remove(i);
                effects.push(effect);
                steps.push(Accepted {
                    effect,
                    evidence,
                    score,
                    fit,
                    together_with: None,
                });
            }
            None => {
                if let Some((first, second, score, fit)) =
                    best_pair(problem, &effects, current, &tested, &mut progress)
                {
                    // Both enter: the first with its own score (what it does alone), the
                    // second with the pair's, so each step reads "the model up to here".
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
                    });
                    steps.push(Accepted {
                        effect: b,
                        evidence: evidence_b,
                        score,
                        fit,
                        together_with: Some(a),
                    });
                    continue;
                }
                let rejected = tested
                    .into_iter()
                    .map(|(e, _, s, _)| (e, s.cv_rms))
                    .collect();
                return Selection {
                    baseline,
                    steps,
                    rejected,
                };
            }
        }
    }
}

/// Tested candidates: effect, evidence, score, fit.
type Tested<P> = Vec<(<P as Problem>::Effect, String, Score, <P as Problem>::Fit)>;

/// The best pair of `tested` that [`passes`] against `current`: the indices (the better of
/// the two alone first) and the pair's score and fit.
fn best_pair<P: Problem>(
    problem: &P,
    effects: &[P::Effect],
    current: &Score,
    tested: &Tested<P>,
    progress: &mut impl FnMut(&str),
) -> Option<(usize, usize, Score, P::Fit)> {
    let mut best: Option<(usize, usize, Score, P::Fit)> = None;
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
            if passes(current, &pair)
                && best
                    .as_ref()
                    .is_none_or(|(_, _, s, _)| pair.cv_rms < s.cv_rms)
            {
                best = Some((a, b, pair, fit));
            }
        }
    }
    best
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
    fn fold_threshold_is_the_student_quantile() {
        // t(0.975; 4) = 2.776 and t(0.975; 6) = 2.447 (standard tables).
        assert_eq!(min_fold_t(5), 2.776);
        assert_eq!(min_fold_t(7), 2.447);
        assert_eq!(min_fold_t(1), Real::INFINITY);
    }

    #[test]
    fn paired_t_matches_a_hand_computation() {
        // d = (3, 1, 2): mean 2, sample sd 1, se 1/√3, t = 2√3.
        let t = paired_t(&[4.0, 2.0, 3.0], &[1.0, 1.0, 1.0]);
        assert!((t - 2.0 * 3.0_f64.sqrt()).abs() < 1e-12);
        assert_eq!(paired_t(&[2.0, 2.0], &[1.0, 1.0]), Real::INFINITY);
    }
}
