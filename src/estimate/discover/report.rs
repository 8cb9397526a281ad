//! Model selection's report: each accepted term in ISO names with its held-out gain, what was
//! tested and rejected, what these tables cannot test, as text and JSON.

use super::{Discovery, SEARCH};
use crate::discovery::engine::{self, folds_text, rejected_text, test_text};
use crate::math::{M_PER_UM, fixed};
use serde_json::{Value, json};

/// Held-out RMS in reports: µm to 3 decimals.
const DECIMALS: usize = 3;

impl Discovery {
    /// The report for people.
    pub fn text(&self) -> String {
        let um = |v: f64| fixed(v / M_PER_UM, DECIMALS);
        let selection = &self.selection;
        let library = self.problem.terms().count();
        let mut out = format!(
            "Model selection (identify --discover): from --params {}, {} terms of the library, {} testable on these tables; each of the {} groups of readings (K-tests; a probed sphere at one tilt) held out in turn, residuals weighted by their uncertainty (µm at the mean σ).\n",
            self.base,
            library,
            library - self.untestable.len(),
            self.problem.groups()
        );
        let (base, _) = selection.after(0);
        out += &format!(
            "  base model: held-out RMS {} µm (fitted to all {} µm); {}\n",
            um(base.cv_rms),
            um(base.rms),
            folds_text(base, DECIMALS)
        );
        for (step, (_, pct)) in selection.steps.iter().zip(selection.gains()) {
            out += &format!(
                "  + {}: {}\n      held-out RMS {} µm ({pct:+.1} %); {}\n      evidence: {}\n",
                step.effect.id(),
                step.effect.cause(),
                um(step.score.cv_rms),
                test_text(&step.test),
                step.evidence
            );
        }
        if selection.steps.is_empty() {
            out += "  nothing accepted: no term of the library predicts the groups held out better than noise can explain.\n";
        }
        out += &selection.moves_text(|t| t.id(), DECIMALS);
        out += &selection.alternatives_text(|t| t.id(), DECIMALS);
        out += &rejected_text(&selection.rejected, |t| t.id(), DECIMALS);
        if !self.untestable.is_empty() {
            let names: Vec<String> = self.untestable.iter().map(|t| t.id()).collect();
            out += &format!(
                "\nNot testable on these tables with the base model (the base already takes every shape it gives here, or no reading sees it): {}\n",
                names.join(", ")
            );
        }
        out += &format!("\nRule: {}\n", SEARCH.rule());
        out += &format!(
            "\nThe estimate below is made with --params {}{}\n\n",
            self.params(),
            if self.drift() { " --drift=rate" } else { "" }
        );
        out
    }

    /// The report as JSON: the base, each accepted step (`term`, `cause`, `params` items and
    /// the engine's scores and test), the moves, the rejected candidates, the untestable
    /// terms, the rule and the extended `params`.
    pub fn to_json(&self) -> Value {
        let selection = &self.selection;
        let (base, _) = selection.after(0);
        let um = |v: f64| engine::round_json(v / M_PER_UM);
        json!({
            "base_params": self.base,
            "groups": self.problem.groups(),
            "scheme": "leave-one-test-out",
            "base": {
                "rms_um": um(base.rms),
                "cv_rms_um": um(base.cv_rms),
                "fold_cv_rms_um": engine::folds_json(base),
            },
            "steps": selection.steps_json(|step| {
                let mut object = serde_json::Map::new();
                object.insert("term".into(), step.effect.id().into());
                object.insert("cause".into(), step.effect.cause().into());
                object.insert("params".into(), json!(step.effect.spec_items()));
                object
            }),
            "moves": selection.moves_json(|t| t.id()),
            "rejected": engine::rejected_json(&selection.rejected, |t| t.id()),
            "untestable": self.untestable.iter().map(|t| t.id()).collect::<Vec<_>>(),
            "rule": SEARCH.rule(),
            "params": self.params(),
            "drift": if self.drift() { "rate" } else { "none" },
        })
    }
}
