//! The `drift` measurement table: displacement channels against time, as the displacement
//! sensors of ISO 230-3 tests (ETVE, spindle, linear motion) record them, zeroed at the start.
//!
//! | column | required | meaning |
//! |---|---|---|
//! | `time_min` | yes | time since the start (min); or `time_s` (s), `time_h` (h) |
//! | `<channel>_um` | at least one channel | a linear displacement (µm) |
//! | `<channel>_urad` | | an angular displacement (µrad) |
//! | `temp_<sensor>_degc` | no | temperatures (°C); the ambient is the preamble's `ambient_sensor`, else the first |
//!
//! Any other column (the date, the humidity, a pressure) is read past and listed in the report
//! as not read, unless it looks like a channel, a clock or a thermometer written another way
//! (`x` without its unit, `x_nm`, `a_arcsec`, `temp_c`, `Time (min)`), which is refused by name.
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
//! | `programme` | the spindle test's speed programme: `constant` (with `speed_rpm`) or `spectrum` (with `spectrum`, its steps as text) |
//! | `run_min` | the end of the running period t: the figures d(·)_t are taken up to it, and it must lie inside the record |
//! | `stop_min` | how long the spindle stood after it; a record that ends more than a sample early is said to |
//!
//! `mtwin analyze drift` says each of them again; keys it does not know are named as not used.

use super::scenario::ControlMode;
use crate::io::{
    Conditions, Range, TableError, csv_reader, number_within, read_file, read_header, row,
};

/// A drift channel's range (µm or µrad): thermal drift is micrometres, and the displacement
/// sensors of an ISO 230-3 nest read a few millimetres at most; 10 mm (10 mrad for a tilt) is
/// the limit scenarios put on any error.
pub const SENSOR: Range = Range {
    limit: 10_000.0,
    why: "thermal drift is µm, and the nest's sensors read a few mm at most",
};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_URAD, Real, fixed, trimmed};
use std::path::Path;

/// A data row as read: its time (s), line, displacements (SI) and temperatures (°C).
type ReadRow = (Real, Option<u64>, Vec<Real>, Vec<Real>);

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
/// file does not say). Every key `mtwin` writes is read, checked where the data can check it,
/// and said again by `mtwin analyze drift`; keys it does not know are kept in `other`, in
/// order, and named by the report as not used.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriftConditions {
    /// The test, e.g. `iso230_3_etve`.
    pub test: Option<String>,
    /// The ambient air's sensor.
    pub ambient_sensor: Option<String>,
    /// The distance between the two sensors of a pair (m).
    pub spacing: Option<Real>,
    /// The machine's state during the test (ISO 230-3 §5.4 k: hold or off).
    pub control: Option<ControlMode>,
    /// Where the axes stood, as written: `x 380, y 205, z 260` (each a letter and mm).
    pub hold: Option<String>,
    /// The height of the first sensor pair above the tool point (m).
    pub first: Option<Real>,
    /// The spindle's speed programme (spindle test): `constant` or `spectrum`.
    pub programme: Option<String>,
    /// The constant speed (rpm) of a `constant` programme.
    pub speed_rpm: Option<Real>,
    /// The steps of a `spectrum` programme, as written (`3000 rpm for 20 min, …`).
    pub spectrum: Option<String>,
    /// The end of the running period t (s from the start): ISO 230-3 Table 1's d(·)_t ends here.
    pub run_period: Option<Real>,
    /// How long the spindle stood after the running period (s).
    pub stop: Option<Real>,
    /// Keys this reader does not know, in order, with their values.
    pub other: Vec<(String, String)>,
}

/// The preamble keys of [`DriftConditions`], in the order they are written.
const KEYS: [&str; 11] = [
    "test",
    "ambient_sensor",
    "spacing_mm",
    "control",
    "hold_mm",
    "first_mm",
    "programme",
    "speed_rpm",
    "spectrum",
    "run_min",
    "stop_min",
];

impl DriftConditions {
    /// The typed conditions of a preamble; a value of the wrong form is an error naming the
    /// file, line and key.
    pub fn from_preamble(c: &Conditions, file: &str) -> Result<DriftConditions, TableError> {
        let wrong = |key: &str, expected: &str| {
            let (text, line) = c.get(key).unwrap_or_default();
            TableError::new(
                file,
                Some(line),
                format!("{key} = {text}: expected {expected}"),
            )
        };
        let positive = |key: &str, scale: Real| -> Result<Option<Real>, TableError> {
            match c.number(key, file)? {
                Some(v) if v <= 0.0 => Err(wrong(key, "a positive number")),
                other => Ok(other.map(|v| v * scale)),
            }
        };
        let spacing = positive("spacing_mm", M_PER_MM)?;
        let first = match c.number("first_mm", file)? {
            Some(v) if v < 0.0 => return Err(wrong("first_mm", "a height of 0 or more")),
            other => other.map(|mm| mm * M_PER_MM),
        };
        let control = match c.get("control") {
            None => None,
            Some(("hold", _)) => Some(ControlMode::Hold),
            Some(("off", _)) => Some(ControlMode::Off),
            Some(_) => return Err(wrong("control", "hold or off (ISO 230-3 §5.4 k)")),
        };
        let hold = match c.get("hold_mm") {
            None => None,
            Some((text, _)) if hold_is_valid(text) => Some(text.to_string()),
            Some(_) => {
                return Err(wrong(
                    "hold_mm",
                    "axis letters with positions in mm, e.g. x 380, y 205, z 260",
                ));
            }
        };
        let programme = match c.get("programme") {
            None => None,
            Some((name @ ("constant" | "spectrum"), _)) => Some(name.to_string()),
            Some(_) => return Err(wrong("programme", "constant or spectrum")),
        };
        let speed_rpm = positive("speed_rpm", 1.0)?;
        let spectrum = c.get("spectrum").map(|(v, _)| v.to_string());
        match (programme.as_deref(), speed_rpm, &spectrum) {
            (Some("constant"), None, _) => {
                return Err(wrong(
                    "programme",
                    "a speed_rpm line with a constant programme",
                ));
            }
            (Some("spectrum"), _, None) => {
                return Err(wrong(
                    "programme",
                    "a spectrum line with a spectrum programme",
                ));
            }
            _ => {}
        }
        let run_period = positive("run_min", 60.0)?;
        let stop = match c.number("stop_min", file)? {
            Some(v) if v < 0.0 => return Err(wrong("stop_min", "a duration of 0 or more")),
            other => other.map(|min| min * 60.0),
        };
        Ok(DriftConditions {
            test: c.get("test").map(|(v, _)| v.to_string()),
            ambient_sensor: c.get("ambient_sensor").map(|(v, _)| v.to_string()),
            spacing,
            control,
            hold,
            first,
            programme,
            speed_rpm,
            spectrum,
            run_period,
            stop,
            other: c
                .keys()
                .filter(|k| !KEYS.contains(k))
                .map(|k| (k.to_string(), c.value(k).unwrap_or_default().to_string()))
                .collect(),
        })
    }

    /// The preamble that says these conditions (file units).
    pub fn to_preamble(&self) -> Conditions {
        let number = |v: Option<Real>, scale: Real| v.map(|v| trimmed(v / scale, 6));
        let values: [Option<String>; 11] = [
            self.test.clone(),
            self.ambient_sensor.clone(),
            number(self.spacing, M_PER_MM),
            self.control.map(|c| c.name().to_string()),
            self.hold.clone(),
            number(self.first, M_PER_MM),
            self.programme.clone(),
            number(self.speed_rpm, 1.0),
            self.spectrum.clone(),
            number(self.run_period, 60.0),
            number(self.stop, 60.0),
        ];
        let pairs = KEYS
            .iter()
            .zip(values)
            .filter_map(|(key, value)| Some((key.to_string(), value?)))
            .chain(self.other.iter().cloned());
        Conditions::from_pairs(pairs)
    }
}

/// Whether `text` reads as `x 380, y 205, z 260`: comma-separated axis letters, each with a
/// finite position.
fn hold_is_valid(text: &str) -> bool {
    text.split(',').all(|part| {
        let mut words = part.split_whitespace();
        let letter = words
            .next()
            .is_some_and(|l| l.len() == 1 && "xyzabcuvw".contains(l.chars().next().unwrap_or(' ')));
        let value = words
            .next()
            .and_then(|v| v.parse::<Real>().ok())
            .is_some_and(Real::is_finite);
        letter && value && words.next().is_none()
    })
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
    /// Columns of the file this reader read past, in header order (no figure depends on them).
    pub columns_not_read: Vec<String>,
}

/// The clock columns a drift table may carry, with their unit in seconds.
const CLOCKS: [(&str, f64); 3] = [("time_min", 60.0), ("time_s", 1.0), ("time_h", 3600.0)];

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
        let clock = crate::io::clock(&header, &CLOCKS, header_line, file)?;
        let mut channels = Vec::new(); // (column, name, angular)
        let mut sensors = Vec::new(); // (column, name)
        let mut columns_not_read = Vec::new();
        for (index, name) in header.iter().enumerate() {
            if CLOCKS.iter().any(|(clock, _)| *clock == name) {
                continue;
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
            } else if let Some(message) = crate::io::looks_like(name, &["time_min"])
                .or_else(|| crate::io::thermometer_slip(name))
                .or_else(|| {
                    use crate::io::Quantity::{Angle, Length};
                    crate::io::channel_slip(name, &["um", "urad"], &[Length, Angle])
                })
            {
                return Err(fail(
                    Some(header_line),
                    format!(
                        "{message} (this reader reads time_min, <channel>_um, <channel>_urad and temp_<sensor>_degc)"
                    ),
                ));
            } else {
                columns_not_read.push(name.to_string());
            }
        }
        let clock = clock.ok_or_else(|| {
            fail(
                Some(header_line),
                "missing column `time_min` (or `time_s`, `time_h`)".into(),
            )
        })?;
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
            columns_not_read,
        };
        if let Some(sensor) = &table.conditions.ambient_sensor
            && !table.temperatures.iter().any(|(name, _)| name == sensor)
        {
            return Err(fail(
                stated.get("ambient_sensor").map(|(_, line)| line),
                format!("ambient_sensor = {sensor}, but there is no column temp_{sensor}_degc"),
            ));
        }
        // Each row: its time, line, displacements and temperatures. An export may list the rows
        // in another order (newest first, sorted by a column): they are read in time order, and
        // two rows at one time are refused (a record pasted again, or two records mixed).
        let mut rows: Vec<ReadRow> = Vec::new();
        for record in reader.records() {
            let record = row(record, bytes, file)?;
            let line = record.position().map(|p| p.line());
            let within = |index: usize, range: Range| {
                number_within(&record, index, &header[index], file, range)
            };
            let time = clock.seconds(&record, file)?;
            let displacements = channels
                .iter()
                .map(|(index, _, angular)| {
                    Ok(within(*index, SENSOR)? * if *angular { RAD_PER_URAD } else { M_PER_UM })
                })
                .collect::<Result<Vec<Real>, TableError>>()?;
            let temperatures = sensors
                .iter()
                .map(|(index, _)| within(*index, crate::io::THERMOMETER))
                .collect::<Result<Vec<Real>, TableError>>()?;
            rows.push((time, line, displacements, temperatures));
        }
        rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let Some(pair) = rows.windows(2).find(|w| w[1].0 <= w[0].0) {
            let at = |l: Option<u64>| l.map_or("?".to_string(), |l| l.to_string());
            return Err(fail(
                pair[1].1,
                format!(
                    "a second reading at {} min (the other at line {}): one nest is read once at each instant; a record pasted again, or two mixed?",
                    crate::math::trimmed(pair[1].0 / 60.0, 6),
                    at(pair[0].1)
                ),
            ));
        }
        for (time, _, displacements, temperatures) in rows {
            table.times.push(time);
            for (channel, value) in table.channels.iter_mut().zip(displacements) {
                channel.values.push(value);
            }
            for ((_, values), value) in table.temperatures.iter_mut().zip(temperatures) {
                values.push(value);
            }
        }
        if table.times.len() < 2 {
            return Err(fail(
                None,
                "fewer than two rows: a drift record needs readings over time".into(),
            ));
        }
        let span = table.times[table.times.len() - 1] - table.times[0];
        if let Some(run) = table.conditions.run_period
            && run > span + 1e-6
        {
            return Err(fail(
                stated.get("run_min").map(|(_, line)| line),
                format!(
                    "run_min = {}: the running period ends after the record, which spans {} min",
                    trimmed(run / 60.0, 6),
                    trimmed(span / 60.0, 6)
                ),
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
