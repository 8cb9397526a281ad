//! `mtwin run`: compute what a scenario asks for, then write every output file whole.

use super::scenario::Scenario;
use crate::errors::{Lu2012Error, ParameterName};
use crate::io::{BallbarTable, PositioningTable};
use crate::machine::Side;
use crate::math::Pose;
use crate::math::{Real, sha256_hex};
use crate::program::Visit;
use crate::twin::{ThermalRecord, VolumetricMap, volumetric_map};
use serde_json::{Value, json};
use std::path::Path;

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunError {
    /// The evaluation model does not fit the machine.
    #[error(transparent)]
    Model(#[from] Lu2012Error),
    /// The model produced a deviation that is not a number (nothing is written).
    #[error("the deviation at grid point {row} is not finite; check the error functions")]
    NotFinite {
        /// The 0-based row of the volumetric map.
        row: usize,
    },
    /// An output could not be written.
    #[error("{path}: cannot write: {message}")]
    Write {
        /// The file or folder.
        path: String,
        /// The system's message.
        message: String,
    },
}

/// The files of one run, in memory, in the order they are listed in the manifest.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutput {
    /// `(file name, bytes)`; `manifest.json` last.
    pub files: Vec<(String, Vec<u8>)>,
}

/// What simulating a scenario produced, before anything is written: the measurement tables
/// and, beside them, what the twin knew (for the files and for the teaching scenes).
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The volumetric map, if asked for.
    pub volumetric: Option<VolumetricMap>,
    /// The laser test, if asked for.
    pub laser: Option<LaserRun>,
    /// One ball-bar table per circle, in the scenario's order.
    pub ballbar: Vec<BallbarTable>,
}

/// A simulated laser test: the table and the truth at each of its readings.
#[derive(Clone, Debug)]
pub struct LaserRun {
    /// The instrument's table (one reading per measurement event).
    pub table: PositioningTable,
    /// Where and when each reading was taken.
    pub visits: Vec<Visit>,
    /// The actual tool pose seen from the workpiece at each reading (geometric and thermal
    /// errors).
    pub poses: Vec<Pose>,
    /// With a thermal model: the true temperatures and sensor readings at each reading.
    pub thermal: Option<Vec<ThermalRecord>>,
}

/// Simulates everything `scenario` asks for. Nothing here depends on the clock, the thread
/// count or the path the scenario was given by: the same scenario and seed give the same
/// results.
pub fn simulate(scenario: &Scenario) -> Result<Simulation, RunError> {
    let volumetric = match &scenario.volumetric {
        Some(spec) => {
            let map = volumetric_map(&scenario.twin, &spec.grid, spec.model)?;
            let finite = |r: &crate::twin::VolumetricRow| {
                r.deviation.translation.is_finite()
                    && r.deviation.tilt.iter().all(|t| t.is_finite())
            };
            if let Some(row) = map.rows.iter().position(|r| !finite(r)) {
                return Err(RunError::NotFinite { row });
            }
            Some(map)
        }
        None => None,
    };
    let laser = scenario.laser_test.as_ref().map(|test| {
        let mut rng = crate::math::seeded_rng(scenario.seed, "laser");
        match &scenario.thermal {
            Some(setup) => {
                let mut sensors = setup.sensors(scenario.seed);
                let records = crate::twin::run_thermal(
                    &scenario.twin,
                    &setup.thermal,
                    &test.program,
                    setup.max_interval,
                    &mut sensors,
                );
                let visits: Vec<_> = records.iter().map(|r| r.visit).collect();
                let poses: Vec<_> = records.iter().map(|r| r.pose).collect();
                // The laser's air is the machine's air, at each reading.
                let air: Vec<Real> = records
                    .iter()
                    .map(|r| setup.thermal.ambient.at(r.visit.time))
                    .collect();
                // The material (NDE) sensor, when it sits on a node, reads it at each reading.
                let material: Option<Vec<Real>> =
                    test.material_sensor.as_ref().map(|(name, offset)| {
                        let node = setup
                            .thermal
                            .network
                            .node(name)
                            .expect("checked when the scenario was loaded");
                        records
                            .iter()
                            .map(|r| r.temperatures[node] + offset)
                            .collect()
                    });
                let mut table = test.laser.measure_in_air(
                    &visits,
                    &poses,
                    Some(&air),
                    material.as_deref(),
                    &test.targets,
                    &mut rng,
                );
                table.sensors = setup
                    .sensors
                    .iter()
                    .map(|(_, spec)| spec.name.clone())
                    .collect();
                for (reading, record) in table.readings.iter_mut().zip(&records) {
                    reading.temperatures = record.readings.clone();
                }
                LaserRun {
                    table,
                    visits,
                    poses,
                    thermal: Some(records),
                }
            }
            None => {
                let visits = crate::program::visits(&test.program.timeline(Real::INFINITY));
                let poses = scenario.twin.poses(&visits);
                let table = test.laser.measure(&visits, &poses, &test.targets, &mut rng);
                LaserRun {
                    table,
                    visits,
                    poses,
                    thermal: None,
                }
            }
        }
    });
    let ballbar = scenario
        .ballbar_test
        .as_ref()
        .map_or_else(Vec::new, |test| {
            test.circles
                .iter()
                .map(|circle| {
                    let plane = circle.plane;
                    let mut rng =
                        crate::math::seeded_rng(scenario.seed, &format!("ballbar {plane}"));
                    test.ballbar
                        .measure(&scenario.twin, circle, &test.servo, &mut rng)
                })
                .collect()
        });
    Ok(Simulation {
        volumetric,
        laser,
        ballbar,
    })
}

/// Computes every output of `scenario` in memory ([`simulate`], then [`Simulation::output`]).
pub fn run_scenario(scenario: &Scenario) -> Result<RunOutput, RunError> {
    Ok(simulate(scenario)?.output(scenario))
}

impl Simulation {
    /// The files of the run: `volumetric.csv`, `positioning.csv`, `ballbar_<plane>.csv` (as
    /// the scenario asks), `truth.json` and `manifest.json`.
    pub fn output(&self, scenario: &Scenario) -> RunOutput {
        let mut files: Vec<(String, Vec<u8>)> = Vec::new();
        if let Some(map) = &self.volumetric {
            let mut bytes = Vec::new();
            map.write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push(("volumetric.csv".into(), bytes));
        }
        if let Some(run) = &self.laser {
            let mut bytes = Vec::new();
            run.table
                .write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push(("positioning.csv".into(), bytes));
        }
        let circles = scenario.ballbar_test.iter().flat_map(|t| &t.circles);
        for (circle, table) in circles.zip(&self.ballbar) {
            let mut bytes = Vec::new();
            table
                .write_csv(&mut bytes)
                .expect("writing to memory cannot fail");
            files.push((format!("ballbar_{}.csv", circle.plane.lower()), bytes));
        }
        let thermal_truth = self.laser.as_ref().and_then(|run| {
            Some(thermal_states(
                scenario.thermal.as_ref()?,
                run.thermal.as_ref()?,
            ))
        });
        let mut truth = truth(scenario);
        if let Some(states) = thermal_truth {
            truth["thermal_states"] = states;
        }
        files.push(("truth.json".into(), to_json_bytes(&truth)));

        let listed: Vec<Value> = files
        .iter()
        .map(|(name, bytes)| json!({ "name": name, "bytes": bytes.len(), "sha256": sha256_hex(bytes) }))
        .collect();
        let manifest = json!({
            "mtwin_version": env!("CARGO_PKG_VERSION"),
            "scenario": { "file": file_name(&scenario.file), "sha256": scenario.sha256 },
            "machine": {
                "name": scenario.twin.machine.name(),
                "file": file_name(&scenario.machine_file),
                "sha256": scenario.machine_sha256,
            },
            "seed": scenario.seed,
            "volumetric_model": scenario.volumetric.as_ref().map(|v| v.model.name()),
            "files": listed,
        });
        files.push(("manifest.json".into(), to_json_bytes(&manifest)));
        RunOutput { files }
    }
}

/// Writes the files into `dir` (created if needed). All are first written under temporary
/// names and only then renamed, so a failure while writing leaves none of the new files (and
/// removes the temporary ones), and a reader never sees half a file.
pub fn write_outputs(output: &RunOutput, dir: &Path) -> Result<(), RunError> {
    let fail = |path: &Path, e: std::io::Error| RunError::Write {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    std::fs::create_dir_all(dir).map_err(|e| fail(dir, e))?;
    let temporary = |name: &str| dir.join(format!(".{name}.partial"));
    for (index, (name, bytes)) in output.files.iter().enumerate() {
        if let Err(e) = std::fs::write(temporary(name), bytes) {
            for (written, _) in &output.files[..=index] {
                let _ = std::fs::remove_file(temporary(written)); // best effort: already failing
            }
            return Err(fail(&temporary(name), e));
        }
    }
    for (name, _) in &output.files {
        let target = dir.join(name);
        std::fs::rename(temporary(name), &target).map_err(|e| fail(&target, e))?;
    }
    Ok(())
}

/// Every injected parameter, as written (file units), with where it acts, plus the linear
/// coefficients in SI in the order of the Jacobian.
fn truth(scenario: &Scenario) -> Value {
    let machine = &scenario.twin.machine;
    let mut errors = serde_json::Map::new();
    for parameter in scenario.twin.errors.parameters() {
        let name = parameter.name;
        let (kind, axis) = match name {
            ParameterName::Component { axis, .. } => ("component", Some(axis)),
            ParameterName::Location { axis, .. } if axis.is_linear() => ("squareness", Some(axis)),
            ParameterName::Location { axis, .. } => ("location", Some(axis)),
            ParameterName::Tool { .. } => ("tool", None),
        };
        let side = axis
            .and_then(|a| machine.axis(a))
            .map_or(Side::Tool, |info| info.side);
        errors.insert(
            name.to_string(),
            json!({
                "kind": kind,
                "axis": axis.map(|a| a.to_string()),
                "axis_side": if side == Side::Tool { "tool" } else { "workpiece" },
                "unit": name.file_unit(),
                "terms": scenario.error_specs.get(&name.to_string()),
            }),
        );
    }
    let coefficients: Vec<Value> = scenario
        .twin
        .errors
        .coefficient_labels()
        .into_iter()
        .zip(scenario.twin.errors.coefficients())
        .map(|(label, value)| json!({ "label": label, "value_si": value }))
        .collect();
    let laser_test = scenario.laser_test.as_ref().map(|test| {
        let laser = &test.laser;
        json!({
            "axis": test.laser.axis.to_string(),
            "targets_mm": test.targets.iter().map(|t| t * 1e3).collect::<Vec<_>>(),
            "runs": test.runs,
            "beam_offset_mm": (laser.beam_offset * 1e3).to_array(),
            "misalignment_urad": laser.misalignment.map(|m| m * 1e6),
            "air": { "temperature_degc": laser.air.temperature, "pressure_hpa": laser.air.pressure / 100.0, "humidity_pct": laser.air.humidity },
            "refractive_index_true": laser.air.refractive_index(crate::instruments::HENE_WAVELENGTH_UM),
            "refractive_index_assumed": laser.assumed_index(),
            "resolution_nm": laser.resolution * 1e9,
            "noise_nm": laser.noise * 1e9,
            "dead_path_mm": laser.dead_path * 1e3,
            "zero": format!("{:?}", laser.zero),
            "interferometer_on": format!("{:?}", laser.mounting),
            "compensation": format!("{:?}", laser.compensation),
            "material": laser.material.map(|m| json!({
                "expansion_ppm_per_degc": m.expansion * 1e6,
                "temperature_degc": m.measured_temperature,
                "sensor_node": test.material_sensor.as_ref().map(|(node, _)| node.clone()),
                "sensor_offset_degc": test.material_sensor.as_ref().map(|(_, offset)| *offset),
            })),
        })
    });
    let thermal_model = scenario.thermal.as_ref().map(thermal_model);
    json!({
        "machine": machine.name(),
        "seed": scenario.seed,
        "laser_test": laser_test,
        "ballbar_test": scenario.ballbar_test.as_ref().map(ballbar_truth),
        "thermal_model": thermal_model,
        "convention": "deviation = actual - nominal, workpiece frame. Component, tool and zero-position errors are \
                       motions of the tool relative to the workpiece in the frame of their axis; location errors \
                       (E?0?) are the axis line itself, actual - nominal, zero at the axis zero (ISO 230-1 names)",
        "errors": errors,
        "coefficients_si": coefficients,
    })
}

/// The ball-bar set-up, the circles and the controller, in file units; per plane the servo
/// mismatch the loops give (lag time of the first axis − the second's).
fn ballbar_truth(test: &crate::io::BallbarTest) -> Value {
    let bar = &test.ballbar;
    let servo = &test.servo;
    let axis_servo = |axis: crate::machine::Axis| {
        let s = servo.axis(axis);
        json!({
            "kv_per_s": s.kv,
            "feed_forward": s.feed_forward,
            "lag_ms": s.lag_time() * 1e3,
            "spike_um": s.spike_height * 1e6,
            "spike_decay_ms": s.spike_decay * 1e3,
            "vibration_um": s.vibration_amplitude * 1e6,
            "vibration_hz": s.vibration_frequency,
        })
    };
    json!({
        "length_mm": bar.length * 1e3,
        "setup_offset_um": (bar.setup_offset * 1e6).to_array(),
        "calibration_um": bar.calibration_error * 1e6,
        "noise_um": bar.noise * 1e6,
        "resolution_um": bar.resolution * 1e6,
        "sample_rate_hz": bar.sample_rate,
        "circles": test.circles.iter().map(|c| json!({
            "plane": c.plane.to_string(),
            "file": format!("ballbar_{}.csv", c.plane.lower()),
            "feed_mm_per_min": c.feed * 60e3,
            "centre": c.centre.0.iter().zip(["x_mm", "y_mm", "z_mm", "a_deg", "b_deg", "c_deg"])
                .map(|(v, k)| (k.to_string(), json!(if k.ends_with("mm") { v * 1e3 } else { v.to_degrees() })))
                .collect::<serde_json::Map<_, _>>(),
            "data_start_deg": c.data_start.to_degrees(),
            "data_arc_deg": c.data_arc.to_degrees(),
            "overshoot_deg": c.overshoot.to_degrees(),
            "acceleration_mm_per_s2": c.acceleration * 1e3,
            "dwell_s": c.dwell,
            "servo_mismatch_ms": (servo.axis(c.plane.first()).lag_time() - servo.axis(c.plane.second()).lag_time()) * 1e3,
        })).collect::<Vec<_>>(),
        "servo": {
            "ipo_period_ms": servo.ipo_period * 1e3,
            "X": axis_servo(crate::machine::Axis::X),
            "Y": axis_servo(crate::machine::Axis::Y),
            "Z": axis_servo(crate::machine::Axis::Z),
        },
    })
}

/// The injected thermal model: nodes, links, heat sources, thermal error terms, air, sensors.
fn thermal_model(setup: &crate::io::ThermalSetup) -> Value {
    let thermal = &setup.thermal;
    let name = |i: usize| thermal.network.nodes()[i].name.clone();
    json!({
        "initial_degc": thermal.initial,
        "nodes": thermal.network.nodes().iter().map(|n| json!({
            "name": n.name, "capacity_j_per_k": n.capacity, "to_ambient_w_per_k": n.to_ambient,
        })).collect::<Vec<_>>(),
        "links": thermal.network.links().iter().map(|&(i, j, g)| json!({
            "nodes": [name(i), name(j)], "conductance_w_per_k": g,
        })).collect::<Vec<_>>(),
        "sources": thermal.sources.iter().map(|s| json!({
            "node": name(s.node), "driver": format!("{:?}", s.driver), "w_per_unit_speed": s.coefficient,
        })).collect::<Vec<_>>(),
        "terms": thermal.errors.terms().map(|t| format!("{t:?}")).collect::<Vec<_>>(),
        "ambient": {
            "mean_degc": thermal.ambient.mean,
            "steps": thermal.ambient.steps.iter().map(|(t, d)| json!({"at_min": t / 60.0, "by_degc": d})).collect::<Vec<_>>(),
            "daily_amplitude_degc": thermal.ambient.daily_amplitude,
            "daily_peak_h": thermal.ambient.daily_peak / 3600.0,
            "oscillation": thermal.ambient.oscillation.map(|(a, p)| json!({"amplitude_degc": a, "period_min": p / 60.0})),
        },
        "max_interval_s": setup.max_interval,
        "sensors": setup.sensors.iter().map(|(node, spec)| json!({
            "name": spec.name, "node": name(*node), "offset_degc": spec.offset, "noise_degc": spec.noise,
            "resolution_degc": spec.resolution, "lag_s": spec.time_constant,
        })).collect::<Vec<_>>(),
    })
}

/// The true node temperatures and air at every measurement: `{nodes: [names], time_min: [..],
/// air_degc: [..], temperatures_degc: [[per node] per measurement]}`.
fn thermal_states(
    setup: &crate::io::ThermalSetup,
    records: &[crate::twin::ThermalRecord],
) -> Value {
    let round = |v: Real| (v * 1e6).round() / 1e6;
    json!({
        "nodes": setup.thermal.network.nodes().iter().map(|n| n.name.clone()).collect::<Vec<_>>(),
        "time_min": records.iter().map(|r| round(r.visit.time / 60.0)).collect::<Vec<_>>(),
        "air_degc": records.iter().map(|r| round(setup.thermal.ambient.at(r.visit.time))).collect::<Vec<_>>(),
        "temperatures_degc": records.iter().map(|r| r.temperatures.iter().map(|t| round(*t)).collect::<Vec<_>>()).collect::<Vec<_>>(),
    })
}

fn to_json_bytes(value: &Value) -> Vec<u8> {
    let mut bytes = serde_json::to_vec_pretty(value).expect("JSON values serialise");
    bytes.push(b'\n');
    bytes
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
