//! The `probe` table (every touch) and the `spheres` table (a fitted sphere per feature),
//! simulated or exported from a controller, in any column order. Lengths in mm, angles in
//! degrees, form in µm; positions and approach vectors are in machine axis coordinates (X, Y,
//! Z: what the controller latches and how it moved), not the workpiece frame.
//!
//! `probe` columns:
//!
//! | column | required | meaning |
//! |---|---|---|
//! | `cycle` | yes | the cycle's number (1, 2, …) |
//! | `kind` | yes | `sphere`, `ring`, `plate` or `mesh` |
//! | `feature` | yes | the feature's number within the cycle (a rotary position, a plate ball) |
//! | `point` | yes | the point's number within the feature |
//! | `a_deg`, `b_deg`, `c_deg` | no | the rotary angles held |
//! | `x_mm`, `y_mm`, `z_mm` | yes | the latched axis positions (the stylus-ball centre) |
//! | `i`, `j`, `k` | yes | the unit approach vector (axis space) |
//! | `cal_diameter_mm` | no | the artefact's calibrated diameter (sphere, ball, ring; empty for none) |
//! | `cal_x_mm`, `cal_y_mm`, `cal_z_mm` | no | a plate ball's calibrated centre in the plate's frame (all three or none) |
//!
//! `spheres` columns: `cycle`, `kind`, `feature`, the rotary angles, `x_mm`, `y_mm`, `z_mm` (the
//! fitted centre), `radius_mm` (the artefact's radius as measured: the fit of the stylus
//! centres minus the stylus radius), `form_um` (range of the residuals), `points`, and the
//! optional calibration columns as above.
//!
//! Preamble (`# key = value`): `stylus_radius_mm` (the stylus radius the controller used;
//! needed to evaluate a `probe` table), `feed_mm_per_min`, `machine`.

use super::cycles::CycleKind;
use crate::io::{Conditions, TableError, csv_reader, finite_number, read_file, read_header, row};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, Vector, fixed, trimmed};
use std::path::Path;

/// What a table's preamble says (SI; each absent when the file does not say), and the columns
/// its reader read past.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProbeConditions {
    /// The stylus radius the controller used (m); 0 for points already compensated to the
    /// surface.
    pub stylus_radius: Option<Real>,
    /// The approach feed (m/s).
    pub feed: Option<Real>,
    /// The machine's name.
    pub machine: Option<String>,
    /// Columns of the file the reader read past, in header order (no figure depends on them).
    pub columns_not_read: Vec<String>,
}

impl ProbeConditions {
    fn from_preamble(c: &Conditions, file: &str) -> Result<ProbeConditions, TableError> {
        let positive = |key: &str| -> Result<Option<Real>, TableError> {
            match c.number(key, file)? {
                Some(v) if v <= 0.0 => Err(TableError::new(
                    file,
                    c.get(key).map(|(_, l)| l),
                    format!("{key} = {v}: expected a positive number"),
                )),
                other => Ok(other),
            }
        };
        // A stylus radius of 0 says the points are already compensated to the surface.
        let stylus_radius = match c.number("stylus_radius_mm", file)? {
            Some(r) if r < 0.0 => {
                return Err(TableError::new(
                    file,
                    c.get("stylus_radius_mm").map(|(_, l)| l),
                    format!(
                        "stylus_radius_mm = {r}: expected a radius ≥ 0 (0 for points already compensated)"
                    ),
                ));
            }
            r => r,
        };
        Ok(ProbeConditions {
            stylus_radius: stylus_radius.map(|r| r * M_PER_MM),
            feed: positive("feed_mm_per_min")?.map(|f| f * M_PER_MM / 60.0),
            machine: c.get("machine").map(|(m, _)| m.to_string()),
            columns_not_read: Vec::new(),
        })
    }

    fn to_preamble(&self) -> Conditions {
        let mut pairs: Vec<(&str, String)> = Vec::new();
        if let Some(m) = &self.machine {
            pairs.push(("machine", m.clone()));
        }
        if let Some(r) = self.stylus_radius {
            pairs.push(("stylus_radius_mm", trimmed(r / M_PER_MM, 9)));
        }
        if let Some(f) = self.feed {
            pairs.push(("feed_mm_per_min", trimmed(f / M_PER_MM * 60.0, 6)));
        }
        Conditions::from_pairs(pairs)
    }
}

/// Where a row sits: its cycle, kind, feature and rotary angles, and the artefact's
/// calibration when the row carries it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowKey {
    /// The cycle's number (from 1).
    pub cycle: usize,
    /// The cycle's kind.
    pub kind: CycleKind,
    /// The feature's number within the cycle (from 1).
    pub feature: usize,
    /// The rotary angles A, B, C (rad), those the table gives.
    pub rotary: [Option<Real>; 3],
    /// The artefact's calibrated diameter (m).
    pub calibrated_diameter: Option<Real>,
    /// A plate ball's calibrated centre in the plate's frame (m).
    pub calibrated_centre: Option<Vector>,
}

/// One touch as the controller latched it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeTouch {
    /// Cycle, feature, angles, calibration.
    pub key: RowKey,
    /// The point's number within the feature (from 1).
    pub point: usize,
    /// The latched axis positions X, Y, Z (m).
    pub position: Vector,
    /// The unit approach vector (axis space).
    pub approach: Vector,
}

/// A `probe` table.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProbeTable {
    /// The touches in file order.
    pub touches: Vec<ProbeTouch>,
    /// The preamble's conditions.
    pub conditions: ProbeConditions,
}

/// One fitted sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereRow {
    /// Cycle, feature, angles, calibration.
    pub key: RowKey,
    /// The fitted centre (axis coordinates, m).
    pub centre: Vector,
    /// The artefact's radius as measured (m).
    pub radius: Real,
    /// The range of the fit's residuals (m).
    pub form: Real,
    /// The number of points.
    pub points: usize,
}

/// A `spheres` table.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpheresTable {
    /// The spheres in file order.
    pub spheres: Vec<SphereRow>,
    /// The preamble's conditions.
    pub conditions: ProbeConditions,
}

const ROTARY: [&str; 3] = ["a_deg", "b_deg", "c_deg"];
const CALIBRATION: [&str; 4] = ["cal_diameter_mm", "cal_x_mm", "cal_y_mm", "cal_z_mm"];
const PROBE_REQUIRED: [&str; 10] = [
    "cycle", "kind", "feature", "point", "x_mm", "y_mm", "z_mm", "i", "j", "k",
];
const SPHERES_REQUIRED: [&str; 9] = [
    "cycle",
    "kind",
    "feature",
    "x_mm",
    "y_mm",
    "z_mm",
    "radius_mm",
    "form_um",
    "points",
];

/// The columns of a header, checked against the required and optional names.
struct Columns {
    header: csv::StringRecord,
    not_read: Vec<String>,
}

impl Columns {
    fn check(
        header: csv::StringRecord,
        line: u64,
        required: &[&str],
        file: &str,
    ) -> Result<Columns, TableError> {
        let known: Vec<&str> = required
            .iter()
            .copied()
            .chain(ROTARY)
            .chain(CALIBRATION)
            .collect();
        let not_read = crate::io::read_past(
            header.iter().filter(|name| !known.contains(name)),
            |name| crate::io::looks_like(name, &known),
            &format!(
                "{}, and optionally {} and {}",
                required.join(", "),
                ROTARY.join(", "),
                CALIBRATION.join(", ")
            ),
            line,
            file,
        )?;
        for name in required {
            if !header.iter().any(|h| h == *name) {
                return Err(TableError::new(
                    file,
                    Some(line),
                    format!(
                        "missing column `{name}` (required: {})",
                        required.join(", ")
                    ),
                ));
            }
        }
        let centre = CALIBRATION[1..]
            .iter()
            .filter(|c| header.iter().any(|h| h == **c));
        if !matches!(centre.count(), 0 | 3) {
            return Err(TableError::new(
                file,
                Some(line),
                "cal_x_mm, cal_y_mm and cal_z_mm come together: give all three or none".into(),
            ));
        }
        Ok(Columns { header, not_read })
    }

    fn index(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }
}

/// A reader of one row's cells.
struct Cells<'a> {
    record: &'a csv::StringRecord,
    columns: &'a Columns,
    file: &'a str,
}

impl Cells<'_> {
    fn line(&self) -> Option<u64> {
        self.record.position().map(|p| p.line())
    }

    fn number(&self, name: &str) -> Result<Real, TableError> {
        let index = self.columns.index(name).unwrap_or_default();
        finite_number(self.record, index, name, self.file)
    }

    /// An optional column's number; an empty cell is none.
    fn optional(&self, name: &str) -> Result<Option<Real>, TableError> {
        match self.columns.index(name) {
            Some(index) if !self.record[index].is_empty() => {
                finite_number(self.record, index, name, self.file).map(Some)
            }
            _ => Ok(None),
        }
    }

    fn count(&self, name: &str) -> Result<usize, TableError> {
        let index = self.columns.index(name).unwrap_or_default();
        let text = &self.record[index];
        match text.parse::<usize>() {
            Ok(n) if n >= 1 => Ok(n),
            _ => Err(TableError::new(
                self.file,
                self.line(),
                format!("column `{name}`: expected a whole number ≥ 1, found \"{text}\""),
            )),
        }
    }

    fn vector(&self, names: [&str; 3], scale: Real) -> Result<Vector, TableError> {
        Ok(Vector::new(
            self.number(names[0])?,
            self.number(names[1])?,
            self.number(names[2])?,
        ) * scale)
    }

    fn key(&self) -> Result<RowKey, TableError> {
        let index = self.columns.index("kind").unwrap_or_default();
        let text = &self.record[index];
        let kind = CycleKind::from_name(&text.to_ascii_lowercase()).ok_or_else(|| {
            TableError::new(
                self.file,
                self.line(),
                format!("column `kind`: expected sphere, ring, plate or mesh, found \"{text}\""),
            )
        })?;
        let mut rotary = [None; 3];
        for (value, name) in rotary.iter_mut().zip(ROTARY) {
            *value = self.optional(name)?.map(|v| v * RAD_PER_DEG);
        }
        let calibrated_diameter = match self.optional("cal_diameter_mm")? {
            Some(d) if d <= 0.0 => {
                return Err(TableError::new(
                    self.file,
                    self.line(),
                    format!("column `cal_diameter_mm`: {d} is not a positive diameter"),
                ));
            }
            d => d.map(|d| d * M_PER_MM),
        };
        let centre = [
            self.optional("cal_x_mm")?,
            self.optional("cal_y_mm")?,
            self.optional("cal_z_mm")?,
        ];
        let calibrated_centre = match centre {
            [Some(x), Some(y), Some(z)] => Some(Vector::new(x, y, z) * M_PER_MM),
            [None, None, None] => None,
            _ => {
                return Err(TableError::new(
                    self.file,
                    self.line(),
                    "cal_x_mm, cal_y_mm and cal_z_mm: give all three or leave all three empty"
                        .into(),
                ));
            }
        };
        Ok(RowKey {
            cycle: self.count("cycle")?,
            kind,
            feature: self.count("feature")?,
            rotary,
            calibrated_diameter,
            calibrated_centre,
        })
    }
}

/// Reads the preamble, header and rows of a table, calling `each` on every row.
fn read_rows(
    bytes: &[u8],
    file: &str,
    required: &[&str],
    mut each: impl FnMut(&Cells<'_>) -> Result<(), TableError>,
) -> Result<ProbeConditions, TableError> {
    let mut conditions = ProbeConditions::from_preamble(&Conditions::parse(bytes, file)?, file)?;
    let mut reader = csv_reader(bytes);
    let (header, line) = read_header(&mut reader, file)?;
    let columns = Columns::check(header, line, required, file)?;
    conditions.columns_not_read.clone_from(&columns.not_read);
    let mut rows = 0;
    for record in reader.records() {
        let record = row(record, bytes, file)?;
        each(&Cells {
            record: &record,
            columns: &columns,
            file,
        })?;
        rows += 1;
    }
    if rows == 0 {
        return Err(TableError::new(
            file,
            None,
            "no rows: expected one row after the header per touch or sphere".into(),
        ));
    }
    Ok(conditions)
}

impl ProbeTable {
    /// Reads a `probe` table file.
    pub fn read(path: impl AsRef<Path>) -> Result<ProbeTable, TableError> {
        let (bytes, file) = read_file(path.as_ref())?;
        ProbeTable::parse(&bytes, &file)
    }

    /// Reads a `probe` table from bytes; `file` names it in messages. An approach vector must
    /// be a unit vector to 1e-3 (it is normalised).
    pub fn parse(bytes: &[u8], file: &str) -> Result<ProbeTable, TableError> {
        let mut touches = Vec::new();
        let conditions = read_rows(bytes, file, &PROBE_REQUIRED, |cells| {
            let approach = cells.vector(["i", "j", "k"], 1.0)?;
            if (approach.length() - 1.0).abs() > 1e-3 {
                return Err(TableError::new(
                    file,
                    cells.line(),
                    format!(
                        "columns `i`, `j`, `k`: ({}, {}, {}) is not a unit approach vector",
                        approach.x, approach.y, approach.z
                    ),
                ));
            }
            touches.push(ProbeTouch {
                key: cells.key()?,
                point: cells.count("point")?,
                position: cells.vector(["x_mm", "y_mm", "z_mm"], M_PER_MM)?,
                approach: approach.normalize(),
            });
            Ok(())
        })?;
        Ok(ProbeTable {
            touches,
            conditions,
        })
    }

    /// Writes the table: positions to 1 nm, angles to 1 µ°, approach vectors to 1e-9.
    pub fn write_csv(&self, out: impl std::io::Write) -> csv::Result<()> {
        let keys: Vec<RowKey> = self.touches.iter().map(|t| t.key).collect();
        let mut header = vec!["cycle", "kind", "feature", "point"];
        let layout = Layout::of(&keys);
        header.extend(layout.rotary_names());
        header.extend(["x_mm", "y_mm", "z_mm", "i", "j", "k"]);
        header.extend(layout.calibration_names());
        write_table(
            out,
            &self.conditions,
            "mtwin probe table (every touch)",
            &header,
            |w| {
                for t in &self.touches {
                    let mut record = vec![
                        t.key.cycle.to_string(),
                        t.key.kind.name().to_string(),
                        t.key.feature.to_string(),
                        t.point.to_string(),
                    ];
                    record.extend(layout.rotary_cells(&t.key));
                    record.extend(millimetres(t.position));
                    record.extend(t.approach.to_array().map(|v| fixed(v, 9)));
                    record.extend(layout.calibration_cells(&t.key));
                    w.write_record(&record)?;
                }
                Ok(())
            },
        )
    }
}

impl SpheresTable {
    /// A sphere row that repeats another's fitted centre and radius exactly
    /// ([`crate::io::plausible::copied_block`]): the same sphere counted twice.
    pub fn copied_sphere(&self) -> Option<String> {
        use crate::io::plausible::{Block, copied_block, copy_sentence};
        let blocks: Vec<Block> = self
            .spheres
            .iter()
            .map(|s| Block {
                label: format!("cycle {} feature {}", s.key.cycle, s.key.feature),
                readings: vec![s.centre.x, s.centre.y, s.centre.z, s.radius],
            })
            .collect();
        copied_block(&blocks).map(|pair| copy_sentence(&blocks, pair))
    }

    /// Reads a `spheres` table file.
    pub fn read(path: impl AsRef<Path>) -> Result<SpheresTable, TableError> {
        let (bytes, file) = read_file(path.as_ref())?;
        SpheresTable::parse(&bytes, &file)
    }

    /// Reads a `spheres` table from bytes; `file` names it in messages.
    pub fn parse(bytes: &[u8], file: &str) -> Result<SpheresTable, TableError> {
        let mut spheres = Vec::new();
        let conditions = read_rows(bytes, file, &SPHERES_REQUIRED, |cells| {
            let radius = cells.number("radius_mm")?;
            let form = cells.number("form_um")?;
            if radius <= 0.0 || form < 0.0 {
                return Err(TableError::new(
                    file,
                    cells.line(),
                    format!(
                        "radius_mm = {radius}, form_um = {form}: expected a positive radius and a form ≥ 0"
                    ),
                ));
            }
            spheres.push(SphereRow {
                key: cells.key()?,
                centre: cells.vector(["x_mm", "y_mm", "z_mm"], M_PER_MM)?,
                radius: radius * M_PER_MM,
                form: form * M_PER_UM,
                points: cells.count("points")?,
            });
            Ok(())
        })?;
        Ok(SpheresTable {
            spheres,
            conditions,
        })
    }

    /// Writes the table: centres and radii to 1 nm, form to 1 pm.
    pub fn write_csv(&self, out: impl std::io::Write) -> csv::Result<()> {
        let keys: Vec<RowKey> = self.spheres.iter().map(|s| s.key).collect();
        let layout = Layout::of(&keys);
        let mut header = vec!["cycle", "kind", "feature"];
        header.extend(layout.rotary_names());
        header.extend(["x_mm", "y_mm", "z_mm", "radius_mm", "form_um", "points"]);
        header.extend(layout.calibration_names());
        write_table(
            out,
            &self.conditions,
            "mtwin spheres table (a sphere fit per feature)",
            &header,
            |w| {
                for s in &self.spheres {
                    let mut record = vec![
                        s.key.cycle.to_string(),
                        s.key.kind.name().to_string(),
                        s.key.feature.to_string(),
                    ];
                    record.extend(layout.rotary_cells(&s.key));
                    record.extend(millimetres(s.centre));
                    record.push(fixed(s.radius / M_PER_MM, 6));
                    record.push(fixed(s.form / M_PER_UM, 6));
                    record.push(s.points.to_string());
                    record.extend(layout.calibration_cells(&s.key));
                    w.write_record(&record)?;
                }
                Ok(())
            },
        )
    }
}

/// Which optional columns a table writes: a rotary column when any row has that angle, the
/// calibration columns when any row has them.
struct Layout {
    rotary: [bool; 3],
    diameter: bool,
    centre: bool,
}

impl Layout {
    fn of(keys: &[RowKey]) -> Layout {
        let mut rotary = [false; 3];
        for key in keys {
            for (seen, angle) in rotary.iter_mut().zip(key.rotary) {
                *seen |= angle.is_some();
            }
        }
        Layout {
            rotary,
            diameter: keys.iter().any(|k| k.calibrated_diameter.is_some()),
            centre: keys.iter().any(|k| k.calibrated_centre.is_some()),
        }
    }

    fn rotary_names(&self) -> Vec<&'static str> {
        ROTARY
            .iter()
            .zip(self.rotary)
            .filter(|(_, on)| *on)
            .map(|(n, _)| *n)
            .collect()
    }

    fn calibration_names(&self) -> Vec<&'static str> {
        let mut names = Vec::new();
        if self.diameter {
            names.push(CALIBRATION[0]);
        }
        if self.centre {
            names.extend(&CALIBRATION[1..]);
        }
        names
    }

    fn rotary_cells(&self, key: &RowKey) -> Vec<String> {
        key.rotary
            .iter()
            .zip(self.rotary)
            .filter(|(_, on)| *on)
            .map(|(a, _)| a.map_or_else(String::new, |a| fixed(a / RAD_PER_DEG, 6)))
            .collect()
    }

    fn calibration_cells(&self, key: &RowKey) -> Vec<String> {
        let mut cells = Vec::new();
        if self.diameter {
            cells.push(
                key.calibrated_diameter
                    .map_or_else(String::new, |d| fixed(d / M_PER_MM, 6)),
            );
        }
        if self.centre {
            match key.calibrated_centre {
                Some(c) => cells.extend(millimetres(c)),
                None => cells.extend([String::new(), String::new(), String::new()]),
            }
        }
        cells
    }
}

fn millimetres(v: Vector) -> [String; 3] {
    (v / M_PER_MM).to_array().map(|x| fixed(x, 6))
}

fn write_table(
    mut out: impl std::io::Write,
    conditions: &ProbeConditions,
    title: &str,
    header: &[&str],
    rows: impl FnOnce(&mut csv::Writer<&mut dyn std::io::Write>) -> csv::Result<()>,
) -> csv::Result<()> {
    let preamble = conditions.to_preamble();
    if !preamble.is_empty() {
        out.write_all(preamble.to_preamble(title).as_bytes())?;
    }
    let out: &mut dyn std::io::Write = &mut out;
    let mut writer = csv::Writer::from_writer(out);
    writer.write_record(header)?;
    rows(&mut writer)?;
    writer.flush()?;
    Ok(())
}
