//! The spindle error analyser's teaching scene (ISO 230-7): the machine parked with the
//! measured axis turning, the test artefact on its rotor and the probes on its stator, the
//! probe readings against time, and four polar plots of one radial test that tell the
//! analysis as a story:
//!
//! 1. `spindle_polar`: the revolutions drawn one by one as they are recorded (earlier ones
//!    faded), then the synchronous error motion (their mean at each angle) and the inner and
//!    outer envelopes of the band they span;
//! 2. `spindle_polar/asynchronous`: each revolution minus the synchronous curve, on its own
//!    scale;
//! 3. `spindle_polar/fundamental`: the synchronous curve with its 1-UPR component (for a fixed
//!    sensitive direction mostly the artefact's set-up eccentricity), which is then taken off
//!    step by step: the off-centre circle collapses onto the error motion;
//! 4. `spindle_polar/error_motion`: what is left, on its own scale, with the band, and the
//!    ISO 230-7 values about the preferred centre.
//!
//! The plots show the first set-up at the first speed. The radial test drawn is the rotating
//! sensitive direction of an X/Y probe pair when the probes allow one (ISO 230-7 formula (1)),
//! otherwise the first radial probe's own signal. Everything comes from
//! [`super::evaluate::evaluate`] and [`super::analysis::motion::decompose`]; the scene only
//! draws.

use super::analysis::motion::{Decomposition, Direction, decompose};
use super::evaluate::{self, Options, Test};
use super::instrument::{ArtefactKind, AxisChain};
use super::record::{Sensing, SpindleRecord};
use super::scenario::SpindleTest;
use super::table::SpindleTable;
use crate::machine::{MachineState, Side};
use crate::math::{Pose, Real, Vector};
use crate::viz::convert::{plot_point, quaternion, vec3};
use crate::viz::machine::MachineScene;
use crate::viz::plot::{circle, polar, scale_per_um};
use crate::viz::rr;
use crate::viz::{TIMELINE, TOOL_NOMINAL, VizError, WORKPIECE_NOMINAL};
use rr::RecordingStream;
use std::f64::consts::TAU;

/// Root of the 2D polar plots (plot units, y upward).
pub const PLOT: &str = "spindle_polar";
/// The asynchronous plot: each revolution minus the synchronous curve.
pub const ASYNCHRONOUS: &str = "spindle_polar/asynchronous";
/// The fundamental plot: the synchronous curve as its 1-UPR component is taken off.
pub const FUNDAMENTAL: &str = "spindle_polar/fundamental";
/// The error motion plot: the synchronous curve without its fundamental, and the band.
pub const ERROR_MOTION: &str = "spindle_polar/error_motion";
/// Root of the time series: `spindle_um/<probe>`, each probe's reading (µm).
pub const SERIES: &str = "spindle_um";

/// Radius of the base circle of each polar plot (plot units).
pub const PLOT_RADIUS: Real = 100.0;
/// Distance between the plots' centres (a 2 × 2 grid).
const PITCH: Real = 3.0 * PLOT_RADIUS;
/// Machine frames per revolution at most, and in all at most this many.
const FRAMES_PER_REVOLUTION: usize = 16;
const MAX_FRAMES: usize = 3000;
/// Samples per probe in the time series at most (longer records are thinned evenly).
const MAX_SERIES: usize = 100_000;
/// Steps of the fundamental's removal, over one second of the timeline.
const REMOVAL_STEPS: usize = 20;
/// Length of a drawn probe (m).
const PROBE_LENGTH: Real = 0.015;

/// `world/<rotor or stator end>/spindle_artefact`, `…/spindle_probes`: where the artefact and
/// the probes hang (the rotor turns with the axis).
fn ends(side: Side) -> (&'static str, &'static str) {
    match side {
        Side::Tool => (TOOL_NOMINAL, WORKPIECE_NOMINAL),
        Side::Workpiece => (WORKPIECE_NOMINAL, TOOL_NOMINAL),
    }
}

/// Logs the spindle test from programme time `start`; returns when its last part ends.
pub(crate) fn record(
    rec: &RecordingStream,
    scene: &mut MachineScene<'_>,
    test: &SpindleTest,
    table: &SpindleTable,
    start: Real,
    legend: &mut Vec<String>,
) -> Result<Real, VizError> {
    let record = &table.record;
    let machine_end = machine(rec, scene, test, start, legend)?;
    let series_end = series(rec, record, start, legend)?;
    let plots_end = plots(rec, table, start, legend)?;
    Ok(machine_end.max(series_end).max(plots_end))
}

/// The artefact and the probes (static, on the ends of the chain) and the machine turning the
/// axis through the programme, its actual frames and tool-tip error (the true error motion).
fn machine(
    rec: &RecordingStream,
    scene: &mut MachineScene<'_>,
    test: &SpindleTest,
    start: Real,
    legend: &mut Vec<String>,
) -> Result<Real, VizError> {
    let twin = scene.twin();
    match AxisChain::new(twin, test.axis, test.parked, test.artefact.stickout) {
        Ok(chain) => {
            let (rotor, stator) = ends(chain.side);
            // Fixed sensitive direction: the artefact turns, the probes stand; rotating: the
            // other way round. Both are given in their carrier's axis frame.
            let (artefact_end, artefact_from_axis, probe_end, probe_from_axis) = match test.sensing
            {
                Sensing::Fixed => (rotor, chain.rotor_from_axis, stator, chain.stator_from_axis),
                Sensing::Rotating => (stator, chain.stator_from_axis, rotor, chain.rotor_from_axis),
            };
            let artefact = format!("{artefact_end}/spindle_artefact");
            log_artefact(rec, &artefact, test, &artefact_from_axis)?;
            let probes = format!("{probe_end}/spindle_probes");
            let probe_specs = test
                .probes
                .iter()
                .map(|p| p.record_probe(&test.artefact, test.sensing));
            let (mut origins, mut vectors, mut labels) = (Vec::new(), Vec::new(), Vec::new());
            for probe in probe_specs {
                let point = Vector::from_array(probe.position);
                let direction = Vector::from_array(probe.direction);
                origins.push(vec3(
                    probe_from_axis.transform_point3(point - direction * PROBE_LENGTH),
                ));
                vectors.push(vec3(
                    probe_from_axis.transform_vector3(direction * PROBE_LENGTH),
                ));
                labels.push(probe.name.clone());
            }
            rec.log_static(
                probes.as_str(),
                &rr::Arrows3D::from_vectors(vectors)
                    .with_origins(origins)
                    .with_labels(labels)
                    .with_colors([rr::Color::from_rgb(60, 190, 120)]),
            )?;
            legend.push(format!(
                "`{artefact}`: the test artefact ({}) on the {} side, drawn nominal (its set-up eccentricity of {:.2} µm is far below what a screen shows); `{probes}`: the probes, each an arrow onto the point it senses (artefact motion along the arrow increases the reading). The machine stands parked while {} turns through the programme.",
                test.artefact.describe(),
                match test.sensing {
                    Sensing::Fixed => "turning",
                    Sensing::Rotating => "standing",
                },
                test.artefact.eccentricity[0].hypot(test.artefact.eccentricity[1]) * 1e6,
                test.axis,
            ));
        }
        Err(e) => legend.push(format!("spindle artefact and probes: not drawn: {e}")),
    }
    let blocks = test.blocks();
    let total: usize = blocks.iter().map(|b| b.sample_count()).sum();
    let stride = (test.samples_per_revolution / FRAMES_PER_REVOLUTION)
        .max(total.div_ceil(MAX_FRAMES))
        .max(1);
    let mut end = start;
    for block in &blocks {
        let count = block.sample_count();
        // Every `stride`-th sample and the block's last.
        let last = (count > 0 && (count - 1) % stride != 0).then(|| count - 1);
        for j in (0..count).step_by(stride).chain(last) {
            let sample = block.sample(j);
            let state = MachineState::at(test.parked.with(test.axis, sample.position))
                .at_time(sample.time)
                .with_velocity(test.axis, block.speed);
            end = start + sample.time;
            rec.set_duration_secs(TIMELINE, end);
            scene.log_nominal(rec, &state)?;
            let ends = scene.ends(&state, None);
            scene.log_actual(rec, &ends)?;
        }
    }
    Ok(end)
}

/// The artefact's shape at `carrier_from_axis` in its carrier's frame.
fn log_artefact(
    rec: &RecordingStream,
    entity: &str,
    test: &SpindleTest,
    carrier_from_axis: &Pose,
) -> Result<(), VizError> {
    let colour = rr::Color::from_rgb(200, 200, 210);
    let radius = test.artefact.radius;
    let at = |z: Real| vec3(carrier_from_axis.transform_point3(Vector::new(0.0, 0.0, z)));
    match test.artefact.kind {
        ArtefactKind::Cylinder { length } => rec.log_static(
            entity,
            &rr::Cylinders3D::from_lengths_and_radii([length as f32], [radius as f32])
                .with_centers([at(length / 2.0)])
                .with_quaternions([quaternion(carrier_from_axis.matrix3)])
                .with_colors([colour])
                .with_fill_mode(rr::FillMode::Solid),
        )?,
        ArtefactKind::Sphere => rec.log_static(
            entity,
            &rr::Ellipsoids3D::from_centers_and_radii([at(0.0)], [radius as f32])
                .with_colors([colour])
                .with_fill_mode(rr::FillMode::Solid),
        )?,
        ArtefactKind::TwoSpheres { separation } => rec.log_static(
            entity,
            &rr::Ellipsoids3D::from_centers_and_radii(
                [at(0.0), at(separation)],
                [radius as f32, radius as f32],
            )
            .with_colors([colour])
            .with_fill_mode(rr::FillMode::Solid),
        )?,
    }
    Ok(())
}

/// Each probe's readings (µm) against time.
fn series(
    rec: &RecordingStream,
    record: &SpindleRecord,
    start: Real,
    legend: &mut Vec<String>,
) -> Result<Real, VizError> {
    let stride = record.len().div_ceil(MAX_SERIES).max(1);
    let mut end = start;
    for i in (0..record.len()).step_by(stride) {
        end = start + record.time[i];
        rec.set_duration_secs(TIMELINE, end);
        for (probe, readings) in record.probes.iter().zip(&record.readings) {
            rec.log(
                format!("{SERIES}/{}", probe.name),
                &rr::Scalars::single(readings[i] * 1e6),
            )?;
        }
    }
    legend.push(format!(
        "`{SERIES}/<probe>`: each probe's reading (µm) against time{}; + when the artefact moves away from the probe (ISO 230-7 A.7.2).",
        if stride > 1 {
            format!(", one sample in {stride}")
        } else {
            String::new()
        }
    ));
    Ok(end)
}

/// The radial test the plots tell the story with: the rotating sensitive direction of a probe
/// pair if there is one, else the first radial probe.
fn radial_test(tests: &[Test]) -> Option<&Test> {
    tests
        .iter()
        .find(|t| {
            t.direction == Direction::Radial
                && t.sensing == Sensing::Rotating
                && t.probes.len() == 2
        })
        .or_else(|| tests.iter().find(|t| t.direction == Direction::Radial))
}

/// The largest magnitude in `values` (µm).
fn largest_um<'a>(values: impl IntoIterator<Item = &'a Real>) -> Real {
    values
        .into_iter()
        .map(|v| v.abs() * 1e6)
        .fold(0.0, Real::max)
}

/// A polar curve closed on its first point.
fn closed(centre: [Real; 2], scale: Real, angles: &[Real], deviations: &[Real]) -> Vec<[f32; 2]> {
    let mut points = polar(centre, PLOT_RADIUS, scale, angles, deviations);
    if let Some(&first) = points.first() {
        points.push(first);
    }
    points
}

/// The base circle and the title of a plot.
fn frame(
    rec: &RecordingStream,
    root: &str,
    centre: [Real; 2],
    title: String,
) -> Result<(), VizError> {
    rec.log_static(
        format!("{root}/nominal"),
        &rr::LineStrips2D::new([circle(centre, PLOT_RADIUS)])
            .with_colors([rr::Color::from_rgb(150, 150, 150)]),
    )?;
    rec.log_static(
        format!("{root}/title"),
        &rr::Points2D::new([plot_point(centre[0], centre[1] + 1.25 * PLOT_RADIUS)])
            .with_radii([0.5f32])
            .with_labels([title]),
    )?;
    Ok(())
}

/// `values` minus a constant.
fn minus(values: &[Real], constant: Real) -> Vec<Real> {
    values.iter().map(|v| v - constant).collect()
}

/// The four polar plots of the first set-up and speed's radial test.
fn plots(
    rec: &RecordingStream,
    table: &SpindleTable,
    start: Real,
    legend: &mut Vec<String>,
) -> Result<Real, VizError> {
    let record = &table.record;
    let options = Options {
        // The preferred centre (always scored first) is all the plots need.
        centres: Vec::new(),
        ..Options::default()
    };
    let evaluation = match evaluate::evaluate(record, table.samples_per_revolution, &options) {
        Ok(e) => e,
        Err(e) => {
            legend.push(format!("`{PLOT}`: not drawn: {e}"));
            return Ok(start);
        }
    };
    let Some(segment) = evaluation.segments.first() else {
        legend.push(format!("`{PLOT}`: not drawn: the record holds no segment"));
        return Ok(start);
    };
    let Some(test) = radial_test(&segment.tests) else {
        legend.push(format!(
            "`{PLOT}`: not drawn: the probes give no radial test (the polar story is told on radial error motion)"
        ));
        return Ok(start);
    };
    let Some(first) = (0..record.len())
        .find(|&i| record.setup[i] == segment.setup && record.speed[i] == segment.speed)
    else {
        return Ok(start);
    };
    let signal = &test.signal;
    let (k_count, m_count) = (signal.count(), signal.samples_per_revolution());
    let period = TAU / segment.speed.abs();
    let t0 = start + record.time[first];
    let revolution_end =
        |k: usize| t0 + (k as Real + (m_count - 1) as Real / m_count as Real) * period;
    let angles = signal.angles();
    let d: Decomposition = decompose(signal);
    let mean = d.synchronous.iter().sum::<Real>() / m_count as Real;
    let [a1, b1] = d.fundamental;
    let fundamental: Vec<Real> = angles.iter().map(|t| a1 * t.cos() + b1 * t.sin()).collect();
    let without = |v: &[Real]| -> Vec<Real> {
        v.iter()
            .zip(&fundamental)
            .map(|(x, f)| x - mean - f)
            .collect()
    };
    let values = &test.values[0];
    let um = |v: Real| v * 1e6;
    let blue = |alpha: u8| rr::Color::from_unmultiplied_rgba(40, 100, 220, alpha);
    let red = rr::Color::from_rgb(225, 70, 30);
    let green = rr::Color::from_rgb(40, 160, 80);
    let purple = rr::Color::from_unmultiplied_rgba(140, 70, 200, 110);
    let speed_rpm = segment.speed * 60.0 / TAU;
    let which = if evaluation.segments.len() > 1 {
        format!(
            " (the first of {} set-ups × speeds: set-up {}, {:.0} rpm)",
            evaluation.segments.len(),
            if segment.setup.is_empty() {
                "as given"
            } else {
                segment.setup.as_str()
            },
            speed_rpm
        )
    } else {
        String::new()
    };

    // 1. The revolutions one by one, then the synchronous curve and the band.
    let origin = [0.0, 0.0];
    let revolutions: Vec<Vec<Real>> = (0..k_count)
        .map(|k| minus(signal.revolution(k), mean))
        .collect();
    let scale = scale_per_um(largest_um(revolutions.iter().flatten()), 0.4 * PLOT_RADIUS);
    frame(
        rec,
        PLOT,
        origin,
        format!(
            "{}: {k_count} revolutions, synchronous and asynchronous",
            test.name
        ),
    )?;
    let strips: Vec<Vec<[f32; 2]>> = revolutions
        .iter()
        .map(|r| closed(origin, scale, &angles, r))
        .collect();
    for k in 0..k_count {
        rec.set_duration_secs(TIMELINE, revolution_end(k));
        let colours = (0..=k).map(|i| if i == k { blue(255) } else { blue(70) });
        rec.log(
            format!("{PLOT}/revolutions"),
            &rr::LineStrips2D::new(strips[..=k].iter().cloned())
                .with_colors(colours)
                .with_labels([format!("revolution {}", k + 1)]),
        )?;
    }
    let t_end = revolution_end(k_count - 1);
    let t_sync = t_end + 0.5;
    rec.set_duration_secs(TIMELINE, t_sync);
    rec.log(
        format!("{PLOT}/revolutions"),
        &rr::LineStrips2D::new(strips.iter().cloned()).with_colors([blue(50)]),
    )?;
    rec.log(
        format!("{PLOT}/synchronous"),
        &rr::LineStrips2D::new([closed(origin, scale, &angles, &minus(&d.synchronous, mean))])
            .with_colors([red])
            .with_radii([0.8f32])
            .with_draw_order(10.0)
            .with_labels([format!("synchronous {:.3} µm", um(values.synchronous))]),
    )?;
    for (name, contour) in [("inner", &d.inner), ("outer", &d.outer)] {
        rec.log(
            format!("{PLOT}/{name}"),
            &rr::LineStrips2D::new([closed(origin, scale, &angles, &minus(contour, mean))])
                .with_colors([green])
                .with_radii([0.4f32])
                .with_draw_order(5.0)
                .with_labels([format!("{name} (asynchronous band)")]),
        )?;
    }
    legend.push(format!(
        "`{PLOT}`: the radial test `{}`{which}, its record's mean taken off (the base circle of radius {PLOT_RADIUS} units stands for it); 1 µm drawn as {scale} units, outward +, angle from the index counter-clockwise (y upward). `{PLOT}/revolutions`: each revolution drawn as it ends ({k_count} of {m_count} samples each), the latest bright, earlier ones faded; after the last, `{PLOT}/synchronous` (red): the synchronous error motion, the mean of the revolutions at each angle (ISO 230-7 §3.5.2); `{PLOT}/inner`, `{PLOT}/outer` (green): the smallest and largest value at each angle, the band the asynchronous error motion spans (§3.6.7, §3.6.8).",
        test.name,
    ));

    // 2. The asynchronous part alone.
    let centre = [PITCH, 0.0];
    let asynchronous: Vec<&[Real]> = (0..k_count)
        .map(|k| &d.asynchronous[k * m_count..(k + 1) * m_count])
        .collect();
    let async_scale = scale_per_um(
        largest_um(asynchronous.iter().flat_map(|a| a.iter())),
        0.4 * PLOT_RADIUS,
    );
    frame(
        rec,
        ASYNCHRONOUS,
        centre,
        format!(
            "asynchronous: each revolution − synchronous; value {:.3} µm",
            um(values.asynchronous)
        ),
    )?;
    rec.log(
        format!("{ASYNCHRONOUS}/revolutions"),
        &rr::LineStrips2D::new(
            asynchronous
                .iter()
                .map(|a| closed(centre, async_scale, &angles, a)),
        )
        .with_colors([purple]),
    )?;
    legend.push(format!(
        "`{ASYNCHRONOUS}/revolutions` (purple, from the end of the record): each revolution minus the synchronous curve, the asynchronous error motion (§3.5.5): what does not repeat turn after turn (bearing cage and ball-pass lines, random motion); 1 µm drawn as {async_scale} units. Its value, the widest band at any one angle, is {:.3} µm (§3.8.4).",
        um(values.asynchronous)
    ));

    // 3. The fundamental taken off step by step.
    let centre = [0.0, -PITCH];
    let synchronous = minus(&d.synchronous, mean);
    let fund_scale = scale_per_um(largest_um(&synchronous), 0.4 * PLOT_RADIUS);
    let eccentricity_um = um(a1.hypot(b1));
    frame(
        rec,
        FUNDAMENTAL,
        centre,
        format!("the fundamental (1 UPR, {eccentricity_um:.3} µm off centre) taken off"),
    )?;
    let t_fundamental = t_sync + 1.0;
    rec.set_duration_secs(TIMELINE, t_fundamental);
    rec.log(
        format!("{FUNDAMENTAL}/measured"),
        &rr::LineStrips2D::new([closed(centre, fund_scale, &angles, &synchronous)])
            .with_colors([rr::Color::from_unmultiplied_rgba(225, 70, 30, 80)]),
    )?;
    for step in 0..=REMOVAL_STEPS {
        let fraction = step as Real / REMOVAL_STEPS as Real;
        rec.set_duration_secs(TIMELINE, t_fundamental + fraction);
        let curve: Vec<Real> = synchronous
            .iter()
            .zip(&fundamental)
            .map(|(s, f)| s - fraction * f)
            .collect();
        rec.log(
            format!("{FUNDAMENTAL}/synchronous"),
            &rr::LineStrips2D::new([closed(centre, fund_scale, &angles, &curve)])
                .with_colors([red])
                .with_radii([0.8f32]),
        )?;
        // The centre of the near-circle a 1-UPR term a·cos θ + b·sin θ draws: (a, b) × scale.
        let left = 1.0 - fraction;
        let offset = [
            centre[0] + left * fund_scale * a1 * 1e6,
            centre[1] + left * fund_scale * b1 * 1e6,
        ];
        rec.log(
            format!("{FUNDAMENTAL}/centre"),
            &rr::LineStrips2D::new([[
                plot_point(centre[0], centre[1]),
                plot_point(offset[0], offset[1]),
            ]])
            .with_colors([rr::Color::from_rgb(90, 90, 90)]),
        )?;
        rec.log(
            format!("{FUNDAMENTAL}/centre_point"),
            &rr::Points2D::new([plot_point(offset[0], offset[1])])
                .with_radii([1.5f32])
                .with_colors([rr::Color::from_rgb(90, 90, 90)])
                .with_labels([format!("1 UPR: {:.3} µm", left * eccentricity_um)]),
        )?;
    }
    let what_fundamental = match test.sensing {
        Sensing::Fixed => {
            "for a fixed sensitive direction it is mostly the artefact's set-up eccentricity, which the analysis cannot tell from a 1-UPR error motion of the axis (§3.5.3 Notes 2–3), so ISO 230-7 takes it off for radial motion (the LSC centre, Tab 1)"
        }
        Sensing::Rotating => {
            "with a rotating sensitive direction the eccentricity turns with the direction and shows as a change of radius (taken off with the mean); the 1-UPR part left is what stands still in the stator frame (the probes' zero, a shift of the axis), and ISO 230-7 takes it off for radial motion too (the LSC centre, Tab 1)"
        }
    };
    legend.push(format!(
        "`{FUNDAMENTAL}/synchronous` (red, from {:.2} s to {:.2} s): the synchronous curve with its fundamental, the 1-UPR component a₁cos θ + b₁sin θ of {eccentricity_um:.3} µm (§3.5.3), taken off in {REMOVAL_STEPS} steps: the off-centre circle collapses onto the error motion; `{FUNDAMENTAL}/measured` (faded): the curve before; `{FUNDAMENTAL}/centre`: the centre the fundamental puts the curve on, moving home. 1 µm drawn as {fund_scale} units. The fundamental: {what_fundamental}; its value is {:.3} µm (twice the offset, §3.8.5).",
        t_fundamental - start,
        t_fundamental + 1.0 - start,
        um(values.fundamental),
    ));

    // 4. The error motion on its own scale, with the band about it.
    let centre = [PITCH, -PITCH];
    let residual = without(&d.synchronous);
    let (inner, outer) = (without(&d.inner), without(&d.outer));
    let motion_scale = scale_per_um(
        largest_um(residual.iter().chain(&inner).chain(&outer)),
        0.4 * PLOT_RADIUS,
    );
    frame(
        rec,
        ERROR_MOTION,
        centre,
        format!(
            "error motion about {}: total {:.3}, synchronous {:.3}, asynchronous {:.3} µm",
            values.centre.name(),
            um(values.total),
            um(values.synchronous),
            um(values.asynchronous)
        ),
    )?;
    let t_motion = t_fundamental + 1.0;
    rec.set_duration_secs(TIMELINE, t_motion);
    rec.log(
        format!("{ERROR_MOTION}/synchronous"),
        &rr::LineStrips2D::new([closed(centre, motion_scale, &angles, &residual)])
            .with_colors([red])
            .with_radii([0.8f32])
            .with_draw_order(10.0)
            .with_labels(["synchronous error motion".to_string()]),
    )?;
    for (name, contour) in [("inner", &inner), ("outer", &outer)] {
        rec.log(
            format!("{ERROR_MOTION}/{name}"),
            &rr::LineStrips2D::new([closed(centre, motion_scale, &angles, contour)])
                .with_colors([green])
                .with_radii([0.4f32])
                .with_draw_order(5.0),
        )?;
    }
    legend.push(format!(
        "`{ERROR_MOTION}/synchronous` (red, at {:.2} s): the synchronous curve without its mean and fundamental, the synchronous radial error motion of the axis itself; `{ERROR_MOTION}/inner`, `…/outer` (green): the band with the same taken off. 1 µm drawn as {motion_scale} units. ISO 230-7 values about the {} centre: total {:.3} µm (§3.8.2), synchronous {:.3} µm (§3.8.3), asynchronous {:.3} µm (§3.8.4), fundamental {:.3} µm (§3.8.5), residual synchronous {:.3} µm (§3.8.6).",
        t_motion - start,
        values.centre.name(),
        um(values.total),
        um(values.synchronous),
        um(values.asynchronous),
        um(values.fundamental),
        um(values.residual),
    ));
    Ok(t_motion)
}
