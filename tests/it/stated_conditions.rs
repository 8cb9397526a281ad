//! Every preamble key a writer puts in a table is read and checked against the rows (issue 42,
//! "every field read"): the R-test's `frame`, the spindle table's `revolutions`, `speeds_rpm`
//! and `setups`. Each table here is written by hand, so what it says and what its rows hold
//! are known without the code under test; a refusal names the file, the preamble line and both
//! values, exits non-zero and writes nothing.

use crate::common::mtwin_output as mtwin;
use mtwin::kinds::rtest::RtestTable;
use mtwin::kinds::spindle::table::parse;

// ---------------------------------------------------------------------------------------------
// R-test: `# frame =`.

/// An R-test table of one C circle (four poses) with `frame` on line 2 when given.
fn rtest_table(frame: Option<&str>) -> String {
    let mut text = String::from("# mtwin rtest table\n");
    if let Some(frame) = frame {
        text += &format!("# frame = {frame}\n");
    }
    text += "test,c_deg,dx_um,dy_um,dz_um\n\
             t,0,0,0,0\nt,90,1,2,0\nt,180,2,0,0\nt,270,1,-2,0\n";
    text
}

#[test]
fn an_rtest_table_in_machine_axes_reads() {
    for frame in [None, Some("machine")] {
        let table = RtestTable::parse(rtest_table(frame).as_bytes(), "r.csv").unwrap();
        assert_eq!(table.rows.len(), 4);
        // dy at the second pose, 2 µm, read as written (machine Y).
        assert!((table.rows[1].deviation.y - 2e-6).abs() < 1e-18);
    }
}

#[test]
fn an_rtest_table_in_another_frame_is_refused_at_its_frame_line() {
    let error = RtestTable::parse(rtest_table(Some("workpiece")).as_bytes(), "r.csv").unwrap_err();
    assert_eq!(error.line(), Some(2));
    let message = error.to_string();
    assert!(
        message.starts_with("r.csv:2: frame = workpiece")
            && message.contains("accepted frames: machine"),
        "{message}"
    );

    // Through the binary: non-zero exit, the file, line and frames named, no SVG written.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("tool_frame.csv");
    std::fs::write(&file, rtest_table(Some("tool"))).unwrap();
    let svg = dir.path().join("never.svg");
    let output = mtwin(&[
        "analyze".as_ref(),
        "rtest".as_ref(),
        file.as_os_str(),
        "--svg".as_ref(),
        svg.as_os_str(),
    ]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("tool_frame.csv:2")
            && stderr.contains("frame = tool")
            && stderr.contains("accepted frames: machine"),
        "{stderr}"
    );
    assert!(output.stdout.is_empty(), "no report for a refused table");
    assert!(!svg.exists(), "nothing written for a refused table");
}

#[test]
fn rtest_set_up_keys_outside_what_the_writer_writes_are_refused() {
    // `zero` decides the readings model's datum; a misspelt one was read as `each_test`.
    for (line, words) in [
        ("zero = first", "expected each_test or first_pose"),
        ("tip = round", "expected flat or point"),
        ("calibration = factory", "expected nominal or six_point"),
        ("mode = moving", "expected static or dynamic"),
        ("sphere_diameter_mm = -25.4", "expected a positive diameter"),
    ] {
        let text = rtest_table(None).replacen('\n', &format!("\n# {line}\n"), 1);
        let error = RtestTable::parse(text.as_bytes(), "r.csv").unwrap_err();
        assert_eq!(error.line(), Some(2), "{error}");
        let message = error.to_string();
        assert!(
            message.starts_with(&format!("r.csv:2: {line}")) && message.contains(words),
            "{message}"
        );
    }
    // What the writer writes reads.
    let text = rtest_table(Some("machine")).replacen(
        '\n',
        "\n# sphere_diameter_mm = 25.4\n# tip = flat\n# calibration = six_point\n# mode = static\n# zero = first_pose\n",
        1,
    );
    assert!(RtestTable::parse(text.as_bytes(), "r.csv").is_ok());
}

// ---------------------------------------------------------------------------------------------
// Spindle: `revolutions`, `speeds_rpm`, `setups`.

/// A spindle table of 8 samples per revolution, set-up `normal`, `revolutions` revolutions at
/// each of `speeds` (rpm), probe `x` reading 0.1·sample; the preamble's record keys on lines
/// 2, 3 and 4 as given. With `times`, a `time_s` column replaces `speed_rpm` (one revolution
/// takes 60/rpm s).
fn spindle_table(stated: [&str; 3], speeds: &[f64], revolutions: usize, times: bool) -> String {
    let [revs, rpm, setups] = stated;
    let mut text = format!(
        "# mtwin spindle table\n# revolutions = {revs}\n# speeds_rpm = {rpm}\n# setups = {setups}\n\
         # samples_per_revolution = 8\n"
    );
    text += if times {
        "setup,revolution,angle_deg,time_s,x_um\n"
    } else {
        "setup,revolution,angle_deg,speed_rpm,x_um\n"
    };
    let mut time = 0.0;
    let mut sample = 0;
    for &speed in speeds {
        for revolution in 0..revolutions {
            for i in 0..8 {
                let third = if times {
                    format!("{time:.6}")
                } else {
                    format!("{speed}")
                };
                text += &format!(
                    "normal,{revolution},{},{third},{:.1}\n",
                    45 * i,
                    0.1 * sample as f64
                );
                time += 60.0 / speed / 8.0;
                sample += 1;
            }
        }
    }
    text
}

#[test]
fn a_spindle_preamble_that_matches_its_rows_reads() {
    // Two revolutions at 600 and at 1200 rpm, set-up `normal`: what the preamble says.
    let text = spindle_table(["2", "600 1200", "normal"], &[600.0, 1200.0], 2, false);
    let table = parse(text.as_bytes(), "s.csv").unwrap();
    assert_eq!(table.record.len(), 2 * 2 * 8);
    // Speeds derived from the times (600 rpm: 0.1 s a revolution) match within 0.1 %.
    let text = spindle_table(["2", "600", "normal"], &[600.0], 2, true);
    let table = parse(text.as_bytes(), "s.csv").unwrap();
    assert!((table.record.speed[0] - 600.0 * std::f64::consts::TAU / 60.0).abs() < 1e-6);
}

#[test]
fn a_spindle_preamble_that_disagrees_with_its_rows_is_refused_with_both_values() {
    // Each case: the preamble line at fault and the words naming both values.
    let cases: [(String, u64, [&str; 2]); 5] = [
        (
            spindle_table(["3", "600", "normal"], &[600.0], 2, false),
            2,
            ["revolutions = 3", "has 2 revolutions"],
        ),
        (
            spindle_table(["2", "600 1200", "normal"], &[600.0], 2, false),
            3,
            ["speeds_rpm = 600 1200", "recorded at 600 rpm"],
        ),
        (
            spindle_table(["2", "1200 600", "normal"], &[600.0, 1200.0], 2, false),
            3,
            ["speeds_rpm = 1200 600", "recorded at 600 1200 rpm"],
        ),
        // 660 rpm stated, 600 rpm in the times: 10 %, far beyond the 0.1 % tolerance.
        (
            spindle_table(["2", "660", "normal"], &[600.0], 2, true),
            3,
            ["speeds_rpm = 660", "recorded at 600 rpm"],
        ),
        (
            spindle_table(["2", "600", "normal reversed"], &[600.0], 2, false),
            4,
            ["setups = normal reversed", "`normal`"],
        ),
    ];
    for (text, line, words) in cases {
        let error = parse(text.as_bytes(), "s.csv").unwrap_err();
        let message = error.to_string();
        assert_eq!(error.line(), Some(line), "{message}");
        assert!(message.starts_with(&format!("s.csv:{line}: ")), "{message}");
        for w in words {
            assert!(message.contains(w), "`{w}` missing: {message}");
        }
    }
}

#[test]
fn analyze_spindle_refuses_a_preamble_that_disagrees_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("three_said.csv");
    std::fs::write(
        &file,
        spindle_table(["3", "600", "normal"], &[600.0], 2, false),
    )
    .unwrap();
    let plots = dir.path().join("plots");
    let output = mtwin(&[
        "analyze".as_ref(),
        "spindle".as_ref(),
        file.as_os_str(),
        "--plot".as_ref(),
        plots.as_os_str(),
    ]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("three_said.csv:2")
            && stderr.contains("revolutions = 3")
            && stderr.contains("has 2 revolutions"),
        "{stderr}"
    );
    assert!(output.stdout.is_empty());
    assert!(!plots.exists(), "nothing written for a refused table");
    assert!(file.exists(), "the table itself is left alone");
}

// ---------------------------------------------------------------------------------------------
// Ball-bar: `first_direction`.

#[test]
fn a_ballbar_first_direction_that_the_rows_contradict_is_refused() {
    use mtwin::kinds::ballbar::BallbarTable;
    let table = |first: &str, rows: &str| {
        format!(
            "# mtwin ballbar table\n# plane = XY\n# first_direction = {first}\n\
             direction,angle_deg,deviation_um,time_s\n{rows}"
        )
    };
    let ccw_then_cw = "ccw,0,1,0.0\nccw,90,1,0.1\ncw,90,1,0.2\ncw,0,1,0.3\n";
    assert!(BallbarTable::parse(table("ccw", ccw_then_cw).as_bytes(), "b.csv").is_ok());
    let error = BallbarTable::parse(table("cw", ccw_then_cw).as_bytes(), "b.csv").unwrap_err();
    assert_eq!(error.line(), Some(3));
    assert!(
        error.to_string().starts_with(
            "b.csv:3: first_direction = cw in the preamble, but the first reading (line 5) runs ccw"
        ),
        "{error}"
    );
    // Rows not in time order: the earliest reading decides (cw at 0.0 s, on the last line).
    let cw_first_in_time = "ccw,0,1,0.2\nccw,90,1,0.3\ncw,90,1,0.1\ncw,0,1,0.0\n";
    assert!(BallbarTable::parse(table("cw", cw_first_in_time).as_bytes(), "b.csv").is_ok());
    let error =
        BallbarTable::parse(table("ccw", cw_first_in_time).as_bytes(), "b.csv").unwrap_err();
    assert!(
        error.to_string().contains("first reading in time runs cw"),
        "{error}"
    );
}

// ---------------------------------------------------------------------------------------------
// Keys that describe the set-up: read, checked for their form, said again by the report.

#[test]
fn the_spindle_set_up_keys_are_checked_and_said_again() {
    // A good table with the set-up's description and an unknown key.
    let good = spindle_table(["2", "600", "normal"], &[600.0], 2, true).replacen(
        "# mtwin spindle table\n",
        "# mtwin spindle table\n# machine = vmc3\n# artefact = sphere 25.4 mm\n\
         # x_mm = 380\n# s_deg = 0\n# operator = A. N. Other\n",
        1,
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.csv");
    std::fs::write(&path, &good).unwrap();
    let out = mtwin(&[
        "analyze".as_ref(),
        "spindle".as_ref(),
        path.as_os_str(),
        "--json".as_ref(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["setup"]["machine"], "vmc3");
    assert_eq!(report["setup"]["axes"], "x 380 mm, s 0°");
    assert_eq!(
        report["setup"]["preamble_not_used"],
        serde_json::json!(["operator"])
    );
    // Wrong forms are refused at their line.
    for (from, to, expected) in [
        (
            "# x_mm = 380",
            "# x_mm = far",
            "x_mm = far: expected a finite number",
        ),
        (
            "# artefact = sphere 25.4 mm",
            "# artefact =",
            "artefact = : expected a description",
        ),
        (
            "# operator = A. N. Other",
            "# reversed_setup = turned 180 deg",
            "reversed_setup defines a reversed set-up, but no row is in one",
        ),
    ] {
        let bad = good.replace(from, to);
        let error = parse(bad.as_bytes(), "s.csv").unwrap_err().to_string();
        assert!(
            error.starts_with("s.csv:") && error.contains(expected),
            "{to}: {error}"
        );
    }
}

#[test]
fn the_rtest_report_says_its_set_up() {
    let text = rtest_table(Some("machine")).replacen(
        "# frame = machine\n",
        "# frame = machine\n# machine = trunnion5\n# sphere_mm = 100 0 250\n# probe_serial = 7\n",
        1,
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("r.csv");
    std::fs::write(&path, &text).unwrap();
    let out = mtwin(&["analyze".as_ref(), "rtest".as_ref(), path.as_os_str()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let printed = String::from_utf8_lossy(&out.stdout);
    assert!(
        printed.contains("Set-up: machine trunnion5, sphere at (100, 0, 250) mm, frame machine."),
        "{printed}"
    );
    assert!(
        printed.contains("preamble (unknown to this reader): probe_serial."),
        "{printed}"
    );
    // A sphere position that is not three numbers is refused at its line.
    let bad = text.replace("100 0 250", "100 0");
    let error = RtestTable::parse(bad.as_bytes(), "r.csv")
        .unwrap_err()
        .to_string();
    assert!(
        error.starts_with("r.csv:4: sphere_mm = 100 0: expected three numbers"),
        "{error}"
    );
}
