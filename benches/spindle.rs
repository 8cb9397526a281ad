//! Spindle analyser benchmarks (ISO 230-7):
//!
//! - `spindle/analyze_20x4096x4`: `mtwin analyze spindle`'s evaluation of one record of 20
//!   revolutions × 4096 samples × 4 radial probes (x1, y1 at one height, x2, y2 at another):
//!   the four single-probe radial tests, the two rotating-direction radial tests and the
//!   fixed and rotating tilts, each about all five centres (PC, LSC, MRS, MIC, MCC), with
//!   their spectra;
//! - `spindle/simulate_20x4096x5`: the virtual analyser on `scenarios/vmc3_spindle.toml`'s
//!   five-probe nest at one speed, 20 revolutions × 4096 samples, through the twin with its
//!   synchronous, asynchronous and random spindle errors (throughput in probe samples).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use mtwin::app::Scenario;
use mtwin::kinds::spindle::evaluate::{Options, evaluate};
use mtwin::kinds::spindle::run::simulate;
use mtwin::kinds::spindle::{Sensing, SpindleProbe, SpindleRecord};
use mtwin::machine::Axis;
use std::f64::consts::TAU;
use std::hint::black_box;
use std::time::Duration;

/// A record with an elliptical 3-per-revolution motion, a 0.43-per-revolution line and a
/// tilt, read by x1, y1 at z = 0 and x2, y2 at z = 80 mm.
fn record(revolutions: usize, m: usize) -> SpindleRecord {
    let n = revolutions * m;
    let probes: Vec<SpindleProbe> = [
        ("x1", 0.0, 0.0),
        ("y1", 90.0, 0.0),
        ("x2", 0.0, 0.08),
        ("y2", 90.0, 0.08),
    ]
    .iter()
    .map(|&(name, azimuth_deg, z): &(&str, f64, f64)| {
        let a = azimuth_deg.to_radians();
        SpindleProbe {
            name: name.to_string(),
            direction: [-a.cos(), -a.sin(), 0.0],
            position: [0.0125 * a.cos(), 0.0125 * a.sin(), z],
            sensing: Sensing::Fixed,
        }
    })
    .collect();
    let mut readings = vec![vec![0.0; n]; 4];
    let (mut revolution, mut angle, mut time) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        let theta = TAU * (i % m) as f64 / m as f64;
        let turns = i as f64 / m as f64;
        let ex = 0.1e-6 * (3.0 * theta).cos() + 0.02e-6 * (TAU * 0.43 * turns).sin();
        let ey = 0.05e-6 * (3.0 * theta + 0.4).sin();
        let tilt = 0.5e-6 * (2.0 * theta).sin();
        for (probe, values) in probes.iter().zip(readings.iter_mut()) {
            let z = probe.position[2];
            let (x, y) = (ex + z * tilt, ey - z * tilt);
            values[i] = probe.direction[0] * x + probe.direction[1] * y;
        }
        revolution.push(i / m);
        angle.push(theta);
        time.push(turns / 100.0);
    }
    SpindleRecord {
        axis: Axis::S,
        probes,
        setup: vec![String::new(); n],
        revolution,
        angle,
        time,
        speed: vec![TAU * 100.0; n],
        readings,
    }
}

fn bench(c: &mut Criterion) {
    let m = 4096;
    let record = record(20, m);
    let options = Options::default();
    let mut group = c.benchmark_group("spindle");
    group.throughput(Throughput::Elements((record.len() * 4) as u64));
    group.measurement_time(Duration::from_secs(10));
    group.bench_function("analyze_20x4096x4", |b| {
        b.iter(|| black_box(evaluate(&record, m, &options).expect("evaluates")))
    });
    group.finish();

    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/vmc3_spindle.toml");
    let scenario = Scenario::load(path).unwrap_or_else(|error| panic!("loading {path}: {error}"));
    let mut test = scenario.spindle_test.clone().expect("a spindle test");
    test.speeds.truncate(1);
    test.revolutions = 20;
    test.samples_per_revolution = m;
    let samples = test.revolutions * m * test.probes.len();
    let mut group = c.benchmark_group("spindle");
    group.throughput(Throughput::Elements(samples as u64));
    group.measurement_time(Duration::from_secs(10));
    group.bench_function("simulate_20x4096x5", |b| {
        b.iter(|| black_box(simulate(&scenario.twin, &test, 11).expect("runs")))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
