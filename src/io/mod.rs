//! Files: scenarios in; measurement tables, truth and manifests out.

mod run;
mod scenario;

pub use run::{RunError, RunOutput, run_scenario, write_outputs};
pub use scenario::{
    ErrorSpec, HarmonicSpec, InterpolationSpec, SCHEMA_VERSION, Scenario, ScenarioError,
    ScenarioErrorKind, TableSpec, VolumetricSpec,
};
