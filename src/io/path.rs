//! Paths between files: how a written file names another one.

use std::path::{Path, PathBuf};

/// A path that could not be resolved.
#[derive(Debug, thiserror::Error)]
#[error("cannot resolve {path}: {message}")]
pub struct PathError {
    /// The path.
    pub path: String,
    /// The system's message.
    pub message: String,
}

/// `target` as a path relative to the folder that will hold `file` (both must exist but
/// `file`), with `/` separators, as a scenario written into that folder names it.
pub fn relative_path(target: &Path, file: &Path) -> Result<String, PathError> {
    let folder = match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let absolute = |p: &Path| {
        p.canonicalize().map_err(|e| PathError {
            path: p.display().to_string(),
            message: e.to_string(),
        })
    };
    let (target, folder) = (absolute(target)?, absolute(folder)?);
    let common = target
        .components()
        .zip(folder.components())
        .take_while(|(a, b)| a == b)
        .count();
    let mut relative = PathBuf::new();
    for _ in folder.components().skip(common) {
        relative.push("..");
    }
    relative.extend(target.components().skip(common));
    Ok(relative.to_string_lossy().replace('\\', "/"))
}
