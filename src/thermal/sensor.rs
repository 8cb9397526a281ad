//! Temperature sensors on network nodes: first-order lag (a thermocouple in its sheath and
//! glue), calibration offset, white noise and quantisation, in that order.

use crate::math::{Real, standard_normal};
use rand_chacha::ChaCha8Rng;

/// A temperature sensor's characteristics.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorSpec {
    /// Its name (the `<sensor>` of a `temp_<sensor>_degc` column).
    pub name: String,
    /// Calibration offset (°C), added to the reading.
    pub offset: Real,
    /// Standard deviation of the white noise (°C).
    pub noise: Real,
    /// Resolution (°C); 0 for none.
    pub resolution: Real,
    /// Time constant of the first-order lag (s); 0 for none.
    pub time_constant: Real,
}

impl SensorSpec {
    /// A thermocouple-like sensor: 0.05 °C noise, 0.1 °C resolution, 20 s lag, no offset.
    pub fn thermocouple(name: &str) -> SensorSpec {
        SensorSpec {
            name: name.into(),
            offset: 0.0,
            noise: 0.05,
            resolution: 0.1,
            time_constant: 20.0,
        }
    }
}

/// A sensor in use: its spec, the lagged temperature it has reached, and its noise stream.
#[derive(Clone, Debug)]
pub struct TemperatureSensor {
    spec: SensorSpec,
    lagged: Real,
    rng: ChaCha8Rng,
}

impl TemperatureSensor {
    /// A sensor that starts in equilibrium at `initial` °C, drawing noise from `rng` (derive it
    /// with [`crate::math::seeded_rng`] from the scenario seed and the sensor's name).
    pub fn new(spec: SensorSpec, initial: Real, rng: ChaCha8Rng) -> TemperatureSensor {
        TemperatureSensor {
            spec,
            lagged: initial,
            rng,
        }
    }

    /// Follows the node temperature `node` (°C, held over the step) for `dt` seconds — exactly:
    /// the lag closes `1 − exp(−dt/τ)` of the gap — and returns the reading.
    pub fn read(&mut self, node: Real, dt: Real) -> Real {
        let tau = self.spec.time_constant;
        self.lagged = if tau > 0.0 {
            node + (self.lagged - node) * (-dt / tau).exp()
        } else {
            node
        };
        let noise = if self.spec.noise > 0.0 {
            self.spec.noise * standard_normal(&mut self.rng)
        } else {
            0.0
        };
        let value = self.lagged + self.spec.offset + noise;
        let q = self.spec.resolution;
        if q > 0.0 {
            (value / q).round() * q
        } else {
            value
        }
    }

    /// The spec.
    pub fn spec(&self) -> &SensorSpec {
        &self.spec
    }
}
