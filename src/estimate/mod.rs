//! Estimators, the shared engine beside [`crate::discovery`]: recover error parameters from
//! measurement tables, say what the tables cannot identify, and give honest uncertainties.
//!
//! - [`lm`]: a damped Gauss–Newton (Levenberg–Marquardt) solver on nalgebra, validated on the
//!   NIST StRD nonlinear-regression problems and MINPACK test functions.
//! - [`identifiability`]: the rank of a design (stacked, noise-weighted, column-scaled
//!   Jacobian), the combinations it cannot see and those it can, in ISO names.
//! - [`Readings`]: what a test kind supplies: its measured values, their uncertainties and the
//!   model of each reading on the twin's own chain (each kind's `readings.rs`).
//! - [`compensate`], [`sinumerik`], [`heidenhain`] and [`score`]: the identified machine
//!   written out (corrected URDF, LinuxCNC pitch tables, SINUMERIK measuring-system error
//!   compensation, HEIDENHAIN nonlinear axis-error tables) and scored against the truth.
//! - [`discover`]: model selection on a calibration: the terms (component-error orders, lost
//!   motions, squareness, drift) that predict held-out tests better than noise can explain.

pub mod compensate;
pub mod discover;
pub mod fit;
pub mod heidenhain;
pub mod identifiability;
pub mod influence;
pub mod lm;
pub mod plan;
mod readings;
pub mod report;
pub mod score;
pub mod sinumerik;
pub mod spec;

pub use readings::{Quantity, ReadingModel, Readings, ReadingsError};
