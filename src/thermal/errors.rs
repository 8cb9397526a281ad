//! Temperatures → errors: thermal terms that move the tool relative to the workpiece as
//! functions of node temperatures, added to the error model's slots (see
//! [`crate::errors::ErrorModel::workpiece_from_tool_with`]).
//!
//! - **Screw expansion** of a linear axis: the screw expands from its fixed (thrust-bearing)
//!   end, so commanding q puts the nut at `(q − q_fixed)·(1 + α·ΔT)` from that end: a
//!   positioning error `α·(T_screw − T_ref)·(q − q_fixed)`. With the origin at the fixed end
//!   (`q_fixed = 0`) the error grows along the axis from zero; with the origin at the free end
//!   the origin itself drifts by `−α·ΔT·q_fixed` (Lu 2012 §2.10). Driven by the *screw*
//!   temperature, which lags the nut's.
//! - **Spindle growth**: the spindle nose grows towards the workpiece, moving the tool tip along
//!   −z of the tool frame by `k·(T − T_ref)`.
//! - **Column tilt**: a front–back temperature difference bends the column; modelled as a tilt
//!   of the head about X, `EAZ += c·(T_front − T_back)`, acting at the Z slot (after the Z
//!   travel), which the chain turns into Y and Z errors with the head's lever arm. "Front" is
//!   the column's face towards the workpiece; the sign of `c` says which way the head turns.
//!   Simplified: a uniform tilt of the head only — the bending shift of the head (about ε·H/2
//!   for a column of height H) and the tilt of the Z guideways themselves are not modelled.

use crate::machine::{Axis, Machine, MachineState};
use crate::math::Real;

/// One thermal error term (SI: 1/K, m/K, rad/K, °C).
#[derive(Clone, Debug, PartialEq)]
pub enum ThermalTerm {
    /// Positioning error of a linear axis from its screw's expansion.
    ScrewExpansion {
        /// The axis.
        axis: Axis,
        /// Network node of the screw.
        screw: usize,
        /// Expansion coefficient (1/K): 11.7e-6 for steel.
        expansion: Real,
        /// Axis position of the fixed (thrust-bearing) end (m).
        fixed_end: Real,
        /// Temperature at which the screw has its nominal length (°C).
        reference: Real,
    },
    /// Axial growth of the spindle towards the workpiece.
    SpindleGrowth {
        /// Network node of the spindle housing or bearing.
        node: usize,
        /// Growth per kelvin (m/K).
        growth: Real,
        /// Temperature with no growth (°C).
        reference: Real,
    },
    /// Tilt of the head about X from a front–back temperature difference of the column.
    ColumnTilt {
        /// Node of the column's front.
        front: usize,
        /// Node of the column's back.
        back: usize,
        /// Tilt per kelvin of difference (rad/K).
        tilt: Real,
    },
}

/// Why a thermal term does not fit the machine or the network.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ThermalTermError {
    /// The term names an axis the machine lacks (or screw expansion on a rotary axis).
    #[error("the machine has no linear axis {0}")]
    Axis(Axis),
    /// The term names a node the network lacks.
    #[error("node index {0} is not in the network")]
    Node(usize),
    /// A coefficient that is not finite.
    #[error("a coefficient of a thermal term is not a finite number")]
    NotFinite,
}

/// Thermal error terms bound to a machine and a network of `node_count` nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct ThermalErrors {
    terms: Vec<(ThermalTerm, usize)>,
    slot_count: usize,
}

impl ThermalErrors {
    /// Binds `terms` to `machine` (slots) and checks their node indices against `node_count`.
    pub fn new(
        machine: &Machine,
        node_count: usize,
        terms: Vec<ThermalTerm>,
    ) -> Result<ThermalErrors, ThermalTermError> {
        let mut bound = Vec::with_capacity(terms.len());
        for term in terms {
            let (nodes, numbers, slot): (Vec<usize>, Vec<Real>, usize) = match &term {
                ThermalTerm::ScrewExpansion {
                    axis,
                    screw,
                    expansion,
                    fixed_end,
                    reference,
                } => {
                    let info = machine
                        .axis(*axis)
                        .filter(|i| i.axis.is_linear())
                        .ok_or(ThermalTermError::Axis(*axis))?;
                    (
                        vec![*screw],
                        vec![*expansion, *fixed_end, *reference],
                        info.slot,
                    )
                }
                ThermalTerm::SpindleGrowth {
                    node,
                    growth,
                    reference,
                } => (vec![*node], vec![*growth, *reference], machine.tool_slot()),
                ThermalTerm::ColumnTilt { front, back, tilt } => {
                    let info = machine
                        .axis(Axis::Z)
                        .ok_or(ThermalTermError::Axis(Axis::Z))?;
                    (vec![*front, *back], vec![*tilt], info.slot)
                }
            };
            if let Some(&bad) = nodes.iter().find(|&&n| n >= node_count) {
                return Err(ThermalTermError::Node(bad));
            }
            if !numbers.iter().all(|v| v.is_finite()) {
                return Err(ThermalTermError::NotFinite);
            }
            bound.push((term, slot));
        }
        Ok(ThermalErrors {
            terms: bound,
            slot_count: machine.slot_count(),
        })
    }

    /// The terms.
    pub fn terms(&self) -> impl Iterator<Item = &ThermalTerm> {
        self.terms.iter().map(|(term, _)| term)
    }

    /// The relative twists `(δx, δy, δz, εx, εy, εz)` per slot (SI) at node `temperatures`
    /// (°C) and machine `state`, in the slot frames the error model uses.
    pub fn slot_twists(&self, temperatures: &[Real], state: &MachineState, out: &mut [[Real; 6]]) {
        assert_eq!(out.len(), self.slot_count, "one twist per slot");
        out.iter_mut().for_each(|t| *t = [0.0; 6]);
        for (term, slot) in &self.terms {
            match *term {
                ThermalTerm::ScrewExpansion {
                    axis,
                    screw,
                    expansion,
                    fixed_end,
                    reference,
                } => {
                    let error = expansion
                        * (temperatures[screw] - reference)
                        * (state.position[axis] - fixed_end);
                    out[*slot][axis.coordinate()] += error;
                }
                ThermalTerm::SpindleGrowth {
                    node,
                    growth,
                    reference,
                } => {
                    out[*slot][2] -= growth * (temperatures[node] - reference);
                }
                ThermalTerm::ColumnTilt { front, back, tilt } => {
                    out[*slot][3] += tilt * (temperatures[front] - temperatures[back]);
                }
            }
        }
    }
}
