//! Making a dataset shard by shard: each shard's files are written into a folder under
//! `.tmp/` private to the call that makes it, renamed into place, and only then recorded in
//! `_shards/` — a shard with a record is complete. A rerun skips the shards whose record and
//! files agree and redoes the others; the process that records the last shard writes
//! `manifest.json` and the dataset card.
//!
//! Any number of processes (or threads) may make the same shard at once — a resubmitted Slurm
//! array task, a Ray retry of a task on a node declared dead: none touches another's private
//! folder (a folder is removed only by its maker, or, once its process has died, by a later
//! maker on the same host), every published file is renamed whole into place, and the content
//! is a function of the command alone, so whoever renames last publishes the same bytes and
//! every maker succeeds.

use super::error::{DatasetError, io_error, parquet_error};
use super::options::Options;
use super::table::{Block, ParquetTable, TableSchema};
use super::{Case, Dataset, SCHEMA_VERSION, card};
use crate::app::simulate;
use rayon::prelude::*;
use serde_json::{Value, json};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;

/// What a call did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    /// Shards made now.
    pub made: Vec<u64>,
    /// Shards found complete and skipped.
    pub skipped: Vec<u64>,
    /// Cases made now.
    pub cases: u64,
    /// Rows written now, over every measurement table.
    pub readings: u64,
    /// Whether the dataset is complete (`manifest.json` written).
    pub complete: bool,
}

/// The record of shard `shard` of `shards` in `_shards/`.
pub fn record_name(shard: u64, shards: u64) -> String {
    format!("shard-{shard:05}-of-{shards:05}.json")
}

/// The first case of shard `shard`.
fn first_case(shard: u64, shards: u64, count: u64) -> u64 {
    (u128::from(shard) * u128::from(count) / u128::from(shards)) as u64
}

/// What identifies a dataset: two shards belong together when these are equal.
fn identity(dataset: &Dataset, options: &Options) -> Value {
    json!({
        "schema_version": SCHEMA_VERSION,
        "scenario_sha256": dataset.scenario.sha256,
        "machine_sha256": dataset.scenario.machine_sha256,
        "seed": dataset.section.seed,
        "count": options.count,
        "shards": options.shards,
    })
}

/// Makes the dataset `options` asks for (every shard, or one), skipping complete shards;
/// `progress` hears of every case made (its argument: cases made since the last call) and,
/// once, of the number of cases to make.
pub fn generate(
    dataset: &Dataset,
    options: &Options,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Summary, DatasetError> {
    if options.count == 0 || options.shards == 0 || options.shards > options.count {
        return Err(DatasetError::Options(format!(
            "--count {} and --shards {}: expected at least one case and one shard, and no more shards than cases",
            options.count, options.shards
        )));
    }
    if let Some(shard) = options.only.filter(|s| *s >= options.shards) {
        return Err(DatasetError::Options(format!(
            "--shard {shard}/{}: shards are numbered from 0 to {}",
            options.shards,
            options.shards - 1
        )));
    }
    if let Some(message) = dataset.empty_split(options.count) {
        return Err(DatasetError::Options(format!(
            "--count {}: {message}",
            options.count
        )));
    }
    let out = &options.out;
    let schemas = schemas(dataset)?;
    let records = out.join("_shards");
    let identity = identity(dataset, options);
    if records.is_dir() {
        check_layout(&records, &identity, out)?;
    }
    super::guard::check_folder(out, &schemas)?;
    std::fs::create_dir_all(&records).map_err(io_error(&records))?;

    let wanted: Vec<u64> = match options.only {
        Some(shard) => vec![shard],
        None => (0..options.shards).collect(),
    };
    let mut summary = Summary::default();
    let mut todo = Vec::new();
    for shard in wanted {
        if complete(
            out,
            &records.join(record_name(shard, options.shards)),
            &identity,
        )? {
            summary.skipped.push(shard);
        } else {
            todo.push(shard);
        }
    }
    let cases: u64 = (todo.iter())
        .map(|s| {
            first_case(s + 1, options.shards, options.count)
                - first_case(*s, options.shards, options.count)
        })
        .sum();
    progress(Progress::Total(cases));
    let pool = {
        let mut builder = rayon::ThreadPoolBuilder::new();
        if let Some(threads) = options.threads {
            builder = builder.num_threads(threads);
        }
        builder
            .build()
            .map_err(|e| DatasetError::Options(format!("--threads: {e}")))?
    };
    for shard in todo {
        let readings =
            pool.install(|| make_shard(dataset, options, &schemas, &identity, shard, progress))?;
        summary.made.push(shard);
        summary.readings += readings;
    }
    summary.cases = cases;
    summary.complete = finish(dataset, options, &schemas, &identity)?;
    Ok(summary)
}

/// What [`generate`] reports as it goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// The number of cases it will make.
    Total(u64),
    /// Cases made since the last report.
    Made(u64),
}

/// Refuses a folder whose shard records are of another dataset.
fn check_layout(records: &Path, identity: &Value, out: &Path) -> Result<(), DatasetError> {
    let entries = std::fs::read_dir(records).map_err(io_error(records))?;
    for entry in entries {
        let path = entry.map_err(io_error(records))?.path();
        if path.extension().is_none_or(|e| e != "json") {
            continue;
        }
        let Some(record) = read_json(&path) else {
            continue; // unreadable: that shard is redone
        };
        if record.get("dataset") != Some(identity) {
            return Err(DatasetError::Layout {
                dir: out.display().to_string(),
                message: format!(
                    "holds shards of another dataset ({} says {}; this one is {identity}); give another --out or remove the folder",
                    path.display(),
                    record.get("dataset").unwrap_or(&Value::Null)
                ),
            });
        }
    }
    Ok(())
}

fn read_json(path: &Path) -> Option<Value> {
    serde_json::from_slice(&std::fs::read(path).ok()?).ok()
}

/// SHA-256 of a file, read in blocks.
pub(super) fn file_sha256(path: &Path) -> std::io::Result<String> {
    let mut file = std::fs::File::open(path)?;
    let mut hasher = Sha256::new();
    let mut buffer = vec![0u8; 1 << 20];
    loop {
        let n = file.read(&mut buffer)?;
        if n == 0 {
            break;
        }
        hasher.update(&buffer[..n]);
    }
    Ok(hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

/// Whether the shard recorded at `record` is complete: its record is of this dataset and
/// every file it lists is there with its hash.
fn complete(out: &Path, record: &Path, identity: &Value) -> Result<bool, DatasetError> {
    let Some(record) = read_json(record) else {
        return Ok(false);
    };
    if record.get("dataset") != Some(identity) {
        return Ok(false);
    }
    let Some(files) = record.get("files").and_then(Value::as_array) else {
        return Ok(false);
    };
    for file in files {
        let (Some(path), Some(hash)) = (
            file.get("path").and_then(Value::as_str),
            file.get("sha256").and_then(Value::as_str),
        ) else {
            return Ok(false);
        };
        match file_sha256(&out.join(path)) {
            Ok(actual) if actual == hash => {}
            _ => return Ok(false),
        }
    }
    Ok(true)
}

/// The tables of the dataset, from the case with every prior at its centre: `cases` first,
/// then each measurement table in the order `mtwin run` writes them.
fn schemas(dataset: &Dataset) -> Result<Vec<TableSchema>, DatasetError> {
    let centre = Case {
        id: 0,
        seed: dataset.scenario.seed,
        test: false,
        values: (dataset.section.priors.iter())
            .map(|p| p.law.distribution.centre())
            .collect(),
    };
    let mut schemas = vec![TableSchema::cases(
        dataset.section.priors.iter().map(|p| p.path.column()),
    )];
    for (name, text) in csv_files(dataset, &centre)? {
        let schema = TableSchema::of_csv(&name, &text).map_err(|message| DatasetError::Table {
            id: centre.id,
            table: name.clone(),
            message,
        })?;
        schemas.push(schema);
    }
    Ok(schemas)
}

/// The CSV tables `mtwin run` writes for `case`, by table name (file stem).
fn csv_files(dataset: &Dataset, case: &Case) -> Result<Vec<(String, String)>, DatasetError> {
    let scenario = dataset.scenario_of(case)?;
    let simulation = simulate(&scenario).map_err(|source| DatasetError::Run {
        id: case.id,
        source,
    })?;
    let tables = simulation
        .tables(&scenario)
        .map_err(|source| DatasetError::Run {
            id: case.id,
            source,
        })?;
    Ok(tables
        .into_iter()
        .filter_map(|(name, bytes)| {
            let stem = name.strip_suffix(".csv")?.to_string();
            Some((stem, String::from_utf8(bytes).expect("tables are UTF-8")))
        })
        .collect())
}

/// Case `id`'s split and its block of every table.
fn case_blocks(
    dataset: &Dataset,
    schemas: &[TableSchema],
    id: u64,
) -> Result<(bool, Vec<Block>), DatasetError> {
    let case = dataset.case(id);
    let mut blocks = vec![Block::case_row(case.id, case.seed, &case.values)];
    let files = csv_files(dataset, &case)?;
    for schema in &schemas[1..] {
        let table = |message: String| DatasetError::Table {
            id,
            table: schema.name.clone(),
            message,
        };
        let (_, text) = (files.iter())
            .find(|(name, _)| *name == schema.name)
            .ok_or_else(|| table("the case did not write this table".into()))?;
        blocks.push(Block::from_csv(schema, id, text).map_err(table)?);
    }
    Ok((case.test, blocks))
}

/// The path of a table's file of one shard and split, relative to the dataset folder. The
/// shard number is not padded: pyarrow, polars and DuckDB type `shard=12` as an integer, while
/// DuckDB keeps `shard=00012` as text.
fn table_path(dataset: &Dataset, table: &str, split: &str, shard: u64) -> String {
    format!(
        "{table}/machine={}/split={split}/shard={shard}/part-0.parquet",
        dataset.machine_name
    )
}

/// Makes shard `shard` and records it; returns the measurement rows written.
fn make_shard(
    dataset: &Dataset,
    options: &Options,
    schemas: &[TableSchema],
    identity: &Value,
    shard: u64,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<u64, DatasetError> {
    let out = &options.out;
    // A folder of this call's own: another maker of the same shard (a retried task) has its
    // own, and nobody removes a live maker's folder; what makers that died left goes first.
    let stem = format!("shard-{shard:05}-of-{:05}.", options.shards);
    let tmp_root = out.join(".tmp");
    remove_dead_makers(&tmp_root);
    let tmp = tmp_root.join(format!("{stem}{}", unique_tag()));
    create_folder(&tmp)?;
    let result = write_shard(dataset, options, schemas, shard, &tmp, progress);
    let files = match result {
        Ok(files) => files,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&tmp); // best effort: already failing
            return Err(e);
        }
    };
    let mut listed = Vec::new();
    let mut readings = 0;
    for (relative, rows, table) in &files {
        let from = tmp.join(relative.replace('/', "_"));
        let to = out.join(relative);
        let folder = to.parent().expect("a table path has folders");
        std::fs::create_dir_all(folder).map_err(io_error(folder))?;
        let sha256 = file_sha256(&from).map_err(io_error(&from))?;
        std::fs::rename(&from, &to).map_err(io_error(&to))?;
        if table != "cases" {
            readings += rows;
        }
        listed.push(json!({ "path": relative, "table": table, "rows": rows, "sha256": sha256 }));
    }
    let _ = std::fs::remove_dir_all(&tmp); // empty now
    let first = first_case(shard, options.shards, options.count);
    let end = first_case(shard + 1, options.shards, options.count);
    let record = json!({
        "schema_version": SCHEMA_VERSION,
        "dataset": identity,
        "shard": shard,
        "first_case": first,
        "end_case": end,
        "files": listed,
    });
    let path = out.join("_shards").join(record_name(shard, options.shards));
    write_json(&path, &record)?;
    Ok(readings)
}

/// A tag unique to one call, for temporary names: this process's id and start time
/// (nanoseconds), a count of the calls in this process (threads of one process making the
/// same shard do not meet either) and the host (`PID-NANOS-N@HOST`).
fn unique_tag() -> String {
    static START: std::sync::OnceLock<u128> = std::sync::OnceLock::new();
    static CALLS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let nanos = START.get_or_init(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos())
    });
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    format!("{}-{nanos}-{call}@{}", std::process::id(), host())
}

/// This host's name (letters, digits, `-` and `.` kept), or `unknown`.
fn host() -> &'static str {
    static HOST: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    HOST.get_or_init(|| {
        let name = ["/proc/sys/kernel/hostname", "/etc/hostname"]
            .iter()
            .find_map(|p| std::fs::read_to_string(p).ok())
            .unwrap_or_default();
        let name: String = (name.trim().chars())
            .filter(|c| c.is_ascii_alphanumeric() || *c == '-' || *c == '.')
            .collect();
        if name.is_empty() {
            "unknown".into()
        } else {
            name
        }
    })
}

/// Removes the private folders under `tmp_root` whose maker has died: made on this host (a
/// process on another host sharing the folder is never judged here) by a process that no
/// longer exists (`/proc/PID` gone). Where `/proc` is not there, or the host is unknown,
/// nothing is removed. Best effort: what cannot be removed stays, harmless.
fn remove_dead_makers(tmp_root: &Path) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() || host() == "unknown" {
        return;
    }
    let Ok(entries) = std::fs::read_dir(tmp_root) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some((tag, on)) = name.rsplit_once('@') else {
            continue;
        };
        let pid = (tag.rsplit_once('.'))
            .and_then(|(_, tag)| tag.split('-').next())
            .and_then(|pid| pid.parse::<u32>().ok());
        if let Some(pid) = pid
            && on == host()
            && pid != std::process::id()
            && !proc.join(pid.to_string()).exists()
        {
            let _ = std::fs::remove_dir_all(entry.path()); // best effort: remains only
        }
    }
}

/// Creates `dir` and its parents. A maker that finishes removes `.tmp/` when it is empty;
/// should that happen between making `.tmp/` and `dir`, it is tried again.
fn create_folder(dir: &Path) -> Result<(), DatasetError> {
    let mut attempts = 0;
    loop {
        match std::fs::create_dir_all(dir) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound && attempts < 10 => attempts += 1,
            result => return result.map_err(io_error(dir)),
        }
    }
}

/// Writes `value` to `path` atomically (pretty JSON, a final newline).
pub(super) fn write_json(path: &Path, value: &Value) -> Result<(), DatasetError> {
    let mut bytes = serde_json::to_vec_pretty(value).expect("JSON values serialise");
    bytes.push(b'\n');
    write_atomically(path, &bytes)
}

/// Writes `bytes` to `path` through a temporary name unique to this call (two processes or
/// threads writing the same file each rename a whole file of their own); a file that already
/// holds these bytes is left as it is (a rerun changes nothing, not even times).
pub(super) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), DatasetError> {
    if std::fs::read(path).is_ok_and(|existing| existing == bytes) {
        return Ok(());
    }
    let name = path.file_name().expect("a file").to_string_lossy();
    let temporary = path.with_file_name(format!(".{name}.{}.partial", unique_tag()));
    if let Err(e) = std::fs::write(&temporary, bytes) {
        let _ = std::fs::remove_file(&temporary); // best effort: already failing
        return Err(io_error(path)(e));
    }
    std::fs::rename(&temporary, path).map_err(io_error(path))
}

/// A batch of cases as made: each case's split and its block of every table.
type Made = Vec<(bool, Vec<Block>)>;

/// The open files of a shard, by (table, split).
#[derive(Default)]
struct Writers(BTreeMap<(usize, bool), (String, ParquetTable)>);

impl Writers {
    /// Appends a batch's blocks, in case order, opening files as their first rows come.
    fn write(
        &mut self,
        made: Made,
        dataset: &Dataset,
        options: &Options,
        schemas: &[TableSchema],
        shard: u64,
        tmp: &Path,
    ) -> Result<(), DatasetError> {
        for (test, blocks) in made {
            for (index, block) in blocks.into_iter().enumerate() {
                if block.rows() == 0 {
                    continue;
                }
                let (relative, writer) = match self.0.entry((index, test)) {
                    std::collections::btree_map::Entry::Occupied(entry) => entry.into_mut(),
                    std::collections::btree_map::Entry::Vacant(entry) => {
                        let split = if test { "test" } else { "train" };
                        let relative = table_path(dataset, &schemas[index].name, split, shard);
                        let file = tmp.join(relative.replace('/', "_"));
                        let metadata = card::file_metadata(dataset, &schemas[index], options);
                        let units = card::column_units(dataset, &schemas[index]);
                        let writer = ParquetTable::create(&file, &schemas[index], metadata, &units)
                            .map_err(parquet_error(&file))?;
                        entry.insert((relative, writer))
                    }
                };
                writer
                    .push(block)
                    .map_err(|e| parquet_error(Path::new(relative))(e))?;
            }
        }
        Ok(())
    }
}

/// Writes shard `shard`'s files into `tmp` (named by their relative paths with `/` → `_`);
/// returns `(relative path, rows, table)` for each, sorted by path.
fn write_shard(
    dataset: &Dataset,
    options: &Options,
    schemas: &[TableSchema],
    shard: u64,
    tmp: &Path,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Vec<(String, u64, String)>, DatasetError> {
    let first = first_case(shard, options.shards, options.count);
    let end = first_case(shard + 1, options.shards, options.count);
    // Cases in batches, each made in parallel; a batch is written (in case order, so the bytes
    // do not depend on the threads) while the next is made. Memory holds two batches.
    let batch = (rayon::current_num_threads() * 4).max(8) as u64;
    let make = |from: u64| -> Result<Made, DatasetError> {
        (from..(from + batch).min(end))
            .into_par_iter()
            .map(|id| case_blocks(dataset, schemas, id))
            .collect()
    };
    let mut writers = Writers::default();
    let mut made = make(first)?;
    let mut start = first;
    while !made.is_empty() {
        let next = start + made.len() as u64;
        let (written, following) = rayon::join(
            || writers.write(made, dataset, options, schemas, shard, tmp),
            || {
                if next < end {
                    make(next)
                } else {
                    Ok(Vec::new())
                }
            },
        );
        written?;
        progress(Progress::Made(next - start));
        made = following?;
        start = next;
    }
    let writers = writers.0;
    let mut files = Vec::new();
    for ((index, _), (relative, writer)) in writers {
        let rows = writer
            .finish()
            .map_err(|e| parquet_error(Path::new(&relative))(e))?;
        files.push((relative, rows, schemas[index].name.clone()));
    }
    files.sort();
    Ok(files)
}

/// Writes `manifest.json` and the dataset card if every shard is recorded; returns whether.
fn finish(
    dataset: &Dataset,
    options: &Options,
    schemas: &[TableSchema],
    identity: &Value,
) -> Result<bool, DatasetError> {
    let out = &options.out;
    let mut files = Vec::new();
    let mut shards = Vec::new();
    for shard in 0..options.shards {
        let path = out.join("_shards").join(record_name(shard, options.shards));
        let Some(record) = read_json(&path).filter(|r| r.get("dataset") == Some(identity)) else {
            return Ok(false);
        };
        for file in record["files"].as_array().into_iter().flatten() {
            let mut file = file.clone();
            file["shard"] = json!(shard);
            files.push(file);
        }
        shards.push(json!({
            "shard": shard,
            "first_case": record["first_case"],
            "end_case": record["end_case"],
            "record": format!("_shards/{}", record_name(shard, options.shards)),
        }));
    }
    files.sort_by(|a, b| a["path"].as_str().cmp(&b["path"].as_str()));
    let manifest = card::manifest(dataset, options.count, schemas, identity, shards, files);
    write_json(&out.join("manifest.json"), &manifest)?;
    write_atomically(
        &out.join("README.md"),
        card::readme(dataset, options, schemas, &manifest).as_bytes(),
    )?;
    let _ = std::fs::remove_dir(out.join(".tmp")); // only if empty: another process may be at work
    Ok(true)
}
