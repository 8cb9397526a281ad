//! The R-test's teaching scene: the sphere on the table, the machine running each K-test with
//! the linear axes following, the tool's deviation relative to the sphere drawn as a growing
//! trail around the sphere (enlarged), and the deviations and raw probe readings as time
//! series.

use super::scenario::RTest;
use super::table::RtestTable;
use crate::machine::{Axis, AxisValues, MachineState, Workspace};
use crate::math::Real;
use crate::viz::convert::vec3;
use crate::viz::machine::MachineScene;
use crate::viz::rr;
use crate::viz::{TIMELINE, VizError, WORKPIECE_NOMINAL, factor};
use rr::RecordingStream;

/// Root of the time series: `rtest/<test>/dx_um`, …, `rtest/<test>/probe1_um`, ….
pub const SERIES: &str = "rtest";

/// `world/workpiece_nominal/rtest_sphere`.
pub fn sphere_path() -> String {
    format!("{WORKPIECE_NOMINAL}/rtest_sphere")
}

/// `world/workpiece_nominal/rtest_<test>_x<m>`: the trail of one test.
pub fn trail_path(test: &str, magnification: Real) -> String {
    format!(
        "{WORKPIECE_NOMINAL}/rtest_{}_{}",
        entity(test),
        factor(magnification)
    )
}

fn entity(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// Logs the sphere and every test from programme time `start`; returns when the last ends.
pub(crate) fn record(
    rec: &RecordingStream,
    scene: &mut MachineScene<'_>,
    test: &RTest,
    table: &RtestTable,
    start: Real,
    legend: &mut Vec<String>,
) -> Result<Real, VizError> {
    let m = scene.magnification();
    let machine = &scene.twin().machine;
    let mut workspace = Workspace::new(machine);
    rec.log_static(
        sphere_path(),
        &rr::Ellipsoids3D::from_centers_and_radii(
            [vec3(test.sphere)],
            [test.nest.sphere_radius as f32],
        )
        .with_colors([rr::Color::from_rgb(200, 200, 210)]),
    )?;
    let mut time = start;
    let mut largest: Real = 0.0;
    for (name, rows) in table.tests() {
        let mut trail: Vec<[f32; 3]> = Vec::with_capacity(rows.len());
        let series = format!("{SERIES}/{}", entity(name));
        let t0 = time;
        for row in &rows {
            let mut position = AxisValues::ZERO;
            for axis in [Axis::A, Axis::B, Axis::C] {
                if let Some(angle) = row.angle(axis) {
                    position[axis] = angle;
                }
            }
            if let Some(linear) = row.linear {
                position[Axis::X] = linear.x;
                position[Axis::Y] = linear.y;
                position[Axis::Z] = linear.z;
            }
            time = t0 + row.time.unwrap_or(0.0);
            rec.set_duration_secs(TIMELINE, time);
            let state = MachineState::at(position);
            scene.log_nominal(rec, &state)?;
            let ends = scene.ends(&state, None);
            scene.log_actual(rec, &ends)?;
            // The deviation is in machine axes; the trail hangs in the workpiece frame.
            workspace.workpiece_from_tool(machine, &position, None);
            let world_from_workpiece = workspace.world_from_ends().1;
            let deviation = world_from_workpiece.matrix3.transpose() * row.deviation;
            largest = largest.max(row.deviation.length());
            trail.push(vec3(test.sphere + deviation * m));
            rec.log(
                trail_path(name, m),
                &rr::LineStrips3D::new([trail.clone()])
                    .with_colors([rr::Color::from_rgb(230, 80, 30)]),
            )?;
            for (axis, value) in ["dx_um", "dy_um", "dz_um"]
                .iter()
                .zip(row.deviation.to_array())
            {
                rec.log(
                    format!("{series}/{axis}"),
                    &rr::Scalars::single(value * 1e6),
                )?;
            }
            for (i, reading) in row.probes.iter().enumerate() {
                rec.log(
                    format!("{series}/probe{}_um", i + 1),
                    &rr::Scalars::single(reading * 1e6),
                )?;
            }
        }
        time += 1.0;
    }
    legend.push(format!(
        "`{}`: the R-test sphere (Ø {:.1} mm) on the table. `{}`…: for each K-test, the tool's deviation relative to the sphere (actual − nominal) drawn from the sphere centre, {m} times enlarged, growing pose by pose (largest {:.2} µm); a location error of the turning axis draws a circle. Time series `{SERIES}/<test>/dx_um` … and the raw readings `probe<i>_um` (+ when the sphere pushes the probe in).",
        sphere_path(),
        2.0 * test.nest.sphere_radius * 1e3,
        trail_path("<test>", m),
        largest * 1e6,
    ));
    Ok(time)
}
