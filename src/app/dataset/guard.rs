//! What a dataset folder may hold besides the dataset: nothing. `mtwin dataset` refuses a
//! folder holding a run (its `manifest.json` would be replaced), files it does not write, and
//! a stray file in a table's folder, which readers of the folder as one dataset would take for
//! part of the table.

use super::error::{DatasetError, io_error};
use super::table::TableSchema;
use crate::app::folder::{Holds, holds, some_of};
use std::path::Path;

/// Refuses a folder that holds something besides this dataset: a run (`mtwin run`, or
/// `--case`), files `mtwin dataset` does not write, or, in a table's folder, a file readers
/// of the folder would take for part of the table. An absent or empty folder, and one
/// holding this dataset (complete or not, to resume), are fine; hidden entries (`.tmp/`,
/// temporary names, `.nfs…`) are ignored, and in a table's folder so are names starting with
/// `_`, which readers skip too.
pub(super) fn check_folder(out: &Path, schemas: &[TableSchema]) -> Result<(), DatasetError> {
    let layout = |message: String| DatasetError::Layout {
        dir: out.display().to_string(),
        message,
    };
    match holds(out) {
        Holds::Nothing => return Ok(()),
        Holds::Run(what) => {
            return Err(layout(format!(
                "holds {what}; a dataset would replace its manifest.json: give another --out"
            )));
        }
        Holds::Other(names) => {
            return Err(layout(format!(
                "holds files `mtwin dataset` does not write ({}): give an empty or new folder",
                some_of(&names)
            )));
        }
        Holds::Dataset(_) => {}
    }
    let tables: Vec<&str> = schemas.iter().map(|s| s.name.as_str()).collect();
    let mut unrelated = Vec::new();
    for entry in std::fs::read_dir(out).map_err(io_error(out))? {
        let entry = entry.map_err(io_error(out))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        let ours = match name.as_str() {
            _ if name.starts_with('.') => true,
            "manifest.json" | "README.md" => !is_dir,
            "_shards" => is_dir,
            table => is_dir && tables.contains(&table),
        };
        if !ours {
            unrelated.push(name);
        }
    }
    if !unrelated.is_empty() {
        unrelated.sort();
        return Err(layout(format!(
            "holds a dataset and files `mtwin dataset` does not write ({}): move them out of the dataset folder",
            some_of(&unrelated)
        )));
    }
    for table in tables {
        let mut stray = Vec::new();
        stray_files(&out.join(table), &mut Vec::new(), &mut stray)?;
        if let Some(first) = stray.first() {
            return Err(DatasetError::Layout {
                dir: out.join(table).display().to_string(),
                message: format!(
                    "{first}{}: not a file of the table (`machine=…/split=…/shard=…/part-0.parquet`); readers of the table's folder (pyarrow.dataset, pandas) would read it as part of it: move it out",
                    if stray.len() > 1 {
                        format!(" (and {} more)", stray.len() - 1)
                    } else {
                        String::new()
                    }
                ),
            });
        }
    }
    Ok(())
}

/// The entries under `dir` (at `relative` in a table's folder) that are not the table's files
/// nor skipped by readers, into `stray` (paths relative to the table's folder).
fn stray_files(
    dir: &Path,
    relative: &mut Vec<String>,
    stray: &mut Vec<String>,
) -> Result<(), DatasetError> {
    const KEYS: [&str; 3] = ["machine=", "split=", "shard="];
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(()); // no such table yet
    };
    for entry in entries {
        let entry = entry.map_err(io_error(dir))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') || name.starts_with('_') {
            continue;
        }
        let depth = relative.len();
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        let expected = match KEYS.get(depth) {
            Some(key) => is_dir && name.starts_with(key),
            None => depth == KEYS.len() && !is_dir && name == "part-0.parquet",
        };
        relative.push(name);
        if !expected {
            stray.push(relative.join("/"));
        } else if is_dir {
            stray_files(&entry.path(), relative, stray)?;
        }
        relative.pop();
    }
    stray.sort();
    Ok(())
}
