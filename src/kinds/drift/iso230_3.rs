//! ISO 230-3:2007 evaluations of drift records: the drift ranges over the first 60 min and over
//! the whole moving (or running) period (§3.14–3.17), the criterion that allows a test to stop
//! early (§6.2, §7.2.3), and the ETVE value for a performance test of a given duration (§5.3).
//!
//! A drift record is a time series `(t, d)` (s; m or rad), zeroed at its start. "Range" is
//! max − min; it is reported with the sign of the larger excursion from the start value, as the
//! standard's examples do (e.g. Z = −0,061).

use super::table::{DriftChannel, DriftTable};
use crate::math::Real;

/// One hour (s).
const HOUR: Real = 3600.0;

/// The signed range of `d` over the samples with `t` in `[from, to]`: max − min, negative when
/// the larger excursion from the first value of the record is downwards. `None` without
/// samples there.
pub fn signed_range(record: &[(Real, Real)], from: Real, to: Real) -> Option<Real> {
    let start = record.first()?.1;
    let inside = record
        .iter()
        .filter(|(t, _)| *t >= from && *t <= to)
        .map(|(_, d)| *d);
    let (low, high) = inside.fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), d| {
        (lo.min(d), hi.max(d))
    });
    let sign = if high - start >= start - low {
        1.0
    } else {
        -1.0
    };
    (low <= high).then_some(sign * (high - low))
}

/// The drift ranges of a record: over its first 60 min, and over its whole span.
pub fn drift_ranges(record: &[(Real, Real)]) -> Option<(Real, Real)> {
    let start = record.first()?.0;
    let end = record.last()?.0;
    Some((
        signed_range(record, start, start + HOUR)?,
        signed_range(record, start, end)?,
    ))
}

/// The first time at which the test could have stopped: the change during the last 60 min
/// (the range of d over [t − 60 min, t]) is less than 15 % of the largest drift in the first
/// hour, `max |d − d(start)|`. `None` if never (or the record is shorter than two hours). The
/// value at t − 60 min is interpolated linearly. The whole record is scanned, cool-down included.
pub fn stop_time(record: &[(Real, Real)]) -> Option<Real> {
    let (start, zero) = *record.first()?;
    let first_hour = record
        .iter()
        .filter(|(t, _)| *t <= start + HOUR)
        .map(|(_, d)| (d - zero).abs())
        .fold(0.0, Real::max);
    record
        .iter()
        .filter(|(t, _)| *t >= start + 2.0 * HOUR)
        .find(|(t, _)| {
            // The change within the last hour: the range of the samples in it and of the value
            // interpolated at its start (for a monotonic drift, |d(t) − d(t − 60 min)|).
            let Some(before) = interpolate(record, t - HOUR) else {
                return false;
            };
            let inside = record
                .iter()
                .filter(|(u, _)| *u > t - HOUR && *u <= *t)
                .map(|(_, d)| *d);
            let (lo, hi) = inside.fold((before, before), |(lo, hi), d| (lo.min(d), hi.max(d)));
            hi - lo < 0.15 * first_hour
        })
        .map(|(t, _)| *t)
}

/// The ETVE for a performance test lasting `duration` s: the largest range of `d` within any
/// window of that length inside the record — windows starting at a sample and windows ending at
/// one, so the record's last sample is covered — and that window's start. Sliding monotonic
/// queues keep it O(n log n).
pub fn etve(record: &[(Real, Real)], duration: Real) -> Option<(Real, Real)> {
    let (first, end) = (record.first()?.0, record.last()?.0);
    let eps = 1e-9 * (1.0 + end.abs());
    let mut starts: Vec<Real> = record
        .iter()
        .map(|(t, _)| *t)
        .filter(|t| t + duration <= end + eps)
        .chain(
            record
                .iter()
                .map(|(t, _)| t - duration)
                .filter(|s| *s >= first - eps),
        )
        .collect();
    starts.sort_by(Real::total_cmp);
    starts.dedup_by(|a, b| (*a - *b).abs() <= eps);
    let (mut entered, mut left) = (0, 0);
    let mut highs: std::collections::VecDeque<usize> = std::collections::VecDeque::new();
    let mut lows: std::collections::VecDeque<usize> = std::collections::VecDeque::new();
    let mut best: Option<(Real, Real)> = None;
    for s in starts {
        while entered < record.len() && record[entered].0 <= s + duration + eps {
            let d = record[entered].1;
            while highs.back().is_some_and(|&k| record[k].1 <= d) {
                highs.pop_back();
            }
            while lows.back().is_some_and(|&k| record[k].1 >= d) {
                lows.pop_back();
            }
            highs.push_back(entered);
            lows.push_back(entered);
            entered += 1;
        }
        while left < record.len() && record[left].0 < s - eps {
            left += 1;
        }
        while highs.front().is_some_and(|&k| k < left) {
            highs.pop_front();
        }
        while lows.front().is_some_and(|&k| k < left) {
            lows.pop_front();
        }
        if let (Some(&hi), Some(&lo)) = (highs.front(), lows.front()) {
            let range = record[hi].1 - record[lo].1;
            if best.is_none_or(|(r, _)| range > r) {
                best = Some((range, s));
            }
        }
    }
    best
}

/// `d` at time `t`, linearly interpolated between samples.
fn interpolate(record: &[(Real, Real)], t: Real) -> Option<Real> {
    let after = record.iter().position(|(time, _)| *time >= t)?;
    if after == 0 {
        return (record[0].0 == t).then_some(record[0].1);
    }
    let ((t0, d0), (t1, d1)) = (record[after - 1], record[after]);
    Some(d0 + (d1 - d0) * (t - t0) / (t1 - t0))
}

/// The tilts of the mandrel from two pairs of parallel sensors `spacing` m apart (ISO 230-3
/// §5.3, used again by §6.3): `a` about X from `y1`, `y2` and `b` about Y from `x1`, `x2`, the
/// pair `1` being the one further from the spindle nose (at L1, nearer the mandrel's end), each
/// pair only when the table has both of its channels (linear). Rotations are right-handed
/// (ISO 841) with Z the spindle axis pointing from the workpiece to the tool:
///
/// `A = (Y1 − Y2) / l`, `B = (X2 − X1) / l`.
///
/// The standard's text gives `B = (X1 − X2) / l`; with X1 the sensor further from the nose that
/// is the rotation about −Y, so B here has the other sign, the same convention as A (a test
/// checks both against a known rotation).
pub fn tilts(table: &DriftTable, spacing: Real) -> Vec<DriftChannel> {
    let linear = |name: &str| {
        table
            .channels
            .iter()
            .find(|c| c.name == name && !c.angular)
            .map(|c| &c.values)
    };
    let mut out = Vec::new();
    if let (Some(y1), Some(y2)) = (linear("y1"), linear("y2")) {
        out.push(DriftChannel {
            name: "a".into(),
            angular: true,
            values: y1.iter().zip(y2).map(|(p, q)| (p - q) / spacing).collect(),
        });
    }
    if let (Some(x1), Some(x2)) = (linear("x1"), linear("x2")) {
        out.push(DriftChannel {
            name: "b".into(),
            angular: true,
            values: x1.iter().zip(x2).map(|(p, q)| (q - p) / spacing).collect(),
        });
    }
    out
}

/// The ISO 230-3 report of a drift table: per channel (and per tilt from sensor pairs
/// `spacing` m apart, when given: [`tilts`]) the range over the first 60 min and the whole
/// record, over the running period t when the preamble gives its end (`run_min`: ISO 230-3
/// Table 1's d(·)_t, the spindle test's figure), when the 15 % stop criterion was met, and the
/// ETVE for a test of `etve_duration` s with its window and the ambient range inside it
/// ([`DriftTable::ambient`]). JSON keys: `kind` ("drift"), `test`, `etve_duration_min`,
/// `ambient_sensor`, `spacing_mm`, `conditions` (what the preamble said: `control`,
/// `hold_mm`, `first_mm`, `programme`, `speed_rpm`, `spectrum`, `run_min`, `stop_min`, each
/// null when not said), `preamble_not_used` (keys the reader does not know),
/// `columns_not_read` (columns it read past), `cautions`,
/// `channels` (each `name`, `unit` ("um" or "urad"), `derived` (a tilt), `range_60_<unit>`,
/// `range_run_<unit>` (null without `run_min`), `range_<unit>`, `stop_min`, `etve_<unit>`,
/// `etve_window_min` [start, end], `etve_ambient_range_degc`, `note`).
pub fn drift_report(
    table: &DriftTable,
    etve_duration: Real,
    spacing: Option<Real>,
) -> serde_json::Value {
    use serde_json::json;
    let ambient = table.ambient();
    let derived = spacing.map_or_else(Vec::new, |l| tilts(table, l));
    let c = &table.conditions;
    let start = table.times.first().copied().unwrap_or(0.0);
    let end = table.times.last().copied().unwrap_or(0.0);
    let run_end = c.run_period.map(|run| start + run);
    let mut cautions = Vec::new();
    if let (Some(run), Some(stop)) = (c.run_period, c.stop) {
        // The record should reach the end of the stop; allow the longest interval between
        // readings, the most an export can lose by sampling.
        let step = table
            .times
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(0.0, Real::max);
        let missing = start + run + stop - end;
        if missing > step + 1e-6 {
            cautions.push(format!(
                "the record ends {} min before the stated stop (run_min + stop_min = {} min): the cool-down is incomplete",
                crate::math::trimmed(missing / 60.0, 3),
                crate::math::trimmed((run + stop) / 60.0, 6)
            ));
        }
    }
    cautions.extend(super::plausible::cautions(table, etve_duration, spacing));
    let channels: Vec<serde_json::Value> = table
        .channels
        .iter()
        .chain(&derived)
        .map(|channel| {
            let record: Vec<(Real, Real)> = table.times.iter().copied().zip(channel.values.iter().copied()).collect();
            let scale = 1e6; // m → µm, rad → µrad
            let round = |v: Real| (v * scale * 1e6).round() / 1e6;
            let ranges = drift_ranges(&record);
            let worst = etve(&record, etve_duration);
            let ambient_range = worst.and_then(|(_, start)| {
                let (_, values) = ambient?;
                let inside = table.times.iter().zip(values).filter(|(t, _)| **t >= start && **t <= start + etve_duration + 1e-9);
                let (lo, hi) = inside.fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), (_, v)| (lo.min(*v), hi.max(*v)));
                Some(((hi - lo) * 1e6).round() / 1e6)
            });
            let unit = if channel.angular { "urad" } else { "um" };
            let mut entry = json!({
                "name": channel.name,
                "unit": unit,
                "derived": derived.iter().any(|d| std::ptr::eq(d, channel)),
                "stop_min": stop_time(&record).map(|t| t / 60.0),
                "etve_window_min": worst.map(|(_, start)| [start / 60.0, (start + etve_duration) / 60.0]),
                "etve_ambient_range_degc": ambient_range,
                "note": worst.is_none().then_some("the record is shorter than the ETVE test"),
            });
            entry[format!("range_60_{unit}")] = json!(ranges.map(|r| round(r.0)));
            entry[format!("range_run_{unit}")] = json!(run_end.and_then(|end| signed_range(&record, start, end)).map(round));
            entry[format!("range_{unit}")] = json!(ranges.map(|r| round(r.1)));
            entry[format!("etve_{unit}")] = json!(worst.map(|w| round(w.0)));
            entry
        })
        .collect();
    json!({
        "kind": "drift",
        "standard": "ISO 230-3:2007",
        "test": table.conditions.test,
        "spacing_mm": spacing.map(|l| l * 1e3),
        "etve_duration_min": etve_duration / 60.0,
        "ambient_sensor": ambient.map(|(name, _)| name.clone()),
        "conditions": {
            "control": c.control.map(|m| m.name()),
            "hold_mm": c.hold,
            "first_mm": c.first.map(|m| m * 1e3),
            "programme": c.programme,
            "speed_rpm": c.speed_rpm,
            "spectrum": c.spectrum,
            "run_min": c.run_period.map(|s| s / 60.0),
            "stop_min": c.stop.map(|s| s / 60.0),
        },
        "preamble_not_used": c.other.iter().map(|(k, _)| k.clone()).collect::<Vec<_>>(),
        "columns_not_read": table.columns_not_read,
        "cautions": cautions,
        "channels": channels,
    })
}
