//! The laser test: the machine running the programme, the beam and reflector, the reading and
//! the tool-tip truth against time, temperatures, and each run's error curve against position
//! coloured by thermal state.

use super::discovery::{PositioningOptions, discover_positioning};
use super::table::PositioningTable;
use crate::kinds::positioning::run::LaserRun;
use crate::kinds::positioning::setup::{Mounting, Zeroing};
use crate::viz::rr;

use crate::kinds::positioning::scenario::LaserTest;
use crate::machine::{Direction, MachineState};
use crate::math::{Real, rigid_inverse};
use crate::program::Approach;
use crate::scenario::ThermalSetup;
use crate::viz::convert::{cold_to_warm, plot_point, vec3};
use crate::viz::machine::MachineScene;
use crate::viz::plot::{label, largest_um, scale_per_um};
use crate::viz::{TIMELINE, VizError, WORKPIECE_NOMINAL};
use rr::RecordingStream;

/// The laser's 2D plot: deviation against position per run.
pub const LASER_PLOT: &str = "laser_plot";
/// Time series of the laser (µm): `…/reading` (the table), `…/tool_tip_truth` (the twin's
/// tool-tip deviation along the axis, zeroed as the laser is), `…/target_<k>` (drift of one
/// target's reading).
pub const LASER_UM: &str = "laser_um";
/// Time series of temperatures (°C): sensors by name, `true/<node>`, `air`.
pub const TEMPERATURES_DEGC: &str = "temperatures_degc";

/// Machine frames at most every this many seconds of programme, and about this many in all (plus
/// one at the end of every motion).
const FRAME_PERIOD_S: Real = 0.1;
const MAX_FRAMES: Real = 3000.0;

/// Logs the test from programme time 0; returns when it ends.
pub(crate) fn record(
    rec: &RecordingStream,
    scene: &mut MachineScene<'_>,
    thermal: Option<&ThermalSetup>,
    test: &LaserTest,
    run: &LaserRun,
    legend: &mut Vec<String>,
) -> Result<Real, VizError> {
    let laser = &test.laser;
    let machine = &scene.twin().machine;
    let beam = laser.beam_direction();
    let tool_point = |state: &MachineState| {
        machine
            .workpiece_from_tool(&state.position)
            .transform_point3(laser.beam_offset)
    };
    let first = run.visits.first().map(|v| tool_point(&v.state));
    let fixed_end = first.map(|p| p - beam * (laser.dead_path.max(0.0) + 0.1));
    let (moving_name, fixed_name) = match laser.mounting {
        Mounting::InterferometerOnWorkpiece => ("reflector", "interferometer"),
        Mounting::InterferometerOnTool => ("interferometer", "reflector"),
    };
    if let Some(fixed) = fixed_end {
        rec.log_static(
            format!("{WORKPIECE_NOMINAL}/laser/{fixed_name}"),
            &rr::Points3D::new([vec3(fixed)])
                .with_radii([0.015f32])
                .with_colors([rr::Color::from_rgb(200, 30, 30)]),
        )?;
    }

    // Thermal truth and the sensors, when there is a thermal model.
    let setup = thermal;
    let mut extra = vec![[0.0; 6]; machine.slot_count()];
    let truth_along = |i: usize| {
        let nominal = machine.workpiece_from_tool(&run.visits[i].state.position);
        (run.poses[i].translation - nominal.translation).dot(laser.axis.unit())
    };

    let duration: Real = test
        .program
        .timeline(Real::INFINITY)
        .iter()
        .map(|e| match e {
            crate::program::Event::Interval(interval) => interval.duration,
            crate::program::Event::Measure(_) => 0.0,
        })
        .sum();
    let period = FRAME_PERIOD_S.max(duration / MAX_FRAMES);
    let frames = test.program.path(period);
    let mut run_zero: Option<(usize, Real)> = None;
    let log_frame = |scene: &mut MachineScene<'_>, state: &MachineState| {
        let ends = scene.log_nominal(rec, state)?;
        let moving = (rigid_inverse(&ends.1) * ends.0).transform_point3(laser.beam_offset);
        rec.log(
            format!("{WORKPIECE_NOMINAL}/laser/{moving_name}"),
            &rr::Points3D::new([vec3(moving)])
                .with_radii([0.012f32])
                .with_colors([rr::Color::from_rgb(240, 200, 40)]),
        )?;
        if let Some(fixed) = fixed_end {
            rec.log(
                format!("{WORKPIECE_NOMINAL}/laser/beam"),
                &rr::LineStrips3D::new([[vec3(fixed), vec3(moving)]])
                    .with_radii([0.002f32])
                    .with_colors([rr::Color::from_rgb(255, 40, 40)]),
            )?;
        }
        Ok::<(), VizError>(())
    };
    let mut log_reading = |scene: &mut MachineScene<'_>, i: usize| {
        let visit = &run.visits[i];
        rec.set_duration_secs(TIMELINE, visit.time);
        log_frame(scene, &visit.state)?;
        let thermal = setup.zip(run.thermal.as_ref()).map(|(setup, records)| {
            setup
                .thermal
                .errors
                .slot_twists(&records[i].temperatures, &visit.state, &mut extra);
            (setup, &records[i])
        });
        let ends = scene.ends(&visit.state, thermal.is_some().then_some(&extra[..]));
        scene.log_actual(rec, &ends)?;
        let reading = &run.table.readings[i];
        // The truth is zeroed where the laser is: each run's first reading, or the first.
        let new_zero = match laser.zero {
            Zeroing::EachRun => run_zero.is_none_or(|(r, _)| r != visit.point.run),
            Zeroing::Once => run_zero.is_none(),
        };
        if new_zero {
            run_zero = Some((visit.point.run, truth_along(i)));
        }
        let zero = run_zero.map_or(0.0, |(_, z)| z);
        rec.log(
            format!("{LASER_UM}/reading"),
            &rr::Scalars::single(reading.deviation * 1e6),
        )?;
        rec.log(
            format!("{LASER_UM}/tool_tip_truth"),
            &rr::Scalars::single((truth_along(i) - zero) * 1e6),
        )?;
        rec.log(
            format!("{LASER_UM}/target_{}", visit.point.target),
            &rr::Scalars::single(reading.deviation * 1e6),
        )?;
        if let Some((setup, record)) = thermal {
            for ((_, spec), value) in setup.sensors.iter().zip(&record.readings) {
                rec.log(
                    format!("{TEMPERATURES_DEGC}/{}", spec.name),
                    &rr::Scalars::single(*value),
                )?;
            }
            for (node, value) in setup
                .thermal
                .network
                .nodes()
                .iter()
                .zip(&record.temperatures)
            {
                rec.log(
                    format!("{TEMPERATURES_DEGC}/true/{}", node.name),
                    &rr::Scalars::single(*value),
                )?;
            }
            rec.log(
                format!("{TEMPERATURES_DEGC}/air"),
                &rr::Scalars::single(setup.thermal.ambient.at(visit.time)),
            )?;
        }
        Ok::<(), VizError>(())
    };
    // Frames and readings in time order (a reading first at equal times); the direction of
    // travel of each axis from the path, for the lost motion between readings.
    let mut next_reading = 0;
    let mut state = MachineState::at(test.program.start);
    for (time, position) in &frames {
        while next_reading < run.visits.len() && run.visits[next_reading].time <= *time {
            log_reading(scene, next_reading)?;
            next_reading += 1;
        }
        for (k, (&new, old)) in position.0.iter().zip(state.position.0).enumerate() {
            if new > old {
                state.direction[k] = Direction::Positive;
            } else if new < old {
                state.direction[k] = Direction::Negative;
            }
        }
        state.position = *position;
        rec.set_duration_secs(TIMELINE, *time);
        log_frame(scene, &state)?;
        // Without a thermal model the actual pose is known at every frame.
        if setup.is_none() {
            let ends = scene.ends(&state, None);
            scene.log_actual(rec, &ends)?;
        }
    }
    for i in next_reading..run.visits.len() {
        log_reading(scene, i)?;
    }
    curves(rec, run, legend)?;
    legend.push(format!(
        "`{WORKPIECE_NOMINAL}/laser`: the beam along {} from the {fixed_name} to the {moving_name} ({:.1}, {:.1}, {:.1}) mm from the tool tip (the Abbe offset); `{LASER_UM}/reading`: the laser's deviation at each reading, `{LASER_UM}/tool_tip_truth`: what a laser at the tool tip would read (the twin's deviation along the axis, zeroed where the laser is), `{LASER_UM}/target_<k>`: one target's reading over time (drift).",
        laser.axis,
        laser.beam_offset.x * 1e3,
        laser.beam_offset.y * 1e3,
        laser.beam_offset.z * 1e3,
    ));
    if setup.is_some() {
        legend.push(format!(
            "`{TEMPERATURES_DEGC}/<sensor>`: the sensors' readings, `…/true/<node>`: the thermal model's nodes, `…/air`: the air, at each reading."
        ));
    }
    Ok(frames.last().map_or(0.0, |(t, _)| *t))
}

/// Each run's deviation against position, one strip per run and direction, coloured by the
/// run's mean temperature (first sensor) from coldest (blue) to warmest (red); without
/// temperatures, up runs blue and down runs red.
fn curves(rec: &RecordingStream, run: &LaserRun, legend: &mut Vec<String>) -> Result<(), VizError> {
    let table = &run.table;
    let readings = &table.readings;
    let (low, high) = target_range(table);
    let travel_mm = ((high - low) * 1e3).max(1.0);
    let largest_um = readings
        .iter()
        .map(|r| r.deviation.abs() * 1e6)
        .fold(0.0, Real::max);
    let scale = scale_per_um(largest_um, travel_mm / 4.0);
    let runs = table.runs.len();
    let mean_temperature = |r: usize| {
        let values: Vec<Real> = readings
            .iter()
            .filter(|x| x.run == r)
            .filter_map(|x| x.temperatures.first().copied())
            .collect();
        (!values.is_empty()).then(|| values.iter().sum::<Real>() / values.len() as Real)
    };
    let temperatures: Vec<Option<Real>> = (0..runs).map(mean_temperature).collect();
    let (cold, warm) = temperatures
        .iter()
        .flatten()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), t| {
            (l.min(*t), h.max(*t))
        });
    for (r, (name, temperature)) in table.runs.iter().zip(&temperatures).enumerate() {
        for (approach, arrow, tag) in [(Approach::Up, "↑", "up"), (Approach::Down, "↓", "down")]
        {
            let mut points: Vec<(Real, Real)> = readings
                .iter()
                .filter(|x| x.run == r && x.approach == approach)
                .map(|x| (x.target, x.deviation))
                .collect();
            if points.is_empty() {
                continue;
            }
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            let colour = match *temperature {
                Some(t) if warm > cold => cold_to_warm((t - cold) / (warm - cold)),
                Some(_) => cold_to_warm(0.5),
                None if approach == Approach::Up => cold_to_warm(0.0),
                None => cold_to_warm(1.0),
            };
            let label = match temperature {
                Some(t) => format!("run {name} {arrow} {t:.2} °C"),
                None => format!("run {name} {arrow}"),
            };
            let strip: Vec<[f32; 2]> = points
                .iter()
                .map(|(x, d)| plot_point(x * 1e3, d * 1e6 * scale))
                .collect();
            rec.log_static(
                format!("{LASER_PLOT}/run_{name}_{tag}"),
                &rr::LineStrips2D::new([strip])
                    .with_colors([colour])
                    .with_labels([label]),
            )?;
        }
    }
    rec.log_static(
        format!("{LASER_PLOT}/zero"),
        &rr::LineStrips2D::new([[plot_point(low * 1e3, 0.0), plot_point(high * 1e3, 0.0)]])
            .with_colors([rr::Color::from_rgb(150, 150, 150)]),
    )?;
    legend.push(format!(
        "`{LASER_PLOT}`: deviation against target per run and direction; x: target (mm), y: deviation, 1 µm drawn as {scale} mm, upward; colour: the run's mean temperature (first sensor), blue coldest to red warmest (without sensors: blue up, red down)."
    ));
    Ok(())
}

/// The plot root of positioning discovery.
pub const DISCOVERY_POSITIONING: &str = "discovery_positioning";

/// Residual against position per run and direction, one band per step (base on top).
pub(crate) fn discovery(
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
                    &rr::LineStrips2D::new([strip]).with_colors([if approach == Approach::Up {
                        rr::Color::from_rgb(60, 120, 230)
                    } else {
                        rr::Color::from_rgb(230, 80, 60)
                    }]),
                )?;
            }
        }
        rec.log_static(
            format!("{base}/zero"),
            &rr::LineStrips2D::new([[
                plot_point(low * 1e3, offset),
                plot_point(high * 1e3, offset),
            ]])
            .with_colors([rr::Color::from_rgb(150, 150, 150)])
            .with_labels([label(step)]),
        )?;
    }
    legend.push(format!(
        "`{DISCOVERY_POSITIONING}/step_<k>`: the residual (measured − model) against target after the base model (step_0) and after each accepted effect, one band per step from the top; 1 µm drawn as {scale} mm; blue up, red down."
    ));
    Ok(())
}

/// The lowest and highest target of a positioning table (m).
fn target_range(table: &PositioningTable) -> (Real, Real) {
    table
        .readings
        .iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), r| {
            (l.min(r.target), h.max(r.target))
        })
}
