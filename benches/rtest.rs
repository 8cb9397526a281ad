//! R-test and collision benchmarks on trunnion5 (`scenarios/trunnion5_rtest.toml`):
//!
//! - `rtest/four_tests_360`: the scenario's four K-tests with 360 static poses each (1 440
//!   poses): the six-point calibration, the linear axes following the sphere, the twin with its
//!   eight location errors, the nest's readings and the software's conversion, into the table;
//! - `collision/one_hour`: the collision sweep of a one-hour programme (X sweeping its travel
//!   every minute, Y every 5 min, A swinging ±90° every 10 min, C turning; one sample per
//!   second) against trunnion5's bodies, cut into steps of at most 0.5 mm of motion.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use mtwin::app::Scenario;
use mtwin::collision::Scene;
use mtwin::kinds::rtest::run::simulate;
use mtwin::machine::{Axis, AxisValues};
use std::f64::consts::TAU;
use std::hint::black_box;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/trunnion5_rtest.toml"
    );
    let scenario = Scenario::load(path).unwrap_or_else(|error| panic!("loading {path}: {error}"));
    let mut test = scenario.rtest.clone().expect("an R-test");
    for k_test in &mut test.tests {
        k_test.points = 360;
    }
    let poses: usize = test.tests.iter().map(|t| t.points).sum();
    let mut group = c.benchmark_group("rtest");
    group.throughput(Throughput::Elements(poses as u64));
    group.measurement_time(Duration::from_secs(10));
    group.bench_function("four_tests_360", |b| {
        b.iter(|| black_box(simulate(&scenario.twin, &test, 7).expect("runs")))
    });
    group.finish();

    let machine = &scenario.twin.machine;
    let scene = Scene::of_machine(machine, &[]);
    let programme: Vec<(f64, AxisValues)> = (0..=3600)
        .map(|second| {
            let t = second as f64;
            let wave = |period: f64| 0.5 - 0.5 * (TAU * t / period).cos();
            let mut at = AxisValues::ZERO;
            at[Axis::X] = 0.65 * wave(60.0);
            at[Axis::Y] = 0.55 * wave(300.0);
            at[Axis::Z] = 0.45;
            at[Axis::A] = (90.0 * (TAU * t / 600.0).sin()).to_radians();
            at[Axis::C] = (TAU * t / 120.0).rem_euclid(TAU);
            (t, at)
        })
        .collect();
    scene
        .sweep(machine, &programme)
        .expect("the programme clears the machine");
    let mut group = c.benchmark_group("collision");
    group.throughput(Throughput::Elements(programme.len() as u64));
    group.measurement_time(Duration::from_secs(10));
    group.sample_size(10);
    group.bench_function("one_hour", |b| {
        b.iter(|| black_box(scene.sweep(machine, &programme).expect("clears")))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
