//! ISO 230-1 geometric error parameters, their functions, and where each enters the chain.
//!
//! # Names
//!
//! - **Component errors** `E<motion><axis>` of every axis, functions of that axis's position
//!   (and direction of travel): for a linear axis X, `EXX` positioning, `EYX` and `EZX`
//!   straightness, `EAX`, `EBX`, `ECX` roll/pitch/yaw about X, Y, Z; for a rotary axis C,
//!   `EXC`, `EYC` radial, `EZC` axial, `EAC`, `EBC` tilt, `ECC` angular positioning. The
//!   spindle `S` takes the same six (its error motions, ISO 230-7).
//! - **Location errors** `E<motion>0<axis>`, constants. Rotary axes: the position of the axis
//!   line in the two directions across it (`EX0C`, `EY0C`; `EY0A`, `EZ0A`; `EX0B`, `EZ0B`),
//!   its orientation about those directions (`EA0C`, `EB0C`; `EB0A`, `EC0A`; `EA0B`, `EC0B`)
//!   and its zero position (`EC0C`; `EA0A`; `EB0B`). Linear axes: the three squareness errors,
//!   X being the reference and X–Y the reference plane: `EC0Y` (Y about Z), `EB0Z` and `EA0Z`
//!   (Z about Y and about X).
//! - **Tool errors** (not named by ISO 230-1): `EXT`, `EYT` tool-tip offset and `EZT` tool
//!   length error, along x, y and z of the `tool` frame (z = tool axis, out of the tip).
//!
//! Translations are in m (µm in files), rotations in rad (µrad in files).
//!
//! # Sign and frame
//!
//! Every parameter is a motion of the **tool relative to the workpiece** (the ISO 230-1 view,
//! which is what a laser, ball-bar or probe sees), so its sign does not depend on which branch
//! the axis moves: `EXX = +2 µm` at X = 100 mm means the tool ends up 2 µm further along +X
//! relative to the workpiece, whether X moves the head or the table (on the workpiece branch
//! the chain applies the inverse motion to the table). Commanded positive motion is itself
//! tool-relative (ISO 841, see [`crate::machine`]), so for the positioning errors this reads
//! "axis X reached X + EXX".
//!
//! # Where each error enters the chain
//!
//! Each axis owns one **slot**: a small rigid motion `Trans(δ) · Exp(ε)` (δ, ε the sums of the
//! parameters acting there, [`crate::math::small_motion`]) inserted in the chain at the
//! **slot frame**: the joint frame with the orientation of the axis's fixed side and the origin
//! at the moving part's reference point, i.e.
//!
//! - linear axis: `origin · Trans(q·u) · [slot] · …` (after the translation: angular errors turn
//!   about the carriage's current reference point, so Abbe offsets are the distance from there
//!   to the tool tip, and come out of the chain);
//! - rotary axis: `origin · [slot] · Rot(u, q) · …` (before the rotation: `EXC` stays along the
//!   fixed X of the axis whatever the angle, as ISO 230-7 measures it).
//!
//! The slot motion is applied as is on the tool branch and inverted on the workpiece branch.
//! At the slot, `δ = (E X·, E Y·, E Z·) + location + squareness`, `ε = (E A·, E B·, E C·) +
//! location`. A squareness `ε_s` about direction `e_m` of linear axis `a` with travel direction
//! `u_a` adds the translation `(e_m × u_a) · q_a` (zero at q = 0): `EC0Y` adds
//! `δx = −EC0Y · y`, so `EC0Y > 0` opens the angle between +X and +Y travel beyond 90°.
//! The tool slot sits at the `tool` frame, after the whole tool branch.

mod function;
mod lu2012;

pub use function::{ErrorFunction, Interpolation, Table, TableError};
pub use lu2012::{Lu2012Error, lu2012_deviation};

use crate::machine::{Axis, Machine, MachineState, Workspace};
use crate::math::{Pose, Real, Vector, rigid_inverse, small_motion};
use std::fmt;
use std::str::FromStr;

/// One of the six motion components: translation along or rotation about x, y, z.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Motion {
    /// Translation along x.
    X,
    /// Translation along y.
    Y,
    /// Translation along z.
    Z,
    /// Rotation about x.
    A,
    /// Rotation about y.
    B,
    /// Rotation about z.
    C,
}

impl Motion {
    const ALL: [Motion; 6] = [
        Motion::X,
        Motion::Y,
        Motion::Z,
        Motion::A,
        Motion::B,
        Motion::C,
    ];

    /// Index in a twist (δx, δy, δz, εx, εy, εz).
    pub fn index(self) -> usize {
        self as usize
    }

    /// Whether it is a translation (value in m) rather than a rotation (rad).
    pub fn is_translation(self) -> bool {
        self.index() < 3
    }

    fn letter(self) -> char {
        ['X', 'Y', 'Z', 'A', 'B', 'C'][self.index()]
    }

    fn from_letter(letter: char) -> Option<Motion> {
        Motion::ALL.into_iter().find(|m| m.letter() == letter)
    }
}

/// The ISO 230-1 name of an error parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ParameterName {
    /// `E<motion><axis>`: component error (error motion) of an axis, a function of its position.
    Component {
        /// Direction of the error.
        motion: Motion,
        /// The moving axis.
        axis: Axis,
    },
    /// `E<motion>0<axis>`: location error of a rotary axis or squareness of a linear axis.
    Location {
        /// Direction of the error.
        motion: Motion,
        /// The axis.
        axis: Axis,
    },
    /// `E<motion>T`: tool-tip offset (X, Y) or tool length (Z) error in the tool frame.
    Tool {
        /// Direction of the error.
        motion: Motion,
    },
}

impl ParameterName {
    /// The motion component it acts on.
    pub fn motion(self) -> Motion {
        match self {
            ParameterName::Component { motion, .. }
            | ParameterName::Location { motion, .. }
            | ParameterName::Tool { motion } => motion,
        }
    }

    /// The axis it belongs to (`None` for tool errors).
    pub fn axis(self) -> Option<Axis> {
        match self {
            ParameterName::Component { axis, .. } | ParameterName::Location { axis, .. } => {
                Some(axis)
            }
            ParameterName::Tool { .. } => None,
        }
    }

    /// Unit in files: `um` for translations, `urad` for rotations.
    pub fn file_unit(self) -> &'static str {
        if self.motion().is_translation() {
            "um"
        } else {
            "urad"
        }
    }

    /// Whether this name is a parameter at all (independent of the machine): tool errors are
    /// translations; a rotary axis has no location error along itself; a linear axis's only
    /// location errors are the squareness errors EC0Y, EB0Z, EA0Z.
    fn check(self) -> Result<(), String> {
        match self {
            ParameterName::Tool { motion } if !motion.is_translation() => Err(format!(
                "{self}: tool errors are translations EXT, EYT, EZT"
            )),
            ParameterName::Location { motion, axis } if axis.is_linear() => {
                let squareness = matches!(
                    (motion, axis),
                    (Motion::C, Axis::Y) | (Motion::B, Axis::Z) | (Motion::A, Axis::Z)
                );
                if squareness {
                    Ok(())
                } else {
                    Err(format!(
                        "{self}: the location errors of linear axes are the squareness errors EC0Y, EB0Z and EA0Z \
                         (X is the reference direction and X-Y the reference plane)"
                    ))
                }
            }
            ParameterName::Location { motion, axis }
                if motion.is_translation() && motion.index() == axis.coordinate() =>
            {
                Err(format!(
                    "{self}: the position of a rotary axis along itself is not a location error"
                ))
            }
            ParameterName::Location { axis: Axis::S, .. } => Err(format!(
                "{self}: the spindle has component errors (error motions), not location errors"
            )),
            _ => Ok(()),
        }
    }
}

impl fmt::Display for ParameterName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParameterName::Component { motion, axis } => {
                write!(f, "E{}{}", motion.letter(), axis.letter())
            }
            ParameterName::Location { motion, axis } => {
                write!(f, "E{}0{}", motion.letter(), axis.letter())
            }
            ParameterName::Tool { motion } => write!(f, "E{}T", motion.letter()),
        }
    }
}

impl FromStr for ParameterName {
    type Err = String;

    fn from_str(text: &str) -> Result<ParameterName, String> {
        let unknown = || {
            format!(
                "\"{text}\" is not an error parameter: expected a component error such as EXX or ECC, \
                 a location error such as EX0C or EC0Y, or a tool error EXT, EYT, EZT"
            )
        };
        let chars: Vec<char> = text.chars().collect();
        let name = match chars[..] {
            ['E', m, 'T'] => ParameterName::Tool {
                motion: Motion::from_letter(m).ok_or_else(unknown)?,
            },
            ['E', m, a] => ParameterName::Component {
                motion: Motion::from_letter(m).ok_or_else(unknown)?,
                axis: Axis::from_letter(a).ok_or_else(unknown)?,
            },
            ['E', m, '0', a] => ParameterName::Location {
                motion: Motion::from_letter(m).ok_or_else(unknown)?,
                axis: Axis::from_letter(a).ok_or_else(unknown)?,
            },
            _ => return Err(unknown()),
        };
        name.check()?;
        Ok(name)
    }
}

/// An injected error: a name and a function.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorParameter {
    /// ISO 230-1 name.
    pub name: ParameterName,
    /// How it varies (SI).
    pub function: ErrorFunction,
}

/// Why an error model does not fit a machine.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ErrorModelError {
    /// The parameter names an axis the machine does not have.
    #[error("{name}: the machine has no axis {axis}")]
    MissingAxis {
        /// The parameter.
        name: ParameterName,
        /// The axis.
        axis: Axis,
    },
    /// The name is not a parameter.
    #[error("{0}")]
    InvalidName(String),
    /// Location, squareness and tool errors are constants.
    #[error("{0}: location, squareness and tool errors are constants")]
    NotConstant(ParameterName),
    /// A name appears twice.
    #[error("{0} is given twice")]
    Duplicate(ParameterName),
    /// A parameter of a rotary axis has a table or harmonic in the wrong position units, etc.
    #[error("{name}: {message}")]
    Invalid {
        /// The parameter.
        name: ParameterName,
        /// What is wrong.
        message: String,
    },
}

/// Where a parameter acts.
#[derive(Clone, Copy, Debug)]
struct Binding {
    slot: usize,
    /// Its position argument (`None`: constant).
    argument: Option<Axis>,
    /// Squareness: the translation per unit parameter per unit travel, `e_m × u_a`.
    squareness: Option<(Axis, Vector)>,
}

/// The tool-in-workpiece deviation: actual − nominal, in the workpiece frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Tool-tip position deviation (m, workpiece frame).
    pub translation: Vector,
    /// Tool-axis tilt (rad): the change of the tool-axis unit vector along the nominal tool
    /// frame's x (`ti`) and y (`tj`) axes.
    pub tilt: [Real; 2],
}

impl Deviation {
    /// As `[dx, dy, dz, ti, tj]` (m, rad): the rows of [`ErrorModel::jacobian`].
    pub fn to_array(self) -> [Real; 5] {
        [
            self.translation.x,
            self.translation.y,
            self.translation.z,
            self.tilt[0],
            self.tilt[1],
        ]
    }

    /// The deviation between a nominal and an actual `workpiece_from_tool`.
    pub fn between(nominal: &Pose, actual: &Pose) -> Deviation {
        let dk = actual.matrix3.z_axis - nominal.matrix3.z_axis;
        Deviation {
            translation: actual.translation - nominal.translation,
            tilt: [
                dk.dot(nominal.matrix3.x_axis),
                dk.dot(nominal.matrix3.y_axis),
            ],
        }
    }
}

/// A set of error parameters bound to a machine: immutable and shareable; evaluations use the
/// machine's [`Workspace`].
#[derive(Clone, Debug)]
pub struct ErrorModel {
    parameters: Vec<ErrorParameter>,
    bindings: Vec<Binding>,
    slot_count: usize,
}

impl ErrorModel {
    /// Binds parameters to `machine`, sorted by name; rejects duplicates, axes the machine lacks
    /// and non-constant location or tool errors.
    pub fn new(
        machine: &Machine,
        mut parameters: Vec<ErrorParameter>,
    ) -> Result<ErrorModel, ErrorModelError> {
        parameters.sort_by_key(|p| p.name);
        for pair in parameters.windows(2) {
            if pair[0].name == pair[1].name {
                return Err(ErrorModelError::Duplicate(pair[0].name));
            }
        }
        let mut bindings = Vec::with_capacity(parameters.len());
        for parameter in &parameters {
            let name = parameter.name;
            name.check().map_err(ErrorModelError::InvalidName)?;
            let binding = match name {
                ParameterName::Tool { .. } => Binding {
                    slot: machine.tool_slot(),
                    argument: None,
                    squareness: None,
                },
                ParameterName::Component { axis, .. } | ParameterName::Location { axis, .. } => {
                    let info = machine
                        .axis(axis)
                        .ok_or(ErrorModelError::MissingAxis { name, axis })?;
                    match name {
                        ParameterName::Component { .. } => Binding {
                            slot: info.slot,
                            argument: Some(axis),
                            squareness: None,
                        },
                        _ if axis.is_linear() => {
                            let direction =
                                Vector::AXES[name.motion().index() - 3].cross(axis.unit());
                            Binding {
                                slot: info.slot,
                                argument: None,
                                squareness: Some((axis, direction)),
                            }
                        }
                        _ => Binding {
                            slot: info.slot,
                            argument: None,
                            squareness: None,
                        },
                    }
                }
            };
            if binding.argument.is_none() && !parameter.function.is_constant() {
                return Err(ErrorModelError::NotConstant(name));
            }
            bindings.push(binding);
        }
        Ok(ErrorModel {
            parameters,
            bindings,
            slot_count: machine.slot_count(),
        })
    }

    /// A model with no errors.
    pub fn empty(machine: &Machine) -> ErrorModel {
        ErrorModel {
            parameters: Vec::new(),
            bindings: Vec::new(),
            slot_count: machine.slot_count(),
        }
    }

    /// The parameters, sorted by name.
    pub fn parameters(&self) -> &[ErrorParameter] {
        &self.parameters
    }

    /// The parameter with this name.
    pub fn parameter(&self, name: ParameterName) -> Option<&ErrorParameter> {
        self.parameters.iter().find(|p| p.name == name)
    }

    /// Sums the parameters into one twist `(δx, δy, δz, εx, εy, εz)` per slot (SI).
    pub fn slot_twists(&self, state: &MachineState, twists: &mut [[Real; 6]]) {
        assert_eq!(twists.len(), self.slot_count, "one twist per slot");
        twists.iter_mut().for_each(|t| *t = [0.0; 6]);
        for (parameter, binding) in self.parameters.iter().zip(&self.bindings) {
            let twist = &mut twists[binding.slot];
            match (binding.argument, binding.squareness) {
                (_, Some((axis, direction))) => {
                    let value = parameter
                        .function
                        .value(0.0, crate::machine::Direction::Positive);
                    let translation = direction * (value * state.position[axis]);
                    twist[0] += translation.x;
                    twist[1] += translation.y;
                    twist[2] += translation.z;
                }
                (Some(axis), None) => {
                    twist[parameter.name.motion().index()] += parameter
                        .function
                        .value(state.position[axis], state.direction(axis));
                }
                (None, None) => {
                    twist[parameter.name.motion().index()] += parameter
                        .function
                        .value(0.0, crate::machine::Direction::Positive);
                }
            }
        }
    }

    /// The actual tool pose seen from the workpiece: the exact chain with every slot motion.
    pub fn workpiece_from_tool(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
    ) -> Pose {
        let mut twists = std::mem::take(&mut workspace.slot_twists);
        let mut motions = std::mem::take(&mut workspace.slot_motions);
        self.slot_twists(state, &mut twists);
        for (motion, t) in motions.iter_mut().zip(&twists) {
            *motion = small_motion(Vector::new(t[0], t[1], t[2]), Vector::new(t[3], t[4], t[5]));
        }
        let pose = workspace.workpiece_from_tool(machine, &state.position, Some(&motions));
        workspace.slot_twists = twists;
        workspace.slot_motions = motions;
        pose
    }

    /// Actual − nominal at `state`, by the exact chain.
    pub fn deviation(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
    ) -> Deviation {
        let nominal = workspace.workpiece_from_tool(machine, &state.position, None);
        let actual = self.workpiece_from_tool(machine, workspace, state);
        Deviation::between(&nominal, &actual)
    }

    /// Total number of linear coefficients (the columns of [`ErrorModel::jacobian`]).
    pub fn coefficient_count(&self) -> usize {
        self.parameters
            .iter()
            .map(|p| p.function.coefficient_count())
            .sum()
    }

    /// All linear coefficients (SI), parameter by parameter in name order.
    pub fn coefficients(&self) -> Vec<Real> {
        let mut out = Vec::with_capacity(self.coefficient_count());
        self.parameters
            .iter()
            .for_each(|p| p.function.coefficients(&mut out));
        out
    }

    /// Replaces all linear coefficients (as laid out by [`ErrorModel::coefficients`]).
    pub fn set_coefficients(&mut self, coefficients: &[Real]) {
        assert_eq!(
            coefficients.len(),
            self.coefficient_count(),
            "one value per coefficient"
        );
        let mut used = 0;
        for parameter in &mut self.parameters {
            used += parameter.function.set_coefficients(&coefficients[used..]);
        }
    }

    /// A label per coefficient, e.g. `EXX.polynomial[1]`.
    pub fn coefficient_labels(&self) -> Vec<String> {
        let mut out = Vec::with_capacity(self.coefficient_count());
        for parameter in &self.parameters {
            parameter
                .function
                .coefficient_labels(&format!("{}.", parameter.name), &mut out);
        }
        out
    }

    /// The sensitivity of the deviation `[dx, dy, dz, ti, tj]` to each slot's twist, at the
    /// nominal pose: `out[slot][row][component]`.
    ///
    /// A twist ξ = (δ, ε) at a slot with frame F moves the tool to
    /// `workpiece_from_F · Exp(ξ) · F_from_tool` (on either branch, by the sign convention),
    /// so to first order `dp = R_F (δ + ε × p_F)` and `dk = R_F (ε × k_F)`, with `p_F`, `k_F`
    /// the nominal tool tip and tool axis in F.
    pub fn slot_sensitivities(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
        out: &mut [[[Real; 6]; 5]],
    ) {
        assert_eq!(out.len(), self.slot_count, "one sensitivity per slot");
        let workpiece_from_tool = workspace.workpiece_from_tool(machine, &state.position, None);
        let world_from_workpiece =
            workspace.world_from_slot[machine.tool_slot()] * rigid_inverse(&workpiece_from_tool);
        let workpiece_from_world = rigid_inverse(&world_from_workpiece);
        let tip = workpiece_from_tool.translation;
        let k = workpiece_from_tool.matrix3.z_axis;
        let (i_axis, j_axis) = (
            workpiece_from_tool.matrix3.x_axis,
            workpiece_from_tool.matrix3.y_axis,
        );
        for (slot, sensitivity) in out.iter_mut().enumerate() {
            let workpiece_from_slot = workpiece_from_world * workspace.world_from_slot[slot];
            let rotation = workpiece_from_slot.matrix3;
            // Lever arm from the slot origin to the tip, in the workpiece frame.
            let lever = tip - workpiece_from_slot.translation;
            for component in 0..6 {
                let (dp, dk) = if component < 3 {
                    (rotation.col(component), Vector::ZERO)
                } else {
                    let e = rotation.col(component - 3);
                    (e.cross(lever), e.cross(k))
                };
                let column = [dp.x, dp.y, dp.z, dk.dot(i_axis), dk.dot(j_axis)];
                for row in 0..5 {
                    sensitivity[row][component] = column[row];
                }
            }
        }
    }

    /// The Jacobian of the deviation `[dx, dy, dz, ti, tj]` with respect to every linear
    /// coefficient, linearised about zero error at `state`: `columns[c][row]`.
    ///
    /// `Deviation ≈ Σ_c columns[c] · coefficient_c` to first order in the errors; the
    /// difference from the exact chain is second order.
    pub fn jacobian(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
        columns: &mut [[Real; 5]],
    ) {
        assert_eq!(
            columns.len(),
            self.coefficient_count(),
            "one column per coefficient"
        );
        let mut sensitivities = vec![[[0.0; 6]; 5]; self.slot_count];
        self.slot_sensitivities(machine, workspace, state, &mut sensitivities);
        let mut basis = Vec::new();
        let mut column = 0;
        for (parameter, binding) in self.parameters.iter().zip(&self.bindings) {
            basis.clear();
            let q = binding.argument.map_or(0.0, |axis| state.position[axis]);
            let direction = binding
                .argument
                .map_or(crate::machine::Direction::Positive, |axis| {
                    state.direction(axis)
                });
            parameter.function.basis(q, direction, &mut basis);
            let s = &sensitivities[binding.slot];
            for &b in &basis {
                let mut twist = [0.0; 6];
                match binding.squareness {
                    Some((axis, direction)) => {
                        let t = direction * (b * state.position[axis]);
                        twist[..3].copy_from_slice(&t.to_array());
                    }
                    None => twist[parameter.name.motion().index()] = b,
                }
                for row in 0..5 {
                    columns[column][row] = (0..6).map(|k| s[row][k] * twist[k]).sum();
                }
                column += 1;
            }
        }
    }
}
