//! What a dataset says about itself: the key-value metadata of every Parquet file,
//! `manifest.json` and the `README.md` dataset card. Nothing here depends on the clock, the
//! host or the path the scenario was given by, so the same command gives the same bytes.

use super::options::Options;
use super::priors::{Distribution, Law, unit_of_key};
use super::spec::SplitRule;
use super::table::{ColumnKind, TableSchema};
use super::{Dataset, SCHEMA_VERSION};
use serde_json::{Value, json};
use std::fmt::Write as _;

/// The unit of a column: the prior's for a sampled parameter, else its name's suffix.
fn unit(dataset: &Dataset, column: &str) -> String {
    match dataset
        .section
        .priors
        .iter()
        .find(|p| p.path.column() == column)
    {
        Some(prior) => prior.path.unit(),
        None => unit_of_key(column).to_string(),
    }
}

/// A prior's distribution, for people.
fn describe(law: &Law) -> String {
    let text = match law.distribution {
        Distribution::Fixed(v) => format!("fixed {v}"),
        Distribution::Uniform { low, high } => format!("uniform on [{low}, {high})"),
        Distribution::Normal { mean, sd } => format!("normal, mean {mean}, sd {sd}"),
        Distribution::LogNormal { median, sigma } => {
            format!("log-normal, median {median}, sd of ln {sigma}")
        }
    };
    match law.bounds {
        Some((low, high)) => format!("{text}, truncated to [{low}, {high}]"),
        None => text,
    }
}

/// The split rule, for people.
fn split_rule(dataset: &Dataset) -> String {
    match dataset.section.split {
        SplitRule::Fraction(f) => format!(
            "each case (one machine and condition, all its rows) is in `test` with probability {f}, drawn from its seed"
        ),
        SplitRule::Threshold {
            prior,
            value,
            above,
        } => format!(
            "extrapolation: the cases whose {} is {} {value} are in `test`, the others in `train`",
            dataset.section.priors[prior].path.column(),
            if above { "above" } else { "below" }
        ),
    }
}

/// The scenario's file name (not its path: the same dataset from another folder is the same).
fn scenario_name(dataset: &Dataset) -> String {
    (dataset.scenario.file.file_name())
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

/// The unit of every column of `schema`'s table, in order (empty for none): each column's
/// Parquet field metadata `unit`.
pub fn column_units(dataset: &Dataset, schema: &TableSchema) -> Vec<String> {
    (schema.columns.iter())
        .map(|(name, _)| unit(dataset, name))
        .collect()
}

/// The key-value metadata of each Parquet file of `schema`'s table.
pub fn file_metadata(
    dataset: &Dataset,
    schema: &TableSchema,
    options: &Options,
) -> Vec<(String, String)> {
    let units: serde_json::Map<String, Value> = (schema.columns.iter())
        .map(|(name, _)| (name.clone(), json!(unit(dataset, name))))
        .collect();
    vec![
        ("mtwin.version".into(), env!("CARGO_PKG_VERSION").into()),
        ("mtwin.schema_version".into(), SCHEMA_VERSION.to_string()),
        ("mtwin.table".into(), schema.name.clone()),
        ("mtwin.scenario".into(), scenario_name(dataset)),
        (
            "mtwin.scenario_sha256".into(),
            dataset.scenario.sha256.clone(),
        ),
        ("mtwin.seed".into(), dataset.section.seed.to_string()),
        ("mtwin.count".into(), options.count.to_string()),
        ("mtwin.shards".into(), options.shards.to_string()),
        ("mtwin.units".into(), Value::Object(units).to_string()),
    ]
}

/// `manifest.json`.
pub fn manifest(
    dataset: &Dataset,
    count: u64,
    schemas: &[TableSchema],
    identity: &Value,
    shards: Vec<Value>,
    files: Vec<Value>,
) -> Value {
    let parameters: Vec<Value> = (dataset.section.priors.iter())
        .map(|p| {
            json!({
                "column": p.path.column(),
                "path": p.path.as_str(),
                "unit": p.path.unit(),
                "prior": describe(&p.law),
            })
        })
        .collect();
    let tables: serde_json::Map<String, Value> = schemas
        .iter()
        .map(|schema| {
            let rows: u64 = (files.iter())
                .filter(|f| f["table"] == json!(schema.name))
                .filter_map(|f| f["rows"].as_u64())
                .sum();
            let columns: Vec<Value> = (schema.columns.iter())
                .map(|(name, kind)| {
                    json!({
                        "name": name,
                        "type": match kind {
                            ColumnKind::Integer => "int64",
                            ColumnKind::Number => "double",
                            ColumnKind::Text => "string",
                        },
                        "unit": unit(dataset, name),
                    })
                })
                .collect();
            (
                schema.name.clone(),
                json!({ "rows": rows, "columns": columns }),
            )
        })
        .collect();
    let (train, test) = dataset.split_counts(count);
    json!({
        "schema_version": SCHEMA_VERSION,
        "mtwin_version": env!("CARGO_PKG_VERSION"),
        "dataset": identity,
        "scenario": scenario_name(dataset),
        "description": dataset.scenario.description,
        "machine": dataset.machine_name,
        "seed_rule": "case_seed = (first u64 of ChaCha8 keyed by SHA-256(seed as 8 little-endian bytes ‖ \"dataset case K\")) >> 1; each prior is drawn from the stream keyed by (case_seed, its path); the case's scenario has seed = case_seed",
        "shard_rule": "shard i of n holds cases [i·count/n, (i+1)·count/n)",
        "tests": dataset.tests,
        "split": split_rule(dataset),
        "split_counts": { "train": train, "test": test },
        "partitioning": ["machine", "split", "shard"],
        "parameters": parameters,
        "tables": tables,
        "shards": shards,
        "files": files,
    })
}

/// `n` and the noun, singular for one: "1 shard", "4 shards".
pub fn counted(n: u64, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The dataset card, `README.md`.
pub fn readme(
    dataset: &Dataset,
    options: &Options,
    schemas: &[TableSchema],
    manifest: &Value,
) -> String {
    let mut s = String::new();
    let name = scenario_name(dataset);
    let _ = writeln!(s, "# mtwin dataset: {name}\n");
    if let Some(description) = &dataset.scenario.description {
        let _ = writeln!(s, "{description}\n");
    }
    let _ = writeln!(
        s,
        "{} of the machine `{}` (each case one machine and condition drawn from the priors below), made by mtwin {} (dataset schema {SCHEMA_VERSION}) from `{name}` (SHA-256 {}), master seed {}, in {}. Tests run in every case: {}.\n",
        counted(options.count, "simulated case", "simulated cases"),
        dataset.machine_name,
        env!("CARGO_PKG_VERSION"),
        dataset.scenario.sha256,
        dataset.section.seed,
        counted(options.shards, "shard", "shards"),
        dataset.tests.join(", ")
    );
    let _ = writeln!(
        s,
        "Remake it with `mtwin dataset {name} --count {} --shards {} --out DIR`: the same files, byte for byte, whatever the thread count; a case is the same in any shard layout.\n",
        options.count, options.shards
    );
    let _ = writeln!(s, "## What was sampled (the ground truth)\n");
    let _ = writeln!(
        s,
        "The `cases` table holds, for every case, `case_id`, `case_seed` and the value drawn for each prior. Everything else in the case is the scenario as written. Signs follow ISO 230-1 (actual − nominal).\n"
    );
    let _ = writeln!(
        s,
        "| column | scenario value | unit | prior |\n|---|---|---|---|"
    );
    for prior in &dataset.section.priors {
        let _ = writeln!(
            s,
            "| `{}` | `{}` | {} | {} |",
            prior.path.column(),
            prior.path.as_str(),
            prior.path.unit(),
            describe(&prior.law)
        );
    }
    // Counted once, for the manifest.
    let count = |split: &str| manifest["split_counts"][split].as_u64().unwrap_or(0);
    let (train, test) = (count("train"), count("test"));
    let _ = writeln!(
        s,
        "\nSplit: {}: {} in `train`, {test} in `test`.\n",
        split_rule(dataset),
        counted(train, "case", "cases")
    );
    let _ = writeln!(s, "## Tables\n");
    let _ = writeln!(
        s,
        "Each table is a folder of Parquet files (snappy), Hive-partitioned as `<table>/machine=…/split=train|test/shard=N/part-0.parquet` (`shard` an integer, unpadded, so readers type it as one); every row carries `case_id`. Measurement tables hold the columns of the CSV that `mtwin run` writes for the test (units in the column names; the CSV preamble's set-up lines as columns too, a vector such as `centre_mm` as one column per component); numbers are doubles, text is UTF-8, empty cells are nulls. Each column's unit is also in its Parquet field metadata (`unit`, in the file's Arrow schema: `pyarrow.parquet.read_schema(file).field(\"deviation_um\").metadata`).\n"
    );
    let tables = &manifest["tables"];
    for schema in schemas {
        let columns: Vec<String> = (schema.columns.iter())
            .map(|(name, _)| format!("`{name}`"))
            .collect();
        let _ = writeln!(
            s,
            "- `{}` ({} rows): {}",
            schema.name,
            tables[&schema.name]["rows"],
            columns.join(", ")
        );
    }
    let measurement = schemas.get(1).map_or("cases", |t| t.name.as_str());
    let _ = writeln!(s, "\n## Loading\n");
    let _ = writeln!(
        s,
        "```python\nimport pyarrow.dataset as ds\ncases = ds.dataset(\"cases\", partitioning=\"hive\").to_table().to_pandas()\nrows = ds.dataset(\"{measurement}\", partitioning=\"hive\").to_table().to_pandas()\njoined = rows.merge(cases, on=[\"case_id\", \"machine\", \"split\", \"shard\"])\n\nimport pandas as pd  # plain Hive types: shard an integer, machine and split strings (pandas' default makes them categories)\nrows = pd.read_parquet(\"{measurement}\", partitioning=ds.partitioning(flavor=\"hive\"))\n\nimport polars as pl\nrows = pl.scan_parquet(\"{measurement}/**/*.parquet\", hive_partitioning=True).collect()\n```\n"
    );
    let _ = writeln!(
        s,
        "`manifest.json` lists every file with its rows and SHA-256, the priors, the tables' columns with units, and the rules for seeds, shards and the split. The files' key-value metadata repeat the essentials (`mtwin.seed`, `mtwin.scenario_sha256`, `mtwin.units`).\n"
    );
    let _ = writeln!(s, "## Limits\n");
    let _ = writeln!(
        s,
        "Simulated data: the twin's models and their stated simplifications (see the mtwin README) are all these cases contain. A prior's value is all that varies between cases besides the noise streams, which each case draws from its own seed."
    );
    s
}
