//! Sphere and circle fits: the algebraic (Kåsa) fit, linear in the centre and `R² − |c|²`, as
//! the start, then the geometric least-squares fit (minimum of `Σ (|pᵢ − c| − R)²`) by
//! Levenberg–Marquardt on nalgebra. One routine serves both dimensions.

use crate::math::{Real, Vector};
use mtwin_kernels::linalg;
use nalgebra::{DMatrix, DVector};

/// Why a fit could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FitError {
    /// Fewer points than the fit needs.
    #[error("{found} points: a {shape} fit needs at least {needed}")]
    TooFewPoints {
        /// The shape (`sphere`, `circle`).
        shape: &'static str,
        /// How many it needs.
        needed: usize,
        /// How many there are.
        found: usize,
    },
    /// The points do not determine the shape (a sphere through coplanar points, a circle
    /// through collinear ones, or repeated points).
    #[error("the points do not determine a {0}: they lie on a lower-dimensional set")]
    Degenerate(&'static str),
    /// A coordinate is not finite.
    #[error("a point is not finite")]
    NotFinite,
}

/// A geometric least-squares fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit<const D: usize> {
    /// The centre.
    pub centre: [Real; D],
    /// The radius.
    pub radius: Real,
    /// Each point's distance from the centre minus the radius, in the points' order.
    pub residuals: Vec<Real>,
}

impl<const D: usize> Fit<D> {
    /// The form deviation: the largest residual minus the smallest (the range of the radii; for
    /// 25 points on a sphere, ISO 10360-5's P_FTU).
    pub fn form(&self) -> Real {
        let max = self.residuals.iter().copied().fold(Real::MIN, Real::max);
        let min = self.residuals.iter().copied().fold(Real::MAX, Real::min);
        max - min
    }

    /// The root-mean-square residual.
    pub fn rms(&self) -> Real {
        let n = self.residuals.len().max(1) as Real;
        (self.residuals.iter().map(|r| r * r).sum::<Real>() / n).sqrt()
    }
}

/// A sphere fit.
pub type SphereFit = Fit<3>;
/// A circle fit (in a plane).
pub type CircleFit = Fit<2>;

/// The algebraic (Kåsa) sphere through `points`: centre and radius.
pub fn algebraic_sphere(points: &[Vector]) -> Result<(Vector, Real), FitError> {
    let arrays: Vec<[Real; 3]> = points.iter().map(|p| p.to_array()).collect();
    let (centre, radius) = algebraic(&arrays, "sphere")?;
    Ok((Vector::from_array(centre), radius))
}

/// The geometric least-squares sphere through `points` (at least 4, not coplanar).
pub fn fit_sphere(points: &[Vector]) -> Result<SphereFit, FitError> {
    let arrays: Vec<[Real; 3]> = points.iter().map(|p| p.to_array()).collect();
    let (centre, radius) = algebraic(&arrays, "sphere")?;
    Ok(geometric(&arrays, centre, radius))
}

/// The algebraic (Kåsa) circle through planar `points`.
pub fn algebraic_circle(points: &[[Real; 2]]) -> Result<([Real; 2], Real), FitError> {
    algebraic(points, "circle")
}

/// The geometric least-squares circle through planar `points` (at least 3, not collinear).
pub fn fit_circle(points: &[[Real; 2]]) -> Result<CircleFit, FitError> {
    let (centre, radius) = algebraic(points, "circle")?;
    Ok(geometric(points, centre, radius))
}

/// Kåsa: `|q|² = 2 c·q + k` is linear in `(c, k)` with `k = R² − |c|²`; solved by SVD on
/// coordinates relative to the mean (for conditioning), refused when the smallest singular
/// value is under 1e-9 of the largest.
fn algebraic<const D: usize>(
    points: &[[Real; D]],
    shape: &'static str,
) -> Result<([Real; D], Real), FitError> {
    let needed = D + 1;
    if points.len() < needed {
        return Err(FitError::TooFewPoints {
            shape,
            needed,
            found: points.len(),
        });
    }
    if points.iter().flatten().any(|x| !x.is_finite()) {
        return Err(FitError::NotFinite);
    }
    let n = points.len() as Real;
    let mut mean = [0.0; D];
    for p in points {
        for (m, x) in mean.iter_mut().zip(p) {
            *m += x / n;
        }
    }
    let scale = points
        .iter()
        .map(|p| {
            p.iter()
                .zip(&mean)
                .map(|(x, m)| (x - m) * (x - m))
                .sum::<Real>()
        })
        .sum::<Real>();
    let scale = (scale / n).sqrt();
    if scale == 0.0 {
        return Err(FitError::Degenerate(shape));
    }
    let a = DMatrix::from_fn(points.len(), needed, |i, j| {
        if j < D {
            2.0 * (points[i][j] - mean[j]) / scale
        } else {
            1.0
        }
    });
    let b = DVector::from_fn(points.len(), |i, _| {
        points[i]
            .iter()
            .zip(&mean)
            .map(|(x, m)| ((x - m) / scale).powi(2))
            .sum::<Real>()
    });
    let svd = linalg::svd(a, true, true);
    let (max, min) = (svd.singular_values.max(), svd.singular_values.min());
    if min.is_nan() || min <= 1e-9 * max {
        return Err(FitError::Degenerate(shape));
    }
    let x = linalg::svd_solve(&svd, &b, 0.0).map_err(|_| FitError::Degenerate(shape))?;
    let mut centre = mean;
    let mut c_squared = 0.0;
    for (j, c) in centre.iter_mut().enumerate() {
        *c += x[j] * scale;
        c_squared += x[j] * x[j];
    }
    let r_squared = x[D] + c_squared;
    if r_squared.is_nan() || r_squared <= 0.0 {
        return Err(FitError::Degenerate(shape));
    }
    Ok((centre, r_squared.sqrt() * scale))
}

/// Levenberg–Marquardt on `rᵢ = |pᵢ − c| − R` from `(centre, radius)`: steps from
/// `(JᵀJ + λ·diag JᵀJ) δ = −Jᵀr`, λ shrunk on success and grown on failure; stops when a step
/// is under 1e-15 of the radius or λ exceeds 1e12.
fn geometric<const D: usize>(points: &[[Real; D]], centre: [Real; D], radius: Real) -> Fit<D> {
    let unknowns = D + 1;
    let residuals = |c: &[Real; D], r: Real| -> Vec<Real> {
        points.iter().map(|p| distance(p, c) - r).collect()
    };
    let cost = |res: &[Real]| res.iter().map(|r| r * r).sum::<Real>();
    let (mut c, mut r) = (centre, radius);
    let mut res = residuals(&c, r);
    let mut current = cost(&res);
    let mut lambda = 1e-3;
    for _ in 0..200 {
        let mut jtj = DMatrix::<Real>::zeros(unknowns, unknowns);
        let mut jtr = DVector::<Real>::zeros(unknowns);
        for (p, ri) in points.iter().zip(&res) {
            let d = distance(p, &c).max(Real::MIN_POSITIVE);
            let mut row = [0.0; 4];
            for j in 0..D {
                row[j] = -(p[j] - c[j]) / d;
            }
            row[D] = -1.0;
            for a in 0..unknowns {
                jtr[a] += row[a] * ri;
                for b in 0..unknowns {
                    jtj[(a, b)] += row[a] * row[b];
                }
            }
        }
        let mut improved = false;
        let mut step_size = 0.0;
        while lambda < 1e12 {
            let mut damped = jtj.clone();
            for a in 0..unknowns {
                damped[(a, a)] += lambda * jtj[(a, a)].max(1e-30);
            }
            let Some(step) = linalg::lu_solve(&linalg::lu(damped), &(-&jtr)) else {
                lambda *= 10.0;
                continue;
            };
            let mut c_new = c;
            for j in 0..D {
                c_new[j] += step[j];
            }
            let r_new = r + step[D];
            let res_new = residuals(&c_new, r_new);
            let new = cost(&res_new);
            if new <= current {
                step_size = step.norm();
                (c, r, res, current) = (c_new, r_new, res_new, new);
                lambda = (lambda / 10.0).max(1e-12);
                improved = true;
                break;
            }
            lambda *= 10.0;
        }
        if !improved || step_size <= 1e-15 * r.abs().max(1e-300) {
            break;
        }
    }
    Fit {
        centre: c,
        radius: r,
        residuals: res,
    }
}

fn distance<const D: usize>(p: &[Real; D], c: &[Real; D]) -> Real {
    p.iter()
        .zip(c)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<Real>()
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_circle_through_three_points_is_exact() {
        // The circle through (1, 0), (0, 1), (−1, 0) is the unit circle about the origin.
        let fit = fit_circle(&[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]]).unwrap();
        assert!(fit.centre[0].abs() < 1e-14 && fit.centre[1].abs() < 1e-14);
        assert!((fit.radius - 1.0).abs() < 1e-14);
        assert!(fit_circle(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).is_err());
    }
}
