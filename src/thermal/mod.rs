//! Thermal behaviour (ISO 230-3): a lumped thermal network driven by what the machine does,
//! and temperature sensors on its nodes.

mod errors;
mod machine;
mod network;
mod record;
mod sensor;

pub use errors::{ThermalErrors, ThermalTerm, ThermalTermError};
pub use machine::{Ambient, HeatDriver, HeatSource, MachineThermal, ScrewSpec};
pub use network::{ThermalNetwork, ThermalNetworkError, ThermalNode, ThermalStepper};
pub use record::TemperatureRecord;
pub use sensor::{SensorSpec, TemperatureSensor, first_order_lag};
