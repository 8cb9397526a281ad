//! Reading the `errors` object of a `truth.json` or an `estimate.json`: every entry's name,
//! unit and `terms` checked against the machine, and the error model they make.

use super::error::ScoreError;
use crate::errors::{ErrorFunction, ErrorModel, ErrorParameter, ParameterName};
use crate::machine::Machine;
use crate::scenario::{ErrorSpec, function_of};
use serde_json::Value;

/// One parameter of an `errors` object: its name, terms and function.
pub(super) struct Entry {
    pub(super) name: ParameterName,
    pub(super) spec: ErrorSpec,
    pub(super) function: ErrorFunction,
    pub(super) raw: Value,
}

/// Builds the error model of `machine` from an `errors` object of `truth.json` or
/// `estimate.json` (names → entries with a `terms` object in file units). Messages name the key
/// path from `errors`.
pub fn error_model_of(errors: &Value, machine: &Machine) -> Result<ErrorModel, ScoreError> {
    model(&entries(errors, machine)?, machine)
}

pub(super) fn model(entries: &[Entry], machine: &Machine) -> Result<ErrorModel, ScoreError> {
    let parameters: Vec<ErrorParameter> = entries
        .iter()
        .map(|e| ErrorParameter {
            name: e.name,
            function: e.function.clone(),
        })
        .collect();
    // The limit every scenario and `identify` enforce (10 mm, 10 mrad): beyond it a value is a
    // unit slip or a corrupted file, and its squares overflow the volumetric figures.
    for parameter in &parameters {
        if let Some(why) = crate::scenario::errors::implausible(parameter, machine) {
            return Err(ScoreError::shape(
                format!("errors.{}", parameter.name),
                format!("{why}; score compares machine errors, not values beyond that limit"),
            ));
        }
    }
    ErrorModel::new(machine, parameters).map_err(|e| ScoreError::shape("errors", e.to_string()))
}

/// Parses and checks every entry of an `errors` object.
pub(super) fn entries(errors: &Value, machine: &Machine) -> Result<Vec<Entry>, ScoreError> {
    let map = match errors {
        Value::Object(map) => map,
        Value::Null => return Err(ScoreError::shape("errors", "missing")),
        _ => {
            return Err(ScoreError::shape(
                "errors",
                "expected an object mapping parameter names to entries",
            ));
        }
    };
    let mut out = Vec::with_capacity(map.len());
    for (key, raw) in map {
        let path = format!("errors.{key}");
        let name: ParameterName = key
            .parse()
            .map_err(|message: String| ScoreError::shape(&path, message))?;
        if let Some(axis) = name.axis().filter(|a| !machine.has_axis(*a)) {
            return Err(ScoreError::shape(
                &path,
                format!("machine \"{}\" has no axis {axis}", machine.name()),
            ));
        }
        let Value::Object(entry) = raw else {
            return Err(ScoreError::shape(
                &path,
                "expected an object with a \"terms\" object",
            ));
        };
        if let Some(unit) = entry.get("unit").filter(|u| !u.is_null())
            && unit.as_str() != Some(name.file_unit())
        {
            return Err(ScoreError::Units {
                file: String::new(),
                path: format!("{path}.unit"),
                parameter: name.to_string(),
                reason: format!("is given in {unit}"),
                expected: format!("\"{}\"", name.file_unit()),
            });
        }
        let terms = entry.get("terms").unwrap_or(&Value::Null);
        let terms_path = format!("{path}.terms");
        if !terms.is_object() {
            return Err(ScoreError::shape(
                terms_path,
                "expected an object of terms (constant_um, polynomial_urad, …)",
            ));
        }
        check_units(terms, name, &terms_path)?;
        let spec: ErrorSpec = serde_json::from_value(terms.clone())
            .map_err(|e| ScoreError::shape(&terms_path, e.to_string()))?;
        let function =
            function_of(&spec, name).map_err(|message| ScoreError::shape(&terms_path, message))?;
        out.push(Entry {
            name,
            spec,
            function,
            raw: raw.clone(),
        });
    }
    out.sort_by_cached_key(|e| e.name.to_string());
    Ok(out)
}

/// The unit of the position a parameter's function takes: `deg` for a component error of a
/// rotary axis (or the spindle), `mm` otherwise.
pub(super) fn position_unit(name: ParameterName) -> &'static str {
    match name {
        ParameterName::Component { axis, .. } if !axis.is_linear() => "deg",
        _ => "mm",
    }
}

/// Rejects value keys in the other value unit and position keys in the other position unit.
fn check_units(terms: &Value, name: ParameterName, path: &str) -> Result<(), ScoreError> {
    let unit = name.file_unit();
    let position = position_unit(name);
    let what = if name.motion().is_translation() {
        "is a translation"
    } else {
        "is a rotation"
    };
    let axis_what = if position == "deg" {
        "varies with the angle of a rotary axis"
    } else {
        "varies with a length"
    };
    let check = |field: &str, at: String, positions: bool| -> Result<(), ScoreError> {
        let Some((stem, suffix)) = field.rsplit_once('_') else {
            return Ok(());
        };
        let (expected, reason, family) = if positions {
            (position, axis_what, ["mm", "deg"])
        } else {
            (unit, what, ["um", "urad"])
        };
        if family.contains(&suffix) && suffix != expected {
            return Err(ScoreError::Units {
                file: String::new(),
                path: at,
                parameter: name.to_string(),
                reason: reason.to_string(),
                expected: format!("{stem}_{expected}"),
            });
        }
        Ok(())
    };
    let Value::Object(map) = terms else {
        return Ok(());
    };
    for (key, value) in map {
        match key.as_str() {
            "harmonic" => {
                for (i, h) in value.as_array().into_iter().flatten().enumerate() {
                    for field in h.as_object().into_iter().flat_map(|h| h.keys()) {
                        let at = format!("{path}.harmonic[{i}].{field}");
                        check(field, at, field.starts_with("period"))?;
                    }
                }
            }
            "table" => {
                for field in value.as_object().into_iter().flat_map(|t| t.keys()) {
                    let at = format!("{path}.table.{field}");
                    check(field, at, field.starts_with("positions"))?;
                }
            }
            _ => check(key, format!("{path}.{key}"), false)?,
        }
    }
    Ok(())
}
