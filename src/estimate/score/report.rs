//! What scoring found ([`Score`]), for people ([`Score::report`]) and as JSON with the stable
//! keys of the module doc ([`Score::to_json`]).

use super::terms::ParameterScore;
use super::volumetric::Volumetric;
use crate::math::Real;
use serde_json::{Value, json};

/// An estimate scored against the truth.
#[derive(Debug, Clone, PartialEq)]
pub struct Score {
    /// The machine both files are for.
    pub machine: String,
    /// Every compared term, parameters in name order.
    pub parameters: Vec<ParameterScore>,
    /// Estimated parameters the truth does not have (scored against zero).
    pub not_in_truth: Vec<String>,
    /// Truth parameters the estimate has no entry for.
    pub not_estimated: Vec<String>,
    /// The parameters the estimate declares unidentifiable.
    pub unidentifiable: Vec<String>,
    /// Truth terms the estimate's families cannot hold (see the module doc).
    pub unmodelled_terms: Vec<String>,
    /// (terms whose 95 % interval covers the truth, terms with an interval).
    pub coverage: (usize, usize),
    /// The tool-tip deviation before and after compensating with the estimate.
    pub volumetric: Volumetric,
}

/// A number for people: 4 significant digits, in exponent form when very small or large.
fn number(value: Real) -> String {
    let magnitude = value.abs();
    if value == 0.0 {
        "0".into()
    } else if !(1e-3..1e5).contains(&magnitude) {
        format!("{value:.3e}")
    } else {
        let decimals = (3 - magnitude.log10().floor() as i32).max(0) as usize;
        crate::math::fixed(value, decimals)
    }
}

impl Score {
    /// The score for people: one line per compared term, the lists, the coverage and the
    /// volumetric figure.
    pub fn report(&self) -> String {
        let mut out = format!(
            "Estimate scored against the truth, machine {}\n\n",
            self.machine
        );
        if self.parameters.is_empty() {
            out += "No term estimated.\n";
        } else {
            out += &format!(
                "{:<34} {:<12} {:>11} {:>11} {:>11} {:>10} {:>8} {:>8}\n",
                "term", "unit", "estimate", "truth", "error", "u (k=1)", "error/u", "in 95%"
            );
            for p in &self.parameters {
                out += &format!(
                    "{:<34} {:<12} {:>11} {:>11} {:>11} {:>10} {:>8} {:>8}\n",
                    p.name,
                    p.unit,
                    number(p.estimate),
                    number(p.truth),
                    number(p.error),
                    p.uncertainty.map_or("-".into(), number),
                    p.normalised.map_or("-".into(), |n| format!("{n:.2}")),
                    p.covered.map_or("-", |c| if c { "yes" } else { "NO" }),
                );
            }
        }
        out += "\n";
        let list = |label: &str, names: &[String]| {
            if names.is_empty() {
                String::new()
            } else {
                format!("{label}: {}\n", names.join(", "))
            }
        };
        out += &list("In the truth, not estimated", &self.not_estimated);
        out += &list(
            "Declared unidentifiable by the estimate",
            &self.unidentifiable,
        );
        out += &list(
            "Estimated, not in the truth (scored against 0)",
            &self.not_in_truth,
        );
        out += &list(
            "Truth terms the estimate's families cannot hold (in the volumetric figure only)",
            &self.unmodelled_terms,
        );
        let (covered, with_interval) = self.coverage;
        if with_interval > 0 {
            out += &format!(
                "95 % intervals covering the truth: {covered} of {with_interval} ({:.0} %)\n",
                100.0 * covered as Real / with_interval as Real
            );
        }
        let v = &self.volumetric;
        out += &format!(
            "\nTool-tip deviation over the working volume ({} states):\n\
             {:<14} RMS {:>9} um   max {:>9} um\n\
             {:<14} RMS {:>9} um   max {:>9} um\n",
            v.points,
            "uncompensated",
            crate::math::fixed(v.uncompensated_rms_um, 3),
            crate::math::fixed(v.uncompensated_max_um, 3),
            "compensated",
            crate::math::fixed(v.compensated_rms_um, 3),
            crate::math::fixed(v.compensated_max_um, 3),
        );
        out
    }

    /// The score as JSON, with the stable keys of the module doc.
    pub fn to_json(&self) -> Value {
        let parameters: Vec<Value> = self
            .parameters
            .iter()
            .map(|p| {
                json!({
                    "name": p.name,
                    "unit": p.unit,
                    "estimate": p.estimate,
                    "truth": p.truth,
                    "error": p.error,
                    "uncertainty": p.uncertainty,
                    "normalised": p.normalised,
                    "covered": p.covered,
                })
            })
            .collect();
        let v = &self.volumetric;
        json!({
            "mtwin": "score",
            "schema": 1,
            "machine": self.machine,
            "parameters": parameters,
            "not_in_truth": self.not_in_truth,
            "not_estimated": self.not_estimated,
            "unidentifiable": self.unidentifiable,
            "unmodelled_terms": self.unmodelled_terms,
            "coverage": { "covered": self.coverage.0, "with_interval": self.coverage.1 },
            "volumetric": {
                "points": v.points,
                "uncompensated_rms_um": v.uncompensated_rms_um,
                "uncompensated_max_um": v.uncompensated_max_um,
                "compensated_rms_um": v.compensated_rms_um,
                "compensated_max_um": v.compensated_max_um,
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_for_people() {
        assert_eq!(number(12.03), "12.03");
        assert_eq!(number(0.0121), "0.01210");
        assert_eq!(number(-8e-6), "-8.000e-6");
        assert_eq!(number(0.0), "0");
    }
}
