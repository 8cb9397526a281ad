//! What a positioning table's own data say against its labels and units, as cautions for the
//! ISO 230-2 report (and, for copies, as a refusal in `identify`): each names the column and
//! the likely slip.
//!
//! - **Thermal stability**: [`super::stability::caution`].
//! - **Direction labels against the travel.** In the standard's linear cycle the `+` readings
//!   are taken with the targets rising and the `-` readings with them falling. When every run
//!   shows the reverse (by `time_min`, or the rows' order without it), the labels are
//!   swapped: B̄ and every one-direction figure change sign. (A pendulum cycle visits the
//!   targets in the same order in both directions, so it never looks reversed.)
//! - **Incomplete runs**: a run with fewer readings than the others (a cut-off export) leaves
//!   its targets with fewer runs than the report's count.
//! - **A lone reading** far from the other runs at its target and direction
//!   ([`crate::io::plausible::lone_reading`], beyond [`SMALLEST_GLITCH`]): a beam
//!   interrupted, a vibration, a typo; it alone sets R and A.
//! - **A copied run** ([`crate::io::plausible::copied_block`]), runs that overlap in time
//!   (records mixed, or a run pasted again with its times), and runs that reverse by
//!   different amounts (records of different conditions mixed).
//! - **Units**: deviations spanning less than [`SMALLEST_SPREAD`] or repeating better than
//!   [`SMALLEST_SCATTER`] (mm in the µm column) or spanning more than [`LARGEST_SPREAD`] (nm
//!   in it), readings more than [`LONGEST_STEP`] or less than [`SHORTEST_STEP`] apart at the
//!   median (seconds or hours in `time_min`), and an air sensor outside a
//!   shop's air ([`crate::io::plausible::air_caution`]: °F).

use super::table::PositioningTable;
use crate::io::plausible::{Block, air_caution, copied_block, copy_sentence, median, spread};
use crate::math::{M_PER_MM, M_PER_UM, Real, trimmed};
use crate::program::Approach;

/// The smallest spread of deviations a laser reads on a machine axis (m): 5 nm. A laser in
/// air over a few minutes alone wanders by more (refractive index, dead path), and no axis of
/// 10 mm or more positions to better; deviations in mm written in the µm column span
/// 1000 times less than their true µm.
pub const SMALLEST_SPREAD: Real = 5e-9;

/// The largest spread of deviations a machine axis shows to a laser (m): 1 mm. ISO 230-2
/// tolerances are tens of µm and an uncompensated, worn axis a few hundred; nm in the µm
/// column read 1000 times larger.
pub const LARGEST_SPREAD: Real = 1e-3;

/// The longest median time between a positioning test's successive readings (s): 3 min. A
/// laser reading takes a dwell of seconds and the move to the next target seconds more (the
/// standard's tests read every 5 to 60 s); seconds written in `time_min` read 60 times apart.
pub const LONGEST_STEP: Real = 180.0;

/// The shortest median time between successive readings (s): 0.5 s. A laser averages over a
/// dwell of a second or more at each target; hours written in `time_min` read 60 times closer.
pub const SHORTEST_STEP: Real = 0.5;

/// The smallest median standard deviation of the readings at a target over the runs (m):
/// 1 nm. A laser in air does not repeat to better (refractive index, dead path, the axis's
/// own settling); deviations in mm written in the µm column repeat 1000 times too well.
pub const SMALLEST_SCATTER: Real = 1e-9;

/// How many times more or less than the other runs one run may span before it reads as
/// another unit: 30. Runs of one axis span the same errors within their drift and noise.
pub const ODD_RUN: Real = 30.0;

/// The smallest distance (m) a lone reading must lie from the other runs' median at its
/// target to be named: 2 µm, so that readings rounded to 1 µm (no scatter left to judge by)
/// are never named for their rounding.
pub const SMALLEST_GLITCH: Real = 2e-6;

/// The shortest travel (m) over which [`SMALLEST_SPREAD`] is judged.
const SHORTEST_TRAVEL: Real = 10e-3;

/// Every caution for the ISO 230-2 report of `table`, each a sentence.
pub fn cautions(table: &PositioningTable) -> Vec<String> {
    let mut found: Vec<String> = super::stability::caution(table).into_iter().collect();
    found.extend(data_cautions(table));
    found
}

/// The cautions on what the readings say against their labels and units, without the
/// thermal-stability one (which concerns the ISO 230-2 figures alone): for `discover`, which
/// models the drift rather than reporting A and R over it.
pub fn data_cautions(table: &PositioningTable) -> Vec<String> {
    let mut found: Vec<String> = swapped_directions(table).into_iter().collect();
    found.extend(incomplete_runs(table));
    let values: Vec<Real> = table.readings.iter().map(|r| r.deviation).collect();
    let rounded = crate::io::plausible::rounded_to(&values);
    let blocks = run_blocks(table);
    // Readings rounded to a micrometre repeat by the rounding, not by a copy.
    if rounded.is_none() {
        found.extend(
            copied_block(&blocks)
                .map(|pair| format!("column `deviation_um`: {}", copy_sentence(&blocks, pair))),
        );
    }
    found.extend(
        crate::io::plausible::odd_block(&blocks, ODD_RUN)
            .map(|odd| crate::io::plausible::odd_sentence("deviation_um", &blocks, odd)),
    );
    found.extend(lone_reading(table));
    found.extend(zeroed_runs(table));
    found.extend(overlapping_runs(table));
    found.extend(changing_reversal(table));
    found.extend(units(table, rounded));
    found.extend(uncompensated_air(table));
    found
}

/// The smallest length error over the measured travel (m) that an uncompensated laser's
/// wavelength in the logged air is named for: 1 µm.
pub const SMALLEST_AIR_ERROR: Real = 1e-6;

/// A laser that did not correct for the air (`compensation = none` or `nde`) in air the table
/// logs away from 20 °C: its wavelength is the standard air's, so every reading is short or
/// long by n(air)/n(standard) − 1 (the modified Edlén equation, [`super::air`]: −0.93 ppm per
/// °C, at standard pressure and humidity since the table logs neither), which the figures
/// take as the axis's scale error. Named when that error over the measured travel exceeds
/// [`SMALLEST_AIR_ERROR`].
fn uncompensated_air(table: &PositioningTable) -> Option<String> {
    let compensation = table.conditions.compensation.as_deref()?;
    if compensation.contains("air") {
        return None;
    }
    let index = table
        .sensors
        .iter()
        .position(|s| s.contains("air") || s.contains("ambient"))?;
    let values: Vec<Real> = table
        .readings
        .iter()
        .map(|r| r.temperatures[index])
        .collect();
    let air = median(values)?;
    let (lo, hi) = crate::io::plausible::SHOP_AIR_DEGC;
    if !(lo..=hi).contains(&air) {
        return None; // named as another unit by `units`
    }
    let n = |temperature: Real| {
        super::air::Air {
            temperature,
            ..super::air::Air::STANDARD
        }
        .refractive_index(super::air::HENE_WAVELENGTH_UM)
    };
    let relative = n(air) / n(20.0) - 1.0;
    let travel = spread(table.readings.iter().map(|r| r.target));
    (relative.abs() * travel >= SMALLEST_AIR_ERROR).then(|| {
        format!(
            "compensation = {compensation}: the laser did not correct for the air, which column `temp_{}_degc` logs at {} °C (median): its wavelength then reads every length {} ppm {} (modified Edlén at standard pressure and humidity), {} µm over the {} mm measured, which the figures take as the axis's own scale error",
            table.sensors[index],
            trimmed(air, 3),
            trimmed(relative.abs() * 1e6, 2),
            if relative < 0.0 { "short" } else { "long" },
            trimmed(relative.abs() * travel / M_PER_UM, 2),
            trimmed(travel / M_PER_MM, 4)
        )
    })
}

/// The indices of each run's readings, in file order (one pass, so every check stays linear
/// in the readings whatever the number of runs).
fn by_run(table: &PositioningTable) -> Vec<Vec<usize>> {
    let mut runs = vec![Vec::new(); table.runs.len()];
    for (k, r) in table.readings.iter().enumerate() {
        if let Some(run) = runs.get_mut(r.run) {
            run.push(k);
        }
    }
    runs
}

/// The readings of each run as blocks, in file order.
pub fn run_blocks(table: &PositioningTable) -> Vec<Block> {
    table
        .runs
        .iter()
        .enumerate()
        .zip(by_run(table))
        .map(|((_, label), indices)| Block {
            label: format!("run \"{label}\""),
            readings: indices
                .iter()
                .map(|&k| table.readings[k].deviation)
                .collect(),
        })
        .collect()
}

/// A run that repeats another reading for reading.
pub fn copied_run(table: &PositioningTable) -> Option<String> {
    let blocks = run_blocks(table);
    copied_block(&blocks)
        .map(|pair| format!("column `deviation_um`: {}", copy_sentence(&blocks, pair)))
}

/// Every run (of three or more) starting on a reading of exactly 0 while the preamble says the
/// laser was zeroed once, or says nothing: the laser re-zeroed at each run (or pass), so the
/// runs share no reference and the spread between them, R and A, is the zeroing's.
fn zeroed_runs(table: &PositioningTable) -> Option<String> {
    use crate::kinds::positioning::setup::Zeroing;
    if table.runs.len() < 3 || table.conditions.zero.is_some_and(|z| z != Zeroing::Once) {
        return None;
    }
    let timed = table.readings.iter().all(|r| r.time.is_some());
    let starts: Vec<Real> = by_run(table)
        .iter()
        .filter_map(|indices| {
            let first = if timed {
                indices.iter().copied().min_by(|&a, &b| {
                    let t = |k: usize| table.readings[k].time.unwrap_or(0.0);
                    t(a).total_cmp(&t(b))
                })
            } else {
                indices.first().copied()
            }?;
            Some(table.readings[first].deviation)
        })
        .collect();
    let zeros = table.readings.iter().filter(|r| r.deviation == 0.0).count();
    (starts.iter().all(|&d| d == 0.0) && zeros < table.readings.len() / 2).then(|| {
        format!(
            "column `deviation_um`: every one of the {} runs starts on exactly 0 while the preamble {}: the laser re-zeroed at each run (or pass)? The runs then share no reference, and R, A and B carry the zeroing (state `zero = each_run` if so)",
            starts.len(),
            if table.conditions.zero.is_some() {
                "says it was zeroed once"
            } else {
                "does not say how the laser was zeroed"
            }
        )
    })
}

/// A reading far from the other runs at its target and direction.
fn lone_reading(table: &PositioningTable) -> Option<String> {
    let mut groups: Vec<Vec<(Real, usize)>> = Vec::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    let mut index: std::collections::HashMap<(u64, Approach), usize> = Default::default();
    for (k, r) in table.readings.iter().enumerate() {
        let key = (r.target.to_bits(), r.approach);
        let g = *index.entry(key).or_insert_with(|| {
            groups.push(Vec::new());
            members.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push((r.deviation, r.run));
        members[g].push(k);
    }
    let lone = crate::io::plausible::lone_reading(&groups, SMALLEST_GLITCH)?;
    let reading = &table.readings[members[lone.group][lone.index]];
    Some(format!(
        "column `deviation_um`: run \"{}\", {} at target {} mm reads {} µm from the other runs' median there, more than {} times the runs' typical scatter of {} µm: a beam interrupted, a vibration or a typo? It alone sets R and A",
        table.runs.get(reading.run).map_or("?", String::as_str),
        match reading.approach {
            Approach::Up => "+ direction",
            Approach::Down => "− direction",
        },
        trimmed(reading.target / M_PER_MM, 4),
        trimmed(lone.off / M_PER_UM, 4),
        crate::io::plausible::LONE_READING,
        trimmed(lone.scale / M_PER_UM, 3)
    ))
}

/// Whether every run travels against its direction labels.
fn swapped_directions(table: &PositioningTable) -> Option<String> {
    if !table.has_direction {
        return None;
    }
    let timed = table.readings.iter().all(|r| r.time.is_some());
    // Steps up and down of the target, per direction, over every run in measurement order.
    let mut steps = [[0usize; 2]; 2]; // [+, -][rising, falling]
    for indices in by_run(table) {
        for (d, approach) in [Approach::Up, Approach::Down].into_iter().enumerate() {
            let mut visits: Vec<(Real, Real)> = indices
                .iter()
                .map(|&k| (k, &table.readings[k]))
                .filter(|(_, r)| r.approach == approach)
                .map(|(k, r)| (r.time.unwrap_or(k as Real), r.target))
                .collect();
            if timed {
                visits.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            for pair in visits.windows(2) {
                if pair[1].1 > pair[0].1 {
                    steps[d][0] += 1;
                } else if pair[1].1 < pair[0].1 {
                    steps[d][1] += 1;
                }
            }
        }
    }
    let [[up_rising, up_falling], [down_rising, down_falling]] = steps;
    let reversed = up_falling >= 2 && up_rising == 0 && down_rising >= 2 && down_falling == 0;
    reversed.then(|| {
        format!(
            "column `direction`: in every run the `+` readings were taken with the targets falling and the `-` readings with them rising (by {}), the reverse of the travel the labels name: the labels look swapped, which changes the sign of the reversal B̄ and swaps every one-direction figure",
            if timed { "time_min" } else { "the rows' order" }
        )
    })
}

/// A run that starts before the run listed before it ended: runs are read one after the
/// other, so the file mixes records (runs of another day's test) or pastes a run again.
fn overlapping_runs(table: &PositioningTable) -> Option<String> {
    let runs = by_run(table);
    let span = |run: usize| -> Option<(Real, Real)> {
        let times: Vec<Real> = runs[run]
            .iter()
            .map(|&k| table.readings[k].time)
            .collect::<Option<_>>()?;
        let first = times.iter().copied().fold(Real::INFINITY, Real::min);
        let last = times.iter().copied().fold(Real::NEG_INFINITY, Real::max);
        (first <= last).then_some((first, last))
    };
    // The runs in the order they were read (by their first time: an export may list its rows,
    // and so its runs, in another order).
    let spans: Vec<(usize, (Real, Real))> = (0..table.runs.len())
        .map(|run| Some((run, span(run)?)))
        .collect::<Option<_>>()?;
    let mut spans = spans;
    spans.sort_by(|a, b| a.1.0.total_cmp(&b.1.0));
    spans.windows(2).find_map(|w| {
        let ((before, (_, ended)), (run, (started, _))) = (w[0], w[1]);
        (started < ended).then(|| {
            format!(
                "column `time_min`: run \"{}\" starts at {} min, before run \"{}\" ended at {} min: runs are read one after the other, so these come from different records (or one was pasted again), and their spread is not the axis's repeatability",
                table.runs[run],
                trimmed(started / 60.0, 4),
                table.runs[before],
                trimmed(ended / 60.0, 4)
            )
        })
    })
}

/// The smallest change of the reversal between runs worth a caution (m): 1 µm.
pub const REVERSAL_CHANGE: Real = 1e-6;

/// Runs whose reversal (the mean over their targets of the `+` reading less the `-` one)
/// differ by more than [`REVERSAL_CHANGE`] and eight times what their noise lets them differ
/// by. Drift moves both directions alike and leaves the reversal, so runs that reverse by
/// different amounts were taken under different conditions (records of another day or
/// another feed mixed), or their lost motion changed with temperature. The noise is taken
/// from each run's reversal profile about the mean profile of the runs, less its own mean
/// (so a reversal that varies along the axis, alike in every run, is not noise).
fn changing_reversal(table: &PositioningTable) -> Option<String> {
    let key = |target: Real| (target * 1e9).round() as i64;
    let mut profiles: Vec<(usize, std::collections::BTreeMap<i64, Real>)> = Vec::new();
    for (run, indices) in by_run(table).iter().enumerate() {
        let mut up: std::collections::BTreeMap<i64, Real> = Default::default();
        let mut down: std::collections::BTreeMap<i64, Real> = Default::default();
        for &k in indices {
            let r = &table.readings[k];
            match r.approach {
                Approach::Up => up.insert(key(r.target), r.deviation),
                Approach::Down => down.insert(key(r.target), r.deviation),
            };
        }
        let profile: std::collections::BTreeMap<i64, Real> = up
            .iter()
            .filter_map(|(t, u)| down.get(t).map(|d| (*t, u - d)))
            .collect();
        if profile.len() >= 3 {
            profiles.push((run, profile));
        }
    }
    if profiles.len() < 3 {
        return None;
    }
    // The mean profile over the runs, then each run's departure from it.
    let mut sums: std::collections::BTreeMap<i64, (Real, usize)> = Default::default();
    for (_, profile) in &profiles {
        for (t, d) in profile {
            let entry = sums.entry(*t).or_insert((0.0, 0));
            entry.0 += d;
            entry.1 += 1;
        }
    }
    let mut shifts: Vec<(usize, Real, usize)> = Vec::new(); // run, mean departure, targets
    let (mut squares, mut dof) = (0.0, 0usize);
    for (run, profile) in &profiles {
        let departures: Vec<Real> = profile
            .iter()
            .map(|(t, d)| d - sums[t].0 / sums[t].1 as Real)
            .collect();
        let n = departures.len();
        let mean = departures.iter().sum::<Real>() / n as Real;
        squares += departures.iter().map(|e| (e - mean).powi(2)).sum::<Real>();
        dof += n - 1;
        shifts.push((*run, mean, n));
    }
    let noise = (squares / dof.max(1) as Real).sqrt();
    let (low, high) = (
        shifts.iter().min_by(|a, b| a.1.total_cmp(&b.1))?,
        shifts.iter().max_by(|a, b| a.1.total_cmp(&b.1))?,
    );
    let fewest = shifts.iter().map(|r| r.2).min()? as Real;
    let allowed = 8.0 * noise / fewest.sqrt();
    let change = high.1 - low.1;
    (change > REVERSAL_CHANGE && change > allowed).then(|| {
        let reversal = |run: usize| {
            let profile = &profiles.iter().find(|(r, _)| *r == run).expect("a run with a profile").1;
            profile.values().sum::<Real>() / profile.len() as Real
        };
        format!(
            "column `deviation_um`: the reversal changes from run to run, from {} µm (run \"{}\") to {} µm (run \"{}\"), more than the {} µm their noise allows: runs of different conditions mixed (another day, another feed), or lost motion changing with temperature; B and R do not describe one state of the axis",
            um(reversal(low.0)),
            table.runs[low.0],
            um(reversal(high.0)),
            table.runs[high.0],
            um(allowed)
        )
    })
}

/// Runs with fewer readings than the fullest run.
fn incomplete_runs(table: &PositioningTable) -> Option<String> {
    let counts: Vec<usize> = by_run(table).iter().map(Vec::len).collect();
    let most = counts.iter().copied().max()?;
    let short: Vec<String> = table
        .runs
        .iter()
        .zip(&counts)
        .filter(|(_, n)| **n < most)
        .map(|(label, n)| format!("run \"{label}\" has {n} of {most}"))
        .collect();
    (!short.is_empty()).then(|| {
        format!(
            "incomplete runs ({}): their missing targets rest on fewer runs than the {} the report counts (a cut-off export?)",
            short.join(", "),
            table.runs.len()
        )
    })
}

/// Deviations or times in a unit other than their column's (`rounded`: the step every
/// deviation is a multiple of, if any).
fn units(table: &PositioningTable, rounded: Option<Real>) -> Vec<String> {
    let mut found = Vec::new();
    let um = |v: Real| trimmed(v / M_PER_UM, 4);
    let deviations = spread(table.readings.iter().map(|r| r.deviation));
    let travel = spread(table.readings.iter().map(|r| r.target));
    if travel >= SHORTEST_TRAVEL && deviations < SMALLEST_SPREAD {
        found.push(format!(
            "column `deviation_um`: the deviations span only {} µm over {} mm of travel, less than the {} µm a laser reads on any machine axis: mm in the µm column?",
            um(deviations),
            trimmed(travel / M_PER_MM, 3),
            um(SMALLEST_SPREAD)
        ));
    }
    if deviations > LARGEST_SPREAD {
        found.push(format!(
            "column `deviation_um`: the deviations span {} µm, more than the {} µm of the worst machine axis a laser calibrates: nm in the µm column?",
            um(deviations),
            um(LARGEST_SPREAD)
        ));
    }
    if let Some(step) = rounded {
        found.push(crate::io::plausible::rounding_sentence(
            "deviation_um",
            step,
            "a laser reads to 0.001 µm; R and s are computed from it",
        ));
    }
    if let Some(scatter) = median_scatter(table)
        .filter(|&s| s < SMALLEST_SCATTER)
        .filter(|_| rounded.is_none())
    {
        found.push(format!(
            "column `deviation_um`: the readings at a target repeat over the runs to {} µm (median standard deviation), better than the {} µm a laser in air repeats to: mm in the µm column (or a noise-free simulation)?",
            um(scatter),
            um(SMALLEST_SCATTER)
        ));
    }
    let mut times: Vec<Real> = table.readings.iter().filter_map(|r| r.time).collect();
    times.sort_by(Real::total_cmp);
    let steps: Vec<Real> = times.windows(2).map(|w| w[1] - w[0]).collect();
    match median(steps) {
        Some(step) if step > LONGEST_STEP => found.push(format!(
            "column `time_min`: successive readings are {} min apart (median), more than the {} min a laser positioning test takes per reading: seconds in the minutes column?",
            trimmed(step / 60.0, 3),
            trimmed(LONGEST_STEP / 60.0, 3)
        )),
        Some(step) if step < SHORTEST_STEP => found.push(format!(
            "column `time_min`: successive readings are {} s apart (median), less than the {} s dwell a laser reading takes: hours in the minutes column?",
            trimmed(step, 4),
            trimmed(SHORTEST_STEP, 3)
        )),
        _ => {}
    }
    for (index, sensor) in table.sensors.iter().enumerate() {
        let values: Vec<Real> = table
            .readings
            .iter()
            .map(|r| r.temperatures[index])
            .collect();
        let column = format!("temp_{sensor}_degc");
        if sensor.contains("air") || sensor.contains("ambient") {
            found.extend(air_caution(&column, &values));
        } else {
            found.extend(crate::io::plausible::structure_caution(&column, &values));
        }
    }
    found
}

/// The median over targets and directions of the readings' standard deviation over the runs
/// (targets read in at least two runs), if any.
fn median_scatter(table: &PositioningTable) -> Option<Real> {
    let mut groups: std::collections::BTreeMap<(bool, i64), Vec<Real>> = Default::default();
    for r in &table.readings {
        let key = (r.approach == Approach::Up, (r.target * 1e9).round() as i64);
        groups.entry(key).or_default().push(r.deviation);
    }
    let scatters: Vec<Real> = groups
        .values()
        .filter(|v| v.len() >= 2)
        .map(|v| {
            let n = v.len() as Real;
            let mean = v.iter().sum::<Real>() / n;
            (v.iter().map(|x| (x - mean).powi(2)).sum::<Real>() / (n - 1.0)).sqrt()
        })
        .collect();
    median(scatters)
}

fn um(value: Real) -> String {
    trimmed(value / M_PER_UM, 3)
}
