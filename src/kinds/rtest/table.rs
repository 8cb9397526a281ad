//! The `rtest` measurement table: the displacement of the tool (the nest) relative to the
//! sphere at each pose of each test, as R-test software exports it, in any column order.
//!
//! | column | required | meaning |
//! |---|---|---|
//! | `test` | yes | the test's name (rows of one test together, in order) |
//! | `point` | no | index of the pose in its test |
//! | `time_s` | no | time since the start of the test (s) |
//! | `a_deg`, `b_deg`, `c_deg` | at least one | the controller's rotary angles |
//! | `x_mm`, `y_mm`, `z_mm` | no | the controller's linear axes |
//! | `dx_um`, `dy_um`, `dz_um` | yes | tool (nest reference point) relative to the sphere centre, actual − nominal, along the machine's X, Y, Z, zeroed at the first pose of the test (the software zeroes the probe readings, so on a tilting head the first pose's offset turns with the nest) |
//! | `probe1_um` … `probe4_um` | no | the raw readings (+ when the sphere pushes the probe in) |
//!
//! Preamble keys (`# key = value`, see [`crate::io::Conditions`]): `machine`, `sphere_mm`
//! (`x y z` in the workpiece frame), `sphere_diameter_mm`, `tip`, `calibration`, `mode`,
//! `zero`, `frame`. Analyses need none of them. `frame` states the axes `dx_um`, `dy_um`,
//! `dz_um` are along; only [`FRAMES`] (the machine's X, Y, Z) is accepted, and a table that
//! declares another frame is refused at the `frame` line rather than read as machine axes.
//!
//! Angles in radians in a `_deg` column are refused where the commanded linear positions show
//! the turn (see `angles`).

use crate::io::{
    Conditions, Range, TableError, csv_reader, finite_number, number_within, read_file,
    read_header, row,
};

pub use super::rows::{RtestRow, RtestTable};

use crate::machine::Axis;
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Vector, fixed};
use std::path::Path;

/// The R-test's range (µm): its probes travel a few millimetres, and the errors it measures are
/// below the 10 mm scenarios allow any error; a deviation or reading beyond 10 mm is a unit slip.
pub const NEST: Range = Range {
    limit: 10_000.0,
    why: "an R-test nest's probes travel a few mm",
};

/// The frames a table's deviations may be stated in (`# frame = …`): `machine`, the machine's
/// X, Y, Z axes, which the evaluation and the readings model take them along. A table without
/// the line is read in machine axes.
pub const FRAMES: [&str; 1] = ["machine"];

const ANGLES: [&str; 3] = ["a_deg", "b_deg", "c_deg"];
const LINEAR: [&str; 3] = ["x_mm", "y_mm", "z_mm"];
const DEVIATION: [&str; 3] = ["dx_um", "dy_um", "dz_um"];
const PROBES: [&str; 4] = ["probe1_um", "probe2_um", "probe3_um", "probe4_um"];

impl RtestTable {
    /// Reads an R-test table file.
    pub fn read(path: impl AsRef<Path>) -> Result<RtestTable, TableError> {
        let (bytes, file) = read_file(path.as_ref())?;
        RtestTable::parse(&bytes, &file)
    }

    /// Reads an R-test table from bytes; `file` names it in messages.
    pub fn parse(bytes: &[u8], file: &str) -> Result<RtestTable, TableError> {
        let fail = |line: Option<u64>, message: String| TableError::new(file, line, message);
        let conditions = Conditions::parse(bytes, file)?;
        if let Some((frame, line)) = conditions.get("frame")
            && !FRAMES.contains(&frame)
        {
            return Err(fail(
                Some(line),
                format!(
                    "frame = {frame}: dx_um, dy_um, dz_um are read along the machine's X, Y, Z; \
                     accepted frames: {}",
                    FRAMES.join(", ")
                ),
            ));
        }
        // The instrument's set-up as the writer states it: no column can confirm these, but a
        // value outside what the writer writes is refused rather than passed over (`zero`
        // decides the readings model's datum).
        let named: [(&str, &[&str]); 4] = [
            (
                "zero",
                &[super::Zero::EachTest.name(), super::Zero::FirstPose.name()],
            ),
            ("tip", &["flat", "point"]),
            ("calibration", &["nominal", "six_point"]),
            ("mode", &["static", "dynamic"]),
        ];
        for (key, values) in named {
            if let Some((value, line)) = conditions.get(key)
                && !values.contains(&value)
            {
                return Err(fail(
                    Some(line),
                    format!("{key} = {value}: expected {}", values.join(" or ")),
                ));
            }
        }
        conditions.triple("sphere_mm", file)?;
        if let Some(d) = conditions.number("sphere_diameter_mm", file)?
            && d <= 0.0
        {
            let line = conditions.get("sphere_diameter_mm").map(|(_, l)| l);
            return Err(fail(
                line,
                format!("sphere_diameter_mm = {d}: expected a positive diameter"),
            ));
        }
        let mut reader = csv_reader(bytes);
        let (header, header_line) = read_header(&mut reader, file)?;
        let known: Vec<&str> = ["test", "point", "time_s"]
            .into_iter()
            .chain(ANGLES)
            .chain(LINEAR)
            .chain(DEVIATION)
            .chain(PROBES)
            .collect();
        let columns_not_read = crate::io::read_past(
            header.iter().filter(|name| !known.contains(name)),
            |name| crate::io::looks_like(name, &known),
            "test, point, time_s, a_deg/b_deg/c_deg, x_mm/y_mm/z_mm, dx_um, dy_um, dz_um, \
             probe1_um … probe4_um",
            header_line,
            file,
        )?;
        let column = |name: &str| header.iter().position(|h| h == name);
        let required = |name: &str| {
            column(name).ok_or_else(|| {
                fail(
                    Some(header_line),
                    format!("missing column `{name}` (required: test, dx_um, dy_um, dz_um and a rotary angle)"),
                )
            })
        };
        let test_column = required("test")?;
        let deviation: Vec<usize> = DEVIATION
            .iter()
            .map(|n| required(n))
            .collect::<Result<_, _>>()?;
        let angles: Vec<Option<usize>> = ANGLES.iter().map(|n| column(n)).collect();
        if angles.iter().all(Option::is_none) {
            return Err(fail(
                Some(header_line),
                "missing a rotary angle column (a_deg, b_deg or c_deg)".into(),
            ));
        }
        let linear: Vec<Option<usize>> = LINEAR.iter().map(|n| column(n)).collect();
        if linear.iter().any(Option::is_some) && linear.iter().any(Option::is_none) {
            return Err(fail(
                Some(header_line),
                "give all of x_mm, y_mm, z_mm or none".into(),
            ));
        }
        let probes: Vec<usize> = PROBES.iter().map_while(|n| column(n)).collect();
        if let Some(extra) = PROBES[probes.len()..].iter().find(|n| column(n).is_some()) {
            return Err(fail(
                Some(header_line),
                format!("`{extra}` without the probes before it"),
            ));
        }
        let (point_column, time_column) = (column("point"), column("time_s"));
        let mut rows = Vec::new();
        let mut lines = Vec::new();
        for record in reader.records() {
            let record = row(record, bytes, file)?;
            let line = record.position().map(|p| p.line());
            let number = |index: usize, name: &str| finite_number(&record, index, name, file);
            let test = record[test_column].to_string();
            if test.is_empty() {
                return Err(fail(line, "column `test`: empty test name".into()));
            }
            let point = match point_column {
                None => None,
                Some(i) => Some(record[i].parse::<usize>().map_err(|_| {
                    fail(
                        line,
                        format!(
                            "column `point`: expected a pose index (0, 1, …), found \"{}\"",
                            &record[i]
                        ),
                    )
                })?),
            };
            let time = time_column
                .map(|i| number_within(&record, i, "time_s", file, crate::io::CLOCK_S))
                .transpose()?;
            let mut row_angles = [None; 3];
            for ((slot, index), name) in row_angles.iter_mut().zip(&angles).zip(ANGLES) {
                *slot = index
                    .map(|i| number(i, name).map(|v| v * RAD_PER_DEG))
                    .transpose()?;
            }
            let linear_values = match linear[..] {
                [Some(x), Some(y), Some(z)] => Some(
                    Vector::new(number(x, "x_mm")?, number(y, "y_mm")?, number(z, "z_mm")?)
                        * M_PER_MM,
                ),
                _ => None,
            };
            let within = |index: usize, name: &str| number_within(&record, index, name, file, NEST);
            let d = Vector::new(
                within(deviation[0], "dx_um")?,
                within(deviation[1], "dy_um")?,
                within(deviation[2], "dz_um")?,
            ) * M_PER_UM;
            let readings = probes
                .iter()
                .zip(PROBES)
                .map(|(&i, name)| within(i, name).map(|v| v * M_PER_UM))
                .collect::<Result<Vec<_>, _>>()?;
            lines.push(line);
            rows.push(RtestRow {
                test,
                point,
                time,
                angles: row_angles,
                linear: linear_values,
                deviation: d,
                probes: readings,
            });
        }
        if rows.is_empty() {
            return Err(fail(None, "no data rows".into()));
        }
        super::angles::check(&rows, &lines, file)?;
        let table = RtestTable {
            rows,
            conditions,
            columns_not_read,
        };
        if let Some(contradiction) = super::plausible::sign_contradiction(&table) {
            return Err(fail(None, contradiction));
        }
        Ok(table)
    }

    /// The table as CSV: the preamble, then the columns the rows have (angles of the axes
    /// `rotary`), deviations and readings in µm to 4 decimals.
    pub fn to_csv(&self, rotary: &[Axis]) -> Vec<u8> {
        let mut text = if self.conditions.is_empty() {
            String::new()
        } else {
            self.conditions.to_preamble("mtwin rtest table")
        };
        let probes = self.rows.first().map_or(0, |r| r.probes.len());
        let mut header = vec!["test", "point", "time_s"];
        header.extend(rotary.iter().map(|a| ANGLES[a.coordinate()]));
        header.extend(LINEAR);
        header.extend(DEVIATION);
        header.extend(&PROBES[..probes]);
        text += &header.join(",");
        text.push('\n');
        for row in &self.rows {
            let mut fields = vec![
                row.test.clone(),
                row.point.map_or_else(String::new, |p| p.to_string()),
                row.time.map_or_else(String::new, |t| fixed(t, 4)),
            ];
            for axis in rotary {
                fields.push(
                    row.angle(*axis)
                        .map_or_else(String::new, |a| fixed(a / RAD_PER_DEG, 6)),
                );
            }
            let linear = row.linear.unwrap_or(Vector::ZERO) / M_PER_MM;
            fields.extend(linear.to_array().map(|v| fixed(v, 6)));
            let d = row.deviation / M_PER_UM;
            fields.extend(d.to_array().map(|v| fixed(v, 4)));
            fields.extend(row.probes.iter().map(|p| fixed(p / M_PER_UM, 4)));
            text += &fields.join(",");
            text.push('\n');
        }
        text.into_bytes()
    }
}
