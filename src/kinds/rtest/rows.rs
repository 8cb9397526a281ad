//! An R-test table in memory ([`RtestTable`]): its rows, one pose of one test each
//! ([`RtestRow`]), and its preamble; read and written in `table.rs`, checked in `angles.rs` and
//! `plausible.rs`.

use crate::io::Conditions;
use crate::machine::Axis;
use crate::math::{Real, Vector};

/// One row: one pose of one test.
#[derive(Clone, Debug, PartialEq)]
pub struct RtestRow {
    /// The test's name.
    pub test: String,
    /// Index of the pose in its test.
    pub point: Option<usize>,
    /// Time since the start of the test (s).
    pub time: Option<Real>,
    /// The controller's rotary angles (rad), A, B, C; `None` for a column the file lacks.
    pub angles: [Option<Real>; 3],
    /// The controller's linear axes (m), when recorded.
    pub linear: Option<Vector>,
    /// Tool relative to the sphere, actual − nominal, machine X, Y, Z (m).
    pub deviation: Vector,
    /// Raw probe readings (m).
    pub probes: Vec<Real>,
}

impl RtestRow {
    /// The angle of a rotary axis (rad), if recorded.
    pub fn angle(&self, axis: Axis) -> Option<Real> {
        match axis {
            Axis::A => self.angles[0],
            Axis::B => self.angles[1],
            Axis::C => self.angles[2],
            _ => None,
        }
    }
}

/// An R-test table: the rows in file order and the preamble.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RtestTable {
    /// The rows.
    pub rows: Vec<RtestRow>,
    /// The preamble (empty for a file without one).
    pub conditions: Conditions,
    /// Columns of the file this reader read past, in header order (no figure depends on them).
    pub columns_not_read: Vec<String>,
}

impl RtestTable {
    /// What the preamble says of the set-up, for the report (checked when the table was
    /// read): JSON (`machine`, `sphere_mm`, `sphere_diameter_mm`, `tip`, `calibration`, `mode`,
    /// `zero`, `frame`, each null when not said, and `preamble_not_used`, the keys no reader
    /// took) and a line for people.
    pub fn setup_report(&self) -> (serde_json::Value, String) {
        let c = &self.conditions;
        let keys = [
            "machine",
            "sphere_mm",
            "sphere_diameter_mm",
            "tip",
            "calibration",
            "mode",
            "zero",
            "frame",
        ];
        let mut json = serde_json::Map::new();
        let mut said = Vec::new();
        for key in keys {
            let value = c.get(key).map(|(v, _)| v.to_string());
            if let Some(v) = &value {
                said.push(match key {
                    "sphere_mm" => format!(
                        "sphere at ({}) mm",
                        v.split_whitespace().collect::<Vec<_>>().join(", ")
                    ),
                    "sphere_diameter_mm" => format!("Ø {v} mm"),
                    _ => format!("{} {v}", key.replace('_', " ")),
                });
            }
            json.insert(key.into(), value.into());
        }
        let not_used: Vec<String> = c.unread().into_iter().map(|(k, _)| k).collect();
        let mut text = if said.is_empty() {
            String::new()
        } else {
            format!("Set-up: {}.\n", said.join(", "))
        };
        text += &crate::io::not_used_line(&not_used);
        json.insert("preamble_not_used".into(), not_used.into());
        (json.into(), text)
    }

    /// The tests in the order they first appear, each with its rows.
    pub fn tests(&self) -> Vec<(&str, Vec<&RtestRow>)> {
        let mut out: Vec<(&str, Vec<&RtestRow>)> = Vec::new();
        for row in &self.rows {
            match out.iter_mut().find(|(name, _)| *name == row.test) {
                Some((_, rows)) => rows.push(row),
                None => out.push((&row.test, vec![row])),
            }
        }
        out
    }
}
