//! Thermal behaviour (ISO 230-3): a lumped thermal network driven by what the machine does,
//! and temperature sensors on its nodes.

mod errors;
mod machine;
mod network;
mod sensor;

pub use crate::math::first_order_lag;
pub use errors::{ThermalErrors, ThermalTerm, ThermalTermError};
pub use machine::{Ambient, HeatDriver, HeatSource, MachineThermal, ScrewSpec};
pub use network::{ThermalNetwork, ThermalNetworkError, ThermalNode, ThermalStepper};
pub use sensor::{SensorSpec, TemperatureSensor};
