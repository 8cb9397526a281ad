//! The diagnostics ([`Diagnostics`]): the joint fit of the ISO terms these data can give, the
//! reversal lags and the significant searched terms' shapes and phases, and every estimate's
//! standard uncertainty ([`TermEstimate`]).

use super::lag::{LAG_SET, LagLocation, rival_mechanisms};
use super::linalg::{gram, gram_pinv};
use super::model::{spike, take_up_arc};
use super::report::lag_key;
use super::{BasisPoint, CircleData, CircularTest, MIN_DIAGNOSTIC_READINGS, ModelFit, Shape, Term};
use crate::machine::Plane;
use crate::math::{M_PER_UM, Real};
use nalgebra::DMatrix;
use std::f64::consts::TAU;

/// One diagnostic's estimate, in the term's SI unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TermEstimate {
    /// The value (the amplitude for a cyclic term).
    pub value: Real,
    /// Its standard uncertainty.
    pub u: Real,
    /// A spike's decay (s) or a cyclic term's period (m) and its uncertainty, when the
    /// amplitude is significant: above √(2·ln(M/0.05)) u for the M shapes searched, about
    /// 4.5 u ([`CircleData::significance`]).
    pub shape: Option<(Real, Real)>,
    /// A cyclic term's phase φ (rad) and its uncertainty, when significant.
    pub phase: Option<(Real, Real)>,
}

/// The diagnostic fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostics {
    /// Every identifiable diagnostic, in the order of [`Term::DIAGNOSTICS`].
    pub estimates: Vec<(Term, TermEstimate)>,
    /// The reversal lag of p and q (s) and its standard uncertainty, when some reversal term
    /// of the axis (backlash, lateral play, spike) is significant.
    pub reversal_lag: [Option<(Real, Real)>; 2],
    /// The diagnostics the data cannot give, with the reason.
    pub unidentifiable: Vec<(Term, String)>,
    /// Remarks (amplitudes that are not significant).
    pub notes: Vec<String>,
    /// RMS of the residual (m).
    pub rms: Real,
    /// n − fitted parameters.
    pub dof: usize,
    /// The fit itself.
    pub fit: ModelFit,
}

impl Diagnostics {
    /// The estimate of `term`, if identifiable.
    pub fn get(&self, term: Term) -> Option<&TermEstimate> {
        self.estimates
            .iter()
            .find(|(t, _)| *t == term)
            .map(|(_, e)| e)
    }
}

/// The joint diagnostic fit with identifiability checks and uncertainties.
pub(super) fn diagnose(data: &CircleData) -> Result<Diagnostics, String> {
    let n = data.len();
    if n < MIN_DIAGNOSTIC_READINGS {
        return Err(format!(
            "{n} readings: the diagnostic fit needs at least {MIN_DIAGNOSTIC_READINGS}"
        ));
    }
    let plane = data.test.plane;
    let mut unidentifiable: Vec<(Term, String)> = Vec::new();
    let mut terms: Vec<Term> = Vec::new();
    for term in Term::DIAGNOSTICS {
        match data.structural(term) {
            Some(reason) => unidentifiable.push((term, reason)),
            None => terms.push(term),
        }
    }
    let all_rows: Vec<usize> = (0..n).collect();
    let everything = vec![true; n];
    // The linear terms first (their columns do not depend on the searched shapes), then
    // everything at the searched shapes, until nothing more is dropped.
    let linear: Vec<Term> = terms.iter().copied().filter(|t| !t.searched()).collect();
    for (term, reason) in data.unidentifiable(&linear, &Shape::default()) {
        terms.retain(|&t| t != term);
        unidentifiable.push((term, reason));
    }
    let fit = loop {
        let fit = data.fit(&terms, &everything);
        let dropped = data.unidentifiable(&terms, &fit.shape);
        if dropped.is_empty() {
            break fit;
        }
        for (term, reason) in dropped {
            terms.retain(|&t| t != term);
            unidentifiable.push((term, reason));
        }
    };
    unidentifiable.sort_by_key(|(t, _)| *t);
    let rss: Real = fit.residuals.iter().map(|r| r * r).sum();
    let searched_count = terms.iter().filter(|t| t.searched()).count();
    let lags = (0..2)
        .filter(|&a| terms.iter().any(|t| t.reversal_axis() == Some(a)))
        .count();
    let k = fit.coefficients.len() + searched_count + lags;
    let dof = n.saturating_sub(k).max(1);
    let variance = rss / dof as Real;
    let columns = data.columns_on(&terms, &fit.shape, &all_rows);
    let covariance = |extra: &[Vec<Real>]| -> DMatrix<Real> {
        let views: Vec<&[Real]> = columns.iter().chain(extra).map(Vec::as_slice).collect();
        gram_pinv(&gram(&views)) * variance
    };
    let linear_covariance = covariance(&[]);
    // Offsets of each term's coefficients.
    let mut offsets = Vec::with_capacity(terms.len());
    let mut start = 0;
    for &t in &terms {
        offsets.push(start);
        start += t.columns();
    }
    let amplitude = |t: usize, cov: &DMatrix<Real>| -> (Real, Real) {
        let j = offsets[t];
        let c = &fit.coefficients[j..j + terms[t].columns()];
        if c.len() == 1 {
            return (c[0], cov[(j, j)].max(0.0).sqrt());
        }
        let a = c[0].hypot(c[1]);
        let var = if a > 0.0 {
            (c[0] * c[0] * cov[(j, j)]
                + 2.0 * c[0] * c[1] * cov[(j, j + 1)]
                + c[1] * c[1] * cov[(j + 1, j + 1)])
                / (a * a)
        } else {
            cov[(j, j)].max(cov[(j + 1, j + 1)])
        };
        (a, var.max(0.0).sqrt())
    };
    // Significant searched terms get derivative columns in their shape parameter.
    let mut notes = Vec::new();
    let mut derivatives: Vec<Vec<Real>> = Vec::new();
    let mut shape_column: Vec<Option<usize>> = vec![None; terms.len()];
    for (t, &term) in terms.iter().enumerate() {
        if !term.searched() {
            continue;
        }
        let (value, u) = amplitude(t, &linear_covariance);
        let threshold = data.significance(term);
        if value.abs() >= threshold * u && u > 0.0 {
            let c = fit.coefficients_of(term).unwrap_or(&[]);
            shape_column[t] = Some(columns.len() + derivatives.len());
            derivatives.push(
                all_rows
                    .iter()
                    .map(|&i| shape_derivative(term, c, &data.points[i], &data.test, &fit.shape))
                    .collect(),
            );
        } else {
            notes.push(format!(
                "{}: amplitude {:.3} µm within {threshold:.1} × its uncertainty ({:.3} µm): not significant, {} not reported",
                term.key(plane),
                value / M_PER_UM,
                u / M_PER_UM,
                shape_name(term),
            ));
        }
    }
    // A lag is reported when the axis has a significant reversal term to be located by.
    let mut reversal_lag = [None; 2];
    for (axis, lag) in reversal_lag.iter_mut().enumerate() {
        let members: Vec<usize> = (0..terms.len())
            .filter(|&t| terms[t].reversal_axis() == Some(axis))
            .collect();
        if members.is_empty() {
            continue;
        }
        let locating: Vec<Term> = members
            .iter()
            .filter(|&&t| {
                let (value, u) = amplitude(t, &linear_covariance);
                terms[t].locates_reversal()
                    && u > 0.0
                    && value.abs() >= data.significance(terms[t]) * u
            })
            .map(|&t| terms[t])
            .collect();
        if locating.is_empty() {
            notes.push(unlocated_lag(plane, axis));
            continue;
        }
        match data.locate_lag(axis, &fit, &locating, variance) {
            LagLocation::Located { lag: value, u } => *lag = Some((value, u)),
            LagLocation::NotLocated { from, to } => {
                notes.push(not_located_lag(plane, axis, &locating, from, to, data));
            }
        }
    }
    let full_covariance = covariance(&derivatives);
    let mut estimates: Vec<(Term, TermEstimate)> = terms
        .iter()
        .enumerate()
        .map(|(t, &term)| {
            let (value, mut u) = amplitude(t, &full_covariance);
            // A spike's height is read back to the reversal instant: h ∝ e^(δ/τ) for the data
            // after it, so the lag's uncertainty adds h·u_δ/τ.
            if matches!(term, Term::ReversalSpikeP | Term::ReversalSpikeQ) {
                let axis = usize::from(term == Term::ReversalSpikeQ);
                if let Some((_, u_lag)) = reversal_lag[axis] {
                    u = u.hypot(value * u_lag / fit.shape.decay[axis]);
                }
            }
            let mut estimate = TermEstimate {
                value,
                u,
                shape: None,
                phase: None,
            };
            if let Some(d) = shape_column[t] {
                let u_shape = full_covariance[(d, d)].max(0.0).sqrt();
                let axis = usize::from(matches!(term, Term::ReversalSpikeQ | Term::CyclicQ));
                estimate.shape = Some(match term {
                    Term::CyclicP | Term::CyclicQ => (fit.shape.period[axis], u_shape),
                    _ => (fit.shape.decay[axis], u_shape),
                });
                if matches!(term, Term::CyclicP | Term::CyclicQ) {
                    let j = offsets[t];
                    let (a, b) = (fit.coefficients[j], fit.coefficients[j + 1]);
                    let cov = &full_covariance;
                    let var = (b * b * cov[(j, j)] - 2.0 * a * b * cov[(j, j + 1)]
                        + a * a * cov[(j + 1, j + 1)])
                        / (a * a + b * b).powi(2);
                    estimate.phase = Some((b.atan2(a), var.max(0.0).sqrt()));
                }
            }
            (term, estimate)
        })
        .collect();
    // The rule is applied once more to the final uncertainties (the searched shapes and the
    // lags free), the ones reported and drawn: a searched term that no longer passes loses its
    // shape, and a lag that no significant reversal term locates any more is not reported.
    for (term, estimate) in &mut estimates {
        let threshold = data.significance(*term);
        if estimate.shape.is_some() && estimate.value.abs() < threshold * estimate.u {
            estimate.shape = None;
            estimate.phase = None;
            notes.push(format!(
                "{}: amplitude {:.3} µm within {threshold:.1} × its uncertainty ({:.3} µm) once its {} and lag are free: not significant, {} not reported",
                term.key(plane),
                estimate.value / M_PER_UM,
                estimate.u / M_PER_UM,
                shape_name(*term),
                shape_name(*term),
            ));
        }
    }
    for (axis, lag) in reversal_lag.iter_mut().enumerate() {
        let located = estimates.iter().any(|(t, e)| {
            t.reversal_axis() == Some(axis)
                && t.locates_reversal()
                && e.u > 0.0
                && e.value.abs() >= data.significance(*t) * e.u
        });
        if lag.is_some() && !located {
            *lag = None;
            notes.push(unlocated_lag(plane, axis));
        }
    }
    // A significant searched term whose shape lies at an end of its range measures nothing:
    // its value and shape are withdrawn, with the reason.
    estimates.retain(|(term, estimate)| {
        match estimate
            .shape
            .and_then(|_| data.shape_at_range_end(*term, &fit.shape))
        {
            Some(reason) => {
                unidentifiable.push((*term, reason));
                false
            }
            None => true,
        }
    });
    // Backlash drawn as real play: say so, with the arc the carriage stood still over; and
    // where the other mechanism fits nearly as well, that the trace does not tell them apart.
    for (axis, term) in [(0, Term::BacklashP), (1, Term::BacklashQ)] {
        let gap = fit.shape.play[axis];
        let Some(estimate) = estimates.iter().find(|(t, _)| *t == term).map(|(_, e)| e) else {
            continue;
        };
        if !(estimate.u > 0.0 && estimate.value.abs() >= 2.0 * estimate.u) {
            continue;
        }
        let letter = if axis == 0 {
            plane.first()
        } else {
            plane.second()
        };
        let rival = rival_mechanisms(&fit, axis, variance)
            .map(|(_, above)| above)
            .reduce(Real::min);
        if gap > 0.0 {
            notes.push(format!(
                "{}: read as play, not as an instantaneous step: after {letter} reverses the carriage stands still while the motor crosses the gap, over {:.2}° of the circle{}",
                term.key(plane),
                take_up_arc(gap, data.test.radius).to_degrees(),
                rival.map_or(String::new(), |above| format!(
                    "; a step at the reversal fits within {above:.1}·σ̂² of it, so the trace does not tell the two apart (the reversal lag spans both)"
                )),
            ));
        } else if let Some(above) = rival {
            notes.push(format!(
                "{}: read as an instantaneous step; play (the carriage standing still while the motor crosses the gap) fits within {above:.1}·σ̂² of it, so the trace does not tell the two apart (the reversal lag spans both)",
                term.key(plane),
            ));
        }
    }
    Ok(Diagnostics {
        estimates,
        reversal_lag,
        unidentifiable,
        notes,
        rms: (rss / n as Real).sqrt(),
        dof,
        fit,
    })
}

/// The note for an axis whose reversal lag is not reported.
fn unlocated_lag(plane: Plane, axis: usize) -> String {
    format!(
        "{}: no significant backlash or reversal spike of {} to time the reversal by (lateral play cannot: it is continuous at the reversal): not reported",
        lag_key(plane, axis),
        if axis == 0 {
            plane.first()
        } else {
            plane.second()
        }
    )
}

/// The note for an axis whose significant reversal terms do not place its reversal.
fn not_located_lag(
    plane: Plane,
    axis: usize,
    locating: &[Term],
    from: Real,
    to: Real,
    data: &CircleData,
) -> String {
    let names: Vec<String> = locating.iter().map(|t| t.key(plane)).collect();
    let (low, high) = data.ranges.lag;
    format!(
        "{}: {} fit{} as well ({LAG_SET}) for any reversal lag from {:.1} to {:.1} ms, which reaches the end of the {:.0} to {:.0} ms searched: the trace does not place {}'s reversal, not reported",
        lag_key(plane, axis),
        names.join(" and "),
        if names.len() == 1 { "s" } else { "" },
        from * 1e3,
        to * 1e3,
        low * 1e3,
        high * 1e3,
        if axis == 0 {
            plane.first()
        } else {
            plane.second()
        }
    )
}

/// What a searched term's shape parameter is called in a note.
fn shape_name(term: Term) -> &'static str {
    if matches!(term, Term::CyclicP | Term::CyclicQ) {
        "period"
    } else {
        "decay"
    }
}

/// The derivative of a searched term's contribution (coefficients `c`) in its decay (m/s)
/// or period (m/m) at `at`.
fn shape_derivative(
    term: Term,
    c: &[Real],
    at: &BasisPoint,
    test: &CircularTest,
    shape: &Shape,
) -> Real {
    match term {
        Term::ReversalSpikeP | Term::ReversalSpikeQ => {
            let axis = usize::from(term == Term::ReversalSpikeQ);
            let tau = shape.decay[axis];
            spike(axis, at, test, shape).map_or(0.0, |(value, dt)| c[0] * value * dt / (tau * tau))
        }
        Term::CyclicP | Term::CyclicQ => {
            let axis = usize::from(term == Term::CyclicQ);
            let (sin, cos) = at.angle.sin_cos();
            let w = if axis == 0 { cos } else { sin };
            let period = shape.period[axis];
            let x = test.radius * w;
            let (s, k) = (TAU * x / period).sin_cos();
            w * (-TAU * x / (period * period)) * (c[0] * k - c[1] * s)
        }
        _ => 0.0,
    }
}
