//! 2D plots (polar traces, curves against position) drawn with a stated deviation scale.

use super::VizError;
use super::convert::plot_point;
use crate::analysis::iso230_4::BasisPoint;
use crate::io::PositioningTable;
use crate::math::Real;
use rerun::RecordingStream;

/// A round scale (1, 2 or 5 × 10ⁿ plot units per µm) that draws `largest_um` at most as
/// `span` plot units; 1 when there is nothing to draw.
pub(super) fn scale_per_um(largest_um: Real, span: Real) -> Real {
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
pub(super) fn polar(
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
pub(super) fn circle(centre: [Real; 2], radius: Real) -> Vec<[f32; 2]> {
    (0..=360)
        .map(|k| {
            let a = (k as Real).to_radians();
            plot_point(centre[0] + radius * a.cos(), centre[1] + radius * a.sin())
        })
        .collect()
}

/// The points of `angles`/`values` sorted by angle (rerun draws a strip in order).
fn sorted_by_angle(angles: &[Real], values: &[Real]) -> (Vec<Real>, Vec<Real>) {
    let mut order: Vec<usize> = (0..angles.len()).collect();
    order.sort_by(|&a, &b| angles[a].total_cmp(&angles[b]));
    (
        order.iter().map(|&i| angles[i]).collect(),
        order.iter().map(|&i| values[i]).collect(),
    )
}

/// The lowest and highest target of a positioning table (m).
pub(super) fn target_range(table: &PositioningTable) -> (Real, Real) {
    table
        .readings
        .iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), r| {
            (l.min(r.target), h.max(r.target))
        })
}

/// One polar strip per sense of a circular test, `values` (m) at its `points`:
/// `<base>/<prefix>ccw` in blue and `<base>/<prefix>cw` in red.
#[allow(clippy::too_many_arguments)]
pub(super) fn log_senses(
    rec: &RecordingStream,
    base: &str,
    prefix: &str,
    points: &[BasisPoint],
    values: &[Real],
    centre: [Real; 2],
    radius: Real,
    scale: Real,
) -> Result<(), VizError> {
    for (sense, tag, colour) in [
        (1.0, "ccw", rerun::Color::from_rgb(60, 120, 230)),
        (-1.0, "cw", rerun::Color::from_rgb(230, 80, 60)),
    ] {
        let (angles, values): (Vec<Real>, Vec<Real>) = points
            .iter()
            .zip(values)
            .filter(|(p, _)| p.sense == sense)
            .map(|(p, v)| (p.angle, *v))
            .unzip();
        if angles.is_empty() {
            continue;
        }
        let (angles, values) = sorted_by_angle(&angles, &values);
        rec.log_static(
            format!("{base}/{prefix}{tag}"),
            &rerun::LineStrips2D::new([polar(centre, radius, scale, &angles, &values)])
                .with_colors([colour]),
        )?;
    }
    Ok(())
}
