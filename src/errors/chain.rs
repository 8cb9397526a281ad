//! The exact chain with errors: an [`ErrorModel`]'s slot twists at a machine state, the slot
//! motions they make, and the actual tool pose.
//!
//! # What is computed once, and why
//!
//! A pose should cost what varies from pose to pose and nothing else. When the model is built
//! or its coefficients change, a [`Plan`] records:
//!
//! - the sum of the constant parameters of every twist component that nothing varying acts
//!   on, so that a pose evaluates only the functions of position, the dynamics and the context
//!   terms, each summed in the order the sums have always had;
//! - the small motion `Trans(δ)·Exp(ε)` of every slot whose relative twist never varies;
//! - for an axis line that never varies, its pose `L` and `L⁻¹` (rotary axes) or the tilt
//!   `Exp(ε)·u − u` of the line of travel (linear axes);
//! - harmonics of a rotary axis with a whole number of periods per turn as a
//!   [`TurnSeries`], evaluated from the sine and cosine of the axis angle;
//! - which slots vary ([`Plan::active`]): a [`Workspace`] remembers whose fixed slot motions
//!   it holds ([`Plan::id`]), so a run of poses of one model sums and builds only the
//!   varying ones (an evaluation with extra twists, or with another model or explicit motions
//!   in between, makes them all again).
//!
//! Each joint's `Rot(u, q)` is computed once per pose, shared by the axis-line motions, the
//! harmonics and the walk ([`Workspace`]), and products leave out the terms of exact identities
//! and zeros (an identity rotation, a pure translation or rotation, the zeros of a rotation
//! about a coordinate axis).
//!
//! A rotary axis of the workpiece branch whose line is located (`L`) is not given a slot
//! motion: its slot motion `M = (L·R·L⁻¹·R⁻¹)⁻¹ · rel`, applied inverted before `R`, is
//! `rel⁻¹ · L · R · L⁻¹`, which the walk computes instead ([`AxisLine`]), with a fixed `rel⁻¹`
//! folded into `L` once, and with a varying one as `rel⁻¹` then `L·R·L⁻¹` built at once by
//! Rodrigues' formula about the located axis. That regrouping moves the pose by a few units
//! in the last place (the tests allow 8 ε, 1.8e-15 of a metre-sized entry); every other
//! operation is the plain composition's, in its order, so models without such a line give the
//! plain chain's poses, slot motions and slot frames to the bit (but for the sign of exact
//! zeros), and the per-turn harmonics differ by ulps of their amplitudes. [`ErrorModel::slot_motions`] gives the whole
//! slot motions when they are needed. Nothing allocates.

mod plan;
#[cfg(test)]
mod tests;

pub(super) use plan::Plan;
use plan::{Line, Value, apply_line, line_geometry, small_motion_of};

use super::ErrorModel;
use super::deviation::Deviation;
use crate::machine::{JointRotation, Machine, MachineState, MotionKind, Workspace};
use crate::math::{Pose, Real};

impl ErrorModel {
    /// Sums the parameters acting at each slot (SI): `relative[slot]`, the twist
    /// `(δx, δy, δz, εx, εy, εz)` of the tool relative to the workpiece from component, tool and
    /// zero-position errors; `line[slot]`, the location of the axis line (translation and
    /// rotation for a rotary axis, rotation only for a linear one). Component errors with
    /// [`super::Dynamics`] add their asynchronous content at `state.time` and the axis's
    /// unwrapped position, and scale by their speed factor at `state.velocity`;
    /// [`super::ContextTerm`]s add their value at `state.time`.
    pub fn slot_twists(
        &self,
        state: &MachineState,
        relative: &mut [[Real; 6]],
        line: &mut [[Real; 6]],
    ) {
        self.sum_twists(state, None, relative, line, true);
    }

    /// [`ErrorModel::slot_twists`], with the joint rotations at `state.position` when the
    /// caller has them (their sines and cosines serve the harmonics of rotary axes). Without
    /// `all`, only the varying relative twists are summed (an evaluation takes the fixed ones'
    /// motions from the plan), and `line` is left as it was when no line varies.
    fn sum_twists(
        &self,
        state: &MachineState,
        rotations: Option<&[JointRotation]>,
        relative: &mut [[Real; 6]],
        line: &mut [[Real; 6]],
        all: bool,
    ) {
        assert_eq!(relative.len(), self.slot_count, "one twist per slot");
        assert_eq!(line.len(), self.slot_count, "one line location per slot");
        if all {
            relative.copy_from_slice(&self.plan.base_relative);
        } else {
            for &slot in &self.plan.varying {
                relative[slot] = self.plan.base_relative[slot];
            }
        }
        if all || self.plan.varying_lines {
            line.copy_from_slice(&self.plan.base_line);
        }
        for term in &self.plan.terms {
            let value = match &term.value {
                Value::Fixed(value) => *value,
                Value::Function(axis) => self.parameters[term.parameter].function.value(
                    self.bindings[term.parameter].argument(state.position[*axis]),
                    state.direction(*axis),
                ),
                Value::Turn(axis, series) => {
                    let (sin, cos) = match rotations {
                        Some(rotations) => rotations[term.slot].sin_cos,
                        None => state.position[*axis].sin_cos(),
                    };
                    series.value(sin, cos)
                }
            };
            let target = if term.on_line {
                &mut *line
            } else {
                &mut *relative
            };
            target[term.slot][term.component] += value;
        }
        for (entry, binding) in self.dynamics.iter().zip(&self.dynamic_bindings) {
            let q = state.position[binding.axis];
            let factor = entry.dynamics.factor(state.velocity[binding.axis]);
            let mut value = factor * entry.dynamics.asynchronous(state.time, q);
            if let Some(index) = binding.parameter.filter(|_| factor != 1.0) {
                value += (factor - 1.0)
                    * self.parameters[index].function.value(
                        self.bindings[index].argument(q),
                        state.direction(binding.axis),
                    );
            }
            relative[binding.slot][binding.component] += value;
        }
        self.context.add(state, relative, line);
    }

    /// The actual tool pose seen from the workpiece: the exact chain with every slot motion.
    ///
    /// At each slot the motion is `line · relative`: `relative = Trans(δ) · Exp(ε)` from
    /// [`ErrorModel::slot_twists`], and `line` the effect of the axis line's location, exactly:
    /// a linear axis at `q` travelling along `Exp(ε_line) · u` instead of `u` adds the translation
    /// `(Exp(ε_line) − I) · u · q`; a rotary axis turning by `R = Rot(axis, q)` about the line
    /// `L = Trans(δ_line) · Exp(ε_line)` instead of its nominal line moves what it carries by
    /// `L · R · L⁻¹ · R⁻¹` (as seen on the tool side; inverted on the workpiece side, because
    /// the line is physical while the slot motion is tool-relative).
    pub fn workpiece_from_tool(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
    ) -> Pose {
        self.evaluate(machine, workspace, state, None, true)
    }

    /// The slot motions at `state`, with `extra` as in [`ErrorModel::workpiece_from_tool_with`]
    /// (one per slot, each `line · relative` as [`ErrorModel::workpiece_from_tool`] describes
    /// them): what the workspace's nominal walk needs to reproduce the actual pose. Leaves
    /// `workspace` as that evaluation does.
    pub(crate) fn slot_motions(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
        extra: Option<&[[Real; 6]]>,
    ) -> Vec<Pose> {
        self.evaluate(machine, workspace, state, extra, true);
        let mut motions = workspace.slot_motions.clone();
        // The slots whose line the walk turned about hold their relative motion only.
        for (slot, line) in self.plan.lines.iter().enumerate() {
            let (Some(_), Some(info)) = (line, machine.axes().get(slot)) else {
                continue;
            };
            let mut kind = match workspace.motion_kinds[slot] {
                MotionKind::InLine => MotionKind::General,
                kind => kind,
            };
            let q = state.position[info.axis];
            let rotation = &workspace.rotations[slot];
            let geometry = &self.plan.slots[slot].line;
            apply_line(geometry, info, q, rotation, &mut motions[slot], &mut kind);
        }
        motions
    }

    /// [`ErrorModel::workpiece_from_tool`] with `extra` relative twists added at each slot
    /// (one per slot, SI, in the slot frames): how thermal terms
    /// ([`crate::thermal::ThermalErrors`]) enter the chain.
    pub fn workpiece_from_tool_with(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
        extra: Option<&[[Real; 6]]>,
    ) -> Pose {
        self.evaluate(machine, workspace, state, extra, true)
    }

    /// Actual − nominal at `state`, by the exact chain.
    pub fn deviation(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
    ) -> Deviation {
        let nominal = workspace.workpiece_from_tool(machine, &state.position, None);
        // The nominal evaluation left the joint rotations at this position.
        let actual = self.evaluate(machine, workspace, state, None, false);
        Deviation::between(&nominal, &actual)
    }

    /// The actual pose; `set_rotations: false` when `workspace` already holds the joint
    /// rotations at `state.position`.
    fn evaluate(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
        extra: Option<&[[Real; 6]]>,
        set_rotations: bool,
    ) -> Pose {
        self.assert_bound_to(machine);
        workspace.assert_sized_for(machine);
        let mut relative = std::mem::take(&mut workspace.slot_twists);
        let mut line = std::mem::take(&mut workspace.slot_lines);
        let mut motions = std::mem::take(&mut workspace.slot_motions);
        let mut kinds = std::mem::take(&mut workspace.motion_kinds);
        if set_rotations {
            workspace.set_rotations(machine, &state.position);
        }
        let rotations = Some(&workspace.rotations[..]);
        self.sum_twists(state, rotations, &mut relative, &mut line, extra.is_some());
        if let Some(extra) = extra {
            assert_eq!(extra.len(), relative.len(), "one extra twist per slot");
            for (twist, add) in relative.iter_mut().zip(extra) {
                for (value, a) in twist.iter_mut().zip(add) {
                    *value += a;
                }
            }
        }
        // The fixed motions stay in a workspace that holds this plan's; the others are made.
        let keeps = extra.is_none() && self.plan.id != 0 && workspace.motions_plan == self.plan.id;
        let slots = if keeps {
            &self.plan.active[..]
        } else {
            &self.plan.all[..]
        };
        for &slot in slots {
            let plan = &self.plan.slots[slot];
            let extra_here = extra.is_some_and(|extra| extra[slot] != [0.0; 6]);
            (motions[slot], kinds[slot]) = match plan.relative {
                Some(fixed) if !extra_here => fixed,
                _ => small_motion_of(&relative[slot]),
            };
            let Some(info) = machine.axes().get(slot) else {
                continue; // the tool slot
            };
            if self.plan.lines[slot].is_some() {
                // The walk turns about the line, with the fixed relative motion folded in.
                if plan.relative.is_some() && !extra_here {
                    kinds[slot] = MotionKind::InLine;
                }
                continue;
            }
            let varying;
            let geometry = match &plan.line {
                Line::Nominal => continue,
                Line::Varying => {
                    varying = line_geometry(info.axis.is_linear(), info.axis.unit(), &line[slot]);
                    &varying
                }
                fixed => fixed,
            };
            let (motion, kind) = (&mut motions[slot], &mut kinds[slot]);
            let q = state.position[info.axis];
            apply_line(geometry, info, q, &workspace.rotations[slot], motion, kind);
        }
        // With extra twists, a fixed slot may hold another motion.
        workspace.motions_plan = if extra.is_none() { self.plan.id } else { 0 };
        let pose = workspace.walk_both(
            machine,
            &state.position,
            Some((&motions, &kinds, Some(&self.plan.lines))),
        );
        workspace.slot_twists = relative;
        workspace.slot_lines = line;
        workspace.slot_motions = motions;
        workspace.motion_kinds = kinds;
        pose
    }
}
