//! Residual diagnostics: what a fit leaves, by target, direction, run, position, time and
//! temperature, and the rules that propose effects from it.

use super::{
    PROPOSAL_T, PositioningEffect, PositioningFit, PositioningProblem, SAME_POSITION, TAU_GRID,
};
use crate::discovery::engine;
use crate::discovery::least_squares::Design;
use crate::math::{M_PER_MM, M_PER_UM, Real};
use std::f64::consts::TAU;

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

/// A periodogram peak removing at most this fraction of the residual's sum of squares is
/// round-off, not a period.
const NOTHING_PERIODIC: Real = 1e-12;

/// What is left after a model, and where.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostics {
    /// RMS of the residual (m).
    pub rms: Real,
    /// Per target, in order of position.
    pub by_target: Vec<TargetResidual>,
    /// Strongest cyclic component: period (m), amplitude (m), F statistic (2 and n − 3 dof);
    /// `None` on 6 readings or fewer, or when the residual has nothing a sinusoid can remove
    /// (it sums to zero at every position).
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
    /// Residual against position × the temperature's rate of change (slope per m·K/s): a
    /// sensor lagging the structure by τ leaves `α·τ·x·dT/dt`.
    pub position_x_rate: Option<Association>,
    /// Best activity time constant (s): residual against x·(1 − e^(−t/τ)).
    pub activity: Option<(Real, Association)>,
    /// Direction-signed residual against position.
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
        // No periodogram when a sinusoid removes nothing but round-off (less than
        // NOTHING_PERIODIC of the sum of squares): when a knot at every target holds each
        // target's mean, the residual sums to zero at every position and the peak's period
        // would be whichever frequency the rounding favours.
        let peak = (n > 6)
            .then(|| self.periodogram_peak(&vec![true; n], r))
            .filter(|&(_, fraction)| fraction > NOTHING_PERIODIC);
        let periodogram = peak.map(|(f, fraction)| {
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
        // The temperature the fit's thermal terms use (through thermal_lag and sensor_lag).
        let sensor_lag = fit.searched.sensor_in(&fit.effects);
        let rise: Option<Vec<Real>> = self
            .driver(fit.searched.lag_in(&fit.effects), sensor_lag)
            .map(|t| {
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
                let lagged = self.driver(Some(tau), None).expect("has temperature");
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
            position_x_rate: self.rate.as_ref().and_then(|rate| {
                let z: Vec<Real> = (0..n).map(|i| self.x[i] * rate[i]).collect();
                associate(r, &z)
            }),
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
            PositioningEffect::SensorLag => association(
                &self.position_x_rate,
                "position × rate of change of the temperature",
            ),
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
