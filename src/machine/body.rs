//! The machine's visible parts, from the URDF `<visual>` elements: what a scene draws, not what
//! the kinematics use. Each link is placed by the moving joint it hangs from (or the bed), so
//! drawing the machine at any axis values needs one forward-kinematics pass.

use super::{Axis, AxisValues, Machine, Workspace};
use crate::math::{Pose, Real, Vector};
use glam::DMat3;

/// A URDF geometry (m).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A box with these side lengths along its x, y, z.
    Box {
        /// Side lengths (m).
        size: Vector,
    },
    /// A cylinder along its z, centred on its origin.
    Cylinder {
        /// Radius (m).
        radius: Real,
        /// Length (m).
        length: Real,
    },
    /// A capsule along its z (cylinder length without the caps), centred on its origin.
    Capsule {
        /// Radius (m).
        radius: Real,
        /// Length of the cylinder between the caps (m).
        length: Real,
    },
    /// A sphere.
    Sphere {
        /// Radius (m).
        radius: Real,
    },
    /// A mesh file, as the URDF names it (drawn by scenes that can load it).
    Mesh {
        /// The file name or URI.
        file: String,
        /// Scale along x, y, z.
        scale: Vector,
    },
}

/// One `<visual>` of a link.
#[derive(Clone, Debug, PartialEq)]
pub struct Visual {
    /// Where the shape sits in its link frame.
    pub link_from_shape: Pose,
    /// The shape.
    pub shape: Shape,
}

/// A link of the machine, with what it looks like and what moves it.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// The URDF link name.
    pub link: String,
    /// The moving joint it hangs from (through fixed joints), or `None` for the bed and what is
    /// fixed to it.
    pub moved_by: Option<Axis>,
    /// Its shapes (none for a frame-only link such as `tool` or `workpiece`).
    pub visuals: Vec<Visual>,
    /// From the moving joint's frame after its motion (or the bed) to the link frame.
    pub(crate) joint_from_link: Pose,
    /// The joint's axis in its frame (for rotary joints).
    pub(crate) unit: Vector,
}

impl Machine {
    /// Every link of the URDF, in file order, with its shapes.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Each body's nominal link frame in the bed (world) frame at `position`, into `out` (one per
    /// [`Machine::bodies`]). No allocation.
    pub fn world_from_bodies(
        &self,
        workspace: &mut Workspace,
        position: &AxisValues,
        out: &mut [Pose],
    ) {
        assert_eq!(out.len(), self.bodies.len(), "one frame per body");
        workspace.workpiece_from_tool(self, position, None);
        for (body, frame) in self.bodies.iter().zip(out.iter_mut()) {
            *frame = match body.moved_by {
                None => body.joint_from_link,
                Some(axis) => {
                    let slot = self
                        .axis(axis)
                        .expect("moved by an axis of the machine")
                        .slot;
                    let mut world_from_joint = workspace.world_from_slot()[slot];
                    if !axis.is_linear() {
                        world_from_joint.matrix3 *=
                            DMat3::from_axis_angle(body.unit, position[axis]);
                    }
                    world_from_joint * body.joint_from_link
                }
            };
        }
    }
}
