//! The ISO 230-4 figures ([`evaluate`] into a [`BallbarEvaluation`]): the first-order circle
//! fits, the circular deviations G of each sense and G(b), the circular hysteresis H and the
//! radial deviations F_max, F_min; the diagnostics attached.

use super::data::sense_index;
use super::diagnose::diagnose;
use super::linalg::Projection;
use super::{BallbarError, BasisPoint, CircleData, CircularTest, Diagnostics, Shape, Term};
use crate::kinds::ballbar::table::BallbarTable;
use crate::math::Real;
use std::f64::consts::TAU;

/// The ISO 230-4 evaluation and the diagnostics of a ball-bar table.
#[derive(Clone, Debug, PartialEq)]
pub struct BallbarEvaluation {
    /// The test conditions.
    pub test: CircularTest,
    /// Readings per sense (ccw, cw).
    pub counts: [usize; 2],
    /// Angular span per sense (rad).
    pub spans: [Option<Real>; 2],
    /// Circular deviation G of the ccw and cw traces (m).
    pub circular_deviation: [Option<Real>; 2],
    /// Bidirectional circular deviation G(b) (m), with both senses.
    pub bidirectional_deviation: Option<Real>,
    /// Circular hysteresis H (m), with both senses overlapping.
    pub hysteresis: Option<Real>,
    /// Largest and smallest radial deviation F_max, F_min (m), centre removed.
    pub radial_max: Real,
    /// See `radial_max`.
    pub radial_min: Real,
    /// Centre offset of the common first-order fit along p and q (m).
    pub centre_offset: [Real; 2],
    /// Mean radial deviation r₀ of the common fit (m).
    pub mean_radial_deviation: Real,
    /// The diagnostics, or why they were not computed.
    pub diagnostics: Result<Diagnostics, String>,
}

/// Evaluates a ball-bar table to ISO 230-4 and fits the diagnostics.
pub fn evaluate(
    table: &BallbarTable,
    test: &CircularTest,
) -> Result<BallbarEvaluation, BallbarError> {
    let data = CircleData::new(table, test)?;
    let n = data.len();
    let circle = [Term::Radius, Term::CentreP, Term::CentreQ];
    let shape = Shape::default();
    let fit_rows = |rows: &[usize]| -> Projection {
        let y: Vec<Real> = rows.iter().map(|&i| data.deviation[i]).collect();
        Projection::new(data.columns_on(&circle, &shape, rows), &y)
    };
    let spread = |values: &[Real]| {
        let (low, high) = values
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        high - low
    };
    let mut circular_deviation = [None; 2];
    for (s, g) in circular_deviation.iter_mut().enumerate() {
        let rows: Vec<usize> = (0..n)
            .filter(|&i| sense_index(data.points[i].sense) == s)
            .collect();
        if !rows.is_empty() {
            *g = Some(spread(&fit_rows(&rows).residual));
        }
    }
    let all: Vec<usize> = (0..n).collect();
    let common = fit_rows(&all);
    let both = data.both_senses();
    let radial: Vec<Real> = common
        .residual
        .iter()
        .map(|r| r + common.coefficients[0])
        .collect();
    let (radial_min, radial_max) = radial
        .iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    Ok(BallbarEvaluation {
        test: *test,
        counts: data.counts,
        spans: data.spans,
        circular_deviation,
        bidirectional_deviation: both.then(|| spread(&common.residual)),
        hysteresis: if both {
            hysteresis(&data.points, &common.residual)
        } else {
            None
        },
        radial_max,
        radial_min,
        centre_offset: [common.coefficients[1], common.coefficients[2]],
        mean_radial_deviation: common.coefficients[0],
        diagnostics: diagnose(&data),
    })
}

/// H: the largest |e_ccw(θ) − e_cw(θ)| with the cw residual interpolated linearly at the ccw
/// angles, only inside cw gaps no wider than 3 median gaps (the wrap at 360° included).
fn hysteresis(points: &[BasisPoint], residual: &[Real]) -> Option<Real> {
    let mut cw: Vec<(Real, Real)> = points
        .iter()
        .zip(residual)
        .filter(|(p, _)| p.sense < 0.0)
        .map(|(p, r)| (p.angle, *r))
        .collect();
    cw.sort_by(|a, b| a.0.total_cmp(&b.0));
    let m = cw.len();
    let gap = |k: usize| {
        if k + 1 < m {
            cw[k + 1].0 - cw[k].0
        } else {
            cw[0].0 + TAU - cw[m - 1].0
        }
    };
    let mut gaps: Vec<Real> = (0..m).map(gap).filter(|g| *g > 0.0).collect();
    gaps.sort_by(Real::total_cmp);
    let limit = 3.0 * *gaps.get(gaps.len() / 2)?;
    let mut largest: Option<Real> = None;
    for (p, r) in points.iter().zip(residual).filter(|(p, _)| p.sense > 0.0) {
        // The cw reading at or before θ (circularly) and the one after it.
        let after = cw.partition_point(|c| c.0 <= p.angle);
        let before = (after + m - 1) % m;
        let width = gap(before);
        if width > limit {
            continue;
        }
        let (a, b) = (cw[before], cw[(before + 1) % m]);
        let offset = (p.angle - a.0).rem_euclid(TAU);
        let value = if width > 0.0 {
            a.1 + (b.1 - a.1) * offset / width
        } else {
            a.1
        };
        let difference = (r - value).abs();
        largest = Some(largest.map_or(difference, |l: Real| l.max(difference)));
    }
    largest
}
