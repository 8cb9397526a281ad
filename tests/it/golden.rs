//! Byte-for-byte regression of everything the command line produces from the bundled
//! scenarios: every file `mtwin run` writes, and the text and JSON of `check`, `analyze` and
//! `discover` on the tables it wrote. The hashes in `tests/golden/outputs.sha256` were
//! recorded before a change that must not alter behaviour (the move to one folder per test
//! kind); a change that alters an output on purpose records them again with
//! `MTWIN_BLESS=1 cargo test --test it golden::` and says why in its commit.
//!
//! Independent of the code under test: the reference is what the program printed and wrote
//! before the change, not anything it computes now.

use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn golden_file() -> PathBuf {
    root().join("tests/golden/outputs.sha256")
}

fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Runs mtwin in `dir` and returns its standard output; a failure is a test failure.
fn mtwin(dir: &Path, args: &[&str]) -> Vec<u8> {
    let output = Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "mtwin {args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output.stdout
}

/// Every preamble key the twin wrote in `table` was read by its analysis: the report's
/// `preamble_not_used` (at `pointer` in `json`) is empty (issue 42: every field written is read).
fn every_key_read(json: &[u8], pointer: &str, table: &str) {
    let report: serde_json::Value = serde_json::from_slice(json).unwrap();
    assert_eq!(
        report.pointer(pointer),
        Some(&serde_json::json!([])),
        "{table}: keys written but not read"
    );
}

/// Every output of the bundled scenarios and of the analyses of their tables, by a name that
/// says how it was made.
fn outputs(work: &Path) -> BTreeMap<String, String> {
    let mut hashes = BTreeMap::new();
    let mut scenarios: Vec<PathBuf> = std::fs::read_dir(root().join("scenarios"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    scenarios.sort();
    for scenario in &scenarios {
        let name = scenario.file_stem().unwrap().to_string_lossy().into_owned();
        let out = work.join(&name);
        let scenario_arg = scenario.to_string_lossy().into_owned();
        // `check` prints the path it was given: run it from the crate root with a relative one.
        let relative = format!("scenarios/{name}.toml");
        hashes.insert(
            format!("{name}/check"),
            sha256_hex(&mtwin(&root(), &["check", &relative])),
        );
        mtwin(work, &["run", &scenario_arg, "--out", &name]);
        let mut files: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        files.sort();
        let truth: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("truth.json")).unwrap()).unwrap();
        for file in &files {
            let bytes = std::fs::read(out.join(file)).unwrap();
            hashes.insert(format!("{name}/{file}"), sha256_hex(&bytes));
            let table = format!("{name}/{file}");
            if file == "positioning.csv" {
                for json in [false, true] {
                    let mut args = vec!["analyze", "positioning", &table];
                    args.extend(json.then_some("--json"));
                    let printed = mtwin(work, &args);
                    if json {
                        every_key_read(&printed, "/preamble_not_used", &table);
                    }
                    hashes.insert(
                        format!("{table} analyze{}", if json { " --json" } else { "" }),
                        sha256_hex(&printed),
                    );
                }
                let model = format!("{name}/model.toml");
                let text = mtwin(
                    work,
                    &["discover", "positioning", &table, "--write-model", &model],
                );
                hashes.insert(format!("{table} discover"), sha256_hex(&text));
                hashes.insert(
                    format!("{table} discover --write-model"),
                    sha256_hex(&std::fs::read(work.join(&model)).unwrap()),
                );
                let json = mtwin(work, &["discover", "positioning", &table, "--json"]);
                hashes.insert(format!("{table} discover --json"), sha256_hex(&json));
            }
            if let Some(plane) = file
                .strip_prefix("ballbar_")
                .and_then(|f| f.strip_suffix(".csv"))
            {
                let test = &truth["ballbar_test"];
                let circle = test["circles"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .find(|c| c["file"] == file.as_str())
                    .unwrap();
                let radius = test["length_mm"].as_f64().unwrap().to_string();
                let feed = circle["feed_mm_per_min"].as_f64().unwrap().to_string();
                let plane = plane.to_uppercase();
                let conditions = [
                    "--plane",
                    &plane,
                    "--radius-mm",
                    &radius,
                    "--feed-mm-per-min",
                    &feed,
                ];
                for json in [false, true] {
                    let mut args = vec!["analyze", "ballbar", &table];
                    args.extend(conditions);
                    args.extend(json.then_some("--json"));
                    hashes.insert(
                        format!("{table} analyze{}", if json { " --json" } else { "" }),
                        sha256_hex(&mtwin(work, &args)),
                    );
                }
                // Ball-bar discovery takes about a minute on a full circle: the short lesson only.
                if name.starts_with("teach_") {
                    for json in [false, true] {
                        let mut args = vec!["discover", "ballbar", &table];
                        args.extend(conditions);
                        args.extend(json.then_some("--json"));
                        hashes.insert(
                            format!("{table} discover{}", if json { " --json" } else { "" }),
                            sha256_hex(&mtwin(work, &args)),
                        );
                    }
                }
            }
            if file == "drift.csv" {
                for json in [false, true] {
                    let mut args = vec!["analyze", "drift", &table];
                    args.extend(json.then_some("--json"));
                    let printed = mtwin(work, &args);
                    if json {
                        every_key_read(&printed, "/preamble_not_used", &table);
                    }
                    hashes.insert(
                        format!("{table} analyze{}", if json { " --json" } else { "" }),
                        sha256_hex(&printed),
                    );
                }
            }
            // The R-test and spindle reports are checked for unread keys only (their numbers
            // have their own tests).
            if file == "rtest.csv" || file == "spindle.csv" {
                let kind = file.trim_end_matches(".csv");
                let printed = mtwin(work, &["analyze", kind, &table, "--json"]);
                every_key_read(&printed, "/setup/preamble_not_used", &table);
            }
        }
        // A small dataset of each dataset scenario: its manifest lists every file's SHA-256.
        if std::fs::read_to_string(scenario)
            .unwrap()
            .contains("\n[dataset]\n")
        {
            let folder = format!("{name}_dataset");
            mtwin(
                work,
                &[
                    "dataset",
                    &scenario_arg,
                    "--count",
                    "6",
                    "--shards",
                    "2",
                    "--out",
                    &folder,
                ],
            );
            for file in ["manifest.json", "README.md"] {
                let bytes = std::fs::read(work.join(&folder).join(file)).unwrap();
                hashes.insert(format!("{name}/dataset/{file}"), sha256_hex(&bytes));
            }
        }
    }
    hashes
}

#[test]
fn every_output_of_the_bundled_scenarios_is_as_recorded() {
    let work = tempfile::tempdir().unwrap();
    let now = outputs(work.path());
    let render = |hashes: &BTreeMap<String, String>| {
        hashes
            .iter()
            .map(|(name, hash)| format!("{hash}  {name}\n"))
            .collect::<String>()
    };
    if std::env::var_os("MTWIN_BLESS").is_some() {
        std::fs::create_dir_all(golden_file().parent().unwrap()).unwrap();
        std::fs::write(golden_file(), render(&now)).unwrap();
        return;
    }
    let recorded: BTreeMap<String, String> = std::fs::read_to_string(golden_file())
        .unwrap()
        .lines()
        .map(|l| {
            let (hash, name) = l.split_once("  ").unwrap();
            (name.to_string(), hash.to_string())
        })
        .collect();
    let differ: Vec<String> = recorded
        .keys()
        .chain(now.keys())
        .filter(|k| recorded.get(*k) != now.get(*k))
        .cloned()
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    assert!(
        differ.is_empty(),
        "outputs differ from tests/golden/outputs.sha256 (or are new or missing): {differ:#?}"
    );
}
