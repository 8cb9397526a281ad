//! What a drift table's own data say against its units, as cautions for the ISO 230-3
//! report, each naming the column and the likely slip:
//!
//! - a displacement channel drifting more than [`LARGEST_DRIFT`] (nm in the µm column), or
//!   spanning less than [`SMALLEST_DRIFT`] (mm in it), alone or with every other;
//! - a sensor reading a unit factor times its partner of the nest, reading for reading
//!   ([`crate::io::plausible::unit_ratio`]: one channel's gain or unit set apart);
//! - sensors of a pair closer than [`SMALLEST_SPACING`] (inches in `spacing_mm`);
//! - a channel holding one value through [`STUCK_READINGS`] readings or a tenth of the record
//!   ([`crate::io::plausible::stuck`]: a sensor out of range, a logger repeating itself), a
//!   thermometer holding one value through an hour or more, a reading standing apart from
//!   both its neighbours ([`crate::io::plausible::spike`]) and a pair whose difference steps
//!   once ([`crate::io::plausible::lone_step`]: a sensor re-zeroed), both beyond
//!   [`SMALLEST_GLITCH`];
//! - a spindle test whose structure is hottest long after its stated running period
//!   (`run_min` and `stop_min` exchanged);
//! - readings more than [`LONGEST_STEP`] apart at the median (seconds in `time_min`);
//! - an air sensor outside a shop's air ([`crate::io::plausible::air_caution`]: °F), and an
//!   ambient sensor not named for the air where one is;
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

/// The closest two sensors of a nest's pair can be (m): 10 mm. A capacitive or inductive
/// sensor's body is about 8 mm across and the pairs of ISO 230-3 (Fig. 4) stand along a test
/// mandrel tens of millimetres apart; a spacing in inches written as mm reads 25.4 times less.
pub const SMALLEST_SPACING: Real = 10e-3;

/// The fewest consecutive readings of one value that read as a stuck sensor (or a tenth of
/// the record, if more): 20. A displacement sensor's noise changes its last digit from
/// reading to reading (channels rounded to 1 µm, whose value may rest, are not judged).
pub const STUCK_READINGS: usize = 20;

/// The smallest spike or step (m) of a displacement channel that is named: 1 µm, above the
/// resolution and noise of the sensors of a nest (0.01 µm) by a hundred.
pub const SMALLEST_GLITCH: Real = 1e-6;

/// The longest median time between a drift record's readings (s): 30 min. ISO 230-3 records
/// are read every few minutes or continuously (§7.2.3 allows every five cycles when storage
/// is short); seconds written in `time_min` read 60 times apart.
pub const LONGEST_STEP: Real = 1800.0;

/// The rows a stretch must span to count as pasted again when it repeats an earlier one
/// value for value: ten readings of every channel.
pub const PASTED_ROWS: usize = 10;

/// Every caution for the ISO 230-3 report of `table` evaluated with an ETVE test of
/// `etve_duration` (s), its pairs `spacing` m apart when known.
pub fn cautions(table: &DriftTable, etve_duration: Real, spacing: Option<Real>) -> Vec<String> {
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
        let rounded = crate::io::plausible::rounded_to(&channel.values);
        if let Some(step) = rounded {
            found.push(crate::io::plausible::rounding_sentence(
                &format!("{}_um", channel.name),
                step,
                "a displacement sensor reads to 0.01 µm or better",
            ));
        }
        if rounded.is_none()
            && let Some((first, count)) = crate::io::plausible::stuck(
                &channel.values,
                STUCK_READINGS.max(channel.values.len() / 10),
            )
        {
            let minute = |i: usize| trimmed(table.times[i] / 60.0, 4);
            found.push(format!(
                "column `{}_um` holds {} µm unchanged from {} to {} min ({count} readings): a sensor out of its range or disconnected, a logger repeating its last value? Its drift, and any tilt from it, stop there",
                channel.name,
                trimmed(channel.values[first] * 1e6, 4),
                minute(first),
                minute(first + count - 1)
            ));
        }
        if let Some((k, size, scale)) =
            crate::io::plausible::spike(&channel.values, SMALLEST_GLITCH)
        {
            found.push(format!(
                "column `{}_um`: the reading at {} min stands {} µm from both its neighbours, more than {} times the channel's typical {} µm: a glitch or a typo? It sets the channel's range",
                channel.name,
                trimmed(table.times[k] / 60.0, 4),
                trimmed(size * 1e6, 4),
                crate::io::plausible::LONE_READING,
                trimmed(scale * 1e6, 3)
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
    } else if let Some(widest) = widest {
        for channel in &linear {
            let span = spread(channel.values.iter().copied());
            if span < SMALLEST_DRIFT {
                found.push(format!(
                    "column `{}_um` spans {} µm over the record, less than the {} µm a sensor's noise alone gives, while another channel spans {} µm: mm in that column?",
                    channel.name,
                    trimmed(span * 1e6, 6),
                    trimmed(SMALLEST_DRIFT * 1e6, 5),
                    trimmed(widest * 1e6, 4)
                ));
            }
        }
    }
    found.extend(pair_units(table, spacing));
    if let Some(l) = spacing.filter(|&l| l < SMALLEST_SPACING) {
        found.push(format!(
            "spacing_mm {}: the sensors of a pair cannot stand closer than about {} mm (their bodies alone), so every tilt reads {} times too large if this is the spacing in inches",
            trimmed(l * 1e3, 4),
            trimmed(SMALLEST_SPACING * 1e3, 3),
            trimmed(25.4, 3)
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
    found.extend(run_and_stop(table));
    let stated = table.conditions.ambient_sensor.as_deref();
    let airy = |name: &str| name.contains("air") || name.contains("ambient");
    if let Some(stated) = stated.filter(|s| !airy(s))
        && let Some((air, _)) = table.temperatures.iter().find(|(name, _)| airy(name))
    {
        found.push(format!(
            "the ambient sensor is `temp_{stated}_degc` while the table has `temp_{air}_degc`: the environment's ΔT (ETVE) is read from a sensor not named for the air (a structure sensor warms with the machine); is the ambient sensor `{air}`?"
        ));
    }
    for (name, values) in &table.temperatures {
        let column = format!("temp_{name}_degc");
        if values.len() >= STUCK_READINGS
            && span >= 3600.0
            && values.iter().all(|v| v.to_bits() == values[0].to_bits())
        {
            found.push(format!(
                "column `{column}` holds {} °C through the whole {} min record: no thermometer in a shop reads one value for an hour (disconnected, or a constant filled in)? Every ΔT from it reads 0",
                trimmed(values[0], 4),
                trimmed(span / 60.0, 4)
            ));
        } else if let Some((first, count)) =
            crate::io::plausible::stuck(values, STUCK_READINGS.max(values.len() / 10))
        {
            found.push(format!(
                "column `{column}` holds {} °C unchanged from {} to {} min ({count} readings) while it otherwise changes: a thermometer disconnected or a logger repeating its last value?",
                trimmed(values[first], 4),
                trimmed(table.times[first] / 60.0, 4),
                trimmed(table.times[first + count - 1] / 60.0, 4)
            ));
        }
        if Some(name.as_str()) == stated || airy(name) {
            found.extend(air_caution(&column, values));
        } else {
            found.extend(crate::io::plausible::structure_caution(&column, values));
        }
    }
    found
}

/// The smallest rise (°C) of a structure sensor through a spindle test for its hottest time to
/// be judged: 1 °C, well above the air's wander.
pub const JUDGED_RISE_DEGC: Real = 1.0;

/// A spindle test whose every structure sensor that warms is hottest long after the stated
/// running period: more than half the stated stop (and 10 min) after `run_min`. A spindle's
/// bearings and housing cool from the moment it stops (heat spreading into a far sensor
/// delays its peak by minutes, not by half a cooling period); hottest at the very end of a
/// record said to run 60 min and stand 240, the spindle ran the 240 (`run_min` and
/// `stop_min` exchanged) and the figures d(·)_t are taken at the wrong time.
fn run_and_stop(table: &DriftTable) -> Option<String> {
    let c = &table.conditions;
    let (run, stop) = (c.run_period?, c.stop.filter(|&s| s > 0.0)?);
    let ambient = c.ambient_sensor.as_deref();
    let late = run + (0.5 * stop).max(600.0);
    let mut judged = Vec::new();
    for (name, values) in &table.temperatures {
        if Some(name.as_str()) == ambient || name.contains("air") || name.contains("ambient") {
            continue;
        }
        let Some((hottest, peak)) = values.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))
        else {
            continue;
        };
        if peak - values[0] >= JUDGED_RISE_DEGC {
            judged.push((name, table.times.get(hottest).copied()?));
        }
    }
    let &(name, when) = judged.iter().min_by(|a, b| a.1.total_cmp(&b.1))?;
    (when > late).then(|| {
        format!(
            "column `temp_{name}_degc` is hottest at {} min (and every warming structure sensor after {} min), {} min after the running period run_min = {} says ends, with stop_min = {}: run_min and stop_min exchanged, or the spindle ran longer than stated? The d(·)_t figures are taken at run_min",
            trimmed(when / 60.0, 4),
            trimmed(late / 60.0, 4),
            trimmed((when - run) / 60.0, 4),
            trimmed(run / 60.0, 4),
            trimmed(stop / 60.0, 4)
        )
    })
}

/// A sensor of a pair (x1 and x2, y1 and y2) reading a unit factor times its partner, reading
/// for reading: one channel's gain or unit set apart (a count of 0.1 µm, nm, inches), which
/// the pair turns into a tilt no structure shows.
fn pair_units(table: &DriftTable, spacing: Option<Real>) -> Vec<String> {
    let linear = |name: &str| {
        table
            .channels
            .iter()
            .find(|c| c.name == name && !c.angular)
            .map(|c| c.values.as_slice())
    };
    let mut found = Vec::new();
    for (first, second) in [("x1", "x2"), ("y1", "y2")] {
        let (Some(a), Some(b)) = (linear(first), linear(second)) else {
            continue;
        };
        let difference: Vec<Real> = a.iter().zip(b).map(|(p, q)| q - p).collect();
        if let Some((k, step, scale)) =
            crate::io::plausible::lone_step(&difference, SMALLEST_GLITCH)
        {
            found.push(format!(
                "columns `{first}_um` and `{second}_um`: their difference steps by {} µm between {} and {} min while it otherwise changes by {} µm a reading: one sensor re-zeroed or knocked? The tilt from the pair carries the step",
                trimmed(step * 1e6, 4),
                trimmed(table.times[k - 1] / 60.0, 4),
                trimmed(table.times[k] / 60.0, 4),
                trimmed(scale * 1e6, 3)
            ));
        }
        let Some(factor) = crate::io::plausible::unit_ratio(a, b) else {
            continue;
        };
        let tilt = spacing.map_or(String::new(), |l| {
            let difference = a.iter().zip(b).map(|(p, q)| q - p);
            format!(
                ", so the pair {} mm apart tilts by {} µrad",
                trimmed(l * 1e3, 4),
                trimmed(spread(difference) / l * 1e6, 4)
            )
        });
        let (large, small, times) = if factor > 1.0 {
            (second, first, factor)
        } else {
            (first, second, 1.0 / factor)
        };
        found.push(format!(
            "columns `{first}_um` and `{second}_um`: {large} reads {} times {small}, reading for reading{tilt}: one sensor's gain or unit (a count of 0.1 µm, nm, inches) set apart from its partner's?",
            trimmed(times, 4)
        ));
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
