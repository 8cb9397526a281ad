//! Discovery on ball-bar tables (ISO 230-4 circular tests).
//!
//! **Base model**, in the columns and conventions of [`crate::kinds::ballbar::iso230_4`] (p, q the
//! plane's first and second axes, θ from +p toward +q, σ = +1 ccw, −1 cw):
//!
//! `d = c₀ + c_p·cos θ + c_q·sin θ + (R·s/2)·sin 2θ + (R·Δk/2)·cos 2θ`
//!
//! — the radius deviation, the centre offset (common to both senses), squareness and scale
//! mismatch: what a circle shows of a sound machine's geometry. Effects ([`BallbarEffect`])
//! add the other diagnostics' terms (servo mismatch, backlash, lateral play, reversal spikes
//! with their decay searched, straightness, cyclic errors with their period searched) and
//! three that no diagnostic covers: `lobes` (sin kθ, cos kθ, k ≥ 3 searched), `radius_drift`
//! (the radius changing linearly with time) and `sense_radius` (a ccw − cw radius difference).
//! Backlash, lateral play and spikes act where their axis actually reverses, its searched
//! reversal lag after the programmed reversal (reported as `reversal_lag_ms` when the model's
//! backlash or spike of the axis places it inside the searched range; lateral play alone,
//! continuous at the reversal, cannot, and the report's `notes` say so).
//!
//! **Held-out data.** The covered arc is cut into 8 contiguous angular sectors and a fold
//! holds out one sector in both senses: neighbouring samples of a trace are correlated, so
//! held-out samples interleaved with training ones would make any wiggle look predictive.
//!
//! **Every effect the table can test is scored every round** (the others are listed with the
//! reason). The residual of the current model only orders the candidates and gives the
//! evidence that points to each: a one-column effect when the residual's regression on its
//! column has |t| ≥ 2; a spike when |t| ≥ 2 at the best decay of a log grid; a cyclic error or
//! lobes when the best periodogram F statistic (2 and n − 2 degrees of freedom) reaches
//! ln(M/0.05) for the M periods or lobe counts tested, the level the largest of M noise-only
//! values exceeds at most 5 % of the time (Bonferroni). Effects no rule points to come after,
//! scored all the same.
//!
//! **Speed.** A candidate's score is nine fits (all readings, then each sector held out),
//! each with its searched lags, decays, periods and lobe count. The readings are cut into the
//! sectors once ([`Blocks`](crate::kinds::ballbar::iso230_4::Blocks)): what depends on the
//! data alone (the static columns' cross products, the cyclic and lobe columns' moments and
//! transforms) is summed per sector, and a fold's fit adds up the sectors it keeps instead of
//! going over its readings again (see
//! [`CircleData::fit_blocks`](crate::kinds::ballbar::iso230_4::CircleData::fit_blocks));
//! every search keeps its own trials on its own training data.

// The files, in reading order: `effects` (the effect library), `problem` (the table prepared
// for discovery and the evidence for each effect) and `report` (the result, as text and JSON).
mod effects;
mod problem;
mod report;

pub use effects::BallbarEffect;
pub use problem::{BallbarDiscoveryError, BallbarProblem};
pub use report::BallbarDiscovery;

use problem::SEARCH;

use crate::discovery::engine;
use crate::kinds::ballbar::iso230_4::CircularTest;
use crate::kinds::ballbar::table::BallbarTable;

/// Runs discovery on a ball-bar table; `progress` hears which candidate is being tested.
pub fn discover_ballbar(
    table: &BallbarTable,
    test: &CircularTest,
    progress: impl FnMut(&str),
) -> Result<BallbarDiscovery, BallbarDiscoveryError> {
    let problem = BallbarProblem::new(table, test)?;
    let selection = engine::stepwise_selection(&problem, SEARCH, progress);
    Ok(BallbarDiscovery { problem, selection })
}
