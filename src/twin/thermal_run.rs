//! Running a programme on the thermal twin: the network integrated over the timeline, its
//! temperatures turned into errors, and the actual tool pose at every measurement event.

use super::Twin;
use crate::machine::Workspace;
use crate::math::{Pose, Real};
use crate::program::{Event, Program, Visit};
use crate::thermal::{MachineThermal, TemperatureSensor, ThermalStepper};

/// What the twin knows at one measurement event: the ground truth.
#[derive(Clone, Debug, PartialEq)]
pub struct ThermalRecord {
    /// The event.
    pub visit: Visit,
    /// Every node's temperature (°C), in network order.
    pub temperatures: Vec<Real>,
    /// Each sensor's reading (°C), in the order the sensors were given.
    pub readings: Vec<Real>,
    /// The actual tool pose seen from the workpiece (geometric and thermal errors).
    pub pose: Pose,
}

/// Runs `program` on `twin` with its thermal model: intervals of at most `max_interval`
/// seconds (a twentieth of the air's fast oscillation, if shorter), heat inputs and the air held
/// over each (the air at its midpoint, exact for constant air and steps at interval ends),
/// sensors `(node, sensor)` following their nodes. Returns one record per measurement event.
pub fn run_thermal(
    twin: &Twin,
    thermal: &MachineThermal,
    program: &Program,
    max_interval: Real,
    sensors: &mut [(usize, TemperatureSensor)],
) -> Vec<ThermalRecord> {
    let mut stepper = ThermalStepper::new(&thermal.network, thermal.initial);
    let mut workspace = Workspace::new(&twin.machine);
    let mut powers = vec![0.0; thermal.network.nodes().len()];
    let mut before = vec![0.0; thermal.network.nodes().len()];
    let mut extra = vec![[0.0; 6]; twin.machine.slot_count()];
    let mut time = 0.0;
    let mut records = Vec::new();
    // The air is held at its midpoint over each interval: keep intervals at a twentieth of a
    // fast oscillation's period or shorter (an error below about 1 % of its amplitude).
    let max_interval = thermal
        .ambient
        .oscillation
        .map_or(max_interval, |(_, period)| max_interval.min(period / 20.0));
    for event in program.timeline(max_interval) {
        match event {
            Event::Interval(interval) => {
                thermal.powers(&interval.speed, interval.spindle, &mut powers);
                let air = thermal.ambient.at(time + interval.duration / 2.0);
                before.copy_from_slice(stepper.temperatures());
                stepper.step(interval.duration, &powers, air);
                for (node, sensor) in sensors.iter_mut() {
                    sensor.follow(
                        before[*node],
                        stepper.temperatures()[*node],
                        interval.duration,
                    );
                }
                time += interval.duration;
            }
            Event::Measure(visit) => {
                let temperatures = stepper.temperatures().to_vec();
                thermal
                    .errors
                    .slot_twists(&temperatures, &visit.state, &mut extra);
                let pose = twin.errors.workpiece_from_tool_with(
                    &twin.machine,
                    &mut workspace,
                    &visit.state,
                    Some(&extra),
                );
                let readings = sensors
                    .iter_mut()
                    .map(|(node, sensor)| sensor.read(temperatures[*node]))
                    .collect();
                records.push(ThermalRecord {
                    visit,
                    temperatures,
                    readings,
                    pose,
                });
            }
        }
    }
    records
}
