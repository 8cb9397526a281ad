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
//!   [`TurnSeries`], evaluated from the sine and cosine of the axis angle.
//!
//! Each joint's `Rot(u, q)` is computed once per pose, shared by the axis-line motions, the
//! harmonics and the walk ([`Workspace`]), and products leave out the terms of exact identities
//! and zeros (an identity rotation, a pure translation or rotation, the zeros of a rotation
//! about a coordinate axis).
//!
//! A rotary axis of the workpiece branch whose line is located (`L`) is not given a slot
//! motion: its slot motion `M = (L·R·L⁻¹·R⁻¹)⁻¹ · rel`, applied inverted before `R`, is
//! `rel⁻¹ · L · R · L⁻¹`, which the walk computes instead ([`AxisLine`]), with a fixed `rel⁻¹`
//! folded into `L` once. That regrouping moves the pose by a few units in the last place
//! (the tests allow 8 ε, 1.8e-15 of a metre-sized entry); every other operation is the plain
//! composition's, in its order, so models without such a line give the plain chain's poses,
//! slot motions and slot frames to the bit (but for the sign of exact zeros), and the per-turn
//! harmonics differ by ulps of their amplitudes. [`ErrorModel::slot_motions`] gives the whole
//! slot motions when they are needed. Nothing allocates.

use super::ErrorModel;
use super::binding::Action;
use super::deviation::Deviation;
use super::function::TurnSeries;
use crate::machine::{
    Axis, AxisInfo, AxisLine, JointRotation, Machine, MachineState, MotionKind, Side, Workspace,
    then_motion,
};
use crate::math::{Pose, Real, Vector, rigid_inverse, small_motion};

/// What an evaluation of an [`ErrorModel`] does not recompute (see the module documentation).
#[derive(Clone, Debug, Default)]
pub(super) struct Plan {
    /// Per slot, the constant parameters' sum of each relative-twist component no varying
    /// term acts on (zero for the others).
    base_relative: Vec<[Real; 6]>,
    /// The same for the axis-line locations.
    base_line: Vec<[Real; 6]>,
    /// Every parameter acting on a component that varies, in parameter order.
    terms: Vec<Term>,
    /// Per slot, its motion's fixed parts.
    slots: Vec<SlotPlan>,
    /// Whether any axis line is [`Line::Varying`].
    varying_lines: bool,
    /// Per slot, the fixed line of a rotary axis on the workpiece branch, which the walk turns
    /// about itself (`None` for the others, whose line motion is in the slot motion).
    lines: Vec<Option<AxisLine>>,
}

/// A parameter summed at each pose.
#[derive(Clone, Debug)]
struct Term {
    /// Index in [`ErrorModel::parameters`].
    parameter: usize,
    slot: usize,
    component: usize,
    /// Whether it locates the axis line (else it adds to the relative twist).
    on_line: bool,
    value: Value,
}

/// How a [`Term`] gets its value.
#[derive(Clone, Debug)]
enum Value {
    /// A constant.
    Fixed(Real),
    /// Its function of the axis position ([`super::ErrorFunction::value`]).
    Function(Axis),
    /// Harmonics of a rotary axis, from the sine and cosine of its angle.
    Turn(Axis, TurnSeries),
}

/// The fixed parts of one slot's motion.
#[derive(Clone, Copy, Debug)]
struct SlotPlan {
    /// The relative twist's small motion and its kind, when the twist never varies.
    relative: Option<(Pose, MotionKind)>,
    /// The axis line.
    line: Line,
}

/// An axis line's fixed geometry.
#[derive(Clone, Copy, Debug)]
enum Line {
    /// At its nominal place: no line motion.
    Nominal,
    /// A linear axis's line of travel `Exp(ε)·u` instead of `u`: `tilt = Exp(ε)·u − u`.
    Linear { tilt: Vector },
    /// A rotary axis line `L` and `L⁻¹`.
    Rotary { pose: Pose, inverse: Pose },
    /// Context terms move it: computed at each pose.
    Varying,
}

impl Plan {
    /// The plan of `model` as it is now.
    pub(super) fn new(model: &ErrorModel) -> Plan {
        let slots = model.slot_count;
        // varies[slot][on_line][component]
        let mut varies = vec![[[false; 6]; 2]; slots];
        for (parameter, binding) in model.parameters.iter().zip(&model.bindings) {
            if matches!(binding.action, Action::Component(_)) && !parameter.function.is_constant() {
                varies[binding.slot][0][parameter.name.motion().index()] = true;
            }
        }
        for binding in &model.dynamic_bindings {
            varies[binding.slot][0][binding.component] = true;
        }
        for (slot, component, on_line) in model.context.targets() {
            varies[slot][usize::from(on_line)][component] = true;
        }

        let mut base = vec![[[0.0; 6]; 2]; slots];
        let mut terms = Vec::new();
        for (index, (parameter, binding)) in
            model.parameters.iter().zip(&model.bindings).enumerate()
        {
            let component = parameter.name.motion().index();
            let on_line = matches!(
                binding.action,
                Action::Squareness(_) | Action::RotaryLocation(_)
            );
            let value = match binding.action {
                Action::Component(axis) if !parameter.function.is_constant() => {
                    match parameter.function.turn_series() {
                        Some(series) if !axis.is_linear() => Value::Turn(axis, series),
                        _ => Value::Function(axis),
                    }
                }
                _ => Value::Fixed(super::constant(&parameter.function)),
            };
            if varies[binding.slot][usize::from(on_line)][component] {
                terms.push(Term {
                    parameter: index,
                    slot: binding.slot,
                    component,
                    on_line,
                    value,
                });
            } else {
                let Value::Fixed(value) = value else {
                    unreachable!("a component nothing varies on has constants only")
                };
                base[binding.slot][usize::from(on_line)][component] += value;
            }
        }

        let plans: Vec<SlotPlan> = (0..slots)
            .map(|slot| {
                let [relative, line] = base[slot];
                let relative =
                    (!varies[slot][0].contains(&true)).then(|| small_motion_of(&relative));
                let line = match model.machine_axes.get(slot) {
                    _ if varies[slot][1].contains(&true) => Line::Varying,
                    Some(&(axis, _)) => line_geometry(axis.is_linear(), axis.unit(), &line),
                    None => Line::Nominal,
                };
                SlotPlan { relative, line }
            })
            .collect();
        let lines = plans
            .iter()
            .zip(&model.machine_axes)
            .map(|(plan, (_, side))| match (plan.line, side) {
                (Line::Rotary { pose, inverse }, Side::Workpiece) => Some(AxisLine {
                    pose,
                    folded: match plan.relative {
                        Some((relative, _)) => rigid_inverse(&relative) * pose,
                        None => pose,
                    },
                    inverse,
                }),
                _ => None,
            })
            .chain(std::iter::repeat(None))
            .take(slots)
            .collect();
        Plan {
            base_relative: base.iter().map(|b| b[0]).collect(),
            base_line: base.iter().map(|b| b[1]).collect(),
            terms,
            varying_lines: plans.iter().any(|plan| matches!(plan.line, Line::Varying)),
            slots: plans,
            lines,
        }
    }
}

/// The small motion `Trans(δ)·Exp(ε)` of a twist `(δ, ε)` and its kind (with `ε = 0` exactly
/// the rotation is the identity, and no series is evaluated).
#[inline(always)]
fn small_motion_of(t: &[Real; 6]) -> (Pose, MotionKind) {
    let delta = Vector::new(t[0], t[1], t[2]);
    if t[3] == 0.0 && t[4] == 0.0 && t[5] == 0.0 {
        let kind = if delta == Vector::ZERO {
            MotionKind::Identity
        } else {
            MotionKind::Translation
        };
        (Pose::from_translation(delta), kind)
    } else {
        let motion = small_motion(delta, Vector::new(t[3], t[4], t[5]));
        let kind = if delta == Vector::ZERO {
            MotionKind::Rotation
        } else {
            MotionKind::General
        };
        (motion, kind)
    }
}

/// The geometry of an axis line located by `l` (translation and rotation) for an axis along
/// `direction`.
fn line_geometry(linear: bool, direction: Vector, l: &[Real; 6]) -> Line {
    if *l == [0.0; 6] {
        Line::Nominal
    } else if linear {
        let tilted = small_motion(Vector::ZERO, Vector::new(l[3], l[4], l[5])).matrix3 * direction;
        Line::Linear {
            tilt: tilted - direction,
        }
    } else {
        let pose = small_motion(Vector::new(l[0], l[1], l[2]), Vector::new(l[3], l[4], l[5]));
        Line::Rotary {
            pose,
            inverse: rigid_inverse(&pose),
        }
    }
}

/// Turns the slot motion `relative` (of kind `kind`) into `line · relative`, for an axis whose
/// line has the fixed geometry `line` at `q`, turning by `rotation` there when rotary.
#[inline]
fn apply_line(
    line: &Line,
    info: &AxisInfo,
    q: Real,
    rotation: &JointRotation,
    relative: &mut Pose,
    kind: &mut MotionKind,
) {
    match line {
        Line::Nominal | Line::Varying => {}
        Line::Linear { tilt } => {
            // Trans((Exp(ε)·u − u)·q) · relative.
            relative.translation += *tilt * q;
            *kind = match kind {
                MotionKind::Identity | MotionKind::Translation => MotionKind::Translation,
                MotionKind::Rotation | MotionKind::General | MotionKind::InLine => {
                    MotionKind::General
                }
            };
        }
        Line::Rotary { pose, inverse } => {
            // L · R · L⁻¹ · R⁻¹ (R's translation is zero), as seen from the tool side.
            let own;
            let rotation = if rotation.unit == info.joint_axis {
                rotation
            } else {
                own = JointRotation::new(info.joint_axis, q);
                &own
            };
            let turned =
                Pose::from_mat3_translation(rotation.right_of(&pose.matrix3), pose.translation);
            let back = turned * *inverse;
            let carried = Pose::from_mat3_translation(
                rotation.transpose().right_of(&back.matrix3),
                back.translation,
            );
            let carried = match info.side {
                Side::Tool => carried,
                Side::Workpiece => rigid_inverse(&carried),
            };
            *relative = then_motion(&carried, relative, *kind);
            *kind = MotionKind::General;
        }
    }
}

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
        self.sum_twists(state, None, relative, line);
    }

    /// [`ErrorModel::slot_twists`], with the joint rotations at `state.position` when the
    /// caller has them (their sines and cosines serve the harmonics of rotary axes). With them
    /// (an evaluation), `line` is filled only when some line varies: the evaluation takes the
    /// fixed ones from the plan.
    fn sum_twists(
        &self,
        state: &MachineState,
        rotations: Option<&[JointRotation]>,
        relative: &mut [[Real; 6]],
        line: &mut [[Real; 6]],
    ) {
        assert_eq!(relative.len(), self.slot_count, "one twist per slot");
        assert_eq!(line.len(), self.slot_count, "one line location per slot");
        relative.copy_from_slice(&self.plan.base_relative);
        // An evaluation reads the line locations only where context terms move them.
        if rotations.is_none() || self.plan.varying_lines {
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
        self.sum_twists(state, Some(&workspace.rotations), &mut relative, &mut line);
        if let Some(extra) = extra {
            assert_eq!(extra.len(), relative.len(), "one extra twist per slot");
            for (twist, add) in relative.iter_mut().zip(extra) {
                for (value, a) in twist.iter_mut().zip(add) {
                    *value += a;
                }
            }
        }
        for (slot, plan) in self.plan.slots.iter().enumerate() {
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

#[cfg(test)]
mod tests {
    //! The planned evaluation against the plain composition it replaces, on every bundled
    //! machine with errors of every kind: the same poses, slot frames and slot motions to the
    //! bit (`==`, which does not tell the signs of zero apart).
    use super::*;
    use crate::errors::{
        ContextTerm, Driver, Dynamics, ErrorFunction, ErrorParameter, Frequency, Interpolation,
        ParameterContext, ParameterDynamics, ParameterName, Sinusoid, Table,
    };
    use crate::machine::{Axis, Direction, axis_angle, plain_workpiece_from_tool, random_position};
    use crate::math::seeded_rng;
    use rand::RngExt;
    use rand_chacha::ChaCha8Rng;
    use std::f64::consts::TAU;

    /// The slot motions as mtwin built them before the plan: every parameter summed at every
    /// pose, every small motion and axis-line motion composed in full.
    fn plain_motions(
        model: &ErrorModel,
        machine: &Machine,
        state: &MachineState,
        extra: Option<&[[Real; 6]]>,
    ) -> Vec<Pose> {
        let slots = machine.slot_count();
        let (mut relative, mut line) = (vec![[0.0; 6]; slots], vec![[0.0; 6]; slots]);
        for (parameter, binding) in model.parameters.iter().zip(&model.bindings) {
            let component = parameter.name.motion().index();
            match binding.action {
                Action::Component(axis) => {
                    relative[binding.slot][component] += parameter.function.value(
                        binding.argument(state.position[axis]),
                        state.direction(axis),
                    );
                }
                Action::Constant => {
                    relative[binding.slot][component] += super::super::constant(&parameter.function)
                }
                Action::Squareness(_) | Action::RotaryLocation(_) => {
                    line[binding.slot][component] += super::super::constant(&parameter.function);
                }
            }
        }
        for (entry, binding) in model.dynamics.iter().zip(&model.dynamic_bindings) {
            let q = state.position[binding.axis];
            let factor = entry.dynamics.factor(state.velocity[binding.axis]);
            let mut value = factor * entry.dynamics.asynchronous(state.time, q);
            if let Some(index) = binding.parameter.filter(|_| factor != 1.0) {
                value += (factor - 1.0)
                    * model.parameters[index].function.value(
                        model.bindings[index].argument(q),
                        state.direction(binding.axis),
                    );
            }
            relative[binding.slot][binding.component] += value;
        }
        model.context.add(state, &mut relative, &mut line);
        if let Some(extra) = extra {
            for (twist, add) in relative.iter_mut().zip(extra) {
                for (value, a) in twist.iter_mut().zip(add) {
                    *value += a;
                }
            }
        }
        (0..slots)
            .map(|slot| {
                let t = relative[slot];
                let motion =
                    small_motion(Vector::new(t[0], t[1], t[2]), Vector::new(t[3], t[4], t[5]));
                let l = line[slot];
                if l == [0.0; 6] {
                    return motion;
                }
                let info = &machine.axes()[slot];
                let q = state.position[info.axis];
                let line_motion = if info.axis.is_linear() {
                    let direction = info.axis.unit();
                    let tilted = small_motion(Vector::ZERO, Vector::new(l[3], l[4], l[5])).matrix3
                        * direction;
                    Pose::from_translation((tilted - direction) * q)
                } else {
                    let line_pose =
                        small_motion(Vector::new(l[0], l[1], l[2]), Vector::new(l[3], l[4], l[5]));
                    let rotation = Pose::from_mat3(axis_angle(info.joint_axis, q));
                    let carried =
                        line_pose * rotation * rigid_inverse(&line_pose) * rigid_inverse(&rotation);
                    match info.side {
                        Side::Tool => carried,
                        Side::Workpiece => rigid_inverse(&carried),
                    }
                };
                line_motion * motion
            })
            .collect()
    }

    fn small(rng: &mut ChaCha8Rng) -> Real {
        rng.random_range(-2e-5..2e-5)
    }

    /// A function of every kind the axis allows (a continuous axis's repeat every turn). With
    /// `whole_turns`, harmonics of rotary axes have a whole number of periods per turn (a
    /// [`TurnSeries`]); without, continuous axes have none.
    fn function(
        rng: &mut ChaCha8Rng,
        continuous: bool,
        travel: (Real, Real),
        whole_turns: bool,
    ) -> ErrorFunction {
        let harmonic = |rng: &mut ChaCha8Rng| ErrorFunction::Harmonic {
            period: if whole_turns {
                TAU / rng.random_range(1..4) as Real
            } else {
                (travel.1 - travel.0) / rng.random_range(0.5..7.0)
            },
            amplitude: small(rng),
            phase: rng.random_range(0.0..TAU),
        };
        if continuous && !whole_turns {
            return ErrorFunction::Reversal(small(rng));
        }
        let table = |rng: &mut ChaCha8Rng| {
            let (low, high) = if continuous { (0.0, TAU) } else { travel };
            let n = rng.random_range(2..7);
            let positions = (0..n)
                .map(|i| low + (high - low) * i as Real / (n - 1) as Real)
                .collect();
            let mut values: Vec<Real> = (0..n).map(|_| small(rng)).collect();
            if continuous {
                values[n - 1] = values[0];
            }
            let interpolation = if rng.random_bool(0.5) {
                Interpolation::Linear
            } else {
                Interpolation::Cubic
            };
            ErrorFunction::Table(Table::new(positions, values, interpolation).unwrap())
        };
        match rng.random_range(0..6) {
            0 => ErrorFunction::Constant(small(rng)),
            1 if !continuous => ErrorFunction::Polynomial((0..4).map(|_| small(rng)).collect()),
            2 => table(rng),
            3 => ErrorFunction::Reversal(small(rng)),
            4 => ErrorFunction::Sum(vec![
                ErrorFunction::Constant(small(rng)),
                harmonic(rng),
                harmonic(rng),
            ]),
            _ => harmonic(rng),
        }
    }

    /// About half of every parameter the machine has, with dynamics on some component errors
    /// and context terms (time-driven, so no record is needed) on a few parameters.
    fn rich_model(machine: &Machine, rng: &mut ChaCha8Rng, whole_turns: bool) -> ErrorModel {
        let mut parameters = Vec::new();
        for name in ParameterName::all() {
            if !rng.random_bool(0.5) {
                continue;
            }
            let Ok(binding) = super::super::Binding::of(machine, name) else {
                continue;
            };
            let function = match (binding.action, name.axis().and_then(|a| machine.axis(a))) {
                (Action::Component(axis), Some(info)) => {
                    let travel = info.limits.unwrap_or((0.0, TAU));
                    let whole_turns = whole_turns && !axis.is_linear();
                    function(rng, binding.periodic, travel, whole_turns)
                }
                _ => ErrorFunction::Constant(small(rng)),
            };
            parameters.push(ErrorParameter { name, function });
        }
        let model = ErrorModel::new(machine, parameters).unwrap();
        let mut dynamics = Vec::new();
        let mut context = Vec::new();
        for name in ParameterName::all() {
            let Ok(binding) = super::super::Binding::of(machine, name) else {
                continue;
            };
            if matches!(binding.action, Action::Component(_)) && rng.random_bool(0.15) {
                let speed_factor = rng.random_bool(0.5).then(|| {
                    Table::new(vec![0.0, 10.0], vec![1.0, 2.5], Interpolation::Linear).unwrap()
                });
                let frequency = Frequency::Hz(rng.random_range(1.0..100.0));
                dynamics.push(ParameterDynamics {
                    name,
                    dynamics: Dynamics {
                        sinusoids: vec![Sinusoid {
                            frequency,
                            amplitude: small(rng),
                            phase: 0.3,
                        }],
                        random: None,
                        speed_factor,
                    },
                });
            }
            if rng.random_bool(0.1) {
                let driver = if rng.random_bool(0.5) {
                    Driver::Drift { from: 1.0 }
                } else {
                    Driver::Heating {
                        tau: 300.0,
                        from: 0.0,
                    }
                };
                context.push(ParameterContext {
                    name,
                    terms: vec![ContextTerm {
                        driver,
                        coefficient: 1e-9,
                        per_position: false,
                    }],
                });
            }
        }
        model
            .with_dynamics(machine, dynamics)
            .unwrap()
            .with_context(machine, context, None)
            .unwrap()
    }

    fn random_state(machine: &Machine, rng: &mut ChaCha8Rng) -> MachineState {
        let position = random_position(machine, rng);
        let mut state = MachineState::at(position).at_time(rng.random_range(0.0..1000.0));
        for axis in Axis::ALL {
            state = state.with_velocity(axis, rng.random_range(-20.0..20.0));
            if rng.random_bool(0.3) {
                state.direction[axis.index()] = Direction::Negative;
            }
        }
        state
    }

    /// How far the walk about a workpiece-side rotary axis line (`rel⁻¹ · L · R · L⁻¹`) may be
    /// from the plain composition (`(L·R·L⁻¹·R⁻¹)⁻¹`-composed, inverted, then `R`): the same
    /// product regrouped, so a few units in the last place of entries of order 1 (rotation)
    /// and of the metre-sized translations (2.2e-16 each), 1e-8 µm.
    const REGROUPED: Real = 8.0 * f64::EPSILON;

    #[test]
    fn planned_chain_is_the_plain_chain_to_the_bit() {
        // To the bit for models without a located rotary line on the workpiece branch; within
        // [`REGROUPED`] for those with one.
        compare_with_plain_chain(false, None);
    }

    #[test]
    fn harmonics_per_turn_agree_with_their_sines() {
        // The recurrence and the sine differ by ulps of the amplitudes (µm, µrad), which shows
        // as round-off of the metre-sized chain at most.
        compare_with_plain_chain(true, Some(1e-15));
    }

    /// Whether the entries of `a` and `b` are equal (`tolerance` `None`; `==`, blind to the
    /// sign of zero) or within `tolerance` of each other.
    fn same(a: &[Pose], b: &[Pose], tolerance: Option<Real>) -> bool {
        let entries = |poses: &[Pose]| -> Vec<Real> {
            poses.iter().flat_map(|p| p.to_cols_array()).collect()
        };
        same_values(&entries(a), &entries(b), tolerance)
    }

    fn same_values(a: &[Real], b: &[Real], tolerance: Option<Real>) -> bool {
        a.len() == b.len()
            && a.iter().zip(b).all(|(x, y)| match tolerance {
                None => x == y,
                Some(tolerance) => (x - y).abs() <= tolerance,
            })
    }

    /// Runs the planned chain against the plain one on random models and states.
    fn compare_with_plain_chain(whole_turns: bool, tolerance: Option<Real>) {
        let mut rng = seeded_rng(2, "planned chain");
        for path in ["vmc3", "trunnion5", "headtable5"] {
            let file = format!("{}/models/{path}.urdf", env!("CARGO_MANIFEST_DIR"));
            let machine = Machine::from_urdf_file(&file).unwrap();
            let mut workspace = Workspace::new(&machine);
            for _ in 0..40 {
                let mut model = rich_model(&machine, &mut rng, whole_turns);
                if rng.random_bool(0.3) {
                    // New coefficients: the plan follows.
                    let scaled: Vec<Real> = model.coefficients().iter().map(|c| -2.0 * c).collect();
                    model.set_coefficients(&scaled);
                }
                let regrouped = model.plan.lines.iter().any(Option::is_some);
                let tolerance = match (regrouped, tolerance) {
                    (true, tolerance) => Some(tolerance.unwrap_or(0.0).max(REGROUPED)),
                    (false, tolerance) => tolerance,
                };
                for _ in 0..25 {
                    let state = random_state(&machine, &mut rng);
                    let extra: Vec<[Real; 6]> = (0..machine.slot_count())
                        .map(|_| {
                            let mut t = [0.0; 6];
                            if rng.random_bool(0.3) {
                                t.iter_mut().for_each(|v| *v = small(&mut rng));
                            }
                            t
                        })
                        .collect();
                    let at = format!("{} at {state:?}", machine.name());
                    for extra in [None, Some(&extra[..])] {
                        let pose =
                            model.workpiece_from_tool_with(&machine, &mut workspace, &state, extra);
                        let motions = plain_motions(&model, &machine, &state, extra);
                        let (plain, world_from_slot, ends) =
                            plain_workpiece_from_tool(&machine, &state.position, Some(&motions));
                        assert!(
                            same(&[pose], &[plain], tolerance),
                            "{at}: {pose} vs {plain}"
                        );
                        assert!(same(
                            workspace.world_from_slot(),
                            &world_from_slot,
                            tolerance
                        ));
                        let (tool, workpiece) = workspace.world_from_ends();
                        assert!(same(&[tool, workpiece], &ends, tolerance), "{at}");
                        // The whole slot motions, lines included, are the plain ones.
                        let planned_motions =
                            model.slot_motions(&machine, &mut workspace, &state, extra);
                        assert!(same(&planned_motions, &motions, tolerance), "{at}");
                    }
                    let nominal = plain_workpiece_from_tool(&machine, &state.position, None).0;
                    let motions = plain_motions(&model, &machine, &state, None);
                    let actual =
                        plain_workpiece_from_tool(&machine, &state.position, Some(&motions)).0;
                    let planned = model.deviation(&machine, &mut workspace, &state);
                    let plain = Deviation::between(&nominal, &actual);
                    assert!(
                        same_values(&planned.to_array(), &plain.to_array(), tolerance),
                        "{at}"
                    );
                }
            }
        }
    }
}
