//! Positioning discovery on the warm-up laser test (`scenarios/vmc3_warmup_laser.toml`: 7 runs
//! of 16 targets in both directions, 224 readings, one nut sensor), the layout issue 15 asks to
//! keep under 1 s:
//!
//! - `positioning_discovery/warmup_7x16`: the whole search (leave-one-run-out scoring of every
//!   testable effect in every round, the pairs, the final refit), on all cores;
//! - `positioning_discovery/warmup_7x16_one_core`: the same on a one-thread rayon pool.

use criterion::{Criterion, criterion_group, criterion_main};
use mtwin::app::Scenario;
use mtwin::kinds::positioning::{PositioningOptions, discover_positioning, run::simulate};
use std::hint::black_box;
use std::time::Duration;

fn warmup_discovery(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/vmc3_warmup_laser.toml"
    );
    let scenario = Scenario::load(path).expect("the bundled scenario loads");
    let test = scenario.laser_test.as_ref().expect("a laser test");
    let table = simulate(
        &scenario.twin,
        test,
        scenario.thermal.as_ref(),
        scenario.seed,
    )
    .table;
    assert_eq!(table.readings.len(), 224);
    let mut group = c.benchmark_group("positioning_discovery");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    group.bench_function("warmup_7x16", |b| {
        b.iter(|| {
            discover_positioning(black_box(&table), PositioningOptions::default(), |_| {})
                .expect("discovery runs")
        })
    });
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    group.bench_function("warmup_7x16_one_core", |b| {
        b.iter(|| {
            one.install(|| {
                discover_positioning(black_box(&table), PositioningOptions::default(), |_| {})
                    .expect("discovery runs")
            })
        })
    });
    group.finish();
}

criterion_group!(benches, warmup_discovery);
criterion_main!(benches);
