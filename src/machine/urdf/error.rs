//! Why a machine model is refused: [`MachineError`] (the file, the line) and its
//! [`MachineErrorKind`] (which check failed), with the largest sizes a model may have.

use crate::machine::Axis;
use crate::math::Real;
use std::fmt;

/// Why a machine model was rejected. Its message names the file, the line where it can be
/// found, the element and what was expected; [`MachineError::kind`] tells which check failed.
#[derive(Debug, thiserror::Error)]
#[error("{}{}: {kind}", .file, .line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct MachineError {
    pub(super) file: String,
    pub(super) line: Option<usize>,
    pub(super) kind: MachineErrorKind,
}

impl MachineError {
    /// Which check failed.
    pub fn kind(&self) -> &MachineErrorKind {
        &self.kind
    }
}

/// The checks a machine model must pass.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum MachineErrorKind {
    /// The file could not be read.
    Io(String),
    /// Not well-formed URDF XML.
    Xml(String),
    /// A `<visual>` geometry with a size that is not a positive finite number.
    Geometry {
        /// The link.
        link: String,
        /// What was found.
        found: String,
    },
    /// No link named `tool` or `workpiece`.
    MissingEndLink(&'static str),
    /// A joint names a parent or child link that does not exist.
    UnknownLink {
        /// The joint.
        joint: String,
        /// The missing link.
        link: String,
    },
    /// A link is the child of two joints: the structure is a closed loop, not a tree.
    ClosedLoop {
        /// The link with two parents.
        link: String,
        /// The two joints that have it as their child.
        joints: [String; 2],
    },
    /// More than one link (or none, which means a cycle) has no parent: the likely root (the
    /// link most others hang from) first.
    Roots(Vec<String>),
    /// A joint type mtwin cannot model (floating, planar, spherical) or a mimic joint.
    UnsupportedJoint {
        /// The joint.
        joint: String,
        /// Its type.
        joint_type: String,
    },
    /// A moving joint is not named after an axis letter (X, Y, Z, A, B, C, S).
    AxisName {
        /// The joint.
        joint: String,
    },
    /// Two joints carry the same axis letter.
    DuplicateAxis(Axis),
    /// The joint type does not suit the letter (prismatic X/Y/Z; revolute or continuous A/B/C;
    /// continuous S).
    AxisType {
        /// The axis.
        axis: Axis,
        /// Its URDF type.
        joint_type: String,
    },
    /// The joint axis vector is not the one the letter and the side require.
    AxisDirection {
        /// The axis.
        axis: Axis,
        /// What the file says.
        found: [Real; 3],
        /// What was expected.
        expected: [Real; 3],
    },
    /// A prismatic or revolute joint without a usable `<limit lower upper>`.
    Limits {
        /// The axis.
        axis: Axis,
    },
    /// A moving joint that moves neither the tool nor the workpiece.
    OffBranch {
        /// The axis.
        axis: Axis,
    },
    /// A moving joint above the point where the tool and workpiece branches split: it moves
    /// both together, so nothing between them.
    SharedBranch {
        /// The axis.
        axis: Axis,
    },
    /// A moving joint whose frame is turned relative to the bed at the home pose: errors are
    /// named in machine X, Y, Z, so moving joints' frames must be parallel to the bed's there.
    JointFrame {
        /// The axis.
        axis: Axis,
    },
    /// The `tool` frame's z axis is not along the machine's +Z at the home pose.
    ToolAxis {
        /// Where it points instead (bed frame).
        found: [Real; 3],
    },
    /// Links that are joined in a cycle, apart from the tree that holds the root.
    Cycle(Vec<String>),
    /// The spindle is not on the tool branch.
    SpindleSide,
    /// A non-finite number in an origin or axis.
    NotFinite {
        /// The joint.
        joint: String,
    },
    /// The set of axes is not a supported machine.
    Configuration(String),
    /// A length or an angle beyond any machine tool (see [`crate::machine::LARGEST_MACHINE`]).
    Implausible {
        /// The element (`joint "X" origin`, `link "bed" <visual>`, …).
        element: String,
        /// The value found.
        found: Real,
        /// The largest magnitude accepted, with its unit.
        limit: &'static str,
    },
}

/// The largest length in a model (m): no machine tool is larger, so every joint offset, body
/// size and place and linear travel lies within ±100 m. Beyond it a model is in another unit
/// (millimetres: a 350 mm offset written 350) or broken, and its geometry would make collision
/// checks and kinematics work at scales nothing is built for.
pub const LARGEST_MACHINE: Real = 100.0;

/// The largest angle of a revolute joint's limits (rad): ten turns.
pub const LARGEST_TURN: Real = 20.0 * std::f64::consts::PI;

impl fmt::Display for MachineErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use MachineErrorKind::*;
        match self {
            Io(message) => write!(f, "cannot read the file: {message}"),
            Geometry { link, found } => write!(
                f,
                "link \"{link}\": a <visual> geometry needs positive finite sizes and a finite origin, found {found}"
            ),
            Xml(message) => write!(f, "not a valid URDF document: {message}"),
            MissingEndLink(name) => write!(
                f,
                "no link named \"{name}\": a machine needs a `tool` link (tool centre point) and a `workpiece` link"
            ),
            UnknownLink { joint, link } => {
                write!(
                    f,
                    "joint \"{joint}\" refers to link \"{link}\", which is not defined"
                )
            }
            ClosedLoop { link, joints } => write!(
                f,
                "link \"{link}\" is the child of joints \"{}\" and \"{}\": the model is a closed loop, expected a tree",
                joints[0], joints[1]
            ),
            Roots(roots) if roots.is_empty() => {
                write!(
                    f,
                    "every link has a parent: the joints form a cycle, expected a tree with one root (the bed)"
                )
            }
            Roots(roots) if roots.is_empty() => write!(
                f,
                "every link has a parent joint, so the joints form a cycle: expected one root (the bed)"
            ),
            Roots(roots) => write!(
                f,
                "link{} {} {} no parent joint (is a <joint> with <child link=\"{}\"/> missing?): \
                 expected one root (the bed, \"{}\" here) and a parent joint for every other link",
                if roots.len() > 2 { "s" } else { "" },
                roots[1..]
                    .iter()
                    .map(|r| format!("\"{r}\""))
                    .collect::<Vec<_>>()
                    .join(", "),
                if roots.len() > 2 { "have" } else { "has" },
                roots[1],
                roots[0]
            ),
            UnsupportedJoint { joint, joint_type } => write!(
                f,
                "joint \"{joint}\" is {joint_type}: expected fixed, prismatic, revolute or continuous (no mimic)"
            ),
            AxisName { joint } => write!(
                f,
                "moving joint \"{joint}\" must be named after its axis letter: X, Y, Z, A, B, C or S (spindle)"
            ),
            DuplicateAxis(axis) => write!(f, "two joints are named \"{axis}\""),
            AxisType { axis, joint_type } => write!(
                f,
                "joint \"{axis}\" is {joint_type}: expected {}",
                match axis {
                    Axis::X | Axis::Y | Axis::Z => "prismatic",
                    Axis::S => "continuous",
                    _ => "revolute or continuous",
                }
            ),
            AxisDirection {
                axis,
                found,
                expected,
            } => write!(
                f,
                "joint \"{axis}\" has axis ({} {} {}): expected ({} {} {}) (it moves along its frame's {} axis, \
                 and ISO 841 makes a positive command move the tool in + relative to the workpiece, so a joint \
                 on the workpiece branch points the other way)",
                found[0],
                found[1],
                found[2],
                expected[0],
                expected[1],
                expected[2],
                ["x", "y", "z"][axis.coordinate()]
            ),
            Limits { axis } => write!(
                f,
                "joint \"{axis}\" needs <limit lower=\"..\" upper=\"..\"/> with finite lower < upper (m or rad)"
            ),
            OffBranch { axis } => write!(
                f,
                "joint \"{axis}\" moves neither the tool nor the workpiece (it is on no path from the root to them)"
            ),
            SharedBranch { axis } => write!(
                f,
                "joint \"{axis}\" is above the split of the tool and workpiece branches: it moves both together, \
                 expected it on the path from the split to `tool` or to `workpiece`"
            ),
            JointFrame { axis } => write!(
                f,
                "the frame of joint \"{axis}\" is turned relative to the bed at the home pose: errors are named in \
                 machine X, Y, Z, so a moving joint's frame must be parallel to the bed's there (put rotations on \
                 fixed joints after it)"
            ),
            ToolAxis { found } => write!(
                f,
                "the `tool` frame's z axis points along ({:.3} {:.3} {:.3}) at the home pose: expected the \
                 machine's +Z (0 0 1), from the tool tip into the spindle",
                found[0], found[1], found[2]
            ),
            Cycle(links) => write!(
                f,
                "links {} are joined in a cycle, apart from the tree of the root: expected one tree",
                links
                    .iter()
                    .map(|l| format!("\"{l}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            SpindleSide => write!(
                f,
                "joint \"S\" (the spindle) must be on the path from the root to `tool`"
            ),
            NotFinite { joint } => write!(
                f,
                "joint \"{joint}\" has a non-finite number in its origin or axis"
            ),
            Configuration(message) => write!(f, "unsupported machine: {message}"),
            Implausible {
                element,
                found,
                limit,
            } => write!(
                f,
                "{element}: {} is beyond {limit}, more than any machine tool; a model in millimetres? (URDF is in metres and radians)",
                crate::math::readable(*found)
            ),
        }
    }
}
