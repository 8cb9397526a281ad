//! `estimate.json` and the report for people.
//!
//! `estimate.json` (schema 1) shares names and units with `truth.json`:
//!
//! | key | what |
//! |---|---|
//! | `mtwin`, `schema` | `"estimate"`, 1 |
//! | `machine`, `machine_file` | the machine's name and the URDF given |
//! | `errors` | per identified parameter, as in `truth.json`: `axis`, `kind`, `unit`, `terms` (file units), plus `standard_uncertainty` (linearised: the readings' noise and the known set-up quantities) and `interval_95` mirroring `terms` key by key (`interval_95` from the Monte Carlo, which draws the same noise and set-up, when it ran, else ± 1.96 u); a harmonic's mirror gives its two coefficients, `sin_um` (A cos φ) and `cos_um` (A sin φ), as the fit has them, and the amplitude and phase linearised from their covariance (`phase_deg` null at zero amplitude) |
//! | `uncertainty` | how `standard_uncertainty` and `interval_95` were formed: `standard_uncertainty` (`"linearised: noise and set-up"`), `interval_95` (`"monte_carlo"` or `"linearised"`), `monte_carlo_trials` |
//! | `unidentifiable` | the parameters the tables cannot identify: no number is given for them (a polynomial or a Fourier series with any unidentified coefficient is listed whole; `coefficients` has the others) |
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
    /// Its index in the parameter set.
    owner: usize,
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
        let mut free = (0..set.len())
            .filter(|j| set.owners(*j).any(|o| o == owner))
            .peekable();
        if free.peek().is_none() || free.any(|j| !fit.identified[j]) {
            missing.push(parameter.name);
            continue;
        }
        let function = |m: &crate::errors::ErrorModel| m.parameters()[owner].function.clone();
        identified.push(Identified {
            owner,
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
        let mut entry = json!({
            "axis": p.name.axis().map(|a| a.to_string()),
            "axis_side": axis_side,
            "kind": kind,
            "unit": p.name.file_unit(),
            "terms": spec_of(&p.value, p.name),
            "standard_uncertainty": spec_of(&p.uncertainty, p.name),
            "interval_95": pair(&low, &high),
        });
        let harmonics = harmonics(set, problem, fit, p.owner);
        if !harmonics.is_empty() {
            let unit = p.name.file_unit();
            let (u, interval): (Vec<Value>, Vec<Value>) =
                harmonics.iter().map(|h| h.mirrors(unit)).unzip();
            entry["standard_uncertainty"]["harmonic"] = Value::Array(u);
            entry["interval_95"]["harmonic"] = Value::Array(interval);
        }
        errors.insert(p.name.to_string(), entry);
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
        let polynomial = problem.labels()[j].contains(".polynomial[");
        let degree = if polynomial { set.degree[j] } else { 0 };
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
    let (identified, _) = parameters(set, problem, fit);
    let fourier: Vec<String> = (identified.iter())
        .flat_map(|parameter| {
            let unit = if parameter.name.motion().is_translation() {
                "µm"
            } else {
                "µrad"
            };
            harmonics(set, problem, fit, parameter.owner)
                .into_iter()
                .map(move |h| {
                    let (a, u) = (h.amplitude(), h.amplitude_uncertainty());
                    // Within 2 u of zero, the phase is anything.
                    let phase = if a > 2.0 * u {
                        format!(
                            "phase {:.2} ± {:.2}°",
                            h.phase().to_degrees(),
                            h.phase_uncertainty().to_degrees()
                        )
                    } else {
                        "phase not determined (amplitude within 2 u of zero)".to_string()
                    };
                    format!(
                        "  {:<6} {} per turn: amplitude {:.4} ± {:.4} {unit}, {phase}\n",
                        parameter.name.to_string(),
                        h.order,
                        a * 1e6,
                        u * 1e6,
                    )
                })
        })
        .collect();
    if !fourier.is_empty() {
        out += "rotary component errors, as amplitude · sin(k·q + phase) (u, k = 1):\n";
        out += &fourier.concat();
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

/// One harmonic of an estimated parameter: its two coefficients (SI), their covariance, and
/// their 95 % intervals.
struct Harmonic {
    /// Cycles per turn.
    order: usize,
    /// The coefficients of sin(k q) and cos(k q): `A cos φ`, `A sin φ`.
    parts: [Real; 2],
    /// Their covariance (SI²).
    covariance: [[Real; 2]; 2],
    /// Their 95 % intervals (the Monte Carlo's when it ran, else ± 1.96 u).
    intervals: [(Real, Real); 2],
}

impl Harmonic {
    fn amplitude(&self) -> Real {
        self.parts[0].hypot(self.parts[1])
    }

    /// φ, with the value `A sin(k q + φ)`.
    fn phase(&self) -> Real {
        self.parts[1].atan2(self.parts[0])
    }

    /// The linearised u of the amplitude: `∂A = (s ∂s + c ∂c) / A`.
    fn amplitude_uncertainty(&self) -> Real {
        let a = self.amplitude();
        if a == 0.0 {
            return self.covariance[0][0]
                .max(self.covariance[1][1])
                .max(0.0)
                .sqrt();
        }
        self.propagate([self.parts[0] / a, self.parts[1] / a])
    }

    /// The linearised u of the phase (rad): `∂φ = (s ∂c − c ∂s) / A²`; infinite at A = 0.
    fn phase_uncertainty(&self) -> Real {
        let a2 = self.parts[0].powi(2) + self.parts[1].powi(2);
        if a2 == 0.0 {
            return Real::INFINITY;
        }
        self.propagate([-self.parts[1] / a2, self.parts[0] / a2])
    }

    fn propagate(&self, g: [Real; 2]) -> Real {
        let c = &self.covariance;
        (g[0] * g[0] * c[0][0] + 2.0 * g[0] * g[1] * c[0][1] + g[1] * g[1] * c[1][1])
            .max(0.0)
            .sqrt()
    }

    /// The `standard_uncertainty` and `interval_95` mirrors of the harmonic in file units:
    /// the two coefficients (`sin_um`, `cos_um`: Gaussian, what a coverage is counted on)
    /// and, linearised, the amplitude and the phase (`amplitude_um`, `phase_deg`).
    fn mirrors(&self, unit: &str) -> (Value, Value) {
        let f = 1e6;
        let (ua, up) = (
            self.amplitude_uncertainty(),
            self.phase_uncertainty().to_degrees(),
        );
        let (a, phase) = (self.amplitude(), self.phase().to_degrees());
        let k = COVERAGE_FACTOR;
        let u = json!({
            format!("sin_{unit}"): self.covariance[0][0].max(0.0).sqrt() * f,
            format!("cos_{unit}"): self.covariance[1][1].max(0.0).sqrt() * f,
            format!("amplitude_{unit}"): ua * f,
            "phase_deg": up.is_finite().then_some(up),
        });
        let interval = json!({
            format!("sin_{unit}"): [self.intervals[0].0 * f, self.intervals[0].1 * f],
            format!("cos_{unit}"): [self.intervals[1].0 * f, self.intervals[1].1 * f],
            format!("amplitude_{unit}"): [(a - k * ua) * f, (a + k * ua) * f],
            "phase_deg": up.is_finite().then_some([phase - k * up, phase + k * up]),
        });
        (u, interval)
    }
}

/// The harmonics of parameter `owner` of `set`, in the order of its terms, with their
/// coefficients' covariance from the fit: each coefficient is its free unknown's value, or a
/// tie's factor times it (see [`super::spec`]).
fn harmonics(set: &ParameterSet, problem: &Problem<'_>, fit: &Fit, owner: usize) -> Vec<Harmonic> {
    let parameters = set.model.parameters();
    let first: usize = parameters[..owner]
        .iter()
        .map(|p| p.function.coefficient_count())
        .sum();
    let terms = match &parameters[owner].function {
        ErrorFunction::Sum(terms) => terms.as_slice(),
        single => std::slice::from_ref(single),
    };
    let si = problem.si(&fit.z);
    let scales = problem.scales();
    // The unknown setting coefficient `i`, and its factor.
    let source = |i: usize| {
        (0..set.len()).find_map(|j| {
            if set.free[j] == i {
                return Some((j, 1.0));
            }
            set.tied[j]
                .iter()
                .find(|t| t.coefficient == i)
                .map(|t| (j, t.factor))
        })
    };
    let mut out = Vec::new();
    let mut at = first;
    for term in terms {
        if let ErrorFunction::Harmonic { period, .. } = term {
            let sources = [source(at), source(at + 1)];
            if let [Some((js, fs)), Some((jc, fc))] = sources {
                let (gs, gc) = (fs * scales[js], fc * scales[jc]);
                let cov = |a: usize, b: usize| fit.covariance[(a, b)];
                let interval = |j: usize, factor: Real| {
                    let (lo, hi) = interval_si(problem, fit, &si, j);
                    let (a, b) = (factor * lo, factor * hi);
                    (a.min(b), a.max(b))
                };
                out.push(Harmonic {
                    order: super::spec::order_of(*period),
                    parts: [fs * si[js], fc * si[jc]],
                    covariance: [
                        [gs * gs * cov(js, js), gs * gc * cov(js, jc)],
                        [gs * gc * cov(jc, js), gc * gc * cov(jc, jc)],
                    ],
                    intervals: [interval(js, fs), interval(jc, fc)],
                });
            }
        }
        at += term.coefficient_count();
    }
    out
}
