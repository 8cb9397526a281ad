//! The R-test evaluation: per test the deviation ranges along X, Y and Z (the values ISO
//! 10791-6 states its K-test tolerances for), the largest 3-D deviation, and the fitted
//! trajectory of the tool relative to the sphere against the swept rotary angle θ:
//!
//! - a test that turns 180° or more: `d(θ) = m + c·cos θ + s·sin θ` per direction (least
//!   squares). A location error of the turning axis draws a circle; its radius is
//!   `√((|c|² + |s|²)/2)` (exact for a circle, the RMS radius of an ellipse), its centre `m`;
//! - a shorter swing: the straight line `d(θ) = m + k·θ` per direction (µm per degree).
//!
//! The residual is what the fit leaves, RMS over the poses and directions.

use super::table::{RtestRow, RtestTable};
use crate::machine::Axis;
use crate::math::{M_PER_UM, Real};
use serde::Serialize;

/// Why a table cannot be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RtestAnalysisError {
    /// A test has too few poses.
    #[error("test \"{0}\" has fewer than 3 poses")]
    TooFew(String),
}

/// The evaluation of a whole table.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RtestEvaluation {
    /// One entry per test, in table order.
    pub tests: Vec<TestEvaluation>,
}

/// The evaluation of one test.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct TestEvaluation {
    /// The test's name.
    pub name: String,
    /// Number of poses.
    pub poses: usize,
    /// The rotary axis that turns furthest (`A`, `B` or `C`), if any turns.
    pub swept_axis: Option<String>,
    /// Its angles at the first and last pose (deg).
    pub swept_deg: [Real; 2],
    /// Deviation range (max − min) along X, Y, Z (µm).
    pub range_um: [Real; 3],
    /// The largest length of the 3-D deviation (µm).
    pub max_deviation_um: Real,
    /// The fitted trajectory.
    pub fit: Fit,
}

/// The trajectory fitted against the swept angle.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Fit {
    /// `m + c·cos θ + s·sin θ` per direction.
    Circle {
        /// `m` along X, Y, Z (µm).
        centre_um: [Real; 3],
        /// `c` (µm).
        cos_um: [Real; 3],
        /// `s` (µm).
        sin_um: [Real; 3],
        /// `√((|c|² + |s|²)/2)` (µm).
        radius_um: Real,
        /// RMS of what the fit leaves (µm).
        residual_um: Real,
    },
    /// `m + k·θ` per direction.
    Line {
        /// `m` at θ = 0 along X, Y, Z (µm).
        intercept_um: [Real; 3],
        /// `k` (µm per degree).
        slope_um_per_deg: [Real; 3],
        /// RMS of what the fit leaves (µm).
        residual_um: Real,
    },
    /// No rotary axis turns: nothing to fit.
    None,
}

/// Evaluates every test of `table`.
pub fn evaluate(table: &RtestTable) -> Result<RtestEvaluation, RtestAnalysisError> {
    let tests = table
        .tests()
        .into_iter()
        .map(|(name, rows)| evaluate_test(name, &rows))
        .collect::<Result<_, _>>()?;
    Ok(RtestEvaluation { tests })
}

/// A value in µm to 4 decimals (0.1 nm): what the table's resolution supports.
fn r4(value: Real) -> Real {
    (value * 1e4).round() / 1e4
}

fn r4s(values: [Real; 3]) -> [Real; 3] {
    values.map(r4)
}

fn evaluate_test(name: &str, rows: &[&RtestRow]) -> Result<TestEvaluation, RtestAnalysisError> {
    if rows.len() < 3 {
        return Err(RtestAnalysisError::TooFew(name.to_string()));
    }
    let um = |v: Real| r4(v / M_PER_UM);
    let mut range = [0.0; 3];
    for (j, r) in range.iter_mut().enumerate() {
        let values = rows.iter().map(|row| row.deviation[j]);
        let max = values.clone().fold(Real::NEG_INFINITY, Real::max);
        let min = values.fold(Real::INFINITY, Real::min);
        *r = um(max - min);
    }
    let max_deviation = rows
        .iter()
        .map(|r| r.deviation.length())
        .fold(0.0, Real::max);
    // The swept axis: the recorded angle that changes most.
    let swept = [Axis::A, Axis::B, Axis::C]
        .into_iter()
        .filter_map(|axis| {
            let angles: Vec<Real> = rows.iter().filter_map(|r| r.angle(axis)).collect();
            (angles.len() == rows.len()).then(|| {
                let max = angles.iter().copied().fold(Real::NEG_INFINITY, Real::max);
                let min = angles.iter().copied().fold(Real::INFINITY, Real::min);
                (axis, max - min)
            })
        })
        .filter(|(_, span)| *span > 1e-9)
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let (swept_axis, swept_deg, fit) = match swept {
        None => (None, [0.0; 2], Fit::None),
        Some((axis, span)) => {
            let theta: Vec<Real> = rows.iter().map(|r| r.angle(axis).unwrap_or(0.0)).collect();
            let first_last = [
                r4(theta[0].to_degrees()),
                r4(theta[theta.len() - 1].to_degrees()),
            ];
            let fit = if span >= std::f64::consts::PI - 1e-9 {
                fit_circle(rows, &theta)
            } else {
                fit_line(rows, &theta)
            };
            (Some(axis.to_string()), first_last, fit)
        }
    };
    Ok(TestEvaluation {
        name: name.to_string(),
        poses: rows.len(),
        swept_axis,
        swept_deg,
        range_um: range,
        max_deviation_um: um(max_deviation),
        fit,
    })
}

/// Least squares of `y ≈ B·p` for each direction, with the basis `basis(θ)`; returns the
/// coefficients per direction and the RMS residual over all.
fn least_squares<const N: usize>(
    rows: &[&RtestRow],
    theta: &[Real],
    basis: impl Fn(Real) -> [Real; N],
) -> ([[Real; N]; 3], Real) {
    let design = nalgebra::DMatrix::from_fn(theta.len(), N, |i, k| basis(theta[i])[k]);
    let svd = mtwin_kernels::linalg::svd(design.clone(), true, true);
    let mut coefficients = [[0.0; N]; 3];
    let mut squares = 0.0;
    for (j, c) in coefficients.iter_mut().enumerate() {
        let y = nalgebra::DVector::from_iterator(
            rows.len(),
            rows.iter().map(|r| r.deviation[j] / M_PER_UM),
        );
        let p = mtwin_kernels::linalg::svd_solve(&svd, &y, 1e-12)
            .unwrap_or_else(|_| nalgebra::DVector::zeros(N));
        squares += (&design * &p - &y).norm_squared();
        c.iter_mut().zip(p.iter()).for_each(|(c, p)| *c = *p);
    }
    (coefficients, (squares / (3 * rows.len()) as Real).sqrt())
}

fn fit_circle(rows: &[&RtestRow], theta: &[Real]) -> Fit {
    let (p, residual) = least_squares(rows, theta, |t| [1.0, t.cos(), t.sin()]);
    let pick = |k: usize| [p[0][k], p[1][k], p[2][k]];
    let (c, s) = (pick(1), pick(2));
    let norm2 = |v: [Real; 3]| v.iter().map(|x| x * x).sum::<Real>();
    Fit::Circle {
        centre_um: r4s(pick(0)),
        cos_um: r4s(c),
        sin_um: r4s(s),
        radius_um: r4(((norm2(c) + norm2(s)) / 2.0).sqrt()),
        residual_um: r4(residual),
    }
}

fn fit_line(rows: &[&RtestRow], theta: &[Real]) -> Fit {
    let (p, residual) = least_squares(rows, theta, |t| [1.0, t.to_degrees()]);
    Fit::Line {
        intercept_um: r4s([p[0][0], p[1][0], p[2][0]]),
        slope_um_per_deg: [p[0][1], p[1][1], p[2][1]].map(|k| (k * 1e6).round() / 1e6),
        residual_um: r4(residual),
    }
}
