//! The physical range of each kind of value a scenario sets, with its reason.
//!
//! A scenario is checked before anything runs: a value beyond what any instrument, machine or
//! workshop has (a laser with 1 m of noise, a feed of 1e300 mm/min, a 10⁹ min lag) is refused
//! at its line with the range and why, so that it can neither make a run work for hours nor
//! publish a table of `inf`. The ranges are generous: they refuse what cannot be meant, not
//! what is unusual.

use crate::math::{Real, readable};

/// A closed range of plausible values and why it ends there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// Smallest plausible value.
    pub lo: Real,
    /// Largest plausible value.
    pub hi: Real,
    /// Why the range ends there, for the message.
    pub why: &'static str,
}

impl Bound {
    /// `value` when finite and within the range, else the message: the value, the range and
    /// its reason (`1e300: expected 0 … 10000 (a laser noisier than 10 µm is not an
    /// interferometer)`).
    pub fn check(self, value: Real) -> Result<Real, String> {
        if value.is_finite() && value >= self.lo && value <= self.hi {
            Ok(value)
        } else {
            Err(format!(
                "{}: expected {} … {} ({})",
                readable(value),
                readable(self.lo),
                readable(self.hi),
                self.why
            ))
        }
    }

    /// [`Bound::check`] on each of `values`: the message of the first refused.
    pub fn check_each(self, values: &[Real]) -> Result<(), String> {
        values.iter().try_for_each(|v| self.check(*v).map(|_| ()))
    }

    /// The range `-hi … hi` of a signed quantity with the same reason.
    pub const fn symmetric(hi: Real, why: &'static str) -> Bound {
        Bound { lo: -hi, hi, why }
    }
}

/// Workshop, air and part temperatures (°C).
pub const TEMPERATURE_DEGC: Bound = Bound {
    lo: -10.0,
    hi: 60.0,
    why: "a machine tool's workshop",
};

/// Programmed feeds (mm/min).
pub const FEED_MM_PER_MIN: Bound = Bound {
    lo: 0.1,
    hi: 200_000.0,
    why: "0.1 mm/min to 200 m/min: the fastest linear-motor machines reach about 120 m/min",
};

/// A dwell at a target or between moves (s).
pub const DWELL_S: Bound = Bound {
    lo: 0.0,
    hi: 3600.0,
    why: "at most an hour at one target",
};

/// Instrument noise (nm, one standard deviation).
pub const NOISE_NM: Bound = Bound {
    lo: 0.0,
    hi: 10_000.0,
    why: "an instrument noisier than 10 µm does not measure a machine tool",
};

/// Instrument resolution (nm).
pub const RESOLUTION_NM: Bound = Bound {
    lo: 0.0,
    hi: 10_000.0,
    why: "an instrument coarser than 10 µm does not measure a machine tool",
};

/// A set-up offset of an instrument from the tool or the axis (mm).
pub const OFFSET_MM: Bound = Bound::symmetric(5000.0, "5 m: the size of the largest machines");

/// An angular misalignment of an instrument (µrad).
pub const MISALIGNMENT_URAD: Bound =
    Bound::symmetric(10_000.0, "10 mrad: a beam that far off leaves the optics");

/// A thermometer's noise or resolution (°C).
pub const THERMOMETER_DEGC: Bound = Bound {
    lo: 0.0,
    hi: 5.0,
    why: "a thermometer that uncertain does not follow a machine's drift",
};

/// A lag or a time constant (min).
pub const LAG_MIN: Bound = Bound {
    lo: 0.0,
    hi: 10_080.0,
    why: "at most a week",
};

/// A frequency of an error motion or a vibration (Hz).
pub const FREQUENCY_HZ: Bound = Bound {
    lo: 0.0,
    hi: 10_000.0,
    why: "machine-tool structures and drives do not move above 10 kHz",
};

/// An amplitude of an error motion or a disturbance (µm, or µrad for tilts).
pub const AMPLITUDE_UM: Bound = Bound {
    lo: 0.0,
    hi: 10_000.0,
    why: "10 mm (or 10 mrad): beyond it a machine does not cut",
};

/// A coefficient of thermal expansion (ppm/°C).
pub const EXPANSION_PPM_PER_DEGC: Bound = Bound {
    lo: -10.0,
    hi: 100.0,
    why: "from carbon fibre and Invar to polymers",
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_the_ends_and_refuses_beyond_with_the_reason() {
        assert_eq!(TEMPERATURE_DEGC.check(-10.0), Ok(-10.0));
        assert_eq!(TEMPERATURE_DEGC.check(60.0), Ok(60.0));
        let message = TEMPERATURE_DEGC.check(60.5).unwrap_err();
        assert_eq!(
            message,
            "60.5: expected -10 … 60 (a machine tool's workshop)"
        );
        assert!(NOISE_NM.check(Real::NAN).is_err());
        assert!(NOISE_NM.check(-1.0).is_err());
        let huge = NOISE_NM.check(1e300).unwrap_err();
        assert!(huge.starts_with("1e300: "), "{huge}");
        assert!(OFFSET_MM.check_each(&[0.0, -5000.0, 5000.0]).is_ok());
        assert!(OFFSET_MM.check_each(&[0.0, -5000.1]).is_err());
    }
}
