//! The ball-bar circular test (ISO 230-4): the `[ballbar]` and `[servo]` sections, the
//! circular interpolation and its run through the servo loops, the virtual ball-bar, the
//! `ballbar` table, the ISO 230-4 evaluation with the diagnostics of ball-bar software, and
//! discovery on circular tests.
//!
//! | file | owns |
//! |---|---|
//! | [`scenario`] | `[ballbar]` and `[servo]` → [`BallbarTest`] |
//! | [`program`] | [`CircularInterpolation`] (G03 then G02, ramps, overshoots) and [`run_circle`] through the servo loops |
//! | [`instrument`] | the virtual [`Ballbar`]: bar length, set-up, calibration, resolution, noise |
//! | [`table`] | the `ballbar` table ([`BallbarTable`]: direction, angle_deg, deviation_um, time_s) |
//! | [`run`] | one table per circle, and the truth of the set-up and servo |
//! | [`iso230_4`] | G, H, F and the joint diagnostic fit |
//! | [`discovery`] | the discovery problem on circular tests |
//! | [`cli`] | `mtwin analyze ballbar` and `mtwin discover ballbar` |
//! | `scene` | the teaching scene (feature `viz`) |

pub mod cli;
pub mod discovery;
mod fragment;
pub mod instrument;
pub mod iso230_4;
pub mod plausible;
pub mod program;
pub mod readings;
pub mod run;
pub mod scenario;
#[cfg(feature = "viz")]
pub mod scene;
pub mod table;

pub use discovery::{BallbarDiscovery, BallbarDiscoveryError, BallbarEffect, discover_ballbar};
pub use instrument::{BALLBAR_LENGTHS, Ballbar};
pub use iso230_4::{BallbarEvaluation, CircularTest};
pub use program::{CircularInterpolation, CommandPoint, ServoSample, run_circle};
pub use scenario::BallbarTest;
pub use table::{BallbarReading, BallbarTable, Sense, TestConditions};
