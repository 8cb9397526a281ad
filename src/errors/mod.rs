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

mod binding;
mod chain;
mod context;
mod deviation;
mod dynamics;
mod error;
mod function;
mod lu2012;
mod name;
mod record;

pub use context::{ContextTerm, Driver, ParameterContext};
pub use deviation::Deviation;
pub use dynamics::{Dynamics, Frequency, ParameterDynamics, RandomMotion, Sinusoid};
pub use error::ErrorModelError;
pub use function::{ErrorFunction, Interpolation, Table, TableError};
pub use lu2012::{Lu2012Error, lu2012_deviation};
pub use name::{Motion, ParameterName};
pub use record::TemperatureRecord;

use crate::machine::{Axis, Direction, Machine, Side};
use crate::math::Real;
use binding::{Action, Binding};

/// An injected error: a name and a function.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorParameter {
    /// ISO 230-1 name.
    pub name: ParameterName,
    /// How it varies (SI).
    pub function: ErrorFunction,
}

/// A set of error parameters bound to a machine: immutable and shareable; evaluations use the
/// machine's [`Workspace`](crate::machine::Workspace).
#[derive(Clone, Debug)]
pub struct ErrorModel {
    parameters: Vec<ErrorParameter>,
    bindings: Vec<Binding>,
    slot_count: usize,
    /// The axes (and their sides) of the machine it was bound to, slot by slot.
    machine_axes: Vec<(Axis, Side)>,
    /// Their joint axes in their joint frames (`AxisInfo::joint_axis`), slot by slot.
    joint_axes: Vec<crate::math::Vector>,
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
            joint_axes: machine.axes().iter().map(|info| info.joint_axis).collect(),
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
            joint_axes: machine.axes().iter().map(|info| info.joint_axis).collect(),
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

    /// Panics when `machine` is not the machine this model was bound to (other axes, sides or
    /// joint directions).
    ///
    /// The joint directions are compared where the plan depends on them: it turns a located
    /// rotary line about the bound machine's joint axis ([`chain::Plan`]), and two machines
    /// with the same axes on the same sides may differ there (an identified machine's axes are
    /// tilted from the nominal one's by µrad), so one must not pass for the other.
    fn assert_bound_to(&self, machine: &Machine) {
        let axes = machine.axes();
        let same = self.machine_axes.len() == axes.len()
            && self
                .machine_axes
                .iter()
                .zip(axes)
                .all(|(&(axis, side), info)| info.axis == axis && info.side == side)
            && self
                .plan
                .line_slots
                .iter()
                .all(|&slot| axes[slot].joint_axis == self.joint_axes[slot]);
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
