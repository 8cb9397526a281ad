//! Linear least squares for the discovery engine: column-scaled QR, then the SVD of its small
//! triangle with a rank cut, so that terms the data cannot tell apart (a polynomial sampled
//! only at the profile's knots, an offset when every run has one temperature) get the
//! minimum-norm share instead of blowing up.

use crate::math::Real;
use mtwin_kernels::linalg;
use nalgebra::linalg::householder::clear_column_unchecked;
use nalgebra::{DMatrix, DVector, Reflection, Unit};

/// Singular values below this fraction of the largest are treated as zero (columns are first
/// scaled to unit norm, so this is a relative collinearity bound, well above f64 round-off).
pub const RANK_TOLERANCE: Real = 1e-9;

/// A design matrix built column by column over the rows selected for a fit.
#[derive(Clone, Debug, Default)]
pub struct Design {
    rows: usize,
    columns: Vec<Vec<Real>>,
}

impl Design {
    /// An empty design for `rows` rows.
    pub fn new(rows: usize) -> Design {
        Design {
            rows,
            columns: Vec::new(),
        }
    }

    /// Appends a column (one value per row).
    pub fn push(&mut self, column: Vec<Real>) {
        debug_assert_eq!(column.len(), self.rows);
        self.columns.push(column);
    }

    /// The number of columns.
    pub fn len(&self) -> usize {
        self.columns.len()
    }

    /// Whether there are no columns.
    pub fn is_empty(&self) -> bool {
        self.columns.is_empty()
    }

    /// A·c, one value per row.
    pub fn times(&self, c: &[Real]) -> Vec<Real> {
        (0..self.rows)
            .map(|i| self.columns.iter().zip(c).map(|(col, k)| col[i] * k).sum())
            .collect()
    }

    /// Unit scales of the columns (1/norm, 0 for a zero column), as [`Design::solve`] takes
    /// them.
    fn scales(&self) -> Vec<Real> {
        self.columns
            .iter()
            .map(|c| {
                let norm = c.iter().map(|v| v * v).sum::<Real>().sqrt();
                if norm > 0.0 { 1.0 / norm } else { 0.0 }
            })
            .collect()
    }

    /// The Householder steps of [`Design::solve`]'s QR on these columns, kept to lead other
    /// designs on the same rows ([`Design::solve_after`]): the steps on a design's leading
    /// columns depend on those columns only.
    pub fn prefix(&self) -> Prefix {
        let scales = self.scales();
        let mut factored = DMatrix::from_fn(self.rows, self.columns.len(), |i, j| {
            self.columns[j][i] * scales[j]
        });
        let steps = self.rows.min(self.columns.len());
        let mut diagonal = Vec::with_capacity(steps);
        let mut reflected = Vec::with_capacity(steps);
        for i in 0..steps {
            // nalgebra reflects the columns to the right only when the column below the
            // diagonal is not zero (its `not_zero`).
            reflected.push(factored.view_range(i.., i).norm_squared() != 0.0);
            diagonal.push(clear_column_unchecked(&mut factored, i, 0, None));
        }
        Prefix {
            design: self.clone(),
            scales,
            factored,
            diagonal,
            reflected,
        }
    }

    /// The coefficients of the design `prefix` then `self` (its columns after the prefix's,
    /// on the same rows) minimising ‖y − A·c‖, bit for bit [`Design::solve`]'s on the whole
    /// design, without repeating the Householder steps on the prefix's columns: Householder QR
    /// reflects each column to the right of a step independently, so the leading steps and the
    /// reflections they apply to the later columns are the same whatever those are.
    pub fn solve_after(&self, prefix: &Prefix, y: &[Real]) -> Vec<Real> {
        let lead = prefix.scales.len();
        let columns = lead + self.columns.len();
        if self.rows != prefix.design.rows || self.rows <= columns {
            let mut whole = prefix.design.clone();
            self.columns.iter().for_each(|c| whole.push(c.clone()));
            return whole.solve(y);
        }
        let scales: Vec<Real> = prefix.scales.iter().copied().chain(self.scales()).collect();
        let mut a = DMatrix::zeros(self.rows, columns);
        a.columns_mut(0, lead).copy_from(&prefix.factored);
        for (j, column) in self.columns.iter().enumerate() {
            let scale = scales[lead + j];
            a.column_mut(lead + j)
                .iter_mut()
                .zip(column)
                .for_each(|(a, v)| *a = v * scale);
        }
        let mut diagonal = prefix.diagonal.clone();
        {
            let (left, mut right) = a.columns_range_pair_mut(0..lead, lead..);
            for i in 0..lead {
                if prefix.reflected[i] {
                    let axis = Unit::new_unchecked(left.view_range(i.., i));
                    let sign = prefix.diagonal[i].signum();
                    Reflection::new(axis, 0.0)
                        .reflect_with_sign(&mut right.rows_range_mut(i..), sign);
                }
            }
        }
        for i in lead..columns {
            diagonal.push(clear_column_unchecked(&mut a, i, 0, None));
        }
        // As nalgebra's QR::r and QR::q_tr_mul.
        let mut square = a.rows(0, columns).upper_triangle();
        square.set_partial_diagonal(diagonal.iter().map(|d| d.abs()));
        let mut b = DVector::from_column_slice(y);
        for (i, d) in diagonal.iter().enumerate() {
            let axis = Unit::new_unchecked(a.view_range(i.., i));
            Reflection::new(axis, 0.0).reflect_with_sign(&mut b.rows_range_mut(i..), d.signum());
        }
        let b = b.rows(0, columns).into_owned();
        let svd = linalg::svd(square, true, true);
        let largest = svd.singular_values.max();
        let solution = linalg::svd_solve(&svd, &b, largest * RANK_TOLERANCE)
            .expect("both factors were computed");
        (0..columns).map(|j| solution[j] * scales[j]).collect()
    }

    /// The coefficients minimising ‖y − A·c‖ (minimum norm within the rank cut).
    pub fn solve(&self, y: &[Real]) -> Vec<Real> {
        let columns = self.columns.len();
        if columns == 0 || self.rows == 0 {
            return vec![0.0; columns];
        }
        let norms: Vec<Real> = self
            .columns
            .iter()
            .map(|c| c.iter().map(|v| v * v).sum::<Real>().sqrt())
            .collect();
        let scale = |j: usize| if norms[j] > 0.0 { 1.0 / norms[j] } else { 0.0 };
        let a = DMatrix::from_fn(self.rows, columns, |i, j| self.columns[j][i] * scale(j));
        let mut b = DVector::from_column_slice(y);
        // Tall designs (the usual case): A = Q·R by Householder, then the SVD of the small R,
        // which has A's singular values: the same rank cut at a fraction of the cost of
        // bidiagonalising A with its left factor.
        let (square, b) = if self.rows > columns {
            let qr = linalg::qr(a);
            linalg::qr_q_tr_mul(&qr, &mut b);
            (linalg::qr_r(&qr), b.rows(0, columns).into_owned())
        } else {
            (a, b)
        };
        let svd = linalg::svd(square, true, true);
        let largest = svd.singular_values.max();
        let solution = linalg::svd_solve(&svd, &b, largest * RANK_TOLERANCE)
            .expect("both factors were computed");
        (0..columns).map(|j| solution[j] * scale(j)).collect()
    }
}

/// A design's leading columns with their Householder steps taken ([`Design::prefix`]).
#[derive(Clone, Debug)]
pub struct Prefix {
    design: Design,
    scales: Vec<Real>,
    /// The scaled columns after the steps (the reflections' axes below the diagonal).
    factored: DMatrix<Real>,
    diagonal: Vec<Real>,
    /// Whether each step reflected the columns to its right.
    reflected: Vec<bool>,
}

/// The least-squares coefficient of `r` on `column` alone (no intercept: centre both first
/// for a slope) and its t statistic (n − 1 degrees of freedom); `None` for the column when it
/// is zero or there are fewer than 3 values. The t statistic is `None` when the residual has no
/// scatter (an exact fit, or nothing in `r` at all): it cannot be formed then, and a report
/// says so in words ([`T_UNDEFINED`]) rather than printing an infinity.
pub fn regression(column: &[Real], r: &[Real]) -> Option<(Real, Option<Real>)> {
    let n = r.len() as Real;
    let (cc, cr, rr) = column
        .iter()
        .zip(r)
        .fold((0.0, 0.0, 0.0), |(cc, cr, rr), (c, r)| {
            (cc + c * c, cr + c * r, rr + r * r)
        });
    if cc <= 0.0 || n < 3.0 {
        return None;
    }
    let slope = cr / cc;
    let variance = ((rr - slope * cr) / (n - 1.0)).max(0.0);
    let t = (variance > 0.0)
        .then(|| slope / (variance / cc).sqrt())
        .filter(|t| t.is_finite());
    Some((slope, t))
}

/// What a report says where [`regression`] could not form a t statistic.
pub const T_UNDEFINED: &str = "t not defined: the residual has no scatter";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regression_t_matches_a_hand_computation() {
        // r = 2·c + e with c = (1, −1, 1, −1), e = (0.1, 0.1, −0.1, −0.1) ⊥ c: slope 2,
        // residual variance 0.04/3, t = 2/√(0.04/3/4) = 34.64.
        let c = [1.0, -1.0, 1.0, -1.0];
        let r = [2.1, -1.9, 1.9, -2.1];
        let (slope, t) = regression(&c, &r).unwrap();
        assert!((slope - 2.0).abs() < 1e-12);
        assert!((t.unwrap() - 2.0 / (0.04_f64 / 3.0 / 4.0).sqrt()).abs() < 1e-9);
    }

    #[test]
    fn regression_t_is_not_formed_without_scatter() {
        // r = 2·c exactly: slope 2, nothing left, so no t; r = 0: slope 0, no t either.
        let c = [1.0, -1.0, 1.0, -1.0];
        assert_eq!(regression(&c, &[2.0, -2.0, 2.0, -2.0]), Some((2.0, None)));
        assert_eq!(regression(&c, &[0.0; 4]), Some((0.0, None)));
    }

    #[test]
    fn a_solve_after_a_prefix_is_the_whole_solve_bit_for_bit() {
        // Leading columns like the profile's hats (one of them zero on these rows, one
        // repeated), then columns like effects (one a copy of a leading one: rank cut);
        // lengths about the blocks of eight.
        for rows in [9, 16, 23, 60] {
            let value = |i: usize, j: usize| {
                let k = (i * 7919 + j * 104_729) % 1009;
                (k as Real / 1009.0 - 0.5) * 10f64.powi((k % 5) as i32 - 2)
            };
            let mut lead = Design::new(rows);
            for j in 0..4 {
                lead.push(
                    (0..rows)
                        .map(|i| if j == 2 { 0.0 } else { value(i, j) })
                        .collect(),
                );
            }
            lead.push((0..rows).map(|i| value(i, 1)).collect());
            let mut rest = Design::new(rows);
            rest.push((0..rows).map(|i| value(i, 7)).collect());
            rest.push((0..rows).map(|i| value(i, 0)).collect());
            rest.push((0..rows).map(|i| (i as Real).sin()).collect());
            let y: Vec<Real> = (0..rows).map(|i| value(i, 9)).collect();
            let mut whole = lead.clone();
            rest.columns.iter().for_each(|c| whole.push(c.clone()));
            let expected = whole.solve(&y);
            let fast = rest.solve_after(&lead.prefix(), &y);
            assert_eq!(fast.len(), expected.len());
            for (a, b) in fast.iter().zip(&expected) {
                assert_eq!(a.to_bits(), b.to_bits(), "{rows} rows: {a} against {b}");
            }
        }
    }

    #[test]
    fn recovers_a_line_and_splits_collinear_columns_evenly() {
        // y = 2 + 3x exactly: recovered to round-off.
        let x: Vec<Real> = (0..10).map(|i| i as Real).collect();
        let y: Vec<Real> = x.iter().map(|x| 2.0 + 3.0 * x).collect();
        let mut design = Design::new(10);
        design.push(vec![1.0; 10]);
        design.push(x.clone());
        let c = design.solve(&y);
        assert!((c[0] - 2.0).abs() < 1e-12 && (c[1] - 3.0).abs() < 1e-12);
        // The same column twice: the minimum-norm answer shares the coefficient equally.
        design.push(x);
        let c = design.solve(&y);
        assert!((c[1] - 1.5).abs() < 1e-9 && (c[2] - 1.5).abs() < 1e-9);
    }
}
