//! Every bundled scenario runs end to end; outputs are byte-identical from run to run and
//! whatever path the scenario is given by; truth.json holds every injected parameter; a row of
//! the vmc3 map against a hand computation.

use mtwin::app::{Scenario, run_scenario, write_outputs};
use std::collections::BTreeSet;
use std::path::PathBuf;

fn scenario_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(name)
}

fn file<'a>(output: &'a mtwin::app::RunOutput, name: &str) -> &'a [u8] {
    &output.files.iter().find(|(n, _)| n == name).unwrap().1
}

#[test]
fn every_bundled_scenario_runs_with_the_outputs_it_asks_for() {
    // Row counts by hand: volumetric grids from the [volumetric] sections; the ISO 230-2 test
    // reads 9 targets × 2 directions × 5 runs, the warm-up experiment 16 × 2 × 7, the
    // ISO 230-3 linear-motion test 2 targets × 240 readings (see tests/it/thermal_twin.rs). A
    // ball-bar reads for data arc × R / v at 250 Hz per sense, ± 1 reading (where the first
    // sample falls): a full circle of 150 mm at 1000 mm/min 56.5 s, 14 137 readings; a 180° arc
    // 7 069; a 100 mm circle 9 425. The lessons: Abbe 6 targets × 2 × 2 runs; squareness a
    // 100 mm circle at 2000 mm/min, 18.85 s at 100 Hz, 1 885 per sense; warm-up 7 targets
    // (5..755 step 125) × 2 × 4 runs. The ETVE test reads every minute for 480 min: 481 rows.
    let full_150 = 2 * 14_137;
    // The R-tests: one row per static pose, 37 + 37 + 19 + 37 on trunnion5, 37 + 37 + 19 on
    // headtable5, 73 + 19 in the lesson. The probe: a touch per point and a fit per sphere:
    // 8 rotary positions × 5 points on trunnion5 and headtable5; a 4 × 5 ball plate at 3
    // placements, 5 points a ball; a ring of 36 points and 3 mesh points (no sphere); the
    // probe lesson 4 C positions × 5 points. The spindle analysers: set-ups × speeds ×
    // revolutions × samples per revolution (vmc3 1 × 3 × 20 × 1024; the reversal 2 × 1 × 20 ×
    // 1024; the multi-probe layout 1 × 1 × 20 × 1024; trunnion5's C 1 × 2 × 20 × 720; the
    // spindle lesson 1 × 1 × 16 × 256); the ISO 230-3 spindle thermal test reads every minute
    // for 240 + 60 min: 301 rows. The dataset scenarios run once as written: a 9 × 5 × 5 map
    // and a full 150 mm circle.
    let expected: [(&str, &[(&str, usize)]); 30] = [
        (
            "vmc3_dataset_volumetric.toml",
            &[("volumetric.csv", 9 * 5 * 5)],
        ),
        ("vmc3_dataset_ballbar.toml", &[("ballbar_xy.csv", full_150)]),
        (
            "trunnion5_probe_sphere.toml",
            &[("probe.csv", 8 * 5), ("spheres.csv", 8)],
        ),
        (
            "headtable5_probe_sphere.toml",
            &[("probe.csv", 8 * 5), ("spheres.csv", 8)],
        ),
        (
            "vmc3_ballplate.toml",
            &[("probe.csv", 3 * 20 * 5), ("spheres.csv", 3 * 20)],
        ),
        (
            "vmc3_probe_ring_mesh.toml",
            &[("probe.csv", 36 + 3), ("spheres.csv", 0)],
        ),
        (
            "teach_probe.toml",
            &[("probe.csv", 4 * 5), ("spheres.csv", 4)],
        ),
        ("teach_rtest.toml", &[("rtest.csv", 73 + 19)]),
        ("trunnion5_rtest.toml", &[("rtest.csv", 37 + 37 + 19 + 37)]),
        ("headtable5_rtest.toml", &[("rtest.csv", 37 + 37 + 19)]),
        ("teach_abbe.toml", &[("positioning.csv", 6 * 2 * 2)]),
        (
            "teach_squareness_ballbar.toml",
            &[("ballbar_xy.csv", 2 * 1_885)],
        ),
        ("teach_warmup.toml", &[("positioning.csv", 7 * 2 * 4)]),
        ("vmc3_volumetric.toml", &[("volumetric.csv", 9 * 5 * 5)]),
        (
            "trunnion5_volumetric.toml",
            &[("volumetric.csv", 3 * 3 * 3 * 5 * 8)],
        ),
        (
            "headtable5_volumetric.toml",
            &[("volumetric.csv", 3 * 3 * 3 * 5 * 4)],
        ),
        ("vmc3_iso230_2.toml", &[("positioning.csv", 9 * 2 * 5)]),
        ("vmc3_warmup_laser.toml", &[("positioning.csv", 16 * 2 * 7)]),
        (
            "vmc3_warmup_sensor_lag.toml",
            &[("positioning.csv", 16 * 2 * 7)],
        ),
        ("vmc3_iso230_3_linear.toml", &[("positioning.csv", 2 * 240)]),
        ("vmc3_iso230_3_etve.toml", &[("drift.csv", 480 + 1)]),
        ("vmc3_iso230_3_spindle.toml", &[("drift.csv", 300 + 1)]),
        ("vmc3_spindle.toml", &[("spindle.csv", 3 * 20 * 1024)]),
        (
            "vmc3_spindle_reversal.toml",
            &[("spindle.csv", 2 * 20 * 1024)],
        ),
        (
            "vmc3_spindle_multiprobe.toml",
            &[("spindle.csv", 20 * 1024)],
        ),
        ("trunnion5_c_axis.toml", &[("spindle.csv", 2 * 20 * 720)]),
        ("teach_spindle.toml", &[("spindle.csv", 16 * 256)]),
        ("vmc3_ballbar_xy.toml", &[("ballbar_xy.csv", full_150)]),
        (
            "vmc3_ballbar_3planes.toml",
            &[
                ("ballbar_xy.csv", full_150),
                ("ballbar_yz.csv", 2 * 7_069),
                ("ballbar_zx.csv", 2 * 7_069),
            ],
        ),
        (
            "trunnion5_ballbar_xy.toml",
            &[("ballbar_xy.csv", 2 * 9_425)],
        ),
    ];
    let on_disk: BTreeSet<String> = std::fs::read_dir(scenario_path(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    let listed: BTreeSet<String> = expected.iter().map(|(n, _)| n.to_string()).collect();
    assert_eq!(
        on_disk, listed,
        "every bundled scenario is run by this test"
    );
    for (name, tables) in expected {
        let output = run_scenario(&Scenario::load(scenario_path(name)).unwrap()).unwrap();
        for &(table, rows) in tables {
            let csv = String::from_utf8(file(&output, table).to_vec()).unwrap();
            let tolerance = if table.starts_with("ballbar") { 2 } else { 0 };
            // Rows after the preamble of test conditions (`# key = value` lines).
            let lines = csv.lines().filter(|l| !l.starts_with('#')).count();
            assert!(
                lines.abs_diff(rows + 1) <= tolerance,
                "{name}: {table} has {lines} lines, expected header + {rows}"
            );
        }
        let names: Vec<&str> = output.files.iter().map(|(n, _)| n.as_str()).collect();
        let mut listed: Vec<&str> = tables.iter().map(|(t, _)| *t).collect();
        listed.extend(["truth.json", "manifest.json"]);
        assert_eq!(names, listed);
    }
}

#[test]
fn the_same_scenario_gives_byte_identical_files() {
    let absolute = scenario_path("trunnion5_volumetric.toml");
    let relative = PathBuf::from("scenarios/trunnion5_volumetric.toml"); // tests run in the crate root
    let dirs = [tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap()];
    for (path, dir) in [&absolute, &relative].into_iter().zip(&dirs) {
        let output = run_scenario(&Scenario::load(path).unwrap()).unwrap();
        write_outputs(&output, dir.path()).unwrap();
    }
    for name in ["volumetric.csv", "truth.json", "manifest.json"] {
        let a = std::fs::read(dirs[0].path().join(name)).unwrap();
        let b = std::fs::read(dirs[1].path().join(name)).unwrap();
        assert!(!a.is_empty() && a == b, "{name} differs between runs");
    }
    let leftovers: Vec<_> = std::fs::read_dir(dirs[0].path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_string_lossy().starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
}

#[test]
fn truth_lists_every_injected_parameter_as_written() {
    let path = scenario_path("trunnion5_volumetric.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let scenario_toml: toml::Value = toml::from_str(&text).unwrap();
    let injected: BTreeSet<String> = scenario_toml["errors"]
        .as_table()
        .unwrap()
        .keys()
        .cloned()
        .collect();
    let output = run_scenario(&Scenario::load(&path).unwrap()).unwrap();
    let truth: serde_json::Value = serde_json::from_slice(file(&output, "truth.json")).unwrap();
    let recorded: BTreeSet<String> = truth["errors"]
        .as_object()
        .unwrap()
        .keys()
        .cloned()
        .collect();
    assert_eq!(recorded, injected);
    // Values as written, in file units.
    assert_eq!(truth["errors"]["EX0C"]["terms"]["constant_um"], 9.0);
    assert_eq!(truth["errors"]["EX0C"]["kind"], "location");
    assert_eq!(
        truth["errors"]["ECC"]["terms"]["harmonic"][1]["period_deg"],
        180.0
    );
    assert_eq!(truth["errors"]["EC0Y"]["kind"], "squareness");
    assert_eq!(truth["seed"], 1);
}

#[test]
fn first_row_of_the_vmc3_map_matches_a_hand_computation() {
    // At X = Y = Z = 0, moving +, with the errors of vmc3_volumetric.toml (arms from the URDF
    // header: X carriage → tip (-0.38, -0.205, 0.20) m, Y carriage → tip (-0.38, -0.205, 0.35),
    // Z head → tip (0, 0.35, -0.30)):
    //   dx = EXX(0) [-1.5 lost motion + 0.4·sin 30°] + ECX(0)·0.205 + ECY·0.205 - EBZ(0)·0.30
    //      = -1.3 + 2·0.205 + 3·0.205 - 1.5·0.30             = -0.725 µm
    //   dy = ECX(0)·(-0.38) + ECY·(-0.38) + EYY(0) [-1.0 lost motion] = -0.76 - 1.14 - 1.0 = -2.9 µm
    //   dz = EZT                                                  = -5.0 µm
    // (squareness and the position-dependent terms are zero at the axis zeros). First order:
    // the neglected terms are below 1 pm; the file rounds to 1 pm.
    let output =
        run_scenario(&Scenario::load(scenario_path("vmc3_volumetric.toml")).unwrap()).unwrap();
    let csv = String::from_utf8(file(&output, "volumetric.csv").to_vec()).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), "x_mm,y_mm,z_mm,dx_um,dy_um,dz_um");
    let row: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    let expected = [0.0, 0.0, 0.0, -0.725, -2.9, -5.0];
    for (got, want) in row.iter().zip(expected) {
        assert!((got - want).abs() < 2e-6, "{row:?} vs {expected:?}");
    }
}

#[test]
fn five_axis_map_columns_match_hand_values() {
    // trunnion5 at A = 0 with only EX0C = 9 µm and EA0C = 10 µrad (the C axis line displaced
    // along X and tilted about X), at the table centre's tool position. Hand values, workpiece
    // frame (= C table frame; the tool frame there is Rz(c)):
    //   EX0C: (I - Rz(c))·(δ, 0, 0)       → C = 0: 0;  C = 180°: (18, 0, 0) µm
    //   EA0C: the table turns about Rx(ε)·z, so the tool axis is seen at Rx(ε)·Rz(c)·Rx(-ε)·e_z
    //         → C = 180°: (0, -sin 2ε, cos 2ε); along the tool frame's y = (0, -1, 0) that is
    //           tj = sin 2ε = 20 µrad, ti = 0; and the tip, h = 100 mm above the table centre
    //           on the C axis, is seen at h·(0, -sin 2ε, cos 2ε): dy = -2.0 µm, dz = -2e-5 µm.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c_axis.toml");
    let machine = scenario_path("../models/trunnion5.urdf");
    std::fs::write(
        &path,
        format!(
            "schema = 1\nmachine = '{}'\nseed = 7\n[errors.EX0C]\nconstant_um = 9.0\n[errors.EA0C]\nconstant_urad = 10.0\n\
             [volumetric]\nx_mm = {{ from = 325.0, to = 325.0, count = 1 }}\ny_mm = {{ from = 275.0, to = 275.0, count = 1 }}\n\
             z_mm = {{ from = 0.0, to = 0.0, count = 1 }}\na_deg = {{ from = 0.0, to = 0.0, count = 1 }}\n\
             c_deg = {{ from = 0.0, to = 180.0, count = 2 }}\n",
            machine.display()
        ),
    )
    .unwrap();
    let output = run_scenario(&Scenario::load(&path).unwrap()).unwrap();
    let csv = String::from_utf8(file(&output, "volumetric.csv").to_vec()).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "x_mm,y_mm,z_mm,a_deg,c_deg,dx_um,dy_um,dz_um,ti_urad,tj_urad"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let expected = [
        [325.0, 275.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [
            325.0,
            275.0,
            0.0,
            0.0,
            180.0,
            18.0,
            -1e5 * (20e-6f64).sin(),
            1e5 * ((20e-6f64).cos() - 1.0),
            0.0,
            1e6 * (20e-6f64).sin(),
        ],
    ];
    assert_eq!(rows.len(), 2);
    for (row, want) in rows.iter().zip(expected) {
        for (got, want) in row.iter().zip(want) {
            // Exact values; the file rounds to 1 pm / 1 prad.
            assert!((got - want).abs() < 2e-6, "{row:?} vs {want:?}");
        }
    }
}

#[test]
fn every_bundled_scenario_is_deterministic() {
    // Same scenario and seed ⇒ the same bytes in every file, noise and sensors included.
    for entry in std::fs::read_dir(scenario_path("")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let first = run_scenario(&Scenario::load(&path).unwrap()).unwrap();
            let second = run_scenario(&Scenario::load(&path).unwrap()).unwrap();
            assert_eq!(first, second, "{}", path.display());
        }
    }
}
