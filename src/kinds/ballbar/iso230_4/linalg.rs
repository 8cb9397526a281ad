//! The linear algebra of the least-squares fits: Gram matrices, their pseudo-inverse and the
//! columns' variance inflations from a column-scaled eigen-decomposition, and [`Projection`],
//! a fit of fixed columns that scores extra columns without refitting.

use crate::math::Real;
use nalgebra::DMatrix;

/// Eigenvalues of the column-scaled Gram matrix below this fraction of the largest are zero.
const EIGEN_TOLERANCE: Real = 1e-13;

/// Dot product.
pub(super) fn dot(a: &[Real], b: &[Real]) -> Real {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The Gram matrix AᵀA of columns over the same rows.
pub(super) fn gram(columns: &[&[Real]]) -> DMatrix<Real> {
    let k = columns.len();
    let mut g = DMatrix::zeros(k, k);
    for i in 0..k {
        for j in i..k {
            let v = dot(columns[i], columns[j]);
            g[(i, j)] = v;
            g[(j, i)] = v;
        }
    }
    g
}

/// The eigen-decomposition of the Gram matrix with columns scaled to unit norm: scales,
/// eigenvalues, eigenvectors.
pub(super) fn scaled_eigen(g: &DMatrix<Real>) -> (Vec<Real>, Vec<Real>, DMatrix<Real>) {
    let k = g.nrows();
    let d: Vec<Real> = (0..k)
        .map(|j| {
            let v = g[(j, j)];
            if v > 0.0 { 1.0 / v.sqrt() } else { 0.0 }
        })
        .collect();
    let scaled = DMatrix::from_fn(k, k, |i, j| g[(i, j)] * d[i] * d[j]);
    let eigen = scaled.symmetric_eigen();
    (
        d,
        eigen.eigenvalues.iter().copied().collect(),
        eigen.eigenvectors,
    )
}

/// The pseudo-inverse (AᵀA)⁺ from the Gram matrix, eigenvalues of the column-scaled matrix
/// below [`EIGEN_TOLERANCE`] of the largest treated as zero (zero columns get zero).
pub(super) fn gram_pinv(g: &DMatrix<Real>) -> DMatrix<Real> {
    let k = g.nrows();
    if k == 0 {
        return DMatrix::zeros(0, 0);
    }
    let (d, values, vectors) = scaled_eigen(g);
    let largest = values.iter().copied().fold(0.0, Real::max);
    DMatrix::from_fn(k, k, |i, j| {
        let sum: Real = values
            .iter()
            .enumerate()
            .filter(|(_, l)| **l > largest * EIGEN_TOLERANCE)
            .map(|(m, l)| vectors[(i, m)] * vectors[(j, m)] / l)
            .sum();
        sum * d[i] * d[j]
    })
}

/// The variance inflation of every column: the diagonal of the inverse of the column-scaled
/// Gram matrix (1 for a column orthogonal to the others; +∞ for one inside their span).
pub(super) fn variance_inflation(g: &DMatrix<Real>) -> Vec<Real> {
    let k = g.nrows();
    if k == 0 {
        return Vec::new();
    }
    let (d, values, vectors) = scaled_eigen(g);
    let largest = values.iter().copied().fold(0.0, Real::max);
    (0..k)
        .map(|j| {
            if d[j] == 0.0 {
                return Real::INFINITY;
            }
            values
                .iter()
                .enumerate()
                .map(|(m, l)| {
                    let weight = vectors[(j, m)].powi(2);
                    if *l > largest * EIGEN_TOLERANCE {
                        weight / l
                    } else if weight > 1e-6 {
                        Real::INFINITY
                    } else {
                        0.0
                    }
                })
                .sum()
        })
        .collect()
}

/// A least-squares fit of fixed columns, ready to score extra columns quickly.
pub(super) struct Projection {
    pub(super) columns: Vec<Vec<Real>>,
    pinv: DMatrix<Real>,
    pub(super) coefficients: Vec<Real>,
    pub(super) residual: Vec<Real>,
    pub(super) rss: Real,
    /// The sum of squares the columns explain (m²).
    pub(super) explained: Real,
}

impl Projection {
    pub(super) fn new(columns: Vec<Vec<Real>>, y: &[Real]) -> Projection {
        let views: Vec<&[Real]> = columns.iter().map(Vec::as_slice).collect();
        let pinv = gram_pinv(&gram(&views));
        let b: Vec<Real> = views.iter().map(|c| dot(c, y)).collect();
        let coefficients: Vec<Real> = (0..b.len())
            .map(|i| (0..b.len()).map(|j| pinv[(i, j)] * b[j]).sum())
            .collect();
        let mut residual = y.to_vec();
        for (c, k) in views.iter().zip(&coefficients) {
            for (r, v) in residual.iter_mut().zip(c.iter()) {
                *r -= k * v;
            }
        }
        let rss = dot(&residual, &residual);
        Projection {
            explained: dot(y, y) - rss,
            columns,
            pinv,
            coefficients,
            residual,
            rss,
        }
    }

    /// The residual sum of squares with `extra` columns added: the fixed fit's, less what the
    /// extras' parts orthogonal to the fixed columns explain of its residual.
    pub(super) fn rss_with(&self, extra: &[&[Real]]) -> Real {
        let (k, m) = (self.columns.len(), extra.len());
        let fb = DMatrix::from_fn(k, m, |i, j| dot(&self.columns[i], extra[j]));
        let bb = DMatrix::from_fn(m, m, |i, j| dot(extra[i], extra[j]));
        let br: Vec<Real> = extra.iter().map(|c| dot(c, &self.residual)).collect();
        self.rss_from(&fb, &bb, &br)
    }

    /// [`Projection::rss_with`] for one extra column that is zero but at `positions` (of the
    /// projection's rows), where it is `values`.
    pub(super) fn rss_with_sparse(&self, positions: &[usize], values: &[Real]) -> Real {
        let sum =
            |of: &[Real]| -> Real { positions.iter().zip(values).map(|(&j, v)| of[j] * v).sum() };
        let fb = DMatrix::from_fn(self.columns.len(), 1, |i, _| sum(&self.columns[i]));
        let bb = DMatrix::from_element(1, 1, dot(values, values));
        self.rss_from(&fb, &bb, &[sum(&self.residual)])
    }

    /// [`Projection::rss_with`] from the extras' sums: Fᵀ·B (fixed × extra), Bᵀ·B and Bᵀ·r.
    pub(super) fn rss_from(&self, fb: &DMatrix<Real>, bb: &DMatrix<Real>, br: &[Real]) -> Real {
        let m = br.len();
        let reduced = bb - fb.transpose() * &self.pinv * fb;
        let inverse = gram_pinv(&reduced);
        let explained: Real = (0..m)
            .map(|i| {
                (0..m)
                    .map(|j| br[i] * inverse[(i, j)] * br[j])
                    .sum::<Real>()
            })
            .sum();
        (self.rss - explained).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variance_inflation_is_one_for_orthogonal_columns_and_infinite_for_collinear_ones() {
        let a = [1.0, 1.0, 1.0, 1.0];
        let b = [1.0, -1.0, 1.0, -1.0];
        let v = variance_inflation(&gram(&[&a, &b]));
        assert!((v[0] - 1.0).abs() < 1e-12 && (v[1] - 1.0).abs() < 1e-12);
        let c = [2.0, 0.0, 2.0, 0.0]; // a + b
        let v = variance_inflation(&gram(&[&a, &b, &c]));
        assert!(v.iter().all(|x| *x > 1e12), "{v:?}");
        // Two columns with correlation ρ: VIF = 1/(1 − ρ²). ρ = 1/√2 here: VIF = 2.
        let d = [1.0, 0.0, 1.0, 0.0];
        let v = variance_inflation(&gram(&[&a, &d]));
        assert!((v[0] - 2.0).abs() < 1e-12, "{v:?}");
    }

    #[test]
    fn projection_scores_an_extra_column_as_a_full_refit_would() {
        let x: Vec<Real> = (0..50).map(|i| i as Real / 10.0).collect();
        let one = vec![1.0; 50];
        let y: Vec<Real> = x.iter().map(|x| 1.0 + x.sin() + 0.1 * x * x).collect();
        let square: Vec<Real> = x.iter().map(|x| x * x).collect();
        let fixed = Projection::new(vec![one.clone(), x.clone()], &y);
        let full = Projection::new(vec![one, x, square.clone()], &y);
        assert!((fixed.rss_with(&[&square]) - full.rss).abs() < 1e-10 * fixed.rss);
    }
}
