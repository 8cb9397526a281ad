//! The roots of a ray against a dilated quadric, `|m + t·e|² = ρ²`, written so that neither
//! root suffers cancellation: with `A = |e|²`, `B = m·e`, `C = |m|² − ρ²` and `D = B² − A·C`, the
//! root whose formula would subtract nearly equal numbers is taken from the product of the roots
//! (`t₁·t₂ = C/A`) instead.

use crate::math::{Real, Vector};

/// The coefficients `(A, B, C)` of the ray `m + t·e` against radius `rho`.
pub(crate) fn coefficients(m: Vector, e: Vector, rho: Real) -> (Real, Real, Real) {
    (e.length_squared(), m.dot(e), m.length_squared() - rho * rho)
}

/// The entry root (first crossing from outside, `C ≥ 0`), `None` when the ray moves away or
/// passes by.
pub(crate) fn entry(a: Real, b: Real, c: Real) -> Option<Real> {
    if b >= 0.0 || a <= 0.0 {
        return None;
    }
    let d = b * b - a * c;
    if d < 0.0 {
        return None;
    }
    // −B > 0 and √D ≥ 0: no cancellation in the denominator.
    Some(c / (-b + d.sqrt()))
}

/// The exit root (crossing from inside, `C ≤ 0`), `None` for a ray with no motion across the
/// quadric (`A = 0`).
pub(crate) fn exit(a: Real, b: Real, c: Real) -> Option<Real> {
    if a <= 0.0 {
        return None;
    }
    let root = (b * b - a * c).max(0.0).sqrt();
    Some(if b <= 0.0 {
        (-b + root) / a
    } else {
        -c / (b + root)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_of_a_unit_circle_from_outside_and_inside() {
        // From x = −3 along +x against ρ = 1: entry at t = 2; from the centre: exit at t = 1.
        let (a, b, c) = coefficients(Vector::new(-3.0, 0.0, 0.0), Vector::X, 1.0);
        assert_eq!(entry(a, b, c), Some(2.0));
        let (a, b, c) = coefficients(Vector::ZERO, Vector::X, 1.0);
        assert_eq!(exit(a, b, c), Some(1.0));
        // Moving away: no entry.
        let (a, b, c) = coefficients(Vector::new(3.0, 0.0, 0.0), Vector::X, 1.0);
        assert_eq!(entry(a, b, c), None);
        // Inside, moving toward the far side with B > 0: exit at 1 − 0.5.
        let (a, b, c) = coefficients(Vector::new(0.5, 0.0, 0.0), Vector::X, 1.0);
        assert_eq!(exit(a, b, c), Some(0.5));
    }
}
