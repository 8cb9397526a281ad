//! The `spindle` table: one spindle-analyser record ([`SpindleRecord`]) as a file, sample by
//! sample, probe by probe, as a spindle error analyser exports it, in any column order. The same
//! reader serves mtwin's own tables and foreign exports (no preamble geometry, conventional
//! probe names, CRLF line endings).
//!
//! | column | required | meaning |
//! |---|---|---|
//! | `setup` | no | set-up name (reversal, multi-step); `""` when absent; trimmed |
//! | `revolution` | yes | revolution number (0, 1, …): consecutive within a run, each revolution `samples_per_revolution` rows; a run's first revolution is stored as 0 (a 1-based export reads as 0-based) |
//! | `angle_deg` | yes | axis angle from the index mark, in `[0, 360)`, strictly increasing within a revolution; at a negative `speed_rpm` decreasing from the mark (0, then just under 360: the angle travelled increases) (stored in rad) |
//! | `time_s` | one of the two | time of the sample (s) |
//! | `speed_rpm` | one of the two | commanded speed, signed (positive for positive rotation of the axis); constant within a run, or a logged measured speed jittering within 1 % of it, read as the run's mean (stored in rad/s) |
//! | `NAME_um` | at least one | the reading of probe `NAME` (µm; artefact motion along the probe's direction increases it); `NAME` is lower-case letters, digits and `_` |
//!
//! Any other column (a sample index, a thermometer) is read past and listed in the report as
//! not read, unless it looks like one of these written another way (`Angle (deg)`, `x_mm`, a
//! probe `x` without its unit), which is refused by name.
//!
//! A **run** is a stretch of consecutive rows with the same `setup` and `speed_rpm` whose
//! revolution numbers do not go back: a change of set-up or speed, or a revolution number lower
//! than the row before, starts the next run.
//!
//! When one of `time_s` and `speed_rpm` is missing it is computed from the other:
//!
//! * no `speed_rpm`: each run's speed is the least-squares slope of the unwrapped angle
//!   (`2π·revolution + angle`) against `time_s`, so positive when time runs with the angle; a
//!   run whose times do not change (or of one sample) gets speed 0;
//! * no `time_s`: time starts at 0 and grows by the angle step over `|speed|` within a run, and
//!   by one nominal sample period (`2π / (samples_per_revolution·|speed|)`) from one run to the
//!   next; if any speed is 0 (a static record, ISO 230-7 Annex E) time cannot be computed and is
//!   then the **sample index in revolutions** (`i / samples_per_revolution`), not seconds.
//!
//! The preamble (`# key = value`, see [`Conditions`]) after the title line
//! `# mtwin spindle table` states the record (ISO 230-7 §5.2):
//!
//! | key | meaning |
//! |---|---|
//! | `machine` | the machine's name |
//! | `axis` | the axis of rotation: `S` (default), `C`, `A` or `B` (either case) |
//! | `samples_per_revolution` | rows per revolution; when absent, the length of the first revolution |
//! | `artefact` | free text, e.g. `sphere 25.4 mm` (§5.2 b) |
//! | `NAME_direction` | `dx dy dz`: probe `NAME`'s sensitive direction (§5.2 e), a unit vector within 1e-6 (normalised on reading) |
//! | `NAME_position_mm` | `x y z`: the sensed point on the artefact (mm), axis frame (§5.2 a, k) |
//! | `NAME_sensing` | `fixed` (default) or `rotating` |
//! | `NAME_azimuth_deg` | instead of the two keys above, for a radial probe given by its angle alone (multi-probe exports): it sits at this azimuth from X (counter-clockwise seen from +z), faces the axis and reads positive when the surface moves away (ISO 230-7 A.7.2), at height `NAME_height_mm` (default 0) |
//! | `station_separation_mm` | height of the second radial station (`x2`, `y2`) above the first |
//! | `face_radius_mm` | radius of the `face` probe's point |
//! | `bandwidth_hz`, `resolution_nm` | the instrumentation (§5.2 j) |
//!
//! `revolutions`, `speeds_rpm` and `setups` (what [`super::run`] writes) are checked against
//! the rows when given (see [`super::stated`]): a preamble that says another number of
//! revolutions, other speeds or other set-ups than the rows is refused at its line with both.
//!
//! Numbers among these are checked when given; every key, these and any other (`date`,
//! `instrument`, `sample_rate_hz`, `temperature_c`, …), is kept in
//! [`SpindleTable::conditions`]. Frames and signs are those of [`super::record`].
//!
//! A probe without `NAME_direction` or `NAME_position_mm` takes them from its conventional
//! name, as foreign exports name their channels (a radial probe's radius is not known from such
//! a file: its point is put on the axis at its height):
//!
//! | name | direction | position |
//! |---|---|---|
//! | `x`, `x1` | +x | on the axis at height 0 |
//! | `y`, `y1` | +y | on the axis at height 0 |
//! | `x2` | +x | on the axis at height `station_separation_mm` (required then) |
//! | `y2` | +y | on the axis at height `station_separation_mm` (required then) |
//! | `z` | +z | on the axis at height 0 |
//! | `face` | +z | at radius `face_radius_mm` (required then) on +x, height 0 |
//!
//! Any other name needs both keys.
//!
//! Every refusal names the file, the line and the column or key: a cell that is not a finite
//! number (`NaN` included), a revolution number that is not a whole number or skips one, a
//! revolution shorter or longer than `samples_per_revolution` (at the line where it ends, with
//! both counts), an angle outside `[0, 360)` or not above the one before in its revolution, a
//! missing or unknown column, a probe without geometry, a preamble value of the wrong form.
//!
//! [`write_csv`] always writes every probe's three keys, `axis` and `samples_per_revolution`,
//! then angles (deg) and times to 6 decimals, speeds (rpm) to 3 and readings (µm) to 6 (1 pm).

use super::record::{Sensing, SpindleProbe, SpindleRecord};
use crate::io::{
    Conditions, Range, TableError, csv_reader, finite_number, number_within, read_file,
    read_header, row,
};
use crate::machine::Axis;
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, trimmed};
use std::f64::consts::TAU;
use std::path::Path;

mod write;
pub use write::write_csv;

/// The title line of the preamble [`write_csv`] writes.
pub const TITLE: &str = "mtwin spindle table";

/// A spindle table: the record, the preamble and the revolution length.
#[derive(Clone, Debug, PartialEq)]
pub struct SpindleTable {
    /// The samples and the probes' geometry, SI.
    pub record: SpindleRecord,
    /// The preamble as read (every key, including the geometry keys the record holds).
    pub conditions: Conditions,
    /// Samples in every revolution.
    pub samples_per_revolution: usize,
    /// Columns of the file this reader read past, in header order (no figure depends on them).
    pub columns_not_read: Vec<String>,
}

/// The fixed columns.
const SETUP: &str = "setup";
const REVOLUTION: &str = "revolution";
const ANGLE: &str = "angle_deg";
const TIME: &str = "time_s";
const SPEED: &str = "speed_rpm";

/// Numeric conditions checked when given.
const NUMBERS: [&str; 4] = [
    "station_separation_mm",
    "face_radius_mm",
    "bandwidth_hz",
    "resolution_nm",
];

/// Radians per second in one revolution per minute.
const RAD_PER_S_PER_RPM: Real = TAU / 60.0;

/// Reads a spindle table file.
pub fn read(path: &Path) -> Result<SpindleTable, TableError> {
    let (bytes, file) = read_file(path)?;
    parse(&bytes, &file)
}

/// A spindle probe's range (µm): error motions are micrometres, and the capacitive and
/// eddy-current probes of spindle analysers read a few millimetres at most; a reading beyond
/// 10 mm is a unit slip or a corrupted cell.
pub const PROBE: Range = Range {
    limit: 10_000.0,
    why: "a spindle analyser's displacement probes read a few mm at most",
};

/// How far a run's speed, from its angles against its times, may differ from its stated
/// `speed_rpm`: 5 %. A spindle turns within a percent or two of its commanded speed; a unit
/// slip is a factor of 57 (radians in `angle_deg`) or 60 (seconds for minutes).
pub const SPEED_AGREEMENT: Real = 0.05;

/// Refuses angles that cannot be degrees: a record of full revolutions (8 samples or more each)
/// whose `angle_deg` never passes 2π is in radians; and, where a run gives both `time_s` and
/// `speed_rpm`, the angles must advance at the stated speed within [`SPEED_AGREEMENT`].
fn check_angle_units(
    rows: &[Row],
    runs: &[(usize, usize)],
    unwrapped: &[Real],
    time: &Option<Vec<Real>>,
    speed: &Option<Vec<Real>>,
    samples_per_revolution: usize,
    file: &str,
) -> Result<(), TableError> {
    let largest = rows.iter().map(|r| r.angle_deg).fold(0.0, Real::max);
    if samples_per_revolution >= 8 && rows.len() >= samples_per_revolution && largest <= TAU + 1e-9
    {
        return Err(TableError::new(
            file,
            rows.first().and_then(|r| r.line),
            format!(
                "column `angle_deg`: the angles never pass {} over revolutions of {samples_per_revolution} samples; \
                 they look like radians (a revolution spans 360°)",
                trimmed(largest, 6)
            ),
        ));
    }
    let (Some(time), Some(speed)) = (time, speed) else {
        return Ok(());
    };
    for &(start, end) in runs {
        let stated = speed[start];
        if end - start < 3 || stated == 0.0 {
            continue;
        }
        let travelled = slope(&time[start..end], &unwrapped[start..end]);
        if (travelled - stated).abs() > SPEED_AGREEMENT * stated.abs() {
            let rpm = |w: Real| trimmed(w / RAD_PER_S_PER_RPM, 3);
            return Err(TableError::new(
                file,
                rows[start].line,
                format!(
                    "column `speed_rpm`: {} rpm, but the angles advance at {} rpm against time_s in the run from this line; \
                     angles in radians, or times in another unit?",
                    rpm(stated),
                    rpm(travelled)
                ),
            ));
        }
    }
    Ok(())
}

/// One data row as read, before the checks across rows.
/// The largest relative spread of a logged `speed_rpm` within one run: 1 %. An analyser that
/// logs the measured speed shows the drive's jitter (a few 0.01 % on a spindle drive); a run
/// is one commanded speed, and a speed programme's steps differ by far more.
pub const SPEED_JITTER: Real = 0.01;

/// Speeds that jitter within a run (consecutive rows of one set-up, revolutions not going
/// back, each speed within [`SPEED_JITTER`] of the run's first and of its sign) are read as
/// the run's mean: the measured speed of an analyser's log, not a new run at every sample.
fn steady_speeds(rows: &mut [Row]) {
    let mut start = 0;
    for i in 1..=rows.len() {
        let ends = i == rows.len() || {
            let (first, this) = (&rows[start], &rows[i]);
            this.setup != first.setup
                || this.revolution < rows[i - 1].revolution
                || match (first.speed_rpm, this.speed_rpm) {
                    (Some(a), Some(b)) => {
                        a.signum() != b.signum() || (b - a).abs() > SPEED_JITTER * a.abs()
                    }
                    _ => false,
                }
        };
        if ends {
            let run = &mut rows[start..i];
            let speeds: Option<Vec<Real>> = run.iter().map(|r| r.speed_rpm).collect();
            if let Some(speeds) = speeds {
                let mean = speeds.iter().sum::<Real>() / speeds.len() as Real;
                for row in run.iter_mut() {
                    row.speed_rpm = Some(mean);
                }
            }
            start = i;
        }
    }
}

struct Row {
    line: Option<u64>,
    setup: String,
    revolution: usize,
    angle_deg: Real,
    time: Option<Real>,
    speed_rpm: Option<Real>,
    readings: Vec<Real>,
}

/// Reads a spindle table from bytes; `file` names it in messages.
pub fn parse(bytes: &[u8], file: &str) -> Result<SpindleTable, TableError> {
    let fail = |line: Option<u64>, message: String| TableError::new(file, line, message);
    let conditions = Conditions::parse(bytes, file)?;
    let axis = match conditions.get("axis") {
        None => Axis::S,
        Some((text, line)) => {
            let mut letters = text.chars();
            match (
                letters.next().map(|c| c.to_ascii_uppercase()),
                letters.next(),
            ) {
                (Some(c @ ('S' | 'C' | 'A' | 'B')), None) => {
                    Axis::from_letter(c).unwrap_or(Axis::S)
                }
                _ => {
                    return Err(fail(
                        Some(line),
                        format!("axis = {text}: expected S, C, A or B (the axis of rotation)"),
                    ));
                }
            }
        }
    };
    let declared = match conditions.get("samples_per_revolution") {
        None => None,
        Some((text, line)) => match text.parse::<usize>() {
            Ok(n) if n > 0 => Some(n),
            _ => {
                return Err(fail(
                    Some(line),
                    format!("samples_per_revolution = {text}: expected a positive whole number"),
                ));
            }
        },
    };
    for key in NUMBERS {
        conditions.number(key, file)?;
    }

    let mut reader = csv_reader(bytes);
    let (header, header_line) = read_header(&mut reader, file)?;
    let mut probe_columns: Vec<(usize, String)> = Vec::new();
    let mut columns_not_read = Vec::new();
    let fixed = [SETUP, REVOLUTION, ANGLE, TIME, SPEED];
    for (index, name) in header.iter().enumerate() {
        if fixed.contains(&name) {
            continue;
        }
        match name.strip_suffix("_um") {
            Some(probe) if !probe.is_empty() => {
                let valid = probe
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
                if !valid {
                    return Err(fail(
                        Some(header_line),
                        format!(
                            "column `{name}`: a probe's name is lower-case letters, digits and `_` \
                             (its preamble keys are `NAME_direction`, `NAME_position_mm`, `NAME_sensing`)"
                        ),
                    ));
                }
                probe_columns.push((index, probe.to_string()));
            }
            _ => {
                let slip = crate::io::looks_like(name, &fixed).or_else(|| {
                    crate::io::channel_slip(name, &["um"], &[crate::io::Quantity::Length])
                });
                if let Some(message) = slip {
                    return Err(fail(
                        Some(header_line),
                        format!(
                            "{message} (this reader reads setup, revolution, angle_deg, time_s, \
                             speed_rpm and one NAME_um per probe)"
                        ),
                    ));
                }
                columns_not_read.push(name.to_string());
            }
        }
    }
    let column = |name: &str| header.iter().position(|h| h == name);
    let required = |name: &str| {
        column(name).ok_or_else(|| {
            fail(
                Some(header_line),
                format!("missing column `{name}` (required: revolution, angle_deg, time_s or speed_rpm, and NAME_um per probe)"),
            )
        })
    };
    let revolution_column = required(REVOLUTION)?;
    let angle_column = required(ANGLE)?;
    let (setup_column, time_column, speed_column) = (column(SETUP), column(TIME), column(SPEED));
    if time_column.is_none() && speed_column.is_none() {
        return Err(fail(
            Some(header_line),
            "missing column `time_s` or `speed_rpm` (at least one is required)".into(),
        ));
    }
    if probe_columns.is_empty() {
        return Err(fail(
            Some(header_line),
            "no probe column: give one `NAME_um` column per probe (e.g. `x_um`, `y_um`)".into(),
        ));
    }
    let probes = probe_columns
        .iter()
        .map(|(_, name)| probe_geometry(name, &conditions, file, header_line))
        .collect::<Result<Vec<_>, _>>()?;

    let mut rows: Vec<Row> = Vec::new();
    for record in reader.records() {
        let record = row(record, bytes, file)?;
        let line = record.position().map(|p| p.line());
        let number = |index: usize, name: &str| finite_number(&record, index, name, file);
        let text = &record[revolution_column];
        let revolution = text.parse::<usize>().map_err(|_| {
            fail(
                line,
                format!(
                    "column `revolution`: expected a revolution number (0, 1, …), found \"{text}\""
                ),
            )
        })?;
        let angle_deg = number(angle_column, ANGLE)?;
        if !(0.0..360.0).contains(&angle_deg) {
            return Err(fail(
                line,
                format!("column `angle_deg`: {angle_deg} is outside [0, 360)"),
            ));
        }
        let readings = probe_columns
            .iter()
            .map(|(index, name)| {
                number_within(&record, *index, &format!("{name}_um"), file, PROBE)
                    .map(|v| v * M_PER_UM)
            })
            .collect::<Result<Vec<_>, _>>()?;
        rows.push(Row {
            line,
            setup: setup_column.map_or_else(String::new, |i| record[i].to_string()),
            revolution,
            angle_deg,
            time: time_column
                .map(|i| number_within(&record, i, TIME, file, crate::io::CLOCK_S))
                .transpose()?,
            speed_rpm: speed_column.map(|i| number(i, SPEED)).transpose()?,
            readings,
        });
    }
    if rows.is_empty() {
        return Err(fail(None, "no data rows".into()));
    }
    steady_speeds(&mut rows);

    // Runs and revolutions.
    let mut samples_per_revolution = declared;
    let mut runs: Vec<(usize, usize)> = Vec::new(); // [start, end) row ranges
    let mut revolution = Vec::with_capacity(rows.len());
    let mut run_start = 0;
    let mut block_start = 0;
    let mut base = rows[0].revolution;
    for i in 0..=rows.len() {
        let (new_run, new_block) = if i == rows.len() {
            (true, true)
        } else if i == 0 {
            (false, false)
        } else {
            let (before, this) = (&rows[i - 1], &rows[i]);
            let new_run = this.setup != before.setup
                || this.speed_rpm != before.speed_rpm
                || this.revolution < before.revolution;
            if !new_run && this.revolution > before.revolution + 1 {
                return Err(fail(
                    this.line,
                    format!(
                        "column `revolution`: revolution {} follows revolution {} (revolutions are consecutive)",
                        this.revolution, before.revolution
                    ),
                ));
            }
            // Angles follow the rotation: they increase within a revolution, and decrease
            // from the index mark (0, then just under 360) when the recorded speed is negative
            // (the axis turning backwards): the angle travelled, `(360 − a) mod 360`, increases.
            let backwards = this.speed_rpm.is_some_and(|w| w < 0.0);
            let travelled = |a: Real| (360.0 - a).rem_euclid(360.0);
            let in_order = if backwards {
                travelled(this.angle_deg) > travelled(before.angle_deg)
            } else {
                this.angle_deg > before.angle_deg
            };
            if !new_run && this.revolution == before.revolution && !in_order {
                let (verb, rule) = if backwards {
                    (
                        "decrease",
                        "angles decrease strictly within a revolution at a negative speed",
                    )
                } else {
                    ("increase", "angles increase strictly within a revolution")
                };
                return Err(fail(
                    this.line,
                    format!(
                        "column `angle_deg`: {} does not {verb} from {} on the row before ({rule})",
                        this.angle_deg, before.angle_deg
                    ),
                ));
            }
            (new_run, new_run || this.revolution != before.revolution)
        };
        if new_block && i > 0 {
            let count = i - block_start;
            let expected = *samples_per_revolution.get_or_insert(count);
            if count != expected {
                let source = if declared.is_some() {
                    "samples_per_revolution in the preamble"
                } else {
                    "samples_per_revolution inferred from the first revolution"
                };
                return Err(fail(
                    rows[i - 1].line,
                    format!(
                        "revolution {} ends here after {count} samples; every revolution has \
                         {expected} ({source})",
                        rows[i - 1].revolution
                    ),
                ));
            }
            block_start = i;
        }
        if new_run && i > 0 {
            runs.push((run_start, i));
            run_start = i;
        }
        if i < rows.len() {
            if new_run {
                base = rows[i].revolution;
            }
            revolution.push(rows[i].revolution - base);
        }
    }
    let samples_per_revolution = samples_per_revolution.unwrap_or(1);

    let angle: Vec<Real> = rows.iter().map(|r| r.angle_deg * RAD_PER_DEG).collect();
    // The angle travelled: backwards revolutions count down.
    let unwrapped: Vec<Real> = revolution
        .iter()
        .zip(&angle)
        .zip(&rows)
        .map(|((k, a), row)| {
            if row.speed_rpm.is_some_and(|w| w < 0.0) {
                -(*k as Real) * TAU - (TAU - a).rem_euclid(TAU)
            } else {
                *k as Real * TAU + a
            }
        })
        .collect();
    let given_time: Option<Vec<Real>> = rows.iter().map(|r| r.time).collect();
    let given_speed: Option<Vec<Real>> = rows
        .iter()
        .map(|r| r.speed_rpm.map(|v| v * RAD_PER_S_PER_RPM))
        .collect();
    let speed = match (&given_speed, &given_time) {
        (Some(speed), _) => speed.clone(),
        (None, Some(time)) => {
            let mut speed = vec![0.0; rows.len()];
            for &(start, end) in &runs {
                let slope = slope(&time[start..end], &unwrapped[start..end]);
                speed[start..end].fill(slope);
            }
            speed
        }
        (None, None) => vec![0.0; rows.len()], // refused at the header
    };
    check_angle_units(
        &rows,
        &runs,
        &unwrapped,
        &given_time,
        &given_speed,
        samples_per_revolution,
        file,
    )?;
    let summaries: Vec<super::stated::RunSummary<'_>> = runs
        .iter()
        .map(|&(start, end)| super::stated::RunSummary {
            setup: &rows[start].setup,
            speed_rpm: speed[start] / RAD_PER_S_PER_RPM,
            revolutions: revolution[end - 1] + 1,
            line: rows[start].line,
        })
        .collect();
    super::stated::check(&conditions, file, &summaries)?;
    let time = match given_time {
        Some(time) => time,
        None if speed.iter().all(|w| *w != 0.0) => {
            let mut time = vec![0.0; rows.len()];
            let mut run = 0;
            for i in 1..rows.len() {
                time[i] = if i == runs[run].1 {
                    run += 1;
                    time[i - 1] + TAU / (samples_per_revolution as Real * speed[i].abs())
                } else {
                    time[i - 1] + (unwrapped[i] - unwrapped[i - 1]).abs() / speed[i].abs()
                };
            }
            time
        }
        None => (0..rows.len())
            .map(|i| i as Real / samples_per_revolution as Real)
            .collect(),
    };
    let mut readings = vec![Vec::with_capacity(rows.len()); probes.len()];
    for r in &rows {
        for (p, v) in r.readings.iter().enumerate() {
            readings[p].push(*v);
        }
    }
    Ok(SpindleTable {
        record: SpindleRecord {
            axis,
            probes,
            setup: rows.iter().map(|r| r.setup.clone()).collect(),
            revolution,
            angle,
            time,
            speed,
            readings,
        },
        conditions,
        samples_per_revolution,
        columns_not_read,
    })
}

/// The least-squares slope of `y` against `x`; 0 when `x` does not vary.
fn slope(x: &[Real], y: &[Real]) -> Real {
    let n = x.len() as Real;
    if x.len() < 2 {
        return 0.0;
    }
    let (mx, my) = (x.iter().sum::<Real>() / n, y.iter().sum::<Real>() / n);
    let sxx: Real = x.iter().map(|x| (x - mx).powi(2)).sum();
    let sxy: Real = x.iter().zip(y).map(|(x, y)| (x - mx) * (y - my)).sum();
    let slope = sxy / sxx;
    if sxx > 0.0 && slope.is_finite() {
        slope
    } else {
        0.0
    }
}

/// Probe `name`'s geometry from its preamble keys, or from its conventional name.
fn probe_geometry(
    name: &str,
    conditions: &Conditions,
    file: &str,
    header_line: u64,
) -> Result<SpindleProbe, TableError> {
    let fail = |line: u64, message: String| TableError::new(file, Some(line), message);
    let direction_key = format!("{name}_direction");
    let position_key = format!("{name}_position_mm");
    let sensing_key = format!("{name}_sensing");
    let height = |key: &str| -> Result<Real, TableError> {
        conditions.number(key, file)?.ok_or_else(|| {
            fail(
                header_line,
                format!(
                    "column `{name}_um`: probe `{name}` needs `{key}` in the preamble (or \
                     `{name}_direction` and `{name}_position_mm`)"
                ),
            )
        })
    };
    let given_direction = conditions.triple(&direction_key, file)?;
    let given_position = conditions.triple(&position_key, file)?;
    let azimuth_key = format!("{name}_azimuth_deg");
    if let Some(azimuth) = conditions.number(&azimuth_key, file)? {
        if given_direction.is_some() || given_position.is_some() {
            let (_, line) = conditions.get(&azimuth_key).unwrap_or(("", header_line));
            return Err(fail(
                line,
                format!(
                    "probe `{name}`: give either `{azimuth_key}` or `{direction_key}` and                      `{position_key}`, not both"
                ),
            ));
        }
        let height = conditions
            .number(&format!("{name}_height_mm"), file)?
            .unwrap_or(0.0);
        let (sin, cos) = (azimuth * RAD_PER_DEG).sin_cos();
        return Ok(SpindleProbe {
            name: name.to_string(),
            direction: [-cos, -sin, 0.0],
            position: [0.0, 0.0, height * M_PER_MM],
            sensing: Sensing::Fixed,
        });
    }
    let default = conventional(name);
    let direction = match (given_direction, &default) {
        (Some(d), _) => {
            let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if (length - 1.0).abs() > 1e-6 {
                let (text, line) = conditions.get(&direction_key).unwrap_or(("", header_line));
                return Err(fail(
                    line,
                    format!(
                        "{direction_key} = {text}: not a unit vector (length {length:.9}); give \
                         it to within 1e-6"
                    ),
                ));
            }
            d.map(|c| c / length)
        }
        (None, Some((d, _))) => *d,
        (None, None) => return Err(no_geometry(name, file, header_line)),
    };
    let position = match (given_position, default) {
        (Some(p), _) => p.map(|c| c * M_PER_MM),
        (None, Some((_, Point::Centre))) => [0.0; 3],
        (None, Some((_, Point::Height(key)))) => [0.0, 0.0, height(key)? * M_PER_MM],
        (None, Some((_, Point::Radius(key)))) => [height(key)? * M_PER_MM, 0.0, 0.0],
        (None, None) => return Err(no_geometry(name, file, header_line)),
    };
    let sensing = match conditions.get(&sensing_key) {
        None | Some(("fixed", _)) => Sensing::Fixed,
        Some(("rotating", _)) => Sensing::Rotating,
        Some((text, line)) => {
            return Err(fail(
                line,
                format!("{sensing_key} = {text}: expected fixed or rotating"),
            ));
        }
    };
    Ok(SpindleProbe {
        name: name.to_string(),
        direction,
        position,
        sensing,
    })
}

/// Where a conventionally named probe's sensed point is.
enum Point {
    /// On the axis at height 0.
    Centre,
    /// On the axis at the height (mm) the preamble key gives.
    Height(&'static str),
    /// On +x at height 0, at the radius (mm) the preamble key gives.
    Radius(&'static str),
}

/// The direction and sensed point of a probe with a conventional name.
fn conventional(name: &str) -> Option<([Real; 3], Point)> {
    let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    Some(match name {
        "x" | "x1" => (x, Point::Centre),
        "y" | "y1" => (y, Point::Centre),
        "x2" => (x, Point::Height("station_separation_mm")),
        "y2" => (y, Point::Height("station_separation_mm")),
        "z" => (z, Point::Centre),
        "face" => (z, Point::Radius("face_radius_mm")),
        _ => return None,
    })
}

/// The error for a probe with neither keys nor a conventional name.
fn no_geometry(name: &str, file: &str, header_line: u64) -> TableError {
    TableError::new(
        file,
        Some(header_line),
        format!(
            "column `{name}_um`: no geometry for probe `{name}`: give `{name}_direction = dx dy dz` \
             and `{name}_position_mm = x y z`, or `{name}_azimuth_deg` for a radial probe, in the \
             preamble (names with defaults: x, x1, y, y1, x2, y2, z, face)"
        ),
    )
}
