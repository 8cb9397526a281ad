//! The `drift` measurement table: displacement channels against time, as the displacement
//! sensors of ISO 230-3 tests (ETVE, spindle, linear motion) record them, zeroed at the start.
//!
//! | column | required | meaning |
//! |---|---|---|
//! | `time_min` | yes | time since the start (min), increasing |
//! | `<channel>_um` | at least one channel | a linear displacement (µm) |
//! | `<channel>_urad` | | an angular displacement (µrad) |
//! | `temp_<sensor>_degc` | no | temperatures (°C); the first is taken as the ambient |

use crate::io::{TableError, csv_reader, finite_number, read_file, read_header, row};
use crate::math::{M_PER_UM, RAD_PER_URAD, Real};
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

/// A drift table.
#[derive(Clone, Debug, PartialEq)]
pub struct DriftTable {
    /// Times (s), increasing.
    pub times: Vec<Real>,
    /// The displacement channels, in column order.
    pub channels: Vec<DriftChannel>,
    /// Temperature sensors (name, values °C), in column order.
    pub temperatures: Vec<(String, Vec<Real>)>,
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
        };
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
}
