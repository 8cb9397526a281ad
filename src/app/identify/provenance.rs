//! Where each table came from, as far as the files say: `mtwin run` writes a `manifest.json`
//! beside its tables naming the scenario and the machine (file and SHA-256) and every table
//! with its own SHA-256. A table listed there with the same bytes has that provenance; a table
//! without a manifest, or edited since (its hash no longer the listed one), has none.
//!
//! With provenance, `identify` refuses a `--scenario` other than the one the tables were made
//! from (its `compensated.toml` would subtract this estimate from another scenario's errors),
//! and says so in words where no table carries any. `estimate.json` records each table's
//! provenance and, when the tables agree, the scenario, so that `score` can refuse a truth of
//! another scenario.

use crate::math::sha256_hex;
use serde_json::{Value, json};
use std::path::Path;

/// What a table's folder says of it.
#[derive(Clone, Debug, PartialEq)]
pub struct Provenance {
    /// The table as given.
    pub file: String,
    /// Its SHA-256.
    pub sha256: String,
    /// The scenario that made it, when a manifest beside it lists it unchanged:
    /// (file name, SHA-256).
    pub scenario: Option<(String, String)>,
    /// The machine it was made on, likewise: (file name, SHA-256).
    pub machine: Option<(String, String)>,
    /// Why there is none, when a manifest lists the table with other bytes.
    pub note: Option<String>,
}

impl Provenance {
    /// The provenance of the table `path` (`file` as given), whose bytes are `bytes`.
    pub fn of(path: &Path, file: &str, bytes: &[u8]) -> Provenance {
        let sha256 = sha256_hex(bytes);
        let mut provenance = Provenance {
            file: file.to_string(),
            sha256: sha256.clone(),
            scenario: None,
            machine: None,
            note: None,
        };
        let manifest = path.parent().map(|dir| dir.join("manifest.json"));
        let Some(manifest) = manifest
            .and_then(|m| std::fs::read(m).ok())
            .and_then(|b| serde_json::from_slice::<Value>(&b).ok())
        else {
            return provenance;
        };
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
        let listed = manifest["files"]
            .as_array()
            .into_iter()
            .flatten()
            .find(|f| f["name"].as_str() == name.as_deref());
        let Some(listed) = listed else {
            return provenance;
        };
        if listed["sha256"].as_str() != Some(sha256.as_str()) {
            provenance.note = Some(
                "its manifest.json lists other bytes under this name: edited since `mtwin run` wrote it".into(),
            );
            return provenance;
        }
        let pair = |v: &Value| {
            Some((
                v["file"].as_str()?.to_string(),
                v["sha256"].as_str()?.to_string(),
            ))
        };
        provenance.scenario = pair(&manifest["scenario"]);
        provenance.machine = pair(&manifest["machine"]);
        provenance
    }

    /// For `estimate.json`: `file`, `sha256`, `scenario_sha256`, `machine_sha256` (null when
    /// unknown) and `note`.
    pub fn to_json(&self) -> Value {
        json!({
            "file": self.file,
            "sha256": self.sha256,
            "scenario": self.scenario.as_ref().map(|s| &s.0),
            "scenario_sha256": self.scenario.as_ref().map(|s| &s.1),
            "machine_sha256": self.machine.as_ref().map(|m| &m.1),
            "note": self.note,
        })
    }
}

/// The one scenario SHA-256 every table with provenance names, when they agree and at least
/// one has it; `Err` with the two that differ otherwise.
pub fn common_scenario(tables: &[Provenance]) -> Result<Option<String>, (String, String)> {
    let mut found: Option<&Provenance> = None;
    for table in tables.iter().filter(|t| t.scenario.is_some()) {
        match found {
            Some(first)
                if first.scenario.as_ref().map(|s| &s.1)
                    != table.scenario.as_ref().map(|s| &s.1) =>
            {
                return Err((first.file.clone(), table.file.clone()));
            }
            Some(_) => {}
            None => found = Some(table),
        }
    }
    Ok(found.and_then(|t| t.scenario.as_ref().map(|s| s.1.clone())))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_listed_unchanged_has_its_runs_provenance_and_an_edited_one_none() {
        let dir = tempfile::tempdir().unwrap();
        let table = b"test,dx_um\na,1\n";
        let manifest = json!({
            "scenario": { "file": "s.toml", "sha256": "aa" },
            "machine": { "name": "vmc3", "file": "vmc3.urdf", "sha256": "bb" },
            "files": [{ "name": "t.csv", "bytes": table.len(), "sha256": sha256_hex(table) }],
        });
        std::fs::write(dir.path().join("manifest.json"), manifest.to_string()).unwrap();
        let path = dir.path().join("t.csv");
        let p = Provenance::of(&path, "t.csv", table);
        assert_eq!(p.scenario, Some(("s.toml".into(), "aa".into())));
        assert_eq!(p.machine, Some(("vmc3.urdf".into(), "bb".into())));
        assert_eq!(p.note, None);
        let edited = Provenance::of(&path, "t.csv", b"test,dx_um\na,2\n");
        assert_eq!(edited.scenario, None);
        assert!(edited.note.unwrap().contains("edited"));
        let elsewhere = Provenance::of(&dir.path().join("u.csv"), "u.csv", table);
        assert_eq!((elsewhere.scenario, elsewhere.note), (None, None));
        // Two tables of two scenarios disagree; one without provenance does not count.
        let mut other = p.clone();
        other.file = "o.csv".into();
        other.scenario = Some(("o.toml".into(), "cc".into()));
        assert_eq!(
            common_scenario(&[p.clone(), elsewhere_none()]),
            Ok(Some("aa".into()))
        );
        assert_eq!(
            common_scenario(&[p, other]),
            Err(("t.csv".into(), "o.csv".into()))
        );
        assert_eq!(common_scenario(&[elsewhere_none()]), Ok(None));
    }

    fn elsewhere_none() -> Provenance {
        Provenance {
            file: "x.csv".into(),
            sha256: "00".into(),
            scenario: None,
            machine: None,
            note: None,
        }
    }
}
