//! Writing files whole: each goes to a temporary name beside its target and is renamed when
//! complete, so a failure leaves no partial file and a reader never sees half of one.

use std::path::Path;

/// A file or folder that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{path}: cannot write: {message}")]
pub struct WriteError {
    /// The file or folder.
    pub path: String,
    /// The system's message.
    pub message: String,
}

impl WriteError {
    fn new(path: &Path, error: std::io::Error) -> WriteError {
        WriteError {
            path: path.display().to_string(),
            message: error.to_string(),
        }
    }
}

/// The temporary name of `name` in `dir` while it is being written.
fn temporary(dir: &Path, name: &str) -> std::path::PathBuf {
    dir.join(format!(".{name}.partial"))
}

/// Writes `(file name, bytes)` pairs into `dir` (created if needed). All are first written
/// under temporary names and only then renamed, so a failure while writing or renaming leaves
/// none of the new files (and removes the temporary ones). A file this call replaced is gone
/// if a later rename fails.
pub fn write_files(files: &[(String, Vec<u8>)], dir: &Path) -> Result<(), WriteError> {
    std::fs::create_dir_all(dir).map_err(|e| WriteError::new(dir, e))?;
    for (index, (name, bytes)) in files.iter().enumerate() {
        if let Err(e) = std::fs::write(temporary(dir, name), bytes) {
            for (written, _) in &files[..=index] {
                let _ = std::fs::remove_file(temporary(dir, written)); // best effort: already failing
            }
            return Err(WriteError::new(&dir.join(name), e));
        }
    }
    for (index, (name, _)) in files.iter().enumerate() {
        let target = dir.join(name);
        if let Err(e) = std::fs::rename(temporary(dir, name), &target) {
            // Best effort, already failing: take back the files renamed so far and remove the
            // temporary ones left, so that nothing of this write remains.
            for (renamed, _) in &files[..index] {
                let _ = std::fs::remove_file(dir.join(renamed));
            }
            for (left, _) in &files[index..] {
                let _ = std::fs::remove_file(temporary(dir, left));
            }
            return Err(WriteError {
                path: target.display().to_string(),
                message: format!("cannot put the file in place: {e}"),
            });
        }
    }
    Ok(())
}

/// Writes `bytes` to `path` through a temporary file beside it.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let name = path.file_name().ok_or_else(|| WriteError {
        path: path.display().to_string(),
        message: "not a file name".into(),
    })?;
    let temporary = path.with_file_name(format!(".{}.partial", name.to_string_lossy()));
    std::fs::write(&temporary, bytes).map_err(|e| WriteError::new(path, e))?;
    std::fs::rename(&temporary, path).map_err(|e| WriteError::new(path, e))
}

/// Refuses, before any long work, a file that cannot be written because the folder that
/// would hold it does not exist (or is not a folder).
pub fn check_folder_of(path: &Path) -> Result<(), WriteError> {
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if folder.is_dir() {
        Ok(())
    } else {
        Err(WriteError {
            path: path.display().to_string(),
            message: format!("the folder {} does not exist", folder.display()),
        })
    }
}
