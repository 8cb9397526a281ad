//! A [`Combination`] of parameters, and the readable basis of a subspace that the report
//! prints: the reduced row echelon form, made safe for a basis known only to the design's
//! noise.

use super::significant;
use crate::math::Real;
use nalgebra::{DMatrix, DVector};
use serde_json::{Value, json};
use std::fmt::Write;

/// Coefficients of a [`Combination`] smaller than this fraction of its largest are dropped.
const NEGLIGIBLE_TERM: Real = 1e-6;

/// Entries at or below this (on unit-norm rows) cannot be pivots of the echelon form.
const PIVOT_TOLERANCE: Real = 1e-9;

/// An entry of the echelon form's column is a pivot only when it is at least this fraction of
/// the largest entry still to be reduced (threshold partial pivoting). A null basis from a
/// Jacobian by finite differences carries noise of about the largest unidentified singular
/// value over the smallest identified one (10⁻⁷ on trunnion5's R-tests with their set-up
/// free): an entry of that size made a pivot divides its row by it, the row becomes that
/// noise magnified a million times, and its own pivot falls below the terms a description
/// keeps. Such rows read as copies of another (8 printed, 6 distinct, one three times). With
/// the threshold a row is divided by no less than a thousandth of what is left, so every row
/// keeps its own pivot and the rows stay distinct.
const PIVOT_FRACTION: Real = 1e-3;

/// The readable combinations leave out coefficients below this many times the null basis's
/// noise (relative to their largest), and never more than [`PIVOT_FRACTION`] of it: what the
/// elimination leaves of the noise (1.5·10⁻⁶ of the largest coefficient on trunnion5's
/// R-tests, printed as `1.55e-6 EYT`) is not a term.
const NOISE_MARGIN: Real = 100.0;

/// A linear combination of parameters: unit-norm coefficients, sparse.
#[derive(Debug, Clone, PartialEq)]
pub struct Combination {
    /// (column index, coefficient), sorted by |coefficient| descending (ties by column), the
    /// largest positive, coefficients below 1e-6 of the largest dropped, Euclidean norm 1.
    pub terms: Vec<(usize, Real)>,
}

impl Combination {
    /// The combination along `vector` (any length and sign; the zero vector gives no terms).
    pub fn from_vector(vector: &DVector<Real>) -> Self {
        Self::above(vector, NEGLIGIBLE_TERM, 1e9)
    }

    /// The combination along `vector` without the coefficients below `floor` times its
    /// largest, magnitudes within `1/ties` of each other (relative to the largest) ordered as
    /// equal.
    fn above(vector: &DVector<Real>, floor: Real, ties: Real) -> Self {
        let largest = vector.amax();
        if largest == 0.0 || !largest.is_finite() {
            return Self { terms: Vec::new() };
        }
        let mut terms: Vec<(usize, Real)> = vector
            .iter()
            .enumerate()
            .filter(|(_, c)| c.abs() >= floor * largest)
            .map(|(j, &c)| (j, c))
            .collect();
        // A total order that treats magnitudes equal to 1/ties as ties (kept in column order).
        let key = |c: Real| -((c.abs() / largest) * ties).round() as i64;
        terms.sort_by_key(|&(j, c)| (key(c), j));
        let norm = terms.iter().map(|(_, c)| c * c).sum::<Real>().sqrt();
        let scale = norm.copysign(terms[0].1);
        for term in &mut terms {
            term.1 /= scale;
        }
        Self { terms }
    }

    /// The combination as a vector over `n` parameters.
    pub fn to_vector(&self, n: usize) -> DVector<Real> {
        let mut v = DVector::zeros(n);
        for &(j, c) in &self.terms {
            v[j] = c;
        }
        v
    }

    /// The largest coefficient (positive; 0 for an empty combination): the combination as
    /// described is `terms / leading()`.
    pub fn leading(&self) -> Real {
        self.terms.first().map_or(0.0, |t| t.1)
    }

    /// The coefficients as described: the largest scaled to 1, rounded to 12 decimals (so that
    /// an exact −1 does not print as −1.0000000000000002).
    pub fn described_terms(&self) -> Vec<(usize, Real)> {
        let lead = self.leading();
        self.terms
            .iter()
            .map(|&(j, c)| (j, ((c / lead) * 1e12).round() / 1e12))
            .collect()
    }

    /// The combination in words, its largest coefficient scaled to 1 and the others to three
    /// significant figures, with the parameters' names and the typographic minus used across
    /// mtwin's reports: `EA0A − EA0C`, `EX0C − 0.5 EY0C + 0.173 sphere1.x` (`0` when empty).
    /// A column without a label is written `#j`.
    pub fn describe(&self, labels: &[String]) -> String {
        let mut text = String::new();
        for (k, (j, c)) in self.described_terms().into_iter().enumerate() {
            let name = labels.get(j).cloned().unwrap_or_else(|| format!("#{j}"));
            if k > 0 {
                text.push_str(if c < 0.0 { " − " } else { " + " });
            }
            let magnitude = significant(c.abs());
            if magnitude == "1" {
                text.push_str(&name);
            } else {
                let _ = write!(text, "{magnitude} {name}");
            }
        }
        if text.is_empty() {
            text.push('0');
        }
        text
    }

    /// The combination with stable keys: `description` ([`Self::describe`]) and `terms`, a list
    /// of `{"parameter": name, "coefficient": c}` with the coefficients as described (largest 1).
    pub fn to_json(&self, labels: &[String]) -> Value {
        let terms: Vec<Value> = self
            .described_terms()
            .into_iter()
            .map(|(j, c)| {
                json!({
                    "parameter": labels.get(j).cloned().unwrap_or_else(|| format!("#{j}")),
                    "coefficient": c,
                })
            })
            .collect();
        json!({ "description": self.describe(labels), "terms": terms })
    }
}

/// The reduced row echelon form of `rows` (pivots in column order, partial pivoting within a
/// column; entries at or below `tolerance`, or below [`PIVOT_FRACTION`] of the largest entry
/// of the rows and columns still to be reduced, never pivots); only the pivoted rows are
/// returned.
fn rref(rows: &DMatrix<Real>, tolerance: Real) -> DMatrix<Real> {
    let mut a = rows.clone();
    let (m, n) = a.shape();
    let mut next = 0;
    for col in 0..n {
        if next == m {
            break;
        }
        let (best, value) = (next..m)
            .map(|i| (i, a[(i, col)].abs()))
            .fold((next, -1.0), |acc, x| if x.1 > acc.1 { x } else { acc });
        let left = a.view_range(next.., col..).amax();
        if value <= tolerance || value < PIVOT_FRACTION * left {
            continue;
        }
        a.swap_rows(next, best);
        let pivot = a[(next, col)];
        for j in 0..n {
            a[(next, j)] /= pivot;
        }
        for i in 0..m {
            let factor = a[(i, col)];
            if i != next && factor != 0.0 {
                for j in 0..n {
                    let d = factor * a[(next, j)];
                    a[(i, j)] -= d;
                }
            }
        }
        next += 1;
    }
    a.rows(0, next).into_owned()
}

/// The readable combinations spanning the columns of `basis` (n × d, orthonormal columns,
/// known to about `noise`): coefficients below [`NOISE_MARGIN`] times the noise, relative to
/// their row's largest, are left out (and those below [`NEGLIGIBLE_TERM`] in any case), and
/// coefficients that differ by less are written in parameter order (`A − B`, not `B − A` for
/// a difference of 10⁻⁸).
pub(super) fn readable(basis: &DMatrix<Real>, noise: Real) -> Vec<Combination> {
    if basis.ncols() == 0 {
        return Vec::new();
    }
    let resolution = NOISE_MARGIN * noise;
    let floor = resolution.clamp(NEGLIGIBLE_TERM, PIVOT_FRACTION);
    let ties = if resolution > 1e-9 {
        1.0 / resolution.min(PIVOT_FRACTION)
    } else {
        1e9
    };
    let echelon = rref(&basis.transpose(), PIVOT_TOLERANCE);
    echelon
        .row_iter()
        .map(|row| Combination::above(&row.transpose(), floor, ties))
        .filter(|c| !c.terms.is_empty())
        .collect()
}
