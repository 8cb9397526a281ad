//! Identifiability of a design and greedy test planning, against hand derivations: equal and
//! zero columns, the noise-tied rank rule on a pair whose singular values are set exactly, the
//! observability indices on a diagonal design, a closed-form correlation, the remedies of a
//! confounded pair and a three-candidate plan.

use mtwin::estimate::identifiability::*;
use mtwin::estimate::plan;
use nalgebra::DMatrix;

fn labels(names: &[&str]) -> Vec<String> {
    names.iter().map(|s| s.to_string()).collect()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

/// Column `j` of an orthogonal design with given column vectors.
fn from_columns(columns: &[&[f64]]) -> DMatrix<f64> {
    let m = columns[0].len();
    DMatrix::from_fn(m, columns.len(), |i, j| columns[j][i])
}

#[test]
fn equal_columns_are_one_null_combination() {
    // EX0C and sphere1.x enter every reading alike; EY0C and EA0C are seen on their own rows.
    // Column norms: EY0C √(3² + 4²) = 5, EA0C √(0.5² + 0.5²) = 1/√2.
    let names = labels(&["EX0C", "EY0C", "sphere1.x", "EA0C"]);
    let j = from_columns(&[
        &[1.0, 1.0, 0.0, 0.0, 0.0, 0.0],
        &[0.0, 0.0, 3.0, 4.0, 0.0, 0.0],
        &[1.0, 1.0, 0.0, 0.0, 0.0, 0.0],
        &[0.0, 0.0, 0.0, 0.0, 0.5, -0.5],
    ]);
    let a = analyse(&j, &names, &Options::default());
    assert_eq!(a.rank, 3);
    assert_eq!(a.unidentifiable, vec![0, 2]);
    assert_eq!(a.null_combinations.len(), 1);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let null = &a.null_combinations[0];
    assert_eq!(null.terms.len(), 2);
    assert_eq!((null.terms[0].0, null.terms[1].0), (0, 2));
    assert!(close(null.terms[0].1, h, 1e-12) && close(null.terms[1].1, -h, 1e-12));
    assert_eq!(null.describe(&names), "EX0C − sphere1.x");
    assert_eq!(a.seen_combinations.len(), 1);
    let seen = &a.seen_combinations[0];
    assert!(close(seen.terms[0].1, h, 1e-12) && close(seen.terms[1].1, h, 1e-12));
    assert_eq!(seen.describe(&names), "EX0C + sphere1.x");
    // The sum is read twice with unit weight: u(EX0C + sphere1.x) = 1/√2.
    assert!(close(a.uncertainty(seen).unwrap(), h, 1e-12));
    assert_eq!(a.uncertainty(null), None);
    // Orthogonal columns: u_j = 1/‖column j‖.
    assert_eq!(a.standard_uncertainty[0], None);
    assert_eq!(a.standard_uncertainty[2], None);
    assert!(close(a.standard_uncertainty[1].unwrap(), 0.2, 1e-12));
    assert!(close(
        a.standard_uncertainty[3].unwrap(),
        2f64.sqrt(),
        1e-12
    ));
    // Orthogonal ⇒ uncorrelated; the unidentifiable rows are NaN.
    assert!(a.correlation[(1, 3)].abs() < 1e-12 && a.correlation[(1, 1)] == 1.0);
    assert!(a.correlation[(0, 1)].is_nan() && a.correlation[(2, 2)].is_nan());
    // Singular values 5, 2 (the pair: ‖(1,1)‖·√2), 1/√2 → κ = 5/(1/√2).
    assert!(close(a.condition_number, 5.0 * 2f64.sqrt(), 1e-12));
    let report = a.report();
    assert!(report.contains("rank 3 of 4"), "{report}");
    assert!(
        report.contains("cannot be told apart: EX0C − sphere1.x"),
        "{report}"
    );
    assert!(report.contains("only EX0C + sphere1.x is seen"), "{report}");
    let json = a.to_json();
    assert_eq!(json["rank"], 3);
    assert_eq!(json["unidentifiable"][1], "sphere1.x");
    assert_eq!(
        json["null_combinations"][0]["description"],
        "EX0C − sphere1.x"
    );
    let coefficient = json["null_combinations"][0]["terms"][1]["coefficient"].as_f64();
    assert!(close(coefficient.unwrap(), -1.0, 1e-12));
    assert!(json["parameters"][0]["standard_uncertainty_um_eq"].is_null());
    assert!(json["correlation"][0][1].is_null());
}

/// A design known to 10⁻⁷ of its entries, as a Jacobian by finite differences on the exact
/// chain is (trunnion5's R-tests with the set-up free: 8 null singular values of 1.0–15 × 10⁻⁷
/// against 9.4 for the smallest identified one). Parameters in the order P0, A, B, P3, C, D:
/// A and B enter every reading alike, D as the opposite of C, P0 and P3 on their own. By hand
/// the null combinations are `A − B` and `C + D`, and only `A + B` and `C − D` are seen. The
/// null basis then holds entries of about 10⁻⁸ in the columns of P0 and P3: made pivots of the
/// echelon form (as when any entry above 10⁻⁹ could be one), each divided its row by that
/// noise, and the report read `C + D` and `A − B + 0.289 C + 0.289 D`.
#[test]
fn a_design_known_to_finite_difference_noise_gives_the_hand_combinations() {
    let names = labels(&["P0", "A", "B", "P3", "C", "D"]);
    let m = 40;
    let wave = |i: usize, k: f64| ((i as f64 + 1.0) * k).sin();
    let mut state: u64 = 12345;
    let mut noise = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2e-7
    };
    let mut j = DMatrix::from_fn(m, 6, |i, c| match c {
        0 => wave(i, 0.37),
        1 | 2 => wave(i, 1.21) + 0.5,
        3 => wave(i, 2.03) - 0.2,
        4 => wave(i, 0.71) * 2.0,
        _ => -wave(i, 0.71) * 2.0,
    });
    j.iter_mut().for_each(|x| *x += noise());
    let a = analyse(&j, &names, &Options::default());
    assert_eq!(a.rank, 4);
    assert_eq!(a.unidentifiable, vec![1, 2, 4, 5]);
    let null: Vec<String> = a
        .null_combinations
        .iter()
        .map(|c| c.describe(&names))
        .collect();
    assert_eq!(null, ["A − B", "C + D"], "{}", a.report());
    let seen: Vec<String> = a
        .seen_combinations
        .iter()
        .map(|c| c.describe(&names))
        .collect();
    assert_eq!(seen, ["A + B", "C − D"], "{}", a.report());
    // Each is seen with the uncertainty of the sum read with these columns.
    for c in &a.seen_combinations {
        assert!(a.uncertainty(c).is_some(), "{}", a.report());
    }
}

#[test]
fn a_zero_column_alone_is_unidentifiable() {
    let names = labels(&["a", "b", "c"]);
    let j = from_columns(&[&[2.0, 0.0, 1.0], &[0.0, 0.0, 0.0], &[0.0, 3.0, 0.0]]);
    let a = analyse(&j, &names, &Options::default());
    assert_eq!(a.rank, 2);
    assert_eq!(a.unidentifiable, vec![1]);
    assert_eq!(a.null_combinations.len(), 1);
    assert_eq!(a.null_combinations[0].terms, vec![(1, 1.0)]);
    assert!(a.seen_combinations.is_empty());
    assert!(close(
        a.standard_uncertainty[0].unwrap(),
        1.0 / 5f64.sqrt(),
        1e-12
    ));
    assert!(close(a.standard_uncertainty[2].unwrap(), 1.0 / 3.0, 1e-12));
    assert!(a.report().contains("not seen at all: b"));
}

#[test]
fn fewer_readings_than_parameters_leave_the_rest_null() {
    // One reading of a + b over three parameters: null space of dimension 2.
    let names = labels(&["a", "b", "c"]);
    let j = DMatrix::from_row_slice(1, 3, &[1.0, 1.0, 0.0]);
    let a = analyse(&j, &names, &Options::default());
    assert_eq!(a.rank, 1);
    assert_eq!(a.singular_values.len(), 3);
    assert_eq!(a.unidentifiable, vec![0, 1, 2]);
    let described: Vec<String> = a
        .null_combinations
        .iter()
        .map(|c| c.describe(&names))
        .collect();
    assert_eq!(described, vec!["a − b", "c"]);
    assert_eq!(a.seen_combinations.len(), 1);
    assert_eq!(a.seen_combinations[0].describe(&names), "a + b");
    assert!(close(
        a.uncertainty(&a.seen_combinations[0]).unwrap(),
        1.0,
        1e-12
    ));
}

/// J = e1·s1·v1ᵀ + e2·s2·v2ᵀ with v1 = (1, 1)/√2, v2 = (1, −1)/√2: singular values s1, s2.
fn pair(s1: f64, s2: f64) -> DMatrix<f64> {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    DMatrix::from_row_slice(2, 2, &[s1 * h, s1 * h, s2 * h, -s2 * h])
}

#[test]
fn the_rank_rule_follows_the_largest_uncertainty() {
    let names = labels(&["EX0C", "EY0C"]);
    let options = Options::default(); // 1000 µm-eq
    // 1/s2 = 900 µm-eq: identified, but weak.
    let a = analyse(&pair(1.0, 1.0 / 900.0), &names, &options);
    assert_eq!(a.rank, 2);
    assert!(a.unidentifiable.is_empty());
    assert!(close(a.tolerance, 1e-3, 1e-15));
    // Σ = V diag(1, 900²) Vᵀ ⇒ u² = (1 + 900²)/2 for each, correlation (1 − 900²)/(1 + 900²).
    let u = ((1.0 + 810_000.0) / 2.0f64).sqrt();
    assert!(close(a.standard_uncertainty[0].unwrap(), u, 1e-9));
    assert!(close(a.standard_uncertainty[1].unwrap(), u, 1e-9));
    assert!(close(
        a.correlation[(0, 1)],
        (1.0 - 810_000.0) / (1.0 + 810_000.0),
        1e-9
    ));
    assert_eq!(a.weak.len(), 1);
    let w = &a.weak[0];
    assert_eq!(w.combination.describe(&names), "EX0C − EY0C");
    assert!(close(w.singular_value, 1.0 / 900.0, 1e-9));
    // The described combination is √2 times the unit one: u = 900·√2.
    assert!(close(w.uncertainty, 900.0 * 2f64.sqrt(), 1e-9));
    assert!(close(
        a.uncertainty(&w.combination).unwrap(),
        w.uncertainty,
        1e-9
    ));
    assert!(close(a.condition_number, 900.0, 1e-9));

    // 1/s2 = 1100 µm-eq: beyond the bound, the difference is a null combination.
    let b = analyse(&pair(1.0, 1.0 / 1100.0), &names, &options);
    assert_eq!(b.rank, 1);
    assert_eq!(b.unidentifiable, vec![0, 1]);
    assert_eq!(b.null_combinations[0].describe(&names), "EX0C − EY0C");
    assert_eq!(b.seen_combinations[0].describe(&names), "EX0C + EY0C");
    assert!(b.weak.is_empty());
    // A looser bound takes it back.
    let loose = Options {
        largest_uncertainty: 2000.0,
        ..Options::default()
    };
    assert_eq!(analyse(&pair(1.0, 1.0 / 1100.0), &names, &loose).rank, 2);
}

#[test]
fn the_numerical_zero_holds_whatever_the_bound() {
    let names = labels(&["a", "b"]);
    let options = Options {
        largest_uncertainty: f64::INFINITY,
        ..Options::default()
    };
    // s2/s1 = 1e-11 < 1e-10: a numerical zero even with no noise bound.
    let a = analyse(&pair(1.0, 1e-11), &names, &options);
    assert_eq!(a.rank, 1);
    assert!(close(a.tolerance, 1e-10, 1e-12));
    let b = analyse(&pair(1.0, 1e-9), &names, &options);
    assert_eq!(b.rank, 2);
}

#[test]
fn observability_indices_on_a_diagonal_design() {
    // Singular values 8, 4, 2 (1/µm-eq) over m = 4 readings (a row of zeros).
    let j = DMatrix::from_row_slice(
        4,
        3,
        &[2.0, 0.0, 0.0, 0.0, 8.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0],
    );
    let a = analyse(&j, &labels(&["a", "b", "c"]), &Options::default());
    assert_eq!(a.singular_values, vec![8.0, 4.0, 2.0]);
    let o = a.observability;
    assert!(close(o.o1, 64f64.cbrt() / 2.0, 1e-12)); // (8·4·2)^(1/3)/√4 = 2
    assert!(close(o.o1, 2.0, 1e-12));
    assert!(close(o.o2, 0.25, 1e-12));
    assert!(close(o.o3, 2.0, 1e-12));
    assert!(close(o.o4, 0.5, 1e-12));
    assert!(close(o.o5, 8.0 / 7.0, 1e-12)); // 1/(1/8 + 1/4 + 1/2)
    assert!(close(a.condition_number, 4.0, 1e-12));
    assert!(a.weak.is_empty());
    assert!(a.report().contains("O5 = 1.14"));
}

#[test]
fn correlation_of_a_straight_line_fit() {
    // Columns (1, 1, 1) and (1, 2, 3): JᵀJ = [[3, 6], [6, 14]], det 6,
    // (JᵀJ)⁻¹ = [[14, −6], [−6, 3]]/6 ⇒ u = √(7/3), √(1/2), ρ = −6/√(14·3) = −√(6/7).
    let j = from_columns(&[&[1.0, 1.0, 1.0], &[1.0, 2.0, 3.0]]);
    let a = analyse(&j, &labels(&["offset", "slope"]), &Options::default());
    assert_eq!(a.rank, 2);
    assert!(close(
        a.standard_uncertainty[0].unwrap(),
        (7.0f64 / 3.0).sqrt(),
        1e-12
    ));
    assert!(close(
        a.standard_uncertainty[1].unwrap(),
        0.5f64.sqrt(),
        1e-12
    ));
    assert!(close(a.correlation[(0, 1)], -(6.0f64 / 7.0).sqrt(), 1e-12));
    assert!(close(a.correlation[(1, 0)], -(6.0f64 / 7.0).sqrt(), 1e-12));
}

#[test]
fn remedies_name_the_test_that_separates_a_pair() {
    // EA0A and EA0C enter two readings alike (unit weight); EX0C is seen alone.
    let names = labels(&["EA0A", "EA0C", "EX0C"]);
    let base = from_columns(&[&[1.0, 1.0, 0.0], &[1.0, 1.0, 0.0], &[0.0, 0.0, 2.0]]);
    let a = analyse(&base, &names, &Options::default());
    assert_eq!(a.null_combinations.len(), 1);
    assert_eq!(a.null_combinations[0].describe(&names), "EA0A − EA0C");
    let candidates = vec![
        // A level on the A axis: EA0A alone, σ = 2 µm-eq.
        (
            "level".to_string(),
            DMatrix::from_row_slice(1, 3, &[0.5, 0.0, 0.0]),
        ),
        // Another reading of the sum: no help.
        (
            "repeat".to_string(),
            DMatrix::from_row_slice(1, 3, &[1.0, 1.0, 0.0]),
        ),
        // EX0C again: no help.
        (
            "x".to_string(),
            DMatrix::from_row_slice(1, 3, &[0.0, 0.0, 1.0]),
        ),
        // EA0C alone, σ = 1 µm-eq.
        (
            "xr20".to_string(),
            DMatrix::from_row_slice(1, 3, &[0.0, 1.0, 0.0]),
        ),
    ];
    let found = remedies(
        &base,
        &a.null_combinations,
        &candidates,
        &Options::default(),
    );
    assert_eq!(found.len(), 1);
    let list = &found[0];
    assert_eq!(list.len(), 2, "{list:?}");
    // var(a + c) = 1/2 from the two readings. xr20: var(c) = 1, a − c = (a + c) − 2c ⇒ 1/2 + 4.
    // level: var(a) = 4, a − c = 2a − (a + c) ⇒ 16 + 1/2.
    assert_eq!(list[0].0, "xr20");
    assert!(close(list[0].1, 4.5f64.sqrt(), 1e-12));
    assert_eq!(list[1].0, "level");
    assert!(close(list[1].1, 16.5f64.sqrt(), 1e-12));
}

#[test]
fn plan_chooses_the_tests_that_see_something_new() {
    let names = labels(&["p1", "p2"]);
    let a = DMatrix::from_row_slice(1, 2, &[2.0, 0.0]);
    let b = DMatrix::from_row_slice(1, 2, &[0.0, 3.0]);
    let candidates = vec![
        ("A".to_string(), a.clone()),
        ("B".to_string(), b),
        ("C".to_string(), a),
    ];
    let options = Options::default();
    let p = 1e-6; // 1/1000²
    // Gains per reading from the prior p·I: A ln((4 + p)/p), B ln((9 + p)/p): B first, then A
    // (C ties with A and comes later in the list).
    let plan = plan::choose(None, &candidates, &names, 2, &options);
    let chosen: Vec<&str> = plan.steps.iter().map(|s| s.test.as_str()).collect();
    assert_eq!(chosen, vec!["B", "A"]);
    assert!(plan.identifiable);
    assert_eq!(plan.identifiable_after, Some(2));
    assert!(close(plan.prior_precision, p, 1e-15));
    assert!(close(plan.base_log_det, 2.0 * p.ln(), 1e-12));
    assert!(close(plan.steps[0].log_det, (p * (9.0 + p)).ln(), 1e-12));
    assert!(close(
        plan.steps[1].log_det,
        ((4.0 + p) * (9.0 + p)).ln(),
        1e-12
    ));
    assert_eq!(plan.steps[0].uncertainties[0], None);
    assert!(close(
        plan.steps[0].uncertainties[1].unwrap(),
        1.0 / 3.0,
        1e-12
    ));
    assert!(close(plan.steps[1].uncertainties[0].unwrap(), 0.5, 1e-12));
    let report = plan.report();
    assert!(report.contains("identifiable after step 2"), "{report}");
    let json = plan.to_json();
    assert_eq!(json["steps"][1]["test"], "A");
    assert_eq!(json["identifiable_after_steps"], 2);

    // With readings to spare the duplicate still halves the variance of p1: it comes third.
    let more = plan::choose(None, &candidates, &names, 10, &options);
    let chosen: Vec<&str> = more.steps.iter().map(|s| s.test.as_str()).collect();
    assert_eq!(chosen, vec!["B", "A", "C"]);
    assert_eq!(more.identifiable_after, Some(2));
    assert!(close(
        more.steps[2].log_det,
        ((8.0 + p) * (9.0 + p)).ln(),
        1e-12
    ));
    assert!(close(
        more.steps[2].uncertainties[0].unwrap(),
        8f64.sqrt().recip(),
        1e-12
    ));

    // A budget of one reading: B only, not identifiable; the budget, not the tests, is why
    // (A and B together see both parameters, in 3 readings with C).
    let short = plan::choose(None, &candidates, &names, 1, &options);
    assert_eq!(short.steps.len(), 1);
    assert!(!short.identifiable && short.identifiable_after.is_none());
    assert_eq!(short.limit(), Some(plan::Limit::Budget));
    assert!(short.structural.is_empty());
    let report = short.report();
    assert!(
        report.contains("within the budget of 1 readings; every test together (3 readings) would identify them all"),
        "{report}"
    );
    assert_eq!(short.to_json()["limited_by"], "budget");
    assert_eq!(plan.limit(), None);
    assert_eq!(plan.to_json()["limited_by"], serde_json::Value::Null);
}

/// Greedy can be beaten at equal budget, and the exchange finds the better set. Two
/// parameters, three one-reading tests: T1 sees p1 + p2 (row [a, a], a = 1), T2 sees p1 and T3
/// p2 (rows [b, 0] and [0, b], b = 1.2); a budget of two readings. By hand, with the prior
/// precision p: T1 alone gives det M = (a² + p)² − a⁴ ≈ 2a²p, T2 alone (b² + p)·p ≈ 1.44p, so
/// greedy takes T1 first (2 > 1.44), then T2 (tied with T3, listed first): det M =
/// (a² + b² + p)(a² + p) − a⁴ ≈ a²b² = 1.44. T2 and T3 give (b² + p)² ≈ b⁴ = 2.07: exchanging
/// T1 for T3 raises log det by ln(b²/a²) = 0.365, and nothing beats T2 with T3.
#[test]
fn plan_exchanges_a_greedy_test_for_a_better_pair() {
    let names = labels(&["p1", "p2"]);
    let (a, b) = (1.0, 1.2);
    let candidates = vec![
        ("T1".to_string(), DMatrix::from_row_slice(1, 2, &[a, a])),
        ("T2".to_string(), DMatrix::from_row_slice(1, 2, &[b, 0.0])),
        ("T3".to_string(), DMatrix::from_row_slice(1, 2, &[0.0, b])),
    ];
    let p: f64 = 1e-6;
    let plan = plan::choose(None, &candidates, &names, 2, &Options::default());
    let greedy = ((a * a + b * b + p) * (a * a + p) - a.powi(4)).ln();
    let best = 2.0 * (b * b + p).ln();
    assert!(close(plan.greedy_log_det, greedy, 1e-9));
    assert_eq!(plan.exchanges.len(), 1);
    assert_eq!(
        (
            plan.exchanges[0].removed.as_str(),
            plan.exchanges[0].added.as_str()
        ),
        ("T1", "T3")
    );
    assert!(close(plan.exchanges[0].gain, best - greedy, 1e-9));
    let mut chosen: Vec<&str> = plan.steps.iter().map(|s| s.test.as_str()).collect();
    chosen.sort();
    assert_eq!(chosen, ["T2", "T3"]);
    assert!(close(plan.steps[1].log_det, best, 1e-9));
    assert_eq!(plan.readings(), 2);
    assert!(
        plan.report().contains("T3 for T1 (+0.365)"),
        "{}",
        plan.report()
    );
    assert_eq!(plan.to_json()["exchanges"][0]["added"], "T3");
    // With three readings every test fits: nothing to exchange.
    let all = plan::choose(None, &candidates, &names, 3, &Options::default());
    assert!(all.exchanges.is_empty());
    assert_eq!(all.steps.len(), 3);
}

/// Tests that see only p1 + p2 (a ball-bar's two scales, say) leave p1 − p2 blind whatever
/// the budget: the plan says so and names the combination, rather than asking for readings.
#[test]
fn plan_names_a_blind_spot_no_budget_removes() {
    let names = labels(&["p1", "p2", "p3"]);
    let sum = DMatrix::from_row_slice(1, 3, &[1.0, 1.0, 0.0]);
    let third = DMatrix::from_row_slice(1, 3, &[0.0, 0.0, 2.0]);
    let candidates = vec![
        ("sum".to_string(), sum.clone()),
        ("sum again".to_string(), sum * 2.0),
        ("third".to_string(), third),
    ];
    let plan = plan::choose(None, &candidates, &names, 1000, &Options::default());
    assert!(!plan.identifiable);
    assert_eq!(plan.limit(), Some(plan::Limit::Structure));
    assert_eq!(plan.structural.len(), 1);
    // The blind direction is (p1 − p2)/√2, up to sign.
    let v = plan.structural[0].to_vector(3);
    assert!(
        close(v[0].abs(), 0.5f64.sqrt(), 1e-9) && close(v[0], -v[1], 1e-9),
        "{v}"
    );
    assert!(close(v[2], 0.0, 1e-9));
    let report = plan.report();
    assert!(
        report.contains("whatever the budget: no test sees"),
        "{report}"
    );
    assert!(report.contains("p1") && report.contains("p2"), "{report}");
    let json = plan.to_json();
    assert_eq!(json["limited_by"], "structure");
    assert_eq!(
        json["structural_null_combinations"]
            .as_array()
            .unwrap()
            .len(),
        1
    );
}

#[test]
fn plan_on_a_base_that_already_identifies_only_improves() {
    let names = labels(&["p1", "p2"]);
    let base = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 1.0]);
    let candidates = vec![("zero".to_string(), DMatrix::zeros(3, 2))];
    let plan = plan::choose(Some(&base), &candidates, &names, 100, &Options::default());
    assert!(
        plan.steps.is_empty(),
        "a test that sees nothing gains nothing"
    );
    assert!(plan.identifiable);
    assert_eq!(plan.identifiable_after, Some(0));
    assert!(close(plan.base_log_det, 2.0 * (1.0f64 + 1e-6).ln(), 1e-12));
}

#[test]
fn plan_pays_a_set_up_once_and_moves_a_test_onto_one_already_made() {
    // p1 is seen by A only; p2 by B and C alike. A and B need set-up s (20 min), C set-up t
    // (10 min); each runs 5 min.
    let names = labels(&["p1", "p2"]);
    let candidates = vec![
        ("A".to_string(), DMatrix::from_row_slice(1, 2, &[2.0, 0.0])),
        ("B".to_string(), DMatrix::from_row_slice(1, 2, &[0.0, 3.0])),
        ("C".to_string(), DMatrix::from_row_slice(1, 2, &[0.0, 3.0])),
    ];
    let costs = plan::Costs {
        run: vec![5.0, 5.0, 5.0],
        setup: vec![
            Some(("s".into(), 20.0)),
            Some(("s".into(), 20.0)),
            Some(("t".into(), 10.0)),
        ],
        present: Vec::new(),
        unit: "min",
    };
    // By hand: A and B share s (20 + 5 + 5), A and C do not (20 + 5 + 10 + 5).
    assert_eq!(costs.of(&[0, 1]), 30.0);
    assert_eq!(costs.of(&[0, 2]), 40.0);
    assert_eq!(costs.of(&[2]), 15.0);
    assert_eq!(costs.of(&[0, 1, 2]), 45.0);
    let with_t = plan::Costs {
        present: vec!["t".into()],
        ..costs.clone()
    };
    assert_eq!(with_t.of(&[2]), 5.0);

    // 30 minutes. Greedy takes C first (ln((9 + p)/p) over 15 min beats A's and B's over 25);
    // then neither A nor B fits (40 min). Exchanging C for A (the first of the two exchanges
    // worth the same) frees t's 10 min, and B then fits on s: B and A (listed in greedy
    // order, B gaining more per minute), 30 min, both parameters identified.
    let options = Options::default();
    let p: f64 = 1e-6;
    let plan = plan::choose_within(None, &candidates, &costs, &names, 30.0, &options);
    let chosen: Vec<&str> = plan.steps.iter().map(|s| s.test.as_str()).collect();
    assert_eq!(chosen, vec!["B", "A"], "{}", plan.report());
    assert!(plan.identifiable);
    assert_eq!(plan.exchanges.len(), 1);
    assert_eq!(
        (
            plan.exchanges[0].removed.as_str(),
            plan.exchanges[0].added.as_str()
        ),
        ("C", "A")
    );
    assert!(close(plan.greedy_log_det, (p * (9.0 + p)).ln(), 1e-12));
    assert!(close(
        plan.steps[1].log_det,
        ((4.0 + p) * (9.0 + p)).ln(),
        1e-12
    ));
    // Each step's cost on top of those before it: B's set-up and run, then A's run.
    assert_eq!((plan.steps[0].cost, plan.steps[1].cost), (25.0, 5.0));
    assert_eq!(plan.spent(), 30.0);
    let report = plan.report();
    assert!(report.contains("2 tests, 30 of 30 min"), "{report}");
    let json = plan.to_json();
    assert_eq!(json["cost_unit"], "min");
    assert_eq!(json["spent"], 30.0);
}
