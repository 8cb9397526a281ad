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
//! - **harmonics**, matched by period (to 1e-9 relative): when the estimate's
//!   `standard_uncertainty` gives the harmonic's two coefficients (`sin_um`, `cos_um`, as
//!   `mtwin identify` writes them), those two (`EXC.harmonic[1].sin_um` = A cos φ, `….cos_um`
//!   = A sin φ; a coverage counted on them is that of Gaussian quantities, which an amplitude
//!   near zero is not); otherwise (`EXX.harmonic[0].amplitude_um`, `….phase_deg`) amplitude
//!   and phase; the truth's `(a, φ)` is written `(−a, φ + 180°)` when
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
//! [`ErrorModel::deviation`](crate::errors::ErrorModel::deviation)`.translation`) is evaluated by the exact chain over a grid of the
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
//!
//! # Files
//!
//! [`score`] is here; `entries` reads the `errors` objects, `terms` matches them term by term,
//! `volumetric` makes the volumetric figure, `report` says the [`Score`] for people and as
//! JSON, and `error` holds the [`ScoreError`].

mod entries;
mod error;
mod report;
mod terms;
mod volumetric;

pub use entries::error_model_of;
pub use error::ScoreError;
pub use report::Score;
pub use terms::ParameterScore;
pub use volumetric::{Volumetric, volumetric, volumetric_grid};

use crate::errors::ParameterName;
use crate::machine::Machine;
use crate::scenario::ErrorSpec;
use entries::{Entry, entries, model};
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use terms::{compare, score_term};

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
        // Harmonics whose uncertainty the estimate gives per coefficient are scored so.
        let part_key = format!("sin_{}", entry.name.file_unit());
        let by_parts = |i: usize| {
            (entry.raw.get("standard_uncertainty"))
                .and_then(|u| u.get("harmonic")?.get(i)?.get(&part_key))
                .is_some_and(|u| !u.is_null())
        };
        for term in compare(
            entry.name,
            &entry.spec,
            truth_spec,
            &by_parts,
            &mut unmodelled_terms,
        ) {
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
