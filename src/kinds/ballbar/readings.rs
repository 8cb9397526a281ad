//! The ball-bar table as readings for the estimators ([`crate::estimate`]): the model of each
//! reading is the twin's own chain, as the bar reads it ([`super::instrument`]).
//!
//! The tool ball sits at the tool tip, the centre ball in its cup on the table, set where the
//! machine put the tool tip when commanded to the circle centre `s_c` (as with a setting
//! ball). With `p(s)` the actual tool tip in the workpiece frame (`workpiece_from_tool`), `L`
//! the nominal radius (the bar's length) and `s_i` the machine on the circle at the reading's
//! angle `θ_i`,
//!
//! ```text
//! deviation_i = |p(s_i) − c| − L + r
//! c           = p(s_c) − (e_p·u_p + e_q·u_q + e_n·n)
//! ```
//!
//! - `s_i`: the plane's first axis at `centre + L·cos θ_i`, the second at `centre + L·sin θ_i`,
//!   the other axes at the centre; each axis's direction of travel that of the programmed
//!   motion in the reading's sense (for the first axis the sign of `−σ·sin θ`, for the second
//!   of `σ·cos θ`, σ = +1 counter-clockwise; at an axis's reversal point the direction it
//!   arrived with), so the reversal terms switch where the axes reverse. The axes off the
//!   plane and the centre's state keep the positive direction, as the instrument has them.
//! - `e_p`, `e_q` (nuisances `centre.<p>`, `centre.<q>`, start 0): the centre of the machine's
//!   circle relative to the centre ball along the plane's axes, the "centre offset" of an
//!   ISO 230-4 analysis ([`super::iso230_4`]), which adds `e_p·cos θ + e_q·sin θ` to the
//!   readings to first order. It is the opposite of the instrument's set-up offset
//!   (`setup_offset_um` of `truth.json`).
//! - `e_n` (set-up quantity `centre.<n>`, stated 0, [`Setup::normal_uncertainty`]): the same
//!   along the plane's normal; it changes the readings by `e_n²/(2L)` only.
//! - `r` (nuisance `radius`, start 0): the bar's calibration error (reported − true length).
//!   The table does not say the bar was calibrated, and the simulated bar has a calibration
//!   error of its own, so the absolute radius is a nuisance: a scale error common to both axes
//!   of the plane then shows only against other tables (the scale mismatch does show).
//! - `u_p`, `u_q`, `n`: the workpiece-frame directions in which the plane's axes move the tool
//!   (nominal chain at the centre) and their normal.
//!
//! The angle column is taken as the programmed angle of the reading. Not in the model, stated:
//! the servo. At the table's feed the position loops shrink the circle by `L·(ω/K_v)²/2`
//! (taken by `r`), unequal lags make the servo-mismatch ellipse, axes reverse a lag after the
//! command, and reversal spikes and vibration add their own shapes: they stay in the residuals
//! (the reached angle's shift by the servo lag is a known open point). No ball sphericity, bar
//! sag or thermal growth of the bar, as the instrument has none.

use super::table::BallbarTable;
use crate::errors::ErrorModel;
use crate::estimate::{Quantity, ReadingModel, Readings, ReadingsError};
use crate::machine::{Axis, AxisValues, Direction, Machine, MachineState, Workspace};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, Vector, trimmed};

/// Default standard uncertainty of a reading: the bundled scenarios' bar, 0.1 µm of noise and
/// a 0.1 µm resolution (√(0.1² + 0.1²/12) µm = 0.104 µm), about what a ball-bar's
/// transducer gives.
pub const DEFAULT_SIGMA: Real = 0.104_083e-6;

/// Default standard uncertainty of the centre ball along the plane's normal: 10 µm, how well
/// a cup is set on a setting ball. It acts at second order only (`e²/(2L)`: 0.3 nm on a
/// 150 mm bar).
pub const DEFAULT_NORMAL_UNCERTAINTY: Real = 10e-6;

/// How far a stated centre may differ from one given in [`Setup::centre`] and still be it
/// (m or rad): the 1 nm of the preamble's digits.
const SAME_POSITION: Real = 1e-9;

/// What the model needs beyond the table, and how well the readings are known. The plane and
/// the radius are the table's conditions (its preamble, or the flags a caller fills them
/// from, as `mtwin analyze ballbar` does).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// Standard uncertainty of each reading (m).
    pub sigma: Real,
    /// The machine's axis positions at the circle centre (SI: the linear axes where the centre
    /// ball was set, the rotary axes held), for a table whose preamble does not say
    /// (`centre_mm`); when both say, they must agree.
    pub centre: Option<AxisValues>,
    /// Standard uncertainty of the centre ball along the plane's normal (m).
    pub normal_uncertainty: Real,
}

impl Default for Setup {
    fn default() -> Setup {
        Setup {
            sigma: DEFAULT_SIGMA,
            centre: None,
            normal_uncertainty: DEFAULT_NORMAL_UNCERTAINTY,
        }
    }
}

/// The model of a ball-bar table.
#[derive(Clone, Debug)]
struct BallbarModel {
    /// The nominal radius (m).
    radius: Real,
    /// The machine at the circle centre.
    centre: MachineState,
    /// The directions of the plane's axes and the normal, workpiece frame.
    frame: [Vector; 3],
    /// The machine at each reading.
    states: Vec<MachineState>,
}

impl ReadingModel for BallbarModel {
    fn predict(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        errors: &ErrorModel,
        nuisance: &[Real],
        setup: &[Real],
        out: &mut [Real],
    ) {
        let at = |k: usize, values: &[Real]| values.get(k).copied().unwrap_or(0.0);
        let offset = self.frame[0] * at(0, nuisance)
            + self.frame[1] * at(1, nuisance)
            + self.frame[2] * at(0, setup);
        let calibration = at(2, nuisance);
        let centre = errors
            .workpiece_from_tool(machine, workspace, &self.centre)
            .translation
            - offset;
        for (value, state) in out.iter_mut().zip(&self.states) {
            let tool = errors
                .workpiece_from_tool(machine, workspace, state)
                .translation;
            *value = (tool - centre).length() - self.radius + calibration;
        }
    }
}

/// The readings of a ball-bar table measured on `machine` (`file` names it in messages).
pub fn readings(
    table: &BallbarTable,
    file: &str,
    machine: &Machine,
    setup: &Setup,
) -> Result<Readings, ReadingsError> {
    let fail = |message: String| ReadingsError::new(file, message);
    let conditions = &table.conditions;
    let plane = conditions.plane.ok_or_else(|| {
        fail("the table does not say its plane (`# plane = XY`, or --plane): the model of the readings needs it".into())
    })?;
    let radius = conditions.radius.ok_or_else(|| {
        fail("the table does not say its radius (`# radius_mm = …`, or --radius-mm): the model of the readings needs it".into())
    })?;
    if !(setup.sigma.is_finite() && setup.sigma > 0.0) {
        return Err(fail(format!(
            "the readings' standard uncertainty must be a positive number of µm, got {}",
            setup.sigma / M_PER_UM
        )));
    }
    let (p, q, normal) = (plane.first(), plane.second(), plane.normal());
    for axis in [p, q] {
        if !machine.has_axis(axis) {
            return Err(fail(format!(
                "the {plane} plane needs axis {axis}, which machine \"{}\" does not have",
                machine.name()
            )));
        }
    }
    let centre = match (setup.centre, conditions.centre) {
        (Some(given), Some(stated)) => {
            if let Some(axis) = Axis::ALL
                .into_iter()
                .find(|a| (given[*a] - stated[*a]).abs() > SAME_POSITION)
            {
                let (unit, scale) = if axis.is_linear() {
                    ("mm", M_PER_MM)
                } else {
                    ("deg", RAD_PER_DEG)
                };
                return Err(fail(format!(
                    "the centre's {axis} = {} {unit} given, but the preamble says {} {unit}",
                    trimmed(given[axis] / scale, 6),
                    trimmed(stated[axis] / scale, 6)
                )));
            }
            stated
        }
        (given, stated) => given.or(stated).ok_or_else(|| {
            fail("the preamble does not state the circle centre (`# centre_mm = x y z`, machine axes): the model of the readings needs it".into())
        })?,
    };
    if let Some(axis) = Axis::ALL
        .into_iter()
        .find(|a| centre[*a] != 0.0 && !machine.has_axis(*a))
    {
        return Err(fail(format!(
            "the centre has a position of {axis}, which machine \"{}\" does not have",
            machine.name()
        )));
    }

    // The directions in which the plane's axes move the tool, workpiece frame (nominal).
    let mut workspace = Workspace::new(machine);
    let mut nominal = |position: &AxisValues| {
        workspace
            .workpiece_from_tool(machine, position, None)
            .translation
    };
    let at_centre = nominal(&centre);
    let mut direction = |axis: Axis| {
        let mut moved = centre;
        moved[axis] += radius;
        ((nominal(&moved) - at_centre) / radius).normalize()
    };
    let (u_p, u_q) = (direction(p), direction(q));
    let frame = [u_p, u_q, u_p.cross(u_q).normalize()];

    let mut states = Vec::with_capacity(table.readings.len());
    let mut measured = Vec::with_capacity(table.readings.len());
    for reading in &table.readings {
        let (sin, cos) = reading.angle.sin_cos();
        let mut state = MachineState::at(centre);
        state.position[p] += radius * cos;
        state.position[q] += radius * sin;
        let sigma = reading.sense.sign();
        // At an axis's reversal point (its speed 0 within rounding) the direction it arrived
        // with: toward the extreme it is at.
        let travel = |velocity: Real, extreme: Real| {
            let sign = if velocity.abs() > 1e-12 {
                velocity
            } else {
                extreme
            };
            if sign >= 0.0 {
                Direction::Positive
            } else {
                Direction::Negative
            }
        };
        state.direction[p.index()] = travel(-sigma * sin, cos);
        state.direction[q.index()] = travel(sigma * cos, sin);
        states.push(state);
        measured.push(reading.deviation);
    }
    if measured.is_empty() {
        return Err(fail("no readings".into()));
    }
    let letter = |a: Axis| a.letter().to_ascii_lowercase();
    // Named after the plane, so that several tables' set-ups read apart in a report.
    let plane = format!("{}{}", p.letter(), q.letter());
    let nuisance = vec![
        Quantity {
            name: format!("{plane}.centre.{}", letter(p)),
            translation: true,
            start: 0.0,
            uncertainty: 0.0,
        },
        Quantity {
            name: format!("{plane}.centre.{}", letter(q)),
            translation: true,
            start: 0.0,
            uncertainty: 0.0,
        },
        Quantity {
            name: format!("{plane}.radius"),
            translation: true,
            start: 0.0,
            uncertainty: 0.0,
        },
    ];
    let setup_quantities = vec![Quantity {
        name: format!("{plane}.centre.{}", letter(normal)),
        translation: true,
        start: 0.0,
        uncertainty: setup.normal_uncertainty,
    }];
    Ok(Readings {
        source: file.to_string(),
        kind: "ballbar",
        machine: table.machine.clone(),
        sigma: vec![setup.sigma; measured.len()],
        measured,
        nuisance,
        setup: setup_quantities,
        model: Box::new(BallbarModel {
            radius,
            centre: MachineState::at(centre),
            frame,
            states,
        }),
    })
}

/// Planning figures of a ball-bar test (minutes; [`planned`]): setting the centre ball's cup
/// on a setting ball and the bar in place, and one plane's test (a circle each way with its
/// arcs in and out). Typical of a QC20-W test as its maker describes it (a ten-minute test), not
/// measured here: they rank candidate tests against each other.
pub const PLANNED_SETUP_MINUTES: Real = 10.0;
/// See [`PLANNED_SETUP_MINUTES`].
pub const PLANNED_RUN_MINUTES: Real = 10.0;

/// A planned ball-bar test (no measurements), for identifiability and test design: a circle
/// of `radius` (m) in `plane` about `centre` (the machine's axes, SI), each sense read at
/// `readings_per_turn` equally spaced angles from 0°.
pub fn planned(
    machine: &Machine,
    plane: crate::machine::Plane,
    centre: AxisValues,
    radius: Real,
    readings_per_turn: usize,
    sigma: Real,
) -> Result<Readings, ReadingsError> {
    use super::table::{BallbarReading, Sense, TestConditions};
    let mut table = BallbarTable {
        readings: Vec::new(),
        conditions: TestConditions {
            plane: Some(plane),
            radius: Some(radius),
            centre: Some(centre),
            ..TestConditions::default()
        },
        machine: None,
        columns_not_read: Vec::new(),
    };
    for sense in [Sense::Ccw, Sense::Cw] {
        for k in 0..readings_per_turn {
            table.readings.push(BallbarReading {
                sense,
                angle: std::f64::consts::TAU * k as Real / readings_per_turn as Real,
                deviation: 0.0,
                time: None,
            });
        }
    }
    let setup = Setup {
        sigma,
        ..Setup::default()
    };
    let mut readings = readings(&table, "planned ball-bar test", machine, &setup)?;
    readings.measured.clear();
    Ok(readings)
}
