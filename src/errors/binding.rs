//! Where each parameter acts on a machine: its axis's slot in the chain and what it does
//! there ([`Action`]), as the module doc's "Where each error enters the chain" describes.

use super::error::ErrorModelError;
use super::name::ParameterName;
use crate::machine::{Axis, Machine};
use crate::math::Real;

/// What a parameter does at its slot.
#[derive(Clone, Copy, Debug)]
pub(super) enum Action {
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

/// Where a parameter acts.
#[derive(Clone, Copy, Debug)]
pub(super) struct Binding {
    pub(super) slot: usize,
    pub(super) action: Action,
    /// Its axis turns without end: the argument is taken modulo one turn, in [0, 2π).
    pub(super) periodic: bool,
}

impl Binding {
    /// Where the parameter `name` acts on `machine`.
    pub(super) fn of(machine: &Machine, name: ParameterName) -> Result<Binding, ErrorModelError> {
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
    pub(super) fn argument(&self, q: Real) -> Real {
        if self.periodic {
            q.rem_euclid(std::f64::consts::TAU)
        } else {
            q
        }
    }
}
