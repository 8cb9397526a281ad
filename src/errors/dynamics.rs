//! Time- and speed-dependent content of an error parameter: what an axis of rotation's error
//! motion holds besides its synchronous function of the angle (ISO 230-7 §3.5).
//!
//! An [`super::ErrorParameter`]'s function of the axis position is its **synchronous** content:
//! it repeats every revolution. [`Dynamics`] adds, for the same parameter:
//!
//! - **asynchronous sinusoids**, at a frequency in Hz (a structural mode, a pump) or at a ratio
//!   to the rotation that is not a whole number (a bearing's cage at 0.43×, a ball pass at
//!   4.6×). A ratio is applied to the axis's **unwrapped** angle, `a · sin(ratio · q + φ)`, so
//!   it follows the rotation through speed changes as a bearing's defect frequencies do;
//! - **band-limited random motion**, realised once from the scenario's seed as a sum of `N`
//!   sinusoids of random frequency (uniform in the band) and random phase, each of amplitude
//!   `rms · √(2/N)` (the spectral representation of a stationary Gaussian process, Shinozuka
//!   1972): its spectrum is flat in the band in expectation and its RMS is `rms` exactly over a
//!   long record. It can be evaluated at any time without state, so records are reproducible
//!   sample by sample. Left out: a non-flat power spectral density within the band;
//! - a **speed factor**: a table of the axis speed (|rad/s|) against a factor multiplying the
//!   whole parameter, synchronous and asynchronous (amplitudes that grow with speed:
//!   unbalance grows with its square, ISO 230-7 A.8). Outside the table the end factor holds.
//!
//! The evaluation context — time and axis velocity — comes from
//! [`crate::machine::MachineState`]; the thermal growth of an axis is a thermal term
//! ([`crate::thermal::ThermalErrors`]), evaluated from the same state's temperatures. None of
//! this content is a linear coefficient: the estimators fit the synchronous functions only and
//! see the rest as noise.

use super::function::Table;
use super::name::ParameterName;
use crate::math::{Real, seeded_rng};
use rand::RngExt;
use std::f64::consts::TAU;

/// A frequency: absolute, or a ratio to the rotation of the parameter's axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Frequency {
    /// Cycles per second.
    Hz(Real),
    /// Cycles per revolution of the axis (rotary axes only).
    PerRevolution(Real),
}

/// `amplitude · sin(2π f t + phase)` or `amplitude · sin(ratio · q + phase)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sinusoid {
    /// Its frequency.
    pub frequency: Frequency,
    /// Amplitude (m or rad).
    pub amplitude: Real,
    /// Phase (rad).
    pub phase: Real,
}

impl Sinusoid {
    /// The value at time `time` (s) and unwrapped axis position `q` (rad).
    pub fn value(&self, time: Real, q: Real) -> Real {
        let argument = match self.frequency {
            Frequency::Hz(f) => TAU * f * time,
            Frequency::PerRevolution(ratio) => ratio * q,
        };
        self.amplitude * (argument + self.phase).sin()
    }
}

/// Band-limited random motion as specified, with its realisation.
#[derive(Clone, Debug, PartialEq)]
pub struct RandomMotion {
    /// RMS (m or rad).
    pub rms: Real,
    /// The band's lower and upper frequency (Hz, or cycles per revolution).
    pub band: (Real, Real),
    /// Whether the band is given per revolution of the axis.
    pub per_revolution: bool,
    /// The realisation: `LINES` sinusoids.
    pub lines: Vec<Sinusoid>,
}

impl RandomMotion {
    /// Number of sinusoids in a realisation.
    pub const LINES: usize = 64;

    /// A realisation of `rms` in the band `low`..`high` (`0 ≤ low < high`, in Hz or, with
    /// `per_revolution`, in cycles per revolution), drawn from the stream named after the
    /// parameter.
    pub fn realise(
        rms: Real,
        (low, high): (Real, Real),
        per_revolution: bool,
        seed: u64,
        name: ParameterName,
    ) -> RandomMotion {
        let mut rng = seeded_rng(seed, &format!("random motion {name}"));
        let amplitude = rms * (2.0 / Self::LINES as Real).sqrt();
        let lines = (0..Self::LINES)
            .map(|_| {
                let u: Real = rng.random();
                let phase = TAU * rng.random::<Real>();
                let f = low + (high - low) * u;
                let frequency = if per_revolution {
                    Frequency::PerRevolution(f)
                } else {
                    Frequency::Hz(f)
                };
                Sinusoid {
                    frequency,
                    amplitude,
                    phase,
                }
            })
            .collect();
        RandomMotion {
            rms,
            band: (low, high),
            per_revolution,
            lines,
        }
    }
}

/// The time- and speed-dependent content of one parameter.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dynamics {
    /// Asynchronous (or any time-dependent) sinusoids.
    pub sinusoids: Vec<Sinusoid>,
    /// Band-limited random motion.
    pub random: Option<RandomMotion>,
    /// Factor on the whole parameter against the axis speed (|rad/s|).
    pub speed_factor: Option<Table>,
}

impl Dynamics {
    /// Whether it holds anything.
    pub fn is_empty(&self) -> bool {
        self.sinusoids.is_empty() && self.random.is_none() && self.speed_factor.is_none()
    }

    /// Whether any term is given per revolution (which needs a rotary axis).
    pub fn has_per_revolution(&self) -> bool {
        let per_rev = |s: &Sinusoid| matches!(s.frequency, Frequency::PerRevolution(_));
        self.sinusoids.iter().any(per_rev) || self.random.as_ref().is_some_and(|r| r.per_revolution)
    }

    /// The factor at axis speed `speed` (rad/s or m/s; its magnitude is used).
    pub fn factor(&self, speed: Real) -> Real {
        self.speed_factor
            .as_ref()
            .map_or(1.0, |table| table.value(speed.abs()))
    }

    /// The time-dependent part at time `time` (s) and unwrapped axis position `q`, before the
    /// speed factor.
    pub fn asynchronous(&self, time: Real, q: Real) -> Real {
        let lines = self.random.as_ref().map_or(&[][..], |r| r.lines.as_slice());
        self.sinusoids
            .iter()
            .chain(lines)
            .map(|s| s.value(time, q))
            .sum()
    }
}

/// Dynamics attached to a parameter by name.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterDynamics {
    /// The parameter (a component error of an axis).
    pub name: ParameterName,
    /// Its content.
    pub dynamics: Dynamics,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::errors::Interpolation;
    use crate::errors::Motion;
    use crate::machine::Axis;

    #[test]
    fn per_revolution_sinusoids_follow_the_unwrapped_angle() {
        let s = Sinusoid {
            frequency: Frequency::PerRevolution(0.5),
            amplitude: 2.0,
            phase: 0.0,
        };
        // Half a cycle per revolution: after one turn sin(π) = 0, after half a turn sin(π/2) = 1.
        assert!(s.value(0.0, TAU).abs() < 1e-15);
        assert!((s.value(0.0, TAU / 2.0) - 2.0).abs() < 1e-15);
        let h = Sinusoid {
            frequency: Frequency::Hz(50.0),
            amplitude: 1.0,
            phase: 0.0,
        };
        assert!((h.value(0.005, 0.0) - 1.0).abs() < 1e-12); // a quarter period of 50 Hz
    }

    #[test]
    fn random_motion_has_its_rms_and_stays_in_band() {
        let name = ParameterName::Component {
            motion: Motion::X,
            axis: Axis::S,
        };
        let r = RandomMotion::realise(1e-6, (100.0, 300.0), false, 7, name);
        assert!(r.lines.iter().all(|l| match l.frequency {
            Frequency::Hz(f) => (100.0..300.0).contains(&f),
            _ => false,
        }));
        // Over 20 s (≥ 2000 periods of the slowest line) the mean square of a sum of sinusoids
        // of distinct frequencies is Σ a²/2 = rms² up to cross terms of order 1/(Δf·T).
        let d = Dynamics {
            random: Some(r),
            ..Default::default()
        };
        let n = 200_000;
        let ms: Real = (0..n)
            .map(|i| d.asynchronous(i as Real * 1e-4, 0.0).powi(2))
            .sum::<Real>()
            / n as Real;
        assert!((ms.sqrt() / 1e-6 - 1.0).abs() < 0.03, "rms {}", ms.sqrt());
        // Same seed, same realisation; another seed, another.
        let again = RandomMotion::realise(1e-6, (100.0, 300.0), false, 7, name);
        assert_eq!(d.random.as_ref().unwrap(), &again);
        let other = RandomMotion::realise(1e-6, (100.0, 300.0), false, 8, name);
        assert_ne!(again, other);
    }

    #[test]
    fn speed_factor_interpolates_on_the_speed_magnitude() {
        let d = Dynamics {
            speed_factor: Some(
                Table::new(vec![0.0, 100.0], vec![1.0, 3.0], Interpolation::Linear).unwrap(),
            ),
            ..Default::default()
        };
        assert_eq!(d.factor(50.0), 2.0);
        assert_eq!(d.factor(-50.0), 2.0);
        assert_eq!(d.factor(1000.0), 3.0);
    }
}
