//! Machines: a URDF tree turned into an immutable, validated [`Machine`] with a reusable
//! [`Workspace`] for kinematics (the model/data split of Pinocchio).
//!
//! # Conventions
//!
//! - The tree has one root (the bed) and two branches: one ends in the link `tool` (the tool
//!   centre point, z axis along the tool axis pointing from the tip into the spindle), the other
//!   in the link `workpiece` (the workpiece/table reference). The quantity everything is about is
//!   [`Machine::workpiece_from_tool`].
//! - Moving joints are named after their ISO axis letter: prismatic `X`, `Y`, `Z`; revolute or
//!   continuous `A`, `B`, `C`; the spindle `S` (continuous, on the tool branch).
//! - A joint moves along (or about) the x axis of its joint frame for `X`/`A`, y for `Y`/`B`,
//!   z for `Z`/`C`/`S`. ISO 841: a positive command moves the *tool relative to the workpiece*
//!   in the positive direction, so a joint on the tool branch has axis `+x`/`+y`/`+z` and a joint
//!   on the workpiece branch (which moves the table the other way) has `-x`/`-y`/`-z`.
//! - Axis values are SI: m for `X`, `Y`, `Z`; rad for `A`, `B`, `C`, `S`.
//!
//! Supported configurations: three linear axes `X`, `Y`, `Z`, with either no rotary axis or two
//! of `A`, `B`, `C` (table-table, head-table or head-head 5-axis), plus the spindle `S`.

mod body;
mod inverse;
mod kinematics;
mod plane;
mod trig;
mod urdf;

pub use body::{Body, Shape, Visual};
pub use inverse::{InverseKinematicsError, TiltBranch, ToolTarget};
pub use kinematics::Workspace;
pub(crate) use kinematics::{AxisLine, JointRotation, MotionKind, then_motion};
#[cfg(test)]
pub(crate) use kinematics::{axis_angle, plain_workpiece_from_tool, random_position};
pub use plane::Plane;
pub use urdf::{LARGEST_MACHINE, LARGEST_TURN, MachineError, MachineErrorKind};

use crate::math::{Pose, Real, Vector};
use std::fmt;
use std::ops::{Index, IndexMut};

/// An ISO 841 axis letter (and the spindle `S`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Axis {
    /// Linear X.
    X,
    /// Linear Y.
    Y,
    /// Linear Z.
    Z,
    /// Rotary about X.
    A,
    /// Rotary about Y.
    B,
    /// Rotary about Z.
    C,
    /// The spindle (rotary about the tool axis).
    S,
}

impl Axis {
    /// All axes in ISO order (also the storage order of [`AxisValues`]).
    pub const ALL: [Axis; 7] = [
        Axis::X,
        Axis::Y,
        Axis::Z,
        Axis::A,
        Axis::B,
        Axis::C,
        Axis::S,
    ];

    /// The axis with this letter.
    pub fn from_letter(letter: char) -> Option<Axis> {
        Axis::ALL.into_iter().find(|axis| axis.letter() == letter)
    }

    /// The ISO letter.
    pub fn letter(self) -> char {
        match self {
            Axis::X => 'X',
            Axis::Y => 'Y',
            Axis::Z => 'Z',
            Axis::A => 'A',
            Axis::B => 'B',
            Axis::C => 'C',
            Axis::S => 'S',
        }
    }

    /// Storage index in [`AxisValues`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// Whether the axis translates (X, Y, Z) rather than rotates.
    pub fn is_linear(self) -> bool {
        matches!(self, Axis::X | Axis::Y | Axis::Z)
    }

    /// Whether it is a rotary feed axis (A, B, C); the spindle is not.
    pub fn is_rotary(self) -> bool {
        matches!(self, Axis::A | Axis::B | Axis::C)
    }

    /// The coordinate direction (0 = x, 1 = y, 2 = z) the axis moves along or about.
    pub fn coordinate(self) -> usize {
        match self {
            Axis::X | Axis::A => 0,
            Axis::Y | Axis::B => 1,
            Axis::Z | Axis::C | Axis::S => 2,
        }
    }

    /// The unit vector of [`Axis::coordinate`].
    pub fn unit(self) -> Vector {
        Vector::AXES[self.coordinate()]
    }
}

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.letter())
    }
}

/// One value per axis letter (SI: m or rad), whatever axes the machine has; the values of axes
/// a machine lacks are ignored.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AxisValues(pub [Real; 7]);

impl AxisValues {
    /// All axes at zero.
    pub const ZERO: AxisValues = AxisValues([0.0; 7]);

    /// These values with `axis` set to `value`.
    pub fn with(mut self, axis: Axis, value: Real) -> AxisValues {
        self[axis] = value;
        self
    }

    /// Linear axes from millimetres, rotary axes from degrees.
    pub fn from_file_units(values: &[(Axis, Real)]) -> AxisValues {
        let mut out = AxisValues::ZERO;
        for &(axis, value) in values {
            out[axis] = value * axis_unit_to_si(axis);
        }
        out
    }
}

/// The factor from file units (mm for linear axes, degrees for rotary ones) to SI.
pub fn axis_unit_to_si(axis: Axis) -> Real {
    if axis.is_linear() {
        crate::math::M_PER_MM
    } else {
        crate::math::RAD_PER_DEG
    }
}

impl Index<Axis> for AxisValues {
    type Output = Real;
    fn index(&self, axis: Axis) -> &Real {
        &self.0[axis.index()]
    }
}

impl IndexMut<Axis> for AxisValues {
    fn index_mut(&mut self, axis: Axis) -> &mut Real {
        &mut self.0[axis.index()]
    }
}

/// Direction of travel of an axis, which direction-dependent errors (lost motion) depend on.
/// An axis at rest keeps the direction of its last move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Direction {
    /// Last moved towards larger values.
    #[default]
    Positive,
    /// Last moved towards smaller values.
    Negative,
}

impl Direction {
    /// +1 or −1.
    pub fn sign(self) -> Real {
        match self {
            Direction::Positive => 1.0,
            Direction::Negative => -1.0,
        }
    }
}

/// What the error model needs to know of the machine at one instant: axis positions (SI) and
/// each axis's direction of travel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MachineState {
    /// Commanded axis positions (m, rad).
    pub position: AxisValues,
    /// Direction of travel per axis, indexed like [`AxisValues`].
    pub direction: [Direction; 7],
    /// Commanded axis velocities (m/s, rad/s): the spindle speed is `velocity[Axis::S]`.
    pub velocity: AxisValues,
    /// Time since the start of the programme (s).
    pub time: Real,
}

impl MachineState {
    /// A state at these positions, at rest at time zero, every axis having last moved in the
    /// positive direction.
    pub fn at(position: AxisValues) -> MachineState {
        MachineState {
            position,
            direction: [Direction::Positive; 7],
            velocity: AxisValues::ZERO,
            time: 0.0,
        }
    }

    /// The same state at time `time` (s).
    pub fn at_time(mut self, time: Real) -> MachineState {
        self.time = time;
        self
    }

    /// The same state with `axis` moving at `velocity` (m/s or rad/s); its direction of travel
    /// follows the sign (unchanged at zero).
    pub fn with_velocity(mut self, axis: Axis, velocity: Real) -> MachineState {
        self.velocity[axis] = velocity;
        if velocity > 0.0 {
            self.direction[axis.index()] = Direction::Positive;
        } else if velocity < 0.0 {
            self.direction[axis.index()] = Direction::Negative;
        }
        self
    }

    /// The direction of travel of one axis.
    pub fn direction(&self, axis: Axis) -> Direction {
        self.direction[axis.index()]
    }
}

/// Which branch of the tree an axis sits on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// Between the bed and the tool: moves the tool.
    Tool,
    /// Between the bed and the workpiece: moves the workpiece.
    Workpiece,
}

/// A moving axis of a machine.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisInfo {
    /// Its letter.
    pub axis: Axis,
    /// Which branch it moves.
    pub side: Side,
    /// Travel limits (m or rad); `None` for continuous joints.
    pub limits: Option<(Real, Real)>,
    /// The URDF joint axis in its joint frame (parallel to the bed at the home pose): `±` the
    /// unit vector of the letter.
    pub joint_axis: Vector,
    /// Index of its error slot (see [`Machine::slot_count`]).
    pub slot: usize,
}

/// How far (rad) a scenario may set a continuous axis either side of zero: ten turns
/// (±3600°).
///
/// A continuous joint has no travel limits, but a scenario angle beyond ten turns is a typo,
/// not a test: the kinematic tests of ISO 10791-6 turn a rotary table once (twice with a
/// return), and a programme's path is checked for collisions at steps of the angle travelled,
/// so an angle of 1e9° would take hours. The spindle's own rotation is not a scenario angle
/// and is not bounded by this.
pub const CONTINUOUS_SCENARIO_TRAVEL_RAD: Real = 10.0 * std::f64::consts::TAU;

impl AxisInfo {
    /// Whether `value` (m or rad) is a number a scenario may set this axis to: within the
    /// travel, allowing 1e-9 of the larger limit for values written in rounded file units, or
    /// for a continuous axis within [`CONTINUOUS_SCENARIO_TRAVEL_RAD`] of zero.
    pub fn within_travel(&self, value: Real) -> bool {
        let (lower, upper) = self.scenario_travel();
        let tolerance = 1e-9 * (1.0 + lower.abs().max(upper.abs()));
        value.is_finite() && value >= lower - tolerance && value <= upper + tolerance
    }

    /// The range (m or rad) a scenario may set this axis to: its travel limits, or
    /// ±[`CONTINUOUS_SCENARIO_TRAVEL_RAD`] for a continuous axis.
    pub fn scenario_travel(&self) -> (Real, Real) {
        self.limits.unwrap_or((
            -CONTINUOUS_SCENARIO_TRAVEL_RAD,
            CONTINUOUS_SCENARIO_TRAVEL_RAD,
        ))
    }

    /// That range in file units for messages: `-110 … 110°`, `0 … 760 mm`, or
    /// `-3600 … 3600° (a continuous axis: ten turns either way)`.
    pub fn scenario_travel_text(&self) -> String {
        let (lower, upper) = self.scenario_travel();
        let (scale, unit) = if self.axis.is_linear() {
            (1e3, " mm")
        } else {
            (180.0 / std::f64::consts::PI, "°")
        };
        let range = format!(
            "{} … {}{unit}",
            crate::math::trimmed(lower * scale, 6),
            crate::math::trimmed(upper * scale, 6)
        );
        if self.limits.is_none() {
            format!("{range} (a continuous axis: ten turns either way in a scenario)")
        } else {
            range
        }
    }

    /// Whether the axis turns without end (continuous joint): its errors repeat every turn.
    pub fn is_continuous(&self) -> bool {
        !self.axis.is_linear() && self.limits.is_none()
    }
}

/// One moving joint of a branch, with the fixed transforms before it folded in.
#[derive(Clone, Debug)]
pub(crate) struct ChainJoint {
    /// `previous_from_joint`: from the previous moving joint's child frame (or the bed) to this
    /// joint's frame.
    pub origin: Pose,
    pub axis: Axis,
    /// The joint axis in its joint frame: `±Axis::unit`.
    pub unit: Vector,
    pub slot: usize,
    /// Whether `origin`'s rotation is exactly the identity (a translation), decided once so
    /// that the walk does not compare it at every pose.
    pub origin_is_translation: bool,
    /// The coordinate (0, 1, 2) `unit` lies exactly along, either way, if any (see
    /// [`kinematics::coordinate_of`]), decided once.
    pub coordinate: Option<usize>,
}

impl ChainJoint {
    /// The joint at `origin`, moving along or about `unit`, at `slot`.
    pub(crate) fn new(origin: Pose, axis: Axis, unit: Vector, slot: usize) -> ChainJoint {
        ChainJoint {
            origin,
            axis,
            unit,
            slot,
            origin_is_translation: origin.matrix3 == glam::DMat3::IDENTITY,
            coordinate: kinematics::coordinate_of(unit),
        }
    }
}

/// A path of joints from the bed to the tool or the workpiece.
#[derive(Clone, Debug)]
pub(crate) struct Branch {
    pub joints: Vec<ChainJoint>,
    /// From the last moving joint's child frame to the end link (`tool` or `workpiece`).
    pub end: Pose,
    /// Whether `end`'s rotation is exactly the identity.
    pub end_is_translation: bool,
    /// Whether `end` is exactly the identity (the end link on the last moving joint's frame).
    pub end_is_identity: bool,
}

/// A validated, immutable machine: share it across threads; keep per-evaluation scratch in a
/// [`Workspace`].
///
/// Errors enter the chain at *slots*: one per moving axis (in the order of [`Machine::axes`])
/// and one at the tool tip ([`Machine::tool_slot`]). See [`crate::errors`] for what is applied
/// there.
#[derive(Clone, Debug)]
pub struct Machine {
    name: String,
    axes: Vec<AxisInfo>,
    tool_branch: Branch,
    work_branch: Branch,
    /// The rotary joints (the spindle's included) of the tool branch, then the workpiece
    /// branch: the rotations [`Workspace`] computes at each pose.
    rotary_joints: Vec<ChainJoint>,
    bodies: Vec<body::Body>,
}

impl Machine {
    /// The URDF robot name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The moving axes in ISO order (X, Y, Z, A, B, C, S).
    pub fn axes(&self) -> &[AxisInfo] {
        &self.axes
    }

    /// The axis with this letter, if the machine has it.
    pub fn axis(&self, axis: Axis) -> Option<&AxisInfo> {
        self.axes.iter().find(|info| info.axis == axis)
    }

    /// Whether the machine has this axis.
    pub fn has_axis(&self, axis: Axis) -> bool {
        self.axis(axis).is_some()
    }

    /// The rotary axes (A, B, C) the machine has, in ISO order; the spindle is not among them.
    pub fn rotary_axes(&self) -> impl Iterator<Item = &AxisInfo> {
        self.axes
            .iter()
            .filter(|info| matches!(info.axis, Axis::A | Axis::B | Axis::C))
    }

    /// Number of error slots: one per moving axis plus the tool tip.
    pub fn slot_count(&self) -> usize {
        self.axes.len() + 1
    }

    /// The slot of the tool tip (tool length and offset errors).
    pub fn tool_slot(&self) -> usize {
        self.axes.len()
    }

    /// Nominal tool pose seen from the workpiece at these axis values.
    ///
    /// Convenience for one-off use; loops should keep a [`Workspace`] and call
    /// [`Workspace::workpiece_from_tool`].
    pub fn workpiece_from_tool(&self, position: &AxisValues) -> Pose {
        Workspace::new(self).workpiece_from_tool(self, position, None)
    }

    /// The first axis of `position` outside its travel limits (or not a number), said for
    /// people in file units: `X = 5000 mm is outside the travel of X on machine "vmc3" (0 …
    /// 760 mm)`; `None` when every axis is within its travel.
    pub fn outside_travel(&self, position: &AxisValues) -> Option<String> {
        let (axis, value, (lower, upper)) = self.check_limits(position).err()?;
        let (unit, scale) = if axis.is_linear() {
            ("mm", 1e-3)
        } else {
            ("°", std::f64::consts::PI / 180.0)
        };
        let text = |v: Real| crate::math::trimmed(v / scale, 6);
        Some(format!(
            "{axis} = {} {unit} is outside the travel of {axis} on machine \"{}\" ({} … {} {unit})",
            text(value),
            self.name(),
            text(lower),
            text(upper)
        ))
    }

    /// Whether every axis value lies within its travel limits; the first axis outside them
    /// (or not a number), with its value and limits, otherwise.
    pub fn check_limits(&self, position: &AxisValues) -> Result<(), (Axis, Real, (Real, Real))> {
        for info in &self.axes {
            let value = position[info.axis];
            let limits = info.limits.unwrap_or((Real::NEG_INFINITY, Real::INFINITY));
            let tolerance = 1e-9 * (1.0 + limits.0.abs().max(limits.1.abs()).min(1e300));
            let inside = value >= limits.0 - tolerance && value <= limits.1 + tolerance;
            if !(value.is_finite() && inside) {
                return Err((info.axis, value, limits));
            }
        }
        Ok(())
    }
}
