//! What a search returns ([`Selection`]): the accepted steps, the rejected candidates, the
//! moves and the alternatives, with their reports.

use super::report::{fold_rms_json, fold_rms_text, in_sample_text, test_keys, test_text};
use super::*;

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
    /// The mean squared held-out residual of each fold with it.
    pub fold_mse: Vec<Real>,
    /// Its acceptance test.
    pub test: Test,
}

/// A block of the last round whose held-out gains are beyond noise (the rule's conditions (2)
/// and (3) hold, and so do they for each of its effects added to the others, at one test's
/// threshold: no effect rides along) but that was not added: it does not lower the pooled
/// held-out RMS by [`MIN_RELATIVE_GAIN`], or one of its effects does not earn its place in it
/// (does not pass its test added to the others at the rule's threshold). Shown so that a
/// user sees evidence the rule did not take, and in which folds (a cold reference run held
/// out, predicted by extrapolation, can outweigh the other runs' gains in the pooled RMS).
#[derive(Clone, Debug, PartialEq)]
pub struct HeldBack<E> {
    /// The block's effects.
    pub effects: Vec<E>,
    /// The held-out RMS of the model with the block.
    pub cv_rms: Real,
    /// The mean squared held-out residual of each fold with the block.
    pub fold_mse: Vec<Real>,
    /// The block's test against the model (C the blocks of its size).
    pub test: Test,
    /// An effect of the block that does not earn its place in it (the block passes its
    /// test); `None`: the block's held-out gain is below [`MIN_RELATIVE_GAIN`].
    pub idle: Option<E>,
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

/// A model that comes close to the final one: one effect of the final model exchanged for
/// another candidate, with a held-out RMS less than [`MIN_RELATIVE_GAIN`] above the final
/// model's (see [`stepwise_selection`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Alternative<E> {
    /// The final model's effect that is exchanged.
    pub removed: E,
    /// The candidate that takes its place.
    pub added: E,
    /// The exchanged model's held-out RMS.
    pub cv_rms: Real,
    /// The final model tested against the exchanged one at one test's threshold (C = 1): its
    /// gain is below [`MIN_RELATIVE_GAIN`], so the data do not show the final model is the
    /// better of the two by a margin worth a term.
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
    /// The blocks of the last round held back although their held-out gains are beyond
    /// noise, lowest held-out RMS first (empty for [`forward_selection`], and for a search
    /// without blocks, [`Search::largest_block`] 1).
    pub held_back: Vec<HeldBack<E>>,
}

/// The most held-back blocks a report for people shows (the JSON report has them all).
pub const HELD_BACK_SHOWN: usize = 5;

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
            return "\nNo alternative: exchanging any effect of the final model for another candidate either does nothing or raises the held-out RMS by 5 % or more.\n".into();
        }
        let last = self.last().0.cv_rms;
        let mut out = String::from(
            "\nAlternatives that come close (one effect of the final model exchanged for another candidate, within 5 % of the final model's held-out RMS — two causes this file cannot separate):\n",
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

/// Why a held-back block was not added, for people.
fn held_back_reason<E: Copy>(block: &HeldBack<E>, id: &impl Fn(E) -> String) -> String {
    match block.idle {
        Some(e) => format!("{} does not earn its place in it", id(e)),
        None => "its pooled held-out gain falls short of the 5 % a term needs".into(),
    }
}

impl<E: Copy, F> Selection<E, F> {
    /// The line of a report's "Accepted" section when the search accepted nothing: that no
    /// effect gains more than noise can, or, when some gain beyond noise but fail the rule's
    /// other conditions, which (listed below the line with the RMS of each fold).
    pub fn nothing_text(&self, id: impl Fn(E) -> String) -> String {
        let mut evidence: Vec<String> = self
            .rejected
            .iter()
            .filter(|r| r.test.significant())
            .map(|r| id(r.effect))
            .collect();
        match self.held_back.len() {
            0 => {}
            1 => evidence.push("a block held back".into()),
            n => evidence.push(format!("{n} blocks held back")),
        }
        if evidence.is_empty() {
            return "  nothing: no effect lowers the held-out RMS more than noise can\n".into();
        }
        let list = match evidence.split_last() {
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
            None => String::new(),
        };
        format!(
            "  nothing passes the rule, though held-out gains beyond noise come from {list} (below: why each was not taken, and the held-out RMS of each fold)\n"
        )
    }

    /// The held-back blocks as JSON, lowest held-out RMS first: `effects` (from `id`),
    /// `cv_rms_um`, `fold_cv_rms_um`, the block's test (`gain_z`, `rest_z`, `z_needed`),
    /// `gain_pct` (its pooled held-out gain) and `not_earning_its_place`, the effect that does
    /// not earn its place in the block (null: the pooled gain is below 5 %).
    pub fn held_back_json(&self, id: impl Fn(E) -> String) -> Vec<serde_json::Value> {
        self.held_back
            .iter()
            .map(|b| {
                let mut object = serde_json::Map::new();
                object.insert(
                    "effects".into(),
                    b.effects.iter().map(|&e| id(e)).collect::<Vec<_>>().into(),
                );
                object.insert(
                    "cv_rms_um".into(),
                    round_json(b.cv_rms / crate::math::M_PER_UM),
                );
                object.insert("fold_cv_rms_um".into(), fold_rms_json(&b.fold_mse));
                object.insert("gain_pct".into(), round_json(100.0 * b.test.gain));
                test_keys(&mut object, &b.test);
                object.insert("not_earning_its_place".into(), b.idle.map(&id).into());
                serde_json::Value::Object(object)
            })
            .collect()
    }

    /// The held-back blocks for people (held-out RMS to `decimals` µm), each with why and the
    /// held-out RMS of each fold; empty when there is none.
    pub fn held_back_text(&self, id: impl Fn(E) -> String, decimals: usize) -> String {
        if self.held_back.is_empty() {
            return String::new();
        }
        let (gains, in_sample) = if self.held_back.iter().any(|b| b.test.in_sample.is_some()) {
            (
                "gains beyond noise held out or in-sample",
                "; the in-sample z likewise",
            )
        } else {
            ("held-out gains beyond noise", "")
        };
        let mut out = format!(
            "\nBlocks held back ({gains}, but not added; held-out RMS; held-out gain; z, and without the fold that contributes most, against the z needed{in_sample}; why):\n",
        );
        for b in self.held_back.iter().take(HELD_BACK_SHOWN) {
            out.push_str(&format!(
                "  {}: {} µm; {:+.1} %; z {:.1}, {:.1} / {:.2}{}; {}\n      {}\n",
                b.effects
                    .iter()
                    .map(|&e| id(e))
                    .collect::<Vec<_>>()
                    .join(" + "),
                crate::math::fixed(b.cv_rms / crate::math::M_PER_UM, decimals),
                100.0 * b.test.gain,
                b.test.z,
                b.test.rest_z,
                b.test.threshold,
                in_sample_text(&b.test),
                held_back_reason(b, &id),
                fold_rms_text(&b.fold_mse, decimals)
            ));
        }
        if self.held_back.len() > HELD_BACK_SHOWN {
            out.push_str(&format!(
                "  and {} more (the JSON report lists them all)\n",
                self.held_back.len() - HELD_BACK_SHOWN
            ));
        }
        out
    }
}

/// The change of a held-out RMS from `before` to `after`, in % of `before`.
pub(super) fn change_pct(before: Real, after: Real) -> Real {
    if before > 0.0 {
        100.0 * (after / before - 1.0)
    } else {
        0.0
    }
}
