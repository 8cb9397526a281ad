//! mtwin's side of the side-by-side with Pinocchio's C++ (`../shared/bench/pin_fk.cpp`, run by
//! `benches/pinocchio_side_by_side.sh`): the same loop as that program, so that the two
//! figures are measured alike.
//!
//! On `models/trunnion5.urdf` with the 15 errors of `scenarios/trunnion5_volumetric.toml`:
//! 4096 machine states drawn once (uniform over the travel of X, Y, Z and A, C over a whole
//! turn, random directions of travel), 100 000 poses of warm-up, then `N` poses timed with a
//! monotonic clock over one loop, cycling through the states; the translation x of every pose
//! is summed into a checksum so that no pose can be left out. It times, in turn:
//!
//! - `nominal`: [`Workspace::workpiece_from_tool`] without errors;
//! - `errors`: [`ErrorModel::workpiece_from_tool`] (the actual pose, every error in the chain),
//!
//! and prints one line: `mtwin_nominal_ns_per_pose … mtwin_errors_ns_per_pose … checksum …`.
//!
//! Use: `cargo bench --bench pose_timer -- [N] [errors]` (default 2 000 000 poses; `errors`
//! times the error-model pose only, for a profiler).
//!
//! [`Workspace::workpiece_from_tool`]: mtwin::machine::Workspace::workpiece_from_tool
//! [`ErrorModel::workpiece_from_tool`]: mtwin::errors::ErrorModel::workpiece_from_tool

mod common;

use mtwin::app::Scenario;
use mtwin::machine::{MachineState, Workspace};
use std::hint::black_box;
use std::time::Instant;

/// States drawn once and cycled through, as the C++ timer does.
const STATES: usize = 4096;
/// Poses evaluated before the clock starts.
const WARM_UP: usize = 100_000;

fn main() {
    // `cargo bench` passes `--bench`; the first number is the pose count.
    let poses: usize = std::env::args()
        .skip(1)
        .find_map(|arg| arg.parse().ok())
        .unwrap_or(2_000_000);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/trunnion5_volumetric.toml"
    );
    let scenario = Scenario::load(path).unwrap_or_else(|error| panic!("loading {path}: {error}"));
    let machine = &scenario.twin.machine;
    let errors = &scenario.twin.errors;

    let states = common::states(machine, STATES, "pose timer");

    let mut workspace = Workspace::new(machine);
    let mut time = |pose: &mut dyn FnMut(&MachineState, &mut Workspace) -> f64| {
        for k in 0..WARM_UP {
            black_box(pose(&states[k % STATES], &mut workspace));
        }
        let mut sum = 0.0;
        let start = Instant::now();
        for k in 0..poses {
            sum += pose(black_box(&states[k % STATES]), &mut workspace);
        }
        let ns = start.elapsed().as_secs_f64() * 1e9 / poses as f64;
        (ns, sum)
    };
    // `errors` as an argument: the error-model pose only (for a profiler).
    let errors_only = std::env::args().any(|arg| arg == "errors");
    let (nominal_ns, _) = time(&mut |state, workspace| {
        if errors_only {
            return 0.0;
        }
        workspace
            .workpiece_from_tool(machine, &state.position, None)
            .translation
            .x
    });
    let (errors_ns, checksum) = time(&mut |state, workspace| {
        errors
            .workpiece_from_tool(machine, workspace, state)
            .translation
            .x
    });
    println!(
        "mtwin_nominal_ns_per_pose {nominal_ns:.2} mtwin_errors_ns_per_pose {errors_ns:.2} \
         checksum {checksum:.9}"
    );
}
