//! The span of the profile's columns (its hats) on a training set, and the projection off it
//! that every trial of a search ([`PositioningProblem::sse_profile`]) makes of its changing
//! columns and target.
//!
//! A reading lies on at most two adjacent hats, so the Gram matrix HᵀH of the hats is
//! tridiagonal and the projection v − H·(HᵀH)⁻¹·Hᵀv costs a few operations per row ([`Banded`])
//! instead of two per row and hat with an orthonormal basis of the span. The normal equations
//! square the hats' condition, so they are used only when the hats, scaled to unit norm, have a
//! Gram matrix whose smallest eigenvalue is above [`WELL_CONDITIONED`] (10⁻²; the largest is
//! below 3, so its condition is below 300 and the hats' below 18): the projection is then good
//! to about 300 · 18 · 2⁻⁵³ ≈ 10⁻¹² of the vector, a thousandth of the rank cut that decides
//! whether a trial's column is one of its own (and to 10⁻⁹ of the full solve's sum of squares,
//! tested). Every singular value of the scaled hats is then above a tenth, far above the rank
//! cut, so the span is the one the dense basis would keep. Otherwise (a hat without training
//! readings, two hats that only readings between them tell apart) the left singular vectors
//! above the rank cut are used, as the full solve cuts them ([`HatSpan::Dense`]). The ISO
//! layout (every reading on a knot) has orthogonal hats; scattered targets fall back to the
//! dense basis only where readings pile up between two knots with none on them.

use super::PositioningProblem;
use crate::discovery::least_squares::RANK_TOLERANCE;
use crate::math::{Real, dot};
use mtwin_kernels::linalg;
use nalgebra::DMatrix;
use std::sync::Arc;

/// The smallest eigenvalue of the unit-scaled hats' Gram matrix for the banded projection.
pub(super) const WELL_CONDITIONED: Real = 1e-2;

/// The hats' span on a training set.
#[derive(Clone, Debug)]
pub(super) enum HatSpan {
    /// Through the tridiagonal normal equations (well-conditioned hats).
    Banded(Arc<Banded>),
    /// An orthonormal basis (rows × rank) above the rank cut; `None` without hats or rows.
    Dense(Option<DMatrix<Real>>),
}

/// The hats on the training rows and the factors of their Gram matrix.
#[derive(Clone, Debug)]
pub(super) struct Banded {
    /// Per training row: its left hat, that hat's weight and the next hat's (0 at the ends,
    /// where the next is a slot past the last hat that is kept at 0).
    left: Vec<usize>,
    a: Vec<Real>,
    b: Vec<Real>,
    /// HᵀH = L·D·Lᵀ: the pivots D and the multipliers below L's diagonal.
    pivots: Vec<Real>,
    multipliers: Vec<Real>,
}

impl PositioningProblem {
    /// A reading's place on the profile's `knots`: the left hat, its weight and the next hat's
    /// (constant beyond the ends: one hat, weight 1).
    pub(super) fn hat_weights(knots: &[Real], x: Real) -> (usize, Real, Real) {
        let j = knots.partition_point(|&k| k <= x);
        if j == 0 {
            (0, 1.0, 0.0)
        } else if j == knots.len() {
            (j - 1, 1.0, 0.0)
        } else {
            let w = (x - knots[j - 1]) / (knots[j] - knots[j - 1]);
            (j - 1, 1.0 - w, w)
        }
    }

    /// The span of the hats on `knots` over the training `rows` (indices, in order).
    pub(super) fn hat_span(&self, knots: &[Real], rows: &[usize]) -> HatSpan {
        let weights: Vec<(usize, Real, Real)> = rows
            .iter()
            .map(|&i| Self::hat_weights(knots, self.x[i]))
            .collect();
        if let Some(banded) = Banded::new(weights, knots.len()) {
            return HatSpan::Banded(Arc::new(banded));
        }
        let hats = self.hats(knots);
        let kept: Vec<Vec<Real>> = hats
            .iter()
            .filter_map(|c| {
                let values: Vec<Real> = rows.iter().map(|&i| c[i]).collect();
                let norm = dot(&values, &values).sqrt();
                (norm > 0.0).then(|| values.iter().map(|v| v / norm).collect())
            })
            .collect();
        HatSpan::Dense(span(&kept, rows.len()))
    }
}

impl Banded {
    /// The factors for `weights` on `hats` hats, or `None` when the unit-scaled Gram matrix has
    /// an eigenvalue at or below [`WELL_CONDITIONED`] (a hat without readings included).
    fn new(weights: Vec<(usize, Real, Real)>, hats: usize) -> Option<Banded> {
        if hats == 0 {
            return None;
        }
        let (mut diagonal, mut off) = (vec![0.0; hats], vec![0.0; hats.saturating_sub(1)]);
        for &(j, a, b) in &weights {
            diagonal[j] += a * a;
            if b != 0.0 {
                diagonal[j + 1] += b * b;
                off[j] += a * b;
            }
        }
        if diagonal.iter().any(|&d| d <= 0.0) {
            return None;
        }
        // Sylvester's criterion on S·G·S − εI (S scaling to a unit diagonal): every pivot of
        // its LDLᵀ positive ⇔ every eigenvalue of the scaled Gram matrix above ε.
        let mut pivot = 1.0 - WELL_CONDITIONED;
        for (j, &g) in off.iter().enumerate() {
            let scaled = g / (diagonal[j] * diagonal[j + 1]).sqrt();
            pivot = 1.0 - WELL_CONDITIONED - scaled * scaled / pivot;
            if pivot <= 0.0 {
                return None;
            }
        }
        let mut pivots = vec![diagonal[0]];
        let mut multipliers = Vec::with_capacity(off.len());
        for (j, &g) in off.iter().enumerate() {
            let l = g / pivots[j];
            multipliers.push(l);
            pivots.push(diagonal[j + 1] - l * g);
        }
        Some(Banded {
            left: weights.iter().map(|w| w.0).collect(),
            a: weights.iter().map(|w| w.1).collect(),
            b: weights.iter().map(|w| w.2).collect(),
            pivots,
            multipliers,
        })
    }

    /// `v` (one value per training row) less its least-squares fit by the hats.
    pub(super) fn project(&self, v: &mut [Real]) {
        let hats = self.pivots.len();
        // One slot past the last hat for the rows beyond the ends (weight 0 there).
        let mut c = vec![0.0; hats + 1];
        let rows = self.left.iter().zip(&self.a).zip(&self.b);
        // A reading on a knot has no second hat (b = 0): its term adds an exact zero there, so
        // it is left out (the sum is the same to the bit; the slot never holds −0).
        for (((&j, &a), &b), &v) in rows.clone().zip(v.iter()) {
            c[j] += a * v;
            if b != 0.0 {
                c[j + 1] += b * v;
            }
        }
        // (L·D·Lᵀ)·c = Hᵀv on the hats; the slot past them stays 0.
        c[hats] = 0.0;
        for j in 1..hats {
            c[j] -= self.multipliers[j - 1] * c[j - 1];
        }
        c.iter_mut().zip(&self.pivots).for_each(|(c, d)| *c /= d);
        for j in (0..hats - 1).rev() {
            c[j] -= self.multipliers[j] * c[j + 1];
        }
        for (((&j, &a), &b), v) in rows.zip(v.iter_mut()) {
            *v -= if b != 0.0 {
                a * c[j] + b * c[j + 1]
            } else {
                a * c[j]
            };
        }
    }
}

/// An orthonormal basis (rows × r) of the span of `columns` (each of length `rows`, scaled to
/// unit norm): the left singular vectors above the rank cut; `None` without columns. Tall
/// (the usual case), by Householder QR first and the SVD of the small triangle, U = Q·U_R:
/// the same singular values at a fraction of the cost of bidiagonalising the tall matrix.
fn span(columns: &[Vec<Real>], rows: usize) -> Option<DMatrix<Real>> {
    if columns.is_empty() || rows == 0 {
        return None;
    }
    let m = DMatrix::from_fn(rows, columns.len(), |i, j| columns[j][i]);
    let (q, svd) = if rows > columns.len() {
        let qr = linalg::qr(m);
        (
            Some(linalg::qr_q(&qr)),
            linalg::svd(linalg::qr_r(&qr), true, false),
        )
    } else {
        (None, linalg::svd(m, true, false))
    };
    let u = svd.u.expect("computed");
    let largest = svd.singular_values.max();
    let keep: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&k| svd.singular_values[k] > largest * RANK_TOLERANCE)
        .collect();
    let kept = DMatrix::from_fn(u.nrows(), keep.len(), |i, j| u[(i, keep[j])]);
    Some(match q {
        Some(q) => q * kept,
        None => kept,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The projection off the columns of `m` by a least-squares solve (QR of `m`).
    fn dense_projection(m: &DMatrix<Real>, v: &[Real]) -> Vec<Real> {
        let u = span(
            &m.column_iter()
                .map(|c| {
                    let n = c.norm();
                    c.iter().map(|x| x / n).collect()
                })
                .collect::<Vec<Vec<Real>>>(),
            m.nrows(),
        )
        .unwrap();
        let v = nalgebra::DVector::from_column_slice(v);
        (&v - &u * (u.transpose() * &v)).iter().copied().collect()
    }

    #[test]
    fn the_banded_projection_is_the_least_squares_residual() {
        // Knots at 0, 10, 25, 40 mm; readings at the knots, between them and beyond both
        // ends: the residual off the hats equals the dense projection's to 1e-13 of the
        // vector, and is orthogonal to every hat.
        let knots = [0.0, 10.0, 25.0, 40.0];
        let x = [
            -3.0, 0.0, 0.0, 4.0, 10.0, 10.0, 13.5, 21.0, 25.0, 25.0, 33.0, 40.0, 40.0, 47.0,
        ];
        let weights: Vec<(usize, Real, Real)> = x
            .iter()
            .map(|&x| PositioningProblem::hat_weights(&knots, x))
            .collect();
        let banded = Banded::new(weights.clone(), knots.len()).expect("well conditioned");
        let h = DMatrix::from_fn(x.len(), knots.len(), |i, j| {
            let (l, a, b) = weights[i];
            if j == l {
                a
            } else if j == l + 1 {
                b
            } else {
                0.0
            }
        });
        let v: Vec<Real> = (0..x.len())
            .map(|i| ((i * 7919) % 101) as Real / 17.0 - 3.0)
            .collect();
        let mut fast = v.clone();
        banded.project(&mut fast);
        let expected = dense_projection(&h, &v);
        let scale = dot(&v, &v).sqrt();
        for (a, b) in fast.iter().zip(&expected) {
            assert!((a - b).abs() <= 1e-13 * scale, "{a} against {b}");
        }
        for hat in h.column_iter() {
            let along: Real = hat.iter().zip(&fast).map(|(h, r)| h * r).sum();
            assert!(along.abs() <= 1e-13 * scale, "{along}");
        }
    }

    #[test]
    fn hats_that_only_readings_between_them_tell_apart_are_left_to_the_dense_basis() {
        // A hat without readings (knot 10 mm, nothing between 0 and 25 mm but at 0 and 25):
        // its Gram diagonal is zero. Two hats seen only by one reading between them (at
        // 5 mm, knots 0 and 10) are proportional. Three readings piled about the middle of
        // that pair (4.999 to 5.001 mm, none at its knots) make the scaled Gram matrix nearly
        // singular, though not singular.
        let knots = [0.0, 10.0, 25.0];
        let weights = |x: &[Real]| -> Vec<(usize, Real, Real)> {
            x.iter()
                .map(|&x| PositioningProblem::hat_weights(&knots, x))
                .collect()
        };
        assert!(Banded::new(weights(&[0.0, 25.0, 25.0, 30.0]), 3).is_none());
        assert!(Banded::new(weights(&[5.0, 25.0]), 3).is_none());
        let piled: Vec<Real> = [4.999, 5.0, 5.001, 25.0].to_vec();
        assert!(Banded::new(weights(&piled), 3).is_none());
        // With a reading at each knot the same hats are well conditioned.
        assert!(Banded::new(weights(&[0.0, 5.0, 10.0, 25.0]), 3).is_some());
    }
}
