//! The `drift` measurement table: displacement channels against time, as the displacement
//! sensors of ISO 230-3 tests (ETVE, spindle, linear motion) record them, zeroed at the start.
//!
//! | column | required | meaning |
//! |---|---|---|
//! | `time_min` | yes | time since the start (min), increasing |
//! | `<channel>_um` | at least one channel | a linear displacement (µm) |
//! | `<channel>_urad` | | an angular displacement (µrad) |
//! | `temp_<sensor>_degc` | no | temperatures (°C); the ambient is the preamble's `ambient_sensor`, else the first |
//!
//! The test's conditions travel in the file's preamble (`# key = value` lines before the
//! header, see [`crate::io::Conditions`]), as `mtwin run` writes them and a real export can
//! carry them; a table without one reads as well:
//!
//! | key | meaning |
//! |---|---|
//! | `test` | the test, e.g. `iso230_3_etve` |
//! | `ambient_sensor` | the `<sensor>` of the ambient air's column |
//! | `spacing_mm` | l, the distance between the two sensors of a pair (`x1`/`x2`, `y1`/`y2`): the tilts A and B follow from it |
//! | `control` | `hold` or `off`, the machine's state |
//! | `hold_mm` | where the axes stood, e.g. `x 380, y 205, z 200` |
//! | `first_mm` | the height of the first pair above the tool point |

use crate::io::{Conditions, TableError, csv_reader, finite_number, read_file, read_header, row};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_URAD, Real, fixed, trimmed};
use std::path::Path;

/// One displacement channel.
#[derive(Clone, Debug, PartialEq)]
pub struct DriftChannel {
    /// Its name (the column without the unit).
    pub name: String,
    /// Whether it is angular (rad) rather than linear (m).
    pub angular: bool,
    /// Values (m or rad), one per row.
    pub values: Vec<Real>,
}

/// The conditions of a drift test, as a table's preamble gives them (SI; each absent when the
/// file does not say). Keys other than these are kept in the preamble and left alone.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriftConditions {
    /// The test, e.g. `iso230_3_etve`.
    pub test: Option<String>,
    /// The ambient air's sensor.
    pub ambient_sensor: Option<String>,
    /// The distance between the two sensors of a pair (m).
    pub spacing: Option<Real>,
    /// Everything else the preamble says, in order (e.g. `control`, `hold_mm`, `first_mm`).
    pub other: Vec<(String, String)>,
}

impl DriftConditions {
    /// The typed conditions of a preamble; a value of the wrong form is an error naming the
    /// file, line and key.
    pub fn from_preamble(c: &Conditions, file: &str) -> Result<DriftConditions, TableError> {
        let spacing = match c.number("spacing_mm", file)? {
            Some(v) if v <= 0.0 => {
                return Err(TableError::new(
                    file,
                    c.get("spacing_mm").map(|(_, line)| line),
                    format!("spacing_mm = {v}: expected a positive distance"),
                ));
            }
            other => other.map(|mm| mm * M_PER_MM),
        };
        let typed = ["test", "ambient_sensor", "spacing_mm"];
        Ok(DriftConditions {
            test: c.get("test").map(|(v, _)| v.to_string()),
            ambient_sensor: c.get("ambient_sensor").map(|(v, _)| v.to_string()),
            spacing,
            other: c
                .keys()
                .filter(|k| !typed.contains(k))
                .map(|k| {
                    (
                        k.to_string(),
                        c.get(k).map_or_else(String::new, |(v, _)| v.to_string()),
                    )
                })
                .collect(),
        })
    }

    /// The preamble that says these conditions (file units).
    pub fn to_preamble(&self) -> Conditions {
        let mut pairs: Vec<(String, String)> = Vec::new();
        if let Some(test) = &self.test {
            pairs.push(("test".into(), test.clone()));
        }
        if let Some(sensor) = &self.ambient_sensor {
            pairs.push(("ambient_sensor".into(), sensor.clone()));
        }
        if let Some(spacing) = self.spacing {
            pairs.push(("spacing_mm".into(), trimmed(spacing / M_PER_MM, 6)));
        }
        pairs.extend(self.other.iter().cloned());
        Conditions::from_pairs(pairs)
    }
}

/// A drift table.
#[derive(Clone, Debug, PartialEq)]
pub struct DriftTable {
    /// Times (s), increasing.
    pub times: Vec<Real>,
    /// The displacement channels, in column order.
    pub channels: Vec<DriftChannel>,
    /// Temperature sensors (name, values °C), in column order.
    pub temperatures: Vec<(String, Vec<Real>)>,
    /// The test conditions from the file's preamble (none for a file without one).
    pub conditions: DriftConditions,
}

impl DriftTable {
    /// Reads a drift table file.
    pub fn read(path: impl AsRef<Path>) -> Result<DriftTable, TableError> {
        let (bytes, file) = read_file(path.as_ref())?;
        DriftTable::parse(&bytes, &file)
    }

    /// Reads a drift table from bytes; `file` names it in messages.
    pub fn parse(bytes: &[u8], file: &str) -> Result<DriftTable, TableError> {
        let fail = |line: Option<u64>, message: String| TableError::new(file, line, message);
        let stated = Conditions::parse(bytes, file)?;
        let conditions = DriftConditions::from_preamble(&stated, file)?;
        let mut reader = csv_reader(bytes);
        let (header, header_line) = read_header(&mut reader, file)?;
        let mut time_column = None;
        let mut channels = Vec::new(); // (column, name, angular)
        let mut sensors = Vec::new(); // (column, name)
        for (index, name) in header.iter().enumerate() {
            if name == "time_min" {
                time_column = Some(index);
            } else if let Some(sensor) = name
                .strip_prefix("temp_")
                .and_then(|r| r.strip_suffix("_degc"))
                .filter(|s| !s.is_empty())
            {
                sensors.push((index, sensor.to_string()));
            } else if let Some(channel) = name.strip_suffix("_urad").filter(|c| !c.is_empty()) {
                channels.push((index, channel.to_string(), true));
            } else if let Some(channel) = name.strip_suffix("_um").filter(|c| !c.is_empty()) {
                channels.push((index, channel.to_string(), false));
            } else {
                return Err(fail(
                    Some(header_line),
                    format!(
                        "unknown column `{name}`: expected time_min, <channel>_um, <channel>_urad or temp_<sensor>_degc"
                    ),
                ));
            }
        }
        let time_column = time_column
            .ok_or_else(|| fail(Some(header_line), "missing column `time_min`".into()))?;
        if channels.is_empty() {
            return Err(fail(
                Some(header_line),
                "no displacement column: expected at least one <channel>_um or <channel>_urad"
                    .into(),
            ));
        }
        let mut table = DriftTable {
            times: Vec::new(),
            channels: channels
                .iter()
                .map(|(_, name, angular)| DriftChannel {
                    name: name.clone(),
                    angular: *angular,
                    values: Vec::new(),
                })
                .collect(),
            temperatures: sensors
                .iter()
                .map(|(_, name)| (name.clone(), Vec::new()))
                .collect(),
            conditions,
        };
        if let Some(sensor) = &table.conditions.ambient_sensor
            && !table.temperatures.iter().any(|(name, _)| name == sensor)
        {
            return Err(fail(
                stated.get("ambient_sensor").map(|(_, line)| line),
                format!("ambient_sensor = {sensor}, but there is no column temp_{sensor}_degc"),
            ));
        }
        for record in reader.records() {
            let record = row(record, bytes, file)?;
            let line = record.position().map(|p| p.line());
            let number = |index: usize| finite_number(&record, index, &header[index], file);
            let time = number(time_column)? * 60.0;
            if table.times.last().is_some_and(|last| time <= *last) {
                return Err(fail(line, "column `time_min`: times must increase".into()));
            }
            table.times.push(time);
            for ((index, _, angular), channel) in channels.iter().zip(&mut table.channels) {
                channel
                    .values
                    .push(number(*index)? * if *angular { RAD_PER_URAD } else { M_PER_UM });
            }
            for ((index, _), (_, values)) in sensors.iter().zip(&mut table.temperatures) {
                values.push(number(*index)?);
            }
        }
        if table.times.len() < 2 {
            return Err(fail(
                None,
                "fewer than two rows: a drift record needs readings over time".into(),
            ));
        }
        Ok(table)
    }

    /// The ambient air's temperatures: the preamble's `ambient_sensor`, else the first
    /// temperature column.
    pub fn ambient(&self) -> Option<&(String, Vec<Real>)> {
        match &self.conditions.ambient_sensor {
            Some(sensor) => self.temperatures.iter().find(|(name, _)| name == sensor),
            None => self.temperatures.first(),
        }
    }

    /// Writes the table: its conditions as a preamble (when it has any), then `time_min`, the
    /// channels (`<name>_um` or `_urad`) and `temp_<sensor>_degc`; times to 1 µmin,
    /// displacements to 1 pm or 1 prad, temperatures to 1 µK, so the same table gives the
    /// same bytes.
    pub fn write_csv(&self, mut out: impl std::io::Write) -> csv::Result<()> {
        let preamble = self.conditions.to_preamble();
        if !preamble.is_empty() {
            out.write_all(
                preamble
                    .to_preamble("mtwin drift table (ISO 230-3)")
                    .as_bytes(),
            )?;
        }
        let mut writer = csv::Writer::from_writer(out);
        let mut header = vec!["time_min".to_string()];
        header.extend(
            self.channels
                .iter()
                .map(|c| format!("{}_{}", c.name, if c.angular { "urad" } else { "um" })),
        );
        header.extend(
            self.temperatures
                .iter()
                .map(|(s, _)| format!("temp_{s}_degc")),
        );
        writer.write_record(&header)?;
        for (row, time) in self.times.iter().enumerate() {
            let mut record = vec![fixed(time / 60.0, 6)];
            record.extend(self.channels.iter().map(|c| fixed(c.values[row] * 1e6, 6)));
            record.extend(self.temperatures.iter().map(|(_, v)| fixed(v[row], 6)));
            writer.write_record(&record)?;
        }
        writer.flush()?;
        Ok(())
    }
}
