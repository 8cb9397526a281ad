//! Files: scenarios in; measurement tables, truth and manifests out.
//!
//! The measurement-table modules (`positioning`, `drift`, `ballbar`) depend only on [`crate::math`] and
//! [`crate::machine`], so instruments, analyses and discovery all use them; `run` sits on top
//! of everything.

mod ballbar;
mod drift;
mod positioning;
mod run;
mod scenario;
mod table;

pub use ballbar::{BallbarReading, BallbarTable, Sense};
pub use drift::{DriftChannel, DriftTable};
pub use positioning::{Approach, PositioningReading, PositioningTable};
pub use run::{LaserRun, RunError, RunOutput, Simulation, run_scenario, simulate, write_outputs};
pub use scenario::{
    BallbarTest, ErrorSpec, HarmonicSpec, InterpolationSpec, LaserTest, Lesson, SCHEMA_VERSION,
    Scenario, ScenarioError, ScenarioErrorKind, TableSpec, ThermalSetup, VolumetricSpec,
};
pub use table::TableError;
