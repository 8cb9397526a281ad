//! The MRS, MIC and MCC centres as linear programmes in 3–4 unknowns, solved exactly by a
//! small primal simplex on their duals (the exchange algorithm; see the module documentation
//! of [`polar`](super)).

use super::centre::{Centre, PolarError};
use super::extremes::{first_max, scale_of};
use crate::math::Real;

/// Pricing tolerance of the simplex, relative to the profile's scale `max |p|`: a point is
/// inside the circles if it is outside by at most this. Rounding of the residuals is about
/// 1e-16 of the scale, so this stops degenerate pivots on noise, and it bounds the error of a
/// value by 2e-13 of the scale.
const PRICING_TOL: Real = 1e-13;

/// Consecutive pivots without progress of the objective after which the simplex uses Bland's
/// rule (smallest index) to leave a degenerate vertex without cycling.
const STALL_LIMIT: usize = 8;

/// A multiplier of the MIC/MCC optimum (they sum to 1) at or below which the optimum is
/// treated as degenerate and the tie-break LP is solved.
const TIE_MULTIPLIER: Real = 1e-9;

/// The MRS offset and contacts: the Chebyshev fit `min_{a0,c} max_m |ρ_c[m] − a0|` (the MRS
/// value is twice its optimum), an LP in `y = (t, a0, cx, cy)`.
pub(super) fn minimum_zone(
    dirs: &[[Real; 2]],
    p: &[Real],
) -> Result<([Real; 2], Vec<usize>), PolarError> {
    const CENTRE: Centre = Centre::Mrs;
    // Four well-spread directions (farthest-point sampling).
    let mut chosen = [0usize; 4];
    let mut nearest = vec![Real::INFINITY; dirs.len()];
    for slot in 1..4 {
        let last = dirs[chosen[slot - 1]];
        let (mut best, mut best_d) = (0, -1.0);
        for (m, (d, near)) in dirs.iter().zip(nearest.iter_mut()).enumerate() {
            let chord2 = (d[0] - last[0]).powi(2) + (d[1] - last[1]).powi(2);
            *near = near.min(chord2);
            if *near > best_d {
                (best, best_d) = (m, *near);
            }
        }
        // A chord below 1e-6 (1e-6 rad) is the same direction.
        if best_d < 1e-12 {
            return Err(PolarError::TooFewDirections {
                centre: CENTRE,
                needed: 4,
            });
        }
        chosen[slot] = best;
    }
    // The null vector μ of the 3×4 matrix [(1, cosθ_i, sinθ_i)] with μ_3 = 1. Its signs give a
    // feasible dual start: λ_i = |μ_i| / Σ|μ| on the constraint of side sign(μ_i).
    let column = |m: usize| [1.0, dirs[m][0], dirs[m][1]];
    let mut a = [[0.0; 3]; 3];
    for (j, &m) in chosen[..3].iter().enumerate() {
        for (row, v) in column(m).into_iter().enumerate() {
            a[row][j] = v;
        }
    }
    let rhs = column(chosen[3]).map(|v| -v);
    let mu3 = solve(a, rhs).ok_or(PolarError::NotCertified {
        centre: CENTRE,
        reason: "singular starting reference",
    })?;
    let mu = [mu3[0], mu3[1], mu3[2], 1.0];
    let total: Real = mu.iter().map(|v| v.abs()).sum();
    if mu.iter().any(|v| v.abs() <= 1e-12 * total) {
        return Err(PolarError::NotCertified {
            centre: CENTRE,
            reason: "degenerate starting reference",
        });
    }
    let basis = std::array::from_fn(|i| 2 * chosen[i] + usize::from(mu[i] < 0.0));
    let family = Band { dirs, p };
    let tol = PRICING_TOL * scale_of(p);
    let vertex = simplex(&family, [1.0, 0.0, 0.0, 0.0], basis, tol, CENTRE)?;
    let mut contacts: Vec<usize> = vertex.basis.iter().map(|k| k / 2).collect();
    contacts.sort_unstable();
    contacts.dedup();
    Ok(([vertex.y[2], vertex.y[3]], contacts))
}

/// The MCC (`sigma = 1`) or MIC (`sigma = −1`) offset and contacts: phase 1 minimises
/// `t = max σρ_c`; if its optimum is degenerate, phase 2 maximises `min σρ_c` among the
/// centres with `max σρ_c ≤ t* + tol`.
/// The caller has checked that the directions surround the centre.
pub(super) fn one_sided(
    dirs: &[[Real; 2]],
    p: &[Real],
    sigma: Real,
    centre: Centre,
) -> Result<([Real; 2], Vec<usize>), PolarError> {
    // Start: a triangle of directions around the centre, from the highest point i: j the
    // farthest direction counter-clockwise within (0, π), k the farthest clockwise within
    // (0, π]. With no gap ≥ π, the arcs i→j, j→k, k→i are all ≤ π.
    let mut i = 0;
    for (m, &v) in p.iter().enumerate() {
        if sigma * v > sigma * p[i] {
            i = m;
        }
    }
    let ui = dirs[i];
    let (mut j, mut k) = (None, None);
    let (mut dot_j, mut dot_k) = (Real::INFINITY, Real::INFINITY);
    for (m, u) in dirs.iter().enumerate() {
        let cross = ui[0] * u[1] - ui[1] * u[0];
        let dot = ui[0] * u[0] + ui[1] * u[1];
        if cross > 0.0 {
            if dot < dot_j {
                (j, dot_j) = (Some(m), dot);
            }
        } else if (cross < 0.0 || dot < 0.0) && dot < dot_k {
            (k, dot_k) = (Some(m), dot);
        }
    }
    let (Some(j), Some(k)) = (j, k) else {
        return Err(PolarError::NotCertified {
            centre,
            reason: "no starting triangle around the centre",
        });
    };
    let tol = PRICING_TOL * scale_of(p);
    let upper = Upper { dirs, p, sigma };
    let first = simplex(&upper, [1.0, 0.0, 0.0], [i, j, k], tol, centre)?;
    // With every multiplier positive, the three contacts are tight at every optimum
    // (complementary slackness) and fix the centre: it is unique, no tie to break.
    let mut contacts: Vec<usize> = first
        .basis
        .iter()
        .zip(first.lambda)
        .filter(|&(_, l)| l > TIE_MULTIPLIER)
        .map(|(&m, _)| m)
        .collect();
    let offset = if contacts.len() == 3 {
        [first.y[1], first.y[2]]
    } else {
        // A degenerate optimum (two antipodal contacts): a segment of centres reaches t*.
        // Among them, the largest min σρ_c; the contacts with a positive multiplier stay on
        // the outer circle, the phase-2 basis is tight at the final centre.
        let capped = Capped {
            dirs,
            p,
            sigma,
            cap: first.y[0] + tol,
        };
        let second = simplex(
            &capped,
            [-1.0, 0.0, 0.0],
            [2 * i, 2 * j, 2 * k],
            tol,
            centre,
        )?;
        contacts.extend(second.basis.iter().map(|k| k / 2));
        [second.y[1], second.y[2]]
    };
    contacts.sort_unstable();
    contacts.dedup();
    Ok((offset, contacts))
}

/// The constraints `a_k · y ≥ h_k` of a primal `min b · y`, i.e. the columns of its dual
/// `max h · λ` s.t. `Σ λ_k a_k = b`, `λ ≥ 0`. The violation of constraint `k` at `y` is
/// `h_k − a_k · y` (the reduced cost of its column).
trait Family<const N: usize> {
    /// Number of constraints.
    fn count(&self) -> usize;
    /// `(a_k, h_k)`.
    fn column(&self, k: usize) -> ([Real; N], Real);
    /// The most violated constraint and its violation (Dantzig's rule).
    fn most_violated(&self, y: &[Real; N]) -> (usize, Real);
    /// The first constraint (smallest `k`) violated by more than `tol` (Bland's rule).
    fn first_violated(&self, y: &[Real; N], tol: Real) -> Option<usize>;
}

/// MCC/MIC phase 1, `y = (t, cx, cy)`: `t ≥ σρ_c[m]`, i.e. `t + σ u_m·c ≥ σ p_m`.
struct Upper<'a> {
    dirs: &'a [[Real; 2]],
    p: &'a [Real],
    sigma: Real,
}

impl Family<3> for Upper<'_> {
    fn count(&self) -> usize {
        self.p.len()
    }

    fn column(&self, k: usize) -> ([Real; 3], Real) {
        let [c, s] = self.dirs[k];
        let g = self.sigma;
        ([1.0, g * c, g * s], g * self.p[k])
    }

    fn most_violated(&self, y: &[Real; 3]) -> (usize, Real) {
        let [t, cx, cy] = *y;
        let g = self.sigma;
        let (best, best_d) = first_max(self.dirs, self.p, |[c, s], v| g * (v - cx * c - cy * s));
        (best, best_d - t)
    }

    fn first_violated(&self, y: &[Real; 3], tol: Real) -> Option<usize> {
        let [t, cx, cy] = *y;
        let g = self.sigma;
        self.dirs
            .iter()
            .zip(self.p)
            .position(|(&[c, s], &v)| g * (v - cx * c - cy * s) - t > tol)
    }
}

/// MRS, `y = (t, a0, cx, cy)`: `t ≥ ±(ρ_c[m] − a0)`; constraint `2m` is the `+` side (outer
/// circle), `2m + 1` the `−` side (inner circle).
struct Band<'a> {
    dirs: &'a [[Real; 2]],
    p: &'a [Real],
}

impl Family<4> for Band<'_> {
    fn count(&self) -> usize {
        2 * self.p.len()
    }

    fn column(&self, k: usize) -> ([Real; 4], Real) {
        let m = k / 2;
        let g = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
        let [c, s] = self.dirs[m];
        ([1.0, g, g * c, g * s], g * self.p[m])
    }

    fn most_violated(&self, y: &[Real; 4]) -> (usize, Real) {
        let [t, a0, cx, cy] = *y;
        let residual = |[c, s]: [Real; 2], v: Real| v - a0 - cx * c - cy * s;
        let (best, _) = first_max(self.dirs, self.p, |d, v| residual(d, v).abs());
        let best_r = residual(self.dirs[best], self.p[best]);
        (2 * best + usize::from(best_r < 0.0), best_r.abs() - t)
    }

    fn first_violated(&self, y: &[Real; 4], tol: Real) -> Option<usize> {
        let [t, a0, cx, cy] = *y;
        for (m, (&[c, s], &v)) in self.dirs.iter().zip(self.p).enumerate() {
            let r = v - a0 - cx * c - cy * s;
            if r - t > tol {
                return Some(2 * m);
            }
            if -r - t > tol {
                return Some(2 * m + 1);
            }
        }
        None
    }
}

/// MCC/MIC phase 2, `y = (l, cx, cy)`, maximise `l`: constraint `2m` is `σρ_c[m] ≥ l`
/// (`−l − σu_m·c ≥ −σp_m`), `2m + 1` is `σρ_c[m] ≤ cap` (`σu_m·c ≥ σp_m − cap`).
struct Capped<'a> {
    dirs: &'a [[Real; 2]],
    p: &'a [Real],
    sigma: Real,
    cap: Real,
}

impl Family<3> for Capped<'_> {
    fn count(&self) -> usize {
        2 * self.p.len()
    }

    fn column(&self, k: usize) -> ([Real; 3], Real) {
        let m = k / 2;
        let [c, s] = self.dirs[m];
        let g = self.sigma;
        if k.is_multiple_of(2) {
            ([-1.0, -g * c, -g * s], -g * self.p[m])
        } else {
            ([0.0, g * c, g * s], g * self.p[m] - self.cap)
        }
    }

    fn most_violated(&self, y: &[Real; 3]) -> (usize, Real) {
        let [l, cx, cy] = *y;
        let g = self.sigma;
        let (mut low, mut low_rho) = (0, Real::INFINITY);
        let (mut high, mut high_rho) = (0, Real::NEG_INFINITY);
        for (m, (&[c, s], &v)) in self.dirs.iter().zip(self.p).enumerate() {
            let rho = g * (v - cx * c - cy * s);
            if rho < low_rho {
                (low, low_rho) = (m, rho);
            }
            if rho > high_rho {
                (high, high_rho) = (m, rho);
            }
        }
        let (below, above) = (l - low_rho, high_rho - self.cap);
        if below >= above {
            (2 * low, below)
        } else {
            (2 * high + 1, above)
        }
    }

    fn first_violated(&self, y: &[Real; 3], tol: Real) -> Option<usize> {
        let [l, cx, cy] = *y;
        let g = self.sigma;
        for (m, (&[c, s], &v)) in self.dirs.iter().zip(self.p).enumerate() {
            let rho = g * (v - cx * c - cy * s);
            if l - rho > tol {
                return Some(2 * m);
            }
            if rho - self.cap > tol {
                return Some(2 * m + 1);
            }
        }
        None
    }
}

/// An optimal vertex: the primal `y`, the basis (constraint indices) and the dual multipliers.
struct Vertex<const N: usize> {
    y: [Real; N],
    basis: [usize; N],
    lambda: [Real; N],
}

/// Primal simplex on the dual `max h·λ` s.t. `Σ λ_k a_k = b`, `λ ≥ 0`, from a feasible basis.
/// Stops when no constraint is violated by more than `tol`, after checking the certificate.
fn simplex<const N: usize, F: Family<N>>(
    family: &F,
    b: [Real; N],
    mut basis: [usize; N],
    tol: Real,
    centre: Centre,
) -> Result<Vertex<N>, PolarError> {
    let fail = |reason| PolarError::NotCertified { centre, reason };
    let max_iterations = 1000 + 4 * family.count();
    let mut bland = false;
    let mut stalls = 0;
    let mut best = Real::NEG_INFINITY;
    for _ in 0..max_iterations {
        let mut matrix = [[0.0; N]; N]; // matrix[row][i] = a_{basis[i]}[row]
        let mut transposed = [[0.0; N]; N];
        let mut h = [0.0; N];
        for (i, &k) in basis.iter().enumerate() {
            let (a, hk) = family.column(k);
            for (row, v) in a.into_iter().enumerate() {
                matrix[row][i] = v;
            }
            transposed[i] = a;
            h[i] = hk;
        }
        let lambda = solve(matrix, b).ok_or_else(|| fail("singular basis"))?;
        let y = solve(transposed, h).ok_or_else(|| fail("singular basis"))?;
        let objective: Real = b.iter().zip(&y).map(|(u, v)| u * v).sum();
        if objective > best + 0.01 * tol {
            best = objective;
            stalls = 0;
        } else {
            stalls += 1;
            bland |= stalls > STALL_LIMIT;
        }
        let entering = if bland {
            family.first_violated(&y, tol)
        } else {
            Some(family.most_violated(&y))
                .filter(|&(_, d)| d > tol)
                .map(|(k, _)| k)
        };
        let Some(q) = entering else {
            certify(&matrix, &b, &lambda).map_err(fail)?;
            return Ok(Vertex { y, basis, lambda });
        };
        let w = solve(matrix, family.column(q).0).ok_or_else(|| fail("singular basis"))?;
        let w_max = w.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
        let mut leaving: Option<(usize, Real)> = None;
        for i in 0..N {
            if w[i] <= 1e-12 * w_max {
                continue;
            }
            let ratio = lambda[i].max(0.0) / w[i];
            leaving = match leaving {
                None => Some((i, ratio)),
                Some((r, best_ratio)) => {
                    let tie = (ratio - best_ratio).abs() <= 1e-12;
                    let better = if tie {
                        if bland {
                            basis[i] < basis[r]
                        } else {
                            w[i] > w[r]
                        }
                    } else {
                        ratio < best_ratio
                    };
                    if better {
                        Some((i, ratio))
                    } else {
                        Some((r, best_ratio))
                    }
                }
            };
        }
        let Some((r, _)) = leaving else {
            return Err(fail("unbounded dual ray"));
        };
        basis[r] = q;
    }
    Err(fail("no convergence within the iteration limit"))
}

/// Dual feasibility of the final basis: `λ ≥ 0` and `B λ = b`, both to 1e-9 relative.
fn certify<const N: usize>(
    matrix: &[[Real; N]; N],
    b: &[Real; N],
    lambda: &[Real; N],
) -> Result<(), &'static str> {
    let size: Real = lambda.iter().map(|v| v.abs()).sum::<Real>() + 1.0;
    if lambda.iter().any(|&l| l < -1e-9 * size) {
        return Err("negative multiplier");
    }
    for (row, &bv) in matrix.iter().zip(b) {
        let residual: Real = row.iter().zip(lambda).map(|(a, l)| a * l).sum::<Real>() - bv;
        if residual.abs() > 1e-9 * size {
            return Err("multipliers do not balance the objective");
        }
    }
    Ok(())
}

/// `a x = b` by Gaussian elimination with partial pivoting; `None` if a pivot is below 1e-13
/// of the largest entry.
fn solve<const N: usize>(mut a: [[Real; N]; N], mut b: [Real; N]) -> Option<[Real; N]> {
    let norm = a.iter().flatten().fold(0.0, |m: Real, v| m.max(v.abs()));
    if norm.is_nan() || norm == 0.0 {
        return None;
    }
    for col in 0..N {
        let mut pivot = col;
        for row in col + 1..N {
            if a[row][col].abs() > a[pivot][col].abs() {
                pivot = row;
            }
        }
        if a[pivot][col].abs() <= 1e-13 * norm {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let head = a[col];
        for row in col + 1..N {
            let f = a[row][col] / head[col];
            for (x, h) in a[row][col..].iter_mut().zip(&head[col..]) {
                *x -= f * h;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; N];
    for col in (0..N).rev() {
        let tail: Real = (col + 1..N).map(|k| a[col][k] * x[k]).sum();
        x[col] = (b[col] - tail) / a[col][col];
    }
    Some(x)
}
