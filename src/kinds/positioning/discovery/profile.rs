//! The training sum of squares as a function of one searched value (a time constant, or the
//! frequency of `periodic`) ([`PositioningProblem::sse_profile`]), without a full least
//! squares per trial.
//!
//! A trial value changes only some columns of the design (those built on the lagged
//! temperature or the heating response, or the sine and cosine of the cyclic error) and, for
//! `thermal_lag`, the nominal expansion the target subtracts; the others (the profile, the
//! lost motion, a time drift …) are the same at every trial. Their span is computed once: the
//! profile's (the same for every model on a fold, so kept per fold; through its tridiagonal
//! normal equations when its hats are well conditioned, else as the left singular vectors of
//! its columns above the rank cut the full solve uses: [`HatSpan`]), the fixed effects' added
//! to it by Gram–Schmidt with that cut; a trial then projects only its changing columns and its
//! target off that span and fits what is left.
//! With P the projection off the fixed span, the least-squares residual of [F V]·c ≈ t is that
//! of P·V·c ≈ P·t (the fixed coefficients absorb whatever lies in their span), so the sum of
//! squares is the full solve's up to round-off and rank-cut details; the fit at the chosen
//! value is the full solve.

use super::fit::Searched;
use super::hat_span::{Banded, HatSpan};
use super::problem::Reference;
use super::{PositioningEffect, PositioningProblem};
use crate::discovery::least_squares::RANK_TOLERANCE;
use crate::math::{Real, dot};
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

impl PositioningProblem {
    /// The training sum of squares of `effects` on the rows where `train` is true, as a
    /// function of the value `at` puts into the searched values (see the module
    /// documentation). The columns that value changes are those that differ between the two
    /// `probes` ([`TAU_PROBES`], [`FREQUENCY_PROBES`]).
    ///
    /// Also, when the value changes no known part (a period, not a lag), the training
    /// residual of the model without the changing columns (the projected target), one value
    /// per training row in order: what the period's periodogram searches.
    pub(super) fn sse_profile<'a>(
        &'a self,
        effects: &'a [PositioningEffect],
        train: &'a [bool],
        reference: &'a Reference,
        probes: [Real; 2],
        at: impl Fn(Real) -> Searched + 'a,
    ) -> (impl Fn(Real) -> Real + 'a, Option<Vec<Real>>) {
        let rows: Vec<usize> = (0..self.x.len()).filter(|&i| train[i]).collect();
        let differ = |a: &[Real], b: &[Real]| rows.iter().any(|&i| a[i] != b[i]);
        // The profile's columns never change; of the effects, those whose columns differ
        // between the probes do, and the nominal expansion when the temperature's lag does.
        let (searched_a, searched_b) = (at(probes[0]), at(probes[1]));
        let (rise_a, _) = self.rise(effects, reference, &searched_a);
        let (rise_b, _) = self.rise(effects, reference, &searched_b);
        let known_changes = differ(&self.known(&rise_a), &self.known(&rise_b));
        let mut fixed_columns = Vec::new();
        let mut changing: Vec<PositioningEffect> = Vec::new();
        for &effect in effects {
            let a = self.columns_given(&[effect], reference, &searched_a, &rise_a);
            let b = self.columns_given(&[effect], reference, &searched_b, &rise_b);
            if a.iter().zip(&b).any(|(a, b)| differ(a, b)) {
                changing.push(effect);
            } else {
                fixed_columns.extend(a);
            }
        }
        let scaled = |column: &[Real]| -> Option<Vec<Real>> {
            let values: Vec<Real> = rows.iter().map(|&i| column[i]).collect();
            let norm = values.iter().map(|v| v * v).sum::<Real>().sqrt();
            (norm > 0.0).then(|| values.iter().map(|v| v / norm).collect())
        };
        // The profile's span depends on the training set only: taken once per fold.
        let hats = self.hat_spans.get_for_knots(train, &reference.knots, || {
            self.hat_span(&reference.knots, &rows)
        });
        let kept: Vec<Vec<Real>> = fixed_columns.iter().filter_map(|c| scaled(c)).collect();
        let fixed = FixedSpan::new(&hats.1, &kept, rows.len());
        let project = move |mut v: Vec<Real>| -> Vec<Real> {
            fixed.project(&mut v);
            v
        };
        let on_rows =
            move |values: &[Real]| -> Vec<Real> { rows.iter().map(|&i| values[i]).collect() };
        let target_of = |known: &[Real]| -> Vec<Real> {
            self.y.iter().zip(known).map(|(y, k)| y - k).collect()
        };
        let fixed_target =
            (!known_changes).then(|| project(on_rows(&target_of(&self.known(&rise_a)))));
        let uses_rise = changing.iter().any(|e| e.uses_rise());
        let fixed_residual = fixed_target.clone();
        let sse = move |value: Real| {
            let searched = at(value);
            let rise = if known_changes || uses_rise {
                self.rise(effects, reference, &searched).0
            } else {
                Vec::new()
            };
            let target = match &fixed_target {
                Some(target) => target.clone(),
                None => project(on_rows(&target_of(&self.known(&rise)))),
            };
            let columns = self.columns_given(&changing, reference, &searched, &rise);
            // The changing columns off the fixed span, orthonormalised among themselves
            // (Gram–Schmidt, each orthogonalised twice); a column that the fixed ones and
            // those before it hold to RANK_TOLERANCE of its norm is none of its own (the
            // full solve's rank cut). The residual is the target off them all.
            let mut orthonormal: Vec<Vec<Real>> = Vec::with_capacity(columns.len());
            for column in &columns {
                let original: Vec<Real> = on_rows(column);
                let norm = dot(&original, &original).sqrt();
                let mut v = project(original);
                for _ in 0..2 {
                    for q in &orthonormal {
                        subtract_along(&mut v, q);
                    }
                }
                let left = dot(&v, &v).sqrt();
                if left > RANK_TOLERANCE * norm {
                    v.iter_mut().for_each(|x| *x /= left);
                    orthonormal.push(v);
                }
            }
            let mut residual = target;
            for q in &orthonormal {
                subtract_along(&mut residual, q);
            }
            dot(&residual, &residual)
        };
        (sse, fixed_residual)
    }
}

/// The span a search holds fixed: the profile's hats and the fixed effects' columns.
enum FixedSpan {
    /// The banded hats, and the fixed columns off them, orthonormal (Gram–Schmidt, twice).
    Banded(Arc<Banded>, Vec<Vec<Real>>),
    /// An orthonormal basis of it all (the hats' dense basis extended); `None` when empty.
    Dense(Option<DMatrix<Real>>),
}

impl FixedSpan {
    /// The span of `hats` and `columns` (each of length `rows`, unit norm): each column off the
    /// span and the columns before it by Gram–Schmidt (twice), kept when more than
    /// [`RANK_TOLERANCE`] of it is left, as a trial keeps its changing columns.
    fn new(hats: &HatSpan, columns: &[Vec<Real>], rows: usize) -> FixedSpan {
        match hats {
            HatSpan::Dense(basis) => FixedSpan::Dense(extend(basis.as_ref(), columns, rows)),
            HatSpan::Banded(banded) => {
                let mut added: Vec<Vec<Real>> = Vec::with_capacity(columns.len());
                for column in columns {
                    let mut v = column.clone();
                    for _ in 0..2 {
                        banded.project(&mut v);
                        for q in &added {
                            subtract_along(&mut v, q);
                        }
                    }
                    let left = dot(&v, &v).sqrt();
                    if left > RANK_TOLERANCE {
                        v.iter_mut().for_each(|x| *x /= left);
                        added.push(v);
                    }
                }
                FixedSpan::Banded(Arc::clone(banded), added)
            }
        }
    }

    /// `v` (one value per training row) off the span.
    fn project(&self, v: &mut [Real]) {
        match self {
            FixedSpan::Dense(Some(u)) => project_off(u, v),
            FixedSpan::Dense(None) => {}
            FixedSpan::Banded(banded, added) => {
                banded.project(v);
                for q in added {
                    subtract_along(v, q);
                }
            }
        }
    }
}

/// An orthonormal basis (rows × r) of the span of `basis` (orthonormal) and `columns` (each
/// of length `rows`, unit norm): each column off the basis and the columns before it by
/// Gram–Schmidt (twice), kept when more than [`RANK_TOLERANCE`] of it is left, as a trial
/// keeps its changing columns; `None` when nothing spans.
fn extend(
    basis: Option<&DMatrix<Real>>,
    columns: &[Vec<Real>],
    rows: usize,
) -> Option<DMatrix<Real>> {
    let mut added: Vec<Vec<Real>> = Vec::with_capacity(columns.len());
    for column in columns {
        let mut v = DVector::from_column_slice(column);
        for _ in 0..2 {
            if let Some(u) = basis {
                project_off(u, v.as_mut_slice());
            }
            for q in &added {
                subtract_along(v.as_mut_slice(), q);
            }
        }
        let left = v.norm();
        if left > RANK_TOLERANCE {
            v /= left;
            added.push(v.data.into());
        }
    }
    let known = basis.map_or(0, |u| u.ncols());
    if known + added.len() == 0 || rows == 0 {
        return None;
    }
    Some(DMatrix::from_fn(rows, known + added.len(), |i, j| {
        if j < known {
            basis.expect("known columns")[(i, j)]
        } else {
            added[j - known][i]
        }
    }))
}

/// `v` less its components along the orthonormal columns of `u`: v − U·(Uᵀv), each Uᵀv entry a
/// [`dot8`], then the columns taken off in order, as nalgebra's `tr_mul` and `gemv(−1, U, ·, 1)`
/// do it (bit for bit, tested), over slices the compiler vectorises.
fn project_off(u: &DMatrix<Real>, v: &mut [Real]) {
    let rows = v.len();
    debug_assert_eq!(u.nrows(), rows);
    let columns = u.as_slice();
    let along: Vec<Real> = columns.chunks_exact(rows).map(|c| dot8(c, v)).collect();
    for (c, a) in columns.chunks_exact(rows).zip(&along) {
        v.iter_mut().zip(c).for_each(|(v, c)| *v -= c * a);
    }
}

/// Σ aᵢbᵢ summed as nalgebra's `dot` sums it: eight running sums over blocks of eight, joined
/// as (s₀ + s₄) + (s₁ + s₅) + (s₂ + s₆) + (s₃ + s₇), then the remainder in order.
fn dot8(a: &[Real], b: &[Real]) -> Real {
    let mut sums = [0.0; 8];
    let (a_blocks, b_blocks) = (a.chunks_exact(8), b.chunks_exact(8));
    let (a_rest, b_rest) = (a_blocks.remainder(), b_blocks.remainder());
    for (x, y) in a_blocks.zip(b_blocks) {
        for k in 0..8 {
            sums[k] += x[k] * y[k];
        }
    }
    let mut total = 0.0;
    total += sums[0] + sums[4];
    total += sums[1] + sums[5];
    total += sums[2] + sums[6];
    total += sums[3] + sums[7];
    for (x, y) in a_rest.iter().zip(b_rest) {
        total += x * y;
    }
    total
}

/// `v` less its component along the unit vector `q`.
fn subtract_along(v: &mut [Real], q: &[Real]) {
    let d = dot(v, q);
    v.iter_mut().zip(q).for_each(|(v, q)| *v -= d * q);
}

/// Time constants (s) far apart: the columns a time constant changes differ between them
/// (10 min and 10 h).
pub(super) const TAU_PROBES: [Real; 2] = [600.0, 36_000.0];

/// Frequencies (1/m) whose sines differ at every position a file can hold: periods of π mm
/// and 10·e mm, irrational in millimetres, so that no grid of targets (whole millimetres,
/// 5 mm steps …) puts both on a whole number of cycles.
pub(super) const FREQUENCY_PROBES: [Real; 2] =
    [1e3 / std::f64::consts::PI, 1e2 / std::f64::consts::E];

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

    /// Four bidirectional runs of 7 targets in whole millimetres, each run's shifted by 17 mm
    /// from the last (the first run's are the profile's knots), 2 µm of lost motion, 1 µm of a
    /// 25 mm cyclic error and a little deterministic scatter.
    fn scattered() -> PositioningTable {
        let mut text = String::from("axis,run,direction,target_mm,deviation_um,time_min\n");
        let mut k = 0;
        for run in 1..=4 {
            for (direction, sign) in [("+", 1.0), ("-", -1.0)] {
                for j in 0..7 {
                    let x = 5.0 + 125.0 * j as f64 + 17.0 * (run - 1) as f64;
                    k += 1;
                    let deviation = 0.004 * x - sign * 1.0
                        + (std::f64::consts::TAU * x / 25.0).sin()
                        + 0.05 * ((k * 7919) % 13) as f64 / 13.0;
                    text.push_str(&format!(
                        "X,{run},{direction},{x},{deviation:.6},{:.1}\n",
                        0.5 * k as f64
                    ));
                }
            }
        }
        PositioningTable::parse(text.as_bytes(), "scattered.csv").unwrap()
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
            let (profile, _) = problem.sse_profile(&effects, &train, &reference, TAU_PROBES, at);
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

    #[test]
    fn the_period_profile_equals_the_full_solve_at_every_frequency() {
        // Targets in whole millimetres, moved from run to run (off the profile's knots, so the
        // cyclic term acts): the probes must still find the sine and cosine as the changing
        // columns.
        let table = scattered();
        let problem = PositioningProblem::new(&table, PositioningOptions::default()).unwrap();
        let effects = [
            PositioningEffect::Reversal,
            PositioningEffect::TimeDrift,
            PositioningEffect::Periodic,
        ];
        for fold in [None, Some(1)] {
            let train: Vec<bool> = match fold {
                None => vec![true; table.readings.len()],
                Some(k) => problem.folds.training(k),
            };
            let reference = problem.reference(&train);
            let at = |f: Real| Searched {
                period: Some(1.0 / f),
                ..Searched::default()
            };
            let (profile, fixed_residual) =
                problem.sse_profile(&effects, &train, &reference, FREQUENCY_PROBES, at);
            // The fixed part's residual is the model without the cyclic term's.
            let without = [PositioningEffect::Reversal, PositioningEffect::TimeDrift];
            let residuals = problem.solve(&without, &train, &reference, &at(1.0)).1;
            let expected: Vec<Real> = (0..residuals.len())
                .filter(|&i| train[i])
                .map(|i| residuals[i])
                .collect();
            let fixed_residual = fixed_residual.expect("a period changes no known part");
            let scale = dot(&expected, &expected).sqrt();
            for (a, b) in fixed_residual.iter().zip(&expected) {
                assert!(
                    (a - b).abs() <= 1e-9 * scale,
                    "fold {fold:?}: {a} against {b}"
                );
            }
            assert_eq!(fixed_residual.len(), expected.len());
            for period_mm in [7.3, 25.0, 100.0, 333.0] {
                let f = 1e3 / period_mm;
                let full = problem.solve(&effects, &train, &reference, &at(f)).2;
                let fast = profile(f);
                assert!(
                    (fast - full).abs() <= 1e-9 * full + 1e-24,
                    "fold {fold:?}, period {period_mm} mm: {fast} against {full}"
                );
            }
        }
    }

    #[test]
    fn the_projection_is_nalgebras_bit_for_bit() {
        // Lengths about the blocks of eight (7, 8, 9, 250 rows), values spread over
        // magnitudes so that any change of the order of the sums shows in the last bits.
        for rows in [7, 8, 9, 250] {
            let value = |i: usize, j: usize| {
                let k = (i * 7919 + j * 104_729) % 1009;
                (k as Real / 1009.0 - 0.5) * 10f64.powi((k % 7) as i32 - 3)
            };
            let u = DMatrix::from_fn(rows, 5, value);
            let v: Vec<Real> = (0..rows).map(|i| value(i, 11)).collect();
            let mut expected = DVector::from_column_slice(&v);
            let along = u.tr_mul(&expected);
            expected.gemv(-1.0, &u, &along, 1.0);
            let mut fast = v.clone();
            project_off(&u, &mut fast);
            for (a, b) in fast.iter().zip(expected.iter()) {
                assert_eq!(a.to_bits(), b.to_bits(), "{rows} rows: {a} against {b}");
            }
        }
    }

    #[test]
    fn a_column_the_span_holds_adds_nothing() {
        // Basis e₁ of R³; columns e₁ (held), (e₁ + e₂)/√2 (adds e₂) and (e₁ − e₂)/√2 (held by
        // e₁ and e₂ together): the extended basis is e₁, e₂, orthonormal.
        let e1 = DMatrix::from_column_slice(3, 1, &[1.0, 0.0, 0.0]);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let columns = vec![vec![1.0, 0.0, 0.0], vec![h, h, 0.0], vec![h, -h, 0.0]];
        let basis = extend(Some(&e1), &columns, 3).unwrap();
        assert_eq!(basis.ncols(), 2);
        let gram = basis.tr_mul(&basis);
        assert!((gram - DMatrix::<Real>::identity(2, 2)).abs().max() < 1e-15);
        assert!(basis[(2, 0)].abs() < 1e-15 && basis[(2, 1)].abs() < 1e-15);
        assert!((basis[(1, 1)].abs() - 1.0).abs() < 1e-15);
    }
}
