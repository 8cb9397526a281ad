//! The kernels against closed forms: transforms of records whose spectrum is known, and
//! factorisations that multiply back to their matrix and solve a system with a known solution.
//! (An integration test: the library's own test build would compile every kernel a second time.)

use mtwin_kernels::linalg::*;
use mtwin_kernels::{Complex, FftPlanner, RealFftPlanner};
use nalgebra::{DMatrix, DVector, dmatrix};

/// The forward then inverse transform is `len` times the identity (checked on a length
/// with an odd prime factor, which takes another algorithm than a power of two).
#[test]
fn forward_then_inverse_is_len_times_the_record() {
    let len = 3 * 7 * 16;
    let record: Vec<Complex<f64>> = (0..len)
        .map(|j| Complex::new((j as f64 * 0.37).sin(), (j as f64 * 0.11).cos()))
        .collect();
    let mut planner = FftPlanner::new();
    let mut buffer = record.clone();
    planner.plan_fft_forward(len).process(&mut buffer);
    planner.plan_fft_inverse(len).process(&mut buffer);
    for (a, b) in buffer.iter().zip(&record) {
        // Round-off of the two transforms: a few ulps of the largest coefficient.
        assert!((a / len as f64 - b).norm() < 1e-13, "{a} vs {b}");
    }
}

/// A cosine of k cycles in a real record has its whole amplitude in line k.
#[test]
fn a_real_cosine_is_one_line() {
    let (len, k) = (200, 7);
    let mut record: Vec<f64> = (0..len)
        .map(|j| (std::f64::consts::TAU * (k * j) as f64 / len as f64).cos())
        .collect();
    let fft = RealFftPlanner::new().plan_fft_forward(len);
    let mut out = fft.make_output_vec();
    fft.process(&mut record, &mut out).unwrap();
    assert_eq!(out.len(), len / 2 + 1);
    for (j, c) in out.iter().enumerate() {
        let expected = if j == k { len as f64 / 2.0 } else { 0.0 };
        assert!((c.norm() - expected).abs() < 1e-12, "line {j}: {c}");
    }
}

fn close(a: &DMatrix<f64>, b: &DMatrix<f64>, tolerance: f64) -> bool {
    (a - b).abs().max() <= tolerance
}

/// Every factorisation reproduces its matrix to round-off (a few ulps of its entries).
#[test]
fn the_factors_multiply_back() {
    let a = dmatrix![4.0, 1.0, 2.0; 1.0, 5.0, 3.0; 2.0, 3.0, 6.0; 1.0, 0.5, 0.25];
    let s = svd(a.clone(), true, true);
    let (u, v_t) = (s.u.clone().unwrap(), s.v_t.clone().unwrap());
    assert!(close(
        &(u * DMatrix::from_diagonal(&s.singular_values) * v_t),
        &a,
        1e-13
    ));
    let q = qr(a.clone());
    assert!(close(&(qr_q(&q) * qr_r(&q)), &a, 1e-13));
    let square = a.tr_mul(&a);
    let e = symmetric_eigen(square.clone());
    let rebuilt =
        &e.eigenvectors * DMatrix::from_diagonal(&e.eigenvalues) * e.eigenvectors.transpose();
    assert!(close(&rebuilt, &square, 1e-12));
    let mut values: Vec<f64> = symmetric_eigenvalues(&square).iter().copied().collect();
    let mut from_eigen: Vec<f64> = e.eigenvalues.iter().copied().collect();
    values.sort_by(f64::total_cmp);
    from_eigen.sort_by(f64::total_cmp);
    for (a, b) in values.iter().zip(&from_eigen) {
        assert!((a - b).abs() < 1e-12);
    }
    let inverse = try_inverse(square.clone()).unwrap();
    assert!(close(&(&square * inverse), &DMatrix::identity(3, 3), 1e-14));
}

/// The three solvers agree on a consistent system with the known solution (1, −2, 3).
#[test]
fn the_solvers_find_the_known_solution() {
    let a = dmatrix![2.0, 1.0, 0.0; 1.0, 3.0, 1.0; 0.0, 1.0, 4.0; 1.0, 1.0, 1.0];
    let x = DVector::from_vec(vec![1.0, -2.0, 3.0]);
    let b = &a * &x;
    let by_svd = svd_solve(&svd(a.clone(), true, true), &b, 0.0).unwrap();
    let q = qr(a.clone());
    let mut qtb = b.clone();
    qr_q_tr_mul(&q, &mut qtb);
    let by_qr = qr_r(&q)
        .solve_upper_triangular(&qtb.rows(0, 3).into_owned())
        .unwrap();
    let square = a.rows(0, 3).into_owned();
    let by_lu = lu_solve(&lu(square), &b.rows(0, 3).into_owned()).unwrap();
    for solution in [by_svd, by_qr, by_lu] {
        assert!((solution - &x).amax() < 1e-13);
    }
    assert!(lu_solve(&lu(DMatrix::zeros(2, 2)), &DVector::zeros(2)).is_none());
}

/// A complex system `(1 + i)·z = 2i` has `z = 1 + i`.
#[test]
fn a_complex_system_is_solved() {
    let a = DMatrix::from_element(1, 1, Complex::new(1.0, 1.0));
    let b = DVector::from_element(1, Complex::new(0.0, 2.0));
    let z = complex_svd_solve(&complex_svd(a, true, true), &b, 0.0).unwrap();
    assert!((z[0] - Complex::new(1.0, 1.0)).norm() < 1e-15);
}
