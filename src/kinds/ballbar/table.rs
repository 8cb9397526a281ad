//! The `ballbar` measurement table: the change in distance between the two balls of a
//! telescopic ball-bar along a circle (ISO 230-4), simulated or exported from a real
//! instrument, in any column order.
//!
//! | column | required | meaning |
//! |---|---|---|
//! | `direction` | yes | `ccw` or `cw`, seen from the positive side of the plane's normal (XY from +Z, YZ from +X, ZX from +Y) |
//! | `angle_deg` | yes | angle of the tool ball about the centre ball in [0, 360), from the plane's first axis toward its second |
//! | `deviation_um` | yes | measured distance − nominal radius (µm) |
//! | `time_s` | no | time since the start of the test (s) |
//!
//! The plane, radius and feed are not in the file; they are the test conditions the user
//! gives (`--plane`, `--radius-mm`, `--feed-mm-per-min`).

use crate::io::{TableError, csv_reader, read_file, read_header};
use crate::math::{M_PER_UM, RAD_PER_DEG, Real, fixed};
use std::path::Path;

/// The sense of travel around the circle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sense {
    /// Counter-clockwise: θ increasing.
    Ccw,
    /// Clockwise: θ decreasing.
    Cw,
}

impl Sense {
    /// +1 for counter-clockwise, −1 for clockwise (the sign of dθ/dt).
    pub fn sign(self) -> Real {
        match self {
            Sense::Ccw => 1.0,
            Sense::Cw => -1.0,
        }
    }

    /// `ccw` or `cw`, as in the table.
    pub fn name(self) -> &'static str {
        match self {
            Sense::Ccw => "ccw",
            Sense::Cw => "cw",
        }
    }
}

/// One reading of the ball-bar.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallbarReading {
    /// Sense of travel.
    pub sense: Sense,
    /// Angle of the tool ball about the centre ball (rad, in [0, 2π)).
    pub angle: Real,
    /// Measured distance − nominal radius (m).
    pub deviation: Real,
    /// Time since the start of the test (s), if recorded.
    pub time: Option<Real>,
}

/// A ball-bar table: the readings of one plane, both senses, in file order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BallbarTable {
    /// The readings.
    pub readings: Vec<BallbarReading>,
}

const KNOWN: [&str; 4] = ["direction", "angle_deg", "deviation_um", "time_s"];

impl BallbarTable {
    /// Reads a ball-bar table file.
    pub fn read(path: impl AsRef<Path>) -> Result<BallbarTable, TableError> {
        let (bytes, file) = read_file(path.as_ref())?;
        BallbarTable::parse(&bytes, &file)
    }

    /// Reads a ball-bar table from bytes; `file` names it in messages.
    pub fn parse(bytes: &[u8], file: &str) -> Result<BallbarTable, TableError> {
        let fail = |line: Option<u64>, message: String| TableError::new(file, line, message);
        let mut reader = csv_reader(bytes);
        let header = read_header(&mut reader, file)?;
        for name in &header {
            if !KNOWN.contains(&name) {
                return Err(fail(
                    Some(1),
                    format!(
                        "unknown column `{name}`: expected direction, angle_deg, deviation_um or time_s"
                    ),
                ));
            }
        }
        let column = |name: &str| header.iter().position(|h| h == name);
        let required = |name: &str| {
            column(name).ok_or_else(|| {
                fail(
                    Some(1),
                    format!(
                        "missing column `{name}` (required: direction, angle_deg, deviation_um)"
                    ),
                )
            })
        };
        let (direction_column, angle_column, deviation_column) = (
            required("direction")?,
            required("angle_deg")?,
            required("deviation_um")?,
        );
        let time_column = column("time_s");
        let mut readings = Vec::new();
        for record in reader.records() {
            let record = record.map_err(|e| {
                fail(
                    e.position().map(|p| p.line()),
                    format!("not a valid CSV row: {e}"),
                )
            })?;
            let line = record.position().map(|p| p.line());
            let number = |index: usize, name: &str| -> Result<Real, TableError> {
                let text = &record[index];
                match text.parse::<Real>() {
                    Ok(value) if value.is_finite() => Ok(value),
                    _ => Err(fail(
                        line,
                        format!("column `{name}`: expected a finite number, found \"{text}\""),
                    )),
                }
            };
            let sense = match record[direction_column].to_ascii_lowercase().as_str() {
                "ccw" => Sense::Ccw,
                "cw" => Sense::Cw,
                other => {
                    return Err(fail(
                        line,
                        format!("column `direction`: expected ccw or cw, found \"{other}\""),
                    ));
                }
            };
            let angle_deg = number(angle_column, "angle_deg")?;
            if !(0.0..360.0).contains(&angle_deg) {
                return Err(fail(
                    line,
                    format!("column `angle_deg`: {angle_deg} is outside [0, 360)"),
                ));
            }
            let deviation = number(deviation_column, "deviation_um")? * M_PER_UM;
            let time = time_column
                .map(|index| number(index, "time_s"))
                .transpose()?;
            readings.push(BallbarReading {
                sense,
                angle: angle_deg * RAD_PER_DEG,
                deviation,
                time,
            });
        }
        if readings.is_empty() {
            return Err(fail(
                None,
                "no readings: expected one row per reading after the header".into(),
            ));
        }
        Ok(BallbarTable { readings })
    }

    /// Writes the table: `direction, angle_deg, deviation_um[, time_s]`; angles to 1 µ°,
    /// deviations to 1 pm, times to 1 µs, so the same table gives the same bytes.
    pub fn write_csv(&self, out: impl std::io::Write) -> csv::Result<()> {
        let mut writer = csv::Writer::from_writer(out);
        let timed = self.readings.iter().any(|r| r.time.is_some());
        let mut header = vec!["direction", "angle_deg", "deviation_um"];
        if timed {
            header.push("time_s");
        }
        writer.write_record(&header)?;
        for r in &self.readings {
            // Rounding may carry an angle just below 360° up to it: write it as 0.
            let mut angle = fixed(r.angle / RAD_PER_DEG, 6);
            if angle == "360.000000" {
                angle = fixed(0.0, 6);
            }
            let mut record = vec![
                r.sense.name().to_string(),
                angle,
                fixed(r.deviation / M_PER_UM, 6),
            ];
            if timed {
                record.push(r.time.map_or_else(String::new, |t| fixed(t, 6)));
            }
            writer.write_record(&record)?;
        }
        writer.flush()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_table_reads_back() {
        let table = BallbarTable {
            readings: vec![
                BallbarReading {
                    sense: Sense::Ccw,
                    angle: 0.5,
                    deviation: 1.25e-6,
                    time: Some(0.004),
                },
                BallbarReading {
                    sense: Sense::Cw,
                    angle: 359.9999999 * RAD_PER_DEG,
                    deviation: -2e-6,
                    time: Some(0.008),
                },
            ],
        };
        let mut bytes = Vec::new();
        table.write_csv(&mut bytes).unwrap();
        let back = BallbarTable::parse(&bytes, "t.csv").unwrap();
        assert_eq!(back.readings.len(), 2);
        assert_eq!(back.readings[1].angle, 0.0, "359.9999999° rounds to 0°");
        assert!((back.readings[0].deviation - 1.25e-6).abs() < 1e-15);
        assert_eq!(back.readings[1].sense, Sense::Cw);
    }
}
