//! The summed first-order 21-component model of Lu (2012), Eqs. 4.11–4.18 — deliberately
//! simpler than the chain, kept to show what such a model gets wrong.
//!
//! ```text
//! V_x = −Y·(ΣZ + εz(r)) + Z·(ΣY + εy(r)) + ΔX
//! V_y = −Z·(ΣX + εx(r)) + X·(ΣZ + εz(r)) + ΔY
//! V_z = −X·(ΣY + εy(r)) + Y·(ΣX + εx(r)) + ΔZ
//! ```
//!
//! with `ΣX = EAX + EAY + EAZ` (all rotations about x), `ΔX = EXX + EXY + EXZ` (all
//! translations along x), and so on, each component evaluated at its own axis's commanded
//! position, and the squareness terms `εz(r) = EC0Y`, `εy(r) = EB0Z`, `εx(r) = EA0Z`.
//!
//! What it leaves out, by construction: every angular error turns about the reference origin
//! with the commanded position `(X, Y, Z)` as lever arm, whatever the axis's place in the
//! chain (no Abbe offset from the carriage to the tool tip, no tool length); squareness is a
//! full rotation of the point (so it also adds `X·EC0Y` to `V_y`, `−X·EB0Z` to `V_z` and
//! `Y·EA0Z` to `V_z`, which a chain does not); tool errors and spindle error motions are
//! ignored; no second-order terms. Defined for 3-axis machines only.

use super::ErrorModel;
use super::name::{Motion, ParameterName};
use crate::machine::{Axis, Machine, MachineState};
use crate::math::Vector;

/// The Lu (2012) model applies to 3-axis machines only.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the Lu (2012) summed model is defined for 3-axis machines; this one has rotary axis {0}")]
pub struct Lu2012Error(pub Axis);

/// The tool-tip deviation (m, machine = workpiece axes) by the Lu (2012) summed model.
pub fn lu2012_deviation(
    errors: &ErrorModel,
    machine: &Machine,
    state: &MachineState,
) -> Result<Vector, Lu2012Error> {
    if let Some(rotary) = machine.rotary_axes().next() {
        return Err(Lu2012Error(rotary.axis));
    }
    let mut sum_delta = Vector::ZERO; // ΔX, ΔY, ΔZ
    let mut sum_epsilon = Vector::ZERO; // ΣX, ΣY, ΣZ
    let mut squareness = Vector::ZERO; // εx(r), εy(r), εz(r)
    for parameter in errors.parameters() {
        match parameter.name {
            ParameterName::Component { motion, axis } if axis.is_linear() => {
                let value = parameter
                    .function
                    .value(state.position[axis], state.direction(axis));
                if motion.is_translation() {
                    sum_delta[motion.index()] += value;
                } else {
                    sum_epsilon[motion.index() - 3] += value;
                }
            }
            ParameterName::Location { motion, axis } if axis.is_linear() => {
                let value = parameter
                    .function
                    .value(0.0, crate::machine::Direction::Positive);
                debug_assert!(matches!(motion, Motion::A | Motion::B | Motion::C));
                squareness[motion.index() - 3] += value;
            }
            // Spindle error motions and tool errors are not part of the 21-component model.
            _ => {}
        }
    }
    let p = Vector::new(
        state.position[Axis::X],
        state.position[Axis::Y],
        state.position[Axis::Z],
    );
    let angle = sum_epsilon + squareness;
    Ok(Vector::new(
        -p.y * angle.z + p.z * angle.y + sum_delta.x,
        -p.z * angle.x + p.x * angle.z + sum_delta.y,
        -p.x * angle.y + p.y * angle.x + sum_delta.z,
    ))
}
