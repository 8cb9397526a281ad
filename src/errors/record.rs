//! A measured temperature record: what real sensors read over a test, as the input of a
//! scenario's temperature-driven error terms (`[inputs] temperatures = "FILE.csv"`, see
//! [`crate::errors::ContextTerm`]) and of its sensors' columns.
//!
//! The reader of the CSV file is `scenario::read_temperature_record` (the `io` layer is above
//! this one).
//!
//! Between samples the temperature is taken as linear in time; before the first sample it
//! holds the first value, after the last the last. A first-order lag of a sensor
//! ([`TemperatureRecord::lagged`]) follows the same linear pieces exactly
//! ([`first_order_lag`]), starting in equilibrium with the first sample — the way
//! positioning discovery lags a sensor, so a model it writes evaluates to the same numbers.

use crate::math::{Real, first_order_lag, local_rates};

/// Temperatures of named sensors sampled over time.
#[derive(Clone, Debug, PartialEq)]
pub struct TemperatureRecord {
    file: String,
    /// SHA-256 of the file's bytes.
    sha256: String,
    /// Sample times (s since the start), strictly increasing.
    times: Vec<Real>,
    sensors: Vec<String>,
    /// Per sensor, its temperature (°C) at each sample time.
    values: Vec<Vec<Real>>,
}

impl TemperatureRecord {
    /// A record of `sensors` sampled at `times` (s, strictly increasing; at least one), with
    /// `values[s][k]` sensor `s`'s temperature (°C) at `times[k]`; `file` names it and `sha256`
    /// is its content's hash. The reader (`scenario::inputs`) checks these with the file's line
    /// numbers; here they are only asserted.
    pub fn new(
        file: String,
        sha256: String,
        times: Vec<Real>,
        sensors: Vec<String>,
        values: Vec<Vec<Real>>,
    ) -> TemperatureRecord {
        assert!(!times.is_empty() && times.windows(2).all(|w| w[0] < w[1]));
        assert!(values.len() == sensors.len() && values.iter().all(|v| v.len() == times.len()));
        TemperatureRecord {
            file,
            sha256,
            times,
            sensors,
            values,
        }
    }

    /// The file it was read from.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// SHA-256 of the file's bytes (a scenario's hash covers its record).
    pub fn sha256(&self) -> &str {
        &self.sha256
    }

    /// The sensor names, in column order.
    pub fn sensors(&self) -> &[String] {
        &self.sensors
    }

    /// The index of the sensor named `name`.
    pub fn sensor(&self, name: &str) -> Option<usize> {
        self.sensors.iter().position(|s| s == name)
    }

    /// The first and last sample times (s).
    pub fn span(&self) -> (Real, Real) {
        (self.times[0], self.times[self.times.len() - 1])
    }

    /// Sensor `sensor`'s samples (°C), one per sample time.
    pub fn samples(&self, sensor: usize) -> &[Real] {
        &self.values[sensor]
    }

    /// Sensor `sensor`'s samples through a first-order lag of `tau` s, one per sample time,
    /// starting in equilibrium with the first sample (exact for the linear pieces between
    /// samples).
    pub fn lagged(&self, sensor: usize, tau: Real) -> Vec<Real> {
        self.lag(&self.values[sensor], tau)
    }

    /// `series` (one value per sample time) through a first-order lag of `tau` s, as
    /// [`TemperatureRecord::lagged`] lags a sensor.
    pub fn lag(&self, series: &[Real], tau: Real) -> Vec<Real> {
        let mut lagged = Vec::with_capacity(series.len());
        lagged.push(series[0]);
        for k in 1..series.len() {
            let dt = self.times[k] - self.times[k - 1];
            lagged.push(first_order_lag(
                lagged[k - 1],
                series[k - 1],
                series[k],
                dt,
                tau,
            ));
        }
        lagged
    }

    /// Sensor `sensor`'s rate of change (°C/s) at each sample time, as [`local_rates`] reads
    /// it from the samples.
    pub fn rates(&self, sensor: usize) -> Vec<Real> {
        local_rates(&self.times, &self.values[sensor])
    }

    /// `series` (one value per sample time, e.g. [`TemperatureRecord::samples`] or
    /// [`TemperatureRecord::lagged`]) at `time` s: linear between samples, held before the
    /// first and after the last.
    pub fn interpolate(&self, series: &[Real], time: Real) -> Real {
        let k = self.times.partition_point(|&t| t <= time);
        if k == 0 {
            return series[0];
        }
        if k == self.times.len() {
            return series[k - 1];
        }
        let (t0, t1) = (self.times[k - 1], self.times[k]);
        let w = (time - t0) / (t1 - t0);
        series[k - 1] + w * (series[k] - series[k - 1])
    }

    /// `series` (one value per sample time) through a lag of `tau` s at `time` s, continuing
    /// `lagged` (its [`TemperatureRecord::lag`]) exactly from the sample before `time` along
    /// the linear piece (held after the last sample, so the lag goes on settling).
    pub fn lag_at(&self, series: &[Real], lagged: &[Real], tau: Real, time: Real) -> Real {
        let k = self.times.partition_point(|&t| t <= time);
        if k == 0 {
            return lagged[0];
        }
        let elapsed = time - self.times[k - 1];
        if elapsed == 0.0 {
            return lagged[k - 1];
        }
        let to = self.interpolate(series, time);
        first_order_lag(lagged[k - 1], series[k - 1], to, elapsed, tau)
    }

    /// Sensor `sensor`'s temperature (°C) at `time` s.
    pub fn at(&self, sensor: usize, time: Real) -> Real {
        self.interpolate(&self.values[sensor], time)
    }
}
