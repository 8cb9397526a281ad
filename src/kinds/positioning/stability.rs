//! Whether a positioning record is thermally stable enough for its ISO 230-2 figures to mean
//! what they say. ISO 230-2 §5.2 asks for the machine to be warmed up and the environment
//! stable; a record whose runs drift (a warm-up, an ISO 230-3 test) gives an accuracy A and
//! a repeatability R that measure the drift, not the axis.
//!
//! The data check it themselves: each run's deviation from the mean of all runs, at every
//! target and direction, is fitted with a straight line along the axis (an offset and a
//! scale: a drifting datum and a growing screw or scale). The line's spread over the runs,
//! at the worst end of the travel, is the runs' drift D; what the lines leave is the scatter
//! s of a stable axis. A drift larger than the band 4s a stable axis would show (ISO 230-2's
//! repeatability is 4s) and larger than [`DRIFT_FLOOR`] is reported as a caution.

use super::conditions::PositioningTest;
use super::table::PositioningTable;
use crate::math::{Real, trimmed};
use crate::program::Approach;

/// Drift below this (m) is not worth a caution: ten times the 0.01 µm a laser export prints.
pub const DRIFT_FLOOR: Real = 0.1e-6;

/// Targets closer than this (m) are the same target.
const SAME_TARGET: Real = 1e-9;

/// The runs' drift D and the scatter s they leave (m), when the table has at least two runs
/// and enough readings to tell them apart.
pub fn run_drift(table: &PositioningTable) -> Option<(Real, Real)> {
    let runs = table.runs.len();
    if runs < 2 {
        return None;
    }
    // Each reading's deviation from the mean of its target and direction over the runs
    // (readings sorted by target and direction, so the grouping is n log n).
    let mut order: Vec<usize> = (0..table.readings.len()).collect();
    let key = |k: usize| (table.readings[k].approach, table.readings[k].target);
    order.sort_by(|&i, &j| key(i).0.cmp(&key(j).0).then(key(i).1.total_cmp(&key(j).1)));
    let mut groups: Vec<(Real, usize)> = Vec::new(); // sum, n
    let mut group_of = vec![0; table.readings.len()];
    let mut previous: Option<(Approach, Real)> = None;
    for &k in &order {
        let (approach, target) = key(k);
        let same = previous.is_some_and(|(a, t)| a == approach && (target - t).abs() < SAME_TARGET);
        if !same {
            groups.push((0.0, 0));
            previous = Some((approach, target));
        }
        let last = groups.len() - 1;
        groups[last].0 += table.readings[k].deviation;
        groups[last].1 += 1;
        group_of[k] = last;
    }
    let residual = |k: usize| {
        let (sum, n) = groups[group_of[k]];
        table.readings[k].deviation - sum / n as Real
    };
    // Per run: the least-squares line r = a + b (x − x̄) through its residuals.
    let mut lines = Vec::with_capacity(runs);
    let mut parameters = 0usize;
    let mut by_run: Vec<Vec<usize>> = vec![Vec::new(); runs];
    for (k, r) in table.readings.iter().enumerate() {
        by_run[r.run].push(k);
    }
    for (run, members) in by_run.iter().enumerate() {
        if members.is_empty() {
            continue;
        }
        let n = members.len() as Real;
        let mean_x = members
            .iter()
            .map(|&k| table.readings[k].target)
            .sum::<Real>()
            / n;
        let a = members.iter().map(|&k| residual(k)).sum::<Real>() / n;
        let sxx: Real = members
            .iter()
            .map(|&k| (table.readings[k].target - mean_x).powi(2))
            .sum();
        let b = if members.len() >= 3 && sxx > 0.0 {
            parameters += 2;
            members
                .iter()
                .map(|&k| (table.readings[k].target - mean_x) * residual(k))
                .sum::<Real>()
                / sxx
        } else {
            parameters += 1;
            0.0
        };
        lines.push((run, a, b, mean_x));
    }
    let mut line_of = vec![(0.0, 0.0, 0.0); runs];
    for &(run, a, b, mean_x) in &lines {
        line_of[run] = (a, b, mean_x);
    }
    let line_at = |run: usize, x: Real| {
        let (a, b, mean_x) = line_of[run];
        a + b * (x - mean_x)
    };
    let left: Real = (0..table.readings.len())
        .map(|k| {
            let r = &table.readings[k];
            (residual(k) - line_at(r.run, r.target)).powi(2)
        })
        .sum();
    // Degrees of freedom: the readings less the group means and the runs' lines.
    let dof = table.readings.len() as isize - groups.len() as isize - parameters as isize;
    if dof < 1 {
        return None;
    }
    let scatter = (left / dof as Real).sqrt();
    let (low, high) = table
        .readings
        .iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), r| {
            (l.min(r.target), h.max(r.target))
        });
    let spread = |x: Real| {
        let values = lines.iter().map(|l| line_at(l.0, x));
        values.clone().fold(Real::NEG_INFINITY, Real::max) - values.fold(Real::INFINITY, Real::min)
    };
    Some((spread(low).max(spread(high)), scatter))
}

/// The caution an ISO 230-2 report of `table` carries, if any: when its preamble names a
/// test that is not thermally stable by design (`warmup`, `iso230_3_linear`), or when its
/// runs drift by more than 4s and [`DRIFT_FLOOR`] ([`run_drift`]).
pub fn caution(table: &PositioningTable) -> Option<String> {
    let stated = table
        .conditions
        .test
        .filter(|t| matches!(t, PositioningTest::Warmup | PositioningTest::Iso230_3Linear));
    let drift = run_drift(table).filter(|&(d, s)| d > 4.0 * s && d > DRIFT_FLOOR);
    let um = |v: Real| trimmed(v * 1e6, 3);
    let why = match (stated, drift) {
        (None, None) => return None,
        (Some(test), None) => format!("the file says test = {}", test.name()),
        (None, Some((d, s))) => format!(
            "its runs drift by {} µm, more than the 4s = {} µm a stable axis shows",
            um(d),
            um(4.0 * s)
        ),
        (Some(test), Some((d, s))) => format!(
            "the file says test = {}, and its runs drift by {} µm, more than the 4s = {} µm a stable axis shows",
            test.name(),
            um(d),
            um(4.0 * s)
        ),
    };
    Some(format!(
        "the record is not thermally stable ({why}): A and R include the drift and do not describe the axis (ISO 230-2 §5.2 asks for a warmed-up machine)"
    ))
}
