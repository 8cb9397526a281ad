//! 2D plots (polar traces, curves against position) drawn with a stated deviation scale.

use super::convert::plot_point;
use crate::discovery::engine::ResidualStep;
use crate::math::Real;

/// A round scale (1, 2 or 5 × 10ⁿ plot units per µm) that draws `largest_um` at most as
/// `span` plot units; 1 when there is nothing to draw.
pub(crate) fn scale_per_um(largest_um: Real, span: Real) -> Real {
    if !(largest_um.is_finite() && largest_um > 0.0) {
        return 1.0;
    }
    let raw = span / largest_um;
    let decade = (10.0 as Real).powf(raw.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|s| *s <= raw)
        .unwrap_or(decade)
}

/// A polar trace around `centre`: radius `radius` plus `scale` plot units per µm of each
/// deviation (m) at its angle (rad, counter-clockwise from +x).
pub(crate) fn polar(
    centre: [Real; 2],
    radius: Real,
    scale: Real,
    angles: &[Real],
    deviations: &[Real],
) -> Vec<[f32; 2]> {
    angles
        .iter()
        .zip(deviations)
        .map(|(a, d)| {
            let r = radius + scale * d * 1e6;
            plot_point(centre[0] + r * a.cos(), centre[1] + r * a.sin())
        })
        .collect()
}

/// The nominal circle of a polar plot, closed.
pub(crate) fn circle(centre: [Real; 2], radius: Real) -> Vec<[f32; 2]> {
    (0..=360)
        .map(|k| {
            let a = (k as Real).to_radians();
            plot_point(centre[0] + radius * a.cos(), centre[1] + radius * a.sin())
        })
        .collect()
}

/// The largest residual of the base model (µm), for a scale shared by every step.
pub(crate) fn largest_um(steps: &[ResidualStep<'_>]) -> Real {
    steps.first().map_or(0.0, |s| {
        s.residuals
            .iter()
            .map(|r| r.abs() * 1e6)
            .fold(0.0, Real::max)
    })
}

/// A discovery step's label: the model and its held-out RMS.
pub(crate) fn label(step: &ResidualStep<'_>) -> String {
    format!("{}: held-out RMS {:.3} µm", step.model, step.cv_rms * 1e6)
}
