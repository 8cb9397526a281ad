//! What the machine does in an R-test: the rotary axes move from one set of angles to another
//! while the linear axes follow so that the nominal tool tip (the nest's reference point)
//! stays on the sphere centre (tool-centre-point control). A K-test of ISO 10791-6 is one such
//! move: C turning at a fixed A (a "CK1"-style circle), A swinging at a fixed C, or both at
//! once (a simultaneous 5-axis path).
//!
//! - **Static**: the machine stops at `points` equally spaced poses and the nest reads there.
//! - **Dynamic**: the rotary axes move at a constant rate, the controller interpolates every
//!   axis each interpolation period and each axis follows through its position loop
//!   ([`crate::program::AxisLoop`]); the nest samples on the move at its rate.

use crate::machine::{Axis, AxisValues, Direction, Machine, MachineState, Workspace};
use crate::math::{Real, Vector};
use crate::program::servo::{Sampling, sample_loops};
use crate::program::{AxisLoop, AxisServo};

/// One test: the rotary axes from `from` to `to` (rad), the linear axes following.
#[derive(Clone, Debug, PartialEq)]
pub struct KTest {
    /// Its name (`CK1 A0`, …), unique in the scenario.
    pub name: String,
    /// The rotary angles at the start (rad; linear axes ignored).
    pub from: AxisValues,
    /// The rotary angles at the end (rad).
    pub to: AxisValues,
    /// Poses read in static mode from `from` to `to` (≥ 2, ends included).
    pub points: usize,
    /// Whether the test then returns to `from` along the same path (the poses read again in
    /// reverse order, the end read once): each pose approached both ways, and the start read
    /// again at the end, an anchor for drift.
    pub back: bool,
}

impl KTest {
    /// The rotary angles a fraction `lambda` ∈ [0, 1] along the test (out and, with
    /// [`KTest::back`], back: the end at one half).
    pub fn angles_at(&self, machine: &Machine, lambda: Real) -> AxisValues {
        let along = if self.back {
            1.0 - (1.0 - 2.0 * lambda).abs()
        } else {
            lambda
        };
        let mut out = AxisValues::ZERO;
        for info in machine.rotary_axes() {
            let (a, b) = (self.from[info.axis], self.to[info.axis]);
            out[info.axis] = a + (b - a) * along;
        }
        out
    }

    /// The poses a static test reads: [`KTest::points`], or `2·points − 1` going back.
    pub fn pose_count(&self) -> usize {
        if self.back {
            2 * self.points - 1
        } else {
            self.points
        }
    }

    /// The rotary axis that turns furthest: the angle the analysis fits against.
    pub fn swept_axis(&self, machine: &Machine) -> Option<Axis> {
        machine
            .rotary_axes()
            .map(|info| (info.axis, (self.to[info.axis] - self.from[info.axis]).abs()))
            .filter(|(_, range)| *range > 0.0)
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(axis, _)| axis)
    }

    /// The largest rotary travel of the test (rad), both ways with [`KTest::back`].
    pub fn rotary_travel(&self, machine: &Machine) -> Real {
        let one_way = machine
            .rotary_axes()
            .map(|info| (self.to[info.axis] - self.from[info.axis]).abs())
            .fold(0.0, Real::max);
        if self.back { 2.0 * one_way } else { one_way }
    }
}

/// Why the linear axes cannot follow the sphere.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FollowError {
    /// The linear axes' directions are degenerate.
    #[error("the linear axes cannot reach the sphere (degenerate directions)")]
    Degenerate,
    /// The sphere is out of reach at these angles.
    #[error(
        "at {angles} the tool tip cannot reach the sphere: {axis} would be at {value}, outside its travel {lower} … {upper}"
    )]
    OutOfTravel {
        /// The rotary angles, for people.
        angles: String,
        /// The axis.
        axis: Axis,
        /// Where it would be (mm or deg).
        value: String,
        /// Lower limit (mm or deg).
        lower: String,
        /// Upper limit.
        upper: String,
    },
}

/// The axis values that put the nominal tool tip on `target` (workpiece frame) at the rotary
/// angles of `angles`: the tool tip is affine in X, Y, Z at fixed angles, so one 3×3 solve.
pub fn follow(
    machine: &Machine,
    workspace: &mut Workspace,
    angles: &AxisValues,
    target: Vector,
) -> Result<AxisValues, FollowError> {
    let linear = [Axis::X, Axis::Y, Axis::Z];
    let mut position = *angles;
    for axis in linear {
        position[axis] = 0.0;
    }
    let t0 = workspace
        .workpiece_from_tool(machine, &position, None)
        .translation;
    let mut columns = [Vector::ZERO; 3];
    for (column, axis) in columns.iter_mut().zip(linear) {
        let mut step = position;
        step[axis] = 1.0;
        *column = workspace
            .workpiece_from_tool(machine, &step, None)
            .translation
            - t0;
    }
    let jacobian = crate::math::Rotation::from_cols(columns[0], columns[1], columns[2]);
    if jacobian.determinant().abs() < 1e-9 {
        return Err(FollowError::Degenerate);
    }
    let solution = jacobian.inverse() * (target - t0);
    for (i, axis) in linear.into_iter().enumerate() {
        position[axis] = solution[i];
    }
    if let Err((axis, value, (lower, upper))) = machine.check_limits(&position) {
        let unit = crate::machine::axis_unit_to_si(axis);
        let show = |v: Real| crate::math::trimmed(v / unit, 3);
        return Err(FollowError::OutOfTravel {
            angles: describe_angles(machine, angles),
            axis,
            value: show(value),
            lower: show(lower),
            upper: show(upper),
        });
    }
    Ok(position)
}

/// `A = -90°, C = 30°`: the rotary angles of a pose, for people.
pub fn describe_angles(machine: &Machine, angles: &AxisValues) -> String {
    machine
        .rotary_axes()
        .map(|info| {
            format!(
                "{} = {}°",
                info.axis,
                crate::math::trimmed(angles[info.axis].to_degrees(), 4)
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// One pose the nest reads: when, the controller's rotary angles, and the machine's state
/// (the axes where they actually are).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Time since the start of the test (s).
    pub time: Real,
    /// The controller's axis values (commanded; m, rad).
    pub command: AxisValues,
    /// The actual axis positions and directions of travel.
    pub state: MachineState,
}

/// The static poses of `test`: stop at each of `points`, `dwell` seconds apart, each axis
/// arriving as [`arrival_directions`] says.
pub fn static_poses(
    machine: &Machine,
    workspace: &mut Workspace,
    test: &KTest,
    sphere: Vector,
    dwell: Real,
) -> Result<Vec<Pose>, FollowError> {
    let count = test.pose_count();
    let commands = (0..count)
        .map(|k| {
            let lambda = k as Real / (count - 1) as Real;
            follow(machine, workspace, &test.angles_at(machine, lambda), sphere)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let directions = arrival_directions(&commands);
    Ok(commands
        .iter()
        .zip(directions)
        .enumerate()
        .map(|(k, (&command, direction))| Pose {
            time: k as Real * dwell,
            command,
            state: MachineState {
                direction,
                ..MachineState::at(command)
            },
        })
        .collect())
}

/// The direction each axis arrives at each of a test's `commands` in: the direction it last
/// moved (kept while it stands still), and at the first pose the direction of its first move
/// in the test (the start approached the way the test goes on, as a test programme's
/// pre-positioning does; `Positive` for an axis that does not move). The simulation and the
/// model of a table's readings ([`super::readings`]) both use this rule, so that a lost motion
/// of a rotary axis reads the same in both.
pub fn arrival_directions(commands: &[AxisValues]) -> Vec<[Direction; 7]> {
    let step_direction = |a: Real, b: Real| {
        if b > a {
            Some(Direction::Positive)
        } else if b < a {
            Some(Direction::Negative)
        } else {
            None
        }
    };
    let mut current = [Direction::Positive; 7];
    for (i, direction) in current.iter_mut().enumerate() {
        if let Some(first) = commands
            .windows(2)
            .find_map(|w| step_direction(w[0].0[i], w[1].0[i]))
        {
            *direction = first;
        }
    }
    let mut out = Vec::with_capacity(commands.len());
    for (k, command) in commands.iter().enumerate() {
        if k > 0 {
            for (i, direction) in current.iter_mut().enumerate() {
                if let Some(moved) = step_direction(commands[k - 1].0[i], command.0[i]) {
                    *direction = moved;
                }
            }
        }
        out.push(current);
    }
    out
}

/// Dynamic mode: the loops rest this long (s) at each end of a test, so they start and end
/// at rest.
pub const SETTLE: Real = 0.2;

/// How a dynamic test runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Dynamic {
    /// Speed of the swept rotary axis (rad/s).
    pub rate: Real,
    /// The nest's sampling rate (Hz).
    pub sample_rate: Real,
    /// The interpolation period (s).
    pub ipo_period: Real,
    /// Position-loop gain per axis (1/s), indexed like [`AxisValues`].
    pub kv: [Real; 7],
}

impl Dynamic {
    /// The position loop of `axis`: its gain, no feed-forward, spike or vibration.
    pub fn servo(&self, axis: Axis) -> AxisServo {
        AxisServo {
            kv: self.kv[axis.index()],
            ..AxisServo::DEFAULT
        }
    }
}

/// The dynamic run of `test`: the rotary axes at `dynamic.rate` on the swept axis, every axis
/// through its loop, the nest sampling at its rate. Settles [`SETTLE`] seconds at each end so
/// the loops start and end at rest.
pub fn dynamic_poses(
    machine: &Machine,
    workspace: &mut Workspace,
    test: &KTest,
    sphere: Vector,
    dynamic: &Dynamic,
) -> Result<Vec<Pose>, FollowError> {
    let Dynamic {
        rate,
        sample_rate,
        ipo_period,
        ..
    } = *dynamic;
    let travel = test.rotary_travel(machine);
    let move_time = if travel > 0.0 { travel / rate } else { 0.0 };
    let settle = SETTLE;
    let duration = move_time + 2.0 * settle;
    let command_at = |workspace: &mut Workspace, t: Real| {
        let lambda = if move_time > 0.0 {
            ((t - settle) / move_time).clamp(0.0, 1.0)
        } else {
            0.0
        };
        follow(machine, workspace, &test.angles_at(machine, lambda), sphere)
    };
    let start = command_at(workspace, 0.0)?;
    // Each loop starts at rest having last moved the way the test goes on (as the static
    // poses do): the first step of the path, a thousandth of it.
    let first_step = follow(machine, workspace, &test.angles_at(machine, 1e-3), sphere)?;
    let initial = arrival_directions(&[start, first_step])[0];
    let mut loops: Vec<AxisLoop> = machine
        .axes()
        .iter()
        .filter(|info| info.axis != Axis::S)
        .map(|info| {
            AxisLoop::new(
                dynamic.servo(info.axis),
                info.axis,
                start[info.axis],
                initial[info.axis.index()],
            )
        })
        .collect();
    let mut poses = Vec::with_capacity((duration * sample_rate) as usize + 1);
    sample_loops(
        &mut loops,
        &start,
        Sampling {
            ipo_period,
            duration,
            sample_period: 1.0 / sample_rate,
        },
        MachineState::at(AxisValues::ZERO),
        |t| command_at(workspace, t),
        |t, state| {
            poses.push(Pose {
                time: t,
                command: AxisValues::ZERO,
                state: *state,
            });
            Ok(())
        },
    )?;
    // The controller's command at each sample (the path exactly; the interpolator's chords
    // differ from it by nanometres).
    for pose in &mut poses {
        pose.command = command_at(workspace, pose.time)?;
    }
    Ok(poses)
}
