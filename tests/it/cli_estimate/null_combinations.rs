//! The identifiability report's combinations on a real design: trunnion5's four K-tests with
//! every location error, the tool offset, a zero per test and the sphere's position free.

use super::{ok, root, run_into};
use crate::common::mtwin_output as mtwin;
use serde_json::Value;
use std::collections::BTreeSet;

/// The R-test's design comes from the exact chain by finite differences, so its null basis
/// carries noise of about 10⁻⁷ (its eight unidentified singular values are 1.0–15 × 10⁻⁷ per
/// µm-eq, the smallest identified 9.4). The report printed eight combinations of which six
/// were distinct, one `zero.z` row three times, none of the three tool offsets against the
/// zeros: identified parameters' noise had been taken as pivots.
///
/// By hand: the tool offset moves every reading of every test as each test's zero does, so for
/// each of x, y and z the tool offset against the four tests' zeros is one null combination,
/// every coefficient ±1 (`EXT − CK1 A0.zero.x − …`). The report must give the eight
/// combinations (28 unknowns, rank 20) in reduced echelon form: pairwise distinct, each with a
/// parameter (its pivot) that no other one holds, and these three among them.
#[test]
fn the_null_combinations_of_a_free_r_test_are_distinct_and_reduced() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_into(&root("scenarios/trunnion5_rtest.toml"), dir.path(), "rtest");
    let machine = root("models/trunnion5.urdf");
    let table = out.join("rtest.csv");
    let json: Value = serde_json::from_str(&ok(&mtwin(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        machine.as_os_str(),
        "--params".as_ref(),
        "location,zero,tool".as_ref(),
        "--free-setup".as_ref(),
        "--json".as_ref(),
        table.as_os_str(),
    ])))
    .unwrap();
    let analysis = &json["identifiability"];
    let combinations: Vec<Vec<(String, f64)>> = analysis["null_combinations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            c["terms"]
                .as_array()
                .unwrap()
                .iter()
                .map(|t| {
                    let name = t["parameter"].as_str().unwrap().to_string();
                    (name, t["coefficient"].as_f64().unwrap())
                })
                .collect()
        })
        .collect();
    let text = format!("{:#}", analysis["null_combinations"]);
    let unknowns = analysis["parameter_count"].as_u64().unwrap();
    let rank = analysis["rank"].as_u64().unwrap();
    assert_eq!((unknowns, rank), (28, 20));
    assert_eq!(combinations.len(), 8, "{text}");
    let descriptions: BTreeSet<&str> = analysis["null_combinations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["description"].as_str().unwrap())
        .collect();
    assert_eq!(descriptions.len(), 8, "{text}");
    for (k, combination) in combinations.iter().enumerate() {
        let own = combination.iter().any(|(name, _)| {
            combinations
                .iter()
                .enumerate()
                .all(|(l, other)| l == k || other.iter().all(|(n, _)| n != name))
        });
        assert!(own, "combination {k} has no parameter of its own: {text}");
    }
    let tests = ["CK1 A0", "CK1 A-45", "AK1 C0", "AC simultaneous"];
    for axis in ["X", "Y", "Z"] {
        let tool = format!("E{axis}T");
        let zero = |test: &str| format!("{test}.zero.{}", axis.to_lowercase());
        let expected: BTreeSet<String> = std::iter::once(tool.clone())
            .chain(tests.iter().map(|t| zero(t)))
            .collect();
        let found = combinations.iter().any(|c| {
            let names: BTreeSet<String> = c.iter().map(|(n, _)| n.clone()).collect();
            names == expected
                && c.iter().all(|(n, v)| {
                    let sign = if *n == tool { 1.0 } else { -1.0 };
                    (v - sign).abs() < 1e-6
                })
        });
        assert!(found, "{tool} against the four zeros: {text}");
    }
}
