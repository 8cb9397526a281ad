//! The twin: a machine and its injected errors, evaluated by the exact chain or by a
//! deliberately simpler model.

mod thermal_run;

pub use thermal_run::{ThermalRecord, run_thermal};

use crate::errors::{Deviation, ErrorModel, Lu2012Error, lu2012_deviation};
use crate::machine::{Machine, MachineState, Workspace};
use crate::math::Pose;
use crate::program::Visit;

/// How the twin turns error parameters into a tool-in-workpiece deviation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EvaluationModel {
    /// The exact non-linear chain: every error at its slot (the truth).
    #[default]
    Chain,
    /// The summed first-order 21-component model of Lu (2012), 3-axis machines only; no tool
    /// tilt (see [`crate::errors::lu2012_deviation`]).
    Lu2012,
}

impl EvaluationModel {
    /// The name used in scenario files.
    pub fn name(self) -> &'static str {
        match self {
            EvaluationModel::Chain => "chain",
            EvaluationModel::Lu2012 => "lu2012",
        }
    }
}

/// A machine with its injected errors.
#[derive(Clone, Debug)]
pub struct Twin {
    /// The machine.
    pub machine: Machine,
    /// Its errors, bound to it.
    pub errors: ErrorModel,
}

impl Twin {
    /// The actual tool pose seen from the workpiece at each visit (geometric errors only).
    pub fn poses(&self, visits: &[Visit]) -> Vec<Pose> {
        let mut workspace = Workspace::new(&self.machine);
        visits
            .iter()
            .map(|v| {
                self.errors
                    .workpiece_from_tool(&self.machine, &mut workspace, &v.state)
            })
            .collect()
    }

    /// The deviation (actual − nominal, workpiece frame) at `state` by `model`.
    pub fn deviation(
        &self,
        workspace: &mut Workspace,
        state: &MachineState,
        model: EvaluationModel,
    ) -> Result<Deviation, Lu2012Error> {
        match model {
            EvaluationModel::Chain => Ok(self.errors.deviation(&self.machine, workspace, state)),
            EvaluationModel::Lu2012 => Ok(Deviation {
                translation: lu2012_deviation(&self.errors, &self.machine, state)?,
                tilt: [0.0, 0.0],
            }),
        }
    }
}
