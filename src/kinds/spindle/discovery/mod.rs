//! Discovery on spindle records: what the synchronous model of an axis of rotation leaves in
//! the probes' readings, named by its physical cause, with its held-out gain
//! (`mtwin discover spindle`).
//!
//! **Base model**, for every probe on its own readings (SI, the record's sign conventions):
//!
//! `reading = c_s + Σ_{k=1..K} (a_k cos kθ + b_k sin kθ)`
//!
//! — each speed segment's mean `c_s`, and the harmonics 1 to `K` of the axis angle θ (default
//! `K = 2`): the artefact's set-up (eccentricity, 1 UPR) and the low-order synchronous error
//! motion (an elliptical orbit, 2 UPR) of a sound axis. Effects ([`SpindleEffect`]):
//!
//! | effect | columns | searched |
//! |---|---|---|
//! | `harmonic`, `harmonic_2`, … | cos kθ, sin kθ | the order k > K |
//! | `asynchronous_line`, `asynchronous_line_2`, … | cos 2πf·u, sin 2πf·u per segment, u the turns travelled | the frequency f (UPR), not within one line spacing of a whole number |
//! | `drift` | the shape g(t), 0 at the set-up's first sample, 1 at its last | linear, or 1 − e^{−t/τ} with τ of T/8 … 2T |
//! | `speed_dependence` | cos kθ, sin kθ (k ≤ K) of every segment after the first | — (two speeds or more) |
//!
//! A line is named by the bearing frequency it matches when a bearing geometry is given
//! ([`bearing::Bearing`]), else by its ratio to the rotation.
//!
//! **Held-out data**: in every segment, its revolutions cut into `F` contiguous blocks
//! (`F = min(5, fewest revolutions)`); fold `f` holds out block `f` of every segment. A
//! synchronous term, a line of constant frequency and a smooth drift predict revolutions they
//! did not see; random motion and noise do not. Every searched value (order, frequency, time
//! constant) is found from the fold's training revolutions only.
//!
//! **Every testable effect is scored** at every round (the next free slot of each repeated
//! effect): the engine's rule ([`crate::discovery::engine::RULE`]) decides, not a screening.
//! The residual statistics of the base model are reported as evidence.
//!
//! What it leaves out: lines whose frequency changes with speed in a multi-speed record are
//! searched at one ratio to the rotation (a bearing line keeps its ratio; a structural
//! resonance keeps its Hz); the probes are modelled separately (a line in X and Y is two
//! amplitudes, not an orbit); tilt and the rotating-direction combinations are what
//! `analyze spindle` evaluates, not discovery.

pub mod bearing;
pub mod model;
mod report;

use self::bearing::Bearing;
use self::model::{
    Column, Data, DiscoveryDataError, LinearFit, fit_linear, search_harmonic, search_line,
};
use super::record::SpindleRecord;
use crate::discovery::engine::{self, Folds, Problem, Score, Selection};
use crate::math::{Real, golden_minimum};
use std::collections::HashMap;
use std::sync::Mutex;

/// How many times a repeated effect (a harmonic, a line) may enter.
pub const SLOTS: usize = 4;
/// The base model's harmonics by default (1 = eccentricity, 2 = an elliptical orbit).
pub const DEFAULT_BASE_HARMONICS: usize = 2;
/// Most base harmonics, whatever the samples per revolution: the base stands for the set-up
/// (1 UPR) and the low-order synchronous error motion, and every harmonic adds two columns
/// as long as the record to every fit of every fold and candidate (memory grows with K times
/// the samples, time with K² times the samples). A record also limits K: a harmonic above the
/// base must be left to search below the Nyquist order, so K + 1 < samples per revolution / 2.
pub const MOST_BASE_HARMONICS: usize = 64;
/// Most folds (blocks of revolutions held out).
const MOST_FOLDS: usize = 5;
/// A drift's time constant from the grid is refined within this factor either side.
const DRIFT_REFINE: Real = 2.0;
/// False-alarm probability of a search's evidence over the values searched.
pub const FALSE_ALARM: Real = 0.05;

/// The effects spindle discovery can add to the base model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SpindleEffect {
    /// A synchronous harmonic beyond the base's orders (slot 0, 1, …).
    Harmonic(u8),
    /// An asynchronous line (slot 0, 1, …).
    AsynchronousLine(u8),
    /// Drift of the mean during the record.
    Drift,
    /// The synchronous error motion changing with speed.
    SpeedDependence,
}

const HARMONIC_IDS: [&str; SLOTS] = ["harmonic", "harmonic_2", "harmonic_3", "harmonic_4"];
const LINE_IDS: [&str; SLOTS] = [
    "asynchronous_line",
    "asynchronous_line_2",
    "asynchronous_line_3",
    "asynchronous_line_4",
];

impl SpindleEffect {
    /// The stable identifier.
    pub fn id(self) -> &'static str {
        match self {
            SpindleEffect::Harmonic(slot) => HARMONIC_IDS[usize::from(slot)],
            SpindleEffect::AsynchronousLine(slot) => LINE_IDS[usize::from(slot)],
            SpindleEffect::Drift => "drift",
            SpindleEffect::SpeedDependence => "speed_dependence",
        }
    }

    /// The physical causes, for reports.
    pub fn cause(self) -> &'static str {
        match self {
            SpindleEffect::Harmonic(_) => {
                "synchronous content at a higher order: waviness of a bearing race, lobing of the shaft or \
                 housing, a motor's pole pitch, or the artefact's own form (a reversal or multi-probe record \
                 tells form from error motion)"
            }
            SpindleEffect::AsynchronousLine(_) => {
                "asynchronous content at a fixed ratio to the rotation: a rolling bearing's cage, ball-pass or \
                 ball-spin frequency, or a vibration of the structure or the drive"
            }
            SpindleEffect::Drift => {
                "the mean moving during the record: thermal growth of the spindle (axial) or shift of the axis \
                 (radial) as the bearings and motor warm, or the probes' own drift"
            }
            SpindleEffect::SpeedDependence => {
                "the synchronous error motion changing with speed: unbalance response (1 UPR, growing with \
                 the square of speed), bearing preload changing with centrifugal and thermal load, \
                 hydrodynamic effects"
            }
        }
    }
}

/// A searched value of an effect in a fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Searched {
    /// A harmonic's order.
    Order(usize),
    /// A line's fundamental (UPR) and its harmonics carried (1: a sinusoid).
    Line(Real, usize),
    /// A drift's time constant (s; `None`: linear).
    TimeConstant(Option<Real>),
    /// Nothing searched.
    Nothing,
}

/// A fitted model: the searched values of its effects and the linear fit.
#[derive(Clone, Debug)]
pub struct SpindleFit {
    /// The effects, in model order.
    pub effects: Vec<SpindleEffect>,
    /// The searched value of each effect.
    pub searched: Vec<Searched>,
    /// The linear fit with them.
    pub linear: LinearFit,
    /// Every probe's residuals, concatenated probe after probe (the problem's sample order).
    residuals: Vec<Real>,
}

/// Why a record cannot be searched.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SpindleDiscoveryError {
    /// The samples.
    #[error(transparent)]
    Data(#[from] DiscoveryDataError),
    /// The bearing geometry.
    #[error(transparent)]
    Bearing(#[from] bearing::BearingError),
    /// A base with no room for a harmonic beyond it below the Nyquist order.
    #[error(
        "--base-harmonics {harmonics}: {} with {samples} samples per revolution (a harmonic \
         above the base must be left to search below the Nyquist order, K + 1 < samples per \
         revolution / 2)",
        match (samples / 2).checked_sub(2) {
            Some(most) => format!("at most {most}"),
            None => "no base at all can be searched".to_string(),
        }
    )]
    BaseHarmonics {
        /// Asked.
        harmonics: usize,
        /// Samples per revolution.
        samples: usize,
    },
    /// A probe that reads one value at every sample of the set-up: its residual is round-off,
    /// and no t, F or z formed from it means anything.
    #[error(
        "probe {probe} reads {value_um:.6} µm at every sample of set-up `{setup}`: a flat channel \
         has no scatter, so no statistic (t, F, z) can be formed from it; drop its column or \
         check the probe"
    )]
    FlatProbe {
        /// The probe.
        probe: String,
        /// Its one reading (µm).
        value_um: Real,
        /// The set-up searched.
        setup: String,
    },
    /// More base harmonics than [`MOST_BASE_HARMONICS`].
    #[error(
        "--base-harmonics {0}: at most {MOST_BASE_HARMONICS} (the base stands for the set-up and \
         the low-order synchronous motion; every harmonic adds two record-long columns to every fit)"
    )]
    TooManyBaseHarmonics(usize),
}

/// What discovery needs besides the record.
#[derive(Clone, Debug)]
pub struct Options {
    /// The set-up to search (the record's first when `None`).
    pub setup: Option<String>,
    /// The base model's harmonics 1..=K.
    pub base_harmonics: usize,
    /// The bearing, to name lines.
    pub bearing: Option<Bearing>,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            setup: None,
            base_harmonics: DEFAULT_BASE_HARMONICS,
            bearing: None,
        }
    }
}

/// A spindle record prepared for discovery.
#[derive(Clone, Debug)]
pub struct SpindleProblem {
    data: Data,
    base_harmonics: usize,
    bearing: Option<Bearing>,
    folds: Folds,
    /// The fold of each record sample (every probe's reading of a sample is in its fold).
    fold_of_sample: Vec<usize>,
    untestable: Vec<(SpindleEffect, String)>,
    /// Searched values already found: a model prefix and a training mask (by its hash) give
    /// the same value every time, and every candidate of a round shares the prefix.
    searches: SearchCache,
}

/// The searched value of the last effect of a model prefix, by (prefix, training-mask hash).
#[derive(Debug, Default)]
struct SearchCache(Mutex<HashMap<(Vec<SpindleEffect>, u64), Searched>>);

impl Clone for SearchCache {
    fn clone(&self) -> SearchCache {
        SearchCache::default()
    }
}

/// A hash of a training mask (FNV-1a over its flags).
fn mask_hash(train: &[bool]) -> u64 {
    train.iter().fold(0xcbf2_9ce4_8422_2325, |h, &t| {
        (h ^ u64::from(t)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

impl SpindleProblem {
    /// Prepares `record`: the set-up's samples, the folds, what it cannot show.
    pub fn new(
        record: &SpindleRecord,
        samples_per_revolution: usize,
        options: &Options,
    ) -> Result<SpindleProblem, SpindleDiscoveryError> {
        if options.base_harmonics > MOST_BASE_HARMONICS {
            return Err(SpindleDiscoveryError::TooManyBaseHarmonics(
                options.base_harmonics,
            ));
        }
        let data = Data::new(record, samples_per_revolution, options.setup.as_deref())?;
        for (probe, readings) in data.probes.iter().zip(&data.readings) {
            if let Some(&first) = readings.first()
                && readings.iter().all(|v| *v == first)
            {
                return Err(SpindleDiscoveryError::FlatProbe {
                    probe: probe.clone(),
                    value_um: first * 1e6,
                    setup: data.setup.clone(),
                });
            }
        }
        if options.base_harmonics + 2 > samples_per_revolution / 2 {
            return Err(SpindleDiscoveryError::BaseHarmonics {
                harmonics: options.base_harmonics,
                samples: samples_per_revolution,
            });
        }
        let count = MOST_FOLDS.min(data.fewest_revolutions());
        let fold_of_sample: Vec<usize> = (0..data.len())
            .map(|i| data.revolution[i] * count / data.segments[data.segment[i]].revolutions)
            .collect();
        let probes = data.probes.len();
        let folds = Folds::new(
            format!(
                "{count} contiguous blocks of revolutions in every speed (a block held out in all of them)"
            ),
            (0..probes).flat_map(|_| fold_of_sample.clone()).collect(),
            count,
        );
        let mut untestable = Vec::new();
        if data.segments.len() < 2 {
            untestable.push((
                SpindleEffect::SpeedDependence,
                "the set-up was recorded at one speed".to_string(),
            ));
        }
        let (t0, t1) = data.time_span();
        if t1 - t0 <= 0.0 {
            untestable.push((
                SpindleEffect::Drift,
                "every sample has the same time (the table has no time_s column)".to_string(),
            ));
        }
        Ok(SpindleProblem {
            data,
            base_harmonics: options.base_harmonics,
            bearing: options.bearing,
            folds,
            fold_of_sample,
            untestable,
            searches: SearchCache::default(),
        })
    }

    /// The samples.
    pub fn data(&self) -> &Data {
        &self.data
    }

    /// The effects the record cannot show, with the reason.
    pub fn untestable(&self) -> &[(SpindleEffect, String)] {
        &self.untestable
    }

    /// The base model's harmonics 1..=K.
    pub fn base_harmonics(&self) -> usize {
        self.base_harmonics
    }

    /// The bearing given.
    pub fn bearing(&self) -> Option<&Bearing> {
        self.bearing.as_ref()
    }

    /// The line spacing of the record (UPR): one over its fewest revolutions.
    pub fn spacing(&self) -> Real {
        1.0 / self.data.fewest_revolutions() as Real
    }

    fn testable(&self, effect: SpindleEffect) -> bool {
        !self.untestable.iter().any(|(e, _)| *e == effect)
    }

    /// A record sample's training flag for a mask over every probe's samples.
    fn sample_mask(&self, train: &[bool]) -> Vec<bool> {
        train[..self.data.len()].to_vec()
    }

    /// The design of the base plus `effects` with their searched values.
    fn columns(&self, effects: &[SpindleEffect], searched: &[Searched]) -> Vec<Column> {
        let data = &self.data;
        let segments = data.segments.len();
        let mut columns: Vec<Column> = (0..segments).map(Column::Offset).collect();
        for k in 1..=self.base_harmonics {
            columns.extend([Column::Cos(k), Column::Sin(k)]);
        }
        for (effect, value) in effects.iter().zip(searched) {
            match (effect, value) {
                (SpindleEffect::Harmonic(_), Searched::Order(k)) => {
                    columns.extend([Column::Cos(*k), Column::Sin(*k)]);
                }
                (SpindleEffect::AsynchronousLine(_), Searched::Line(f, harmonics)) => {
                    for h in 1..=*harmonics {
                        let f = h as Real * f;
                        for s in 0..segments {
                            columns.extend([Column::LineCos(f, s), Column::LineSin(f, s)]);
                        }
                    }
                }
                (SpindleEffect::Drift, Searched::TimeConstant(tau)) => {
                    let (t0, t1) = data.time_span();
                    columns.push(Column::Drift(*tau, t0, t1));
                }
                (SpindleEffect::SpeedDependence, _) => {
                    for s in 1..segments {
                        for k in 1..=self.base_harmonics {
                            columns.extend([Column::SegmentCos(k, s), Column::SegmentSin(k, s)]);
                        }
                    }
                }
                _ => {}
            }
        }
        columns
    }

    /// The time constants a drift is first tried with (s; `None` linear): T/16 … 4T by
    /// factors of 2, T the set-up's time span.
    fn time_constants(&self) -> Vec<Option<Real>> {
        let (t0, t1) = self.data.time_span();
        let span = t1 - t0;
        std::iter::once(None)
            .chain((-4..=2).map(|e| Some(span * (2.0 as Real).powi(e))))
            .collect()
    }

    /// Why a drift's time constant `tau` (s) is not a measurement, when it lies at an end of
    /// what the search can reach: the grid of time constants tried (T/16 to 4T, T the record's
    /// span) refined within a factor of 2, so T/32 to 8T (within 1 % in logarithm; the
    /// refinement ends within 0.5 % of a bound its minimum runs into). The residual still falls
    /// toward the end, so the record holds no time constant the search can take; the drift over
    /// the record is still measured.
    pub fn time_constant_at_range_end(&self, tau: Real) -> Option<&'static str> {
        let grid = self.time_constants().into_iter().flatten();
        let (shortest, longest) = grid.fold((Real::INFINITY, 0.0), |(low, high), tau| {
            (Real::min(low, tau), Real::max(high, tau))
        });
        if (tau / (longest * DRIFT_REFINE)).ln() > -0.01 {
            Some(
                "not measured: the longest the search reaches (8 × the record), the drift hardly bends over the record (at least this long)",
            )
        } else if (tau / (shortest / DRIFT_REFINE)).ln() < 0.01 {
            Some(
                "not measured: the shortest the search reaches (the record / 32), the drift settles at the start (at most this long)",
            )
        } else {
            None
        }
    }

    /// The searched value of `effect` given the model `effects`/`searched` before it, from the
    /// samples where `train` is true.
    fn search(
        &self,
        effect: SpindleEffect,
        effects: &[SpindleEffect],
        searched: &[Searched],
        train: &[bool],
    ) -> Searched {
        let columns = self.columns(effects, searched);
        match effect {
            SpindleEffect::Harmonic(_) => {
                let fit = fit_linear(&self.data, &columns, train);
                let taken = taken_orders(searched);
                search_harmonic(
                    &self.data,
                    &fit.residuals,
                    train,
                    self.base_harmonics + 1,
                    &taken,
                )
                .map_or(Searched::Nothing, |peak| Searched::Order(peak.at as usize))
            }
            SpindleEffect::AsynchronousLine(_) => {
                let fit = fit_linear(&self.data, &columns, train);
                search_line(&self.data, &fit.residuals, train, &taken_lines(searched))
                    .map_or(Searched::Nothing, |peak| {
                        Searched::Line(peak.frequency, peak.harmonics)
                    })
            }
            SpindleEffect::Drift => {
                let (t0, t1) = self.data.time_span();
                let sse = |tau: Option<Real>| {
                    let mut trial = columns.clone();
                    trial.push(Column::Drift(tau, t0, t1));
                    fit_linear(&self.data, &trial, train).training_sse(train)
                };
                let best = self
                    .time_constants()
                    .into_iter()
                    .map(|tau| (tau, sse(tau)))
                    .min_by(|a, b| a.1.total_cmp(&b.1));
                // A time constant from the grid is refined by golden section on ln τ within
                // a factor of 2 either side (12 steps: to 0.4 % of τ).
                let tau = match best {
                    Some((Some(tau), _)) => Some(
                        golden_minimum(
                            |log_tau| sse(Some(log_tau.exp())),
                            (tau / DRIFT_REFINE).ln(),
                            (tau * DRIFT_REFINE).ln(),
                            12,
                        )
                        .0
                        .exp(),
                    ),
                    _ => None,
                };
                Searched::TimeConstant(tau)
            }
            SpindleEffect::SpeedDependence => Searched::Nothing,
        }
    }

    /// Fits the base plus `effects`, searching each effect's value in model order on the
    /// samples where `train` (one flag per record sample) is true.
    pub fn fit_samples(&self, effects: &[SpindleEffect], train: &[bool]) -> SpindleFit {
        let mut searched = Vec::with_capacity(effects.len());
        let hash = mask_hash(train);
        for (i, &effect) in effects.iter().enumerate() {
            let key = (effects[..=i].to_vec(), hash);
            let known = self
                .searches
                .0
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .get(&key)
                .copied();
            let value = match known {
                Some(value) => value,
                None => {
                    let value = self.search(effect, &effects[..i], &searched, train);
                    self.searches
                        .0
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .insert(key, value);
                    value
                }
            };
            searched.push(value);
        }
        let columns = self.columns(effects, &searched);
        let linear = fit_linear(&self.data, &columns, train);
        let residuals = linear.residuals.concat();
        SpindleFit {
            effects: effects.to_vec(),
            searched,
            linear,
            residuals,
        }
    }

    /// The next slot of a repeated effect not yet in `effects`, or the effect itself.
    fn next(&self, effects: &[SpindleEffect]) -> Vec<SpindleEffect> {
        let used = |make: fn(u8) -> SpindleEffect| {
            (0..SLOTS as u8).map(make).find(|e| !effects.contains(e))
        };
        [
            used(SpindleEffect::Harmonic),
            used(SpindleEffect::AsynchronousLine),
            Some(SpindleEffect::Drift),
            Some(SpindleEffect::SpeedDependence),
        ]
        .into_iter()
        .flatten()
        .filter(|e| !effects.contains(e) && self.testable(*e))
        .collect()
    }

    /// What the residual of `fit` shows for `effect`, in words.
    pub fn evidence(&self, effect: SpindleEffect, fit: &SpindleFit) -> String {
        report::evidence(self, effect, fit)
    }
}

/// The orders of the harmonics in `searched`.
fn taken_orders(searched: &[Searched]) -> Vec<usize> {
    searched
        .iter()
        .filter_map(|s| match s {
            Searched::Order(k) => Some(*k),
            _ => None,
        })
        .collect()
}

/// The lines in `searched`: fundamental and harmonics.
pub(crate) fn taken_lines(searched: &[Searched]) -> Vec<(Real, usize)> {
    searched
        .iter()
        .filter_map(|s| match s {
            Searched::Line(f, h) => Some((*f, *h)),
            _ => None,
        })
        .collect()
}

impl Problem for SpindleProblem {
    type Effect = SpindleEffect;
    type Fit = SpindleFit;

    fn id(&self, effect: SpindleEffect) -> String {
        effect.id().into()
    }

    fn n_samples(&self) -> usize {
        self.data.len() * self.data.probes.len()
    }

    fn folds(&self) -> &Folds {
        &self.folds
    }

    fn fit(&self, effects: &[SpindleEffect], train: &[bool]) -> SpindleFit {
        self.fit_samples(effects, &self.sample_mask(train))
    }

    fn residuals(&self, fit: &SpindleFit) -> Vec<Real> {
        fit.residuals.clone()
    }

    fn proposals(
        &self,
        effects: &[SpindleEffect],
        fit: &SpindleFit,
    ) -> Vec<(SpindleEffect, String)> {
        self.next(effects)
            .into_iter()
            .map(|e| (e, self.evidence(e, fit)))
            .collect()
    }
}

/// The result of spindle discovery.
#[derive(Debug)]
pub struct SpindleDiscovery {
    problem: SpindleProblem,
    selection: Selection<SpindleEffect, SpindleFit>,
}

/// Runs discovery on a spindle record; `progress` hears which candidate is being tested.
pub fn discover_spindle(
    record: &SpindleRecord,
    samples_per_revolution: usize,
    options: &Options,
    progress: impl FnMut(&str),
) -> Result<SpindleDiscovery, SpindleDiscoveryError> {
    let problem = SpindleProblem::new(record, samples_per_revolution, options)?;
    let selection = engine::forward_selection(&problem, progress);
    Ok(SpindleDiscovery { problem, selection })
}

impl SpindleDiscovery {
    /// The accepted effects, in order.
    pub fn accepted(&self) -> Vec<SpindleEffect> {
        self.selection.effects()
    }

    /// The final model's fit (all samples, every accepted effect).
    pub fn final_fit(&self) -> &SpindleFit {
        self.selection.last().1
    }

    /// The base model's score.
    pub fn baseline_score(&self) -> &Score {
        &self.selection.baseline.0
    }

    /// The final model's score.
    pub fn final_score(&self) -> &Score {
        self.selection.last().0
    }

    /// The candidates of the last round with their scores.
    pub fn rejected(&self) -> &[engine::Rejected<SpindleEffect>] {
        &self.selection.rejected
    }

    /// The problem searched.
    pub fn problem(&self) -> &SpindleProblem {
        &self.problem
    }

    /// The searched value of `effect` in the final model.
    pub fn searched(&self, effect: SpindleEffect) -> Option<Searched> {
        let fit = self.final_fit();
        fit.effects
            .iter()
            .position(|e| *e == effect)
            .map(|i| fit.searched[i])
    }

    /// The name of the final model's line `effect`: a multiple of a line before it, the
    /// bearing frequency it matches, else its ratio to the rotation (`None` when `effect` is
    /// not a line of the model).
    pub fn line_name(&self, effect: SpindleEffect) -> Option<String> {
        let fit = self.final_fit();
        let index = fit.effects.iter().position(|e| *e == effect)?;
        match fit.searched[index] {
            Searched::Line(f, _) => Some(report::line_name(
                &self.problem,
                f,
                &taken_lines(&fit.searched[..index]),
            )),
            _ => None,
        }
    }

    /// The fold of each record sample.
    pub fn fold_of_sample(&self) -> &[usize] {
        &self.problem.fold_of_sample
    }
}
