//! The test conditions a measurement table carries: `# key = value` lines before its header
//! (its preamble), as a real instrument's export can carry them too.
//!
//! ```text
//! # mtwin ballbar table
//! # plane = XY
//! # radius_mm = 150
//! # feed_mm_per_min = 1000
//! direction,angle_deg,deviation_um,time_s
//! ccw,0.000000,1.234,0.000
//! ```
//!
//! Keys are lower-case letters, digits and `_`, with the unit in the name as everywhere else;
//! values are plain text (numbers as written, names without quotes). Comment lines that are not
//! `key = value` are free text. A file without a preamble reads as before: its conditions are
//! then given on the command line. A key given twice is refused.

use super::TableError;
use std::cell::Cell;

/// The `# key = value` lines of a table's preamble, in file order, with their lines. It
/// remembers which keys a reader asked for, so a reader can say which it left unused
/// ([`Conditions::unread`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Conditions {
    entries: Vec<(String, String, u64)>,
    read: Vec<Cell<bool>>,
}

impl Conditions {
    /// The conditions in `bytes` (the whole table): every `# key = value` line before the first
    /// line that is neither a comment nor blank. `file` names the table in messages.
    pub fn parse(bytes: &[u8], file: &str) -> Result<Conditions, TableError> {
        let text = String::from_utf8_lossy(bytes);
        let mut entries: Vec<(String, String, u64)> = Vec::new();
        for (index, line) in text.lines().enumerate() {
            let line_number = index as u64 + 1;
            let trimmed = line.trim_start_matches('\u{feff}').trim();
            if trimmed.is_empty() {
                continue;
            }
            let Some(comment) = trimmed.strip_prefix('#') else {
                break; // the header
            };
            let Some((key, value)) = comment.split_once('=') else {
                continue;
            };
            let key = key.trim();
            let is_key = !key.is_empty()
                && key
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
            if !is_key {
                continue;
            }
            if let Some((_, _, first)) = entries.iter().find(|(k, _, _)| k == key) {
                return Err(TableError::new(
                    file,
                    Some(line_number),
                    format!("`{key}` is given twice in the preamble (first on line {first})"),
                ));
            }
            entries.push((key.to_string(), value.trim().to_string(), line_number));
        }
        let read = vec![Cell::new(false); entries.len()];
        Ok(Conditions { entries, read })
    }

    /// Conditions from `(key, value)` pairs, for writing.
    pub fn from_pairs<K: Into<String>>(pairs: impl IntoIterator<Item = (K, String)>) -> Self {
        let entries: Vec<_> = pairs.into_iter().map(|(k, v)| (k.into(), v, 0)).collect();
        let read = vec![Cell::new(false); entries.len()];
        Conditions { entries, read }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The value of `key` and its 1-based line, if given; the key counts as read.
    pub fn get(&self, key: &str) -> Option<(&str, u64)> {
        let index = self.entries.iter().position(|(k, _, _)| k == key)?;
        self.read[index].set(true);
        let (_, value, line) = &self.entries[index];
        Some((value.as_str(), *line))
    }

    /// The value of `key`, if given, without counting it as read: for a reader that carries
    /// keys it does not know.
    pub fn value(&self, key: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|(k, _, _)| k == key)
            .map(|(_, v, _)| v.as_str())
    }

    /// The keys no reader has asked for ([`Conditions::get`] and the typed getters), with
    /// their lines, in file order: what a table said that its reader did not use.
    pub fn unread(&self) -> Vec<(String, u64)> {
        self.entries
            .iter()
            .zip(&self.read)
            .filter(|(_, read)| !read.get())
            .map(|((key, _, line), _)| (key.clone(), *line))
            .collect()
    }

    /// The keys, in file order.
    pub fn keys(&self) -> impl Iterator<Item = &str> {
        self.entries.iter().map(|(k, _, _)| k.as_str())
    }

    /// The number under `key`, if given; a value that is not a finite number is an error naming
    /// the file, line and key.
    pub fn number(&self, key: &str, file: &str) -> Result<Option<f64>, TableError> {
        let Some((text, line)) = self.get(key) else {
            return Ok(None);
        };
        match text.parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(Some(value)),
            _ => Err(TableError::new(
                file,
                Some(line),
                format!("{key} = {text}: expected a finite number"),
            )),
        }
    }

    /// The three numbers under `key` (`x y z`, separated by spaces), if given; anything else
    /// is an error naming the file, line and key.
    pub fn triple(&self, key: &str, file: &str) -> Result<Option<[f64; 3]>, TableError> {
        let Some((text, line)) = self.get(key) else {
            return Ok(None);
        };
        let values: Option<Vec<f64>> = text
            .split_whitespace()
            .map(|v| v.parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect();
        match values.as_deref() {
            Some(&[x, y, z]) => Ok(Some([x, y, z])),
            _ => Err(TableError::new(
                file,
                Some(line),
                format!("{key} = {text}: expected three numbers separated by spaces"),
            )),
        }
    }

    /// The preamble as text: a title line, then one `# key = value` line per condition.
    pub fn to_preamble(&self, title: &str) -> String {
        let mut text = format!("# {title}\n");
        for (key, value, _) in &self.entries {
            text += &format!("# {key} = {value}\n");
        }
        text
    }
}

/// The report's line for preamble keys its reader does not know (empty without any): they
/// are kept, but no figure depends on them, and a user should know that.
pub fn not_used_line<S: AsRef<str>>(keys: impl IntoIterator<Item = S>) -> String {
    let keys: Vec<String> = keys.into_iter().map(|k| k.as_ref().to_string()).collect();
    if keys.is_empty() {
        return String::new();
    }
    format!(
        "Not used from the preamble (unknown to this reader): {}.\n",
        keys.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_key_value_lines_before_the_header_only() {
        let text = "\u{feff}# mtwin ballbar table\n# plane = XY\n#radius_mm=150\n\n# free text: a = b c\ndirection,angle_deg\n# plane = YZ\nccw,0\n";
        let c = Conditions::parse(text.as_bytes(), "t.csv").unwrap();
        assert_eq!(c.get("plane"), Some(("XY", 2)));
        assert_eq!(c.get("radius_mm"), Some(("150", 3)));
        // `free text: a` is not a key; the `# plane = YZ` after the header is not the preamble.
        assert_eq!(c.keys().collect::<Vec<_>>(), ["plane", "radius_mm"]);
        assert_eq!(c.number("radius_mm", "t.csv").unwrap(), Some(150.0));
    }

    #[test]
    fn refuses_a_key_twice_and_a_number_that_is_not_one() {
        let twice = Conditions::parse(b"# plane = XY\n# plane = YZ\na\n", "t.csv").unwrap_err();
        assert_eq!(twice.line(), Some(2));
        assert!(twice.to_string().contains("given twice"), "{twice}");
        let c = Conditions::parse(b"# radius_mm = 1O0\na\n", "t.csv").unwrap();
        let bad = c.number("radius_mm", "t.csv").unwrap_err();
        assert_eq!(
            bad.to_string(),
            "t.csv:1: radius_mm = 1O0: expected a finite number"
        );
    }

    #[test]
    fn writes_what_it_reads() {
        let c = Conditions::from_pairs([("plane", "XY".to_string()), ("radius_mm", "150".into())]);
        let text = c.to_preamble("mtwin ballbar table") + "direction\n";
        let back = Conditions::parse(text.as_bytes(), "t.csv").unwrap();
        assert_eq!(back.get("plane"), Some(("XY", 2)));
        assert_eq!(back.get("radius_mm"), Some(("150", 3)));
    }
}
