//! The ISO 230-3 §5 ETVE test end to end: the bundled scenario through the thermal twin, the
//! drift table it writes (with its conditions), and `analyze drift` on it, checked against the
//! thermal model's closed forms and the noise-free truth.

use mtwin::app::{Scenario, simulate};
use mtwin::kinds::drift::iso230_3::{drift_report, etve, tilts};
use mtwin::kinds::drift::{DriftChannel, DriftConditions, DriftTable};
use std::path::PathBuf;
use std::process::Command;

fn scenario() -> Scenario {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenarios/vmc3_iso230_3_etve.toml");
    Scenario::load(path).unwrap()
}

#[test]
fn the_nest_reads_what_the_screws_and_the_spindle_do() {
    let scenario = scenario();
    let simulation = simulate(&scenario).unwrap();
    let run = simulation
        .etve
        .as_ref()
        .expect("the scenario has an ETVE test");
    let setup = scenario.thermal.as_ref().unwrap();
    let node = |name: &str| setup.thermal.network.node(name).unwrap();
    let (x_screw, y_screw, z_screw, housing) = (
        node("x_screw"),
        node("y_screw"),
        node("z_screw"),
        node("spindle_housing"),
    );
    let (front, back) = (node("column_front"), node("column_back"));
    // The thermal terms in closed form (the thermal model's doc): each screw expands with
    // 11.7 ppm/K from its fixed end (X at 760 mm, Y and Z at 0), the spindle housing pushes the
    // tool 1 µm/K towards the workpiece (−Z), and the column tilts the head about X by 2 µrad
    // per K of front−back difference (the front is warmed by the housing, the back is not). The
    // axes hold at x 380, y 205, z 260 mm.
    let alpha = 11.7e-6;
    let nest = scenario.etve_test.as_ref().unwrap().nest;
    let first = &run.records[0].temperatures;
    for (row, record) in run.records.iter().enumerate() {
        let rise = |n: usize| record.temperatures[n] - first[n];
        let tilt = 2e-6 * (rise(front) - rise(back));
        let x = alpha * (0.380 - 0.760) * rise(x_screw);
        let y = alpha * 0.205 * rise(y_screw);
        let z = alpha * 0.260 * rise(z_screw) - 1e-6 * rise(housing);
        // The tilt about X moves Y and Z by at most |tilt| times the lever from the head's
        // pivot, under 1 m on this machine; X not at all.
        let lever_bound = tilt.abs() * 1.0 + 1e-12;
        let expected = [
            (x, 1e-12),
            (y, lever_bound),
            (x, 1e-12),
            (y, lever_bound),
            (z, lever_bound),
        ];
        for (channel, (want, within)) in run.true_channels.iter().zip(expected) {
            let got = channel.values[row];
            assert!(
                (got - want).abs() <= within,
                "{} at row {row}: {got} m, closed form {want} m ± {within}",
                channel.name
            );
        }
        // The tilt itself, from the pairs, needs no lever: a rigid mandrel's two points differ by
        // the rotation times their distance.
        let value = |k: usize| run.true_channels[k].values[row];
        let a = (value(1) - value(3)) / nest.spacing;
        let b = (value(2) - value(0)) / nest.spacing;
        assert!(
            (a - tilt).abs() < 1e-12,
            "A at row {row}: {a} rad, column tilt {tilt} rad"
        );
        assert!(b.abs() < 1e-12, "B at row {row}: {b} rad");
    }
    // The air drove them: the screws warmed by more than 1 K over the 8 h.
    let last = &run.records.last().unwrap().temperatures;
    assert!(last[x_screw] - first[x_screw] > 1.0, "{}", last[x_screw]);
}

#[test]
fn the_analysis_finds_the_true_etve_within_the_nest_noise() {
    let scenario = scenario();
    let simulation = simulate(&scenario).unwrap();
    let run = simulation.etve.as_ref().unwrap();
    let test = scenario.etve_test.as_ref().unwrap();
    // The table as written and read back: the conditions travel with it.
    let mut bytes = Vec::new();
    run.table.write_csv(&mut bytes).unwrap();
    let table = DriftTable::parse(&bytes, "drift.csv").unwrap();
    assert_eq!(table.conditions.test.as_deref(), Some("iso230_3_etve"));
    assert_eq!(table.conditions.ambient_sensor.as_deref(), Some("air"));
    assert_eq!(table.conditions.spacing, Some(test.nest.spacing));
    let report = drift_report(&table, 3600.0, table.conditions.spacing);
    assert_eq!(report["ambient_sensor"], "air");
    // A noisy window's range differs from the true one by at most twice the largest noise
    // value plus a resolution step: 2 × 4.5 σ (2 405 draws) + 0.01 µm.
    let bound_um = 2.0 * 4.5 * test.nest.noise * 1e6 + test.nest.resolution * 1e6;
    let times = &run.table.times;
    for truth in &run.true_channels {
        let record: Vec<(f64, f64)> = times
            .iter()
            .copied()
            .zip(truth.values.iter().copied())
            .collect();
        let (true_etve, _) = etve(&record, 3600.0).unwrap();
        let entry = report["channels"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == truth.name.as_str())
            .unwrap();
        let measured = entry["etve_um"].as_f64().unwrap();
        assert!(
            (measured - true_etve * 1e6).abs() <= bound_um,
            "{}: ETVE {measured} µm, true {} µm, bound {bound_um} µm",
            truth.name,
            true_etve * 1e6
        );
        // The drift is well above what the noise can do (so the check above means something).
        assert!(
            true_etve * 1e6 > 3.0 * bound_um,
            "{}: {} µm",
            truth.name,
            true_etve * 1e6
        );
    }
    // No tilt in the model: A and B stay within the pair noise, √2 σ / l each sample.
    let tilt_bound_urad = 2.0 * 4.5 * 2f64.sqrt() * test.nest.noise / test.nest.spacing * 1e6
        + 2.0 * test.nest.resolution / test.nest.spacing * 1e6;
    for name in ["a", "b"] {
        let entry = report["channels"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == name)
            .unwrap();
        assert_eq!(entry["derived"], true);
        let range = entry["range_urad"].as_f64().unwrap().abs();
        assert!(
            range <= tilt_bound_urad,
            "{name}: {range} µrad > {tilt_bound_urad}"
        );
    }
}

#[test]
fn tilts_are_the_right_handed_rotations_of_the_mandrel() {
    // A mandrel along −Z (tool point at the origin, pair 1 at 20 mm, pair 2 at 120 mm above
    // it), turned by known small angles about X and Y by glam's quaternions: the tilts from the
    // pairs must give those angles back.
    use glam::{DQuat, DVec3};
    let (l, first) = (0.1, 0.02);
    let (a, b) = (12e-6, -7e-6);
    let turn = DQuat::from_rotation_x(a) * DQuat::from_rotation_y(b);
    let moved = |z: f64| turn * DVec3::new(0.0, 0.0, z) - DVec3::new(0.0, 0.0, z);
    let (p1, p2) = (moved(first), moved(first + l));
    let channel = |name: &str, v: f64| DriftChannel {
        name: name.into(),
        angular: false,
        values: vec![0.0, v],
    };
    let table = DriftTable {
        times: vec![0.0, 60.0],
        channels: vec![
            channel("x1", p1.x),
            channel("y1", p1.y),
            channel("x2", p2.x),
            channel("y2", p2.y),
        ],
        temperatures: Vec::new(),
        conditions: DriftConditions::default(),
        columns_not_read: Vec::new(),
    };
    let found = tilts(&table, l);
    assert_eq!(
        found.iter().map(|c| c.name.as_str()).collect::<Vec<_>>(),
        ["a", "b"]
    );
    // Second-order terms of the small rotation: below 1e-10 rad here.
    assert!(
        (found[0].values[1] - a).abs() < 1e-10,
        "A {} rad, turned {a}",
        found[0].values[1]
    );
    assert!(
        (found[1].values[1] - b).abs() < 1e-10,
        "B {} rad, turned {b}",
        found[1].values[1]
    );
}

fn mtwin(args: &[&str]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .args(args)
        .output()
        .unwrap();
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn analyze_drift_takes_its_conditions_from_the_file_or_its_flags() {
    let dir = tempfile::tempdir().unwrap();
    let with = dir.path().join("with.csv");
    std::fs::write(
        &with,
        "# ambient_sensor = hall\n# spacing_mm = 150\n\
         time_min,x1_um,x2_um,temp_spindle_degc,temp_hall_degc\n\
         0,0,0,20,20\n30,1.5,0,20.5,20.4\n60,3,0,21,20.8\n",
    )
    .unwrap();
    let with = with.to_str().unwrap();
    let (ok, out, err) = mtwin(&["analyze", "drift", with, "--json"]);
    assert!(ok, "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).unwrap();
    // The preamble's ambient, not the first column; B = (X2 − X1)/l = −3 µm / 150 mm.
    assert_eq!(report["ambient_sensor"], "hall");
    let b = report["channels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "b")
        .unwrap();
    assert!(
        (b["range_urad"].as_f64().unwrap() + 20.0).abs() < 1e-9,
        "{b}"
    );
    let (ok, _, err) = mtwin(&["analyze", "drift", with, "--spacing-mm", "100"]);
    assert!(!ok);
    assert!(
        err.contains("--spacing-mm 100 disagrees with") && err.contains("spacing_mm = 150"),
        "{err}"
    );
    let (ok, _, err) = mtwin(&["analyze", "drift", with, "--ambient-sensor", "spindle"]);
    assert!(!ok);
    assert!(
        err.contains("--ambient-sensor spindle disagrees") && err.contains("ambient_sensor = hall"),
        "{err}"
    );
    let (ok, _, err) = mtwin(&["analyze", "drift", with, "--spacing-mm", "-5"]);
    assert!(!ok);
    assert!(
        err.contains("--spacing-mm must be a positive number of millimetres, got -5"),
        "{err}"
    );

    // A real-style file without a preamble: the flags give what it lacks.
    let bare = dir.path().join("bare.csv");
    std::fs::write(
        &bare,
        "time_min,x1_um,x2_um,temp_spindle_degc,temp_hall_degc\n0,0,0,20,20\n30,1.5,0,20.5,20.4\n60,3,0,21,20.8\n",
    )
    .unwrap();
    let bare = bare.to_str().unwrap();
    let (ok, out, err) = mtwin(&[
        "analyze",
        "drift",
        bare,
        "--json",
        "--spacing-mm",
        "150",
        "--ambient-sensor",
        "hall",
    ]);
    assert!(ok, "{err}");
    let flagged: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(flagged["channels"], report["channels"]);
    assert_eq!(flagged["ambient_sensor"], "hall");
    let (ok, out, _) = mtwin(&["analyze", "drift", bare, "--json"]);
    assert!(ok);
    let plain: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        plain["ambient_sensor"], "spindle",
        "without a word, the first column"
    );
    assert_eq!(
        plain["channels"].as_array().unwrap().len(),
        2,
        "no tilts without a spacing"
    );
    let (ok, _, err) = mtwin(&["analyze", "drift", bare, "--ambient-sensor", "air"]);
    assert!(!ok);
    assert!(
        err.contains("has no column temp_air_degc (its sensors: spindle, hall)"),
        "{err}"
    );
}

#[test]
fn a_stated_ambient_sensor_must_be_a_column() {
    let error = DriftTable::parse(
        b"# mtwin drift table\n# ambient_sensor = air\ntime_min,z_um,temp_hall_degc\n0,0,20\n1,1,20\n",
        "d.csv",
    )
    .unwrap_err();
    assert_eq!(
        error.to_string(),
        "d.csv:2: ambient_sensor = air, but there is no column temp_air_degc"
    );
}

#[test]
fn an_etve_scenario_is_refused_where_it_cannot_run() {
    let dir = tempfile::tempdir().unwrap();
    let models = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("models/vmc3.urdf");
    let base = format!(
        "schema = 1\nmachine = {:?}\nseed = 1\n",
        models.display().to_string()
    );
    let etve = "[iso230_3_etve]\nhold_mm = { x = 380.0 }\nduration_min = 120.0\nnest = { first_mm = 20.0, spacing_mm = 100.0 }\n";
    let cases = [
        (
            format!("{base}{etve}"),
            "iso230_3_etve is a thermal test: add a [thermal] section",
        ),
        (
            format!(
                "{base}[thermal]\n{}",
                etve.replace(
                    "duration_min = 120.0",
                    "duration_min = 120.0\nsample_min = 6.0"
                )
            ),
            "iso230_3_etve.sample_min: 6 min; ISO 230-3 §5.2 asks for a reading at least every 5 min",
        ),
        (
            // 8 h written as 8: shorter than the first hour the report's range covers.
            format!(
                "{base}[thermal]\n{}",
                etve.replace("duration_min = 120.0", "duration_min = 8.0")
            ),
            "iso230_3_etve.duration_min: 8 min; expected at least 60 (the first-hour range; hours written as minutes?)",
        ),
        (
            format!(
                "{base}[thermal]\n{}",
                etve.replace("x = 380.0", "x = 900.0")
            ),
            "iso230_3_etve.hold_mm.x: 900 mm is outside the travel of X",
        ),
        (
            format!(
                "{base}[thermal]\n{etve}[iso230_2]\naxis = \"X\"\ntargets_mm = {{ from = 10.0, to = 750.0, count = 5 }}\n"
            ),
            "one thermal experiment per scenario",
        ),
    ];
    for (k, (text, expected)) in cases.iter().enumerate() {
        let path = dir.path().join(format!("s{k}.toml"));
        std::fs::write(&path, text).unwrap();
        let error = Scenario::load(&path).unwrap_err().to_string();
        assert!(error.contains(expected), "case {k}: {error}");
    }
}

/// A spindle test whose Z grows 5 µm over a 120 min running period and then falls to −3 µm in a
/// 60 min cool-down: d(Z)_t over the running period is +5 µm (ISO 230-3 Table 1), the whole
/// record's range −8 µm. Before `run_min` was read, the report gave only the whole record.
#[test]
fn a_spindle_tests_running_period_is_where_its_preamble_says() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from(
        "# mtwin drift table (ISO 230-3)\n# test = iso230_3_spindle\n# control = hold\n\
         # hold_mm = x 380, y 205, z 260\n# first_mm = 25\n# programme = constant\n\
         # speed_rpm = 6000\n# run_min = 120\n# stop_min = 60\n# operator = A. N. Other\n\
         time_min,z_um\n",
    );
    for minute in (0..=180).step_by(10) {
        let t = f64::from(minute);
        let z = if t <= 120.0 {
            5.0 * t / 120.0
        } else {
            5.0 - 8.0 * (t - 120.0) / 60.0
        };
        text += &format!("{t},{z}\n");
    }
    let file = dir.path().join("spindle.csv");
    std::fs::write(&file, &text).unwrap();
    let path = file.to_str().unwrap();
    let (ok, out, err) = mtwin(&["analyze", "drift", path, "--json"]);
    assert!(ok, "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).unwrap();
    let z = &report["channels"][0];
    assert!(
        (z["range_run_um"].as_f64().unwrap() - 5.0).abs() < 1e-9,
        "{z}"
    );
    // The whole record: max 5, min −3, the larger excursion from 0 upwards.
    assert!((z["range_um"].as_f64().unwrap() - 8.0).abs() < 1e-9, "{z}");
    assert_eq!(report["conditions"]["control"], "hold");
    assert_eq!(report["conditions"]["first_mm"], 25.0);
    assert_eq!(report["preamble_not_used"], serde_json::json!(["operator"]));
    assert_eq!(report["cautions"], serde_json::json!([]));
    let (ok, out, err) = mtwin(&["analyze", "drift", path]);
    assert!(ok, "{err}");
    assert!(
        out.contains("t = 120 min") && out.contains("control hold"),
        "{out}"
    );
    assert!(
        out.contains("Not used from the preamble (unknown to this reader): operator."),
        "{out}"
    );

    // A stop longer than the record: the cool-down is incomplete, and the report says so.
    let short = dir.path().join("short.csv");
    std::fs::write(&short, text.replace("stop_min = 60", "stop_min = 90")).unwrap();
    let (ok, out, err) = mtwin(&["analyze", "drift", short.to_str().unwrap(), "--json"]);
    assert!(ok, "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).unwrap();
    let cautions = report["cautions"].to_string();
    assert!(
        cautions.contains("ends 30 min before the stated stop"),
        "{cautions}"
    );

    // A running period the record does not hold, and words the reader cannot take.
    for (from, to, expected) in [
        (
            "run_min = 120",
            "run_min = 200",
            "run_min = 200: the running period ends after the record, which spans 180 min",
        ),
        (
            "control = hold",
            "control = standby",
            "control = standby: expected hold or off",
        ),
        (
            "first_mm = 25",
            "first_mm = -25",
            "first_mm = -25: expected a height of 0 or more",
        ),
        (
            "hold_mm = x 380, y 205, z 260",
            "hold_mm = 380 205 260",
            "hold_mm = 380 205 260: expected axis letters",
        ),
        (
            "speed_rpm = 6000",
            "spindle_rpm = 6000",
            "programme = constant: expected a speed_rpm line",
        ),
    ] {
        let bad = dir.path().join("bad.csv");
        std::fs::write(&bad, text.replace(from, to)).unwrap();
        let (ok, out, err) = mtwin(&["analyze", "drift", bad.to_str().unwrap()]);
        assert!(!ok && out.is_empty(), "{to}: {out}");
        assert!(
            err.contains("bad.csv:") && err.contains(expected),
            "{to}: {err}"
        );
    }
}
