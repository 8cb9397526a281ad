//! The application layer, above every test kind: a whole [`Scenario`] assembled from the
//! shared sections and the kinds' own, running it ([`simulate`]: programme → twin →
//! instruments → tables and truth) and the files of a run ([`RunOutput`]); datasets of many
//! such runs drawn from priors ([`dataset`]); with the `viz` feature, the teaching recording of
//! a run (`record`).
//!
//! ```
//! use mtwin::app::{Scenario, run_scenario};
//! let scenario = Scenario::load("scenarios/vmc3_iso230_2.toml").unwrap();
//! let output = run_scenario(&scenario).unwrap();
//! let names: Vec<&str> = output.files.iter().map(|(name, _)| name.as_str()).collect();
//! assert_eq!(names, ["positioning.csv", "truth.json", "manifest.json"]);
//! ```

pub mod dataset;
pub mod folder;
pub mod identify;
#[cfg(feature = "viz")]
pub mod record;
mod run;
mod scenario;
pub mod score;

pub use run::{
    RunError, RunOutput, Simulation, check_run_folder, run_scenario, simulate, write_outputs,
};
pub use scenario::{Scenario, ScenarioFiles};
