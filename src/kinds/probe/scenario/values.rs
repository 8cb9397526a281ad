//! The section's values checked one by one: finite, within bounds, whole numbers in a range,
//! points in mm, unit directions.

use crate::math::{M_PER_MM, Real, Vector};
use crate::scenario::bounds::Bound;
use crate::scenario::{Checker, ScenarioError};
use std::ops::Range;
use toml::Spanned;

/// A finite value ≥ `min` (or > `min` when `strict`), with its default.
pub(super) fn value(
    check: &Checker<'_>,
    v: &Option<Spanned<Real>>,
    key: &str,
    default: Real,
    min: Real,
    strict: bool,
) -> Result<Real, ScenarioError> {
    check.value(v, key, default, |x| {
        if x.is_finite() && (x > min || (!strict && x == min)) {
            Ok(x)
        } else {
            let relation = if strict { ">" } else { "≥" };
            Err(format!(
                "expected a finite number {relation} {min}, got {x}"
            ))
        }
    })
}

/// A value within `bound`, `default` when absent.
pub(super) fn bounded(
    check: &Checker<'_>,
    v: &Option<Spanned<Real>>,
    key: &str,
    default: Real,
    bound: Bound,
) -> Result<Real, ScenarioError> {
    check.value(v, key, default, |x| bound.check(x))
}

/// A finite value, 0 by default.
pub(super) fn finite(
    check: &Checker<'_>,
    v: &Option<Spanned<Real>>,
    key: &str,
) -> Result<Real, ScenarioError> {
    value(check, v, key, 0.0, Real::MIN, false)
}

/// A whole number within `range`, with its default.
pub(super) fn count(
    check: &Checker<'_>,
    v: &Option<Spanned<i64>>,
    key: &str,
    default: usize,
    range: (usize, usize),
) -> Result<usize, ScenarioError> {
    check.value(v, key, default, |n| {
        if n >= range.0 as i64 && n <= range.1 as i64 {
            Ok(n as usize)
        } else {
            Err(format!("expected {} … {}, got {n}", range.0, range.1))
        }
    })
}

/// A point given in mm, in m.
pub(super) fn point(
    check: &Checker<'_>,
    v: &Spanned<[Real; 3]>,
    key: &str,
) -> Result<Vector, ScenarioError> {
    let p = Vector::from_array(*v.get_ref());
    if p.is_finite() {
        Ok(p * M_PER_MM)
    } else {
        Err(check.fail(Some(v.span()), key, "expected three finite numbers (mm)"))
    }
}

/// The unit vector along `v`, which must have a length.
pub(super) fn direction(
    check: &Checker<'_>,
    v: [Real; 3],
    span: Range<usize>,
    key: &str,
) -> Result<Vector, ScenarioError> {
    let d = Vector::from_array(v);
    if d.is_finite() && d.length() > 1e-12 {
        Ok(d.normalize())
    } else {
        Err(check.fail(
            Some(span),
            key,
            format!(
                "({}, {}, {}) has zero length or is not finite: an approach needs a direction",
                v[0], v[1], v[2]
            ),
        ))
    }
}
