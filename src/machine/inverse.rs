//! Closed-form inverse kinematics: tool-tip position (and, on 5-axis machines, tool-axis
//! direction) in workpiece coordinates → axis values.
//!
//! The orientation is solved first. The tool-axis direction seen from the workpiece is
//! `k = C0 · R(u1, θ1) · C1 · R(u2, θ2) · C2 · e_z`, where the `C` are the constant rotations
//! of the chain and `R(u, θ)` the two rotary joints (workpiece-side joints enter inverted).
//! That is Paden–Kahan subproblem 2 (two rotations carrying one vector onto another), solved
//! in closed form with two solutions that differ in the sign of the tilting axis (A or B):
//! the [`TiltBranch`] picks one. With the rotary angles fixed, the tool-tip position is affine
//! in X, Y, Z, so the linear axes come from one 3×3 solve. The spindle angle is set to zero.

use super::{Axis, AxisValues, Machine, Side};
use crate::math::{Real, Rotation, Vector};
use std::f64::consts::PI;

/// What the tool should do, in the workpiece frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolTarget {
    /// Tool-tip position (m, workpiece frame).
    pub position: Vector,
    /// Tool-axis direction (unit, workpiece frame, pointing from the tip into the spindle).
    /// Required on 5-axis machines; on 3-axis machines it must be the machine's fixed tool axis
    /// or `None`.
    pub axis: Option<Vector>,
}

/// Which of the two closed-form solutions of a 5-axis machine to return: the sign of the
/// tilting axis (A on an A/C machine, B on a B/C machine).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TiltBranch {
    /// Tilt angle ≥ 0.
    Positive,
    /// Tilt angle ≤ 0.
    Negative,
}

/// Why no axis values reach a target.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum InverseKinematicsError {
    /// The tool-axis direction is not a unit vector, or is missing on a 5-axis machine.
    #[error("the tool-axis direction must be a unit vector (and is required on a 5-axis machine)")]
    BadAxis,
    /// No rotary angles give this tool-axis direction.
    #[error("no rotary-axis angles give the tool-axis direction ({0:.6} {1:.6} {2:.6})", .direction.x, .direction.y, .direction.z)]
    UnreachableDirection {
        /// The requested direction.
        direction: Vector,
    },
    /// The requested branch has no solution (the tilt of both solutions has the other sign).
    #[error("no solution on the {0:?} tilt branch")]
    NoSolutionOnBranch(TiltBranch),
    /// The solution lies outside an axis's travel.
    #[error(
        "axis {axis} would be at {value:.6} (SI units), outside its travel {lower:.6} .. {upper:.6}"
    )]
    OutOfTravel {
        /// The axis.
        axis: Axis,
        /// Its value (m or rad).
        value: Real,
        /// Lower limit.
        lower: Real,
        /// Upper limit.
        upper: Real,
    },
    /// The linear axes cannot reach the point (their directions are degenerate).
    #[error("the linear axes are degenerate at these rotary angles")]
    Degenerate,
    /// The two rotary axes are parallel, so they cannot orient the tool.
    #[error("the two rotary axes are parallel: they cannot orient the tool")]
    ParallelRotaryAxes,
    /// The target position is not finite.
    #[error("the target position must be finite")]
    NotFinite,
}

/// One factor of the rotation part of `workpiece_from_tool`.
enum Factor {
    Constant(Rotation),
    Joint {
        axis: Axis,
        unit: Vector,
        sign: Real,
    },
}

impl Machine {
    /// Axis values that put the tool tip at `target.position` with the tool axis along
    /// `target.axis`, on the given branch, with the spindle at zero. Nominal kinematics.
    pub fn inverse_kinematics(
        &self,
        target: &ToolTarget,
        branch: TiltBranch,
    ) -> Result<AxisValues, InverseKinematicsError> {
        if !target.position.is_finite() {
            return Err(InverseKinematicsError::NotFinite);
        }
        let is_unit = |k: Vector| (k.length() - 1.0).abs() <= 1e-9; // false for NaN
        let mut values = AxisValues::ZERO;
        let rotary: Vec<Axis> = self.rotary_axes().map(|info| info.axis).collect();
        let nominal_axis = self.workpiece_from_tool(&values).matrix3.z_axis;
        match (rotary.len(), target.axis) {
            (0, None) => {}
            (0, Some(k)) => {
                if !is_unit(k) {
                    return Err(InverseKinematicsError::BadAxis);
                }
                if (k - nominal_axis).length() > 1e-9 {
                    return Err(InverseKinematicsError::UnreachableDirection { direction: k });
                }
            }
            (_, None) => return Err(InverseKinematicsError::BadAxis),
            (_, Some(k)) => {
                if !is_unit(k) {
                    return Err(InverseKinematicsError::BadAxis);
                }
                self.solve_rotary(k, branch, &mut values)?;
            }
        }
        self.solve_linear(target.position, &mut values)?;
        if let Err((axis, value, (lower, upper))) = self.check_limits(&values) {
            return Err(InverseKinematicsError::OutOfTravel {
                axis,
                value,
                lower,
                upper,
            });
        }
        Ok(values)
    }

    /// The rotation of `workpiece_from_tool` as constants and joint rotations, with the spindle
    /// folded in at zero.
    fn rotation_factors(&self) -> Vec<Factor> {
        let branch_factors = |side: Side| -> Vec<Factor> {
            let branch = if side == Side::Tool {
                &self.tool_branch
            } else {
                &self.work_branch
            };
            let mut factors = Vec::new();
            let mut constant = Rotation::IDENTITY;
            for joint in &branch.joints {
                constant *= joint.origin.matrix3;
                if joint.axis.is_rotary() {
                    factors.push(Factor::Constant(constant));
                    factors.push(Factor::Joint {
                        axis: joint.axis,
                        unit: joint.unit,
                        sign: 1.0,
                    });
                    constant = Rotation::IDENTITY;
                }
            }
            factors.push(Factor::Constant(constant * branch.end.matrix3));
            factors
        };
        // R = R_work^T · R_tool; transposing reverses the work factors and negates their angles.
        let mut factors: Vec<Factor> = branch_factors(Side::Workpiece)
            .into_iter()
            .rev()
            .map(|factor| match factor {
                Factor::Constant(c) => Factor::Constant(c.transpose()),
                Factor::Joint { axis, unit, sign } => Factor::Joint {
                    axis,
                    unit,
                    sign: -sign,
                },
            })
            .collect();
        factors.extend(branch_factors(Side::Tool));
        factors
    }

    fn solve_rotary(
        &self,
        k: Vector,
        branch: TiltBranch,
        values: &mut AxisValues,
    ) -> Result<(), InverseKinematicsError> {
        // Merge into C0 · R1 · C1 · R2 · C2.
        let mut constants = vec![Rotation::IDENTITY];
        let mut joints = Vec::new();
        for factor in self.rotation_factors() {
            match factor {
                Factor::Constant(c) => *constants.last_mut().expect("non-empty") *= c,
                Factor::Joint { axis, unit, sign } => {
                    joints.push((axis, unit, sign));
                    constants.push(Rotation::IDENTITY);
                }
            }
        }
        let [(axis1, unit1, sign1), (axis2, unit2, sign2)] = joints[..] else {
            unreachable!("a validated 5-axis machine has two rotary axes");
        };
        let w = constants[0].transpose() * k;
        let u1 = unit1;
        let u2 = constants[1] * unit2;
        let v = constants[1] * (constants[2] * Vector::Z);

        let d = u1.dot(u2);
        let cross = u1.cross(u2);
        let denominator = 1.0 - d * d;
        if denominator < 1e-12 {
            return Err(InverseKinematicsError::ParallelRotaryAxes);
        }
        let a = (u1.dot(w) - d * u2.dot(v)) / denominator;
        let b = (u2.dot(v) - d * u1.dot(w)) / denominator;
        let c_squared =
            (v.length_squared() - a * a - b * b - 2.0 * a * b * d) / cross.length_squared();
        if c_squared < -1e-10 {
            return Err(InverseKinematicsError::UnreachableDirection { direction: k });
        }
        let c = c_squared.max(0.0).sqrt();

        let tilt_axis = if is_tilt(axis1) && !is_tilt(axis2) {
            axis1
        } else if is_tilt(axis2) && !is_tilt(axis1) {
            axis2
        } else {
            axis1.min(axis2)
        };
        for c_sign in [1.0, -1.0] {
            let z = a * u1 + b * u2 + c_sign * c * cross;
            let beta = rotation_angle(u2, v, z);
            let alpha = rotation_angle(u1, z, w);
            let mut candidate = *values;
            candidate[axis1] = wrap_angle(alpha * sign1);
            candidate[axis2] = wrap_angle(beta * sign2);
            let tilt = candidate[tilt_axis];
            let on_branch = match branch {
                TiltBranch::Positive => tilt >= -1e-12,
                TiltBranch::Negative => tilt <= 1e-12,
            };
            if on_branch {
                *values = candidate;
                return Ok(());
            }
        }
        Err(InverseKinematicsError::NoSolutionOnBranch(branch))
    }

    fn solve_linear(
        &self,
        target: Vector,
        values: &mut AxisValues,
    ) -> Result<(), InverseKinematicsError> {
        // The tip position is affine in X, Y, Z once the rotary axes are fixed.
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            values[axis] = 0.0;
        }
        let origin = self.workpiece_from_tool(values).translation;
        let mut columns = [Vector::ZERO; 3];
        for (column, axis) in columns.iter_mut().zip([Axis::X, Axis::Y, Axis::Z]) {
            let mut unit_move = *values;
            unit_move[axis] = 1.0;
            *column = self.workpiece_from_tool(&unit_move).translation - origin;
        }
        let matrix = Rotation::from_cols(columns[0], columns[1], columns[2]);
        if matrix.determinant().abs() < 1e-9 {
            return Err(InverseKinematicsError::Degenerate);
        }
        let solution = matrix.inverse() * (target - origin);
        values[Axis::X] = solution.x;
        values[Axis::Y] = solution.y;
        values[Axis::Z] = solution.z;
        Ok(())
    }
}

/// A or B: the axes that tilt the tool relative to a C table or head.
fn is_tilt(axis: Axis) -> bool {
    matches!(axis, Axis::A | Axis::B)
}

/// The angle about unit `u` that carries `from` onto `to` (Paden–Kahan subproblem 1), using
/// their components perpendicular to `u`; zero when `from` lies along `u`.
fn rotation_angle(u: Vector, from: Vector, to: Vector) -> Real {
    let from_perp = from - u * u.dot(from);
    let to_perp = to - u * u.dot(to);
    if from_perp.length_squared() < 1e-24 || to_perp.length_squared() < 1e-24 {
        return 0.0;
    }
    u.dot(from_perp.cross(to_perp))
        .atan2(from_perp.dot(to_perp))
}

/// An angle in (−π, π].
fn wrap_angle(angle: Real) -> Real {
    let wrapped = (angle + PI).rem_euclid(2.0 * PI) - PI;
    if wrapped <= -PI {
        wrapped + 2.0 * PI
    } else {
        wrapped
    }
}
