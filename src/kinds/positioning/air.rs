//! The refractive index of air for a laser interferometer: the modified Edlén equation of
//! Birch & Downs (Metrologia 30, 1993, 155–162; corrected in Metrologia 31, 1994, 315–316),
//! as laser compensation units apply it.
//!
//! Near 20 °C, 1013.25 hPa, 50 %RH it gives n − 1 ≈ 2.71 × 10⁻⁴ and the familiar
//! sensitivities: about −0.93 ppm per °C, +0.27 ppm per hPa, −0.009 ppm per %RH.

use crate::math::Real;

/// Vacuum wavelength of a stabilised He-Ne laser (µm).
pub const HENE_WAVELENGTH_UM: Real = 0.632_991;

/// The state of the air along the beam.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Air {
    /// Temperature (°C).
    pub temperature: Real,
    /// Pressure (Pa).
    pub pressure: Real,
    /// Relative humidity (%).
    pub humidity: Real,
}

impl Air {
    /// 20 °C, 101 325 Pa, 50 %RH.
    pub const STANDARD: Air = Air {
        temperature: 20.0,
        pressure: 101_325.0,
        humidity: 50.0,
    };

    /// The refractive index at vacuum wavelength `wavelength_um`.
    pub fn refractive_index(&self, wavelength_um: Real) -> Real {
        let sigma2 = (1.0 / wavelength_um).powi(2); // wavenumber² (µm⁻²)
        let (t, p) = (self.temperature, self.pressure);
        // Standard dry air (15 °C, 101 325 Pa, 450 ppm CO₂).
        let ns = (8342.54 + 2_406_147.0 / (130.0 - sigma2) + 15_998.0 / (38.9 - sigma2)) * 1e-8;
        // Temperature and pressure.
        let ntp = p * ns / 96_095.43 * (1.0 + 1e-8 * (0.601 - 0.009_72 * t) * p)
            / (1.0 + 0.003_661_0 * t);
        // Water vapour, partial pressure f (Pa) from the relative humidity (Magnus formula).
        let saturation = 611.2 * (17.62 * t / (243.12 + t)).exp();
        let f = self.humidity / 100.0 * saturation;
        1.0 + ntp - f * (3.7345 - 0.0401 * sigma2) * 1e-10
    }
}
