//! What a test kind supplies to the estimators: readings, their uncertainties and their model.

use crate::errors::ErrorModel;
use crate::machine::{Machine, Workspace};
use crate::math::Real;

/// A quantity of the set-up: estimated alongside the errors (a nuisance, e.g. where a sphere
/// stands on the table) or taken as known with a standard uncertainty (for the Monte Carlo).
#[derive(Clone, Debug, PartialEq)]
pub struct Quantity {
    /// Its name in reports, e.g. `sphere1.x` (the unit follows from `translation`).
    pub name: String,
    /// A translation (µm in files) rather than a rotation (µrad).
    pub translation: bool,
    /// Start value (nuisances) in SI.
    pub start: Real,
    /// Standard uncertainty in SI (known set-up quantities; 0 for nuisances).
    pub uncertainty: Real,
}

/// The model of a set of readings: the twin's own chain, as the instrument reads it.
pub trait ReadingModel: Send + Sync {
    /// Predicts every reading (SI) for `machine` with the errors `errors`, the set-up unknowns
    /// `nuisance` (SI, one per [`Readings::nuisance`]) and the offsets `setup` of the known
    /// set-up quantities from their stated values (SI, one per [`Readings::setup`]; zero = as
    /// stated). `out` has one value per reading.
    fn predict(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        errors: &ErrorModel,
        nuisance: &[Real],
        setup: &[Real],
        out: &mut [Real],
    );

    /// The readings' first-order sensitivities at zero error and at the nuisances' starts (SI
    /// per SI): to every coefficient of `errors` (`readings × coefficients`, the error
    /// model's own coefficients, [`ErrorModel::jacobian`]) and to each of the `nuisances`
    /// set-up unknowns (`readings × nuisances`). The estimators' design at the start is then
    /// one pass of the chain per reading instead of one prediction of every reading per
    /// unknown. `None` (the default): they take forward differences of
    /// [`ReadingModel::predict`].
    fn sensitivities(
        &self,
        _machine: &Machine,
        _workspace: &mut Workspace,
        _errors: &ErrorModel,
        _nuisances: usize,
    ) -> Option<(nalgebra::DMatrix<Real>, nalgebra::DMatrix<Real>)> {
        None
    }

    /// How many consecutive readings one row of the table gives (a sphere centre's or an
    /// R-test pose's x, y, z: 3), for naming and leaving out a whole row; 1 by default.
    fn per_row(&self) -> usize {
        1
    }

    /// The group of reading `i` whose readings a held-out check leaves out together (an
    /// R-test's K-test, a probed sphere at one tilt; [`crate::estimate::discover`]): its own set-up
    /// unknowns and the correlations between its readings stay inside it. 0 by default (the
    /// whole set one group).
    fn group(&self, _i: usize) -> usize {
        0
    }

    /// What reading `i` (from 0, in the set's order) is, for people: `reading 7` by default.
    fn reading_name(&self, i: usize) -> String {
        format!("reading {} in file order", i + 1)
    }
}

/// One set of readings from one table (or one planned test): what was measured, how well,
/// and the model of each reading.
pub struct Readings {
    /// Where it comes from, for reports: `rtest.csv: CK1 A0`.
    pub source: String,
    /// The test kind (`rtest`, `spheres`, `positioning`, `ballbar`).
    pub kind: &'static str,
    /// The machine the table says it was measured on, if it says.
    pub machine: Option<String>,
    /// The measured values (SI); empty for a planned test.
    pub measured: Vec<Real>,
    /// The standard uncertainty of each reading (SI).
    pub sigma: Vec<Real>,
    /// Set-up unknowns estimated with the errors.
    pub nuisance: Vec<Quantity>,
    /// Set-up quantities taken as known, with their uncertainties.
    pub setup: Vec<Quantity>,
    /// The model.
    pub model: Box<dyn ReadingModel>,
}

impl Readings {
    /// The number of readings.
    pub fn len(&self) -> usize {
        self.sigma.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.sigma.is_empty()
    }

    /// The mean of the readings' standard uncertainties (m; 0 for none).
    pub fn mean_sigma(&self) -> Real {
        self.sigma.iter().sum::<Real>() / self.sigma.len().max(1) as Real
    }
}

impl std::fmt::Debug for Readings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Readings")
            .field("source", &self.source)
            .field("kind", &self.kind)
            .field("readings", &self.len())
            .finish()
    }
}

/// Why a table cannot be turned into readings: the file and what it lacks or gets wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {message}")]
pub struct ReadingsError {
    /// The table file.
    pub file: String,
    /// What is wrong, for people.
    pub message: String,
}

impl ReadingsError {
    /// An error about `file`.
    pub fn new(file: &str, message: impl Into<String>) -> ReadingsError {
        ReadingsError {
            file: file.to_string(),
            message: message.into(),
        }
    }
}
