//! The result of discovery for people and programs: the accepted, rejected and untestable
//! effects, scores and parameters, the residual steps, and the text and JSON reports.

use super::{Association, PositioningDiscovery, PositioningEffect, PositioningFit};
use crate::discovery::engine::{self, ResidualStep, Score, params_json, round_json as round};
use crate::math::{M_PER_MM, M_PER_UM, Real};
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// A lag whose gain smoothing the sensor's readings recovers to this share is reported as
/// smoothing ([`PositioningDiscovery::smoothing_note`]).
pub const SMOOTHING_SHARE: Real = 0.5;

fn association_json(a: &Option<Association>, slope_unit: &str, scale: Real) -> Value {
    match a {
        None => Value::Null,
        Some(a) => json!({
            format!("slope_{slope_unit}"): round(a.slope * scale),
            "correlation": round(a.correlation),
            "t": round(a.t),
        }),
    }
}

impl PositioningDiscovery {
    /// The base model's name.
    fn base_name(&self) -> &'static str {
        if self.problem.temperature.is_some() {
            "profile + nominal expansion"
        } else {
            "profile"
        }
    }

    /// The model after the first `k` accepted effects, by name.
    pub(super) fn model_name(&self, k: usize) -> String {
        let mut name = self.base_name().to_string();
        for step in &self.selection.steps[..k] {
            name.push_str(" + ");
            name.push_str(step.effect.id());
        }
        name
    }

    /// The base model and each accepted effect in turn, with the residual it leaves.
    pub fn residual_steps(&self) -> Vec<ResidualStep<'_>> {
        self.selection
            .residual_steps(|k| self.model_name(k), |fit| &fit.residuals)
    }

    /// The accepted effects in order.
    pub fn accepted(&self) -> Vec<PositioningEffect> {
        self.selection.effects()
    }

    /// The effects tested in the last round and not accepted, with their scores.
    pub fn rejected(&self) -> &[engine::Rejected<PositioningEffect>] {
        &self.selection.rejected
    }

    /// Every move of the search in order (additions, and the removals and exchanges that
    /// backed out of earlier steps).
    pub fn moves(&self) -> &[engine::Move<PositioningEffect>] {
        &self.selection.moves
    }

    /// The exchanges of one final effect for another candidate that the held-out data cannot
    /// rule out, lowest held-out RMS first.
    pub fn alternatives(&self) -> &[engine::Alternative<PositioningEffect>] {
        &self.selection.alternatives
    }

    /// The testable effects the final model cannot take beside its own, with why (a lag of
    /// the structure and a lag of the sensor exclude each other).
    pub fn excluded(&self) -> Vec<(PositioningEffect, String)> {
        let model = self.accepted();
        self.problem
            .testable
            .iter()
            .filter(|e| !model.contains(e))
            .filter_map(|&e| {
                let other = model
                    .iter()
                    .find(|&&m| PositioningEffect::lags(m, e))?;
                Some((
                    e,
                    format!(
                        "cannot join {}: the structure either lags the sensor or leads it, and a lag with a lead is a filter of the reading (it smooths the sensor's noise), not a cause; it was scored against the base model and in blocks without {}",
                        other.id(),
                        other.id()
                    ),
                ))
            })
            .collect()
    }

    /// The labels of the runs each fold holds out (a run in several folds when the folds are
    /// blocks in time that cut it), fold by fold, in the file's run order.
    pub fn fold_runs(&self) -> Vec<Vec<String>> {
        let folds = &self.problem.folds;
        let mut held: Vec<Vec<bool>> =
            vec![vec![false; self.problem.run_labels.len()]; folds.count];
        for (i, &run) in self.problem.run.iter().enumerate() {
            held[folds.of_sample[i]][run] = true;
        }
        held.iter()
            .map(|runs| {
                runs.iter()
                    .enumerate()
                    .filter(|(_, held)| **held)
                    .map(|(r, _)| self.problem.run_labels[r].clone())
                    .collect()
            })
            .collect()
    }

    /// The folds that test extrapolation for people: a line naming each fold whose held-out
    /// runs lie outside the other runs' temperature range, and by how much; empty when none
    /// does ([`PositioningProblem::extrapolated_folds`](super::PositioningProblem::extrapolated_folds)).
    fn extrapolation_text(&self) -> String {
        let extrapolated = self.problem.extrapolated_folds();
        if extrapolated.is_empty() {
            return String::new();
        }
        let runs = self.fold_runs();
        let list: Vec<String> = extrapolated
            .iter()
            .map(|e| {
                let held = &runs[e.fold];
                let label = match held.as_slice() {
                    [run] => format!("run {run}"),
                    runs => format!("runs {}", runs.join(", ")),
                };
                let mut sides = Vec::new();
                if e.below_degc > 0.0 {
                    sides.push(format!("{:.2} °C below", e.below_degc));
                }
                if e.above_degc > 0.0 {
                    sides.push(format!("{:.2} °C above", e.above_degc));
                }
                format!("{label} ({})", sides.join(", "))
            })
            .collect();
        format!(
            "  Folds that test extrapolation (held out, outside the other runs' temperature range): {}\n",
            list.join("; ")
        )
    }

    /// The folds that test extrapolation as JSON: `fold`, `runs` (held out), `below_degc` and
    /// `above_degc`.
    fn extrapolation_json(&self) -> Value {
        let runs = self.fold_runs();
        self.problem
            .extrapolated_folds()
            .iter()
            .map(|e| {
                json!({
                    "fold": e.fold,
                    "runs": runs[e.fold],
                    "below_degc": round(e.below_degc),
                    "above_degc": round(e.above_degc),
                })
            })
            .collect()
    }

    /// The effects the file cannot show, with why.
    pub fn untestable(&self) -> &[(PositioningEffect, String)] {
        self.problem.untestable()
    }

    /// The final model's score.
    pub fn final_score(&self) -> &Score {
        self.selection.last().0
    }

    /// The base model's score.
    pub fn baseline_score(&self) -> &Score {
        &self.selection.baseline.0
    }

    /// The final model's parameters of an accepted effect.
    pub fn final_params(&self, effect: PositioningEffect) -> Option<BTreeMap<&'static str, Real>> {
        let fit = self.selection.last().1;
        fit.effects.contains(&effect).then(|| fit.params(effect))
    }

    /// Whether the final model's lag (`thermal_lag` or `sensor_lag`) gains mostly by smoothing
    /// the sensor's noise: without the lag, the model refitted to the sensor's readings
    /// smoothed in time (a local line through the readings within ±5 min, or 1.5 typical
    /// intervals) recovers at least half of what the lag gains on the raw
    /// readings (in-sample sums of squares). A structure that truly warms later than its
    /// sensor is not imitated by smoothing the reading; noise and quantisation of the sensor
    /// are, and a short lag averages them over neighbouring readings just as well.
    pub fn smoothing_note(&self) -> Option<String> {
        let fit = self.selection.last().1;
        let effect = [PositioningEffect::ThermalLag, PositioningEffect::SensorLag]
            .into_iter()
            .find(|e| fit.effects.contains(e))?;
        let without: Vec<PositioningEffect> = fit
            .effects
            .iter()
            .copied()
            .filter(|&e| e != effect)
            .collect();
        let all = vec![true; self.problem.x.len()];
        let sum = |r: &[Real]| r.iter().map(|v| v * v).sum::<Real>();
        let raw = sum(&self.problem.fit_with(&without, &all).residuals);
        let smoothed_problem = self.problem.with_smoothed_temperature()?;
        let smoothed = sum(&smoothed_problem.fit_with(&without, &all).residuals);
        let lagged = sum(&fit.residuals);
        let gain = raw - lagged;
        let share = (raw - smoothed) / gain;
        (gain > 0.0 && share >= SMOOTHING_SHARE).then(|| {
            format!(
                "{} (τ {:.1} min) gains mostly by smoothing the sensor's noise: without it, the sensor's readings smoothed in time recover {:.0} % of its gain in sum of squares; read it as noise in the temperature reading, not as a part of the machine warming later than its sensor",
                effect.id(),
                fit.params(effect)["tau_min"],
                100.0 * share
            )
        })
    }

    /// The final model's time constants and period that lie at an end of their searched range,
    /// each with why it is not a measurement.
    pub fn range_end_notes(&self) -> Vec<String> {
        let fit = self.selection.last().1;
        let all = vec![true; self.problem.x.len()];
        [
            (PositioningEffect::ThermalLag, fit.searched.lag_tau, 0.0),
            (PositioningEffect::SensorLag, fit.searched.sensor_tau, 0.0),
            (
                PositioningEffect::SecondHeatSource,
                fit.searched.heat_tau,
                fit.searched
                    .heat_tau
                    .map_or(0.0, |_| self.problem.shortest_heating_tau(&all)),
            ),
        ]
        .into_iter()
        .filter(|(effect, _, _)| fit.effects.contains(effect))
        .filter_map(|(effect, tau, shortest)| {
            let tau = tau?;
            let why = self.problem.tau_at_range_end(tau, shortest)?;
            Some(format!(
                "{}: tau_min = {:.1} {why}",
                effect.id(),
                tau / 60.0
            ))
        })
        .chain(
            fit.searched
                .period
                .filter(|_| fit.effects.contains(&PositioningEffect::Periodic))
                .and_then(|period| {
                    let why = self.problem.period_at_range_end(period)?;
                    Some(format!(
                        "{}: period_mm = {:.1} {why}",
                        PositioningEffect::Periodic.id(),
                        period / M_PER_MM
                    ))
                }),
        )
        .collect()
    }

    fn baseline_params(&self, fit: &PositioningFit) -> Value {
        let mut params = serde_json::Map::new();
        if self.problem.temperature.is_some() {
            params.insert(
                "expansion_ppm_per_degc".into(),
                round(self.problem.options.expansion * 1e6),
            );
        }
        if let Some(t) = fit.reference_temperature {
            params.insert("reference_temperature_degc".into(), round(t));
        }
        params.insert("profile_knots".into(), json!(fit.reference.knots.len()));
        Value::Object(params)
    }

    /// The in-sample route's rule ([`engine::IN_SAMPLE_RULE`]) when this file's folds are few
    /// enough for it.
    fn in_sample_rule(&self) -> Option<&'static str> {
        (self.problem.folds.count <= engine::IN_SAMPLE_FOLDS).then_some(engine::IN_SAMPLE_RULE)
    }

    /// The report with stable keys.
    pub fn to_json(&self) -> Value {
        let um = |v: Real| round(v / M_PER_UM);
        let (base_score, base_fit) = &self.selection.baseline;
        let (knots, values) = base_fit.profile();
        let steps = self.selection.steps_json(|step| {
            let json = json!({
                "effect": step.effect.id(),
                "together_with": step.together_with.map(PositioningEffect::id),
                "together": step.together.iter().map(|e| e.id()).collect::<Vec<_>>(),
                "cause": step.effect.cause(),
                "params": params_json(&step.fit.params(step.effect)),
            });
            json.as_object().cloned().unwrap_or_default()
        });
        let (final_score, final_fit) = self.selection.last();
        let final_params: serde_json::Map<String, Value> = final_fit
            .effects
            .iter()
            .map(|&e| (e.id().to_string(), params_json(&final_fit.params(e))))
            .collect();
        json!({
            "kind": "positioning",
            "n_samples": self.problem.x.len(),
            "n_runs": self.problem.run_labels.len(),
            "axis": self.problem.axis.map(|a| a.to_string()),
            "sensor": self.problem.sensor,
            "validation": {
                "scheme": self.problem.folds.scheme,
                "folds": self.problem.folds.count,
                "fold_runs": self.fold_runs(),
                "extrapolated_folds": self.extrapolation_json(),
                "rule": engine::STEPWISE_RULE,
                "in_sample_rule": self.in_sample_rule(),
            },
            "baseline": {
                "model": self.base_name(),
                "reference_run": self.problem.run_labels[base_fit.reference.run],
                "params": self.baseline_params(base_fit),
                "profile": {
                    "positions_mm": knots.iter().map(|k| round(k / M_PER_MM)).collect::<Vec<_>>(),
                    "values_um": values.iter().map(|v| um(*v)).collect::<Vec<_>>(),
                },
                "rms_um": um(base_score.rms),
                "cv_rms_um": um(base_score.cv_rms),
                "fold_cv_rms_um": engine::folds_json(base_score),
            },
            "steps": steps,
            "moves": self.selection.moves_json(|e| e.id().into()),
            "rejected": engine::rejected_json(&self.selection.rejected, |e| e.id().into()),
            "held_back": self.selection.held_back_json(|e| e.id().into()),
            "alternatives": self.selection.alternatives_json(|e| e.id().into()),
            "notes": self
                .smoothing_note()
                .into_iter()
                .chain(self.range_end_notes())
                .collect::<Vec<_>>(),
            "excluded": self.excluded().iter().map(|(e, why)| json!({
                "effect": e.id(),
                "reason": why,
            })).collect::<Vec<_>>(),
            "untestable": self.problem.untestable.iter().map(|(e, why)| json!({
                "effect": e.id(),
                "reason": why,
            })).collect::<Vec<_>>(),
            "final": {
                "model": self.model_name(self.selection.steps.len()),
                "params": Value::Object(final_params),
                "rms_um": um(final_score.rms),
                "cv_rms_um": um(final_score.cv_rms),
                "fold_cv_rms_um": engine::folds_json(final_score),
            },
            "diagnostics": {
                "baseline": self.diagnostics_json(base_fit),
                "final": self.diagnostics_json(final_fit),
            },
        })
    }

    fn diagnostics_json(&self, fit: &PositioningFit) -> Value {
        let d = self.problem.diagnose(fit);
        let um = |v: Real| round(v / M_PER_UM);
        json!({
            "rms_um": um(d.rms),
            "position": {
                "targets": d.by_target.iter().map(|t| json!({
                    "target_mm": round(t.target / M_PER_MM),
                    "mean_up_um": t.mean_up.map(um),
                    "mean_down_um": t.mean_down.map(um),
                    "rms_um": um(t.rms),
                    "n": t.count,
                })).collect::<Vec<_>>(),
                "periodogram": d.periodogram.map(|(p, a, f)| json!({
                    "period_mm": round(p / M_PER_MM),
                    "amplitude_um": um(a),
                    "f_statistic": round(f),
                })),
                "curvature_f_statistic": d.curvature_f.map(round),
            },
            "direction": d.direction.map(|(diff, se)| json!({
                "up_minus_down_um": um(diff),
                "standard_error_um": um(se),
            })),
            "runs": d.runs.iter().map(|(label, mean, rms, t)| json!({
                "run": label,
                "mean_um": um(*mean),
                "rms_um": um(*rms),
                "temperature_degc": t.map(round),
            })).collect::<Vec<_>>(),
            "time": association_json(&d.time, "um_per_h", 3600.0 / M_PER_UM),
            "temperature": association_json(&d.temperature, "um_per_degc", 1.0 / M_PER_UM),
            "position_x_temperature": association_json(&d.position_x_temperature, "ppm_per_degc", 1e6),
            "lagged_temperature": d.lagged_temperature.map(|(tau, a)| json!({
                "tau_min": round(tau / 60.0),
                "correlation": round(a.correlation),
                "t": round(a.t),
            })),
            "position_x_rate": association_json(&d.position_x_rate, "ppm_min_per_degc", 1e6 / 60.0),
            "activity": d.activity.map(|(tau, a)| json!({
                "tau_min": round(tau / 60.0),
                "correlation": round(a.correlation),
                "t": round(a.t),
            })),
            "reversal_x_position": association_json(&d.reversal_x_position, "um_per_m", 1e6),
            "reversal_x_temperature": association_json(&d.reversal_x_temperature, "um_per_degc", 1.0 / M_PER_UM),
        })
    }

    /// The report for people.
    pub fn to_text(&self) -> String {
        let um = |v: Real| v / M_PER_UM;
        let (base_score, base_fit) = &self.selection.baseline;
        let mut out = String::new();
        let axis = self
            .problem
            .axis
            .map_or_else(|| "axis not named".to_string(), |a| format!("axis {a}"));
        out.push_str(&format!(
            "Model discovery, positioning table ({axis}): {} readings in {} runs\n",
            self.problem.x.len(),
            self.problem.run_labels.len()
        ));
        out.push_str(&format!(
            "Held-out data: {} ({} folds); {}.\n",
            self.problem.folds.scheme,
            self.problem.folds.count,
            engine::STEPWISE_RULE
        ));
        if let Some(rule) = self.in_sample_rule() {
            out.push_str(&format!("In-sample evidence: {rule}.\n"));
        }
        out.push('\n');
        out.push_str(&format!(
            "Base model: {} — profile through {} targets of run {}",
            self.base_name(),
            base_fit.reference.knots.len(),
            self.problem.run_labels[base_fit.reference.run]
        ));
        if let (Some(t), Some(sensor)) = (base_fit.reference_temperature, &self.problem.sensor) {
            out.push_str(&format!(
                ", {:.1} µm/(m·°C) × x × (temp_{sensor} − {t:.2} °C)",
                self.problem.options.expansion * 1e6
            ));
        }
        out.push_str(&format!(
            "\n  RMS {:.3} µm, held-out RMS {:.3} µm ({})\n",
            um(base_score.rms),
            um(base_score.cv_rms),
            engine::folds_text(base_score, 3)
        ));
        out.push_str(&self.extrapolation_text());
        let d = self.problem.diagnose(base_fit);
        out.push_str("\nWhat the base model leaves:\n");
        for effect in PositioningEffect::ALL {
            if let Some(text) = d.evidence(effect) {
                out.push_str(&format!("  {:<19} {text}\n", effect.id()));
            }
        }
        out.push_str(&self.selection.moves_text(|e| e.id().into(), 3));
        out.push_str("\nAccepted, in order:\n");
        if self.selection.steps.is_empty() {
            out.push_str(&self.selection.nothing_text(|e| e.id().into()));
        }
        for (step, (gain, pct)) in self.selection.steps.iter().zip(self.selection.gains()) {
            let params = engine::params_text(&step.fit.params(step.effect));
            let together = if step.together.is_empty() {
                String::new()
            } else {
                format!(
                    " (entered together with {}: the block passed its test as a whole)",
                    step.together
                        .iter()
                        .map(|e| e.id())
                        .collect::<Vec<_>>()
                        .join(" and ")
                )
            };
            out.push_str(&format!(
                "  + {}{together}: {params} at acceptance\n      cause: {}\n      held-out RMS {:.3} µm (gain {:.3} µm, {:.1} %; {}; {})\n",
                step.effect.id(),
                step.effect.cause(),
                um(step.score.cv_rms),
                um(gain),
                pct,
                engine::folds_text(&step.score, 3),
                engine::test_text(&step.test)
            ));
        }
        out.push_str(&engine::rejected_text(
            &self.selection.rejected,
            |e| e.id().into(),
            3,
        ));
        out.push_str(&self.selection.held_back_text(|e| e.id().into(), 3));
        out.push_str(&self.selection.alternatives_text(|e| e.id().into(), 3));
        let excluded = self.excluded();
        if !excluded.is_empty() {
            out.push_str("\nNot scored beside the final model:\n");
            for (effect, why) in &excluded {
                out.push_str(&format!("  {:<19} {why}\n", effect.id()));
            }
        }
        if !self.problem.untestable.is_empty() {
            out.push_str("\nCannot be tested with this file:\n");
            for (effect, why) in &self.problem.untestable {
                out.push_str(&format!("  {:<19} {why}\n", effect.id()));
            }
        }
        let (final_score, final_fit) = self.selection.last();
        out.push_str(&format!(
            "\nFinal model: {}\n  RMS {:.3} µm, held-out RMS {:.3} µm ({})\n",
            self.model_name(self.selection.steps.len()),
            um(final_score.rms),
            um(final_score.cv_rms),
            engine::folds_text(final_score, 3)
        ));
        if !final_fit.effects.is_empty() {
            out.push_str(engine::FINAL_VALUES.trim_end_matches("):"));
            out.push_str(" and the model --write-model writes):\n");
            for &effect in &final_fit.effects {
                out.push_str(&format!(
                    "    {:<19} {}\n",
                    effect.id(),
                    engine::params_text(&final_fit.params(effect))
                ));
            }
        }
        for note in self
            .smoothing_note()
            .into_iter()
            .chain(self.range_end_notes())
        {
            out.push_str(&format!("  Note: {note}.\n"));
        }
        out
    }
}
