//! The kinematic calibration as a discovery problem ([`Calibration`]): the readings
//! linearised once on the twin's exact chain, each test's own set-up profiled out, and every
//! fit a weighted least squares on the columns of the base and the terms asked for.

use super::library::{DRIFT_NUISANCE, Term};
use crate::discovery::engine::{self, Folds, Parameters, Problem};
use crate::estimate::Readings;
use crate::estimate::fit::{self, EstimateError};
use crate::estimate::identifiability;
use crate::estimate::spec::ParameterSet;
use crate::machine::{Machine, Workspace};
use crate::math::Real;
use mtwin_kernels::linalg;
use nalgebra::{DMatrix, DVector};

/// A fit: the columns it used and their values (solver units).
#[derive(Clone, Debug)]
pub struct Fit {
    columns: Vec<usize>,
    beta: Vec<Real>,
    /// The number of directions the columns identify on the fit's readings.
    rank: usize,
}

/// The readings of a calibration prepared for model selection.
///
/// With `J` the weighted design of every unknown at the start (forward differences on the
/// exact chain, [`fit::start_design`]) and `y = (measured − predicted)/σ` there, the model
/// with columns `S` predicts `y ≈ J_S z`: the readings are linear in the errors to about
/// 1e-5 at these sizes ([`crate::estimate::fit`]), far below any gain a term must show.
/// Each group's own set-up unknowns (a K-test's zero; a sphere's centre, probed at several
/// tilts, is shared by its groups and fitted with the model) are projected out of its rows once ([`fit::project_off`], group by group), so
/// a group held out is predicted from the other groups' fit with only its own set-up taken
/// from itself, as any model must. The projected cross products are summed per group, so a
/// fold's fit adds the groups it keeps.
pub struct Calibration {
    /// `y` projected, group by group (weighted, dimensionless).
    y: DVector<Real>,
    /// The model columns projected, group by group (weighted, per solver unit).
    x: DMatrix<Real>,
    /// Per group: `XᵀX` and `Xᵀy` of its projected rows.
    grams: Vec<(DMatrix<Real>, DVector<Real>)>,
    /// Their sums over every group.
    total: (DMatrix<Real>, DVector<Real>),
    /// The group of each reading.
    group_of: Vec<usize>,
    folds: Folds,
    /// The base model's columns.
    base: Vec<usize>,
    /// Each term of the library with its columns.
    terms: Vec<(Term, Vec<usize>)>,
    /// The set-up unknowns profiled out, over all groups.
    profiled: usize,
    /// The mean standard uncertainty of a reading (m): residuals are reported in metres
    /// at this weight.
    sigma: Real,
    /// The singular-value cut of the identifiability analysis.
    options: identifiability::Options,
}

impl Calibration {
    /// Prepares `sets` on `machine` for model selection from the `base` parameters among
    /// `terms`; `full` is the parameter set of the base and every term together.
    pub fn new(
        machine: &Machine,
        base: &ParameterSet,
        full: &ParameterSet,
        terms: &[Term],
        sets: &[Readings],
    ) -> Result<Calibration, EstimateError> {
        let problem = fit::Problem::new(machine, full, sets)?;
        let design = fit::start_design(&problem);
        if !design.iter().all(|v| v.is_finite()) {
            return Err(EstimateError::Solver(
                "the design is not finite (an uncertainty too small, or positions beyond the chain's range)".into(),
            ));
        }
        let n = problem.rows();
        let mut r0 = vec![0.0; n];
        problem.residuals(
            &vec![0.0; problem.unknowns()],
            &problem.measured(),
            &mut Workspace::new(machine),
            &mut r0,
        );
        // Groups: (set, the model's group), numbered in the order met (a key's lookup is
        // linear in the groups, a few dozen).
        let mut keys: Vec<(usize, usize)> = Vec::new();
        let mut group_of = Vec::with_capacity(n);
        for (k, set) in sets.iter().enumerate() {
            for i in 0..set.len() {
                let key = (k, set.model.group(i));
                let g = match keys.iter().position(|x| *x == key) {
                    Some(g) => g,
                    None => {
                        keys.push(key);
                        keys.len() - 1
                    }
                };
                group_of.push(g);
            }
        }
        let groups = keys.len();
        // Columns: the parameters by label, then the nuisances: a drift rate's belong to the
        // drift term, one group's own are profiled out, the others are the base's.
        let labels = problem.labels();
        let column_of = |label: &str| labels[..full.len()].iter().position(|l| l == label);
        let mut base_columns: Vec<usize> = Vec::new();
        for label in &base.labels {
            base_columns.push(column_of(label).ok_or_else(|| {
                EstimateError::Solver(format!("{label}: not among the library's columns"))
            })?);
        }
        let mut drift_columns = Vec::new();
        let mut own: Vec<Vec<usize>> = vec![Vec::new(); groups];
        let mut at = full.len();
        for set in sets {
            for quantity in &set.nuisance {
                let j = at;
                at += 1;
                if quantity.name.starts_with(DRIFT_NUISANCE) {
                    drift_columns.push(j);
                    continue;
                }
                let touched: Vec<usize> = (0..n)
                    .filter(|&i| design[(i, j)] != 0.0)
                    .map(|i| group_of[i])
                    .collect();
                match touched.first() {
                    Some(&g) if touched.iter().all(|&h| h == g) => own[g].push(j),
                    Some(_) => base_columns.push(j),
                    None => {}
                }
            }
        }
        // A drift rate the base asks for (`--drift=rate`) is the base's.
        if !terms.contains(&Term::Drift) {
            base_columns.append(&mut drift_columns);
        }
        let mut columns: Vec<usize> = base_columns.clone();
        let mut term_columns = Vec::new();
        for &term in terms {
            let cols: Vec<usize> = match term {
                Term::Drift => drift_columns.clone(),
                _ => term
                    .labels()
                    .iter()
                    .map(|l| {
                        column_of(l).ok_or_else(|| {
                            EstimateError::Solver(format!("{l}: not among the library's columns"))
                        })
                    })
                    .collect::<Result<_, _>>()?,
            };
            for &c in &cols {
                if !columns.contains(&c) {
                    columns.push(c);
                }
            }
            term_columns.push((term, cols));
        }
        // The model's columns, renumbered, and every group's rows projected off its own
        // set-up.
        let index = |j: usize| columns.iter().position(|&c| c == j).expect("listed");
        let m = columns.len();
        let mut x = DMatrix::from_fn(n, m, |i, c| design[(i, columns[c])]);
        let mut y = DVector::from_fn(n, |i, _| -r0[i]);
        let mut profiled = 0;
        let rows_of: Vec<Vec<usize>> = (0..groups)
            .map(|g| (0..n).filter(|&i| group_of[i] == g).collect())
            .collect();
        for g in 0..groups {
            let rows = &rows_of[g];
            let nuisance = DMatrix::from_fn(rows.len(), own[g].len(), |r, c| {
                design[(rows[r], own[g][c])]
            });
            // The group's model columns and `y` side by side, projected off its own set-up.
            let block = DMatrix::from_fn(rows.len(), m + 1, |r, c| {
                if c < m { x[(rows[r], c)] } else { y[rows[r]] }
            });
            let (block, rank) = fit::project_off(nuisance, block);
            profiled += rank;
            for (r, &i) in rows.iter().enumerate() {
                for c in 0..m {
                    x[(i, c)] = block[(r, c)];
                }
                y[i] = block[(r, m)];
            }
        }
        let grams: Vec<(DMatrix<Real>, DVector<Real>)> = rows_of
            .iter()
            .map(|rows| {
                let xg = DMatrix::from_fn(rows.len(), m, |r, c| x[(rows[r], c)]);
                let yg = DVector::from_fn(rows.len(), |r, _| y[rows[r]]);
                (xg.transpose() * &xg, xg.transpose() * yg)
            })
            .collect();
        let mut total = (DMatrix::zeros(m, m), DVector::zeros(m));
        for (gram, moment) in &grams {
            total.0 += gram;
            total.1 += moment;
        }
        let sigma = sets.iter().flat_map(|s| &s.sigma).sum::<Real>() / n.max(1) as Real;
        Ok(Calibration {
            y,
            x,
            grams,
            total,
            folds: Folds::leave_one_group_out(&group_of, "leave-one-test-out"),
            group_of,
            base: base_columns.iter().map(|&j| index(j)).collect(),
            terms: term_columns
                .into_iter()
                .map(|(t, cols)| (t, cols.into_iter().map(index).collect()))
                .collect(),
            profiled,
            sigma,
            options: identifiability::Options::default(),
        })
    }

    /// The number of groups (K-tests, a probed sphere's tilts) held out in turn.
    pub fn groups(&self) -> usize {
        self.grams.len()
    }

    /// The columns of the base and `effects`, sorted.
    fn columns(&self, effects: &[Term]) -> Vec<usize> {
        let mut columns = self.base.clone();
        for effect in effects {
            let (_, cols) = self
                .terms
                .iter()
                .find(|(t, _)| t == effect)
                .expect("a term of the library");
            columns.extend(cols);
        }
        columns.sort_unstable();
        columns.dedup();
        columns
    }

    /// The least-squares fit on `columns` of the cross products `(gram, moment)`: the
    /// minimum-norm solution over the directions the identifiability analysis keeps.
    fn solve(&self, columns: &[usize], gram: &DMatrix<Real>, moment: &DVector<Real>) -> Fit {
        let k = columns.len();
        let a = DMatrix::from_fn(k, k, |r, c| gram[(columns[r], columns[c])]);
        let b = DVector::from_fn(k, |r, _| moment[columns[r]]);
        let eigen = linalg::symmetric_eigen(a);
        let largest = eigen.eigenvalues.max().max(0.0);
        let cut = self.options.tolerance(largest.sqrt()).powi(2);
        let mut beta = DVector::zeros(k);
        let mut rank = 0;
        for (i, &lambda) in eigen.eigenvalues.iter().enumerate() {
            if lambda > cut {
                let v = eigen.eigenvectors.column(i);
                beta += v * (v.dot(&b) / lambda);
                rank += 1;
            }
        }
        Fit {
            columns: columns.to_vec(),
            beta: beta.iter().copied().collect(),
            rank,
        }
    }

    /// The fit of the base and `effects` to every reading.
    pub(super) fn fit_all(&self, effects: &[Term]) -> Fit {
        self.solve(&self.columns(effects), &self.total.0, &self.total.1)
    }

    /// Whether `term` adds a direction the model with `effects` cannot take: its columns
    /// raise the identified rank on every reading.
    pub(super) fn acts(&self, effects: &[Term], term: Term) -> bool {
        self.fit_all(&with(effects, term)).rank > self.fit_all(effects).rank
    }

    /// The weighted residual sum of squares of `fit` on every reading.
    fn sum_of_squares(&self, fit: &Fit) -> Real {
        let (gram, moment) = &self.total;
        let yy = self.y.norm_squared();
        let mut xb = 0.0;
        let mut bxxb = 0.0;
        for (r, &i) in fit.columns.iter().enumerate() {
            xb += moment[i] * fit.beta[r];
            for (c, &j) in fit.columns.iter().enumerate() {
                bxxb += fit.beta[r] * gram[(i, j)] * fit.beta[c];
            }
        }
        yy - 2.0 * xb + bxxb
    }

    /// The evidence in the residual of `fit` (the model's fit to every reading) that points
    /// to a term whose fit with the model is `bigger`: it lowers the weighted sum of squares
    /// by more than four times what one noise-only direction would (F ≥ 4 per added
    /// direction). With the evidence, the drop of the sum of squares (for the order).
    fn evidence(&self, fit: &Fit, bigger: &Fit) -> Option<(String, Real)> {
        let added = bigger.rank.checked_sub(fit.rank).filter(|&d| d > 0)?;
        let (ss0, ss1) = (self.sum_of_squares(fit), self.sum_of_squares(bigger));
        let dof = self
            .y
            .len()
            .checked_sub(bigger.rank + self.profiled)
            .filter(|&d| d > 0)?;
        let f = (ss0 - ss1) / added as Real / (ss1 / dof as Real);
        (f >= 4.0).then(|| {
            let text = format!(
                "fitted to every reading it takes {:.1} % of the residual sum of squares (F = {f:.1} for {added} direction{})",
                100.0 * (ss0 - ss1) / ss0,
                if added == 1 { "" } else { "s" }
            );
            (text, ss0 - ss1)
        })
    }

    /// The library's terms.
    pub fn terms(&self) -> impl Iterator<Item = Term> + '_ {
        self.terms.iter().map(|(t, _)| *t)
    }
}

impl Problem for Calibration {
    type Effect = Term;
    type Fit = Fit;

    fn id(&self, effect: Term) -> String {
        effect.id()
    }

    fn n_samples(&self) -> usize {
        self.y.len()
    }

    fn folds(&self) -> &Folds {
        &self.folds
    }

    fn fit(&self, effects: &[Term], train: &[bool]) -> Fit {
        let columns = self.columns(effects);
        // Groups wholly out of the training set are taken off the sums; one partly out is
        // summed row by row (the engine's folds are whole groups).
        let mut kept = vec![0usize; self.grams.len()];
        let mut sizes = vec![0usize; self.grams.len()];
        for (i, &g) in self.group_of.iter().enumerate() {
            sizes[g] += 1;
            kept[g] += usize::from(train[i]);
        }
        let (mut gram, mut moment) = self.total.clone();
        for g in 0..self.grams.len() {
            if kept[g] == sizes[g] {
                continue;
            }
            gram -= &self.grams[g].0;
            moment -= &self.grams[g].1;
            if kept[g] > 0 {
                for (i, _) in
                    (self.group_of.iter().enumerate()).filter(|(i, h)| **h == g && train[*i])
                {
                    let row = self.x.row(i);
                    gram += row.transpose() * row;
                    moment += row.transpose() * self.y[i];
                }
            }
        }
        self.solve(&columns, &gram, &moment)
    }

    fn residuals(&self, fit: &Fit) -> Vec<Real> {
        let mut r = self.y.clone();
        for (&c, &b) in fit.columns.iter().zip(&fit.beta) {
            r.axpy(-b, &self.x.column(c), 1.0);
        }
        r.iter().map(|v| v * self.sigma).collect()
    }

    fn proposals(&self, effects: &[Term], fit: &Fit) -> Vec<(Term, String)> {
        // `fit` is the model's fit to every reading: each open term is fitted with it once,
        // for whether it acts at all and for the evidence that points to it.
        let mut pointed: Vec<(Term, String, Real)> = Vec::new();
        let mut others = Vec::new();
        for term in self.terms().filter(|t| !effects.contains(t)) {
            let bigger = self.fit_all(&with(effects, term));
            if bigger.rank <= fit.rank {
                continue;
            }
            match self.evidence(fit, &bigger) {
                Some((text, gain)) => pointed.push((term, text, gain)),
                None => others.push((term, engine::NO_DIAGNOSTIC.to_string())),
            }
        }
        pointed.sort_by(|a, b| b.2.total_cmp(&a.2));
        pointed
            .into_iter()
            .map(|(t, e, _)| (t, e))
            .chain(others)
            .collect()
    }

    fn parameters(&self, fit: &Fit) -> Option<Parameters> {
        Some(Parameters {
            count: fit.rank + self.profiled,
            grid: 1.0,
        })
    }
}

/// `effects` and `term`.
fn with(effects: &[Term], term: Term) -> Vec<Term> {
    effects.iter().copied().chain([term]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::errors::ErrorModel;
    use crate::estimate::{Quantity, ReadingModel};
    use crate::machine::{Axis, AxisValues, MachineState};
    use crate::math::{seeded_rng, standard_normal};

    /// Readings of the actual tool tip relative to the workpiece (x, y, z) at poses of C every
    /// 30° at three angles of A, each tilt a group with its own offset (three nuisances): a
    /// reading model as plain as a test needs, on the twin's chain.
    struct Tip {
        poses: Vec<(MachineState, usize)>,
    }

    impl ReadingModel for Tip {
        fn predict(
            &self,
            machine: &Machine,
            workspace: &mut Workspace,
            errors: &ErrorModel,
            nuisance: &[Real],
            _setup: &[Real],
            out: &mut [Real],
        ) {
            for (i, (state, group)) in self.poses.iter().enumerate() {
                let tip = errors
                    .workpiece_from_tool(machine, workspace, state)
                    .translation;
                for c in 0..3 {
                    out[3 * i + c] = tip.to_array()[c] + nuisance[3 * group + c];
                }
            }
        }

        fn per_row(&self) -> usize {
            3
        }

        fn group(&self, i: usize) -> usize {
            self.poses[i / 3].1
        }
    }

    /// [`Tip`] on trunnion5 with `measured` in place of measurements, as a calibration from
    /// the location errors with two terms.
    fn calibration(measured: impl Fn(usize) -> Real) -> Calibration {
        let machine = Machine::from_urdf_file(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/models/trunnion5.urdf"
        ))
        .unwrap();
        let mut poses = Vec::new();
        for group in 0..3 {
            for k in 0..12 {
                let mut at = AxisValues::ZERO;
                at[Axis::X] = 0.3;
                at[Axis::Y] = 0.25;
                at[Axis::Z] = 0.2;
                at[Axis::A] = -(15.0 * group as Real).to_radians();
                at[Axis::C] = (30.0 * k as Real).to_radians();
                poses.push((MachineState::at(at), group));
            }
        }
        let n = 3 * poses.len();
        let set = Readings {
            source: "tip".into(),
            kind: "tip",
            machine: None,
            measured: (0..n).map(measured).collect(),
            sigma: vec![1e-6; n],
            nuisance: (0..9)
                .map(|k| Quantity {
                    name: format!("offset{}.{}", k / 3, k % 3),
                    translation: true,
                    start: 0.0,
                    uncertainty: 0.0,
                })
                .collect(),
            setup: Vec::new(),
            model: Box::new(Tip { poses }),
        };
        let base = ParameterSet::parse("location", &machine).unwrap();
        let full =
            ParameterSet::parse("location,EXC.harmonic[2],ECC.harmonic[1]", &machine).unwrap();
        let terms = [
            Term::Order {
                name: "EXC".parse().unwrap(),
                order: 2,
            },
            Term::Order {
                name: "ECC".parse().unwrap(),
                order: 1,
            },
        ];
        Calibration::new(&machine, &base, &full, &terms, &[set]).unwrap()
    }

    fn noise(seed: u64) -> impl Fn(usize) -> Real {
        let mut rng = seeded_rng(seed, "discover problem test");
        let values: Vec<Real> = (0..10_000)
            .map(|_| 1e-6 * standard_normal(&mut rng))
            .collect();
        move |i| values[i]
    }

    /// A fold's fit by the sums of the groups it keeps is the least squares on its training
    /// rows, solved directly (the SVD pseudo-inverse of the training rows' columns, with the
    /// identifiability analysis's cut): the same values to 1e-9 of their size, the same rank.
    #[test]
    fn a_folds_fit_is_the_least_squares_of_its_training_rows() {
        let problem = calibration(noise(1));
        let effects: Vec<Term> = problem.terms().collect();
        let train = problem.folds.training(1);
        let fit = problem.fit(&effects, &train);
        let rows: Vec<usize> = (0..train.len()).filter(|&i| train[i]).collect();
        let x = DMatrix::from_fn(rows.len(), fit.columns.len(), |r, c| {
            problem.x[(rows[r], fit.columns[c])]
        });
        let y = DVector::from_fn(rows.len(), |r, _| problem.y[rows[r]]);
        let svd = linalg::svd(x, true, true);
        let cut = problem.options.tolerance(svd.singular_values.max());
        let kept = svd.singular_values.iter().filter(|&&s| s > cut).count();
        let direct = linalg::svd_solve(&svd, &y, cut).unwrap();
        let size = direct.amax();
        for (a, b) in fit.beta.iter().zip(direct.iter()) {
            assert!((a - b).abs() <= 1e-9 * size, "{a} against {b}");
        }
        assert_eq!(fit.rank, kept);
    }

    /// No reading of a held-out group reaches its fold's fit: readings changed in group 1
    /// only (by a shape no zero takes, 3 µm·sin i) leave the fold holding it out as it was and
    /// change the fit to all by more than 1e-3 µm. "As it was": to 1e-8 of a value, the
    /// round-off of taking the group's cross products off the sums (1e-16 times the condition
    /// number of the fold's normal matrix, below 1e8 here), five orders below what the change
    /// would bring if it leaked.
    #[test]
    fn a_held_out_group_does_not_reach_its_folds_fit() {
        let first = noise(2);
        let before = calibration(&first);
        let group_1: Vec<bool> = before.group_of.iter().map(|&g| g == 1).collect();
        let after = calibration(|i| {
            first(i)
                + if group_1[i] {
                    3e-6 * (i as Real).sin()
                } else {
                    0.0
                }
        });
        let effects: Vec<Term> = before.terms().collect();
        let train = before.folds.training(1);
        let (a, b) = (before.fit(&effects, &train), after.fit(&effects, &train));
        for (a, b) in a.beta.iter().zip(&b.beta) {
            assert!((a - b).abs() <= 1e-8 * a.abs().max(1.0), "{a} against {b}");
        }
        let all = vec![true; train.len()];
        let (a, b) = (before.fit(&effects, &all), after.fit(&effects, &all));
        assert!(
            a.beta
                .iter()
                .zip(&b.beta)
                .any(|(a, b)| (a - b).abs() > 1e-3)
        );
    }
}
