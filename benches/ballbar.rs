//! Ball-bar benchmarks on `scenarios/vmc3_ballbar_xy.toml` (vmc3, XY, 150 mm, 1000 mm/min, a
//! full circle each way with 180° overshoots: 226 s of programme, 28 274 readings):
//!
//! - `simulate/xy_test`: controller (1 ms interpolation, exact loop integration), twin (errors
//!   at every reading) and bar, for the whole test;
//! - `analyze/xy_test`: the ISO 230-4 evaluation with every diagnostic (spike decay and cyclic
//!   period searches included) of the table that test writes;
//! - `discover/xy_test`: model discovery on that table (`mtwin discover ballbar`): every
//!   testable effect scored in every round by 8 angular-sector folds (nine fits a score, each
//!   with its lag, decay, period and lobe searches), pairs when no single effect passes.
//!
//! All report readings per second (`Throughput::Elements`). The fits of a score run on rayon's
//! pool: set `RAYON_NUM_THREADS` to pin the thread count.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use mtwin::app::Scenario;
use mtwin::kinds::ballbar::discover_ballbar;
use mtwin::kinds::ballbar::iso230_4::{CircularTest, evaluate};
use mtwin::math::seeded_rng;
use std::hint::black_box;
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/vmc3_ballbar_xy.toml"
    );
    let scenario = Scenario::load(path).unwrap_or_else(|error| panic!("loading {path}: {error}"));
    let test = scenario.ballbar_test.as_ref().expect("a ball-bar test");
    let circle = &test.circles[0];
    let measure = || {
        test.ballbar.measure(
            &scenario.twin,
            circle,
            &test.servo,
            &mut seeded_rng(scenario.seed, "ballbar XY"),
        )
    };
    let table = measure();
    let readings = table.readings.len() as u64;

    let mut group = c.benchmark_group("simulate");
    group.throughput(Throughput::Elements(readings));
    group.measurement_time(Duration::from_secs(10));
    group.bench_function("xy_test", |b| b.iter(|| black_box(measure())));
    group.finish();

    let conditions = CircularTest {
        plane: circle.plane,
        radius: circle.radius,
        feed: circle.feed,
    };
    let mut group = c.benchmark_group("analyze");
    group.throughput(Throughput::Elements(readings));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(20));
    group.bench_function("xy_test", |b| {
        b.iter(|| black_box(evaluate(black_box(&table), &conditions).unwrap()))
    });
    group.finish();

    let mut group = c.benchmark_group("discover");
    group.throughput(Throughput::Elements(readings));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(40));
    group.bench_function("xy_test", |b| {
        b.iter(|| black_box(discover_ballbar(black_box(&table), &conditions, |_| {}).unwrap()))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
