//! The `[errors.NAME]` sections: ISO 230-1 error parameters as written (file units), checked
//! and turned into the error model.
//!
//! The terms as written are [`super::error_spec`]'s; here `error_model` checks each section
//! and assembles the model, with the terms of the error function in `function` (both ways:
//! [`function_of`], [`spec_of`]), the time- and speed-dependent terms in `dynamics`, the terms
//! measured inputs drive in [`super::inputs`], and the bound on a plausible error in
//! `plausible` ([`implausible`]).

mod dynamics;
mod function;
mod plausible;

pub use super::error_spec::{
    ErrorSpec, HarmonicSpec, InterpolationSpec, RandomSpec, SinusoidSpec, SpeedSpec, TableSpec,
};
pub use function::{MAX_POLYNOMIAL_DEGREE, function_of, spec_of};
pub use plausible::{LARGEST_ERROR, implausible};

use super::inputs::context_terms;
use super::{Context, ScenarioError, ScenarioErrorKind};
use crate::errors::TemperatureRecord;
use crate::errors::{
    ErrorFunction, ErrorModel, ErrorModelError, ErrorParameter, ParameterContext,
    ParameterDynamics, ParameterName,
};
use crate::machine::Machine;
use dynamics::{dynamic_key, spec_to_dynamics};
use function::{spec_to_function, varying_key};
use std::collections::BTreeMap;
use std::sync::Arc;
use toml::Spanned;

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
