//! Drift records (ISO 230-3:2007): displacement channels against time from a displacement
//! nest or an interferometer, with temperatures; the drift ranges, the stop criterion and the
//! environmental temperature variation error (ETVE); the ETVE (§5) and spindle (§6) tests that
//! write them.
//!
//! | file | owns |
//! |---|---|
//! | [`scenario`] | `[iso230_3_etve]`, the ETVE test (with `[thermal]`) → [`EtveTest`] |
//! | [`run`] | the ETVE test through the thermal twin: the nest and the thermometers ([`EtveRun`]); the nest's reading, shared with the spindle test |
//! | [`spindle_test`] | `[iso230_3_spindle]`, the §6 spindle thermal test: its section, speed programme and run ([`SpindleThermalTest`], [`SpindleThermalRun`]) |
//! | [`table`] | the `drift` table ([`DriftTable`]: time_min, `<channel>_um`/`_urad`, `temp_<sensor>_degc`, its conditions) |
//! | [`iso230_3`] | drift ranges, stop criterion, ETVE, tilts from sensor pairs, the report |
//! | [`cli`] | `mtwin analyze drift` |

pub mod cli;
pub mod iso230_3;
pub mod plausible;
pub mod run;
pub mod scenario;
pub mod spindle_test;
pub mod table;

pub use run::EtveRun;
pub use scenario::EtveTest;
pub use spindle_test::{SpeedProgramme, SpindleThermalRun, SpindleThermalTest};
pub use table::{DriftChannel, DriftConditions, DriftTable};
