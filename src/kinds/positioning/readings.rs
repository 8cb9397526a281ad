//! The positioning table as readings for the estimators ([`crate::estimate`]): the model of
//! each reading is the twin's own chain, as the laser reads it ([`super::laser`]).
//!
//! The interferometer counts the displacement of the reflector, at `b` from the tool tip
//! (tool frame: the Abbe offset), along the beam `u` (the axis's direction in the workpiece
//! frame) since its zero, and the table holds reached − target. With `T_i` the actual
//! `workpiece_from_tool` at reading `i` and `z` the reading where the laser was zeroed,
//!
//! ```text
//! deviation_i = t_z + travel_i − t_i
//! travel_i   = u · (T_i·b − T_z·b)                  interferometer on the workpiece
//!            = −u · (T_i⁻¹·T_z·b − b)               interferometer on the tool (reverse set-up)
//! ```
//!
//! `t_i` is the reading's target, plus an offset `c` of the zero's group — the whole table
//! (`zero = once`) or each run (`zero = each_run`) — fitted as a nuisance: the reading the laser
//! was zeroed on is an assumption (a test that starts with the minus pass may have been
//! datumed at the near end before it), and with `c` free any reading of the group serves as
//! `z`: a datum elsewhere only moves every reading of the group by one constant. The machine at reading `i` is the axis under test at its
//! target, its direction of travel that of the approach (`+`: positive, so reversal terms
//! take the approach's sign), the other axes where the table's preamble says they stood (the
//! line of the test: `y_mm`, `z_mm`, … or [`Setup::axes`]), their direction positive (they
//! did not move). The zero is where the instrument set it ([`super::setup::Zeroing`]): the
//! table's first reading (`zero = once`, ISO 230-2 practice, the default for a table that does
//! not say) or each run's first reading (`zero = each_run`). In an ISO 230-2 or ISO 230-3 test
//! every run starts at the same target in the same direction, so for a geometric model the two
//! are the same. What no laser sees — a translation common to every reading of a group, the
//! constant term of `EXX` — is `c`'s.
//!
//! Set-up quantities (for the Monte Carlo): the reflector offset `b` (`reflector.x`, `.y`,
//! `.z`, tool frame), stated with [`Setup::beam_offset_uncertainty`] each. The line of the test
//! is the controller's own axis positions, taken as exact.
//!
//! Not in the model, stated: the laser's scale — refractive index of the air (its sensors'
//! offsets, the dead path when the air changes) and material (NDE) compensation — which
//! multiplies every reading by `1 + κ` with `κ` of a few 0.1 ppm and is read as the axis's scale
//! error (`EXX`'s slope) by any estimator; the beam's misalignment (cosine error, `(1 − cos m)`
//! of the travel: 5 nm per metre at 100 µrad); and the thermal drift (the estimator is
//! geometric: a drifting test shows in the residuals, run by run). Noise and resolution are
//! the readings' `sigma`.

use super::setup::{Mounting, Zeroing};
use super::table::{Approach, PositioningTable};
use crate::errors::ErrorModel;
use crate::estimate::{Quantity, ReadingModel, Readings, ReadingsError};
use crate::machine::{Axis, AxisValues, Direction, Machine, MachineState, Workspace};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, Vector, rigid_inverse, trimmed};

/// Default standard uncertainty of a reading: 0.02 µm, the laser noise of the bundled ISO 230-2
/// scenario (20 nm) with its 1 nm resolution (√(20² + 1²/12) nm): a workshop laser's short-term
/// noise with air turbulence. The machine's own non-repeatability (on top of it in a real test)
/// is for the caller to add by overriding it.
pub const DEFAULT_SIGMA: Real = 0.02e-6;

/// Default standard uncertainty of each component of the reflector offset (the Abbe offset,
/// tool frame): 1 mm, what a rule across the optics gives.
pub const DEFAULT_BEAM_OFFSET_UNCERTAINTY: Real = 1e-3;

/// How far a stated axis position may differ from one given in [`Setup::axes`] and still be
/// it (m or rad): the 1 nm of the preamble's digits.
const SAME_POSITION: Real = 1e-9;

/// What the model needs beyond the table, and how well the readings are known. A fact the
/// table's preamble states and one given here must agree (as the command line's flags do).
#[derive(Clone, Debug, PartialEq)]
pub struct Setup {
    /// Standard uncertainty of each reading (m).
    pub sigma: Real,
    /// Where the machine's other axes stood (SI), for a table whose preamble does not say:
    /// every linear axis but the one under test is needed; a rotary axis not given is at 0.
    pub axes: Vec<(Axis, Real)>,
    /// The reflector relative to the tool tip, tool frame (m), for a table whose preamble does
    /// not say; neither: at the tool tip.
    pub beam_offset: Option<Vector>,
    /// Which side carries the interferometer, for a table whose preamble does not say;
    /// neither: the workpiece.
    pub mounting: Option<Mounting>,
    /// When the laser was zeroed, for a table whose preamble does not say; neither: once, at
    /// the table's first reading.
    pub zero: Option<Zeroing>,
    /// Standard uncertainty of each component of the reflector offset (m).
    pub beam_offset_uncertainty: Real,
}

impl Default for Setup {
    fn default() -> Setup {
        Setup {
            sigma: DEFAULT_SIGMA,
            axes: Vec::new(),
            beam_offset: None,
            mounting: None,
            zero: None,
            beam_offset_uncertainty: DEFAULT_BEAM_OFFSET_UNCERTAINTY,
        }
    }
}

/// The model of a positioning table.
#[derive(Clone, Debug)]
struct LaserModel {
    /// The beam direction in the workpiece frame.
    beam: Vector,
    /// The reflector relative to the tool tip, tool frame, as stated (m).
    beam_offset: Vector,
    mounting: Mounting,
    /// The machine at each reading.
    states: Vec<MachineState>,
    /// The target of each reading (m).
    targets: Vec<Real>,
    /// The reading each reading's travel is counted from (the first of its zero group).
    zero_of: Vec<usize>,
    /// The zero group (nuisance offset) of each reading.
    group_of: Vec<usize>,
}

impl ReadingModel for LaserModel {
    fn predict(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        errors: &ErrorModel,
        nuisance: &[Real],
        setup: &[Real],
        out: &mut [Real],
    ) {
        let mut b = self.beam_offset;
        if setup.len() == 3 {
            b += Vector::new(setup[0], setup[1], setup[2]);
        }
        let poses: Vec<_> = self
            .states
            .iter()
            .map(|state| errors.workpiece_from_tool(machine, workspace, state))
            .collect();
        for (i, value) in out.iter_mut().enumerate() {
            let z = self.zero_of[i];
            let travel = match self.mounting {
                Mounting::InterferometerOnWorkpiece => self
                    .beam
                    .dot(poses[i].transform_point3(b) - poses[z].transform_point3(b)),
                Mounting::InterferometerOnTool => {
                    let origin = poses[z].transform_point3(b);
                    -self
                        .beam
                        .dot(rigid_inverse(&poses[i]).transform_point3(origin) - b)
                }
            };
            *value = self.targets[z] + travel - self.targets[i] + nuisance[self.group_of[i]];
        }
    }
}

/// The readings of a positioning table measured on `machine` (`file` names it in messages):
/// one set for the whole table, so that the runs share the set-up quantities.
pub fn readings(
    table: &PositioningTable,
    file: &str,
    machine: &Machine,
    setup: &Setup,
) -> Result<Readings, ReadingsError> {
    let fail = |message: String| ReadingsError::new(file, message);
    let conditions = &table.conditions;
    let axis = table.axis.ok_or_else(|| {
        fail("the table does not name its axis (an `axis` column or `# axis = X` in the preamble): the model of the readings needs it".into())
    })?;
    if !machine.has_axis(axis) {
        return Err(fail(format!(
            "the table measures {axis}, which machine \"{}\" does not have",
            machine.name()
        )));
    }
    if !(setup.sigma.is_finite() && setup.sigma > 0.0) {
        return Err(fail(format!(
            "the readings' standard uncertainty must be a positive number of µm, got {}",
            setup.sigma / M_PER_UM
        )));
    }

    // The line of the test: every other axis, from the preamble and the set-up.
    let mut line = AxisValues::ZERO;
    let mut stated = [false; 7];
    let unit = |a: Axis| {
        if a.is_linear() {
            ("mm", M_PER_MM)
        } else {
            ("deg", RAD_PER_DEG)
        }
    };
    for &(other, value) in &setup.axes {
        if other == axis {
            return Err(fail(format!(
                "{axis} is the axis under test: its positions are the targets, not a line position"
            )));
        }
        if !machine.has_axis(other) {
            return Err(fail(format!(
                "a position of {other} is given, which machine \"{}\" does not have",
                machine.name()
            )));
        }
        line[other] = value;
        stated[other.index()] = true;
    }
    for &(other, value) in &conditions.axes {
        if !machine.has_axis(other) {
            return Err(fail(format!(
                "the preamble gives a position of {other}, which machine \"{}\" does not have",
                machine.name()
            )));
        }
        if stated[other.index()] && (line[other] - value).abs() > SAME_POSITION {
            let (name, scale) = unit(other);
            return Err(fail(format!(
                "{other} = {} {name} given, but the preamble says {} {name}",
                trimmed(line[other] / scale, 6),
                trimmed(value / scale, 6)
            )));
        }
        line[other] = value;
        stated[other.index()] = true;
    }
    let missing: Vec<String> = machine
        .axes()
        .iter()
        .map(|info| info.axis)
        .filter(|a| a.is_linear() && *a != axis && !stated[a.index()])
        .map(|a| format!("`# {}_mm = …`", a.letter().to_ascii_lowercase()))
        .collect();
    if !missing.is_empty() {
        return Err(fail(format!(
            "the preamble does not say where the other axes stood ({}): the model of the readings needs the line of the test",
            missing.join(", ")
        )));
    }

    let agree = |what: &str, given: Option<String>, said: Option<String>| match (given, said) {
        (Some(g), Some(s)) if g != s => {
            Err(fail(format!("{what} {g} given, but the preamble says {s}")))
        }
        _ => Ok(()),
    };
    let mm3 = |v: Vector| {
        let mm = v.to_array().map(|c| trimmed(c / M_PER_MM, 6));
        format!("{} mm", mm.join(" "))
    };
    agree(
        "beam offset",
        setup.beam_offset.map(mm3),
        conditions.beam_offset.map(mm3),
    )?;
    agree(
        "interferometer on",
        setup.mounting.map(mounting_name),
        conditions.mounting.map(mounting_name),
    )?;
    agree(
        "zero",
        setup.zero.map(zero_name),
        conditions.zero.map(zero_name),
    )?;
    let beam_offset = conditions
        .beam_offset
        .or(setup.beam_offset)
        .unwrap_or(Vector::ZERO);
    let mounting = conditions
        .mounting
        .or(setup.mounting)
        .unwrap_or(Mounting::InterferometerOnWorkpiece);
    let zero = conditions.zero.or(setup.zero).unwrap_or(Zeroing::Once);

    let mut states = Vec::with_capacity(table.readings.len());
    let mut targets = Vec::with_capacity(table.readings.len());
    let mut zero_of = Vec::with_capacity(table.readings.len());
    let mut group_of = Vec::with_capacity(table.readings.len());
    let mut measured = Vec::with_capacity(table.readings.len());
    // The reading the laser was zeroed on: the first of the test (Zeroing::Once) or of each run,
    // by `time_min` when every reading has one (an export may list the rows in another order),
    // else in file order.
    let timed = table.readings.iter().all(|r| r.time.is_some());
    let earlier = |a: usize, b: usize| {
        let t = |i: usize| table.readings[i].time.unwrap_or(0.0);
        if timed && t(b) < t(a) { b } else { a }
    };
    let mut first_of_run: Vec<Option<usize>> = vec![None; table.runs.len().max(1)];
    for (i, reading) in table.readings.iter().enumerate() {
        if let Some(first) = first_of_run.get_mut(reading.run) {
            *first = Some(first.map_or(i, |f| earlier(f, i)));
        }
    }
    let first_of_test = (0..table.readings.len()).reduce(earlier).unwrap_or(0);
    for (i, reading) in table.readings.iter().enumerate() {
        let mut state = MachineState::at(line);
        state.position[axis] = reading.target;
        state.direction[axis.index()] = match reading.approach {
            Approach::Up => Direction::Positive,
            Approach::Down => Direction::Negative,
        };
        let run_zero = first_of_run
            .get(reading.run)
            .copied()
            .flatten()
            .ok_or_else(|| {
                fail(format!(
                    "reading {}: run index {} beyond the table's runs",
                    i + 1,
                    reading.run
                ))
            })?;
        // A commanded position outside the machine's travel is a table of another machine or
        // in another unit: no reading of this machine was taken there.
        if let Some(outside) = machine.outside_travel(&state.position) {
            return Err(fail(format!(
                "reading {}: {outside}: a table of another machine, or positions in another unit",
                i + 1
            )));
        }
        zero_of.push(match zero {
            Zeroing::Once => first_of_test,
            Zeroing::EachRun => run_zero,
        });
        group_of.push(match zero {
            Zeroing::Once => 0,
            Zeroing::EachRun => reading.run,
        });
        states.push(state);
        targets.push(reading.target);
        measured.push(reading.deviation);
    }
    if measured.is_empty() {
        return Err(fail("no readings".into()));
    }
    let reflector = ["x", "y", "z"].map(|c| Quantity {
        name: format!("reflector.{c}"),
        translation: true,
        start: 0.0,
        uncertainty: setup.beam_offset_uncertainty,
    });
    Ok(Readings {
        source: file.to_string(),
        kind: "positioning",
        machine: conditions.machine.clone(),
        sigma: vec![setup.sigma; measured.len()],
        measured,
        nuisance: zero_offsets(table, zero),
        setup: reflector.to_vec(),
        model: Box::new(LaserModel {
            beam: axis.unit(),
            beam_offset,
            mounting,
            states,
            targets,
            zero_of,
            group_of,
        }),
    })
}

/// The nuisance offset of each zero group: `laser.zero` for a table zeroed once, `laser.zero
/// run R` for each run of one zeroed at every run.
fn zero_offsets(table: &PositioningTable, zero: Zeroing) -> Vec<Quantity> {
    let quantity = |name: String| Quantity {
        name,
        translation: true,
        start: 0.0,
        uncertainty: 0.0,
    };
    match zero {
        Zeroing::Once => vec![quantity("laser.zero".into())],
        Zeroing::EachRun => (0..table.runs.len().max(1))
            .map(|r| {
                let label = table.runs.get(r).map_or("1", String::as_str);
                quantity(format!("laser.zero run {label}"))
            })
            .collect(),
    }
}

/// `workpiece` or `tool`, as the preamble says it.
fn mounting_name(mounting: Mounting) -> String {
    match mounting {
        Mounting::InterferometerOnWorkpiece => "workpiece",
        Mounting::InterferometerOnTool => "tool",
    }
    .into()
}

/// `once` or `each_run`, as the preamble says it.
fn zero_name(zero: Zeroing) -> String {
    match zero {
        Zeroing::Once => "once",
        Zeroing::EachRun => "each_run",
    }
    .into()
}

/// Planning figures of a laser line (minutes; [`planned`]): setting up and aligning the
/// interferometer and the optics on a new line, and the ISO 230-2 run itself (five
/// bidirectional runs over about eleven targets with their dwells). Typical of a workshop
/// laser calibration (Renishaw XL-80 and the like), not measured here: they rank candidate
/// tests against each other, and a user with other figures reads the ranking accordingly.
pub const PLANNED_SETUP_MINUTES: Real = 30.0;
/// See [`PLANNED_SETUP_MINUTES`].
pub const PLANNED_RUN_MINUTES: Real = 30.0;

/// A planned laser line (no measurements), for identifiability and test design: `axis` over
/// `targets` (m), `runs` bidirectional runs (each target approached up, then down), the other
/// axes at `line` (SI), the reflector at `beam_offset` from the tool tip (tool frame, m), the
/// interferometer on the workpiece and zeroed once, as ISO 230-2 and [`readings`] have it.
pub fn planned(
    machine: &Machine,
    axis: Axis,
    targets: &[Real],
    runs: usize,
    line: &AxisValues,
    beam_offset: Vector,
    sigma: Real,
) -> Result<Readings, ReadingsError> {
    let mut table = PositioningTable {
        axis: Some(axis),
        runs: (1..=runs).map(|r| r.to_string()).collect(),
        sensors: Vec::new(),
        has_direction: true,
        readings: Vec::new(),
        conditions: Default::default(),
        columns_not_read: Vec::new(),
    };
    table.conditions.axes = machine
        .axes()
        .iter()
        .map(|info| info.axis)
        .filter(|&a| a != axis && a != Axis::S)
        .map(|a| (a, line[a]))
        .collect();
    table.conditions.beam_offset = Some(beam_offset);
    for run in 0..runs {
        for approach in [Approach::Up, Approach::Down] {
            let order: Vec<&Real> = match approach {
                Approach::Up => targets.iter().collect(),
                Approach::Down => targets.iter().rev().collect(),
            };
            for &target in order {
                table.readings.push(super::table::PositioningReading {
                    target,
                    deviation: 0.0,
                    approach,
                    run,
                    time: None,
                    temperatures: Vec::new(),
                });
            }
        }
    }
    let setup = Setup {
        sigma,
        ..Setup::default()
    };
    let mut readings = readings(&table, "planned laser line", machine, &setup)?;
    readings.measured.clear();
    Ok(readings)
}
