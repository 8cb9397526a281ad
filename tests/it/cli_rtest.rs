//! `mtwin run` on the bundled R-test and `mtwin analyze rtest` on what it writes: the JSON keys
//! the help documents, the figures equal to the library's, the SVG drawn per test, and bad
//! files refused with the file and line, non-zero exit.

use crate::common::mtwin_output as mtwin;
use serde_json::Value;
use std::path::Path;

#[test]
fn analyze_rtest_reports_the_documented_keys_and_draws_each_test() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/trunnion5_rtest.toml");
    let out = dir.path().join("out");
    let run = mtwin(&[
        "run".as_ref(),
        scenario.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let table = out.join("rtest.csv");
    let svg = dir.path().join("rtest.svg");
    let analyze = mtwin(&[
        "analyze".as_ref(),
        "rtest".as_ref(),
        table.as_os_str(),
        "--json".as_ref(),
        "--svg".as_ref(),
        svg.as_os_str(),
    ]);
    assert!(
        analyze.status.success(),
        "{}",
        String::from_utf8_lossy(&analyze.stderr)
    );
    let json: Value = serde_json::from_slice(&analyze.stdout).unwrap();
    let tests = json["tests"].as_array().unwrap();
    let names: Vec<&str> = tests.iter().map(|t| t["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["CK1 A0", "CK1 A-45", "AK1 C0", "AC simultaneous"]);
    // The figures are the library's, on the same file.
    let evaluation =
        mtwin::kinds::rtest::evaluate(&mtwin::kinds::rtest::RtestTable::read(&table).unwrap())
            .unwrap();
    for (entry, ours) in tests.iter().zip(&evaluation.tests) {
        for key in [
            "poses",
            "swept_axis",
            "swept_deg",
            "range_um",
            "max_deviation_um",
            "fit",
        ] {
            assert!(entry.get(key).is_some(), "{key} missing in {entry}");
        }
        let range: Vec<f64> = entry["range_um"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(range, ours.range_um);
    }
    assert_eq!(tests[0]["fit"]["kind"], "circle");
    assert_eq!(tests[2]["fit"]["kind"], "line");
    // One panel pair per test: three curves against the angle and the XY trajectory.
    let drawing = std::fs::read_to_string(&svg).unwrap();
    assert!(drawing.starts_with("<svg"));
    assert_eq!(drawing.matches("<polyline").count(), 4 * 4);
}

#[test]
fn analyze_rtest_refuses_a_bad_file_naming_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.csv");
    std::fs::write(
        &bad,
        "test,c_deg,dx_um,dy_um,dz_um\nt,0,0,0,0\nt,10,1,2,nan\n",
    )
    .unwrap();
    let svg = dir.path().join("never.svg");
    let output = mtwin(&[
        "analyze".as_ref(),
        "rtest".as_ref(),
        bad.as_os_str(),
        "--svg".as_ref(),
        svg.as_os_str(),
    ]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("bad.csv:3") && stderr.contains("dz_um"),
        "{stderr}"
    );
    assert!(!svg.exists(), "nothing written for a refused file");
}
