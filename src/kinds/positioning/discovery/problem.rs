//! A positioning table prepared for discovery: its readings as columns, the checks, which
//! effects the file can show, the reference run and its knots, and the temperature and
//! activity inputs of the model's terms.

use super::hat_span::HatSpan;
use super::memo::{PerTraining, PerValue};
use super::periodogram::Spectrum;
use super::{
    DiscoveryError, MAX_FREQUENCIES, MAX_RUN_FOLDS, MIN_TEMPERATURE_RANGE, PositioningEffect,
    PositioningOptions, SAME_POSITION,
};
use crate::discovery::engine::{self, Folds};
use crate::discovery::least_squares::Prefix;
use crate::kinds::positioning::table::PositioningTable;
use crate::machine::Axis;
use crate::math::{M_PER_MM, Real};
use crate::math::{local_lines, local_rates};
use crate::program::Approach;
use crate::thermal::first_order_lag;

/// A positioning table prepared for discovery.
#[derive(Clone, Debug)]
pub struct PositioningProblem {
    pub(super) axis: Option<Axis>,
    pub(super) run_labels: Vec<String>,
    /// Position (m), deviation (m), direction sign, run of every reading.
    pub(super) x: Vec<Real>,
    pub(super) y: Vec<Real>,
    pub(super) s: Vec<Real>,
    pub(super) run: Vec<usize>,
    /// Time since the start (s) and temperature (°C), when the file has them.
    pub(super) time: Option<Vec<Real>>,
    pub(super) temperature: Option<Vec<Real>>,
    /// The temperature's rate of change (°C/s) at each reading, from its neighbours in time
    /// ([`local_rates`]), when the file has times and temperatures.
    pub(super) rate: Option<Vec<Real>>,
    pub(super) sensor: Option<String>,
    /// Reading indices in the order they were taken.
    pub(super) order: Vec<usize>,
    /// Centre and half-range of the targets (m), for the polynomial terms.
    pub(super) centre: Real,
    pub(super) half_range: Real,
    pub(super) options: PositioningOptions,
    pub(super) folds: Folds,
    pub(super) testable: Vec<PositioningEffect>,
    pub(super) untestable: Vec<(PositioningEffect, String)>,
    /// The distinct positions (m, in order) and the index among them of every reading: the
    /// cyclic term's sines are taken once per position.
    pub(super) positions: (Vec<Real>, Vec<usize>),
    /// The period search's position-only sums, per training set.
    pub(super) spectra: PerTraining<Spectrum>,
    /// The span of the profile's columns on the training rows, with the knots it was taken
    /// for, per training set ([`PositioningProblem::sse_profile`]).
    pub(super) hat_spans: PerTraining<(Vec<Real>, HatSpan)>,
    /// The Householder steps on the profile's columns, with the knots they were taken for, per
    /// training set ([`PositioningProblem::solve`]).
    pub(super) hat_prefixes: PerTraining<(Vec<Real>, Prefix)>,
    /// The driving temperature per (lag, sensor lag) searched ([`PositioningProblem::driver`]).
    pub(super) drivers: PerValue<Option<Vec<Real>>>,
    /// The heating response per time constant ([`PositioningProblem::activity`]).
    pub(super) activities: PerValue<Vec<Real>>,
}

/// The run a fit is referred to and its knots.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Reference {
    pub(super) run: usize,
    pub(super) knots: Vec<Real>,
    pub(super) time: Real,
}

impl PositioningProblem {
    /// Prepares `table`: checks it, chooses the temperature column, the folds and which
    /// effects the file can show at all.
    pub fn new(
        table: &PositioningTable,
        options: PositioningOptions,
    ) -> Result<PositioningProblem, DiscoveryError> {
        let n = table.readings.len();
        if n < 6 {
            return Err(DiscoveryError(format!(
                "{n} readings: discovery needs at least 6 (one model fit per fold)"
            )));
        }
        if options.folds < 2 {
            return Err(DiscoveryError(format!(
                "{} folds: cross-validation needs at least 2",
                options.folds
            )));
        }
        if !(options.expansion.is_finite() && options.min_period > 0.0) {
            return Err(DiscoveryError(
                "the expansion coefficient must be finite and the shortest period positive".into(),
            ));
        }
        let finite = |r: &crate::kinds::positioning::table::PositioningReading| {
            [r.target, r.deviation, r.time.unwrap_or(0.0)]
                .iter()
                .chain(&r.temperatures)
                .all(|v| v.is_finite())
        };
        if let Some(k) = table.readings.iter().position(|r| !finite(r)) {
            return Err(DiscoveryError(format!(
                "reading {}: a value is not a finite number",
                k + 1
            )));
        }
        let sensor_index =
            match &options.sensor {
                Some(name) => Some(table.sensors.iter().position(|s| s == name).ok_or_else(
                    || {
                        DiscoveryError(format!(
                            "no column temp_{name}_degc; the file has {}",
                            if table.sensors.is_empty() {
                                "no temperature columns".to_string()
                            } else {
                                table
                                    .sensors
                                    .iter()
                                    .map(|s| format!("temp_{s}_degc"))
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            }
                        ))
                    },
                )?),
                None => (!table.sensors.is_empty()).then_some(0),
            };
        let x: Vec<Real> = table.readings.iter().map(|r| r.target).collect();
        let y = table.readings.iter().map(|r| r.deviation).collect();
        let s = table
            .readings
            .iter()
            .map(|r| {
                if r.approach == Approach::Up {
                    1.0
                } else {
                    -1.0
                }
            })
            .collect::<Vec<_>>();
        let run: Vec<usize> = table.readings.iter().map(|r| r.run).collect();
        let time: Option<Vec<Real>> = table.readings.iter().map(|r| r.time).collect();
        let temperature: Option<Vec<Real>> =
            sensor_index.map(|k| table.readings.iter().map(|r| r.temperatures[k]).collect());
        let mut order: Vec<usize> = (0..n).collect();
        if let Some(t) = &time {
            order.sort_by(|&a, &b| t[a].total_cmp(&t[b]));
        }
        let rate = match (&time, &temperature) {
            (Some(time), Some(temperature)) => {
                let times: Vec<Real> = order.iter().map(|&i| time[i]).collect();
                let values: Vec<Real> = order.iter().map(|&i| temperature[i]).collect();
                let mut rate = vec![0.0; n];
                for (&i, r) in order.iter().zip(local_rates(&times, &values)) {
                    rate[i] = r;
                }
                Some(rate)
            }
            _ => None,
        };
        let (low, high) = x
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        // The period search tests 4 frequencies per 1/travel down to the shortest period.
        let frequencies = 4.0 * (high - low) / options.min_period;
        if frequencies > MAX_FREQUENCIES {
            return Err(DiscoveryError(format!(
                "a shortest period of {} mm over {} mm of travel would test {frequencies:.0} frequencies (at most {MAX_FREQUENCIES}); give a longer one",
                options.min_period / M_PER_MM,
                (high - low) / M_PER_MM
            )));
        }
        let n_runs = table.runs.len();
        let folds = if n_runs > MAX_RUN_FOLDS {
            let blocks: Vec<usize> = run.iter().map(|&r| r * MAX_RUN_FOLDS / n_runs).collect();
            Folds::leave_one_group_out(
                &blocks,
                &format!(
                    "leave-one-block-of-runs-out ({MAX_RUN_FOLDS} blocks of {} to {} consecutive runs)",
                    n_runs / MAX_RUN_FOLDS,
                    n_runs.div_ceil(MAX_RUN_FOLDS)
                ),
            )
        } else if n_runs >= 3 {
            Folds::leave_one_group_out(&run, "leave-one-run-out")
        } else {
            Folds::contiguous(&order, options.folds)
        };
        let mut problem = PositioningProblem {
            axis: table.axis,
            run_labels: table.runs.clone(),
            positions: distinct(&x),
            x,
            y,
            s,
            run,
            time,
            temperature,
            rate,
            sensor: sensor_index.map(|k| table.sensors[k].clone()),
            order,
            centre: (low + high) / 2.0,
            half_range: ((high - low) / 2.0).max(SAME_POSITION),
            options,
            folds,
            testable: Vec::new(),
            untestable: Vec::new(),
            spectra: PerTraining::default(),
            hat_spans: PerTraining::default(),
            hat_prefixes: PerTraining::default(),
            drivers: PerValue::default(),
            activities: PerValue::default(),
        };
        problem.sort_effects();
        problem.set_aside_inert();
        Ok(problem)
    }

    /// Moves the testable effects whose terms cannot change the fit on this file
    /// ([`engine::inert`]) to the untestable ones: e.g. a lag on a file whose time stamps
    /// leave it nothing to act on.
    fn set_aside_inert(&mut self) {
        let probes: Vec<PositioningProblem> = engine::probe_signals(self.y.len(), 1e-6)
            .into_iter()
            .map(|y| PositioningProblem {
                y,
                testable: Vec::new(),
                untestable: Vec::new(),
                ..self.clone()
            })
            .collect();
        for effect in engine::inert(&probes, &self.testable) {
            self.testable.retain(|&e| e != effect);
            self.untestable.push((effect, engine::INERT_REASON.into()));
        }
        self.untestable.sort_by_key(|(e, _)| *e);
    }

    /// Splits the library into what this file can and cannot show, with the reason.
    fn sort_effects(&mut self) {
        let both_directions = self.s.contains(&1.0) && self.s.contains(&-1.0);
        let repeats = self.has_repeats();
        let temperature_range = self.temperature.as_ref().map(|t| {
            let (l, h) = t
                .iter()
                .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &v| {
                    (l.min(v), h.max(v))
                });
            h - l
        });
        let reference = self.reference(&vec![true; self.x.len()]);
        let off_knot = self
            .x
            .iter()
            .filter(|&&x| {
                reference
                    .knots
                    .iter()
                    .all(|k| (k - x).abs() > SAME_POSITION)
            })
            .count();
        for effect in PositioningEffect::ALL {
            let mut reasons: Vec<String> = Vec::new();
            let directional = matches!(
                effect,
                PositioningEffect::Reversal
                    | PositioningEffect::ReversalPosition
                    | PositioningEffect::ReversalThermal
            );
            let thermal = matches!(
                effect,
                PositioningEffect::ReversalThermal
                    | PositioningEffect::ThermalLag
                    | PositioningEffect::SensorLag
                    | PositioningEffect::ThermalScale
                    | PositioningEffect::ThermalOffset
            );
            let timed = matches!(
                effect,
                PositioningEffect::ThermalLag
                    | PositioningEffect::SensorLag
                    | PositioningEffect::SecondHeatSource
                    | PositioningEffect::TimeDrift
            );
            let changing = thermal || timed;
            let positional = matches!(
                effect,
                PositioningEffect::Periodic | PositioningEffect::NonlinearScale
            );
            if directional && !both_directions {
                reasons.push("every reading is in one direction".into());
            }
            if thermal {
                match temperature_range {
                    None => reasons.push("the file has no temperature column".into()),
                    Some(range) if range < MIN_TEMPERATURE_RANGE => reasons.push(format!(
                        "the temperature varies by only {range:.3} °C (at least {MIN_TEMPERATURE_RANGE} °C needed)"
                    )),
                    Some(_) => {}
                }
            }
            if timed && self.time.is_none() {
                reasons.push("the file has no time_min column".into());
            }
            if changing && !repeats {
                reasons.push(
                    "no target is read twice in the same direction, so a change with time or temperature cannot be told from the profile"
                        .into(),
                );
            }
            if positional && off_knot < 4 {
                reasons.push(format!(
                    "{off_knot} readings lie between the reference run's targets (at least 4 needed); at the targets the profile already holds any error that depends on position only"
                ));
            }
            if reasons.is_empty() {
                self.testable.push(effect);
            } else {
                self.untestable.push((effect, reasons.join("; ")));
            }
        }
    }

    /// Whether some target is read more than once in the same direction.
    fn has_repeats(&self) -> bool {
        let mut seen: Vec<(Real, Real)> = Vec::new();
        for (&x, &s) in self.x.iter().zip(&self.s) {
            if seen
                .iter()
                .any(|&(px, ps)| ps == s && (px - x).abs() <= SAME_POSITION)
            {
                return true;
            }
            seen.push((x, s));
        }
        false
    }

    /// This file with its temperature readings smoothed in time: each replaced by the value of
    /// the least-squares line through the readings within the window of [`local_rates`]
    /// ([`crate::math::local_lines`]); `None` without times and temperatures.
    pub(super) fn with_smoothed_temperature(&self) -> Option<PositioningProblem> {
        let (time, temperature) = (self.time.as_ref()?, self.temperature.as_ref()?);
        let times: Vec<Real> = self.order.iter().map(|&i| time[i]).collect();
        let values: Vec<Real> = self.order.iter().map(|&i| temperature[i]).collect();
        let mut smoothed = vec![0.0; values.len()];
        for (&i, (level, _)) in self.order.iter().zip(local_lines(&times, &values)) {
            smoothed[i] = level;
        }
        Some(PositioningProblem {
            temperature: Some(smoothed),
            ..self.clone()
        })
    }

    /// The effects this file cannot show, with the reason.
    pub fn untestable(&self) -> &[(PositioningEffect, String)] {
        &self.untestable
    }

    /// The folds whose held-out readings lie outside the training readings' temperature range
    /// by at least 0.1 °C (the least variation a thermal term needs to be tested at all), in
    /// fold order; empty without a temperature. Such a fold's held-out RMS
    /// measures extrapolation: the models are fitted without its thermal state (a cold
    /// reference run held out is predicted from warm runs alone).
    pub fn extrapolated_folds(&self) -> Vec<Extrapolation> {
        let Some(temperature) = &self.temperature else {
            return Vec::new();
        };
        let folds = &self.folds;
        let range = |keep: &dyn Fn(usize) -> bool| {
            (0..temperature.len())
                .filter(|&i| keep(folds.of_sample[i]))
                .fold((Real::INFINITY, Real::NEG_INFINITY), |(low, high), i| {
                    (low.min(temperature[i]), high.max(temperature[i]))
                })
        };
        (0..folds.count)
            .filter_map(|k| {
                let (held_low, held_high) = range(&|f| f == k);
                let (low, high) = range(&|f| f != k);
                let extrapolation = Extrapolation {
                    fold: k,
                    below_degc: (low - held_low).max(0.0),
                    above_degc: (held_high - high).max(0.0),
                };
                (extrapolation.below_degc >= MIN_TEMPERATURE_RANGE
                    || extrapolation.above_degc >= MIN_TEMPERATURE_RANGE)
                    .then_some(extrapolation)
            })
            .collect()
    }

    /// The reference run among the training readings (coldest, else first) and its knots.
    pub(super) fn reference(&self, train: &[bool]) -> Reference {
        let runs = self.run_labels.len();
        let mut sum = vec![0.0; runs];
        let mut count = vec![0usize; runs];
        for i in (0..self.x.len()).filter(|&i| train[i]) {
            sum[self.run[i]] += self.temperature.as_ref().map_or(0.0, |t| t[i]);
            count[self.run[i]] += 1;
        }
        let present = (0..runs).filter(|&r| count[r] > 0);
        let run = if self.temperature.is_some() {
            present
                .min_by(|&a, &b| {
                    (sum[a] / count[a] as Real).total_cmp(&(sum[b] / count[b] as Real))
                })
                .unwrap_or(0)
        } else {
            present.min().unwrap_or(0)
        };
        let mut knots: Vec<Real> = Vec::new();
        let mut time_sum = 0.0;
        for i in (0..self.x.len()).filter(|&i| train[i] && self.run[i] == run) {
            if knots.iter().all(|k| (k - self.x[i]).abs() > SAME_POSITION) {
                knots.push(self.x[i]);
            }
            time_sum += self.time.as_ref().map_or(0.0, |t| t[i]);
        }
        knots.sort_by(Real::total_cmp);
        Reference {
            run,
            knots,
            time: time_sum / count[run].max(1) as Real,
        }
    }

    /// The temperature the structure follows: measured; ahead by `sensor_tau·dT/dt` (s) when
    /// the sensor lags the structure; then lagged by `lag_tau` (s) when the structure lags it.
    pub(super) fn driver(
        &self,
        lag_tau: Option<Real>,
        sensor_tau: Option<Real>,
    ) -> Option<Vec<Real>> {
        let measured = self.temperature.as_ref()?;
        let source: Vec<Real> = match (sensor_tau, &self.rate) {
            (Some(tau), Some(rate)) => measured
                .iter()
                .zip(rate)
                .map(|(t, r)| t + tau * r)
                .collect(),
            _ => measured.clone(),
        };
        let Some(tau) = lag_tau else {
            return Some(source);
        };
        let time = self.time.as_ref()?;
        let mut lagged = vec![0.0; source.len()];
        let mut previous: Option<usize> = None;
        for &i in &self.order {
            lagged[i] = match previous {
                None => source[i],
                Some(p) => first_order_lag(lagged[p], source[p], source[i], time[i] - time[p], tau),
            };
            previous = Some(i);
        }
        Some(lagged)
    }

    /// Activity response `1 − e^(−(t − t₀)/τ)` since the first reading.
    pub(super) fn activity(&self, tau: Real) -> Vec<Real> {
        let time = self
            .time
            .as_ref()
            .expect("only proposed with a time column");
        let start = self.order.first().map_or(0.0, |&i| time[i]);
        time.iter()
            .map(|t| 1.0 - (-(t - start) / tau).exp())
            .collect()
    }
}

/// A fold whose held-out readings lie outside the training readings' temperature range
/// ([`PositioningProblem::extrapolated_folds`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extrapolation {
    /// The fold.
    pub fold: usize,
    /// How far its coldest reading lies below the training readings' coldest (°C, 0: not).
    pub below_degc: Real,
    /// How far its warmest reading lies above the training readings' warmest (°C, 0: not).
    pub above_degc: Real,
}

/// The distinct values of `x` in increasing order (−0 and +0 apart, as `total_cmp` orders
/// them), and the index among them of every value: the readings' positions, for the cyclic
/// term's sines and the periodogram's groups.
pub(super) fn distinct(x: &[Real]) -> (Vec<Real>, Vec<usize>) {
    let mut values = x.to_vec();
    values.sort_by(Real::total_cmp);
    values.dedup_by(|a, b| a.total_cmp(b).is_eq());
    let index = x
        .iter()
        .map(|v| values.partition_point(|p| p.total_cmp(v).is_lt()))
        .collect();
    (values, index)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distinct_positions_index_every_reading() {
        let x = [0.2, -0.0, 0.0, 0.1, 0.2, 0.1];
        let (values, index) = distinct(&x);
        assert_eq!(values.len(), 4);
        for (v, &k) in x.iter().zip(&index) {
            assert_eq!(values[k].to_bits(), v.to_bits());
        }
        assert_eq!(index, [3, 0, 1, 2, 3, 2]);
    }
}
