//! Scoring an estimate against the truth (`mtwin::estimate::score`), and the file-units ↔ SI
//! conversion of error terms (`scenario::function_of` / `spec_of`) it rests on.
//!
//! Independent checks: a perfect estimate (the truth itself) must score zero error on every
//! term and leave no volumetric deviation; hand values for single errors on vmc3 (squareness
//! `δx = −EC0Y·y` over the documented 5×5×5 grid; lost motion ∓r/2 in both directions);
//! compensating with part of the truth must leave the figure of the rest (to second order in
//! the errors); normalised errors and coverage on hand-built numbers; unit conversions written
//! out by hand.

use crate::common::machine;
use mtwin::app::{Scenario, run_scenario};
use mtwin::errors::{ErrorFunction, Interpolation, ParameterName, Table};
use mtwin::estimate::score::{ScoreError, error_model_of, score};
use mtwin::machine::{Direction, MachineState, Workspace};
use mtwin::math::{M_PER_MM, RAD_PER_DEG, Real};
use mtwin::scenario::{ErrorSpec, function_of, spec_of};
use serde_json::{Value, json};

/// Round-off of a deviation taken between poses about 1 m from the origin (1e-16 m), with
/// margin: 1e-15 m.
const ROUND_OFF_UM: Real = 1e-9;

fn scenario_path(name: &str) -> String {
    format!("{}/scenarios/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// `truth.json` of a bundled scenario, as `mtwin run` writes it.
fn truth_of(name: &str) -> Value {
    let output = run_scenario(&Scenario::load(scenario_path(name)).unwrap()).unwrap();
    let bytes = &output
        .files
        .iter()
        .find(|(n, _)| n == "truth.json")
        .unwrap()
        .1;
    serde_json::from_slice(bytes).unwrap()
}

/// An estimate file holding these `errors` entries.
fn estimate(machine: &str, errors: Value) -> Value {
    json!({ "mtwin": "estimate", "schema": 1, "machine": machine,
            "machine_file": format!("models/{machine}.urdf"), "errors": errors,
            "unidentifiable": [] })
}

/// A truth file holding these `errors` entries.
fn truth(machine: &str, errors: Value) -> Value {
    json!({ "machine": machine, "errors": errors })
}

/// An `errors` entry with these terms (the unit left to the name).
fn entry(terms: Value) -> Value {
    json!({ "terms": terms })
}

fn name(text: &str) -> ParameterName {
    text.parse().unwrap()
}

#[test]
fn a_perfect_estimate_scores_zero_everywhere() {
    // vmc3_iso230_2: EXX polynomial + harmonic + reversal, EBX polynomial; trunnion5_rtest: the
    // eight location errors of A and C; headtable5_volumetric: locations of B and C, EBB
    // polynomial in degrees, squareness, tool length; vmc3_ballbar_3planes: three reversals.
    // Reversal axes double the states per grid point: 125·2 (X), 125·2³ (X, Y, Z).
    let cases = [
        ("vmc3_iso230_2.toml", 250),
        ("trunnion5_rtest.toml", 1500),
        ("headtable5_volumetric.toml", 1500),
        ("vmc3_ballbar_3planes.toml", 1000),
    ];
    for (scenario, points) in cases {
        let truth = truth_of(scenario);
        let machine_name = truth["machine"].as_str().unwrap();
        let m = machine(machine_name);
        let estimate = estimate(machine_name, truth["errors"].clone());
        let s = score(&estimate, &truth, &m).unwrap();
        assert_eq!(s.machine, machine_name);
        assert!(!s.parameters.is_empty());
        for p in &s.parameters {
            assert_eq!(p.error, 0.0, "{scenario}: {p:?}");
            assert_eq!(p.estimate, p.truth, "{scenario}: {p:?}");
        }
        assert!(s.not_estimated.is_empty() && s.not_in_truth.is_empty());
        assert!(s.unmodelled_terms.is_empty(), "{:?}", s.unmodelled_terms);
        assert_eq!(s.coverage, (0, 0));
        let v = &s.volumetric;
        assert_eq!(v.points, points, "{scenario}");
        assert!(
            v.compensated_rms_um <= 1e-9 && v.compensated_max_um <= 1e-9,
            "{v:?}"
        );
        assert!(v.uncompensated_rms_um > 0.1, "{scenario}: {v:?}");
        assert!(v.uncompensated_max_um >= v.uncompensated_rms_um);

        // The truth's `errors` read back give the scenario's own model (12 digits written).
        let loaded = Scenario::load(scenario_path(scenario)).unwrap();
        let model = error_model_of(&truth["errors"], &m).unwrap();
        let (read, injected) = (model.coefficients(), loaded.twin.errors.coefficients());
        assert_eq!(
            model.coefficient_labels(),
            loaded.twin.errors.coefficient_labels()
        );
        for (a, b) in read.iter().zip(&injected) {
            assert!((a - b).abs() <= 1e-11 * b.abs(), "{scenario}: {a} vs {b}");
        }
        // The report and the JSON name every term.
        let report = s.report();
        let json = s.to_json();
        for p in &s.parameters {
            assert!(report.contains(&p.name), "{report}");
        }
        assert_eq!(
            json["parameters"].as_array().unwrap().len(),
            s.parameters.len()
        );
        assert_eq!(json["volumetric"]["points"], points);
    }
}

#[test]
fn squareness_alone_gives_the_hand_figure() {
    // vmc3, EC0Y = 10 µrad only: δx = −EC0Y·y, |δ| = EC0Y·y. The grid takes Y at 5 points over
    // [0, 410] mm (0, ¼, ½, ¾, 1 of 410 mm), each 25 times (X and Z at 5 points each):
    // max = 10 µrad · 410 mm = 4.1 µm; RMS = 4.1 µm · √((0 + 1/16 + 1/4 + 9/16 + 1)/5)
    // = 4.1 µm · √0.375.
    let m = machine("vmc3");
    let truth = truth(
        "vmc3",
        json!({ "EC0Y": entry(json!({ "constant_urad": 10.0 })) }),
    );
    let none = estimate("vmc3", json!({}));
    let s = score(&none, &truth, &m).unwrap();
    let v = &s.volumetric;
    let (rms, max) = (4.1 * 0.375_f64.sqrt(), 4.1);
    assert_eq!(v.points, 125);
    // The exact chain turns by ε: |δ| = 2·sin(ε/2)·y, 4e-12 relative below ε·y.
    assert!((v.uncompensated_rms_um - rms).abs() < ROUND_OFF_UM, "{v:?}");
    assert!((v.uncompensated_max_um - max).abs() < ROUND_OFF_UM, "{v:?}");
    assert_eq!(v.compensated_rms_um, v.uncompensated_rms_um);
    assert_eq!(s.not_estimated, ["EC0Y"]);
    assert!(s.parameters.is_empty());

    // Compensating with 9 µrad leaves 1 µrad: a tenth of the figure.
    let nine = estimate(
        "vmc3",
        json!({ "EC0Y": entry(json!({ "constant_urad": 9.0 })) }),
    );
    let s = score(&nine, &truth, &m).unwrap();
    assert!((s.volumetric.compensated_rms_um - rms / 10.0).abs() < ROUND_OFF_UM);
    assert!((s.volumetric.compensated_max_um - max / 10.0).abs() < ROUND_OFF_UM);
    assert_eq!(s.parameters.len(), 1);
    let p = &s.parameters[0];
    assert_eq!((p.name.as_str(), p.unit.as_str()), ("EC0Y", "urad"));
    assert_eq!((p.estimate, p.truth, p.error), (9.0, 10.0, -1.0));
    assert_eq!((p.uncertainty, p.normalised, p.covered), (None, None, None));
}

#[test]
fn lost_motion_counts_in_both_directions() {
    // EXX reversal 3 µm: the tool lags 1.5 µm behind X whichever way X last moved, so every
    // state is off by exactly 1.5 µm; the grid is visited with X positive and negative.
    let m = machine("vmc3");
    let truth = truth(
        "vmc3",
        json!({ "EXX": entry(json!({ "reversal_um": 3.0 })) }),
    );
    let s = score(&estimate("vmc3", json!({})), &truth, &m).unwrap();
    let v = &s.volumetric;
    assert_eq!(v.points, 250);
    assert!((v.uncompensated_rms_um - 1.5).abs() < ROUND_OFF_UM, "{v:?}");
    assert!((v.uncompensated_max_um - 1.5).abs() < ROUND_OFF_UM, "{v:?}");
    // An estimate holding only a polynomial for EXX cannot hold the lost motion.
    let polynomial = estimate(
        "vmc3",
        json!({ "EXX": entry(json!({ "polynomial_um": [0.0, 0.001] })) }),
    );
    let s = score(&polynomial, &truth, &m).unwrap();
    assert_eq!(s.unmodelled_terms, ["EXX.reversal_um"]);
    let names: Vec<&str> = s.parameters.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["EXX.polynomial_um[0]", "EXX.polynomial_um[1]"]);
    assert_eq!(s.parameters[1].unit, "um/mm");
    assert_eq!(s.parameters[1].truth, 0.0);
}

#[test]
fn compensating_part_of_the_truth_leaves_the_figure_of_the_rest() {
    // trunnion5: the R-test scenario's eight location errors, plus EXX = 0.01 µm/mm · x plus a
    // harmonic of 25 mm, 1.5 µm. The estimate holds the locations and EXX's polynomial
    // exactly, not the harmonic: what remains must be the harmonic's own figure, to second
    // order in the errors (location rotations of ~25 µrad times deviations of ~10 µm:
    // ~3e-4 µm).
    let m = machine("trunnion5");
    let locations = truth_of("trunnion5_rtest.toml")["errors"].clone();
    let exx = json!({ "polynomial_um": [0.0, 0.01],
                      "harmonic": [{ "period_mm": 25.0, "amplitude_um": 1.5, "phase_deg": 30.0 }] });
    let mut full = locations.clone();
    full["EXX"] = entry(exx);
    let mut held = locations.clone();
    held["EXX"] = entry(json!({ "polynomial_um": [0.0, 0.01] }));
    let s = score(&estimate("trunnion5", held), &truth("trunnion5", full), &m).unwrap();
    assert_eq!(s.unmodelled_terms, ["EXX.harmonic[0]"]);
    assert!(s.parameters.iter().all(|p| p.error == 0.0));

    let harmonic_only = truth(
        "trunnion5",
        json!({ "EXX": entry(json!({ "harmonic": [{ "period_mm": 25.0, "amplitude_um": 1.5, "phase_deg": 30.0 }] })) }),
    );
    let rest = score(&estimate("trunnion5", json!({})), &harmonic_only, &m).unwrap();
    let (v, r) = (&s.volumetric, &rest.volumetric);
    assert_eq!(v.points, r.points);
    // By hand: X at 0, 162.5, …, 650 mm is 6.5 periods apart, so 1.5 µm · sin(30° + k·180°)
    // = ±0.75 µm along X at every point, whatever A and C.
    assert!(
        (r.uncompensated_rms_um - 0.75).abs() < ROUND_OFF_UM,
        "{r:?}"
    );
    assert!(
        (r.uncompensated_max_um - 0.75).abs() < ROUND_OFF_UM,
        "{r:?}"
    );
    assert!(
        (v.compensated_rms_um - r.uncompensated_rms_um).abs() < 1e-3,
        "{v:?} {r:?}"
    );
    assert!(
        (v.compensated_max_um - r.uncompensated_max_um).abs() < 1e-3,
        "{v:?} {r:?}"
    );
    assert!(v.uncompensated_rms_um > 5.0 * v.compensated_rms_um, "{v:?}");

    // With the locations alone, EXX is not estimated at all and the rest is all of EXX.
    let s = score(
        &estimate("trunnion5", locations.clone()),
        &truth("trunnion5", {
            let mut full = locations;
            full["EXX"] = entry(json!({ "polynomial_um": [0.0, 0.01],
                "harmonic": [{ "period_mm": 25.0, "amplitude_um": 1.5, "phase_deg": 30.0 }] }));
            full
        }),
        &m,
    )
    .unwrap();
    assert_eq!(s.not_estimated, ["EXX"]);
    assert!(s.unmodelled_terms.is_empty());
    let exx_only = truth(
        "trunnion5",
        json!({ "EXX": entry(json!({ "polynomial_um": [0.0, 0.01],
            "harmonic": [{ "period_mm": 25.0, "amplitude_um": 1.5, "phase_deg": 30.0 }] })) }),
    );
    let rest = score(&estimate("trunnion5", json!({})), &exx_only, &m).unwrap();
    assert!((s.volumetric.compensated_rms_um - rest.volumetric.uncompensated_rms_um).abs() < 1e-3);
    assert!((s.volumetric.compensated_max_um - rest.volumetric.uncompensated_max_um).abs() < 1e-3);
}

#[test]
fn normalised_error_and_coverage_on_hand_numbers() {
    let m = machine("vmc3");
    let truth = truth(
        "vmc3",
        json!({
            "EC0Y": entry(json!({ "constant_urad": 10.0 })),
            "EXX": entry(json!({ "polynomial_um": [0.0, 0.012, -8e-6],
                                 "harmonic": [{ "period_mm": 10.0, "amplitude_um": 0.4, "phase_deg": 30.0 }] })),
        }),
    );
    let estimate = estimate(
        "vmc3",
        json!({
            // error 0.1, u 0.05 ⇒ 2.0; [10.0, 10.2] covers 10.
            "EC0Y": { "axis": "Y", "kind": "squareness", "unit": "urad",
                      "terms": { "constant_urad": 10.1 },
                      "standard_uncertainty": { "constant_urad": 0.05 },
                      "interval_95": { "constant_urad": [10.0, 10.2] } },
            // Degree 1: error 0.0003, u 0.0001 ⇒ 3.0, [0.0121, 0.0125] misses 0.012. Degree 0:
            // no uncertainty. The truth's −8e-6 x² is beyond the estimate's degree.
            // Harmonic: amplitude 0.5 vs 0.4 (u 0.05 ⇒ 2.0, [0.3, 0.5] covers); phase −330°
            // is 30°: error 0 after the turn, [-335, -325] covers.
            "EXX": { "axis": "X", "kind": "component", "unit": "um",
                     "terms": { "polynomial_um": [0.0, 0.0123],
                                "harmonic": [{ "period_mm": 10.0, "amplitude_um": 0.5, "phase_deg": -330.0 }] },
                     "standard_uncertainty": { "polynomial_um": [null, 0.0001],
                                               "harmonic": [{ "amplitude_um": 0.05, "phase_deg": 2.0 }] },
                     "interval_95": { "polynomial_um": [null, [0.0121, 0.0125]],
                                      "harmonic": [{ "amplitude_um": [0.3, 0.5], "phase_deg": [-335.0, -325.0] }] } },
            // Not in the truth: scored against 0; interval [-1, 1] covers it.
            "EZT": { "terms": { "constant_um": 0.5 }, "standard_uncertainty": { "constant_um": 0.25 },
                     "interval_95": { "constant_um": [-1.0, 1.0] } },
        }),
    );
    let s = score(&estimate, &truth, &m).unwrap();
    let p = |n: &str| s.parameters.iter().find(|p| p.name == n).unwrap();
    let ec0y = p("EC0Y");
    assert!((ec0y.error - 0.1).abs() < 1e-12);
    assert!((ec0y.normalised.unwrap() - 2.0).abs() < 1e-9);
    assert_eq!((ec0y.uncertainty, ec0y.covered), (Some(0.05), Some(true)));
    let c1 = p("EXX.polynomial_um[1]");
    assert_eq!((c1.unit.as_str(), c1.truth), ("um/mm", 0.012));
    assert!((c1.normalised.unwrap() - 3.0).abs() < 1e-9);
    assert_eq!(c1.covered, Some(false));
    let c0 = p("EXX.polynomial_um[0]");
    assert_eq!(
        (c0.uncertainty, c0.normalised, c0.covered),
        (None, None, None)
    );
    let amplitude = p("EXX.harmonic[0].amplitude_um");
    assert!((amplitude.normalised.unwrap() - 2.0).abs() < 1e-9);
    assert_eq!(amplitude.covered, Some(true));
    let phase = p("EXX.harmonic[0].phase_deg");
    assert_eq!(phase.unit, "deg");
    assert!(phase.error.abs() < 1e-12, "{phase:?}");
    assert_eq!(phase.covered, Some(true));
    let ezt = p("EZT");
    assert_eq!((ezt.truth, ezt.error, ezt.covered), (0.0, 0.5, Some(true)));
    assert!((ezt.normalised.unwrap() - 2.0).abs() < 1e-12);
    assert_eq!(s.not_in_truth, ["EZT"]);
    assert_eq!(s.unmodelled_terms, ["EXX.polynomial_um[2]"]);
    // Intervals: EC0Y yes, c1 no, amplitude yes, phase yes, EZT yes.
    assert_eq!(s.coverage, (4, 5));
    let json = s.to_json();
    assert_eq!(
        json["coverage"],
        json!({ "covered": 4, "with_interval": 5 })
    );
    let first = &json["parameters"][0];
    for key in [
        "name",
        "unit",
        "estimate",
        "truth",
        "error",
        "uncertainty",
        "normalised",
        "covered",
    ] {
        assert!(first.get(key).is_some(), "{key}");
    }
    assert!(s.report().contains("4 of 5"), "{}", s.report());
}

#[test]
fn a_table_estimate_is_compared_at_its_knots() {
    // EYX = 0.01 µm/mm · x + a 40 mm harmonic: a table with knots every 190 mm samples the
    // line (truth at the knots = 0.01·x) and cannot resolve the harmonic.
    let m = machine("vmc3");
    let truth = truth(
        "vmc3",
        json!({ "EYX": entry(json!({ "polynomial_um": [0.0, 0.01],
            "harmonic": [{ "period_mm": 40.0, "amplitude_um": 0.3 }] })) }),
    );
    let table = estimate(
        "vmc3",
        json!({ "EYX": entry(json!({ "table": {
            "positions_mm": [0.0, 190.0, 380.0, 570.0, 760.0],
            "values_um": [0.0, 1.9, 3.8, 5.7, 7.6] } })) }),
    );
    let s = score(&table, &truth, &m).unwrap();
    assert_eq!(s.parameters.len(), 5);
    for (i, p) in s.parameters.iter().enumerate() {
        assert_eq!(p.name, format!("EYX.table.values_um[{i}]"));
        assert!((p.truth - 1.9 * i as Real).abs() < 1e-12, "{p:?}");
        assert!(p.error.abs() < 1e-12);
    }
    assert_eq!(s.unmodelled_terms, ["EYX.harmonic[0]"]);
}

#[test]
fn another_machine_or_a_wrong_unit_is_refused_with_its_name() {
    let m = machine("vmc3");
    let good_truth = truth(
        "vmc3",
        json!({ "EC0Y": entry(json!({ "constant_urad": 10.0 })) }),
    );
    let e = score(&estimate("trunnion5", json!({})), &good_truth, &m).unwrap_err();
    assert!(
        matches!(&e, ScoreError::Machine { file, named, loaded }
            if file == "estimate" && named == "trunnion5" && loaded == "vmc3"),
        "{e:?}"
    );
    let message = e.to_string();
    assert!(
        message.contains("trunnion5") && message.contains("vmc3"),
        "{message}"
    );
    let e = score(
        &estimate("vmc3", json!({})),
        &truth("headtable5", json!({})),
        &m,
    )
    .unwrap_err();
    assert!(
        matches!(&e, ScoreError::Machine { file, named, .. } if file == "truth" && named == "headtable5"),
        "{e:?}"
    );

    // µm for a rotation.
    let e = score(
        &estimate(
            "vmc3",
            json!({ "EC0Y": entry(json!({ "constant_um": 10.0 })) }),
        ),
        &good_truth,
        &m,
    )
    .unwrap_err();
    match &e {
        ScoreError::Units {
            file,
            path,
            parameter,
            expected,
            ..
        } => {
            assert_eq!(file, "estimate");
            assert_eq!(path, "errors.EC0Y.terms.constant_um");
            assert_eq!(parameter, "EC0Y");
            assert_eq!(expected, "constant_urad");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        e.to_string(),
        "estimate: errors.EC0Y.terms.constant_um: EC0Y is a rotation; expected constant_urad"
    );
    // A period in degrees along a linear axis, and a unit field that disagrees.
    let e = score(
        &estimate(
            "vmc3",
            json!({ "EXX": entry(json!({ "harmonic": [{ "period_deg": 10.0, "amplitude_um": 1.0 }] })) }),
        ),
        &good_truth,
        &m,
    )
    .unwrap_err();
    assert!(
        matches!(&e, ScoreError::Units { path, expected, .. }
            if path == "errors.EXX.terms.harmonic[0].period_deg" && expected == "period_mm"),
        "{e:?}"
    );
    let e = score(
        &estimate(
            "vmc3",
            json!({ "EC0Y": { "unit": "um", "terms": { "constant_urad": 1.0 } } }),
        ),
        &good_truth,
        &m,
    )
    .unwrap_err();
    assert!(
        matches!(&e, ScoreError::Units { path, .. } if path == "errors.EC0Y.unit"),
        "{e:?}"
    );

    // Malformed shapes name the key path.
    let shape = |estimate: Value| match score(&estimate, &good_truth, &m).unwrap_err() {
        ScoreError::Shape {
            file,
            path,
            message,
        } => (file, path, message),
        other => panic!("{other:?}"),
    };
    let (file, path, _) = shape(json!({ "machine": "vmc3" }));
    assert_eq!((file.as_str(), path.as_str()), ("estimate", "errors"));
    let (_, path, _) = shape(estimate("vmc3", json!({ "EXX": { "axis": "X" } })));
    assert_eq!(path, "errors.EXX.terms");
    let (_, path, message) = shape(estimate(
        "vmc3",
        json!({ "EXX": entry(json!({ "constant_um": 1.0, "slope": 2.0 })) }),
    ));
    assert_eq!(path, "errors.EXX.terms");
    assert!(message.contains("slope"), "{message}");
    let (_, path, _) = shape(estimate(
        "vmc3",
        json!({ "EXA": entry(json!({ "constant_um": 1.0 })) }),
    ));
    assert_eq!(path, "errors.EXA");
    let (_, path, _) = shape(estimate(
        "vmc3",
        json!({ "EC0Y": { "terms": { "constant_urad": 1.0 },
                          "standard_uncertainty": { "constant_urad": "small" } } }),
    ));
    assert_eq!(path, "errors.EC0Y.standard_uncertainty.constant_urad");
    let (_, path, _) = shape(estimate(
        "vmc3",
        json!({ "EC0Y": { "terms": { "constant_urad": 1.0 },
                          "interval_95": { "constant_urad": [2.0, 1.0] } } }),
    ));
    assert_eq!(path, "errors.EC0Y.interval_95.constant_urad");
    let (_, path, message) = shape(estimate(
        "vmc3",
        json!({ "EC0Y": entry(json!({ "polynomial_urad": [1.0, 2.0] })) }),
    ));
    assert_eq!(path, "errors.EC0Y.terms");
    assert!(message.starts_with("polynomial_urad: "), "{message}");
    let e = score(&json!([]), &good_truth, &m).unwrap_err();
    assert_eq!(e.to_string(), "estimate: expected a JSON object");
    let e = score(&json!({ "machine": "vmc3" }), &good_truth, &m).unwrap_err();
    assert_eq!(e.to_string(), "estimate: errors: missing");
    assert_eq!(
        e.in_file("runs/a/estimate.json").to_string(),
        "runs/a/estimate.json: errors: missing"
    );
    // The truth passed as the estimate.
    let (_, path, _) = shape(json!({ "mtwin": "score", "machine": "vmc3", "errors": {} }));
    assert_eq!(path, "mtwin");
}

/// Compares two JSON values: the same shape, numbers equal to `relative`.
fn assert_close(a: &Value, b: &Value, relative: Real, at: &str) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!(
                (x - y).abs() <= relative * x.abs().max(y.abs()),
                "{at}: {x} vs {y}"
            );
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{at}");
            for (i, (x, y)) in x.iter().zip(y).enumerate() {
                assert_close(x, y, relative, &format!("{at}[{i}]"));
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            let keys = |m: &serde_json::Map<String, Value>| m.keys().cloned().collect::<Vec<_>>();
            assert_eq!(keys(x), keys(y), "{at}");
            for (k, v) in x {
                assert_close(v, &y[k], relative, &format!("{at}.{k}"));
            }
        }
        _ => assert_eq!(a, b, "{at}"),
    }
}

fn spec(terms: Value) -> ErrorSpec {
    serde_json::from_value(terms).unwrap()
}

#[test]
fn spec_and_function_convert_both_ways() {
    let cases = [
        ("EX0C", json!({ "constant_um": 12.0 })),
        ("EA0C", json!({ "constant_urad": 25.0 })),
        ("EXX", json!({ "polynomial_um": [0.3, 0.012, -8e-6] })),
        (
            "EBB",
            json!({ "polynomial_urad": [0.0, 0.05, 1e-4, -3e-7] }),
        ),
        ("EXX", json!({ "reversal_um": 3.0 })),
        ("ECC", json!({ "reversal_urad": 1.5 })),
        (
            "EXX",
            json!({ "harmonic": [{ "period_mm": 10.0, "amplitude_um": 0.4, "phase_deg": 30.0 }] }),
        ),
        (
            "ECC",
            json!({ "harmonic": [{ "period_deg": 90.0, "amplitude_urad": 2.0, "phase_deg": -45.0 },
                                     { "period_deg": 120.0, "amplitude_urad": 0.7, "phase_deg": 10.0 }] }),
        ),
        (
            "EYX",
            json!({ "table": { "positions_mm": [0.0, 380.0, 760.0], "values_um": [0.0, 1.3, -0.7], "interpolation": "linear" } }),
        ),
        (
            "ECC",
            json!({ "table": { "positions_deg": [0.0, 120.0, 240.0, 360.0], "values_urad": [1.0, 3.0, -2.0, 1.0], "interpolation": "cubic" } }),
        ),
        (
            "EZC",
            json!({ "constant_um": 0.2, "polynomial_um": [0.0, 0.001], "reversal_um": 0.5,
                        "harmonic": [{ "period_deg": 45.0, "amplitude_um": 0.1, "phase_deg": 5.0 }],
                        "table": { "positions_deg": [0.0, 90.0], "values_um": [0.0, 0.4], "interpolation": "linear" } }),
        ),
    ];
    for (parameter, terms) in cases {
        let name = name(parameter);
        let f = function_of(&spec(terms.clone()), name).unwrap();
        let back = spec_of(&f, name);
        assert_close(
            &serde_json::to_value(&back).unwrap(),
            &terms,
            1e-15,
            parameter,
        );
        let again = function_of(&back, name).unwrap();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        f.coefficients(&mut a);
        again.coefficients(&mut b);
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x - y).abs() <= 1e-15 * x.abs().max(y.abs()),
                "{parameter}: {x} vs {y}"
            );
        }
    }

    // SI by hand: µm per mm^k → m per m^k (1e-6 / 1e-3^k); µrad per deg^k → rad per rad^k.
    let f = function_of(
        &spec(json!({ "polynomial_um": [0.3, 0.012, -8e-6] })),
        name("EXX"),
    )
    .unwrap();
    let expected = [
        0.3e-6,
        0.012e-6 / M_PER_MM,
        -8e-6 * 1e-6 / (M_PER_MM * M_PER_MM),
    ];
    let ErrorFunction::Polynomial(c) = &f else {
        panic!("{f:?}")
    };
    for (c, e) in c.iter().zip(expected) {
        assert!((c - e).abs() <= 1e-15 * e.abs(), "{c} vs {e}");
    }
    let f = function_of(
        &spec(json!({ "polynomial_urad": [0.0, 0.05] })),
        name("EBB"),
    )
    .unwrap();
    let at_ten_degrees = f.value(10.0 * RAD_PER_DEG, Direction::Positive);
    assert!((at_ten_degrees - 0.5e-6).abs() < 1e-20, "{at_ten_degrees}");
    let f = function_of(
        &spec(json!({ "harmonic": [{ "period_deg": 90.0, "amplitude_urad": 2.0, "phase_deg": 90.0 }] })),
        name("ECC"),
    )
    .unwrap();
    assert!((f.value(0.0, Direction::Positive) - 2e-6).abs() < 1e-20);

    // A sum (nested) merges into one spec.
    let sum = ErrorFunction::Sum(vec![
        ErrorFunction::Constant(1e-6),
        ErrorFunction::Sum(vec![
            ErrorFunction::Constant(2e-6),
            ErrorFunction::Polynomial(vec![1e-6, 1e-5]),
            ErrorFunction::Reversal(2e-6),
        ]),
        ErrorFunction::Polynomial(vec![0.0, 1e-5, 1e-3]),
    ]);
    let merged = spec_of(&sum, name("EYY"));
    assert_close(
        &serde_json::to_value(&merged).unwrap(),
        &json!({ "constant_um": 3.0, "polynomial_um": [1.0, 0.02, 0.001], "reversal_um": 2.0 }),
        1e-14,
        "sum",
    );
    let back = function_of(&merged, name("EYY")).unwrap();
    for q in [0.0, 0.1, 0.37] {
        for d in [Direction::Positive, Direction::Negative] {
            let (x, y) = (sum.value(q, d), back.value(q, d));
            assert!((x - y).abs() < 1e-18, "{q}: {x} vs {y}");
        }
    }
    // Two linear tables on different knots: their sum on the union of the knots, exactly.
    let t1 = Table::new(vec![0.0, 0.2], vec![0.0, 2e-6], Interpolation::Linear).unwrap();
    let t2 = Table::new(vec![0.1, 0.3], vec![1e-6, -1e-6], Interpolation::Linear).unwrap();
    let sum = ErrorFunction::Sum(vec![ErrorFunction::Table(t1), ErrorFunction::Table(t2)]);
    let merged = spec_of(&sum, name("EZY"));
    let table = merged.table.as_ref().unwrap();
    assert_close(
        &json!(table.positions_mm),
        &json!([0.0, 100.0, 200.0, 300.0]),
        1e-15,
        "union",
    );
    let back = function_of(&merged, name("EZY")).unwrap();
    for q in [-0.1, 0.0, 0.05, 0.15, 0.25, 0.3, 0.5] {
        let (x, y) = (
            sum.value(q, Direction::Positive),
            back.value(q, Direction::Positive),
        );
        assert!((x - y).abs() < 1e-18, "{q}: {x} vs {y}");
    }
}

#[test]
fn function_of_names_the_key_and_what_is_wrong() {
    let err =
        |parameter: &str, terms: Value| function_of(&spec(terms), name(parameter)).unwrap_err();
    assert_eq!(
        err("EA0C", json!({ "constant_um": 1.0 })),
        "constant_um: EA0C is a rotation; give it in urad as constant_urad"
    );
    assert!(err("EXX", json!({})).starts_with("no term given"));
    assert!(
        err("EX0C", json!({ "polynomial_um": [1.0, 2.0] }))
            .starts_with("polynomial_um: location, squareness and tool errors are constants")
    );
    assert!(
        err(
            "ECC",
            json!({ "table": { "positions_mm": [0.0, 1.0], "values_urad": [0.0, 1.0] } })
        )
        .starts_with("table.positions_mm: ")
    );
    assert_eq!(
        err("EXX", json!({ "harmonic": [{ "amplitude_um": 1.0 }] })),
        "harmonic[0].period_mm: required"
    );
}

#[test]
fn the_volumetric_figure_uses_the_exact_chain_of_each_model() {
    // Independent of the scorer: the compensated maximum on vmc3 with EC0Y = 10 µrad and an
    // estimate of 9 µrad is the largest |dev(10) − dev(9)| over the grid corners, at y = 410 mm.
    let m = machine("vmc3");
    let ten = error_model_of(
        &json!({ "EC0Y": entry(json!({ "constant_urad": 10.0 })) }),
        &m,
    )
    .unwrap();
    let nine = error_model_of(
        &json!({ "EC0Y": entry(json!({ "constant_urad": 9.0 })) }),
        &m,
    )
    .unwrap();
    let mut w = Workspace::new(&m);
    let state = MachineState::at(mtwin::machine::AxisValues::from_file_units(&[
        (mtwin::machine::Axis::X, 760.0),
        (mtwin::machine::Axis::Y, 410.0),
        (mtwin::machine::Axis::Z, 520.0),
    ]));
    let d = ten.deviation(&m, &mut w, &state).translation
        - nine.deviation(&m, &mut w, &state).translation;
    assert!((d.length() * 1e6 - 0.41).abs() < ROUND_OFF_UM, "{d}");
    let truth = truth(
        "vmc3",
        json!({ "EC0Y": entry(json!({ "constant_urad": 10.0 })) }),
    );
    let estimate = estimate(
        "vmc3",
        json!({ "EC0Y": entry(json!({ "constant_urad": 9.0 })) }),
    );
    let s = score(&estimate, &truth, &m).unwrap();
    assert!((s.volumetric.compensated_max_um - d.length() * 1e6).abs() < ROUND_OFF_UM);
}
