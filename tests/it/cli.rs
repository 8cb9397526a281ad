//! The `mtwin` binary end to end: `check` accepts every shipped model and scenario and
//! rejects a broken file naming it on stderr; `run` with a bad scenario fails without leaving
//! any file behind; `run` on `scenarios/vmc3_volumetric.toml` writes exactly
//! `volumetric.csv` (the documented header, the 9×5×5 grid in order), `truth.json` (the
//! parameters the scenario injects) and `manifest.json` (the inputs' and outputs' SHA-256,
//! recomputed here); every subcommand answers `--help`.

use crate::common::{mtwin_output as mtwin, root};
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::process::Output;
use tempfile::TempDir;

fn check(file: &Path) -> Output {
    mtwin(&["check".as_ref(), file.as_os_str()])
}

fn run(scenario: &Path, out: &Path) -> Output {
    mtwin(&[
        "run".as_ref(),
        scenario.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ])
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The files in `dir` with extension `ext`, sorted.
fn files_with_extension(dir: &str, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == ext))
        .collect();
    files.sort();
    files
}

fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Every entry of `dir` (hidden ones included), sorted; empty if it does not exist.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = match std::fs::read_dir(dir) {
        Ok(read) => read
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect(),
        Err(_) => Vec::new(),
    };
    names.sort();
    names
}

/// Runs the vmc3 scenario into a fresh directory; returns it (kept alive) and the out path.
fn run_vmc3() -> (TempDir, PathBuf) {
    let dir = TempDir::new().unwrap();
    let out = dir.path().join("out");
    let output = run(&root().join("scenarios/vmc3_volumetric.toml"), &out);
    assert!(output.status.success(), "{}", text(&output.stderr));
    (dir, out)
}

fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn check_accepts_every_model() {
    let models = files_with_extension("models", "urdf");
    assert_eq!(models.len(), 3, "vmc3, trunnion5, headtable5");
    for model in models {
        let output = check(&model);
        assert!(
            output.status.success(),
            "{}: {}",
            model.display(),
            text(&output.stderr)
        );
    }
}

#[test]
fn check_accepts_every_scenario() {
    let scenarios = files_with_extension("scenarios", "toml");
    assert_eq!(
        scenarios.len(),
        30,
        "one volumetric scenario per model, the ISO 230-2 laser test, the warm-up experiment and its lagging-sensor variant, the ISO 230-3 linear-motion and ETVE tests, three ball-bar tests, two R-tests, four probe scenarios, six lessons, four spindle analyser records, the ISO 230-3 spindle thermal test and two datasets"
    );
    for scenario in scenarios {
        let output = check(&scenario);
        assert!(
            output.status.success(),
            "{}: {}",
            scenario.display(),
            text(&output.stderr)
        );
    }
}

#[test]
fn check_rejects_broken_model_naming_it() {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join("bent_machine.urdf");
    let urdf = std::fs::read_to_string(root().join("models/vmc3.urdf")).unwrap();
    std::fs::write(
        &path,
        urdf.replace(r#"<axis xyz="-1 0 0"/>"#, r#"<axis xyz="1 0 0"/>"#),
    )
    .unwrap();
    let output = check(&path);
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains(&path.display().to_string()),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn check_rejects_broken_scenario_naming_it() {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join("future_schema.toml");
    std::fs::write(&path, "schema = 2\n").unwrap();
    let output = check(&path);
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains(&format!("{}:1:", path.display())),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn run_with_bad_scenario_fails_and_writes_nothing() {
    // Valid up to the last check: the X grid runs past the 760 mm travel.
    let dir = TempDir::new().unwrap();
    let scenario = dir.path().join("too_far.toml");
    let good = std::fs::read_to_string(root().join("scenarios/vmc3_volumetric.toml")).unwrap();
    let bad = good
        .replace("../models/vmc3.urdf", "vmc3.urdf")
        .replace("to = 760.0, count = 9", "to = 800.0, count = 9");
    assert_ne!(bad, good);
    std::fs::copy(
        root().join("models/vmc3.urdf"),
        dir.path().join("vmc3.urdf"),
    )
    .unwrap();
    std::fs::write(&scenario, bad).unwrap();
    let out = dir.path().join("out");
    let output = run(&scenario, &out);
    assert!(!output.status.success());
    assert!(text(&output.stderr).contains(&scenario.display().to_string()));
    assert_eq!(entries(&out), Vec::<String>::new());
}

#[test]
fn run_vmc3_writes_exactly_the_three_outputs() {
    let (_dir, out) = run_vmc3();
    assert_eq!(
        entries(&out),
        ["manifest.json", "truth.json", "volumetric.csv"]
    );
}

#[test]
fn run_vmc3_volumetric_csv_is_the_9x5x5_grid() {
    let (_dir, out) = run_vmc3();
    let csv = std::fs::read_to_string(out.join("volumetric.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("x_mm,y_mm,z_mm,dx_um,dy_um,dz_um"));
    let rows: Vec<Vec<f64>> = lines
        .map(|line| line.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 9 * 5 * 5);
    // X 0..760 in 9 (step 95), Y 0..410 in 5 (102.5), Z 0..520 in 5 (130); Z varies fastest.
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 6, "row {i}");
        let expected = [
            95.0 * (i / 25) as f64,
            102.5 * (i / 5 % 5) as f64,
            130.0 * (i % 5) as f64,
        ];
        let close = row.iter().zip(expected).all(|(v, e)| (v - e).abs() < 1e-6);
        assert!(close, "row {i}: {row:?}, expected {expected:?}");
    }
    // The scenario injects errors, so the map is not all zero.
    assert!(rows.iter().any(|r| r[3..].iter().any(|d| d.abs() > 1e-3)));
}

#[test]
fn run_vmc3_truth_lists_the_injected_parameters() {
    let (_dir, out) = run_vmc3();
    let truth = read_json(&out.join("truth.json"));
    assert_eq!(truth["machine"], "vmc3");
    assert_eq!(truth["seed"], 1);
    assert!(truth["convention"].is_string());
    assert!(
        truth["coefficients_si"]
            .as_array()
            .is_some_and(|c| !c.is_empty())
    );
    // The [errors.*] tables of scenarios/vmc3_volumetric.toml.
    let mut expected = [
        "EXX", "EYX", "EZX", "EBX", "ECX", "EYY", "EXY", "EAY", "ECY", "EZZ", "EAZ", "EBZ", "EC0Y",
        "EB0Z", "EA0Z", "EZT",
    ];
    expected.sort();
    let errors = truth["errors"].as_object().unwrap();
    let names: Vec<&str> = errors.keys().map(String::as_str).collect();
    assert_eq!(names, expected);
    assert_eq!(errors["EC0Y"]["kind"], "squareness");
    assert_eq!(errors["EC0Y"]["unit"], "urad");
    assert_eq!(errors["EZT"]["kind"], "tool");
    assert_eq!(errors["EXX"]["axis_side"], "workpiece");
    assert_eq!(errors["EZZ"]["axis_side"], "tool");
}

#[test]
fn run_vmc3_manifest_hashes_inputs_and_outputs() {
    let (_dir, out) = run_vmc3();
    let manifest = read_json(&out.join("manifest.json"));
    let scenario = std::fs::read(root().join("scenarios/vmc3_volumetric.toml")).unwrap();
    let machine = std::fs::read(root().join("models/vmc3.urdf")).unwrap();
    assert_eq!(manifest["mtwin_version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(manifest["scenario"]["file"], "vmc3_volumetric.toml");
    assert_eq!(manifest["scenario"]["sha256"], sha256_hex(&scenario));
    assert_eq!(manifest["machine"]["name"], "vmc3");
    assert_eq!(manifest["machine"]["file"], "vmc3.urdf");
    assert_eq!(manifest["machine"]["sha256"], sha256_hex(&machine));
    assert_eq!(manifest["seed"], 1);
    assert_eq!(manifest["volumetric_model"], "chain");
    let files = manifest["files"].as_array().unwrap();
    let names: Vec<&str> = files.iter().map(|f| f["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["volumetric.csv", "truth.json"]);
    for file in files {
        let bytes = std::fs::read(out.join(file["name"].as_str().unwrap())).unwrap();
        assert_eq!(file["bytes"], bytes.len());
        assert_eq!(file["sha256"], sha256_hex(&bytes));
    }
}

#[test]
fn help_for_each_subcommand() {
    for (subcommand, mentions) in [
        ("run", "--out"),
        ("check", "<FILE>"),
        ("discover", "reference error profile"),
    ] {
        let output = mtwin(&[subcommand, "--help"]);
        assert!(output.status.success(), "{subcommand} --help");
        let stdout = text(&output.stdout);
        assert!(stdout.contains("Usage"), "{stdout}");
        assert!(stdout.contains(mentions), "{stdout}");
    }
}

/// Simulates the warm-up laser scenario (lost motion 4 µm hidden in EXX; the screw warms later
/// and less than the nut sensor) and discovers it from the table alone.
fn discover_warmup(dir: &Path, extra: &[&std::ffi::OsStr]) -> (Output, PathBuf) {
    let out = dir.join("warmup");
    let scenario = root().join("scenarios/vmc3_warmup_laser.toml");
    assert!(run(&scenario, &out).status.success());
    let table = out.join("positioning.csv");
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "discover".as_ref(),
        "positioning".as_ref(),
        table.as_os_str(),
    ];
    args.extend_from_slice(extra);
    (mtwin(&args), table)
}

#[test]
fn discover_finds_the_lost_motion_hidden_in_a_simulated_warm_up() {
    let dir = TempDir::new().unwrap();
    let (output, _) = discover_warmup(dir.path(), &["--json".as_ref()]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let report: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(report["kind"], "positioning");
    assert_eq!(report["n_runs"], 7);
    assert_eq!(report["n_samples"], 7 * 2 * 16);
    let steps = report["steps"].as_array().unwrap();
    assert_eq!(steps[0]["effect"], "reversal", "{report:#}");
    // The scenario's EXX reversal_um = 4.0; the profile carries the rest of the error.
    let lost_motion = steps[0]["params"]["lost_motion_um"].as_f64().unwrap();
    assert!((lost_motion - 4.0).abs() < 0.3, "{lost_motion}");
    // The nut sensor over-reads the screw's warming: the thermal terms must enter too and
    // lower the held-out RMS below a third of the base model's.
    let effects: Vec<&str> = steps
        .iter()
        .map(|s| s["effect"].as_str().unwrap())
        .collect();
    assert!(effects.contains(&"thermal_scale"), "{effects:?}");
    let base = report["baseline"]["cv_rms_um"].as_f64().unwrap();
    let last = report["final"]["cv_rms_um"].as_f64().unwrap();
    assert!(last < base / 3.0, "{base} -> {last}");
}

#[test]
fn discover_writes_a_model_that_run_simulates_again() {
    let dir = TempDir::new().unwrap();
    let model = dir.path().join("model.toml");
    let base = root().join("scenarios/vmc3_warmup_laser.toml");
    let (output, _) = discover_warmup(
        dir.path(),
        &[
            "--write-model".as_ref(),
            model.as_os_str(),
            "--extends".as_ref(),
            base.as_os_str(),
        ],
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let fragment = std::fs::read_to_string(&model).unwrap();
    assert!(
        fragment.contains("[errors.EXX]") && fragment.contains("reversal_um = "),
        "{fragment}"
    );
    let again = dir.path().join("again");
    let output = run(&model, &again);
    assert!(output.status.success(), "{}", text(&output.stderr));
    // The extended twin's EXX is the discovered one (profile table + lost motion), replacing
    // the scenario's polynomial; the rest of the scenario (the warm-up test) is inherited.
    let truth = read_json(&again.join("truth.json"));
    let terms = &truth["errors"]["EXX"]["terms"];
    assert!(terms.get("polynomial_um").is_none(), "{terms}");
    assert_eq!(terms["table"]["positions_mm"].as_array().unwrap().len(), 16);
    let lost_motion = terms["reversal_um"].as_f64().unwrap();
    assert!((lost_motion - 4.0).abs() < 0.3, "{lost_motion}");
    assert!(again.join("positioning.csv").exists());
}

#[test]
fn discover_rejects_bad_input_naming_it_and_writes_nothing() {
    let dir = TempDir::new().unwrap();
    let table = dir.path().join("bad.csv");
    std::fs::write(&table, "target_mm,deviation_um\n0,1\n100,nan\n").unwrap();
    let model = dir.path().join("model.toml");
    let output = mtwin(&[
        "discover".as_ref(),
        "positioning".as_ref(),
        table.as_os_str(),
        "--write-model".as_ref(),
        model.as_os_str(),
    ]);
    assert!(!output.status.success());
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("bad.csv") && stderr.contains("deviation_um"),
        "{stderr}"
    );
    assert!(!model.exists());

    // A valid table without an axis column cannot name the error to write.
    let rows: String = (0..12)
        .map(|k| format!("{},{}\n", k * 50, 0.01 * k as f64))
        .collect();
    std::fs::write(&table, format!("target_mm,deviation_um\n{rows}")).unwrap();
    let output = mtwin(&[
        "discover".as_ref(),
        "positioning".as_ref(),
        table.as_os_str(),
        "--write-model".as_ref(),
        model.as_os_str(),
    ]);
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains("axis column"),
        "{}",
        text(&output.stderr)
    );
    assert!(!model.exists());

    // An unknown sensor is named with the columns the file has.
    let output = mtwin(&[
        "discover".as_ref(),
        "positioning".as_ref(),
        table.as_os_str(),
        "--sensor".as_ref(),
        "spindle".as_ref(),
    ]);
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains("temp_spindle_degc"),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn ballbar_scenario_runs_and_its_table_is_analysed_and_discovered() {
    // vmc3_ballbar_xy through the binary: the table, then `analyze ballbar --json` with the
    // injected squareness (−EC0Y = 20 µm/m), servo mismatch (1/33.3 − 1/32.8 s = −0.458 ms)
    // and lost motion of X and Y (4 and 2 µm) within the issue's 5 % or 0.2 µm; then
    // `discover ballbar --json` names effects beyond the base model.
    let dir = TempDir::new().unwrap();
    let out = dir.path().join("bb");
    let output = run(&root().join("scenarios/vmc3_ballbar_xy.toml"), &out);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let table = out.join("ballbar_xy.csv");
    let conditions = [
        "--plane",
        "XY",
        "--radius-mm",
        "150",
        "--feed-mm-per-min",
        "1000",
    ];
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "analyze".as_ref(),
        "ballbar".as_ref(),
        table.as_os_str(),
        "--json".as_ref(),
    ];
    args.extend(conditions.iter().map(std::ffi::OsStr::new));
    let output = mtwin(&args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let report: Value = serde_json::from_slice(&output.stdout).unwrap();
    for key in [
        "G_ccw_um", "G_cw_um", "G_um", "H_um", "F_max_um", "F_min_um",
    ] {
        assert!(report[key].as_f64().is_some(), "{key}");
    }
    let d = &report["diagnostics"];
    let near = |key: &str, truth: f64, tolerance: f64| {
        let got = d[key]["value"].as_f64().unwrap();
        assert!((got - truth).abs() <= tolerance, "{key}: {got} vs {truth}");
    };
    near("squareness_um_per_m", 20.0, 1.0);
    near("servo_mismatch_ms", 1e3 / 33.3 - 1e3 / 32.8, 0.024);
    near("backlash_x_um", 4.0, 0.2);
    near("backlash_y_um", 2.0, 0.2);

    args[0] = "discover".as_ref();
    let output = mtwin(&args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let report: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(report["kind"], "ballbar");
    let steps = report["steps"].as_array().unwrap();
    assert!(
        !steps.is_empty(),
        "the faulty machine needs more than the base model"
    );
    assert!(
        text(&output.stderr).contains("discover:"),
        "progress on stderr"
    );
}

#[test]
fn ballbar_analysis_needs_its_test_conditions() {
    let dir = TempDir::new().unwrap();
    let table = dir.path().join("bb.csv");
    std::fs::write(&table, "direction,angle_deg,deviation_um\nccw,0,1\n").unwrap();
    let output = mtwin(&["analyze".as_ref(), "ballbar".as_ref(), table.as_os_str()]);
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains("--plane"),
        "{}",
        text(&output.stderr)
    );
    // …and positioning tables refuse them.
    let output = mtwin(&[
        "analyze".as_ref(),
        "positioning".as_ref(),
        table.as_os_str(),
        "--plane".as_ref(),
        "XY".as_ref(),
    ]);
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains("ball-bar"),
        "{}",
        text(&output.stderr)
    );
}

/// `mtwin run scenarios/<name> --out DIR/out --rrd DIR/<rrd>`.
fn run_recording(name: &str, dir: &Path, rrd: &str) -> Output {
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(name);
    mtwin(&[
        "run".as_ref(),
        scenario.as_os_str(),
        "--out".as_ref(),
        dir.join("out").as_os_str(),
        "--rrd".as_ref(),
        dir.join(rrd).as_os_str(),
    ])
}

#[test]
fn run_refuses_a_recording_that_is_not_an_rrd_file() {
    let dir = TempDir::new().unwrap();
    let output = run_recording("teach_abbe.toml", dir.path(), "lesson.txt");
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains(".rrd"),
        "{}",
        text(&output.stderr)
    );
    assert!(!dir.path().join("out").exists(), "no partial output");
}

#[cfg(not(feature = "viz"))]
#[test]
fn run_without_the_viz_feature_says_how_to_get_recordings() {
    let dir = TempDir::new().unwrap();
    let output = run_recording("teach_abbe.toml", dir.path(), "lesson.rrd");
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains("--features viz"),
        "{}",
        text(&output.stderr)
    );
    assert!(!dir.path().join("out").exists(), "no partial output");
}

#[cfg(feature = "viz")]
#[test]
fn a_lesson_runs_end_to_end_with_its_recording() {
    let dir = TempDir::new().unwrap();
    let output = run_recording("teach_warmup.toml", dir.path(), "warmup.rrd");
    assert!(output.status.success(), "{}", text(&output.stderr));
    let bytes = std::fs::read(dir.path().join("warmup.rrd")).unwrap();
    // An .rrd stream starts with rerun's magic bytes.
    assert!(
        bytes.starts_with(b"RRF2"),
        "{:?}",
        &bytes[..8.min(bytes.len())]
    );
    assert!(text(&output.stderr).contains("recording: discovery on the laser table"));
    assert!(dir.path().join("out/positioning.csv").exists());
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}
