//! The design of the stacked problem: its weighted Jacobian at the start, from the readings'
//! own sensitivities or by forward differences, and the set-up quantities' sensitivities.

use super::{Problem, STEP};
use crate::machine::Workspace;
use crate::math::Real;
use nalgebra::DMatrix;
use rayon::prelude::*;

impl Problem<'_> {
    /// The weighted design `∂r/∂(B w)` at `z` along the directions `basis` (columns in solver
    /// units; the identity for the full design), by forward differences of the exact chain
    /// (step 0.01 µm). Columns are computed in parallel; each is independent, so the result
    /// does not depend on the thread count.
    pub fn design(&self, z: &[Real], basis: &DMatrix<Real>) -> DMatrix<Real> {
        let rows = self.rows;
        let mut base = vec![0.0; rows];
        self.predict(z, &[], &mut Workspace::new(self.machine), &mut base);
        let columns: Vec<Vec<Real>> = (0..basis.ncols())
            .into_par_iter()
            .map_init(
                || Workspace::new(self.machine),
                |workspace, k| {
                    let shifted: Vec<Real> = z
                        .iter()
                        .enumerate()
                        .map(|(i, v)| v + STEP * basis[(i, k)])
                        .collect();
                    let mut column = vec![0.0; rows];
                    self.predict(&shifted, &[], workspace, &mut column);
                    for (c, b) in column.iter_mut().zip(&base) {
                        *c = (*c - b) / STEP;
                    }
                    self.weigh(&mut column);
                    column
                },
            )
            .collect();
        DMatrix::from_fn(rows, basis.ncols(), |i, k| columns[k][i])
    }

    /// The weighted design at the start from every set's own sensitivities, in solver units
    /// (a free coefficient's column with its ties'); `None` when a set gives none or a
    /// nuisance does not start at zero.
    fn analytic_start_design(&self) -> Option<DMatrix<Real>> {
        let k = self.parameters.len();
        if self.starts[k..].iter().any(|s| *s != 0.0) {
            return None;
        }
        let template = &self.parameters.model;
        let mut design = DMatrix::zeros(self.rows, self.unknowns());
        let mut workspace = Workspace::new(self.machine);
        for (s, set) in self.sets.iter().enumerate() {
            let (of_errors, of_nuisances) = set.model.sensitivities(
                self.machine,
                &mut workspace,
                template,
                set.nuisance.len(),
            )?;
            let at = self.row_at[s];
            for (i, sigma) in set.sigma.iter().enumerate() {
                for j in 0..k {
                    let mut value = of_errors[(i, self.parameters.free[j])];
                    for tie in &self.parameters.tied[j] {
                        value += tie.factor * of_errors[(i, tie.coefficient)];
                    }
                    design[(at + i, j)] = value * self.scales[j] / sigma;
                }
                for q in 0..set.nuisance.len() {
                    let j = self.nuisance_at[s] + q;
                    design[(at + i, j)] = of_nuisances[(i, q)] * self.scales[j] / sigma;
                }
            }
        }
        Some(design)
    }

    /// The weighted sensitivity of the readings to each known set-up quantity times its
    /// standard uncertainty, at `z` (rows × quantities, in the order of the sets and their
    /// `setup`): central differences of the exact chain with a step of the quantity's own
    /// uncertainty, so a quantity that enters at second order only (a ball-bar's centre off
    /// its plane) has none, as the linearised model has it.
    pub fn setup_design(&self, z: &[Real]) -> DMatrix<Real> {
        let quantities: Vec<(usize, usize, Real)> = (self.sets.iter().enumerate())
            .flat_map(|(k, set)| {
                (set.setup.iter().enumerate())
                    .map(move |(q, quantity)| (k, q, quantity.uncertainty))
            })
            .filter(|(_, _, u)| *u > 0.0)
            .collect();
        let rows = self.rows;
        let mut workspace = Workspace::new(self.machine);
        let mut columns = Vec::with_capacity(quantities.len());
        for &(k, q, u) in &quantities {
            let mut offsets: Vec<Vec<Real>> = vec![Vec::new(); self.sets.len()];
            offsets[k] = vec![0.0; self.sets[k].setup.len()];
            let (mut plus, mut minus) = (vec![0.0; rows], vec![0.0; rows]);
            offsets[k][q] = u;
            self.predict(z, &offsets, &mut workspace, &mut plus);
            offsets[k][q] = -u;
            self.predict(z, &offsets, &mut workspace, &mut minus);
            let mut column: Vec<Real> = plus
                .iter()
                .zip(&minus)
                .map(|(p, m)| 0.5 * (p - m))
                .collect();
            self.weigh(&mut column);
            columns.push(column);
        }
        DMatrix::from_fn(rows, columns.len(), |i, c| columns[c][i])
    }
}

/// The design at the start (the linearisation), for identifiability and test design: needs
/// no measured values. From the readings' own first-order sensitivities when every set gives
/// them ([`crate::estimate::ReadingModel::sensitivities`]: one pass of the chain per reading), else by
/// forward differences.
pub fn start_design(problem: &Problem<'_>) -> DMatrix<Real> {
    let n = problem.unknowns();
    problem
        .analytic_start_design()
        .unwrap_or_else(|| problem.design(&vec![0.0; n], &DMatrix::identity(n, n)))
}

/// The design at the start with the set-up unknowns profiled out: the error-coefficient
/// columns projected onto the complement of the nuisance columns, `(I − P_ν) J_θ`, whose
/// normal matrix `J_θᵀ (I − P_ν) J_θ` is the information the readings hold on the errors
/// whatever the set-up. Designs of separate tests profiled this way stack: their nuisances
/// are their own. (For test design: the candidate tests share the error columns only.)
pub fn profiled_design(problem: &Problem<'_>) -> DMatrix<Real> {
    let design = start_design(problem);
    let k = problem.parameters.len();
    let theta = design.columns(0, k).into_owned();
    let nuisance = design.columns(k, design.ncols() - k).into_owned();
    project_off(nuisance, theta).0
}

/// `columns` projected onto the complement of the column space of `nuisance` (same rows),
/// `(I − P_ν)·columns`, and the rank of `nuisance` (singular values above 1e-10 of the
/// largest): what the readings say whatever the nuisances, and how many they take.
pub fn project_off(nuisance: DMatrix<Real>, columns: DMatrix<Real>) -> (DMatrix<Real>, usize) {
    if nuisance.ncols() == 0 {
        return (columns, 0);
    }
    let svd = mtwin_kernels::linalg::svd(nuisance, true, false);
    let u = svd.u.expect("asked for U");
    let largest = svd.singular_values.max();
    let kept: Vec<usize> = (0..svd.singular_values.len())
        .filter(|i| svd.singular_values[*i] > largest * 1e-10)
        .collect();
    let q = DMatrix::from_fn(u.nrows(), kept.len(), |i, c| u[(i, kept[c])]);
    let projection = q.transpose() * &columns;
    (columns - q * projection, kept.len())
}
