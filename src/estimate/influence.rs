//! Which readings a fit's misfit comes from: the exact change of χ² when a block of readings
//! is left out of a linear least-squares fit, from the fit itself (no refit).
//!
//! With weighted residuals e, the weighted design J and P = (JᵀJ)⁻¹, leaving out the readings
//! B lowers χ² by
//!
//! Δχ²_B = e_Bᵀ (I − H_BB)⁻¹ e_B,  H_BB = J_B P J_Bᵀ,
//!
//! the block form of the deleted residual (Cook & Weisberg, *Residuals and Influence in
//! Regression*, 1982, §2.2; for one reading Δχ² = e_i² / (1 − h_ii), the squared externally
//! scaled residual). It is exact for a linear model and first-order for the twin's (the
//! design at the start, as the covariance uses). A fit whose χ² is far above its noise but
//! falls back to the noise's without one block has one bad block (a mistyped value, a stylus
//! re-qualified between spheres), not a model that misses a term.

use crate::math::Real;
use mtwin_kernels::linalg;
use nalgebra::DMatrix;

/// The block of readings whose leaving-out lowers χ² most.
#[derive(Clone, Debug, PartialEq)]
pub struct Influential {
    /// The set (table) it belongs to.
    pub set: usize,
    /// Its first reading, within the set.
    pub first: usize,
    /// How many readings it holds.
    pub count: usize,
    /// χ² of the fit without it.
    pub chi2_without: Real,
    /// Its largest unweighted residual (m).
    pub residual: Real,
}

/// The single reading whose leaving-out lowers χ² most, then the row of three (where a set's
/// readings come in rows of three: a sphere centre's or an R-test pose's x, y, z) that does.
/// `sets[k]` gives set k's first row in `residuals` (weighted) and `jacobian` (weighted, in
/// the fit's reduced unknowns, with `inverse` = (JᵀJ)⁻¹), its readings per row and its
/// readings' uncertainties (SI). `chi2` = Σ residuals².
pub fn most_influential(
    jacobian: &DMatrix<Real>,
    inverse: &DMatrix<Real>,
    residuals: &[Real],
    chi2: Real,
    sets: &[(usize, usize, &[Real])],
) -> Vec<Influential> {
    // H_BB = J_B P J_Bᵀ = (J P)_B J_Bᵀ: the gain J P once (one product), then a block's hat
    // is dot products of its rows, read as columns of the transposes.
    let gain_t = (jacobian * inverse).transpose();
    let jacobian_t = jacobian.transpose();
    let mut best: Vec<Influential> = Vec::new();
    for size in [1, 3] {
        let mut top: Option<Influential> = None;
        for (k, &(at, per_row, sigma)) in sets.iter().enumerate() {
            if size > 1 && per_row != size {
                continue;
            }
            let n = sigma.len();
            let mut first = 0;
            while first + size <= n {
                let rows: Vec<usize> = (at + first..at + first + size).collect();
                if let Some(delta) = deleted(&jacobian_t, &gain_t, residuals, &rows) {
                    let without = chi2 - delta;
                    if top.as_ref().is_none_or(|t| without < t.chi2_without) {
                        let residual = (0..size)
                            .map(|i| residuals[at + first + i] * sigma[first + i])
                            .fold(0.0, |m: Real, r| if r.abs() > m.abs() { r } else { m });
                        top = Some(Influential {
                            set: k,
                            first,
                            count: size,
                            chi2_without: without.max(0.0),
                            residual,
                        });
                    }
                }
                first += size;
            }
        }
        best.extend(top);
    }
    best
}

/// Δχ² of leaving out `rows`; None when they alone determine a direction of the fit
/// (I − H_BB singular: without them the fit would not be the same problem). `jacobian_t` is
/// Jᵀ and `gain_t` (J P)ᵀ.
fn deleted(
    jacobian_t: &DMatrix<Real>,
    gain_t: &DMatrix<Real>,
    residuals: &[Real],
    rows: &[usize],
) -> Option<Real> {
    let size = rows.len();
    let complement = DMatrix::from_fn(size, size, |a, b| {
        let hat = gain_t.column(rows[a]).dot(&jacobian_t.column(rows[b]));
        if a == b { 1.0 - hat } else { -hat }
    });
    let e = nalgebra::DVector::from_iterator(size, rows.iter().map(|&r| residuals[r]));
    if size == 1 {
        // e² / (1 − h), the one eigenvalue being 1 − h.
        let lowest = complement[(0, 0)];
        return (lowest > 1e-9).then(|| e[0] * (e[0] / lowest));
    }
    let solved = linalg::lu_solve(&linalg::lu(complement.clone()), &e)?;
    let lowest = linalg::symmetric_eigenvalues(&complement).min();
    (lowest > 1e-9).then(|| e.dot(&solved))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight line through six points, one of them 10 units off: by hand, leaving it out
    /// leaves a perfect fit, so χ² without it is 0 and Δχ² is the whole χ².
    #[test]
    fn one_bad_point_on_a_line_is_found_and_its_removal_is_exact() {
        let x = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let mut y: Vec<Real> = x.iter().map(|x| 1.0 + 2.0 * x).collect();
        y[3] += 10.0;
        let j = DMatrix::from_fn(6, 2, |i, c| if c == 0 { 1.0 } else { x[i] });
        let inverse = (j.transpose() * &j).try_inverse().unwrap();
        let beta = &inverse * j.transpose() * nalgebra::DVector::from_vec(y.clone());
        let fitted = &j * beta;
        let residuals: Vec<Real> = (0..6).map(|i| y[i] - fitted[i]).collect();
        let chi2: Real = residuals.iter().map(|r| r * r).sum();
        let sigma = [1.0; 6];
        let found = most_influential(&j, &inverse, &residuals, chi2, &[(0, 1, &sigma)]);
        assert_eq!(found.len(), 1);
        assert_eq!((found[0].set, found[0].first, found[0].count), (0, 3, 1));
        assert!(found[0].chi2_without.abs() < 1e-9, "{found:?}");
        // Its own residual: 10 (1 − h), h = 1/6 + (3 − 2.5)²/17.5 by hand.
        let h = 1.0 / 6.0 + 0.25 / 17.5;
        assert!((found[0].residual - 10.0 * (1.0 - h)).abs() < 1e-9);
    }

    /// Rows of three: one row of a 3-D point set moved is found as that row.
    #[test]
    fn a_row_of_three_is_left_out_together() {
        // Eight 3-D points fitted by a common offset (3 unknowns); point 5 moved by (1, −2, 3).
        let n = 8;
        let j = DMatrix::from_fn(3 * n, 3, |i, c| if i % 3 == c { 1.0 } else { 0.0 });
        let mut y = vec![0.0; 3 * n];
        y[15] = 1.0;
        y[16] = -2.0;
        y[17] = 3.0;
        let inverse = (j.transpose() * &j).try_inverse().unwrap();
        let beta = &inverse * j.transpose() * nalgebra::DVector::from_vec(y.clone());
        let fitted = &j * beta;
        let residuals: Vec<Real> = (0..3 * n).map(|i| y[i] - fitted[i]).collect();
        let chi2: Real = residuals.iter().map(|r| r * r).sum();
        let sigma = vec![1.0; 3 * n];
        let found = most_influential(&j, &inverse, &residuals, chi2, &[(0, 3, &sigma)]);
        assert_eq!(found.len(), 2);
        // The single reading: the z of point 5 (largest offset); without it x, y still misfit.
        assert_eq!((found[0].first, found[0].count), (17, 1));
        assert!(found[0].chi2_without > 1.0);
        // The row: point 5 whole, and then nothing is left to misfit.
        assert_eq!((found[1].first, found[1].count), (15, 3));
        assert!(found[1].chi2_without.abs() < 1e-9);
    }
}
