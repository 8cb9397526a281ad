//! Identifiability: the terms these data cannot give, with the reason. Structurally
//! ([`CircleData::structural`]: a sense missing, no crossed reversal, sampling too coarse), or
//! because the other terms inflate their variance more than [`MAX_VARIANCE_INFLATION`] times
//! ([`CircleData::unidentifiable`]).

use super::linalg::{gram, gram_pinv, scaled_eigen, variance_inflation};
use super::{CircleData, MAX_VARIANCE_INFLATION, Shape, Term, arc_since_reversal};
use crate::math::{M_PER_MM, Real};
use nalgebra::DMatrix;

/// A spike needs at least this many readings within 3 decays (at the longest) of its reversals.
const MIN_SPIKE_READINGS: usize = 10;

impl CircleData {
    /// Why `term` cannot be fitted to these data at all, if it cannot (both senses needed, no
    /// crossed reversal, sampling too coarse for the searched range).
    pub fn structural(&self, term: Term) -> Option<String> {
        let plane = self.test.plane;
        if term.sense_dependent() && !self.both_senses() {
            let like = match term {
                Term::ServoMismatch => "squareness",
                Term::SenseRadius => "the radius",
                _ => "the radius and the scale mismatch",
            };
            return Some(format!(
                "needs both senses: in one sense it cannot be told from {like}"
            ));
        }
        match term {
            Term::ReversalSpikeP | Term::ReversalSpikeQ => {
                let axis = usize::from(term == Term::ReversalSpikeQ);
                let letter = if axis == 0 {
                    plane.first()
                } else {
                    plane.second()
                };
                let (low, high) = self.ranges.decay;
                if low >= high {
                    return Some(format!(
                        "the readings are {:.1} ms apart: too coarse for decays up to {:.1} ms",
                        low * 1e3,
                        high * 1e3
                    ));
                }
                let near = self
                    .points
                    .iter()
                    .filter(|p| {
                        p.crossed[axis]
                            && self.test.radius
                                * arc_since_reversal(axis, p, &self.test, &Shape::default())
                                / self.test.feed
                                < 3.0 * high
                    })
                    .count();
                (near < MIN_SPIKE_READINGS).then(|| {
                    format!(
                        "{near} reading(s) follow a crossed reversal of {letter} within {:.0} ms (at least {MIN_SPIKE_READINGS} needed)",
                        3e3 * high
                    )
                })
            }
            Term::CyclicP | Term::CyclicQ => {
                let (low, high) = self.ranges.period;
                (low >= high).then(|| {
                    format!(
                        "the readings are too far apart for periods up to {:.1} mm",
                        high / M_PER_MM
                    )
                })
            }
            Term::Lobes => {
                let (low, high) = self.ranges.lobes;
                (low > high).then(|| "too few readings per turn for 3 or more lobes".into())
            }
            _ => None,
        }
    }

    /// The terms of `terms` (in order of importance) these data cannot tell from the others,
    /// with the reason: a column whose variance the others inflate more than
    /// [`MAX_VARIANCE_INFLATION`] times costs its near-collinear group its least important
    /// member. Shapes of searched terms as in `shape`.
    pub fn unidentifiable(&self, terms: &[Term], shape: &Shape) -> Vec<(Term, String)> {
        screen(self, terms, shape)
    }
}

/// The terms of `terms` the data cannot tell from the others, with the reason. While some
/// column's variance inflation exceeds [`MAX_VARIANCE_INFLATION`], the near-collinear group
/// (the terms weighing in the eigenvector of the smallest eigenvalue of the column-scaled Gram
/// matrix) loses its least important member (`terms` is in order of importance).
fn screen(data: &CircleData, terms: &[Term], shape: &Shape) -> Vec<(Term, String)> {
    let plane = data.test.plane;
    let rows: Vec<usize> = (0..data.len()).collect();
    let mut kept: Vec<Term> = terms.to_vec();
    let mut dropped = Vec::new();
    let columns: Vec<(Term, Vec<Real>)> = terms
        .iter()
        .flat_map(|&t| (0..t.columns()).map(move |k| (t, k)))
        .map(|(t, k)| (t, data.column_on(t, k, shape, &rows)))
        .collect();
    loop {
        let active: Vec<&(Term, Vec<Real>)> =
            columns.iter().filter(|(t, _)| kept.contains(t)).collect();
        let views: Vec<&[Real]> = active.iter().map(|(_, c)| c.as_slice()).collect();
        let g = gram(&views);
        let inflation = variance_inflation(&g);
        if inflation.iter().all(|v| *v <= MAX_VARIANCE_INFLATION) {
            return dropped;
        }
        let (_, values, vectors) = scaled_eigen(&g);
        let smallest = (0..values.len())
            .min_by(|&a, &b| values[a].total_cmp(&values[b]))
            .unwrap_or(0);
        let weight = |j: usize| vectors[(j, smallest)].abs();
        let heaviest = (0..active.len()).map(weight).fold(0.0, Real::max);
        let Some(victim) = kept
            .iter()
            .rev()
            .copied()
            .find(|&t| (0..active.len()).any(|j| active[j].0 == t && weight(j) >= 0.2 * heaviest))
            .or_else(|| kept.last().copied())
        else {
            return dropped;
        };
        let vif = (0..active.len())
            .filter(|&j| active[j].0 == victim)
            .map(|j| inflation[j])
            .fold(0.0, Real::max);
        // Which of the others make it up: regress its first column on them.
        let j = active
            .iter()
            .position(|(t, _)| *t == victim)
            .unwrap_or_default();
        let others: Vec<usize> = (0..active.len())
            .filter(|&i| active[i].0 != victim)
            .collect();
        let sub = DMatrix::from_fn(others.len(), others.len(), |a, b| g[(others[a], others[b])]);
        let pinv = gram_pinv(&sub);
        let norm = g[(j, j)].sqrt();
        let mut share: Vec<(Term, Real)> = Vec::new();
        for (a, &i) in others.iter().enumerate() {
            let coefficient: Real = (0..others.len())
                .map(|b| pinv[(a, b)] * g[(others[b], j)])
                .sum();
            let size = coefficient.abs() * g[(i, i)].sqrt() / norm.max(Real::MIN_POSITIVE);
            match share.iter_mut().find(|(t, _)| *t == active[i].0) {
                Some(entry) => entry.1 = entry.1.max(size),
                None => share.push((active[i].0, size)),
            }
        }
        share.sort_by(|a, b| b.1.total_cmp(&a.1));
        let top = share.first().map_or(0.0, |s| s.1);
        let names: Vec<String> = share
            .iter()
            .take(3)
            .filter(|(_, s)| *s >= 0.25 * top && *s > 0.0)
            .map(|(t, _)| t.key(plane))
            .collect();
        // The rule fires on the group's largest inflation; the term dropped is the group's
        // least important member, whose own inflation may be below the limit.
        let largest = inflation.iter().copied().fold(0.0, Real::max);
        let inflation_text = if vif.is_finite() && largest.is_finite() {
            format!(
                "their near-collinear group inflates a variance {largest:.3e} times, over the \
                 limit of {MAX_VARIANCE_INFLATION}; this term, its least important member, by \
                 {vif:.3e}"
            )
        } else {
            "exactly collinear".to_string()
        };
        dropped.push((
            victim,
            if names.is_empty() || norm == 0.0 {
                "no signal in these data (its column is zero)".to_string()
            } else {
                format!(
                    "cannot be told from {} with these data ({inflation_text})",
                    names.join(", ")
                )
            },
        ));
        kept.retain(|&t| t != victim);
    }
}
