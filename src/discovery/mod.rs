//! Model discovery, the shared engine: show what the twin's model of a measurement gets
//! wrong, name the physical cause, extend the model and measure the gain on data the fit did
//! not see.
//!
//! The [`engine`] is independent of the measurement: a [`engine::Problem`] supplies a base
//! model, a library of effects with rules that propose them from residual diagnostics, and
//! fits that use only a fold's training samples; the engine scores by cross-validated RMS and
//! selects forward. Each test kind brings its own problem in its folder:
//! `crate::kinds::positioning::discovery` (laser positioning tables) and
//! `crate::kinds::ballbar::discovery` (ISO 230-4 circular tests); spindle, R-test and drift
//! tables plug into the same engine.

pub mod engine;
pub mod least_squares;
pub mod nufft;
