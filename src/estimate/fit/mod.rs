//! The estimate: every reading set stacked into one weighted least-squares problem on the
//! twin's exact chain, its identifiability, the Levenberg–Marquardt fit, the linearised
//! covariance and the Monte Carlo propagation (GUM Supplement 1).
//!
//! # The problem
//!
//! The unknowns are the free coefficients of the [`ParameterSet`] and every set's nuisances,
//! in **solver units** `z` (1 µm, or the rotation moving a point at
//! [`super::spec::REFERENCE_LENGTH`] by 1 µm; a nuisance from its start value). The residual of
//! reading `i` is `(prediction_i(z) − measured_i) / σ_i`, so the design `J = ∂r/∂z` is
//! noise-weighted and column-scaled, and `1/s` for a singular value `s` of `J` is the standard
//! uncertainty (µm) of the combination along its right singular vector.
//!
//! # The steps
//!
//! 1. **Identifiability first**, at the start (`z = 0`, the linearisation): the design from
//!    the readings' own first-order sensitivities on the chain's Jacobian where the kind gives
//!    them (R-tests), else by forward differences on the exact chain (step 0.01 µm:
//!    truncation 1e-7 and round-off 5e-9 of a column), [`super::identifiability::analyse`].
//! 2. **The fit** on the identified subspace only: `z = B w` with `B` the right singular
//!    vectors of the `r` identified directions, by [`super::lm::solve`] from `w = 0` (its first
//!    step is the linearised estimate), the residuals on the exact chain and the Jacobian kept
//!    at the start's (the readings are linear in the errors to about 1e-5 at these sizes, so a
//!    fresh Jacobian per step would move the solution by 1e-5 of the residual's pull, far below
//!    its uncertainty, at twenty times the cost). Directions the design cannot see stay at
//!    zero: the estimate is the minimum-norm one, and unidentifiable parameters get no number.
//! 3. **Uncertainty**: `C_z = B (J_Bᵀ J_B)⁻¹ Bᵀ` with `J_B = J B`, the start's design again
//!    (at the solution it differs by about 1e-5 relative). When the residuals are significantly larger than the stated
//!    uncertainties (χ² above its 99 % quantile), `C_z` is scaled by the Birge ratio χ²/dof
//!    and the report says so. The known set-up quantities then add `B G S Sᵀ Gᵀ Bᵀ`, with
//!    `G = (J_Bᵀ J_B)⁻¹ J_Bᵀ` and `S` the readings' sensitivity to each quantity times its
//!    uncertainty at the solution ([`Problem::setup_design`]): the u every output gives is the
//!    noise's and the set-up's, as the Monte Carlo draws them.
//! 4. **Monte Carlo** (`trials > 0`): each trial draws the known set-up quantities from their
//!    stated uncertainties and the readings' noise, simulates the readings through the twin at
//!    the estimate, and refits (Gauss–Newton with the Jacobian frozen at the solution, two
//!    steps: the model is linear to 1e-5 at these error sizes). Trial `t` draws from its own
//!    stream (`seed`, `monte carlo t`), so the result is the same whatever the thread count.
//!    Trials run in batches of [`MONTE_CARLO_BATCH`], so memory does not grow with their
//!    number: the mean and standard deviation gather every trial (batch statistics combined
//!    in batch order), and the 95 % interval is the order statistics' interval of one batch,
//!    or with several the average of the batches' intervals weighted by their trials (GUM
//!    Supplement 1 §7.9.4 averages its sequences' endpoints the same way).

use super::Readings;
use super::identifiability::{self, Identifiability};
use super::lm;
use super::spec::ParameterSet;
use crate::machine::{Machine, Workspace};
use crate::math::{Real, seeded_rng, standard_normal};
use mtwin_kernels::linalg;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

mod design;

pub use design::{profiled_design, project_off, start_design};

/// Finite-difference step in solver units: 0.01 µm. Forward differences then err by
/// `h·f''/2`, about 1e-7 of a column at these error sizes (the chain bends by (1 µm / 0.1 m)
/// per µm), far below the rank cut, while round-off (1e-16 of positions of 0.5 m over a step of
/// 1e-8 m) stays at 5e-9.
const STEP: Real = 0.01;

/// Why an estimate cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EstimateError {
    /// No readings at all.
    #[error("no readings: give at least one measurement table")]
    NoReadings,
    /// A table says it was measured on another machine.
    #[error("{file}: measured on machine \"{table}\", not on \"{machine}\" (--machine)")]
    OtherMachine {
        /// The table.
        file: String,
        /// The machine it names.
        table: String,
        /// The machine given.
        machine: String,
    },
    /// A measured value or an uncertainty is missing, not finite, or too small: the table
    /// and the reading.
    #[error("{0}")]
    BadReadings(String),
    /// The tables identify none of the error parameters.
    #[error(
        "the tables see none of the parameters (each is unseen or confounded with the set-up): give other tables or other parameters"
    )]
    NothingIdentifiable,
    /// The solver failed.
    #[error("the fit failed: {0}")]
    Solver(String),
}

/// The stacked problem: the parameters, the reading sets and the layout of the unknowns.
pub struct Problem<'a> {
    machine: &'a Machine,
    parameters: &'a ParameterSet,
    sets: &'a [Readings],
    /// Where each set's nuisances start in `z`.
    nuisance_at: Vec<usize>,
    /// Where each set's readings start in the residuals.
    row_at: Vec<usize>,
    rows: usize,
    /// SI per solver unit of each unknown.
    scales: Vec<Real>,
    /// SI start of each unknown.
    starts: Vec<Real>,
    /// A label per unknown.
    labels: Vec<String>,
    /// Whether each unknown is a rotation.
    rotation: Vec<bool>,
}

impl<'a> Problem<'a> {
    /// Stacks `sets` for `parameters` on `machine`; checks that every table was measured on
    /// it (when it says) and that the readings are usable.
    pub fn new(
        machine: &'a Machine,
        parameters: &'a ParameterSet,
        sets: &'a [Readings],
    ) -> Result<Problem<'a>, EstimateError> {
        if sets.iter().all(|s| s.is_empty()) {
            return Err(EstimateError::NoReadings);
        }
        let mut scales = parameters.scales.clone();
        let mut starts = vec![0.0; parameters.len()];
        let mut labels = parameters.labels.clone();
        let mut rotation = parameters.rotation.clone();
        let (mut nuisance_at, mut row_at, mut rows) = (Vec::new(), Vec::new(), 0);
        for set in sets {
            if let Some(name) = set.machine.as_deref().filter(|n| *n != machine.name()) {
                return Err(EstimateError::OtherMachine {
                    file: set.source.clone(),
                    table: name.to_string(),
                    machine: machine.name().to_string(),
                });
            }
            let planned = set.measured.is_empty();
            let bad = |what: String| EstimateError::BadReadings(format!("{}: {what}", set.source));
            if !planned && set.measured.len() != set.sigma.len() {
                return Err(bad(format!(
                    "{} measured values for {} uncertainties",
                    set.measured.len(),
                    set.sigma.len()
                )));
            }
            if let Some(i) = set.measured.iter().position(|v| !v.is_finite()) {
                return Err(bad(format!("reading {} is not a finite number", i + 1)));
            }
            if let Some(i) = set
                .sigma
                .iter()
                .position(|s| !(s.is_finite() && *s >= 1e-12))
            {
                return Err(bad(format!(
                    "the uncertainty of reading {} is {:e} m: expected at least 1 pm",
                    i + 1,
                    set.sigma[i]
                )));
            }
            nuisance_at.push(scales.len());
            for q in &set.nuisance {
                scales.push(if q.translation {
                    1e-6
                } else {
                    1e-6 / super::spec::REFERENCE_LENGTH
                });
                starts.push(q.start);
                labels.push(q.name.clone());
                rotation.push(!q.translation);
            }
            row_at.push(rows);
            rows += set.len();
        }
        // Two tables of one kind name their set-ups alike: number the later ones.
        for (k, at) in nuisance_at.iter().enumerate() {
            for j in *at..*at + sets[k].nuisance.len() {
                if labels[..*at].contains(&labels[j]) {
                    labels[j] = format!("{} (table {})", labels[j], k + 1);
                }
            }
        }
        Ok(Problem {
            machine,
            parameters,
            sets,
            nuisance_at,
            row_at,
            rows,
            scales,
            starts,
            labels,
            rotation,
        })
    }

    /// The number of unknowns (coefficients and nuisances).
    pub fn unknowns(&self) -> usize {
        self.scales.len()
    }

    /// The number of readings.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// A label per unknown.
    pub fn labels(&self) -> &[String] {
        &self.labels
    }

    /// SI per solver unit of each unknown.
    pub fn scales(&self) -> &[Real] {
        &self.scales
    }

    /// Whether each unknown is a rotation (µrad in files).
    pub fn rotation(&self) -> &[bool] {
        &self.rotation
    }

    /// The SI value of each unknown at `z`.
    pub fn si(&self, z: &[Real]) -> Vec<Real> {
        z.iter()
            .zip(&self.scales)
            .zip(&self.starts)
            .map(|((z, s), x0)| x0 + s * z)
            .collect()
    }

    /// Every reading predicted at `z` (SI), with the known set-up quantities offset by
    /// `setup` (one slice per set; empty = as stated).
    pub fn predict(
        &self,
        z: &[Real],
        setup: &[Vec<Real>],
        workspace: &mut Workspace,
        out: &mut [Real],
    ) {
        let si = self.si(z);
        let model = self.parameters.model_with(&si[..self.parameters.len()]);
        for (k, set) in self.sets.iter().enumerate() {
            let nuisance = &si[self.nuisance_at[k]..self.nuisance_at[k] + set.nuisance.len()];
            let zero = vec![0.0; set.setup.len()];
            let offsets = setup.get(k).filter(|s| !s.is_empty()).unwrap_or(&zero);
            let rows = &mut out[self.row_at[k]..self.row_at[k] + set.len()];
            set.model
                .predict(self.machine, workspace, &model, nuisance, offsets, rows);
        }
    }

    /// The weighted residuals `(prediction − measured) / σ` at `z` for the measured values
    /// `measured` (all sets stacked, SI).
    pub fn residuals(
        &self,
        z: &[Real],
        measured: &[Real],
        workspace: &mut Workspace,
        out: &mut [Real],
    ) {
        self.predict(z, &[], workspace, out);
        for (r, m) in out.iter_mut().zip(measured) {
            *r -= m;
        }
        self.weigh(out);
    }

    /// The measured values of every set, stacked (SI); zeros for planned sets.
    pub fn measured(&self) -> Vec<Real> {
        let mut out = vec![0.0; self.rows];
        for (k, set) in self.sets.iter().enumerate() {
            if !set.measured.is_empty() {
                out[self.row_at[k]..self.row_at[k] + set.len()].copy_from_slice(&set.measured);
            }
        }
        out
    }

    /// Divides stacked per-reading values by their σ, in place.
    fn weigh(&self, values: &mut [Real]) {
        for (k, set) in self.sets.iter().enumerate() {
            let at = self.row_at[k];
            for (value, sigma) in values[at..at + set.len()].iter_mut().zip(&set.sigma) {
                *value /= sigma;
            }
        }
    }

    /// Draws the known set-up quantities' offsets (SI) for one Monte Carlo trial.
    fn draw_setup(&self, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<Vec<Real>> {
        self.sets
            .iter()
            .map(|set| {
                set.setup
                    .iter()
                    .map(|q| q.uncertainty * standard_normal(rng))
                    .collect()
            })
            .collect()
    }

    /// Draws noise on every reading (SI), `factor` times its stated uncertainty, for one trial.
    fn draw_noise(&self, rng: &mut rand_chacha::ChaCha8Rng, factor: Real, out: &mut [Real]) {
        for (k, set) in self.sets.iter().enumerate() {
            let at = self.row_at[k];
            for (i, sigma) in set.sigma.iter().enumerate() {
                out[at + i] += factor * sigma * standard_normal(rng);
            }
        }
    }
}

/// Trials per Monte Carlo batch: the memory held at once (trials × unknowns numbers).
pub const MONTE_CARLO_BATCH: usize = 10_000;

/// Told the trials of each Monte Carlo batch as it ends (for a progress bar).
#[derive(Clone)]
pub struct Progress(pub std::sync::Arc<dyn Fn(usize) + Send + Sync>);

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Progress")
    }
}

/// Options of an estimate.
#[derive(Clone, Debug)]
pub struct Options {
    /// The rank rule and the flag for weak directions.
    pub identifiability: identifiability::Options,
    /// The solver's options.
    pub solver: lm::Options,
    /// Monte Carlo trials (0: none).
    pub trials: usize,
    /// Seed of the Monte Carlo streams.
    pub seed: u64,
    /// Where the Monte Carlo reports its progress, if anywhere.
    pub progress: Option<Progress>,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            identifiability: identifiability::Options::default(),
            solver: lm::Options::default(),
            trials: 0,
            seed: 1,
            progress: None,
        }
    }
}

/// The Monte Carlo's result per unknown (solver units).
#[derive(Clone, Debug)]
pub struct MonteCarlo {
    /// Trials run.
    pub trials: usize,
    /// Mean of each unknown.
    pub mean: Vec<Real>,
    /// Standard deviation of each unknown.
    pub std: Vec<Real>,
    /// The probabilistically symmetric 95 % coverage interval of each unknown.
    pub interval: Vec<(Real, Real)>,
}

/// An estimate.
#[derive(Clone, Debug)]
pub struct Fit {
    /// The identifiability of the design at the start.
    pub identifiability: Identifiability,
    /// The solution (solver units).
    pub z: Vec<Real>,
    /// The covariance of `z` (solver units²), zero along unidentified directions.
    pub covariance: DMatrix<Real>,
    /// Whether each unknown is identified (gets a number).
    pub identified: Vec<bool>,
    /// Σ r² at the solution.
    pub chi2: Real,
    /// Degrees of freedom: readings − identified directions.
    pub dof: usize,
    /// χ²/dof when the covariance was scaled by it (the residuals exceed the stated
    /// uncertainties), else `None`.
    pub birge_scaled: Option<Real>,
    /// RMS of the unweighted residuals (m) per set.
    pub residual_rms: Vec<Real>,
    /// The reading, and the row of three, whose leaving-out lowers χ² most
    /// ([`super::influence`]).
    pub influential: Vec<super::influence::Influential>,
    /// Solver iterations.
    pub iterations: usize,
    /// The Monte Carlo, when asked.
    pub monte_carlo: Option<MonteCarlo>,
}

impl Fit {
    /// The standard uncertainty of unknown `j` (solver units), `None` if unidentified.
    pub fn uncertainty(&self, j: usize) -> Option<Real> {
        self.identified[j].then(|| self.covariance[(j, j)].max(0.0).sqrt())
    }
}

/// The reduced problem `w ↦ r(B w)` for the solver, its Jacobian kept at the start's.
struct Reduced<'p, 'a> {
    problem: &'p Problem<'a>,
    basis: &'p DMatrix<Real>,
    measured: &'p [Real],
    jacobian: DMatrix<Real>,
}

impl Reduced<'_, '_> {
    fn z(&self, w: &[Real]) -> Vec<Real> {
        (self.basis * DVector::from_column_slice(w))
            .as_slice()
            .to_vec()
    }
}

impl lm::Problem for Reduced<'_, '_> {
    fn residual_count(&self) -> usize {
        self.problem.rows
    }

    fn parameter_count(&self) -> usize {
        self.basis.ncols()
    }

    fn residuals(&self, w: &[Real], out: &mut [Real]) {
        let mut workspace = Workspace::new(self.problem.machine);
        self.problem
            .residuals(&self.z(w), self.measured, &mut workspace, out);
    }

    fn jacobian(&self, _: &[Real], out: &mut DMatrix<Real>) {
        out.copy_from(&self.jacobian);
    }
}

/// What the readings of `problem` can identify (its design at the start).
pub fn identifiability(
    problem: &Problem<'_>,
    options: &identifiability::Options,
) -> Identifiability {
    identifiability::analyse(&start_design(problem), problem.labels(), options)
}

/// Estimates the unknowns of `problem` from its measured values.
pub fn estimate(problem: &Problem<'_>, options: &Options) -> Result<Fit, EstimateError> {
    if problem.sets.iter().any(|s| s.measured.is_empty()) {
        return Err(EstimateError::BadReadings(
            "a planned test (no measured values) cannot be estimated from".into(),
        ));
    }
    let design = start_design(problem);
    if !design.iter().all(|v| v.is_finite()) {
        return Err(EstimateError::Solver(
            "the design is not finite (an uncertainty too small, or positions beyond the chain's range)".into(),
        ));
    }
    let report = identifiability::analyse(&design, problem.labels(), &options.identifiability);
    let basis = identified_basis(&design, report.rank);
    let errors = problem.parameters.len();
    if basis.ncols() == 0 || (0..errors).all(|j| report.unidentifiable.contains(&j)) {
        return Err(EstimateError::NothingIdentifiable);
    }
    let measured = problem.measured();
    let reduced = Reduced {
        problem,
        basis: &basis,
        measured: &measured,
        jacobian: &design * &basis,
    };
    let solution = lm::solve(&reduced, &vec![0.0; basis.ncols()], &options.solver)
        .map_err(|e| EstimateError::Solver(e.to_string()))?;
    if solution.termination == lm::Termination::MaxIterations {
        return Err(EstimateError::Solver(format!(
            "no convergence after {} steps",
            solution.iterations
        )));
    }
    let z = reduced.z(&solution.x);
    // The design at the start serves the covariance too: at the solution it differs by the
    // readings' nonlinearity, about 1e-5 relative at these error sizes.
    let jb = reduced.jacobian;
    let precision = jb.transpose() * &jb;
    let inverse = linalg::try_inverse(precision)
        .ok_or_else(|| EstimateError::Solver("the identified design became singular".into()))?;
    let mut covariance = &basis * &inverse * basis.transpose();
    let mut residuals = vec![0.0; problem.rows];
    problem.residuals(
        &z,
        &measured,
        &mut Workspace::new(problem.machine),
        &mut residuals,
    );
    let chi2: Real = residuals.iter().map(|r| r * r).sum();
    let dof = problem.rows.saturating_sub(basis.ncols());
    let birge_scaled =
        (dof > 0 && chi2 > chi2_quantile_99(dof as Real)).then(|| chi2 / dof as Real);
    if let Some(factor) = birge_scaled {
        covariance *= factor;
    }
    // The known set-up quantities (a sphere's preset, a reflector's offset) move every reading
    // of their set together: C += B G S Sᵀ Gᵀ Bᵀ, with G the solver's gain and S their
    // weighted sensitivities times their uncertainties at the solution (not scaled by the
    // Birge ratio: they are not the residuals' scatter).
    let setup = problem.setup_design(&z);
    if setup.ncols() > 0 {
        let moved = &basis * (&inverse * jb.transpose() * setup);
        covariance += &moved * moved.transpose();
    }
    let residual_rms = problem
        .sets
        .iter()
        .enumerate()
        .map(|(k, set)| {
            let at = problem.row_at[k];
            let sum: Real = (0..set.len())
                .map(|i| (residuals[at + i] * set.sigma[i]).powi(2))
                .sum();
            (sum / set.len().max(1) as Real).sqrt()
        })
        .collect();
    let blocks: Vec<(usize, usize, &[Real])> = problem
        .sets
        .iter()
        .enumerate()
        .map(|(k, set)| (problem.row_at[k], set.model.per_row(), set.sigma.as_slice()))
        .collect();
    let influential = super::influence::most_influential(&jb, &inverse, &residuals, chi2, &blocks);
    let identified = (0..problem.unknowns())
        .map(|j| !report.unidentifiable.contains(&j))
        .collect();
    let monte_carlo = (options.trials > 0).then(|| {
        // Noise drawn as the residuals show it when the fit scaled the uncertainties.
        let noise = birge_scaled.map_or(1.0, Real::sqrt);
        monte_carlo(
            problem,
            &z,
            &basis,
            &jb,
            &inverse,
            options.trials,
            options.seed,
            noise,
            options.progress.as_ref(),
        )
    });
    Ok(Fit {
        identifiability: report,
        z,
        covariance,
        identified,
        chi2,
        dof,
        birge_scaled,
        residual_rms,
        influential,
        iterations: solution.iterations,
        monte_carlo,
    })
}

/// The right singular vectors of the `rank` largest singular values of `design` (n × rank).
pub fn identified_basis(design: &DMatrix<Real>, rank: usize) -> DMatrix<Real> {
    let n = design.ncols();
    // With at least as many rows as columns the SVD of the design itself has all n right
    // singular vectors (the rank analysis's own); with fewer, the normal matrix's SVD does.
    let svd = if design.nrows() >= n {
        linalg::svd(design.clone(), false, true)
    } else {
        linalg::svd(design.transpose() * design, false, true)
    };
    let v_t = svd.v_t.expect("asked for V");
    let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
    order.sort_by(|a, b| svd.singular_values[*b].total_cmp(&svd.singular_values[*a]));
    DMatrix::from_fn(n, rank.min(order.len()), |i, k| v_t[(order[k], i)])
}

/// The Monte Carlo of the estimate (module doc, step 4); the readings' noise is drawn at
/// `noise` times the stated uncertainties (the Birge ratio's root when the fit scaled them).
#[allow(clippy::too_many_arguments)]
fn monte_carlo(
    problem: &Problem<'_>,
    z: &[Real],
    basis: &DMatrix<Real>,
    jb: &DMatrix<Real>,
    inverse: &DMatrix<Real>,
    trials: usize,
    seed: u64,
    noise: Real,
    progress: Option<&Progress>,
) -> MonteCarlo {
    let rows = problem.rows;
    let gain = inverse * jb.transpose(); // r × m
    let w_hat = basis.transpose() * DVector::from_column_slice(z);
    let mut at_estimate = vec![0.0; rows];
    problem.predict(
        z,
        &[],
        &mut Workspace::new(problem.machine),
        &mut at_estimate,
    );
    let trial = |(workspace, data, residuals): &mut (Workspace, Vec<Real>, Vec<Real>), t: usize| {
        let mut rng = seeded_rng(seed, &format!("monte carlo {t}"));
        let setup = problem.draw_setup(&mut rng);
        problem.predict(z, &setup, workspace, data);
        problem.draw_noise(&mut rng, noise, data);
        // Two Gauss–Newton steps from the estimate: the first from the predictions there
        // (computed once for all trials), the second on the exact chain.
        for ((r, p), d) in residuals.iter_mut().zip(&at_estimate).zip(data.iter()) {
            *r = p - d;
        }
        problem.weigh(residuals);
        let mut w = &w_hat - &gain * DVector::from_column_slice(residuals);
        problem.residuals((basis * &w).as_slice(), data, workspace, residuals);
        w -= &gain * DVector::from_column_slice(residuals);
        (basis * w).as_slice().to_vec()
    };
    let n = z.len();
    // Running statistics over the batches, combined in batch order (Chan et al.): the same
    // numbers whatever the thread count.
    let mut count = 0usize;
    let mut mean = vec![0.0; n];
    let mut m2 = vec![0.0; n];
    let mut interval = vec![(0.0, 0.0); n];
    let mut start = 0;
    while start < trials {
        let end = (start + MONTE_CARLO_BATCH).min(trials);
        let samples: Vec<Vec<Real>> = (start..end)
            .into_par_iter()
            .map_init(
                || {
                    (
                        Workspace::new(problem.machine),
                        vec![0.0; rows],
                        vec![0.0; rows],
                    )
                },
                trial,
            )
            .collect();
        let size = end - start;
        let weight = size as Real / trials as Real;
        for j in 0..n {
            let mut values: Vec<Real> = samples.iter().map(|s| s[j]).collect();
            let batch_mean = values.iter().sum::<Real>() / size as Real;
            let batch_m2 = values
                .iter()
                .map(|v| (v - batch_mean).powi(2))
                .sum::<Real>();
            let total = (count + size) as Real;
            let delta = batch_mean - mean[j];
            mean[j] += delta * size as Real / total;
            m2[j] += batch_m2 + delta * delta * count as Real * size as Real / total;
            values.sort_by(Real::total_cmp);
            interval[j].0 += weight * quantile(&values, 0.025);
            interval[j].1 += weight * quantile(&values, 0.975);
        }
        count += size;
        if let Some(progress) = progress {
            (progress.0)(size);
        }
        start = end;
    }
    let std = m2
        .iter()
        .map(|m| (m / (trials.max(2) - 1) as Real).sqrt())
        .collect();
    MonteCarlo {
        trials,
        mean,
        std,
        interval,
    }
}

/// The `p` quantile of sorted values (linear between order statistics, GUM-S1 §7.7 takes the
/// order statistics directly; the difference is below the Monte Carlo's own resolution).
fn quantile(sorted: &[Real], p: Real) -> Real {
    let at = p * (sorted.len() - 1) as Real;
    let (low, frac) = (at.floor() as usize, at - at.floor());
    let high = (low + 1).min(sorted.len() - 1);
    sorted[low] + frac * (sorted[high] - sorted[low])
}

/// The 99 % quantile of χ² with `k` degrees of freedom (Wilson–Hilferty, within 0.5 % for
/// k ≥ 3).
pub(crate) fn chi2_quantile_99(k: Real) -> Real {
    let z = 2.326_347_874;
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + z * a.sqrt()).powi(3)
}
