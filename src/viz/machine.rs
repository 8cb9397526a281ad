//! The machine from its URDF, its nominal and actual tool and workpiece frames, and the
//! tool-tip error arrow.

use super::convert::{quaternion, transform, vec3};
use super::{MACHINE, TOOL_NOMINAL, TOOL_TIP_ERROR_UM, VizError, WORKPIECE_NOMINAL, WORLD};
use crate::machine::{MachineState, Shape, Side, Workspace};
use crate::math::{Pose, Real, Vector, rigid_inverse};
use crate::twin::Twin;
use crate::viz::rr;
use glam::{DMat3, DQuat};
use rr::RecordingStream;

/// Length of the drawn frame axes (m).
const FRAME_AXIS_LENGTH: f32 = 0.08;

/// Draws one twin: keeps the scratch for its kinematics and the entity paths of its bodies.
pub(crate) struct MachineScene<'a> {
    twin: &'a Twin,
    workspace: Workspace,
    frames: Vec<Pose>,
    /// `world/machine/<link>` per body.
    paths: Vec<String>,
    magnification: Real,
}

/// The nominal and actual ends of both branches in the bed frame: (tool, workpiece).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ends {
    pub nominal: (Pose, Pose),
    pub actual: (Pose, Pose),
}

impl Ends {
    /// The nominal tool tip in the workpiece frame (m).
    pub fn nominal_tip(&self) -> Vector {
        (rigid_inverse(&self.nominal.1) * self.nominal.0).translation
    }

    /// The tool-tip deviation, actual − nominal, in the workpiece frame (m).
    pub fn deviation(&self) -> Vector {
        (rigid_inverse(&self.actual.1) * self.actual.0).translation - self.nominal_tip()
    }
}

impl<'a> MachineScene<'a> {
    pub fn new(twin: &'a Twin, magnification: Real) -> MachineScene<'a> {
        let bodies = twin.machine.bodies();
        MachineScene {
            twin,
            workspace: Workspace::new(&twin.machine),
            frames: vec![Pose::IDENTITY; bodies.len()],
            paths: bodies
                .iter()
                .map(|b| format!("{MACHINE}/{}", b.link))
                .collect(),
            magnification,
        }
    }

    pub fn twin(&self) -> &'a Twin {
        self.twin
    }

    pub fn magnification(&self) -> Real {
        self.magnification
    }

    /// The world's axes, every body's shapes, the fixed bodies' frames and the frame axes.
    pub fn log_static(
        &mut self,
        rec: &RecordingStream,
        legend: &mut Vec<String>,
    ) -> Result<(), VizError> {
        rec.log_static(WORLD, &rr::ViewCoordinates::RIGHT_HAND_Z_UP())?;
        let machine = &self.twin.machine;
        // Fixed bodies: their frames at any axis values.
        machine.world_from_bodies(
            &mut self.workspace,
            &crate::machine::AxisValues::ZERO,
            &mut self.frames,
        );
        let side_of = |axis| machine.axis(axis).map(|info| info.side);
        let mut meshes = Vec::new();
        for ((body, path), frame) in machine.bodies().iter().zip(&self.paths).zip(&self.frames) {
            let colour = match body.moved_by.and_then(side_of) {
                None => rr::Color::from_rgb(110, 110, 120),
                Some(Side::Workpiece) => rr::Color::from_rgb(90, 140, 200),
                Some(Side::Tool) => rr::Color::from_rgb(230, 150, 60),
            };
            for (i, visual) in body.visuals.iter().enumerate() {
                let entity = format!("{path}/visual_{i}");
                let centre = [vec3(visual.link_from_shape.translation)];
                let rotation = [quaternion(visual.link_from_shape.matrix3)];
                match &visual.shape {
                    Shape::Box { size } => rec.log_static(
                        entity,
                        &rr::Boxes3D::from_centers_and_sizes(centre, [vec3(*size)])
                            .with_quaternions(rotation)
                            .with_colors([colour])
                            .with_fill_mode(rr::FillMode::Solid),
                    )?,
                    Shape::Cylinder { radius, length } => rec.log_static(
                        entity,
                        &rr::Cylinders3D::from_lengths_and_radii(
                            [*length as f32],
                            [*radius as f32],
                        )
                        .with_centers(centre)
                        .with_quaternions(rotation)
                        .with_colors([colour])
                        .with_fill_mode(rr::FillMode::Solid),
                    )?,
                    Shape::Capsule { radius, length } => rec.log_static(
                        entity,
                        &rr::Capsules3D::from_lengths_and_radii([*length as f32], [*radius as f32])
                            // Capsules start at their origin; URDF centres them.
                            .with_translations([vec3(
                                visual.link_from_shape.transform_point3(Vector::new(
                                    0.0,
                                    0.0,
                                    -length / 2.0,
                                )),
                            )])
                            .with_quaternions(rotation)
                            .with_colors([colour]),
                    )?,
                    Shape::Sphere { radius } => rec.log_static(
                        entity,
                        &rr::Ellipsoids3D::from_centers_and_radii(centre, [*radius as f32])
                            .with_colors([colour])
                            .with_fill_mode(rr::FillMode::Solid),
                    )?,
                    Shape::Mesh { file, .. } => meshes.push(format!("{} ({file})", body.link)),
                }
            }
            if body.moved_by.is_none() {
                rec.log_static(path.as_str(), &transform(frame))?;
            }
        }
        for frame in [
            TOOL_NOMINAL.to_string(),
            WORKPIECE_NOMINAL.to_string(),
            super::tool_actual(self.magnification),
            super::workpiece_actual(self.magnification),
        ] {
            rec.log_static(frame, &rr::TransformAxes3D::new(FRAME_AXIS_LENGTH))?;
        }
        legend.push(format!(
            "`{MACHINE}/<link>`: the machine from its URDF, drawn nominal (grey: bed; blue: workpiece side; orange: tool side){}.",
            if meshes.is_empty() {
                String::new()
            } else {
                format!("; meshes not drawn: {}", meshes.join(", "))
            }
        ));
        legend.push(format!(
            "`{TOOL_NOMINAL}`, `{WORKPIECE_NOMINAL}`: nominal frames; `{}`, `{}`: actual frames, their error from nominal (translation and rotation) enlarged.",
            super::tool_actual(self.magnification),
            super::workpiece_actual(self.magnification)
        ));
        legend.push(format!(
            "`{}`: the tool-tip deviation (actual − nominal, workpiece frame) from the nominal tip, enlarged; `{TOOL_TIP_ERROR_UM}/dx|dy|dz`: the same in µm against time.",
            super::tool_tip_error(self.magnification)
        ));
        Ok(())
    }

    /// The moving bodies and the nominal frames at `state`; returns the nominal ends.
    pub fn log_nominal(
        &mut self,
        rec: &RecordingStream,
        state: &MachineState,
    ) -> Result<(Pose, Pose), VizError> {
        let machine = &self.twin.machine;
        machine.world_from_bodies(&mut self.workspace, &state.position, &mut self.frames);
        let ends = self.workspace.world_from_ends();
        for ((body, path), frame) in machine.bodies().iter().zip(&self.paths).zip(&self.frames) {
            if body.moved_by.is_some() {
                rec.log(path.as_str(), &transform(frame))?;
            }
        }
        rec.log(TOOL_NOMINAL, &transform(&ends.0))?;
        rec.log(WORKPIECE_NOMINAL, &transform(&ends.1))?;
        Ok(ends)
    }

    /// The nominal and actual ends at `state`, geometric errors plus `extra` twists per slot
    /// (thermal errors), without logging.
    pub fn ends(&mut self, state: &MachineState, extra: Option<&[[Real; 6]]>) -> Ends {
        let (machine, errors) = (&self.twin.machine, &self.twin.errors);
        self.workspace
            .workpiece_from_tool(machine, &state.position, None);
        let nominal = self.workspace.world_from_ends();
        errors.workpiece_from_tool_with(machine, &mut self.workspace, state, extra);
        let actual = self.workspace.world_from_ends();
        Ends { nominal, actual }
    }

    /// The actual frames (errors enlarged), the tool-tip error arrow and its time series.
    pub fn log_actual(&self, rec: &RecordingStream, ends: &Ends) -> Result<(), VizError> {
        let m = self.magnification;
        rec.log(
            super::tool_actual(m),
            &transform(&magnified(&ends.nominal.0, &ends.actual.0, m)),
        )?;
        rec.log(
            super::workpiece_actual(m),
            &transform(&magnified(&ends.nominal.1, &ends.actual.1, m)),
        )?;
        let deviation = ends.deviation();
        rec.log(
            super::tool_tip_error(m),
            &rr::Arrows3D::from_vectors([vec3(deviation * m)])
                .with_origins([vec3(ends.nominal_tip())])
                .with_colors([rr::Color::from_rgb(230, 40, 40)]),
        )?;
        for (name, value) in ["dx", "dy", "dz"].iter().zip(deviation.to_array()) {
            rec.log(
                format!("{TOOL_TIP_ERROR_UM}/{name}"),
                &rr::Scalars::single(value * 1e6),
            )?;
        }
        Ok(())
    }
}

/// `actual` with its difference from `nominal` (in the nominal frame) enlarged `m` times:
/// translation times `m`, rotation angle times `m` about the same axis.
pub(crate) fn magnified(nominal: &Pose, actual: &Pose, m: Real) -> Pose {
    let error = rigid_inverse(nominal) * *actual;
    let rotation = DQuat::from_mat3(&error.matrix3).to_scaled_axis() * m;
    *nominal
        * Pose::from_mat3_translation(
            DMat3::from_quat(DQuat::from_scaled_axis(rotation)),
            error.translation * m,
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn magnified_scales_the_error_translation_and_angle() {
        // Nominal: turned 90° about z at (1, 2, 3). Actual: 2 µm further along the nominal
        // frame's x and turned 5 µrad more about its z. ×1000: 2 mm along the nominal x, which
        // is the world's +y, and 5 mrad.
        let nominal = Pose::from_rotation_translation(
            DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
            Vector::new(1.0, 2.0, 3.0),
        );
        let error = Pose::from_rotation_translation(
            DQuat::from_rotation_z(5e-6),
            Vector::new(2e-6, 0.0, 0.0),
        );
        let shown = magnified(&nominal, &(nominal * error), 1000.0);
        assert!((shown.translation - Vector::new(1.0, 2.002, 3.0)).length() < 1e-12);
        let angle = DQuat::from_mat3(&(rigid_inverse(&nominal) * shown).matrix3).to_scaled_axis();
        assert!((angle - Vector::new(0.0, 0.0, 5e-3)).length() < 1e-12);
        // ×1 is the actual pose itself.
        let same = magnified(&nominal, &(nominal * error), 1.0);
        assert!((same.translation - (nominal * error).translation).length() < 1e-15);
    }
}
