//! A ball-bar circular test: the machine running the circle with the bar between the balls,
//! the reading against time, and the polar plot of the trace (both senses) around the nominal
//! circle with the fitted diagnostic contributions, each on its own small plot.

use super::discovery::discover_ballbar;
use super::iso230_4::{self, BasisPoint, CircleData, CircularTest, Term};
use crate::kinds::ballbar::table::BallbarTable;
use crate::viz::rr;

use crate::kinds::ballbar::program::{CircularInterpolation, run_circle};
use crate::kinds::ballbar::scenario::BallbarTest;
use crate::math::Real;
use crate::viz::convert::{plot_point, vec3};
use crate::viz::machine::MachineScene;
use crate::viz::plot::{circle as nominal_circle, label, largest_um, polar, scale_per_um};
use crate::viz::{TIMELINE, VizError, WORKPIECE_NOMINAL};
use rr::RecordingStream;

/// Radius of the nominal circle of the polar plots (plot units).
pub const PLOT_RADIUS: Real = 100.0;
/// Radius of the diagnostics' small plots and the distance between their centres.
const DIAGNOSTIC_RADIUS: Real = 40.0;
const DIAGNOSTIC_PITCH: Real = 130.0;
/// Machine frames per second of programme at most, and in all at most this many.
const FRAME_PERIOD_S: Real = 0.05;
const MAX_FRAMES: Real = 3000.0;

/// The 2D plot root of a plane: `ballbar_xy`.
pub fn plot_root(circle: &CircularInterpolation) -> String {
    format!("ballbar_{}", circle.plane.lower())
}

/// The root of a plane's time series (µm): `ballbar_xy_um`.
pub fn series_root(circle: &CircularInterpolation) -> String {
    format!("ballbar_{}_um", circle.plane.lower())
}

/// The time series of a plane's readings (µm): `ballbar_xy_um/deviation`.
pub fn series(circle: &CircularInterpolation) -> String {
    format!("{}/deviation", series_root(circle))
}

/// The test's conditions as the analysis needs them.
pub(crate) fn conditions(circle: &CircularInterpolation) -> CircularTest {
    CircularTest {
        plane: circle.plane,
        radius: circle.radius,
        feed: circle.feed,
    }
}

/// Logs the circle from programme time `start`; returns when it ends.
pub(crate) fn record(
    rec: &RecordingStream,
    scene: &mut MachineScene<'_>,
    test: &BallbarTest,
    circle: &CircularInterpolation,
    table: &BallbarTable,
    start: Real,
    legend: &mut Vec<String>,
) -> Result<Real, VizError> {
    let machine = &scene.twin().machine;
    let centre = machine.workpiece_from_tool(&circle.centre).translation;
    let bar = format!("{WORKPIECE_NOMINAL}/ballbar_{}", circle.plane.lower());
    rec.log_static(
        format!("{bar}/centre_ball"),
        &rr::Points3D::new([vec3(centre)])
            .with_radii([0.00635f32])
            .with_colors([rr::Color::from_rgb(220, 220, 220)]),
    )?;
    let period = FRAME_PERIOD_S.max(circle.duration() / MAX_FRAMES);
    let samples = run_circle(circle, &test.servo, period);
    let mut readings = table.readings.iter().peekable();
    for sample in &samples {
        while let Some(reading) = readings.next_if(|r| r.time.is_some_and(|t| t <= sample.time)) {
            rec.set_duration_secs(TIMELINE, start + reading.time.unwrap_or(0.0));
            rec.log(
                series(circle),
                &rr::Scalars::single(reading.deviation * 1e6),
            )?;
        }
        rec.set_duration_secs(TIMELINE, start + sample.time);
        scene.log_nominal(rec, &sample.state)?;
        let ends = scene.ends(&sample.state, None);
        scene.log_actual(rec, &ends)?;
        let tip = ends.nominal_tip();
        rec.log(
            format!("{bar}/bar"),
            &rr::LineStrips3D::new([[vec3(centre), vec3(tip)]])
                .with_radii([0.003f32])
                .with_colors([rr::Color::from_rgb(200, 200, 210)]),
        )?;
        rec.log(
            format!("{bar}/tool_ball"),
            &rr::Points3D::new([vec3(tip)])
                .with_radii([0.00635f32])
                .with_colors([rr::Color::from_rgb(220, 220, 220)]),
        )?;
    }
    for reading in readings {
        rec.set_duration_secs(TIMELINE, start + reading.time.unwrap_or(0.0));
        rec.log(
            series(circle),
            &rr::Scalars::single(reading.deviation * 1e6),
        )?;
    }
    polar_plots(rec, circle, table, legend)?;
    legend.push(format!(
        "`{bar}`: the bar between the centre ball and the tool ball; `{}`: its readings (µm) against time.",
        series(circle)
    ));
    Ok(start + samples.last().map_or(0.0, |s| s.time))
}

/// The trace around the nominal circle and each fitted diagnostic on its own plot.
fn polar_plots(
    rec: &RecordingStream,
    circle: &CircularInterpolation,
    table: &BallbarTable,
    legend: &mut Vec<String>,
) -> Result<(), VizError> {
    let root = plot_root(circle);
    let test = conditions(circle);
    let (data, evaluation) = match (
        CircleData::new(table, &test),
        iso230_4::evaluate(table, &test),
    ) {
        (Ok(data), Ok(evaluation)) => (data, evaluation),
        (Err(e), _) | (_, Err(e)) => {
            legend.push(format!("`{root}`: not drawn: {e}"));
            return Ok(());
        }
    };
    // As ball-bar software draws it: the fitted radius and centre (the set-up) removed.
    let setup: Vec<Real> = match &evaluation.diagnostics {
        Ok(d) => [Term::Radius, Term::CentreP, Term::CentreQ]
            .iter()
            .filter_map(|&t| d.fit.contribution(t, &data))
            .fold(vec![0.0; data.len()], |sum, c| {
                sum.iter().zip(&c).map(|(a, b)| a + b).collect()
            }),
        Err(_) => vec![0.0; data.len()],
    };
    let centred: Vec<Real> = data
        .deviation
        .iter()
        .zip(&setup)
        .map(|(d, s)| d - s)
        .collect();
    let largest_um = centred.iter().map(|d| d.abs() * 1e6).fold(0.0, Real::max);
    let scale = scale_per_um(largest_um, 0.4 * PLOT_RADIUS);
    let origin = [0.0, 0.0];
    rec.log_static(
        format!("{root}/nominal"),
        &rr::LineStrips2D::new([nominal_circle(origin, PLOT_RADIUS)])
            .with_colors([rr::Color::from_rgb(150, 150, 150)]),
    )?;
    log_senses(
        rec,
        &root,
        "trace_",
        &data.points,
        &centred,
        origin,
        PLOT_RADIUS,
        scale,
    )?;
    legend.push(format!(
        "`{root}`: the trace (blue ccw, red cw) around the nominal circle (radius {PLOT_RADIUS} units for {} mm), the fitted radius and centre offset removed as ball-bar software does; 1 µm of radial deviation drawn as {scale} units, outward +; angles from +{} toward +{} (y upward).",
        circle.radius * 1e3,
        circle.plane.first(),
        circle.plane.second(),
    ));
    let diagnostics = match &evaluation.diagnostics {
        Ok(d) => d,
        Err(reason) => {
            legend.push(format!("`{root}/diagnostics`: not drawn: {reason}"));
            return Ok(());
        }
    };
    // The machine's diagnostics that the data show (by the analysis's significance test), then
    // the residual; the radius and centre terms are the set-up and stay in the trace only.
    let fit = &diagnostics.fit;
    let mut plots: Vec<(String, String, Vec<Real>)> = Vec::new();
    for &term in &fit.terms {
        if matches!(term, Term::Radius | Term::CentreP | Term::CentreQ) {
            continue;
        }
        let (Some(values), Some(estimate)) = (fit.contribution(term, &data), diagnostics.get(term))
        else {
            continue;
        };
        if estimate.value.abs() <= data.significance(term) * estimate.u {
            continue;
        }
        let (unit, factor) = term.unit();
        let name = term.name(circle.plane);
        let label = format!("{name} {:.3} {unit}", estimate.value * factor);
        plots.push((name, label, values));
    }
    plots.push(("residual".into(), "residual".into(), fit.residuals.clone()));
    let largest_um = plots
        .iter()
        .flat_map(|(.., v)| v.iter().map(|d| d.abs() * 1e6))
        .fold(0.0, Real::max);
    let radius = DIAGNOSTIC_RADIUS;
    let scale = scale_per_um(largest_um, 0.4 * radius);
    for (k, (name, label, values)) in plots.iter().enumerate() {
        let centre = [
            1.8 * PLOT_RADIUS + DIAGNOSTIC_PITCH * (k % 3) as Real,
            PLOT_RADIUS - radius - DIAGNOSTIC_PITCH * (k / 3) as Real,
        ];
        let base = format!("{root}/diagnostics/{name}");
        rec.log_static(
            format!("{base}/nominal"),
            &rr::LineStrips2D::new([nominal_circle(centre, radius)])
                .with_colors([rr::Color::from_rgb(150, 150, 150)]),
        )?;
        log_senses(rec, &base, "", &data.points, values, centre, radius, scale)?;
        rec.log_static(
            format!("{base}/label"),
            &rr::Points2D::new([plot_point(centre[0], centre[1] + radius * 1.3)])
                .with_radii([0.5f32])
                .with_labels([label.clone()]),
        )?;
    }
    legend.push(format!(
        "`{root}/diagnostics/<term>`: each ISO 230-4 diagnostic the fit finds significant (by the analysis's significance test), what it contributes to the trace on its own small circle, and the residual; 1 µm drawn as {scale} units. With the radius and centre terms (the set-up) and the terms not drawn (not significant) they add up to the measured deviation."
    ));
    Ok(())
}

/// The plot root of a plane's ball-bar discovery: `discovery_ballbar_xy`.
pub fn discovery_root(circle: &CircularInterpolation) -> String {
    format!("discovery_ballbar_{}", circle.plane.lower())
}

/// The residual polar plot per step, in a row (base on the left).
pub(crate) fn discovery(
    rec: &RecordingStream,
    circle: &CircularInterpolation,
    table: &BallbarTable,
    legend: &mut Vec<String>,
    progress: &mut dyn FnMut(&str),
) -> Result<(), VizError> {
    let root = discovery_root(circle);
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
            &rr::LineStrips2D::new([nominal_circle(centre, PLOT_RADIUS)])
                .with_colors([rr::Color::from_rgb(150, 150, 150)])
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

/// One polar strip per sense of a circular test, `values` (m) at its `points`:
/// `<base>/<prefix>ccw` in blue and `<base>/<prefix>cw` in red.
#[allow(clippy::too_many_arguments)]
fn log_senses(
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
        (1.0, "ccw", rr::Color::from_rgb(60, 120, 230)),
        (-1.0, "cw", rr::Color::from_rgb(230, 80, 60)),
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
            &rr::LineStrips2D::new([polar(centre, radius, scale, &angles, &values)])
                .with_colors([colour]),
        )?;
    }
    Ok(())
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
