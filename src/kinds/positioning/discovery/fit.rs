//! Fitting: the columns of the base model and of each effect, the linear fit on a fold's
//! training readings, the fitted model and its parameters in file units.

use super::problem::Reference;
use super::profile::TAU_PROBES;
use super::{PositioningEffect, PositioningProblem};
use crate::discovery::least_squares::Design;
use crate::math::{M_PER_MM, Real};
use std::collections::BTreeMap;
use std::f64::consts::TAU;

/// The values of the searched parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Searched {
    pub(super) lag_tau: Option<Real>,
    pub(super) sensor_tau: Option<Real>,
    pub(super) heat_tau: Option<Real>,
    pub(super) period: Option<Real>,
}

impl Searched {
    /// The structure's lag behind the sensor (s), when `effects` has `thermal_lag`.
    pub(super) fn lag_in(&self, effects: &[PositioningEffect]) -> Option<Real> {
        self.lag_tau
            .filter(|_| effects.contains(&PositioningEffect::ThermalLag))
    }

    /// The sensor's lag behind the structure (s), when `effects` has `sensor_lag`.
    pub(super) fn sensor_in(&self, effects: &[PositioningEffect]) -> Option<Real> {
        self.sensor_tau
            .filter(|_| effects.contains(&PositioningEffect::SensorLag))
    }

    fn has(&self, effect: PositioningEffect) -> bool {
        match effect {
            PositioningEffect::ThermalLag => self.lag_tau.is_some(),
            PositioningEffect::SensorLag => self.sensor_tau.is_some(),
            PositioningEffect::SecondHeatSource => self.heat_tau.is_some(),
            PositioningEffect::Periodic => self.period.is_some(),
            _ => true,
        }
    }
}

/// A fitted positioning model.
#[derive(Clone, Debug)]
pub struct PositioningFit {
    pub(super) effects: Vec<PositioningEffect>,
    pub(super) reference: Reference,
    /// The reference temperature (°C): the reference run's mean (lagged, with `thermal_lag`).
    pub(super) reference_temperature: Option<Real>,
    pub(super) searched: Searched,
    /// Profile values at the knots (m), then each effect's coefficients in order.
    pub(super) coefficients: Vec<Real>,
    pub(super) residuals: Vec<Real>,
}

impl PositioningProblem {
    /// Every reading's columns (profile hats, then each effect's), the known part of the
    /// prediction (nominal expansion) and the reference temperature.
    pub(super) fn columns(
        &self,
        effects: &[PositioningEffect],
        reference: &Reference,
        searched: &Searched,
    ) -> (Vec<Vec<Real>>, Vec<Real>, Option<Real>) {
        let mut columns = self.hats(&reference.knots);
        let (effect_columns, known, reference_temperature) =
            self.effect_columns(effects, reference, searched);
        columns.extend(effect_columns);
        (columns, known, reference_temperature)
    }

    /// The profile's columns: every reading's piecewise-linear weights on the `knots`
    /// (constant beyond the ends).
    pub(super) fn hats(&self, knots: &[Real]) -> Vec<Vec<Real>> {
        let n = self.x.len();
        let mut columns: Vec<Vec<Real>> = vec![vec![0.0; n]; knots.len()];
        for (i, &x) in self.x.iter().enumerate() {
            let (j, a, b) = Self::hat_weights(knots, x);
            columns[j][i] = a;
            if j + 1 < knots.len() {
                columns[j + 1][i] = b;
            }
        }
        columns
    }

    /// Each effect's columns (in order), the known part of the prediction (nominal
    /// expansion) and the reference temperature: [`PositioningProblem::columns`] without the
    /// profile's.
    pub(super) fn effect_columns(
        &self,
        effects: &[PositioningEffect],
        reference: &Reference,
        searched: &Searched,
    ) -> (Vec<Vec<Real>>, Vec<Real>, Option<Real>) {
        let (rise, reference_temperature) = self.rise(effects, reference, searched);
        let known = self.known(&rise);
        let columns = self.columns_given(effects, reference, searched, &rise);
        (columns, known, reference_temperature)
    }

    /// Every reading's temperature rise over the reference temperature (°C; zero without
    /// temperatures), the driving temperature lagged as `searched` says for `effects`, and
    /// the reference temperature: the reference run's mean.
    pub(super) fn rise(
        &self,
        effects: &[PositioningEffect],
        reference: &Reference,
        searched: &Searched,
    ) -> (Vec<Real>, Option<Real>) {
        let n = self.x.len();
        let (lag, sensor) = (searched.lag_in(effects), searched.sensor_in(effects));
        let held = self.drivers.get([lag, sensor], || self.driver(lag, sensor));
        let driver: Option<&Vec<Real>> = held.as_ref().as_ref();
        let reference_temperature = driver.map(|d| {
            let (sum, count) = (0..n)
                .filter(|&i| self.run[i] == reference.run)
                .fold((0.0, 0usize), |(s, c), i| (s + d[i], c + 1));
            sum / count.max(1) as Real
        });
        let rise: Vec<Real> = match (driver, reference_temperature) {
            (Some(d), Some(t_ref)) => d.iter().map(|t| t - t_ref).collect(),
            _ => vec![0.0; n],
        };
        (rise, reference_temperature)
    }

    /// The known part of every reading's prediction: the nominal expansion for `rise`.
    pub(super) fn known(&self, rise: &[Real]) -> Vec<Real> {
        self.x
            .iter()
            .zip(rise)
            .map(|(x, r)| self.options.expansion * x * r)
            .collect()
    }

    /// The columns of `effects` (in order) on the temperature rise `rise` (from
    /// [`PositioningProblem::rise`] for the whole model: `effects` may be a part of it; empty
    /// when none of `effects` [uses it](PositioningEffect::uses_rise)).
    pub(super) fn columns_given(
        &self,
        effects: &[PositioningEffect],
        reference: &Reference,
        searched: &Searched,
        rise: &[Real],
    ) -> Vec<Vec<Real>> {
        let n = self.x.len();
        let mut columns: Vec<Vec<Real>> = Vec::new();
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
                PositioningEffect::ThermalLag | PositioningEffect::SensorLag => {}
                PositioningEffect::ThermalScale => columns.push(map(&|i| self.x[i] * rise[i])),
                PositioningEffect::ThermalOffset => columns.push(rise.to_vec()),
                PositioningEffect::SecondHeatSource => {
                    let tau = searched.heat_tau.expect("searched first");
                    let g = self
                        .activities
                        .get([Some(tau), None], || self.activity(tau));
                    columns.push(map(&|i| self.x[i] * g[i]));
                }
                PositioningEffect::Periodic => {
                    let w = TAU / searched.period.expect("searched first");
                    let (positions, index) = &self.positions;
                    let at: Vec<(Real, Real)> =
                        positions.iter().map(|&x| (w * x).sin_cos()).collect();
                    columns.push(index.iter().map(|&k| at[k].0).collect());
                    columns.push(index.iter().map(|&k| at[k].1).collect());
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
        columns
    }

    /// The linear fit of `effects` with `searched` fixed: coefficients, every residual and the
    /// training sum of squares.
    pub(super) fn solve(
        &self,
        effects: &[PositioningEffect],
        train: &[bool],
        reference: &Reference,
        searched: &Searched,
    ) -> (Vec<Real>, Vec<Real>, Real, Option<Real>) {
        let (columns, known, reference_temperature) = self.columns(effects, reference, searched);
        let rows: Vec<usize> = (0..self.x.len()).filter(|&i| train[i]).collect();
        // The profile's columns lead every design on a fold: their Householder steps are taken
        // once per fold ([`Design::solve_after`], bit for bit the whole solve).
        let hats = reference.knots.len();
        let lead = self
            .hat_prefixes
            .get_for_knots(train, &reference.knots, || {
                let mut design = Design::new(rows.len());
                for column in &columns[..hats] {
                    design.push(rows.iter().map(|&i| column[i]).collect());
                }
                design.prefix()
            });
        let mut design = Design::new(rows.len());
        for column in &columns[hats..] {
            design.push(rows.iter().map(|&i| column[i]).collect());
        }
        let target: Vec<Real> = rows.iter().map(|&i| self.y[i] - known[i]).collect();
        let coefficients = design.solve_after(&lead.1, &target);
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

    /// Searches every searched parameter (in order, twice when there are several, each with
    /// the others held), then fits.
    pub(super) fn fit_with(&self, effects: &[PositioningEffect], train: &[bool]) -> PositioningFit {
        let reference = self.reference(train);
        let mut searched = Searched::default();
        let shortest_heating = if effects.contains(&PositioningEffect::SecondHeatSource) {
            self.shortest_heating_tau(train)
        } else {
            0.0
        };
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
                let held = searched;
                match effect {
                    PositioningEffect::ThermalLag => {
                        let (sse, _) =
                            self.sse_profile(&active, train, &reference, TAU_PROBES, move |tau| {
                                Searched {
                                    lag_tau: Some(tau),
                                    ..held
                                }
                            });
                        searched.lag_tau = Some(self.search_tau(0.0, sse));
                    }
                    PositioningEffect::SensorLag => {
                        let (sse, _) =
                            self.sse_profile(&active, train, &reference, TAU_PROBES, move |tau| {
                                Searched {
                                    sensor_tau: Some(tau),
                                    ..held
                                }
                            });
                        searched.sensor_tau = Some(self.search_tau(0.0, sse));
                    }
                    PositioningEffect::SecondHeatSource => {
                        let (sse, _) =
                            self.sse_profile(&active, train, &reference, TAU_PROBES, move |tau| {
                                Searched {
                                    heat_tau: Some(tau),
                                    ..held
                                }
                            });
                        searched.heat_tau = Some(self.search_tau(shortest_heating, sse));
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

impl PositioningFit {
    /// The coefficients of `effect` (in SI), if it is in the fit.
    pub(super) fn coefficients_of(&self, effect: PositioningEffect) -> Option<&[Real]> {
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
            PositioningEffect::SensorLag => {
                params.insert("tau_min", self.searched.sensor_tau.unwrap_or(0.0) / 60.0);
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
