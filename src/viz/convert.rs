//! The metrology path is `f64`; rerun draws in `f32`. Every narrowing happens here.

use crate::math::{Pose, Real, Rotation, Vector};
use crate::viz::rr;
use glam::DQuat;

/// A point or vector (m) for rerun.
pub(crate) fn vec3(v: Vector) -> [f32; 3] {
    v.as_vec3().to_array()
}

/// A rotation for rerun.
pub(crate) fn quaternion(rotation: Rotation) -> rr::Quaternion {
    rr::Quaternion::from_xyzw(DQuat::from_mat3(&rotation).as_quat().to_array())
}

/// A rigid transform (parent_from_child) for rerun.
pub(crate) fn transform(pose: &Pose) -> rr::Transform3D {
    rr::Transform3D::from_translation_rotation(vec3(pose.translation), quaternion(pose.matrix3))
}

/// A 2D plot point, y drawn upward (rerun's 2D views have y down).
pub(crate) fn plot_point(x: Real, y: Real) -> [f32; 2] {
    [x as f32, -y as f32]
}

/// Blue (0) through grey to red (1), for thermal state and error size.
pub(crate) fn cold_to_warm(fraction: Real) -> rr::Color {
    let f = fraction.clamp(0.0, 1.0);
    let channel = |a: Real, b: Real| (a + (b - a) * f).round() as u8;
    rr::Color::from_rgb(
        channel(40.0, 220.0),
        channel(90.0, 50.0),
        channel(220.0, 40.0),
    )
}
