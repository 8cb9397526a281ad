//! Linear least squares for the discovery engine: column-scaled QR, then the SVD of its small
//! triangle with a rank cut, so that terms the data cannot tell apart (a polynomial sampled
//! only at the profile's knots, an offset when every run has one temperature) get the
//! minimum-norm share instead of blowing up.

use crate::math::Real;
use nalgebra::{DMatrix, DVector};

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
            let qr = a.qr();
            qr.q_tr_mul(&mut b);
            (qr.r(), b.rows(0, columns).into_owned())
        } else {
            (a, b)
        };
        let svd = square.svd(true, true);
        let largest = svd.singular_values.max();
        let solution = svd
            .solve(&b, largest * RANK_TOLERANCE)
            .expect("both factors were computed");
        (0..columns).map(|j| solution[j] * scale(j)).collect()
    }
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
