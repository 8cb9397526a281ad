//! Drift records (ISO 230-3:2007): displacement channels against time from a displacement
//! nest or an interferometer, with temperatures; the drift ranges, the stop criterion and the
//! environmental temperature variation error (ETVE).
//!
//! | file | owns |
//! |---|---|
//! | [`scenario`] | `[iso230_3_etve]`, the ETVE test (with `[thermal]`) → [`EtveTest`] |
//! | [`run`] | the ETVE test through the thermal twin: the nest and the thermometers ([`EtveRun`]) |
//! | [`table`] | the `drift` table ([`DriftTable`]: time_min, `<channel>_um`/`_urad`, `temp_<sensor>_degc`, its conditions) |
//! | [`iso230_3`] | drift ranges, stop criterion, ETVE, tilts from sensor pairs, the report |
//! | [`cli`] | `mtwin analyze drift` |

pub mod cli;
pub mod iso230_3;
pub mod run;
pub mod scenario;
pub mod table;

pub use run::EtveRun;
pub use scenario::EtveTest;
pub use table::{DriftChannel, DriftConditions, DriftTable};
