//! Forward kinematics benchmarks on the table-table 5-axis machine (`models/trunnion5.urdf`)
//! with the errors of `scenarios/trunnion5_volumetric.toml`.
//!
//! - `nominal/single`: `Workspace::workpiece_from_tool(.., None)`, one pose per iteration;
//! - `nominal/batch_1000`: `Workspace::workpiece_from_tool_batch` over 1000 poses;
//! - `errors/single`: `ErrorModel::workpiece_from_tool`, one pose per iteration;
//! - `errors/batch_1000`: `ErrorModel::workpiece_from_tool` over 1000 states;
//! - `errors/deviation`: `ErrorModel::deviation`, one pose per iteration;
//! - `errors/jacobian`: `ErrorModel::jacobian` into preallocated columns, one pose per
//!   iteration.
//!
//! Poses are drawn once, outside the timed loops, uniformly over the travel of X, Y, Z, A and
//! over a full turn of C, with random directions of travel. The single-pose benchmarks cycle
//! through the same 1000 poses so that no branch predictor learns one pose. Every benchmark
//! reports poses per second (`Throughput::Elements`).
//!
//! Pinocchio's nominal forward kinematics of the same machine is timed side by side with
//! mtwin's pose by `benches/pinocchio_side_by_side.sh` (Pinocchio's C++ against
//! `benches/pose_timer.rs`, the same loop); `benches/pinocchio_fk.py` is the older comparison
//! through Pinocchio's Python binding.

mod common;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use mtwin::app::Scenario;
use mtwin::machine::{AxisValues, Workspace};
use mtwin::math::Pose;
use std::hint::black_box;
use std::time::Duration;

/// Number of poses of the batch benchmarks (and of the pool the single-pose ones cycle over).
const POSES: usize = 1000;

/// The scenario's machine and error model.
fn load_scenario() -> Scenario {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/trunnion5_volumetric.toml"
    );
    Scenario::load(path).unwrap_or_else(|error| panic!("loading {path}: {error}"))
}

fn kinematics(c: &mut Criterion) {
    let scenario = load_scenario();
    let machine = &scenario.twin.machine;
    let errors = &scenario.twin.errors;
    assert!(
        !errors.parameters().is_empty(),
        "the scenario should inject errors"
    );
    let states = common::states(machine, POSES, "bench");
    let positions: Vec<AxisValues> = states.iter().map(|state| state.position).collect();
    let mut workspace = Workspace::new(machine);
    let mut out = vec![Pose::IDENTITY; POSES];
    let mut columns = vec![[0.0; 5]; errors.coefficient_count()];

    let mut group = c.benchmark_group("nominal");
    group.throughput(Throughput::Elements(1));
    group.bench_function("single", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % POSES;
            workspace.workpiece_from_tool(machine, black_box(&positions[i]), None)
        });
    });
    group.throughput(Throughput::Elements(POSES as u64));
    group.bench_function(BenchmarkId::new("batch", POSES), |b| {
        b.iter(|| {
            workspace.workpiece_from_tool_batch(machine, black_box(&positions), &mut out);
            black_box(&mut out);
        });
    });
    group.finish();

    let mut group = c.benchmark_group("errors");
    group.throughput(Throughput::Elements(1));
    group.bench_function("single", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % POSES;
            errors.workpiece_from_tool(machine, &mut workspace, black_box(&states[i]))
        });
    });
    group.throughput(Throughput::Elements(POSES as u64));
    group.bench_function(BenchmarkId::new("batch", POSES), |b| {
        b.iter(|| {
            for (state, pose) in black_box(&states).iter().zip(out.iter_mut()) {
                *pose = errors.workpiece_from_tool(machine, &mut workspace, state);
            }
            black_box(&mut out);
        });
    });
    group.throughput(Throughput::Elements(1));
    group.bench_function("deviation", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % POSES;
            errors.deviation(machine, &mut workspace, black_box(&states[i]))
        });
    });
    group.bench_function("jacobian", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % POSES;
            errors.jacobian(machine, &mut workspace, black_box(&states[i]), &mut columns);
            black_box(&mut columns);
        });
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .measurement_time(Duration::from_secs(3))
        .warm_up_time(Duration::from_secs(1))
        .sample_size(30);
    targets = kinematics
}
criterion_main!(benches);
