//! Where the axes a test does not move stand (`x_mm = 380.0`, `c_deg = 0.0`, … in a test's
//! section): as given, else a linear axis at mid-travel and a rotary axis at 0.

use crate::machine::{Axis, AxisValues, Machine, axis_unit_to_si};
use crate::math::Real;
use std::ops::Range;
use toml::Spanned;

/// A position given for an axis the test holds: the axis, the key it is given by (`x_mm`)
/// and its value in file units (mm or deg), when given.
pub type Given<'a> = (Axis, &'a str, &'a Option<Spanned<Real>>);

/// A position that cannot be held, by the key that gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct Refused<'a> {
    /// The axis.
    pub axis: Axis,
    /// The key the position is given by.
    pub key: &'a str,
    /// The given value's span; `None` for a default position.
    pub span: Option<Range<usize>>,
    /// Why.
    pub why: Why,
}

/// Why a position cannot be held.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Why {
    /// It is given for the axis under test.
    UnderTest,
    /// It is given for an axis the machine lacks.
    NoAxis,
    /// It is outside the axis's travel: the position and the limits (NaN when the axis has
    /// none), in file units.
    OutsideTravel {
        /// The position.
        position: Real,
        /// The lower limit.
        lower: Real,
        /// The upper limit.
        upper: Real,
    },
}

/// The positions (SI units) of the axes of `given` that the machine has, as given or by default
/// (the axis under test, which may not be given, at its default); every other axis at 0. The
/// first position refused, in the order of `given`, is the error.
pub fn parked<'a>(
    machine: &Machine,
    under_test: Axis,
    given: &[Given<'a>],
) -> Result<AxisValues, Refused<'a>> {
    let mut parked = AxisValues::ZERO;
    for &(axis, key, value) in given {
        let refused = |span, why| Refused {
            axis,
            key,
            span,
            why,
        };
        match (machine.axis(axis), value) {
            (_, Some(v)) if axis == under_test => {
                return Err(refused(Some(v.span()), Why::UnderTest));
            }
            (None, Some(v)) => return Err(refused(Some(v.span()), Why::NoAxis)),
            (None, None) => {}
            (Some(info), value) => {
                let scale = axis_unit_to_si(axis);
                let position = match (value, info.limits) {
                    (Some(v), _) => *v.get_ref() * scale,
                    (None, Some((lo, hi))) if axis.is_linear() => (lo + hi) / 2.0,
                    (None, _) => 0.0,
                };
                if !info.within_travel(position) {
                    let (lo, hi) = info.scenario_travel();
                    let why = Why::OutsideTravel {
                        position: position / scale,
                        lower: lo / scale,
                        upper: hi / scale,
                    };
                    return Err(refused(value.as_ref().map(|v| v.span()), why));
                }
                parked[axis] = position;
            }
        }
    }
    Ok(parked)
}
