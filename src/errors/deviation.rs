//! The tool-in-workpiece deviation ([`Deviation`]) and its first-order model: how it responds
//! to each slot's twist ([`ErrorModel::slot_sensitivities`]) and to each coefficient
//! ([`ErrorModel::jacobian`], [`ErrorModel::stacked_jacobian`]).

use super::ErrorModel;
use super::binding::Action;
use crate::machine::{Direction, Machine, MachineState, Side, Workspace};
use crate::math::{Pose, Real, Vector, rigid_inverse};

/// The tool-in-workpiece deviation: actual − nominal, in the workpiece frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Tool-tip position deviation (m, workpiece frame).
    pub translation: Vector,
    /// Tool-axis tilt (rad): the change of the tool-axis unit vector along the nominal tool
    /// frame's x (`ti`) and y (`tj`) axes. That frame turns with the spindle angle S; the
    /// volumetric map holds S at zero.
    pub tilt: [Real; 2],
}

impl Deviation {
    /// As `[dx, dy, dz, ti, tj]` (m, rad): the rows of [`ErrorModel::jacobian`].
    pub fn to_array(self) -> [Real; 5] {
        [
            self.translation.x,
            self.translation.y,
            self.translation.z,
            self.tilt[0],
            self.tilt[1],
        ]
    }

    /// The deviation between a nominal and an actual `workpiece_from_tool`.
    pub fn between(nominal: &Pose, actual: &Pose) -> Deviation {
        let dk = actual.matrix3.z_axis - nominal.matrix3.z_axis;
        Deviation {
            translation: actual.translation - nominal.translation,
            tilt: [
                dk.dot(nominal.matrix3.x_axis),
                dk.dot(nominal.matrix3.y_axis),
            ],
        }
    }
}

impl ErrorModel {
    /// The sensitivity of the deviation `[dx, dy, dz, ti, tj]` to each slot's twist, at the
    /// nominal pose: `out[slot][row][component]`.
    ///
    /// A twist ξ = (δ, ε) at a slot with frame F moves the tool to
    /// `workpiece_from_F · Exp(ξ) · F_from_tool` (on either branch, by the sign convention),
    /// so to first order `dp = R_F (δ + ε × p_F)` and `dk = R_F (ε × k_F)`, with `p_F`, `k_F`
    /// the nominal tool tip and tool axis in F.
    pub fn slot_sensitivities(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
        out: &mut [[[Real; 6]; 5]],
    ) {
        self.assert_bound_to(machine);
        assert_eq!(out.len(), self.slot_count, "one sensitivity per slot");
        let workpiece_from_tool = workspace.workpiece_from_tool(machine, &state.position, None);
        let world_from_workpiece =
            workspace.world_from_slot[machine.tool_slot()] * rigid_inverse(&workpiece_from_tool);
        let workpiece_from_world = rigid_inverse(&world_from_workpiece);
        let tip = workpiece_from_tool.translation;
        let k = workpiece_from_tool.matrix3.z_axis;
        let (i_axis, j_axis) = (
            workpiece_from_tool.matrix3.x_axis,
            workpiece_from_tool.matrix3.y_axis,
        );
        for (slot, sensitivity) in out.iter_mut().enumerate() {
            let workpiece_from_slot = workpiece_from_world * workspace.world_from_slot[slot];
            let rotation = workpiece_from_slot.matrix3;
            // Lever arm from the slot origin to the tip, in the workpiece frame.
            let lever = tip - workpiece_from_slot.translation;
            for component in 0..6 {
                let (dp, dk) = if component < 3 {
                    (rotation.col(component), Vector::ZERO)
                } else {
                    let e = rotation.col(component - 3);
                    (e.cross(lever), e.cross(k))
                };
                let column = [dp.x, dp.y, dp.z, dk.dot(i_axis), dk.dot(j_axis)];
                for (row, value) in sensitivity.iter_mut().zip(column) {
                    row[component] = value;
                }
            }
        }
    }

    /// The Jacobian of the deviation `[dx, dy, dz, ti, tj]` with respect to every linear
    /// coefficient, linearised about zero error at `state`: `columns[c][row]`.
    ///
    /// `Deviation ≈ Σ_c columns[c] · coefficient_c` to first order in the errors; the
    /// difference from the exact chain is second order. To first order a squareness `ε` of a
    /// linear axis adds the relative twist `(ε × u·q, 0)`, and a rotary axis line `ξ = (δ, ε)`
    /// adds `±(ξ − Ad_R ξ) = ±(δ − Rδ, ε − Rε)` (+ on the tool side, − on the workpiece side).
    pub fn jacobian(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        state: &MachineState,
        columns: &mut [[Real; 5]],
    ) {
        assert_eq!(
            columns.len(),
            self.coefficient_count(),
            "one column per coefficient"
        );
        let mut sensitivities = std::mem::take(&mut workspace.slot_sensitivities);
        let mut basis = std::mem::take(&mut workspace.basis);
        self.slot_sensitivities(machine, workspace, state, &mut sensitivities);
        let mut column = 0;
        for (parameter, binding) in self.parameters.iter().zip(&self.bindings) {
            basis.clear();
            let component = parameter.name.motion().index();
            // The relative twist per unit of the parameter.
            let mut unit_twist = [0.0; 6];
            match binding.action {
                Action::Component(axis) => {
                    unit_twist[component] = 1.0;
                    parameter.function.basis(
                        binding.argument(state.position[axis]),
                        state.direction(axis),
                        &mut basis,
                    );
                }
                Action::Constant => {
                    unit_twist[component] = 1.0;
                    parameter
                        .function
                        .basis(0.0, Direction::Positive, &mut basis);
                }
                Action::Squareness(axis) => {
                    let translation =
                        Vector::AXES[component - 3].cross(axis.unit()) * state.position[axis];
                    unit_twist[..3].copy_from_slice(&translation.to_array());
                    parameter
                        .function
                        .basis(0.0, Direction::Positive, &mut basis);
                }
                Action::RotaryLocation(axis) => {
                    let info = &machine.axes()[binding.slot];
                    // The nominal evaluation above left the joint's rotation at this position.
                    let walked = &workspace.rotations[binding.slot];
                    let rotation = if walked.unit == info.joint_axis {
                        walked.matrix()
                    } else {
                        glam::DMat3::from_axis_angle(info.joint_axis, state.position[axis])
                    };
                    let side = if info.side == Side::Tool { 1.0 } else { -1.0 };
                    let e = Vector::AXES[component % 3];
                    let moved = (e - rotation * e) * side;
                    let offset = if component < 3 { 0 } else { 3 };
                    unit_twist[offset..offset + 3].copy_from_slice(&moved.to_array());
                    parameter
                        .function
                        .basis(0.0, Direction::Positive, &mut basis);
                }
            }
            let s = &sensitivities[binding.slot];
            for &b in &basis {
                for row in 0..5 {
                    columns[column][row] =
                        b * (0..6).map(|k| s[row][k] * unit_twist[k]).sum::<Real>();
                }
                column += 1;
            }
        }
        workspace.slot_sensitivities = sensitivities;
        workspace.basis = basis;
    }

    /// The Jacobians at many states stacked into the design matrix of a linearised estimator:
    /// five rows per state (`dx, dy, dz, ti, tj`, in that order), one column per coefficient.
    /// Its null space is what the states cannot tell apart.
    pub fn stacked_jacobian(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        states: &[MachineState],
    ) -> nalgebra::DMatrix<Real> {
        let n = self.coefficient_count();
        let mut matrix = nalgebra::DMatrix::zeros(5 * states.len(), n);
        let mut columns = vec![[0.0; 5]; n];
        for (i, state) in states.iter().enumerate() {
            self.jacobian(machine, workspace, state, &mut columns);
            for (c, column) in columns.iter().enumerate() {
                for (row, value) in column.iter().enumerate() {
                    matrix[(5 * i + row, c)] = *value;
                }
            }
        }
        matrix
    }
}
