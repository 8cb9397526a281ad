//! Scoring an estimate against the ground truth (`mtwin score ESTIMATE.json TRUTH.json`): the
//! error of every identified term, its uncertainty and whether the 95 % interval covers the
//! truth, and the figure a machine user cares about: how far the tool tip is off over the
//! working volume before and after compensating with the estimate.
//!
//! # Inputs
//!
//! Both files hold an `errors` object mapping ISO 230-1 names to entries whose `terms` object
//! is an [`ErrorSpec`] in file units (`constant_um`, `polynomial_urad`, `reversal_um`,
//! `harmonic`, `table`, …), and a `machine` name that must be the loaded machine's.
//! `truth.json` is what `mtwin run` writes; `estimate.json` (`"mtwin": "estimate"`,
//! `"schema": 1`) is what `mtwin identify` writes and adds, beside `terms`,
//! `standard_uncertainty` (standard uncertainties, k = 1) and `interval_95` (`[low, high]`
//! pairs), both mirroring `terms` key by key (`{"polynomial_um": [u0, u1]}`,
//! `{"harmonic": [{"amplitude_um": u, "phase_deg": u}]}`, `{"table": {"values_um": [...]}}`),
//! and an `unidentifiable` list of names (which have no entry in `errors`). An entry's `unit`,
//! when given, must be the parameter's file unit. A term in the wrong unit (µm for a rotation,
//! a period in mm on a rotary axis) is a [`ScoreError::Units`]. When the estimate names the
//! scenario its tables were made from (`scenario_sha256`) and the truth names its own, they
//! must be the same.
//!
//! # Term by term
//!
//! Every parameter of the estimate is compared with the truth's terms of the same parameter,
//! missing truth terms being zero (so a parameter estimated but absent from the truth is scored
//! against zero, and also listed in [`Score::not_in_truth`]). How a truth term is matched
//! depends on the families the estimate holds for that parameter:
//!
//! - **constant** (`EX0C`, or `EXX.constant_um` for a component error): against the truth's
//!   constant, plus its polynomial's degree-0 coefficient when the estimate has no polynomial;
//! - **polynomial**, index by index (`EXX.polynomial_um[1]`, unit `um/mm`): against the
//!   truth's coefficient of that degree (0 when missing), plus the truth's constant at degree 0
//!   when the estimate has no constant of its own;
//! - **reversal** (`EXX.reversal_um`): against the truth's reversal;
//! - **harmonics** (`EXX.harmonic[0].amplitude_um`, `….phase_deg`), matched by period (to
//!   1e-9 relative): amplitude and phase; the truth's `(a, φ)` is written `(−a, φ + 180°)` when
//!   the signs of the amplitudes differ, and its phase is taken within ±180° of the
//!   estimate's. A harmonic with no truth counterpart is scored against amplitude 0 (no phase);
//! - **table** (`EXX.table.values_um[i]`): at each knot, against the value of the truth's
//!   terms that the estimate does not compare elsewhere (its table, and polynomial terms and
//!   harmonics the estimate holds no separate term for).
//!
//! Truth terms the estimate's families cannot hold are listed in [`Score::unmodelled_terms`]
//! (`EXX.polynomial_um[2]`, `EXX.reversal_um`, `EXX.harmonic[0]` indexed as in the truth,
//! `EXX.table`, `EXX.constant_um`): a polynomial degree beyond the estimate's, a reversal when
//! the estimate has none, a harmonic whose period the estimate has no harmonic for (for a table
//! estimate: only one shorter than twice the widest knot spacing, the rest being sampled by the
//! table), a truth table when the estimate has no table. They still count in the volumetric
//! figure. Truth parameters with no estimate at all are in [`Score::not_estimated`].
//!
//! `normalised` is `error / u` (signed; none without a positive uncertainty); `covered` is
//! whether the truth lies in the 95 % interval; [`Score::coverage`] counts both over the terms
//! that have an interval (about 95 % of them should be covered, over many terms or runs).
//!
//! # Volumetric figure
//!
//! The tool-tip deviation (actual − nominal, workpiece frame,
//! [`ErrorModel::deviation`]`.translation`) is evaluated by the exact chain over a grid of the
//! working volume:
//!
//! - every linear axis at 5 equally spaced points from its lower to its upper travel limit
//!   (5³ = 125 points on a 3-axis machine);
//! - a rotary axis with travel limits (A, B) at its lower limit, 0 (when strictly inside) and
//!   its upper limit; a continuous rotary axis (C) at 0°, 90°, 180°, 270° (125 × 3 × 4 = 1500
//!   points on the 5-axis machines); the spindle S at 0;
//! - directions of travel: every axis positive, except that when the truth or the estimate has
//!   a reversal term on some axes, every combination of directions of those axes is visited at
//!   each point (2ⁿ states per point for n such axes), so that lost motion counts with both
//!   signs.
//!
//! The grid is coarse on purpose (it is the figure of the volume, not of a pitch): a cyclic
//! error of short period is seen only at the phases the grid points hit (a 25 mm harmonic on
//! a 650 mm X travel, 162.5 mm = 6.5 periods apart, shows as ±half its amplitude).
//!
//! The uncompensated figure is `|dev_truth(state)|`; the compensated one
//! `|dev_truth(state) − dev_estimate(state)|`: a controller that subtracts the deviation the
//! estimate predicts. This first-order compensation leaves, besides the estimate's error, a
//! second-order residue of about (error/length)² × length, ≈ 1e-10 m for µm errors over a
//! metre, which this figure neglects. Both are reported as RMS and maximum over the states, in
//! µm. Thermal terms are not part of it: the `errors` objects hold the geometric parameters.
//!
//! # JSON (`Score::to_json`)
//!
//! ```json
//! { "mtwin": "score", "schema": 1, "machine": "trunnion5",
//!   "parameters": [ { "name": "EX0C", "unit": "um", "estimate": 12.03, "truth": 12.0,
//!                     "error": 0.03, "uncertainty": 0.05, "normalised": 0.6, "covered": true } ],
//!   "not_in_truth": [], "not_estimated": ["EC0C"], "unidentifiable": ["EC0C"],
//!   "unmodelled_terms": ["EXX.harmonic[0]"],
//!   "coverage": { "covered": 7, "with_interval": 8 },
//!   "volumetric": { "points": 1500, "uncompensated_rms_um": 21.3, "uncompensated_max_um": 48.0,
//!                   "compensated_rms_um": 0.08, "compensated_max_um": 0.3 } }
//! ```
//!
//! `uncertainty`, `normalised` and `covered` are `null` when the estimate gives no uncertainty
//! or interval for the term.

use crate::errors::{ErrorFunction, ErrorModel, ErrorParameter, ParameterName};
use crate::machine::{Axis, AxisValues, Direction, Machine, MachineState, Workspace};
use crate::math::{RAD_PER_URAD, Real};
use crate::scenario::{ErrorSpec, function_of};
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet};

/// Points per linear axis in the volumetric grid.
const LINEAR_POINTS: usize = 5;

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

/// The tool-tip deviation over the working volume (see the module doc for the grid), µm.
#[derive(Debug, Clone, PartialEq)]
pub struct Volumetric {
    /// Number of machine states evaluated (grid points × direction combinations).
    pub points: usize,
    /// RMS of `|dev_truth|`.
    pub uncompensated_rms_um: Real,
    /// Largest `|dev_truth|`.
    pub uncompensated_max_um: Real,
    /// RMS of `|dev_truth − dev_estimate|`.
    pub compensated_rms_um: Real,
    /// Largest `|dev_truth − dev_estimate|`.
    pub compensated_max_um: Real,
}

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

/// Why an estimate could not be scored.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScoreError {
    /// The estimate or the truth is for another machine than the one loaded.
    #[error(
        "{file} is for machine \"{named}\", but the machine loaded is \"{loaded}\"; score it with that machine's URDF"
    )]
    Machine {
        /// `estimate` or `truth`.
        file: String,
        /// The machine the file names.
        named: String,
        /// The machine loaded.
        loaded: String,
    },
    /// A term in a unit that does not fit its parameter or axis.
    #[error("{}{parameter} {reason}; expected {expected}", located(.file, .path))]
    Units {
        /// `estimate` or `truth` (empty from [`error_model_of`]).
        file: String,
        /// Key path of the term, e.g. `errors.EA0C.terms.constant_um`.
        path: String,
        /// The parameter.
        parameter: String,
        /// What the parameter is, e.g. `is a rotation`.
        reason: String,
        /// The key or unit expected, e.g. `constant_urad`.
        expected: String,
    },
    /// The JSON does not have the expected shape or values.
    #[error("{}{message}", located(.file, .path))]
    Shape {
        /// `estimate` or `truth` (empty from [`error_model_of`]).
        file: String,
        /// Key path, e.g. `errors.EXX.standard_uncertainty.polynomial_um[1]`.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// `file: path: `, leaving out the empty parts.
fn located(file: &str, path: &str) -> String {
    [file, path]
        .iter()
        .filter(|part| !part.is_empty())
        .map(|part| format!("{part}: "))
        .collect()
}

impl ScoreError {
    fn shape(path: impl Into<String>, message: impl Into<String>) -> ScoreError {
        ScoreError::Shape {
            file: String::new(),
            path: path.into(),
            message: message.into(),
        }
    }

    /// The same error, said of the file `name`: [`score`] says `estimate` and `truth`; a
    /// command line may put the paths instead.
    pub fn in_file(mut self, name: &str) -> ScoreError {
        match &mut self {
            ScoreError::Machine { file, .. }
            | ScoreError::Units { file, .. }
            | ScoreError::Shape { file, .. } => *file = name.to_string(),
        }
        self
    }
}

/// One parameter of an `errors` object: its name, terms and function.
struct Entry {
    name: ParameterName,
    spec: ErrorSpec,
    function: ErrorFunction,
    raw: Value,
}

/// Builds the error model of `machine` from an `errors` object of `truth.json` or
/// `estimate.json` (names → entries with a `terms` object in file units). Messages name the key
/// path from `errors`.
pub fn error_model_of(errors: &Value, machine: &Machine) -> Result<ErrorModel, ScoreError> {
    model(&entries(errors, machine)?, machine)
}

fn model(entries: &[Entry], machine: &Machine) -> Result<ErrorModel, ScoreError> {
    let parameters: Vec<ErrorParameter> = entries
        .iter()
        .map(|e| ErrorParameter {
            name: e.name,
            function: e.function.clone(),
        })
        .collect();
    // The limit every scenario and `identify` enforce (10 mm, 10 mrad): beyond it a value is a
    // unit slip or a corrupted file, and its squares overflow the volumetric figures.
    for parameter in &parameters {
        if let Some(why) = crate::scenario::errors::implausible(parameter, machine) {
            return Err(ScoreError::shape(
                format!("errors.{}", parameter.name),
                format!("{why}; score compares machine errors, not values beyond that limit"),
            ));
        }
    }
    ErrorModel::new(machine, parameters).map_err(|e| ScoreError::shape("errors", e.to_string()))
}

/// Parses and checks every entry of an `errors` object.
fn entries(errors: &Value, machine: &Machine) -> Result<Vec<Entry>, ScoreError> {
    let map = match errors {
        Value::Object(map) => map,
        Value::Null => return Err(ScoreError::shape("errors", "missing")),
        _ => {
            return Err(ScoreError::shape(
                "errors",
                "expected an object mapping parameter names to entries",
            ));
        }
    };
    let mut out = Vec::with_capacity(map.len());
    for (key, raw) in map {
        let path = format!("errors.{key}");
        let name: ParameterName = key
            .parse()
            .map_err(|message: String| ScoreError::shape(&path, message))?;
        if let Some(axis) = name.axis().filter(|a| !machine.has_axis(*a)) {
            return Err(ScoreError::shape(
                &path,
                format!("machine \"{}\" has no axis {axis}", machine.name()),
            ));
        }
        let Value::Object(entry) = raw else {
            return Err(ScoreError::shape(
                &path,
                "expected an object with a \"terms\" object",
            ));
        };
        if let Some(unit) = entry.get("unit").filter(|u| !u.is_null())
            && unit.as_str() != Some(name.file_unit())
        {
            return Err(ScoreError::Units {
                file: String::new(),
                path: format!("{path}.unit"),
                parameter: name.to_string(),
                reason: format!("is given in {unit}"),
                expected: format!("\"{}\"", name.file_unit()),
            });
        }
        let terms = entry.get("terms").unwrap_or(&Value::Null);
        let terms_path = format!("{path}.terms");
        if !terms.is_object() {
            return Err(ScoreError::shape(
                terms_path,
                "expected an object of terms (constant_um, polynomial_urad, …)",
            ));
        }
        check_units(terms, name, &terms_path)?;
        let spec: ErrorSpec = serde_json::from_value(terms.clone())
            .map_err(|e| ScoreError::shape(&terms_path, e.to_string()))?;
        let function =
            function_of(&spec, name).map_err(|message| ScoreError::shape(&terms_path, message))?;
        out.push(Entry {
            name,
            spec,
            function,
            raw: raw.clone(),
        });
    }
    out.sort_by_cached_key(|e| e.name.to_string());
    Ok(out)
}

/// The unit of the position a parameter's function takes: `deg` for a component error of a
/// rotary axis (or the spindle), `mm` otherwise.
fn position_unit(name: ParameterName) -> &'static str {
    match name {
        ParameterName::Component { axis, .. } if !axis.is_linear() => "deg",
        _ => "mm",
    }
}

/// Rejects value keys in the other value unit and position keys in the other position unit.
fn check_units(terms: &Value, name: ParameterName, path: &str) -> Result<(), ScoreError> {
    let unit = name.file_unit();
    let position = position_unit(name);
    let what = if name.motion().is_translation() {
        "is a translation"
    } else {
        "is a rotation"
    };
    let axis_what = if position == "deg" {
        "varies with the angle of a rotary axis"
    } else {
        "varies with a length"
    };
    let check = |field: &str, at: String, positions: bool| -> Result<(), ScoreError> {
        let Some((stem, suffix)) = field.rsplit_once('_') else {
            return Ok(());
        };
        let (expected, reason, family) = if positions {
            (position, axis_what, ["mm", "deg"])
        } else {
            (unit, what, ["um", "urad"])
        };
        if family.contains(&suffix) && suffix != expected {
            return Err(ScoreError::Units {
                file: String::new(),
                path: at,
                parameter: name.to_string(),
                reason: reason.to_string(),
                expected: format!("{stem}_{expected}"),
            });
        }
        Ok(())
    };
    let Value::Object(map) = terms else {
        return Ok(());
    };
    for (key, value) in map {
        match key.as_str() {
            "harmonic" => {
                for (i, h) in value.as_array().into_iter().flatten().enumerate() {
                    for field in h.as_object().into_iter().flat_map(|h| h.keys()) {
                        let at = format!("{path}.harmonic[{i}].{field}");
                        check(field, at, field.starts_with("period"))?;
                    }
                }
            }
            "table" => {
                for field in value.as_object().into_iter().flat_map(|t| t.keys()) {
                    let at = format!("{path}.table.{field}");
                    check(field, at, field.starts_with("positions"))?;
                }
            }
            _ => check(key, format!("{path}.{key}"), false)?,
        }
    }
    Ok(())
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
struct Term {
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
fn compare(
    name: ParameterName,
    estimate: &ErrorSpec,
    truth: &ErrorSpec,
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
fn score_term(term: Term, entry: &Value, name: &str) -> Result<ParameterScore, ScoreError> {
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

/// The `machine` of a file, checked against the loaded machine.
fn check_machine(file: &Value, which: &str, machine: &Machine) -> Result<(), ScoreError> {
    let named = match file.get("machine") {
        Some(Value::String(named)) => named,
        Some(other) => {
            return Err(ScoreError::shape(
                "machine",
                format!("expected the machine name as a string, got {other}"),
            )
            .in_file(which));
        }
        None => return Err(ScoreError::shape("machine", "missing").in_file(which)),
    };
    if named != machine.name() {
        return Err(ScoreError::Machine {
            file: which.to_string(),
            named: named.clone(),
            loaded: machine.name().to_string(),
        });
    }
    Ok(())
}

/// Scores `estimate` (an `estimate.json`) against `truth` (a `truth.json`) on `machine`: the
/// term-by-term comparison and the volumetric figure (see the module doc).
pub fn score(estimate: &Value, truth: &Value, machine: &Machine) -> Result<Score, ScoreError> {
    for (file, which) in [(estimate, "estimate"), (truth, "truth")] {
        if !file.is_object() {
            return Err(ScoreError::shape("", "expected a JSON object").in_file(which));
        }
    }
    match estimate.get("mtwin") {
        None | Some(Value::Null) => {}
        Some(Value::String(kind)) if kind == "estimate" => {}
        Some(other) => {
            return Err(ScoreError::shape(
                "mtwin",
                format!("expected \"estimate\", got {other} (is this the estimate?)"),
            )
            .in_file("estimate"));
        }
    }
    // A truth says it is one (`mtwin run` writes `"mtwin": "truth"`); one that says it is
    // something else (an estimate given twice, a score) would score the estimate against
    // itself. A truth from elsewhere that says nothing is taken as it is.
    match truth.get("mtwin") {
        None | Some(Value::Null) => {}
        Some(Value::String(kind)) if kind == "truth" => {}
        Some(other) => {
            return Err(ScoreError::shape(
                "mtwin",
                format!(
                    "expected \"truth\", got {other}: this is not a truth (give the truth.json `mtwin run` wrote)"
                ),
            )
            .in_file("truth"));
        }
    }
    // The tables an estimate came from may name their scenario (the manifest `mtwin run`
    // wrote beside them); a truth of another scenario would score it against errors it never
    // saw.
    if let (Some(from), Some(of)) = (
        estimate.get("scenario_sha256").and_then(Value::as_str),
        truth.get("scenario_sha256").and_then(Value::as_str),
    ) && from != of
    {
        return Err(ScoreError::shape(
            "scenario_sha256",
            format!(
                "{of} is not the scenario the estimate's tables were made from ({from}): give the truth.json of the run that wrote them"
            ),
        )
        .in_file("truth"));
    }
    match estimate.get("schema") {
        None | Some(Value::Null) => {}
        Some(schema) if schema.as_i64() == Some(1) => {}
        Some(other) => {
            return Err(ScoreError::shape(
                "schema",
                format!("this version reads schema 1, got {other}"),
            )
            .in_file("estimate"));
        }
    }
    check_machine(estimate, "estimate", machine)?;
    check_machine(truth, "truth", machine)?;
    let get_errors = |file: &Value, which: &str| {
        entries(file.get("errors").unwrap_or(&Value::Null), machine).map_err(|e| e.in_file(which))
    };
    let estimated = get_errors(estimate, "estimate")?;
    let true_entries = get_errors(truth, "truth")?;
    let unidentifiable = match estimate.get("unidentifiable") {
        None | Some(Value::Null) => Vec::new(),
        Some(Value::Array(items)) => items
            .iter()
            .enumerate()
            .map(|(i, item)| {
                item.as_str().map(str::to_string).ok_or_else(|| {
                    ScoreError::shape(
                        format!("unidentifiable[{i}]"),
                        format!("expected a parameter name, got {item}"),
                    )
                    .in_file("estimate")
                })
            })
            .collect::<Result<_, _>>()?,
        Some(other) => {
            return Err(ScoreError::shape(
                "unidentifiable",
                format!("expected a list of parameter names, got {other}"),
            )
            .in_file("estimate"));
        }
    };

    let truth_by_name: BTreeMap<ParameterName, &Entry> =
        true_entries.iter().map(|e| (e.name, e)).collect();
    let estimated_names: BTreeSet<ParameterName> = estimated.iter().map(|e| e.name).collect();
    let empty = ErrorSpec::default();
    let mut parameters = Vec::new();
    let mut not_in_truth = Vec::new();
    let mut unmodelled_terms = Vec::new();
    for entry in &estimated {
        let truth_spec = match truth_by_name.get(&entry.name) {
            Some(t) => &t.spec,
            None => {
                not_in_truth.push(entry.name.to_string());
                &empty
            }
        };
        let name = entry.name.to_string();
        for term in compare(entry.name, &entry.spec, truth_spec, &mut unmodelled_terms) {
            parameters
                .push(score_term(term, &entry.raw, &name).map_err(|e| e.in_file("estimate"))?);
        }
    }
    let not_estimated = true_entries
        .iter()
        .filter(|e| !estimated_names.contains(&e.name))
        .map(|e| e.name.to_string())
        .collect();
    let with_interval = parameters.iter().filter(|p| p.covered.is_some()).count();
    let covered = parameters
        .iter()
        .filter(|p| p.covered == Some(true))
        .count();

    let truth_model = model(&true_entries, machine).map_err(|e| e.in_file("truth"))?;
    let estimate_model = model(&estimated, machine).map_err(|e| e.in_file("estimate"))?;
    Ok(Score {
        machine: machine.name().to_string(),
        parameters,
        not_in_truth,
        not_estimated,
        unidentifiable,
        unmodelled_terms,
        coverage: (covered, with_interval),
        volumetric: volumetric(machine, &truth_model, &estimate_model),
    })
}

/// The positions of the volumetric grid (see the module doc), SI, the first axis of
/// [`Machine::axes`] varying slowest.
pub fn volumetric_grid(machine: &Machine) -> Vec<AxisValues> {
    let per_axis: Vec<(Axis, Vec<Real>)> = machine
        .axes()
        .iter()
        .map(|info| {
            let values = if info.axis == Axis::S {
                vec![0.0]
            } else if info.axis.is_linear() {
                match info.limits {
                    Some((low, high)) => (0..LINEAR_POINTS)
                        .map(|i| low + (high - low) * i as Real / (LINEAR_POINTS - 1) as Real)
                        .collect(),
                    None => vec![0.0],
                }
            } else {
                match info.limits {
                    Some((low, high)) => {
                        let mut v = vec![low];
                        if low < 0.0 && 0.0 < high {
                            v.push(0.0);
                        }
                        if high > low {
                            v.push(high);
                        }
                        v
                    }
                    None => (0..4)
                        .map(|i| i as Real * std::f64::consts::FRAC_PI_2)
                        .collect(),
                }
            };
            (info.axis, values)
        })
        .collect();
    let mut grid = vec![AxisValues::ZERO];
    for (axis, values) in per_axis {
        grid = grid
            .iter()
            .flat_map(|base| {
                values.iter().map(move |&v| {
                    let mut p = *base;
                    p[axis] = v;
                    p
                })
            })
            .collect();
    }
    grid
}

/// The axes whose component errors have a reversal term.
fn reversal_axes(model: &ErrorModel, out: &mut BTreeSet<Axis>) {
    fn has_reversal(f: &ErrorFunction) -> bool {
        match f {
            ErrorFunction::Reversal(_) => true,
            ErrorFunction::Sum(terms) => terms.iter().any(has_reversal),
            _ => false,
        }
    }
    for p in model.parameters() {
        if let ParameterName::Component { axis, .. } = p.name
            && has_reversal(&p.function)
        {
            out.insert(axis);
        }
    }
}

/// The volumetric figure of `truth` compensated by `estimate`, two models of `machine`: the
/// deviations over [`volumetric_grid`] in the directions the module doc describes.
pub fn volumetric(machine: &Machine, truth: &ErrorModel, estimate: &ErrorModel) -> Volumetric {
    let mut reversing = BTreeSet::new();
    reversal_axes(truth, &mut reversing);
    reversal_axes(estimate, &mut reversing);
    let reversing: Vec<Axis> = reversing.into_iter().collect();
    let mut workspace = Workspace::new(machine);
    let (mut count, mut sum_raw, mut max_raw, mut sum_comp, mut max_comp) =
        (0usize, 0.0, 0.0 as Real, 0.0, 0.0 as Real);
    for position in volumetric_grid(machine) {
        for combination in 0..1usize << reversing.len() {
            let mut state = MachineState::at(position);
            for (bit, axis) in reversing.iter().enumerate() {
                if combination >> bit & 1 == 1 {
                    state.direction[axis.index()] = Direction::Negative;
                }
            }
            let d_truth = truth.deviation(machine, &mut workspace, &state).translation;
            let d_estimate = estimate
                .deviation(machine, &mut workspace, &state)
                .translation;
            let raw = d_truth.length() / RAD_PER_URAD;
            let compensated = (d_truth - d_estimate).length() / RAD_PER_URAD;
            count += 1;
            sum_raw += raw * raw;
            sum_comp += compensated * compensated;
            max_raw = max_raw.max(raw);
            max_comp = max_comp.max(compensated);
        }
    }
    let rms = |sum: Real| (sum / count.max(1) as Real).sqrt();
    Volumetric {
        points: count,
        uncompensated_rms_um: rms(sum_raw),
        uncompensated_max_um: max_raw,
        compensated_rms_um: rms(sum_comp),
        compensated_max_um: max_comp,
    }
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
    use crate::scenario::HarmonicSpec;

    #[test]
    fn numbers_for_people() {
        assert_eq!(number(12.03), "12.03");
        assert_eq!(number(0.0121), "0.01210");
        assert_eq!(number(-8e-6), "-8.000e-6");
        assert_eq!(number(0.0), "0");
    }

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
        let terms = compare(name, &spec(0.4, 350.0), &spec(-0.4, 210.0), &mut unmodelled);
        assert!(unmodelled.is_empty());
        assert_eq!(terms[0].truth, 0.4);
        assert!((terms[1].truth - 390.0).abs() < 1e-12, "{}", terms[1].truth);
    }
}
