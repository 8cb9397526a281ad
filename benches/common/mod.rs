//! What the pose benchmarks share: the machine states they cycle through.

use mtwin::machine::{Axis, AxisValues, Direction, Machine, MachineState};
use mtwin::math::seeded_rng;
use rand::RngExt;

/// `count` deterministic machine states (seed 1, random stream `stream`) spread over the travel
/// of every axis of `machine` (continuous axes over one turn, the spindle at zero), each axis
/// with a random direction of travel.
pub fn states(machine: &Machine, count: usize, stream: &str) -> Vec<MachineState> {
    let mut rng = seeded_rng(1, stream);
    (0..count)
        .map(|_| {
            let mut state = MachineState::at(AxisValues::ZERO);
            for info in machine.axes() {
                if info.axis == Axis::S {
                    continue;
                }
                let (lower, upper) = info.limits.unwrap_or((0.0, std::f64::consts::TAU));
                state.position[info.axis] = rng.random_range(lower..=upper);
                state.direction[info.axis.index()] = if rng.random_bool(0.5) {
                    Direction::Positive
                } else {
                    Direction::Negative
                };
            }
            state
        })
        .collect()
}
