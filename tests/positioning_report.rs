//! The positioning report leads with its figures, keeps per-run detail short unless asked, and
//! every note is true of the data it describes.

use mtwin::kinds::positioning::PositioningTable;
use mtwin::kinds::positioning::iso230_2::evaluate;

mod common;
use common::mtwin;

fn simulate(name: &str, dir: &std::path::Path) -> String {
    let scenario = format!("{}/scenarios/{name}", env!("CARGO_MANIFEST_DIR"));
    mtwin(&["run", &scenario, "--out", dir.to_str().unwrap()]);
    dir.join("positioning.csv").to_string_lossy().into_owned()
}

/// Three runs at three targets with the directions given per target (`"+-"`, `"+"`, `"-"`).
fn table(directions: [&str; 3]) -> PositioningTable {
    let mut text = String::from("run,target_mm,direction,deviation_um\n");
    for run in 1..=3 {
        for (target, dirs) in [0.0, 100.0, 200.0].iter().zip(directions) {
            for d in dirs.chars() {
                text += &format!("{run},{target},{d},{}\n", 0.1 * run as f64);
            }
        }
    }
    PositioningTable::parse(text.as_bytes(), "hand.csv").unwrap()
}

#[test]
fn the_note_on_a_missing_direction_is_true_of_the_file() {
    // Every target both ways: ISO 230-2 figures, no note about directions.
    assert!(evaluate(&table(["+-", "+-", "+-"])).is_ok());
    // One target one way, the two others both: "2 other targets have both".
    let one = evaluate(&table(["+-", "+", "+-"])).unwrap_err().to_string();
    assert!(
        one.contains(
            "target 100 mm has readings in one direction only, while 2 other targets have both"
        ),
        "{one}"
    );
    let two = evaluate(&table(["+-", "+", "-"])).unwrap_err().to_string();
    assert!(two.contains("while 1 other target has both"), "{two}");
    // Each target one way, as in the ISO 230-3 linear-motion test: no target has both.
    let none = evaluate(&table(["-", "+", "-"])).unwrap_err().to_string();
    assert!(none.contains("and so has every other target"), "{none}");
    assert!(!none.contains("have both"), "{none}");
    // One direction in the whole file: that direction's figures, and the note says so.
    let up = evaluate(&table(["+", "+", "+"])).unwrap();
    assert!(up.both.is_none());
    assert!(
        up.to_text(&table(["+", "+", "+"]))
            .contains("+ direction only")
    );
}

#[test]
fn a_drift_record_leads_with_its_figures_and_keeps_the_runs_short() {
    let dir = tempfile::tempdir().unwrap();
    let table = simulate("vmc3_iso230_3_linear.toml", dir.path());
    let text = mtwin(&["analyze", "positioning", &table]);
    let lines: Vec<&str> = text.lines().collect();
    // The preamble names the test: straight to the drift report.
    assert!(
        lines[0].starts_with("ISO 230-3 §7 linear-motion drift record, axis X"),
        "{text}"
    );
    // Without the preamble (a real export need not have one) the ISO 230-2 evaluation finds
    // it is not a positioning test and says why.
    let bare = dir.path().join("bare.csv");
    let rows: String = std::fs::read_to_string(&table)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&bare, rows).unwrap();
    let bare_text = mtwin(&["analyze", "positioning", bare.to_str().unwrap()]);
    assert!(
        bare_text.starts_with("ISO 230-3 drift record, axis X: no ISO 230-2 figures (target 20 mm has readings in one direction only"),
        "{bare_text}"
    );
    // The figures are the same either way.
    let figures = |t: &str| t.lines().skip(1).collect::<Vec<_>>().join("\n");
    assert_eq!(figures(&bare_text), figures(&text));
    let first_target = lines
        .iter()
        .position(|l| l.contains("drift range"))
        .unwrap();
    let first_run = lines
        .iter()
        .position(|l| l.trim_start().starts_with("run "))
        .unwrap();
    assert!(first_target < first_run, "{text}");
    // 240 readings pairs (tests/scenarios.rs): 8 shown, all with --verbose.
    assert!(
        text.contains("240 runs, 8 of them shown (all with --verbose)"),
        "{text}"
    );
    assert!(lines.len() < 30, "{} lines", lines.len());
    let verbose = mtwin(&["analyze", "positioning", &table, "--verbose"]);
    let runs = verbose
        .lines()
        .filter(|l| l.trim_start().starts_with("run "))
        .count();
    assert_eq!(runs, 240);
}

#[test]
fn the_warm_up_slope_is_in_the_text_as_in_the_json() {
    let dir = tempfile::tempdir().unwrap();
    let table = simulate("vmc3_warmup_laser.toml", dir.path());
    let text = mtwin(&["analyze", "positioning", &table]);
    let json: serde_json::Value =
        serde_json::from_str(&mtwin(&["analyze", "positioning", &table, "--json"])).unwrap();
    let drift = json["drift"]
        .as_array()
        .expect("the thermal series in the JSON");
    let last_up = drift
        .iter()
        .find(|d| d["target_mm"].as_f64() == Some(755.0) && d["direction"] == "+")
        .unwrap();
    let slope = last_up["slope_um_per_degc"]["x_nut"].as_f64().unwrap();
    let line = text
        .lines()
        .find(|l| l.contains("target   755.0000 mm +"))
        .unwrap();
    assert!(
        line.contains(&format!("{slope:.3} µm/°C against x_nut")),
        "{line} against {slope}"
    );
}
