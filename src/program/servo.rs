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
//! **Play** (optional, per axis, gap width `b` ≥ 0, default 0): the loop drives the motor (the
//! loop position above, measured on the motor side as with a rotary encoder) and the carriage
//! (load) follows it through a dead band of width `b`: `load = motor − (b/2)·d`, `d` the last
//! direction in which the motor pushed the load. While the motor moves inside the band (after
//! it reverses, until it has crossed the gap) the load stands still; then it follows offset by
//! `b/2` against the new direction. Within an interpolation period the motor is monotone on
//! either side of its reversal, so the load is the motor clamped to the band (`load =
//! clamp(load₀, motor − b/2, motor + b/2)`) over each monotone piece: exact, like the loop.
//! The instant the load starts to move in its new direction (the motor reaching the far side
//! of the gap) is found by bisection on the monotone motor path (to the last bit of f64);
//! with play the reversal spike starts there, when the carriage itself reverses and sticks.
//! With `b = 0` the load is the motor and nothing else changes. On a ball-bar trace this is
//! not a step: at a quadrant crossing the axis's speed grows linearly from zero, so the motor
//! crosses the gap over a finite arc, R·(1 − cos φ) = b (φ ≈ √(2b/R), 0.4° for b = 4 µm on a
//! 150 mm bar), during which the carriage stands still. Play and the error model's reversal
//! term may be combined; they add.
//!
//! Simplified: ideal velocity loop and drive (no current limits, no resonance beyond the
//! stated vibration), the spike as a jump and an exponential decay (not a stick–slip
//! simulation), lost motion either as a step at the reversal (the error model's reversal
//! term) or as play (a rigid dead band: no elasticity of screw, nut or coupling, no friction
//! inside the gap beyond the spike above, the loop closed on the motor so that it does not see
//! the gap), axes off the plane exactly at their commands.

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
    /// Play between motor and carriage: the width of the dead band (m, ≥ 0; 0 = none).
    pub play: Real,
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
        play: 0.0,
    };

    /// Lag time of the loop on a ramp, `(1 − f)/Kv` (s).
    pub fn lag_time(&self) -> Real {
        (1.0 - self.feed_forward) / self.kv
    }

    /// Why these values cannot be simulated, if they cannot.
    pub fn problem(&self) -> Option<String> {
        // Physical ranges (SI): a position loop's gain from 1 to 1000 1/s, and disturbances
        // of at most a millimetre (beyond it a machine does not cut) below 10 kHz.
        let within = |v: Real, lo: Real, hi: Real| v.is_finite() && v >= lo && v <= hi;
        let shown = crate::math::readable;
        if !within(self.kv, 1.0, 1000.0) {
            return Some(format!(
                "kv must be within 1 … 1000 1/s (position-loop gains), got {}",
                shown(self.kv)
            ));
        }
        if !(0.0..=1.0).contains(&self.feed_forward) {
            return Some(format!(
                "feed_forward must be within 0 … 1, got {}",
                self.feed_forward
            ));
        }
        if !within(self.spike_height, 0.0, 1e-3) {
            return Some(format!(
                "the spike height must be within 0 … 1000 µm, got {} µm",
                shown(self.spike_height * 1e6)
            ));
        }
        if !within(self.spike_decay, 1e-5, 10.0) {
            return Some(format!(
                "the spike decay must be within 0.01 ms … 10 s, got {} ms",
                shown(self.spike_decay * 1e3)
            ));
        }
        if !within(self.vibration_amplitude.abs(), 0.0, 1e-3)
            || !within(self.vibration_frequency, 0.0, 10_000.0)
        {
            return Some(format!(
                "the vibration must be at most 1000 µm and within 0 … 10000 Hz (machine structures do not move faster), got {} µm at {} Hz",
                shown(self.vibration_amplitude * 1e6),
                shown(self.vibration_frequency)
            ));
        }
        if !within(self.play, 0.0, 1e-3) {
            return Some(format!(
                "the play must be within 0 … 1000 µm, got {} µm",
                shown(self.play * 1e6)
            ));
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
    /// Loop (motor) position at the start of the current period (m).
    position: Real,
    /// Direction of travel (sign of the loop velocity, kept while it is zero).
    direction: Direction,
    /// Last reversal: when, and the direction after it.
    reversal: Option<(Real, Direction)>,
    /// With play: the load (carriage) position at the start of the current period (m).
    load: Real,
    /// With play: the last direction in which the motor pushed the load.
    push: Direction,
    /// With play: when the load last started to move in a new direction, and that direction
    /// (where the spike starts).
    engaged: Option<(Real, Direction)>,
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
    /// With play: the load when the motor reverses in this period (else at its start).
    load_at_reversal: Real,
    /// With play: the load at the end of the period and the last push direction then.
    load_end: (Real, Direction),
    /// With play: the instant in this period the load starts to move in a new direction.
    engaged: Option<(Real, Direction)>,
}

impl AxisLoop {
    /// A loop at rest at `position`, its direction of travel `direction`, no reversal yet;
    /// with play, the load pushed in `direction` (at `position − (b/2)·direction`).
    pub fn new(servo: AxisServo, axis: Axis, position: Real, direction: Direction) -> AxisLoop {
        AxisLoop {
            servo,
            axis,
            position,
            direction,
            reversal: None,
            load: position - servo.play / 2.0 * direction.sign(),
            push: direction,
            engaged: None,
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
        let mut period = Period {
            t0,
            c0,
            rate,
            transient,
            reversal,
            load_at_reversal: self.load,
            load_end: (self.load, self.push),
            engaged: None,
        };
        if self.servo.play > 0.0 {
            self.take_up(&mut period, t0 + dt);
        }
        period
    }

    /// With play: the load over the period ending at `t1`, piece by monotone piece of the
    /// motor's path (before and after its reversal), and the instant the load starts to move
    /// in a new direction, if it does in this period.
    fn take_up(&self, period: &mut Period, t1: Real) {
        let half = self.servo.play / 2.0;
        let (mut load, mut push) = (self.load, self.push);
        let turn = period.reversal.map_or(t1, |(at, _)| at);
        let pieces = [
            Some((period.t0, turn, self.direction)),
            period.reversal.map(|(at, after)| (at, t1, after)),
        ];
        for (i, (from, to, direction)) in pieces.into_iter().flatten().enumerate() {
            let d = direction.sign();
            // The motor position at which the load starts to move in `direction`.
            let contact = load + d * half;
            let end = self.loop_position(period, to);
            if d * (end - contact) > 0.0 {
                if direction != push {
                    let at = self.crossing(period, from, to, contact, d);
                    period.engaged = Some((at, direction));
                    push = direction;
                }
                load = end - d * half;
            }
            if i == 0 {
                period.load_at_reversal = load;
            }
        }
        period.load_end = (load, push);
    }

    /// When the motor, moving monotonically in direction `d` over `[from, to]`, reaches
    /// `target` (bisection to the resolution of f64).
    fn crossing(&self, period: &Period, from: Real, to: Real, target: Real, d: Real) -> Real {
        let (mut low, mut high) = (from, to);
        for _ in 0..200 {
            let middle = 0.5 * (low + high);
            if middle <= low || middle >= high {
                break;
            }
            if d * (self.loop_position(period, middle) - target) >= 0.0 {
                high = middle;
            } else {
                low = middle;
            }
        }
        high
    }

    /// Loop (motor) position at `t` within the period.
    pub fn loop_position(&self, period: &Period, t: Real) -> Real {
        let (kv, lag) = (self.servo.kv, 1.0 - self.servo.feed_forward);
        let tau = t - period.t0;
        period.c0 + period.rate * tau - lag * period.rate / kv
            + period.transient * (-kv * tau).exp()
    }

    /// Actual position and direction of travel (the motor's) at `t` within the period.
    pub fn actual(&self, period: &Period, t: Real) -> (Real, Direction) {
        let (reversal, direction) = match period.reversal {
            Some((at, after)) if t >= at => (Some((at, after)), after),
            _ => (self.reversal, self.direction),
        };
        let servo = &self.servo;
        let motor = self.loop_position(period, t);
        // Without play the load is the motor and the spike starts at the motor's reversal;
        // with play the load is the motor clamped to the band, the spike starts when the load
        // itself starts to move in its new direction.
        let (load, start) = if servo.play > 0.0 {
            let half = servo.play / 2.0;
            let before = match period.reversal {
                Some((at, _)) if t >= at => period.load_at_reversal,
                _ => self.load,
            };
            let engaged = match period.engaged {
                Some((at, after)) if t >= at => Some((at, after)),
                _ => self.engaged,
            };
            (before.clamp(motor - half, motor + half), engaged)
        } else {
            (motor, reversal)
        };
        let spike = start.map_or(0.0, |(at, after)| {
            -after.sign() * servo.spike_height * (-(t - at) / servo.spike_decay).exp()
        });
        let vibration = servo.vibration_amplitude
            * (std::f64::consts::TAU * servo.vibration_frequency * t).sin();
        (load + spike + vibration, direction)
    }

    /// Ends the period at `t1`.
    pub fn finish_period(&mut self, period: &Period, t1: Real) {
        self.position = self.loop_position(period, t1);
        if let Some(reversal) = period.reversal {
            self.reversal = Some(reversal);
            self.direction = reversal.1;
        }
        (self.load, self.push) = period.load_end;
        if period.engaged.is_some() {
            self.engaged = period.engaged;
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
/// loops' actual positions and directions written into `base`'s axes and its time advanced
/// by `t`, so that time-dependent error terms act during the run (at most
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
            let mut state = base.at_time(base.time + t);
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
