//! What every measurement-table reader shares: the error that names the file, line and column,
//! the header row (no column twice),
//! reading the file, and the CSV dialect (a header row, trimmed fields, `#` comment lines).

use std::path::Path;

/// Why a measurement table was rejected; the message names the file, line and column.
#[derive(Debug, thiserror::Error)]
#[error("{file}{}: {message}", .line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct TableError {
    file: String,
    line: Option<u64>,
    message: String,
}

impl TableError {
    /// An error at `line` (1-based) of `file`.
    pub(crate) fn new(file: &str, line: Option<u64>, message: String) -> TableError {
        TableError {
            file: file.to_string(),
            line,
            message,
        }
    }

    /// The 1-based line of the file the error is at, if any.
    pub fn line(&self) -> Option<u64> {
        self.line
    }
}

/// The bytes of a table file and its name for messages.
pub(crate) fn read_file(path: &Path) -> Result<(Vec<u8>, String), TableError> {
    let file = path.display().to_string();
    std::fs::read(path)
        .map(|bytes| (bytes, file.clone()))
        .map_err(|e| TableError::new(&file, None, format!("cannot read: {e}")))
}

/// A CSV reader in the tables' dialect.
pub(crate) fn csv_reader(bytes: &[u8]) -> csv::Reader<&[u8]> {
    csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(bytes)
}

/// The header row of a table, refused if it cannot be read or names a column twice.
pub(crate) fn read_header(
    reader: &mut csv::Reader<&[u8]>,
    file: &str,
) -> Result<csv::StringRecord, TableError> {
    let header = reader
        .headers()
        .map_err(|e| TableError::new(file, Some(1), format!("cannot read the header: {e}")))?
        .clone();
    for (index, name) in header.iter().enumerate() {
        if header.iter().skip(index + 1).any(|h| h == name) {
            return Err(TableError::new(
                file,
                Some(1),
                format!("column `{name}` appears twice"),
            ));
        }
    }
    Ok(header)
}

/// A data row of a table, or the error that names its line.
pub(crate) fn row(
    record: Result<csv::StringRecord, csv::Error>,
    file: &str,
) -> Result<csv::StringRecord, TableError> {
    record.map_err(|e| {
        TableError::new(
            file,
            e.position().map(|p| p.line()),
            format!("not a valid CSV row: {e}"),
        )
    })
}

/// The finite number in column `index` (named `name` in messages) of `record`.
pub(crate) fn finite_number(
    record: &csv::StringRecord,
    index: usize,
    name: &str,
    file: &str,
) -> Result<f64, TableError> {
    let text = &record[index];
    match text.parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        _ => Err(TableError::new(
            file,
            record.position().map(|p| p.line()),
            format!("column `{name}`: expected a finite number, found \"{text}\""),
        )),
    }
}
