//! nalgebra's dense decompositions of dynamically sized `f64` (and complex `f64`) matrices,
//! instantiated here. Each function is the nalgebra call named in its documentation, with
//! the same arguments and result.

use nalgebra::{DMatrix, DVector, Dyn, LU, QR, SVD, SymmetricEigen};
use rustfft::num_complex::Complex;

/// A singular value decomposition.
pub type Svd = SVD<f64, Dyn, Dyn>;
/// A singular value decomposition of a complex matrix.
pub type ComplexSvd = SVD<Complex<f64>, Dyn, Dyn>;
/// A Householder QR decomposition.
pub type Qr = QR<f64, Dyn, Dyn>;
/// An LU decomposition with partial pivoting.
pub type Lu = LU<f64, Dyn, Dyn>;
/// The eigen-decomposition of a symmetric matrix.
pub type Eigen = SymmetricEigen<f64, Dyn>;

/// [`SVD::new`]: singular values in decreasing order, with `U` and `Vᵀ` when asked for.
#[inline(never)]
pub fn svd(m: DMatrix<f64>, compute_u: bool, compute_v: bool) -> Svd {
    SVD::new(m, compute_u, compute_v)
}

/// [`SVD::new_unordered`]: singular values in no particular order.
#[inline(never)]
pub fn svd_unordered(m: DMatrix<f64>, compute_u: bool, compute_v: bool) -> Svd {
    SVD::new_unordered(m, compute_u, compute_v)
}

/// [`SVD::try_new_unordered`]: `None` when the iterations do not converge (`max_niter` 0:
/// without limit).
#[inline(never)]
pub fn try_svd_unordered(
    m: DMatrix<f64>,
    compute_u: bool,
    compute_v: bool,
    eps: f64,
    max_niter: usize,
) -> Option<Svd> {
    SVD::try_new_unordered(m, compute_u, compute_v, eps, max_niter)
}

/// [`SVD::solve`] for one right-hand side: the least-squares solution, singular values at or
/// below `eps` taken as zero. Fails when `U` or `Vᵀ` was not computed.
#[inline(never)]
pub fn svd_solve(svd: &Svd, b: &DVector<f64>, eps: f64) -> Result<DVector<f64>, &'static str> {
    svd.solve(b, eps)
}

/// [`SVD::new`] of a complex matrix.
#[inline(never)]
pub fn complex_svd(m: DMatrix<Complex<f64>>, compute_u: bool, compute_v: bool) -> ComplexSvd {
    SVD::new(m, compute_u, compute_v)
}

/// [`SVD::solve`] of a complex decomposition for one right-hand side.
#[inline(never)]
pub fn complex_svd_solve(
    svd: &ComplexSvd,
    b: &DVector<Complex<f64>>,
    eps: f64,
) -> Result<DVector<Complex<f64>>, &'static str> {
    svd.solve(b, eps)
}

/// [`QR::new`].
#[inline(never)]
pub fn qr(m: DMatrix<f64>) -> Qr {
    QR::new(m)
}

/// [`QR::q`]: the orthonormal factor (rows × min(rows, columns)).
#[inline(never)]
pub fn qr_q(qr: &Qr) -> DMatrix<f64> {
    qr.q()
}

/// [`QR::r`]: the upper-triangular factor (min(rows, columns) × columns).
#[inline(never)]
pub fn qr_r(qr: &Qr) -> DMatrix<f64> {
    qr.r()
}

/// [`QR::q_tr_mul`]: `b ← Qᵀ·b`.
#[inline(never)]
pub fn qr_q_tr_mul(qr: &Qr, b: &mut DVector<f64>) {
    qr.q_tr_mul(b)
}

/// [`SymmetricEigen::new`]: eigenvalues (unordered) and orthonormal eigenvectors.
#[inline(never)]
pub fn symmetric_eigen(m: DMatrix<f64>) -> Eigen {
    SymmetricEigen::new(m)
}

/// [`nalgebra::Matrix::symmetric_eigenvalues`]: the eigenvalues only.
#[inline(never)]
pub fn symmetric_eigenvalues(m: &DMatrix<f64>) -> DVector<f64> {
    m.symmetric_eigenvalues()
}

/// [`LU::new`].
#[inline(never)]
pub fn lu(m: DMatrix<f64>) -> Lu {
    LU::new(m)
}

/// [`LU::solve`] for one right-hand side: `None` when the matrix is singular.
#[inline(never)]
pub fn lu_solve(lu: &Lu, b: &DVector<f64>) -> Option<DVector<f64>> {
    lu.solve(b)
}

/// [`nalgebra::Matrix::try_inverse`]: `None` when the matrix is singular (or not square).
#[inline(never)]
pub fn try_inverse(m: DMatrix<f64>) -> Option<DMatrix<f64>> {
    m.try_inverse()
}
