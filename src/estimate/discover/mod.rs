//! Model selection on a kinematic calibration (`identify --discover`): what the calibration
//! model is missing, found by held-out evidence on the shared discovery engine
//! ([`crate::discovery::engine`]).
//!
//! **The base** is the model of `--params` (typically the location errors of the rotary
//! axes). **The library** ([`library`]) holds what calibration engineers add when a base
//! model does not fit: each rotary axis's component errors order by order (ISO 230-1's EXC …
//! ECC as Fourier orders 1 to 3, order 1 of the radial and tilt pairs as the part turning
//! against the axis), the lost motion of every axis, the squareness errors, and the R-test
//! pivot drifting in time. **Held-out evidence**: each group of readings — an R-test's
//! K-test, a probed sphere at one tilt — is left out in turn, the model fitted to the others
//! predicts it (its own set-up, the test's zero, taken from itself as for any model; a sphere's
//! centre from its other tilts), and a term enters only when the held-out predictions improve by more than noise
//! can explain, by the engine's rule ([`crate::discovery::engine::RULE`]: a 5 % lower
//! held-out RMS, a weighted Stouffer z over the folds at the Bonferroni level of the round,
//! and again without the fold that gains most), with its stepwise search (the lean one:
//! pairs when no single term passes, removals, one-for-one exchanges). On tables without the
//! effects the probability that a round accepts anything is at most 2.5 %.
//!
//! **The fits** are linear: the readings are linearised once at the start on the exact chain
//! (they are linear in the errors to about 1e-5 at these sizes), every group's own set-up is
//! projected out of its rows, and each fit is a weighted least squares on the columns of
//! the base and the terms, over the directions the identifiability analysis keeps (the
//! minimum-norm solution, as [`crate::estimate::fit`] gives). A term whose columns add no
//! identified direction to the model (its shapes are already in it, or these tables cannot
//! see them) is not scored, and the report lists it as not testable here.
//!
//! **The result** is the extended `--params` (the base and every accepted term, a drift as
//! `--drift=rate`), which `identify` then estimates as usual: the nonlinear fit, the
//! uncertainties, the compensation files.
//!
//! Simplifications, stated: the drift term is one rate through each R-test table (a machine
//! warming steadily through a session), since a drift of each test's own cannot be checked on
//! the test held out; R-test sensor gain errors are not in the library (the table's readings
//! are taken as exact displacements, [`crate::kinds::rtest::readings`]); the Fourier orders
//! stop at 3.

pub mod library;
mod problem;
mod report;

pub use library::Term;
pub use problem::{Calibration, Fit};

use crate::discovery::engine::{self, Search, Selection};
use crate::estimate::Readings;
use crate::estimate::fit::EstimateError;
use crate::estimate::spec::{ParameterSet, SpecError};
use crate::machine::Machine;

/// The search: forward additions (a pair when no single term passes), removals and
/// one-for-one exchanges ([`Search::LEAN`]).
pub const SEARCH: Search = Search::LEAN;

/// Why model selection cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DiscoverError {
    /// The base parameters.
    #[error(transparent)]
    Spec(#[from] SpecError),
    /// The readings.
    #[error(transparent)]
    Estimate(#[from] EstimateError),
    /// Nothing to hold out.
    #[error(
        "model selection needs at least two groups of readings to hold out in turn (K-tests of an R-test, a probed sphere's tilts); the tables give {0}"
    )]
    TooFewGroups(usize),
}

/// What model selection found.
pub struct Discovery {
    /// The base `--params`.
    pub base: String,
    /// The problem it ran on.
    pub problem: Calibration,
    /// The search's result.
    pub selection: Selection<Term, Fit>,
    /// The library's terms the tables cannot test with the base model (their shapes are in
    /// it, or unseen).
    pub untestable: Vec<Term>,
}

impl Discovery {
    /// The accepted terms, in the order they entered.
    pub fn accepted(&self) -> Vec<Term> {
        self.selection.effects()
    }

    /// The extended `--params`: the base and every accepted term's items.
    pub fn params(&self) -> String {
        let mut items = vec![self.base.clone()];
        for term in self.accepted() {
            items.extend(term.spec_items());
        }
        items.join(",")
    }

    /// Whether the pivot's drift rate was accepted (`--drift=rate`).
    pub fn drift(&self) -> bool {
        self.accepted().contains(&Term::Drift)
    }
}

/// Runs model selection on `sets` for `machine` from the base `params`; with `offer_drift`
/// the library holds the pivot's drift rate (R-test tables read with
/// [`crate::kinds::rtest::readings::Drift::Rate`] give its columns; without `offer_drift`
/// their drift is the base's). `progress` hears each model scored.
pub fn discover(
    machine: &Machine,
    params: &str,
    sets: &[Readings],
    offer_drift: bool,
    progress: impl FnMut(&str),
) -> Result<Discovery, DiscoverError> {
    let base = ParameterSet::parse(params, machine)?;
    let drift = offer_drift
        && sets.iter().any(|s| {
            s.nuisance
                .iter()
                .any(|q| q.name.starts_with(library::DRIFT_NUISANCE))
        });
    let terms = library::library(machine, &base, drift);
    let mut items = vec![params.to_string()];
    items.extend(terms.iter().flat_map(|t| t.spec_items()));
    let full = ParameterSet::parse(&items.join(","), machine)?;
    let problem = Calibration::new(machine, &base, &full, &terms, sets)?;
    if problem.groups() < 2 {
        return Err(DiscoverError::TooFewGroups(problem.groups()));
    }
    let untestable: Vec<Term> = terms
        .iter()
        .copied()
        .filter(|t| !problem.acts(&[], *t))
        .collect();
    let selection = engine::stepwise_selection(&problem, SEARCH, progress);
    Ok(Discovery {
        base: params.to_string(),
        problem,
        selection,
        untestable,
    })
}
