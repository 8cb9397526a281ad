//! The result of ball-bar discovery ([`BallbarDiscovery`]): the accepted and rejected effects,
//! their parameters in file units, the scores, as text and JSON.

use super::effects::BallbarEffect;
use super::problem::{BASE, BallbarProblem, SEARCH};
use crate::discovery::engine::{
    self, ResidualStep, Score, Selection, params_json, round_json as round,
};
use crate::kinds::ballbar::iso230_4::{
    CircleData, CircularTest, LAG_SET, LagLocation, ModelFit, Term, lag_key,
};
use crate::machine::Plane;
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, fixed};
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// The result of ball-bar discovery.
#[derive(Debug)]
pub struct BallbarDiscovery {
    pub(super) problem: BallbarProblem,
    pub(super) selection: Selection<BallbarEffect, ModelFit>,
}

/// The parameters of `effect` in `fit`, in file units with the unit in the name.
fn params(
    fit: &ModelFit,
    effect: BallbarEffect,
    data: &CircleData,
) -> BTreeMap<&'static str, Real> {
    let mut params = BTreeMap::new();
    let term = effect.term();
    let Some(c) = fit.coefficients_of(term) else {
        return params;
    };
    let um = |v: Real| v / M_PER_UM;
    let which = usize::from(matches!(
        effect,
        BallbarEffect::ReversalSpikeQ | BallbarEffect::CyclicQ
    ));
    // A shape at an end of its range measures nothing (the report's notes say why).
    let measured = data.shape_at_range_end(term, &fit.shape).is_none();
    match effect {
        BallbarEffect::ServoMismatch => {
            params.insert("servo_mismatch_ms", c[0] * 1e3);
        }
        BallbarEffect::BacklashP | BallbarEffect::BacklashQ => {
            params.insert("backlash_um", um(c[0]));
            // Lost motion as play (the carriage stands still while the motor crosses the
            // gap) rather than a step at the reversal: the gap the fit took up.
            let axis = usize::from(effect == BallbarEffect::BacklashQ);
            if fit.shape.play[axis] > 0.0 {
                params.insert("play_um", um(fit.shape.play[axis]));
            }
        }
        BallbarEffect::LateralPlayP | BallbarEffect::LateralPlayQ => {
            params.insert("lateral_play_um", um(c[0]));
        }
        BallbarEffect::ReversalSpikeP | BallbarEffect::ReversalSpikeQ if measured => {
            params.insert("amplitude_um", um(c[0]));
            params.insert("decay_ms", fit.shape.decay[which] * 1e3);
        }
        BallbarEffect::StraightnessP | BallbarEffect::StraightnessQ => {
            params.insert("straightness_um", um(c[0]));
        }
        BallbarEffect::CyclicP | BallbarEffect::CyclicQ if measured => {
            params.insert("amplitude_um", um(c[0].hypot(c[1])));
            params.insert("period_mm", fit.shape.period[which] / M_PER_MM);
            params.insert("phase_deg", c[1].atan2(c[0]) / RAD_PER_DEG);
        }
        BallbarEffect::Lobes if measured => {
            params.insert("lobes", Real::from(fit.shape.lobes));
            params.insert("amplitude_um", um(c[0].hypot(c[1])));
            params.insert("phase_deg", c[1].atan2(c[0]) / RAD_PER_DEG);
        }
        BallbarEffect::RadiusDrift => {
            let duration = data.points.iter().map(|p| p.time).fold(0.0, Real::max);
            params.insert("rate_um_per_min", um(c[0]) * 60.0);
            params.insert("change_um", um(c[0]) * duration);
        }
        BallbarEffect::SenseRadius => {
            params.insert("ccw_minus_cw_um", um(c[0]));
        }
        _ => {}
    }
    // Reversal terms are located at the axis's actual reversal: its lag after the
    // programmed one, when the fit places it.
    if let Some(axis) = term.reversal_axis()
        && let LagLocation::Located { lag, .. } = locate_lag(fit, axis, data)
    {
        params.insert("reversal_lag_ms", lag * 1e3);
    }
    params
}

/// The terms of `fit` that can place `axis`'s reversal: its backlash and spike.
fn locating(fit: &ModelFit, axis: usize) -> Vec<Term> {
    fit.terms
        .iter()
        .copied()
        .filter(|t| t.reversal_axis() == Some(axis) && t.locates_reversal())
        .collect()
}

/// Where `fit` places `axis`'s reversal, by its backlash and spike ([`CircleData::locate_lag`],
/// σ̂² from the fit's residuals).
fn locate_lag(fit: &ModelFit, axis: usize, data: &CircleData) -> LagLocation {
    let locating = locating(fit, axis);
    let rss: Real = fit.residuals.iter().map(|r| r * r).sum();
    let dof = fit
        .residuals
        .len()
        .saturating_sub(fit.coefficients.len())
        .max(1);
    data.locate_lag(axis, fit, &locating, rss / dof as Real)
}

/// What the final model's parameters leave out, and why: a searched shape at an end of its
/// range (the effect's values), a reversal lag the model does not place.
fn notes(fit: &ModelFit, data: &CircleData) -> Vec<String> {
    let plane = data.test.plane;
    let ends = BallbarEffect::ALL.iter().filter_map(|&effect| {
        let term = effect.term();
        fit.terms.contains(&term).then_some(())?;
        let reason = data.shape_at_range_end(term, &fit.shape)?;
        Some(format!(
            "{}: {reason}: its values are not reported",
            effect.id(plane)
        ))
    });
    let lags = (0..2)
        .filter(|&axis| fit.terms.iter().any(|t| t.reversal_axis() == Some(axis)))
        .filter_map(|axis| {
            let letter = if axis == 0 {
                plane.first()
            } else {
                plane.second()
            };
            let name = lag_key(plane, axis);
            match locate_lag(fit, axis, data) {
                LagLocation::Located { .. } => None,
                LagLocation::NotLocated { .. } if locating(fit, axis).is_empty() => {
                    Some(format!(
                        "{name}: no backlash or reversal spike of {letter} in the model to time its reversal by (lateral play cannot: it is continuous at the reversal): not reported"
                    ))
                }
                LagLocation::NotLocated { from, to } => Some(format!(
                    "{name}: the model fits as well ({LAG_SET}) for any lag from {:.1} to {:.1} ms, which reaches the end of the range searched: the trace does not place {letter}'s reversal, not reported",
                    from * 1e3,
                    to * 1e3
                )),
            }
        });
    ends.chain(lags).collect()
}

impl BallbarDiscovery {
    fn plane(&self) -> Plane {
        self.problem.data.test.plane
    }

    /// The test conditions of the table.
    pub fn test(&self) -> &CircularTest {
        &self.problem.data.test
    }

    /// The model after the first `k` accepted effects, by name.
    fn model_name(&self, k: usize) -> String {
        let mut name = "base".to_string();
        for step in &self.selection.steps[..k] {
            name.push_str(" + ");
            name.push_str(step.effect.id(self.plane()));
        }
        name
    }

    /// The prepared table (angles, senses and deviations in the table's order).
    pub fn data(&self) -> &CircleData {
        &self.problem.data
    }

    /// The base model and each accepted effect in turn, with the residual it leaves.
    pub fn residual_steps(&self) -> Vec<ResidualStep<'_>> {
        self.selection
            .residual_steps(|k| self.model_name(k), |fit| &fit.residuals)
    }

    /// The accepted effects in order.
    pub fn accepted(&self) -> Vec<BallbarEffect> {
        self.selection.effects()
    }

    /// The effects tested in the last round and not accepted, with their scores.
    pub fn rejected(&self) -> &[engine::Rejected<BallbarEffect>] {
        &self.selection.rejected
    }

    /// The effects the table cannot show, with why.
    pub fn untestable(&self) -> &[(BallbarEffect, String)] {
        self.problem.untestable()
    }

    /// The base model's score.
    pub fn baseline_score(&self) -> &Score {
        &self.selection.baseline.0
    }

    /// The final model's score.
    pub fn final_score(&self) -> &Score {
        self.selection.last().0
    }

    /// The final model's parameters of an accepted effect, in file units.
    pub fn final_params(&self, effect: BallbarEffect) -> Option<BTreeMap<&'static str, Real>> {
        let fit = self.selection.last().1;
        fit.terms
            .contains(&effect.term())
            .then(|| params(fit, effect, &self.problem.data))
    }

    /// The base terms of a fit, keyed as the ISO 230-4 diagnostics are (file units).
    fn base_params(&self, fit: &ModelFit) -> Value {
        Value::Object(
            BASE.iter()
                .filter_map(|&t| {
                    let c = fit.coefficients_of(t)?;
                    Some((t.key(self.plane()), round(c[0] * t.unit().1)))
                })
                .collect(),
        )
    }

    /// The report with stable keys.
    pub fn to_json(&self) -> Value {
        let um = |v: Real| round(v / M_PER_UM);
        let plane = self.plane();
        let data = &self.problem.data;
        let (base_score, base_fit) = &self.selection.baseline;
        let steps = self.selection.steps_json(|step| {
            let json = json!({
                "effect": step.effect.id(plane),
                "axis": step.effect.axis(plane).map(|a| a.to_string()),
                "together_with": step.together_with.map(|e| e.id(plane)),
                "cause": step.effect.cause(),
                "params": params_json(&params(&step.fit, step.effect, data)),
            });
            json.as_object().cloned().unwrap_or_default()
        });
        let (final_score, final_fit) = self.selection.last();
        let mut final_params = serde_json::Map::new();
        final_params.insert("base".into(), self.base_params(final_fit));
        for step in &self.selection.steps {
            final_params.insert(
                step.effect.id(plane).into(),
                params_json(&params(final_fit, step.effect, data)),
            );
        }
        let evidence: serde_json::Map<String, Value> = BallbarEffect::ALL
            .iter()
            .filter(|e| self.problem.testable.contains(e))
            .filter_map(|&e| {
                self.problem
                    .evidence(e, base_fit)
                    .map(|text| (e.id(plane).to_string(), json!(text)))
            })
            .collect();
        json!({
            "kind": "ballbar",
            "plane": plane.to_string(),
            "radius_mm": round(data.test.radius / M_PER_MM),
            "feed_mm_per_min": round(data.test.feed / M_PER_MM * 60.0),
            "n_samples": data.len(),
            "validation": {
                "scheme": self.problem.folds.scheme,
                "folds": self.problem.folds.count,
                "rule": SEARCH.rule(),
                "angle_lag_ms": round(self.problem.angle_lag(&self.accepted()) * 1e3),
            },
            "baseline": {
                "model": "radius + centre offset + squareness + scale mismatch",
                "params": self.base_params(base_fit),
                "rms_um": um(base_score.rms),
                "cv_rms_um": um(base_score.cv_rms),
                "fold_cv_rms_um": engine::folds_json(base_score),
                "evidence": Value::Object(evidence),
            },
            "steps": steps,
            "moves": self.selection.moves_json(|e| e.id(plane).into()),
            "rejected": engine::rejected_json(&self.selection.rejected, |e| e.id(plane).into()),
            "held_back": self.selection.held_back_json(|e| e.id(plane).into()),
            "alternatives": self.selection.alternatives_json(|e| e.id(plane).into()),
            "untestable": self.problem.untestable.iter().map(|(e, why)| json!({
                "effect": e.id(plane),
                "reason": why,
            })).collect::<Vec<_>>(),
            "notes": notes(final_fit, data),
            "final": {
                "model": self.model_name(self.selection.steps.len()),
                "params": Value::Object(final_params),
                "rms_um": um(final_score.rms),
                "cv_rms_um": um(final_score.cv_rms),
                "fold_cv_rms_um": engine::folds_json(final_score),
            },
        })
    }

    /// The report for people.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let um = |v: Real| v / M_PER_UM;
        let plane = self.plane();
        let data = &self.problem.data;
        let (base_score, base_fit) = &self.selection.baseline;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Model discovery, ball-bar table, plane {plane} (p = {}, q = {}): {} readings, radius {} mm, feed {} mm/min",
            plane.first(),
            plane.second(),
            data.len(),
            fixed(data.test.radius / M_PER_MM, 3),
            fixed(data.test.feed / M_PER_MM * 60.0, 1)
        );
        let _ = writeln!(
            out,
            "Held-out data: {}; {}.",
            self.problem.folds.scheme,
            SEARCH.rule()
        );
        let _ = writeln!(
            out,
            "Servo angle lag (final model) {} ms: each model's is estimated once on the whole trace and held in all its fits, full and per fold.\n",
            fixed(self.problem.angle_lag(&self.accepted()) * 1e3, 2)
        );
        let _ = writeln!(
            out,
            "Base model: radius + centre offset + squareness + scale mismatch\n  RMS {:.3} µm, held-out RMS {:.3} µm ({})",
            um(base_score.rms),
            um(base_score.cv_rms),
            engine::folds_text(base_score, 3)
        );
        let _ = writeln!(out, "\nWhat the base model leaves:");
        for &effect in &self.problem.testable {
            if let Some(text) = self.problem.evidence(effect, base_fit) {
                let _ = writeln!(out, "  {:<18} {text}", effect.id(plane));
            }
        }
        out.push_str(&self.selection.moves_text(|e| e.id(plane).into(), 3));
        let _ = writeln!(out, "\nAccepted, in order:");
        if self.selection.steps.is_empty() {
            out.push_str(&self.selection.nothing_text(|e| e.id(plane).into()));
        }
        for (step, (gain, pct)) in self.selection.steps.iter().zip(self.selection.gains()) {
            let params = engine::params_text(&params(&step.fit, step.effect, data));
            let together = step.together_with.map_or_else(String::new, |other| {
                format!(
                    " (accepted together with {}: neither passes alone)",
                    other.id(plane)
                )
            });
            let _ = writeln!(
                out,
                "  + {}{together}: {params} at acceptance\n      cause: {}\n      held-out RMS {:.3} µm (gain {:.3} µm, {:.1} %; {}; {})",
                step.effect.id(plane),
                step.effect.cause(),
                um(step.score.cv_rms),
                um(gain),
                pct,
                engine::folds_text(&step.score, 3),
                engine::test_text(&step.test)
            );
        }
        out.push_str(&engine::rejected_text(
            &self.selection.rejected,
            |e| e.id(plane).into(),
            3,
        ));
        out.push_str(&self.selection.held_back_text(|e| e.id(plane).into(), 3));
        out.push_str(&self.selection.alternatives_text(|e| e.id(plane).into(), 3));
        let _ = writeln!(
            out,
            "\nEvery effect this table can test was scored in every round: {} accepted, {} rejected in the last round{}.",
            self.selection.steps.len(),
            self.selection.rejected.len(),
            match self.problem.untestable.len() {
                0 => String::new(),
                k => format!("; {k} cannot be tested (below)"),
            }
        );
        if !self.problem.untestable.is_empty() {
            let _ = writeln!(out, "\nCannot be tested with this table:");
            for (effect, why) in &self.problem.untestable {
                let _ = writeln!(out, "  {:<18} {why}", effect.id(plane));
            }
        }
        let (final_score, final_fit) = self.selection.last();
        let _ = writeln!(
            out,
            "\nFinal model: {}\n  RMS {:.3} µm, held-out RMS {:.3} µm ({})",
            self.model_name(self.selection.steps.len()),
            um(final_score.rms),
            um(final_score.cv_rms),
            engine::folds_text(final_score, 3)
        );
        let _ = writeln!(out, "{}", engine::FINAL_VALUES);
        let base = self.base_params(final_fit);
        let base: Vec<String> = base
            .as_object()
            .into_iter()
            .flatten()
            .filter_map(|(k, v)| Some(format!("{k} = {:.3}", v.as_f64()?)))
            .collect();
        let _ = writeln!(out, "    {:<18} {}", "base", base.join(", "));
        for step in &self.selection.steps {
            let _ = writeln!(
                out,
                "    {:<18} {}",
                step.effect.id(plane),
                engine::params_text(&params(final_fit, step.effect, data))
            );
        }
        for note in notes(final_fit, data) {
            let _ = writeln!(out, "  note: {note}");
        }
        out
    }
}
