//! `mtwin dataset`: determinism across runs, shard layouts and thread counts; resumption after
//! a kill; the truth in `cases` against `mtwin run`'s truth.json for the same case; the
//! Parquet schema read back, with each column's unit in its field metadata; bad priors
//! refused before anything is written; and, in `dataset/robust.rs`, concurrent makers of one
//! shard and the folder refusals.

mod robust;

use crate::common::mtwin;
use parquet::file::reader::{FileReader, SerializedFileReader};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const VOLUMETRIC: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/scenarios/vmc3_dataset_volumetric.toml"
);
const BALLBAR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/scenarios/vmc3_dataset_ballbar.toml"
);

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Every file under `dir` (relative path → bytes).
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let relative = p.strip_prefix(root).unwrap().to_string_lossy().into_owned();
                out.insert(relative, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// One row: its split (from the path) and its columns' values.
type Row = (String, serde_json::Map<String, serde_json::Value>);

/// Every row of `table`, sorted (by split, then as printed: rows start with their case_id).
fn rows(dir: &Path, table: &str) -> Vec<Row> {
    use parquet::record::Field;
    let mut out = Vec::new();
    for (relative, _) in files(&dir.join(table)) {
        let split = relative
            .split('/')
            .find_map(|p| p.strip_prefix("split="))
            .unwrap()
            .to_string();
        let file = std::fs::File::open(dir.join(table).join(&relative)).unwrap();
        let reader = SerializedFileReader::new(file).unwrap();
        for row in reader.get_row_iter(None).unwrap() {
            let row = row.unwrap();
            let values: serde_json::Map<String, serde_json::Value> = row
                .get_column_iter()
                .map(|(name, field)| {
                    let value = match field {
                        Field::Long(v) => serde_json::json!(v),
                        Field::Double(v) => serde_json::json!(v),
                        Field::Str(v) => serde_json::json!(v),
                        Field::Null => serde_json::Value::Null,
                        other => panic!("{name}: unexpected {other:?}"),
                    };
                    (name.clone(), value)
                })
                .collect();
            out.push((split.clone(), values));
        }
    }
    out.sort_by_key(|(split, values)| {
        (
            split.clone(),
            values["case_id"].as_i64(),
            serde_json::to_string(values).unwrap(),
        )
    });
    out
}

/// The rows of case `k`.
fn of_case(rows: &[Row], k: usize) -> Vec<&Row> {
    rows.iter()
        .filter(|(_, r)| r["case_id"] == k as i64)
        .collect()
}

fn dataset(scenario: &str, out: &Path, extra: &[&str]) -> String {
    let mut args = vec!["dataset", scenario, "--out", path(out)];
    args.extend(extra);
    mtwin(&args)
}

#[test]
fn the_same_command_gives_the_same_bytes_and_layouts_give_the_same_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b, c, d) = (
        tmp.path().join("a"),
        tmp.path().join("b"),
        tmp.path().join("c"),
        tmp.path().join("d"),
    );
    let one = ["--count", "24", "--shards", "1", "--threads", "1"];
    dataset(VOLUMETRIC, &a, &one);
    dataset(
        VOLUMETRIC,
        &b,
        &["--count", "24", "--shards", "1", "--threads", "4"],
    );
    assert_eq!(files(&a), files(&b), "one thread and four: the same bytes");

    dataset(
        VOLUMETRIC,
        &c,
        &["--count", "24", "--shards", "4", "--threads", "2"],
    );
    for shard in [2, 0, 3, 1] {
        let printed = dataset(
            VOLUMETRIC,
            &d,
            &["--count", "24", "--shard", &format!("{shard}/4")],
        );
        assert_eq!(printed.contains("complete"), shard == 1, "{printed}");
    }
    assert_eq!(
        files(&c),
        files(&d),
        "four shards in one process or in four"
    );

    // The card and the manifest count each split as the cases table holds it.
    let cases = rows(&a, "cases");
    let test = cases.iter().filter(|(split, _)| split == "test").count();
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(a.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(
        manifest["split_counts"],
        serde_json::json!({ "train": 24 - test, "test": test })
    );
    let card = std::fs::read_to_string(a.join("README.md")).unwrap();
    let counts = format!("{} cases in `train`, {test} in `test`.", 24 - test);
    assert!(card.contains(&counts), "{counts} not in the card");
    assert!(test > 0 && test < 24, "a fifth of 24 cases: {test} in test");

    for table in ["cases", "volumetric"] {
        let (one_shard, four_shards) = (rows(&a, table), rows(&c, table));
        assert_eq!(
            one_shard.len(),
            if table == "cases" { 24 } else { 24 * 225 }
        );
        assert_eq!(one_shard, four_shards, "{table}: 1 shard against 4");
    }
}

#[test]
fn a_killed_run_resumes_to_the_uninterrupted_result() {
    let tmp = tempfile::tempdir().unwrap();
    let (whole, resumed) = (tmp.path().join("whole"), tmp.path().join("resumed"));
    let args = ["--count", "1200", "--shards", "12", "--threads", "1"];
    dataset(VOLUMETRIC, &whole, &args);

    let mut child = Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .args(["dataset", VOLUMETRIC, "--out", path(&resumed)])
        .args(args)
        .spawn()
        .unwrap();
    let records = resumed.join("_shards");
    // A record is written under a hidden temporary name and renamed into place: only the
    // visible names are recorded shards (counting the temporary one raced the kill).
    let recorded = || {
        std::fs::read_dir(&records).map_or(0, |d| {
            d.flatten()
                .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
                .count()
        })
    };
    let started = std::time::Instant::now();
    while recorded() < 2 && started.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let done = recorded();
    assert!(
        (2..12).contains(&done),
        "the run should be killed part-way ({done} of 12 shards recorded)"
    );
    assert!(!resumed.join("manifest.json").exists());

    let printed = dataset(VOLUMETRIC, &resumed, &args);
    assert!(
        printed.contains(&format!("{done} shard(s) already complete")),
        "{printed}"
    );
    let mut left = files(&resumed);
    left.retain(|name, _| !name.starts_with(".tmp"));
    assert_eq!(left, files(&whole), "resumed = uninterrupted");

    // A damaged shard (a file changed after it was recorded) is made again.
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(records.join("shard-00005-of-00012.json")).unwrap())
            .unwrap();
    let file = resumed.join(record["files"][0]["path"].as_str().unwrap());
    std::fs::write(&file, b"not parquet").unwrap();
    let printed = dataset(VOLUMETRIC, &resumed, &args);
    assert!(
        printed.contains("11 shard(s) already complete"),
        "{printed}"
    );
    assert_eq!(files(&resumed), files(&whole));
}

/// The value of `terms[key]` (or `terms[key][index]`) of `name` in truth.json.
fn truth_term(truth: &serde_json::Value, name: &str, key: &str, index: Option<usize>) -> f64 {
    let term = &truth["errors"][name]["terms"][key];
    match index {
        Some(i) => term[i].as_f64(),
        None => term.as_f64(),
    }
    .unwrap_or_else(|| panic!("{name}.{key} missing from truth.json"))
}

#[test]
fn cases_hold_the_truth_that_mtwin_run_writes_for_the_same_case() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("set");
    dataset(VOLUMETRIC, &out, &["--count", "20", "--shards", "2"]);
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap();
    let parameters = manifest["parameters"].as_array().unwrap();
    // 3 positioning × (3 + lost motion) + 6 straightness × 4 + 9 angular × 2 + 3 squareness.
    assert_eq!(
        parameters.len(),
        12 + 24 + 18 + 3,
        "21 geometric errors in 57 values"
    );
    let cases = rows(&out, "cases");
    for k in [0usize, 7, 19] {
        let folder = tmp.path().join(format!("case{k}"));
        dataset(VOLUMETRIC, &folder, &["--case", &k.to_string()]);
        let truth: serde_json::Value =
            serde_json::from_slice(&std::fs::read(folder.join("truth.json")).unwrap()).unwrap();
        let case: serde_json::Value =
            serde_json::from_slice(&std::fs::read(folder.join("case.json")).unwrap()).unwrap();
        assert_eq!(
            truth["seed"], case["case_seed"],
            "the case's scenario has its seed"
        );
        let row = of_case(&cases, k)[0];
        assert_eq!(row.0, case["split"].as_str().unwrap());
        for parameter in parameters {
            // errors.EXX.polynomial_um[1] → EXX, polynomial_um, 1
            let path = parameter["path"].as_str().unwrap();
            let column = parameter["column"].as_str().unwrap();
            let mut parts = path.split('.').skip(1);
            let name = parts.next().unwrap();
            let key = parts.next().unwrap();
            let (key, index) = match key.split_once('[') {
                Some((k, i)) => (k, Some(i.trim_end_matches(']').parse().unwrap())),
                None => (key, None),
            };
            let drawn = case["values"][column].as_f64().unwrap();
            let written = truth_term(&truth, name, key, index);
            // truth.json writes 12 significant digits.
            assert!(
                (drawn - written).abs() <= 1e-11 * drawn.abs().max(1e-300),
                "case {k} {path}: cases {drawn}, truth.json {written}"
            );
            // case.json is read back by serde_json, whose default float parser may be one
            // unit in the last place off; the Parquet double is the draw itself.
            let stored = row.1[column].as_f64().unwrap();
            assert!(
                (stored - drawn).abs() <= 2.0 * f64::EPSILON * drawn.abs(),
                "case {k}: {column}: Parquet {stored}, case.json {drawn}"
            );
        }
        // The case's map in the dataset is its volumetric.csv, row for row.
        let csv = std::fs::read_to_string(folder.join("volumetric.csv")).unwrap();
        let ours: Vec<Vec<f64>> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        let table = rows(&out, "volumetric");
        let in_set = of_case(&table, k);
        assert_eq!(in_set.len(), ours.len());
        let columns = ["x_mm", "y_mm", "z_mm", "dx_um", "dy_um", "dz_um"];
        let mut theirs: Vec<Vec<f64>> = in_set
            .iter()
            .map(|(_, r)| columns.iter().map(|c| r[*c].as_f64().unwrap()).collect())
            .collect();
        let mut ours = ours;
        let order = |a: &Vec<f64>, b: &Vec<f64>| a.partial_cmp(b).unwrap();
        theirs.sort_by(order);
        ours.sort_by(order);
        assert_eq!(
            theirs, ours,
            "case {k}: the map in the dataset is its volumetric.csv"
        );
    }
}

#[test]
fn the_parquet_files_have_the_documented_schema_units_and_row_counts() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("bb");
    dataset(BALLBAR, &out, &["--count", "6", "--shards", "1"]);
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap();
    for file in manifest["files"].as_array().unwrap() {
        let p = out.join(file["path"].as_str().unwrap());
        let reader = SerializedFileReader::new(std::fs::File::open(&p).unwrap()).unwrap();
        let metadata = reader.metadata();
        assert_eq!(
            metadata.file_metadata().num_rows() as u64,
            file["rows"].as_u64().unwrap()
        );
        let schema = metadata.file_metadata().schema_descr();
        let first = schema.column(0);
        assert_eq!(first.name(), "case_id");
        assert_eq!(first.physical_type(), parquet::basic::Type::INT64);
        let kv = metadata.file_metadata().key_value_metadata().unwrap();
        let get = |key: &str| {
            kv.iter()
                .find(|e| e.key == key)
                .and_then(|e| e.value.clone())
                .unwrap()
        };
        assert_eq!(get("mtwin.seed"), "23");
        let units: serde_json::Value = serde_json::from_str(&get("mtwin.units")).unwrap();
        if file["table"] == "cases" {
            assert_eq!(units["servo_X_kv_per_s"], "1/s");
            assert_eq!(units["EXX_polynomial_um_1"], "µm/mm");
            assert_eq!(units["ballbar_noise_um"], "µm");
        } else {
            assert_eq!(file["table"], "ballbar_xy");
            assert_eq!(units["deviation_um"], "µm");
            let names: Vec<String> = (0..schema.num_columns())
                .map(|i| schema.column(i).name().to_string())
                .collect();
            for column in [
                "plane",
                "radius_mm",
                "feed_mm_per_min",
                "direction",
                "angle_deg",
                "deviation_um",
                "time_s",
            ] {
                assert!(names.iter().any(|n| n == column), "{column} in {names:?}");
            }
        }
    }
    // The split is by the drawn X gain: test exactly when kv_X > 36/s.
    for (split, row) in rows(&out, "cases") {
        let kv = row["servo_X_kv_per_s"].as_f64().unwrap();
        assert_eq!(split == "test", kv > 36.0, "{row:?}");
    }
}

/// A copy of the volumetric dataset scenario in `dir` with `edit` applied, its machine path
/// absolute.
fn edited(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(VOLUMETRIC).unwrap().replace(
        "../models/vmc3.urdf",
        concat!(env!("CARGO_MANIFEST_DIR"), "/models/vmc3.urdf"),
    );
    let file = dir.join("bad.toml");
    std::fs::write(&file, edit(text)).unwrap();
    file
}

#[test]
fn bad_priors_are_refused_at_their_line_before_anything_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let cases: [(&str, &str, &str, usize); 6] = [
        (
            "\"errors.EC0Y.constant_urad\" = { normal = [0.0, 25.0], bounds = [-80.0, 80.0] }",
            "\"errors.EC0Y.constant_urad\" = { normal = [0.0, -25.0] }",
            "positive standard deviation",
            48,
        ),
        (
            "\"errors.EC0Y.constant_urad\" = { normal = [0.0, 25.0], bounds = [-80.0, 80.0] }",
            "\"errors.EC0Y.constant_urad\" = { normal = [0.0, 25.0], bounds = [10.0, 80.0] }",
            "exclude",
            48,
        ),
        (
            "\"errors.EC0Y.constant_urad\" = { normal = [0.0, 25.0], bounds = [-80.0, 80.0] }",
            "\"errors.EQQ.constant_urad\" = { normal = [0.0, 25.0] }",
            "EQQ",
            48,
        ),
        (
            "\"errors.EC0Y.constant_urad\" = { normal = [0.0, 25.0], bounds = [-80.0, 80.0] }",
            "\"volumetric.spacing_mm\" = { fixed = 2.0 }",
            "spacing_mm",
            48,
        ),
        (
            "family = \"squareness\"",
            "family = \"squarenes\"",
            "unknown family",
            42,
        ),
        (
            "test_fraction = 0.2 ",
            "test_fraction = 1.5 ",
            "test_fraction",
            23,
        ),
    ];
    for (from, to, expected, line) in cases {
        let file = edited(tmp.path(), |t| {
            assert!(t.contains(from), "{from}");
            t.replace(from, to)
        });
        let out = tmp.path().join("out");
        let output = Command::new(env!("CARGO_BIN_EXE_mtwin"))
            .args(["dataset", path(&file), "--count", "4", "--out", path(&out)])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{to}: accepted");
        assert!(stderr.contains(expected), "{to}: {stderr}");
        assert!(
            stderr.contains(&format!("bad.toml:{line}:")),
            "{to}: line {line}? {stderr}"
        );
        assert!(!out.exists(), "{to}: nothing is written");
    }
    let file = edited(tmp.path(), |t| {
        t.split("\n[dataset]\n").next().unwrap().to_string()
    });
    let output = Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .args([
            "dataset",
            path(&file),
            "--count",
            "4",
            "--out",
            path(&tmp.path().join("o")),
        ])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&output.stderr).contains("no [dataset] section"));
    for shard in ["4/4", "x/4", "1"] {
        let output = Command::new(env!("CARGO_BIN_EXE_mtwin"))
            .args(["dataset", VOLUMETRIC, "--count", "8", "--shard", shard])
            .args(["--out", path(&tmp.path().join("o"))])
            .output()
            .unwrap();
        assert!(!output.status.success(), "--shard {shard}");
        assert!(!tmp.path().join("o").join("manifest.json").exists());
    }
}

#[test]
fn a_split_that_leaves_a_split_empty_is_refused_before_anything_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let ballbar = std::fs::read_to_string(BALLBAR).unwrap().replace(
        "../models/vmc3.urdf",
        concat!(env!("CARGO_MANIFEST_DIR"), "/models/vmc3.urdf"),
    );
    let refused = |text: &str, count: &str, expected: &str, line: Option<usize>| {
        let file = tmp.path().join("split.toml");
        std::fs::write(&file, text).unwrap();
        let out = tmp.path().join("out");
        let output = Command::new(env!("CARGO_BIN_EXE_mtwin"))
            .args([
                "dataset",
                path(&file),
                "--count",
                count,
                "--out",
                path(&out),
            ])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "accepted: {expected}");
        assert!(stderr.contains(expected), "{stderr}");
        if let Some(line) = line {
            assert!(stderr.contains(&format!("split.toml:{line}:")), "{stderr}");
        }
        assert!(!out.exists(), "nothing is written: {expected}");
    };
    // kv_per_s is bounded to 25 … 42 1/s: above 45 no case can be in `test`.
    let text = ballbar.replace("test_above = 36.0", "test_above = 45.0");
    refused(
        &text,
        "4",
        "kv_per_s > 45 leaves `test` empty: its prior reaches 25 … 42",
        Some(29),
    );
    // Below the lower bound every case is in `test`.
    let text = ballbar.replace("test_above = 36.0", "test_above = 20.0");
    refused(&text, "4", "leaves `train` empty", Some(29));
    // Within the reach, but no kv of the section's 200 cases is above 41.9 (4.3 sd out, a
    // chance of 1e-5 a case): the cases themselves are counted before any runs.
    let text = ballbar.replace("test_above = 36.0", "test_above = 41.9");
    refused(
        &text,
        "4",
        "dataset.split_by: of the 200 cases, none falls in `test` with the threshold",
        Some(29),
    );
    // Without a count in the section, the count asked for is.
    let text = text.replace("count = 200\n", "");
    refused(
        &text,
        "4",
        "--count 4: of the 4 cases, none falls in `test` with the threshold",
        None,
    );
}

#[test]
fn readers_find_units_per_column_numbers_for_the_centre_and_an_integer_shard_key() {
    use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("bb");
    dataset(BALLBAR, &out, &["--count", "4", "--shards", "1"]);
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap();
    // The units the column names and the priors' keys state (README: `_um` µm, `_mm` mm,
    // `_mm_per_min` mm/min, `_per_s` 1/s, a polynomial's coefficient 1 of a µm error µm/mm).
    let expected: [(&str, &str, Option<&str>); 9] = [
        ("cases", "case_id", None),
        ("cases", "servo_X_kv_per_s", Some("1/s")),
        ("cases", "EXX_polynomial_um_1", Some("µm/mm")),
        ("cases", "ballbar_noise_um", Some("µm")),
        ("ballbar_xy", "case_id", None),
        ("ballbar_xy", "deviation_um", Some("µm")),
        ("ballbar_xy", "radius_mm", Some("mm")),
        ("ballbar_xy", "feed_mm_per_min", Some("mm/min")),
        ("ballbar_xy", "centre_y_mm", Some("mm")),
    ];
    for file in manifest["files"].as_array().unwrap() {
        let relative = file["path"].as_str().unwrap();
        // `shard=0`, not `shard=00000`: what DuckDB, polars and pyarrow type as a number.
        let shard = relative
            .split('/')
            .find_map(|p| p.strip_prefix("shard="))
            .unwrap();
        assert_eq!(shard, "0", "{relative}");
        let reader = ParquetRecordBatchReaderBuilder::try_new(
            std::fs::File::open(out.join(relative)).unwrap(),
        )
        .unwrap();
        let schema = reader.schema();
        for (table, column, unit) in expected {
            if file["table"] != table {
                continue;
            }
            let field = schema.field_with_name(column).unwrap();
            assert_eq!(
                field.metadata().get("unit").map(String::as_str),
                unit,
                "{table}.{column}"
            );
        }
        if file["table"] == "ballbar_xy" {
            assert!(schema.field_with_name("centre_mm").is_err());
            for axis in ["x", "y", "z"] {
                let field = schema
                    .field_with_name(&format!("centre_{axis}_mm"))
                    .unwrap();
                assert_eq!(field.data_type(), &arrow_schema::DataType::Float64);
            }
            assert_eq!(
                schema.field_with_name("plane").unwrap().data_type(),
                &arrow_schema::DataType::Utf8
            );
        }
    }
    // The scenario's `centre_mm = { x = 380.0, y = 205.0, z = 300.0 }`, on every row.
    let table = rows(&out, "ballbar_xy");
    assert!(!table.is_empty());
    for (_, row) in &table {
        assert_eq!(
            [
                &row["centre_x_mm"],
                &row["centre_y_mm"],
                &row["centre_z_mm"]
            ],
            [380.0, 205.0, 300.0]
        );
    }
    let card = std::fs::read_to_string(out.join("README.md")).unwrap();
    assert!(card.contains("in 1 shard."), "{card}");
    assert!(!card.contains("1 shards"));
}
