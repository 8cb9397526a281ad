//! The axis under test and how it turns: which axis, its speeds, the set-ups, and where the
//! other axes stand meanwhile.

use super::super::program::Setup;
use super::RawSpindle;
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::Real;
use crate::scenario::parked::{self, Why};
use crate::scenario::{Checker, ScenarioError};
use toml::Spanned;

/// The axis `given` (default `S`): an axis of rotation of the machine that turns without end.
pub(super) fn axis_under_test(
    check: &Checker<'_>,
    machine: &Machine,
    given: &Option<Spanned<String>>,
) -> Result<Axis, ScenarioError> {
    let axis = match given {
        None => Axis::S,
        Some(a) => {
            let text = a.get_ref().trim();
            let mut letters = text.chars();
            let letter = match (letters.next(), letters.next()) {
                (Some(c), None) => Axis::from_letter(c.to_ascii_uppercase()),
                _ => None,
            };
            match letter {
                Some(axis) if !axis.is_linear() => axis,
                _ => {
                    return Err(check.fail(
                        Some(a.span()),
                        "axis",
                        format!("expected an axis of rotation, S, C, A or B, got \"{text}\""),
                    ));
                }
            }
        }
    };
    match machine.axis(axis) {
        None => Err(check.fail(
            given.as_ref().map(|a| a.span()),
            "axis",
            format!("machine \"{}\" has no axis {axis}", machine.name()),
        )),
        Some(info) if !info.is_continuous() => Err(check.fail(
            given.as_ref().map(|a| a.span()),
            "axis",
            format!(
                "{axis} has a limited travel: the test turns the axis through whole revolutions (a swivelling axis needs a partial-arc test, ISO 230-7 §6, which this analyser does not run)"
            ),
        )),
        Some(_) => Ok(axis),
    }
}

/// The speeds (rad/s, signed) of `speeds_rpm`, by default three for the spindle and one for a
/// table axis.
pub(super) fn speeds(
    check: &Checker<'_>,
    axis: Axis,
    speeds_rpm: &Option<Spanned<Vec<Real>>>,
) -> Result<Vec<Real>, ScenarioError> {
    let speeds_rpm = match speeds_rpm {
        None if axis == Axis::S => vec![2000.0, 6000.0, 12000.0],
        None => vec![10.0],
        Some(v) => {
            if v.get_ref().is_empty() {
                return Err(check.fail(Some(v.span()), "speeds_rpm", "give at least one speed"));
            }
            if let Some(bad) = v
                .get_ref()
                .iter()
                .find(|w| !(w.is_finite() && **w != 0.0 && w.abs() <= 200_000.0))
            {
                return Err(check.fail(
                    Some(v.span()),
                    "speeds_rpm",
                    format!(
                        "{bad}: expected speeds other than 0 within ±200000 rpm (negative: the axis turns backwards)"
                    ),
                ));
            }
            v.get_ref().clone()
        }
    };
    Ok(speeds_rpm
        .iter()
        .map(|w| w * std::f64::consts::TAU / 60.0)
        .collect())
}

/// The set-ups of `setups` (default: `normal` alone), each once.
pub(super) fn setups(
    check: &Checker<'_>,
    setups: &Option<Spanned<Vec<String>>>,
) -> Result<Vec<Setup>, ScenarioError> {
    let Some(v) = setups else {
        return Ok(vec![Setup::Normal]);
    };
    if v.get_ref().is_empty() {
        return Err(check.fail(Some(v.span()), "setups", "give at least one set-up"));
    }
    let mut setups = Vec::new();
    for text in v.get_ref() {
        let setup = Setup::parse(text.trim()).ok_or_else(|| {
            check.fail(
                Some(v.span()),
                "setups",
                format!(
                    "\"{text}\": expected \"normal\", \"reversed\" or \"turned_<deg>\" (0 < deg < 360)"
                ),
            )
        })?;
        if setups.iter().any(|s: &Setup| s.name() == setup.name()) {
            return Err(check.fail(
                Some(v.span()),
                "setups",
                format!("\"{text}\" is given twice"),
            ));
        }
        setups.push(setup);
    }
    Ok(setups)
}

/// Where the other axes stand (`x_mm` … `s_deg`; linear: mid-travel, rotary: 0); the axis
/// under test may not be given.
pub(super) fn parked(
    check: &Checker<'_>,
    machine: &Machine,
    axis: Axis,
    s: &RawSpindle,
) -> Result<AxisValues, ScenarioError> {
    let given = [
        (Axis::X, "x_mm", &s.x_mm),
        (Axis::Y, "y_mm", &s.y_mm),
        (Axis::Z, "z_mm", &s.z_mm),
        (Axis::A, "a_deg", &s.a_deg),
        (Axis::B, "b_deg", &s.b_deg),
        (Axis::C, "c_deg", &s.c_deg),
        (Axis::S, "s_deg", &s.s_deg),
    ];
    parked::parked(machine, axis, &given).map_err(|refused| {
        let other = refused.axis;
        let message = match refused.why {
            Why::UnderTest => {
                format!("{axis} is the axis under test: it turns through the whole test")
            }
            Why::NoAxis => format!("machine \"{}\" has no axis {other}", machine.name()),
            Why::OutsideTravel {
                position,
                lower,
                upper,
            } => format!("{position} is outside the travel of {other} ({lower} … {upper})"),
        };
        check.fail(refused.span, refused.key, message)
    })
}
