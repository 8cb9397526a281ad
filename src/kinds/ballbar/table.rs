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
//! Any other column (the carriage's `x_mm`, a feed, a flag) is read past and listed in the
//! report as not read, unless it looks like one of these written another way
//! (`Deviation (µm)`, `deviation_nm`, `angle_rad`, `time_ms`), which is refused by name.
//!
//! The test conditions travel in the file's preamble (`# key = value` lines before the header,
//! see [`crate::io::Conditions`]), as `mtwin run` writes them and a real export can carry them:
//!
//! | key | meaning |
//! |---|---|
//! | `plane` | `XY`, `YZ` or `ZX` |
//! | `radius_mm` | the nominal radius of the test, the bar's length |
//! | `feed_mm_per_min` | the programmed feed |
//! | `sample_rate_hz` | the bar's sampling rate |
//! | `first_direction` | `ccw` or `cw`, the sense of the first run |
//! | `machine` | the machine's name |
//! | `centre_mm` | `x y z`: the machine's linear axes at the circle centre (where the centre ball was set) |
//! | `a_deg`, `b_deg`, `c_deg` | the rotary axes held during the test, when not at 0 (with `centre_mm`) |
//!
//! A table without them reads as well: its conditions are then given on the command line
//! (`--plane`, `--radius-mm`, `--feed-mm-per-min`).

use crate::io::{
    Conditions, Range, TableError, csv_reader, finite_number, number_within, read_file,
    read_header, row,
};
use crate::machine::{Axis, AxisValues, Plane};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, fixed, trimmed};
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

/// The conditions of the circular test a table was measured in, as its preamble gives them
/// (SI; each absent when the file does not say).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TestConditions {
    /// The plane of the circle.
    pub plane: Option<Plane>,
    /// The nominal radius (m).
    pub radius: Option<Real>,
    /// The programmed feed (m/s).
    pub feed: Option<Real>,
    /// The sampling rate (Hz).
    pub sample_rate: Option<Real>,
    /// The sense of the first run.
    pub first: Option<Sense>,
    /// The machine's axis positions at the circle centre (SI): the linear axes where the centre
    /// ball was set, the rotary axes held during the test.
    pub centre: Option<AxisValues>,
}

impl TestConditions {
    /// The typed conditions of a preamble; a value of the wrong form is an error naming the
    /// file, line and key. Keys it does not know are left to other readers.
    pub fn from_preamble(c: &Conditions, file: &str) -> Result<TestConditions, TableError> {
        let positive = |key: &str| -> Result<Option<Real>, TableError> {
            match c.number(key, file)? {
                Some(v) if v <= 0.0 => {
                    let line = c.get(key).map(|(_, l)| l);
                    Err(TableError::new(
                        file,
                        line,
                        format!("{key} = {v}: expected a positive number"),
                    ))
                }
                other => Ok(other),
            }
        };
        let plane = match c.get("plane") {
            None => None,
            Some((text, line)) => Some(text.parse::<Plane>().map_err(|_| {
                TableError::new(
                    file,
                    Some(line),
                    format!("plane = {text}: expected XY, YZ or ZX"),
                )
            })?),
        };
        let first = match c.get("first_direction") {
            None => None,
            Some((text, line)) => Some(match text.to_ascii_lowercase().as_str() {
                "ccw" => Sense::Ccw,
                "cw" => Sense::Cw,
                _ => {
                    return Err(TableError::new(
                        file,
                        Some(line),
                        format!("first_direction = {text}: expected ccw or cw"),
                    ));
                }
            }),
        };
        let centre = match c.triple("centre_mm", file)? {
            None => None,
            Some(values) => {
                let mut centre = AxisValues::ZERO;
                for (axis, value) in [Axis::X, Axis::Y, Axis::Z].into_iter().zip(values) {
                    centre[axis] = value * M_PER_MM;
                }
                for (axis, key) in ROTARY_KEYS {
                    if let Some(value) = c.number(key, file)? {
                        centre[axis] = value * RAD_PER_DEG;
                    }
                }
                Some(centre)
            }
        };
        Ok(TestConditions {
            plane,
            radius: positive("radius_mm")?.map(|r| r * M_PER_MM),
            feed: positive("feed_mm_per_min")?.map(|f| f * M_PER_MM / 60.0),
            sample_rate: positive("sample_rate_hz")?,
            first,
            centre,
        })
    }

    /// The preamble that says these conditions (file units).
    pub fn to_preamble(&self) -> Conditions {
        let mut pairs: Vec<(&str, String)> = Vec::new();
        if let Some(plane) = self.plane {
            pairs.push(("plane", plane.to_string()));
        }
        if let Some(r) = self.radius {
            pairs.push(("radius_mm", trimmed(r / M_PER_MM, 6)));
        }
        if let Some(f) = self.feed {
            pairs.push(("feed_mm_per_min", trimmed(f / M_PER_MM * 60.0, 6)));
        }
        if let Some(rate) = self.sample_rate {
            pairs.push(("sample_rate_hz", trimmed(rate, 6)));
        }
        if let Some(first) = self.first {
            pairs.push(("first_direction", first.name().to_string()));
        }
        if let Some(centre) = self.centre {
            let mm = [Axis::X, Axis::Y, Axis::Z].map(|a| trimmed(centre[a] / M_PER_MM, 9));
            pairs.push(("centre_mm", mm.join(" ")));
            for (axis, key) in ROTARY_KEYS {
                if centre[axis] != 0.0 {
                    pairs.push((key, trimmed(centre[axis] / RAD_PER_DEG, 9)));
                }
            }
        }
        Conditions::from_pairs(pairs)
    }
}

/// The preamble keys of the rotary axes held during a test.
const ROTARY_KEYS: [(Axis, &str); 3] = [(Axis::A, "a_deg"), (Axis::B, "b_deg"), (Axis::C, "c_deg")];

/// A ball-bar table: the readings of one plane, both senses, in file order, and the test
/// conditions its preamble gives.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BallbarTable {
    /// The readings.
    pub readings: Vec<BallbarReading>,
    /// The test conditions from the file's preamble (none for a file without one).
    pub conditions: TestConditions,
    /// The machine's name, from the preamble's `machine`.
    pub machine: Option<String>,
    /// Columns of the file this reader read past, in header order (no figure depends on them).
    pub columns_not_read: Vec<String>,
}

/// The ball-bar transducer's range (µm): ±1 mm, the QC20-W's (Renishaw's specification); a
/// deviation beyond it cannot be a ball-bar reading.
pub const TRANSDUCER: Range = Range {
    limit: 1000.0,
    why: "a ball-bar's transducer reads ±1 mm (Renishaw QC20-W)",
};

const KNOWN: [&str; 4] = ["direction", "angle_deg", "deviation_um", "time_s"];

/// The fewest timed readings of a sense from which its angles' turn in time is judged against
/// its label (a trace has thousands; a handful of hand-typed rows is not judged).
const MIN_TIMED_FOR_SENSE: usize = 10;

/// Whether each sense's readings were timed on a clock of its own: both senses timed, and
/// their time spans overlap (a single capture's clock runs on from one sense to the next).
fn own_clocks(readings: &[BallbarReading]) -> bool {
    let span = |sense: Sense| {
        readings
            .iter()
            .filter(|r| r.sense == sense)
            .filter_map(|r| r.time)
            .fold(None, |span: Option<(Real, Real)>, t| {
                Some(span.map_or((t, t), |(lo, hi)| (lo.min(t), hi.max(t))))
            })
    };
    match (span(Sense::Ccw), span(Sense::Cw)) {
        (Some((a0, a1)), Some((b0, b1))) => a0 < b1 && b0 < a1,
        _ => false,
    }
}

impl BallbarTable {
    /// Reads a ball-bar table file.
    pub fn read(path: impl AsRef<Path>) -> Result<BallbarTable, TableError> {
        let (bytes, file) = read_file(path.as_ref())?;
        BallbarTable::parse(&bytes, &file)
    }

    /// Reads a ball-bar table from bytes; `file` names it in messages.
    pub fn parse(bytes: &[u8], file: &str) -> Result<BallbarTable, TableError> {
        let fail = |line: Option<u64>, message: String| TableError::new(file, line, message);
        let stated = Conditions::parse(bytes, file)?;
        let conditions = TestConditions::from_preamble(&stated, file)?;
        let machine = stated.get("machine").map(|(m, _)| m.to_string());
        let mut reader = csv_reader(bytes);
        let (header, header_line) = read_header(&mut reader, file)?;
        let columns_not_read = crate::io::read_past(
            header.iter().filter(|name| !KNOWN.contains(name)),
            |name| crate::io::looks_like(name, &KNOWN),
            "direction, angle_deg, deviation_um and time_s",
            header_line,
            file,
        )?;
        let column = |name: &str| header.iter().position(|h| h == name);
        let required = |name: &str| {
            column(name).ok_or_else(|| {
                fail(
                    Some(header_line),
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
        let mut first_line = None;
        // The times of each sense so far, with their lines: two readings of one sense at one
        // instant are a sweep pasted or appended again (rows may come in any order).
        let mut instants: [std::collections::HashMap<u64, Option<u64>>; 2] = Default::default();
        for record in reader.records() {
            let record = row(record, bytes, file)?;
            let line = record.position().map(|p| p.line());
            first_line = first_line.or(Some(line));
            let number = |index: usize, name: &str| finite_number(&record, index, name, file);
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
            let deviation =
                number_within(&record, deviation_column, "deviation_um", file, TRANSDUCER)?
                    * M_PER_UM;
            let time = time_column
                .map(|index| number_within(&record, index, "time_s", file, crate::io::CLOCK_S))
                .transpose()?;
            if let Some(t) = time
                && let Some(at) =
                    instants[usize::from(sense == Sense::Cw)].insert(t.to_bits(), line)
            {
                return Err(fail(
                    line,
                    format!(
                        "column `time_s`: a second {} reading at {t} s{}: one sense is read once at each instant, so the sweep was pasted or appended twice; give each sweep once",
                        sense.name(),
                        at.map_or_else(String::new, |l| format!(" (the first at line {l})"))
                    ),
                ));
            }
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
        // `first_direction` against the rows: the sense of the first reading (the earliest
        // when every reading has a time on one clock; in file order when each sense's capture
        // kept its own clock, both starting near 0, as an instrument that saves each run as
        // its own file and a user who joins them write it).
        if let (Some(first), Some((text, line))) = (conditions.first, stated.get("first_direction"))
        {
            let one_clock = !own_clocks(&readings);
            let earliest = readings
                .iter()
                .enumerate()
                .map(|(i, r)| r.time.map(|t| (i, t)))
                .collect::<Option<Vec<_>>>()
                .filter(|_| one_clock)
                .and_then(|timed| timed.into_iter().min_by(|a, b| a.1.total_cmp(&b.1)))
                .map_or(0, |(i, _)| i);
            let sense = readings[earliest].sense;
            if sense != first {
                let at = if earliest == 0 {
                    first_line.flatten()
                } else {
                    None
                };
                return Err(fail(
                    Some(line),
                    format!(
                        "first_direction = {text} in the preamble, but the first reading{} runs {}",
                        at.map_or_else(|| " in time".to_string(), |l| format!(" (line {l})")),
                        sense.name()
                    ),
                ));
            }
        }
        let table = BallbarTable {
            readings,
            conditions,
            machine,
            columns_not_read,
        };
        if let Some(message) =
            table.timing_contradiction(stated.get("sample_rate_hz").map(|(_, l)| l))
        {
            return Err(fail(None, message));
        }
        Ok(table)
    }

    /// What the clock says against the labels: a sense whose angles turn the other way in
    /// time (ccw is θ rising, from +p toward +q), or a clock stepping other than the preamble's
    /// sampling rate (line `rate_line`) says (more than 10 % off at the median: a time or feed
    /// column rescaled).
    fn timing_contradiction(&self, rate_line: Option<u64>) -> Option<String> {
        let mut steps = Vec::new();
        for sense in [Sense::Ccw, Sense::Cw] {
            let mut timed: Vec<(Real, Real)> = self
                .readings
                .iter()
                .filter(|r| r.sense == sense)
                .filter_map(|r| r.time.map(|t| (t, r.angle)))
                .collect();
            timed.sort_by(|a, b| a.0.total_cmp(&b.0));
            let turn: Real = timed
                .windows(2)
                .map(|w| {
                    let d = (w[1].1 - w[0].1).rem_euclid(std::f64::consts::TAU);
                    if d > std::f64::consts::PI {
                        d - std::f64::consts::TAU
                    } else {
                        d
                    }
                })
                .sum();
            steps.extend(timed.windows(2).map(|w| w[1].0 - w[0].0));
            if timed.len() >= MIN_TIMED_FOR_SENSE
                && turn * sense.sign() < -std::f64::consts::FRAC_PI_2
            {
                return Some(format!(
                    "column `direction`: the readings labelled {} turn {:.0}° the other way in time (angle_deg against time_s; ccw is the angle rising): the senses are swapped",
                    sense.name(),
                    turn.abs().to_degrees()
                ));
            }
        }
        let rate = self.conditions.sample_rate?;
        let step = crate::io::plausible::median(steps)?;
        ((step * rate - 1.0).abs() > 0.1).then(|| {
            format!(
                "column `time_s`: the readings are {} ms apart (median), but the preamble's sample_rate_hz = {}{} says {} ms: time_s (or the feed with it) rescaled?",
                trimmed(step * 1e3, 4),
                trimmed(rate, 6),
                rate_line.map_or_else(String::new, |l| format!(" (line {l})")),
                trimmed(1e3 / rate, 4)
            )
        })
    }

    /// The angular speed of the test (rad/s) that the angles and times imply, with its standard
    /// error: a straight line θ(t) fitted to each sense's readings in time order (angles
    /// unwrapped), pooled. `None` without times or with fewer than three timed readings in
    /// each sense that has any.
    pub fn angular_speed(&self) -> Option<(Real, Real)> {
        let mut slopes = Vec::new();
        for sense in [Sense::Ccw, Sense::Cw] {
            let mut points: Vec<(Real, Real)> = self
                .readings
                .iter()
                .filter(|r| r.sense == sense)
                .map(|r| r.time.map(|t| (t, r.angle)))
                .collect::<Option<_>>()?;
            if points.is_empty() {
                continue;
            }
            if points.len() < 3 {
                return None;
            }
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut unwrapped = Vec::with_capacity(points.len());
            let mut previous = points[0].1;
            let mut turns = 0.0;
            for &(t, angle) in &points {
                let step = angle - previous;
                if step > std::f64::consts::PI {
                    turns -= std::f64::consts::TAU;
                } else if step < -std::f64::consts::PI {
                    turns += std::f64::consts::TAU;
                }
                previous = angle;
                unwrapped.push((t, angle + turns));
            }
            let n = unwrapped.len() as Real;
            let (mt, ma) = unwrapped
                .iter()
                .fold((0.0, 0.0), |(a, b), (t, y)| (a + t / n, b + y / n));
            let (mut stt, mut sty) = (0.0, 0.0);
            for (t, y) in &unwrapped {
                stt += (t - mt) * (t - mt);
                sty += (t - mt) * (y - ma);
            }
            if stt <= 0.0 {
                return None;
            }
            let slope = sty / stt;
            let rss: Real = unwrapped
                .iter()
                .map(|(t, y)| (y - ma - slope * (t - mt)).powi(2))
                .sum();
            let se = (rss / (n - 2.0) / stt).sqrt();
            slopes.push((slope.abs(), se));
        }
        if slopes.is_empty() {
            return None;
        }
        let k = slopes.len() as Real;
        let speed = slopes.iter().map(|s| s.0).sum::<Real>() / k;
        let se = slopes.iter().map(|s| s.1 * s.1).sum::<Real>().sqrt() / k;
        Some((speed, se))
    }

    /// Writes the table: its conditions as a preamble (when it has any), then `direction,
    /// angle_deg, deviation_um[, time_s]`; angles to 1 µ°, deviations to 1 pm, times to 1 µs, so
    /// the same table gives the same bytes.
    pub fn write_csv(&self, mut out: impl std::io::Write) -> csv::Result<()> {
        let conditions = self.conditions.to_preamble();
        let machine = self
            .machine
            .iter()
            .map(|m| ("machine".to_string(), m.clone()));
        let stated = conditions.keys().map(|key| {
            let (value, _) = conditions.get(key).expect("a key it lists");
            (key.to_string(), value.to_string())
        });
        let preamble = Conditions::from_pairs(stated.chain(machine));
        if !preamble.is_empty() {
            out.write_all(
                preamble
                    .to_preamble("mtwin ballbar table (ISO 230-4 circular test)")
                    .as_bytes(),
            )?;
        }
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
            ..Default::default()
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
