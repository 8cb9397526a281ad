//! `mtwin compare MEASURED.csv SIMULATED.csv`: how far a simulated positioning table is from a
//! measured one — per run and overall, the RMS, mean and largest of measured − simulated, and
//! how far apart the two tables' times and temperatures are (a simulation that did not replay
//! the file's timing or temperatures says so instead of hiding it in the deviations).
//!
//! Readings are paired by run (by label when the simulated table has every run label of the
//! measured one, else in order of appearance), direction, target (within 0.1 µm) and
//! occurrence, so the two files may list them in different orders; readings of one file
//! without a partner in the other are counted and reported.

use super::table::{PositioningReading, PositioningTable};
use crate::math::{M_PER_MM, M_PER_UM, Real, fixed};
use serde_json::{Value, json};

/// Targets closer than this are the same target (m).
const SAME_TARGET: Real = 1e-7;

/// The differences of one group of paired readings (m, s, °C).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Difference {
    /// Paired readings.
    pub count: usize,
    /// RMS of measured − simulated (m).
    pub rms: Real,
    /// Mean of measured − simulated (m).
    pub mean: Real,
    /// Largest |measured − simulated| (m).
    pub largest: Real,
    /// Largest |Δ time| (s), when both tables have times.
    pub time: Option<Real>,
    /// Largest |Δ temperature| over the sensors both tables have (°C).
    pub temperature: Option<Real>,
}

/// The comparison of two positioning tables.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Run labels of the measured table and each run's differences.
    pub runs: Vec<(String, Difference)>,
    /// Every paired reading.
    pub overall: Difference,
    /// Readings of the measured table without a partner.
    pub unpaired_measured: usize,
    /// Readings of the simulated table without a partner.
    pub unpaired_simulated: usize,
    /// Sensors both tables have.
    pub common_sensors: Vec<String>,
}

/// Why two tables cannot be compared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct CompareError(String);

/// Pairs the readings of `measured` and `simulated` and measures their differences.
pub fn compare(
    measured: &PositioningTable,
    simulated: &PositioningTable,
) -> Result<Comparison, CompareError> {
    if let (Some(a), Some(b)) = (measured.axis, simulated.axis)
        && a != b
    {
        return Err(CompareError(format!(
            "the measured table is of axis {a}, the simulated one of axis {b}"
        )));
    }
    let common_sensors: Vec<String> = measured
        .sensors
        .iter()
        .filter(|s| simulated.sensors.contains(s))
        .cloned()
        .collect();
    let sensor_pairs: Vec<(usize, usize)> = common_sensors
        .iter()
        .map(|name| {
            let at = |t: &PositioningTable| t.sensors.iter().position(|s| s == name).unwrap();
            (at(measured), at(simulated))
        })
        .collect();
    // Runs by label when the simulated table has every label, else in order of appearance.
    let by_label: Option<Vec<usize>> = measured
        .runs
        .iter()
        .map(|label| simulated.runs.iter().position(|l| l == label))
        .collect();
    let run_of = |run: usize| by_label.as_ref().map_or(run, |map| map[run]);
    let mut used = vec![false; simulated.readings.len()];
    let mut groups: Vec<Vec<Pair>> = vec![Vec::new(); measured.runs.len()];
    let mut unpaired_measured = 0;
    for (k, reading) in measured.readings.iter().enumerate() {
        let occurrence = measured.readings[..k]
            .iter()
            .filter(|r| same_place(r, reading, reading.run))
            .count();
        let partner = simulated
            .readings
            .iter()
            .enumerate()
            .filter(|(_, r)| same_place(r, reading, run_of(reading.run)))
            .nth(occurrence)
            .map(|(j, _)| j);
        let Some(j) = partner else {
            unpaired_measured += 1;
            continue;
        };
        used[j] = true;
        let other = &simulated.readings[j];
        groups[reading.run].push(Pair {
            difference: reading.deviation - other.deviation,
            time: reading.time.zip(other.time).map(|(a, b)| (a - b).abs()),
            temperature: sensor_pairs
                .iter()
                .map(|&(a, b)| (reading.temperatures[a] - other.temperatures[b]).abs())
                .reduce(Real::max),
        });
    }
    let all: Vec<Pair> = groups.iter().flatten().cloned().collect();
    if all.is_empty() {
        return Err(CompareError(
            "no reading of the measured table has a partner in the simulated one (same run, direction and target)".into(),
        ));
    }
    Ok(Comparison {
        runs: measured
            .runs
            .iter()
            .cloned()
            .zip(groups.iter().map(|g| summarise(g)))
            .collect(),
        overall: summarise(&all),
        unpaired_measured,
        unpaired_simulated: used.iter().filter(|u| !**u).count(),
        common_sensors,
    })
}

/// One paired reading.
#[derive(Clone, Debug)]
struct Pair {
    difference: Real,
    time: Option<Real>,
    temperature: Option<Real>,
}

/// `a` is in run `run` (of its table) and at `b`'s direction and target.
fn same_place(a: &PositioningReading, b: &PositioningReading, run: usize) -> bool {
    a.run == run && a.approach == b.approach && (a.target - b.target).abs() <= SAME_TARGET
}

fn summarise(pairs: &[Pair]) -> Difference {
    if pairs.is_empty() {
        return Difference::default();
    }
    let n = pairs.len() as Real;
    let largest_of = |f: &dyn Fn(&Pair) -> Option<Real>| -> Option<Real> {
        pairs
            .iter()
            .map(f)
            .collect::<Option<Vec<Real>>>()?
            .into_iter()
            .reduce(Real::max)
    };
    Difference {
        count: pairs.len(),
        rms: (pairs.iter().map(|p| p.difference.powi(2)).sum::<Real>() / n).sqrt(),
        mean: pairs.iter().map(|p| p.difference).sum::<Real>() / n,
        largest: pairs
            .iter()
            .map(|p| p.difference.abs())
            .fold(0.0, Real::max),
        time: largest_of(&|p| p.time),
        temperature: largest_of(&|p| p.temperature),
    }
}

impl Comparison {
    /// The report for people.
    pub fn to_text(&self, measured: &str, simulated: &str) -> String {
        let um = |v: Real| fixed(v / M_PER_UM, 3);
        let line = |label: &str, d: &Difference| {
            let mut text = format!(
                "  {label:<10} {:>5} readings  RMS {:>8} µm  mean {:>8} µm  largest {:>8} µm",
                d.count,
                um(d.rms),
                um(d.mean),
                um(d.largest)
            );
            if let Some(t) = d.time {
                text += &format!("  |Δt| ≤ {} s", fixed(t, 3));
            }
            if let Some(t) = d.temperature {
                text += &format!("  |ΔT| ≤ {} °C", fixed(t, 3));
            }
            text + "\n"
        };
        let mut out = format!(
            "Measured − simulated positioning deviations\n  measured:  {measured}\n  simulated: {simulated}\n\n"
        );
        for (label, d) in &self.runs {
            out += &line(&format!("run {label}"), d);
        }
        out += &line("overall", &self.overall);
        if self.unpaired_measured + self.unpaired_simulated > 0 {
            out += &format!(
                "\n{} measured and {} simulated readings have no partner (same run, direction and target within {} µm).\n",
                self.unpaired_measured,
                self.unpaired_simulated,
                fixed(SAME_TARGET / M_PER_UM, 1)
            );
        }
        if self.common_sensors.is_empty() {
            out += "\nThe tables share no temperature sensor: their thermal conditions are not compared.\n";
        }
        out
    }

    /// The comparison as JSON (µm, s, °C).
    pub fn to_json(&self) -> Value {
        let difference = |d: &Difference| {
            json!({
                "readings": d.count,
                "rms_um": d.rms / M_PER_UM,
                "mean_um": d.mean / M_PER_UM,
                "largest_um": d.largest / M_PER_UM,
                "largest_time_difference_s": d.time,
                "largest_temperature_difference_degc": d.temperature,
            })
        };
        json!({
            "runs": self.runs.iter().map(|(label, d)| {
                let mut value = difference(d);
                value["run"] = label.clone().into();
                value
            }).collect::<Vec<_>>(),
            "overall": difference(&self.overall),
            "unpaired_measured": self.unpaired_measured,
            "unpaired_simulated": self.unpaired_simulated,
            "common_sensors": self.common_sensors,
            "same_target_mm": SAME_TARGET / M_PER_MM,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(rows: &str) -> PositioningTable {
        PositioningTable::parse(
            format!("run,direction,target_mm,deviation_um,time_min,temp_s_degc\n{rows}").as_bytes(),
            "t.csv",
        )
        .unwrap()
    }

    #[test]
    fn pairs_by_place_whatever_the_order_and_measures_by_hand() {
        let measured = table("1,+,0,1.0,0,20\n1,+,100,2.0,1,20.5\n2,+,0,1.5,10,21\n");
        // Same readings, another order, deviations off by 0.3, −0.1 and 0.5 µm.
        let simulated = table("2,+,0,1.0,10,21\n1,+,100,2.1,1,20.4\n1,+,0,0.7,0,20\n");
        let c = compare(&measured, &simulated).unwrap();
        let by_hand = ((0.09 + 0.01 + 0.25) / 3.0_f64).sqrt();
        assert!((c.overall.rms / M_PER_UM - by_hand).abs() < 1e-9);
        assert!((c.overall.largest / M_PER_UM - 0.5).abs() < 1e-9);
        assert!((c.overall.mean / M_PER_UM - 0.7 / 3.0).abs() < 1e-9);
        assert_eq!(c.runs[0].1.count, 2);
        assert!((c.overall.temperature.unwrap() - 0.1).abs() < 1e-9);
        assert_eq!(c.overall.time, Some(0.0));
        assert_eq!((c.unpaired_measured, c.unpaired_simulated), (0, 0));
    }

    #[test]
    fn unpaired_readings_are_counted_and_nothing_in_common_is_an_error() {
        let measured = table("1,+,0,1.0,0,20\n1,-,0,2.0,1,20\n");
        let simulated = table("1,+,0,1.0,0,20\n1,+,50,2.0,1,20\n");
        let c = compare(&measured, &simulated).unwrap();
        assert_eq!((c.unpaired_measured, c.unpaired_simulated), (1, 1));
        let far = table("1,+,500,1.0,0,20\n");
        assert!(compare(&measured, &far).is_err());
    }
}
