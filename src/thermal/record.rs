//! A measured temperature record: what real sensors read over a test, as the input of a
//! scenario's temperature-driven error terms (`[inputs] temperatures = "FILE.csv"`, see
//! [`crate::errors::ContextTerm`]) and of its sensors' columns.
//!
//! The file is a CSV table with a `time_min` column (time since the start of the test) and one
//! or more `temp_<sensor>_degc` columns; other columns are ignored, so a positioning table
//! (`positioning.csv`, as `mtwin run` writes it or a laser exports it) is a record of its own
//! sensors. Times must increase strictly; every temperature must be a finite number (a gap is
//! an error naming its line and column, not a silent interpolation).
//!
//! Between samples the temperature is taken as linear in time; before the first sample it
//! holds the first value, after the last the last. A first-order lag of a sensor
//! ([`TemperatureRecord::lagged`]) follows the same linear pieces exactly
//! ([`super::first_order_lag`]), starting in equilibrium with the first sample — the way
//! positioning discovery lags a sensor, so a model it writes evaluates to the same numbers.

use super::first_order_lag;
use crate::io::{TableError, csv_reader, finite_number, read_file, read_header, row};
use crate::math::Real;
use std::path::Path;

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
    /// Reads a record from a CSV file (see the module documentation).
    pub fn read(path: impl AsRef<Path>) -> Result<TemperatureRecord, TableError> {
        let (bytes, file) = read_file(path.as_ref())?;
        TemperatureRecord::parse(&bytes, &file)
    }

    /// Reads a record from CSV bytes; `file` names it in messages.
    pub fn parse(bytes: &[u8], file: &str) -> Result<TemperatureRecord, TableError> {
        let fail = |line: Option<u64>, message: String| TableError::new(file, line, message);
        let mut reader = csv_reader(bytes);
        let (header, header_line) = read_header(&mut reader, file)?;
        let time_column = header.iter().position(|h| h == "time_min").ok_or_else(|| {
            fail(
                Some(header_line),
                "missing column `time_min` (a temperature record needs the time of each sample)"
                    .into(),
            )
        })?;
        let (mut sensors, mut columns) = (Vec::new(), Vec::new());
        for (index, name) in header.iter().enumerate() {
            if let Some(sensor) = name
                .strip_prefix("temp_")
                .and_then(|rest| rest.strip_suffix("_degc"))
                .filter(|s| !s.is_empty())
            {
                sensors.push(sensor.to_string());
                columns.push((index, name.to_string()));
            }
        }
        if sensors.is_empty() {
            return Err(fail(
                Some(header_line),
                "no temperature column: expected one or more `temp_<sensor>_degc`".into(),
            ));
        }
        let mut times: Vec<Real> = Vec::new();
        let mut values = vec![Vec::new(); sensors.len()];
        for record in reader.records() {
            let record = row(record, bytes, file)?;
            let line = record.position().map(|p| p.line());
            let time = finite_number(&record, time_column, "time_min", file)? * 60.0;
            if let Some(&last) = times.last()
                && time <= last
            {
                return Err(fail(
                    line,
                    format!(
                        "column `time_min`: {} min after {} min; the times of a temperature record must increase",
                        time / 60.0,
                        last / 60.0
                    ),
                ));
            }
            times.push(time);
            for ((index, name), series) in columns.iter().zip(&mut values) {
                series.push(finite_number(&record, *index, name, file)?);
            }
        }
        if times.is_empty() {
            return Err(fail(None, "no samples after the header".into()));
        }
        Ok(TemperatureRecord {
            file: file.to_string(),
            sha256: crate::math::sha256_hex(bytes),
            times,
            sensors,
            values,
        })
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
        let measured = &self.values[sensor];
        let mut lagged = Vec::with_capacity(measured.len());
        lagged.push(measured[0]);
        for k in 1..measured.len() {
            let dt = self.times[k] - self.times[k - 1];
            lagged.push(first_order_lag(
                lagged[k - 1],
                measured[k - 1],
                measured[k],
                dt,
                tau,
            ));
        }
        lagged
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

    /// Sensor `sensor` through a lag of `tau` s at `time` s, continuing `lagged` (its
    /// [`TemperatureRecord::lagged`] series) exactly from the sample before `time` along the
    /// linear piece (held after the last sample, so the lag goes on settling).
    pub fn lagged_at(&self, sensor: usize, lagged: &[Real], tau: Real, time: Real) -> Real {
        let k = self.times.partition_point(|&t| t <= time);
        if k == 0 {
            return lagged[0];
        }
        let elapsed = time - self.times[k - 1];
        if elapsed == 0.0 {
            return lagged[k - 1];
        }
        let from = self.values[sensor][k - 1];
        first_order_lag(lagged[k - 1], from, self.at(sensor, time), elapsed, tau)
    }

    /// Sensor `sensor`'s temperature (°C) at `time` s.
    pub fn at(&self, sensor: usize, time: Real) -> Real {
        self.interpolate(&self.values[sensor], time)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RAMP: &[u8] = b"time_min,temp_nut_degc,deviation_um\n0,20,1\n10,21,2\n20,23,3\n";

    #[test]
    fn interpolates_linearly_and_holds_outside() {
        let record = TemperatureRecord::parse(RAMP, "r.csv").unwrap();
        assert_eq!(record.sensors(), ["nut"]);
        assert_eq!(record.at(0, -60.0), 20.0);
        assert!((record.at(0, 300.0) - 20.5).abs() < 1e-12);
        assert!((record.at(0, 900.0) - 22.0).abs() < 1e-12);
        assert_eq!(record.at(0, 5000.0), 23.0);
    }

    #[test]
    fn the_lag_of_a_steady_ramp_settles_at_tau_times_the_rate() {
        // A ramp of 1 °C per 10 min, long after the start, lags by τ·r (closed form).
        let rows: String = (0..=200)
            .map(|k| format!("{},{}\n", k as Real, 20.0 + 0.1 * k as Real))
            .collect();
        let text = format!("time_min,temp_s_degc\n{rows}");
        let record = TemperatureRecord::parse(text.as_bytes(), "r.csv").unwrap();
        let tau = 300.0;
        let lagged = record.lagged(0, tau);
        let rate = 0.1 / 60.0;
        let last = lagged.len() - 1;
        assert!((record.samples(0)[last] - lagged[last] - tau * rate).abs() < 1e-9);
        // And from equilibrium: τr·(1 − e^(−t/τ)) behind after t.
        let t = 600.0;
        let expected = tau * rate * (1.0 - (-t / tau).exp());
        assert!((record.samples(0)[10] - lagged[10] - expected).abs() < 1e-12);
    }

    #[test]
    fn gaps_unordered_times_and_missing_columns_are_refused_with_their_line() {
        let gap = TemperatureRecord::parse(b"time_min,temp_s_degc\n0,20\n1,\n", "g.csv");
        let message = gap.unwrap_err().to_string();
        assert!(
            message.starts_with("g.csv:3:") && message.contains("temp_s_degc"),
            "{message}"
        );
        let order = TemperatureRecord::parse(b"time_min,temp_s_degc\n0,20\n2,21\n1,22\n", "o.csv");
        let message = order.unwrap_err().to_string();
        assert!(
            message.starts_with("o.csv:4:") && message.contains("must increase"),
            "{message}"
        );
        let none = TemperatureRecord::parse(b"time_min,deviation_um\n0,1\n", "n.csv");
        assert!(none.unwrap_err().to_string().contains("temp_<sensor>_degc"));
        let no_time = TemperatureRecord::parse(b"temp_s_degc\n20\n", "t.csv");
        assert!(no_time.unwrap_err().to_string().contains("time_min"));
    }
}
