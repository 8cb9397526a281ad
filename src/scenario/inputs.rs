//! Measured inputs of a scenario (`[inputs]`) and the error terms they drive (the
//! `temperature`, `heating` and `drift` keys of `[errors.NAME]`, see
//! [`crate::errors::ContextTerm`]).
//!
//! ```toml
//! [inputs]
//! temperatures = "positioning.csv"    # time_min + temp_<sensor>_degc columns (relative to this file)
//! thermal_network_errors = false      # the [thermal] network's error terms are off: the
//!                                     # [errors.*] temperature terms replace them
//!
//! [errors.EXX]
//! table = { positions_mm = [5, 380, 755], values_um = [0.1, 2.3, 4.4] }
//! temperature = [
//!   { sensor = "x_nut", reference_degc = 20.62, um_per_m_per_degc = 11.7, lag_min = 21.0 },  # expansion
//!   { sensor = "x_nut", reference_degc = 20.62, um_per_degc = -0.8 },                        # origin drift
//! ]
//! # A sensor that lags the structure: `sensor_lag_min = 20.0` reads T + 20 min · dT/dt.
//! heating = [{ um_per_m = 3.1, tau_min = 35.0, from_min = 0.0 }]   # a heat source no sensor sees
//! drift = [{ um_per_h = 0.2, from_min = 40.0 }]                    # drift linear in time
//! ```
//!
//! Coefficients are in the parameter's unit (µm for translations, µrad for rotations), per °C,
//! per unit of heating or per hour, and with `_per_m` per metre of the parameter's axis
//! position (component errors of a linear axis: an expansion rather than an offset). Time
//! is measured from the start of the programme, as the record's `time_min` is from the start
//! of the test.

pub use super::error_spec::{DriftTermSpec, HeatingTermSpec, TemperatureTermSpec};

use super::ScenarioErrorKind;
use super::bounds::{self, Bound};
use super::error_spec::{ErrorSpec, SpecError};
use crate::errors::TemperatureRecord;
use crate::errors::{ContextTerm, Driver, ParameterName};
use crate::machine::Axis;
use crate::math::{RAD_PER_URAD, Real};
use serde::Deserialize;
use toml::Spanned;

/// The `[inputs]` section.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawInputs {
    /// The measured temperature record (relative to the scenario file).
    pub(crate) temperatures: Option<Spanned<String>>,
    /// Whether the `[thermal]` network's error terms act (default true; without a network
    /// there are none).
    pub(crate) thermal_network_errors: Option<Spanned<bool>>,
}

/// The context terms of `[errors.NAME]` (SI), checked: units match the parameter, exactly one
/// coefficient per term, `_per_m` only on a linear axis's component error, time constants
/// positive, temperature terms on a sensor of `record`.
pub(crate) fn context_terms(
    spec: &ErrorSpec,
    name: ParameterName,
    record: Option<&TemperatureRecord>,
) -> Result<Vec<ContextTerm>, SpecError> {
    use ScenarioErrorKind::{Units, Value};
    let translation = name.motion().is_translation();
    let linear_component =
        matches!(name, ParameterName::Component { axis, .. } if Axis::is_linear(axis));
    let (unit, other) = if translation {
        ("um", "urad")
    } else {
        ("urad", "um")
    };
    // Exactly one coefficient of the right unit: (value in file units, per metre of travel).
    let coefficient = |term: String,
                       options: [(Option<Real>, &str, bool, bool); 4],
                       suffix: &str|
     -> Result<(Real, bool), SpecError> {
        let given: Vec<_> = options.iter().filter(|(v, ..)| v.is_some()).collect();
        let keys = format!("{unit}{suffix} or {unit}_per_m{suffix}");
        match given.as_slice() {
            [] => Err((Value, term, format!("no coefficient; give {keys}"))),
            [(Some(v), field, per_m, is_translation)] => {
                let key = format!("{term}.{field}");
                if *is_translation != translation {
                    return Err((
                        Units,
                        key,
                        format!(
                            "{name} is a {}; give the coefficient in {unit} ({keys}), not {other}",
                            if translation {
                                "translation"
                            } else {
                                "rotation"
                            }
                        ),
                    ));
                }
                if *per_m && !linear_component {
                    return Err((
                        Value,
                        key,
                        "a coefficient per metre of travel needs a component error of a linear axis"
                            .into(),
                    ));
                }
                let bound = match suffix {
                    "_per_degc" => Bound::symmetric(
                        1000.0,
                        "steel expands 11.7 µm per metre and degree; a thousand is no machine",
                    ),
                    "_per_h" => {
                        Bound::symmetric(1000.0, "a millimetre an hour is a crash, not a drift")
                    }
                    _ => Bound::symmetric(bounds::AMPLITUDE_UM.hi, bounds::AMPLITUDE_UM.why),
                };
                bound.check(*v).map_err(|message| (Value, key, message))?;
                Ok((*v * RAD_PER_URAD, *per_m))
            }
            _ => Err((
                Value,
                term,
                format!("give one coefficient ({keys}), not several"),
            )),
        }
    };
    // Lags and time constants up to a week (τ > 0); start times within a record's clock.
    let minutes = |key: String, value: Real, positive: bool| -> Result<Real, SpecError> {
        let bound = if key.ends_with("from_min") {
            Bound {
                lo: 0.0,
                hi: crate::io::CLOCK_MIN.limit,
                why: crate::io::CLOCK_MIN.why,
            }
        } else {
            bounds::LAG_MIN
        };
        match bound.check(value) {
            Ok(_) if positive && value <= 0.0 => Err((
                Value,
                key,
                format!("expected a positive number of minutes, found {value}"),
            )),
            Ok(value) => Ok(value),
            Err(message) => Err((Value, key, format!("{message} min"))),
        }
    };
    let mut terms = Vec::new();
    for (i, t) in spec.temperature.iter().enumerate() {
        let key = |field: &str| format!("temperature[{i}].{field}");
        let (c, per_position) = coefficient(
            format!("temperature[{i}]"),
            [
                (t.um_per_degc, "um_per_degc", false, true),
                (t.um_per_m_per_degc, "um_per_m_per_degc", true, true),
                (t.urad_per_degc, "urad_per_degc", false, false),
                (t.urad_per_m_per_degc, "urad_per_m_per_degc", true, false),
            ],
            "_per_degc",
        )?;
        let lag = minutes(key("lag_min"), t.lag_min.unwrap_or(0.0), false)? * 60.0;
        let sensor_lag = minutes(
            key("sensor_lag_min"),
            t.sensor_lag_min.unwrap_or(0.0),
            false,
        )? * 60.0;
        bounds::TEMPERATURE_DEGC
            .check(t.reference_degc)
            .map_err(|message| (Value, key("reference_degc"), message))?;
        let Some(record) = record else {
            return Err((
                Value,
                key("sensor"),
                "a temperature term needs a measured temperature record: add `[inputs] temperatures = \"FILE.csv\"`".into(),
            ));
        };
        if record.sensor(&t.sensor).is_none() {
            return Err((
                Value,
                key("sensor"),
                format!(
                    "no sensor \"{}\" in {} (it has {})",
                    t.sensor,
                    record.file(),
                    record.sensors().join(", ")
                ),
            ));
        }
        terms.push(ContextTerm {
            driver: Driver::Temperature {
                sensor: t.sensor.clone(),
                reference: t.reference_degc,
                lag,
                sensor_lag,
            },
            coefficient: c,
            per_position,
        });
    }
    for (i, h) in spec.heating.iter().enumerate() {
        let key = |field: &str| format!("heating[{i}].{field}");
        let (c, per_position) = coefficient(
            format!("heating[{i}]"),
            [
                (h.um, "um", false, true),
                (h.um_per_m, "um_per_m", true, true),
                (h.urad, "urad", false, false),
                (h.urad_per_m, "urad_per_m", true, false),
            ],
            "",
        )?;
        let tau = minutes(key("tau_min"), h.tau_min, true)? * 60.0;
        let from = minutes(key("from_min"), h.from_min, false)? * 60.0;
        terms.push(ContextTerm {
            driver: Driver::Heating { tau, from },
            coefficient: c,
            per_position,
        });
    }
    for (i, d) in spec.drift.iter().enumerate() {
        let key = |field: &str| format!("drift[{i}].{field}");
        let (c, per_position) = coefficient(
            format!("drift[{i}]"),
            [
                (d.um_per_h, "um_per_h", false, true),
                (d.um_per_m_per_h, "um_per_m_per_h", true, true),
                (d.urad_per_h, "urad_per_h", false, false),
                (d.urad_per_m_per_h, "urad_per_m_per_h", true, false),
            ],
            "_per_h",
        )?;
        let from = minutes(key("from_min"), d.from_min, false)? * 60.0;
        terms.push(ContextTerm {
            driver: Driver::Drift { from },
            coefficient: c / 3600.0,
            per_position,
        });
    }
    Ok(terms)
}
