//! `mtwin identify`, `score` and `plan` end to end: simulate → identify → score → compensate →
//! simulate again, and bad inputs refused with the file and what is wrong, non-zero exit, no
//! files written.

use crate::common::mtwin_output as mtwin;
use serde_json::Value;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Output;

mod discover;
mod null_combinations;
mod wrong_data;

fn root(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

fn ok(output: &Output) -> String {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn failed(output: &Output) -> String {
    assert!(!output.status.success(), "expected a failure");
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// `mtwin run SCENARIO --out DIR/NAME`: the output folder.
fn run_into(scenario: &Path, dir: &Path, name: &str) -> PathBuf {
    let out = dir.join(name);
    ok(&mtwin(&[
        "run".as_ref(),
        scenario.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]));
    out
}

/// The largest R-test range (µm) of a table, from `mtwin analyze rtest --json`.
fn largest_range(table: &Path) -> f64 {
    let json: Value = serde_json::from_str(&ok(&mtwin(&[
        "analyze".as_ref(),
        "rtest".as_ref(),
        table.as_os_str(),
        "--json".as_ref(),
    ])))
    .unwrap();
    json["tests"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|t| {
            t["range_um"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
        })
        .fold(0.0, f64::max)
}

/// The whole loop on the bundled R-test. The compensated machine's R-test ranges must fall
/// below a tenth of the uncompensated ones (the estimate is within 1 µm and 1 µrad of errors of
/// 6–25 µm and µrad, whose ranges are 20–33 µm), and the score must show the volumetric
/// deviation falling likewise.
#[test]
fn simulate_identify_score_compensate_simulate_again() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = root("scenarios/trunnion5_rtest.toml");
    let run = run_into(&scenario, dir.path(), "run");
    let id = dir.path().join("id");
    let text = ok(&mtwin(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        root("models/trunnion5.urdf").as_os_str(),
        "--params".as_ref(),
        "location".as_ref(),
        run.join("rtest.csv").as_os_str(),
        "--scenario".as_ref(),
        scenario.as_os_str(),
        "--monte-carlo".as_ref(),
        "200".as_ref(),
        "--out".as_ref(),
        id.as_os_str(),
    ]));
    assert!(text.contains("rank 20 of 20"), "{text}");
    let estimate: Value =
        serde_json::from_slice(&std::fs::read(id.join("estimate.json")).unwrap()).unwrap();
    assert_eq!(estimate["mtwin"], "estimate");
    assert_eq!(estimate["errors"].as_object().unwrap().len(), 8);
    assert!(estimate["errors"]["EX0C"]["terms"]["constant_um"].is_f64());
    assert!(estimate["errors"]["EX0C"]["interval_95"]["constant_um"].is_array());
    assert!(id.join("trunnion5_identified.urdf").exists());
    let check = ok(&mtwin(&[
        "check".as_ref(),
        id.join("trunnion5_identified.urdf").as_os_str(),
    ]));
    assert!(check.contains("ok, machine \"trunnion5\""), "{check}");

    let score: Value = serde_json::from_str(&ok(&mtwin(&[
        "score".as_ref(),
        id.join("estimate.json").as_os_str(),
        run.join("truth.json").as_os_str(),
        "--json".as_ref(),
    ])))
    .unwrap();
    let volumetric = &score["volumetric"];
    let before = volumetric["uncompensated_rms_um"].as_f64().unwrap();
    let after = volumetric["compensated_rms_um"].as_f64().unwrap();
    assert!(after < 0.1 * before, "{volumetric}");

    let compensated = run_into(&id.join("compensated.toml"), dir.path(), "compensated");
    let (before, after) = (
        largest_range(&run.join("rtest.csv")),
        largest_range(&compensated.join("rtest.csv")),
    );
    assert!(
        after < 0.1 * before,
        "R-test ranges {before} µm → {after} µm"
    );
}

/// The manifest `mtwin run` writes beside its tables ties them to their scenario: `identify`
/// records it in estimate.json, refuses a `--scenario` of another machine or another scenario
/// (its compensated.toml would subtract the estimate from errors the tables never saw), says
/// so where a table carries nothing, and `score` refuses a truth of another scenario.
#[test]
fn provenance_ties_an_estimate_to_its_scenario_and_refuses_another() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = root("scenarios/trunnion5_rtest.toml");
    let run = run_into(&scenario, dir.path(), "run");
    let machine = root("models/trunnion5.urdf");
    let identify = |table: &Path, scenario: &Path, out: &Path| {
        identify_location(
            &machine,
            table.as_os_str(),
            &[
                "--scenario".as_ref(),
                scenario.as_os_str(),
                "--out".as_ref(),
                out.as_os_str(),
            ],
        )
    };
    let id = dir.path().join("id");
    let text = ok(&identify(&run.join("rtest.csv"), &scenario, &id));
    assert!(!text.contains("Provenance:"), "{text}");
    let read =
        |path: &Path| -> Value { serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap() };
    let (estimate, truth) = (
        read(&id.join("estimate.json")),
        read(&run.join("truth.json")),
    );
    assert!(truth["scenario_sha256"].is_string());
    assert_eq!(estimate["scenario_sha256"], truth["scenario_sha256"]);
    assert_eq!(
        estimate["provenance"][0]["scenario"],
        "trunnion5_rtest.toml"
    );

    // A scenario of another machine, and another scenario of the same machine file.
    for (other, expected) in [
        ("scenarios/headtable5_rtest.toml", "runs the machine"),
        (
            "scenarios/trunnion5_volumetric.toml",
            "its manifest.json says it was made from the scenario trunnion5_rtest.toml",
        ),
    ] {
        let out = dir.path().join("other");
        let message = failed(&identify(&run.join("rtest.csv"), &root(other), &out));
        assert!(message.contains(expected), "{other}: {message}");
        assert!(!out.exists(), "{other}: nothing written");
    }

    // The same table copied away from its manifest: accepted, and the report says what it
    // cannot check.
    let bare = dir.path().join("bare");
    std::fs::create_dir_all(&bare).unwrap();
    std::fs::copy(run.join("rtest.csv"), bare.join("rtest.csv")).unwrap();
    let text = ok(&identify(
        &bare.join("rtest.csv"),
        &scenario,
        &dir.path().join("id2"),
    ));
    assert!(
        text.contains("Provenance: no table names the scenario"),
        "{text}"
    );

    // score: the truth of another scenario is refused.
    let volumetric = run_into(
        &root("scenarios/trunnion5_volumetric.toml"),
        dir.path(),
        "vol",
    );
    let message = failed(&mtwin(&[
        "score".as_ref(),
        id.join("estimate.json").as_os_str(),
        volumetric.join("truth.json").as_os_str(),
    ]));
    assert!(
        message.contains("is not the scenario the estimate's tables were made from"),
        "{message}"
    );
}

/// A table measured on another machine is refused, naming both, and nothing is written.
#[test]
fn a_table_from_another_machine_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(&root("scenarios/headtable5_rtest.toml"), dir.path(), "run");
    let out = dir.path().join("id");
    let message = failed(&mtwin(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        root("models/trunnion5.urdf").as_os_str(),
        "--params".as_ref(),
        "location".as_ref(),
        run.join("rtest.csv").as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]));
    assert!(message.contains("rtest.csv"), "{message}");
    assert!(
        message.contains("headtable5") && message.contains("trunnion5"),
        "{message}"
    );
    assert!(!out.join("estimate.json").exists());
}

/// Bad parameters, a table of no known kind, and parameters no table can see.
#[test]
fn bad_inputs_are_refused_with_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(&root("scenarios/trunnion5_rtest.toml"), dir.path(), "run");
    let table = run.join("rtest.csv");
    let identify = |params: &str, table: &OsStr| {
        mtwin(&[
            "identify".as_ref(),
            "--machine".as_ref(),
            root("models/trunnion5.urdf").as_os_str(),
            "--params".as_ref(),
            params.as_ref(),
            table,
        ])
    };
    let message = failed(&identify("ECOY", table.as_os_str()));
    assert!(message.contains("did you mean EC0Y"), "{message}");
    let message = failed(&identify("EX0B", table.as_os_str()));
    assert!(message.contains("no axis B"), "{message}");
    let message = failed(&identify("location", run.join("truth.json").as_os_str()));
    assert!(
        message.contains("rtest:") && message.contains("truth.json"),
        "{message}"
    );
    // Nothing an R-test reads depends on the tool's offset across its axis and its length at
    // once with the zeros free: all three unseen.
    let message = failed(&identify("EXT,EYT,EZT", table.as_os_str()));
    assert!(message.contains("see none of the parameters"), "{message}");
    let message = failed(&mtwin(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        root("models/trunnion5.urdf").as_os_str(),
        "--params".as_ref(),
        "location".as_ref(),
        "--sigma-um".as_ref(),
        "rtest=-1".as_ref(),
        table.as_os_str(),
    ]));
    assert!(message.contains("--sigma-um rtest=-1"), "{message}");
    let message = failed(&mtwin(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        root("models/trunnion5.urdf").as_os_str(),
        "--params".as_ref(),
        "location".as_ref(),
        "--monte-carlo".as_ref(),
        "5".as_ref(),
        table.as_os_str(),
    ]));
    assert!(message.contains("--monte-carlo 5"), "{message}");
    let message = failed(&identify("EYX:1", table.as_os_str()));
    assert!(message.contains("starts at degree 2"), "{message}");
}

/// The plan for trunnion5's eight location errors: identifiable after exactly two tests, one
/// turning C and one sweeping A. By hand: no single test is enough, because a test zeroed at
/// its start at a fixed A removes what A's line position does there (a constant), so a C turn
/// leaves EY0A and EZ0A unseen, and an A sweep at fixed C sees A's four errors only in pairs
/// (the lever to the sphere is fixed) and none of C's; a C turn at a tilt plus an A sweep
/// see all eight.
#[test]
fn plan_chooses_tests_that_identify_the_location_errors() {
    let plan: Value = serde_json::from_str(&ok(&mtwin(&[
        "plan",
        "--machine",
        root("models/trunnion5.urdf").to_str().unwrap(),
        "--params",
        "location",
        "--sphere-mm",
        "100,0,250",
        "--json",
    ])))
    .unwrap();
    assert_eq!(plan["identifiable"], true, "{plan:#}");
    assert_eq!(plan["identifiable_after_steps"], 2, "{plan:#}");
    let mut two: Vec<&str> = (0..2)
        .map(|i| plan["steps"][i]["test"].as_str().unwrap())
        .collect();
    two.sort();
    assert!(
        two[0].contains("A sweep") && two[1].contains("C turn at A = "),
        "{two:?}"
    );
    assert!(
        !two[1].contains("A = 0°"),
        "a turn at A = 0 sees none of A: {two:?}"
    );
}

// ---------------------------------------------------------------------------------------
// The door: plausible-looking but wrong tables (a unit off, a mistyped set-up, one wild
// reading) must not give a compensation file. Each is built from a clean table the way a real
// export or a tired user gets it wrong; the clean table passes the same door.
// ---------------------------------------------------------------------------------------

/// `text` with column `column` of every data row transformed by `f`.
fn with_column(text: &str, column: &str, f: impl Fn(f64) -> f64) -> String {
    let mut out = String::new();
    let mut index = None;
    for line in text.lines() {
        if line.starts_with('#') {
            out += line;
            out += "\n";
            continue;
        }
        let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
        match index {
            None => index = Some(fields.iter().position(|f| f == column).expect("the column")),
            Some(i) => fields[i] = format!("{}", f(fields[i].parse::<f64>().unwrap())),
        }
        out += &fields.join(",");
        out += "\n";
    }
    out
}

/// `identify` with `args` must be refused by its checks (exit 1), naming `expected` and the
/// likely cause `cause`, with nothing written into `out`.
fn refused_by_the_door(args: &[&OsStr], out: &Path, expected: &[&str], cause: &str) -> String {
    let message = refused(args, out, expected, true);
    assert!(
        message.contains(cause),
        "should name the cause {cause}: {message}"
    );
    message
}

/// `identify` with `args` must be refused where the table is read (exit 1), before any fit,
/// naming `expected`, with nothing written into `out`.
fn refused_by_the_reader(args: &[&OsStr], out: &Path, expected: &[&str]) -> String {
    refused(args, out, expected, false)
}

/// `identify ARGS --out OUT` must exit 1 naming each of `expected`, by the door (`by_door`:
/// the fit, or the tables' own data, fail their checks) or by a reader, printing and writing
/// nothing.
fn refused(args: &[&OsStr], out: &Path, expected: &[&str], by_door: bool) -> String {
    let mut all: Vec<&OsStr> = vec!["identify".as_ref()];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out".as_ref(), out.as_os_str()]);
    let output = mtwin(&all);
    let message = failed(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert_eq!(
        message.contains("fails its own checks") || message.contains("fail their own checks"),
        by_door,
        "{message}"
    );
    for e in expected {
        assert!(message.contains(e), "should name {e}: {message}");
    }
    assert!(!out.exists(), "nothing may be written: {message}");
    assert!(output.stdout.is_empty(), "no estimate printed");
    message
}

#[test]
fn laser_deviations_in_nanometres_are_refused_not_compensated() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(&root("scenarios/vmc3_iso230_2.toml"), dir.path(), "run");
    let text = std::fs::read_to_string(run.join("positioning.csv")).unwrap();
    // The export wrote nanometres in a column named deviation_um: every value ×1000.
    let nm = dir.path().join("nm.csv");
    std::fs::write(&nm, with_column(&text, "deviation_um", |v| v * 1000.0)).unwrap();
    let machine = root("models/vmc3.urdf");
    let args = |table: &Path| -> Vec<std::ffi::OsString> {
        vec![
            "--machine".into(),
            machine.clone().into(),
            "--params".into(),
            "EXX:2".into(),
            table.into(),
        ]
    };
    let nm_args = args(&nm);
    let nm_refs: Vec<&OsStr> = nm_args.iter().map(|a| a.as_os_str()).collect();
    // The readings reach 11 mm: no laser reading of an axis is that large, and the reader says
    // so at the first such line, before any fit.
    refused_by_the_reader(
        &nm_refs,
        &dir.path().join("id"),
        &[
            "nm.csv:",
            "column `deviation_um`",
            "nm or mm in a µm column?",
        ],
    );
    // The clean table is refused too, for another reason: the scenario injects 3 µm of lost
    // motion that EXX:2 cannot hold (χ²/dof in the thousands at the laser's 0.02 µm), and the
    // door names that cause, not units: its residuals are micrometres, not millimetres.
    let clean = run.join("positioning.csv");
    let clean_args = args(&clean);
    let clean_refs: Vec<&OsStr> = clean_args.iter().map(|a| a.as_os_str()).collect();
    let message = refused_by_the_door(
        &clean_refs,
        &dir.path().join("id"),
        &["χ²/dof"],
        "a term the model lacks (lost motion",
    );
    assert!(!message.contains("units or set-up"), "{message}");

    // --accept-implausible writes the clean fit, with the warnings in the report and the
    // estimate; it cannot take a reading the reader refused.
    let mut all: Vec<&OsStr> = vec!["identify".as_ref()];
    all.extend_from_slice(&nm_refs);
    all.extend_from_slice(&["--accept-implausible".as_ref()]);
    assert!(failed(&mtwin(&all)).contains("nm or mm in a µm column?"));
    let id = dir.path().join("accepted");
    let mut all: Vec<&OsStr> = vec!["identify".as_ref()];
    all.extend_from_slice(&clean_refs);
    all.extend_from_slice(&[
        "--accept-implausible".as_ref(),
        "--out".as_ref(),
        id.as_os_str(),
    ]);
    let report = ok(&mtwin(&all));
    assert!(
        report.starts_with("CAUTION: the fit fails its own checks"),
        "{report}"
    );
    let estimate: Value =
        serde_json::from_slice(&std::fs::read(id.join("estimate.json")).unwrap()).unwrap();
    assert!(
        !estimate["warnings"].as_array().unwrap().is_empty(),
        "{estimate}"
    );
}

#[test]
fn an_estimate_beyond_ten_millimetres_is_named_and_refused() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(&root("scenarios/vmc3_iso230_2.toml"), dir.path(), "run");
    let clean = run.join("positioning.csv");
    let text = std::fs::read_to_string(&clean).unwrap();
    // A scale error of 2.5 % on top of the readings (25 µm per mm of target: the deviation
    // column of a file whose positions were in another unit), on the first half of the axis
    // only: the readings stay below 10 mm (9.6 mm at 383 mm, so the reader takes them), but
    // EXX, a perfectly fitting line, reaches 19 mm at the end of the travel: no machine error.
    let mut target_column = None;
    let mut lines = Vec::new();
    for line in text.lines() {
        if line.starts_with('#') {
            // The targets the file lists include the half left out.
            if !line.starts_with("# targets_mm") {
                lines.push(line.to_string());
            }
            continue;
        }
        let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
        match target_column {
            None => target_column = fields.iter().position(|f| f == "target_mm"),
            Some(t) => {
                let target: f64 = fields[t].parse().unwrap();
                if target > 400.0 {
                    continue;
                }
                let column = text
                    .lines()
                    .find(|l| !l.starts_with('#'))
                    .unwrap()
                    .split(',')
                    .position(|c| c == "deviation_um")
                    .unwrap();
                let deviation: f64 = fields[column].parse().unwrap();
                fields[column] = format!("{:.4}", deviation + 25.0 * target);
            }
        }
        lines.push(fields.join(","));
    }
    let scaled = dir.path().join("scaled.csv");
    std::fs::write(&scaled, lines.join("\n") + "\n").unwrap();
    // The readings' uncertainty stated at 3 µm, the size of the lost motion EXX:2 cannot
    // hold, so that the clean table passes. The scaled one is refused naming EXX's size (the
    // readings' model is not linear in so large an error, so χ²/dof fails too).
    let args = |table: &Path| -> Vec<std::ffi::OsString> {
        vec![
            "--machine".into(),
            root("models/vmc3.urdf").into(),
            "--params".into(),
            "EXX:2".into(),
            "--sigma-um".into(),
            "positioning=3".into(),
            table.into(),
        ]
    };
    let scaled_args = args(&scaled);
    let refs: Vec<&OsStr> = scaled_args.iter().map(|a| a.as_os_str()).collect();
    refused_by_the_door(
        &refs,
        &dir.path().join("id"),
        &["EXX: the estimate reaches", "more than the 10000 um"],
        "units or set-up",
    );
    // The same table without the scale error passes the door and writes its files.
    let clean_args = args(&clean);
    let mut all: Vec<&OsStr> = vec!["identify".as_ref()];
    all.extend(clean_args.iter().map(|a| a.as_os_str()));
    let id = dir.path().join("clean");
    all.extend_from_slice(&["--out".as_ref(), id.as_os_str()]);
    ok(&mtwin(&all));
    assert!(id.join("linuxcnc_X.comp").exists() || id.join("estimate.json").exists());
}

/// `mtwin identify --machine MACHINE --params location TABLE` with `more` arguments.
fn identify_location(machine: &Path, table: &OsStr, more: &[&OsStr]) -> Output {
    let mut args: Vec<&OsStr> = vec![
        "identify".as_ref(),
        "--machine".as_ref(),
        machine.as_os_str(),
        "--params".as_ref(),
        "location".as_ref(),
        table,
    ];
    args.extend_from_slice(more);
    mtwin(&args)
}

/// `mtwin identify` of the location errors from the R-test `table` (`rtest:FILE`) with the
/// sphere given as `sphere` (mm).
fn identify_bare(machine: &Path, table: &str, sphere: &str) -> Output {
    identify_location(
        machine,
        table.as_ref(),
        &["--rtest-sphere-mm".as_ref(), sphere.as_ref()],
    )
}

#[test]
fn an_r_test_with_a_mistyped_sphere_or_angles_in_radians_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(&root("scenarios/trunnion5_rtest.toml"), dir.path(), "run");
    let text = std::fs::read_to_string(run.join("rtest.csv")).unwrap();
    let machine = root("models/trunnion5.urdf");
    // An export without its preamble, the sphere typed 50 mm off in X (150 for 100). Its own
    // commanded x_mm, y_mm, z_mm keep the tool on the real sphere, so the reader sees the
    // contradiction at the first row.
    let bare = dir.path().join("bare.csv");
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    std::fs::write(&bare, rows.join("\n") + "\n").unwrap();
    let table = format!("rtest:{}", bare.display());
    let message = failed(&identify_bare(&machine, &table, "150,0,250"));
    assert!(
        message.contains("bare.csv") && message.contains("50 mm from the sphere at 150 0 250 mm"),
        "{message}"
    );
    // Without those columns (an export of the probe readings alone) the reader follows the
    // sphere where the flag puts it, and the machine cannot reach it at every pose.
    let drop = |text: &str| -> String {
        let mut out = Vec::new();
        for line in text.lines() {
            let fields: Vec<&str> = line.split(',').collect();
            out.push([&fields[..5], &fields[8..]].concat().join(","));
        }
        out.join("\n") + "\n"
    };
    assert!(rows[0].starts_with("test,point,time_s,a_deg,c_deg,x_mm,y_mm,z_mm,dx_um"));
    std::fs::write(&bare, drop(&rows.join("\n"))).unwrap();
    let message = failed(&identify_bare(&machine, &table, "150,0,250"));
    assert!(
        message.contains("bare.csv") && message.contains("cannot reach the sphere"),
        "{message}"
    );
    // The right sphere on the same bare export passes the door.
    ok(&identify_bare(&machine, &table, "100,0,250"));
    // Angles exported in radians in the _deg columns: the commanded positions turn round
    // their circle 57.3 times further than the angles say, so the reader refuses the table
    // itself, for identify and for analyze alike (no machine needed).
    let radians = dir.path().join("radians.csv");
    let text = with_column(&text, "a_deg", f64::to_radians);
    let text = with_column(&text, "c_deg", f64::to_radians);
    std::fs::write(&radians, &text).unwrap();
    let identify = failed(&mtwin(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        machine.as_os_str(),
        "--params".as_ref(),
        "location".as_ref(),
        radians.as_os_str(),
    ]));
    let analyze = failed(&mtwin(&[
        "analyze".as_ref(),
        "rtest".as_ref(),
        radians.as_os_str(),
    ]));
    for message in [identify, analyze] {
        assert!(
            message.contains("radians.csv") && message.contains("_deg` holds radians"),
            "{message}"
        );
    }

    // The sphere typed 0.3 mm off in the preamble: under tool-centre-point control the
    // commanded positions put the tip on the sphere the controller was given, so 0.3 mm is no
    // machine error (it was fitted as EX0C = 312 µm with χ²/dof 0.93 when 1 mm was allowed).
    let clean = std::fs::read_to_string(run.join("rtest.csv")).unwrap();
    let typo = dir.path().join("typo.csv");
    let line = "# sphere_mm = 100 0 250";
    assert!(clean.contains(line), "the preamble's sphere line");
    std::fs::write(&typo, clean.replacen(line, "# sphere_mm = 100.3 0 250", 1)).unwrap();
    refused_by_the_reader(
        &[
            "--machine".as_ref(),
            machine.as_os_str(),
            "--params".as_ref(),
            "location".as_ref(),
            typo.as_os_str(),
        ],
        &dir.path().join("id"),
        &["typo.csv", "0.3 mm from the sphere at 100.3 0 250 mm"],
    );
    // Deviations exported in mm in the _um columns: every reading 1000 times too small, the
    // residuals a thousandth of the noise (χ²/dof ≈ 1e-6), every estimate 1000 times too
    // small. The door refuses the fit as units.
    let mm = dir.path().join("mm.csv");
    let in_mm = ["dx_um", "dy_um", "dz_um"]
        .iter()
        .fold(clean.clone(), |t, c| with_column(&t, c, |v| v / 1000.0));
    std::fs::write(&mm, in_mm).unwrap();
    refused_by_the_door(
        &[
            "--machine".as_ref(),
            machine.as_os_str(),
            "--params".as_ref(),
            "location".as_ref(),
            mm.as_os_str(),
        ],
        &dir.path().join("id"),
        &["χ²/dof", "is below 0.01", "mm in a `_um` column"],
        "units or set-up",
    );
    // And without the commanded positions, the door refuses the fit.
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    let preamble: Vec<&str> = text.lines().filter(|l| l.starts_with('#')).collect();
    std::fs::write(
        &radians,
        preamble.join("\n") + "\n" + &drop(&rows.join("\n")),
    )
    .unwrap();
    refused_by_the_door(
        &[
            "--machine".as_ref(),
            machine.as_os_str(),
            "--params".as_ref(),
            "location".as_ref(),
            radians.as_os_str(),
        ],
        &dir.path().join("id"),
        &["EB0A: the estimate reaches", "χ²/dof"],
        "units or set-up",
    );
}

#[test]
fn one_wild_reading_is_refused_not_fitted_to_zero_plus_minus_infinity() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(&root("scenarios/trunnion5_rtest.toml"), dir.path(), "run");
    let text = std::fs::read_to_string(run.join("rtest.csv")).unwrap();
    // One reading of 1e300 µm (a logger's overflow), the rest as measured.
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let header = lines.iter().position(|l| l.starts_with("test,")).unwrap();
    let column = lines[header].split(',').position(|c| c == "dx_um").unwrap();
    let mut fields: Vec<String> = lines[header + 5].split(',').map(str::to_string).collect();
    fields[column] = "1e300".into();
    lines[header + 5] = fields.join(",");
    let table = dir.path().join("wild.csv");
    std::fs::write(&table, lines.join("\n") + "\n").unwrap();
    // Refused where it is read: no R-test probe reads 1e300 µm.
    let message = refused_by_the_reader(
        &[
            "--machine".as_ref(),
            root("models/trunnion5.urdf").as_os_str(),
            "--params".as_ref(),
            "location".as_ref(),
            table.as_os_str(),
        ],
        &dir.path().join("id"),
        &["wild.csv:", "column `dx_um`: 1e300 is beyond ±10000"],
    );
    assert!(!message.contains("inf µm"), "{message}");
}

#[test]
fn a_table_given_twice_or_a_target_beyond_the_travel_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(&root("scenarios/trunnion5_rtest.toml"), dir.path(), "run");
    let table = run.join("rtest.csv");
    // A renamed copy: the same readings twice would shrink every uncertainty by √2.
    let copy = dir.path().join("copy.csv");
    std::fs::copy(&table, &copy).unwrap();
    let out = dir.path().join("id");
    let message = failed(&mtwin(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        root("models/trunnion5.urdf").as_os_str(),
        "--params".as_ref(),
        "location".as_ref(),
        table.as_os_str(),
        copy.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]));
    assert!(
        message.contains("copy.csv") && message.contains("the same data rows as"),
        "{message}"
    );
    assert!(!out.exists());

    // A laser table whose last target is 5000 mm, on vmc3's 760 mm X.
    let run = run_into(&root("scenarios/vmc3_iso230_2.toml"), dir.path(), "laser");
    let text = std::fs::read_to_string(run.join("positioning.csv")).unwrap();
    let last = text
        .lines()
        .find_map(|l| l.strip_prefix("# targets_mm = "))
        .unwrap()
        .rsplit(", ")
        .next()
        .unwrap()
        .to_string();
    assert_eq!(last, "750");
    let far = dir.path().join("far.csv");
    let moved = text
        .replace(", 750\n", ", 5000\n")
        .replace(",750.000000,", ",5000.000000,");
    std::fs::write(&far, moved).unwrap();
    let far_text = std::fs::read_to_string(&far).unwrap();
    assert!(far_text.contains("5000."), "the test must move a target");
    let message = failed(&mtwin(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        root("models/vmc3.urdf").as_os_str(),
        "--params".as_ref(),
        "EXX:2".as_ref(),
        far.as_os_str(),
    ]));
    assert!(
        message.contains("far.csv") && message.contains("X = 5000 mm is outside the travel of X"),
        "{message}"
    );
}
