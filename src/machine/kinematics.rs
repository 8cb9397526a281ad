//! Forward kinematics: axis values (and optional error motions at the slots) → the tool pose
//! seen from the workpiece.
//!
//! # Speed
//!
//! The walk computes the plain composition `origin · Trans(q·u) · [slot motion] · Rot(u, q)`
//! per joint, leaving out the terms of the full products that are exact zeros and ones:
//!
//! - a joint origin whose rotation is exactly the identity is a translation;
//! - a joint axis exactly along ±x, ±y or ±z makes `Rot(u, q)` a 2×2 block ([`JointRotation`]),
//!   computed once per pose (one sine and cosine per rotary axis) and shared with the error
//!   model's axis-line motions;
//! - a slot motion that is the identity, a translation or a rotation ([`MotionKind`]) costs
//!   nothing, a matrix-vector product or a matrix product;
//! - until the first rotation, the frame's rotation is exactly the identity, and products with
//!   it are copies and sums;
//! - a branch whose end link sits on its last joint's frame (an identity `end`) is not placed
//!   by it;
//! - the rotary joints are listed once ([`Machine`]'s `rotary_joints`), and the sines and
//!   cosines of two of them are computed together ([`trig::sin_cos_pair`]).
//!
//! The sums left are the full products' in their order, so poses are the plain composition's
//! to the bit, but for the sign of exact zeros (the tests below hold the walk to that).

use super::{AxisValues, Branch, ChainJoint, Machine, Side, trig};
use crate::math::{Pose, Real, Vector, rigid_inverse};
use glam::DMat3;

/// Per-evaluation scratch for one machine: reuse it across poses so kinematics never
/// allocates. Not shared between threads; make one per thread.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// Error motion at each slot, in the slot frame (see [`crate::errors`]). After an error
    /// model's evaluation, a rotary axis of the workpiece branch with a located line holds its
    /// relative motion only (the walk turned about the line, [`AxisLine`]); the whole motions
    /// are `ErrorModel::slot_motions`.
    pub(crate) slot_motions: Vec<Pose>,
    /// What each slot motion is (identity, translation, general), filled with it.
    pub(crate) motion_kinds: Vec<MotionKind>,
    /// The error model plan (its id, 0 for none) whose fixed slot motions `slot_motions` and
    /// `motion_kinds` hold: an evaluation with that plan recomputes only the others.
    pub(crate) motions_plan: u64,
    /// Each rotary axis's rotation at the position of the evaluation, by slot (the identity
    /// for linear axes and the tool slot), computed once per pose for the chain and for the
    /// error model's axis-line motions.
    pub(crate) rotations: Vec<JointRotation>,
    /// `world_from_slot` frames from the last evaluation.
    pub(crate) world_from_slot: Vec<Pose>,
    /// Relative error twists per slot (δx, δy, δz, εx, εy, εz), filled by the error model.
    pub(crate) slot_twists: Vec<[f64; 6]>,
    /// Axis-line locations per slot, filled by the error model.
    pub(crate) slot_lines: Vec<[f64; 6]>,
    /// Sensitivity of the deviation to each slot's twist (Jacobian scratch).
    pub(crate) slot_sensitivities: Vec<[[f64; 6]; 5]>,
    /// Basis values of one error function (Jacobian scratch).
    pub(crate) basis: Vec<f64>,
    /// `world_from_tool` and `world_from_workpiece` from the last evaluation.
    pub(crate) world_from_ends: [Pose; 2],
}

/// What a slot motion is, so that the walk multiplies only by what it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MotionKind {
    /// Exactly the identity: nothing to apply.
    Identity,
    /// An identity rotation and a translation.
    Translation,
    /// A rotation and a zero translation.
    Rotation,
    /// Anything else.
    General,
    /// Anything, folded by the error model into the slot's [`AxisLine::folded`]: the walk
    /// applies it there (elsewhere it is taken as [`MotionKind::General`]).
    InLine,
}

impl MotionKind {
    /// The kind of `motion`, from its values (exact comparisons).
    pub(crate) fn of(motion: &Pose) -> MotionKind {
        match (
            motion.matrix3 == DMat3::IDENTITY,
            motion.translation == Vector::ZERO,
        ) {
            (true, true) => MotionKind::Identity,
            (true, false) => MotionKind::Translation,
            (false, true) => MotionKind::Rotation,
            (false, false) => MotionKind::General,
        }
    }
}

/// The line a rotary axis of the workpiece branch actually turns about, `L` (its pose in the
/// slot frame) and `L⁻¹`: the walk then turns the frame by `L · Rot(u, q) · L⁻¹` after the
/// slot's relative motion `rel` (applied inverted, as on that branch), instead of applying the
/// slot motion `(L·R·L⁻¹·R⁻¹)⁻¹ · rel` inverted and turning by `Rot(u, q)`: the same product
/// regrouped, with fewer operations (see [`crate::errors`]).
///
/// When the relative motion is not folded in (it varies), the walk turns by
/// `L · Rot(u, q) · L⁻¹` built at once ([`AxisLine::turned_by`]) rather than by three
/// products.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisLine {
    /// `rel⁻¹ · L` for the slot's fixed relative motion, used when its kind is
    /// [`MotionKind::InLine`].
    pub folded: Pose,
    /// `L⁻¹`.
    pub inverse: Pose,
    /// `K = [Q·u]×` and `K²`, for `L = Trans(δ)·Q` and the joint axis `u`, and `K·δ`, `K²·δ`.
    k: DMat3,
    k2: DMat3,
    k_delta: Vector,
    k2_delta: Vector,
}

impl AxisLine {
    /// The line `pose` (`L`, with its `inverse`) of a joint turning about `unit`, with
    /// `folded` = `rel⁻¹ · L`.
    pub(crate) fn new(pose: Pose, inverse: Pose, folded: Pose, unit: Vector) -> AxisLine {
        let u = pose.matrix3 * unit;
        let k = DMat3::from_cols(
            Vector::new(0.0, u.z, -u.y),
            Vector::new(-u.z, 0.0, u.x),
            Vector::new(u.y, -u.x, 0.0),
        );
        let k2 = k * k;
        AxisLine {
            folded,
            inverse,
            k,
            k2,
            k_delta: k * pose.translation,
            k2_delta: k2 * pose.translation,
        }
    }

    /// `L · Rot(u, q) · L⁻¹` from `rotation` (`Rot(u, q)`): the rotation by `q` about the
    /// located axis `Q·u` through `δ`, `M = I + sin q·K + (1 − cos q)·K²` (Rodrigues' formula
    /// about `Q·u`, which is `Q·Rot(u, q)·Qᵀ`), and the translation `δ − M·δ`
    /// `= −sin q·K·δ − (1 − cos q)·K²·δ`. The same pose as the three products to a few units
    /// in the last place (a regrouping; the chain's tests bound it).
    #[inline(always)]
    fn turned_by(&self, rotation: &JointRotation) -> Pose {
        let (sin, cos) = rotation.sin_cos;
        let omc = 1.0 - cos;
        let (k, k2) = (&self.k, &self.k2);
        let column = |j: usize| {
            let mut c = k.col(j) * sin + k2.col(j) * omc;
            c[j] += 1.0;
            c
        };
        Pose::from_mat3_translation(
            DMat3::from_cols(column(0), column(1), column(2)),
            -(self.k_delta * sin) - self.k2_delta * omc,
        )
    }
}

/// Per slot, the motion, its kind and (workpiece-side rotary axes) the axis line, as the error
/// model hands them to the walk.
pub(crate) type SlotMotions<'a> = (&'a [Pose], &'a [MotionKind], Option<&'a [Option<AxisLine>]>);

/// `Rot(u, q)` of a joint, as `DMat3::from_axis_angle` builds it. When `u` is exactly ±x, ±y
/// or ±z (coordinate `k`, the others `a < b`), that matrix has exact zeros in row and column
/// `k` but for the diagonal `d = (1 − cos) + cos`, `cos` at `[a][a]` and `[b][b]`, and `±sin`
/// off the diagonal: only those are kept, and products with it leave the zeros out.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JointRotation {
    /// The joint axis it turns about.
    pub unit: Vector,
    /// The sine and cosine of the angle.
    pub sin_cos: (Real, Real),
    shape: Shape,
}

/// The non-zero entries of a [`JointRotation`].
#[derive(Clone, Copy, Debug)]
enum Shape {
    /// About coordinate `k`: the diagonal entry `d` there and the entry `s` in row `b`,
    /// column `a` (minus it in row `a`, column `b`).
    About { k: usize, d: Real, s: Real },
    /// Any other axis: the whole matrix.
    Tilted(DMat3),
}

impl JointRotation {
    /// No rotation (linear axes).
    pub(crate) const IDENTITY: JointRotation = JointRotation {
        unit: Vector::X,
        sin_cos: (0.0, 1.0),
        shape: Shape::About {
            k: 0,
            d: 1.0,
            s: 0.0,
        },
    };

    /// The rotation by `angle` about the unit vector `unit`. Its sine and cosine are
    /// [`super::trig::sin_cos`]'s: FreeBSD's algorithm (under 1 ulp, the same on every
    /// platform) without branches on the angle's range; [`libm::sincos`], its port with them,
    /// was 30 ns a pose cheaper on trunnion5 than glibc's `sincos` (which, profiled in the
    /// chain, spends a third of its time setting the rounding mode), and this is cheaper again.
    #[inline(always)]
    pub(crate) fn new(unit: Vector, angle: Real) -> JointRotation {
        JointRotation::along(unit, coordinate_of(unit), angle)
    }

    /// [`JointRotation::new`] with `coordinate_of(unit)` known.
    #[inline(always)]
    fn along(unit: Vector, coordinate: Option<usize>, angle: Real) -> JointRotation {
        let (sin, cos) = trig::sin_cos(angle);
        JointRotation::from_sin_cos(unit, coordinate, sin, cos)
    }

    /// [`JointRotation::along`] with the sine and cosine of the angle known.
    #[inline(always)]
    fn from_sin_cos(
        unit: Vector,
        coordinate: Option<usize>,
        sin: Real,
        cos: Real,
    ) -> JointRotation {
        let shape = match coordinate {
            // DMat3::from_axis_angle's entries with the zero terms of a coordinate axis left
            // out: the diagonal (u_k² = 1)·(1 − cos) + cos, and u_k·sin (with a sign that
            // depends on the coordinate, as in the cross-product matrix of u).
            Some(k) => {
                let s = unit[k] * sin;
                Shape::About {
                    k,
                    d: (1.0 - cos) + cos,
                    s: if k == 1 { -s } else { s },
                }
            }
            None => {
                // DMat3::from_axis_angle(unit, angle), term for term, with this sine and cosine.
                let (x, y, z) = unit.into();
                let (xsin, ysin, zsin) = (unit * sin).into();
                let (x2, y2, z2) = (unit * unit).into();
                let omc = 1.0 - cos;
                let (xyomc, xzomc, yzomc) = (x * y * omc, x * z * omc, y * z * omc);
                Shape::Tilted(DMat3::from_cols(
                    Vector::new(x2 * omc + cos, xyomc + zsin, xzomc - ysin),
                    Vector::new(xyomc - zsin, y2 * omc + cos, yzomc + xsin),
                    Vector::new(xzomc + ysin, yzomc - xsin, z2 * omc + cos),
                ))
            }
        };
        JointRotation {
            unit,
            sin_cos: (sin, cos),
            shape,
        }
    }

    /// The rotation matrix.
    #[inline(always)]
    pub(crate) fn matrix(&self) -> DMat3 {
        let (k, d, s) = match self.shape {
            Shape::About { k, d, s } => (k, d, s),
            Shape::Tilted(m) => return m,
        };
        let c = self.sin_cos.1;
        let v = Vector::new;
        match k {
            0 => DMat3::from_cols(v(d, 0.0, 0.0), v(0.0, c, s), v(0.0, -s, c)),
            1 => DMat3::from_cols(v(c, 0.0, s), v(0.0, d, 0.0), v(-s, 0.0, c)),
            _ => DMat3::from_cols(v(c, s, 0.0), v(-s, c, 0.0), v(0.0, 0.0, d)),
        }
    }

    /// The inverse rotation (the transpose).
    #[inline(always)]
    pub(crate) fn transpose(&self) -> JointRotation {
        let shape = match self.shape {
            Shape::About { k, d, s } => Shape::About { k, d, s: -s },
            Shape::Tilted(m) => Shape::Tilted(m.transpose()),
        };
        JointRotation { shape, ..*self }
    }

    /// `m · self`, summed in the order of glam's product with the zero terms left out.
    #[inline(always)]
    pub(crate) fn right_of(&self, m: &DMat3) -> DMat3 {
        let (k, d, s) = match self.shape {
            Shape::About { k, d, s } => (k, d, s),
            Shape::Tilted(r) => return *m * r,
        };
        let c = self.sin_cos.1;
        // Column j of m·R is Σ_i m.col(i)·R[i][j], summed over i = x, y, z.
        let (x, y, z) = (m.x_axis, m.y_axis, m.z_axis);
        match k {
            0 => DMat3::from_cols(x * d, y * c + z * s, y * -s + z * c),
            1 => DMat3::from_cols(x * c + z * s, y * d, x * -s + z * c),
            _ => DMat3::from_cols(x * c + y * s, x * -s + y * c, z * d),
        }
    }
}

/// The coordinate (0, 1, 2) a unit vector lies exactly along, either way; `None` when it is
/// tilted from all three.
#[inline(always)]
pub(crate) fn coordinate_of(unit: Vector) -> Option<usize> {
    match unit.to_array().map(f64::abs) {
        [1.0, 0.0, 0.0] => Some(0),
        [0.0, 1.0, 0.0] => Some(1),
        [0.0, 0.0, 1.0] => Some(2),
        _ => None,
    }
}

/// `a · b` by what `b` is ([`MotionKind`]): the full product's values, leaving out the terms of
/// `b`'s exact identity rotation or zero translation.
#[inline(always)]
pub(crate) fn then_motion(a: &Pose, b: &Pose, kind: MotionKind) -> Pose {
    match kind {
        MotionKind::Identity => *a,
        MotionKind::Translation => {
            Pose::from_mat3_translation(a.matrix3, a.matrix3 * b.translation + a.translation)
        }
        MotionKind::Rotation => Pose::from_mat3_translation(a.matrix3 * b.matrix3, a.translation),
        MotionKind::General | MotionKind::InLine => *a * *b,
    }
}

/// A frame walked from the bed, which knows while its rotation is still exactly the identity
/// (before the first rotary joint or rotated origin): products with it are then copies and
/// sums (`I·v = v`, `I·M = M`, to the bit but for the sign of zero).
struct Frame {
    pose: Pose,
    turned: bool,
}

impl Frame {
    /// `self · Trans(d)`.
    #[inline(always)]
    fn translate(&mut self, d: Vector) {
        let moved = if self.turned {
            self.pose.matrix3 * d
        } else {
            d
        };
        self.pose.translation = moved + self.pose.translation;
    }

    /// `self · Trans(u·q)` for a joint axis `u` along `coordinate` ([`coordinate_of`]).
    #[inline(always)]
    fn travel(&mut self, unit: Vector, coordinate: Option<usize>, q: Real) {
        let travel = unit * q;
        let moved = match coordinate {
            Some(k) if self.turned => self.pose.matrix3.col(k) * travel[k],
            Some(k) => Vector::AXES[k] * travel[k],
            None if self.turned => self.pose.matrix3 * travel,
            None => travel,
        };
        self.pose.translation += moved;
    }

    /// `self · Rot(m)` (no translation).
    #[inline(always)]
    fn rotate(&mut self, m: &DMat3) {
        self.pose.matrix3 = if self.turned {
            self.pose.matrix3 * *m
        } else {
            *m
        };
        self.turned = true;
    }

    /// `self · Rot(u, q)`.
    #[inline(always)]
    fn turn(&mut self, rotation: &JointRotation) {
        self.pose.matrix3 = if self.turned {
            rotation.right_of(&self.pose.matrix3)
        } else {
            rotation.matrix()
        };
        self.turned = true;
    }

    /// `self · p`.
    #[inline(always)]
    fn transform(&mut self, p: &Pose) {
        if self.turned {
            self.pose *= *p;
        } else {
            self.pose =
                Pose::from_mat3_translation(p.matrix3, p.translation + self.pose.translation);
            self.turned = true;
        }
    }

    /// `self · origin`: a translation when `origin`'s rotation is exactly the identity
    /// (`is_translation`, as for the joints of the bundled machines).
    #[inline(always)]
    fn place(&mut self, origin: &Pose, is_translation: bool) {
        if is_translation {
            self.translate(origin.translation);
        } else {
            self.transform(origin);
        }
    }

    /// `self · motion` (tool side) or `self · motion⁻¹` (workpiece side).
    #[inline(always)]
    fn apply(&mut self, motion: &Pose, kind: MotionKind, side: Side) {
        match (kind, side) {
            (MotionKind::Identity, _) => {}
            (MotionKind::Translation, Side::Tool) => self.translate(motion.translation),
            (MotionKind::Translation, Side::Workpiece) => self.translate(-motion.translation),
            (MotionKind::Rotation, Side::Tool) => self.rotate(&motion.matrix3),
            (MotionKind::Rotation, Side::Workpiece) => self.rotate(&motion.matrix3.transpose()),
            (MotionKind::General | MotionKind::InLine, Side::Tool) => self.transform(motion),
            (MotionKind::General | MotionKind::InLine, Side::Workpiece) => {
                self.transform(&rigid_inverse(motion))
            }
        }
    }
}

impl Workspace {
    /// Scratch sized for `machine`.
    pub fn new(machine: &Machine) -> Workspace {
        let slots = machine.slot_count();
        Workspace {
            slot_motions: vec![Pose::IDENTITY; slots],
            motion_kinds: vec![MotionKind::Identity; slots],
            motions_plan: 0,
            rotations: vec![JointRotation::IDENTITY; slots],
            world_from_slot: vec![Pose::IDENTITY; slots],
            slot_twists: vec![[0.0; 6]; slots],
            slot_lines: vec![[0.0; 6]; slots],
            slot_sensitivities: vec![[[0.0; 6]; 5]; slots],
            basis: Vec::new(),
            world_from_ends: [Pose::IDENTITY; 2],
        }
    }

    /// The tool pose seen from the workpiece at `position`.
    ///
    /// With `slot_motions` (one small transform per slot, see [`Machine::slot_count`]), each is
    /// applied in its slot frame: as is on the tool branch, inverted on the workpiece branch,
    /// so that every slot motion is a motion of the tool *relative to the workpiece*.
    /// Without, the result is nominal.
    pub fn workpiece_from_tool(
        &mut self,
        machine: &Machine,
        position: &AxisValues,
        slot_motions: Option<&[Pose]>,
    ) -> Pose {
        self.assert_sized_for(machine);
        self.set_rotations(machine, position);
        match slot_motions {
            Some(motions) => {
                assert_eq!(
                    motions.len(),
                    machine.slot_count(),
                    "one slot motion per slot"
                );
                let mut kinds = std::mem::take(&mut self.motion_kinds);
                self.motions_plan = 0;
                for (kind, motion) in kinds.iter_mut().zip(motions) {
                    *kind = MotionKind::of(motion);
                }
                let pose = self.walk_both(machine, position, Some((motions, &kinds, None)));
                self.motion_kinds = kinds;
                pose
            }
            None => self.walk_both(machine, position, None),
        }
    }

    /// [`Workspace::workpiece_from_tool`] for many poses, written into `out` (same length as
    /// `positions`). Nominal; no allocation.
    pub fn workpiece_from_tool_batch(
        &mut self,
        machine: &Machine,
        positions: &[AxisValues],
        out: &mut [Pose],
    ) {
        assert_eq!(positions.len(), out.len(), "one output per pose");
        for (position, pose) in positions.iter().zip(out.iter_mut()) {
            *pose = self.workpiece_from_tool(machine, position, None);
        }
    }

    /// `world_from_slot` of every slot as left by the last evaluation: the frame each error
    /// motion is expressed in, including the error motions of the slots before it when that
    /// evaluation had errors (nominal after a nominal evaluation).
    pub fn world_from_slot(&self) -> &[Pose] {
        &self.world_from_slot
    }

    /// The tool frame (with its tool-slot motion) and the workpiece frame in the world (bed)
    /// frame from the last evaluation: where each branch put its end, errors included when the
    /// evaluation had them. Their relative pose is what the evaluation returned.
    pub fn world_from_ends(&self) -> (Pose, Pose) {
        (self.world_from_ends[0], self.world_from_ends[1])
    }

    /// Panics when the workspace was made for a machine with another number of slots.
    pub(crate) fn assert_sized_for(&self, machine: &Machine) {
        assert_eq!(
            self.world_from_slot.len(),
            machine.slot_count(),
            "workspace of another machine"
        );
    }

    /// Fills [`Workspace::rotations`] at `position`: one sine and cosine per rotary axis, about
    /// the joint axis as the URDF gives it.
    ///
    /// Angles that [`trig::sin_cos`] reduces are taken two at a time
    /// ([`trig::sin_cos_pair`]: the same bits, two chains of dependent operations in one).
    pub(crate) fn set_rotations(&mut self, machine: &Machine, position: &AxisValues) {
        let mut waiting: Option<(&ChainJoint, Real)> = None;
        for joint in &machine.rotary_joints {
            let angle = position[joint.axis];
            if !trig::is_medium(angle) {
                self.rotations[joint.slot] =
                    JointRotation::along(joint.unit, joint.coordinate, angle);
                continue;
            }
            let Some((first, first_angle)) = waiting.take() else {
                waiting = Some((joint, angle));
                continue;
            };
            let [(s0, c0), (s1, c1)] = trig::sin_cos_pair([first_angle, angle]);
            self.rotations[first.slot] =
                JointRotation::from_sin_cos(first.unit, first.coordinate, s0, c0);
            self.rotations[joint.slot] =
                JointRotation::from_sin_cos(joint.unit, joint.coordinate, s1, c1);
        }
        if let Some((joint, angle)) = waiting {
            self.rotations[joint.slot] = JointRotation::along(joint.unit, joint.coordinate, angle);
        }
    }

    /// Both branches with the rotations already set and, with errors, the slot motions and
    /// their kinds: records the slot frames and the ends, returns `workpiece_from_tool`.
    pub(crate) fn walk_both(
        &mut self,
        machine: &Machine,
        position: &AxisValues,
        motions: Option<SlotMotions<'_>>,
    ) -> Pose {
        let world_from_tool = walk(
            &machine.tool_branch,
            position,
            &self.rotations,
            motions,
            Side::Tool,
            &mut self.world_from_slot,
        );
        let tool_slot = machine.tool_slot();
        self.world_from_slot[tool_slot] = world_from_tool;
        let world_from_tool = match motions {
            Some((motions, kinds, _)) => {
                then_motion(&world_from_tool, &motions[tool_slot], kinds[tool_slot])
            }
            None => world_from_tool,
        };
        let world_from_workpiece = walk(
            &machine.work_branch,
            position,
            &self.rotations,
            motions,
            Side::Workpiece,
            &mut self.world_from_slot,
        );
        self.world_from_ends = [world_from_tool, world_from_workpiece];
        rigid_inverse(&world_from_workpiece) * world_from_tool
    }
}

/// Walks one branch from the bed: `origin · translation(q) · [slot motion] · rotation(q)` per
/// joint (`· L · rotation(q) · L⁻¹` after the slot motion where an [`AxisLine`] is given),
/// recording each slot frame. Returns `world_from_end`.
#[inline(always)]
fn walk(
    branch: &Branch,
    position: &AxisValues,
    rotations: &[JointRotation],
    motions: Option<SlotMotions<'_>>,
    side: Side,
    world_from_slot: &mut [Pose],
) -> Pose {
    let mut frame = Frame {
        pose: Pose::IDENTITY,
        turned: false,
    };
    for joint in &branch.joints {
        frame.place(&joint.origin, joint.origin_is_translation);
        if joint.axis.is_linear() {
            frame.travel(joint.unit, joint.coordinate, position[joint.axis]);
        }
        world_from_slot[joint.slot] = frame.pose;
        let rotation = &rotations[joint.slot];
        let rotary = !joint.axis.is_linear();
        match motions {
            Some((motions, kinds, lines)) => {
                let (motion, kind) = (&motions[joint.slot], kinds[joint.slot]);
                match (lines.and_then(|lines| lines[joint.slot].as_ref()), kind) {
                    // `(rel⁻¹ · L) · R · L⁻¹`, `rel⁻¹` folded into `L` once.
                    (Some(line), MotionKind::InLine) => {
                        frame.transform(&line.folded);
                        frame.turn(rotation);
                        frame.transform(&line.inverse);
                    }
                    // `rel⁻¹ · (L · R · L⁻¹)`, the second factor built at once.
                    (Some(line), kind) => {
                        frame.apply(motion, kind, side);
                        frame.transform(&line.turned_by(rotation));
                    }
                    (None, kind) => {
                        frame.apply(motion, kind, side);
                        if rotary {
                            frame.turn(rotation);
                        }
                    }
                }
            }
            None if rotary => frame.turn(rotation),
            None => {}
        }
    }
    // Placing by an exact identity would add exact zeros.
    if !branch.end_is_identity {
        frame.place(&branch.end, branch.end_is_translation);
    }
    frame.pose
}

/// The plain composition, every product in full, as the walk computed it before it skipped
/// exact identities: the reference the walk (and [`crate::errors`]'s chain) is held to.
/// Returns `workpiece_from_tool`, `world_from_slot` and the two ends.
#[cfg(test)]
pub(crate) fn plain_workpiece_from_tool(
    machine: &Machine,
    position: &AxisValues,
    motions: Option<&[Pose]>,
) -> (Pose, Vec<Pose>, [Pose; 2]) {
    let mut world_from_slot = vec![Pose::IDENTITY; machine.slot_count()];
    let mut walk = |branch: &Branch, side: Side| {
        let mut world_from_frame = Pose::IDENTITY;
        for joint in &branch.joints {
            world_from_frame *= joint.origin;
            let value = position[joint.axis];
            if joint.axis.is_linear() {
                world_from_frame.translation += world_from_frame.matrix3 * (joint.unit * value);
            }
            world_from_slot[joint.slot] = world_from_frame;
            if let Some(motions) = motions {
                let motion = motions[joint.slot];
                world_from_frame = match side {
                    Side::Tool => world_from_frame * motion,
                    Side::Workpiece => world_from_frame * rigid_inverse(&motion),
                };
            }
            if !joint.axis.is_linear() {
                world_from_frame.matrix3 *= axis_angle(joint.unit, value);
            }
        }
        world_from_frame * branch.end
    };
    let world_from_tool = walk(&machine.tool_branch, Side::Tool);
    let world_from_workpiece = walk(&machine.work_branch, Side::Workpiece);
    world_from_slot[machine.tool_slot()] = world_from_tool;
    let world_from_tool = match motions {
        Some(motions) => world_from_tool * motions[machine.tool_slot()],
        None => world_from_tool,
    };
    (
        rigid_inverse(&world_from_workpiece) * world_from_tool,
        world_from_slot,
        [world_from_tool, world_from_workpiece],
    )
}

/// `DMat3::from_axis_angle(unit, angle)`, term for term, with the sine and cosine the walk uses
/// ([`super::trig::sin_cos`]; glam takes the platform's).
#[cfg(test)]
pub(crate) fn axis_angle(unit: Vector, angle: Real) -> DMat3 {
    let (sin, cos) = trig::sin_cos(angle);
    let (x, y, z) = unit.into();
    let (xsin, ysin, zsin) = (unit * sin).into();
    let (x2, y2, z2) = (unit * unit).into();
    let omc = 1.0 - cos;
    let (xyomc, xzomc, yzomc) = (x * y * omc, x * z * omc, y * z * omc);
    DMat3::from_cols(
        Vector::new(x2 * omc + cos, xyomc + zsin, xzomc - ysin),
        Vector::new(xyomc - zsin, y2 * omc + cos, yzomc + xsin),
        Vector::new(xzomc + ysin, yzomc - xsin, z2 * omc + cos),
    )
}

#[cfg(test)]
/// Random axis values over the travel (continuous axes over three turns either way).
pub(crate) fn random_position(machine: &Machine, rng: &mut rand_chacha::ChaCha8Rng) -> AxisValues {
    use rand::RngExt;
    let mut position = AxisValues::ZERO;
    for info in machine.axes() {
        let (low, high) = info.limits.unwrap_or((-20.0, 20.0));
        position[info.axis] = rng.random_range(low..=high);
    }
    // Now and then an axis exactly at zero, where sines are exact zeros.
    if rng.random_bool(0.2) {
        position[crate::machine::Axis::ALL[rng.random_range(0..7)]] = 0.0;
    }
    position
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{seeded_rng, small_motion};
    use rand::RngExt;

    /// The bundled machines.
    pub(crate) fn machines() -> Vec<Machine> {
        ["vmc3", "trunnion5", "headtable5"]
            .map(|name| {
                let path = format!("{}/models/{name}.urdf", env!("CARGO_MANIFEST_DIR"));
                Machine::from_urdf_file(&path).unwrap()
            })
            .into()
    }

    #[test]
    fn the_walk_is_the_plain_composition_to_the_bit() {
        let mut rng = seeded_rng(1, "walk");
        for machine in machines() {
            let mut workspace = Workspace::new(&machine);
            for _ in 0..500 {
                let position = random_position(&machine, &mut rng);
                // Identities, translations and general motions, at random slots.
                let motions: Vec<Pose> = (0..machine.slot_count())
                    .map(|_| {
                        let mut twist = [0.0; 6];
                        match rng.random_range(0..3) {
                            0 => {}
                            1 => (0..3).for_each(|i| twist[i] = rng.random_range(-1e-5..1e-5)),
                            _ => twist
                                .iter_mut()
                                .for_each(|t| *t = rng.random_range(-1e-5..1e-5)),
                        }
                        let [dx, dy, dz, ex, ey, ez] = twist;
                        small_motion(Vector::new(dx, dy, dz), Vector::new(ex, ey, ez))
                    })
                    .collect();
                for motions in [None, Some(&motions[..])] {
                    let pose = workspace.workpiece_from_tool(&machine, &position, motions);
                    let (plain, world_from_slot, ends) =
                        plain_workpiece_from_tool(&machine, &position, motions);
                    assert_eq!(pose, plain, "{} at {position:?}", machine.name());
                    assert_eq!(workspace.world_from_slot(), &world_from_slot[..]);
                    assert_eq!(workspace.world_from_ends(), (ends[0], ends[1]));
                }
            }
        }
    }
}
