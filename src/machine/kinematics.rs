//! Forward kinematics: axis values (and optional error motions at the slots) → the tool pose
//! seen from the workpiece.

use super::{AxisValues, Branch, Machine, Side};
use crate::math::{Pose, rigid_inverse};
use glam::DMat3;

/// Per-evaluation scratch for one machine: reuse it across poses so kinematics never
/// allocates. Not shared between threads; make one per thread.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// Error motion at each slot, in the slot frame (see [`crate::errors`]).
    pub(crate) slot_motions: Vec<Pose>,
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

impl Workspace {
    /// Scratch sized for `machine`.
    pub fn new(machine: &Machine) -> Workspace {
        let slots = machine.slot_count();
        Workspace {
            slot_motions: vec![Pose::IDENTITY; slots],
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
        assert_eq!(
            self.world_from_slot.len(),
            machine.slot_count(),
            "workspace of another machine"
        );
        if let Some(motions) = slot_motions {
            assert_eq!(
                motions.len(),
                machine.slot_count(),
                "one slot motion per slot"
            );
        }
        let world_from_tool = walk(
            &machine.tool_branch,
            position,
            slot_motions,
            Side::Tool,
            &mut self.world_from_slot,
        );
        let tool_slot = machine.tool_slot();
        self.world_from_slot[tool_slot] = world_from_tool;
        let world_from_tool = match slot_motions {
            Some(motions) => world_from_tool * motions[tool_slot],
            None => world_from_tool,
        };
        let world_from_workpiece = walk(
            &machine.work_branch,
            position,
            slot_motions,
            Side::Workpiece,
            &mut self.world_from_slot,
        );
        self.world_from_ends = [world_from_tool, world_from_workpiece];
        rigid_inverse(&world_from_workpiece) * world_from_tool
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
}

/// Walks one branch from the bed: `origin · translation(q) · [slot motion] · rotation(q)` per
/// joint, recording each slot frame. Returns `world_from_end`.
fn walk(
    branch: &Branch,
    position: &AxisValues,
    slot_motions: Option<&[Pose]>,
    side: Side,
    world_from_slot: &mut [Pose],
) -> Pose {
    let mut world_from_frame = Pose::IDENTITY;
    for joint in &branch.joints {
        world_from_frame *= joint.origin;
        let value = position[joint.axis];
        if joint.axis.is_linear() {
            world_from_frame.translation += world_from_frame.matrix3 * (joint.unit * value);
        }
        world_from_slot[joint.slot] = world_from_frame;
        if let Some(motions) = slot_motions {
            let motion = motions[joint.slot];
            world_from_frame = match side {
                Side::Tool => world_from_frame * motion,
                Side::Workpiece => world_from_frame * rigid_inverse(&motion),
            };
        }
        if !joint.axis.is_linear() {
            world_from_frame.matrix3 *= DMat3::from_axis_angle(joint.unit, value);
        }
    }
    world_from_frame * branch.end
}
