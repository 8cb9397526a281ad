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
//! reversal lag after the programmed reversal (reported as `reversal_lag_ms`).
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
//! sectors once ([`Blocks`]): what depends on the data alone (the static columns' cross
//! products, the cyclic and lobe columns' moments and transforms) is summed per sector, and a
//! fold's fit adds up the sectors it keeps instead of going over its readings again (see
//! [`CircleData::fit_blocks`]); every search keeps its own trials on its own training data.

use crate::discovery::engine::{
    self, Folds, Problem, ResidualStep, Score, Selection, params_json, round_json as round,
};
use crate::discovery::least_squares::{T_UNDEFINED, regression};
use crate::kinds::ballbar::iso230_4::{
    BallbarError, Blocks, CircleData, CircularTest, MIN_DIAGNOSTIC_READINGS, ModelFit, Shape, Term,
    covered_arc, diagnostic_column,
};
use crate::kinds::ballbar::table::BallbarTable;
use crate::machine::{Axis, Plane};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, fixed};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::f64::consts::TAU;

/// The base model's terms.
const BASE: [Term; 5] = [
    Term::Radius,
    Term::CentreP,
    Term::CentreQ,
    Term::Squareness,
    Term::ScaleMismatch,
];
/// Angular sectors of the cross-validation.
const SECTORS: usize = 8;
/// One-column proposals need |t| at least this.
const PROPOSAL_T: Real = 2.0;
/// False-alarm probability of a periodogram proposal over its whole search.
const PROPOSAL_FALSE_ALARM: Real = 0.05;
/// Decays (log-spaced over the searched range) at which a spike is looked for.
const SPIKE_PROBES: usize = 8;

/// Why a ball-bar table cannot be searched.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BallbarDiscoveryError {
    /// The table or the test conditions are not a valid circular test.
    #[error(transparent)]
    Table(#[from] BallbarError),
    /// Too few readings for a fit in every fold.
    #[error(
        "{0} readings: ball-bar discovery needs at least {MIN_DIAGNOSTIC_READINGS} (a model of up to 20 terms in each of 8 folds)"
    )]
    TooFewReadings(usize),
}

/// The effects ball-bar discovery can add to the base model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum BallbarEffect {
    /// Different lags of p and q: σ·(v·Δτ/2)·sin 2θ.
    ServoMismatch,
    /// Lost motion of p: +σ·sgn(sin θ)·cos θ·b_p/2.
    BacklashP,
    /// Lost motion of q: −σ·sgn(cos θ)·sin θ·b_q/2.
    BacklashQ,
    /// The p carriage shifting along q on reversal: +σ·|sin θ|·l_p/2.
    LateralPlayP,
    /// The q carriage shifting along p on reversal: −σ·|cos θ|·l_q/2.
    LateralPlayQ,
    /// A decaying bump after each reversal of p; decay searched.
    ReversalSpikeP,
    /// A decaying bump after each reversal of q; decay searched.
    ReversalSpikeQ,
    /// A bow of p along q: S_p·sin³θ.
    StraightnessP,
    /// A bow of q along p: S_q·cos³θ.
    StraightnessQ,
    /// A periodic error of p along p; period searched.
    CyclicP,
    /// A periodic error of q along q; period searched.
    CyclicQ,
    /// k lobes per turn at fixed angles: a·sin kθ + b·cos kθ, k ≥ 3 searched.
    Lobes,
    /// The radius changing linearly with time (rate).
    RadiusDrift,
    /// The ccw trace's radius minus the cw trace's: σ·Δ/2.
    SenseRadius,
}

/// Effect names that carry an axis letter: stem, then the name for X, Y and Z.
const LETTERED: [[&str; 3]; 5] = [
    ["backlash_x", "backlash_y", "backlash_z"],
    ["lateral_play_x", "lateral_play_y", "lateral_play_z"],
    ["reversal_spike_x", "reversal_spike_y", "reversal_spike_z"],
    ["straightness_x", "straightness_y", "straightness_z"],
    ["cyclic_x", "cyclic_y", "cyclic_z"],
];

impl BallbarEffect {
    /// Every effect, in the order they are reported.
    pub const ALL: [BallbarEffect; 14] = [
        BallbarEffect::ServoMismatch,
        BallbarEffect::BacklashP,
        BallbarEffect::BacklashQ,
        BallbarEffect::LateralPlayP,
        BallbarEffect::LateralPlayQ,
        BallbarEffect::ReversalSpikeP,
        BallbarEffect::ReversalSpikeQ,
        BallbarEffect::StraightnessP,
        BallbarEffect::StraightnessQ,
        BallbarEffect::CyclicP,
        BallbarEffect::CyclicQ,
        BallbarEffect::Lobes,
        BallbarEffect::RadiusDrift,
        BallbarEffect::SenseRadius,
    ];

    /// The model term it adds.
    pub fn term(self) -> Term {
        match self {
            BallbarEffect::ServoMismatch => Term::ServoMismatch,
            BallbarEffect::BacklashP => Term::BacklashP,
            BallbarEffect::BacklashQ => Term::BacklashQ,
            BallbarEffect::LateralPlayP => Term::LateralPlayP,
            BallbarEffect::LateralPlayQ => Term::LateralPlayQ,
            BallbarEffect::ReversalSpikeP => Term::ReversalSpikeP,
            BallbarEffect::ReversalSpikeQ => Term::ReversalSpikeQ,
            BallbarEffect::StraightnessP => Term::StraightnessP,
            BallbarEffect::StraightnessQ => Term::StraightnessQ,
            BallbarEffect::CyclicP => Term::CyclicP,
            BallbarEffect::CyclicQ => Term::CyclicQ,
            BallbarEffect::Lobes => Term::Lobes,
            BallbarEffect::RadiusDrift => Term::RadiusDrift,
            BallbarEffect::SenseRadius => Term::SenseRadius,
        }
    }

    /// The axis it belongs to in `plane`, if it belongs to one.
    pub fn axis(self, plane: Plane) -> Option<Axis> {
        match self {
            BallbarEffect::BacklashP
            | BallbarEffect::LateralPlayP
            | BallbarEffect::ReversalSpikeP
            | BallbarEffect::StraightnessP
            | BallbarEffect::CyclicP => Some(plane.first()),
            BallbarEffect::BacklashQ
            | BallbarEffect::LateralPlayQ
            | BallbarEffect::ReversalSpikeQ
            | BallbarEffect::StraightnessQ
            | BallbarEffect::CyclicQ => Some(plane.second()),
            _ => None,
        }
    }

    /// The stable identifier in `plane`, with the axis letter where the effect has an axis
    /// (`backlash_y`, `servo_mismatch`).
    pub fn id(self, plane: Plane) -> &'static str {
        let stem = match self {
            BallbarEffect::BacklashP | BallbarEffect::BacklashQ => 0,
            BallbarEffect::LateralPlayP | BallbarEffect::LateralPlayQ => 1,
            BallbarEffect::ReversalSpikeP | BallbarEffect::ReversalSpikeQ => 2,
            BallbarEffect::StraightnessP | BallbarEffect::StraightnessQ => 3,
            BallbarEffect::CyclicP | BallbarEffect::CyclicQ => 4,
            BallbarEffect::ServoMismatch => return "servo_mismatch",
            BallbarEffect::Lobes => return "lobes",
            BallbarEffect::RadiusDrift => return "radius_drift",
            BallbarEffect::SenseRadius => return "sense_radius",
        };
        let axis = match self.axis(plane) {
            Some(Axis::X) => 0,
            Some(Axis::Y) => 1,
            _ => 2,
        };
        LETTERED[stem][axis]
    }

    /// The physical cause and what to check, as a service engineer would name them.
    pub fn cause(self) -> &'static str {
        match self {
            BallbarEffect::ServoMismatch => {
                "the two axes follow their commands with different lags: position-loop gains (Kv) or feed-forward set differently; match the servo tuning of the two axes"
            }
            BallbarEffect::BacklashP | BallbarEffect::BacklashQ => {
                "lost motion when the axis reverses: worn ball-screw nut or thrust-bearing float, a loose coupling; check the pre-load and the backlash compensation"
            }
            BallbarEffect::LateralPlayP | BallbarEffect::LateralPlayQ => {
                "the carriage shifts sideways when the axis reverses: play in the guideways (worn gibs or strips, linear bearings without pre-load); check and adjust the guideways"
            }
            BallbarEffect::ReversalSpikeP | BallbarEffect::ReversalSpikeQ => {
                "the axis sticks when it reverses and catches up late: friction (stick-slip) in the guideways or the screw, or a friction/backlash compensation pulse that is too small, too late or too short; check lubrication and the reversal compensation"
            }
            BallbarEffect::StraightnessP | BallbarEffect::StraightnessQ => {
                "the axis does not travel straight: a bowed guideway (wear, a twisted bed, foundation or levelling); check the levelling, then the guideway"
            }
            BallbarEffect::CyclicP | BallbarEffect::CyclicQ => {
                "a periodic error of the axis with the period of its drive or scale: ball-screw lead error per turn, a bent or eccentric screw, encoder or scale interpolation error"
            }
            BallbarEffect::Lobes => {
                "a trace with k lobes per turn at the same angles in both senses: the control interpolating the circle by segments, a disturbance locked to the path (motor cogging), or a lobed or loose ball or magnetic cup of the set-up"
            }
            BallbarEffect::RadiusDrift => {
                "the radius changes steadily during the test: thermal growth of the machine (spindle, structure) or of the bar while the circles run; let the machine and the bar settle, check the bar's temperature compensation"
            }
            BallbarEffect::SenseRadius => {
                "the circle is larger in one sense than in the other: a contouring error that depends on the sense of rotation (friction or acceleration feed-forward set differently for G02 and G03), or the cups' friction pulling the bar"
            }
        }
    }
}

/// A ball-bar table prepared for discovery.
#[derive(Clone, Debug)]
pub struct BallbarProblem {
    data: CircleData,
    folds: Folds,
    /// The readings cut into the folds' sectors, for fits that share their sums.
    blocks: Blocks,
    testable: Vec<BallbarEffect>,
    untestable: Vec<(BallbarEffect, String)>,
}

/// The terms of the base model plus `effects`.
fn terms(effects: &[BallbarEffect]) -> Vec<Term> {
    BASE.iter()
        .copied()
        .chain(effects.iter().map(|e| e.term()))
        .collect()
}

impl BallbarProblem {
    /// Prepares `table`: checks it, cuts the sectors and sorts the effects into those the
    /// table can and cannot show.
    pub fn new(
        table: &BallbarTable,
        test: &CircularTest,
    ) -> Result<BallbarProblem, BallbarDiscoveryError> {
        let data = CircleData::new(table, test)?;
        let n = data.len();
        if n < MIN_DIAGNOSTIC_READINGS {
            return Err(BallbarDiscoveryError::TooFewReadings(n));
        }
        let folds = Self::sectors(&data);
        let blocks = Blocks::new(&data, &folds.of_sample, folds.count);
        let mut problem = BallbarProblem {
            data,
            folds,
            blocks,
            testable: Vec::new(),
            untestable: Vec::new(),
        };
        for effect in BallbarEffect::ALL {
            match problem.why_untestable(effect) {
                Some(reason) => problem.untestable.push((effect, reason)),
                None => problem.testable.push(effect),
            }
        }
        Ok(problem)
    }

    /// Contiguous angular sectors over the covered arc (a full circle from 0°).
    fn sectors(data: &CircleData) -> Folds {
        let angles: Vec<Real> = data.points.iter().map(|p| p.angle).collect();
        let (start, span) = covered_arc(&angles);
        // Nearly closed (the largest gap under 10°): a full circle, cut from 0°.
        let (start, span) = if span > TAU - 10.0 * RAD_PER_DEG {
            (0.0, TAU)
        } else {
            (start, span)
        };
        let of_sample = data
            .points
            .iter()
            .map(|p| {
                let at = (p.angle - start).rem_euclid(TAU);
                ((at / span * SECTORS as Real) as usize).min(SECTORS - 1)
            })
            .collect();
        Folds::new(
            format!(
                "{SECTORS} angular sectors of {:.1}° from {:.1}° (a sector held out in both senses)",
                span / SECTORS as Real / RAD_PER_DEG,
                start / RAD_PER_DEG
            ),
            of_sample,
            SECTORS,
        )
    }

    /// Why the table cannot show `effect`, if it cannot.
    fn why_untestable(&self, effect: BallbarEffect) -> Option<String> {
        let term = effect.term();
        if let Some(reason) = self.data.structural(term) {
            return Some(reason);
        }
        if term == Term::RadiusDrift {
            let (low, high) = self
                .data
                .points
                .iter()
                .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), p| {
                    (l.min(p.time), h.max(p.time))
                });
            if high - low <= 0.0 {
                return Some("every reading has the same time".into());
            }
        }
        self.data
            .unidentifiable(&terms(&[effect]), &Shape::default())
            .into_iter()
            .find(|(t, _)| *t == term)
            .map(|(_, reason)| format!("against the base model it {reason}"))
    }

    /// The effects this table cannot show, with the reason.
    pub fn untestable(&self) -> &[(BallbarEffect, String)] {
        &self.untestable
    }

    /// The residual's evidence for `effect` after `fit`, in words, when a rule proposes it.
    pub fn evidence(&self, effect: BallbarEffect, fit: &ModelFit) -> Option<String> {
        let data = &self.data;
        let plane = data.test.plane;
        let r = &fit.residuals;
        let n = r.len();
        let term = effect.term();
        let (unit, scale) = term.unit();
        let axis = effect.axis(plane).map_or(String::new(), |a| a.to_string());
        let column = |shape: &Shape| -> Vec<Real> {
            data.points
                .iter()
                .map(|p| diagnostic_column(term, 0, p, &data.test, shape))
                .collect()
        };
        let all: Vec<usize> = (0..n).collect();
        let f_statistic =
            |fraction: Real| fraction / 2.0 / ((1.0 - fraction).max(1e-300) / (n as Real - 2.0));
        match effect {
            BallbarEffect::ReversalSpikeP | BallbarEffect::ReversalSpikeQ => {
                let which = usize::from(effect == BallbarEffect::ReversalSpikeQ);
                let (low, high) = data.ranges.decay;
                (0..SPIKE_PROBES)
                    .filter_map(|k| {
                        let tau = low * (high / low).powf(k as Real / (SPIKE_PROBES - 1) as Real);
                        let mut shape = Shape::default();
                        shape.decay[which] = tau;
                        regression(&column(&shape), r).and_then(|(h, t)| Some((tau, h, t?)))
                    })
                    .max_by(|a, b| a.2.abs().total_cmp(&b.2.abs()))
                    .filter(|(_, _, t)| t.abs() >= PROPOSAL_T)
                    .map(|(tau, h, t)| {
                        format!(
                            "a bump after {axis}'s reversals decaying in about {:.0} ms: {:.2} µm (t = {t:.1})",
                            tau * 1e3,
                            h / M_PER_UM
                        )
                    })
            }
            BallbarEffect::CyclicP | BallbarEffect::CyclicQ => {
                let (period, fraction) = self.blocks.cyclic_periodogram(data, term, r);
                let f = f_statistic(fraction);
                let level = data.significance(term).powi(2) / 2.0;
                let amplitude = (2.0 * fraction * r.iter().map(|v| v * v).sum::<Real>()
                    / data
                        .points
                        .iter()
                        .map(|p| {
                            let (s, c) = p.angle.sin_cos();
                            if term == Term::CyclicP { c * c } else { s * s }
                        })
                        .sum::<Real>())
                .sqrt();
                (f >= level).then(|| {
                    format!(
                        "periodogram along {axis}: period {:.3} mm, about {:.2} µm (F = {f:.1} ≥ {level:.1})",
                        period / M_PER_MM,
                        amplitude / M_PER_UM
                    )
                })
            }
            BallbarEffect::Lobes => {
                let (k, fraction) = data.lobes_periodogram(&all, r);
                let f = f_statistic(fraction);
                let (low, high) = data.ranges.lobes;
                let level = ((high - low + 1) as Real / PROPOSAL_FALSE_ALARM).ln();
                let amplitude =
                    (2.0 * fraction * r.iter().map(|v| v * v).sum::<Real>() / n as Real).sqrt();
                (f >= level).then(|| {
                    format!(
                        "{k} lobes per turn, about {:.2} µm (F = {f:.1} ≥ {level:.1})",
                        amplitude / M_PER_UM
                    )
                })
            }
            _ => {
                let (slope, t) = regression(&column(&Shape::default()), r)?;
                // No t (no scatter about the shape): said in words when the shape is there.
                let statistic = match t {
                    Some(t) if t.abs() >= PROPOSAL_T => format!("t = {t:.1}"),
                    None if slope != 0.0 => T_UNDEFINED.to_string(),
                    _ => return None,
                };
                let what = match effect {
                    BallbarEffect::ServoMismatch => {
                        "sin 2θ with opposite signs in the two senses".to_string()
                    }
                    BallbarEffect::BacklashP => {
                        format!(
                            "steps at {axis}'s reversals (0°, 180°), opposite in the two senses"
                        )
                    }
                    BallbarEffect::BacklashQ => {
                        format!(
                            "steps at {axis}'s reversals (90°, 270°), opposite in the two senses"
                        )
                    }
                    BallbarEffect::LateralPlayP => format!(
                        "a difference between the senses growing with {axis}'s speed (|sin θ|)"
                    ),
                    BallbarEffect::LateralPlayQ => format!(
                        "a difference between the senses growing with {axis}'s speed (|cos θ|)"
                    ),
                    BallbarEffect::StraightnessP => format!("a bow of {axis} (sin³θ)"),
                    BallbarEffect::StraightnessQ => format!("a bow of {axis} (cos³θ)"),
                    BallbarEffect::RadiusDrift => "a trend with time".to_string(),
                    _ => "a radius difference between the senses (ccw − cw)".to_string(),
                };
                let unit = unit.replace("um", "µm").replace("_per_", "/");
                Some(format!("{what}: {:.3} {unit} ({statistic})", slope * scale))
            }
        }
    }
}

impl Problem for BallbarProblem {
    type Effect = BallbarEffect;
    type Fit = ModelFit;

    fn id(&self, effect: BallbarEffect) -> &'static str {
        effect.id(self.data.test.plane)
    }

    fn n_samples(&self) -> usize {
        self.data.len()
    }

    fn folds(&self) -> &Folds {
        &self.folds
    }

    fn fit(&self, effects: &[BallbarEffect], train: &[bool]) -> ModelFit {
        match self.blocks.included(train) {
            Some(included) => self
                .data
                .fit_blocks(&self.blocks, &terms(effects), &included),
            None => self.data.fit(&terms(effects), train),
        }
    }

    fn residuals(&self, fit: &ModelFit) -> Vec<Real> {
        fit.residuals.clone()
    }

    fn proposals(&self, effects: &[BallbarEffect], fit: &ModelFit) -> Vec<(BallbarEffect, String)> {
        // Every testable effect not yet in the model (a report must not hide a candidate):
        // those a residual diagnostic points to first, with its evidence, then the others.
        let (pointed, others): (Vec<_>, Vec<_>) = self
            .testable
            .iter()
            .copied()
            .filter(|e| !effects.contains(e))
            .map(|e| (e, self.evidence(e, fit)))
            .partition(|(_, evidence)| evidence.is_some());
        pointed
            .into_iter()
            .filter_map(|(e, evidence)| Some((e, evidence?)))
            .chain(
                others
                    .into_iter()
                    .map(|(e, _)| (e, engine::NO_DIAGNOSTIC.to_string())),
            )
            .collect()
    }
}

/// The ball-bar's search: forward steps with removals and one-for-one swaps, so that a term
/// taken early as a stand-in (`sense_radius` for the mean of lateral play) leaves once the
/// true one is in. Blocks in every round and swaps for pairs ([`engine::Search::FULL`]) would
/// score 91 pairs a round on the 14-effect library: several times the 5 s a 28 000-reading
/// trace may take.
const SEARCH: engine::Search = engine::Search::LEAN;

/// The result of ball-bar discovery.
#[derive(Debug)]
pub struct BallbarDiscovery {
    problem: BallbarProblem,
    selection: Selection<BallbarEffect, ModelFit>,
}

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

/// The parameters of `effect` in `fit`, in file units with the unit in the name.
fn params(
    fit: &ModelFit,
    effect: BallbarEffect,
    data: &CircleData,
) -> BTreeMap<&'static str, Real> {
    let mut params = BTreeMap::new();
    let term = effect.term();
    let Some(c) = fit.coefficients_of(term) else {
        return params;
    };
    let um = |v: Real| v / M_PER_UM;
    let which = usize::from(matches!(
        effect,
        BallbarEffect::ReversalSpikeQ | BallbarEffect::CyclicQ
    ));
    match effect {
        BallbarEffect::ServoMismatch => {
            params.insert("servo_mismatch_ms", c[0] * 1e3);
        }
        BallbarEffect::BacklashP | BallbarEffect::BacklashQ => {
            params.insert("backlash_um", um(c[0]));
            // Lost motion as play (the carriage stands still while the motor crosses the
            // gap) rather than a step at the reversal: the gap the fit took up.
            let axis = usize::from(effect == BallbarEffect::BacklashQ);
            if fit.shape.play[axis] > 0.0 {
                params.insert("play_um", um(fit.shape.play[axis]));
            }
        }
        BallbarEffect::LateralPlayP | BallbarEffect::LateralPlayQ => {
            params.insert("lateral_play_um", um(c[0]));
        }
        BallbarEffect::ReversalSpikeP | BallbarEffect::ReversalSpikeQ => {
            params.insert("amplitude_um", um(c[0]));
            params.insert("decay_ms", fit.shape.decay[which] * 1e3);
        }
        BallbarEffect::StraightnessP | BallbarEffect::StraightnessQ => {
            params.insert("straightness_um", um(c[0]));
        }
        BallbarEffect::CyclicP | BallbarEffect::CyclicQ => {
            params.insert("amplitude_um", um(c[0].hypot(c[1])));
            params.insert("period_mm", fit.shape.period[which] / M_PER_MM);
            params.insert("phase_deg", c[1].atan2(c[0]) / RAD_PER_DEG);
        }
        BallbarEffect::Lobes => {
            params.insert("lobes", Real::from(fit.shape.lobes));
            params.insert("amplitude_um", um(c[0].hypot(c[1])));
            params.insert("phase_deg", c[1].atan2(c[0]) / RAD_PER_DEG);
        }
        BallbarEffect::RadiusDrift => {
            let duration = data.points.iter().map(|p| p.time).fold(0.0, Real::max);
            params.insert("rate_um_per_min", um(c[0]) * 60.0);
            params.insert("change_um", um(c[0]) * duration);
        }
        BallbarEffect::SenseRadius => {
            params.insert("ccw_minus_cw_um", um(c[0]));
        }
    }
    // Reversal terms are located at the axis's actual reversal: its lag after the
    // programmed one.
    if let Some(axis) = term.reversal_axis() {
        params.insert("reversal_lag_ms", fit.shape.lag[axis] * 1e3);
    }
    params
}

impl BallbarDiscovery {
    fn plane(&self) -> Plane {
        self.problem.data.test.plane
    }

    /// The test conditions of the table.
    pub fn test(&self) -> &CircularTest {
        &self.problem.data.test
    }

    /// The model after the first `k` accepted effects, by name.
    fn model_name(&self, k: usize) -> String {
        let mut name = "base".to_string();
        for step in &self.selection.steps[..k] {
            name.push_str(" + ");
            name.push_str(step.effect.id(self.plane()));
        }
        name
    }

    /// The prepared table (angles, senses and deviations in the table's order).
    pub fn data(&self) -> &CircleData {
        &self.problem.data
    }

    /// The base model and each accepted effect in turn, with the residual it leaves.
    pub fn residual_steps(&self) -> Vec<ResidualStep<'_>> {
        self.selection
            .residual_steps(|k| self.model_name(k), |fit| &fit.residuals)
    }

    /// The accepted effects in order.
    pub fn accepted(&self) -> Vec<BallbarEffect> {
        self.selection.effects()
    }

    /// The effects tested in the last round and not accepted, with their scores.
    pub fn rejected(&self) -> &[engine::Rejected<BallbarEffect>] {
        &self.selection.rejected
    }

    /// The effects the table cannot show, with why.
    pub fn untestable(&self) -> &[(BallbarEffect, String)] {
        self.problem.untestable()
    }

    /// The base model's score.
    pub fn baseline_score(&self) -> &Score {
        &self.selection.baseline.0
    }

    /// The final model's score.
    pub fn final_score(&self) -> &Score {
        self.selection.last().0
    }

    /// The final model's parameters of an accepted effect, in file units.
    pub fn final_params(&self, effect: BallbarEffect) -> Option<BTreeMap<&'static str, Real>> {
        let fit = self.selection.last().1;
        fit.terms
            .contains(&effect.term())
            .then(|| params(fit, effect, &self.problem.data))
    }

    /// The base terms of a fit, keyed as the ISO 230-4 diagnostics are (file units).
    fn base_params(&self, fit: &ModelFit) -> Value {
        Value::Object(
            BASE.iter()
                .filter_map(|&t| {
                    let c = fit.coefficients_of(t)?;
                    Some((t.key(self.plane()), round(c[0] * t.unit().1)))
                })
                .collect(),
        )
    }

    /// The report with stable keys.
    pub fn to_json(&self) -> Value {
        let um = |v: Real| round(v / M_PER_UM);
        let plane = self.plane();
        let data = &self.problem.data;
        let (base_score, base_fit) = &self.selection.baseline;
        let steps = self.selection.steps_json(|step| {
            let json = json!({
                "effect": step.effect.id(plane),
                "axis": step.effect.axis(plane).map(|a| a.to_string()),
                "together_with": step.together_with.map(|e| e.id(plane)),
                "cause": step.effect.cause(),
                "params": params_json(&params(&step.fit, step.effect, data)),
            });
            json.as_object().cloned().unwrap_or_default()
        });
        let (final_score, final_fit) = self.selection.last();
        let mut final_params = serde_json::Map::new();
        final_params.insert("base".into(), self.base_params(final_fit));
        for step in &self.selection.steps {
            final_params.insert(
                step.effect.id(plane).into(),
                params_json(&params(final_fit, step.effect, data)),
            );
        }
        let evidence: serde_json::Map<String, Value> = BallbarEffect::ALL
            .iter()
            .filter(|e| self.problem.testable.contains(e))
            .filter_map(|&e| {
                self.problem
                    .evidence(e, base_fit)
                    .map(|text| (e.id(plane).to_string(), json!(text)))
            })
            .collect();
        json!({
            "kind": "ballbar",
            "plane": plane.to_string(),
            "radius_mm": round(data.test.radius / M_PER_MM),
            "feed_mm_per_min": round(data.test.feed / M_PER_MM * 60.0),
            "n_samples": data.len(),
            "validation": {
                "scheme": self.problem.folds.scheme,
                "folds": self.problem.folds.count,
                "rule": SEARCH.rule(),
            },
            "baseline": {
                "model": "radius + centre offset + squareness + scale mismatch",
                "params": self.base_params(base_fit),
                "rms_um": um(base_score.rms),
                "cv_rms_um": um(base_score.cv_rms),
                "fold_cv_rms_um": engine::folds_json(base_score),
                "evidence": Value::Object(evidence),
            },
            "steps": steps,
            "moves": self.selection.moves_json(|e| e.id(plane).into()),
            "rejected": engine::rejected_json(&self.selection.rejected, |e| e.id(plane).into()),
            "held_back": self.selection.held_back_json(|e| e.id(plane).into()),
            "alternatives": self.selection.alternatives_json(|e| e.id(plane).into()),
            "untestable": self.problem.untestable.iter().map(|(e, why)| json!({
                "effect": e.id(plane),
                "reason": why,
            })).collect::<Vec<_>>(),
            "final": {
                "model": self.model_name(self.selection.steps.len()),
                "params": Value::Object(final_params),
                "rms_um": um(final_score.rms),
                "cv_rms_um": um(final_score.cv_rms),
                "fold_cv_rms_um": engine::folds_json(final_score),
            },
        })
    }

    /// The report for people.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let um = |v: Real| v / M_PER_UM;
        let plane = self.plane();
        let data = &self.problem.data;
        let (base_score, base_fit) = &self.selection.baseline;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Model discovery, ball-bar table, plane {plane} (p = {}, q = {}): {} readings, radius {} mm, feed {} mm/min",
            plane.first(),
            plane.second(),
            data.len(),
            fixed(data.test.radius / M_PER_MM, 3),
            fixed(data.test.feed / M_PER_MM * 60.0, 1)
        );
        let _ = writeln!(
            out,
            "Held-out data: {}; {}.\n",
            self.problem.folds.scheme,
            SEARCH.rule()
        );
        let _ = writeln!(
            out,
            "Base model: radius + centre offset + squareness + scale mismatch\n  RMS {:.3} µm, held-out RMS {:.3} µm ({})",
            um(base_score.rms),
            um(base_score.cv_rms),
            engine::folds_text(base_score, 3)
        );
        let _ = writeln!(out, "\nWhat the base model leaves:");
        for &effect in &self.problem.testable {
            if let Some(text) = self.problem.evidence(effect, base_fit) {
                let _ = writeln!(out, "  {:<18} {text}", effect.id(plane));
            }
        }
        out.push_str(&self.selection.moves_text(|e| e.id(plane).into(), 3));
        let _ = writeln!(out, "\nAccepted, in order:");
        if self.selection.steps.is_empty() {
            out.push_str(&self.selection.nothing_text(|e| e.id(plane).into()));
        }
        for (step, (gain, pct)) in self.selection.steps.iter().zip(self.selection.gains()) {
            let params = engine::params_text(&params(&step.fit, step.effect, data));
            let together = step.together_with.map_or_else(String::new, |other| {
                format!(
                    " (accepted together with {}: neither passes alone)",
                    other.id(plane)
                )
            });
            let _ = writeln!(
                out,
                "  + {}{together}: {params} at acceptance\n      cause: {}\n      held-out RMS {:.3} µm (gain {:.3} µm, {:.1} %; {}; {})",
                step.effect.id(plane),
                step.effect.cause(),
                um(step.score.cv_rms),
                um(gain),
                pct,
                engine::folds_text(&step.score, 3),
                engine::test_text(&step.test)
            );
        }
        out.push_str(&engine::rejected_text(
            &self.selection.rejected,
            |e| e.id(plane).into(),
            3,
        ));
        out.push_str(&self.selection.held_back_text(|e| e.id(plane).into(), 3));
        out.push_str(&self.selection.alternatives_text(|e| e.id(plane).into(), 3));
        let _ = writeln!(
            out,
            "\nEvery effect this table can test was scored in every round: {} accepted, {} rejected in the last round{}.",
            self.selection.steps.len(),
            self.selection.rejected.len(),
            match self.problem.untestable.len() {
                0 => String::new(),
                k => format!("; {k} cannot be tested (below)"),
            }
        );
        if !self.problem.untestable.is_empty() {
            let _ = writeln!(out, "\nCannot be tested with this table:");
            for (effect, why) in &self.problem.untestable {
                let _ = writeln!(out, "  {:<18} {why}", effect.id(plane));
            }
        }
        let (final_score, final_fit) = self.selection.last();
        let _ = writeln!(
            out,
            "\nFinal model: {}\n  RMS {:.3} µm, held-out RMS {:.3} µm ({})",
            self.model_name(self.selection.steps.len()),
            um(final_score.rms),
            um(final_score.cv_rms),
            engine::folds_text(final_score, 3)
        );
        let _ = writeln!(out, "{}", engine::FINAL_VALUES);
        let base = self.base_params(final_fit);
        let base: Vec<String> = base
            .as_object()
            .into_iter()
            .flatten()
            .filter_map(|(k, v)| Some(format!("{k} = {:.3}", v.as_f64()?)))
            .collect();
        let _ = writeln!(out, "    {:<18} {}", "base", base.join(", "));
        for step in &self.selection.steps {
            let _ = writeln!(
                out,
                "    {:<18} {}",
                step.effect.id(plane),
                engine::params_text(&params(final_fit, step.effect, data))
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lettered_ids_follow_the_plane() {
        assert_eq!(BallbarEffect::BacklashQ.id(Plane::XY), "backlash_y");
        assert_eq!(BallbarEffect::BacklashQ.id(Plane::YZ), "backlash_z");
        assert_eq!(BallbarEffect::CyclicP.id(Plane::ZX), "cyclic_z");
        assert_eq!(BallbarEffect::LateralPlayQ.id(Plane::ZX), "lateral_play_x");
        assert_eq!(BallbarEffect::Lobes.id(Plane::ZX), "lobes");
    }
}
