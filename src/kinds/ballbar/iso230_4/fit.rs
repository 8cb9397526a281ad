//! The joint fit of a model to the readings ([`CircleData::fit`]): the searched parameters in
//! turn (see `search.rs`), then the linear coefficients by least squares; and its result
//! ([`ModelFit`]).

use super::linalg::Projection;
use super::{CircleData, Shape, Term, diagnostic_column};
use crate::math::Real;

impl CircleData {
    /// Fits `terms` to the readings where `train` is true: every searched parameter (the
    /// reversal lag of each axis with a reversal term, then the searched terms' shapes in the
    /// order of `terms`; twice over when there are several, each with the others held), then
    /// the linear coefficients. Residuals are given for every reading.
    pub fn fit(&self, terms: &[Term], train: &[bool]) -> ModelFit {
        let rows: Vec<usize> = (0..self.len()).filter(|&i| train[i]).collect();
        let y: Vec<Real> = rows.iter().map(|&i| self.deviation[i]).collect();
        let mut shape = Shape::default();
        let mut searches: Vec<Search> = (0..2)
            .filter(|&a| terms.iter().any(|t| t.reversal_axis() == Some(a)))
            .map(Search::Lag)
            .collect();
        searches.extend(
            terms
                .iter()
                .copied()
                .filter(|t| t.searched())
                .map(Search::Shape),
        );
        let linear: Vec<Term> = terms.iter().copied().filter(|t| !t.searched()).collect();
        let mut done: Vec<Term> = Vec::new();
        let passes = if searches.len() > 1 { 2 } else { 1 };
        for pass in 0..passes {
            for &search in &searches {
                match search {
                    Search::Lag(axis) => {
                        let (fixed, moving) = self.split_reversal(axis, terms, &shape, &rows, &y);
                        let profile = self.lag_profile(axis, &moving, &fixed, &rows, &shape);
                        shape.lag[axis] = self.search_lag(&profile);
                    }
                    Search::Shape(term) => {
                        let fixed_terms: Vec<Term> = linear
                            .iter()
                            .chain(done.iter().filter(|&&t| t != term))
                            .copied()
                            .collect();
                        let fixed =
                            Projection::new(self.columns_on(&fixed_terms, &shape, &rows), &y);
                        self.search(term, &fixed, &rows, &mut shape, pass > 0);
                        if !done.contains(&term) {
                            done.push(term);
                        }
                    }
                }
            }
        }
        let all: Vec<usize> = (0..self.len()).collect();
        let columns = self.columns_on(terms, &shape, &all);
        let training: Vec<Vec<Real>> = columns
            .iter()
            .map(|c| rows.iter().map(|&i| c[i]).collect())
            .collect();
        let coefficients = Projection::new(training, &y).coefficients;
        let residuals = (0..self.len())
            .map(|i| {
                self.deviation[i]
                    - columns
                        .iter()
                        .zip(&coefficients)
                        .map(|(c, k)| c[i] * k)
                        .sum::<Real>()
            })
            .collect();
        ModelFit {
            terms: terms.to_vec(),
            shape,
            coefficients,
            residuals,
        }
    }
}

/// A searched parameter of a fit: an axis's reversal lag or a searched term's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Search {
    Lag(usize),
    Shape(Term),
}

/// A fitted model of the radial deviation.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelFit {
    /// The terms, in column order.
    pub terms: Vec<Term>,
    /// The searched parameters (meaningful for the searched terms present).
    pub shape: Shape,
    /// Every column's coefficient (SI), terms in order.
    pub coefficients: Vec<Real>,
    /// Measured − predicted for every reading (m).
    pub residuals: Vec<Real>,
}

impl ModelFit {
    /// The radial deviation `term` accounts for at each point of `data` (m), if it is in the
    /// fit: its columns times its coefficients. Over every term of the fit these and the
    /// residuals add up to the measured deviations.
    pub fn contribution(&self, term: Term, data: &CircleData) -> Option<Vec<Real>> {
        let coefficients = self.coefficients_of(term)?;
        Some(
            data.points
                .iter()
                .map(|at| {
                    coefficients
                        .iter()
                        .enumerate()
                        .map(|(k, c)| c * diagnostic_column(term, k, at, &data.test, &self.shape))
                        .sum()
                })
                .collect(),
        )
    }

    /// The coefficients of `term`, if it is in the fit.
    pub fn coefficients_of(&self, term: Term) -> Option<&[Real]> {
        let mut start = 0;
        for &t in &self.terms {
            let end = start + t.columns();
            if t == term {
                return Some(&self.coefficients[start..end]);
            }
            start = end;
        }
        None
    }
}
