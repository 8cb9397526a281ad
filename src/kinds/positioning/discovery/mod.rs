//! Discovery on positioning tables (laser interferometer, ISO 230-2 layout).
//!
//! **Base model** of a reading at position `x` (m, from the axis zero), direction `s` (±1),
//! time `t` and measured temperature `T`:
//!
//! `e = P(x) + α₀·x·(T − T_ref)`
//!
//! - `P` is the reference error profile: piecewise linear through knots at the targets of the
//!   reference run (the coldest run when the file has temperatures, else the first), its knot
//!   values fitted to every training reading at once, so it is the axis's error at the
//!   reference run's temperature (a flat extension beyond the end knots);
//! - `α₀` is the nominal expansion coefficient of the axis (11.7 µm/(m·°C), a steel screw, unless
//!   told otherwise), `T_ref` the reference run's mean temperature. The term is absent when the
//!   file has no temperature.
//!
//! The nominal coefficient is not fitted: a fitted coefficient *is* the `thermal_scale` effect,
//! which would otherwise be undiscoverable. Effects add terms to this model (see
//! [`PositioningEffect`]); the engine in [`super::engine`] selects them by held-out RMS.
//!
//! Temperatures and times are inputs: the lagged temperature of `thermal_lag` is computed from
//! the whole file's temperature record (readings held out of a fold keep their temperatures,
//! never their deviations). Between readings the temperature is taken to change linearly.

use crate::discovery::engine::{
    self, Folds, Problem, ResidualStep, Score, Selection, params_json, round_json as round,
};
use crate::discovery::least_squares::Design;
use crate::kinds::positioning::PositioningTable;
use crate::machine::Axis;
use crate::math::golden_minimum;
use crate::math::{M_PER_MM, M_PER_UM, Real, fixed};
use crate::program::Approach;
use crate::thermal::first_order_lag;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::f64::consts::TAU;

/// Knots and repeated targets are the same position when closer than this (m).
const SAME_POSITION: Real = 1e-6;
/// Below this temperature range (°C) the file cannot show a temperature effect.
const MIN_TEMPERATURE_RANGE: Real = 0.1;
/// Proposal rules fire when the residual's association has |t| at least this.
const PROPOSAL_T: Real = 2.0;
/// The most frequencies a period search may test.
const MAX_FREQUENCIES: Real = 1e5;
/// Grid points of a time-constant search (log-spaced), before golden-section refinement.
const TAU_GRID: usize = 24;

/// Settings of positioning discovery.
#[derive(Clone, Debug, PartialEq)]
pub struct PositioningOptions {
    /// Nominal expansion coefficient of the axis (1/K) used by the base model.
    pub expansion: Real,
    /// The temperature column to use (`<sensor>` of `temp_<sensor>_degc`); the first if none.
    pub sensor: Option<String>,
    /// Shortest period the cyclic-error search considers (m).
    pub min_period: Real,
    /// Folds of the contiguous split used when the file has fewer than three runs.
    pub folds: usize,
}

impl Default for PositioningOptions {
    fn default() -> PositioningOptions {
        PositioningOptions {
            expansion: 11.7e-6,
            sensor: None,
            min_period: 2.0 * M_PER_MM,
            folds: 5,
        }
    }
}

/// Why a positioning table cannot be searched.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct DiscoveryError(String);

/// The effects positioning discovery can add to the base model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PositioningEffect {
    /// Constant lost motion `v`: the reading is `−s·v/2`.
    Reversal,
    /// Lost motion changing along the axis: `−s·k·(x − x_c)/2` about the targets' centre.
    ReversalPosition,
    /// Lost motion changing with temperature: `−s·k·(T − T_ref)/2`.
    ReversalThermal,
    /// The expanding structure follows a first-order lag (τ) of the measured temperature.
    ThermalLag,
    /// Expansion coefficient different from the nominal one: `Δα·x·(T − T_ref)`.
    ThermalScale,
    /// Origin drift with temperature: `c·(T − T_ref)`.
    ThermalOffset,
    /// Expansion driven by machine activity since the first reading: `b·x·(1 − e^(−t/τ))`.
    SecondHeatSource,
    /// Cyclic error `a·sin(2πx/p) + b·cos(2πx/p)`, period `p` searched.
    Periodic,
    /// Quadratic and cubic terms in position beyond the profile's knots.
    NonlinearScale,
    /// Drift linear in time not explained by temperature: `d·(t − t_ref)`.
    TimeDrift,
}

impl PositioningEffect {
    /// Every effect, in the order they are reported.
    pub const ALL: [PositioningEffect; 10] = [
        PositioningEffect::Reversal,
        PositioningEffect::ReversalPosition,
        PositioningEffect::ReversalThermal,
        PositioningEffect::ThermalLag,
        PositioningEffect::ThermalScale,
        PositioningEffect::ThermalOffset,
        PositioningEffect::SecondHeatSource,
        PositioningEffect::Periodic,
        PositioningEffect::NonlinearScale,
        PositioningEffect::TimeDrift,
    ];

    /// The stable identifier.
    pub fn id(self) -> &'static str {
        match self {
            PositioningEffect::Reversal => "reversal",
            PositioningEffect::ReversalPosition => "reversal_position",
            PositioningEffect::ReversalThermal => "reversal_thermal",
            PositioningEffect::ThermalLag => "thermal_lag",
            PositioningEffect::ThermalScale => "thermal_scale",
            PositioningEffect::ThermalOffset => "thermal_offset",
            PositioningEffect::SecondHeatSource => "second_heat_source",
            PositioningEffect::Periodic => "periodic",
            PositioningEffect::NonlinearScale => "nonlinear_scale",
            PositioningEffect::TimeDrift => "time_drift",
        }
    }

    /// The physical cause, as a metrologist would name it.
    pub fn cause(self) -> &'static str {
        match self {
            PositioningEffect::Reversal => {
                "lost motion (backlash): play and elastic wind-up in the screw, nut and drive leave the axis short of the target in the direction of travel"
            }
            PositioningEffect::ReversalPosition => {
                "lost motion that changes along the travel: uneven nut preload or screw wear, guideway friction varying with position"
            }
            PositioningEffect::ReversalThermal => {
                "lost motion that changes with temperature: nut preload and friction changing as the drive warms"
            }
            PositioningEffect::ThermalLag => {
                "the expanding structure (the screw) warms later than the sensor reads: its effective temperature is a first-order lag of the measured one"
            }
            PositioningEffect::ThermalScale => {
                "the axis expands per degree differently from the nominal coefficient: another material, a sensor that is not at the screw's temperature, or thermal compensation in the control"
            }
            PositioningEffect::ThermalOffset => {
                "the axis origin moves with temperature: the screw's fixed end (thrust bearing) or the measurement zero is away from the axis zero, or the structure carrying the reference grows"
            }
            PositioningEffect::SecondHeatSource => {
                "a heat source the sensor does not see (motor, support bearings, the nut on the screw) expands the axis as the machine runs, with its own time constant"
            }
            PositioningEffect::Periodic => {
                "cyclic error with the period of the drive or scale: screw lead (pitch) error, thread drunkenness, scale interpolation error"
            }
            PositioningEffect::NonlinearScale => {
                "curved positioning error between the reference targets: lead error varying along the screw, guideway bending"
            }
            PositioningEffect::TimeDrift => {
                "slow drift with time that the temperature does not explain: laser set-up drift, creep, an unmeasured part of the environment"
            }
        }
    }

    /// Whether the effect has a searched (nonlinear) parameter.
    fn searched(self) -> bool {
        matches!(
            self,
            PositioningEffect::ThermalLag
                | PositioningEffect::SecondHeatSource
                | PositioningEffect::Periodic
        )
    }

    /// The number of linear coefficients it adds.
    fn columns(self) -> usize {
        match self {
            PositioningEffect::ThermalLag => 0,
            PositioningEffect::Periodic | PositioningEffect::NonlinearScale => 2,
            _ => 1,
        }
    }
}

/// A positioning table prepared for discovery.
#[derive(Clone, Debug)]
pub struct PositioningProblem {
    axis: Option<Axis>,
    run_labels: Vec<String>,
    /// Position (m), deviation (m), direction sign, run of every reading.
    x: Vec<Real>,
    y: Vec<Real>,
    s: Vec<Real>,
    run: Vec<usize>,
    /// Time since the start (s) and temperature (°C), when the file has them.
    time: Option<Vec<Real>>,
    temperature: Option<Vec<Real>>,
    sensor: Option<String>,
    /// Reading indices in the order they were taken.
    order: Vec<usize>,
    /// Centre and half-range of the targets (m), for the polynomial terms.
    centre: Real,
    half_range: Real,
    options: PositioningOptions,
    folds: Folds,
    testable: Vec<PositioningEffect>,
    untestable: Vec<(PositioningEffect, String)>,
}

/// The values of the searched parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Searched {
    lag_tau: Option<Real>,
    heat_tau: Option<Real>,
    period: Option<Real>,
}

impl Searched {
    fn has(&self, effect: PositioningEffect) -> bool {
        match effect {
            PositioningEffect::ThermalLag => self.lag_tau.is_some(),
            PositioningEffect::SecondHeatSource => self.heat_tau.is_some(),
            PositioningEffect::Periodic => self.period.is_some(),
            _ => true,
        }
    }
}

/// The run a fit is referred to and its knots.
#[derive(Clone, Debug, PartialEq)]
struct Reference {
    run: usize,
    knots: Vec<Real>,
    time: Real,
}

/// A fitted positioning model.
#[derive(Clone, Debug)]
pub struct PositioningFit {
    effects: Vec<PositioningEffect>,
    reference: Reference,
    /// The reference temperature (°C): the reference run's mean (lagged, with `thermal_lag`).
    reference_temperature: Option<Real>,
    searched: Searched,
    /// Profile values at the knots (m), then each effect's coefficients in order.
    coefficients: Vec<Real>,
    residuals: Vec<Real>,
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
        let finite = |r: &crate::kinds::positioning::PositioningReading| {
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
        let folds = if n_runs >= 3 {
            Folds::leave_one_group_out(&run, "leave-one-run-out")
        } else {
            Folds::contiguous(&order, options.folds)
        };
        let mut problem = PositioningProblem {
            axis: table.axis,
            run_labels: table.runs.clone(),
            x,
            y,
            s,
            run,
            time,
            temperature,
            sensor: sensor_index.map(|k| table.sensors[k].clone()),
            order,
            centre: (low + high) / 2.0,
            half_range: ((high - low) / 2.0).max(SAME_POSITION),
            options,
            folds,
            testable: Vec::new(),
            untestable: Vec::new(),
        };
        problem.sort_effects();
        Ok(problem)
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
                    | PositioningEffect::ThermalScale
                    | PositioningEffect::ThermalOffset
            );
            let timed = matches!(
                effect,
                PositioningEffect::ThermalLag
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

    /// The effects this file cannot show, with the reason.
    pub fn untestable(&self) -> &[(PositioningEffect, String)] {
        &self.untestable
    }

    /// The reference run among the training readings (coldest, else first) and its knots.
    fn reference(&self, train: &[bool]) -> Reference {
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

    /// The temperature the structure follows: measured, or lagged by `tau` (s).
    fn driver(&self, lag_tau: Option<Real>) -> Option<Vec<Real>> {
        let measured = self.temperature.as_ref()?;
        let Some(tau) = lag_tau else {
            return Some(measured.clone());
        };
        let time = self.time.as_ref()?;
        let mut lagged = vec![0.0; measured.len()];
        let mut previous: Option<usize> = None;
        for &i in &self.order {
            lagged[i] = match previous {
                None => measured[i],
                Some(p) => {
                    first_order_lag(lagged[p], measured[p], measured[i], time[i] - time[p], tau)
                }
            };
            previous = Some(i);
        }
        Some(lagged)
    }

    /// Activity response `1 − e^(−(t − t₀)/τ)` since the first reading.
    fn activity(&self, tau: Real) -> Vec<Real> {
        let time = self
            .time
            .as_ref()
            .expect("only proposed with a time column");
        let start = self.order.first().map_or(0.0, |&i| time[i]);
        time.iter()
            .map(|t| 1.0 - (-(t - start) / tau).exp())
            .collect()
    }

    /// Every reading's columns (profile hats, then each effect's), the known part of the
    /// prediction (nominal expansion) and the reference temperature.
    fn columns(
        &self,
        effects: &[PositioningEffect],
        reference: &Reference,
        searched: &Searched,
    ) -> (Vec<Vec<Real>>, Vec<Real>, Option<Real>) {
        let n = self.x.len();
        let knots = &reference.knots;
        let mut columns: Vec<Vec<Real>> = vec![vec![0.0; n]; knots.len()];
        for (i, &x) in self.x.iter().enumerate() {
            let j = knots.partition_point(|&k| k <= x);
            if j == 0 {
                columns[0][i] = 1.0;
            } else if j == knots.len() {
                columns[j - 1][i] = 1.0;
            } else {
                let w = (x - knots[j - 1]) / (knots[j] - knots[j - 1]);
                columns[j - 1][i] = 1.0 - w;
                columns[j][i] = w;
            }
        }
        let driver = self.driver(
            effects
                .contains(&PositioningEffect::ThermalLag)
                .then_some(searched.lag_tau)
                .flatten(),
        );
        let reference_temperature = driver.as_ref().map(|d| {
            let (sum, count) = (0..n)
                .filter(|&i| self.run[i] == reference.run)
                .fold((0.0, 0usize), |(s, c), i| (s + d[i], c + 1));
            sum / count.max(1) as Real
        });
        let rise: Vec<Real> = match (&driver, reference_temperature) {
            (Some(d), Some(t_ref)) => d.iter().map(|t| t - t_ref).collect(),
            _ => vec![0.0; n],
        };
        let known: Vec<Real> = (0..n)
            .map(|i| self.options.expansion * self.x[i] * rise[i])
            .collect();
        let map = |f: &dyn Fn(usize) -> Real| (0..n).map(f).collect::<Vec<Real>>();
        for &effect in effects {
            match effect {
                PositioningEffect::Reversal => columns.push(map(&|i| -self.s[i] / 2.0)),
                PositioningEffect::ReversalPosition => {
                    columns.push(map(&|i| -self.s[i] / 2.0 * (self.x[i] - self.centre)))
                }
                PositioningEffect::ReversalThermal => {
                    columns.push(map(&|i| -self.s[i] / 2.0 * rise[i]))
                }
                PositioningEffect::ThermalLag => {}
                PositioningEffect::ThermalScale => columns.push(map(&|i| self.x[i] * rise[i])),
                PositioningEffect::ThermalOffset => columns.push(rise.clone()),
                PositioningEffect::SecondHeatSource => {
                    let g = self.activity(searched.heat_tau.expect("searched first"));
                    columns.push(map(&|i| self.x[i] * g[i]));
                }
                PositioningEffect::Periodic => {
                    let w = TAU / searched.period.expect("searched first");
                    columns.push(map(&|i| (w * self.x[i]).sin()));
                    columns.push(map(&|i| (w * self.x[i]).cos()));
                }
                PositioningEffect::NonlinearScale => {
                    let xi = |i: usize| (self.x[i] - self.centre) / self.half_range;
                    columns.push(map(&|i| xi(i).powi(2)));
                    columns.push(map(&|i| xi(i).powi(3)));
                }
                PositioningEffect::TimeDrift => {
                    let time = self
                        .time
                        .as_ref()
                        .expect("only proposed with a time column");
                    columns.push(map(&|i| (time[i] - reference.time) / 3600.0));
                }
            }
        }
        (columns, known, reference_temperature)
    }

    /// The linear fit of `effects` with `searched` fixed: coefficients, every residual and the
    /// training sum of squares.
    fn solve(
        &self,
        effects: &[PositioningEffect],
        train: &[bool],
        reference: &Reference,
        searched: &Searched,
    ) -> (Vec<Real>, Vec<Real>, Real, Option<Real>) {
        let (columns, known, reference_temperature) = self.columns(effects, reference, searched);
        let rows: Vec<usize> = (0..self.x.len()).filter(|&i| train[i]).collect();
        let mut design = Design::new(rows.len());
        for column in &columns {
            design.push(rows.iter().map(|&i| column[i]).collect());
        }
        let target: Vec<Real> = rows.iter().map(|&i| self.y[i] - known[i]).collect();
        let coefficients = design.solve(&target);
        let residuals: Vec<Real> = (0..self.x.len())
            .map(|i| {
                let predicted: Real = columns
                    .iter()
                    .zip(&coefficients)
                    .map(|(c, k)| c[i] * k)
                    .sum();
                self.y[i] - known[i] - predicted
            })
            .collect();
        let sse = rows.iter().map(|&i| residuals[i].powi(2)).sum();
        (coefficients, residuals, sse, reference_temperature)
    }

    /// The time span of the file (s), for the time-constant search range.
    fn time_span(&self) -> Real {
        let time = self
            .time
            .as_ref()
            .expect("only searched with a time column");
        let (first, last) = (self.order[0], self.order[self.order.len() - 1]);
        (time[last] - time[first]).max(60.0)
    }

    /// Searches a time constant (s) on a log grid from 1 min to twice the file's span, then
    /// refines by golden section between the best point's neighbours.
    fn search_tau(&self, sse: impl Fn(Real) -> Real) -> Real {
        let (low, high) = (60.0_f64.ln(), (2.0 * self.time_span()).max(120.0).ln());
        let grid: Vec<Real> = (0..TAU_GRID)
            .map(|k| low + (high - low) * k as Real / (TAU_GRID - 1) as Real)
            .collect();
        let values: Vec<Real> = grid.iter().map(|&g| sse(g.exp())).collect();
        let best = (0..TAU_GRID)
            .min_by(|&a, &b| values[a].total_cmp(&values[b]))
            .unwrap_or(0);
        let (a, b) = (
            grid[best.saturating_sub(1)],
            grid[(best + 1).min(TAU_GRID - 1)],
        );
        let (refined, value) = golden_minimum(|g| sse(g.exp()), a, b, 16);
        if value < values[best] {
            refined.exp()
        } else {
            grid[best].exp()
        }
    }

    /// Searches the period (m): a periodogram of the residual of the model without the cyclic
    /// term over frequencies from 1/(span) to 1/min_period (4 points per 1/span), then a
    /// golden-section refinement of the full fit around the peak.
    fn search_period(
        &self,
        effects: &[PositioningEffect],
        train: &[bool],
        reference: &Reference,
        searched: &Searched,
    ) -> Real {
        let without: Vec<PositioningEffect> = effects
            .iter()
            .copied()
            .filter(|&e| e != PositioningEffect::Periodic)
            .collect();
        let (_, residuals, _, _) = self.solve(&without, train, reference, searched);
        let rows: Vec<usize> = (0..self.x.len()).filter(|&i| train[i]).collect();
        let x: Vec<Real> = rows.iter().map(|&i| self.x[i]).collect();
        let r: Vec<Real> = rows.iter().map(|&i| residuals[i]).collect();
        let (step, f_low) = self.frequency_grid();
        let (peak, _) = self.periodogram_peak(&x, &r);
        let sse = |f: Real| {
            let trial = Searched {
                period: Some(1.0 / f),
                ..*searched
            };
            self.solve(effects, train, reference, &trial).2
        };
        let (low, high) = ((peak - step).max(f_low / 2.0), peak + step);
        let (refined, value) = golden_minimum(sse, low, high, 16);
        if value < sse(peak) {
            1.0 / refined
        } else {
            1.0 / peak
        }
    }

    /// The periodogram's frequency step and lowest frequency (1/m): from 1/travel to
    /// 1/min_period, 4 points per 1/travel.
    fn frequency_grid(&self) -> (Real, Real) {
        let span = (2.0 * self.half_range).max(self.options.min_period);
        (1.0 / (4.0 * span), 1.0 / span)
    }

    /// The frequency (1/m) whose sinusoid removes the largest fraction of `r`'s sum of squares
    /// over positions `x`, and that fraction.
    fn periodogram_peak(&self, x: &[Real], r: &[Real]) -> (Real, Real) {
        let (step, f_low) = self.frequency_grid();
        let count = ((1.0 / self.options.min_period - f_low) / step).ceil() as usize + 1;
        (0..count)
            .map(|k| f_low + step * k as Real)
            .map(|f| (f, sinusoid_reduction(x, r, f)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((f_low, 0.0))
    }

    /// Searches every searched parameter (in order, twice when there are several, each with
    /// the others held), then fits.
    fn fit_with(&self, effects: &[PositioningEffect], train: &[bool]) -> PositioningFit {
        let reference = self.reference(train);
        let mut searched = Searched::default();
        let nonlinear: Vec<PositioningEffect> =
            effects.iter().copied().filter(|e| e.searched()).collect();
        let passes = if nonlinear.len() > 1 { 2 } else { 1 };
        for _ in 0..passes {
            for &effect in &nonlinear {
                let active: Vec<PositioningEffect> = effects
                    .iter()
                    .copied()
                    .filter(|&e| e == effect || searched.has(e))
                    .collect();
                let sse_with = |trial: Searched| self.solve(&active, train, &reference, &trial).2;
                match effect {
                    PositioningEffect::ThermalLag => {
                        searched.lag_tau = Some(self.search_tau(|tau| {
                            sse_with(Searched {
                                lag_tau: Some(tau),
                                ..searched
                            })
                        }));
                    }
                    PositioningEffect::SecondHeatSource => {
                        searched.heat_tau = Some(self.search_tau(|tau| {
                            sse_with(Searched {
                                heat_tau: Some(tau),
                                ..searched
                            })
                        }));
                    }
                    _ => {
                        searched.period =
                            Some(self.search_period(&active, train, &reference, &searched));
                    }
                }
            }
        }
        let (coefficients, residuals, _, reference_temperature) =
            self.solve(effects, train, &reference, &searched);
        PositioningFit {
            effects: effects.to_vec(),
            reference,
            reference_temperature,
            searched,
            coefficients,
            residuals,
        }
    }
}

/// The fraction of `r`'s sum of squares removed by fitting `a·sin(2πfx) + b·cos(2πfx) + c`
/// (normal equations of the three columns: this runs for every trial frequency).
fn sinusoid_reduction(x: &[Real], r: &[Real], frequency: Real) -> Real {
    let mut normal = nalgebra::Matrix3::<Real>::zeros();
    let mut right = nalgebra::Vector3::<Real>::zeros();
    let mut total = 0.0;
    for (x, r) in x.iter().zip(r) {
        let (sin, cos) = (TAU * frequency * x).sin_cos();
        let row = nalgebra::Vector3::new(sin, cos, 1.0);
        normal += row * row.transpose();
        right += row * *r;
        total += r * r;
    }
    let Some(c) = normal.cholesky().map(|c| c.solve(&right)) else {
        return 0.0;
    };
    // Residual sum of squares = total − cᵀ·(Aᵀr) at the least-squares solution.
    if total > 0.0 {
        (c.dot(&right) / total).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Least-squares slope of `r` on `z` (with an intercept), Pearson correlation and its t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Association {
    /// Slope (unit of `r` per unit of `z`).
    pub slope: Real,
    /// Correlation coefficient.
    pub correlation: Real,
    /// `r·√((n − 2)/(1 − r²))`.
    pub t: Real,
}

fn associate(r: &[Real], z: &[Real]) -> Option<Association> {
    let n = r.len() as Real;
    if r.len() < 3 {
        return None;
    }
    let (mr, mz) = (r.iter().sum::<Real>() / n, z.iter().sum::<Real>() / n);
    let (mut srz, mut szz, mut srr) = (0.0, 0.0, 0.0);
    for (a, b) in r.iter().zip(z) {
        srz += (a - mr) * (b - mz);
        szz += (b - mz).powi(2);
        srr += (a - mr).powi(2);
    }
    if szz <= 0.0 || srr <= 0.0 {
        return None;
    }
    let correlation = srz / (szz * srr).sqrt();
    let t = correlation * ((n - 2.0) / (1.0 - correlation.powi(2)).max(1e-300)).sqrt();
    Some(Association {
        slope: srz / szz,
        correlation,
        t,
    })
}

impl Problem for PositioningProblem {
    type Effect = PositioningEffect;
    type Fit = PositioningFit;

    fn id(&self, effect: PositioningEffect) -> &'static str {
        effect.id()
    }

    fn n_samples(&self) -> usize {
        self.x.len()
    }

    fn folds(&self) -> &Folds {
        &self.folds
    }

    fn fit(&self, effects: &[PositioningEffect], train: &[bool]) -> PositioningFit {
        self.fit_with(effects, train)
    }

    fn residuals(&self, fit: &PositioningFit) -> Vec<Real> {
        fit.residuals.clone()
    }

    fn proposals(
        &self,
        effects: &[PositioningEffect],
        fit: &PositioningFit,
    ) -> Vec<(PositioningEffect, String)> {
        let d = self.diagnose(fit);
        self.testable
            .iter()
            .copied()
            .filter(|e| !effects.contains(e))
            .filter_map(|e| d.evidence(e).map(|text| (e, text)))
            .collect()
    }
}

/// The residual at one target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TargetResidual {
    /// Target position (m).
    pub target: Real,
    /// Mean residual of the readings travelling positive and negative (m), if any.
    pub mean_up: Option<Real>,
    /// See `mean_up`.
    pub mean_down: Option<Real>,
    /// RMS residual (m).
    pub rms: Real,
    /// Number of readings.
    pub count: usize,
}

/// What is left after a model, and where.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostics {
    /// RMS of the residual (m).
    pub rms: Real,
    /// Per target, in order of position.
    pub by_target: Vec<TargetResidual>,
    /// Strongest cyclic component: period (m), amplitude (m), F statistic (2 and n − 3 dof).
    pub periodogram: Option<(Real, Real, Real)>,
    /// F statistic of quadratic + cubic terms in position on the residual.
    pub curvature_f: Option<Real>,
    /// Mean residual up − down (m) and its standard error (m).
    pub direction: Option<(Real, Real)>,
    /// Per run: label, mean and RMS residual (m), mean temperature (°C).
    pub runs: Vec<(String, Real, Real, Option<Real>)>,
    /// Residual against time (slope per s).
    pub time: Option<Association>,
    /// Residual against temperature rise (slope per K).
    pub temperature: Option<Association>,
    /// Residual against position × temperature rise (slope per m·K).
    pub position_x_temperature: Option<Association>,
    /// Best first-order lag (s) of the temperature: residual against x·(T_lag − T).
    pub lagged_temperature: Option<(Real, Association)>,
    /// Best activity time constant (s): residual against x·(1 − e^(−t/τ)).
    pub activity: Option<(Real, Association)>,
    /// Direction-signed residual against position and against temperature rise.
    pub reversal_x_position: Option<Association>,
    /// Direction-signed residual against temperature rise.
    pub reversal_x_temperature: Option<Association>,
}

impl PositioningProblem {
    /// The residual diagnostics of a fit (to all data).
    pub fn diagnose(&self, fit: &PositioningFit) -> Diagnostics {
        let r = &fit.residuals;
        let n = r.len();
        let mut targets: Vec<Real> = Vec::new();
        for &x in &self.x {
            if targets.iter().all(|t| (t - x).abs() > SAME_POSITION) {
                targets.push(x);
            }
        }
        targets.sort_by(Real::total_cmp);
        let mean_of = |pick: &dyn Fn(usize) -> bool| {
            let (s, c) = (0..n)
                .filter(|&i| pick(i))
                .fold((0.0, 0usize), |(s, c), i| (s + r[i], c + 1));
            (c > 0).then(|| s / c as Real)
        };
        let by_target = targets
            .iter()
            .map(|&t| {
                let at = |i: usize| (self.x[i] - t).abs() <= SAME_POSITION;
                let members: Vec<Real> = (0..n).filter(|&i| at(i)).map(|i| r[i]).collect();
                TargetResidual {
                    target: t,
                    mean_up: mean_of(&|i| at(i) && self.s[i] > 0.0),
                    mean_down: mean_of(&|i| at(i) && self.s[i] < 0.0),
                    rms: engine::rms(&members),
                    count: members.len(),
                }
            })
            .collect();
        let periodogram = (n > 6).then(|| {
            let (f, fraction) = self.periodogram_peak(&self.x, r);
            let mut design = Design::new(n);
            design.push(self.x.iter().map(|x| (TAU * f * x).sin()).collect());
            design.push(self.x.iter().map(|x| (TAU * f * x).cos()).collect());
            design.push(vec![1.0; n]);
            let c = design.solve(r);
            let f_statistic = fraction / 2.0 / ((1.0 - fraction).max(1e-300) / (n as Real - 3.0));
            (1.0 / f, c[0].hypot(c[1]), f_statistic)
        });
        let curvature_f = (n > 6).then(|| {
            let xi: Vec<Real> = self
                .x
                .iter()
                .map(|x| (x - self.centre) / self.half_range)
                .collect();
            let mut design = Design::new(n);
            design.push(vec![1.0; n]);
            design.push(xi.clone());
            let c = design.solve(r);
            let base: Real = (0..n).map(|i| (r[i] - c[0] - c[1] * xi[i]).powi(2)).sum();
            design.push(xi.iter().map(|v| v * v).collect());
            design.push(xi.iter().map(|v| v * v * v).collect());
            let c = design.solve(r);
            let full: Real = (0..n)
                .map(|i| {
                    (r[i] - c[0] - c[1] * xi[i] - c[2] * xi[i].powi(2) - c[3] * xi[i].powi(3))
                        .powi(2)
                })
                .sum();
            (base - full) / 2.0 / (full.max(1e-300) / (n as Real - 4.0))
        });
        let direction = {
            let up: Vec<Real> = (0..n).filter(|&i| self.s[i] > 0.0).map(|i| r[i]).collect();
            let down: Vec<Real> = (0..n).filter(|&i| self.s[i] < 0.0).map(|i| r[i]).collect();
            (up.len() > 1 && down.len() > 1).then(|| {
                let stats = |v: &[Real]| {
                    let m = v.iter().sum::<Real>() / v.len() as Real;
                    let var =
                        v.iter().map(|x| (x - m).powi(2)).sum::<Real>() / (v.len() - 1) as Real;
                    (m, var / v.len() as Real)
                };
                let ((mu, vu), (md, vd)) = (stats(&up), stats(&down));
                (mu - md, (vu + vd).sqrt())
            })
        };
        let runs = (0..self.run_labels.len())
            .map(|k| {
                let members: Vec<usize> = (0..n).filter(|&i| self.run[i] == k).collect();
                let values: Vec<Real> = members.iter().map(|&i| r[i]).collect();
                let temperature = self.temperature.as_ref().map(|t| {
                    members.iter().map(|&i| t[i]).sum::<Real>() / members.len().max(1) as Real
                });
                (
                    self.run_labels[k].clone(),
                    values.iter().sum::<Real>() / values.len().max(1) as Real,
                    engine::rms(&values),
                    temperature,
                )
            })
            .collect();
        // The temperature the fit's thermal terms use (lagged with thermal_lag).
        let lag = fit
            .effects
            .contains(&PositioningEffect::ThermalLag)
            .then_some(fit.searched.lag_tau)
            .flatten();
        let rise: Option<Vec<Real>> = self.driver(lag).map(|t| {
            let reference = fit.reference_temperature.unwrap_or(t[0]);
            t.iter().map(|v| v - reference).collect()
        });
        let signed: Vec<Real> = (0..n).map(|i| r[i] * self.s[i]).collect();
        let times = self.time.as_ref();
        let best_over_tau = |z: &dyn Fn(Real) -> Vec<Real>| {
            let span = self.time_span();
            (0..TAU_GRID)
                .map(|k| 60.0 * (2.0 * span / 60.0).powf(k as Real / (TAU_GRID - 1) as Real))
                .filter_map(|tau| associate(r, &z(tau)).map(|a| (tau, a)))
                .max_by(|a, b| a.1.t.abs().total_cmp(&b.1.t.abs()))
        };
        let lagged_temperature = match (&self.temperature, times) {
            (Some(measured), Some(_)) => best_over_tau(&|tau| {
                let lagged = self.driver(Some(tau)).expect("has temperature");
                (0..n)
                    .map(|i| self.x[i] * (lagged[i] - measured[i]))
                    .collect()
            }),
            _ => None,
        };
        let activity = times.and_then(|_| {
            best_over_tau(&|tau| {
                let g = self.activity(tau);
                (0..n).map(|i| self.x[i] * g[i]).collect()
            })
        });
        Diagnostics {
            rms: engine::rms(r),
            by_target,
            periodogram,
            curvature_f,
            direction,
            runs,
            time: times.and_then(|t| associate(r, t)),
            temperature: rise.as_ref().and_then(|d| associate(r, d)),
            position_x_temperature: rise.as_ref().and_then(|d| {
                let z: Vec<Real> = (0..n).map(|i| self.x[i] * d[i]).collect();
                associate(r, &z)
            }),
            lagged_temperature,
            activity,
            reversal_x_position: associate(&signed, &self.x),
            reversal_x_temperature: rise.as_ref().and_then(|d| associate(&signed, d)),
        }
    }
}

impl Diagnostics {
    /// The rule that proposes `effect`, with the evidence in words; `None` when the residual
    /// shows nothing of the kind (association |t| < 2, reversal below two standard errors,
    /// periodogram or curvature F below 3).
    pub fn evidence(&self, effect: PositioningEffect) -> Option<String> {
        let um = |v: Real| v / M_PER_UM;
        let association = |a: &Option<Association>, what: &str| {
            a.filter(|a| a.t.abs() >= PROPOSAL_T)
                .map(|a| format!("residual correlates with {what} (r = {:.2})", a.correlation))
        };
        match effect {
            PositioningEffect::Reversal => self.direction.and_then(|(d, se)| {
                (d.abs() >= PROPOSAL_T * se).then(|| {
                    format!(
                        "up − down mean residual {:.2} µm (± {:.2} µm)",
                        um(d),
                        um(se)
                    )
                })
            }),
            PositioningEffect::ReversalPosition => association(
                &self.reversal_x_position,
                "position, with opposite signs by direction",
            ),
            PositioningEffect::ReversalThermal => association(
                &self.reversal_x_temperature,
                "temperature, with opposite signs by direction",
            ),
            PositioningEffect::ThermalLag => self
                .lagged_temperature
                .filter(|(_, a)| a.t.abs() >= PROPOSAL_T)
                .map(|(tau, a)| {
                    format!(
                        "residual correlates with position × (lagged − measured temperature) at τ = {:.0} min (r = {:.2})",
                        tau / 60.0,
                        a.correlation
                    )
                }),
            PositioningEffect::ThermalScale => association(
                &self.position_x_temperature,
                "position × temperature rise",
            ),
            PositioningEffect::ThermalOffset => {
                association(&self.temperature, "temperature rise")
            }
            PositioningEffect::SecondHeatSource => self
                .activity
                .filter(|(_, a)| a.t.abs() >= PROPOSAL_T)
                .map(|(tau, a)| {
                    format!(
                        "residual correlates with position × running time response at τ = {:.0} min (r = {:.2})",
                        tau / 60.0,
                        a.correlation
                    )
                }),
            PositioningEffect::Periodic => self
                .periodogram
                .filter(|p| p.2 >= 3.0)
                .map(|(period, amplitude, f)| {
                    format!(
                        "periodogram peak at {:.2} mm, {:.2} µm (F = {f:.1})",
                        period / M_PER_MM,
                        um(amplitude)
                    )
                }),
            PositioningEffect::NonlinearScale => self
                .curvature_f
                .filter(|f| *f >= 3.0)
                .map(|f| format!("quadratic + cubic trend in position (F = {f:.1})")),
            PositioningEffect::TimeDrift => association(&self.time, "time"),
        }
    }
}

/// The result of positioning discovery.
#[derive(Debug)]
pub struct PositioningDiscovery {
    problem: PositioningProblem,
    selection: Selection<PositioningEffect, PositioningFit>,
}

/// Runs discovery on a positioning table; `progress` hears which candidate is being tested.
pub fn discover_positioning(
    table: &PositioningTable,
    options: PositioningOptions,
    progress: impl FnMut(&str),
) -> Result<PositioningDiscovery, DiscoveryError> {
    let problem = PositioningProblem::new(table, options)?;
    let selection = engine::forward_selection(&problem, progress);
    Ok(PositioningDiscovery { problem, selection })
}

impl PositioningFit {
    /// The coefficients of `effect` (in SI), if it is in the fit.
    fn coefficients_of(&self, effect: PositioningEffect) -> Option<&[Real]> {
        let mut start = self.reference.knots.len();
        for &e in &self.effects {
            let end = start + e.columns();
            if e == effect {
                return Some(&self.coefficients[start..end]);
            }
            start = end;
        }
        None
    }

    /// The profile: knot positions (m) and values (m).
    pub fn profile(&self) -> (&[Real], &[Real]) {
        (
            &self.reference.knots,
            &self.coefficients[..self.reference.knots.len()],
        )
    }

    /// The fitted parameters of `effect`, in file units with the unit in the name.
    pub fn params(&self, effect: PositioningEffect) -> BTreeMap<&'static str, Real> {
        let c = self
            .coefficients_of(effect)
            .expect("parameters are asked of effects in the fit");
        let mut params = BTreeMap::new();
        let per_million = |v: Real| v * 1e6;
        match effect {
            PositioningEffect::Reversal => {
                params.insert("lost_motion_um", per_million(c[0]));
            }
            PositioningEffect::ReversalPosition => {
                params.insert("lost_motion_change_um_per_m", per_million(c[0]));
            }
            PositioningEffect::ReversalThermal => {
                params.insert("lost_motion_change_um_per_degc", per_million(c[0]));
            }
            PositioningEffect::ThermalLag => {
                params.insert("tau_min", self.searched.lag_tau.unwrap_or(0.0) / 60.0);
            }
            PositioningEffect::ThermalScale => {
                params.insert("expansion_change_ppm_per_degc", per_million(c[0]));
            }
            PositioningEffect::ThermalOffset => {
                params.insert("offset_um_per_degc", per_million(c[0]));
            }
            PositioningEffect::SecondHeatSource => {
                params.insert("expansion_um_per_m", per_million(c[0]));
                params.insert("tau_min", self.searched.heat_tau.unwrap_or(0.0) / 60.0);
            }
            PositioningEffect::Periodic => {
                params.insert("period_mm", self.searched.period.unwrap_or(0.0) / M_PER_MM);
                params.insert("amplitude_um", per_million(c[0].hypot(c[1])));
                params.insert("phase_deg", c[1].atan2(c[0]).to_degrees());
            }
            PositioningEffect::NonlinearScale => {
                params.insert("quadratic_um", per_million(c[0]));
                params.insert("cubic_um", per_million(c[1]));
            }
            PositioningEffect::TimeDrift => {
                params.insert("rate_um_per_h", per_million(c[0]));
            }
        }
        params
    }
}

fn association_json(a: &Option<Association>, slope_unit: &str, scale: Real) -> Value {
    match a {
        None => Value::Null,
        Some(a) => json!({
            format!("slope_{slope_unit}"): round(a.slope * scale),
            "correlation": round(a.correlation),
            "t": round(a.t),
        }),
    }
}

impl PositioningDiscovery {
    /// The base model's name.
    fn base_name(&self) -> &'static str {
        if self.problem.temperature.is_some() {
            "profile + nominal expansion"
        } else {
            "profile"
        }
    }

    /// The model after the first `k` accepted effects, by name.
    fn model_name(&self, k: usize) -> String {
        let mut name = self.base_name().to_string();
        for step in &self.selection.steps[..k] {
            name.push_str(" + ");
            name.push_str(step.effect.id());
        }
        name
    }

    /// The base model and each accepted effect in turn, with the residual it leaves.
    pub fn residual_steps(&self) -> Vec<ResidualStep<'_>> {
        self.selection
            .residual_steps(|k| self.model_name(k), |fit| &fit.residuals)
    }

    /// The accepted effects in order.
    pub fn accepted(&self) -> Vec<PositioningEffect> {
        self.selection.effects()
    }

    /// The effects tested in the last round and not accepted, with their held-out RMS (m).
    pub fn rejected(&self) -> &[(PositioningEffect, Real)] {
        &self.selection.rejected
    }

    /// The effects the file cannot show, with why.
    pub fn untestable(&self) -> &[(PositioningEffect, String)] {
        self.problem.untestable()
    }

    /// The final model's score.
    pub fn final_score(&self) -> &Score {
        self.selection.last().0
    }

    /// The base model's score.
    pub fn baseline_score(&self) -> &Score {
        &self.selection.baseline.0
    }

    /// The final model's parameters of an accepted effect.
    pub fn final_params(&self, effect: PositioningEffect) -> Option<BTreeMap<&'static str, Real>> {
        let fit = self.selection.last().1;
        fit.effects.contains(&effect).then(|| fit.params(effect))
    }

    fn baseline_params(&self, fit: &PositioningFit) -> Value {
        let mut params = serde_json::Map::new();
        if self.problem.temperature.is_some() {
            params.insert(
                "expansion_ppm_per_degc".into(),
                round(self.problem.options.expansion * 1e6),
            );
        }
        if let Some(t) = fit.reference_temperature {
            params.insert("reference_temperature_degc".into(), round(t));
        }
        params.insert("profile_knots".into(), json!(fit.reference.knots.len()));
        Value::Object(params)
    }

    /// The report with stable keys.
    pub fn to_json(&self) -> Value {
        let um = |v: Real| round(v / M_PER_UM);
        let (base_score, base_fit) = &self.selection.baseline;
        let (knots, values) = base_fit.profile();
        let steps: Vec<Value> = self
            .selection
            .steps
            .iter()
            .zip(self.selection.gains())
            .map(|(step, (gain, pct))| {
                json!({
                    "effect": step.effect.id(),
                    "together_with": step.together_with.map(PositioningEffect::id),
                    "cause": step.effect.cause(),
                    "evidence": step.evidence,
                    "params": params_json(&step.fit.params(step.effect)),
                    "rms_um": um(step.score.rms),
                    "cv_rms_um": um(step.score.cv_rms),
                    "gain_um": um(gain),
                    "gain_pct": round(pct),
                })
            })
            .collect();
        let (final_score, final_fit) = self.selection.last();
        let final_params: serde_json::Map<String, Value> = final_fit
            .effects
            .iter()
            .map(|&e| (e.id().to_string(), params_json(&final_fit.params(e))))
            .collect();
        json!({
            "kind": "positioning",
            "n_samples": self.problem.x.len(),
            "n_runs": self.problem.run_labels.len(),
            "axis": self.problem.axis.map(|a| a.to_string()),
            "sensor": self.problem.sensor,
            "validation": {
                "scheme": self.problem.folds.scheme,
                "folds": self.problem.folds.count,
                "rule": engine::RULE,
            },
            "baseline": {
                "model": self.base_name(),
                "reference_run": self.problem.run_labels[base_fit.reference.run],
                "params": self.baseline_params(base_fit),
                "profile": {
                    "positions_mm": knots.iter().map(|k| round(k / M_PER_MM)).collect::<Vec<_>>(),
                    "values_um": values.iter().map(|v| um(*v)).collect::<Vec<_>>(),
                },
                "rms_um": um(base_score.rms),
                "cv_rms_um": um(base_score.cv_rms),
            },
            "steps": steps,
            "rejected": self.selection.rejected.iter().map(|(e, cv)| json!({
                "effect": e.id(),
                "cv_rms_um": um(*cv),
            })).collect::<Vec<_>>(),
            "untestable": self.problem.untestable.iter().map(|(e, why)| json!({
                "effect": e.id(),
                "reason": why,
            })).collect::<Vec<_>>(),
            "final": {
                "model": self.model_name(self.selection.steps.len()),
                "params": Value::Object(final_params),
                "rms_um": um(final_score.rms),
                "cv_rms_um": um(final_score.cv_rms),
            },
            "diagnostics": {
                "baseline": self.diagnostics_json(base_fit),
                "final": self.diagnostics_json(final_fit),
            },
        })
    }

    fn diagnostics_json(&self, fit: &PositioningFit) -> Value {
        let d = self.problem.diagnose(fit);
        let um = |v: Real| round(v / M_PER_UM);
        json!({
            "rms_um": um(d.rms),
            "position": {
                "targets": d.by_target.iter().map(|t| json!({
                    "target_mm": round(t.target / M_PER_MM),
                    "mean_up_um": t.mean_up.map(um),
                    "mean_down_um": t.mean_down.map(um),
                    "rms_um": um(t.rms),
                    "n": t.count,
                })).collect::<Vec<_>>(),
                "periodogram": d.periodogram.map(|(p, a, f)| json!({
                    "period_mm": round(p / M_PER_MM),
                    "amplitude_um": um(a),
                    "f_statistic": round(f),
                })),
                "curvature_f_statistic": d.curvature_f.map(round),
            },
            "direction": d.direction.map(|(diff, se)| json!({
                "up_minus_down_um": um(diff),
                "standard_error_um": um(se),
            })),
            "runs": d.runs.iter().map(|(label, mean, rms, t)| json!({
                "run": label,
                "mean_um": um(*mean),
                "rms_um": um(*rms),
                "temperature_degc": t.map(round),
            })).collect::<Vec<_>>(),
            "time": association_json(&d.time, "um_per_h", 3600.0 / M_PER_UM),
            "temperature": association_json(&d.temperature, "um_per_degc", 1.0 / M_PER_UM),
            "position_x_temperature": association_json(&d.position_x_temperature, "ppm_per_degc", 1e6),
            "lagged_temperature": d.lagged_temperature.map(|(tau, a)| json!({
                "tau_min": round(tau / 60.0),
                "correlation": round(a.correlation),
                "t": round(a.t),
            })),
            "activity": d.activity.map(|(tau, a)| json!({
                "tau_min": round(tau / 60.0),
                "correlation": round(a.correlation),
                "t": round(a.t),
            })),
            "reversal_x_position": association_json(&d.reversal_x_position, "um_per_m", 1e6),
            "reversal_x_temperature": association_json(&d.reversal_x_temperature, "um_per_degc", 1.0 / M_PER_UM),
        })
    }

    /// The report for people.
    pub fn to_text(&self) -> String {
        let um = |v: Real| v / M_PER_UM;
        let (base_score, base_fit) = &self.selection.baseline;
        let mut out = String::new();
        let axis = self
            .problem
            .axis
            .map_or_else(|| "axis not named".to_string(), |a| format!("axis {a}"));
        out.push_str(&format!(
            "Model discovery, positioning table ({axis}): {} readings in {} runs\n",
            self.problem.x.len(),
            self.problem.run_labels.len()
        ));
        out.push_str(&format!(
            "Held-out data: {} ({} folds); {}.\n\n",
            self.problem.folds.scheme,
            self.problem.folds.count,
            engine::RULE
        ));
        out.push_str(&format!(
            "Base model: {} — profile through {} targets of run {}",
            self.base_name(),
            base_fit.reference.knots.len(),
            self.problem.run_labels[base_fit.reference.run]
        ));
        if let (Some(t), Some(sensor)) = (base_fit.reference_temperature, &self.problem.sensor) {
            out.push_str(&format!(
                ", {:.1} µm/(m·°C) × x × (temp_{sensor} − {t:.2} °C)",
                self.problem.options.expansion * 1e6
            ));
        }
        out.push_str(&format!(
            "\n  RMS {:.3} µm, held-out RMS {:.3} µm\n",
            um(base_score.rms),
            um(base_score.cv_rms)
        ));
        let d = self.problem.diagnose(base_fit);
        out.push_str("\nWhat the base model leaves:\n");
        for effect in PositioningEffect::ALL {
            if let Some(text) = d.evidence(effect) {
                out.push_str(&format!("  {:<19} {text}\n", effect.id()));
            }
        }
        out.push_str("\nAccepted, in order:\n");
        if self.selection.steps.is_empty() {
            out.push_str("  nothing: no effect lowers the held-out RMS more than noise can\n");
        }
        for (step, (gain, pct)) in self.selection.steps.iter().zip(self.selection.gains()) {
            let params = step
                .fit
                .params(step.effect)
                .iter()
                .map(|(k, v)| format!("{k} = {v:.3}"))
                .collect::<Vec<_>>()
                .join(", ");
            let together = step.together_with.map_or_else(String::new, |other| {
                format!(
                    " (accepted together with {}: neither passes alone)",
                    other.id()
                )
            });
            out.push_str(&format!(
                "  + {}{together}: {params}\n      cause: {}\n      held-out RMS {:.3} µm (gain {:.3} µm, {:.1} %)\n",
                step.effect.id(),
                step.effect.cause(),
                um(step.score.cv_rms),
                um(gain),
                pct
            ));
        }
        if !self.selection.rejected.is_empty() {
            out.push_str("\nTested and rejected (held-out RMS):\n");
            for (effect, cv) in &self.selection.rejected {
                out.push_str(&format!("  {:<19} {:.3} µm\n", effect.id(), um(*cv)));
            }
        }
        if !self.problem.untestable.is_empty() {
            out.push_str("\nCannot be tested with this file:\n");
            for (effect, why) in &self.problem.untestable {
                out.push_str(&format!("  {:<19} {why}\n", effect.id()));
            }
        }
        let final_score = self.selection.last().0;
        out.push_str(&format!(
            "\nFinal model: {}\n  RMS {:.3} µm, held-out RMS {:.3} µm\n",
            self.model_name(self.selection.steps.len()),
            um(final_score.rms),
            um(final_score.cv_rms)
        ));
        out
    }
}

impl PositioningDiscovery {
    /// The extended model as a scenario fragment: the axis's positioning error
    /// `E<axis><axis>` at the reference temperature (profile table, plus the accepted
    /// reversal, cyclic and polynomial terms) and, as comments, the thermal and time terms the
    /// scenario schema cannot express yet. With `extends` (a scenario path relative to the
    /// fragment) the fragment is a scenario that `mtwin run` simulates: the base scenario with
    /// this error replacing its own. `source` names the table in the header.
    pub fn to_scenario_fragment(
        &self,
        source: &str,
        extends: Option<&str>,
    ) -> Result<String, DiscoveryError> {
        let axis = self.problem.axis.ok_or_else(|| {
            DiscoveryError(
                "--write-model: the table has no axis column, so the error's name (EXX, EYY or EZZ) is unknown"
                    .into(),
            )
        })?;
        let (score, fit) = self.selection.last();
        let (knots, values) = fit.profile();
        // The profile is the error at the reference temperature; the twin's thermal model
        // expands from 20 °C, so move it there with the base model's nominal expansion.
        let to_20 = fit
            .reference_temperature
            .map_or(0.0, |t| self.problem.options.expansion * (t - 20.0));
        let values: Vec<Real> = knots
            .iter()
            .zip(values)
            .map(|(x, v)| v - to_20 * x)
            .collect();
        let source: String = source.chars().filter(|c| !c.is_control()).collect();
        let number = |v: Real| fixed(v, 4);
        let list = |values: Vec<Real>| {
            values
                .into_iter()
                .map(number)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut out = String::new();
        out.push_str(&format!(
            "# Extended model found by `mtwin discover positioning {source}`:\n# {} (held-out RMS {} µm; base model {} µm).\n",
            self.model_name(self.selection.steps.len()),
            fixed(score.cv_rms / M_PER_UM, 3),
            fixed(self.selection.baseline.0.cv_rms / M_PER_UM, 3)
        ));
        if let Some(t) = fit.reference_temperature {
            out.push_str(&format!(
                "# E{axis}{axis} below is the error at 20 °C: the profile at the reference run's {} °C less\n# the nominal expansion ({} µm/(m·°C)) between the two.\n",
                fixed(t, 2),
                fixed(self.problem.options.expansion * 1e6, 2)
            ));
        }
        if let Some(base) = extends {
            out.push_str(&format!(
                "schema = 1\nextends = {}\n",
                toml::Value::String(base.replace('\\', "/"))
            ));
        } else {
            out.push_str(
                "# Add `schema = 1` and `extends = \"<the machine's scenario>\"` to run it.\n",
            );
        }
        out.push_str(&format!("\n[errors.E{axis}{axis}]\n"));
        let mm = |v: &Real| v / M_PER_MM;
        let um = |v: &Real| v / M_PER_UM;
        if knots.len() == 1 {
            out.push_str(&format!("constant_um = {}\n", number(values[0] / M_PER_UM)));
        } else {
            out.push_str(&format!(
                "table = {{ positions_mm = [{}], values_um = [{}], interpolation = \"linear\" }}\n",
                list(knots.iter().map(mm).collect()),
                list(values.iter().map(um).collect())
            ));
        }
        let mut comments = Vec::new();
        for &effect in &fit.effects {
            let p = fit.params(effect);
            match effect {
                PositioningEffect::Reversal => {
                    out.push_str(&format!("reversal_um = {}\n", number(p["lost_motion_um"])));
                }
                PositioningEffect::Periodic => out.push_str(&format!(
                    "harmonic = [{{ period_mm = {}, amplitude_um = {}, phase_deg = {} }}]\n",
                    number(p["period_mm"]),
                    number(p["amplitude_um"]),
                    number(p["phase_deg"])
                )),
                PositioningEffect::NonlinearScale => {
                    // q2·ξ² + q3·ξ³ with ξ = (x − c)/h, expanded in powers of x (mm).
                    let (q2, q3) = (p["quadratic_um"], p["cubic_um"]);
                    let (c, h) = (
                        self.problem.centre / M_PER_MM,
                        self.problem.half_range / M_PER_MM,
                    );
                    let coefficients = [
                        q2 * c * c / (h * h) - q3 * c.powi(3) / h.powi(3),
                        -2.0 * q2 * c / (h * h) + 3.0 * q3 * c * c / h.powi(3),
                        q2 / (h * h) - 3.0 * q3 * c / h.powi(3),
                        q3 / h.powi(3),
                    ];
                    out.push_str(&format!(
                        "polynomial_um = [{}]\n",
                        coefficients
                            .iter()
                            .map(|v| format!("{v:e}"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ));
                }
                _ => comments.push(format!(
                    "#   {}: {}",
                    effect.id(),
                    p.iter()
                        .map(|(k, v)| format!("{k} = {}", number(*v)))
                        .collect::<Vec<_>>()
                        .join(", ")
                )),
            }
        }
        if !comments.is_empty() {
            out.push_str(
                "\n# Found but not expressible in a scenario yet (the twin's thermal network is not fitted\n# by discovery, and error functions have no temperature or time input):\n",
            );
            for line in comments {
                out.push_str(&line);
                out.push('\n');
            }
        }
        Ok(out)
    }
}
