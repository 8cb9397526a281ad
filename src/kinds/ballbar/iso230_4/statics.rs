//! The table's static columns: the columns that do not depend on the searched shape (with no
//! angle lag), three more that make the position-dependent columns at an angle lag, and the
//! deviation, [`WIDTH`] values a reading; which of them a term's column is, or which
//! combination at an angle lag.

use super::{CircularTest, Shape, Term};
use crate::math::Real;

/// The columns that do not depend on the searched shape (with no angle lag), the reversal
/// terms among them at no lag and no play: their change with a lag or a play is on the
/// readings near the reversals only.
pub(super) const STATICS: [Term; 14] = [
    Term::Radius,
    Term::CentreP,
    Term::CentreQ,
    Term::Squareness,
    Term::ScaleMismatch,
    Term::ServoMismatch,
    Term::StraightnessP,
    Term::StraightnessQ,
    Term::RadiusDrift,
    Term::SenseRadius,
    Term::BacklashP,
    Term::BacklashQ,
    Term::LateralPlayP,
    Term::LateralPlayQ,
];
/// Three more static columns, σ·sin θ, σ·cos θ and σ·(R/2)·cos 2θ: with them (and the servo
/// mismatch's σ·sin 2θ) the position-dependent columns at an angle lag, at θ − σ·φ, are
/// combinations of static ones.
pub(super) const SIGMA_SIN: usize = STATICS.len();
pub(super) const SIGMA_COS: usize = STATICS.len() + 1;
pub(super) const SIGMA_COS_2: usize = STATICS.len() + 2;
/// The deviation's index after the static columns.
pub(super) const Y: usize = STATICS.len() + 3;
/// Values per reading in the table: the static columns, then the deviation.
pub(super) const WIDTH: usize = Y + 1;

/// The index of `term` among [`STATICS`] (position-dependent terms only without angle lag).
pub(super) fn static_index(term: Term, shape: &Shape) -> Option<usize> {
    let position = matches!(
        term,
        Term::CentreP | Term::CentreQ | Term::Squareness | Term::ScaleMismatch
    );
    if position && shape.angle_lag != 0.0 {
        return None;
    }
    STATICS.iter().position(|t| *t == term)
}

/// A position-dependent column at `shape`'s angle lag as a combination of static columns
/// (index, weight): with φ = v·ℓ/R, cos(θ − σφ) = cos φ·cos θ + sin φ·σ sin θ, and alike.
pub(super) fn lagged(term: Term, shape: &Shape, test: &CircularTest) -> Option<Vec<(usize, Real)>> {
    let phi = test.feed * shape.angle_lag / test.radius;
    let (s, c) = phi.sin_cos();
    let (s2, c2) = (2.0 * phi).sin_cos();
    let index = |t: Term| STATICS.iter().position(|x| *x == t).unwrap_or_default();
    Some(match term {
        Term::CentreP => vec![(index(Term::CentreP), c), (SIGMA_SIN, s)],
        Term::CentreQ => vec![(index(Term::CentreQ), c), (SIGMA_COS, -s)],
        // (R/2)·sin 2θ_a = cos 2φ·(R/2)·sin 2θ − sin 2φ·σ·(R/2)·cos 2θ.
        Term::Squareness => vec![(index(Term::Squareness), c2), (SIGMA_COS_2, -s2)],
        // (R/2)·cos 2θ_a = cos 2φ·(R/2)·cos 2θ + sin 2φ·σ·(R/2)·sin 2θ, the servo column
        // σ·(v/2)·sin 2θ times R/v.
        Term::ScaleMismatch => vec![
            (index(Term::ScaleMismatch), c2),
            (index(Term::ServoMismatch), s2 * test.radius / test.feed),
        ],
        _ => return None,
    })
}

/// The derivative in the angle lag ℓ of c_p·cos θ_a + c_q·sin θ_a at `shape`'s angle lag,
/// σ·(v/R)·(c_p·sin θ_a − c_q·cos θ_a), as a combination of static columns.
pub(super) fn angle_lag_derivative(
    centre: (Real, Real),
    shape: &Shape,
    test: &CircularTest,
) -> Vec<(usize, Real)> {
    let rate = test.feed / test.radius;
    let (s, c) = (rate * shape.angle_lag).sin_cos();
    let index = |t: Term| STATICS.iter().position(|x| *x == t).unwrap_or_default();
    let (cp, cq) = centre;
    // σ·sin θ_a = σ·sin θ·cos φ − cos θ·sin φ; σ·cos θ_a = σ·cos θ·cos φ + sin θ·sin φ.
    vec![
        (SIGMA_SIN, rate * cp * c),
        (index(Term::CentreP), -rate * cp * s),
        (SIGMA_COS, -rate * cq * c),
        (index(Term::CentreQ), -rate * cq * s),
    ]
}
