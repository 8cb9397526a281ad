//! Drift records (ISO 230-3:2007): displacement channels against time from a displacement
//! nest or an interferometer, with temperatures; the drift ranges, the stop criterion and the
//! environmental temperature variation error (ETVE).
//!
//! | file | owns |
//! |---|---|
//! | [`table`] | the `drift` table ([`DriftTable`]: time_min, `<channel>_um`/`_urad`, `temp_<sensor>_degc`) |
//! | [`iso230_3`] | drift ranges, stop criterion, ETVE, the report |
//! | [`cli`] | `mtwin analyze drift` |
//!
//! No bundled scenario writes a drift table yet: real or foreign records are read as they are.

pub mod cli;
pub mod iso230_3;
pub mod table;

pub use table::{DriftChannel, DriftTable};
