//! The three faces of a discovery — the text for people, the JSON and the written model — give
//! the same final values: the text's "Final model" block is parsed and checked against the
//! JSON's `final` to the printed precision (3 decimals), and the written model's values against
//! the JSON's. Steps keep their values at acceptance, labelled as such.

use serde_json::Value;
use std::path::Path;

use crate::common::mtwin;

/// Simulates a bundled scenario into `dir` and returns the path of `table` in it.
fn simulate(scenario: &str, dir: &Path, table: &str) -> String {
    let scenario = format!("{}/scenarios/{scenario}", env!("CARGO_MANIFEST_DIR"));
    mtwin(&["run", &scenario, "--out", dir.to_str().unwrap()]);
    dir.join(table).to_string_lossy().into_owned()
}

/// The `effect  key = value, key = value` lines under the text's "Final model" heading.
fn final_block(text: &str) -> Vec<(String, Vec<(String, f64)>)> {
    let block = text
        .split("\nFinal model: ")
        .nth(1)
        .expect("a Final model section");
    block
        .lines()
        .filter(|l| l.starts_with("    "))
        .map(|line| {
            let line = line.trim();
            let (effect, values) = line.split_once(char::is_whitespace).unwrap();
            let values = values
                .trim()
                .split(", ")
                .map(|kv| {
                    let (k, v) = kv.split_once(" = ").unwrap();
                    (k.to_string(), v.parse::<f64>().unwrap())
                })
                .collect();
            (effect.to_string(), values)
        })
        .collect()
}

/// Every value of the text's final block equals the JSON's `final` value to 3 decimals, and
/// every JSON final parameter is in the text.
fn assert_text_agrees_with_json(text: &str, json: &Value) {
    let block = final_block(text);
    let params = json["final"]["params"].as_object().unwrap();
    let in_text: usize = block.iter().map(|(_, v)| v.len()).sum();
    let in_json: usize = params.values().map(|p| p.as_object().unwrap().len()).sum();
    assert_eq!(in_text, in_json, "{block:?} against {params:?}");
    for (effect, values) in &block {
        for (key, value) in values {
            let expected = params[effect.as_str()][key.as_str()].as_f64().unwrap();
            assert!(
                (value - expected).abs() <= 0.0005 + 1e-9,
                "{effect}.{key}: text {value}, JSON {expected}"
            );
        }
    }
}

#[test]
fn positioning_text_json_and_written_model_agree() {
    let dir = tempfile::tempdir().unwrap();
    let table = simulate("vmc3_warmup_laser.toml", dir.path(), "positioning.csv");
    let model = dir.path().join("model.toml").to_string_lossy().into_owned();
    let text = mtwin(&["discover", "positioning", &table, "--write-model", &model]);
    let json: Value =
        serde_json::from_str(&mtwin(&["discover", "positioning", &table, "--json"])).unwrap();
    assert_text_agrees_with_json(&text, &json);
    // Lost motion moves when the thermal effects enter after it: the step's value is kept,
    // labelled, and differs from the final one (4.13 against 3.96 µm here).
    let step = json["steps"][0]["params"]["lost_motion_um"]
        .as_f64()
        .unwrap();
    let last = json["final"]["params"]["reversal"]["lost_motion_um"]
        .as_f64()
        .unwrap();
    assert!((step - last).abs() > 0.05, "{step} vs {last}");
    assert!(
        text.contains(&format!("lost_motion_um = {step:.3} at acceptance")),
        "{text}"
    );
    // The written model: reversal_um is the final lost motion; the effects it cannot express
    // are listed with their final values.
    let fragment = std::fs::read_to_string(&model).unwrap();
    let written: f64 = fragment
        .lines()
        .find_map(|l| l.strip_prefix("reversal_um = "))
        .unwrap()
        .parse()
        .unwrap();
    assert!((written - last).abs() < 1e-9, "{written} vs {last}");
    let tau = json["final"]["params"]["thermal_lag"]["tau_min"]
        .as_f64()
        .unwrap();
    // thermal_lag is a real scenario term now: the lag of the sensor's temperature term.
    let lag: f64 = fragment
        .split("lag_min = ")
        .nth(1)
        .and_then(|rest| rest.split([' ', ',', '}']).next())
        .unwrap_or_else(|| panic!("no lag_min in {fragment}"))
        .parse()
        .unwrap();
    assert!((lag - tau).abs() <= 0.0005 + 1e-9, "{lag} vs {tau}");
}

#[test]
fn ballbar_text_and_json_agree() {
    let dir = tempfile::tempdir().unwrap();
    let table = simulate(
        "teach_squareness_ballbar.toml",
        dir.path(),
        "ballbar_xy.csv",
    );
    let conditions = [
        "--plane",
        "XY",
        "--radius-mm",
        "100",
        "--feed-mm-per-min",
        "2000",
    ];
    let mut args = vec!["discover", "ballbar", table.as_str()];
    args.extend(conditions);
    let text = mtwin(&args);
    args.push("--json");
    let json: Value = serde_json::from_str(&mtwin(&args)).unwrap();
    assert_text_agrees_with_json(&text, &json);
    // The lesson injects EC0Y = −40 µrad (squareness +40 µm/m in the ball-bar's sign) and a
    // 2 µm backlash of X: the final values say so.
    let params = &json["final"]["params"];
    assert!((params["base"]["squareness_um_per_m"].as_f64().unwrap() - 40.0).abs() < 0.5);
    assert!((params["backlash_x"]["backlash_um"].as_f64().unwrap() - 2.0).abs() < 0.1);
}

/// Positioning discovery writes the same text, JSON and model, byte for byte, on one thread
/// and on two (rayon's pool size from `RAYON_NUM_THREADS`): its folds and candidates are
/// scored in parallel and gathered in a fixed order. `vmc3_warmup_laser` accepts three effects
/// with a searched time constant among them, so the searches and the block pairs all run.
#[test]
fn positioning_discovery_does_not_depend_on_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let table = simulate("vmc3_warmup_laser.toml", dir.path(), "positioning.csv");
    let run = |threads: &str, extra: &[&str]| {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_mtwin"))
            .args(["discover", "positioning", &table])
            .args(extra)
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(output.status.success());
        output.stdout
    };
    for extra in [&[][..], &["--json"][..]] {
        let one = run("1", extra);
        assert_eq!(one, run("2", extra), "{extra:?}");
        assert!(String::from_utf8_lossy(&one).contains("thermal_lag"));
    }
}
