//! The R-test table as readings for the estimators ([`crate::estimate`]): the model of each
//! reading is the twin's own chain, as the nest and its software read it ([`super::run`]).
//!
//! A row holds the tool's displacement relative to the sphere `(dx, dy, dz)` (actual −
//! nominal, as the table's columns), in machine axes, since the test's first pose: the
//! software zeroes the probes there. With `s_i` the sphere
//! centre in the actual nest frame at pose `i` and `R_i` the nominal orientation of the tool
//! in machine axes,
//!
//! ```text
//! reading_i = −R_i · (s_i − c),    c = s_0 + ε_0
//! ```
//!
//! where `c` is the nest-frame reading at the pose where the software zeroed, noise `ε_0`
//! included. `c` is a nuisance of each test (three per test), or of the whole table when the
//! table says `zero = first_pose` (one datum for the sequence), and the zeroing row (reading 0 = prediction
//! `−R_0 (s_0 − c)`) is kept as an observation of it: this is exactly the generalised least
//! squares of the zeroed rows, whose noise is correlated through `ε_0`, with independent rows.
//!
//! **Drift during a test** ([`Setup::drift`]): the pivot (sphere against nest) drifting as the
//! machine warms reads, at a row's time `t` since its test's start, as `D·t/T` added to the
//! reading, with `D` the drift over the test (machine axes) and `T` the test's last time: three
//! nuisances per test (`NAME.drift.x` …, in µm by the test's end). The model is linear in time
//! within a test; a drift before the test started is an offset the test's own zero takes, so a
//! drifting table gets a datum per test even when it says `zero = first_pose`. What anchors `D`
//! is a pose the test reads twice: a circle's end (C 360° is C 0°), a test out and back.
//! [`Drift::Rate`] is the same drift at one rate over the whole table (three nuisances,
//! `drift_per_h.x` …, in µm per hour, entering as rate × the row's time since its test's
//! start): a machine warming steadily through a session of tests, which the tests held out
//! of a fit can check (model selection, [`crate::estimate::discover`]).
//!
//! Simplifications, stated: the conversion of the probe readings is taken as exact (flat tips,
//! calibrated nest): the six-point calibration's gain and direction errors (1e-4–1e-3 of the
//! reading) and the point tips' cross-talk are left in the residuals; a dynamic test's rows
//! are modelled at their commanded poses (the servo lag is not in the model). Each axis's
//! direction of travel at a row is the one it arrived in, by the rule of the simulation
//! ([`super::program::arrival_directions`]): the direction of its last move in the test, and
//! at a test's first row that of its first move; on a dynamic table the commanded motion's,
//! which the actual one follows but for the servo lag at a reversal.

use super::program::{arrival_directions, follow};
use super::table::RtestTable;
use crate::errors::ErrorModel;
use crate::estimate::{Quantity, ReadingModel, Readings, ReadingsError};
use crate::machine::{Axis, AxisValues, Machine, MachineState, Workspace};
use crate::math::{M_PER_MM, Real, Rotation, Vector, rigid_inverse, trimmed};

/// Default standard uncertainty of each displacement component: 0.2 µm, the nest noise of
/// the bundled scenarios and of contact R-tests (wave2-anchors §1.4).
pub const DEFAULT_SIGMA: Real = 0.2e-6;

/// Default standard uncertainty of the sphere position the operator centres the nest on at
/// the first pose (the preset): 0.5 µm in each direction, for the Monte Carlo.
pub const DEFAULT_SETUP_UNCERTAINTY: Real = 0.5e-6;

/// How the set-up enters the estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// Standard uncertainty of each reading component (m).
    pub sigma: Real,
    /// Standard uncertainty of the sphere position (m) as a known set-up quantity.
    pub sphere_uncertainty: Real,
    /// The sphere position is unknown and estimated (ISO's protocol without a preset; the
    /// literature's P1): then it is a nuisance rather than a known set-up quantity.
    pub free_sphere: bool,
    /// The sphere centre (workpiece frame, m) for a table whose preamble does not state it (a
    /// foreign export); when both do, they must agree.
    pub sphere: Option<Vector>,
    /// Whether and how the pivot drifts during the tests (see the module doc); each test is
    /// then its own datum, and the table needs its `time_s`.
    pub drift: Drift,
}

/// How the pivot's drift during the tests enters the model (see the module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Drift {
    /// No drift.
    #[default]
    None,
    /// Each test drifts linearly in time by its own amount: three nuisances per test.
    PerTest,
    /// The pivot drifts at one rate through the whole table: three nuisances (µm per hour).
    Rate,
}

impl Default for Setup {
    fn default() -> Setup {
        Setup {
            sigma: DEFAULT_SIGMA,
            sphere_uncertainty: DEFAULT_SETUP_UNCERTAINTY,
            free_sphere: false,
            sphere: None,
            drift: Drift::None,
        }
    }
}

/// One pose of the model.
#[derive(Clone, Debug)]
struct Row {
    state: MachineState,
    /// Nominal tool orientation in machine axes.
    world_from_tool: Rotation,
    /// Index of its datum (its test, or 0 when the table is one datum).
    test: usize,
    /// Index of its test in the table (for held-out evidence, [`ReadingModel::group`]).
    group: usize,
    /// Its time as a fraction of its test's last time ([`Drift::PerTest`]), or in hours since
    /// its test's start ([`Drift::Rate`]); 0 without drift.
    progress: Real,
}

/// The model of an R-test table.
#[derive(Clone, Debug)]
struct RtestModel {
    sphere: Vector,
    rows: Vec<Row>,
    tests: usize,
    free_sphere: bool,
    /// What the nuisances hold after the zeros: a drift per test, a rate, or nothing.
    drift: Drift,
}

impl RtestModel {
    /// The drift's nuisances after the zeros: none, three per test, or three.
    fn drifts(&self) -> usize {
        match self.drift {
            Drift::None => 0,
            Drift::PerTest => 3 * self.tests,
            Drift::Rate => 3,
        }
    }

    /// Where `row`'s drift (x, y, z) starts among the drift's nuisances, if there is one.
    fn drift_of(&self, row: &Row) -> Option<usize> {
        match self.drift {
            Drift::None => None,
            Drift::PerTest => Some(3 * row.test),
            Drift::Rate => Some(0),
        }
    }
}

impl ReadingModel for RtestModel {
    fn per_row(&self) -> usize {
        3
    }

    fn group(&self, i: usize) -> usize {
        self.rows[i / 3].group
    }

    /// To first order, an error moving the actual tool tip by `δt` relative to the workpiece
    /// (the chain's own Jacobian, workpiece frame) reads `R_w·δt`, `R_w` the nominal rotation
    /// from the workpiece frame to machine axes (`s − c = R_tᵀ(p − t)` with the tip on the
    /// sphere: the error's rotation turns a lever `p − t` of at most
    /// [`MAX_TIP_OFF_SPHERE`] and is left out, 1e-3 of a column at worst and 0 on a table
    /// commanded exactly onto the sphere); a test's zero `c` reads `R_i`, a drift its row's
    /// `progress` along each axis, the sphere's offset `−R_w`.
    fn sensitivities(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        errors: &ErrorModel,
        nuisances: usize,
    ) -> Option<(nalgebra::DMatrix<Real>, nalgebra::DMatrix<Real>)> {
        let n = 3 * self.rows.len();
        let count = errors.coefficient_count();
        let mut of_errors = nalgebra::DMatrix::zeros(n, count);
        let mut of_nuisances = nalgebra::DMatrix::zeros(n, nuisances);
        let mut columns = vec![[0.0; 5]; count];
        let drift_at = 3 * self.tests;
        let sphere_at = drift_at + self.drifts();
        for (i, row) in self.rows.iter().enumerate() {
            errors.jacobian(machine, workspace, &row.state, &mut columns);
            let nominal = workspace.workpiece_from_tool(machine, &row.state.position, None);
            let world_from_workpiece = row.world_from_tool * nominal.matrix3.transpose();
            for (c, column) in columns.iter().enumerate() {
                let read = world_from_workpiece * Vector::new(column[0], column[1], column[2]);
                for (a, value) in read.to_array().into_iter().enumerate() {
                    of_errors[(3 * i + a, c)] = value;
                }
            }
            for a in 0..3 {
                for b in 0..3 {
                    of_nuisances[(3 * i + a, 3 * row.test + b)] = row.world_from_tool.col(b)[a];
                    if self.free_sphere && sphere_at + 3 <= nuisances {
                        of_nuisances[(3 * i + a, sphere_at + b)] = -world_from_workpiece.col(b)[a];
                    }
                }
                if let Some(at) = self.drift_of(row) {
                    of_nuisances[(3 * i + a, drift_at + at + a)] = row.progress;
                }
            }
        }
        Some((of_errors, of_nuisances))
    }

    fn reading_name(&self, i: usize) -> String {
        format!(
            "pose {} in file order (d{})",
            i / 3 + 1,
            ["x", "y", "z"][i % 3]
        )
    }

    fn predict(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        errors: &ErrorModel,
        nuisance: &[Real],
        setup: &[Real],
        out: &mut [Real],
    ) {
        let (offsets, rest) = nuisance.split_at(3 * self.tests);
        let (drifts, rest) = rest.split_at(self.drifts());
        let mut sphere = self.sphere;
        let shift = if self.free_sphere { rest } else { setup };
        if shift.len() == 3 {
            sphere += Vector::new(shift[0], shift[1], shift[2]);
        }
        for (i, row) in self.rows.iter().enumerate() {
            let actual = errors.workpiece_from_tool(machine, workspace, &row.state);
            let s = rigid_inverse(&actual).transform_point3(sphere);
            let c = &offsets[3 * row.test..3 * row.test + 3];
            let mut d = -(row.world_from_tool * (s - Vector::new(c[0], c[1], c[2])));
            if let Some(at) = self.drift_of(row) {
                let drift = &drifts[at..at + 3];
                d += Vector::new(drift[0], drift[1], drift[2]) * row.progress;
            }
            out[3 * i..3 * i + 3].copy_from_slice(&d.to_array());
        }
    }
}

/// How far (m) the table's commanded positions may put the nominal tool tip from the sphere:
/// 0.1 mm. Under tool-centre-point control the controller commands the tip onto the sphere
/// position it was given, so the two differ only by the controller's own kinematic
/// parameters against the model's (a calibrated pivot or axis line: the machine's location
/// errors, tens of µm) and the file's rounding. A sphere typed 0.3 mm off would otherwise be
/// fitted as a 0.3 mm axis offset with a perfect χ².
pub const MAX_TIP_OFF_SPHERE: Real = 1e-4;

/// The smallest constant offset (m) between the commanded tool tip and the stated sphere that
/// is refused: 2 µm, twice the rounding of a position exported to the µm.
pub const MIN_CONSTANT_OFFSET: Real = 2e-6;

/// The refusal when the commanded positions put the nominal tool tip at one point that is not
/// the stated sphere: the same offset at every pose (its mean `m` more than
/// [`MIN_CONSTANT_OFFSET`] and more than three times the largest row's departure from it).
/// A controller whose kinematic parameters differ from the model's puts the tip off the sphere
/// by an amount that turns with the axes; a constant offset is the sphere position itself
/// mistyped (in the preamble or `--rtest-sphere-mm`), which the fit would otherwise read as
/// location errors of the rotary axes.
fn constant_offset(offsets: &[Vector], sphere: Vector) -> Option<String> {
    if offsets.len() < 3 {
        return None;
    }
    let mean = offsets.iter().copied().sum::<Vector>() / offsets.len() as Real;
    let scatter = offsets
        .iter()
        .map(|o| (*o - mean).length())
        .fold(0.0, Real::max);
    (mean.length() > MIN_CONSTANT_OFFSET.max(3.0 * scatter)).then(|| {
        let mm = |v: Vector| (v / M_PER_MM).to_array().map(|c| trimmed(c, 4)).join(" ");
        format!(
            "the commanded positions put the nominal tool tip at one point, {} mm, {} µm from the stated sphere at {} mm at every pose (within {} µm): under tool-centre-point control the tip is commanded onto the sphere, so the sphere position (preamble or --rtest-sphere-mm) is mistyped; the fit would read the difference as axis location errors",
            mm(sphere + mean),
            trimmed(mean.length() * 1e6, 3),
            mm(sphere),
            trimmed(scatter * 1e6, 3)
        )
    })
}

/// The readings of an R-test table measured on `machine` (`file` names it in messages).
pub fn readings(
    table: &RtestTable,
    file: &str,
    machine: &Machine,
    setup: Setup,
) -> Result<Readings, ReadingsError> {
    let fail = |message: String| ReadingsError::new(file, message);
    let stated = table.conditions.get("sphere_mm").is_some();
    let sphere = match (stated, setup.sphere) {
        (false, Some(given)) => given,
        (true, Some(given)) => {
            let stated = sphere_of(table, file)?;
            if (stated - given).length() > 1e-9 {
                return Err(fail(format!(
                    "the preamble puts the sphere at {:?} mm, --rtest-sphere-mm at {:?} mm",
                    (stated / M_PER_MM).to_array(),
                    (given / M_PER_MM).to_array()
                )));
            }
            stated
        }
        _ => sphere_of(table, file)?,
    };
    let mut workspace = Workspace::new(machine);
    let shared = setup.drift == Drift::None
        && table.conditions.get("zero").map(|(z, _)| z) == Some(super::Zero::FirstPose.name());
    let tests: Vec<&str> = table.tests().iter().map(|(name, _)| *name).collect();
    let names: Vec<&str> = if shared { vec!["datum"] } else { tests.clone() };
    let mut rows = Vec::with_capacity(table.rows.len());
    let mut measured = Vec::with_capacity(3 * table.rows.len());
    // The nominal tip's offset from the sphere at each row with commanded positions.
    let mut offsets: Vec<Vector> = Vec::new();
    for (line, row) in table.rows.iter().enumerate() {
        let mut angles = AxisValues::ZERO;
        for axis in [Axis::A, Axis::B, Axis::C] {
            if let Some(angle) = row.angle(axis) {
                if !machine.has_axis(axis) {
                    return Err(fail(format!(
                        "row {}: an angle of {axis}, which machine \"{}\" does not have",
                        line + 1,
                        machine.name()
                    )));
                }
                angles[axis] = angle;
            }
        }
        let command = match row.linear {
            Some(linear) => {
                let mut command = angles;
                command[Axis::X] = linear.x;
                command[Axis::Y] = linear.y;
                command[Axis::Z] = linear.z;
                command
            }
            None => follow(machine, &mut workspace, &angles, sphere)
                .map_err(|e| fail(format!("row {}: {e}", line + 1)))?,
        };
        if let Some(outside) = machine.outside_travel(&command) {
            return Err(fail(format!(
                "row {}: {outside}: a table of another machine, or a column in another unit",
                line + 1
            )));
        }
        let tip = workspace
            .workpiece_from_tool(machine, &command, None)
            .translation;
        // The table's own commanded positions must keep the nominal tool tip on the sphere
        // (tool-centre-point control): a sphere position mistyped, or angles in radians in a
        // `_deg` column, put it far off ([`MAX_TIP_OFF_SPHERE`]).
        if row.linear.is_some() {
            offsets.push(tip - sphere);
        }
        if row.linear.is_some() && (tip - sphere).length() > MAX_TIP_OFF_SPHERE {
            let mm = |v: Vector| (v / M_PER_MM).to_array().map(|c| trimmed(c, 3)).join(" ");
            return Err(fail(format!(
                "row {}: the commanded positions put the nominal tool tip at {} mm, {} mm from the sphere at {} mm: an R-test keeps the tip on the sphere, so the sphere position (preamble or --rtest-sphere-mm) or the angles' unit is wrong",
                line + 1,
                mm(tip),
                trimmed((tip - sphere).length() / M_PER_MM, 3),
                mm(sphere)
            )));
        }
        let world_from_tool = workspace.world_from_ends().0.matrix3;
        let group = tests
            .iter()
            .position(|n| *n == row.test)
            .expect("every row's test is listed");
        rows.push(Row {
            state: MachineState::at(command),
            world_from_tool,
            test: if shared { 0 } else { group },
            group,
            progress: 0.0,
        });
        measured.extend_from_slice(&row.deviation.to_array());
    }
    if rows.is_empty() {
        return Err(fail("no rows".into()));
    }
    // The directions of travel, test by test in the table's order, by the rule the
    // simulation follows (a lost motion of an axis then reads as it was simulated).
    for (name, _) in table.tests() {
        let members: Vec<usize> = (0..rows.len())
            .filter(|&i| table.rows[i].test == name)
            .collect();
        let commands: Vec<AxisValues> = members.iter().map(|&i| rows[i].state.position).collect();
        for (&i, direction) in members.iter().zip(arrival_directions(&commands)) {
            rows[i].state.direction = direction;
        }
    }
    if let Some(message) = constant_offset(&offsets, sphere) {
        return Err(fail(message));
    }
    if setup.drift != Drift::None {
        drift_progress(table, &mut rows, &names, setup.drift).map_err(fail)?;
    }
    let mut nuisance = Vec::new();
    let kinds: &[&str] = if setup.drift == Drift::PerTest {
        &["zero", "drift"]
    } else {
        &["zero"]
    };
    let quantity = |name: String| Quantity {
        name,
        translation: true,
        start: 0.0,
        uncertainty: 0.0,
    };
    for kind in kinds {
        for name in &names {
            for c in ["x", "y", "z"] {
                nuisance.push(quantity(format!("{name}.{kind}.{c}")));
            }
        }
    }
    if setup.drift == Drift::Rate {
        for c in ["x", "y", "z"] {
            nuisance.push(quantity(format!("drift_per_h.{c}")));
        }
    }
    let sphere_quantities = ["x", "y", "z"].map(|c| Quantity {
        name: format!("sphere.offset.{c}"),
        translation: true,
        start: 0.0,
        uncertainty: if setup.free_sphere {
            0.0
        } else {
            setup.sphere_uncertainty
        },
    });
    let (setup_quantities, nuisance) = if setup.free_sphere {
        nuisance.extend(sphere_quantities);
        (Vec::new(), nuisance)
    } else {
        (sphere_quantities.to_vec(), nuisance)
    };
    let tests = names.len();
    Ok(Readings {
        source: file.to_string(),
        kind: "rtest",
        machine: table.conditions.get("machine").map(|(m, _)| m.to_string()),
        sigma: vec![setup.sigma; measured.len()],
        measured,
        nuisance,
        setup: setup_quantities,
        model: Box::new(RtestModel {
            sphere,
            rows,
            tests,
            free_sphere: setup.free_sphere,
            drift: setup.drift,
        }),
    })
}

/// Each row's time as a fraction of its test's last time ([`Drift::PerTest`]) or in hours
/// ([`Drift::Rate`]), for the drift (rows in the table's order, `names` the tests); why not,
/// when a row has no time or a test no time after its start.
fn drift_progress(
    table: &RtestTable,
    rows: &mut [Row],
    names: &[&str],
    drift: Drift,
) -> Result<(), String> {
    let mut last = vec![0.0; names.len()];
    for (i, row) in table.rows.iter().enumerate() {
        let time = row.time.filter(|t| t.is_finite() && *t >= 0.0).ok_or_else(|| {
            format!(
                "row {}: a drift in time needs each row's time since its test's start (the time_s column)",
                i + 1
            )
        })?;
        last[rows[i].test] = Real::max(last[rows[i].test], time);
    }
    if let Some(k) = last.iter().position(|t| *t <= 0.0) {
        return Err(format!(
            "test \"{}\": every row at time 0, so no drift in time can be told from its zero",
            names[k]
        ));
    }
    for (row, line) in rows.iter_mut().zip(&table.rows) {
        let time = line.time.unwrap_or(0.0);
        row.progress = match drift {
            Drift::Rate => time / 3600.0,
            _ => time / last[row.test],
        };
    }
    Ok(())
}

/// Planning figures of an R-test (minutes; [`planned`]): the nest in the spindle, the sphere
/// on the table and the nest's calibration, and each static pose read (the move, the dwell and
/// the reading: 15 s). Typical of a static R-test as ISO 10791-6 describes it, not measured
/// here: they rank candidate tests against each other.
pub const PLANNED_SETUP_MINUTES: Real = 20.0;
/// See [`PLANNED_SETUP_MINUTES`].
pub const PLANNED_MINUTES_PER_POSE: Real = 0.25;

/// A planned R-test (no measurements): the poses of `tests` on `machine` with the sphere at
/// `sphere` (workpiece frame, m), zeroed as `zero` says, for identifiability and test design.
pub fn planned(
    machine: &Machine,
    tests: &[super::KTest],
    sphere: Vector,
    zero: super::Zero,
    setup: Setup,
) -> Result<Readings, ReadingsError> {
    let fail = |message: String| ReadingsError::new("planned R-test", message);
    if tests.is_empty() {
        return Err(fail("no test".into()));
    }
    let setup = Setup {
        sphere: None,
        ..setup
    };
    let mut workspace = Workspace::new(machine);
    let mut table = RtestTable {
        rows: Vec::new(),
        conditions: crate::io::Conditions::from_pairs([
            (
                "sphere_mm",
                format!(
                    "{} {} {}",
                    sphere.x / M_PER_MM,
                    sphere.y / M_PER_MM,
                    sphere.z / M_PER_MM
                ),
            ),
            ("zero", zero.name().to_string()),
        ]),
        columns_not_read: Vec::new(),
    };
    for test in tests {
        let poses = super::program::static_poses(machine, &mut workspace, test, sphere, 0.0)
            .map_err(|e| fail(format!("{}: {e}", test.name)))?;
        for (index, pose) in poses.iter().enumerate() {
            let mut angles = [None; 3];
            for info in machine.rotary_axes() {
                angles[info.axis.coordinate()] = Some(pose.command[info.axis]);
            }
            table.rows.push(super::RtestRow {
                test: test.name.clone(),
                point: Some(index),
                time: None,
                angles,
                linear: Some(Vector::new(
                    pose.command[Axis::X],
                    pose.command[Axis::Y],
                    pose.command[Axis::Z],
                )),
                deviation: Vector::ZERO,
                probes: Vec::new(),
            });
        }
    }
    let mut readings = readings(&table, "planned R-test", machine, setup)?;
    readings.measured.clear();
    Ok(readings)
}

/// The sphere position the table's preamble states (`sphere_mm = x y z`, workpiece frame).
pub fn sphere_of(table: &RtestTable, file: &str) -> Result<Vector, ReadingsError> {
    match table.conditions.triple("sphere_mm", file) {
        Ok(Some(mm)) => Ok(Vector::from_array(mm) * M_PER_MM),
        Ok(None) => Err(ReadingsError::new(
            file,
            "the preamble does not state the sphere position (`# sphere_mm = x y z`, workpiece frame): the model of the readings needs it (give it with --rtest-sphere-mm X,Y,Z)",
        )),
        Err(e) => Err(ReadingsError::new(file, e.to_string())),
    }
}

/// Candidate K-tests for test design on `machine` (static, 13 poses each): for each angle of
/// the tilting axis (A or B) from −90° to 90° in 15° steps within its travel, a full turn of
/// the turning axis (C); and sweeps of the tilting axis over its travel (at most ±90°) at the
/// turning axis at 0°, 90°, 180° and 270° (and over narrower spans, ±60°, ±45°, ±30°, in case
/// the linear axes cannot follow to the ends). With one rotary axis: a full turn of it. The
/// caller drops those the linear axes cannot follow ([`planned`] refuses them).
pub fn candidates(machine: &Machine) -> Vec<super::KTest> {
    let rotary: Vec<&crate::machine::AxisInfo> = machine.rotary_axes().collect();
    let turning = rotary
        .iter()
        .find(|i| i.is_continuous() || i.axis == Axis::C)
        .or(rotary.last())
        .map(|i| i.axis);
    let tilting = rotary
        .iter()
        .find(|i| Some(i.axis) != turning)
        .map(|i| (i.axis, i.limits));
    let mut out = Vec::new();
    let test = |name: String, from: &[(Axis, Real)], to: &[(Axis, Real)]| {
        let mut a = AxisValues::ZERO;
        for (axis, deg) in from {
            a[*axis] = deg.to_radians();
        }
        let mut b = a;
        for (axis, deg) in to {
            b[*axis] = deg.to_radians();
        }
        super::KTest {
            name,
            from: a,
            to: b,
            points: 13,
            back: false,
        }
    };
    let Some(turning) = turning else {
        return out;
    };
    let Some((tilt, limits)) = tilting else {
        out.push(test(
            format!("{turning} turn"),
            &[(turning, 0.0)],
            &[(turning, 360.0)],
        ));
        return out;
    };
    let (lower, upper) = limits.map_or((-90.0, 90.0), |(l, u)| {
        (l.to_degrees().max(-90.0), u.to_degrees().min(90.0))
    });
    for step in -6..=6 {
        let angle = 15.0 * step as Real;
        if angle >= lower - 1e-9 && angle <= upper + 1e-9 {
            out.push(test(
                format!("{turning} turn at {tilt} = {angle}°"),
                &[(tilt, angle), (turning, 0.0)],
                &[(turning, 360.0)],
            ));
        }
    }
    // Sweeps over the travel and over narrower spans (the linear axes may not follow the
    // sphere to the ends of the travel).
    for c in [0.0, 90.0, 180.0, 270.0] {
        let mut spans: Vec<(Real, Real)> = Vec::new();
        for half in [90.0, 60.0, 45.0, 30.0] {
            let span = (lower.max(-half), upper.min(half));
            if span.1 - span.0 >= 30.0 && !spans.contains(&span) {
                spans.push(span);
            }
        }
        for (from, to) in spans {
            out.push(test(
                format!("{tilt} sweep {from}°..{to}° at {turning} = {c}°"),
                &[(tilt, from), (turning, c)],
                &[(tilt, to)],
            ));
        }
    }
    out
}
