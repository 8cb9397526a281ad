//! A ball-bar table carries its test conditions (plane, radius, feed) in a `# key = value`
//! preamble; the analyses take them from there, refuse a flag that disagrees (naming both
//! values), read a real-style file without a preamble from flags, and check feed ÷ radius
//! against what the angles and times imply.

use crate::common::mtwin_output as mtwin;
use std::path::{Path, PathBuf};
use std::process::Output;

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The squareness lesson's table: a 100 mm circle in XY at 2000 mm/min, 100 Hz.
fn lesson_table(dir: &Path) -> PathBuf {
    let scenario = format!(
        "{}/scenarios/teach_squareness_ballbar.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let out = mtwin(&["run", &scenario, "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    dir.join("ballbar_xy.csv")
}

#[test]
fn the_table_says_its_conditions_and_the_analysis_uses_them() {
    let dir = tempfile::tempdir().unwrap();
    let table = lesson_table(dir.path());
    let text = std::fs::read_to_string(&table).unwrap();
    // The preamble, as the scenario states the test (teach_squareness_ballbar.toml).
    for line in [
        "# plane = XY\n",
        "# radius_mm = 100\n",
        "# feed_mm_per_min = 2000\n",
        "# sample_rate_hz = 100\n",
        "# first_direction = ccw\n",
    ] {
        assert!(text.contains(line), "{line} in\n{}", &text[..300]);
    }
    let path = table.to_str().unwrap();
    let bare = mtwin(&["analyze", "ballbar", path, "--json"]);
    assert!(bare.status.success(), "{}", stderr(&bare));
    let json: serde_json::Value = serde_json::from_slice(&bare.stdout).unwrap();
    assert_eq!(json["plane"], "XY");
    assert_eq!(json["radius_mm"], 100.0);
    assert_eq!(json["feed_mm_per_min"], 2000.0);
    // Flags that agree change nothing.
    let agreeing = mtwin(&[
        "analyze",
        "ballbar",
        path,
        "--json",
        "--plane",
        "XY",
        "--radius-mm",
        "100",
        "--feed-mm-per-min",
        "2000",
    ]);
    assert_eq!(agreeing.stdout, bare.stdout);
}

#[test]
fn a_flag_that_disagrees_with_the_file_is_refused_naming_both_values() {
    let dir = tempfile::tempdir().unwrap();
    let table = lesson_table(dir.path());
    let path = table.to_str().unwrap();
    for (flag, value, expected) in [
        ("--radius-mm", "150", "--radius-mm 150 disagrees with"),
        (
            "--feed-mm-per-min",
            "1000",
            "--feed-mm-per-min 1000 disagrees with",
        ),
        ("--plane", "YZ", "--plane YZ disagrees with"),
    ] {
        for verb in ["analyze", "discover"] {
            let out = mtwin(&[verb, "ballbar", path, flag, value]);
            assert!(!out.status.success(), "{verb} {flag} {value}");
            let message = stderr(&out);
            assert!(message.contains(expected), "{message}");
            let stated = match flag {
                "--radius-mm" => "radius_mm = 100",
                "--feed-mm-per-min" => "feed_mm_per_min = 2000",
                _ => "plane = XY",
            };
            assert!(message.contains(stated), "{message}");
        }
    }
}

/// The table as another instrument's export might give it: no conditions in it, a free-text
/// comment, times to 10 ms and angles to 0.01°.
fn foreign(table: &Path, dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(table).unwrap();
    let mut out = String::from("# exported by a ball-bar program, 2026-11-25\n");
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let fields: Vec<&str> = line.split(',').collect();
        if fields[0] == "direction" {
            out += line;
        } else {
            let angle: f64 = fields[1].parse().unwrap();
            let time: f64 = fields[3].parse().unwrap();
            out += &format!(
                "{},{:.2},{},{:.2}",
                fields[0],
                angle.min(359.994),
                fields[2],
                time
            );
        }
        out.push('\n');
    }
    let path = dir.join("foreign.csv");
    std::fs::write(&path, out).unwrap();
    path
}

#[test]
fn a_file_without_conditions_reads_with_flags_and_the_data_check_their_ratio() {
    let dir = tempfile::tempdir().unwrap();
    let table = lesson_table(dir.path());
    let foreign = foreign(&table, dir.path());
    let path = foreign.to_str().unwrap();
    let missing = mtwin(&["analyze", "ballbar", path]);
    assert!(!missing.status.success());
    assert!(
        stderr(&missing).contains("--plane XY|YZ|ZX --radius-mm R --feed-mm-per-min F"),
        "{}",
        stderr(&missing)
    );
    let with = |radius: &str, feed: &str| {
        mtwin(&[
            "analyze",
            "ballbar",
            path,
            "--plane",
            "XY",
            "--radius-mm",
            radius,
            "--feed-mm-per-min",
            feed,
        ])
    };
    let right = with("100", "2000");
    assert!(right.status.success(), "{}", stderr(&right));
    // The times checked the flags: no caution.
    assert!(!String::from_utf8_lossy(&right.stdout).contains("CAUTION"));
    // 2000 mm/min on 100 mm is 0.3333 rad/s; the rounded times and angles keep it well inside
    // the 1 % the check allows. A feed 5 % off is refused with the feed the data imply.
    let off = with("100", "2100");
    assert!(!off.status.success());
    let message = stderr(&off);
    assert!(
        message.contains("gives a feed of 2000.0 mm/min"),
        "{message}"
    );
    assert!(message.contains("0.3333 rad/s"), "{message}");
    // So is a wrong radius at the right feed (the XY table relabelled as 150 mm): the data
    // name the radius that fits.
    let wrong_radius = with("150", "2000");
    assert!(!wrong_radius.status.success());
    let message = stderr(&wrong_radius);
    assert!(message.contains("a radius of 100.000 mm"), "{message}");
}

#[test]
fn numeric_flags_take_a_minus_and_get_the_range_message() {
    let dir = tempfile::tempdir().unwrap();
    let table = lesson_table(dir.path());
    let out = mtwin(&[
        "analyze",
        "ballbar",
        table.to_str().unwrap(),
        "--feed-mm-per-min",
        "-1000",
    ]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("--feed-mm-per-min must be a positive number, got -1000"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_preamble_value_of_the_wrong_form_names_the_file_line_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.csv");
    std::fs::write(
        &path,
        "# plane = XY\n# radius_mm = 1OO\ndirection,angle_deg,deviation_um\nccw,0,1\n",
    )
    .unwrap();
    let out = mtwin(&["analyze", "ballbar", path.to_str().unwrap()]);
    assert!(!out.status.success());
    let message = stderr(&out);
    assert!(
        message.contains("bad.csv:2: radius_mm = 1OO: expected a finite number"),
        "{message}"
    );
}

/// The same export without `time_s`: nothing in the file can check the flags, and the report
/// says so (a wrong radius would scale every figure unseen).
#[test]
fn a_file_without_conditions_or_times_says_its_conditions_are_unchecked() {
    let dir = tempfile::tempdir().unwrap();
    let table = lesson_table(dir.path());
    let foreign = foreign(&table, dir.path());
    let untimed: String = std::fs::read_to_string(&foreign)
        .unwrap()
        .lines()
        .map(|l| match l.rsplit_once(',') {
            Some((kept, _)) if !l.starts_with('#') => format!("{kept}\n"),
            _ => format!("{l}\n"),
        })
        .collect();
    assert!(
        untimed.contains("direction,angle_deg,deviation_um\n"),
        "{}",
        &untimed[..200]
    );
    let path = dir.path().join("untimed.csv");
    std::fs::write(&path, untimed).unwrap();
    let flags = [
        "--plane",
        "XY",
        "--radius-mm",
        "150",
        "--feed-mm-per-min",
        "2000",
    ];
    let mut args = vec!["analyze", "ballbar", path.to_str().unwrap()];
    args.extend(flags);
    let out = mtwin(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("CAUTION: the plane, radius and feed came from the flags, the file having no preamble: the file has no time_s, so nothing in it could check them"),
        "{text}"
    );
    args.push("--json");
    let json: serde_json::Value = serde_json::from_slice(&mtwin(&args).stdout).unwrap();
    assert_eq!(json["cautions"].as_array().unwrap().len(), 1);
    // The twin's own table (preamble and times): no caution.
    let own = mtwin(&["analyze", "ballbar", table.to_str().unwrap(), "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&own.stdout).unwrap();
    assert_eq!(json["cautions"], serde_json::json!([]));
}
