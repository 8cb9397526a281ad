//! The touch probe on artefacts: the `[probe]` section, the probing cycles (a calibration
//! sphere at several rotary positions as KinematicsOpt's cycle 451 probes it, a ring gauge, a
//! ball plate, points on a mesh workpiece), the virtual kinematic touch-trigger probe, the
//! `probe` and `spheres` tables, the sphere and circle fits and their evaluation.
//!
//! | file | owns |
//! |---|---|
//! | [`scenario`] | `[probe]` → [`ProbeTest`], every value and every move checked |
//! | [`cycles`] | [`Cycle`], [`Feature`], [`ProbeMove`]: the artefacts and the moves planned on the nominal chain |
//! | [`instrument`] | the virtual [`TouchProbe`]: stylus radius and its error, lobed pre-travel, latency, repeatability; the touch on the twin |
//! | [`table`] | the [`ProbeTable`] (every touch) and the [`SpheresTable`] (a fit per sphere) |
//! | [`fit`] | Kåsa and geometric sphere and circle fits |
//! | [`results`] | [`SphereResult`](results::SphereResult), [`RingResult`](results::RingResult), [`PlateResult`](results::PlateResult), [`SurfacePoint`](results::SurfacePoint): what the evaluation finds per feature |
//! | [`analysis`] | [`ProbeEvaluation`]: sphere form and radius error, P_FTU, ring diameter and roundness, plate centre distances |
//! | [`run`] | the simulation: tables and truth |
//! | [`cli`] | `mtwin analyze probe` |
//! | `scene` | the teaching scene (feature `viz`) |

pub mod analysis;
pub mod cli;
pub mod cycles;
pub mod fit;
pub mod instrument;
pub mod plausible;
pub mod readings;
pub mod results;
pub mod run;
pub mod scenario;
#[cfg(feature = "viz")]
pub mod scene;
pub mod table;

pub use analysis::{ProbeEvaluation, evaluate};
pub use cycles::{Cycle, CycleKind, Feature, LinearFrame, ProbeMove, Target};
pub use instrument::{Latched, TouchError, TouchProbe};
pub use run::{ProbeRun, simulate, summary, truth};
pub use scenario::{ProbeTest, RawProbe, probe_test};
pub use table::{ProbeConditions, ProbeTable, ProbeTouch, RowKey, SphereRow, SpheresTable};
