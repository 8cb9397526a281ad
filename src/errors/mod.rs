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
//! - **Tool errors** (not named by ISO 230-1): `EXT`, `EYT` tool-tip offset and `EZT` along the
//!   tool axis, translations along x, y and z of the `tool` frame, whose z runs from the tip
//!   into the spindle: `EZT > 0` is a tool that much shorter than its offset says.
//!
//! Translations are in m (µm in files), rotations in rad (µrad in files).
//!
//! # Sign and frame
//!
//! **Component, tool and zero-position errors** are motions of the **tool relative to the
//! workpiece** (the view of a laser, ball-bar or probe), so their sign does not depend on which
//! branch the axis moves: `EXX = +2 µm` at X = 100 mm means the tool ends up 2 µm further along
//! +X relative to the workpiece, whether X moves the head or the table (on the workpiece branch
//! the chain applies the inverse motion to the table). Commanded motion is itself
//! tool-relative (ISO 841, see [`crate::machine`]), so for positioning errors this reads "axis
//! X reached X + EXX", and `EC0C` reads "C reached C + EC0C".
//!
//! **Location errors** describe the **axis line itself**, actual − nominal, in the frame of the
//! axis's fixed side: `EX0C = +5 µm` means the C axis line lies 5 µm towards +X of where the
//! model puts it, whichever branch C is on. As in ISO 230-1, what the axis carries is at its
//! nominal place when the axis is at zero: a location error shows only as the axis moves. The
//! nominal line is the URDF joint axis through the joint origin, which is also the pivot of the
//! orientation errors (`EA0C`, `EB0C`).
//! Turning by `R` about a line displaced by `δ` moves a point by `(I − R)·δ`, so on a rotary
//! table `EX0C` shifts the tool relative to the workpiece by 0 at C = 0 and by 2·EX0C at 180°.
//! A squareness error `ε` about direction `e_m` tilts a linear axis's line of travel, adding
//! `(Exp(ε e_m) − I)·u·q ≈ (e_m × u)·ε·q` (zero at q = 0): `EC0Y` adds `δx = −EC0Y·y`, so
//! `EC0Y > 0` opens the angle between +X and +Y travel beyond 90°.
//!
//! # Where each error enters the chain
//!
//! Each axis owns one **slot** in the chain, at the **slot frame**: the joint frame with the
//! orientation of the axis's fixed side and the origin at the moving part's reference point:
//!
//! - linear axis: `origin · Trans(q·u) · [slot] · …` (after the translation: angular errors turn
//!   about the carriage's current reference point, so Abbe offsets are the distance from there
//!   to the tool tip, and come out of the chain);
//! - rotary axis: `origin · [slot] · Rot(u, q) · …` (before the rotation: `EXC` stays along the
//!   fixed X of the axis whatever the angle, as ISO 230-7 measures it).
//!
//! The slot motion is `line · Trans(δ) · Exp(ε)` (see [`crate::math::small_motion`]), `δ`, `ε`
//! summing the component (`E X·` … `E C·`), zero-position and tool errors acting there and
//! `line` the exact effect of the location errors (see [`ErrorModel::workpiece_from_tool`]).
//! It is applied as is on the tool branch and inverted on the workpiece branch. The tool slot
//! sits at the `tool` frame, after the whole tool branch.

mod chain;
mod context;
mod dynamics;
mod function;
mod lu2012;
mod record;

pub use context::{ContextTerm, Driver, ParameterContext};
pub use dynamics::{Dynamics, Frequency, ParameterDynamics, RandomMotion, Sinusoid};
pub use function::{ErrorFunction, Interpolation, Table, TableError};
pub use lu2012::{Lu2012Error, lu2012_deviation};
pub use record::TemperatureRecord;

use crate::machine::{Axis, Direction, Machine, MachineState, Side, Workspace};
use crate::math::{Pose, Real, Vector, rigid_inverse};
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
            ParameterName::Tool { motion } if !motion.is_translation() => {
                Err("tool errors are translations: EXT, EYT, EZT".to_string())
            }
            ParameterName::Location { motion, axis } if axis.is_linear() => {
                let squareness = matches!(
                    (motion, axis),
                    (Motion::C, Axis::Y) | (Motion::B, Axis::Z) | (Motion::A, Axis::Z)
                );
                if squareness {
                    Ok(())
                } else {
                    Err("the location errors of linear axes are the squareness errors EC0Y, EB0Z and EA0Z \
                         (X is the reference direction and X-Y the reference plane)".to_string())
                }
            }
            ParameterName::Location { motion, axis }
                if motion.is_translation() && motion.index() == axis.coordinate() =>
            {
                Err(
                    "the position of a rotary axis along itself is not a location error"
                        .to_string(),
                )
            }
            ParameterName::Location { axis: Axis::S, .. } => Err(
                "the spindle has component errors (error motions), not location errors".to_string(),
            ),
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

impl ParameterName {
    /// Every valid name.
    pub fn all() -> Vec<ParameterName> {
        let mut names = Vec::new();
        for motion in Motion::ALL {
            names.push(ParameterName::Tool { motion });
            for axis in Axis::ALL {
                names.push(ParameterName::Component { motion, axis });
                names.push(ParameterName::Location { motion, axis });
            }
        }
        names.retain(|n| n.check().is_ok());
        names
    }

    /// The valid name one keystroke from `text` (a letter replaced, added or dropped, or any
    /// case), preferring a replacement (`ECOY` → `EC0Y`); none when it is not unique.
    fn nearest(text: &str) -> Option<ParameterName> {
        let text: Vec<char> = text.to_ascii_uppercase().chars().collect();
        let names = ParameterName::all();
        // 0: the name in other case; 1: one letter replaced; 2: one added or dropped.
        let near = |stage: usize| -> Vec<ParameterName> {
            names
                .iter()
                .copied()
                .filter(|n| {
                    let name: Vec<char> = n.to_string().chars().collect();
                    if stage < 2 {
                        name.len() == text.len()
                            && name.iter().zip(&text).filter(|(a, b)| a != b).count() == stage
                    } else {
                        let (long, short) = if name.len() > text.len() {
                            (&name, &text)
                        } else {
                            (&text, &name)
                        };
                        long.len() == short.len() + 1
                            && (0..long.len()).any(|skip| {
                                long.iter()
                                    .enumerate()
                                    .filter(|(i, _)| *i != skip)
                                    .map(|(_, c)| c)
                                    .eq(short.iter())
                            })
                    }
                })
                .collect()
        };
        (0..3)
            .map(near)
            .find(|found| !found.is_empty())
            .and_then(|found| (found.len() == 1).then(|| found[0]))
    }
}

impl FromStr for ParameterName {
    type Err = String;

    fn from_str(text: &str) -> Result<ParameterName, String> {
        let unknown = || {
            let mut message = "not an error parameter: expected a component error such as EXX or \
                 ECC, a location error such as EX0C or EC0Y, or a tool error EXT, EYT, EZT"
                .to_string();
            if let Some(near) = ParameterName::nearest(text) {
                message += &format!("; did you mean {near}?");
            }
            message
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
    #[error("{0}: {1}")]
    InvalidName(ParameterName, String),
    /// Location, squareness and tool errors are constants.
    #[error("{0}: location, squareness and tool errors are constants")]
    NotConstant(ParameterName),
    /// A function that does not repeat every turn on an axis that turns without end.
    #[error("{name}: {message}")]
    NotPeriodic {
        /// The parameter.
        name: ParameterName,
        /// What is wrong.
        message: String,
    },
    /// A name appears twice.
    #[error("{0} is given twice")]
    Duplicate(ParameterName),
}

/// What a parameter does at its slot.
#[derive(Clone, Copy, Debug)]
enum Action {
    /// Adds its function of the axis position to one component of the slot's relative twist.
    Component(Axis),
    /// Adds a constant to one component of the slot's relative twist (tool errors and the
    /// zero-position errors EA0A, EB0B, EC0C).
    Constant,
    /// Orientation of a linear axis's line of travel (squareness).
    Squareness(Axis),
    /// Position or orientation of a rotary axis line.
    RotaryLocation(Axis),
}

impl ErrorModelError {
    /// The parameter the error is about.
    pub fn parameter(&self) -> ParameterName {
        match self {
            ErrorModelError::MissingAxis { name, .. }
            | ErrorModelError::InvalidName(name, _)
            | ErrorModelError::NotConstant(name)
            | ErrorModelError::NotPeriodic { name, .. }
            | ErrorModelError::Duplicate(name) => *name,
        }
    }
}

/// Where a parameter acts.
#[derive(Clone, Copy, Debug)]
struct Binding {
    slot: usize,
    action: Action,
    /// Its axis turns without end: the argument is taken modulo one turn, in [0, 2π).
    periodic: bool,
}

impl Binding {
    /// Where the parameter `name` acts on `machine`.
    fn of(machine: &Machine, name: ParameterName) -> Result<Binding, ErrorModelError> {
        Ok(match name {
            ParameterName::Tool { .. } => Binding {
                slot: machine.tool_slot(),
                action: Action::Constant,
                periodic: false,
            },
            ParameterName::Component { axis, .. } | ParameterName::Location { axis, .. } => {
                let info = machine
                    .axis(axis)
                    .ok_or(ErrorModelError::MissingAxis { name, axis })?;
                let action = match name {
                    ParameterName::Component { .. } => Action::Component(axis),
                    _ if axis.is_linear() => Action::Squareness(axis),
                    _ if name.motion().index() == axis.coordinate() + 3 => Action::Constant,
                    _ => Action::RotaryLocation(axis),
                };
                Binding {
                    slot: info.slot,
                    action,
                    periodic: info.is_continuous() && matches!(action, Action::Component(_)),
                }
            }
        })
    }

    /// The function's argument for an axis position.
    fn argument(&self, q: Real) -> Real {
        if self.periodic {
            q.rem_euclid(std::f64::consts::TAU)
        } else {
            q
        }
    }
}

/// The tool-in-workpiece deviation: actual − nominal, in the workpiece frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Tool-tip position deviation (m, workpiece frame).
    pub translation: Vector,
    /// Tool-axis tilt (rad): the change of the tool-axis unit vector along the nominal tool
    /// frame's x (`ti`) and y (`tj`) axes. That frame turns with the spindle angle S; the
    /// volumetric map holds S at zero.
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
    /// The axes (and their sides) of the machine it was bound to, slot by slot.
    machine_axes: Vec<(Axis, Side)>,
    /// Time- and speed-dependent content, by parameter name.
    dynamics: Vec<ParameterDynamics>,
    /// Where each entry of `dynamics` acts.
    dynamic_bindings: Vec<DynamicBinding>,
    /// Terms driven by measured temperatures and time.
    context: context::ContextErrors,
    /// What every evaluation would otherwise recompute; rebuilt whenever any of the above
    /// changes.
    plan: chain::Plan,
}

/// Where a parameter's [`Dynamics`] act: its axis's slot and twist component, and the
/// parameter whose synchronous function the speed factor scales.
#[derive(Clone, Copy, Debug)]
struct DynamicBinding {
    slot: usize,
    component: usize,
    axis: Axis,
    parameter: Option<usize>,
}

impl ErrorModel {
    /// Binds parameters to `machine`, sorted by their names as text (`EX0C` before `EXX`);
    /// rejects duplicates, axes the machine lacks
    /// and non-constant location or tool errors.
    pub fn new(
        machine: &Machine,
        mut parameters: Vec<ErrorParameter>,
    ) -> Result<ErrorModel, ErrorModelError> {
        parameters.sort_by_cached_key(|p| p.name.to_string());
        for pair in parameters.windows(2) {
            if pair[0].name == pair[1].name {
                return Err(ErrorModelError::Duplicate(pair[0].name));
            }
        }
        let mut bindings = Vec::with_capacity(parameters.len());
        for parameter in &parameters {
            let name = parameter.name;
            name.check()
                .map_err(|message| ErrorModelError::InvalidName(name, message))?;
            let binding = Binding::of(machine, name)?;
            if let Some(message) = parameter
                .function
                .periodicity_problem(std::f64::consts::TAU)
                .filter(|_| binding.periodic)
            {
                return Err(ErrorModelError::NotPeriodic { name, message });
            }
            if !matches!(binding.action, Action::Component(_)) && !parameter.function.is_constant()
            {
                return Err(ErrorModelError::NotConstant(name));
            }
            bindings.push(binding);
        }
        Ok(ErrorModel {
            parameters,
            bindings,
            slot_count: machine.slot_count(),
            machine_axes: axes_of(machine),
            dynamics: Vec::new(),
            dynamic_bindings: Vec::new(),
            context: Default::default(),
            plan: Default::default(),
        }
        .planned())
    }

    /// The model with its [`chain::Plan`] made for what it holds now.
    fn planned(mut self) -> ErrorModel {
        self.plan = chain::Plan::new(&self);
        self
    }

    /// A model with no errors.
    pub fn empty(machine: &Machine) -> ErrorModel {
        ErrorModel {
            parameters: Vec::new(),
            bindings: Vec::new(),
            slot_count: machine.slot_count(),
            machine_axes: axes_of(machine),
            dynamics: Vec::new(),
            dynamic_bindings: Vec::new(),
            context: Default::default(),
            plan: Default::default(),
        }
        .planned()
    }

    /// The model with time- and speed-dependent content (see [`Dynamics`]) added to component
    /// errors, replacing any content the model had. Each name must be a component error of an
    /// axis of `machine`, named once; content given per revolution needs a rotary axis. A
    /// parameter may have dynamics without a synchronous function.
    pub fn with_dynamics(
        mut self,
        machine: &Machine,
        mut dynamics: Vec<ParameterDynamics>,
    ) -> Result<ErrorModel, ErrorModelError> {
        self.assert_bound_to(machine);
        dynamics.retain(|d| !d.dynamics.is_empty());
        dynamics.sort_by_cached_key(|d| d.name.to_string());
        for pair in dynamics.windows(2) {
            if pair[0].name == pair[1].name {
                return Err(ErrorModelError::Duplicate(pair[0].name));
            }
        }
        let mut bindings = Vec::with_capacity(dynamics.len());
        for entry in &dynamics {
            let name = entry.name;
            let ParameterName::Component { motion, axis } = name else {
                return Err(ErrorModelError::InvalidName(
                    name,
                    "only component errors (error motions) vary with time and speed".to_string(),
                ));
            };
            let info = machine
                .axis(axis)
                .ok_or(ErrorModelError::MissingAxis { name, axis })?;
            if axis.is_linear() && entry.dynamics.has_per_revolution() {
                return Err(ErrorModelError::InvalidName(
                    name,
                    "a frequency per revolution needs an axis of rotation; give it in Hz"
                        .to_string(),
                ));
            }
            bindings.push(DynamicBinding {
                slot: info.slot,
                component: motion.index(),
                axis,
                parameter: self.parameters.iter().position(|p| p.name == name),
            });
        }
        self.dynamics = dynamics;
        self.dynamic_bindings = bindings;
        Ok(self.planned())
    }

    /// The time- and speed-dependent content, sorted by parameter name.
    pub fn dynamics(&self) -> &[ParameterDynamics] {
        &self.dynamics
    }

    /// The model with terms driven by measured temperatures and time ([`ContextTerm`]) added,
    /// replacing any it had; temperature terms read `record`, which must have their sensors.
    pub fn with_context(
        mut self,
        machine: &Machine,
        context: Vec<ParameterContext>,
        record: Option<std::sync::Arc<TemperatureRecord>>,
    ) -> Result<ErrorModel, ErrorModelError> {
        self.assert_bound_to(machine);
        self.context = context::ContextErrors::new(machine, context, record)?;
        Ok(self.planned())
    }

    /// The terms driven by measured temperatures and time, by parameter.
    pub fn context(&self) -> &[ParameterContext] {
        self.context.entries()
    }

    /// The measured temperature record the model's temperature terms read, if any.
    pub fn temperature_record(&self) -> Option<&std::sync::Arc<TemperatureRecord>> {
        self.context.record()
    }

    /// Panics when `machine` is not the machine this model was bound to (other axes or sides).
    fn assert_bound_to(&self, machine: &Machine) {
        let same = self.machine_axes.len() == machine.axes().len()
            && self
                .machine_axes
                .iter()
                .zip(machine.axes())
                .all(|(&(axis, side), info)| info.axis == axis && info.side == side);
        assert!(
            same,
            "error model bound to another machine ({:?}) used with \"{}\"",
            self.machine_axes,
            machine.name()
        );
    }

    /// The parameters, sorted by their names as text.
    pub fn parameters(&self) -> &[ErrorParameter] {
        &self.parameters
    }

    /// The parameter with this name.
    pub fn parameter(&self, name: ParameterName) -> Option<&ErrorParameter> {
        self.parameters.iter().find(|p| p.name == name)
    }

    /// Total number of linear coefficients (the columns of [`ErrorModel::jacobian`]).
    pub fn coefficient_count(&self) -> usize {
        self.parameters
            .iter()
            .map(|p| p.function.coefficient_count())
            .sum()
    }

    /// All linear coefficients (SI), parameter by parameter in the order of
    /// [`ErrorModel::parameters`].
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
        self.plan = chain::Plan::new(self);
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
        self.assert_bound_to(machine);
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
                for (row, value) in sensitivity.iter_mut().zip(column) {
                    row[component] = value;
                }
            }
        }
    }

    /// The Jacobian of the deviation `[dx, dy, dz, ti, tj]` with respect to every linear
    /// coefficient, linearised about zero error at `state`: `columns[c][row]`.
    ///
    /// `Deviation ≈ Σ_c columns[c] · coefficient_c` to first order in the errors; the
    /// difference from the exact chain is second order. To first order a squareness `ε` of a
    /// linear axis adds the relative twist `(ε × u·q, 0)`, and a rotary axis line `ξ = (δ, ε)`
    /// adds `±(ξ − Ad_R ξ) = ±(δ − Rδ, ε − Rε)` (+ on the tool side, − on the workpiece side).
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
        let mut sensitivities = std::mem::take(&mut workspace.slot_sensitivities);
        let mut basis = std::mem::take(&mut workspace.basis);
        self.slot_sensitivities(machine, workspace, state, &mut sensitivities);
        let mut column = 0;
        for (parameter, binding) in self.parameters.iter().zip(&self.bindings) {
            basis.clear();
            let component = parameter.name.motion().index();
            // The relative twist per unit of the parameter.
            let mut unit_twist = [0.0; 6];
            match binding.action {
                Action::Component(axis) => {
                    unit_twist[component] = 1.0;
                    parameter.function.basis(
                        binding.argument(state.position[axis]),
                        state.direction(axis),
                        &mut basis,
                    );
                }
                Action::Constant => {
                    unit_twist[component] = 1.0;
                    parameter
                        .function
                        .basis(0.0, Direction::Positive, &mut basis);
                }
                Action::Squareness(axis) => {
                    let translation =
                        Vector::AXES[component - 3].cross(axis.unit()) * state.position[axis];
                    unit_twist[..3].copy_from_slice(&translation.to_array());
                    parameter
                        .function
                        .basis(0.0, Direction::Positive, &mut basis);
                }
                Action::RotaryLocation(axis) => {
                    let info = &machine.axes()[binding.slot];
                    // The nominal evaluation above left the joint's rotation at this position.
                    let walked = &workspace.rotations[binding.slot];
                    let rotation = if walked.unit == info.joint_axis {
                        walked.matrix()
                    } else {
                        glam::DMat3::from_axis_angle(info.joint_axis, state.position[axis])
                    };
                    let side = if info.side == Side::Tool { 1.0 } else { -1.0 };
                    let e = Vector::AXES[component % 3];
                    let moved = (e - rotation * e) * side;
                    let offset = if component < 3 { 0 } else { 3 };
                    unit_twist[offset..offset + 3].copy_from_slice(&moved.to_array());
                    parameter
                        .function
                        .basis(0.0, Direction::Positive, &mut basis);
                }
            }
            let s = &sensitivities[binding.slot];
            for &b in &basis {
                for row in 0..5 {
                    columns[column][row] =
                        b * (0..6).map(|k| s[row][k] * unit_twist[k]).sum::<Real>();
                }
                column += 1;
            }
        }
        workspace.slot_sensitivities = sensitivities;
        workspace.basis = basis;
    }
}

impl ErrorModel {
    /// The Jacobians at many states stacked into the design matrix of a linearised estimator:
    /// five rows per state (`dx, dy, dz, ti, tj`, in that order), one column per coefficient.
    /// Its null space is what the states cannot tell apart.
    pub fn stacked_jacobian(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        states: &[MachineState],
    ) -> nalgebra::DMatrix<Real> {
        let n = self.coefficient_count();
        let mut matrix = nalgebra::DMatrix::zeros(5 * states.len(), n);
        let mut columns = vec![[0.0; 5]; n];
        for (i, state) in states.iter().enumerate() {
            self.jacobian(machine, workspace, state, &mut columns);
            for (c, column) in columns.iter().enumerate() {
                for (row, value) in column.iter().enumerate() {
                    matrix[(5 * i + row, c)] = *value;
                }
            }
        }
        matrix
    }
}

/// The axes and sides of a machine, slot by slot.
fn axes_of(machine: &Machine) -> Vec<(Axis, Side)> {
    machine
        .axes()
        .iter()
        .map(|info| (info.axis, info.side))
        .collect()
}

/// The value of a constant function.
fn constant(function: &ErrorFunction) -> Real {
    function.value(0.0, Direction::Positive)
}
