//! `estimate.json` and the report for people.
//!
//! `estimate.json` (schema 1) shares names and units with `truth.json`:
//!
//! | key | what |
//! |---|---|
//! | `mtwin`, `schema` | `"estimate"`, 1 |
//! | `machine`, `machine_file` | the machine's name and the URDF given |
//! | `errors` | per identified parameter, as in `truth.json`: `axis`, `kind`, `unit`, `terms` (file units), plus `standard_uncertainty` (linearised: the readings' noise and the known set-up quantities) and `interval_95` mirroring `terms` key by key (`interval_95` from the Monte Carlo, which draws the same noise and set-up, when it ran, else ± 1.96 u) |
//! | `uncertainty` | how `standard_uncertainty` and `interval_95` were formed: `standard_uncertainty` (`"linearised: noise and set-up"`), `interval_95` (`"monte_carlo"` or `"linearised"`), `monte_carlo_trials` |
//! | `unidentifiable` | the parameters the tables cannot identify: no number is given for them (a polynomial with any unidentified coefficient is listed whole; `coefficients` has the others) |
//! | `null_combinations` | what cannot be told apart (each a text in ISO names) |
//! | `seen_combinations` | what the tables do see among the unidentifiable parameters: `combination`, `value_um`, `standard_uncertainty_um` (solver units: µm, a rotation as its motion at 100 mm, a polynomial coefficient at the end of travel) |
//! | `nuisance` | the set-up unknowns: `name`, `value_um` or `value_urad`, `standard_uncertainty_…` |
//! | `fit` | `readings`, `chi2`, `dof`, `birge_scaled` (χ²/dof when the uncertainties were scaled by it, else null), `iterations`, `residual_rms_um` per table, `monte_carlo_trials` |
//! | `identifiability` | [`super::identifiability::Identifiability::to_json`] |
//! | `coefficients` | every unknown: `label`, `value_si`, `standard_uncertainty_si` (null if unidentified), `identified` |
//! | `remedies` | (with an R-test table and unseen combinations) per combination the candidate R-tests that would make it identifiable, best first: `combination`, `tests` [{`test`, `standard_uncertainty_um`}] |

use super::fit::{Fit, Problem};
use super::spec::ParameterSet;
use crate::errors::{ErrorFunction, ParameterName};
use crate::machine::Machine;
use crate::math::Real;
use crate::scenario::spec_of;
use serde_json::{Value, json};

/// Coverage factor of the linearised 95 % interval (normal distribution).
pub const COVERAGE_FACTOR: Real = 1.96;

/// The standard uncertainty (SI) of unknown `j`, 0 when unidentified.
fn uncertainty_si(problem: &Problem<'_>, fit: &Fit, j: usize) -> Real {
    fit.uncertainty(j).unwrap_or(0.0) * problem.scales()[j]
}

/// The 95 % interval (SI) of unknown `j`: the Monte Carlo's when it ran, else ± 1.96 u.
fn interval_si(problem: &Problem<'_>, fit: &Fit, si: &[Real], j: usize) -> (Real, Real) {
    let scale = problem.scales()[j];
    match &fit.monte_carlo {
        Some(mc) => {
            let (lo, hi) = mc.interval[j];
            (
                si[j] + (lo - fit.z[j]) * scale,
                si[j] + (hi - fit.z[j]) * scale,
            )
        }
        None => {
            let u = uncertainty_si(problem, fit, j);
            (si[j] - COVERAGE_FACTOR * u, si[j] + COVERAGE_FACTOR * u)
        }
    }
}

/// The identified value, uncertainty and interval of one parameter (SI functions).
struct Identified {
    name: ParameterName,
    value: ErrorFunction,
    uncertainty: ErrorFunction,
    low: ErrorFunction,
    high: ErrorFunction,
}

/// The parameters of `set` that the fit identified, each as functions (value, uncertainty and
/// the ends of the 95 % interval), and the names of the unidentified ones.
fn parameters(
    set: &ParameterSet,
    problem: &Problem<'_>,
    fit: &Fit,
) -> (Vec<Identified>, Vec<ParameterName>) {
    let si = problem.si(&fit.z);
    // Each quantity of every free coefficient written into the parameters' functions.
    let model = |value: &dyn Fn(usize) -> Real| {
        set.model_with(&(0..set.len()).map(value).collect::<Vec<_>>())
    };
    let values = model(&|j| si[j]);
    let uncertainties = model(&|j| uncertainty_si(problem, fit, j));
    let lows = model(&|j| interval_si(problem, fit, &si, j).0);
    let highs = model(&|j| interval_si(problem, fit, &si, j).1);
    let mut identified = Vec::new();
    let mut missing = Vec::new();
    for (owner, parameter) in set.model.parameters().iter().enumerate() {
        let mut free = (0..set.len()).filter(|j| set.owner[*j] == owner).peekable();
        if free.peek().is_none() || free.any(|j| !fit.identified[j]) {
            missing.push(parameter.name);
            continue;
        }
        let function = |m: &crate::errors::ErrorModel| m.parameters()[owner].function.clone();
        identified.push(Identified {
            name: parameter.name,
            value: function(&values),
            uncertainty: function(&uncertainties),
            low: function(&lows),
            high: function(&highs),
        });
    }
    (identified, missing)
}

/// The identified parameters as an error model's functions (SI), for compensation and
/// scoring: the unidentified ones are left out.
pub fn identified_model(
    set: &ParameterSet,
    problem: &Problem<'_>,
    fit: &Fit,
    machine: &Machine,
) -> crate::errors::ErrorModel {
    let (identified, _) = parameters(set, problem, fit);
    let parameters = identified
        .into_iter()
        .map(|p| crate::errors::ErrorParameter {
            name: p.name,
            function: p.value,
        })
        .collect();
    crate::errors::ErrorModel::new(machine, parameters)
        .expect("a subset of a valid parameter set is valid")
}

/// `estimate.json` for a fit.
pub fn to_json(
    set: &ParameterSet,
    problem: &Problem<'_>,
    fit: &Fit,
    machine: &Machine,
    machine_file: &str,
    sources: &[String],
) -> Value {
    let (identified, missing) = parameters(set, problem, fit);
    let mut errors = serde_json::Map::new();
    for p in &identified {
        let axis_side = p
            .name
            .axis()
            .and_then(|a| machine.axis(a))
            .map(|i| format!("{:?}", i.side).to_lowercase());
        let kind = match p.name {
            ParameterName::Component { .. } => "component",
            ParameterName::Location { axis, .. } if axis.is_linear() => "squareness",
            ParameterName::Location { .. } => "location",
            ParameterName::Tool { .. } => "tool",
        };
        let low = serde_json::to_value(spec_of(&p.low, p.name)).unwrap_or(Value::Null);
        let high = serde_json::to_value(spec_of(&p.high, p.name)).unwrap_or(Value::Null);
        errors.insert(
            p.name.to_string(),
            json!({
                "axis": p.name.axis().map(|a| a.to_string()),
                "axis_side": axis_side,
                "kind": kind,
                "unit": p.name.file_unit(),
                "terms": spec_of(&p.value, p.name),
                "standard_uncertainty": spec_of(&p.uncertainty, p.name),
                "interval_95": pair(&low, &high),
            }),
        );
    }
    let labels = problem.labels();
    let scales = problem.scales();
    let si = problem.si(&fit.z);
    let nuisance: Vec<Value> = (set.len()..problem.unknowns())
        .map(|j| {
            let unit = if problem.rotation()[j] { "urad" } else { "um" };
            let u = fit.uncertainty(j).map(|u| u * scales[j] * 1e6);
            json!({
                "name": labels[j],
                format!("value_{unit}"): fit.identified[j].then(|| si[j] * 1e6),
                format!("standard_uncertainty_{unit}"): u,
            })
        })
        .collect();
    let seen: Vec<Value> = fit
        .identifiability
        .seen_combinations
        .iter()
        .map(|c| {
            // The coefficients as `describe` prints them (the largest one).
            let terms = c.described_terms();
            let value: Real = terms.iter().map(|(j, k)| k * fit.z[*j]).sum();
            let variance: Real = terms
                .iter()
                .flat_map(|(i, a)| terms.iter().map(move |(j, b)| (i, a, j, b)))
                .map(|(i, a, j, b)| a * b * fit.covariance[(*i, *j)])
                .sum();
            json!({
                "combination": c.describe(labels),
                "value_um": value,
                "standard_uncertainty_um": variance.max(0.0).sqrt(),
            })
        })
        .collect();
    let coefficients: Vec<Value> = (0..problem.unknowns())
        .map(|j| {
            json!({
                "label": labels[j],
                "value_si": fit.identified[j].then(|| si[j]),
                "standard_uncertainty_si": fit.uncertainty(j).map(|u| u * scales[j]),
                "identified": fit.identified[j],
            })
        })
        .collect();
    json!({
        "mtwin": "estimate",
        "schema": 1,
        "machine": machine.name(),
        "machine_file": machine_file,
        "tables": sources,
        "errors": errors,
        "unidentifiable": missing.iter().map(|n| n.to_string()).collect::<Vec<_>>(),
        "null_combinations": fit.identifiability.null_combinations.iter().map(|c| c.describe(labels)).collect::<Vec<_>>(),
        "seen_combinations": seen,
        "nuisance": nuisance,
        "fit": {
            "readings": problem.rows(),
            "chi2": fit.chi2,
            "dof": fit.dof,
            "birge_scaled": fit.birge_scaled,
            "iterations": fit.iterations,
            "residual_rms_um": fit.residual_rms.iter().map(|r| r * 1e6).collect::<Vec<_>>(),
            "monte_carlo_trials": fit.monte_carlo.as_ref().map(|m| m.trials),
        },
        "identifiability": fit.identifiability.to_json(),
        "coefficients": coefficients,
        "uncertainty": {
            "standard_uncertainty": "linearised: noise and set-up",
            "interval_95": if fit.monte_carlo.is_some() { "monte_carlo" } else { "linearised" },
            "monte_carlo_trials": fit.monte_carlo.as_ref().map(|m| m.trials),
        },
    })
}

/// Two JSON trees of the same shape zipped into `[low, high]` pairs at the numbers.
fn pair(low: &Value, high: &Value) -> Value {
    match (low, high) {
        (Value::Number(_), Value::Number(_)) => json!([low, high]),
        (Value::Array(a), Value::Array(b)) => {
            Value::Array(a.iter().zip(b).map(|(x, y)| pair(x, y)).collect())
        }
        (Value::Object(a), Value::Object(b)) => Value::Object(
            a.iter()
                .filter_map(|(k, x)| Some((k.clone(), pair(x, b.get(k)?))))
                .collect(),
        ),
        _ => Value::Null,
    }
}

/// The report for people.
pub fn text(set: &ParameterSet, problem: &Problem<'_>, fit: &Fit, sources: &[String]) -> String {
    let mut out = String::new();
    out += &format!(
        "identify: {} readings from {} table(s), {} unknowns ({} error coefficients, {} set-up)\n",
        problem.rows(),
        sources.len(),
        problem.unknowns(),
        set.len(),
        problem.unknowns() - set.len()
    );
    out += &fit.identifiability.report();
    let shows_u =
        !fit.identifiability.seen_combinations.is_empty() || !fit.identifiability.weak.is_empty();
    if let Some(b) = fit.birge_scaled.filter(|_| shows_u) {
        out += &format!(
            "(the uncertainties above are the design's at the stated reading uncertainties; the table below scales them by √{b:.2}, the residuals being larger)\n"
        );
    }
    out += "\n";
    let si = problem.si(&fit.z);
    out += &format!(
        "{:<22} {:>12} {:>10} {:>25}  unit\n",
        "parameter", "estimate", "u (k=1)", "95 % interval"
    );
    for j in 0..problem.unknowns() {
        let unit = if problem.rotation()[j] {
            "µrad"
        } else {
            "µm"
        };
        let degree = set.degree.get(j).copied().unwrap_or(0);
        // File units: µm (µrad) per mm^k for a polynomial coefficient of a linear axis.
        let factor = 1e6 * 1e-3_f64.powi(degree as i32);
        let unit = match degree {
            0 => unit.to_string(),
            1 => format!("{unit}/mm"),
            k => format!("{unit}/mm^{k}"),
        };
        if !fit.identified[j] {
            out += &format!("{:<22} {:>12}\n", problem.labels()[j], "unidentifiable");
            continue;
        }
        let u = uncertainty_si(problem, fit, j);
        let (lo, hi) = interval_si(problem, fit, &si, j);
        out += &format!(
            "{:<22} {:>12.4} {:>10.4} {:>12.4} … {:<10.4}  {unit}\n",
            problem.labels()[j],
            si[j] * factor,
            u * factor,
            lo * factor,
            hi * factor
        );
    }
    out += &format!(
        "fit: χ² = {:.1} for {} degrees of freedom (χ²/dof = {:.2}), {} iterations",
        fit.chi2,
        fit.dof,
        fit.chi2 / fit.dof.max(1) as Real,
        fit.iterations
    );
    if let Some(b) = fit.birge_scaled {
        out += &format!(
            "; the residuals exceed the stated uncertainties: uncertainties scaled by √{b:.2}"
        );
    }
    out += "\n";
    for (source, rms) in sources.iter().zip(&fit.residual_rms) {
        out += &format!("  residual RMS {:.3} µm  {source}\n", rms * 1e6);
    }
    out += &format!(
        "u: linearised, from the readings' noise and the set-up quantities' uncertainties; {}\n",
        match &fit.monte_carlo {
            Some(mc) => format!(
                "95 % intervals: Monte Carlo, {} trials drawing the same noise and set-up (GUM Supplement 1)",
                mc.trials
            ),
            None => "95 % intervals: ± 1.96 u".to_string(),
        }
    );
    out
}
