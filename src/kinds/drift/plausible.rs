//! What a drift table's own data say against its units, as cautions for the ISO 230-3
//! report, each naming the column and the likely slip:
//!
//! - a displacement channel drifting more than [`LARGEST_DRIFT`] (nm in the µm column), or
//!   every one spanning less than [`SMALLEST_DRIFT`] (mm in it);
//! - readings more than [`LONGEST_STEP`] apart at the median (seconds in `time_min`);
//! - an air sensor outside a shop's air ([`crate::io::plausible::air_caution`]: °F);
//! - a record shorter than its ETVE test or than the first hour (hours in `time_min`, a
//!   record cut short), and a stretch pasted again ([`PASTED_ROWS`]).

use super::table::DriftTable;
use crate::io::plausible::{air_caution, median, spread};
use crate::math::{Real, trimmed};

/// The largest thermal drift a machine tool shows at a sensor nest (m): 1 mm. ISO 230-3's
/// own example (Fig. 7) reaches 108 µm after 4 h of spindle running at 6 000 min⁻¹; nm written
/// in the µm column read 1000 times larger.
pub const LARGEST_DRIFT: Real = 1e-3;

/// The smallest span every displacement channel of a record can have (m): 5 nm, about what a
/// capacitive sensor's noise alone gives over hours; no machine holds all its nests closer
/// than that through a test. Millimetres written in the µm column span 1000 times less.
pub const SMALLEST_DRIFT: Real = 5e-9;

/// The longest median time between a drift record's readings (s): 30 min. ISO 230-3 records
/// are read every few minutes or continuously (§7.2.3 allows every five cycles when storage
/// is short); seconds written in `time_min` read 60 times apart.
pub const LONGEST_STEP: Real = 1800.0;

/// The rows a stretch must span to count as pasted again when it repeats an earlier one
/// value for value: ten readings of every channel.
pub const PASTED_ROWS: usize = 10;

/// Every caution for the ISO 230-3 report of `table` evaluated with an ETVE test of
/// `etve_duration` (s).
pub fn cautions(table: &DriftTable, etve_duration: Real) -> Vec<String> {
    let mut found = Vec::new();
    let span = match (table.times.first(), table.times.last()) {
        (Some(a), Some(b)) => b - a,
        _ => 0.0,
    };
    if span < etve_duration.max(3600.0) {
        found.push(format!(
            "column `time_min`: the record lasts {} min, shorter than {}: {} (hours in the minutes column, or a record cut short?)",
            trimmed(span / 60.0, 3),
            if span < etve_duration {
                format!("the {} min ETVE test it is evaluated for", trimmed(etve_duration / 60.0, 3))
            } else {
                "the 60 min of the first-hour range".to_string()
            },
            if span < etve_duration {
                "no ETVE value, and the first-hour range covers the whole record"
            } else {
                "the first-hour range covers the whole record"
            }
        ));
    }
    found.extend(pasted(table));
    let linear: Vec<_> = table.channels.iter().filter(|c| !c.angular).collect();
    for channel in &linear {
        if let Some(step) = crate::io::plausible::rounded_to(&channel.values) {
            found.push(crate::io::plausible::rounding_sentence(
                &format!("{}_um", channel.name),
                step,
                "a displacement sensor reads to 0.01 µm or better",
            ));
        }
        let span = spread(channel.values.iter().copied());
        if span > LARGEST_DRIFT {
            found.push(format!(
                "column `{}_um`: the record drifts by {} µm, more than the {} µm of any machine tool's thermal drift (ISO 230-3's example reaches 108 µm): nm in the µm column?",
                channel.name,
                trimmed(span * 1e6, 3),
                trimmed(LARGEST_DRIFT * 1e6, 3)
            ));
        }
    }
    let widest = linear
        .iter()
        .map(|c| spread(c.values.iter().copied()))
        .fold(None, |m: Option<Real>, s| Some(m.map_or(s, |m| m.max(s))));
    if let Some(widest) = widest.filter(|&w| w < SMALLEST_DRIFT) {
        found.push(format!(
            "the displacement columns span at most {} µm, less than the {} µm a sensor's noise alone gives over a record: mm in the µm columns?",
            trimmed(widest * 1e6, 5),
            trimmed(SMALLEST_DRIFT * 1e6, 5)
        ));
    }
    let steps: Vec<Real> = table.times.windows(2).map(|w| w[1] - w[0]).collect();
    if let Some(step) = median(steps).filter(|&s| s > LONGEST_STEP) {
        found.push(format!(
            "column `time_min`: readings are {} min apart (median), more than the {} min an ISO 230-3 record leaves between readings: seconds in the minutes column?",
            trimmed(step / 60.0, 3),
            trimmed(LONGEST_STEP / 60.0, 3)
        ));
    }
    let stated = table.conditions.ambient_sensor.as_deref();
    for (name, values) in &table.temperatures {
        let column = format!("temp_{name}_degc");
        if Some(name.as_str()) == stated || name.contains("air") || name.contains("ambient") {
            found.extend(air_caution(&column, values));
        } else {
            found.extend(crate::io::plausible::structure_caution(&column, values));
        }
    }
    found
}

/// A stretch of [`PASTED_ROWS`] rows whose every channel repeats an earlier stretch value for
/// value: a record pasted again (a sensor's noise never repeats ten readings).
fn pasted(table: &DriftTable) -> Option<String> {
    let rows = table.times.len();
    if rows < 2 * PASTED_ROWS || table.channels.is_empty() {
        return None;
    }
    let row = |i: usize| -> Vec<u64> {
        table
            .channels
            .iter()
            .map(|c| c.values[i].to_bits())
            .collect()
    };
    let all: Vec<Vec<u64>> = (0..rows).map(row).collect();
    let mut seen: std::collections::HashMap<&[Vec<u64>], usize> = Default::default();
    for start in 0..=rows - PASTED_ROWS {
        let window = &all[start..start + PASTED_ROWS];
        if window.iter().all(|r| *r == window[0]) {
            continue;
        }
        if let Some(&earlier) = seen.get(window) {
            let minute = |i: usize| trimmed(table.times[i] / 60.0, 3);
            return Some(format!(
                "the readings from {} min repeat those from {} min in every channel, value for value: the record pasted again (a sensor's noise never repeats)",
                minute(start),
                minute(earlier)
            ));
        }
        seen.entry(window).or_insert(start);
    }
    None
}
