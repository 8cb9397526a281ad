//! Edges a newcomer hits: values in truth.json read back as written, write errors that name
//! the user's file, output folders checked before long work, a run that says what it found.

use mtwin::app::{Scenario, run_scenario};
use std::path::Path;
use std::process::{Command, Output};

fn mtwin(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .args(args)
        .output()
        .unwrap()
}

fn scenario(name: &str) -> String {
    format!("{}/scenarios/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// `mtwin run scenarios/NAME --out DIR`, which must succeed.
fn simulate(name: &str, dir: &Path) {
    let run = mtwin(&["run", &scenario(name), "--out", dir.to_str().unwrap()]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
}

#[test]
fn truth_values_read_back_as_written() {
    let output =
        run_scenario(&Scenario::load(scenario("teach_squareness_ballbar.toml")).unwrap()).unwrap();
    let truth = &output
        .files
        .iter()
        .find(|(n, _)| n == "truth.json")
        .unwrap()
        .1;
    let text = String::from_utf8(truth.clone()).unwrap();
    // As written in the scenario: noise_um = 0.1, the centre's y_mm = 205, EC0Y = −40 µrad.
    assert!(text.contains("\"noise_um\": 0.1,"), "{text}");
    assert!(text.contains("\"y_mm\": 205.0,"), "{text}");
    assert!(text.contains("\"value_si\": -0.00004"), "{text}");
    // No bundled scenario's truth shows conversion noise (a run of eight 9s or 0s before a
    // last digit).
    for entry in std::fs::read_dir(scenario("")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let output = run_scenario(&Scenario::load(&path).unwrap()).unwrap();
        let truth = &output
            .files
            .iter()
            .find(|(n, _)| n == "truth.json")
            .unwrap()
            .1;
        let text = String::from_utf8_lossy(truth);
        let noisy: Vec<&str> = text
            .split(|c: char| !(c.is_ascii_digit() || c == '.'))
            .filter(|number| {
                let Some((_, fraction)) = number.split_once('.') else {
                    return false;
                };
                fraction.contains("99999999")
                    || fraction
                        .find("00000000")
                        .is_some_and(|at| !fraction[at..].trim_end_matches('0').is_empty())
            })
            .collect();
        assert!(noisy.is_empty(), "{}: {noisy:?}", path.display());
    }
}

#[test]
fn a_write_error_names_the_users_file_not_the_temporary_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    // A folder where the temporary file would go: writing it fails.
    std::fs::create_dir_all(out.join(".truth.json.partial")).unwrap();
    let result = mtwin(&[
        "run",
        &scenario("vmc3_volumetric.toml"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!result.status.success());
    let message = String::from_utf8_lossy(&result.stderr);
    assert!(
        message.contains(&format!(
            "{}: cannot write",
            out.join("truth.json").display()
        )),
        "{message}"
    );
    assert!(!message.contains(".partial"), "{message}");
    assert!(!out.join("volumetric.csv").exists(), "nothing half-written");
}

#[test]
fn a_missing_output_folder_is_refused_before_the_search() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let run = mtwin(&[
        "run",
        &scenario("teach_warmup.toml"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success());
    let model = dir.path().join("missing").join("model.toml");
    let result = mtwin(&[
        "discover",
        "positioning",
        out.join("positioning.csv").to_str().unwrap(),
        "--write-model",
        model.to_str().unwrap(),
    ]);
    assert!(!result.status.success());
    let message = String::from_utf8_lossy(&result.stderr);
    assert!(
        message.contains(&format!(
            "{}: cannot write: the folder {} does not exist",
            model.display(),
            model.parent().unwrap().display()
        )),
        "{message}"
    );
    // Refused before discovery began: it reports progress as it searches, and said nothing.
    assert!(!message.contains("discover:"), "{message}");
}

#[test]
fn run_ends_with_what_it_found() {
    let dir = tempfile::tempdir().unwrap();
    let out = Path::new(dir.path()).join("vmc3");
    let result = mtwin(&[
        "run",
        &scenario("vmc3_volumetric.toml"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(result.status.success());
    let stdout = String::from_utf8_lossy(&result.stdout);
    let last = stdout.lines().last().unwrap();
    // The vmc3 map is 9 × 5 × 5 points (tests/scenarios.rs).
    assert!(
        last.starts_with("volumetric map: 225 points, largest deviation "),
        "{last}"
    );
    assert!(last.ends_with("(seed 1)"), "{last}");
}

#[test]
fn check_lists_every_test_the_scenario_asks_for() {
    let result = mtwin(&["check", &scenario("vmc3_warmup_laser.toml")]);
    assert!(result.status.success());
    let stdout = String::from_utf8_lossy(&result.stdout);
    // By hand from the scenario: [warmup] on X, targets 5..755 step 50 (16), 7 runs; one
    // sensor on the X nut.
    assert!(
        stdout.contains("\n  laser: X, 16 targets × 7 runs, "),
        "{stdout}"
    );
    assert!(stdout.contains(" nodes, 1 sensor (x_nut)\n"), "{stdout}");
}

#[test]
fn an_error_name_one_keystroke_off_gets_a_suggestion() {
    use mtwin::errors::ParameterName;
    let message = |text: &str| text.parse::<ParameterName>().unwrap_err();
    assert!(
        message("ECOY").ends_with("; did you mean EC0Y?"),
        "{}",
        message("ECOY")
    );
    assert!(message("exx").ends_with("; did you mean EXX?"));
    // Nothing is suggested when no valid name is that near, or several are.
    assert!(
        !message("EXQ").contains("did you mean"),
        "{}",
        message("EXQ")
    );
    assert!(!message("QQQQQ").contains("did you mean"));
}

#[test]
fn text_reports_write_micrometres_as_people_do() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("drift.csv");
    std::fs::write(
        &path,
        "time_min,x_um,a_urad,temp_air_degc\n0,0,0,20\n30,1,2,20.5\n60,2,3,21\n90,3,5,21.2\n",
    )
    .unwrap();
    let result = mtwin(&["analyze", "drift", path.to_str().unwrap()]);
    assert!(result.status.success());
    let text = String::from_utf8_lossy(&result.stdout);
    // x over the first 60 min: 0 → 2 µm; a: 0 → 3 µrad (by hand from the rows).
    assert!(text.contains("2.000 µm"), "{text}");
    assert!(text.contains("3.000 µrad"), "{text}");
    assert!(!text.contains(" um") && !text.contains(" urad"), "{text}");
}

#[test]
fn an_unidentifiable_term_names_the_inflation_that_broke_the_limit() {
    // The YZ partial arc (180°): straightness of Y goes, as tests/iso230_4.rs shows; the words
    // must give an inflation over the limit, whatever the dropped term's own.
    let dir = tempfile::tempdir().unwrap();
    simulate("vmc3_ballbar_3planes.toml", dir.path());
    let table = dir.path().join("ballbar_yz.csv");
    let result = mtwin(&["analyze", "ballbar", table.to_str().unwrap(), "--json"]);
    assert!(result.status.success());
    let json: serde_json::Value = serde_json::from_slice(&result.stdout).unwrap();
    let mut collinear = 0;
    for entry in json["unidentifiable"].as_array().unwrap() {
        let reason = entry["reason"].as_str().unwrap();
        let Some((_, rest)) = reason.split_once("inflates a variance ") else {
            continue;
        };
        collinear += 1;
        let largest: f64 = rest.split(' ').next().unwrap().parse().unwrap();
        assert!(largest > 1000.0, "{reason}");
        assert!(reason.contains("over the limit of 1000"), "{reason}");
    }
    assert!(collinear > 0, "{}", json["unidentifiable"]);
    assert!(
        json["unidentifiable"]
            .as_array()
            .unwrap()
            .iter()
            .any(|e| e["term"] == "straightness_y_um")
    );
}

#[test]
fn the_ball_bar_report_says_which_centre_offset_is_which() {
    let dir = tempfile::tempdir().unwrap();
    simulate("teach_squareness_ballbar.toml", dir.path());
    let table = dir.path().join("ballbar_xy.csv");
    let result = mtwin(&["analyze", "ballbar", table.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&result.stdout);
    let circle = text
        .lines()
        .find(|l| l.trim_start().starts_with("centre offset: "))
        .expect("a line on the ISO circle's centre offset");
    let joint = text
        .lines()
        .find(|l| l.trim_start().starts_with("centre_offset_* below: "))
        .expect("a line on the joint fit's centre offsets");
    assert!(circle.contains("least-squares circle"), "{circle}");
    assert!(joint.contains("joint fit"), "{joint}");
}

#[test]
fn a_reused_output_folder_with_another_runs_files_gets_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run = |name: &str| {
        let result = mtwin(&["run", &scenario(name), "--out", out.to_str().unwrap()]);
        assert!(result.status.success());
        String::from_utf8_lossy(&result.stderr).into_owned()
    };
    assert!(!run("teach_squareness_ballbar.toml").contains("warning"));
    // The map's run writes volumetric.csv, truth.json and manifest.json: the ball-bar table
    // stays behind, from the other run.
    let warned = run("vmc3_volumetric.toml");
    assert!(
        warned.contains("holds files this run does not write (ballbar_xy.csv)"),
        "{warned}"
    );
    assert!(out.join("ballbar_xy.csv").exists(), "left as it is");
    // Its own files again: nothing to say but the leftover.
    std::fs::remove_file(out.join("ballbar_xy.csv")).unwrap();
    assert!(!run("vmc3_volumetric.toml").contains("warning"));
}
