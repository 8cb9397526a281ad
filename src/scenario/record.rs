//! Reading a measured temperature record ([`TemperatureRecord`], the input named by
//! `[inputs] temperatures`): a CSV table with a `time_min` column (time since the start of the
//! test) and one or more `temp_<sensor>_degc` columns; other columns are ignored, so a
//! positioning table (`positioning.csv`, as `mtwin run` writes it or a laser exports it) is a
//! record of its own sensors. Times must increase strictly; every temperature must be a finite
//! number (a gap is an error naming its line and column, not a silent interpolation).

use crate::errors::TemperatureRecord;
use crate::io::{
    CLOCK_MIN, THERMOMETER, TableError, csv_reader, number_within, read_file, read_header, row,
};
use crate::math::Real;
use std::path::Path;

/// Reads a record from a CSV file (see the module documentation).
pub fn read_temperature_record(path: impl AsRef<Path>) -> Result<TemperatureRecord, TableError> {
    let (bytes, file) = read_file(path.as_ref())?;
    parse_temperature_record(&bytes, &file)
}

/// Reads a record from CSV bytes; `file` names it in messages.
pub fn parse_temperature_record(bytes: &[u8], file: &str) -> Result<TemperatureRecord, TableError> {
    let fail = |line: Option<u64>, message: String| TableError::new(file, line, message);
    let mut reader = csv_reader(bytes);
    let (header, header_line) = read_header(&mut reader, file)?;
    let time_column = header.iter().position(|h| h == "time_min").ok_or_else(|| {
        fail(
            Some(header_line),
            "missing column `time_min` (a temperature record needs the time of each sample)".into(),
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
        let time = number_within(&record, time_column, "time_min", file, CLOCK_MIN)? * 60.0;
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
            series.push(number_within(&record, *index, name, file, THERMOMETER)?);
        }
    }
    if times.is_empty() {
        return Err(fail(None, "no samples after the header".into()));
    }
    Ok(TemperatureRecord::new(
        file.to_string(),
        crate::math::sha256_hex(bytes),
        times,
        sensors,
        values,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const RAMP: &[u8] = b"time_min,temp_nut_degc,deviation_um\n0,20,1\n10,21,2\n20,23,3\n";

    #[test]
    fn interpolates_linearly_and_holds_outside() {
        let record = parse_temperature_record(RAMP, "r.csv").unwrap();
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
        let record = parse_temperature_record(text.as_bytes(), "r.csv").unwrap();
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
        let gap = parse_temperature_record(b"time_min,temp_s_degc\n0,20\n1,\n", "g.csv");
        let message = gap.unwrap_err().to_string();
        assert!(
            message.starts_with("g.csv:3:") && message.contains("temp_s_degc"),
            "{message}"
        );
        let order = parse_temperature_record(b"time_min,temp_s_degc\n0,20\n2,21\n1,22\n", "o.csv");
        let message = order.unwrap_err().to_string();
        assert!(
            message.starts_with("o.csv:4:") && message.contains("must increase"),
            "{message}"
        );
        let none = parse_temperature_record(b"time_min,deviation_um\n0,1\n", "n.csv");
        assert!(none.unwrap_err().to_string().contains("temp_<sensor>_degc"));
        let no_time = parse_temperature_record(b"temp_s_degc\n20\n", "t.csv");
        assert!(no_time.unwrap_err().to_string().contains("time_min"));
    }
}
