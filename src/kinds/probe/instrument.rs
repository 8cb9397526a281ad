//! The virtual kinematic touch-trigger probe in the spindle.
//!
//! A simplified model of a kinematic-seat probe (Estler et al. 1996/97; the wave-2 anchors §2.3):
//!
//! - the stylus ball: the radius the controller believes ([`TouchProbe::stylus_radius`]) and
//!   the true one, which differ by [`TouchProbe::radius_error`] (true − believed);
//! - pre-travel: the stylus deflects before the seat opens, by
//!   `δ = s²·(δ0 + δ3·cos 3(θ − θ0)) + c²·δz`, with `θ` the approach direction's azimuth in the
//!   tool frame (from its x axis), `s` and `c` the sine and cosine of its angle to the stylus
//!   axis (a smooth blend from the 3-lobe lateral value to the axial one, not a mechanical
//!   model; no stylus bending or gravity term);
//! - latency: the axes latched `v·t` after the trigger;
//! - repeatability: a Gaussian trigger scatter of standard deviation σ along the motion.
//!
//! The touch is with the actual tool pose from the twin, while the controller moves and latches
//! nominal axis values: the travel at which the actual stylus ball touches is found by a few
//! fixed-point steps ([`TouchProbe::touch`]), then pre-travel, latency and scatter are added
//! along the motion, and the axis values there are what the controller latches.

use super::cycles::{ProbeMove, Target};
use crate::contact::{Approach, ContactError};
use crate::machine::{Axis, AxisValues, Direction, MachineState, Workspace};
use crate::math::{Real, Vector, standard_normal};
use crate::twin::Twin;
use rand_chacha::ChaCha8Rng;

/// A kinematic touch-trigger probe (SI: m, s, rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TouchProbe {
    /// The stylus ball radius the controller believes (its calibrated value).
    pub stylus_radius: Real,
    /// True − believed stylus radius.
    pub radius_error: Real,
    /// Lateral pre-travel δ0 (the mean over directions normal to the stylus).
    pub pretravel: Real,
    /// Amplitude δ3 of the 3-lobe variation of the lateral pre-travel.
    pub lobing: Real,
    /// Phase θ0 of the lobing, from the tool frame's x axis.
    pub lobing_phase: Real,
    /// Pre-travel along the stylus axis δz.
    pub pretravel_axial: Real,
    /// Trigger repeatability, one standard deviation along the motion.
    pub repeatability: Real,
    /// Approach speed (m/s).
    pub feed: Real,
    /// Trigger latency (s).
    pub latency: Real,
}

/// What one touch gave: the controller's latched axes, and the truth beside them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Latched {
    /// The axis values the controller latched.
    pub axes: AxisValues,
    /// The commanded travel from the start at which the actual stylus ball touched (m).
    pub contact_travel: Real,
    /// The true contact point (workpiece frame, m).
    pub contact_point: Vector,
}

/// Why a touch could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TouchError {
    /// The stylus ball missed the artefact within the move's travel.
    #[error("the stylus ball did not touch within {0:.3} mm of travel")]
    Missed(Real),
    /// The search for the actual contact did not settle: the errors bend the path too much.
    #[error("the contact on the actual path did not settle within {0} steps")]
    NotConverged(usize),
    /// The contact query failed.
    #[error(transparent)]
    Contact(#[from] ContactError),
}

/// Fixed-point steps at most, and the step (m) that ends them.
const MAX_STEPS: usize = 12;
const CONVERGED: Real = 1e-13;

impl TouchProbe {
    /// The true stylus radius.
    pub fn true_radius(&self) -> Real {
        self.stylus_radius + self.radius_error
    }

    /// The pre-travel for a unit approach `direction` given in the tool frame.
    pub fn pretravel_toward(&self, direction: Vector) -> Real {
        let c2 = (direction.z * direction.z).min(1.0);
        let s2 = 1.0 - c2;
        let theta = direction.y.atan2(direction.x);
        let lateral = self.pretravel + self.lobing * (3.0 * (theta - self.lobing_phase)).cos();
        s2 * lateral + c2 * self.pretravel_axial
    }

    /// The controller's distance past the contact at which the axes are latched, without the
    /// scatter: pre-travel for `tool_direction` (tool frame) plus `v·t`.
    pub fn overrun(&self, tool_direction: Vector) -> Real {
        self.pretravel_toward(tool_direction) + self.feed * self.latency
    }

    /// One touch: `probing` moves the axes from its start along its direction. The
    /// commanded travel `s` at which the actual stylus centre `P(s)` touches `target` is the
    /// fixed point of `s ← s·t(s)/|P(s) − P(0)|`, with `t(s)` the contact travel from `P(0)`
    /// toward `P(s)`: at convergence `P(s)` lies on the path and on the dilated artefact.
    pub fn touch(
        &self,
        twin: &Twin,
        workspace: &mut Workspace,
        target: &Target,
        probing: &ProbeMove,
        rng: &mut ChaCha8Rng,
    ) -> Result<Latched, TouchError> {
        let e = probing.direction;
        let mut state = MachineState::at(probing.start);
        for (axis, component) in [(Axis::X, e.x), (Axis::Y, e.y), (Axis::Z, e.z)] {
            if component < 0.0 {
                state.direction[axis.index()] = Direction::Negative;
            }
        }
        let mut actual = |s: Real| {
            for (axis, component) in [(Axis::X, e.x), (Axis::Y, e.y), (Axis::Z, e.z)] {
                state.position[axis] = probing.start[axis] + component * s;
            }
            twin.errors
                .workpiece_from_tool(&twin.machine, workspace, &state)
                .translation
        };
        let radius = self.true_radius();
        let limit = probing.max_travel;
        let start = actual(0.0);
        let guess = actual(limit);
        let mut s = {
            let approach = Approach::new(start, guess - start)?;
            let touch = target.touch(radius, &approach, 2.0 * limit)?;
            touch.ok_or(TouchError::Missed(limit * 1e3))?.travel
        };
        let mut contact = start;
        let mut converged = false;
        for _ in 0..MAX_STEPS {
            let here = actual(s);
            let chord = here - start;
            let length = chord.length();
            let approach = Approach::new(start, chord)?;
            let touch = target
                .touch(radius, &approach, 2.0 * limit)?
                .ok_or(TouchError::Missed(limit * 1e3))?;
            let next = s * touch.travel / length;
            contact = touch.point(&approach, radius);
            let step = (next - s).abs();
            s = next;
            if step < CONVERGED {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(TouchError::NotConverged(MAX_STEPS));
        }
        if s > limit {
            return Err(TouchError::Missed(limit * 1e3));
        }
        let latched =
            s + self.overrun(probing.tool_direction) + self.repeatability * standard_normal(rng);
        let mut axes = probing.start;
        for (axis, component) in [(Axis::X, e.x), (Axis::Y, e.y), (Axis::Z, e.z)] {
            axes[axis] = probing.start[axis] + component * latched;
        }
        Ok(Latched {
            axes,
            contact_travel: s,
            contact_point: contact,
        })
    }
}
