//! The [`Plan`] of an [`ErrorModel`]: what an evaluation does not recompute (see
//! [`super`]), and the small motions and axis-line motions it builds from twists.

use crate::errors::ErrorModel;
use crate::errors::binding::Action;
use crate::errors::function::TurnSeries;
use crate::machine::{Axis, AxisInfo, AxisLine, JointRotation, MotionKind, Side, then_motion};
use crate::math::{Pose, Real, Vector, rigid_inverse, small_motion};
use std::sync::atomic::{AtomicU64, Ordering};

/// What an evaluation of an [`ErrorModel`] does not recompute (see the module documentation).
#[derive(Clone, Debug, Default)]
pub(crate) struct Plan {
    /// Per slot, the constant parameters' sum of each relative-twist component no varying
    /// term acts on (zero for the others).
    pub(super) base_relative: Vec<[Real; 6]>,
    /// The same for the axis-line locations.
    pub(super) base_line: Vec<[Real; 6]>,
    /// Every parameter acting on a component that varies, in parameter order.
    pub(super) terms: Vec<Term>,
    /// Per slot, its motion's fixed parts.
    pub(super) slots: Vec<SlotPlan>,
    /// Whether any axis line is [`Line::Varying`].
    pub(super) varying_lines: bool,
    /// Per slot, the fixed line of a rotary axis on the workpiece branch, which the walk turns
    /// about itself (`None` for the others, whose line motion is in the slot motion).
    pub(super) lines: Vec<Option<AxisLine>>,
    /// The slots of [`Plan::lines`] that hold a line: where the plan depends on the bound
    /// machine's joint axis.
    pub(in crate::errors) line_slots: Vec<usize>,
    /// The slots whose relative twist varies (whose [`SlotPlan::relative`] is `None`).
    pub(super) varying: Vec<usize>,
    /// The slots whose motion an evaluation without extra twists recomputes at each pose: the
    /// varying ones and those with a line motion that depends on the position. The others'
    /// motions are fixed: a workspace that holds them from this plan ([`Plan::id`]) keeps them.
    pub(super) active: Vec<usize>,
    /// Every slot, in order (what an evaluation goes through when the workspace holds other
    /// motions).
    pub(super) all: Vec<usize>,
    /// This plan's number, unique in the process (from 1; 0 for the default plan), by which a
    /// [`crate::machine::Workspace`] knows that its fixed slot motions are this plan's.
    pub(super) id: u64,
}

/// The next [`Plan::id`].
static NEXT_PLAN_ID: AtomicU64 = AtomicU64::new(1);

/// A parameter summed at each pose.
#[derive(Clone, Debug)]
pub(super) struct Term {
    /// Index in [`ErrorModel::parameters`].
    pub(super) parameter: usize,
    pub(super) slot: usize,
    pub(super) component: usize,
    /// Whether it locates the axis line (else it adds to the relative twist).
    pub(super) on_line: bool,
    pub(super) value: Value,
}

/// How a [`Term`] gets its value.
#[derive(Clone, Debug)]
pub(super) enum Value {
    /// A constant.
    Fixed(Real),
    /// Its function of the axis position ([`crate::errors::ErrorFunction::value`]).
    Function(Axis),
    /// Harmonics of a rotary axis, from the sine and cosine of its angle.
    Turn(Axis, TurnSeries),
}

/// The fixed parts of one slot's motion.
#[derive(Clone, Copy, Debug)]
pub(super) struct SlotPlan {
    /// The relative twist's small motion and its kind, when the twist never varies.
    pub(super) relative: Option<(Pose, MotionKind)>,
    /// The axis line.
    pub(super) line: Line,
}

/// An axis line's fixed geometry.
#[derive(Clone, Copy, Debug)]
pub(super) enum Line {
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
    pub(crate) fn new(model: &ErrorModel) -> Plan {
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
                _ => Value::Fixed(crate::errors::constant(&parameter.function)),
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
            .enumerate()
            .map(
                |(slot, plan)| match (plan.line, model.machine_axes.get(slot)) {
                    (Line::Rotary { pose, inverse }, Some((_, Side::Workpiece))) => {
                        let folded = match plan.relative {
                            Some((relative, _)) => rigid_inverse(&relative) * pose,
                            None => pose,
                        };
                        Some(AxisLine::new(pose, inverse, folded, model.joint_axes[slot]))
                    }
                    _ => None,
                },
            )
            .collect::<Vec<Option<AxisLine>>>();
        let varying = (0..slots)
            .filter(|&slot| plans[slot].relative.is_none())
            .collect();
        let active = (0..slots)
            .filter(|&slot| {
                let turned_about = lines[slot].is_some();
                let line_moves = !turned_about && !matches!(plans[slot].line, Line::Nominal);
                plans[slot].relative.is_none() || line_moves
            })
            .collect();
        let line_slots = (0..slots).filter(|&slot| lines[slot].is_some()).collect();
        Plan {
            varying,
            active,
            line_slots,
            all: (0..slots).collect(),
            id: NEXT_PLAN_ID.fetch_add(1, Ordering::Relaxed),
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
pub(super) fn small_motion_of(t: &[Real; 6]) -> (Pose, MotionKind) {
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
pub(super) fn line_geometry(linear: bool, direction: Vector, l: &[Real; 6]) -> Line {
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
/// (Always inlined: as a plain `#[inline]` in its own module the error pose measured 3 % slower.)
#[inline(always)]
pub(super) fn apply_line(
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
