//! Discovery on positioning tables (laser interferometer, ISO 230-2 layout).
//!
//! **Base model** of a reading at position `x` (m, from the axis zero), direction `s` (±1),
//! time `t` and measured temperature `T`:
//!
//! `e = P(x) + α₀·x·(T − T_ref)`
//!
//! - `P` is the reference error profile: piecewise linear through knots at the targets of the
//!   reference run (the coldest run when the file has temperatures, else the first), its knot
//!   values fitted to every training reading at once, so it is the axis's error at the
//!   reference run's temperature (a flat extension beyond the end knots);
//! - `α₀` is the nominal expansion coefficient of the axis (11.7 µm/(m·°C), a steel screw, unless
//!   told otherwise), `T_ref` the reference run's mean temperature. The term is absent when the
//!   file has no temperature.
//!
//! The nominal coefficient is not fitted: a fitted coefficient *is* the `thermal_scale` effect,
//! which would otherwise be undiscoverable. Effects add terms to this model (see
//! [`PositioningEffect`]); the engine in [`crate::discovery::engine`] selects them by held-out RMS.
//!
//! Temperatures and times are inputs: the lagged temperature of `thermal_lag` is computed from
//! the whole file's temperature record (readings held out of a fold keep their temperatures,
//! never their deviations). Between readings the temperature is taken to change linearly.

// The files, in reading order: `effects` (the effect library), `problem` (the table prepared
// for discovery), `fit` (the model's terms and the linear fit), `profile` (a fit's sum of
// squares as a function of one searched value), `search` (the searched parameters: time
// constants and period), `periodogram` (the period search's first step), `diagnostics` (what a
// fit leaves and the rules that propose effects from it), `report` (text and JSON) and
// `fragment` (the model as a scenario).
mod diagnostics;
mod effects;
mod fit;
mod fragment;
mod hat_span;
mod memo;
mod periodogram;
mod problem;
mod profile;
mod report;
mod search;

pub use diagnostics::{Association, Diagnostics, TargetResidual};
pub use effects::PositioningEffect;
pub use fit::PositioningFit;
pub use problem::{Extrapolation, PositioningProblem};

use crate::discovery::engine::{self, Folds, Problem, Selection};
use crate::kinds::positioning::table::PositioningTable;
use crate::math::{M_PER_MM, Real};

/// Knots and repeated targets are the same position when closer than this (m).
const SAME_POSITION: Real = 1e-6;
/// Below this temperature range (°C) the file cannot show a temperature effect.
const MIN_TEMPERATURE_RANGE: Real = 0.1;
/// Proposal rules fire when the residual's association has |t| at least this.
const PROPOSAL_T: Real = 2.0;
/// The most runs held out one at a time. A file with more (an ISO 230-3 record reads a run
/// every few minutes for hours) is held out in this many blocks of consecutive runs, in the
/// file's run order: a run's neighbours in time are nearly the same run, so holding out one
/// run tests interpolation rather than prediction, and every fold costs a fit of every model.
const MAX_RUN_FOLDS: usize = 20;
/// The most frequencies a period search may test.
const MAX_FREQUENCIES: Real = 1e5;
/// Grid points of a time-constant search (log-spaced), before golden-section refinement.
const TAU_GRID: usize = 24;

/// Settings of positioning discovery.
#[derive(Clone, Debug, PartialEq)]
pub struct PositioningOptions {
    /// Nominal expansion coefficient of the axis (1/K) used by the base model.
    pub expansion: Real,
    /// The temperature column to use (`<sensor>` of `temp_<sensor>_degc`); the first if none.
    pub sensor: Option<String>,
    /// Shortest period the cyclic-error search considers (m).
    pub min_period: Real,
    /// Folds of the contiguous split used when the file has fewer than three runs.
    pub folds: usize,
}

impl Default for PositioningOptions {
    fn default() -> PositioningOptions {
        PositioningOptions {
            expansion: 11.7e-6,
            sensor: None,
            min_period: 2.0 * M_PER_MM,
            folds: 5,
        }
    }
}

/// Why a positioning table cannot be searched.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct DiscoveryError(String);

impl Problem for PositioningProblem {
    type Effect = PositioningEffect;
    type Fit = PositioningFit;

    fn id(&self, effect: PositioningEffect) -> String {
        effect.id().into()
    }

    fn n_samples(&self) -> usize {
        self.x.len()
    }

    fn folds(&self) -> &Folds {
        &self.folds
    }

    fn fit(&self, effects: &[PositioningEffect], train: &[bool]) -> PositioningFit {
        self.fit_with(effects, train)
    }

    fn residuals(&self, fit: &PositioningFit) -> Vec<Real> {
        fit.residuals.clone()
    }

    /// `thermal_lag` and `sensor_lag` exclude each other: the structure's temperature either
    /// lags the sensor's or leads it. Both at once are a lead-lag filter of the reading, which
    /// gains held-out by smoothing the sensor's noise and quantisation (on noise-only tables
    /// the pair, both τ at about a minute, was the one false acceptance the new effect
    /// brought), not a cause on the machine.
    fn compatible(&self, a: PositioningEffect, b: PositioningEffect) -> bool {
        !PositioningEffect::lags(a, b)
    }

    /// Every coefficient (the profile's values at the knots, each effect's) and searched
    /// value: a time constant chosen among `TAU_GRID` (24) grid points, a period among the
    /// periodogram's frequencies.
    fn parameters(&self, fit: &PositioningFit) -> Option<engine::Parameters> {
        let searched: Vec<PositioningEffect> = fit
            .effects
            .iter()
            .copied()
            .filter(|e| e.searched())
            .collect();
        let grid = searched
            .iter()
            .map(|&e| match e {
                PositioningEffect::Periodic => self.frequency_count() as Real,
                _ => TAU_GRID as Real,
            })
            .product();
        Some(engine::Parameters {
            count: fit.coefficients.len() + searched.len(),
            grid,
        })
    }

    fn proposals(
        &self,
        effects: &[PositioningEffect],
        fit: &PositioningFit,
    ) -> Vec<(PositioningEffect, String)> {
        // Every testable effect is scored (issue 15: no silent screening); the diagnostics
        // only order them and say what points to each.
        let d = self.diagnose(fit);
        let (mut pointed, unpointed): (Vec<_>, Vec<_>) = self
            .testable
            .iter()
            .copied()
            .filter(|e| !effects.contains(e))
            .map(|e| (e, d.evidence(e)))
            .partition(|(_, evidence)| evidence.is_some());
        pointed.extend(unpointed);
        pointed
            .into_iter()
            .map(|(e, evidence)| (e, evidence.unwrap_or_else(|| engine::NO_DIAGNOSTIC.into())))
            .collect()
    }
}

/// The result of positioning discovery.
#[derive(Debug)]
pub struct PositioningDiscovery {
    problem: PositioningProblem,
    selection: Selection<PositioningEffect, PositioningFit>,
}

/// Runs discovery on a positioning table by the engine's stepwise search
/// ([`engine::stepwise_selection`]: forward steps, blocks of up to three effects when no single
/// one passes, removal of an effect that no longer helps, exchanges, and the alternatives that
/// come close); `progress` hears which model is being tested.
pub fn discover_positioning(
    table: &PositioningTable,
    options: PositioningOptions,
    progress: impl FnMut(&str),
) -> Result<PositioningDiscovery, DiscoveryError> {
    let problem = PositioningProblem::new(table, options)?;
    let selection = engine::stepwise_selection(&problem, engine::Search::FULL, progress);
    Ok(PositioningDiscovery { problem, selection })
}
