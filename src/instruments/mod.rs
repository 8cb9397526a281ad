//! Virtual instruments: each measures the twin as the real one would, with its own errors and
//! noise, and writes a measurement table.

mod air;
pub mod ballbar;
pub mod laser;

pub use air::{Air, HENE_WAVELENGTH_UM};
