//! Temperature sensors on network nodes: first-order lag (a thermocouple in its sheath and
//! glue), calibration offset, white noise and quantisation, in that order. The lag follows the
//! node between readings ([`TemperatureSensor::follow`]); noise is drawn only when a reading is
//! taken ([`TemperatureSensor::read`]), so the stream does not depend on the step length.

use crate::math::{Real, first_order_lag, standard_normal};
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

    /// Follows its node for `dt` seconds while the node goes from `from` to `to` °C, exactly
    /// for a node changing linearly over the step (first-order hold): with `r = (to − from)/dt`,
    /// the lagged temperature becomes `to − τr + (s − from + τr)·e^(−dt/τ)`, so a steady ramp
    /// leaves the lag `τ·r` whatever the step length. No reading is taken.
    pub fn follow(&mut self, from: Real, to: Real, dt: Real) {
        self.lagged = first_order_lag(self.lagged, from, to, dt, self.spec.time_constant);
    }

    /// A reading now: the lagged temperature (the node's, `node` °C, when the sensor has no lag)
    /// plus the offset and the noise, quantised. Draws one noise value per reading.
    pub fn read(&mut self, node: Real) -> Real {
        let value = if self.spec.time_constant > 0.0 {
            self.lagged
        } else {
            node
        };
        let noise = if self.spec.noise > 0.0 {
            self.spec.noise * standard_normal(&mut self.rng)
        } else {
            0.0
        };
        let value = value + self.spec.offset + noise;
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
