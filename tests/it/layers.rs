//! The crate's layering, as its docs state it (`src/lib.rs`, `src/kinds/mod.rs`): each
//! top-level module uses only the modules listed before it; a test kind uses the shared
//! layers and itself, never another kind (but for the one stated edge: the positioning
//! kind's thermal-series view uses the drift kind's ISO 230-3 functions); no kind uses `app`
//! (a verb is handed a `ScenarioLoader` by the binary instead).
//!
//! Independent of the code under test: the imports are read from the source text.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The layers, lowest first.
const LAYERS: [&str; 15] = [
    "math",
    "machine",
    "errors",
    "thermal",
    "program",
    "twin",
    "io",
    "contact",
    "collision",
    "scenario",
    "discovery",
    "estimate",
    "viz",
    "kinds",
    "app",
];

/// Which kinds each kind may use besides itself.
const KIND_EDGES: [(&str, &str); 1] = [("positioning", "drift")];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Every `crate::a::b` path in the code of `text` (comments and doc comments left out), as
/// `[a, b]` (b empty when absent).
fn crate_paths(text: &str) -> BTreeSet<(String, String)> {
    let mut paths = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            let before = rest[..at].chars().next_back();
            let after = &rest[at + "crate::".len()..];
            rest = after;
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue; // e.g. `mtwin_crate::`
            }
            if let Some(group) = after.strip_prefix('{') {
                // `crate::{a::B, c::D}` on one line.
                let group = group.split('}').next().unwrap_or("");
                for item in group.split(',') {
                    let mut parts = item.trim().split("::");
                    let first = parts.next().unwrap_or("").to_string();
                    let second = parts.next().unwrap_or("").trim_matches('{').to_string();
                    paths.insert((first, second));
                }
                continue;
            }
            let mut parts = after.split("::").map(|p| {
                p.split(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .next()
                    .unwrap_or("")
            });
            let first = parts.next().unwrap_or("").to_string();
            let second = parts.next().unwrap_or("").to_string();
            paths.insert((first, second));
        }
    }
    paths
}

#[test]
fn every_module_uses_only_the_layers_below_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let layer = |name: &str| LAYERS.iter().position(|l| *l == name);
    let mut broken = Vec::new();
    for file in &files {
        let relative = file.strip_prefix(&src).unwrap();
        let parts: Vec<String> = relative
            .iter()
            .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
            .collect();
        let Some(own) = layer(&parts[0]) else {
            continue; // lib.rs, main.rs
        };
        let own_kind = (parts[0] == "kinds" && parts.len() > 2).then(|| parts[1].clone());
        let text = std::fs::read_to_string(file).unwrap();
        for (module, sub) in crate_paths(&text) {
            let Some(used) = layer(&module) else {
                continue;
            };
            // Never up a layer (a kind's `cli.rs` included: it is handed what it needs).
            let allowed = if used > own {
                false
            } else if module == "kinds" && parts[0] == "kinds" {
                match &own_kind {
                    // kinds/mod.rs names every kind
                    None => true,
                    Some(kind) => {
                        sub.is_empty()
                            || sub == *kind
                            || KIND_EDGES.contains(&(kind.as_str(), sub.as_str()))
                            // the registry types
                            || sub == "Kind"
                            || sub == "Verb"
                            || sub == "ScenarioLoader"
                    }
                }
            } else {
                true
            };
            if !allowed {
                broken.push(format!(
                    "{} uses crate::{module}::{sub}",
                    relative.display()
                ));
            }
        }
    }
    assert!(
        broken.is_empty(),
        "imports against the layering: {broken:#?}"
    );
}

#[test]
fn the_layer_reader_sees_imports_and_skips_comments() {
    // The checker itself: a `use` is seen, a path in a comment or a doc comment is not.
    let text = "use crate::machine::Axis;\n/// see [`crate::app`]\nlet x = crate::math::Real::MAX; // crate::kinds\nuse crate::{twin::Twin, io::TableError};\n";
    let paths = crate_paths(text);
    assert!(paths.contains(&("machine".into(), "Axis".into())));
    assert!(paths.contains(&("math".into(), "Real".into())));
    assert!(paths.contains(&("twin".into(), "Twin".into())));
    assert!(paths.contains(&("io".into(), "TableError".into())));
    assert_eq!(paths.len(), 4, "{paths:?}");
}
