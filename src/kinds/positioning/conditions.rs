//! The conditions of a positioning test, as a table's preamble carries them (`# key = value`
//! lines before the header, see [`crate::io::Conditions`]):
//!
//! | key | meaning |
//! |---|---|
//! | `test` | `iso230_2` (ISO 230-2 positioning), `warmup` (runs between warm-up intervals) or `iso230_3_linear` (ISO 230-3 §7 drift) |
//! | `axis` | `X`, `Y` or `Z` |
//! | `runs` | the number of runs |
//! | `targets_mm` | the target positions, comma-separated |
//! | `compensation` | what the laser corrected: `none`, `air` (the refractive index, from its sensors), `nde` (the material's expansion, to 20 °C) or `air+nde` |
//! | `machine` | the machine's name |
//! | `x_mm`, `y_mm`, `z_mm`, `a_deg`, `b_deg`, `c_deg` | where the machine's other axes stood during the test (the line of the test), as `[iso230_2]` sets them; not the axis under test |
//! | `beam_offset_mm` | `x y z`: the reflector relative to the tool tip, tool frame (the Abbe offset), as `[laser]` sets it |
//! | `interferometer_on` | `workpiece` (the reflector rides on the tool) or `tool` (the reverse set-up) |
//! | `zero` | `once` (one datum for the test, at its first reading) or `each_run` (at each run's first reading) |
//!
//! A table without them reads as before. Those the data can check are checked when the table is
//! read: the axis against an `axis` column, the runs against the runs the rows hold, every
//! reading's target against the targets (within [`TARGET_TOLERANCE`]) and every target against
//! the readings.

use super::setup::{Mounting, Zeroing};
use crate::io::{Conditions, TableError};
use crate::machine::{Axis, axis_unit_to_si};
use crate::math::{M_PER_MM, Real, Vector, trimmed};

/// How far a reading's target may lie from a stated target and still be it (m): half the last
/// digit of an export that writes targets to 0.01 mm (the targets of a test lie millimetres
/// apart, so no reading is taken for its neighbour).
pub const TARGET_TOLERANCE: Real = 5e-6;

/// The test a positioning table comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PositioningTest {
    /// ISO 230-2 linear positioning (bidirectional runs over targets).
    Iso230_2,
    /// Runs over the axis between idle-running warm-up intervals (Lu 2012 Ch. 5).
    Warmup,
    /// The ISO 230-3 §7 linear-motion drift test (two targets, 4 h of cycling, cool-down).
    Iso230_3Linear,
}

impl PositioningTest {
    /// The name in preambles and scenario files.
    pub fn name(self) -> &'static str {
        match self {
            PositioningTest::Iso230_2 => "iso230_2",
            PositioningTest::Warmup => "warmup",
            PositioningTest::Iso230_3Linear => "iso230_3_linear",
        }
    }

    /// The title line of a table from this test.
    pub fn title(self) -> &'static str {
        match self {
            PositioningTest::Iso230_2 => "mtwin positioning table (ISO 230-2 linear positioning)",
            PositioningTest::Warmup => "mtwin positioning table (runs between warm-up intervals)",
            PositioningTest::Iso230_3Linear => {
                "mtwin positioning table (ISO 230-3 §7 linear-motion drift)"
            }
        }
    }
}

/// The conditions of a positioning test, each absent when the file does not say (SI).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PositioningConditions {
    /// The test.
    pub test: Option<PositioningTest>,
    /// The axis.
    pub axis: Option<Axis>,
    /// The number of runs.
    pub runs: Option<usize>,
    /// The target positions (m).
    pub targets: Option<Vec<Real>>,
    /// What the laser corrected (`none`, `air`, `air+nde`), as stated.
    pub compensation: Option<String>,
    /// The machine's name.
    pub machine: Option<String>,
    /// Where the machine's other axes stood during the test (SI), those the preamble names, in
    /// ISO order.
    pub axes: Vec<(Axis, Real)>,
    /// The reflector relative to the tool tip, tool frame (m).
    pub beam_offset: Option<Vector>,
    /// Which side carries the interferometer.
    pub mounting: Option<Mounting>,
    /// When the laser was zeroed.
    pub zero: Option<Zeroing>,
    /// Keys of the preamble this reader does not know, in file order (kept out of every
    /// figure, named by the report).
    pub not_used: Vec<String>,
}

/// The laser's compensations a preamble may state.
pub const COMPENSATIONS: [&str; 4] = ["none", "air", "nde", "air+nde"];

/// The preamble key of an axis position: `x_mm`, …, `c_deg` (none for the spindle).
pub fn axis_key(axis: Axis) -> Option<String> {
    let unit = match axis {
        Axis::S => return None,
        a if a.is_linear() => "mm",
        _ => "deg",
    };
    Some(format!("{}_{unit}", axis.letter().to_ascii_lowercase()))
}

impl PositioningConditions {
    /// The typed conditions of a preamble; a value of the wrong form is an error naming the
    /// file, line and key. Keys it does not know are left to other readers.
    pub fn from_preamble(c: &Conditions, file: &str) -> Result<Self, TableError> {
        let wrong = |key: &str, text: &str, line: u64, expected: &str| {
            TableError::new(
                file,
                Some(line),
                format!("{key} = {text}: expected {expected}"),
            )
        };
        let test = match c.get("test") {
            None => None,
            Some((text, line)) => Some(
                [
                    PositioningTest::Iso230_2,
                    PositioningTest::Warmup,
                    PositioningTest::Iso230_3Linear,
                ]
                .into_iter()
                .find(|t| t.name() == text)
                .ok_or_else(|| wrong("test", text, line, "iso230_2, warmup or iso230_3_linear"))?,
            ),
        };
        let axis = match c.get("axis") {
            None => None,
            Some((text, line)) => {
                Some(parse_axis(text).ok_or_else(|| wrong("axis", text, line, "X, Y or Z"))?)
            }
        };
        let runs = match c.get("runs") {
            None => None,
            Some((text, line)) => Some(
                text.parse::<usize>()
                    .ok()
                    .filter(|n| *n > 0)
                    .ok_or_else(|| {
                        wrong("runs", text, line, "a whole number of runs, 1 or more")
                    })?,
            ),
        };
        let targets = match c.get("targets_mm") {
            None => None,
            Some((text, line)) => {
                let values: Option<Vec<Real>> = text
                    .split(',')
                    .map(|v| v.trim().parse::<Real>().ok().filter(|v| v.is_finite()))
                    .map(|v| v.map(|mm| mm * M_PER_MM))
                    .collect();
                Some(values.filter(|v| !v.is_empty()).ok_or_else(|| {
                    wrong(
                        "targets_mm",
                        text,
                        line,
                        "finite numbers separated by commas",
                    )
                })?)
            }
        };
        let compensation = match c.get("compensation") {
            None => None,
            Some((text, _)) if COMPENSATIONS.contains(&text) => Some(text.to_string()),
            Some((text, line)) => {
                return Err(wrong(
                    "compensation",
                    text,
                    line,
                    "none, air, nde or air+nde (what the laser corrected)",
                ));
            }
        };
        let machine = c.get("machine").map(|(text, _)| text.to_string());
        let mut axes = Vec::new();
        for axis in Axis::ALL {
            if let Some(key) = axis_key(axis)
                && let Some(value) = c.number(&key, file)?
            {
                axes.push((axis, value * axis_unit_to_si(axis)));
            }
        }
        let beam_offset = c
            .triple("beam_offset_mm", file)?
            .map(|[x, y, z]| Vector::new(x, y, z) * M_PER_MM);
        let mounting = match c.get("interferometer_on") {
            None => None,
            Some(("workpiece", _)) => Some(Mounting::InterferometerOnWorkpiece),
            Some(("tool", _)) => Some(Mounting::InterferometerOnTool),
            Some((text, line)) => {
                return Err(wrong("interferometer_on", text, line, "workpiece or tool"));
            }
        };
        let zero = match c.get("zero") {
            None => None,
            Some(("once", _)) => Some(Zeroing::Once),
            Some(("each_run", _)) => Some(Zeroing::EachRun),
            Some((text, line)) => return Err(wrong("zero", text, line, "once or each_run")),
        };
        Ok(PositioningConditions {
            test,
            axis,
            runs,
            targets,
            compensation,
            machine,
            axes,
            beam_offset,
            mounting,
            zero,
            not_used: c.unread().into_iter().map(|(key, _)| key).collect(),
        })
    }

    /// What the preamble said of the set-up, for the report (ISO 230-2 §7 asks it to state
    /// the position of the measurement line, the offsets and the compensation): JSON with a
    /// key per condition (null when not said) and one line for people (empty when none).
    pub fn report(&self) -> (serde_json::Value, String) {
        let line: Vec<String> = self
            .axes
            .iter()
            .map(|&(axis, value)| {
                let unit = if axis.is_linear() { " mm" } else { "°" };
                format!(
                    "{} {}{unit}",
                    axis.letter().to_ascii_lowercase(),
                    trimmed(value / axis_unit_to_si(axis), 6)
                )
            })
            .collect();
        let offset = self
            .beam_offset
            .map(|o| o.to_array().map(|v| trimmed(v / M_PER_MM, 6)).join(" "));
        let mounting = self.mounting.map(|m| match m {
            Mounting::InterferometerOnWorkpiece => "workpiece",
            Mounting::InterferometerOnTool => "tool",
        });
        let zero = self.zero.map(|z| match z {
            Zeroing::Once => "once",
            Zeroing::EachRun => "each_run",
        });
        let mut said = Vec::new();
        if let Some(machine) = &self.machine {
            said.push(format!("machine {machine}"));
        }
        if !line.is_empty() {
            said.push(format!("line at {}", line.join(", ")));
        }
        if let Some(offset) = &offset {
            said.push(format!("reflector offset {offset} mm"));
        }
        if let Some(side) = mounting {
            said.push(format!("interferometer on the {side}"));
        }
        if let Some(compensation) = &self.compensation {
            said.push(format!("laser compensation {compensation}"));
        }
        if let Some(zero) = zero {
            said.push(format!("zeroed {}", zero.replace('_', " ")));
        }
        let json = serde_json::json!({
            "test": self.test.map(PositioningTest::name),
            "machine": self.machine,
            "line": line.join(", "),
            "beam_offset_mm": offset,
            "interferometer_on": mounting,
            "compensation": self.compensation,
            "zero": zero,
        });
        let text = if said.is_empty() {
            String::new()
        } else {
            format!("Conditions: {}.\n", said.join(", "))
        };
        (json, text)
    }

    /// The preamble that says these conditions (file units).
    pub fn to_preamble(&self) -> Conditions {
        let mut pairs: Vec<(String, String)> = Vec::new();
        if let Some(test) = self.test {
            pairs.push(("test".into(), test.name().to_string()));
        }
        if let Some(axis) = self.axis {
            pairs.push(("axis".into(), axis.to_string()));
        }
        if let Some(runs) = self.runs {
            pairs.push(("runs".into(), runs.to_string()));
        }
        if let Some(targets) = &self.targets {
            let list: Vec<String> = targets.iter().map(|t| trimmed(t / M_PER_MM, 6)).collect();
            pairs.push(("targets_mm".into(), list.join(", ")));
        }
        if let Some(compensation) = &self.compensation {
            pairs.push(("compensation".into(), compensation.clone()));
        }
        if let Some(machine) = &self.machine {
            pairs.push(("machine".into(), machine.clone()));
        }
        for &(axis, value) in &self.axes {
            if let Some(key) = axis_key(axis) {
                pairs.push((key, trimmed(value / axis_unit_to_si(axis), 9)));
            }
        }
        if let Some(offset) = self.beam_offset {
            let mm = offset.to_array().map(|v| trimmed(v / M_PER_MM, 9));
            pairs.push(("beam_offset_mm".into(), mm.join(" ")));
        }
        if let Some(mounting) = self.mounting {
            let side = match mounting {
                Mounting::InterferometerOnWorkpiece => "workpiece",
                Mounting::InterferometerOnTool => "tool",
            };
            pairs.push(("interferometer_on".into(), side.into()));
        }
        if let Some(zero) = self.zero {
            let when = match zero {
                Zeroing::Once => "once",
                Zeroing::EachRun => "each_run",
            };
            pairs.push(("zero".into(), when.into()));
        }
        Conditions::from_pairs(pairs)
    }

    /// Checks the conditions against the rows of a table (read from `file`, whose preamble
    /// `stated` gave them, with the axis its `axis` column names, if any, the labels of the
    /// runs its rows hold in `runs`, the target of each row in `row_targets` and the lines of
    /// its rows in `lines`).
    pub(crate) fn check(
        &self,
        stated: &Conditions,
        column_axis: Option<Axis>,
        runs: &[String],
        row_targets: &[Real],
        lines: &[Option<u64>],
        file: &str,
    ) -> Result<(), TableError> {
        let line_of = |key: &str| stated.get(key).map(|(_, line)| line);
        if let Some(axis) = column_axis.or(self.axis)
            && self.axes.iter().any(|(a, _)| *a == axis)
        {
            let key = axis_key(axis).expect("a linear axis has a key");
            return Err(TableError::new(
                file,
                line_of(&key),
                format!(
                    "{key}: {axis} is the axis under test; the preamble's axis positions are the other axes'"
                ),
            ));
        }
        if let (Some(said), Some(column)) = (self.axis, column_axis)
            && said != column
        {
            return Err(TableError::new(
                file,
                line_of("axis"),
                format!("axis = {said}, but the rows' axis column says {column}"),
            ));
        }
        if let Some(stated_runs) = self.runs
            && stated_runs != runs.len()
        {
            return Err(TableError::new(
                file,
                line_of("runs"),
                format!(
                    "runs = {stated_runs}, but the rows hold {} run{} ({})",
                    runs.len(),
                    if runs.len() == 1 { "" } else { "s" },
                    runs.join(", ")
                ),
            ));
        }
        if let Some(targets) = &self.targets {
            let near = |a: Real, b: Real| (a - b).abs() <= TARGET_TOLERANCE;
            let stray = row_targets
                .iter()
                .zip(lines)
                .find(|(r, _)| !targets.iter().any(|t| near(*t, **r)));
            if let Some((row_target, line)) = stray {
                return Err(TableError::new(
                    file,
                    *line,
                    format!(
                        "target_mm {} is not one of the preamble's targets_mm (line {})",
                        trimmed(*row_target / M_PER_MM, 6),
                        line_of("targets_mm").unwrap_or_default()
                    ),
                ));
            }
            let unvisited = targets
                .iter()
                .find(|t| !row_targets.iter().any(|r| near(**t, *r)));
            if let Some(target) = unvisited {
                return Err(TableError::new(
                    file,
                    line_of("targets_mm"),
                    format!(
                        "targets_mm: no reading at {} mm",
                        trimmed(target / M_PER_MM, 6)
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// `X`, `Y` or `Z` (either case).
pub(crate) fn parse_axis(text: &str) -> Option<Axis> {
    match text {
        "X" | "x" => Some(Axis::X),
        "Y" | "y" => Some(Axis::Y),
        "Z" | "z" => Some(Axis::Z),
        _ => None,
    }
}
