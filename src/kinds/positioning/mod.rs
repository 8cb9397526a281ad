//! Linear positioning measured by a laser interferometer: the ISO 230-2 test and the thermal
//! tests measured the same way (the `[warmup]` experiment, the ISO 230-3 §7 linear-motion
//! test), the `positioning` table, the ISO 230-2 evaluation and the thermal-series view, and
//! discovery on positioning tables.
//!
//! | file | owns |
//! |---|---|
//! | [`scenario`] | `[iso230_2]`, the `[laser]` ([`scenario::laser`]), `[warmup]` and `[iso230_3_linear]` ([`scenario::thermal_tests`], with `[thermal]`) → [`LaserTest`] |
//! | [`program`] | the ISO 230-2 [`LinearCycle`], the [`LinearMotionTest`], irregular targets |
//! | [`laser`], [`air`] | the virtual [`Laser`] (set-up, air and material compensation, dead path, noise) |
//! | [`setup`] | how the laser is set up: [`setup::Mounting`], [`setup::Zeroing`] |
//! | [`conditions`] | the conditions a table's preamble states ([`conditions::PositioningConditions`]) |
//! | [`table`] | the `positioning` table ([`PositioningTable`]) |
//! | [`run`] | the laser test through the twin, or through the thermal twin ([`LaserRun`]) |
//! | [`iso230_2`] | the ISO 230-2:2014 figures |
//! | [`thermal_series`] | the drift of each target over runs, against temperature and time |
//! | [`discovery`] | the discovery problem on positioning tables |
//! | [`compare`] | `mtwin compare`: a measured table against a simulated one, per run |
//! | [`cli`] | `mtwin analyze positioning` and `mtwin discover positioning` |
//! | `scene` | the teaching scene (feature `viz`) |

pub mod air;
pub mod cli;
pub mod compare;
pub mod conditions;
pub mod discovery;
pub mod iso230_2;
pub mod laser;
pub mod plausible;
pub mod program;
pub mod readings;
pub mod run;
pub mod scenario;
#[cfg(feature = "viz")]
pub mod scene;
pub mod setup;
pub mod stability;
pub mod table;
pub mod thermal_series;

pub use air::{Air, HENE_WAVELENGTH_UM};
pub use discovery::{
    DiscoveryError, PositioningDiscovery, PositioningEffect, PositioningOptions,
    discover_positioning,
};
pub use laser::Laser;
pub use program::{LinearCycle, LinearMotionTest, irregular_targets};
pub use run::LaserRun;
pub use scenario::LaserTest;
pub use table::{PositioningReading, PositioningTable};
