//! Spindle discovery's reports: the evidence for each effect, its fitted values in file units,
//! the JSON with stable keys and the text for people.

use super::model::{Column, false_alarm_level, fit_linear, search_harmonic, search_line};
use super::{FALSE_ALARM, Searched, SpindleDiscovery, SpindleEffect, SpindleFit, SpindleProblem};
use crate::discovery::engine::{self, Score, round_json};
use crate::discovery::least_squares::{T_UNDEFINED, regression};
use crate::math::Real;
use serde_json::{Value, json};
use std::f64::consts::TAU;
use std::fmt::Write;

/// µm per m.
const UM: Real = 1e6;

fn rpm(speed: Real) -> Real {
    speed * 60.0 / TAU
}

/// A line's name: a whole multiple of a line found before it (`others`: fundamental and
/// harmonics carried), the bearing frequency it matches, else its ratio to the rotation.
pub(super) fn line_name(
    problem: &SpindleProblem,
    per_revolution: Real,
    others: &[(Real, usize)],
) -> String {
    let spacing = problem.spacing();
    let multiple = others.iter().find_map(|&(f, _)| {
        let h = (per_revolution / f).round();
        (h >= 2.0 && (per_revolution - h * f).abs() < spacing).then(|| {
            format!(
                "{h:.0} × the line at {f:.3} UPR ({}): a harmonic of the same periodic train",
                line_name(problem, f, &[])
            )
        })
    });
    multiple
        .or_else(|| {
            problem
                .bearing()
                .and_then(|b| b.name(per_revolution, spacing))
        })
        .unwrap_or_else(|| format!("{per_revolution:.3} × the rotation"))
}

/// The frequency of a line at `per_revolution` in Hz at each speed, for people.
fn hz_text(problem: &SpindleProblem, per_revolution: Real) -> String {
    let speeds: Vec<String> = problem
        .data()
        .segments
        .iter()
        .map(|s| {
            format!(
                "{:.1} Hz at {:.0} min⁻¹",
                per_revolution * s.turns_per_second,
                s.turns_per_second * 60.0
            )
        })
        .collect();
    speeds.join(", ")
}

/// What the residual of `fit` shows for `effect`, in words.
pub(super) fn evidence(
    problem: &SpindleProblem,
    effect: SpindleEffect,
    fit: &SpindleFit,
) -> String {
    let data = problem.data();
    let train = vec![true; data.len()];
    let residuals = &fit.linear.residuals;
    let probes = data.probes.len();
    // A search's F is each probe's gain over its residual variance: with no scatter left in
    // any probe it cannot be formed, which is said in words rather than as a number.
    let scatter = residuals.iter().any(|r| r.iter().any(|v| *v != 0.0));
    match effect {
        SpindleEffect::Harmonic(_) | SpindleEffect::AsynchronousLine(_) if !scatter => {
            "F not defined: the residual has no scatter in any probe".to_string()
        }
        SpindleEffect::Harmonic(_) => {
            let taken: Vec<usize> = fit
                .searched
                .iter()
                .filter_map(|s| match s {
                    Searched::Order(k) => Some(*k),
                    _ => None,
                })
                .collect();
            match search_harmonic(
                data,
                residuals,
                &train,
                problem.base_harmonics() + 1,
                &taken,
            ) {
                Some(peak) => format!(
                    "strongest synchronous order {} UPR: F summed over {probes} probe(s) {:.1} (5 % false-alarm level over {} orders {:.1})",
                    peak.at,
                    peak.f,
                    peak.searched,
                    false_alarm_level(probes, peak.searched, FALSE_ALARM)
                ),
                None => "no order left to search".to_string(),
            }
        }
        SpindleEffect::AsynchronousLine(_) => {
            let taken = super::taken_lines(&fit.searched);
            match search_line(data, residuals, &train, &taken) {
                Some(peak) => format!(
                    "strongest asynchronous component at {:.3} UPR ({}; {}){}: its fundamental's F summed over {probes} probe(s) {:.1} (5 % false-alarm level over {} frequencies {:.1})",
                    peak.frequency,
                    line_name(problem, peak.frequency, &taken),
                    hz_text(problem, peak.frequency),
                    if peak.harmonics > 1 {
                        format!(" with {} harmonics (a periodic train)", peak.harmonics)
                    } else {
                        String::new()
                    },
                    peak.f,
                    peak.searched,
                    false_alarm_level(probes * data.segments.len(), peak.searched, FALSE_ALARM)
                ),
                None => "no frequency left to search".to_string(),
            }
        }
        SpindleEffect::Drift => {
            let (t0, t1) = data.time_span();
            let column = Column::Drift(None, t0, t1);
            let x: Vec<Real> = (0..data.len()).map(|i| column.value(data, i)).collect();
            // The probe with the largest |t|; a probe whose residual has no scatter has no t.
            let strongest = residuals
                .iter()
                .enumerate()
                .filter_map(|(p, r)| slope(&x, r).and_then(|(s, t)| Some((p, s, t?))))
                .max_by(|a, b| a.2.abs().total_cmp(&b.2.abs()));
            match strongest {
                Some((probe, slope, t)) => format!(
                    "a trend over the {:.1} s of the record: strongest in {} ({:+.3} µm, t = {t:.1})",
                    t1 - t0,
                    data.probes[probe],
                    slope * UM
                ),
                None => format!(
                    "a trend over the {:.1} s of the record: {T_UNDEFINED} in any probe",
                    t1 - t0
                ),
            }
        }
        SpindleEffect::SpeedDependence => {
            let mut columns = fit.linear.columns.clone();
            let base = columns.len();
            for s in 1..data.segments.len() {
                for k in 1..=problem.base_harmonics() {
                    columns.extend([Column::SegmentCos(k, s), Column::SegmentSin(k, s)]);
                }
            }
            let extended = fit_linear(data, &columns, &train);
            let (probe, change) = extended
                .coefficients
                .iter()
                .enumerate()
                .map(|(p, c)| (p, c[base..].iter().map(|v| v * v).sum::<Real>().sqrt()))
                .max_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap_or((0, 0.0));
            format!(
                "the harmonics 1–{} differ between the {} speeds: largest change in {} ({:.3} µm, root sum of squares of the differences)",
                problem.base_harmonics(),
                data.segments.len(),
                data.probes[probe],
                change * UM
            )
        }
    }
}

/// The least-squares slope of `r` on `x` with an intercept (both centred) and its t statistic
/// (`None` when the residual has no scatter).
fn slope(x: &[Real], r: &[Real]) -> Option<(Real, Option<Real>)> {
    let centred = |v: &[Real]| -> Vec<Real> {
        let mean = v.iter().sum::<Real>() / v.len().max(1) as Real;
        v.iter().map(|a| a - mean).collect()
    };
    regression(&centred(x), &centred(r))
}

/// The amplitude of a cos/sin pair in `fit` for probe `p` (m).
fn pair(fit: &SpindleFit, p: usize, cos: Column, sin: Column) -> Real {
    fit.linear
        .coefficient(p, cos)
        .hypot(fit.linear.coefficient(p, sin))
}

/// The values of `effect` in `fit`, in file units with the unit in the name.
pub(super) fn params(problem: &SpindleProblem, fit: &SpindleFit, effect: SpindleEffect) -> Value {
    let data = problem.data();
    let Some(index) = fit.effects.iter().position(|e| *e == effect) else {
        return Value::Null;
    };
    let per_probe = |value: &dyn Fn(usize) -> Value| -> Value {
        Value::Object(
            data.probes
                .iter()
                .enumerate()
                .map(|(p, name)| (format!("{name}_um"), value(p)))
                .collect(),
        )
    };
    match (effect, fit.searched[index]) {
        (SpindleEffect::Harmonic(_), Searched::Order(k)) => json!({
            "per_revolution": k,
            "amplitude": per_probe(&|p| round_json(pair(fit, p, Column::Cos(k), Column::Sin(k)) * UM)),
        }),
        (SpindleEffect::AsynchronousLine(_), Searched::Line(f, harmonics)) => json!({
            "per_revolution": round_json(f),
            "harmonics": harmonics,
            "name": line_name(problem, f, &super::taken_lines(&fit.searched[..index])),
            "hz": data.segments.iter().map(|s| round_json(f * s.turns_per_second)).collect::<Vec<_>>(),
            "amplitude": per_probe(&|p| json!((0..data.segments.len())
                .map(|s| round_json(pair(fit, p, Column::LineCos(f, s), Column::LineSin(f, s)) * UM))
                .collect::<Vec<_>>())),
        }),
        (SpindleEffect::Drift, Searched::TimeConstant(tau)) => {
            let (t0, t1) = data.time_span();
            json!({
                "time_constant_s": tau.map(round_json),
                "time_constant_note": tau.and_then(|tau| problem.time_constant_at_range_end(tau)),
                "over_s": round_json(t1 - t0),
                "drift": per_probe(&|p| round_json(fit.linear.coefficient(p, Column::Drift(tau, t0, t1)) * UM)),
            })
        }
        (SpindleEffect::SpeedDependence, _) => json!({
            "speeds_rpm": data.segments.iter().map(|s| round_json(rpm(s.speed))).collect::<Vec<_>>(),
            "amplitude": per_probe(&|p| {
                Value::Object((1..=problem.base_harmonics()).map(|k| {
                    let at: Vec<Value> = (0..data.segments.len()).map(|s| {
                        let part = |c: Column, sc: Column| {
                            fit.linear.coefficient(p, c) + if s > 0 { fit.linear.coefficient(p, sc) } else { 0.0 }
                        };
                        let a = part(Column::Cos(k), Column::SegmentCos(k, s));
                        let b = part(Column::Sin(k), Column::SegmentSin(k, s));
                        round_json(a.hypot(b) * UM)
                    }).collect();
                    (format!("upr_{k}"), json!(at))
                }).collect())
            }),
        }),
        _ => Value::Null,
    }
}

/// An effect's values for people, one line.
fn params_text(problem: &SpindleProblem, fit: &SpindleFit, effect: SpindleEffect) -> String {
    let value = params(problem, fit, effect);
    match effect {
        SpindleEffect::Harmonic(_) => format!(
            "{} UPR, amplitude {}",
            value["per_revolution"],
            numbers_flat(&value["amplitude"])
        ),
        SpindleEffect::AsynchronousLine(_) => format!(
            "{:.3} UPR{} = {} ({}), fundamental's amplitude per speed {}",
            value["per_revolution"].as_f64().unwrap_or(0.0),
            match value["harmonics"].as_u64() {
                Some(h) if h > 1 => format!(" with {h} harmonics"),
                _ => String::new(),
            },
            value["name"].as_str().unwrap_or(""),
            value["hz"]
                .as_array()
                .map(|hz| hz
                    .iter()
                    .map(|v| format!("{:.1} Hz", v.as_f64().unwrap_or(0.0)))
                    .collect::<Vec<_>>()
                    .join("/"))
                .unwrap_or_default(),
            numbers_flat(&value["amplitude"])
        ),
        SpindleEffect::Drift => format!(
            "{}{} over {:.1} s, drift {}",
            value["time_constant_s"]
                .as_f64()
                .map_or("linear".to_string(), |t| format!("τ = {t:.1} s")),
            value["time_constant_note"]
                .as_str()
                .map_or(String::new(), |note| format!(" ({note})")),
            value["over_s"].as_f64().unwrap_or(0.0),
            numbers_flat(&value["drift"])
        ),
        SpindleEffect::SpeedDependence => format!(
            "at {} min⁻¹: {}",
            numbers_flat(&value["speeds_rpm"]),
            numbers_flat(&value["amplitude"])
        ),
    }
}

/// Numbers of a JSON array or number, `/`-separated, 3 decimals.
fn numbers_flat(v: &Value) -> String {
    match v {
        Value::Array(items) => items.iter().map(numbers_flat).collect::<Vec<_>>().join("/"),
        Value::Number(n) => format!("{:.3}", n.as_f64().unwrap_or(0.0)),
        Value::Object(map) => map
            .iter()
            .map(|(k, v)| format!("{k} {}", numbers_flat(v)))
            .collect::<Vec<_>>()
            .join(", "),
        _ => v.to_string(),
    }
}

impl SpindleDiscovery {
    /// The model after `k` accepted effects, named.
    fn model_name(&self, k: usize) -> String {
        std::iter::once(format!("base (K = {})", self.problem.base_harmonics()))
            .chain(
                self.selection.steps[..k]
                    .iter()
                    .map(|s| s.effect.id().to_string()),
            )
            .collect::<Vec<_>>()
            .join(" + ")
    }

    fn base_model(&self) -> String {
        format!(
            "each speed's mean + harmonics 1–{} of the angle, per probe (set-up and low-order synchronous error motion)",
            self.problem.base_harmonics()
        )
    }

    /// The report with stable keys.
    pub fn to_json(&self) -> Value {
        let problem = &self.problem;
        let data = problem.data();
        let (base_score, base_fit) = &self.selection.baseline;
        let steps = self.selection.steps_json(|step| {
            let json = json!({
                "effect": step.effect.id(),
                "together_with": step.together_with.map(|e| e.id()),
                "cause": step.effect.cause(),
                "params": params(problem, &step.fit, step.effect),
            });
            json.as_object().cloned().unwrap_or_default()
        });
        let (final_score, final_fit) = self.selection.last();
        let final_params: serde_json::Map<String, Value> = self
            .selection
            .steps
            .iter()
            .map(|s| {
                (
                    s.effect.id().to_string(),
                    params(problem, final_fit, s.effect),
                )
            })
            .collect();
        let evidence: serde_json::Map<String, Value> = problem
            .next(&[])
            .into_iter()
            .map(|e| (e.id().to_string(), json!(evidence(problem, e, base_fit))))
            .collect();
        json!({
            "kind": "spindle",
            "setup": data.setup,
            "other_setups": data.other_setups,
            "probes": data.probes,
            "samples_per_revolution": data.samples_per_revolution,
            "speeds_rpm": data.segments.iter().map(|s| round_json(rpm(s.speed))).collect::<Vec<_>>(),
            "revolutions": data.segments.iter().map(|s| s.revolutions).collect::<Vec<_>>(),
            "n_samples": data.len() * data.probes.len(),
            "validation": {
                "scheme": problem.folds.scheme,
                "folds": problem.folds.count,
                "rule": engine::RULE,
            },
            "baseline": {
                "model": self.base_model(),
                "base_harmonics": problem.base_harmonics(),
                "rms_um": round_json(base_score.rms * UM),
                "cv_rms_um": round_json(base_score.cv_rms * UM),
                "fold_cv_rms_um": engine::folds_json(base_score),
                "evidence": Value::Object(evidence),
            },
            "steps": steps,
            "rejected": engine::rejected_json(&self.selection.rejected, |e| e.id().into()),
            "untestable": problem.untestable().iter().map(|(e, why)| json!({
                "effect": e.id(),
                "reason": why,
            })).collect::<Vec<_>>(),
            "final": {
                "model": self.model_name(self.selection.steps.len()),
                "params": Value::Object(final_params),
                "rms_um": round_json(final_score.rms * UM),
                "cv_rms_um": round_json(final_score.cv_rms * UM),
                "fold_cv_rms_um": engine::folds_json(final_score),
            },
        })
    }

    /// The report for people.
    pub fn to_text(&self) -> String {
        let problem = &self.problem;
        let data = problem.data();
        let (base_score, base_fit) = &self.selection.baseline;
        let folds = |score: &Score| engine::folds_text(score, 4);
        let mut out = String::new();
        let setup = if data.setup.is_empty() {
            String::new()
        } else {
            format!(", set-up `{}`", data.setup)
        };
        let _ = writeln!(
            out,
            "Model discovery, spindle record{setup}: probes {}, {} samples per revolution, {} speed(s) ({} min⁻¹), {} revolutions",
            data.probes.join(" "),
            data.samples_per_revolution,
            data.segments.len(),
            data.segments
                .iter()
                .map(|s| format!("{:.0}", rpm(s.speed)))
                .collect::<Vec<_>>()
                .join("/"),
            data.segments
                .iter()
                .map(|s| s.revolutions.to_string())
                .collect::<Vec<_>>()
                .join("/")
        );
        if !data.other_setups.is_empty() {
            let _ = writeln!(
                out,
                "(set-ups not searched: {}; choose one with --setup)",
                data.other_setups.join(", ")
            );
        }
        let _ = writeln!(
            out,
            "Held-out data: {}; {}.\n",
            problem.folds.scheme,
            engine::RULE
        );
        let _ = writeln!(
            out,
            "Base model: {}\n  RMS {:.4} µm, held-out RMS {:.4} µm ({})",
            self.base_model(),
            base_score.rms * UM,
            base_score.cv_rms * UM,
            folds(base_score)
        );
        let _ = writeln!(out, "\nWhat the base model leaves:");
        for effect in problem.next(&[]) {
            let _ = writeln!(
                out,
                "  {:<20} {}",
                effect.id(),
                evidence(problem, effect, base_fit)
            );
        }
        let _ = writeln!(out, "\nAccepted, in order:");
        if self.selection.steps.is_empty() {
            out.push_str(&self.selection.nothing_text(|e| e.id().into()));
        }
        for (step, (gain, pct)) in self.selection.steps.iter().zip(self.selection.gains()) {
            let together = step.together_with.map_or_else(String::new, |other| {
                format!(
                    " (accepted together with {}: neither passes alone)",
                    other.id()
                )
            });
            let _ = writeln!(
                out,
                "  + {}{together}: {}\n      cause: {}\n      held-out RMS {:.4} µm (gain {:.4} µm, {:.1} %; {}; {})",
                step.effect.id(),
                params_text(problem, &step.fit, step.effect),
                step.effect.cause(),
                step.score.cv_rms * UM,
                gain * UM,
                pct,
                folds(&step.score),
                engine::test_text(&step.test)
            );
        }
        out.push_str(&engine::rejected_text(
            &self.selection.rejected,
            |e| e.id().into(),
            4,
        ));
        if !problem.untestable().is_empty() {
            let _ = writeln!(out, "\nCannot be tested with this record:");
            for (effect, why) in problem.untestable() {
                let _ = writeln!(out, "  {:<20} {why}", effect.id());
            }
        }
        let (final_score, final_fit) = self.selection.last();
        let _ = writeln!(
            out,
            "\nFinal model: {}\n  RMS {:.4} µm, held-out RMS {:.4} µm ({})",
            self.model_name(self.selection.steps.len()),
            final_score.rms * UM,
            final_score.cv_rms * UM,
            folds(final_score)
        );
        if !self.selection.steps.is_empty() {
            let _ = writeln!(out, "{}", engine::FINAL_VALUES);
            for step in &self.selection.steps {
                let _ = writeln!(
                    out,
                    "    {:<20} {}",
                    step.effect.id(),
                    params_text(problem, final_fit, step.effect)
                );
            }
        }
        out
    }
}
