//! A ball-bar table prepared for discovery ([`BallbarProblem`]): the base model, the angular
//! sectors held out, the effects the table can and cannot show, and the evidence in a fit's
//! residual that points to each.

use super::effects::BallbarEffect;
use crate::discovery::engine::{self, Folds, Problem};
use crate::discovery::least_squares::{T_UNDEFINED, regression};
use crate::kinds::ballbar::iso230_4::{
    BallbarError, Blocks, CircleData, CircularTest, MIN_DIAGNOSTIC_READINGS, ModelFit, Shape, Term,
    covered_arc, diagnostic_column,
};
use crate::kinds::ballbar::table::BallbarTable;
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real};
use rayon::prelude::*;
use std::collections::HashMap;
use std::f64::consts::TAU;
use std::sync::Mutex;

/// The base model's terms.
pub(super) const BASE: [Term; 5] = [
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

/// The ball-bar's search: forward steps with removals and one-for-one swaps, so that a term
/// taken early as a stand-in (`sense_radius` for the mean of lateral play) leaves once the
/// true one is in. Blocks in every round and swaps for pairs ([`engine::Search::FULL`]) would
/// score 91 pairs a round on the 14-effect library: several times the 5 s a 28 000-reading
/// trace may take.
pub(super) const SEARCH: engine::Search = engine::Search::LEAN;

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

/// A ball-bar table prepared for discovery.
#[derive(Clone, Debug)]
pub struct BallbarProblem {
    pub(super) data: CircleData,
    pub(super) folds: Folds,
    /// The readings cut into the folds' sectors, for fits that share their sums.
    pub(super) blocks: Blocks,
    pub(super) testable: Vec<BallbarEffect>,
    pub(super) untestable: Vec<(BallbarEffect, String)>,
    /// The servo angle lag (s) of each model, by its effects: estimated once, by the model on
    /// the whole trace ([`CircleData::angle_lag`]; 0 unless both senses cover a full circle),
    /// and held in every fit of that model, full and per fold. A fold holds a sector out, so
    /// its readings never cover the circle the estimate needs: estimated per fold, every fold
    /// would be fitted without the lag the full fit has, and the held-out score would judge
    /// another servo model than the one reported. Per model, because terms beside the centre
    /// (a radius drift over a ccw then a cw circle is a sawtooth in the angle) share first
    /// harmonics with the lag's column.
    pub(super) angle_lags: AngleLags,
}

/// The angle lag of each model scored (by its sorted effects).
#[derive(Debug, Default)]
pub(super) struct AngleLags(Mutex<HashMap<Vec<BallbarEffect>, Real>>);

impl Clone for AngleLags {
    fn clone(&self) -> AngleLags {
        AngleLags::default()
    }
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
            angle_lags: AngleLags::default(),
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

    /// The servo angle lag (s) of the model with `effects`, estimated on the whole trace and
    /// held in all its fits (see `angle_lags`).
    pub fn angle_lag(&self, effects: &[BallbarEffect]) -> Real {
        let mut key = effects.to_vec();
        key.sort();
        if let Some(&lag) = self.angle_lags.0.lock().expect("not poisoned").get(&key) {
            return lag;
        }
        let lag = self.data.full_angle_lag(&self.blocks, &terms(effects));
        self.angle_lags
            .0
            .lock()
            .expect("not poisoned")
            .insert(key, lag);
        lag
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

    fn id(&self, effect: BallbarEffect) -> String {
        effect.id(self.data.test.plane).into()
    }

    fn n_samples(&self) -> usize {
        self.data.len()
    }

    fn folds(&self) -> &Folds {
        &self.folds
    }

    fn fit(&self, effects: &[BallbarEffect], train: &[bool]) -> ModelFit {
        let terms = terms(effects);
        let lag = self.angle_lag(effects);
        match self.blocks.included(train) {
            Some(included) => self
                .data
                .fit_blocks_at_lag(&self.blocks, &terms, &included, lag),
            None => self.data.fit_blocks_at_lag(
                &Blocks::training(&self.data, train),
                &terms,
                &[true, false],
                lag,
            ),
        }
    }

    fn residuals(&self, fit: &ModelFit) -> Vec<Real> {
        fit.residuals.clone()
    }

    fn proposals(&self, effects: &[BallbarEffect], fit: &ModelFit) -> Vec<(BallbarEffect, String)> {
        // Every testable effect not yet in the model (a report must not hide a candidate):
        // those a residual diagnostic points to first, with its evidence, then the others.
        // Each effect's evidence is a few periodograms or regressions over the trace: in
        // parallel, in the order of `testable`.
        let evidence: Vec<(BallbarEffect, Option<String>)> = self
            .testable
            .par_iter()
            .copied()
            .filter(|e| !effects.contains(e))
            .map(|e| (e, self.evidence(e, fit)))
            .collect();
        let (pointed, others): (Vec<_>, Vec<_>) = evidence
            .into_iter()
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
