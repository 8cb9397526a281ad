//! Edges a newcomer hits: values in truth.json read back as written, write errors that name
//! the user's file, output folders checked before long work, a run that says what it found.

use crate::common::mtwin_output as mtwin;
use mtwin::app::{Scenario, run_scenario};
use std::path::Path;
use std::process::Command;

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
    // The vmc3 map is 9 × 5 × 5 points (tests/it/scenarios.rs).
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
    // The YZ partial arc (180°): straightness of Y goes, as tests/it/iso230_4.rs shows; the words
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

// ---------------------------------------------------------------------------------------
// Bounded work and finite outputs: the fuzzing reproducers (shared/repro) of issue 42. Each
// input is a few lines that used to run for hours, allocate gigabytes or write `inf` with
// exit 0; now each is refused at its line, at once, naming the limit.
// ---------------------------------------------------------------------------------------

/// Writes `text` (with `MODELS` replaced by the bundled models' folder) as `NAME` in `dir`.
fn scenario_file(dir: &Path, name: &str, text: &str) -> String {
    let models = format!("{}/models", env!("CARGO_MANIFEST_DIR"));
    let path = dir.join(name);
    std::fs::write(&path, text.replace("MODELS", &models)).unwrap();
    path.display().to_string()
}

/// `mtwin ARGS` must fail (exit 1, no panic); its message, which must start with `FILE:LINE: `.
fn refused_at(args: &[&str], file: &str, line: usize) -> String {
    let out = mtwin(args);
    let message = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{args:?}: {message}");
    assert!(
        message.starts_with(&format!("error: {file}:{line}: ")),
        "{args:?}: should name {file}:{line}: {message}"
    );
    message
}

/// `mtwin check FILE` must accept the scenario.
fn accepted(file: &str) {
    let out = mtwin(&["check", file]);
    assert!(
        out.status.success(),
        "{file}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

const RTEST_SWEEP: &str = "schema = 1
machine = \"MODELS/trunnion5.urdf\"
seed = 7
[rtest]
sphere_mm = [100.0, 0.0, 250.0]
[[rtest.test]]
name = \"CK1 A0\"
to_deg = { C = ANGLE }
";

#[test]
fn a_sweep_of_a_continuous_axis_beyond_ten_turns_is_refused_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    // 1e9° used to take ~37 h (the path's collision check is proportional to the degrees);
    // i64::MIN never ended. Ten turns (3600°) is the limit, either way.
    for angle in ["1e9", "-9223372036854775808.0", "3600.5", "-3601.0"] {
        let file = scenario_file(
            dir.path(),
            "sweep.toml",
            &RTEST_SWEEP.replace("ANGLE", angle),
        );
        let message = refused_at(&["check", &file], &file, 8);
        assert!(
            message.contains("rtest.test.to_deg") && message.contains("-3600 … 3600°"),
            "{message}"
        );
    }
    // Inside the limit the same sweep is a test (two turns here, to keep the check short).
    let file = scenario_file(
        dir.path(),
        "sweep.toml",
        &RTEST_SWEEP.replace("ANGLE", "720.0"),
    );
    accepted(&file);
}

#[test]
fn a_probing_pose_beyond_ten_turns_of_c_is_refused_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let text = "schema = 1
machine = \"MODELS/trunnion5.urdf\"
seed = 1
[probe]
stylus_diameter_mm = 6.0
[[probe.sphere]]
diameter_mm = 25.0
centre_mm = [60.0, 0.0, 150.0]
rotary = [{ a_deg = 0.0, c_deg = 0.0 }, { a_deg = 0.0, c_deg = ANGLE }]
";
    let file = scenario_file(dir.path(), "probe.toml", &text.replace("ANGLE", "1e9"));
    let message = refused_at(&["check", &file], &file, 9);
    assert!(
        message.contains("C 1000000000°") && message.contains("ten turns"),
        "{message}"
    );
    // The limit itself is a pose: ten turns of C probe the sphere as zero turns do.
    let file = scenario_file(dir.path(), "probe.toml", &text.replace("ANGLE", "3600.0"));
    accepted(&file);
}

#[test]
fn a_dataset_prior_on_an_element_that_cannot_exist_is_refused_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let base = "schema = 1
machine = \"MODELS/vmc3.urdf\"
seed = 1
[ballbar]
length_mm = 150.0
setup_offset_um = [0.0, 0.0, 0.0]
[dataset.priors]
\"PATH\" = { normal = [0.0, 1.0] }
";
    // Index 1e9 grew the coefficient list to 8 GiB before anything was checked.
    for (path, expected) in [
        (
            "errors.EXX.polynomial_um[1000000000]",
            "degree 1000000000 is above the limit of a polynomial, 10",
        ),
        (
            "errors.EXX.polynomial_um[11]",
            "degree 11 is above the limit of a polynomial, 10",
        ),
        (
            "ballbar.setup_offset_um[7]",
            "ballbar.setup_offset_um has 3 entries in the scenario; [7] does not exist",
        ),
    ] {
        let file = scenario_file(dir.path(), "prior.toml", &base.replace("PATH", path));
        let message = refused_at(&["check", &file], &file, 8);
        assert!(message.contains(expected), "{path}: {message}");
        assert!(!String::from_utf8_lossy(&mtwin(&["check", &file]).stdout).contains("ok"));
    }
    // Degree 10 is a polynomial a scenario accepts, and so is a prior on it whose draws stay a
    // machine error: 4.9 × 1e-30 µm/mm¹⁰ reaches 0.3 µm at 760 mm. With sd 1 µm/mm¹⁰ the same
    // prior reaches 3e29 µm, and `check` says so at its line (it tries the prior's reach).
    let file = scenario_file(
        dir.path(),
        "prior.toml",
        &base
            .replace("PATH", "errors.EXX.polynomial_um[10]")
            .replace("normal = [0.0, 1.0]", "normal = [0.0, 1.0e-30]"),
    );
    accepted(&file);
    let file = scenario_file(
        dir.path(),
        "prior.toml",
        &base.replace("PATH", "errors.EXX.polynomial_um[10]"),
    );
    let message = refused_at(&["check", &file], &file, 8);
    assert!(
        message
            .contains("can reach -4.9 (the lower end of its prior, 4.9 standard deviations out)"),
        "{message}"
    );
}

#[test]
fn a_header_of_a_hundred_thousand_columns_is_read_through() {
    // The header check was pairwise (13-17 s for 100 000 columns before the first message); a
    // repeated name is still found when it is the last column repeating the first.
    let dir = tempfile::tempdir().unwrap();
    simulate("trunnion5_rtest.toml", dir.path());
    let text = std::fs::read_to_string(dir.path().join("rtest.csv")).unwrap();
    let header_line = text.lines().position(|l| !l.starts_with('#')).unwrap();
    let wide = |extra: &str| -> String {
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        let columns: String = (0..100_000).map(|i| format!(",c{i}")).collect();
        lines[header_line] = format!("{}{columns}{extra}", lines[header_line]);
        lines.join("\n") + "\n"
    };
    let file = dir.path().join("wide.csv");
    let file_name = file.display().to_string();
    // 100 000 names the reader does not know are read past (listed as not read); the first
    // row, 100 000 cells short, is then refused at its line.
    std::fs::write(&file, wide("")).unwrap();
    let message = refused_at(
        &["analyze", "rtest", &file_name],
        &file_name,
        header_line + 2,
    );
    assert!(message.contains("found record with"), "{message}");
    let first = text
        .lines()
        .nth(header_line)
        .unwrap()
        .split(',')
        .next()
        .unwrap();
    std::fs::write(&file, wide(&format!(",{first}"))).unwrap();
    let message = refused_at(
        &["analyze", "rtest", &file_name],
        &file_name,
        header_line + 1,
    );
    assert!(
        message.contains(&format!("column `{first}` appears twice")),
        "{message}"
    );
}

#[test]
fn a_ball_bar_calibration_beyond_the_transducer_range_is_refused_not_run_to_inf() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scenario("vmc3_ballbar_xy.toml"))
        .unwrap()
        .replace("\"../models/", "\"MODELS/");
    let line = text
        .lines()
        .position(|l| l.starts_with("calibration_um"))
        .expect("the scenario sets calibration_um")
        + 1;
    let set = |value: &str| {
        let lines: Vec<String> = (text.lines())
            .map(|l| {
                if l.starts_with("calibration_um") {
                    format!("calibration_um = {value}")
                } else {
                    l.to_string()
                }
            })
            .collect();
        scenario_file(dir.path(), "cal.toml", &(lines.join("\n") + "\n"))
    };
    // f64::MAX used to pass `check`, and `run` wrote every deviation as `inf` with exit 0.
    for value in ["1.7976931348623157e308", "1000.5", "-2000.0"] {
        let file = set(value);
        let out_dir = dir.path().join("run");
        let message = refused_at(
            &["run", &file, "--out", out_dir.to_str().unwrap()],
            &file,
            line,
        );
        assert!(
            message.contains("ballbar.calibration_um") && message.contains("±1000"),
            "{message}"
        );
        // Huge values are quoted in scientific notation, not as 309 digits.
        assert!(!message.contains("17976931348623157000"), "{message}");
        assert!(!out_dir.exists(), "nothing is written");
    }
    accepted(&set("-999.0"));
    // 100 nm written in the µm key: a 0.1 mm step would quantise every ISO 230-4 figure away,
    // and `check` refuses it where it stands (the ball-bar resolves 0.1 µm).
    let at = text
        .lines()
        .position(|l| l.starts_with("resolution_um"))
        .expect("the scenario sets resolution_um")
        + 1;
    let coarse: Vec<String> = (text.lines())
        .map(|l| match l.starts_with("resolution_um") {
            true => "resolution_um = 100".to_string(),
            false => l.to_string(),
        })
        .collect();
    let file = scenario_file(dir.path(), "coarse.toml", &(coarse.join("\n") + "\n"));
    let message = refused_at(&["check", &file], &file, at);
    assert!(
        message.contains("ballbar.resolution_um") && message.contains("up to 1 ("),
        "{message}"
    );
}

#[test]
fn an_estimate_given_as_the_truth_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    simulate("trunnion5_rtest.toml", &dir.path().join("run"));
    let id = dir.path().join("id");
    let machine = format!("{}/models/trunnion5.urdf", env!("CARGO_MANIFEST_DIR"));
    let rtest = dir.path().join("run/rtest.csv");
    let out = mtwin(&[
        "identify",
        "--machine",
        &machine,
        "--params",
        "location",
        rtest.to_str().unwrap(),
        "--out",
        id.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let estimate = id.join("estimate.json");
    let estimate = estimate.to_str().unwrap();
    // Scored against itself it was "8 of 8 covered, compensated RMS 0.000 µm", exit 0.
    let out = mtwin(&["score", estimate, estimate]);
    let message = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{message}");
    assert!(
        message.contains("truth") && message.contains("\"estimate\""),
        "{message}"
    );
    assert!(out.stdout.is_empty());
    // The truth the run wrote says what it is, and scores.
    let truth = dir.path().join("run/truth.json");
    let written: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&truth).unwrap()).unwrap();
    assert_eq!(written["mtwin"], "truth");
    let out = mtwin(&["score", estimate, truth.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn count_flags_refuse_zero_and_negative_values_by_their_range() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("ds");
    for (args, expected) in [
        (vec!["--threads", "0"], "0 is not in 1..=1024"),
        (vec!["--threads", "-2"], "-2 is not in 1..=1024"),
    ] {
        let mut all = vec![
            "dataset",
            "scenarios/vmc3_dataset_volumetric.toml",
            "--count",
            "4",
            "--out",
            out_dir.to_str().unwrap(),
        ];
        all.extend(args);
        let out = Command::new(env!("CARGO_BIN_EXE_mtwin"))
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .args(&all)
            .output()
            .unwrap();
        let message = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{message}");
        assert!(message.contains(expected), "{message}");
        assert!(!out_dir.exists(), "nothing is written");
    }
    let machine = format!("{}/models/trunnion5.urdf", env!("CARGO_MANIFEST_DIR"));
    for (budget, expected) in [
        ("0", "0 is not in 3..=30000"),
        ("-10", "-10 is not in 3..=30000"),
    ] {
        let out = mtwin(&[
            "plan",
            "--machine",
            &machine,
            "--params",
            "location",
            "--sphere-mm",
            "100,0,250",
            "--budget",
            budget,
        ]);
        let message = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{message}");
        assert!(message.contains(expected), "{message}");
    }
    // A plan in minutes: a budget that is no number of minutes, a kind that is none, and
    // R-tests without the sphere they are made about, each refused with what is wrong.
    for (extra, expected) in [
        (
            &["--budget-min", "0", "--sphere-mm", "100,0,250"][..],
            "--budget-min 0",
        ),
        (
            &[
                "--budget-min",
                "60",
                "--sphere-mm",
                "100,0,250",
                "--kinds",
                "laser",
            ][..],
            "test kind \"laser\"",
        ),
        (&["--budget-min", "60"][..], "--sphere-mm X,Y,Z"),
        (
            &[
                "--budget-min",
                "60",
                "--budget",
                "30",
                "--sphere-mm",
                "100,0,250",
            ][..],
            "cannot be used with",
        ),
    ] {
        let mut args = vec!["plan", "--machine", &machine, "--params", "location"];
        args.extend_from_slice(extra);
        let out = mtwin(&args);
        let message = String::from_utf8_lossy(&out.stderr);
        assert_ne!(out.status.code(), Some(0), "{extra:?}: {message}");
        assert!(message.contains(expected), "{extra:?}: {message}");
        assert!(out.stdout.is_empty(), "{extra:?}");
    }
    // Laser lines and ball-bar circles need no sphere.
    let out = mtwin(&[
        "plan",
        "--machine",
        &format!("{}/models/vmc3.urdf", env!("CARGO_MANIFEST_DIR")),
        "--params",
        "squareness",
        "--budget-min",
        "60",
        "--kinds",
        "ballbar,positioning",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(
        report.contains("every parameter identifiable after step 3"),
        "{report}"
    );
}

// ---------------------------------------------------------------------------------------------
// Readings no instrument can give (issue 34: plausibility where numbers enter). Each table is
// written by hand; the refusal names the file, line, column and the instrument's range.

/// `mtwin analyze KIND FILE` on `text`, which must be refused with `expected` in its message
/// and nothing on stdout.
fn refused_reading(kind: &str, text: &str, expected: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.csv");
    std::fs::write(&path, text).unwrap();
    let out = mtwin(&["analyze", kind, path.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && out.stdout.is_empty(),
        "{kind}: {err}"
    );
    assert!(
        err.contains("t.csv:") && err.contains(expected),
        "{kind}: {err}"
    );
}

#[test]
fn readings_beyond_each_instruments_range_are_refused_at_their_line() {
    // A ball-bar reads ±1 mm: 1 000.5 µm cannot be one of its readings; −1e300 neither.
    let ballbar = |d: &str| {
        format!(
            "# plane = XY\n# radius_mm = 150\n# feed_mm_per_min = 1000\n\
             direction,angle_deg,deviation_um\nccw,0,1\nccw,90,{d}\nccw,180,1\nccw,270,1\n"
        )
    };
    for d in ["1000.5", "-1e300"] {
        refused_reading("ballbar", &ballbar(d), "t.csv:6: column `deviation_um`: ");
    }
    refused_reading(
        "ballbar",
        &ballbar("1000.5"),
        "is beyond ±1000 (a ball-bar's transducer reads ±1 mm",
    );
    // Drift sensors: 2 cm of drift is a unit slip; so is a 1e3 °C air.
    let drift = "time_min,z_um,temp_air_degc\n0,0,20\n30,20000,20.5\n60,3,21\n";
    refused_reading(
        "drift",
        drift,
        "t.csv:3: column `z_um`: 20000 is beyond ±10000",
    );
    let hot = "time_min,z_um,temp_air_degc\n0,0,20\n30,1,1000\n60,3,21\n";
    refused_reading(
        "drift",
        hot,
        "t.csv:3: column `temp_air_degc`: 1000 is beyond ±200",
    );
    // R-test: a deviation in nm written in the µm column.
    let rtest =
        "test,c_deg,dx_um,dy_um,dz_um\nt,0,0,0,0\nt,90,12000,2,0\nt,180,2,0,0\nt,270,1,-2,0\n";
    refused_reading(
        "rtest",
        rtest,
        "t.csv:3: column `dx_um`: 12000 is beyond ±10000",
    );
}

/// An 8-sample spindle record, two revolutions at 600 rpm, with its angles from `angle` (the
/// degrees of sample i) and its times scaled by `time_scale`.
fn spindle_record(angle: impl Fn(usize) -> f64, time_scale: f64) -> String {
    let mut text = String::from("revolution,angle_deg,time_s,speed_rpm,x_um\n");
    for k in 0..16 {
        let t = k as f64 * 0.1 / 8.0 * time_scale; // 600 rpm: 0.1 s per revolution
        text += &format!("{},{},{t},600,{}\n", k / 8, angle(k % 8), 0.1 * k as f64);
    }
    text
}

#[test]
fn spindle_angles_that_cannot_be_degrees_are_refused() {
    // As recorded: 45° steps, 0.1 s per revolution, 600 rpm. Read.
    let good = spindle_record(|i| 45.0 * i as f64, 1.0);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.csv");
    std::fs::write(&path, &good).unwrap();
    let out = mtwin(&["analyze", "spindle", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The same angles in radians (issue 34's record: 3.56 µm reported for 0.59 µm): they never
    // pass 2π over revolutions of 8 samples.
    let radians = spindle_record(|i| (45.0 * i as f64).to_radians(), 1.0);
    refused_reading(
        "spindle",
        &radians,
        "column `angle_deg`: the angles never pass 5.497787 over revolutions of 8 samples; they look like radians",
    );
    // Times in another unit (ms written as s): the angles advance at 0.6 rpm, not 600.
    let slow = spindle_record(|i| 45.0 * i as f64, 1000.0);
    refused_reading(
        "spindle",
        &slow,
        "t.csv:2: column `speed_rpm`: 600 rpm, but the angles advance at 0.6 rpm against time_s",
    );
    // 4 % slower than commanded, as a loaded spindle can run: read.
    std::fs::write(&path, spindle_record(|i| 45.0 * i as f64, 1.04)).unwrap();
    let out = mtwin(&["analyze", "spindle", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

mod bounded_work;
