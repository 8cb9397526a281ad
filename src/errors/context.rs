//! Error terms driven by the machine's context rather than by its axis positions alone:
//! measured temperatures (by sensor name), the time since the start, and for each term
//! optionally the position of the parameter's own axis. They are what model discovery finds
//! in thermal and time-dependent data (`thermal_scale`, `thermal_offset`, `thermal_lag`,
//! `second_heat_source`, `time_drift`), written as scenario terms of any error parameter
//! (`[errors.NAME]` keys `temperature`, `heating`, `drift`; see
//! [`crate::scenario::errors`]) so that the extended twin runs.
//!
//! Each [`ContextTerm`] adds `coefficient · driver · factor` to its parameter, with `factor`
//! the axis position (m) for a term per metre of travel and 1 otherwise, and the driver one of
//! (`t` the time since the start of the programme, s):
//!
//! - [`Driver::Temperature`]: `T(t) − T_ref`, `T` a sensor of a measured
//!   [`TemperatureRecord`], ahead of its reading by `sensor_lag·dT/dt` when the sensor lags
//!   the structure, then through a first-order lag of time constant `lag` when the structure
//!   lags the sensor (0: none);
//! - [`Driver::Heating`]: `1 − e^(−(t − t₀)/τ)` from `t₀` on, 0 before — a heat source no sensor
//!   sees, warming with its own time constant from when the machine starts working;
//! - [`Driver::Drift`]: `t − t₀` (a drift linear in time).
//!
//! Simplified: temperatures come from a measured record, not from the simulated thermal
//! network's sensors, so a model with temperature terms reproduces the conditions of the file
//! it was found on (the usual use: check and extend a model on measured data); driving it from
//! the network for a new programme is not wired yet.

use super::binding::{Action, Binding};
use super::error::ErrorModelError;
use super::name::ParameterName;
use crate::errors::TemperatureRecord;
use crate::machine::{Machine, MachineState};
use crate::math::Real;
use std::sync::Arc;

/// What drives a [`ContextTerm`].
#[derive(Clone, Debug, PartialEq)]
pub enum Driver {
    /// A measured sensor's temperature above `reference` (°C), through a first-order lag of
    /// `lag` s (0: none).
    Temperature {
        /// The sensor's name (its `temp_<sensor>_degc` column in the record).
        sensor: String,
        /// The temperature at which the term is zero (°C).
        reference: Real,
        /// Time constant of the structure behind the sensor (s); 0 for none.
        lag: Real,
        /// Time constant of the sensor behind the structure (s); 0 for none: the structure's
        /// temperature is `T + τ_s·dT/dt`, the inverse of the sensor's first-order lag, with
        /// the rate read from the record ([`TemperatureRecord::rates`]).
        sensor_lag: Real,
    },
    /// A heat source no sensor sees: `1 − e^(−(t − from)/tau)` from `from` (s) on.
    Heating {
        /// Time constant (s), positive.
        tau: Real,
        /// When it starts (s since the start of the programme).
        from: Real,
    },
    /// Time since `from` (s): a drift linear in time.
    Drift {
        /// When the drift is zero (s since the start of the programme).
        from: Real,
    },
}

/// One context-driven term of an error parameter (SI).
#[derive(Clone, Debug, PartialEq)]
pub struct ContextTerm {
    /// What drives it.
    pub driver: Driver,
    /// m or rad per unit of the driver (per K, per unit of heating, per s), and per metre of
    /// travel when `per_position`.
    pub coefficient: Real,
    /// The term grows with the position of the parameter's axis (a linear axis's component
    /// error only): an expansion rather than an offset.
    pub per_position: bool,
}

/// The context terms of one error parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterContext {
    /// The parameter.
    pub name: ParameterName,
    /// Its terms, summed.
    pub terms: Vec<ContextTerm>,
}

/// Context terms bound to a machine and, for temperature terms, to a measured record.
#[derive(Clone, Debug, Default)]
pub(super) struct ContextErrors {
    entries: Vec<ParameterContext>,
    bound: Vec<BoundTerm>,
    record: Option<Arc<TemperatureRecord>>,
}

/// One term where it acts, with its sensor series precomputed.
#[derive(Clone, Debug)]
struct BoundTerm {
    binding: Binding,
    component: usize,
    term: ContextTerm,
    /// Temperature terms: the structure's temperature at each record sample before the lag
    /// (the sensor's, ahead by its own lag), and after the lag (with a lag).
    source: Vec<Real>,
    series: Vec<Real>,
}

impl ContextErrors {
    /// Binds `entries` to `machine`; temperature terms need `record` and a sensor of it.
    pub(super) fn new(
        machine: &Machine,
        entries: Vec<ParameterContext>,
        record: Option<Arc<TemperatureRecord>>,
    ) -> Result<ContextErrors, ErrorModelError> {
        let mut bound = Vec::new();
        for entry in &entries {
            let name = entry.name;
            let binding = Binding::of(machine, name)?;
            for term in &entry.terms {
                let invalid = |message: String| ErrorModelError::InvalidName(name, message);
                if term.per_position
                    && !matches!(binding.action, Action::Component(axis) if axis.is_linear())
                {
                    return Err(invalid(
                        "a term per metre of travel needs a component error of a linear axis"
                            .into(),
                    ));
                }
                let (source, series) = match &term.driver {
                    Driver::Temperature {
                        sensor,
                        lag,
                        sensor_lag,
                        ..
                    } => {
                        let record = record.as_ref().ok_or_else(|| {
                            invalid(format!(
                                "a temperature term (sensor {sensor}) needs a measured temperature record"
                            ))
                        })?;
                        let index = record.sensor(sensor).ok_or_else(|| {
                            invalid(format!(
                                "no sensor {sensor} in {} (it has {})",
                                record.file(),
                                record.sensors().join(", ")
                            ))
                        })?;
                        let mut source = record.samples(index).to_vec();
                        if *sensor_lag > 0.0 {
                            for (value, rate) in source.iter_mut().zip(record.rates(index)) {
                                *value += sensor_lag * rate;
                            }
                        }
                        let series = if *lag > 0.0 {
                            record.lag(&source, *lag)
                        } else {
                            Vec::new()
                        };
                        (source, series)
                    }
                    Driver::Heating { .. } | Driver::Drift { .. } => (Vec::new(), Vec::new()),
                };
                bound.push(BoundTerm {
                    binding,
                    component: name.motion().index(),
                    term: term.clone(),
                    source,
                    series,
                });
            }
        }
        Ok(ContextErrors {
            entries,
            bound,
            record,
        })
    }

    /// The terms, by parameter.
    pub(super) fn entries(&self) -> &[ParameterContext] {
        &self.entries
    }

    /// The measured record the temperature terms read.
    pub(super) fn record(&self) -> Option<&Arc<TemperatureRecord>> {
        self.record.as_ref()
    }

    /// Where each term acts: its slot, its twist component and whether it moves the axis line
    /// (`line`) rather than the relative twist.
    pub(super) fn targets(&self) -> impl Iterator<Item = (usize, usize, bool)> + '_ {
        self.bound.iter().map(|bound| {
            let on_line = matches!(
                bound.binding.action,
                Action::Squareness(_) | Action::RotaryLocation(_)
            );
            (bound.binding.slot, bound.component, on_line)
        })
    }

    /// Adds every term at `state` to the slot twists (`relative`) or axis-line locations
    /// (`line`), as its parameter acts.
    pub(super) fn add(
        &self,
        state: &MachineState,
        relative: &mut [[Real; 6]],
        line: &mut [[Real; 6]],
    ) {
        for bound in &self.bound {
            let t = state.time;
            let driver = match &bound.term.driver {
                Driver::Temperature { reference, lag, .. } => {
                    let record = self.record.as_ref().expect("checked when bound");
                    let temperature = if *lag > 0.0 {
                        record.lag_at(&bound.source, &bound.series, *lag, t)
                    } else {
                        record.interpolate(&bound.source, t)
                    };
                    temperature - reference
                }
                Driver::Heating { tau, from } if t >= *from => 1.0 - (-(t - from) / tau).exp(),
                Driver::Heating { .. } => 0.0,
                Driver::Drift { from } => t - from,
            };
            let factor = match bound.binding.action {
                Action::Component(axis) if bound.term.per_position => state.position[axis],
                _ => 1.0,
            };
            let value = bound.term.coefficient * driver * factor;
            let slot = bound.binding.slot;
            match bound.binding.action {
                Action::Component(_) | Action::Constant => relative[slot][bound.component] += value,
                Action::Squareness(_) | Action::RotaryLocation(_) => {
                    line[slot][bound.component] += value
                }
            }
        }
    }
}
