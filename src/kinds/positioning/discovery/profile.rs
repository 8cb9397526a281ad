//! The training sum of squares as a function of one time constant, for the τ searches
//! ([`PositioningProblem::sse_profile`]), without a full least squares per trial.
//!
//! A trial time constant changes only some columns of the design (those built on the lagged
//! temperature or the heating response) and, for `thermal_lag`, the nominal expansion the
//! target subtracts; the others (the profile, the lost motion, a time drift …) are the same
//! at every trial. Their span is computed once, as the left singular vectors of the fixed
//! columns (each scaled to unit norm) above the same relative rank cut the full solve uses;
//! a trial then projects only its changing columns and its target off that span and fits
//! what is left. With P the projection off the fixed span, the least-squares residual of
//! [F V]·c ≈ t is that of P·V·c ≈ P·t (the fixed coefficients absorb whatever lies in their
//! span), so the sum of squares is the full solve's up to round-off and rank-cut details; the
//! fit at the chosen τ is the full solve.

use super::fit::Searched;
use super::problem::Reference;
use super::{PositioningEffect, PositioningProblem};
use crate::discovery::least_squares::{Design, RANK_TOLERANCE};
use crate::math::Real;
use nalgebra::{DMatrix, DVector};

impl PositioningProblem {
    /// The training sum of squares of `effects` on the rows where `train` is true, as a
    /// function of the time constant `at` puts into the searched values (see the module
    /// documentation).
    pub(super) fn sse_profile<'a>(
        &'a self,
        effects: &'a [PositioningEffect],
        train: &'a [bool],
        reference: &'a Reference,
        at: impl Fn(Real) -> Searched + 'a,
    ) -> impl Fn(Real) -> Real + 'a {
        let rows: Vec<usize> = (0..self.x.len()).filter(|&i| train[i]).collect();
        // Which columns a time constant changes: compare two far apart.
        let (a, _, _) = self.columns(effects, reference, &at(600.0));
        let (b, _, _) = self.columns(effects, reference, &at(36_000.0));
        let fixed: Vec<bool> = a
            .iter()
            .zip(&b)
            .map(|(a, b)| rows.iter().all(|&i| a[i] == b[i]))
            .collect();
        let scaled = |column: &[Real]| -> Option<Vec<Real>> {
            let values: Vec<Real> = rows.iter().map(|&i| column[i]).collect();
            let norm = values.iter().map(|v| v * v).sum::<Real>().sqrt();
            (norm > 0.0).then(|| values.iter().map(|v| v / norm).collect())
        };
        let kept: Vec<Vec<Real>> = a
            .iter()
            .zip(&fixed)
            .filter(|(_, f)| **f)
            .filter_map(|(c, _)| scaled(c))
            .collect();
        let basis = span(&kept, rows.len());
        move |tau: Real| {
            let (columns, known, _) = self.columns(effects, reference, &at(tau));
            let project = |v: Vec<Real>| -> Vec<Real> {
                let mut v = DVector::from_vec(v);
                if let Some(u) = &basis {
                    // v − U·(Uᵀv), without forming Uᵀ.
                    let along = u.tr_mul(&v);
                    v.gemv(-1.0, u, &along, 1.0);
                }
                v.data.into()
            };
            let target = project(rows.iter().map(|&i| self.y[i] - known[i]).collect());
            let mut design = Design::new(rows.len());
            for (column, _) in columns.iter().zip(&fixed).filter(|(_, f)| !**f) {
                let original: Vec<Real> = rows.iter().map(|&i| column[i]).collect();
                let norm = original.iter().map(|v| v * v).sum::<Real>().sqrt();
                let projected = project(original);
                let left = projected.iter().map(|v| v * v).sum::<Real>().sqrt();
                // What the fixed columns already hold is no column of its own (the full
                // solve's rank cut).
                if left > RANK_TOLERANCE * norm {
                    design.push(projected);
                }
            }
            let c = design.solve(&target);
            let fitted = design.times(&c);
            target
                .iter()
                .zip(&fitted)
                .map(|(t, f)| (t - f).powi(2))
                .sum()
        }
    }
}

/// An orthonormal basis (rows × r) of the span of `columns` (each of length `rows`, scaled to
/// unit norm): the left singular vectors above the rank cut; `None` without columns.
fn span(columns: &[Vec<Real>], rows: usize) -> Option<DMatrix<Real>> {
    if columns.is_empty() || rows == 0 {
        return None;
    }
    let m = DMatrix::from_fn(rows, columns.len(), |i, j| columns[j][i]);
    let svd = m.svd(true, false);
    let u = svd.u.expect("computed");
    let largest = svd.singular_values.max();
    let keep: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&k| svd.singular_values[k] > largest * RANK_TOLERANCE)
        .collect();
    Some(DMatrix::from_fn(rows, keep.len(), |i, j| u[(i, keep[j])]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::positioning::{PositioningOptions, PositioningTable};

    /// A warm-up file: 4 bidirectional runs of 7 targets, 40 min apart, the nut sensor rising
    /// 3 °C with a 30 min time constant, the screw following it through a 20 min lag, 3 µm
    /// of lost motion and a little deterministic scatter.
    fn warmup() -> PositioningTable {
        let mut text =
            String::from("axis,run,direction,target_mm,deviation_um,time_min,temp_x_nut_degc\n");
        let (alpha, lag) = (11.7e-6, 20.0);
        let nut = |t: f64| 20.0 + 3.0 * (1.0 - (-t / 30.0).exp());
        // The lagged temperature in closed form for T = 20 + A(1 − e^(−t/a)) through a lag b.
        let screw = |t: f64| {
            20.0 + 3.0 * (1.0 - (30.0 * (-t / 30.0).exp() - lag * (-t / lag).exp()) / (30.0 - lag))
        };
        let mut k = 0;
        for run in 1..=4 {
            for (direction, sign) in [("+", 1.0), ("-", -1.0)] {
                for j in 0..7 {
                    let x = 5.0 + 125.0 * j as f64;
                    let t = 40.0 * (run - 1) as f64 + 0.1 * k as f64;
                    k += 1;
                    let deviation = alpha * x * 1e3 * (screw(t) - 20.0) - sign * 1.5
                        + 0.05 * ((k * 7919) % 13) as f64 / 13.0;
                    text.push_str(&format!(
                        "X,{run},{direction},{x},{deviation:.6},{t:.6},{:.6}\n",
                        nut(t)
                    ));
                }
            }
        }
        PositioningTable::parse(text.as_bytes(), "warmup.csv").unwrap()
    }

    #[test]
    fn the_profile_equals_the_full_solve_at_every_time_constant() {
        let table = warmup();
        let problem = PositioningProblem::new(&table, PositioningOptions::default()).unwrap();
        let effects = [
            PositioningEffect::Reversal,
            PositioningEffect::ThermalLag,
            PositioningEffect::ThermalScale,
        ];
        for fold in [None, Some(0), Some(2)] {
            let train: Vec<bool> = match fold {
                None => vec![true; table.readings.len()],
                Some(k) => problem.folds.training(k),
            };
            let reference = problem.reference(&train);
            let at = |tau: Real| Searched {
                lag_tau: Some(tau),
                ..Searched::default()
            };
            let profile = problem.sse_profile(&effects, &train, &reference, at);
            for tau_min in [1.0, 5.0, 20.0, 60.0, 300.0] {
                let full = problem
                    .solve(&effects, &train, &reference, &at(tau_min * 60.0))
                    .2;
                let fast = profile(tau_min * 60.0);
                assert!(
                    (fast - full).abs() <= 1e-9 * full + 1e-24,
                    "fold {fold:?}, τ {tau_min} min: {fast} against {full}"
                );
            }
        }
    }
}
