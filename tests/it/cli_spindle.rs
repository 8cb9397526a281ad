//! `mtwin analyze spindle` end to end, through the binary:
//!
//! * on what `mtwin run scenarios/vmc3_spindle.toml` writes: the JSON has exactly the keys the
//!   help documents, three segments at 2000/6000/12000 rpm, the speed series, the preferred
//!   centre first, and values equal to those computed here from the table's rows by hand;
//! * `--plot` writes well-formed SVG files named polar_*, spectrum_*, speed_* and nothing else,
//!   and a folder that cannot be made fails with nothing written;
//! * `--centres` restricts the centres (the preferred one still first) and refuses an unknown
//!   one by name;
//! * the malformed fixtures are refused with file:line, non-zero exit, nothing on stdout;
//! * a foreign export (`tests/data/spindle/foreign/`, written by an independent Python model,
//!   sampled on time with a speed ripple, CRLF, its own column order, no geometry): the values
//!   and lines agree with the closed forms of that model within stated tolerances and the
//!   report says it resampled.
//! * `discover spindle`: the JSON keys its help documents, on the foreign export; bad set-up,
//!   bearing and revolution counts refused with the file named, non-zero exit, nothing on
//!   stdout.

use crate::common::{mtwin_output as mtwin, root};
use serde_json::Value;
use std::collections::BTreeSet;
use std::f64::consts::{PI, TAU};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Output;

fn data(name: &str) -> PathBuf {
    root().join("tests/data/spindle").join(name)
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// `mtwin analyze spindle FILE EXTRA…`.
fn analyze(file: &Path, extra: &[&OsStr]) -> Output {
    let mut args: Vec<&OsStr> = vec!["analyze".as_ref(), "spindle".as_ref(), file.as_os_str()];
    args.extend_from_slice(extra);
    mtwin(&args)
}

/// `analyze spindle FILE --json EXTRA…`, which must succeed; its JSON.
fn analyze_json(file: &Path, extra: &[&OsStr]) -> Value {
    let mut args: Vec<&OsStr> = vec!["--json".as_ref()];
    args.extend_from_slice(extra);
    let output = analyze(file, &args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    serde_json::from_slice(&output.stdout).expect("JSON on stdout")
}

fn keys(value: &Value) -> BTreeSet<&str> {
    value
        .as_object()
        .unwrap_or_else(|| panic!("an object: {value}"))
        .keys()
        .map(String::as_str)
        .collect()
}

fn set<'a>(names: &[&'a str]) -> BTreeSet<&'a str> {
    names.iter().copied().collect()
}

fn number(value: &Value) -> f64 {
    value
        .as_f64()
        .unwrap_or_else(|| panic!("a number: {value}"))
}

fn array(value: &Value) -> &Vec<Value> {
    value
        .as_array()
        .unwrap_or_else(|| panic!("an array: {value}"))
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

fn range(values: &[f64]) -> f64 {
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    hi - lo
}

/// `p` without its first harmonic, for angles spread evenly over a full turn (then the least-
/// squares 1-UPR fit is `2/M Σ p cos θ`, `2/M Σ p sin θ`): the LSC residual of ISO 230-7 in the
/// limaçon model.
fn without_first_harmonic(p: &[f64], angles: &[f64]) -> Vec<f64> {
    let m = p.len() as f64;
    let a: f64 = 2.0 / m * p.iter().zip(angles).map(|(v, t)| v * t.cos()).sum::<f64>();
    let b: f64 = 2.0 / m * p.iter().zip(angles).map(|(v, t)| v * t.sin()).sum::<f64>();
    p.iter()
        .zip(angles)
        .map(|(v, t)| v - a * t.cos() - b * t.sin())
        .collect()
}

/// Panics unless `svg` is well-formed XML (quick-xml) with one `<svg>` root, all closed.
fn assert_well_formed_svg(svg: &str, name: &str) {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(svg);
    let (mut depth, mut roots) = (0usize, 0usize);
    loop {
        match reader
            .read_event()
            .unwrap_or_else(|e| panic!("{name}: not well-formed XML: {e}"))
        {
            Event::Start(e) => {
                if depth == 0 {
                    roots += 1;
                    assert_eq!(e.name().as_ref(), b"svg", "{name}: the root");
                }
                depth += 1;
            }
            Event::Empty(e) if depth == 0 => {
                roots += 1;
                assert_eq!(e.name().as_ref(), b"svg", "{name}: the root");
            }
            Event::End(_) => depth -= 1,
            Event::Eof => break,
            _ => {}
        }
    }
    assert_eq!((depth, roots), (0, 1), "{name}: one <svg> root, closed");
}

// ---------------------------------------------------------------------------------------------
// A table read by hand: the test's own reading of the CSV, to compute values independently.

struct Csv {
    /// `# key = value` lines of the preamble.
    keys: Vec<(String, String)>,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Csv {
    fn read(path: &Path) -> Csv {
        let content = std::fs::read_to_string(path).unwrap();
        let mut keys = Vec::new();
        let mut header = Vec::new();
        let mut rows = Vec::new();
        for line in content.lines() {
            let line = line.trim_end_matches('\r');
            if let Some(comment) = line.strip_prefix('#') {
                if let Some((k, v)) = comment.split_once('=') {
                    keys.push((k.trim().to_string(), v.trim().to_string()));
                }
            } else if header.is_empty() {
                header = line.split(',').map(str::to_string).collect();
            } else if !line.is_empty() {
                rows.push(line.split(',').map(str::to_string).collect());
            }
        }
        Csv { keys, header, rows }
    }

    fn key(&self, key: &str) -> &str {
        self.keys
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
            .unwrap_or_else(|| panic!("no `{key}` in the preamble"))
    }

    fn column(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column `{name}`"))
    }

    fn value(&self, row: usize, column: usize) -> f64 {
        self.rows[row][column].trim().parse().unwrap()
    }
}

/// Runs the bundled vmc3 spindle scenario into `dir/out`; returns its `spindle.csv`.
fn run_vmc3_spindle(dir: &Path) -> PathBuf {
    let out = dir.join("out");
    let scenario = root().join("scenarios/vmc3_spindle.toml");
    let output = mtwin(&[
        "run".as_ref(),
        scenario.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    out.join("spindle.csv")
}

/// Writes to `to` the preamble, the header and the rows of `from` whose revolution is below
/// `keep`, at the speeds `speeds` (as written in the table, e.g. "2000.000"; all when empty),
/// with the preamble's `revolutions` and `speeds_rpm` saying so (the reader checks them).
///
/// Why not the whole table: it keeps the test short (the full record is 5.3 MB; reading it
/// once took 77 s while the reader counted lines from the file's start for every row, a bug
/// these tests found and that is fixed). The first revolutions of each run are themselves a
/// valid record of that run.
fn first_revolutions(from: &Path, to: &Path, keep: usize, speeds: &[&str]) {
    let content = std::fs::read_to_string(from).unwrap();
    let mut lines = content.lines();
    let mut out = String::new();
    let header = loop {
        let line = lines.next().expect("a header");
        // The preamble says what the rows hold: the revolutions and speeds kept.
        if line.starts_with("# revolutions = ") {
            out += &format!("# revolutions = {keep}\n");
            continue;
        }
        if line.starts_with("# speeds_rpm = ") && !speeds.is_empty() {
            out += &format!("# speeds_rpm = {}\n", speeds.join(" "));
            continue;
        }
        out += line;
        out.push('\n');
        if !line.starts_with('#') {
            break line.split(',').collect::<Vec<_>>();
        }
    };
    let revolution = header.iter().position(|h| *h == "revolution").unwrap();
    let speed = header.iter().position(|h| *h == "speed_rpm").unwrap();
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        let kept = fields[revolution].parse::<usize>().unwrap() < keep
            && (speeds.is_empty() || speeds.contains(&fields[speed]));
        if kept {
            out += line;
            out.push('\n');
        }
    }
    std::fs::write(to, out).unwrap();
}

// ---------------------------------------------------------------------------------------------
// 1. The JSON report on mtwin's own record.

const SEGMENT_KEYS: [&str; 5] = ["setup", "speed_rpm", "revolutions", "pooled", "tests"];
const TEST_KEYS: [&str; 9] = [
    "name",
    "direction",
    "sensing",
    "probes",
    "height_mm",
    "unit",
    "values",
    "lines",
    "uncertainty",
];
const VALUE_KEYS: [&str; 11] = [
    "centre",
    "offset",
    "total_own_offset",
    "total",
    "total_own_centre",
    "synchronous",
    "asynchronous",
    "fundamental",
    "residual",
    "inner",
    "outer",
];
const LINE_KEYS: [&str; 4] = ["per_revolution", "hz", "amplitude", "synchronous"];
const ALL_CENTRES: [&str; 5] = ["PC", "LSC", "MRS", "MIC", "MCC"];

/// The centres in report order: the preferred one (ISO 230-7 Tab 1: PC for axial and face, LSC
/// for radial and tilt), then the others asked, in the order PC, LSC, MRS, MIC, MCC.
fn centre_order(direction: &str, asked: &[&'static str]) -> Vec<&'static str> {
    let preferred = match direction {
        "axial" | "face" => "PC",
        "radial" | "tilt" => "LSC",
        other => panic!("unknown direction {other}"),
    };
    std::iter::once(preferred)
        .chain(asked.iter().copied().filter(|c| *c != preferred))
        .collect()
}

fn test_named<'a>(segment: &'a Value, name: &str) -> &'a Value {
    array(&segment["tests"])
        .iter()
        .find(|t| t["name"] == name)
        .unwrap_or_else(|| panic!("no test `{name}` in {}", segment["speed_rpm"]))
}

#[test]
fn run_then_analyze_reports_the_documented_keys_and_the_values_of_the_table() {
    let dir = tempfile::tempdir().unwrap();
    let full = run_vmc3_spindle(dir.path());
    let table = dir.path().join("spindle.csv");
    first_revolutions(&full, &table, 2, &[]);
    let json = analyze_json(&table, &[]);

    assert_eq!(
        keys(&json),
        set(&[
            "samples_per_revolution",
            "segments",
            "speeds",
            "speed_shifts",
            "separations",
            "notes",
            "cautions",
            "columns_not_read",
            "setup"
        ])
    );
    // The twin's own record (micrometres of error motion, in µm): no unit caution.
    assert_eq!(json["cautions"], serde_json::json!([]));
    assert_eq!(json["samples_per_revolution"], 1024);
    // Every key the twin wrote was read; the set-up is said again.
    assert_eq!(json["setup"]["preamble_not_used"], serde_json::json!([]));
    assert_eq!(json["setup"]["machine"], "vmc3");
    assert_eq!(json["notes"], serde_json::json!([]), "on the index grid");
    assert_eq!(
        json["separations"],
        serde_json::json!([]),
        "one set-up and two probes per height: nothing to separate"
    );

    // Three segments, one per speed of the scenario, each with its 2 revolutions.
    let segments = array(&json["segments"]);
    let speeds: Vec<f64> = segments.iter().map(|s| number(&s["speed_rpm"])).collect();
    assert_eq!(speeds, [2000.0, 6000.0, 12000.0]);
    // The five probes of the nest (x1, y1 at 0, x2, y2 80 mm up, z on the axis) give these
    // tests (module docs of evaluate.rs).
    let expected_tests = [
        ("radial x1", "radial", "fixed", vec!["x1"], 0.0, "um"),
        ("radial y1", "radial", "fixed", vec!["y1"], 0.0, "um"),
        ("radial x2", "radial", "fixed", vec!["x2"], 80.0, "um"),
        ("radial y2", "radial", "fixed", vec!["y2"], 80.0, "um"),
        ("axial z", "axial", "fixed", vec!["z"], 0.0, "um"),
        (
            "radial x1+y1 rotating",
            "radial",
            "rotating",
            vec!["x1", "y1"],
            0.0,
            "um",
        ),
        (
            "radial x2+y2 rotating",
            "radial",
            "rotating",
            vec!["x2", "y2"],
            80.0,
            "um",
        ),
        ("tilt x1-x2", "tilt", "fixed", vec!["x1", "x2"], 0.0, "urad"),
        ("tilt y1-y2", "tilt", "fixed", vec!["y1", "y2"], 0.0, "urad"),
        (
            "tilt x1+y1-x2+y2 rotating",
            "tilt",
            "rotating",
            vec!["x1", "y1", "x2", "y2"],
            0.0,
            "urad",
        ),
    ];
    for segment in segments {
        assert_eq!(keys(segment), set(&SEGMENT_KEYS));
        assert_eq!(segment["setup"], "normal");
        assert_eq!(segment["revolutions"], 2);
        let tests = array(&segment["tests"]);
        assert_eq!(tests.len(), expected_tests.len());
        for (test, (name, direction, sensing, probes, height, unit)) in
            tests.iter().zip(&expected_tests)
        {
            assert_eq!(keys(test), set(&TEST_KEYS));
            assert_eq!(test["name"], *name);
            assert_eq!(test["direction"], *direction);
            assert_eq!(test["sensing"], *sensing, "{name}");
            assert_eq!(test["probes"], serde_json::json!(probes), "{name}");
            assert_eq!(number(&test["height_mm"]), *height, "{name}");
            assert_eq!(test["unit"], *unit, "{name}");
            let values = array(&test["values"]);
            let centres: Vec<&str> = values
                .iter()
                .map(|v| v["centre"].as_str().unwrap())
                .collect();
            assert_eq!(centres, centre_order(direction, &ALL_CENTRES), "{name}");
            for v in values {
                assert_eq!(keys(v), set(&VALUE_KEYS), "{name}");
                assert_eq!(array(&v["offset"]).len(), 2);
                assert_eq!(array(&v["total_own_offset"]).len(), 2);
                for key in &VALUE_KEYS[3..] {
                    assert!(number(&v[*key]) >= 0.0, "{name} {key}: {v}");
                }
            }
            // MRS is the centre of the minimum radial separation: every other centre's
            // synchronous value is at least its value (to the JSON's rounding).
            let mrs = values.iter().find(|v| v["centre"] == "MRS").unwrap();
            // The whole cloud's own MRS is no wider than the cloud about the synchronous MRS.
            assert!(
                number(&mrs["total_own_centre"]) <= number(&mrs["total"]) + 2e-6,
                "{name}: {mrs}"
            );
            for v in values {
                assert!(
                    number(&v["synchronous"]) >= number(&mrs["synchronous"]) - 2e-6,
                    "{name}: MRS is the minimum radial separation: {v} vs {mrs}"
                );
            }
            let lines = array(&test["lines"]);
            assert!(!lines.is_empty() && lines.len() <= 8, "{name}");
            for (l, next) in lines.iter().zip(lines.iter().skip(1)) {
                assert_eq!(keys(l), set(&LINE_KEYS));
                assert!(
                    number(&l["amplitude"]) >= number(&next["amplitude"]),
                    "largest first"
                );
            }
            for l in lines {
                // hz = UPR × revolutions per second, the speed of the segment.
                let hz = number(&l["per_revolution"]) * number(&segment["speed_rpm"]) / 60.0;
                assert!((number(&l["hz"]) - hz).abs() < 2e-6, "{l}");
                // 2 revolutions: lines every 1/2 UPR, the whole ones synchronous.
                let upr = number(&l["per_revolution"]);
                assert_eq!(l["synchronous"], upr.fract() == 0.0, "{l}");
            }
        }
    }

    // Values against speed: each test, its preferred centre, the three speeds.
    let series = array(&json["speeds"]);
    assert_eq!(series.len(), expected_tests.len());
    for (entry, (name, _, _, _, _, unit)) in series.iter().zip(&expected_tests) {
        assert_eq!(keys(entry), set(&["test", "unit", "points"]));
        assert_eq!(entry["test"], format!("{name} (normal)"));
        assert_eq!(entry["unit"], *unit);
        let points = array(&entry["points"]);
        assert_eq!(points.len(), 3);
        for (point, segment) in points.iter().zip(segments) {
            assert_eq!(
                keys(point),
                set(&["speed_rpm", "synchronous", "asynchronous"])
            );
            assert_eq!(point["speed_rpm"], segment["speed_rpm"]);
            let preferred = &test_named(segment, name)["values"][0];
            assert_eq!(point["synchronous"], preferred["synchronous"]);
            assert_eq!(point["asynchronous"], preferred["asynchronous"]);
        }
    }

    // The values, computed here from the table's rows. Tolerance 2e-6 (µm or µrad): the JSON's
    // rounding to 1e-6 plus floating-point noise.
    let csv = Csv::read(&table);
    let m: usize = csv.key("samples_per_revolution").parse().unwrap();
    assert_eq!(m, 1024);
    let (speed, angle) = (csv.column("speed_rpm"), csv.column("angle_deg"));
    let (x1, x2, z) = (csv.column("x1_um"), csv.column("x2_um"), csv.column("z_um"));
    // The height of the x2 station above x1 (mm), from the preamble.
    let height = |key: &str| -> f64 {
        csv.key(key)
            .split_whitespace()
            .nth(2)
            .unwrap()
            .parse()
            .unwrap()
    };
    let separation_mm = height("x2_position_mm") - height("x1_position_mm");
    assert_eq!(separation_mm, 80.0);
    for segment in segments {
        let rpm = number(&segment["speed_rpm"]);
        let rows: Vec<usize> = (0..csv.rows.len())
            .filter(|&i| csv.value(i, speed) == rpm)
            .collect();
        assert_eq!(rows.len(), 2 * m);
        let angles: Vec<f64> = rows[..m]
            .iter()
            .map(|&i| csv.value(i, angle).to_radians())
            .collect();
        // Per angle: the mean over the revolutions (synchronous) and the band (asynchronous).
        let profile = |signal: &dyn Fn(usize) -> f64| -> (Vec<f64>, f64) {
            let revolutions = rows.len() / m;
            let mut mean = vec![0.0; m];
            let mut band: f64 = 0.0;
            for (j, slot) in mean.iter_mut().enumerate() {
                let at: Vec<f64> = (0..revolutions).map(|k| signal(rows[k * m + j])).collect();
                *slot = at.iter().sum::<f64>() / revolutions as f64;
                band = band.max(range(&at));
            }
            (mean, band)
        };
        let close = |json: &Value, ours: f64, what: &str| {
            assert!(
                (number(json) - ours).abs() < 2e-6,
                "{rpm} rpm {what}: JSON {json}, by hand {ours}"
            );
        };
        // Axial z about PC: the range of the mean profile.
        let (z_mean, z_band) = profile(&|i| csv.value(i, z));
        let axial = &test_named(segment, "axial z")["values"][0];
        assert_eq!(axial["centre"], "PC");
        close(
            &axial["synchronous"],
            range(&z_mean),
            "axial z PC synchronous",
        );
        close(&axial["asynchronous"], z_band, "axial z asynchronous");
        // Radial x1 about LSC: the mean profile without its first harmonic.
        let (x1_mean, x1_band) = profile(&|i| csv.value(i, x1));
        let radial = &test_named(segment, "radial x1")["values"][0];
        assert_eq!(radial["centre"], "LSC");
        let lsc = range(&without_first_harmonic(&x1_mean, &angles));
        close(&radial["synchronous"], lsc, "radial x1 LSC synchronous");
        close(&radial["asynchronous"], x1_band, "radial x1 asynchronous");
        // Tilt x1-x2 about LSC, in µrad: (upper − lower) / L, µm / mm = mrad.
        let (tilt_mean, _) =
            profile(&|i| (csv.value(i, x2) - csv.value(i, x1)) / separation_mm * 1e3);
        let tilt = &test_named(segment, "tilt x1-x2")["values"][0];
        assert_eq!(tilt["centre"], "LSC");
        let lsc = range(&without_first_harmonic(&tilt_mean, &angles));
        close(
            &tilt["synchronous"],
            lsc,
            "tilt x1-x2 LSC synchronous (µrad)",
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Centres (the plots are in `plots.rs`).

#[test]
fn centres_restrict_the_report_and_the_preferred_comes_first() {
    // The foreign export of tests/data/spindle has axial, radial and tilt tests.
    let table = data("foreign_sea.csv");
    let json = analyze_json(&table, &["--centres".as_ref(), "LSC,MRS".as_ref()]);
    let mut directions = BTreeSet::new();
    for segment in array(&json["segments"]) {
        for test in array(&segment["tests"]) {
            let direction = test["direction"].as_str().unwrap();
            directions.insert(direction.to_string());
            let centres: Vec<&str> = array(&test["values"])
                .iter()
                .map(|v| v["centre"].as_str().unwrap())
                .collect();
            assert_eq!(
                centres,
                centre_order(direction, &["LSC", "MRS"]),
                "{}",
                test["name"]
            );
        }
    }
    assert_eq!(
        directions,
        ["axial", "radial", "tilt"]
            .map(String::from)
            .into_iter()
            .collect(),
        "axial gets PC added in front, radial and tilt have LSC first"
    );
    // The values about the centres kept are those of the report without the option.
    let all = analyze_json(&table, &[]);
    for (a, b) in array(&json["segments"]).iter().zip(array(&all["segments"])) {
        for (ta, tb) in array(&a["tests"]).iter().zip(array(&b["tests"])) {
            for va in array(&ta["values"]) {
                let vb = array(&tb["values"])
                    .iter()
                    .find(|v| v["centre"] == va["centre"])
                    .unwrap();
                assert_eq!(va, vb);
            }
        }
    }

    for bad in ["XYZ", "LSC,XYZ"] {
        let output = analyze(
            &table,
            &["--json".as_ref(), "--centres".as_ref(), bad.as_ref()],
        );
        assert!(!output.status.success(), "{bad}");
        assert!(output.stdout.is_empty());
        let stderr = text(&output.stderr);
        assert!(
            stderr.contains("--centres") && stderr.contains("\"XYZ\""),
            "{stderr}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Bad files.

/// The 1-based number of the first line of `content` for which `is_it` holds.
fn line_where(content: &str, is_it: impl Fn(&str) -> bool) -> usize {
    content
        .lines()
        .position(is_it)
        .map(|i| i + 1)
        .expect("such a line")
}

#[test]
fn malformed_tables_are_refused_with_file_and_line_and_nothing_on_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let read = |name: &str| std::fs::read_to_string(data(name)).unwrap();

    // The lines, found here in the fixtures: the header of the table without probes; the last
    // row of the short revolution (revolution 1 ends there after 7 of 8 samples); the row whose
    // angle is not above the one before it in its revolution; the row with NaN.
    let missing = read("missing_probes.csv");
    let header = line_where(&missing, |l| !l.starts_with('#'));
    let short = read("short_revolution.csv");
    let last = short.lines().count();
    let angles = read("angle_not_increasing.csv");
    let rows: Vec<(usize, f64)> = angles
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("revolution"))
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].parse().unwrap(), f[1].parse().unwrap())
        })
        .collect();
    let offender = (1..rows.len())
        .find(|&i| rows[i].0 == rows[i - 1].0 && rows[i].1 <= rows[i - 1].1)
        .unwrap();
    let angle_line = line_where(&angles, |l| l.starts_with("revolution")) + 1 + offender;
    let nan = read("nan.csv");
    let nan_line = line_where(&nan, |l| l.contains("NaN"));

    let cases = [
        ("missing_probes.csv", header, "probe"),
        ("short_revolution.csv", last, "7 samples"),
        ("angle_not_increasing.csv", angle_line, "angle_deg"),
        ("nan.csv", nan_line, "NaN"),
    ];
    for (name, line, what) in cases {
        let plots = dir.path().join(format!("plots_{name}"));
        let output = analyze(
            &data(name),
            &["--json".as_ref(), "--plot".as_ref(), plots.as_os_str()],
        );
        assert!(!output.status.success(), "{name}");
        assert_eq!(output.status.code(), Some(1), "{name}");
        assert!(output.stdout.is_empty(), "{name}: {}", text(&output.stdout));
        let stderr = text(&output.stderr);
        assert!(
            stderr.contains(&format!("{name}:{line}:")) && stderr.contains(what),
            "{name}: expected line {line} and `{what}` in: {stderr}"
        );
        assert!(!plots.exists(), "{name}: no plot folder");
    }
}

// ---------------------------------------------------------------------------------------------
// 4. A foreign export: time-sampled, resampled by the analyser, against the closed forms of an
// independent model.

mod foreign_and_discovery;
mod foreign_separations;
mod plots;

#[test]
fn a_multi_probe_layout_blind_to_harmonics_gives_no_form_or_motion_value() {
    // Three probes 120° apart see only the multiples of 3 (tests/it/spindle_chain: every
    // k ≢ 0 mod 3 from 2 up is blind). The bundled multi-probe record's motion along X has
    // 2, 3 and 4 UPR (0.10, 0.04, 0.02 µm) and its sphere 2, 3 and 7 UPR (20, 35, 12 nm):
    // with 120° probes the motion's LSC value was printed from 3 UPR alone as if it were the
    // motion's. Now both values are null with the reason, and what the seen harmonics give is
    // labelled so: 2 × 0.04 = 0.08 µm of motion and 2 × 35 nm = 0.07 µm of form, noise-free.
    let dir = tempfile::tempdir().unwrap();
    let scenario = std::fs::read_to_string(root().join("scenarios/vmc3_spindle_multiprobe.toml"))
        .unwrap()
        .replace(
            "machine = \"../models/",
            &format!("machine = \"{}/models/", root().display()),
        )
        .replace("revolutions = 20", "revolutions = 2")
        .replace("noise_nm = 1.0", "noise_nm = 0.0")
        .replace("resolution_nm = 0.1", "resolution_nm = 0.0")
        .replace("azimuth_deg = 57.29577951308232", "azimuth_deg = 120.0")
        .replace("azimuth_deg = 180.0", "azimuth_deg = 240.0");
    // Drop the fourth probe (the last block).
    let scenario = &scenario[..scenario.rfind("[[spindle.probe]]").unwrap()];
    // Runs `scenario` under `name` and analyzes it: the record, and its multi-probe separation.
    let separated = |name: &str, scenario: &str| -> (PathBuf, Value) {
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, scenario).unwrap();
        let out = dir.path().join(name);
        let output = mtwin(&[
            "run".as_ref(),
            path.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        assert!(output.status.success(), "{}", text(&output.stderr));
        let record = out.join("spindle.csv");
        let json = analyze_json(&record, &[]);
        let separation = array(&json["separations"])
            .iter()
            .find(|s| s["method"] == "multi-probe")
            .expect("a multi-probe separation")
            .clone();
        (record, separation)
    };
    let (record, separation) = separated("three_probes", scenario);
    assert_eq!(separation["probes"], serde_json::json!(["p1", "p2", "p3"]));
    // No synchronous value of the form or of any direction of the motion.
    assert!(separation["form"]["values"].is_null(), "{separation}");
    let motions = array(&separation["motion"]);
    let axes: Vec<&str> = motions
        .iter()
        .map(|m| m["axis"].as_str().unwrap())
        .collect();
    assert_eq!(axes, ["X", "Y", "rotating"]);
    for m in motions {
        assert!(m["values"].is_null(), "{m}");
        // The asynchronous motion needs no harmonic: noise-free, it is nil.
        assert_eq!(m["asynchronous_um"], 0.0, "{m}");
    }
    let why = separation["not_determined"].as_str().unwrap();
    assert!(why.contains("cannot see harmonics 2, 4, 5, 7"), "{why}");
    // The probes read the motion's 2 and 4 UPR and the form's 2 and 7 UPR there, nothing else.
    assert_eq!(
        separation["unknown"],
        serde_json::json!([2, 4, 7]),
        "{separation}"
    );
    // Over the harmonics seen (LSC first): the motion's 3 UPR and the form's, labelled so.
    let motion = number(&motions[0]["values_seen"][0]["synchronous"]);
    let form = number(&separation["form"]["values_seen"][0]["value"]);
    assert_eq!(motions[0]["values_seen"][0]["centre"], "LSC");
    assert!((motion - 0.08).abs() < 2e-4, "motion seen {motion}");
    assert!((form - 0.07).abs() < 2e-4, "form seen {form}");
    // The coefficients: null where the layout is blind (2 UPR is the first entry), the seen
    // 3 UPR of the motion along X is 0.04 µm.
    let harmonics = &motions[0]["harmonics_um"];
    assert_eq!(harmonics["from"], 2);
    assert!(harmonics["a"][0].is_null() && harmonics["b"][0].is_null());
    let (a3, b3) = (number(&harmonics["a"][1]), number(&harmonics["b"][1]));
    assert!((a3.hypot(b3) - 0.04).abs() < 1e-4, "3 UPR {a3}, {b3}");
    let printed = text(&analyze(&record, &[]).stdout);
    assert!(
        printed.contains("not determined: the probe layout cannot see harmonics 2, 4, 5, 7"),
        "{printed}"
    );

    // The control: a fourth probe at 217.7° leaves only 500 and 502 UPR blind, where the
    // probes read nothing: the values are given.
    let four = format!(
        "{scenario}[[spindle.probe]]\nname = \"p4\"\nkind = \"radial\"\nazimuth_deg = 217.72395214971282\n"
    );
    let (_, separation) = separated("four_probes", &four);
    assert_eq!(
        separation["blind"],
        serde_json::json!([500, 502]),
        "{separation}"
    );
    assert_eq!(separation["unknown"], serde_json::json!([]), "{separation}");
    assert!(separation["not_determined"].is_null(), "{separation}");
    let x = &separation["motion"][0];
    assert!(number(&x["values"][0]["synchronous"]) > 0.0, "{x}");
    assert!(x["values_seen"].is_null(), "{x}");
    // Blind 500 and 502 UPR hold no coefficient; 501 UPR does.
    let a = array(&x["harmonics_um"]["a"]);
    assert!(
        a[498].is_null() && a[500].is_null() && a[499].is_number(),
        "{}",
        a.len()
    );
}
