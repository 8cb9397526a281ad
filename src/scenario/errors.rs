//! The `[errors.NAME]` sections: ISO 230-1 error parameters as written (file units), checked
//! and turned into the error model.

use super::bounds::{self, Bound};
use super::inputs::{DriftTermSpec, HeatingTermSpec, TemperatureTermSpec, context_terms};
use super::{Context, ScenarioError, ScenarioErrorKind};
use crate::errors::TemperatureRecord;
use crate::errors::{
    Dynamics, ErrorFunction, ErrorModel, ErrorModelError, ErrorParameter, Frequency, Interpolation,
    ParameterContext, ParameterDynamics, ParameterName, RandomMotion, Sinusoid, Table, TableError,
};
use crate::machine::{Axis, Machine, axis_unit_to_si};
use crate::math::{RAD_PER_URAD, Real};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;
use toml::Spanned;

/// The highest degree of a polynomial error function a scenario may give (11 coefficients).
///
/// In file units (µm per mm^k) a degree-10 term over a 1 m travel already has a coefficient of
/// order 1e-30 for a micrometre of error, near where f64 stops resolving it; a shape that needs
/// more is a table function. The limit also bounds a dataset prior on `polynomial_um[k]`, which
/// fills the coefficients below k with zeros.
pub const MAX_POLYNOMIAL_DEGREE: usize = 10;

/// The largest error the small-motion model is meant for: 10 mm or 10 mrad. Larger values are
/// typing mistakes (a unit off by 10³), not machine errors.
pub const LARGEST_ERROR: Real = 1e-2;

/// The terms of one error parameter, in file units (the `[errors.NAME]` table).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorSpec {
    /// Constant (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub constant_um: Option<Real>,
    /// Constant (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub constant_urad: Option<Real>,
    /// Polynomial coefficients from degree 0, in µm per (mm or deg)^k.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polynomial_um: Option<Vec<Real>>,
    /// Polynomial coefficients from degree 0, in µrad per (mm or deg)^k.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polynomial_urad: Option<Vec<Real>>,
    /// Lost motion (the axis lags the command by half of it against its direction of travel).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reversal_um: Option<Real>,
    /// Angular lost motion.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reversal_urad: Option<Real>,
    /// Cyclic errors.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub harmonic: Vec<HarmonicSpec>,
    /// A measured map.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub table: Option<TableSpec>,
    /// Asynchronous sinusoids: time-dependent content (see [`crate::errors::Dynamics`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub asynchronous: Vec<SinusoidSpec>,
    /// Band-limited random motion.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub random: Option<RandomSpec>,
    /// A factor on the whole parameter against the speed of its axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed: Option<SpeedSpec>,
    /// Terms driven by a measured sensor's temperature (see [`super::inputs`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub temperature: Vec<TemperatureTermSpec>,
    /// Terms from heat sources no sensor sees.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub heating: Vec<HeatingTermSpec>,
    /// Drifts linear in time.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub drift: Vec<DriftTermSpec>,
}

/// `amplitude · sin(2π · frequency_hz · t + phase)` or `amplitude · sin(per_revolution · q +
/// phase)` with `q` the axis's unwrapped angle.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SinusoidSpec {
    /// Amplitude (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_um: Option<Real>,
    /// Amplitude (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_urad: Option<Real>,
    /// Frequency in Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequency_hz: Option<Real>,
    /// Frequency in cycles per revolution of the axis (axes of rotation).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_revolution: Option<Real>,
    /// Phase at time zero (angle zero).
    #[serde(default)]
    pub phase_deg: Real,
}

/// Band-limited random motion of a given RMS, flat in its band.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomSpec {
    /// RMS (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_um: Option<Real>,
    /// RMS (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_urad: Option<Real>,
    /// The band in Hz, `[low, high]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub band_hz: Option<[Real; 2]>,
    /// The band in cycles per revolution of the axis, `[low, high]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub band_per_revolution: Option<[Real; 2]>,
}

/// A factor on the whole parameter at knots of the axis speed (magnitude), interpolated
/// linearly, end values held.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedSpec {
    /// Speeds of an axis of rotation (min⁻¹).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rpm: Option<Vec<Real>>,
    /// Speeds of a linear axis (mm/min).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mm_per_min: Option<Vec<Real>>,
    /// The factor at each speed.
    pub factor: Vec<Real>,
}

/// `amplitude · sin(360° · q / period + phase)`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HarmonicSpec {
    /// Period along a linear axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_mm: Option<Real>,
    /// Period about a rotary axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_deg: Option<Real>,
    /// Amplitude (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_um: Option<Real>,
    /// Amplitude (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_urad: Option<Real>,
    /// Phase at q = 0.
    #[serde(default)]
    pub phase_deg: Real,
}

/// Values at knots, interpolated linearly or by a natural cubic spline; end values held
/// outside.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    /// Knots along a linear axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub positions_mm: Option<Vec<Real>>,
    /// Knots about a rotary axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub positions_deg: Option<Vec<Real>>,
    /// Values (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub values_um: Option<Vec<Real>>,
    /// Values (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub values_urad: Option<Vec<Real>>,
    /// `linear` (default) or `cubic`.
    #[serde(default)]
    pub interpolation: InterpolationSpec,
}

/// Table interpolation as written in files.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InterpolationSpec {
    /// Straight lines.
    #[default]
    Linear,
    /// Natural cubic spline.
    Cubic,
}

/// Builds the error model of `machine` from the `[errors.*]` sections of one file (messages
/// name it through `context`), on top of `inherited` parameters and dynamics (an extended
/// scenario's model), which the sections replace by name. Random motion is realised from
/// `seed`. Returns the model and the specs as written.
pub(crate) fn error_model(
    context: &Context<'_>,
    machine: &Machine,
    errors_raw: &BTreeMap<Spanned<String>, Spanned<ErrorSpec>>,
    inherited: Option<&ErrorModel>,
    seed: u64,
    record: Option<&Arc<TemperatureRecord>>,
) -> Result<(ErrorModel, BTreeMap<String, ErrorSpec>), ScenarioError> {
    let mut parameters = Vec::new();
    let mut dynamics = Vec::new();
    let mut contexts = Vec::new();
    let mut error_specs = BTreeMap::new();
    for (name, spec) in errors_raw {
        let at = Some(name.span());
        let parameter: ParameterName = name.get_ref().parse().map_err(|message| {
            context.error(
                at.clone(),
                ScenarioErrorKind::Parameter,
                format!("errors.{}: {message}", name.get_ref()),
            )
        })?;
        let argument = parameter
            .axis()
            .filter(|_| matches!(parameter, ParameterName::Component { .. }));
        if let Some(axis) = parameter.axis().filter(|axis| !machine.has_axis(*axis)) {
            return Err(context.error(
                at,
                ScenarioErrorKind::Parameter,
                format!(
                    "errors.{parameter}: machine \"{}\" has no axis {axis}",
                    machine.name()
                ),
            ));
        }
        if *spec.get_ref() == ErrorSpec::default() {
            let unit = parameter.file_unit();
            return Err(context.error(
                Some(spec.span()),
                ScenarioErrorKind::Value,
                format!(
                    "errors.{parameter}: no term given; expected one or more of constant_{unit}, \
                     polynomial_{unit}, reversal_{unit}, harmonic, table, asynchronous, random, \
                     speed, temperature, heating, drift"
                ),
            ));
        }
        let key_error = |kind, key: &str, message: String| {
            let line = context.key_line(spec.span().start, key);
            let mut error = context.error(
                Some(spec.span()),
                kind,
                format!("errors.{parameter}.{key}: {message}"),
            );
            error.line = line.or(error.line);
            error
        };
        let function = spec_to_function(spec.get_ref(), parameter, argument)
            .map_err(|(kind, key, message)| key_error(kind, &key, message))?;
        if argument.is_none() && !function.is_constant() {
            return Err(key_error(
                ScenarioErrorKind::Value,
                varying_key(spec.get_ref()),
                format!(
                    "location, squareness and tool errors are constants; use constant_{}",
                    parameter.file_unit()
                ),
            ));
        }
        let terms = context_terms(spec.get_ref(), parameter, record.map(|r| r.as_ref()))
            .map_err(|(kind, key, message)| key_error(kind, &key, message))?;
        if !terms.is_empty() {
            contexts.push(ParameterContext {
                name: parameter,
                terms,
            });
        }
        let content = spec_to_dynamics(spec.get_ref(), parameter, seed)
            .map_err(|(kind, key, message)| key_error(kind, &key, message))?;
        if !content.is_empty() {
            if argument.is_none() {
                return Err(key_error(
                    ScenarioErrorKind::Value,
                    dynamic_key(spec.get_ref()),
                    "only component errors (error motions) vary with time and speed".to_string(),
                ));
            }
            dynamics.push(ParameterDynamics {
                name: parameter,
                dynamics: content,
            });
        }
        if !(function == ErrorFunction::Sum(Vec::new())
            && dynamics.last().is_some_and(|d| d.name == parameter))
        {
            parameters.push(ErrorParameter {
                name: parameter,
                function,
            });
        }
        error_specs.insert(parameter.to_string(), spec.get_ref().clone());
    }
    let replaced = |name: ParameterName| error_specs.contains_key(&name.to_string());
    let mut all: Vec<ErrorParameter> = inherited
        .map(|model| model.parameters().to_vec())
        .unwrap_or_default()
        .into_iter()
        .filter(|p| !replaced(p.name))
        .collect();
    all.extend(parameters);
    let mut all_dynamics: Vec<ParameterDynamics> = inherited
        .map(|model| model.dynamics().to_vec())
        .unwrap_or_default()
        .into_iter()
        .filter(|d| !replaced(d.name))
        .collect();
    all_dynamics.extend(dynamics);
    let mut all_contexts: Vec<ParameterContext> = inherited
        .map(|model| model.context().to_vec())
        .unwrap_or_default()
        .into_iter()
        .filter(|c| !replaced(c.name))
        .collect();
    all_contexts.extend(contexts);
    let errors = ErrorModel::new(machine, all)
        .and_then(|model| model.with_dynamics(machine, all_dynamics))
        .and_then(|model| model.with_context(machine, all_contexts, record.cloned()))
        .map_err(|e| {
            let name = e.parameter().to_string();
            let span = errors_raw
                .iter()
                .find(|(key, _)| *key.get_ref() == name)
                .map(|(_, spec)| spec.span());
            let kind = match e {
                ErrorModelError::NotPeriodic { .. } | ErrorModelError::NotConstant(_) => {
                    ScenarioErrorKind::Value
                }
                _ => ScenarioErrorKind::Parameter,
            };
            context.error(span, kind, format!("errors.{e}"))
        })?;
    for parameter in errors.parameters() {
        if let Some(message) = implausible(parameter, machine) {
            let spec = errors_raw
                .iter()
                .find(|(key, _)| *key.get_ref() == parameter.name.to_string());
            return Err(context.error(
                spec.map(|(_, spec)| spec.span()),
                ScenarioErrorKind::Value,
                format!("errors.{}: {message}", parameter.name),
            ));
        }
    }
    Ok((errors, error_specs))
}

/// What is wrong with one key of an `[errors.NAME]` table: the kind, the key's path inside the
/// table (e.g. `table.positions_deg`) and the message.
type SpecError = (ScenarioErrorKind, String, String);

/// Turns the terms of `[errors.NAME]` into a function (SI), checking units and values.
/// `argument` is the axis whose position the function takes (component errors only).
fn spec_to_function(
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

/// The first time- or speed-dependent key of a spec, for messages.
fn dynamic_key(spec: &ErrorSpec) -> &'static str {
    if !spec.asynchronous.is_empty() {
        "asynchronous"
    } else if spec.random.is_some() {
        "random"
    } else {
        "speed"
    }
}

/// Turns the time- and speed-dependent terms of `[errors.NAME]` (`asynchronous`, `random`,
/// `speed`) into [`Dynamics`] (SI); the random motion is realised from `seed`.
fn spec_to_dynamics(
    spec: &ErrorSpec,
    name: ParameterName,
    seed: u64,
) -> Result<Dynamics, SpecError> {
    use ScenarioErrorKind::{Units, Value};
    let translation = name.motion().is_translation();
    let (unit, other_unit) = if translation {
        ("um", "urad")
    } else {
        ("urad", "um")
    };
    let rotary = name.axis().is_some_and(|axis| !axis.is_linear());
    let pick =
        |um: Option<Real>, urad: Option<Real>| if translation { (um, urad) } else { (urad, um) };
    let fail = |kind, key: String, message: String| -> SpecError { (kind, key, message) };
    let finite = |key: &str, v: Real| {
        if v.is_finite() {
            Ok(())
        } else {
            Err(fail(Value, key.to_string(), "not a finite number".into()))
        }
    };
    let within = |key: &str, v: Real, bound: Bound| {
        bound
            .check(v)
            .map(|_| ())
            .map_err(|message| fail(Value, key.to_string(), message))
    };
    let amplitude_bound = Bound::symmetric(bounds::AMPLITUDE_UM.hi, bounds::AMPLITUDE_UM.why);
    let frequency_bound = |per_revolution: bool| {
        if per_revolution {
            Bound {
                lo: 0.0,
                hi: HIGHEST_PER_REVOLUTION,
                why: "no error motion of a spindle has more waves a turn",
            }
        } else {
            bounds::FREQUENCY_HZ
        }
    };
    let mut dynamics = Dynamics::default();
    for (i, a) in spec.asynchronous.iter().enumerate() {
        let key = |field: &str| format!("asynchronous[{i}].{field}");
        let (amplitude, other) = pick(a.amplitude_um, a.amplitude_urad);
        if other.is_some() {
            return Err(fail(
                Units,
                key(&format!("amplitude_{other_unit}")),
                format!("{name} is in {unit}; give amplitude_{unit}"),
            ));
        }
        let amplitude_key = key(&format!("amplitude_{unit}"));
        let amplitude =
            amplitude.ok_or_else(|| fail(Value, amplitude_key.clone(), "required".into()))?;
        within(&amplitude_key, amplitude, amplitude_bound)?;
        finite(&key("phase_deg"), a.phase_deg)?;
        let frequency = match (a.frequency_hz, a.per_revolution) {
            (Some(f), None) => {
                within(&key("frequency_hz"), f, frequency_bound(false))?;
                if f <= 0.0 {
                    return Err(fail(
                        Value,
                        key("frequency_hz"),
                        format!("must be positive, got {f}"),
                    ));
                }
                Frequency::Hz(f)
            }
            (None, Some(r)) => {
                within(&key("per_revolution"), r, frequency_bound(true))?;
                if !rotary {
                    return Err(fail(
                        Value,
                        key("per_revolution"),
                        "a frequency per revolution needs an axis of rotation; give frequency_hz"
                            .into(),
                    ));
                }
                if r <= 0.0 {
                    return Err(fail(
                        Value,
                        key("per_revolution"),
                        format!("must be positive, got {r}"),
                    ));
                }
                Frequency::PerRevolution(r)
            }
            _ => {
                return Err(fail(
                    Value,
                    key("frequency_hz"),
                    "give one of frequency_hz or per_revolution".into(),
                ));
            }
        };
        dynamics.sinusoids.push(Sinusoid {
            frequency,
            amplitude: amplitude * RAD_PER_URAD,
            phase: a.phase_deg * crate::math::RAD_PER_DEG,
        });
    }
    if let Some(r) = &spec.random {
        let (rms, other) = pick(r.rms_um, r.rms_urad);
        if other.is_some() {
            return Err(fail(
                Units,
                format!("random.rms_{other_unit}"),
                format!("{name} is in {unit}; give rms_{unit}"),
            ));
        }
        let rms_key = format!("random.rms_{unit}");
        let rms = rms.ok_or_else(|| fail(Value, rms_key.clone(), "required".into()))?;
        within(&rms_key, rms, bounds::AMPLITUDE_UM)?;
        let (band, per_revolution, band_key) = match (r.band_hz, r.band_per_revolution) {
            (Some(b), None) => (b, false, "random.band_hz"),
            (None, Some(b)) if rotary => (b, true, "random.band_per_revolution"),
            (None, Some(_)) => {
                return Err(fail(
                    Value,
                    "random.band_per_revolution".into(),
                    "a band per revolution needs an axis of rotation; give band_hz".into(),
                ));
            }
            _ => {
                return Err(fail(
                    Value,
                    "random.band_hz".into(),
                    "give one of band_hz or band_per_revolution".into(),
                ));
            }
        };
        if !(band[0].is_finite() && band[1].is_finite() && 0.0 <= band[0] && band[0] < band[1]) {
            return Err(fail(
                Value,
                band_key.into(),
                format!(
                    "expected [low, high] with 0 <= low < high, got [{}, {}]",
                    band[0], band[1]
                ),
            ));
        }
        within(band_key, band[1], frequency_bound(per_revolution))?;
        dynamics.random = Some(RandomMotion::realise(
            rms * RAD_PER_URAD,
            (band[0], band[1]),
            per_revolution,
            seed,
            name,
        ));
    }
    if let Some(v) = &spec.speed {
        let (speeds, key, scale) = match (&v.rpm, &v.mm_per_min, rotary) {
            (Some(s), None, true) => (s, "speed.rpm", std::f64::consts::TAU / 60.0),
            (None, Some(s), false) => (s, "speed.mm_per_min", crate::math::M_PER_MM / 60.0),
            _ => {
                let expected = if rotary {
                    "speed.rpm"
                } else {
                    "speed.mm_per_min"
                };
                return Err(fail(
                    Units,
                    expected.into(),
                    format!(
                        "the speeds of axis {} are given as {expected}",
                        name.axis().map_or('?', |a| a.letter())
                    ),
                ));
            }
        };
        let fastest = if rotary {
            Bound {
                lo: 0.0,
                hi: 200_000.0,
                why: "the fastest spindles turn at about 150 000 min⁻¹",
            }
        } else {
            Bound {
                lo: 0.0,
                ..bounds::FEED_MM_PER_MIN
            }
        };
        let factors = Bound {
            lo: 0.0,
            hi: 1000.0,
            why: "a speed multiplies an error motion by at most a thousand",
        };
        for (values, key, bound) in [(speeds, key, fastest), (&v.factor, "speed.factor", factors)] {
            for (i, x) in values.iter().enumerate() {
                bound.check(*x).map_err(|message| {
                    fail(Value, key.into(), format!("value {}: {message}", i + 1))
                })?;
            }
        }
        let table = Table::new(
            speeds.iter().map(|s| s * scale).collect(),
            v.factor.clone(),
            Interpolation::Linear,
        )
        .map_err(|e| fail(Value, key.into(), e.to_string()))?;
        dynamics.speed_factor = Some(table);
    }
    Ok(dynamics)
}

/// The shortest period of a harmonic term (mm or deg): no pitch, tooth or scale line is finer.
const SHORTEST_PERIOD: Real = 0.001;

/// The highest frequency of an error motion in cycles per revolution: beyond it the
/// spindle's own probes (and its structure) cannot follow.
const HIGHEST_PER_REVOLUTION: Real = 1000.0;

/// Why an error parameter is not a plausible machine error, if it is not: its largest value
/// over its axis's travel (or a turn, sampled at 1001 points) beyond [`LARGEST_ERROR`], or not
/// finite once in SI units (e.g. a period that underflows to zero).
pub fn implausible(parameter: &ErrorParameter, machine: &Machine) -> Option<String> {
    let (lower, upper) = match parameter.name {
        ParameterName::Component { axis, .. } => machine
            .axis(axis)
            .and_then(|info| info.limits)
            .unwrap_or((0.0, std::f64::consts::TAU)),
        _ => (0.0, 0.0),
    };
    let mut largest: Real = 0.0;
    for i in 0..=1000 {
        let q = lower + (upper - lower) * i as Real / 1000.0;
        for direction in [
            crate::machine::Direction::Positive,
            crate::machine::Direction::Negative,
        ] {
            let value = parameter.function.value(q, direction);
            if !value.is_finite() {
                return Some(format!(
                    "not a finite number at {q} (SI units) once converted"
                ));
            }
            largest = largest.max(value.abs());
        }
    }
    let unit = parameter.name.file_unit();
    (largest > LARGEST_ERROR).then(|| {
        format!(
            "reaches {:.0} {unit} over the travel, more than the {:.0} {unit} the small-motion error model is for",
            largest / RAD_PER_URAD,
            LARGEST_ERROR / RAD_PER_URAD
        )
    })
}

/// The first key of a spec that makes it vary with position or direction (to name it when a
/// constant is required).
fn varying_key(spec: &ErrorSpec) -> &'static str {
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
