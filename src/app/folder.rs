//! What an output folder already holds, so that one kind of output is never written over
//! another: `mtwin run` and `mtwin dataset --case` write a run folder, `mtwin dataset` a
//! dataset folder, and each one's `manifest.json` says which it is by its content (a run's
//! lists `files` by `name` under a `scenario` object; a dataset's has a `dataset` identity and
//! its `shards`).

use serde_json::Value;
use std::path::Path;

/// What a folder holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Holds {
    /// Nothing: no folder, an empty one, or hidden files only (`.nfs…`, `.DS_Store`).
    Nothing,
    /// A run (`mtwin run`, `mtwin dataset --case`), described for people.
    Run(String),
    /// A dataset, complete or in the making (`_shards/`, or a dataset's `manifest.json`),
    /// described for people.
    Dataset(String),
    /// Other files (their names, sorted, hidden ones left out).
    Other(Vec<String>),
}

/// What `dir` holds.
pub fn holds(dir: &Path) -> Holds {
    let manifest = std::fs::read(dir.join("manifest.json"))
        .ok()
        .and_then(|bytes| serde_json::from_slice::<Value>(&bytes).ok());
    if let Some(manifest) = &manifest {
        if let Some(identity) = manifest.get("dataset").filter(|d| d.is_object())
            && manifest.get("shards").is_some()
        {
            return Holds::Dataset(describe_dataset(manifest.get("scenario"), identity));
        }
        if let Some(scenario) = manifest.get("scenario").filter(|s| s.is_object())
            && manifest.get("files").is_some()
        {
            let seed = manifest
                .get("seed")
                .map_or(String::new(), |s| format!(", seed {s}"));
            return Holds::Run(format!(
                "a run of {}{seed} (the manifest.json of `mtwin run`)",
                scenario
                    .get("file")
                    .and_then(Value::as_str)
                    .unwrap_or("a scenario")
            ));
        }
    }
    // Listed before `_shards/` is looked for: the shards of one dataset run side by side, and
    // each creates `_shards/` before it writes anything else, so whatever this listing holds
    // of another shard's, `_shards/` exists by the time it is looked for below.
    let mut names: Vec<String> = (std::fs::read_dir(dir).into_iter().flatten())
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|name| !name.starts_with('.'))
        .collect();
    if dir.join("_shards").is_dir() {
        // A dataset whose manifest is not written yet: its shard records say which.
        let identity = (std::fs::read_dir(dir.join("_shards")).into_iter().flatten())
            .flatten()
            .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
            .find_map(|e| {
                let record: Value = serde_json::from_slice(&std::fs::read(e.path()).ok()?).ok()?;
                record.get("dataset").cloned()
            });
        return Holds::Dataset(match identity {
            Some(identity) => describe_dataset(None, &identity),
            None => "a dataset in the making (`_shards/`, no shard recorded yet)".into(),
        });
    }
    if names.is_empty() {
        return Holds::Nothing;
    }
    names.sort();
    Holds::Other(names)
}

fn describe_dataset(scenario: Option<&Value>, identity: &Value) -> String {
    let number = |key: &str| identity.get(key).map_or("?".into(), Value::to_string);
    let of = scenario
        .and_then(Value::as_str)
        .map_or(String::new(), |s| format!(" of {s}"));
    format!(
        "a dataset{of} ({} cases in {} shards, `mtwin dataset`)",
        number("count"),
        number("shards")
    )
}

/// Up to five of `names`, then how many more.
pub(crate) fn some_of(names: &[String]) -> String {
    let shown: Vec<&str> = names.iter().take(5).map(String::as_str).collect();
    match names.len().saturating_sub(5) {
        0 => shown.join(", "),
        more => format!("{} and {more} more", shown.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifests_say_which_kind_a_folder_holds() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        assert_eq!(holds(&dir.join("absent")), Holds::Nothing);
        std::fs::write(dir.join(".nfs0001"), b"").unwrap();
        assert_eq!(holds(dir), Holds::Nothing, "hidden files only");
        std::fs::write(
            dir.join("manifest.json"),
            br#"{"scenario": {"file": "a.toml", "sha256": "00"}, "seed": 7, "files": []}"#,
        )
        .unwrap();
        let Holds::Run(what) = holds(dir) else {
            panic!("{:?}", holds(dir))
        };
        assert!(what.contains("a.toml") && what.contains("seed 7"), "{what}");
        std::fs::write(
            dir.join("manifest.json"),
            br#"{"scenario": "a.toml", "dataset": {"count": 20, "shards": 2}, "shards": [], "files": []}"#,
        )
        .unwrap();
        let Holds::Dataset(what) = holds(dir) else {
            panic!("{:?}", holds(dir))
        };
        assert!(what.contains("20 cases in 2 shards"), "{what}");
        std::fs::remove_file(dir.join("manifest.json")).unwrap();
        std::fs::write(dir.join("notes.txt"), b"mine").unwrap();
        assert_eq!(holds(dir), Holds::Other(vec!["notes.txt".into()]));
        std::fs::create_dir(dir.join("_shards")).unwrap();
        assert!(matches!(holds(dir), Holds::Dataset(_)));
    }
}
