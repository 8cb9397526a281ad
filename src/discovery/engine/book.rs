//! The models a search has scored ([`Book`]) and the members of its current model.

use super::*;

/// Every model a search has scored: its effects (in the order they were fitted), its score
/// and its fit. A model is found again by its set of effects.
pub(super) struct Book<'a, P: Problem> {
    pub(super) problem: &'a P,
    pub(super) models: Vec<(Vec<P::Effect>, Score, P::Fit)>,
    /// The models the search has been at (indices into `models`): it never moves back to one.
    pub(super) visited: Vec<usize>,
}

impl<'a, P: Problem + Sync> Book<'a, P>
where
    P::Effect: Sync,
    P::Fit: Send,
{
    pub(super) fn new(problem: &'a P) -> Self {
        Book {
            problem,
            models: Vec::new(),
            visited: Vec::new(),
        }
    }

    /// Whether the search has been at the model with `effects`.
    pub(super) fn visited(&self, effects: &[P::Effect]) -> bool {
        self.find(effects)
            .is_some_and(|i| self.visited.contains(&i))
    }

    /// Where the model with `effects` (in any order) is, if it has been scored.
    pub(super) fn find(&self, effects: &[P::Effect]) -> Option<usize> {
        self.models.iter().position(|(scored, _, _)| {
            scored.len() == effects.len() && effects.iter().all(|e| scored.contains(e))
        })
    }

    /// Where each model of `models` is, scoring (and naming to `progress`) those not scored
    /// yet. They are scored in parallel and gathered in the order given, so the book does not
    /// depend on the thread count.
    pub(super) fn score_all(
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
    pub(super) fn at(&mut self, effects: &[P::Effect], progress: &mut dyn FnMut(&str)) -> usize {
        self.score_all(&[effects.to_vec()], progress)[0]
    }

    pub(super) fn score(&self, i: usize) -> &Score {
        &self.models[i].1
    }

    /// Orders two scored models by held-out RMS.
    pub(super) fn by_cv_rms(&self, a: usize, b: usize) -> std::cmp::Ordering {
        self.score(a).cv_rms.total_cmp(&self.score(b).cv_rms)
    }

    pub(super) fn fit(&self, i: usize) -> &P::Fit {
        &self.models[i].2
    }

    /// A model's effects for progress messages: `base + a + b`.
    pub(super) fn name(&self, effects: &[P::Effect]) -> String {
        let mut name = String::from("base");
        for &e in effects {
            name.push_str(" + ");
            name.push_str(&self.problem.id(e));
        }
        name
    }
}

/// An effect of the model during a search: what pointed to it, the move that brought it in
/// and the number of candidates of that move's family (its test's C).
pub(super) struct Member<E> {
    pub(super) effect: E,
    pub(super) evidence: String,
    pub(super) entered: usize,
    pub(super) family: usize,
}

/// The number of `k`-subsets of `n` things.
pub(super) fn subsets(n: usize, k: usize) -> usize {
    if k > n {
        return 0;
    }
    (0..k).fold(1, |c, i| c * (n - i) / (i + 1))
}
