//! Levenberg–Marquardt for nonlinear least squares: minimise ½‖r(x)‖².
//!
//! The algorithm is Moré's (1978), as in MINPACK's `lmder`, with the linear algebra done by a
//! singular value decomposition instead of a pivoted QR.
//!
//! # Step
//!
//! At the current point `x`, with residuals `r` and Jacobian `J`, a trial step `δ` solves the
//! damped normal equations
//!
//! ```text
//! (JᵀJ + λ D²) δ = −Jᵀ r
//! ```
//!
//! without forming them. With the thin SVD of the column-scaled Jacobian `J D⁻¹ = U Σ Vᵀ`
//! (computed once per Jacobian, and kept while the scaled Jacobian is the same to the bit; for
//! a tall `J`, by a Householder QR first and the SVD of its small `R`, `U` never formed: see
//! `Decomposition`) and `c = Uᵀ r`, the scaled step is
//! `D δ = −V diag(σᵢ / (σᵢ² + λ)) c`, the exact least-squares solution of the augmented system
//! `[J; √λ D] δ ≈ [−r; 0]` for every `λ`, so trying another `λ` costs O(n²), not a new
//! factorisation. Singular values below `ε · max(m, n) · σ_max` are treated as zero (the rank
//! cut of a pseudo-inverse): a rank-deficient `J` gives a finite step with no component along
//! the directions the residuals cannot see, even at `λ = 0`.
//!
//! # Scaling, trust region and damping (Moré 1978, §§4–7)
//!
//! - `D = diag(dⱼ)`, with `dⱼ` the largest Euclidean norm that column `j` of `J` has had so far
//!   (1 while the column has always been zero). The iterates do not change when the parameters
//!   are rescaled, so metres, radians and seconds can be mixed.
//! - `λ` is not updated by a rule of thumb but chosen for a trust-region radius `Δ`: `λ = 0` if
//!   the Gauss–Newton step is shorter than `1.1 Δ` (in the scaled norm `‖Dδ‖`), otherwise the `λ`
//!   with `‖Dδ(λ)‖` within 10 % of `Δ`, found by Moré's safeguarded Newton iteration on
//!   `1/‖Dδ(λ)‖` (a few O(n) evaluations of `Σ (σᵢ cᵢ / (σᵢ² + λ))²`).
//! - `Δ₀ = factor · ‖D x₀‖` (`factor` = [`Options::initial_damping`], or `Δ₀ = factor` when
//!   `x₀ = 0`), then at most the length of the first step.
//! - The gain ratio `ρ = (F(x) − F(x + δ)) / (L(0) − L(δ))` compares the actual decrease of
//!   `F = ½‖r‖²` with the one predicted by the linear model `L(δ) = ½‖r + Jδ‖²`,
//!   `L(0) − L(δ) = Σ cᵢ² σᵢ² (σᵢ² + 2λ) / (2 (σᵢ² + λ)²)` (a sum of non-negative terms, no
//!   cancellation). `ρ ≤ ¼` shrinks `Δ` (by ½, or by MINPACK's interpolated factor in
//!   [0.1, 0.5] when `F` increased); `ρ ≥ ¾`, or `λ = 0`, sets `Δ = 2 ‖Dδ‖`. The step is taken
//!   when `ρ ≥ 10⁻⁴`.
//! - A trial point whose residuals are not all finite counts as a failed step (`Δ` shrinks).
//!
//! # Stopping tests (MINPACK's; Moré, Garbow & Hillstrom 1980, ANL-80-74, §2)
//!
//! - [`Termination::SmallCostChange`]: the actual and the predicted relative decreases of `F`
//!   are both at most `ftol`, and `ρ ≤ 2`.
//! - [`Termination::SmallStep`]: the scaled step `‖Dδ‖`, or the radius `Δ`, is at most
//!   `xtol (‖Dx‖ + xtol)`.
//! - [`Termination::SmallGradient`]: the largest cosine between `r` and a column of `J`,
//!   `maxⱼ |Jⱼᵀ r| / (‖Jⱼ‖ ‖r‖)`, is at most `gtol`.
//! - [`Termination::ZeroResidual`]: `r = 0` exactly.
//!
//! # References
//!
//! - J. J. Moré (1978), "The Levenberg–Marquardt algorithm: implementation and theory", in
//!   G. A. Watson (ed.), *Numerical Analysis*, Lecture Notes in Mathematics 630, pp. 105–116.
//! - J. J. Moré, B. S. Garbow, K. E. Hillstrom (1980), *User guide for MINPACK-1*, Argonne
//!   National Laboratory report ANL-80-74.

use crate::math::Real;
use mtwin_kernels::linalg;
use nalgebra::{DMatrix, DVector};

/// A nonlinear least-squares problem: minimise ½‖r(x)‖² over `x`.
pub trait Problem {
    /// Number of residuals `m`.
    fn residual_count(&self) -> usize;

    /// Number of parameters `n`.
    fn parameter_count(&self) -> usize;

    /// r(x) into `out` (length [`Problem::residual_count`]). Non-finite values at a trial point
    /// make the solver reject that point.
    fn residuals(&self, x: &[Real], out: &mut [Real]);

    /// Typical magnitude of parameter `j`, used only by the default finite-difference
    /// [`Problem::jacobian`] to size its step when `|xⱼ|` is smaller. The default, 0, makes the
    /// step relative to `|xⱼ|` alone (MINPACK's `fdjac2` rule); override it when a parameter
    /// starts at or passes through 0 and its scale is known (e.g. 1e-6 for errors in metres).
    fn typical_magnitude(&self, j: usize) -> Real {
        let _ = j;
        0.0
    }

    /// ∂rᵢ/∂xⱼ into `out` (residual_count × parameter_count).
    ///
    /// The default is [`forward_difference_jacobian`]: forward differences with the step
    /// `hⱼ = √ε · max(|xⱼ|, typical_magnitude(j))` (ε the f64 machine epsilon; `hⱼ = √ε` when
    /// that is 0), good to about eight significant digits, at the cost of n + 1 residual
    /// evaluations (not counted in [`Solution::evaluations`]). Problems with analytic Jacobians
    /// override it.
    fn jacobian(&self, x: &[Real], out: &mut DMatrix<Real>) {
        forward_difference_jacobian(self, x, out);
    }
}

/// The forward-difference Jacobian of `problem` at `x` into `out` (see [`Problem::jacobian`]
/// for the step). The step is rounded so that `xⱼ + hⱼ` is exact; n + 1 residual evaluations.
pub fn forward_difference_jacobian<P: Problem + ?Sized>(
    problem: &P,
    x: &[Real],
    out: &mut DMatrix<Real>,
) {
    let m = problem.residual_count();
    let mut r0 = vec![0.0; m];
    let mut r1 = vec![0.0; m];
    let mut xh = x.to_vec();
    problem.residuals(x, &mut r0);
    for j in 0..x.len() {
        let mut h = Real::EPSILON.sqrt() * x[j].abs().max(problem.typical_magnitude(j));
        if h == 0.0 {
            h = Real::EPSILON.sqrt();
        }
        xh[j] = x[j] + h;
        let h = xh[j] - x[j];
        problem.residuals(&xh, &mut r1);
        for (i, (a, b)) in r1.iter().zip(&r0).enumerate() {
            out[(i, j)] = (a - b) / h;
        }
        xh[j] = x[j];
    }
}

/// Solver settings.
#[derive(Clone, Debug)]
pub struct Options {
    /// Largest number of trial steps (each one a linear solve and a residual evaluation,
    /// whether the step is taken or not).
    pub max_iterations: usize,
    /// Stop when the actual and the predicted relative decreases of the cost are both at most
    /// this.
    pub ftol: Real,
    /// Stop when the scaled step, or the trust-region radius, is at most `xtol (‖Dx‖ + xtol)`.
    pub xtol: Real,
    /// Stop when the largest cosine between the residual vector and a Jacobian column is at
    /// most this.
    pub gtol: Real,
    /// Moré's `factor`: the first trust-region radius is `initial_damping · ‖D x₀‖` in the
    /// scaled norm (`initial_damping` itself when `x₀ = 0`), and the first step is no longer.
    /// Smaller values damp the first steps more, for starting points far from the solution;
    /// MINPACK's default is 100.
    pub initial_damping: Real,
}

impl Default for Options {
    /// `ftol` = 1e-15, `xtol` = `gtol` = 1e-12, `initial_damping` = 100, 1000 trial steps.
    ///
    /// `ftol` sits near rounding (a relative change of the cost of a few ulps) because the cost
    /// is flat at the minimum: a cost test at 1e-12 stops with parameters off by about
    /// `√(ftol · dof)` standard deviations, which is 1e-5 of one, but ≈ 1e-5 relative for a
    /// parameter whose standard deviation exceeds its value (NIST's ENSO b8). When rounding
    /// noise in the residuals keeps the cost test from firing, the step test ends the run.
    fn default() -> Self {
        Options {
            max_iterations: 1000,
            ftol: 1e-15,
            xtol: 1e-12,
            gtol: 1e-12,
            initial_damping: 100.0,
        }
    }
}

/// Why the solver stopped. Every reason but [`Termination::MaxIterations`] is a convergence test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// Actual and predicted relative decreases of the cost were both at most `ftol`.
    SmallCostChange,
    /// The scaled step, or the trust-region radius, was at most `xtol` relative to the scaled
    /// parameters.
    SmallStep,
    /// The residual vector is orthogonal to every Jacobian column within `gtol`.
    SmallGradient,
    /// The residuals are exactly zero.
    ZeroResidual,
    /// `max_iterations` trial steps were made without meeting a convergence test.
    MaxIterations,
}

/// The result of [`solve`].
#[derive(Clone, Debug)]
pub struct Solution {
    /// The parameters reached.
    pub x: Vec<Real>,
    /// r(x) at [`Solution::x`].
    pub residuals: Vec<Real>,
    /// ½‖r‖² at [`Solution::x`].
    pub cost: Real,
    /// Trial steps made (accepted and rejected).
    pub iterations: usize,
    /// Residual evaluations made by the solver (those inside a finite-difference Jacobian are
    /// not counted).
    pub evaluations: usize,
    /// Jacobian evaluations.
    pub jacobian_evaluations: usize,
    /// Why the solver stopped.
    pub termination: Termination,
    /// The Jacobian at [`Solution::x`].
    pub jacobian: DMatrix<Real>,
}

/// Why [`solve`] could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LmError {
    /// The starting vector does not have one value per parameter.
    #[error("the starting point has {found} values, but the problem has {expected} parameters")]
    DimensionMismatch {
        /// The problem's parameter count.
        expected: usize,
        /// The length of the starting point.
        found: usize,
    },
    /// The problem has no parameters or no residuals.
    #[error("the problem is empty ({residuals} residuals, {parameters} parameters)")]
    EmptyProblem {
        /// Residual count.
        residuals: usize,
        /// Parameter count.
        parameters: usize,
    },
    /// A setting is out of range.
    #[error("option {name} = {value} is out of range ({expected})")]
    InvalidOption {
        /// The option's field name.
        name: &'static str,
        /// Its value.
        value: Real,
        /// What is allowed.
        expected: &'static str,
    },
    /// The starting point has a non-finite value.
    #[error("starting parameter {index} is not finite ({value})")]
    NonFiniteStart {
        /// Parameter index.
        index: usize,
        /// Its value.
        value: Real,
    },
    /// The residuals at the starting point are not all finite.
    #[error("residual {index} is not finite ({value}) at the starting point")]
    NonFiniteResiduals {
        /// Residual index.
        index: usize,
        /// Its value.
        value: Real,
    },
    /// The Jacobian has a non-finite entry at an accepted point.
    #[error(
        "the Jacobian is not finite at an accepted point (entry ({row}, {column}) = {value}, after {iterations} trial steps)"
    )]
    NonFiniteJacobian {
        /// Residual index.
        row: usize,
        /// Parameter index.
        column: usize,
        /// The entry.
        value: Real,
        /// Trial steps made before.
        iterations: usize,
    },
    /// The singular value decomposition of the scaled Jacobian failed.
    #[error(
        "the SVD of the scaled Jacobian did not converge or was not finite (after {iterations} trial steps)"
    )]
    Svd {
        /// Trial steps made before.
        iterations: usize,
    },
}

/// Minimises ½‖r(x)‖² from `x0`. See the module documentation for the algorithm.
///
/// Workspaces are allocated once per call, except the SVD, which allocates its factors once per
/// Jacobian evaluation. The result is deterministic.
pub fn solve(problem: &impl Problem, x0: &[Real], options: &Options) -> Result<Solution, LmError> {
    let m = problem.residual_count();
    let n = problem.parameter_count();
    if m == 0 || n == 0 {
        return Err(LmError::EmptyProblem {
            residuals: m,
            parameters: n,
        });
    }
    if x0.len() != n {
        return Err(LmError::DimensionMismatch {
            expected: n,
            found: x0.len(),
        });
    }
    check_options(options)?;
    if let Some((index, &value)) = x0.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(LmError::NonFiniteStart { index, value });
    }

    let mut x = DVector::from_column_slice(x0);
    let mut r = DVector::zeros(m);
    problem.residuals(x.as_slice(), r.as_mut_slice());
    if let Some((index, &value)) = r.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(LmError::NonFiniteResiduals { index, value });
    }
    let mut cost = 0.5 * r.norm_squared();
    let mut evaluations = 1;
    let mut iterations = 0;

    let mut jac = DMatrix::zeros(m, n);
    evaluate_jacobian(problem, &x, &mut jac, iterations)?;
    let mut jacobian_evaluations = 1;
    let mut col_norms = DVector::zeros(n);
    let mut diag = DVector::zeros(n);
    update_scaling(&jac, &mut col_norms, &mut diag);

    // Workspaces.
    let k = m.min(n);
    let mut sigma = DVector::zeros(k);
    let mut c = DVector::zeros(k);
    let mut z = DVector::zeros(k);
    let mut p = DVector::zeros(n);
    let mut g = DVector::zeros(n);
    let mut x_new = DVector::zeros(n);
    let mut r_new = DVector::zeros(m);

    let mut delta: Real = 0.0;
    let mut lambda: Real = 0.0;
    // The last scaled Jacobian's decomposition.
    let mut kept: Option<Decomposition> = None;

    let termination = 'outer: loop {
        if cost == 0.0 {
            break Termination::ZeroResidual;
        }
        // Scaled gradient: the largest cosine between r and a column of J.
        jac.tr_mul_to(&r, &mut g);
        let r_norm = r.norm();
        let gnorm = g
            .iter()
            .zip(col_norms.iter())
            .filter(|&(_, &cn)| cn > 0.0)
            .map(|(&gj, &cn)| (gj / (cn * r_norm)).abs())
            .fold(0.0, Real::max);
        if gnorm <= options.gtol {
            break Termination::SmallGradient;
        }

        // Thin SVD of the column-scaled Jacobian J D⁻¹ = U Σ Vᵀ, c = Uᵀ r, and the rank cut.
        // A problem whose Jacobian does not change (a fixed design) gives the same scaled
        // matrix again, to the bit: its decomposition is kept rather than made anew.
        let scaled = DMatrix::from_fn(m, n, |i, j| jac[(i, j)] / diag[j]);
        let same = |previous: &DMatrix<Real>| {
            let bits = |a: &Real, b: &Real| a.to_bits() == b.to_bits();
            previous
                .as_slice()
                .iter()
                .zip(scaled.as_slice())
                .all(|(a, b)| bits(a, b))
        };
        if kept.as_ref().is_none_or(|kept| !same(&kept.scaled)) {
            kept = Some(Decomposition::new(scaled).ok_or(LmError::Svd { iterations })?);
        }
        let decomposition = kept.as_ref().expect("made above");
        let (svd, v_t) = (&decomposition.svd, &decomposition.v_t);
        let cut = svd.singular_values.max() * Real::EPSILON * m.max(n) as Real;
        for (s, &sv) in sigma.iter_mut().zip(svd.singular_values.iter()) {
            *s = if sv > cut { sv } else { 0.0 };
        }
        decomposition.u_tr_mul(&r, &mut c);
        let x_norm = x.component_mul(&diag).norm();
        if iterations == 0 {
            delta = if x_norm > 0.0 {
                options.initial_damping * x_norm
            } else {
                options.initial_damping
            };
        }

        loop {
            if iterations >= options.max_iterations {
                break 'outer Termination::MaxIterations;
            }
            lambda = lm_parameter(sigma.as_slice(), c.as_slice(), delta, lambda);

            // Scaled step p = D δ = V z, the decrease of ½‖r + Jδ‖² it predicts, and ‖Jδ‖².
            let mut predicted = 0.0;
            let mut jp2 = 0.0;
            for i in 0..k {
                let s2 = sigma[i] * sigma[i];
                if s2 > 0.0 {
                    let den = s2 + lambda;
                    z[i] = -sigma[i] * c[i] / den;
                    predicted += c[i] * c[i] * s2 * (1.0 + lambda / den) / (2.0 * den);
                    jp2 += s2 * z[i] * z[i];
                } else {
                    z[i] = 0.0;
                }
            }
            v_t.tr_mul_to(&z, &mut p);
            let p_norm = p.norm();
            if iterations == 0 {
                delta = delta.min(p_norm);
            }

            for j in 0..n {
                x_new[j] = x[j] + p[j] / diag[j];
            }
            problem.residuals(x_new.as_slice(), r_new.as_mut_slice());
            evaluations += 1;
            iterations += 1;
            let new_cost = if r_new.iter().all(|v| v.is_finite()) {
                0.5 * r_new.norm_squared()
            } else {
                Real::INFINITY
            };
            let actual = cost - new_cost;
            let rho = if predicted > 0.0 {
                actual / predicted
            } else {
                0.0
            };

            // Trust-region update (MINPACK lmder).
            if rho <= 0.25 {
                let mut shrink = if actual >= 0.0 {
                    0.5
                } else {
                    // Interpolate the cost along the step (directional derivative and value).
                    let dirder = -(jp2 + lambda * p_norm * p_norm) / (2.0 * cost);
                    let actred = actual / cost;
                    0.5 * dirder / (dirder + 0.5 * actred)
                };
                if new_cost >= 100.0 * cost || shrink.is_nan() || shrink < 0.1 {
                    shrink = 0.1;
                }
                delta = shrink * delta.min(p_norm / 0.1);
                lambda /= shrink;
            } else if lambda == 0.0 || rho >= 0.75 {
                delta = 2.0 * p_norm;
                lambda *= 0.5;
            }

            let small_change = actual.abs() <= options.ftol * cost
                && predicted <= options.ftol * cost
                && rho <= 2.0;
            let step_floor = options.xtol * (x_norm + options.xtol);
            let small_step = p_norm <= step_floor || delta <= step_floor;

            if rho >= 1e-4 {
                std::mem::swap(&mut x, &mut x_new);
                std::mem::swap(&mut r, &mut r_new);
                cost = new_cost;
                evaluate_jacobian(problem, &x, &mut jac, iterations)?;
                jacobian_evaluations += 1;
                update_scaling(&jac, &mut col_norms, &mut diag);
            }
            if small_change {
                break 'outer Termination::SmallCostChange;
            }
            if small_step {
                break 'outer Termination::SmallStep;
            }
            if rho >= 1e-4 {
                continue 'outer;
            }
        }
    };

    Ok(Solution {
        x: x.as_slice().to_vec(),
        residuals: r.as_slice().to_vec(),
        cost,
        iterations,
        evaluations,
        jacobian_evaluations,
        termination,
        jacobian: jac,
    })
}

/// Moré's `lmpar` on the SVD: the damping `λ ≥ 0` whose scaled step length
/// `‖p(λ)‖ = (Σ (σᵢ cᵢ / (σᵢ² + λ))²)^½` is within 10 % of `delta`, or 0 when the Gauss–Newton
/// step is already that short. Safeguarded Newton iteration on `1/‖p(λ)‖` (Moré 1978, §5),
/// started from `guess`, in the bracket `[0, ‖Σ c‖ / delta]` (at the upper end `‖p‖ ≤ delta`).
fn lm_parameter(sigma: &[Real], c: &[Real], delta: Real, guess: Real) -> Real {
    // ‖p(λ)‖ and Σ σᵢ² cᵢ² / (σᵢ² + λ)³ = −‖p‖ d‖p‖/dλ.
    let length = |lambda: Real| {
        let (mut p2, mut slope) = (0.0, 0.0);
        for (&s, &ci) in sigma.iter().zip(c) {
            if s > 0.0 {
                let den = s * s + lambda;
                let t = s * ci / den;
                p2 += t * t;
                slope += t * t / den;
            }
        }
        (p2.sqrt(), slope)
    };
    if length(0.0).0 <= 1.1 * delta {
        return 0.0;
    }
    let g_norm = sigma
        .iter()
        .zip(c)
        .map(|(s, ci)| (s * ci).powi(2))
        .sum::<Real>()
        .sqrt();
    let (mut low, mut high) = (0.0, g_norm / delta);
    if !high.is_finite() {
        return Real::MAX;
    }
    let mut lambda = guess;
    for _ in 0..50 {
        if !(lambda > low && lambda < high) {
            lambda = Real::max(1e-3 * high, (low * high).sqrt());
        }
        let (p_norm, slope) = length(lambda);
        let excess = p_norm - delta;
        if excess.abs() <= 0.1 * delta {
            return lambda;
        }
        if excess > 0.0 {
            low = lambda;
        } else {
            high = lambda;
        }
        lambda += (excess / delta) * p_norm * p_norm / slope;
    }
    // Not within 10 % after 50 iterations (does not happen in practice): the upper end of the
    // bracket gives a step no longer than `delta`.
    high
}

fn check_options(options: &Options) -> Result<(), LmError> {
    let nonnegative = [
        ("ftol", options.ftol),
        ("xtol", options.xtol),
        ("gtol", options.gtol),
    ];
    for (name, value) in nonnegative {
        if !(value >= 0.0 && value.is_finite()) {
            return Err(LmError::InvalidOption {
                name,
                value,
                expected: "finite and >= 0",
            });
        }
    }
    let value = options.initial_damping;
    if !(value > 0.0 && value.is_finite()) {
        return Err(LmError::InvalidOption {
            name: "initial_damping",
            value,
            expected: "finite and > 0",
        });
    }
    Ok(())
}

fn evaluate_jacobian(
    problem: &impl Problem,
    x: &DVector<Real>,
    jac: &mut DMatrix<Real>,
    iterations: usize,
) -> Result<(), LmError> {
    problem.jacobian(x.as_slice(), jac);
    match jac.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(at) => Err(LmError::NonFiniteJacobian {
            row: at % jac.nrows(),
            column: at / jac.nrows(),
            value: jac[at],
            iterations,
        }),
    }
}

/// Column norms of `jac`, and Moré's running-maximum scaling `dⱼ = max(dⱼ, ‖Jⱼ‖)` (1 while a
/// column has only ever been zero).
fn update_scaling(jac: &DMatrix<Real>, col_norms: &mut DVector<Real>, diag: &mut DVector<Real>) {
    for (j, column) in jac.column_iter().enumerate() {
        col_norms[j] = column.norm();
        if col_norms[j] > diag[j] {
            diag[j] = col_norms[j];
        }
        if diag[j] == 0.0 {
            diag[j] = 1.0;
        }
    }
}

/// The thin SVD `J D⁻¹ = U Σ Vᵀ` of a scaled Jacobian (m × n). Tall (m > n, the usual case:
/// thousands of readings, tens of unknowns), by Householder QR first, `J D⁻¹ = Q R`, and the
/// SVD of the small `R = U_R Σ Vᵀ`, so that `U = Q U_R` is never formed: `Uᵀ r = U_Rᵀ (Qᵀ r)`
/// with `Qᵀ r` from the reflections. The same singular values and `V` as the SVD of the tall
/// matrix (to rounding), at a fraction of its cost (bidiagonalising m × n and accumulating its
/// m × n `U`).
struct Decomposition {
    /// The matrix decomposed.
    scaled: DMatrix<Real>,
    /// Its QR when tall.
    qr: Option<mtwin_kernels::linalg::Qr>,
    /// The SVD of `R` (tall) or of the matrix itself, with `U`.
    svd: mtwin_kernels::linalg::Svd,
    v_t: DMatrix<Real>,
}

impl Decomposition {
    /// `None` when the SVD fails or gives a non-finite singular value.
    fn new(scaled: DMatrix<Real>) -> Option<Decomposition> {
        let tall = scaled.nrows() > scaled.ncols();
        let qr = tall.then(|| linalg::qr(scaled.clone()));
        let small = match &qr {
            Some(qr) => linalg::qr_r(qr),
            None => scaled.clone(),
        };
        let mut svd = linalg::try_svd_unordered(small, true, true, 5.0 * Real::EPSILON, 0)?;
        if svd.u.is_none() || svd.singular_values.iter().any(|s| !s.is_finite()) {
            return None;
        }
        let v_t = svd.v_t.take()?;
        Some(Decomposition {
            scaled,
            qr,
            svd,
            v_t,
        })
    }

    /// `c = Uᵀ r`.
    fn u_tr_mul(&self, r: &DVector<Real>, c: &mut DVector<Real>) {
        let u = self.svd.u.as_ref().expect("checked when made");
        match &self.qr {
            Some(qr) => {
                let mut qtr = r.clone();
                linalg::qr_q_tr_mul(qr, &mut qtr);
                u.tr_mul_to(&qtr.rows(0, u.nrows()), c);
            }
            None => u.tr_mul_to(r, c),
        }
    }
}
