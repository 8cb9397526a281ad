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

/// The header row of a table and its 1-based line (after any preamble), refused if it cannot
/// be read or names a column twice. A trailing comma on every line (a spreadsheet's export)
/// leaves an unnamed last column: it is dropped from the header when it holds nothing, and
/// refused when a row puts a value under it (a header one name short).
pub(crate) fn read_header(
    reader: &mut csv::Reader<&[u8]>,
    file: &str,
) -> Result<(csv::StringRecord, u64), TableError> {
    // The whole table, taken before the reader consumes it.
    let bytes: &[u8] = reader.get_ref();
    let line = record_line(bytes, 0, 1);
    let mut header = reader
        .headers()
        .map_err(|e| TableError::new(file, Some(line), format!("cannot read the header: {e}")))?
        .clone();
    if header.len() > 1 && header.get(header.len() - 1) == Some("") {
        for record in csv_reader(bytes).records() {
            let record = row(record, bytes, file)?;
            if record.get(header.len() - 1).is_some_and(|v| !v.is_empty()) {
                return Err(TableError::new(
                    file,
                    record.position().map(|p| p.line()),
                    format!(
                        "the last column has no name in the header but holds \"{}\" here: a header one name short?",
                        &record[header.len() - 1]
                    ),
                ));
            }
        }
        header.truncate(header.len() - 1);
    }
    // A set, not a pairwise scan: a header of 100 000 names is checked in milliseconds.
    let mut seen = std::collections::HashSet::with_capacity(header.len());
    for name in header.iter() {
        if !seen.insert(name) {
            return Err(TableError::new(
                file,
                Some(line),
                format!("column `{name}` appears twice"),
            ));
        }
    }
    Ok((header, line))
}

/// The 1-based line of the record that starts reading at `byte` of `bytes`, which is on line
/// `line` (the reader's count): the reader's positions point at the first byte after the
/// record before, so the comment and blank lines it then skips are stepped over here. Only
/// those lines are scanned, so reading a table stays linear in its length.
fn record_line(bytes: &[u8], byte: u64, line: u64) -> u64 {
    let start = (byte as usize).min(bytes.len());
    let mut line = line;
    for text in bytes[start..].split(|b| *b == b'\n') {
        let text = text.strip_prefix("\u{feff}".as_bytes()).unwrap_or(text);
        let text = text.trim_ascii();
        if !text.is_empty() && !text.starts_with(b"#") {
            break;
        }
        line += 1;
    }
    line
}

/// A data row of a table, or the error that names its line. `bytes` is the whole table: the
/// reader's position of a row is where it started reading it, before the comment lines it
/// skipped, so the row's own line is found from there and set on the record for the messages
/// that follow.
pub(crate) fn row(
    record: Result<csv::StringRecord, csv::Error>,
    bytes: &[u8],
    file: &str,
) -> Result<csv::StringRecord, TableError> {
    let line_at = |position: &csv::Position| record_line(bytes, position.byte(), position.line());
    match record {
        Ok(mut record) => {
            if let Some(position) = record.position() {
                let mut position = position.clone();
                position.set_line(line_at(&position));
                record.set_position(Some(position));
            }
            Ok(record)
        }
        Err(e) => Err(TableError::new(
            file,
            e.position().map(line_at),
            format!("not a valid CSV row: {e}"),
        )),
    }
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

/// An instrument's range: readings beyond ±`limit` (file units) cannot come from it, so a
/// reader refuses them instead of evaluating them (a unit slip, a corrupted cell).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// The largest magnitude a reading can have (file units).
    pub limit: f64,
    /// Why, with its source: what reads that far and no further.
    pub why: &'static str,
}

/// A temperature column's range (°C): every table's `temp_<sensor>_degc`. A machine tool's air
/// and structure stay far inside ±200 °C (a Pt100's usual range is −50 … 200 °C).
pub const THERMOMETER: Range = Range {
    limit: 200.0,
    why: "no machine tool's air or structure is that hot or cold",
};

/// A time column's range in seconds (`time_s`): a test record lasts hours or days, not years.
pub const CLOCK_S: Range = Range {
    limit: 1e8,
    why: "about three years: no test record lasts that long",
};

/// A time column's range in minutes (`time_min`): [`CLOCK_S`] in minutes.
pub const CLOCK_MIN: Range = Range {
    limit: 1e8 / 60.0,
    why: "about three years: no test record lasts that long",
};

/// [`finite_number`] within `range`; beyond it, an error naming the file, line, column, value
/// and the range's reason.
pub(crate) fn number_within(
    record: &csv::StringRecord,
    index: usize,
    name: &str,
    file: &str,
    range: Range,
) -> Result<f64, TableError> {
    let value = finite_number(record, index, name, file)?;
    if value.abs() > range.limit {
        return Err(TableError::new(
            file,
            record.position().map(|p| p.line()),
            format!(
                "column `{name}`: {} is beyond ±{} ({}); units?",
                crate::math::readable(value),
                range.limit,
                range.why
            ),
        ));
    }
    Ok(value)
}

/// Where a table about to be written holds a number that is not finite: its 1-based line, the
/// column (or the preamble key) and the text, or `None` when every number is finite.
///
/// A table is text, so this reads it as any reader would: every comma-separated field of a
/// data row, and every value of a `# key = value` preamble line, that parses as a number
/// (`inf`, `NaN` and overflowing literals included) must be finite. Linear in the table's length.
pub fn first_non_finite(bytes: &[u8]) -> Option<(u64, String, String)> {
    let text = String::from_utf8_lossy(bytes);
    let mut header: Option<Vec<&str>> = None;
    let not_finite = |field: &str| field.trim().parse::<f64>().is_ok_and(|v| !v.is_finite());
    for (index, line) in text.lines().enumerate() {
        let line_number = index as u64 + 1;
        if let Some(comment) = line.trim_start().strip_prefix('#') {
            if let Some((key, value)) = comment.split_once('=') {
                let bad = value
                    .split(|c: char| c == ',' || c.is_whitespace())
                    .find(|v| not_finite(v));
                if let Some(bad) = bad {
                    return Some((line_number, key.trim().to_string(), bad.trim().to_string()));
                }
            }
            continue;
        }
        if line.trim().is_empty() {
            continue;
        }
        let Some(names) = &header else {
            header = Some(line.split(',').map(str::trim).collect());
            continue;
        };
        if let Some((column, field)) = line.split(',').enumerate().find(|(_, f)| not_finite(f)) {
            let name = names.get(column).copied().unwrap_or("?");
            return Some((line_number, name.to_string(), field.trim().to_string()));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_line_counts_the_preamble() {
        let text = b"# mtwin table\n# plane = XY\n\na,b,a\n1,2,3\n";
        let error = read_header(&mut csv_reader(text), "t.csv").unwrap_err();
        assert_eq!(error.line(), Some(4), "{error}");
        let (header, line) = read_header(&mut csv_reader(b"a,b\n1,2\n"), "t.csv").unwrap();
        assert_eq!((header.len(), line), (2, 1));
        // Data rows: the reader counts the comment lines it skipped.
        let mut reader = csv_reader(b"# a = 1\nx,y\n# note\n1,z\n");
        read_header(&mut reader, "t.csv").unwrap();
        let record = row(
            reader.records().next().unwrap(),
            b"# a = 1\nx,y\n# note\n1,z\n",
            "t.csv",
        )
        .unwrap();
        let error = finite_number(&record, 1, "y", "t.csv").unwrap_err();
        assert_eq!(error.line(), Some(4), "{error}");
    }

    #[test]
    fn a_trailing_comma_on_every_line_is_no_column_and_a_value_under_it_is_refused() {
        let text = b"# zero = once\na,b,\n1,2,\n3,4,\n";
        let mut reader = csv_reader(text);
        let (header, _) = read_header(&mut reader, "t.csv").unwrap();
        assert_eq!(header.iter().collect::<Vec<_>>(), ["a", "b"]);
        let rows: Vec<_> = reader.records().map(|r| r.unwrap()).collect();
        assert_eq!((&rows[1][0], &rows[1][1]), ("3", "4"));
        let short = b"a,b,\n1,2,\n3,4,5\n";
        let error = read_header(&mut csv_reader(short), "t.csv").unwrap_err();
        assert_eq!(error.line(), Some(3), "{error}");
        assert!(error.to_string().contains("holds \"5\""), "{error}");
    }

    #[test]
    fn finds_the_first_non_finite_number_with_its_line_and_column() {
        let clean = b"# mtwin table\n# radius_mm = 150\nangle_deg,deviation_um\n0,0.5\n1,-0.25\n";
        assert_eq!(first_non_finite(clean), None);
        let row = b"# radius_mm = 150\nangle_deg,deviation_um\n0,0.5\n1, inf\n2,NaN\n";
        assert_eq!(
            first_non_finite(row),
            Some((4, "deviation_um".into(), "inf".into()))
        );
        // A literal beyond f64's range reads as infinite too.
        let literal = b"a,b\n1e999,0\n";
        assert_eq!(
            first_non_finite(literal),
            Some((2, "a".into(), "1e999".into()))
        );
        let preamble = b"# speeds_rpm = 1000, inf\na\n1\n";
        assert_eq!(
            first_non_finite(preamble),
            Some((1, "speeds_rpm".into(), "inf".into()))
        );
        // Words are not numbers: a text column named "info" or a value "infeed" is no alarm.
        let words = b"# test = infeed\ntest,x\ninfo,1\n";
        assert_eq!(first_non_finite(words), None);
    }
}
