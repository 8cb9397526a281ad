//! The axis of rotation on the machine: its stator and rotor axis frames, and the actual pose of
//! the rotor in the stator from the twin — by the plain chain
//! ([`crate::errors::ErrorModel::workpiece_from_tool`]) or factored for speed.
//!
//! # Placing the frames
//!
//! At the parked position with the measured axis at 0, the nominal chain gives the axis's slot
//! frame (its joint frame: origin on the axis line, joint axis `u = ±` the letter's unit
//! vector). The rotor's end frame `E` is the end of the axis's branch (`tool` for a tool-side
//! axis such as the spindle S, `workpiece` for a table axis); the stator's end frame is the
//! other end. The axis frame's z is `u`, its x the next machine direction (see
//! [`super`]), its origin the artefact's reference point. `rotor_from_axis` (E ← F_r) is fixed
//! in `E`; `stator_from_axis` (stator end ← F_s) is the same frame at angle 0 on the nominal
//! chain, so that `F_s` and `F_r` coincide there.
//!
//! # The actual rotor pose
//!
//! `M = F_s ← F_r` actual: `stator_from_axis⁻¹ · A · rotor_from_axis` for a tool-side axis, with
//! `A` the actual `workpiece_from_tool`, and `stator_from_axis⁻¹ · A⁻¹ · rotor_from_axis` for a
//! workpiece-side one. Nominally `M = Rot_z(θ)`.
//!
//! **Factored.** The other axes stand still, so when none of their errors varies with time
//! (no content in Hz on another axis, [`crate::errors::ErrorModel::dynamics`]: content per
//! revolution and speed factors are constant on a parked axis), everything in the chain but
//! the measured axis's slot is constant: `M = K · S(θ, t) · R(θ) · Q`, with `K` and `Q`
//! evaluated once through the twin (the other slots' actual motions included) and `S` the
//! measured slot's motion built as the error model builds it (`line · Trans(δ) · Exp(ε)`, the
//! line motion `L·R·L⁻¹·R⁻¹` of the axis's location errors; as is on the tool branch, inverted
//! on the workpiece branch) and `R = Rot(u, θ)`. Along a record ([`AxisChain::along`]) the
//! angle-dependent factors are tabled on the index grid and only the measured axis's twist is
//! evaluated per sample. The factored pose agrees with the plain one to rounding (tests hold
//! it to 1e-12 m on the probes' points); with time-dependent errors on another axis the plain
//! chain is used.

use super::super::program::{Block, Sample};
use crate::errors::{ErrorModel, ErrorParameter, Frequency, Sinusoid};
use crate::machine::{Axis, AxisValues, MachineState, Side, Workspace};
use crate::math::{Pose, Real, Rotation, Vector, rigid_inverse, small_motion};
use crate::twin::Twin;
use glam::DMat3;
use std::f64::consts::TAU;

/// Why the axis frames cannot be placed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FrameError {
    /// The machine lacks the axis.
    #[error("machine \"{machine}\" has no axis {axis}")]
    MissingAxis {
        /// The machine.
        machine: String,
        /// The axis.
        axis: Axis,
    },
    /// The axis is linear.
    #[error("{0} is not an axis of rotation")]
    Linear(Axis),
}

/// The measured axis on the machine: its frames and the factored chain.
#[derive(Clone, Debug)]
pub struct AxisChain {
    /// The axis of rotation.
    pub axis: Axis,
    /// The branch it turns (the rotor's side).
    pub side: Side,
    slot: usize,
    unit: Vector,
    /// Stator end frame ← F_s (m).
    pub stator_from_axis: Pose,
    /// Rotor end frame ← F_r (m).
    pub rotor_from_axis: Pose,
    /// The axis's slot frame as seen in F_s (nominal, angle 0): where its component errors act.
    pub axis_from_slot: Pose,
    /// The parked position, the measured axis at 0.
    pub parked: AxisValues,
    measured: ErrorModel,
    factored: Option<(Pose, Pose)>,
}

/// Per-thread scratch of an [`AxisChain`].
#[derive(Clone, Debug)]
pub struct ChainScratch {
    workspace: Workspace,
}

impl ChainScratch {
    /// Scratch for `twin`'s machine.
    pub fn new(twin: &Twin) -> ChainScratch {
        ChainScratch {
            workspace: Workspace::new(&twin.machine),
        }
    }
}

/// The axis frame's axes in the slot frame: z = `u`, x the next coordinate direction, y = z × x.
fn axis_basis(axis: Axis, unit: Vector) -> Rotation {
    let x = Vector::AXES[(axis.coordinate() + 1) % 3];
    Rotation::from_cols(x, unit.cross(x), unit)
}

impl AxisChain {
    /// Places `axis` on `twin`'s machine with the other axes at `parked` (the measured axis's
    /// value there is ignored) and the artefact's reference point `stickout` (m) below the foot
    /// of the perpendicular from the rotor's end frame onto the axis line.
    pub fn new(
        twin: &Twin,
        axis: Axis,
        parked: AxisValues,
        stickout: Real,
    ) -> Result<AxisChain, FrameError> {
        let machine = &twin.machine;
        let info = machine.axis(axis).ok_or_else(|| FrameError::MissingAxis {
            machine: machine.name().to_string(),
            axis,
        })?;
        if axis.is_linear() {
            return Err(FrameError::Linear(axis));
        }
        let (slot, side, unit) = (info.slot, info.side, info.joint_axis);
        let parked = parked.with(axis, 0.0);
        let mut workspace = Workspace::new(machine);
        let nominal = workspace.workpiece_from_tool(machine, &parked, None);
        let world_from_slot = workspace.world_from_slot()[slot];
        let (world_from_tool, world_from_workpiece) = workspace.world_from_ends();
        let world_from_rotor_end = match side {
            Side::Tool => world_from_tool,
            Side::Workpiece => world_from_workpiece,
        };
        let rotor_from_slot = rigid_inverse(&world_from_rotor_end) * world_from_slot;
        let basis = rotor_from_slot.matrix3 * axis_basis(axis, unit);
        let along = basis.z_axis;
        let on_line = rotor_from_slot.translation;
        let foot = on_line - along * on_line.dot(along);
        let rotor_from_axis = Pose::from_mat3_translation(basis, foot - along * stickout);
        let stator_from_rotor = match side {
            Side::Tool => nominal,
            Side::Workpiece => rigid_inverse(&nominal),
        };
        let stator_from_axis = stator_from_rotor * rotor_from_axis;
        let axis_from_slot = rigid_inverse(&rotor_from_axis) * rotor_from_slot;

        let parameters = twin
            .errors
            .parameters()
            .iter()
            .filter(|p| p.name.axis() == Some(axis))
            .cloned()
            .collect();
        let (own, others): (Vec<_>, Vec<_>) = twin
            .errors
            .dynamics()
            .iter()
            .cloned()
            .partition(|d| d.name.axis() == Some(axis));
        let measured = ErrorModel::new(machine, parameters)
            .and_then(|m| m.with_dynamics(machine, own))
            .expect("a subset of a valid error model is valid");

        // Another axis's content per revolution or speed factor is constant while it is parked
        // (its angle fixed, its speed 0); content in Hz varies with time.
        let time_dependent = others.iter().any(|d| {
            d.dynamics
                .sinusoids
                .iter()
                .any(|s| matches!(s.frequency, Frequency::Hz(_)))
                || d.dynamics
                    .random
                    .as_ref()
                    .is_some_and(|r| !r.per_revolution)
        });
        let factored = (!time_dependent).then(|| {
            // Everything but the measured slot, through the twin, once.
            let state = MachineState::at(parked);
            let mut motions = twin
                .errors
                .slot_motions(machine, &mut workspace, &state, None);
            let before = workspace.world_from_slot()[slot];
            motions[slot] = Pose::IDENTITY;
            workspace.workpiece_from_tool(machine, &parked, Some(&motions));
            let (tool_end, workpiece_end) = workspace.world_from_ends();
            let (rotor_end, stator_end) = match side {
                Side::Tool => (tool_end, workpiece_end),
                Side::Workpiece => (workpiece_end, tool_end),
            };
            let after = rigid_inverse(&before) * rotor_end;
            (
                rigid_inverse(&stator_from_axis) * rigid_inverse(&stator_end) * before,
                after * rotor_from_axis,
            )
        });
        Ok(AxisChain {
            axis,
            side,
            slot,
            unit,
            stator_from_axis,
            rotor_from_axis,
            axis_from_slot,
            parked,
            measured,
            factored,
        })
    }

    /// Whether the factored chain is in use (no time-dependent error on another axis).
    pub fn is_factored(&self) -> bool {
        self.factored.is_some()
    }

    /// The state the twin is evaluated at: parked, the axis at unwrapped angle `q` (rad)
    /// turning at `speed` (rad/s), at `time` (s).
    pub fn state(&self, q: Real, speed: Real, time: Real) -> MachineState {
        MachineState::at(self.parked.with(self.axis, q))
            .at_time(time)
            .with_velocity(self.axis, speed)
    }

    /// `M`, the actual rotor axis frame in the stator axis frame at `state`, by the plain chain.
    pub fn rotor_in_stator_plain(
        &self,
        twin: &Twin,
        scratch: &mut ChainScratch,
        state: &MachineState,
    ) -> Pose {
        let actual = twin
            .errors
            .workpiece_from_tool(&twin.machine, &mut scratch.workspace, state);
        let stator_from_rotor = match self.side {
            Side::Tool => actual,
            Side::Workpiece => rigid_inverse(&actual),
        };
        rigid_inverse(&self.stator_from_axis) * stator_from_rotor * self.rotor_from_axis
    }

    /// The chain along one record (`block`): [`RecordChain::pose`] gives `M` sample by
    /// sample, factored when possible.
    pub fn along<'a>(&'a self, twin: &'a Twin, block: &Block) -> RecordChain<'a> {
        let per_rev = block.samples_per_revolution;
        let Some((before, after)) = self.factored else {
            return RecordChain {
                chain: self,
                twin,
                block: *block,
                factored: None,
            };
        };
        let machine = &twin.machine;
        // The synchronous twist at each grid angle, each parameter scaled by its speed factor
        // at this record's speed (a factor multiplies the whole parameter).
        let factor_of = |name| {
            self.measured
                .dynamics()
                .iter()
                .find(|d| d.name == name)
                .map_or(1.0, |d| d.dynamics.factor(block.speed))
        };
        let scaled: Vec<ErrorParameter> = self
            .measured
            .parameters()
            .iter()
            .map(|p| {
                let mut p = p.clone();
                let factor = factor_of(p.name);
                if factor != 1.0 {
                    let mut c = Vec::new();
                    p.function.coefficients(&mut c);
                    c.iter_mut().for_each(|v| *v *= factor);
                    p.function.set_coefficients(&c);
                }
                p
            })
            .collect();
        let synchronous = ErrorModel::new(machine, scaled).expect("scaled parameters stay valid");
        let slots = machine.slot_count();
        let (mut relative, mut line) = (vec![[0.0; 6]; slots], vec![[0.0; 6]; slots]);
        let mut twists = Vec::with_capacity(per_rev);
        let mut located = None;
        let mut outer = Vec::with_capacity(per_rev);
        let mut inner = Vec::with_capacity(per_rev);
        for m in 0..per_rev {
            let theta = TAU * m as Real / per_rev as Real;
            let state = self.state(theta, block.speed, 0.0);
            synchronous.slot_twists(&state, &mut relative, &mut line);
            twists.push(relative[self.slot]);
            let l = line[self.slot];
            let line_pose = located.get_or_insert_with(|| {
                (l != [0.0; 6]).then(|| {
                    small_motion(Vector::new(l[0], l[1], l[2]), Vector::new(l[3], l[4], l[5]))
                })
            });
            let rotation = Pose::from_mat3(DMat3::from_axis_angle(self.unit, theta));
            // M = outer · Exp(twist)^(±1) · inner: the slot motion as the error model builds it
            // (line · relative), as is on the tool branch and inverted on the workpiece branch,
            // then the joint's rotation.
            let (o, i) = match (self.side, line_pose) {
                (Side::Tool, None) => (before, rotation * after),
                (Side::Tool, Some(l)) => (
                    before * *l * rotation * rigid_inverse(l) * rigid_inverse(&rotation),
                    rotation * after,
                ),
                (Side::Workpiece, None) => (before, rotation * after),
                (Side::Workpiece, Some(l)) => (before, *l * rotation * rigid_inverse(l) * after),
            };
            outer.push(o);
            inner.push(i);
        }
        let interval = block.interval();
        let mut lines: Vec<Lines> = Vec::new();
        for d in self.measured.dynamics() {
            let factor = d.dynamics.factor(block.speed);
            let component = d.name.motion().index();
            let index = match lines.iter().position(|l| l.component == component) {
                Some(index) => index,
                None => {
                    lines.push(Lines {
                        component,
                        ..Lines::default()
                    });
                    lines.len() - 1
                }
            };
            let set = &mut lines[index];
            let random = d.dynamics.random.iter().flat_map(|r| r.lines.iter());
            for s in d.dynamics.sinusoids.iter().chain(random) {
                let step = match s.frequency {
                    Frequency::Hz(f) => TAU * f * interval,
                    Frequency::PerRevolution(r) => r * block.speed.signum() * TAU / per_rev as Real,
                };
                let (step_sin, step_cos) = step.sin_cos();
                set.sinusoids.push(*s);
                set.amplitude.push(factor * s.amplitude);
                set.step_sin.push(step_sin);
                set.step_cos.push(step_cos);
                // Set at the record's first sample, which is evaluated afresh.
                set.sin.push(0.0);
                set.cos.push(0.0);
            }
        }
        RecordChain {
            chain: self,
            twin,
            block: *block,
            factored: Some(Factored {
                twists,
                outer,
                inner,
                lines,
                next: None,
            }),
        }
    }
}

/// The asynchronous sinusoids acting on one twist component along a record, advanced sample
/// by sample (stored by column so that the loops vectorise). Each line is held as its phasor
/// scaled by its amplitude, `a·(sin, cos)`: a rotation by the phase step is linear, so the
/// scaled phasor advances as the unit one does and the sum is that of the scaled sines.
#[derive(Clone, Debug, Default)]
struct Lines {
    component: usize,
    sinusoids: Vec<Sinusoid>,
    /// Each amplitude times its parameter's speed factor at the record's speed.
    amplitude: Vec<Real>,
    step_sin: Vec<Real>,
    step_cos: Vec<Real>,
    /// `a·sin` and `a·cos` of each line at the current sample.
    sin: Vec<Real>,
    cos: Vec<Real>,
}

impl Lines {
    /// Their sum at the sample at `time` and unwrapped angle `position`: evaluated afresh when
    /// `exact`, else advanced by one step from the previous sample.
    fn value(&mut self, exact: bool, time: Real, position: Real) -> Real {
        if exact {
            let scaled = self.sin.iter_mut().zip(self.cos.iter_mut());
            for ((s, a), (sin, cos)) in self.sinusoids.iter().zip(&self.amplitude).zip(scaled) {
                let argument = match s.frequency {
                    Frequency::Hz(frequency) => TAU * frequency * time,
                    Frequency::PerRevolution(ratio) => ratio * position,
                };
                let (unit_sin, unit_cos) = (argument + s.phase).sin_cos();
                (*sin, *cos) = (a * unit_sin, a * unit_cos);
            }
            return four_lane_sum(&self.sin);
        }
        let steps = self.step_sin.iter().zip(&self.step_cos);
        for ((sin, cos), (ss, sc)) in self.sin.iter_mut().zip(self.cos.iter_mut()).zip(steps) {
            (*sin, *cos) = (*sin * sc + *cos * ss, *cos * sc - *sin * ss);
        }
        four_lane_sum(&self.sin)
    }
}

/// The sum of `values`: four partial sums over whole groups of four (they vectorise), then the
/// rest.
fn four_lane_sum(values: &[Real]) -> Real {
    let mut partial = [0.0; 4];
    let chunks = values.chunks_exact(4);
    let rest: Real = chunks.remainder().iter().sum();
    for c in chunks {
        for k in 0..4 {
            partial[k] += c[k];
        }
    }
    (partial[0] + partial[1]) + (partial[2] + partial[3]) + rest
}

/// What a factored record holds.
#[derive(Clone, Debug)]
struct Factored {
    /// The measured slot's synchronous twist at each grid angle.
    twists: Vec<[Real; 6]>,
    /// `M = outer[m] · Exp(twist)^(±1) · inner[m]`.
    outer: Vec<Pose>,
    inner: Vec<Pose>,
    lines: Vec<Lines>,
    /// The sample the lines stand at.
    next: Option<usize>,
}

/// The chain along one record: see [`AxisChain::along`].
///
/// **Factored**, the synchronous part of the measured axis's twist is evaluated once per grid
/// angle (it depends on the angle, the direction and, through the speed factor, the speed,
/// which a record holds), and each asynchronous sinusoid (its content in Hz or per revolution,
/// the lines of its random motion) advances by a fixed phase step per sample — a rotation of
/// its sine and cosine, evaluated afresh at each revolution's first sample (and whenever the
/// samples are not taken in order) so that rounding cannot build up.
pub struct RecordChain<'a> {
    chain: &'a AxisChain,
    twin: &'a Twin,
    block: Block,
    factored: Option<Factored>,
}

impl RecordChain<'_> {
    /// `M` at sample `j` of the record (`sample = block.sample(j)`).
    pub fn pose(&mut self, j: usize, sample: &Sample, scratch: &mut ChainScratch) -> Pose {
        let Some(f) = &mut self.factored else {
            let state = self
                .chain
                .state(sample.position, self.block.speed, sample.time);
            return self.chain.rotor_in_stator_plain(self.twin, scratch, &state);
        };
        let m = sample.angle_index;
        let mut t = f.twists[m];
        let exact = f.next != Some(j) || j.is_multiple_of(self.block.samples_per_revolution);
        for lines in &mut f.lines {
            t[lines.component] += lines.value(exact, sample.time, sample.position);
        }
        f.next = Some(j + 1);
        let small = small_motion(Vector::new(t[0], t[1], t[2]), Vector::new(t[3], t[4], t[5]));
        match self.chain.side {
            Side::Tool => f.outer[m] * small * f.inner[m],
            Side::Workpiece => f.outer[m] * rigid_inverse(&small) * f.inner[m],
        }
    }
}
