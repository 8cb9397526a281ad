//! The linear algebra of the least-squares fits: Gram matrices, their pseudo-inverse (also
//! for the one to three extra columns a search scores, [`small_pinv`]) and the columns'
//! variance inflations from a column-scaled eigen-decomposition, and [`Projection`], a fit of
//! columns given reading by reading.

use crate::math::{Real, dot};
use nalgebra::DMatrix;

/// Eigenvalues of the column-scaled Gram matrix below this fraction of the largest are zero.
const EIGEN_TOLERANCE: Real = 1e-13;

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
    let eigen = mtwin_kernels::linalg::symmetric_eigen(scaled);
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

/// [`gram_pinv`] of an `m` × `m` Gram matrix given row by row, for the one to three extra
/// columns a search scores at a time (fixed-size eigen-decompositions, no allocation beyond
/// the result).
pub(super) fn small_pinv(m: usize, g: &[Real]) -> Vec<Real> {
    macro_rules! fixed {
        ($m:literal) => {{
            const M: usize = $m;
            let d: [Real; M] = std::array::from_fn(|j| {
                let v = g[j * M + j];
                if v > 0.0 { 1.0 / v.sqrt() } else { 0.0 }
            });
            let scaled =
                nalgebra::SMatrix::<Real, M, M>::from_fn(|i, j| g[i * M + j] * d[i] * d[j]);
            let eigen = scaled.symmetric_eigen();
            let largest = eigen.eigenvalues.iter().copied().fold(0.0, Real::max);
            let mut out = vec![0.0; M * M];
            for i in 0..M {
                for j in 0..M {
                    let sum: Real = (0..M)
                        .filter(|&m| eigen.eigenvalues[m] > largest * EIGEN_TOLERANCE)
                        .map(|m| {
                            eigen.eigenvectors[(i, m)] * eigen.eigenvectors[(j, m)]
                                / eigen.eigenvalues[m]
                        })
                        .sum();
                    out[i * M + j] = sum * d[i] * d[j];
                }
            }
            out
        }};
    }
    match m {
        0 => Vec::new(),
        1 => fixed!(1),
        2 => fixed!(2),
        3 => fixed!(3),
        _ => {
            let pinv = gram_pinv(&DMatrix::from_row_slice(m, m, g));
            (0..m * m).map(|k| pinv[(k / m, k % m)]).collect()
        }
    }
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

/// A least-squares fit of columns given reading by reading.
pub(super) struct Projection {
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
            coefficients,
            residual,
            rss,
        }
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
}
