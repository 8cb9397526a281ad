//! The R-test (ISO 10791-6 kinematic tests): a precision sphere on the table, a nest of
//! displacement probes in the spindle (the arrangement of IBS's Rotary Inspector, whose head
//! is loaded from the tool magazine), the rotary axes turning while the linear axes follow.
//!
//! | file | owns |
//! |---|---|
//! | [`scenario`] | `[rtest]` → [`RTest`] |
//! | [`program`] | [`KTest`]: the rotary angles along a test, the linear axes following ([`program::follow`]); static and dynamic poses |
//! | [`instrument`] | the virtual [`Nest`]: probe axes, flat or point tips, gains, noise, resolution; the software's conversion and six-point calibration |
//! | [`table`] | the `rtest` table ([`RtestTable`]) |
//! | [`run`] | calibration, the tests through the twin, the truth |
//! | [`analysis`] | deviation ranges and the fitted circle or line per test |
//! | [`plot`] | the SVG of each test |
//! | [`cli`] | `mtwin analyze rtest` |
//! | `scene` | the teaching scene (feature `viz`) |

pub mod analysis;
mod angles;
pub mod cli;
pub mod instrument;
pub mod plausible;
pub mod plot;
pub mod program;
pub mod readings;
mod rows;
pub mod run;
pub mod scenario;
#[cfg(feature = "viz")]
pub mod scene;
pub mod table;

pub use analysis::{RtestEvaluation, TestEvaluation, evaluate};
pub use instrument::{Calibration, Nest, Probe, Tip};
pub use program::KTest;
pub use run::RtestRunError;
pub use scenario::{Mode, RTest, Zero};
pub use table::{RtestRow, RtestTable};
