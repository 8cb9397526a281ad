//! Running a laser test: through the twin (geometric errors), or through the thermal twin
//! when the scenario has a `[thermal]` model (temperatures change the errors, sensors are read
//! at each measurement, the laser's air is the machine's air).

use super::conditions::PositioningConditions;
use super::scenario::LaserTest;
use super::table::PositioningTable;
use crate::machine::Axis;
use crate::math::{Pose, Real};
use crate::program::Visit;
use crate::scenario::ThermalSetup;
use crate::twin::{ThermalRecord, Twin};
use serde_json::{Value, json};

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

/// Simulates `test` on `twin` (through `thermal` when given), the random streams seeded from
/// `seed`.
pub fn simulate(
    twin: &Twin,
    test: &LaserTest,
    thermal: Option<&ThermalSetup>,
    seed: u64,
) -> LaserRun {
    let mut rng = crate::math::seeded_rng(seed, "laser");
    match thermal {
        Some(setup) => {
            let records = setup.run(twin, &test.program, seed);
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
            table.conditions = conditions(twin, test);
            measured_sensors(twin, &mut table, &visits);
            LaserRun {
                table,
                visits,
                poses,
                thermal: Some(records),
            }
        }
        None => {
            let visits = crate::program::visits(&test.program.timeline(Real::INFINITY));
            let poses = twin.poses(&visits);
            let mut table = test.laser.measure(&visits, &poses, &test.targets, &mut rng);
            table.conditions = conditions(twin, test);
            measured_sensors(twin, &mut table, &visits);
            LaserRun {
                table,
                visits,
                poses,
                thermal: None,
            }
        }
    }
}

/// With a measured temperature record (`[inputs] temperatures`), its sensors read the record
/// at each reading's time: the column of a simulated sensor of the same name is replaced, and
/// the record's other sensors are added.
fn measured_sensors(twin: &Twin, table: &mut PositioningTable, visits: &[Visit]) {
    let Some(record) = twin.errors.temperature_record() else {
        return;
    };
    for (index, name) in record.sensors().iter().enumerate() {
        let column = match table.sensors.iter().position(|s| s == name) {
            Some(column) => column,
            None => {
                table.sensors.push(name.clone());
                table
                    .readings
                    .iter_mut()
                    .for_each(|r| r.temperatures.push(0.0));
                table.sensors.len() - 1
            }
        };
        for (reading, visit) in table.readings.iter_mut().zip(visits) {
            reading.temperatures[column] = record.at(index, visit.time);
        }
    }
}

/// The conditions the table states: the test's ([`LaserTest::conditions`]) and the set-up the
/// model of its readings needs ([`super::readings`]): the machine, where its other axes stand
/// (every axis but the spindle), the reflector's offset, the mounting and the zeroing.
fn conditions(twin: &Twin, test: &LaserTest) -> PositioningConditions {
    let laser = &test.laser;
    let mut axes: Vec<_> = twin
        .machine
        .axes()
        .iter()
        .map(|info| info.axis)
        .filter(|&axis| axis != laser.axis && axis != Axis::S)
        .map(|axis| (axis, test.program.start[axis]))
        .collect();
    axes.sort_by_key(|(axis, _)| *axis);
    PositioningConditions {
        machine: Some(twin.machine.name().to_string()),
        axes,
        beam_offset: Some(laser.beam_offset),
        mounting: Some(laser.mounting),
        zero: Some(laser.zero),
        ..test.conditions()
    }
}

/// The laser test as injected (file units), for `truth.json`.
pub fn truth(test: &LaserTest) -> Value {
    let laser = &test.laser;
    json!({
        "axis": test.laser.axis.to_string(),
        "targets_mm": test.targets.iter().map(|t| t * 1e3).collect::<Vec<_>>(),
        "runs": test.runs,
        "beam_offset_mm": (laser.beam_offset * 1e3).to_array(),
        "misalignment_urad": laser.misalignment.map(|m| m * 1e6),
        "air": { "temperature_degc": laser.air.temperature, "pressure_hpa": laser.air.pressure / 100.0, "humidity_pct": laser.air.humidity },
        "refractive_index_true": laser.air.refractive_index(super::HENE_WAVELENGTH_UM),
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
}

impl LaserRun {
    /// One line for people: the ISO 230-2 figures of the table, or what a drift test gives.
    pub fn summary(&self) -> String {
        let axis = self
            .table
            .axis
            .map_or_else(String::new, |a| format!(" on {a}"));
        match super::iso230_2::evaluate(&self.table) {
            Ok(figures) => match figures.both {
                Some(b) => format!(
                    "laser{axis}: ISO 230-2 A = {:.3} µm, E = {:.3} µm, R = {:.3} µm, B = {:.3} µm",
                    b.accuracy * 1e6,
                    b.systematic * 1e6,
                    b.repeatability * 1e6,
                    b.reversal * 1e6
                ),
                None => format!("laser{axis}: {} readings", self.table.readings.len()),
            },
            Err(_) => format!(
                "laser{axis}: {} readings, a drift test (mtwin analyze positioning for its figures)",
                self.table.readings.len()
            ),
        }
    }
}
