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

mod book;
mod forward;
mod report;
mod selection;
mod stepwise;
mod test;
#[cfg(test)]
mod tests;

pub use forward::forward_selection;
pub(crate) use report::{
    FINAL_VALUES, folds_text, params_json, params_text, rejected_text, test_text,
};
pub use report::{folds_json, rejected_json, round_json};
pub use selection::{
    Accepted, Action, Alternative, HELD_BACK_SHOWN, HeldBack, Move, Rejected, ResidualStep,
    Selection,
};
pub use stepwise::{LARGEST_BLOCK, LEAN_STEPWISE_RULE, STEPWISE_RULE, Search, stepwise_selection};
pub use test::{
    IN_SAMPLE_FOLDS, IN_SAMPLE_RULE, InSample, RULE, Test, f_as_normal, normal_quantile,
};

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
    fn id(&self, effect: Self::Effect) -> String;
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
    /// Whether `a` and `b` may be in one model (true unless the problem says otherwise). The
    /// searches never score a model with an incompatible pair: a proposal that cannot join
    /// the current model is not scored with it (the problem's report says why), and no block
    /// or exchange brings in such a pair.
    fn compatible(&self, _a: Self::Effect, _b: Self::Effect) -> bool {
        true
    }
    /// The free parameters of `fit`, for the in-sample route of [`Test`] on files of few
    /// folds; `None` (the default) when the problem does not count them, and then only the
    /// held-out test judges.
    fn parameters(&self, _fit: &Self::Fit) -> Option<Parameters> {
        None
    }
}

/// The free parameters of a fit: how many there are, and among how many values its searched
/// ones (a time constant, a period) were chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameters {
    /// Linear coefficients and searched values together.
    pub count: usize,
    /// The product over the searched values of the number of grid points each was chosen
    /// among (1 without): an in-sample test of a searched term is the best of that many, and
    /// its level is divided by it (Bonferroni).
    pub grid: Real,
}

/// `problem.proposals(effects, fit)` without those that cannot join `effects`
/// ([`Problem::compatible`]).
pub(crate) fn admissible_proposals<P: Problem>(
    problem: &P,
    effects: &[P::Effect],
    fit: &P::Fit,
) -> Vec<(P::Effect, String)>
where
    P::Effect: Copy,
{
    problem
        .proposals(effects, fit)
        .into_iter()
        .filter(|(e, _)| effects.iter().all(|&m| problem.compatible(m, *e)))
        .collect()
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
    /// The fit to all samples: its residual sum of squares in each fold, for the in-sample
    /// route of [`Test`].
    pub fold_ss: Vec<Real>,
    /// The same fit's sum of products of neighbouring residuals in each fold (in the order
    /// taken, [`Folds::sequence`]).
    pub fold_lag_one: Vec<Real>,
    /// The full fit's free parameters ([`Problem::parameters`]).
    pub parameters: Option<Parameters>,
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
    let residuals = problem.residuals(&full);
    let rms = rms(&residuals);
    let (mut fold_ss, mut fold_lag_one) = (vec![0.0; folds.count], vec![0.0; folds.count]);
    let mut previous: Vec<Option<Real>> = vec![None; folds.count];
    for &i in &folds.sequence {
        let k = folds.of_sample[i];
        fold_ss[k] += residuals[i] * residuals[i];
        if let Some(r) = previous[k] {
            fold_lag_one[k] += r * residuals[i];
        }
        previous[k] = Some(residuals[i]);
    }
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
            fold_ss,
            fold_lag_one,
            parameters: problem.parameters(&full),
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

/// Random signals an effect's terms are tried on ([`inert`]).
pub const PROBES: usize = 2;
/// The smallest relative change of a probe's sum of squares that counts as the effect acting.
/// An effect that can act lowers a random signal's sum of squares by about one part in the
/// number of samples per term (the chance that it moves by less than 1e-10 of it is about
/// 1e-4 per probe for a thousand samples); one that cannot leaves it to rounding (1e-14).
pub const INERT_CHANGE: Real = 1e-10;

/// The signals of [`inert`]: `PROBES` seeded standard-normal vectors of `n` samples times
/// `scale` (the problem's unit of a typical reading), the same for every file of that length.
pub fn probe_signals(n: usize, scale: Real) -> Vec<Vec<Real>> {
    let mut rng = crate::math::seeded_rng(0, "discovery probe signals");
    (0..PROBES)
        .map(|_| {
            (0..n)
                .map(|_| scale * crate::math::standard_normal(&mut rng))
                .collect()
        })
        .collect()
}

/// The effects of `candidates` whose terms cannot change the fit on this file: fitted with
/// the base model to each of `probes` (the problem with a random signal in place of its
/// measurements, [`probe_signals`]), none moves the sum of squares of any by more than
/// [`INERT_CHANGE`] of it. A column the file makes zero, constant where the base model already
/// has a constant, or a searched shape (a time constant, a lag) the file's time stamps cannot
/// express, is such an effect: scored, it would show a held-out gain of exactly 0 % and read
/// as evidence that the effect is absent, where the file simply cannot show it.
pub fn inert<P: Problem + Sync>(probes: &[P], candidates: &[P::Effect]) -> Vec<P::Effect>
where
    P::Effect: Sync + Send,
{
    use rayon::prelude::*;
    let sum_of_squares = |problem: &P, effects: &[P::Effect]| -> Real {
        let all = vec![true; problem.n_samples()];
        let fit = problem.fit(effects, &all);
        problem.residuals(&fit).iter().map(|r| r * r).sum()
    };
    let base: Vec<Real> = probes.iter().map(|p| sum_of_squares(p, &[])).collect();
    let acts: Vec<bool> = candidates
        .par_iter()
        .map(|&effect| {
            probes.iter().zip(&base).any(|(probe, &b)| {
                let with = sum_of_squares(probe, &[effect]);
                (with - b).abs() > INERT_CHANGE * b
            })
        })
        .collect();
    candidates
        .iter()
        .zip(acts)
        .filter(|(_, acts)| !acts)
        .map(|(&e, _)| e)
        .collect()
}

/// The reason [`inert`] gives, for reports.
pub const INERT_REASON: &str = "on this file its terms cannot change the fit (tried on random signals, the base model already holds every shape they take here)";
