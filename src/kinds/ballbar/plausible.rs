//! What a ball-bar table's own data say against its conditions and units, as cautions for
//! the ISO 230-4 report (and, for a copied sweep or a single sense, as problems `identify`
//! refuses to compensate from).
//!
//! - **Conditions nothing checked**: without `time_s` the angles cannot confirm feed ÷
//!   radius, whether the radius and feed came from the preamble or the flags. A wrong radius
//!   scales every figure in µm/m, a wrong plane names the wrong axes; neither shows in the
//!   deviations.
//! - **One sense only**: ISO 230-4 runs both. In one sense a servo mismatch Δτ adds
//!   `σ·(v·Δτ/2)·sin 2θ` to the trace, the shape of a squareness `(R·s/2)·sin 2θ`: the
//!   squareness read is `s + σ·v·Δτ/R` ([`apparent_squareness_per_ms`]).
//! - **A copied sweep**: a stretch of one sense holding the same readings as another
//!   ([`crate::io::plausible::copied_block`]).
//! - **Units**: a trace spanning less than [`SMALLEST_SPREAD`] (mm in the µm column).

use super::iso230_4::CircularTest;
use super::table::{BallbarTable, Sense};
use crate::io::plausible::{Block, copied_block, copy_sentence, spread};
use crate::math::{M_PER_UM, Real, trimmed};

/// The smallest spread of a ball-bar trace over a circle (m): 0.1 µm, a ball-bar's
/// resolution (Renishaw QC20-W). No machine interpolates a circle rounder than its own
/// reversal and servo effects, which a ball-bar sees as a micrometre or more; deviations in
/// mm written in the µm column span 1000 times less.
pub const SMALLEST_SPREAD: Real = 0.1e-6;

/// How many times more or less than the other sweeps one may span before it reads as another
/// unit: 5. The two senses of one circle differ by their servo and reversal terms, which a
/// machine keeps within a factor of two or so.
pub const ODD_SENSE: Real = 5.0;

/// The smallest single-reading spike (m) of a ball-bar trace that is named: 5 µm, above the
/// reversal spikes a sweep shows between two readings (they rise and decay over several) and
/// a hundred times the bar's noise.
pub const SMALLEST_SPIKE: Real = 5e-6;

/// Every caution for the ISO 230-4 report of `table` measured under `test`, each a sentence.
pub fn cautions(table: &BallbarTable, test: &CircularTest) -> Vec<String> {
    let mut found: Vec<String> = unchecked_conditions(table).into_iter().collect();
    found.extend(one_sense(table, test));
    let blocks = sweep_blocks(table);
    found.extend(
        copied_block(&blocks)
            .map(|pair| format!("column `deviation_um`: {}", copy_sentence(&blocks, pair))),
    );
    found.extend(
        crate::io::plausible::odd_block(&blocks, ODD_SENSE)
            .map(|odd| crate::io::plausible::odd_sentence("deviation_um", &blocks, odd)),
    );
    for block in &blocks {
        if let Some((k, size, scale)) = crate::io::plausible::spike(&block.readings, SMALLEST_SPIKE)
        {
            found.push(format!(
                "column `deviation_um`: {} reading {} stands {} µm from both its neighbours, more than {} times the trace's typical {} µm: a glitch or a typo (a reversal spike rises and decays over several readings)? It sets the circular deviation",
                block.label,
                k + 1,
                trimmed(size / M_PER_UM, 4),
                crate::io::plausible::LONE_READING,
                trimmed(scale / M_PER_UM, 3)
            ));
        }
    }
    let values: Vec<Real> = table.readings.iter().map(|r| r.deviation).collect();
    if let Some(step) = crate::io::plausible::rounded_to(&values) {
        found.push(crate::io::plausible::rounding_sentence(
            "deviation_um",
            step,
            "a ball-bar reads to 0.1 µm",
        ));
    }
    let trace = spread(table.readings.iter().map(|r| r.deviation));
    if trace < SMALLEST_SPREAD {
        found.push(format!(
            "column `deviation_um`: the trace spans only {} µm, less than the {} µm a ball-bar resolves: mm in the µm column?",
            trimmed(trace / M_PER_UM, 4),
            trimmed(SMALLEST_SPREAD / M_PER_UM, 4)
        ));
    }
    found
}

/// The caution for a table whose conditions nothing in it could check (no `time_s`).
pub fn unchecked_conditions(table: &BallbarTable) -> Option<String> {
    let c = &table.conditions;
    let stated = c.plane.is_some() || c.radius.is_some() || c.feed.is_some();
    table.angular_speed().is_none().then(|| {
        format!(
            "the plane, radius and feed came from {}: the file has no time_s, so nothing in it could check them (a wrong radius scales every figure in µm/m, a wrong plane names the wrong axes)",
            if stated {
                "the preamble (or the flags)"
            } else {
                "the flags, the file having no preamble"
            }
        )
    })
}

/// The squareness (dimensionless, m/m) one millisecond of servo mismatch reads as in one
/// sense of `test`: `v·Δτ/R` with Δτ = 1 ms.
pub fn apparent_squareness_per_ms(test: &CircularTest) -> Real {
    test.feed * 1e-3 / test.radius
}

/// The caution for a table with one sense only.
pub fn one_sense(table: &BallbarTable, test: &CircularTest) -> Option<String> {
    let has = |sense: Sense| table.readings.iter().any(|r| r.sense == sense);
    let only = match (has(Sense::Ccw), has(Sense::Cw)) {
        (true, false) => Sense::Ccw,
        (false, true) => Sense::Cw,
        _ => return None,
    };
    Some(format!(
        "only the {} sense was measured (ISO 230-4 runs both): a servo mismatch has the shape of a squareness in one sense, so the squareness reported includes it (1 ms of mismatch reads as {} µm/m at this feed and radius), and radius and scale mismatch include the other sense-dependent terms; measure the other sense to separate them",
        only.name(),
        trimmed(apparent_squareness_per_ms(test) * 1e6, 1)
    ))
}

/// The readings of each stretch of rows in one sense, as blocks.
pub fn sweep_blocks(table: &BallbarTable) -> Vec<Block> {
    let mut blocks: Vec<Block> = Vec::new();
    let mut current: Option<Sense> = None;
    for r in &table.readings {
        if current != Some(r.sense) {
            current = Some(r.sense);
            blocks.push(Block {
                label: format!("sweep {} ({})", blocks.len() + 1, r.sense.name()),
                readings: Vec::new(),
            });
        }
        if let Some(block) = blocks.last_mut() {
            block.readings.push(r.deviation);
        }
    }
    blocks
}

/// A sweep that repeats another reading for reading.
pub fn copied_sweep(table: &BallbarTable) -> Option<String> {
    let blocks = sweep_blocks(table);
    copied_block(&blocks)
        .map(|pair| format!("column `deviation_um`: {}", copy_sentence(&blocks, pair)))
}

/// The angular speed (rad/s) `table`'s angles and times turn at, when it disagrees with
/// `feed / radius` by more than 1 % plus three standard errors of that slope: the one test
/// `analyze` (conditions from the preamble or the flags) and `identify` (from the preamble)
/// both refuse. `None` without times, or when they agree.
pub fn speed_disagreement(table: &BallbarTable, radius: Real, feed: Real) -> Option<Real> {
    let (speed, se) = table.angular_speed()?;
    let stated = feed / radius;
    ((speed - stated).abs() > 0.01 * stated + 3.0 * se).then_some(speed)
}

/// The preamble's feed ÷ radius against what the angles and times turn at
/// ([`speed_disagreement`]): a radius or a feed mistyped in the preamble, which scales every
/// figure in µm/m. `None` without the three.
pub fn stated_speed_contradiction(table: &BallbarTable) -> Option<String> {
    let (radius, feed) = (table.conditions.radius?, table.conditions.feed?);
    let speed = speed_disagreement(table, radius, feed)?;
    let stated = feed / radius;
    Some({
        format!(
            "angle_deg against time_s turn at {} rad/s, which at the preamble's radius {} mm gives a feed of {} mm/min (or, at its feed {} mm/min, a radius of {} mm); the preamble says {} rad/s: its radius or feed is mistyped",
            trimmed(speed, 4),
            trimmed(radius * 1e3, 3),
            trimmed(speed * radius * 6e4, 1),
            trimmed(feed * 6e4, 1),
            trimmed(feed / speed * 1e3, 3),
            trimmed(stated, 4)
        )
    })
}

/// How many times the trace's own noise a model's residual RMS must exceed, and by at least
/// [`SMALLEST_UNEXPLAINED`], before the trace is said to hold what no term explains: 10.
pub const UNEXPLAINED_FACTOR: Real = 10.0;

/// The smallest unexplained residual RMS (m) named: 1 µm, ten times a ball-bar's resolution
/// and above the servo ripple real traces keep after the diagnostic terms.
pub const SMALLEST_UNEXPLAINED: Real = 1e-6;

/// The trace's noise (m): the robust scale of each sense's second differences in angle order
/// (the median absolute one / 0.6745, over √6, white noise's second difference having
/// variance 6σ²); steps at reversals and a smooth trace barely move the median.
pub fn trace_noise(table: &BallbarTable) -> Option<Real> {
    let mut second = Vec::new();
    for sense in [Sense::Ccw, Sense::Cw] {
        let mut trace: Vec<(Real, Real)> = table
            .readings
            .iter()
            .filter(|r| r.sense == sense)
            .map(|r| (r.angle, r.deviation))
            .collect();
        trace.sort_by(|a, b| a.0.total_cmp(&b.0));
        second.extend(
            trace
                .windows(3)
                .map(|w| (w[2].1 - 2.0 * w[1].1 + w[0].1).abs()),
        );
    }
    crate::io::plausible::median(second).map(|m| m / 0.6745 / 6f64.sqrt())
}

/// A model (`what`) whose residual RMS `rms` (m) stands [`UNEXPLAINED_FACTOR`] times above the
/// trace's noise and above [`SMALLEST_UNEXPLAINED`]: the trace holds something no term of it
/// explains — a feed override (angles assigned at a feed the machine did not run), a crash,
/// a disturbed test — and the values fitted around it are not to be trusted.
pub fn unexplained(table: &BallbarTable, rms: Real, what: &str) -> Option<String> {
    let noise = trace_noise(table)?;
    (rms > SMALLEST_UNEXPLAINED && rms > UNEXPLAINED_FACTOR * noise).then(|| {
        format!(
            "{what} leaves {} µm RMS, {} times the trace's noise ({} µm, from successive readings): the trace holds something no term explains (a feed override, so that the angles were assigned at a feed the machine did not run; a crash or a disturbed test), and the values fitted around it are not to be trusted",
            trimmed(rms / M_PER_UM, 3),
            trimmed(rms / noise.max(Real::MIN_POSITIVE), 2),
            trimmed(noise / M_PER_UM, 3)
        )
    })
}
