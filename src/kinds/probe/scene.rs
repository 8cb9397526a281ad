//! The touch probe's teaching scene: the artefacts on the table, the machine making every
//! touch (from the approach start to where the axes latched), the latched stylus centres as
//! the controller believes them, and each fitted sphere's centre error from the artefact's
//! centre (enlarged), so that a location error of a rotary axis shows as the sphere appearing
//! to move between rotary positions; the fit residuals and centre errors as time series.
//!
//! Everything is drawn in the nominal workpiece frame. A latched point is the nominal tool tip
//! at the latched axes (the controller's belief of where the stylus centre was); a fitted
//! centre, given in axis coordinates by the `spheres` table, is mapped the same way at its
//! feature's rotary angles (the map is rigid there, so the fit moves with it).

use super::cycles::{Feature, Target};
use super::run::ProbeRun;
use super::scenario::ProbeTest;
use super::table::SphereRow;
use crate::machine::{Axis, AxisValues, Direction, Machine, MachineState};
use crate::math::{Real, Vector};
use crate::viz::convert::{cold_to_warm, vec3};
use crate::viz::machine::MachineScene;
use crate::viz::rr;
use crate::viz::{TIMELINE, VizError, WORKPIECE_NOMINAL, factor};
use rr::RecordingStream;
use std::f64::consts::TAU;

/// Root of the time series: `probe/residual_um`, `probe/centre_error_um/dx` ….
pub const SERIES: &str = "probe";

/// From the latch to the next approach start (s), and from a feature's last touch to the
/// next feature's first (s; the rotary axes turn in between).
const RETRACT_S: Real = 0.5;
const REPOSITION_S: Real = 1.0;

/// Drawn radius of a latched point (m).
const POINT_RADIUS: f32 = 0.0005;

/// `world/workpiece_nominal/probe_artefact_<cycle>`: a cycle's sphere, plate balls or ring.
pub fn artefact_path(cycle: usize) -> String {
    format!("{WORKPIECE_NOMINAL}/probe_artefact_{cycle}")
}

/// `world/workpiece_nominal/probe_touches`: every latched stylus centre so far.
pub fn touches_path() -> String {
    format!("{WORKPIECE_NOMINAL}/probe_touches")
}

/// `world/workpiece_nominal/probe_centre_error_x<m>`: an arrow per fitted sphere so far, from
/// the artefact's centre, the fitted centre's error enlarged.
pub fn centre_error_path(magnification: Real) -> String {
    format!(
        "{WORKPIECE_NOMINAL}/probe_centre_error_{}",
        factor(magnification)
    )
}

/// `world/workpiece_nominal/probe_fitted_sphere_x<m>`: the last fitted sphere, its centre's
/// error enlarged.
pub fn fitted_sphere_path(magnification: Real) -> String {
    format!(
        "{WORKPIECE_NOMINAL}/probe_fitted_sphere_{}",
        factor(magnification)
    )
}

/// The nominal tool tip (the stylus centre the controller believes) at `xyz` (axis
/// coordinates) and the rotary angles of `rotary`, in the workpiece frame.
fn believed(machine: &Machine, rotary: &AxisValues, xyz: Vector) -> Vector {
    let mut axes = *rotary;
    axes[Axis::X] = xyz.x;
    axes[Axis::Y] = xyz.y;
    axes[Axis::Z] = xyz.z;
    machine.workpiece_from_tool(&axes).translation
}

/// The centre of the artefact a sphere or plate feature fits (`index` from 0: a plate's
/// features are its balls in order).
fn artefact_centre(feature: &Feature, index: usize) -> Option<Vector> {
    match &feature.target {
        Target::Sphere(s) => Some(s.centre),
        Target::Plate(p) => p.centres.get(index).copied(),
        Target::Ring(_) | Target::Mesh(_) => None,
    }
}

/// The rotary angles of a feature, for labels: `A 0° C 90°`.
fn angles(machine: &Machine, rotary: &AxisValues) -> String {
    [Axis::A, Axis::B, Axis::C]
        .into_iter()
        .filter(|a| machine.has_axis(*a))
        .map(|a| format!("{a} {}°", round(rotary[a].to_degrees())))
        .collect::<Vec<_>>()
        .join(" ")
}

fn round(x: Real) -> Real {
    (x * 1e3).round() / 1e3 + 0.0
}

/// Logs the artefacts (static) and every touch from programme time `start`; returns when the
/// last ends.
pub(crate) fn record(
    rec: &RecordingStream,
    scene: &mut MachineScene<'_>,
    test: &ProbeTest,
    run: &ProbeRun,
    start: Real,
    legend: &mut Vec<String>,
) -> Result<Real, VizError> {
    let m = scene.magnification();
    let machine = &scene.twin().machine;
    let grey = rr::Color::from_rgb(200, 200, 210);
    for (c, cycle) in test.cycles.iter().enumerate() {
        let Some(feature) = cycle.features.first() else {
            continue;
        };
        match &feature.target {
            Target::Sphere(s) => rec.log_static(
                artefact_path(c + 1),
                &rr::Ellipsoids3D::from_centers_and_radii([vec3(s.centre)], [s.radius as f32])
                    .with_colors([grey]),
            )?,
            Target::Plate(p) => rec.log_static(
                artefact_path(c + 1),
                &rr::Ellipsoids3D::from_centers_and_radii(
                    p.centres.iter().map(|c| vec3(*c)),
                    p.centres.iter().map(|_| p.radius as f32),
                )
                .with_colors([grey]),
            )?,
            Target::Ring(r) => {
                let u = r.axis.any_orthonormal_vector();
                let v = r.axis.cross(u);
                let circle: Vec<[f32; 3]> = (0..=72)
                    .map(|k| {
                        let a = TAU * k as Real / 72.0;
                        vec3(r.point + (u * a.cos() + v * a.sin()) * r.radius)
                    })
                    .collect();
                rec.log_static(
                    artefact_path(c + 1),
                    &rr::LineStrips3D::new([circle]).with_colors([grey]),
                )?
            }
            Target::Mesh(_) => {}
        }
    }
    let spheres = &run.spheres.spheres;
    let fit_of = |cycle: usize, feature: usize| -> Option<&SphereRow> {
        spheres
            .iter()
            .find(|s| s.key.cycle == cycle && s.key.feature == feature)
    };
    let stylus = run
        .spheres
        .conditions
        .stylus_radius
        .unwrap_or(test.probe.stylus_radius);
    let features = test
        .cycles
        .iter()
        .map(|c| c.features.len())
        .sum::<usize>()
        .max(2);
    let mut touches = run.probe.touches.iter();
    let mut points: Vec<[f32; 3]> = Vec::new();
    let mut colours: Vec<rr::Color> = Vec::new();
    let (mut origins, mut arrows, mut labels) = (Vec::new(), Vec::new(), Vec::new());
    let (mut time, mut last, mut count) = (start, start, 0);
    let (mut largest, mut worst): (Real, Real) = (0.0, 0.0);
    for (c, cycle) in test.cycles.iter().enumerate() {
        for (f, feature) in cycle.features.iter().enumerate() {
            let colour = cold_to_warm(count as Real / (features - 1) as Real);
            count += 1;
            let fit = fit_of(c + 1, f + 1);
            for (probing, touch) in feature.moves.iter().zip(touches.by_ref()) {
                let mut state = MachineState::at(probing.start);
                let e = probing.direction;
                for (axis, component) in [(Axis::X, e.x), (Axis::Y, e.y), (Axis::Z, e.z)] {
                    if component < 0.0 {
                        state.direction[axis.index()] = Direction::Negative;
                    }
                }
                rec.set_duration_secs(TIMELINE, time);
                scene.log_nominal(rec, &state)?;
                let ends = scene.ends(&state, None);
                scene.log_actual(rec, &ends)?;
                let begin = Vector::new(
                    probing.start[Axis::X],
                    probing.start[Axis::Y],
                    probing.start[Axis::Z],
                );
                last = time + (touch.position - begin).dot(e).max(0.0) / test.probe.feed;
                state.position[Axis::X] = touch.position.x;
                state.position[Axis::Y] = touch.position.y;
                state.position[Axis::Z] = touch.position.z;
                rec.set_duration_secs(TIMELINE, last);
                scene.log_nominal(rec, &state)?;
                let ends = scene.ends(&state, None);
                scene.log_actual(rec, &ends)?;
                points.push(vec3(ends.nominal_tip()));
                colours.push(colour);
                rec.log(
                    touches_path(),
                    &rr::Points3D::new(points.clone())
                        .with_radii([POINT_RADIUS])
                        .with_colors(colours.clone()),
                )?;
                if let Some(fit) = fit {
                    // The latched stylus centre's distance from the fitted centre less the
                    // fitted radius (artefact + stylus); distances are the same in axis
                    // coordinates and in the workpiece frame.
                    let residual = (touch.position - fit.centre).length() - (fit.radius + stylus);
                    worst = worst.max(residual.abs());
                    rec.log(
                        format!("{SERIES}/residual_um"),
                        &rr::Scalars::single(residual * 1e6),
                    )?;
                }
                time = last + RETRACT_S;
            }
            // The fit, at the feature's last latch.
            if let (Some(fit), Some(nominal)) = (fit, artefact_centre(feature, f)) {
                let error = believed(machine, &feature.rotary, fit.centre) - nominal;
                largest = largest.max(error.length());
                origins.push(vec3(nominal));
                arrows.push(vec3(error * m));
                labels.push(angles(machine, &feature.rotary));
                rec.log(
                    centre_error_path(m),
                    &rr::Arrows3D::from_vectors(arrows.clone())
                        .with_origins(origins.clone())
                        .with_labels(labels.clone())
                        .with_colors([rr::Color::from_rgb(230, 80, 30)]),
                )?;
                rec.log(
                    fitted_sphere_path(m),
                    &rr::Ellipsoids3D::from_centers_and_radii(
                        [vec3(nominal + error * m)],
                        [fit.radius as f32],
                    )
                    .with_colors([rr::Color::from_rgb(230, 80, 30)]),
                )?;
                for (axis, value) in ["dx", "dy", "dz"].iter().zip(error.to_array()) {
                    rec.log(
                        format!("{SERIES}/centre_error_um/{axis}"),
                        &rr::Scalars::single(value * 1e6),
                    )?;
                }
            }
            time = last + REPOSITION_S;
        }
    }
    legend.push(format!(
        "`{WORKPIECE_NOMINAL}/probe_artefact_<cycle>`: the probed artefacts (spheres, plate balls, ring gauges; meshes are not drawn) on the table. From {start:.1} s the machine makes every touch: at the approach start, then where the axes latched (the approach at the probing feed, {RETRACT_S} s to the next start, {REPOSITION_S} s to the next rotary position). `{}`: each latched stylus centre as the controller believes it (the nominal tip at the latched axes), coloured by feature. `{}`: from each artefact's centre, the fitted centre's error (fitted − placed, workpiece frame) {m} times enlarged, labelled with its rotary angles (largest {:.2} µm); `{}`: the last fitted sphere there. A location error of a rotary axis makes the sphere appear to move between rotary positions; for such an error, the same at every touch of a position, the arrow is the opposite of the tool-tip error arrow: the probe sees the artefact where the tool is not. Time series `{SERIES}/residual_um` (each touch's distance from its fitted centre less the fitted radius, largest {:.3} µm) and `{SERIES}/centre_error_um/dx|dy|dz`.",
        touches_path(),
        centre_error_path(m),
        largest * 1e6,
        fitted_sphere_path(m),
        worst * 1e6,
    ));
    Ok(last)
}
