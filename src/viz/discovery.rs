//! Discovery: the residual the base model leaves, then what is left after each accepted
//! effect, side by side with the held-out RMS of each model.

use super::VizError;
use super::ballbar::{PLOT_RADIUS, conditions};
use super::convert::plot_point;
use super::plot::{circle as nominal_circle, log_senses, scale_per_um, target_range};
use crate::discovery::engine::ResidualStep;
use crate::discovery::{PositioningOptions, discover_ballbar, discover_positioning};
use crate::io::{Approach, BallbarTable, PositioningTable};
use crate::math::Real;
use crate::program::CircularInterpolation;
use rerun::RecordingStream;

/// The plot root of positioning discovery.
pub const DISCOVERY_POSITIONING: &str = "discovery_positioning";

/// The plot root of a plane's ball-bar discovery: `discovery_ballbar_xy`.
pub fn ballbar_root(circle: &CircularInterpolation) -> String {
    format!("discovery_ballbar_{}", circle.plane.lower())
}

/// The largest residual of the base model (µm), for a scale shared by every step.
fn largest_um(steps: &[ResidualStep<'_>]) -> Real {
    steps.first().map_or(0.0, |s| {
        s.residuals
            .iter()
            .map(|r| r.abs() * 1e6)
            .fold(0.0, Real::max)
    })
}

fn label(step: &ResidualStep<'_>) -> String {
    format!("{}: held-out RMS {:.3} µm", step.model, step.cv_rms * 1e6)
}

/// Residual against position per run and direction, one band per step (base on top).
pub(super) fn positioning(
    rec: &RecordingStream,
    table: &PositioningTable,
    legend: &mut Vec<String>,
    progress: &mut dyn FnMut(&str),
) -> Result<(), VizError> {
    let discovery =
        match discover_positioning(table, PositioningOptions::default(), |what| progress(what)) {
            Ok(d) => d,
            Err(e) => {
                legend.push(format!("`{DISCOVERY_POSITIONING}`: not drawn: {e}"));
                return Ok(());
            }
        };
    let steps = discovery.residual_steps();
    let readings = &table.readings;
    let (low, high) = target_range(table);
    let travel_mm = ((high - low) * 1e3).max(1.0);
    let band = travel_mm / 3.0;
    let scale = scale_per_um(largest_um(&steps), band / 2.5);
    for (k, step) in steps.iter().enumerate() {
        let offset = -(k as Real) * band;
        let base = format!("{DISCOVERY_POSITIONING}/step_{k}");
        for r in 0..table.runs.len() {
            for (approach, tag) in [(Approach::Up, "up"), (Approach::Down, "down")] {
                let mut points: Vec<(Real, Real)> = readings
                    .iter()
                    .zip(step.residuals)
                    .filter(|(x, _)| x.run == r && x.approach == approach)
                    .map(|(x, residual)| (x.target, *residual))
                    .collect();
                if points.is_empty() {
                    continue;
                }
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                let strip: Vec<[f32; 2]> = points
                    .iter()
                    .map(|(x, d)| plot_point(x * 1e3, offset + d * 1e6 * scale))
                    .collect();
                rec.log_static(
                    format!("{base}/run_{}_{tag}", table.runs[r]),
                    &rerun::LineStrips2D::new([strip]).with_colors([if approach == Approach::Up {
                        rerun::Color::from_rgb(60, 120, 230)
                    } else {
                        rerun::Color::from_rgb(230, 80, 60)
                    }]),
                )?;
            }
        }
        rec.log_static(
            format!("{base}/zero"),
            &rerun::LineStrips2D::new([[
                plot_point(low * 1e3, offset),
                plot_point(high * 1e3, offset),
            ]])
            .with_colors([rerun::Color::from_rgb(150, 150, 150)])
            .with_labels([label(step)]),
        )?;
    }
    legend.push(format!(
        "`{DISCOVERY_POSITIONING}/step_<k>`: the residual (measured − model) against target after the base model (step_0) and after each accepted effect, one band per step from the top; 1 µm drawn as {scale} mm; blue up, red down."
    ));
    Ok(())
}

/// The residual polar plot per step, in a row (base on the left).
pub(super) fn ballbar(
    rec: &RecordingStream,
    circle: &CircularInterpolation,
    table: &BallbarTable,
    legend: &mut Vec<String>,
    progress: &mut dyn FnMut(&str),
) -> Result<(), VizError> {
    let root = ballbar_root(circle);
    let discovery = match discover_ballbar(table, &conditions(circle), |what| progress(what)) {
        Ok(d) => d,
        Err(e) => {
            legend.push(format!("`{root}`: not drawn: {e}"));
            return Ok(());
        }
    };
    let steps = discovery.residual_steps();
    let points = &discovery.data().points;
    let scale = scale_per_um(largest_um(&steps), 0.4 * PLOT_RADIUS);
    for (k, step) in steps.iter().enumerate() {
        let centre = [2.6 * PLOT_RADIUS * k as Real, 0.0];
        let base = format!("{root}/step_{k}");
        rec.log_static(
            format!("{base}/nominal"),
            &rerun::LineStrips2D::new([nominal_circle(centre, PLOT_RADIUS)])
                .with_colors([rerun::Color::from_rgb(150, 150, 150)])
                .with_labels([label(step)]),
        )?;
        log_senses(
            rec,
            &base,
            "",
            points,
            step.residuals,
            centre,
            PLOT_RADIUS,
            scale,
        )?;
    }
    legend.push(format!(
        "`{root}/step_<k>`: the residual (measured − model) around the circle after the base model (step_0, left) and after each accepted effect; 1 µm drawn as {scale} units; blue ccw, red cw."
    ));
    Ok(())
}
