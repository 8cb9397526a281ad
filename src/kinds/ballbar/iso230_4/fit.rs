//! The joint fit of a model to the readings ([`CircleData::fit`]): the searched parameters in
//! turn (see `search.rs`), then the linear coefficients by least squares; and its result
//! ([`ModelFit`]). The fits run on a [`Blocks`] of the readings in normal-equation form
//! (`normal.rs`), so that fits of unions of the same blocks share what depends on the data
//! alone.

use super::blocks::Blocks;
use super::columns::{Column, Dense};
use super::linalg::{Projection, gram, gram_pinv};
use super::normal::{Fitter, NormalFit};
use super::profile::LagProfile;
use super::statics::angle_lag_derivative;
use super::{CircleData, Shape, Term, covered_arc, diagnostic_column};
use crate::math::Real;
use std::f64::consts::TAU;

/// The angle lag must reach this many standard uncertainties to be used: one parameter
/// tested, noise alone passes 0.27 % of the time, so traces whose angles are already the axes'
/// own (ℓ = 0) keep the columns they had.
const ANGLE_LAG_SIGNIFICANCE: Real = 3.0;
/// Both senses must cover this much arc (rad) for the angle lag: on a full circle its column
/// σ·(c_p·sin θ − c_q·cos θ) is orthogonal to lateral play (σ·|sin θ|, σ·|cos θ|), spikes and
/// servo mismatch; on a half circle σ·sin θ is lateral play of p.
const ANGLE_LAG_SPAN: Real = 350.0 * crate::math::RAD_PER_DEG;
/// Refits of the play at fixed shapes after its search (g ← |b|; each leaves the change in g
/// a few per cent of the last: the take-up is a few readings of each turn).
const PLAY_REFITS: usize = 3;

impl CircleData {
    /// Fits `terms` to the readings where `train` is true: the angle lag of the
    /// position-dependent terms ([`CircleData::angle_lag`]), every searched parameter (the
    /// reversal lag of each axis with a reversal term, then the searched terms' shapes in the
    /// order of `terms`; twice over when there are several, each with the others held), then
    /// the linear coefficients. With backlash the play is chosen too: the fit is done with the
    /// backlash as an instantaneous step and as real play (the columns taking up a gap equal to
    /// the fitted backlash, the searched parameters searched again in one refining pass from
    /// the step fit's values, g ← |b| refitted), and the
    /// one with the smaller residual sum of squares is kept; with backlash of both axes, also
    /// each axis back at the step. Residuals are given for every reading.
    pub fn fit(&self, terms: &[Term], train: &[bool]) -> ModelFit {
        let blocks = Blocks::training(self, train);
        self.fit_blocks(&blocks, terms, &[true, false])
    }

    /// [`CircleData::fit`] to the readings of the `included` blocks of `blocks` (made from
    /// these data): fits of unions of the same blocks (cross-validation folds) share the
    /// sums that depend on the data alone.
    pub fn fit_blocks(&self, blocks: &Blocks, terms: &[Term], included: &[bool]) -> ModelFit {
        Fitter::new(self, blocks, included.to_vec()).fit(terms)
    }

    /// The angle lag (s) the fit of `terms` to every reading of `blocks` uses
    /// ([`CircleData::angle_lag`]), for [`CircleData::fit_blocks_at_lag`] to hold in fits to
    /// parts of the trace.
    pub fn full_angle_lag(&self, blocks: &Blocks, terms: &[Term]) -> Real {
        Fitter::new(self, blocks, vec![true; blocks.count]).angle_lag(terms)
    }

    /// [`CircleData::fit_blocks`] with the angle lag held at `angle_lag` (s) instead of
    /// estimated from the fitted readings ([`CircleData::angle_lag`]): so that fits to parts
    /// of a trace (cross-validation folds, which hold out a sector and so never cover the full
    /// circle the estimate needs) use the servo model of the whole trace.
    pub fn fit_blocks_at_lag(
        &self,
        blocks: &Blocks,
        terms: &[Term],
        included: &[bool],
        angle_lag: Real,
    ) -> ModelFit {
        let mut fitter = Fitter::new(self, blocks, included.to_vec());
        fitter.held_angle_lag = Some(angle_lag);
        fitter.fit(terms)
    }

    /// The angle lag ℓ (s) of the position-dependent terms over `rows` (`y` the deviations
    /// there): how far the trace's angles lead the direction the axes actually reach, σ·v·ℓ/R.
    ///
    /// Derivation: a trace whose angles are the programmed ones at the sampling time (not
    /// timed from the machine's motion) runs the lagging axes' direction θ_a = θ − σ·v·ℓ/R,
    /// ℓ the common lag (1/K_v without feed-forward); the centre offset then reads
    /// c_p·cos θ_a + c_q·sin θ_a, which differs from the columns at θ by
    /// σ·(v·ℓ/R)·(c_p·sin θ − c_q·cos θ): opposite in the two senses, 0.2 µm for a 20 µm offset
    /// at 2000 mm/min on 100 mm with K_v = 33 s⁻¹, above a 0.1 µm noise. ℓ is estimated by
    /// Gauss–Newton on that column (two steps, the second from the first's ℓ), with the
    /// position-dependent and sense-dependent linear terms of `terms` beside it (the reversal
    /// terms are orthogonal to it over a full circle); it is used only when both senses of
    /// `rows` cover a full circle and the first step is significant (`ANGLE_LAG_SIGNIFICANCE`), and is
    /// kept within the reversal-lag search range. 0 otherwise, and without both centre terms.
    pub fn angle_lag(&self, terms: &[Term], rows: &[usize], y: &[Real]) -> Real {
        // Full circles in both senses among the rows fitted (a held-out sector breaks the
        // orthogonality the estimate rests on).
        let full = [1.0, -1.0].iter().all(|&sense| {
            let angles: Vec<Real> = rows
                .iter()
                .filter(|&&i| self.points[i].sense == sense)
                .map(|&i| self.points[i].angle)
                .collect();
            covered_arc(&angles).1 >= ANGLE_LAG_SPAN
        });
        if !full {
            return 0.0;
        }
        self.angle_lag_steps(terms, rows, y)
    }

    /// The Gauss–Newton steps of [`CircleData::angle_lag`] once both senses are full circles.
    fn angle_lag_steps(&self, terms: &[Term], rows: &[usize], y: &[Real]) -> Real {
        if !(terms.contains(&Term::CentreP) && terms.contains(&Term::CentreQ)) {
            return 0.0;
        }
        let base: Vec<Term> = terms
            .iter()
            .copied()
            .filter(|t| !t.searched() && t.reversal_axis().is_none())
            .collect();
        let rate = self.test.feed / self.test.radius;
        let mut lag = 0.0;
        for step in 0..2 {
            let shape = Shape {
                angle_lag: lag,
                ..Shape::default()
            };
            let mut columns = self.columns_on(&base, &shape, rows);
            let centre = Projection::new(columns.clone(), y).coefficients;
            let (cp, cq) = (
                coefficient(&base, Term::CentreP, &centre),
                coefficient(&base, Term::CentreQ, &centre),
            );
            // ∂/∂ℓ of c_p·cos θ_a + c_q·sin θ_a.
            columns.push(
                rows.iter()
                    .map(|&i| {
                        let p = &self.points[i];
                        let (s, c) = (p.angle - p.sense * rate * lag).sin_cos();
                        p.sense * rate * (cp * s - cq * c)
                    })
                    .collect(),
            );
            let views: Vec<&[Real]> = columns.iter().map(Vec::as_slice).collect();
            let covariance = gram_pinv(&gram(&views));
            let fit = Projection::new(columns, y);
            let k = fit.coefficients.len();
            let change = fit.coefficients[k - 1];
            if step == 0 {
                let variance = fit.rss / (rows.len().saturating_sub(k).max(1)) as Real;
                let u = (covariance[(k - 1, k - 1)] * variance).max(0.0).sqrt();
                if !(change.is_finite() && change.abs() >= ANGLE_LAG_SIGNIFICANCE * u && u > 0.0) {
                    return 0.0;
                }
            }
            if !change.is_finite() {
                break;
            }
            lag += change;
        }
        lag.clamp(self.ranges.lag.0, self.ranges.lag.1)
    }
}

impl Fitter<'_> {
    /// [`CircleData::fit`] over the fitted readings.
    pub(super) fn fit(&self, terms: &[Term]) -> ModelFit {
        let start = Shape {
            angle_lag: self.angle_lag(terms),
            ..Shape::default()
        };
        // The fits of the model at the shapes tried, each made once.
        let fits: std::cell::RefCell<Vec<(Shape, std::rc::Rc<NormalFit>)>> = Default::default();
        let fit_at = |shape: &Shape| -> std::rc::Rc<NormalFit> {
            if let Some((_, fit)) = fits.borrow().iter().find(|(s, _)| s == shape) {
                return fit.clone();
            }
            let fit = std::rc::Rc::new(self.project(&self.columns(terms, shape)));
            fits.borrow_mut().push((*shape, fit.clone()));
            fit
        };
        let step = self.search_shapes(terms, start, Passes::Full);
        let mut best = (step, fit_at(&step).rss);
        let mut mechanisms = Vec::new();
        let backlash: Vec<(usize, Term)> = [(0, Term::BacklashP), (1, Term::BacklashQ)]
            .into_iter()
            .filter(|(_, t)| terms.contains(t))
            .collect();
        let gaps = |shape: &Shape| -> [Real; 2] {
            let fit = fit_at(shape);
            let mut gaps = [0.0; 2];
            for &(axis, term) in &backlash {
                gaps[axis] = coefficient(terms, term, &fit.coefficients).abs();
            }
            gaps
        };
        let first = gaps(&step);
        if first.iter().any(|g| *g > 0.0) {
            let mut play = self.search_shapes(
                terms,
                Shape {
                    play: first,
                    ..step
                },
                Passes::Refine,
            );
            for _ in 0..PLAY_REFITS {
                let next = gaps(&play);
                let change = (0..2)
                    .map(|a| (next[a] - play.play[a]).abs())
                    .fold(0.0, Real::max);
                play.play = next;
                if change <= 1e-4 * next.iter().copied().fold(0.0, Real::max) {
                    break;
                }
            }
            let mut candidates = vec![play];
            if backlash.len() == 2 {
                for axis in 0..2 {
                    let mut mixed = play;
                    mixed.play[axis] = 0.0;
                    mixed.lag[axis] = step.lag[axis];
                    candidates.push(mixed);
                }
            }
            mechanisms.push(best);
            for candidate in candidates {
                let rss = fit_at(&candidate).rss;
                mechanisms.push((candidate, rss));
                if rss < best.1 {
                    best = (candidate, rss);
                }
            }
        }
        let shape = best.0;
        let columns = self.columns(terms, &shape);
        let coefficients = fit_at(&shape).coefficients.clone();
        let residuals = self.residuals(&columns, &coefficients);
        ModelFit {
            terms: terms.to_vec(),
            shape,
            coefficients,
            residuals,
            mechanisms,
        }
    }

    /// [`CircleData::angle_lag`] over the fitted readings, its columns (static columns at the
    /// angle lag, and the derivative in it) combinations of the table's static columns.
    fn angle_lag(&self, terms: &[Term]) -> Real {
        if let Some(lag) = self.held_angle_lag {
            return lag;
        }
        let full = (0..2)
            .all(|sense| TAU - self.blocks.largest_gap(sense, &self.included) >= ANGLE_LAG_SPAN);
        if !(full && terms.contains(&Term::CentreP) && terms.contains(&Term::CentreQ)) {
            return 0.0;
        }
        let test = &self.data.test;
        let base: Vec<Term> = terms
            .iter()
            .copied()
            .filter(|t| !t.searched() && t.reversal_axis().is_none())
            .collect();
        let mut lag = 0.0;
        for step in 0..2 {
            let shape = Shape {
                angle_lag: lag,
                ..Shape::default()
            };
            let mut columns = self.columns(&base, &shape);
            let centre = self.project(&columns).coefficients;
            let (cp, cq) = (
                coefficient(&base, Term::CentreP, &centre),
                coefficient(&base, Term::CentreQ, &centre),
            );
            // ∂/∂ℓ of c_p·cos θ_a + c_q·sin θ_a.
            columns.push(Column::dense(Dense::Mix(
                angle_lag_derivative((cp, cq), &shape, test).into(),
            )));
            let fit = self.project(&columns);
            let k = fit.coefficients.len();
            let change = fit.coefficients[k - 1];
            if step == 0 {
                let variance = fit.rss / (self.rows.len().saturating_sub(k).max(1)) as Real;
                let u = (fit.pinv[(k - 1, k - 1)] * variance).max(0.0).sqrt();
                if !(change.is_finite() && change.abs() >= ANGLE_LAG_SIGNIFICANCE * u && u > 0.0) {
                    return 0.0;
                }
            }
            if !change.is_finite() {
                break;
            }
            lag += change;
        }
        lag.clamp(self.data.ranges.lag.0, self.data.ranges.lag.1)
    }

    /// Every searched parameter of `terms` from `start` (its play and angle lag kept): the
    /// reversal lag of each axis with a reversal term, then the searched terms' shapes in the
    /// order of `terms`, each with the others held; with [`Passes::Full`] twice over when there
    /// are several (the first pass finds each period and lobe count afresh, the second refines
    /// them), with [`Passes::Refine`] once, refining.
    fn search_shapes(&self, terms: &[Term], start: Shape, passes: Passes) -> Shape {
        let mut shape = start;
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
        // The searched terms whose shapes hold a found value, held with the others.
        let mut done: Vec<Term> = match passes {
            Passes::Full => Vec::new(),
            Passes::Refine => terms.iter().copied().filter(|t| t.searched()).collect(),
        };
        let (first, passes) = match passes {
            Passes::Full if searches.len() > 1 => (0, 2),
            Passes::Full => (0, 1),
            Passes::Refine => (1, 2),
        };
        for pass in first..passes {
            for &search in &searches {
                match search {
                    Search::Lag(axis) => {
                        let (moving, fixed): (Vec<Term>, Vec<Term>) = terms
                            .iter()
                            .copied()
                            .partition(|t| t.reversal_axis() == Some(axis));
                        let columns = self.columns(&fixed, &shape);
                        let profile = LagProfile::new(self, axis, &moving, &columns, &shape);
                        shape.lag[axis] = self.search_lag(&profile);
                    }
                    Search::Shape(term) => {
                        let fixed_terms: Vec<Term> = linear
                            .iter()
                            .chain(done.iter().filter(|&&t| t != term))
                            .copied()
                            .collect();
                        let columns = self.columns(&fixed_terms, &shape);
                        self.search(term, &columns, &mut shape, pass > 0);
                        if !done.contains(&term) {
                            done.push(term);
                        }
                    }
                }
            }
        }
        shape
    }
}

/// The coefficient of the one-column `term` among `terms`' columns, 0 if it is not there.
fn coefficient(terms: &[Term], term: Term, coefficients: &[Real]) -> Real {
    let mut start = 0;
    for &t in terms {
        if t == term {
            return coefficients.get(start).copied().unwrap_or(0.0);
        }
        start += t.columns();
    }
    0.0
}

/// How [`Fitter::search_shapes`] goes over the searched parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Passes {
    /// From scratch: periods from the periodogram, every lobe count; twice over when there
    /// are several searched parameters.
    Full,
    /// From shapes a full search found (the play search: the same model with the backlash
    /// taking up its gap): once, refining the periods and lobe counts about their values.
    Refine,
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
    /// The backlash mechanisms the fit compared, each with its searched shape and residual sum
    /// of squares (m²): the step, the gap taken up and, with backlash of both axes, each axis
    /// back at the step. An axis's lag is known only across those the trace does not tell from
    /// the chosen one ([`CircleData::locate_lag`]). Empty without backlash.
    pub mechanisms: Vec<(Shape, Real)>,
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
