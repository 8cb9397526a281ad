//! Probing cycles: the artefacts and the moves the controller makes to touch them.
//!
//! Every move is a linear-axis move at fixed rotary angles, planned on the nominal chain: at
//! the rotary angles of a feature the tool tip is affine in X, Y, Z ([`LinearFrame`]), so a
//! start point and an approach direction in the workpiece frame become a start in axis values
//! and a direction in axis space. The controller plans with the stylus radius it believes.
//!
//! Patterns (directions are the outward surface normals probed, in the workpiece frame):
//! - a sphere ([`sphere_pattern`]): `points − 1` points around the tool axis at an elevation
//!   (the angle of incidence) above the sphere's equator, plus one on the pole, as
//!   KinematicsOpt's cycle 451 does; with 25 points, the ISO 10360-5 distribution instead;
//! - a ring gauge ([`ring_pattern`]): points equally spaced around the bore at one height,
//!   approached from near the centre outward;
//! - a mesh: start points and directions as given.

use crate::contact::{Approach, Artefact, BallPlate, ContactError, Cylinder, Mesh, Sphere, Touch};
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::{Real, Rotation, Vector};
use std::f64::consts::{FRAC_PI_2, TAU};
use std::sync::Arc;

/// What a cycle probes, which decides how its features are evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleKind {
    /// A calibration sphere at one or more rotary positions: a sphere fit per position.
    Sphere,
    /// A ring gauge: a circle fit (diameter, roundness).
    Ring,
    /// A ball plate at one placement: a sphere fit per ball, centre distances against the
    /// calibrated plate.
    Plate,
    /// Points on a mesh workpiece.
    Mesh,
}

impl CycleKind {
    /// Its name in the tables (`sphere`, `ring`, `plate`, `mesh`).
    pub fn name(self) -> &'static str {
        match self {
            CycleKind::Sphere => "sphere",
            CycleKind::Ring => "ring",
            CycleKind::Plate => "plate",
            CycleKind::Mesh => "mesh",
        }
    }

    /// The kind named `name` in a table.
    pub fn from_name(name: &str) -> Option<CycleKind> {
        [
            CycleKind::Sphere,
            CycleKind::Ring,
            CycleKind::Plate,
            CycleKind::Mesh,
        ]
        .into_iter()
        .find(|k| k.name() == name)
    }
}

/// The artefact of a feature, in the workpiece frame.
#[derive(Clone, Debug)]
pub enum Target {
    /// A sphere touched from outside.
    Sphere(Sphere),
    /// A ring gauge's bore.
    Ring(Cylinder),
    /// A ball plate (the first ball met).
    Plate(Arc<BallPlate>),
    /// A mesh workpiece.
    Mesh(Arc<Mesh>),
}

impl Target {
    /// The first contact of a ball of radius `tip_radius` on `approach` (see
    /// [`crate::contact`]).
    pub fn touch(
        &self,
        tip_radius: Real,
        approach: &Approach,
        max_travel: Real,
    ) -> Result<Option<Touch>, ContactError> {
        match self {
            Target::Sphere(s) => s.touch(tip_radius, approach, max_travel),
            Target::Ring(c) => c.touch(tip_radius, approach, max_travel),
            Target::Plate(p) => p.touch(tip_radius, approach, max_travel),
            Target::Mesh(m) => m.touch(tip_radius, approach, max_travel),
        }
    }
}

/// One probing move of the controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeMove {
    /// Axis values at the start (m, rad; rotary axes at the feature's angles).
    pub start: AxisValues,
    /// The unit direction of the move in axis space (X, Y, Z).
    pub direction: Vector,
    /// The same direction seen in the tool frame (nominal), which the probe's pre-travel
    /// depends on.
    pub tool_direction: Vector,
    /// How far the move may go before the cycle reports no touch (m).
    pub max_travel: Real,
}

/// One element a cycle fits (a sphere at one rotary position, a ball of a plate, a ring) or
/// the points on a mesh.
#[derive(Clone, Debug)]
pub struct Feature {
    /// The rotary angles held (rad; the linear entries are zero).
    pub rotary: AxisValues,
    /// What is touched.
    pub target: Target,
    /// The moves, one per point.
    pub moves: Vec<ProbeMove>,
    /// The artefact's calibrated diameter (sphere, ball, ring), if it has one (m).
    pub calibrated_diameter: Option<Real>,
    /// A plate ball's calibrated centre in the plate's frame (m).
    pub calibrated_centre: Option<Vector>,
}

/// A probing cycle: one kind of artefact, one or more features.
#[derive(Clone, Debug)]
pub struct Cycle {
    /// What it probes.
    pub kind: CycleKind,
    /// Its features, in order.
    pub features: Vec<Feature>,
}

/// The nominal chain at fixed rotary angles: tool tip = `origin + matrix · (X, Y, Z)` in the
/// workpiece frame, and the tool's orientation there.
#[derive(Clone, Copy, Debug)]
pub struct LinearFrame {
    rotary: AxisValues,
    origin: Vector,
    inverse: Rotation,
    /// `workpiece_from_tool`'s rotation: the tool frame's axes in the workpiece frame (its z is
    /// the stylus axis, from the tip into the spindle).
    pub tool: Rotation,
}

impl LinearFrame {
    /// The frame at the rotary angles of `rotary` (its linear entries are ignored); `None` when
    /// the linear axes are degenerate there.
    pub fn at(machine: &Machine, rotary: &AxisValues) -> Option<LinearFrame> {
        let mut at_zero = *rotary;
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            at_zero[axis] = 0.0;
        }
        let pose = machine.workpiece_from_tool(&at_zero);
        let column = |axis: Axis| {
            let mut moved = at_zero;
            moved[axis] = 1.0;
            machine.workpiece_from_tool(&moved).translation - pose.translation
        };
        let matrix = Rotation::from_cols(column(Axis::X), column(Axis::Y), column(Axis::Z));
        (matrix.determinant().abs() > 1e-9).then(|| LinearFrame {
            rotary: at_zero,
            origin: pose.translation,
            inverse: matrix.inverse(),
            tool: pose.matrix3,
        })
    }

    /// The axis values that put the nominal tool tip at `tip` (workpiece frame).
    pub fn axes_for(&self, tip: Vector) -> AxisValues {
        let q = self.inverse * (tip - self.origin);
        let mut axes = self.rotary;
        axes[Axis::X] = q.x;
        axes[Axis::Y] = q.y;
        axes[Axis::Z] = q.z;
        axes
    }

    /// The unit axis-space direction of a workpiece-frame direction.
    pub fn axis_direction(&self, direction: Vector) -> Vector {
        (self.inverse * direction).normalize()
    }

    /// The move whose tip starts at `start` and travels along the workpiece-frame `direction`.
    pub fn move_from(&self, start: Vector, direction: Vector, max_travel: Real) -> ProbeMove {
        ProbeMove {
            start: self.axes_for(start),
            direction: self.axis_direction(direction),
            tool_direction: (self.tool.transpose() * direction).normalize(),
            max_travel,
        }
    }
}

/// A unit vector across `axis`: `reference` with its component along `axis` removed, or any
/// perpendicular when `reference` is parallel to it.
fn across(axis: Vector, reference: Vector) -> Vector {
    let v = reference - axis * axis.dot(reference);
    if v.length_squared() > 1e-12 {
        v.normalize()
    } else {
        axis.any_orthonormal_vector()
    }
}

/// The outward normals probed on a sphere: about the unit `axis` (the tool axis), azimuths
/// from `reference` (the tool frame's x). With 25 points, the ISO 10360-5 distribution [as
/// commonly quoted]: the pole, 4 at 22.5° from it, 8 at 45°, 4 at 67.5° and 8 on the equator,
/// each ring turned by half its spacing from the one before. Otherwise `points − 1` at
/// `elevation` (rad) above the equator and the pole; when `facing` is given (a plate whose
/// normal is across the tool axis), the side points keep to the half facing it (azimuths
/// −90° … +90° about it).
pub fn sphere_pattern(
    points: usize,
    elevation: Real,
    axis: Vector,
    reference: Vector,
    facing: Option<Vector>,
) -> Vec<Vector> {
    let x = across(axis, facing.unwrap_or(reference));
    let y = axis.cross(x);
    let normal = |polar: Real, azimuth: Real| {
        axis * polar.cos() + (x * azimuth.cos() + y * azimuth.sin()) * polar.sin()
    };
    if points == 25 {
        let deg = |d: Real| d.to_radians();
        let mut normals = vec![axis];
        for (polar, count, offset) in [
            (22.5, 4, 0.0),
            (45.0, 8, 22.5),
            (67.5, 4, 45.0),
            (90.0, 8, 22.5),
        ] {
            for i in 0..count {
                normals.push(normal(
                    deg(polar),
                    deg(offset) + TAU * i as Real / count as Real,
                ));
            }
        }
        return normals;
    }
    let side = points.saturating_sub(1);
    let polar = FRAC_PI_2 - elevation;
    let mut normals: Vec<Vector> = (0..side)
        .map(|i| {
            let azimuth = match (facing, side) {
                (Some(_), 1) => 0.0,
                (Some(_), _) => -FRAC_PI_2 + std::f64::consts::PI * i as Real / (side - 1) as Real,
                (None, _) => TAU * i as Real / side as Real,
            };
            normal(polar, azimuth)
        })
        .collect();
    normals.push(axis);
    normals
}

/// The outward radial directions of `points` equally spaced points around a bore of unit
/// `axis`, from `reference` (the tool frame's x).
pub fn ring_pattern(points: usize, axis: Vector, reference: Vector) -> Vec<Vector> {
    let x = across(axis, reference);
    let y = axis.cross(x);
    (0..points)
        .map(|i| {
            let azimuth = TAU * i as Real / points as Real;
            x * azimuth.cos() + y * azimuth.sin()
        })
        .collect()
}
