//! A positioning table as a thermal series (ISO 230-3 §7 style): runs taken at different
//! times or temperatures, each with its error curve, and the drift of every target against
//! time and temperature.
//!
//! A table is a thermal series when it has at least two runs and either run times spread over
//! at least [`MIN_SERIES_SPAN_MIN`] minutes or a sensor whose run temperatures spread over at
//! least [`MIN_SERIES_SPREAD_DEGC`] (a plain ISO 230-2 test of a few minutes, temperatures
//! recorded as the standard asks, is not one). A run's time and temperatures are the means over its readings. The drift of
//! a target (in one direction) is its mean deviation in each run minus that in the first run
//! that reached it; its sensitivity to a sensor is the least-squares slope of the deviation
//! against that sensor's run temperature.

use crate::kinds::positioning::table::PositioningTable;
use crate::math::Real;
use crate::program::Approach;

/// One run of a thermal series.
#[derive(Clone, Debug, PartialEq)]
pub struct RunCurve {
    /// The run label.
    pub label: String,
    /// Mean time of its readings (s), if recorded.
    pub time: Option<Real>,
    /// Mean temperature of each sensor over its readings (°C).
    pub temperatures: Vec<Real>,
    /// Mean deviation (m) per (target, direction), in increasing target, + before −.
    pub points: Vec<(Real, Approach, Real)>,
}

/// The drift of one target in one direction over the runs.
#[derive(Clone, Debug, PartialEq)]
pub struct TargetDrift {
    /// Target position (m).
    pub target: Real,
    /// Direction of approach.
    pub approach: Approach,
    /// Per run that reached it: (run index, deviation − deviation in its first run) (m).
    pub drift: Vec<(usize, Real)>,
    /// max − min of the drift (m), negative when the larger excursion from the first run is
    /// downwards.
    pub range: Real,
    /// ISO 230-3 drift range over the first 60 min, signed (m), when runs are timed.
    pub range_first_hour: Option<Real>,
    /// When the ISO 230-3 stop criterion was first met (s), when runs are timed.
    pub stop_time: Option<Real>,
    /// Least-squares slope of the deviation against each sensor's run temperature (m/°C);
    /// `None` when that sensor's run temperatures span less than [`MIN_SERIES_SPREAD_DEGC`].
    pub slopes: Vec<Option<Real>>,
}

/// The thermal-series view of a positioning table.
#[derive(Clone, Debug, PartialEq)]
pub struct ThermalSeries {
    /// Sensor names, as in the table.
    pub sensors: Vec<String>,
    /// Each run's curve, in run order.
    pub runs: Vec<RunCurve>,
    /// Each target's drift.
    pub drift: Vec<TargetDrift>,
}

/// Targets closer than this (m) are the same target.
const SAME_TARGET: Real = 1e-9;

/// How many runs the report for people shows without `--verbose`.
pub const COMPACT_RUNS: usize = 8;

/// The spread of run times (min) that makes a timed table a thermal series.
pub const MIN_SERIES_SPAN_MIN: Real = 30.0;

/// The spread of a sensor's run temperatures (°C) that makes a table a thermal series, and below
/// which no slope against that sensor is reported (it would fit noise and quantisation).
pub const MIN_SERIES_SPREAD_DEGC: Real = 0.5;

/// The thermal series of `table`, if it is one.
pub fn thermal_series(table: &PositioningTable) -> Option<ThermalSeries> {
    let times = table.readings.iter().filter_map(|r| r.time);
    let span =
        times.clone().fold(Real::NEG_INFINITY, Real::max) - times.fold(Real::INFINITY, Real::min);
    if table.runs.len() < 2 {
        return None;
    }
    // The spread of each sensor's run-mean temperature.
    let spreads: Vec<Real> = (0..table.sensors.len())
        .map(|k| {
            let means = (0..table.runs.len()).filter_map(|run| {
                let values: Vec<Real> = table
                    .readings
                    .iter()
                    .filter(|r| r.run == run)
                    .map(|r| r.temperatures[k])
                    .collect();
                (!values.is_empty()).then(|| values.iter().sum::<Real>() / values.len() as Real)
            });
            means.clone().fold(Real::NEG_INFINITY, Real::max)
                - means.fold(Real::INFINITY, Real::min)
        })
        .collect();
    let thermal =
        span >= MIN_SERIES_SPAN_MIN * 60.0 || spreads.iter().any(|s| *s >= MIN_SERIES_SPREAD_DEGC);
    if !thermal {
        return None;
    }
    let mut keys: Vec<(Real, Approach)> = table
        .readings
        .iter()
        .map(|r| (r.target, r.approach))
        .collect();
    keys.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    keys.dedup_by(|a, b| (a.0 - b.0).abs() < SAME_TARGET && a.1 == b.1);

    let mean = |values: &mut dyn Iterator<Item = Real>| {
        let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
        (n > 0).then(|| sum / n as Real)
    };
    let runs: Vec<RunCurve> = table
        .runs
        .iter()
        .enumerate()
        .map(|(run, label)| {
            let readings = || table.readings.iter().filter(move |r| r.run == run);
            let points = keys
                .iter()
                .filter_map(|&(target, approach)| {
                    let mut values = readings()
                        .filter(|r| {
                            r.approach == approach && (r.target - target).abs() < SAME_TARGET
                        })
                        .map(|r| r.deviation);
                    mean(&mut values).map(|m| (target, approach, m))
                })
                .collect();
            RunCurve {
                label: label.clone(),
                time: mean(&mut readings().filter_map(|r| r.time)),
                temperatures: (0..table.sensors.len())
                    .map(|k| mean(&mut readings().map(|r| r.temperatures[k])).unwrap_or(Real::NAN))
                    .collect(),
                points,
            }
        })
        .collect();

    let drift = keys
        .iter()
        .map(|&(target, approach)| {
            let visits: Vec<(usize, Real)> = runs
                .iter()
                .enumerate()
                .filter_map(|(run, curve)| {
                    curve
                        .points
                        .iter()
                        .find(|p| (p.0 - target).abs() < SAME_TARGET && p.1 == approach)
                        .map(|p| (run, p.2))
                })
                .collect();
            let first = visits.first().map_or(0.0, |v| v.1);
            let drift: Vec<(usize, Real)> =
                visits.iter().map(|&(run, d)| (run, d - first)).collect();
            // Signed like ISO 230-3's ranges: by the larger excursion from the first run.
            let by_run: Vec<(Real, Real)> =
                drift.iter().map(|&(run, d)| (run as Real, d)).collect();
            let range = crate::kinds::drift::iso230_3::signed_range(
                &by_run,
                Real::NEG_INFINITY,
                Real::INFINITY,
            )
            .unwrap_or(0.0);
            let slopes = (0..table.sensors.len())
                .map(|k| {
                    (spreads[k] >= MIN_SERIES_SPREAD_DEGC)
                        .then(|| {
                            slope(
                                visits
                                    .iter()
                                    .map(|&(run, d)| (runs[run].temperatures[k], d)),
                            )
                        })
                        .flatten()
                })
                .collect();
            let timed: Vec<(Real, Real)> = drift
                .iter()
                .filter_map(|&(run, d)| runs[run].time.map(|t| (t, d)))
                .collect();
            let complete = timed.len() == drift.len();
            let range_first_hour = if complete {
                crate::kinds::drift::iso230_3::drift_ranges(&timed).map(|r| r.0)
            } else {
                None
            };
            let stop_time = if complete {
                crate::kinds::drift::iso230_3::stop_time(&timed)
            } else {
                None
            };
            TargetDrift {
                target,
                approach,
                drift,
                range,
                range_first_hour,
                stop_time,
                slopes,
            }
        })
        .collect();
    Some(ThermalSeries {
        sensors: table.sensors.clone(),
        runs,
        drift,
    })
}

/// Least-squares slope of y on x; `None` when x does not vary (or fewer than two points).
fn slope(points: impl Iterator<Item = (Real, Real)> + Clone) -> Option<Real> {
    let n = points.clone().count() as Real;
    if n < 2.0 {
        return None;
    }
    let (mx, my) = points
        .clone()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let sxx: Real = points.clone().map(|(x, _)| (x - mx).powi(2)).sum();
    let sxy: Real = points.map(|(x, y)| (x - mx) * (y - my)).sum();
    (sxx > 1e-12).then(|| sxy / sxx)
}

impl ThermalSeries {
    /// JSON: `runs` (per run: `run, time_min, temperatures_degc {sensor: °C}, points [{target_mm,
    /// direction, deviation_um}]`) and `drift` (per target and direction: `target_mm, direction,
    /// range_um, range_60_um` (ISO 230-3 range over the first 60 min, signed), `stop_min` (when
    /// the ISO 230-3 15 % stop criterion was first met), `values [{run, drift_um}],
    /// slope_um_per_degc {sensor: µm/°C or null}`).
    pub fn to_json(&self) -> (serde_json::Value, serde_json::Value) {
        use serde_json::{Map, json};
        let um = |v: Real| (v * 1e12).round() / 1e6;
        let mm = |v: Real| (v * 1e9).round() / 1e6;
        let sign = |a: Approach| if a == Approach::Up { "+" } else { "-" };
        let runs = self
            .runs
            .iter()
            .map(|run| {
                let temperatures: Map<String, serde_json::Value> = self
                    .sensors
                    .iter()
                    .zip(&run.temperatures)
                    .map(|(s, t)| (s.clone(), json!((t * 1e6).round() / 1e6)))
                    .collect();
                json!({
                    "run": run.label,
                    "time_min": run.time.map(|t| (t / 60.0 * 1e6).round() / 1e6),
                    "temperatures_degc": temperatures,
                    "points": run.points.iter().map(|&(t, a, d)| json!({
                        "target_mm": mm(t), "direction": sign(a), "deviation_um": um(d)
                    })).collect::<Vec<_>>(),
                })
            })
            .collect::<Vec<_>>();
        let drift = self
            .drift
            .iter()
            .map(|d| {
                let slopes: Map<String, serde_json::Value> = self
                    .sensors
                    .iter()
                    .zip(&d.slopes)
                    .map(|(s, v)| (s.clone(), json!(v.map(um))))
                    .collect();
                json!({
                    "target_mm": mm(d.target),
                    "direction": sign(d.approach),
                    "range_um": um(d.range),
                    "range_60_um": d.range_first_hour.map(um),
                    "stop_min": d.stop_time.map(|t| t / 60.0),
                    "values": d.drift.iter().map(|&(run, v)| json!({
                        "run": self.runs[run].label, "drift_um": um(v)
                    })).collect::<Vec<_>>(),
                    "slope_um_per_degc": slopes,
                })
            })
            .collect::<Vec<_>>();
        (json!(runs), json!(drift))
    }

    /// The JSON report of a positioning table that is a thermal series but not an ISO 230-2
    /// test (e.g. the ISO 230-3 linear-motion test, each target approached from one side): the
    /// ISO 230-2 keys are null and `note` says why.
    pub fn report_json(
        &self,
        table: &PositioningTable,
        why_not_iso230_2: &str,
    ) -> serde_json::Value {
        let (runs, drift) = self.to_json();
        let mut report = serde_json::json!({
            "kind": "positioning",
            "standard": "ISO 230-3:2007 (drift)",
            "axis": table.axis.map(|a| a.to_string()),
            "n_runs": table.runs.len(),
            "bidirectional": false,
            "note": format!("no ISO 230-2 figures: {why_not_iso230_2}; drift only"),
            "targets": [],
            "runs": runs,
            "drift": drift,
            "conditions": table.conditions.report().0,
            "preamble_not_used": table.conditions.not_used,
            "columns_not_read": table.columns_not_read,
            "cautions": [],
        });
        for key in [
            "E_um",
            "E_up_um",
            "E_down_um",
            "M_um",
            "A_um",
            "A_up_um",
            "A_down_um",
            "R_um",
            "R_up_um",
            "R_down_um",
            "B_um",
            "B_mean_um",
        ] {
            report[key] = serde_json::Value::Null;
        }
        report
    }

    /// The report for people, its runs compact ([`Self::to_text_with`]).
    pub fn to_text(&self) -> String {
        self.to_text_with(false)
    }

    /// The report for people: each target's drift figures first (drift range, the ISO 230-3
    /// first-hour range and stop criterion, the slope against each sensor), then the runs'
    /// times and temperatures: every run when `verbose`, else at most [`COMPACT_RUNS`] of them
    /// spread over the series (the first and the last included).
    pub fn to_text_with(&self, verbose: bool) -> String {
        use std::fmt::Write;
        let mut out =
            String::from("\nThermal series (drift relative to each target's first run):\n");
        for d in &self.drift {
            let sign = if d.approach == Approach::Up { '+' } else { '-' };
            let first_hour = d.range_first_hour.map_or_else(String::new, |r| {
                format!("  first 60 min {:>8.3} µm", r * 1e6)
            });
            let stop = d.stop_time.map_or_else(String::new, |t| {
                format!("  15 % criterion met at {:.0} min", t / 60.0)
            });
            let slopes: String = self
                .sensors
                .iter()
                .zip(&d.slopes)
                .filter_map(|(name, slope)| {
                    slope.map(|k| format!("  {:>7.3} µm/°C against {name}", k * 1e6))
                })
                .collect();
            let _ = writeln!(
                out,
                "  target {:>10.4} mm {sign}  drift range {:>8.3} µm{first_hour}{stop}{slopes}",
                d.target * 1e3,
                d.range * 1e6
            );
        }
        let shown: Vec<usize> = if verbose || self.runs.len() <= COMPACT_RUNS {
            (0..self.runs.len()).collect()
        } else {
            let last = self.runs.len() - 1;
            let mut picked: Vec<usize> = (0..COMPACT_RUNS)
                .map(|k| (k * last + (COMPACT_RUNS - 1) / 2) / (COMPACT_RUNS - 1))
                .collect();
            picked.dedup();
            picked
        };
        let _ = writeln!(
            out,
            "\n  {} runs{}:",
            self.runs.len(),
            if shown.len() < self.runs.len() {
                format!(", {} of them shown (all with --verbose)", shown.len())
            } else {
                String::new()
            }
        );
        for &k in &shown {
            let run = &self.runs[k];
            let time = run
                .time
                .map_or_else(String::new, |t| format!("  t = {:.1} min", t / 60.0));
            let temps: String = self
                .sensors
                .iter()
                .zip(&run.temperatures)
                .map(|(s, t)| format!("  {s} {t:.2} °C"))
                .collect();
            let _ = writeln!(out, "  run {}{time}{temps}", run.label);
        }
        out
    }
}
