//! The controller and servo model that turns an interpolator's commands into actual axis
//! positions.
//!
//! Each axis of the test plane has a proportional position loop with gain `Kv` (1/s) and
//! optional velocity feed-forward `f` (0 … 1), its velocity loop taken as ideal:
//! `ẋ = Kv·(c − x) + f·ċ`. The interpolator hands the loop a new command every `ipo_period`
//! and the command is linear in between (as in a CNC), so the loop is integrated exactly:
//! over a period with `c(t) = c₀ + ċ·t`,
//! `x(t) = c(t) − (1 − f)·ċ/Kv + (x₀ − c₀ + (1 − f)·ċ/Kv)·e^(−Kv·t)`.
//! On a ramp the following error is `(1 − f)·ċ/Kv`: the lag time `(1 − f)/Kv`; unequal lag
//! times of two axes turn a circle into an ellipse at 45° (servo mismatch).
//!
//! On top of the loop: friction at velocity reversal (the axis sticks and lags the command in
//! its new direction by `h·e^(−Δt/τ)`, Δt since the reversal: a reversal spike of height `h`)
//! and vibration (`a·sin(2π·f_v·t)` along the axis). Lost motion and cyclic errors are not
//! here: they are the error model's reversal and harmonic terms, applied by the twin to the
//! actual positions with each axis's direction of travel (the sign of its loop velocity).
//!
//! Simplified: ideal velocity loop and drive (no current limits, no resonance beyond the
//! stated vibration), the spike as a jump and an exponential decay (not a stick–slip
//! simulation), lost motion as a step at the reversal (the real take-up of play spreads it over
//! the first micrometres of motor travel), axes off the plane exactly at their commands.

use crate::machine::{Axis, Direction};
use crate::math::Real;

/// The servo of one axis (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisServo {
    /// Position-loop gain Kv (1/s).
    pub kv: Real,
    /// Velocity feed-forward fraction (0 … 1; 1 removes the steady following error).
    pub feed_forward: Real,
    /// Reversal spike height (m, ≥ 0): how far the axis lags in its new direction just after a
    /// reversal.
    pub spike_height: Real,
    /// Decay time of the spike (s, > 0).
    pub spike_decay: Real,
    /// Vibration amplitude along the axis (m).
    pub vibration_amplitude: Real,
    /// Vibration frequency (Hz).
    pub vibration_frequency: Real,
}

impl AxisServo {
    /// A plain position loop: Kv = 33.3/s (2 m/min per mm of following error), no
    /// feed-forward, spike or vibration.
    pub const DEFAULT: AxisServo = AxisServo {
        kv: 100.0 / 3.0,
        feed_forward: 0.0,
        spike_height: 0.0,
        spike_decay: 0.01,
        vibration_amplitude: 0.0,
        vibration_frequency: 0.0,
    };

    /// Lag time of the loop on a ramp, `(1 − f)/Kv` (s).
    pub fn lag_time(&self) -> Real {
        (1.0 - self.feed_forward) / self.kv
    }

    /// Why these values cannot be simulated, if they cannot.
    pub fn problem(&self) -> Option<String> {
        if !(self.kv.is_finite() && self.kv > 0.0) {
            return Some(format!("kv must be a positive number, got {}", self.kv));
        }
        if !(0.0..=1.0).contains(&self.feed_forward) {
            return Some(format!(
                "feed_forward must be within 0 … 1, got {}",
                self.feed_forward
            ));
        }
        if !(self.spike_height.is_finite() && self.spike_height >= 0.0) {
            return Some(format!(
                "the spike height must be ≥ 0, got {}",
                self.spike_height
            ));
        }
        if !(self.spike_decay.is_finite() && self.spike_decay > 0.0) {
            return Some(format!(
                "the spike decay must be positive, got {}",
                self.spike_decay
            ));
        }
        if !(self.vibration_amplitude.is_finite() && self.vibration_frequency.is_finite())
            || self.vibration_frequency < 0.0
        {
            return Some("vibration amplitude and frequency must be finite, frequency ≥ 0".into());
        }
        None
    }
}

impl Default for AxisServo {
    fn default() -> AxisServo {
        AxisServo::DEFAULT
    }
}

/// The controller: interpolation period and the servo of each linear axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Servo {
    /// Interpolation (command) period (s).
    pub ipo_period: Real,
    /// Servo of X, Y and Z.
    pub axes: [AxisServo; 3],
}

impl Default for Servo {
    fn default() -> Servo {
        Servo {
            ipo_period: 1e-3,
            axes: [AxisServo::DEFAULT; 3],
        }
    }
}

impl Servo {
    /// The servo of a linear axis.
    pub fn axis(&self, axis: Axis) -> &AxisServo {
        &self.axes[axis.index()]
    }
}

/// The loop of one axis, integrated period by period: [`AxisLoop::start_period`] for each
/// interpolation period, [`AxisLoop::actual`] at the samples inside it, then
/// [`AxisLoop::finish_period`].
#[derive(Clone, Copy, Debug)]
pub struct AxisLoop {
    servo: AxisServo,
    /// The axis it drives.
    pub axis: Axis,
    /// Loop position at the start of the current period (m).
    position: Real,
    /// Direction of travel (sign of the loop velocity, kept while it is zero).
    direction: Direction,
    /// Last reversal: when, and the direction after it.
    reversal: Option<(Real, Direction)>,
}

/// One period of one axis: command `c(t) = c0 + rate·(t − t0)` from `t0`.
#[derive(Clone, Copy, Debug)]
pub struct Period {
    t0: Real,
    c0: Real,
    rate: Real,
    /// `x₀ − c₀ + (1 − f)·rate/Kv`: the decaying part of the loop's response.
    transient: Real,
    /// The reversal inside this period, if any: (time, new direction).
    reversal: Option<(Real, Direction)>,
}

impl AxisLoop {
    /// A loop at rest at `position`, its direction of travel `direction`, no reversal yet.
    pub fn new(servo: AxisServo, axis: Axis, position: Real, direction: Direction) -> AxisLoop {
        AxisLoop {
            servo,
            axis,
            position,
            direction,
            reversal: None,
        }
    }

    /// Starts a period from `t0` with the command going from `c0` to `c1` over `dt`.
    pub fn start_period(&self, t0: Real, c0: Real, c1: Real, dt: Real) -> Period {
        let (kv, lag) = (self.servo.kv, 1.0 - self.servo.feed_forward);
        let rate = (c1 - c0) / dt;
        let transient = self.position - c0 + lag * rate / kv;
        // Loop velocity ẋ(τ) = rate − Kv·transient·e^(−Kv·τ): monotone over the period.
        let velocity_end = rate - kv * transient * (-kv * dt).exp();
        let mut reversal = None;
        if velocity_end != 0.0 {
            let direction = if velocity_end > 0.0 {
                Direction::Positive
            } else {
                Direction::Negative
            };
            if direction != self.direction {
                // Where ẋ = 0: e^(−Kv·τ) = rate/(Kv·transient); at the start if it is not inside.
                let ratio = rate / (kv * transient);
                let tau = if ratio > 0.0 && ratio <= 1.0 {
                    (-ratio.ln() / kv).min(dt)
                } else {
                    0.0
                };
                reversal = Some((t0 + tau, direction));
            }
        }
        Period {
            t0,
            c0,
            rate,
            transient,
            reversal,
        }
    }

    /// Loop position at `t` within the period.
    pub fn loop_position(&self, period: &Period, t: Real) -> Real {
        let (kv, lag) = (self.servo.kv, 1.0 - self.servo.feed_forward);
        let tau = t - period.t0;
        period.c0 + period.rate * tau - lag * period.rate / kv
            + period.transient * (-kv * tau).exp()
    }

    /// Actual position and direction of travel at `t` within the period.
    pub fn actual(&self, period: &Period, t: Real) -> (Real, Direction) {
        let (reversal, direction) = match period.reversal {
            Some((at, after)) if t >= at => (Some((at, after)), after),
            _ => (self.reversal, self.direction),
        };
        let servo = &self.servo;
        let spike = reversal.map_or(0.0, |(at, after)| {
            -after.sign() * servo.spike_height * (-(t - at) / servo.spike_decay).exp()
        });
        let vibration = servo.vibration_amplitude
            * (std::f64::consts::TAU * servo.vibration_frequency * t).sin();
        (self.loop_position(period, t) + spike + vibration, direction)
    }

    /// Ends the period at `t1`.
    pub fn finish_period(&mut self, period: &Period, t1: Real) {
        self.position = self.loop_position(period, t1);
        if let Some(reversal) = period.reversal {
            self.reversal = Some(reversal);
            self.direction = reversal.1;
        }
    }
}

/// The timing of [`sample_loops`] (s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    /// The interpolation period.
    pub ipo_period: Real,
    /// How long the run lasts.
    pub duration: Real,
    /// The time between samples.
    pub sample_period: Real,
}

/// Runs position loops behind a command interpolated linearly over each period and samples
/// them: periods of `ipo_period` from 0 to `duration` (the last one cut at `duration`), the
/// command at each period's end from `command_at(t1)` (from `start` at 0), every loop
/// integrated exactly, and `sample(t, state)` called every `sample_period` from t = 0 with the
/// loops' actual positions and directions written into `base`'s axes (at most
/// `⌊duration / sample_period⌋ + 1` samples; a sample on a period boundary belongs to the
/// period it starts, the very last to the last period). Allocates one scratch period per loop.
pub fn sample_loops<E>(
    loops: &mut [AxisLoop],
    start: &crate::machine::AxisValues,
    timing: Sampling,
    base: crate::machine::MachineState,
    mut command_at: impl FnMut(Real) -> Result<crate::machine::AxisValues, E>,
    mut sample: impl FnMut(Real, &crate::machine::MachineState) -> Result<(), E>,
) -> Result<(), E> {
    let Sampling {
        ipo_period,
        duration,
        sample_period,
    } = timing;
    let periods = (duration / ipo_period).ceil() as usize;
    let samples = (duration / sample_period).floor() as usize + 1;
    let mut spans = Vec::with_capacity(loops.len());
    let mut next_sample = 0usize;
    let mut command_start = *start;
    for i in 0..periods {
        let t0 = i as Real * ipo_period;
        let t1 = ((i + 1) as Real * ipo_period).min(duration);
        let dt = t1 - t0;
        if dt <= 0.0 {
            break;
        }
        let command_end = command_at(t1)?;
        spans.clear();
        spans.extend(
            loops
                .iter()
                .map(|l| l.start_period(t0, command_start[l.axis], command_end[l.axis], dt)),
        );
        loop {
            let t = next_sample as Real * sample_period;
            let last = i + 1 == periods;
            if next_sample >= samples || t > t1 || (t == t1 && !last) {
                break;
            }
            let mut state = base;
            for (l, span) in loops.iter().zip(&spans) {
                let (position, direction) = l.actual(span, t);
                state.position[l.axis] = position;
                state.direction[l.axis.index()] = direction;
            }
            sample(t, &state)?;
            next_sample += 1;
        }
        for (l, span) in loops.iter_mut().zip(&spans) {
            l.finish_period(span, t1);
        }
        command_start = command_end;
    }
    Ok(())
}
