//! Term by term: every term of an estimated parameter matched with the truth's (see the
//! module doc for how each family is matched), then scored with the uncertainty and the
//! 95 % interval the estimate gives for it ([`ParameterScore`]).

use super::entries::position_unit;
use super::error::ScoreError;
use crate::errors::ParameterName;
use crate::machine::Direction;
use crate::math::{RAD_PER_URAD, Real};
use crate::scenario::{ErrorSpec, function_of};
use serde_json::Value;

/// Periods closer than this (relative) are the same harmonic.
const SAME_PERIOD: Real = 1e-9;

/// One compared term.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterScore {
    /// `EX0C` (the constant of a location, squareness or tool error), or the term within the
    /// parameter: `EXX.constant_um`, `EXX.polynomial_um[1]`, `EXX.reversal_um`,
    /// `EXX.harmonic[0].amplitude_um`, `EXX.harmonic[0].phase_deg`, `EXX.table.values_um[3]`.
    pub name: String,
    /// Unit of the values: `um`, `urad`, `deg` (phases), `um/mm`, `urad/deg^2`, ….
    pub unit: String,
    /// The estimate's value.
    pub estimate: Real,
    /// The truth's value (0 when the truth has no such term).
    pub truth: Real,
    /// `estimate − truth`.
    pub error: Real,
    /// The estimate's standard uncertainty (k = 1), when it gives one.
    pub uncertainty: Option<Real>,
    /// `error / uncertainty`, when the uncertainty is positive.
    pub normalised: Option<Real>,
    /// Whether the truth lies inside the estimate's 95 % interval, when it gives one.
    pub covered: Option<bool>,
}

/// A step of a key path inside `terms` (and its mirrors).
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn key(k: &str) -> Step {
    Step::Key(k.to_string())
}

fn path_text(steps: &[Step]) -> String {
    let mut text = String::new();
    for step in steps {
        match step {
            Step::Key(k) if text.is_empty() => text.push_str(k),
            Step::Key(k) => {
                text.push('.');
                text.push_str(k);
            }
            Step::Index(i) => text.push_str(&format!("[{i}]")),
        }
    }
    text
}

fn lookup<'a>(value: &'a Value, steps: &[Step]) -> Option<&'a Value> {
    steps.iter().try_fold(value, |v, step| match step {
        Step::Key(k) => v.get(k.as_str()),
        Step::Index(i) => v.get(*i),
    })
}

/// A term to compare, before its uncertainty is looked up.
pub(super) struct Term {
    name: String,
    unit: String,
    locator: Vec<Step>,
    estimate: Real,
    truth: Real,
    /// For phases: compare modulo 360°.
    angle: bool,
}

/// The values of a spec in the parameter's own units (the other unit's keys were rejected).
struct Terms {
    constant: Option<Real>,
    polynomial: Option<Vec<Real>>,
    reversal: Option<Real>,
    /// (period, amplitude, phase in deg).
    harmonics: Vec<(Real, Real, Real)>,
    /// (positions, values).
    table: Option<(Vec<Real>, Vec<Real>)>,
}

impl Terms {
    fn of(spec: &ErrorSpec) -> Terms {
        Terms {
            constant: spec.constant_um.or(spec.constant_urad),
            polynomial: spec.polynomial_um.clone().or(spec.polynomial_urad.clone()),
            reversal: spec.reversal_um.or(spec.reversal_urad),
            harmonics: spec
                .harmonic
                .iter()
                .map(|h| {
                    (
                        h.period_mm.or(h.period_deg).unwrap_or(0.0),
                        h.amplitude_um.or(h.amplitude_urad).unwrap_or(0.0),
                        h.phase_deg,
                    )
                })
                .collect(),
            table: spec.table.as_ref().map(|t| {
                (
                    t.positions_mm
                        .clone()
                        .or(t.positions_deg.clone())
                        .unwrap_or_default(),
                    t.values_um
                        .clone()
                        .or(t.values_urad.clone())
                        .unwrap_or_default(),
                )
            }),
        }
    }
}

/// A term compared as a plain number.
fn plain(name: String, unit: String, locator: Vec<Step>, estimate: Real, truth: Real) -> Term {
    Term {
        name,
        unit,
        locator,
        estimate,
        truth,
        angle: false,
    }
}

/// The terms of `estimate` against those of `truth` for one parameter (see the module doc);
/// truth terms the estimate cannot hold go to `unmodelled`.
pub(super) fn compare(
    name: ParameterName,
    estimate: &ErrorSpec,
    truth: &ErrorSpec,
    by_parts: &dyn Fn(usize) -> bool,
    unmodelled: &mut Vec<String>,
) -> Vec<Term> {
    let unit = name.file_unit();
    let position = position_unit(name);
    let translation = name.motion().is_translation();
    let e = Terms::of(estimate);
    let t = Terms::of(truth);
    let mut terms = Vec::new();
    // Truth terms the estimate compares nowhere else, folded into its table if it has one.
    let mut rest = ErrorSpec::default();
    let has_table = e.table.is_some();

    // Constant and polynomial.
    let constant_key = format!("constant_{unit}");
    let polynomial_key = format!("polynomial_{unit}");
    let t_poly = t.polynomial.clone().unwrap_or_default();
    let t_const = t.constant.unwrap_or(0.0);
    let constant_label = if matches!(name, ParameterName::Component { .. }) {
        format!("{name}.{constant_key}")
    } else {
        name.to_string()
    };
    let poly_unit = |k: usize| match k {
        0 => unit.to_string(),
        1 => format!("{unit}/{position}"),
        _ => format!("{unit}/{position}^{k}"),
    };
    if let Some(est) = e.constant {
        let tru = if e.polynomial.is_none() {
            t_const + t_poly.first().copied().unwrap_or(0.0)
        } else {
            t_const
        };
        terms.push(plain(
            constant_label.clone(),
            unit.into(),
            vec![key(&constant_key)],
            est,
            tru,
        ));
    }
    if let Some(coefficients) = &e.polynomial {
        for (k, &est) in coefficients.iter().enumerate() {
            let mut tru = t_poly.get(k).copied().unwrap_or(0.0);
            if k == 0 && e.constant.is_none() {
                tru += t_const;
            }
            terms.push(plain(
                format!("{name}.{polynomial_key}[{k}]"),
                poly_unit(k),
                vec![key(&polynomial_key), Step::Index(k)],
                est,
                tru,
            ));
        }
    }
    if e.constant.is_none() && e.polynomial.is_none() && t_const != 0.0 {
        if has_table {
            if translation {
                rest.constant_um = Some(t_const);
            } else {
                rest.constant_urad = Some(t_const);
            }
        } else {
            unmodelled.push(constant_label);
        }
    }
    // The degrees the estimate holds: 0 by a constant or a polynomial, the rest by its
    // polynomial.
    let compared_degrees = e.polynomial.as_ref().map_or(0, Vec::len);
    let first_unheld = if e.constant.is_some() {
        compared_degrees.max(1)
    } else {
        compared_degrees
    };
    let mut rest_polynomial = Vec::new();
    for (k, &c) in t_poly.iter().enumerate().skip(first_unheld) {
        if c == 0.0 {
            continue;
        }
        if has_table {
            rest_polynomial.resize(k + 1, 0.0);
            rest_polynomial[k] = c;
        } else {
            unmodelled.push(format!("{name}.{polynomial_key}[{k}]"));
        }
    }
    if !rest_polynomial.is_empty() {
        if translation {
            rest.polynomial_um = Some(rest_polynomial);
        } else {
            rest.polynomial_urad = Some(rest_polynomial);
        }
    }

    // Reversal (which no table holds).
    let reversal_key = format!("reversal_{unit}");
    match (e.reversal, t.reversal) {
        (Some(est), tru) => terms.push(plain(
            format!("{name}.{reversal_key}"),
            unit.into(),
            vec![key(&reversal_key)],
            est,
            tru.unwrap_or(0.0),
        )),
        (None, Some(tru)) if tru != 0.0 => unmodelled.push(format!("{name}.{reversal_key}")),
        _ => {}
    }

    // Harmonics, matched by period.
    let amplitude_key = format!("amplitude_{unit}");
    let mut matched = vec![false; t.harmonics.len()];
    for (i, &(period, est_a, est_phase)) in e.harmonics.iter().enumerate() {
        let found = t.harmonics.iter().enumerate().position(|(j, h)| {
            !matched[j] && (h.0 - period).abs() <= SAME_PERIOD * period.abs().max(h.0.abs())
        });
        let with = |field: &str| vec![key("harmonic"), Step::Index(i), key(field)];
        if by_parts(i) {
            // The two coefficients, A cos φ of sin(2π q / p) and A sin φ of its cosine.
            let parts = |a: Real, phase: Real| {
                let phase = phase.to_radians();
                [a * phase.cos(), a * phase.sin()]
            };
            let truth = found.map_or([0.0; 2], |j| {
                matched[j] = true;
                parts(t.harmonics[j].1, t.harmonics[j].2)
            });
            let estimate = parts(est_a, est_phase);
            for (k, part) in ["sin", "cos"].into_iter().enumerate() {
                let field = format!("{part}_{unit}");
                terms.push(plain(
                    format!("{name}.harmonic[{i}].{field}"),
                    unit.into(),
                    with(&field),
                    estimate[k],
                    truth[k],
                ));
            }
            continue;
        }
        let amplitude_label = format!("{name}.harmonic[{i}].{amplitude_key}");
        let Some(j) = found else {
            terms.push(plain(
                amplitude_label,
                unit.into(),
                with(&amplitude_key),
                est_a,
                0.0,
            ));
            continue;
        };
        matched[j] = true;
        let (_, mut a, mut phase) = t.harmonics[j];
        if (a < 0.0) != (est_a < 0.0) {
            a = -a;
            phase += 180.0;
        }
        // The truth's phase within ±180° of the estimate's.
        let phase = est_phase + (phase - est_phase + 180.0).rem_euclid(360.0) - 180.0;
        terms.push(plain(
            amplitude_label,
            unit.into(),
            with(&amplitude_key),
            est_a,
            a,
        ));
        terms.push(Term {
            angle: true,
            ..plain(
                format!("{name}.harmonic[{i}].phase_deg"),
                "deg".into(),
                with("phase_deg"),
                est_phase,
                phase,
            )
        });
    }
    // A table samples a harmonic it can resolve (two knots per period or more).
    let widest_spacing = e.table.as_ref().map_or(Real::INFINITY, |(positions, _)| {
        positions
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(0.0, Real::max)
    });
    for (j, h) in truth.harmonic.iter().enumerate() {
        if matched[j] || t.harmonics[j].1 == 0.0 {
            continue;
        }
        if has_table && t.harmonics[j].0 >= 2.0 * widest_spacing {
            rest.harmonic.push(h.clone());
        } else {
            unmodelled.push(format!("{name}.harmonic[{j}]"));
        }
    }

    // Table: the estimate's knots against the value of the rest of the truth there.
    match &e.table {
        Some((positions, values)) => {
            rest.table = truth.table.clone();
            let scale = match name {
                ParameterName::Component { axis, .. } => crate::machine::axis_unit_to_si(axis),
                _ => crate::math::M_PER_MM,
            };
            let target = (rest != ErrorSpec::default())
                .then(|| function_of(&rest, name).expect("parts of a valid truth are valid"));
            let values_key = format!("values_{unit}");
            for (i, (&q, &est)) in positions.iter().zip(values).enumerate() {
                let tru = target.as_ref().map_or(0.0, |f| {
                    f.value(q * scale, Direction::Positive) / RAD_PER_URAD
                });
                terms.push(plain(
                    format!("{name}.table.{values_key}[{i}]"),
                    unit.into(),
                    vec![key("table"), key(&values_key), Step::Index(i)],
                    est,
                    tru,
                ));
            }
        }
        None if truth.table.is_some() => unmodelled.push(format!("{name}.table")),
        None => {}
    }
    terms
}

/// The uncertainty and interval of a term, from an estimate entry.
pub(super) fn score_term(
    term: Term,
    entry: &Value,
    name: &str,
) -> Result<ParameterScore, ScoreError> {
    let at = |mirror: &str| format!("errors.{name}.{mirror}.{}", path_text(&term.locator));
    let uncertainty = match entry
        .get("standard_uncertainty")
        .and_then(|u| lookup(u, &term.locator))
    {
        None | Some(Value::Null) => None,
        Some(value) => Some(
            value
                .as_f64()
                .filter(|u| u.is_finite() && *u >= 0.0)
                .ok_or_else(|| {
                    ScoreError::shape(
                        at("standard_uncertainty"),
                        format!("expected a non-negative number, got {value}"),
                    )
                })?,
        ),
    };
    let interval = match entry
        .get("interval_95")
        .and_then(|u| lookup(u, &term.locator))
    {
        None | Some(Value::Null) => None,
        Some(value) => {
            let pair = value
                .as_array()
                .filter(|a| a.len() == 2)
                .and_then(|a| Some((a[0].as_f64()?, a[1].as_f64()?)))
                .filter(|(low, high)| low <= high);
            Some(pair.ok_or_else(|| {
                ScoreError::shape(
                    at("interval_95"),
                    format!("expected [low, high] with low <= high, got {value}"),
                )
            })?)
        }
    };
    let error = term.estimate - term.truth;
    let covered = interval.map(|(low, high)| {
        let mut truth = term.truth;
        if term.angle {
            // The truth's turn nearest the interval's middle.
            let middle = 0.5 * (low + high);
            truth = middle + (truth - middle + 180.0).rem_euclid(360.0) - 180.0;
        }
        low <= truth && truth <= high
    });
    Ok(ParameterScore {
        name: term.name,
        unit: term.unit,
        estimate: term.estimate,
        truth: term.truth,
        error,
        uncertainty,
        normalised: uncertainty.filter(|u| *u > 0.0).map(|u| error / u),
        covered,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::HarmonicSpec;

    #[test]
    fn paths_read_as_written() {
        let steps = [key("harmonic"), Step::Index(0), key("amplitude_um")];
        assert_eq!(path_text(&steps), "harmonic[0].amplitude_um");
    }

    #[test]
    fn harmonic_phase_is_compared_within_half_a_turn() {
        let name: ParameterName = "EXX".parse().unwrap();
        let spec = |a: Real, phase: Real| ErrorSpec {
            harmonic: vec![HarmonicSpec {
                period_mm: Some(10.0),
                amplitude_um: Some(a),
                phase_deg: phase,
                ..HarmonicSpec::default()
            }],
            ..ErrorSpec::default()
        };
        let mut unmodelled = Vec::new();
        // −0.4 at 210° is 0.4 at 30°; 350° is −10°.
        let terms = compare(
            name,
            &spec(0.4, 350.0),
            &spec(-0.4, 210.0),
            &|_| false,
            &mut unmodelled,
        );
        assert!(unmodelled.is_empty());
        assert_eq!(terms[0].truth, 0.4);
        assert!((terms[1].truth - 390.0).abs() < 1e-12, "{}", terms[1].truth);
    }
}
