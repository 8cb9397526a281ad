//! The `positioning` measurement table: linear positioning deviations along one axis, as a
//! laser interferometer records them (ISO 230-2) — simulated or exported from a real
//! instrument, written by hand, in any column order.
//!
//! | column | required | meaning |
//! |---|---|---|
//! | `target_mm` | yes | target position (mm) |
//! | `deviation_um` | yes | reached − target (µm) |
//! | `axis` | no | `X`, `Y` or `Z` |
//! | `run` | no | run label; runs are ordered by first appearance |
//! | `direction` | no | `+` reached while travelling positive, `-` negative |
//! | `time_min` | no | time since the start of the test (min); or `time_s` (s), `time_h` (h) |
//! | `temp_<sensor>_degc` | no, any number | temperatures (°C) |
//!
//! Any other column (a status flag, a comment, the operator) is read past and listed in the
//! report as not read, unless it looks like one of these written another way (`Deviation (µm)`,
//! `deviation_nm`, `temp_c`), which is refused by name ([`crate::io`]'s column checks).
//!
//! Without `direction`, every reading counts as one direction (`+`). Without `run`, the k-th
//! reading at a target in a direction belongs to run k. The test's conditions (test, axis,
//! runs, targets, compensation) and its set-up (machine, where the other axes stood, reflector
//! offset, mounting, zero: what [`super::readings`] models the readings with) travel in the
//! file's preamble, as `mtwin run` writes them and a real export can carry them
//! ([`super::conditions`]); a table without one reads as well.

use super::conditions::{PositioningConditions, parse_axis};
use crate::io::{Conditions, TableError, csv_reader, finite_number, read_file, read_header, row};
use crate::machine::Axis;
use crate::math::{M_PER_MM, M_PER_UM, Real, fixed};
pub use crate::program::Approach;
use std::path::Path;

/// One reading.
#[derive(Clone, Debug, PartialEq)]
pub struct PositioningReading {
    /// Target position (m).
    pub target: Real,
    /// Reached − target (m).
    pub deviation: Real,
    /// Direction of approach.
    pub approach: Approach,
    /// Index into [`PositioningTable::runs`].
    pub run: usize,
    /// Time since the start of the test (s), if recorded.
    pub time: Option<Real>,
    /// Temperatures (°C), in the order of [`PositioningTable::sensors`].
    pub temperatures: Vec<Real>,
}

/// A positioning table of one axis.
#[derive(Clone, Debug, PartialEq)]
pub struct PositioningTable {
    /// The axis, if the file names it.
    pub axis: Option<Axis>,
    /// Run labels in order of first appearance.
    pub runs: Vec<String>,
    /// Temperature sensor names (the `<sensor>` of `temp_<sensor>_degc`), in column order.
    pub sensors: Vec<String>,
    /// Whether the file has a `direction` column.
    pub has_direction: bool,
    /// The readings, in file order.
    pub readings: Vec<PositioningReading>,
    /// The test conditions from the file's preamble (none for a file without one).
    pub conditions: PositioningConditions,
    /// Columns of the file this reader read past, in header order (no figure depends on them).
    pub columns_not_read: Vec<String>,
}

/// The largest deviation a positioning reading may have (m): the scenarios' own limit on any
/// error ([`crate::scenario::errors::LARGEST_ERROR`], 10 mm). No axis a laser calibrates is
/// that far off; a reading beyond it is nearly always a unit slip (nm or mm in the µm
/// column), and is refused rather than evaluated.
pub const LARGEST_DEVIATION: Real = crate::scenario::errors::LARGEST_ERROR;

/// The largest target position (m): 80 m, the linear range of a laser interferometer
/// (Renishaw XL-80, Keysight 5530); a target beyond it is not a laser measurement.
pub const LARGEST_TARGET: Real = 80.0;

const KNOWN: [&str; 8] = [
    "target_mm",
    "deviation_um",
    "axis",
    "run",
    "direction",
    "time_min",
    "time_s",
    "time_h",
];

/// The clock columns a positioning table may carry, with their unit in seconds.
const CLOCKS: [(&str, Real); 3] = [("time_min", 60.0), ("time_s", 1.0), ("time_h", 3600.0)];

impl PositioningTable {
    /// Reads a positioning table file.
    pub fn read(path: impl AsRef<Path>) -> Result<PositioningTable, TableError> {
        let (bytes, file) = read_file(path.as_ref())?;
        PositioningTable::parse(&bytes, &file)
    }

    /// Reads a positioning table from bytes; `file` names it in messages.
    pub fn parse(bytes: &[u8], file: &str) -> Result<PositioningTable, TableError> {
        let fail = |line: Option<u64>, message: String| TableError::new(file, line, message);
        let stated = Conditions::parse(bytes, file)?;
        let conditions = PositioningConditions::from_preamble(&stated, file)?;
        let mut reader = csv_reader(bytes);
        let (header, header_line) = read_header(&mut reader, file)?;
        let column = |name: &str| header.iter().position(|h| h == name);
        let mut sensors = Vec::new();
        let mut sensor_columns = Vec::new();
        let mut columns_not_read = Vec::new();
        for (index, name) in header.iter().enumerate() {
            if KNOWN.contains(&name) {
                continue;
            }
            match name
                .strip_prefix("temp_")
                .and_then(|rest| rest.strip_suffix("_degc"))
            {
                Some(sensor) if !sensor.is_empty() => {
                    sensors.push(sensor.to_string());
                    sensor_columns.push(index);
                }
                _ => {
                    if let Some(message) = crate::io::looks_like(name, &KNOWN)
                        .or_else(|| crate::io::thermometer_slip(name))
                    {
                        return Err(fail(
                            Some(header_line),
                            format!(
                                "{message} (this reader reads target_mm, deviation_um, axis, run, direction, \
                                 time_min and temp_<sensor>_degc)"
                            ),
                        ));
                    }
                    columns_not_read.push(name.to_string());
                }
            }
        }
        let required = |name: &str| {
            column(name).ok_or_else(|| {
                fail(
                    Some(header_line),
                    format!("missing column `{name}` (required: target_mm, deviation_um)"),
                )
            })
        };
        let (target_column, deviation_column) = (required("target_mm")?, required("deviation_um")?);
        let (axis_column, run_column, direction_column) =
            (column("axis"), column("run"), column("direction"));
        let clock = crate::io::clock(&header, &CLOCKS, header_line, file)?;

        let mut axis: Option<Axis> = None;
        let mut runs: Vec<String> = Vec::new();
        let mut readings = Vec::new();
        let mut lines = Vec::new();
        // Without a run column: the k-th reading at a (target, direction) is run k.
        let mut visits: Vec<(Real, Approach, usize)> = Vec::new();
        for record in reader.records() {
            let record = row(record, bytes, file)?;
            let line = record.position().map(|p| p.line());
            let number = |index: usize, name: &str| finite_number(&record, index, name, file);
            let target = number(target_column, "target_mm")? * M_PER_MM;
            let deviation = number(deviation_column, "deviation_um")? * M_PER_UM;
            if target.abs() > LARGEST_TARGET {
                return Err(fail(
                    line,
                    format!(
                        "column `target_mm`: {} mm is beyond the 80 m a laser interferometer measures over; units?",
                        crate::math::readable(target / M_PER_MM)
                    ),
                ));
            }
            if deviation.abs() > LARGEST_DEVIATION {
                return Err(fail(
                    line,
                    format!(
                        "column `deviation_um`: {} µm is beyond the ±10 mm an axis can be off; nm or mm in a µm column?",
                        crate::math::readable(deviation / M_PER_UM)
                    ),
                ));
            }
            if let Some(index) = axis_column {
                let text = &record[index];
                let this = parse_axis(text).ok_or_else(|| {
                    fail(
                        line,
                        format!("column `axis`: expected X, Y or Z, found \"{text}\""),
                    )
                })?;
                match axis {
                    Some(first) if first != this => {
                        return Err(fail(
                            line,
                            format!(
                                "column `axis`: axis {this} after {first}; a positioning table holds one axis"
                            ),
                        ));
                    }
                    _ => axis = Some(this),
                }
            }
            let approach = match direction_column.map(|index| &record[index]) {
                None | Some("+") => Approach::Up,
                Some("-") => Approach::Down,
                Some(other) => {
                    return Err(fail(
                        line,
                        format!("column `direction`: expected + or -, found \"{other}\""),
                    ));
                }
            };
            let run = match run_column {
                Some(index) => {
                    let label = &record[index];
                    if label.is_empty() {
                        return Err(fail(line, "column `run`: empty label".into()));
                    }
                    match runs.iter().position(|r| r == label) {
                        Some(run) => run,
                        None => {
                            runs.push(label.to_string());
                            runs.len() - 1
                        }
                    }
                }
                None => {
                    let key = (target / M_PER_MM * 1e6).round() * M_PER_MM / 1e6;
                    let count = match visits
                        .iter_mut()
                        .find(|(t, a, _)| *t == key && *a == approach)
                    {
                        Some(visit) => {
                            visit.2 += 1;
                            visit.2
                        }
                        None => {
                            visits.push((key, approach, 1));
                            1
                        }
                    };
                    while runs.len() < count {
                        runs.push((runs.len() + 1).to_string());
                    }
                    count - 1
                }
            };
            let time = clock
                .as_ref()
                .map(|clock| clock.seconds(&record, file))
                .transpose()?;
            let temperatures = sensor_columns
                .iter()
                .zip(&sensors)
                .map(|(&index, sensor)| {
                    crate::io::number_within(
                        &record,
                        index,
                        &format!("temp_{sensor}_degc"),
                        file,
                        crate::io::THERMOMETER,
                    )
                })
                .collect::<Result<Vec<_>, _>>()?;
            lines.push(line);
            readings.push(PositioningReading {
                target,
                deviation,
                approach,
                run,
                time,
                temperatures,
            });
        }
        if readings.is_empty() {
            return Err(fail(
                None,
                "no readings: expected one row per reading after the header".into(),
            ));
        }
        let table = PositioningTable {
            axis: axis.or(conditions.axis),
            runs,
            sensors,
            has_direction: direction_column.is_some(),
            readings,
            conditions,
            columns_not_read,
        };
        let row_targets: Vec<Real> = table.readings.iter().map(|r| r.target).collect();
        table
            .conditions
            .check(&stated, axis, &table.runs, &row_targets, &lines, file)?;
        Ok(table)
    }
}

impl PositioningTable {
    /// Writes the table: its conditions as a preamble (when it has any), then `axis, run, direction, target_mm, deviation_um, time_min` (the columns
    /// it has) then `temp_<sensor>_degc`; positions to 1 nm, deviations to 1 pm, times to
    /// 1 µmin, temperatures to 1 µK, so the same table gives the same bytes.
    pub fn write_csv(&self, mut out: impl std::io::Write) -> csv::Result<()> {
        let preamble = self.conditions.to_preamble();
        if !preamble.is_empty() {
            let title = self
                .conditions
                .test
                .map_or("mtwin positioning table", |t| t.title());
            out.write_all(preamble.to_preamble(title).as_bytes())?;
        }
        let mut writer = csv::Writer::from_writer(out);
        let timed = self.readings.iter().any(|r| r.time.is_some());
        let mut header: Vec<String> = Vec::new();
        if self.axis.is_some() {
            header.push("axis".into());
        }
        header.extend(["run", "direction", "target_mm", "deviation_um"].map(String::from));
        if timed {
            header.push("time_min".into());
        }
        header.extend(self.sensors.iter().map(|s| format!("temp_{s}_degc")));
        writer.write_record(&header)?;
        for r in &self.readings {
            let mut record: Vec<String> = Vec::with_capacity(header.len());
            if let Some(axis) = self.axis {
                record.push(axis.to_string());
            }
            record.push(self.runs[r.run].clone());
            record.push(if r.approach == Approach::Up { "+" } else { "-" }.into());
            record.push(fixed(r.target / M_PER_MM, 6));
            record.push(fixed(r.deviation / M_PER_UM, 6));
            if timed {
                record.push(r.time.map_or_else(String::new, |t| fixed(t / 60.0, 6)));
            }
            record.extend(r.temperatures.iter().map(|t| fixed(*t, 6)));
            writer.write_record(&record)?;
        }
        writer.flush()?;
        Ok(())
    }
}

/// The conditions a preamble states, as the table reads them and checks them against its rows.
#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::positioning::conditions::PositioningTest;
    use crate::kinds::positioning::setup::{Mounting, Zeroing};
    use crate::math::Vector;

    const ROWS: &str = "run,direction,target_mm,deviation_um\n\
                        1,+,0,0.5\n1,+,100,1.5\n1,-,100,2.5\n1,-,0,1.0\n\
                        2,+,0,0.6\n2,+,100,1.4\n2,-,100,2.4\n2,-,0,1.1\n";

    fn read(preamble: &str) -> Result<PositioningTable, TableError> {
        PositioningTable::parse(format!("{preamble}{ROWS}").as_bytes(), "p.csv")
    }

    #[test]
    fn a_preamble_names_the_axis_runs_and_targets_the_rows_hold() {
        let table = read(
            "# a laser export\n# test = iso230_2\n# axis = Y\n# runs = 2\n# targets_mm = 0, 100\n# compensation = air\n",
        )
        .unwrap();
        // No axis column: the axis is the preamble's.
        assert_eq!(table.axis, Some(Axis::Y));
        assert_eq!(table.conditions.test, Some(PositioningTest::Iso230_2));
        assert_eq!(table.conditions.runs, Some(2));
        assert_eq!(table.conditions.targets, Some(vec![0.0, 0.1]));
        // Without one, the table reads as before.
        let bare = read("").unwrap();
        assert_eq!((bare.axis, bare.conditions), (None, Default::default()));
        // An export that rounds its targets to 1 µm still matches them.
        let rounded = read("# targets_mm = 0.0000004, 99.9999996\n").unwrap();
        assert_eq!(rounded.readings.len(), 8);
    }

    #[test]
    fn conditions_the_rows_contradict_are_refused_naming_both() {
        let axis = PositioningTable::parse(
            b"# axis = Y\naxis,target_mm,deviation_um\nX,0,1\nX,100,2\n",
            "p.csv",
        )
        .unwrap_err();
        assert_eq!(
            axis.to_string(),
            "p.csv:1: axis = Y, but the rows' axis column says X"
        );
        let runs = read("# runs = 3\n").unwrap_err();
        assert_eq!(
            runs.to_string(),
            "p.csv:1: runs = 3, but the rows hold 2 runs (1, 2)"
        );
        // The row at 100 mm (line 4: the preamble, the header, then the first row) is stray.
        let stray = read("# targets_mm = 0, 50\n").unwrap_err();
        assert_eq!(
            stray.to_string(),
            "p.csv:4: target_mm 100 is not one of the preamble's targets_mm (line 1)"
        );
        let tested = read("# axis = Y\n# x_mm = 5\n# y_mm = 205\n").unwrap_err();
        assert_eq!(
            tested.to_string(),
            "p.csv:3: y_mm: Y is the axis under test; the preamble's axis positions are the other axes'"
        );
        let unvisited = read("# targets_mm = 0, 100, 200\n").unwrap_err();
        assert_eq!(
            unvisited.to_string(),
            "p.csv:1: targets_mm: no reading at 200 mm"
        );
    }

    #[test]
    fn values_of_the_wrong_form_are_refused() {
        for (line, expected) in [
            (
                "# test = iso230_4",
                "test = iso230_4: expected iso230_2, warmup or iso230_3_linear",
            ),
            ("# axis = W", "axis = W: expected X, Y or Z"),
            (
                "# runs = 0",
                "runs = 0: expected a whole number of runs, 1 or more",
            ),
            (
                "# targets_mm = 0, ten",
                "targets_mm = 0, ten: expected finite numbers separated by commas",
            ),
            (
                "# beam_offset_mm = 0 60",
                "beam_offset_mm = 0 60: expected three numbers separated by spaces",
            ),
            (
                "# interferometer_on = bed",
                "interferometer_on = bed: expected workpiece or tool",
            ),
            ("# zero = never", "zero = never: expected once or each_run"),
            ("# y_mm = far", "y_mm = far: expected a finite number"),
        ] {
            let error = read(&format!("{line}\n")).unwrap_err();
            assert_eq!(error.to_string(), format!("p.csv:1: {expected}"));
        }
    }

    #[test]
    fn what_is_written_reads_back() {
        let mut table = read("").unwrap();
        table.axis = Some(Axis::Z);
        table.conditions = PositioningConditions {
            test: Some(PositioningTest::Warmup),
            axis: Some(Axis::Z),
            runs: Some(2),
            targets: Some(vec![0.0, 0.1]),
            compensation: Some("air+nde".into()),
            machine: Some("vmc3".into()),
            axes: vec![
                (Axis::X, 380.0 * M_PER_MM),
                (Axis::Y, 205.5 * M_PER_MM),
                (Axis::C, 30.0 * crate::math::RAD_PER_DEG),
            ],
            beam_offset: Some(Vector::new(0.0, 20.0, 60.0) * M_PER_MM),
            mounting: Some(Mounting::InterferometerOnTool),
            zero: Some(Zeroing::EachRun),
            not_used: Vec::new(),
        };
        let mut bytes = Vec::new();
        table.write_csv(&mut bytes).unwrap();
        let text = String::from_utf8(bytes).unwrap();
        assert!(
            text.starts_with(
                "# mtwin positioning table (runs between warm-up intervals)\n# test = warmup\n"
            ),
            "{text}"
        );
        let back = PositioningTable::parse(text.as_bytes(), "p.csv").unwrap();
        assert_eq!(back, table);
    }
}
