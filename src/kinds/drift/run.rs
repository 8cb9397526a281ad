//! Running the ETVE test through the thermal twin: the machine holds, the air changes, the nest
//! reads the mandrel and the thermometers read the air and the structure at every sample.

use super::iso230_3::etve;
use super::scenario::{EtveTest, Nest};
use super::table::{DriftChannel, DriftConditions, DriftTable};
use crate::machine::{Axis, AxisValues};
use crate::math::{M_PER_MM, Pose, Real, Vector, quantise, seeded_rng, standard_normal, trimmed};
use crate::program::Program;
use crate::scenario::ThermalSetup;
use crate::thermal::{SensorSpec, TemperatureSensor};
use crate::twin::{ThermalRecord, Twin};
use serde_json::{Value, json};

/// The linear axes, where the machine holds.
const LINEAR: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

/// The five channels of the nest, in table order.
pub const CHANNELS: [&str; 5] = ["x1", "y1", "x2", "y2", "z"];

/// A simulated ETVE test: the table and what the twin knew at each sample.
#[derive(Clone, Debug)]
pub struct EtveRun {
    /// The instrument's table.
    pub table: DriftTable,
    /// The true displacement of each channel, zeroed at the start (m), without noise or
    /// resolution: the truth the table's channels measure.
    pub true_channels: Vec<DriftChannel>,
    /// The thermal twin at each sample.
    pub records: Vec<ThermalRecord>,
}

/// The points the nest reads, in the tool frame (m): X1/Y1, X2/Y2 and the mandrel's end.
fn nest_points(nest: &Nest) -> [Vector; 3] {
    [
        Vector::new(0.0, 0.0, nest.first),
        Vector::new(0.0, 0.0, nest.first + nest.spacing),
        Vector::ZERO,
    ]
}

/// The true channel values at `pose` relative to `start` (m): each sensor reads how far the
/// mandrel's point in front of it has moved along the sensor's axis, in the workpiece frame.
fn channel_values(nest: &Nest, start: &Pose, pose: &Pose) -> [Real; 5] {
    let [first, second, end] = nest_points(nest);
    let moved = |q: Vector| pose.transform_point3(q) - start.transform_point3(q);
    let (one, two, tip) = (moved(first), moved(second), moved(end));
    [one.x, one.y, two.x, two.y, tip.z]
}

/// What a nest and the thermometers read while `program` runs on the thermal twin: shared by
/// the drift tests (ETVE, spindle), which add their conditions to make the table.
pub(crate) struct NestReadings {
    /// The thermal twin at each measurement.
    pub records: Vec<ThermalRecord>,
    /// The five channels as the nest read them (m), in [`CHANNELS`] order.
    pub channels: Vec<DriftChannel>,
    /// The same without noise or resolution: the truth.
    pub true_channels: Vec<DriftChannel>,
    /// The ambient thermometer `air`, then `setup`'s sensors (°C).
    pub temperatures: Vec<(String, Vec<Real>)>,
}

/// Runs `program` on `twin` through `setup` and reads `nest` (its noise from the stream
/// `<test> nest`) and the ambient thermometer `air` (stream `<test> air`) at every measurement,
/// relative to the first; the random streams are seeded from `seed`.
pub(crate) fn read_nest(
    twin: &Twin,
    setup: &ThermalSetup,
    program: &Program,
    nest: &Nest,
    air: &SensorSpec,
    seed: u64,
    test: &str,
) -> NestReadings {
    let records = setup.run(twin, program, seed);
    let start = records.first().map_or(Pose::IDENTITY, |r| r.pose);
    let truth: Vec<[Real; 5]> = records
        .iter()
        .map(|r| channel_values(nest, &start, &r.pose))
        .collect();
    let mut rng = seeded_rng(seed, &format!("{test} nest"));
    let channel = |k: usize, values: Vec<Real>| DriftChannel {
        name: CHANNELS[k].to_string(),
        angular: false,
        values,
    };
    let mut read = |value: Real| {
        let noise = if nest.noise > 0.0 {
            nest.noise * standard_normal(&mut rng)
        } else {
            0.0
        };
        quantise(value + noise, nest.resolution)
    };
    // Channel by channel over time would change with the channel count; row by row is the
    // order an instrument samples in.
    let mut measured = vec![Vec::with_capacity(records.len()); CHANNELS.len()];
    for row in &truth {
        for (k, value) in row.iter().enumerate() {
            measured[k].push(read(*value));
        }
    }
    let mut thermometer = TemperatureSensor::new(
        air.clone(),
        setup.thermal.initial,
        seeded_rng(seed, &format!("{test} air")),
    );
    let air_readings: Vec<Real> = records
        .iter()
        .map(|r| thermometer.read(setup.thermal.ambient.at(r.visit.time)))
        .collect();
    let mut temperatures = vec![(air.name.clone(), air_readings)];
    for (k, (_, spec)) in setup.sensors.iter().enumerate() {
        let values = records.iter().map(|r| r.readings[k]).collect();
        temperatures.push((spec.name.clone(), values));
    }
    NestReadings {
        channels: measured
            .into_iter()
            .enumerate()
            .map(|(k, values)| channel(k, values))
            .collect(),
        true_channels: (0..CHANNELS.len())
            .map(|k| channel(k, truth.iter().map(|row| row[k]).collect()))
            .collect(),
        temperatures,
        records,
    }
}

/// Where the linear axes of `twin`'s machine hold, for a table's conditions: `x 380, y 205, z 260`.
pub(crate) fn hold_condition(twin: &Twin, hold: &AxisValues) -> String {
    let hold: Vec<String> = LINEAR
        .iter()
        .filter(|a| twin.machine.has_axis(**a))
        .map(|a| {
            format!(
                "{} {}",
                a.letter().to_ascii_lowercase(),
                trimmed(hold[*a] / M_PER_MM, 6)
            )
        })
        .collect();
    hold.join(", ")
}

/// Simulates `test` on `twin` through `setup`, the random streams seeded from `seed`.
pub fn simulate(twin: &Twin, test: &EtveTest, setup: &ThermalSetup, seed: u64) -> EtveRun {
    let readings = read_nest(
        twin,
        setup,
        &test.program,
        &test.nest,
        &test.air,
        seed,
        "etve",
    );
    let table = DriftTable {
        times: readings.records.iter().map(|r| r.visit.time).collect(),
        channels: readings.channels,
        temperatures: readings.temperatures,
        conditions: DriftConditions {
            test: Some("iso230_3_etve".into()),
            ambient_sensor: Some("air".into()),
            spacing: Some(test.nest.spacing),
            control: Some(test.control),
            hold: Some(hold_condition(twin, &test.hold)),
            first: Some(test.nest.first),
            ..DriftConditions::default()
        },
        columns_not_read: Vec::new(),
    };
    EtveRun {
        table,
        true_channels: readings.true_channels,
        records: readings.records,
    }
}

/// The ETVE test as injected and the true ETVE of each channel for a 60 min test (file units),
/// for `truth.json`.
pub fn truth(test: &EtveTest, run: &EtveRun) -> Value {
    let times = &run.table.times;
    let channels: Vec<Value> = run
        .true_channels
        .iter()
        .map(|c| {
            let record: Vec<(Real, Real)> = times
                .iter()
                .copied()
                .zip(c.values.iter().copied())
                .collect();
            let worst = etve(&record, 3600.0);
            json!({
                "name": c.name,
                "etve_60_min_um": worst.map(|(range, _)| range * 1e6),
                "etve_60_min_window_min": worst.map(|(_, s)| [s / 60.0, s / 60.0 + 60.0]),
                "final_um": c.values.last().map(|v| v * 1e6),
            })
        })
        .collect();
    json!({
        "test": "iso230_3_etve",
        "hold_mm": LINEAR.map(|a| (a.letter().to_ascii_lowercase().to_string(), json!(test.hold[a] / M_PER_MM))).into_iter().collect::<serde_json::Map<_, _>>(),
        "control": test.control.name(),
        "sample_min": test.sample / 60.0,
        "nest": {
            "first_mm": test.nest.first / M_PER_MM,
            "spacing_mm": test.nest.spacing / M_PER_MM,
            "noise_um": test.nest.noise * 1e6,
            "resolution_um": test.nest.resolution * 1e6,
        },
        "air_thermometer": { "noise_degc": test.air.noise, "resolution_degc": test.air.resolution },
        "true_channels": channels,
    })
}

impl EtveRun {
    /// One line for people: the largest ETVE of a 60 min test among the linear channels.
    pub fn summary(&self) -> String {
        let times = &self.table.times;
        let worst = self
            .table
            .channels
            .iter()
            .filter_map(|c| {
                let record: Vec<(Real, Real)> = times
                    .iter()
                    .copied()
                    .zip(c.values.iter().copied())
                    .collect();
                etve(&record, 3600.0).map(|(range, _)| (range, c.name.clone()))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        match worst {
            Some((range, name)) => format!(
                "ETVE test: {:.1} h, largest ETVE of a 60 min test {:.3} µm ({})",
                times.last().copied().unwrap_or(0.0) / 3600.0,
                range * 1e6,
                name.to_uppercase()
            ),
            None => format!(
                "ETVE test: {:.1} h (shorter than a 60 min test)",
                times.last().copied().unwrap_or(0.0) / 3600.0
            ),
        }
    }
}
