//! The position-dependent terms of `[errors.NAME]` and the error function they make, both
//! ways: [`function_of`] checks the terms (file units) and turns them into an
//! [`ErrorFunction`] (SI); [`spec_of`] writes a function back as terms.

use crate::errors::{ErrorFunction, Interpolation, ParameterName, Table, TableError};
use crate::machine::{Axis, axis_unit_to_si};
use crate::math::{RAD_PER_URAD, Real};
use crate::scenario::ScenarioErrorKind;
use crate::scenario::error_spec::{
    ErrorSpec, HarmonicSpec, InterpolationSpec, SpecError, TableSpec,
};

/// The highest degree of a polynomial error function a scenario may give (11 coefficients).
///
/// In file units (µm per mm^k) a degree-10 term over a 1 m travel already has a coefficient of
/// order 1e-30 for a micrometre of error, near where f64 stops resolving it; a shape that needs
/// more is a table function. The limit also bounds a dataset prior on `polynomial_um[k]`, which
/// fills the coefficients below k with zeros.
pub const MAX_POLYNOMIAL_DEGREE: usize = 10;

/// The shortest period of a harmonic term (mm or deg): no pitch, tooth or scale line is finer.
const SHORTEST_PERIOD: Real = 0.001;

/// Turns the terms of `[errors.NAME]` into a function (SI), checking units and values.
/// `argument` is the axis whose position the function takes (component errors only).
pub(super) fn spec_to_function(
    spec: &ErrorSpec,
    name: ParameterName,
    argument: Option<Axis>,
) -> Result<ErrorFunction, SpecError> {
    use ScenarioErrorKind::{Units, Value};
    let translation = name.motion().is_translation();
    let (value_unit, other_unit) = if translation {
        ("um", "urad")
    } else {
        ("urad", "um")
    };
    let (position_unit, other_position_unit) = match argument {
        Some(axis) if !axis.is_linear() => ("deg", "mm"),
        _ => ("mm", "deg"),
    };
    let position_scale = argument.map_or(crate::math::M_PER_MM, axis_unit_to_si);
    let value_scale = RAD_PER_URAD; // µm → m and µrad → rad are the same factor
    fn fail<T>(kind: ScenarioErrorKind, key: String, message: String) -> Result<T, SpecError> {
        Err((kind, key, message))
    }
    let wrong_value_unit = |key: &str| -> SpecError {
        let what = if translation {
            "a translation"
        } else {
            "a rotation"
        };
        (
            Units,
            format!("{key}_{other_unit}"),
            format!("{name} is {what}; give it in {value_unit} as {key}_{value_unit}"),
        )
    };
    let wrong_position_unit = |key: &str| -> SpecError {
        (
            Units,
            format!("{key}_{other_position_unit}"),
            format!("the axis is measured in {position_unit}; give {key}_{position_unit}"),
        )
    };
    let finite = |key: String, values: &[Real]| -> Result<(), SpecError> {
        match values.iter().position(|v| !v.is_finite()) {
            Some(i) if values.len() > 1 => fail(
                Value,
                key,
                format!("value {} is not a finite number", i + 1),
            ),
            Some(_) => fail(Value, key, "not a finite number".into()),
            None => Ok(()),
        }
    };
    let by_unit = |um: &Option<Real>, urad: &Option<Real>| {
        if translation {
            (*um, *urad)
        } else {
            (*urad, *um)
        }
    };

    let mut terms = Vec::new();
    let (constant, constant_other) = by_unit(&spec.constant_um, &spec.constant_urad);
    if constant_other.is_some() {
        return Err(wrong_value_unit("constant"));
    }
    if let Some(c) = constant {
        finite(format!("constant_{value_unit}"), &[c])?;
        terms.push(ErrorFunction::Constant(c * value_scale));
    }
    let (polynomial, polynomial_other) = if translation {
        (&spec.polynomial_um, &spec.polynomial_urad)
    } else {
        (&spec.polynomial_urad, &spec.polynomial_um)
    };
    if polynomial_other.is_some() {
        return Err(wrong_value_unit("polynomial"));
    }
    if let Some(coefficients) = polynomial {
        let key = format!("polynomial_{value_unit}");
        finite(key.clone(), coefficients)?;
        if coefficients.is_empty() {
            return fail(Value, key, "give at least one coefficient".into());
        }
        if coefficients.len() > MAX_POLYNOMIAL_DEGREE + 1 {
            return fail(
                Value,
                key,
                format!(
                    "{} coefficients make degree {}; the limit is degree {MAX_POLYNOMIAL_DEGREE} \
                     (finer shapes are a table function)",
                    coefficients.len(),
                    coefficients.len() - 1
                ),
            );
        }
        let si = coefficients
            .iter()
            .enumerate()
            .map(|(k, c)| c * value_scale / position_scale.powi(k as i32))
            .collect();
        terms.push(ErrorFunction::Polynomial(si));
    }
    let (reversal, reversal_other) = by_unit(&spec.reversal_um, &spec.reversal_urad);
    if reversal_other.is_some() {
        return Err(wrong_value_unit("reversal"));
    }
    if let Some(r) = reversal {
        finite(format!("reversal_{value_unit}"), &[r])?;
        terms.push(ErrorFunction::Reversal(r * value_scale));
    }
    for (i, h) in spec.harmonic.iter().enumerate() {
        let key = |field: &str| format!("harmonic[{i}].{field}");
        let (period, period_other) = if position_unit == "mm" {
            (h.period_mm, h.period_deg)
        } else {
            (h.period_deg, h.period_mm)
        };
        if period_other.is_some() {
            let (kind, field, message) = wrong_position_unit("period");
            return fail(kind, key(&field), message);
        }
        let (amplitude, amplitude_other) = by_unit(&h.amplitude_um, &h.amplitude_urad);
        if amplitude_other.is_some() {
            let (kind, field, message) = wrong_value_unit("amplitude");
            return fail(kind, key(&field), message);
        }
        let period_key = key(&format!("period_{position_unit}"));
        let Some(period) = period else {
            return fail(Value, period_key, "required".into());
        };
        let amplitude_key = key(&format!("amplitude_{value_unit}"));
        let Some(amplitude) = amplitude else {
            return fail(Value, amplitude_key, "required".into());
        };
        finite(period_key.clone(), &[period])?;
        finite(amplitude_key, &[amplitude])?;
        finite(key("phase_deg"), &[h.phase_deg])?;
        if !(period >= SHORTEST_PERIOD && (period * position_scale) > 0.0) {
            return fail(
                Value,
                period_key,
                format!(
                    "must be at least {SHORTEST_PERIOD} {position_unit} (no pitch, tooth or scale line is finer), got {}",
                    crate::math::readable(period)
                ),
            );
        }
        terms.push(ErrorFunction::Harmonic {
            period: period * position_scale,
            amplitude: amplitude * value_scale,
            phase: h.phase_deg * crate::math::RAD_PER_DEG,
        });
    }
    if let Some(t) = &spec.table {
        let key = |field: &str| format!("table.{field}");
        let (positions, positions_other) = if position_unit == "mm" {
            (&t.positions_mm, &t.positions_deg)
        } else {
            (&t.positions_deg, &t.positions_mm)
        };
        if positions_other.is_some() {
            let (kind, field, message) = wrong_position_unit("positions");
            return fail(kind, key(&field), message);
        }
        let (values, values_other) = if translation {
            (&t.values_um, &t.values_urad)
        } else {
            (&t.values_urad, &t.values_um)
        };
        if values_other.is_some() {
            let (kind, field, message) = wrong_value_unit("values");
            return fail(kind, key(&field), message);
        }
        let positions_key = key(&format!("positions_{position_unit}"));
        let values_key = key(&format!("values_{value_unit}"));
        let Some(positions) = positions else {
            return fail(Value, positions_key, "required".into());
        };
        let Some(values) = values else {
            return fail(Value, values_key, "required".into());
        };
        finite(positions_key.clone(), positions)?;
        finite(values_key.clone(), values)?;
        let interpolation = match t.interpolation {
            InterpolationSpec::Linear => Interpolation::Linear,
            InterpolationSpec::Cubic => Interpolation::Cubic,
        };
        let table = Table::new(
            positions.iter().map(|p| p * position_scale).collect(),
            values.iter().map(|v| v * value_scale).collect(),
            interpolation,
        );
        match table {
            Ok(table) => terms.push(ErrorFunction::Table(table)),
            Err(e @ TableError::Shape { .. }) => return fail(Value, key("values"), e.to_string()),
            Err(e @ TableError::Order(_)) => return fail(Value, positions_key, e.to_string()),
            Err(e @ TableError::Value(_)) => return fail(Value, values_key, e.to_string()),
        }
    }
    match terms.len() {
        1 => Ok(terms.pop().expect("one term")),
        _ => Ok(ErrorFunction::Sum(terms)),
    }
}

/// The first key of a spec that makes it vary with position or direction (to name it when a
/// constant is required).
pub(super) fn varying_key(spec: &ErrorSpec) -> &'static str {
    let candidates: [(&'static str, bool); 7] = [
        (
            "polynomial_um",
            spec.polynomial_um.as_ref().is_some_and(|c| c.len() > 1),
        ),
        (
            "polynomial_urad",
            spec.polynomial_urad.as_ref().is_some_and(|c| c.len() > 1),
        ),
        ("reversal_um", spec.reversal_um.is_some()),
        ("reversal_urad", spec.reversal_urad.is_some()),
        ("harmonic", !spec.harmonic.is_empty()),
        ("table", spec.table.is_some()),
        ("", true),
    ];
    candidates
        .into_iter()
        .find(|(_, present)| *present)
        .map_or("", |(key, _)| key)
}

/// The error function (SI) of the terms `spec` (file units) give for parameter `name`: what an
/// `[errors.NAME]` section or a `terms` object of `truth.json` / `estimate.json` means.
///
/// The function's argument is the position of the parameter's own axis for component errors
/// (mm or deg in the file, m or rad in SI); location, squareness and tool errors are constants.
/// The message names the key inside the terms (e.g. `harmonic[0].period_mm`) and what is wrong
/// with it: a unit that does not fit the parameter or its axis, a value that is not a finite
/// number, a missing field, no term at all, or a varying term for a constant parameter.
pub fn function_of(spec: &ErrorSpec, name: ParameterName) -> Result<ErrorFunction, String> {
    let unit = name.file_unit();
    if *spec == ErrorSpec::default() {
        return Err(format!(
            "no term given; expected one or more of constant_{unit}, polynomial_{unit}, \
             reversal_{unit}, harmonic, table"
        ));
    }
    let argument = name
        .axis()
        .filter(|_| matches!(name, ParameterName::Component { .. }));
    let function = spec_to_function(spec, name, argument)
        .map_err(|(_, key, message)| format!("{key}: {message}"))?;
    if argument.is_none() && !function.is_constant() {
        return Err(format!(
            "{}: location, squareness and tool errors are constants; use constant_{unit}",
            varying_key(spec)
        ));
    }
    Ok(function)
}

/// The terms, in file units, of the SI `function` of parameter `name`: the inverse of
/// [`function_of`] (`function_of(&spec_of(f, name), name)` is `f` to round-off, with the terms
/// of a sum in the order constant, polynomial, reversal, harmonics, table).
///
/// Values go to `*_um` for translations and `*_urad` for rotations; polynomial coefficients of
/// degree k to µm (µrad) per mm^k, or per deg^k for a component error of a rotary axis;
/// harmonic periods and table positions to mm or deg the same way, phases to degrees. A
/// [`ErrorFunction::Sum`] (nested or not) is merged into one spec: constants, reversals and
/// polynomials (coefficient by coefficient) add, harmonics are listed in turn, and tables add:
/// on the same knots value by value, otherwise on the union of both tables' knots (exact for
/// linear tables, which the sum of two is; a cubic sum is then exact at the knots only).
pub fn spec_of(function: &ErrorFunction, name: ParameterName) -> ErrorSpec {
    let translation = name.motion().is_translation();
    let rotary_argument =
        matches!(name, ParameterName::Component { axis, .. } if !axis.is_linear());
    let position_scale = match name {
        ParameterName::Component { axis, .. } => axis_unit_to_si(axis),
        _ => crate::math::M_PER_MM,
    };
    let value = |v: Real| v / RAD_PER_URAD;
    let mut spec = ErrorSpec::default();
    let mut constant: Option<Real> = None;
    let mut polynomial: Option<Vec<Real>> = None;
    let mut reversal: Option<Real> = None;
    let mut table: Option<(Vec<Real>, Vec<Real>, Interpolation)> = None;
    let mut flat = Vec::new();
    flatten(function, &mut flat);
    for term in flat {
        match term {
            ErrorFunction::Constant(c) => *constant.get_or_insert(0.0) += value(*c),
            ErrorFunction::Reversal(r) => *reversal.get_or_insert(0.0) += value(*r),
            ErrorFunction::Polynomial(c) => {
                let sum = polynomial.get_or_insert_with(Vec::new);
                if sum.len() < c.len() {
                    sum.resize(c.len(), 0.0);
                }
                for (k, (s, c)) in sum.iter_mut().zip(c).enumerate() {
                    *s += value(*c) * position_scale.powi(k as i32);
                }
            }
            ErrorFunction::Harmonic {
                period,
                amplitude,
                phase,
            } => {
                let period = Some(period / position_scale);
                let amplitude = Some(value(*amplitude));
                spec.harmonic.push(HarmonicSpec {
                    period_mm: period.filter(|_| !rotary_argument),
                    period_deg: period.filter(|_| rotary_argument),
                    amplitude_um: amplitude.filter(|_| translation),
                    amplitude_urad: amplitude.filter(|_| !translation),
                    phase_deg: phase / crate::math::RAD_PER_DEG,
                });
            }
            ErrorFunction::Table(t) => {
                table = Some(match table.take() {
                    None => (
                        t.positions().to_vec(),
                        t.values().to_vec(),
                        t.interpolation(),
                    ),
                    Some((positions, values, interpolation)) => {
                        add_tables(positions, values, interpolation, t)
                    }
                });
            }
            ErrorFunction::Sum(_) => unreachable!("flattened"),
        }
    }
    let by_unit = |v: Option<Real>| (v.filter(|_| translation), v.filter(|_| !translation));
    (spec.constant_um, spec.constant_urad) = by_unit(constant);
    (spec.reversal_um, spec.reversal_urad) = by_unit(reversal);
    if translation {
        spec.polynomial_um = polynomial;
    } else {
        spec.polynomial_urad = polynomial;
    }
    if let Some((positions, values, interpolation)) = table {
        let positions: Vec<Real> = positions.iter().map(|p| p / position_scale).collect();
        let values: Vec<Real> = values.iter().map(|v| value(*v)).collect();
        let (values_um, values_urad) = if translation {
            (Some(values), None)
        } else {
            (None, Some(values))
        };
        spec.table = Some(TableSpec {
            positions_mm: Some(positions.clone()).filter(|_| !rotary_argument),
            positions_deg: Some(positions).filter(|_| rotary_argument),
            values_um,
            values_urad,
            interpolation: match interpolation {
                Interpolation::Linear => InterpolationSpec::Linear,
                Interpolation::Cubic => InterpolationSpec::Cubic,
            },
        });
    }
    spec
}

/// The terms of `function`, sums opened recursively.
fn flatten<'a>(function: &'a ErrorFunction, out: &mut Vec<&'a ErrorFunction>) {
    match function {
        ErrorFunction::Sum(terms) => terms.iter().for_each(|term| flatten(term, out)),
        term => out.push(term),
    }
}

/// The sum of a table (SI knots and values) and `other`: value by value on the same knots,
/// otherwise both evaluated on the union of their knots.
fn add_tables(
    positions: Vec<Real>,
    values: Vec<Real>,
    interpolation: Interpolation,
    other: &Table,
) -> (Vec<Real>, Vec<Real>, Interpolation) {
    if positions == other.positions() {
        let values = values
            .iter()
            .zip(other.values())
            .map(|(a, b)| a + b)
            .collect();
        return (positions, values, interpolation);
    }
    let first = Table::new(positions.clone(), values, interpolation)
        .map(ErrorFunction::Table)
        .expect("a table that was valid stays valid");
    let second = ErrorFunction::Table(other.clone());
    let mut union: Vec<Real> = positions.iter().chain(other.positions()).copied().collect();
    union.sort_by(Real::total_cmp);
    union.dedup();
    let up = crate::machine::Direction::Positive;
    let values = union
        .iter()
        .map(|&q| first.value(q, up) + second.value(q, up))
        .collect();
    (union, values, interpolation)
}
