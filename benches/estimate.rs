//! Estimator benchmarks on trunnion5 (`scenarios/trunnion5_rtest.toml`, its four K-tests with
//! 360 static poses each: 1 440 poses, 4 320 readings):
//!
//! - `estimate/identify_location_1440`: the 8 location errors of A and C (plus the 12 zero
//!   offsets of the four tests) from the simulated table: the identifiability analysis at the
//!   start, the Levenberg–Marquardt fit on the exact chain, the covariance;
//! - `estimate/identify_location_components_2880`: the 8 location errors and 12 component
//!   coefficients of C (`EAC:2,EBC:2,EZC:2,ECC:1`: orders 1–2 of the tilts, the order-1 pair
//!   turning against C, and of the axial motion; order 1 of the angular motion) from two
//!   spheres 80 mm apart in height, each read by the four K-tests (2 880 poses, 8 640
//!   readings), on one core;
//! - `estimate/discover_2880`: model selection on the same two spheres' tables (read with a
//!   drift rate) from the 8 location errors, the library's 41 terms (`identify --discover`,
//!   [`mtwin::estimate::discover`]): the linearisation, the held-out scores and the search,
//!   on the machine's cores;
//! - `estimate/monte_carlo_1000_one_core`: the same with 1 000 Monte Carlo trials, on a
//!   one-thread rayon pool;
//! - `estimate/linear_design_lm`: the solver alone on the linear problem `J z = y` with the
//!   fit's own design matrix (4 320 × 20), the problem `benches/scipy_least_squares.py` gives
//!   `scipy.optimize.least_squares` (the matrix is written to
//!   `target/criterion/estimate_design.csv` for it).

use criterion::{Criterion, criterion_group, criterion_main};
use mtwin::app::Scenario;
use mtwin::estimate::fit::{self, Problem};
use mtwin::estimate::lm;
use mtwin::estimate::spec::ParameterSet;
use mtwin::kinds::rtest::readings::{Setup, readings};
use mtwin::kinds::rtest::run::simulate;
use nalgebra::DMatrix;
use std::hint::black_box;
use std::time::Duration;

/// `J z = y` as a least-squares problem with an analytic Jacobian.
struct Linear<'a> {
    design: &'a DMatrix<f64>,
    y: &'a [f64],
}

impl lm::Problem for Linear<'_> {
    fn residual_count(&self) -> usize {
        self.design.nrows()
    }
    fn parameter_count(&self) -> usize {
        self.design.ncols()
    }
    fn residuals(&self, x: &[f64], out: &mut [f64]) {
        let r = self.design * nalgebra::DVector::from_column_slice(x);
        for (o, (r, y)) in out.iter_mut().zip(r.iter().zip(self.y)) {
            *o = r - y;
        }
    }
    fn jacobian(&self, _: &[f64], out: &mut DMatrix<f64>) {
        out.copy_from(self.design);
    }
}

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
    let machine = &scenario.twin.machine;
    let table = simulate(&scenario.twin, &test, 7).expect("runs");
    let sets = [readings(&table, "bench", machine, Setup::default()).expect("readings")];
    let set = ParameterSet::parse("location", machine).expect("a spec");
    let problem = Problem::new(machine, &set, &sets).expect("a problem");
    let one_core = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool");

    let mut group = c.benchmark_group("estimate");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(20));
    group.bench_function("identify_location_1440", |b| {
        b.iter(|| {
            one_core.install(|| {
                black_box(fit::estimate(&problem, &fit::Options::default()).expect("fits"))
            })
        })
    });
    // The second sphere 80 mm higher on its post.
    let mut higher = test.clone();
    higher.sphere.z += 0.080;
    let two = [
        readings(&table, "bench", machine, Setup::default()).expect("readings"),
        readings(
            &simulate(&scenario.twin, &higher, 8).expect("runs"),
            "bench",
            machine,
            Setup::default(),
        )
        .expect("readings"),
    ];
    let components =
        ParameterSet::parse("location,EAC:2,EBC:2,EZC:2,ECC:1", machine).expect("a spec");
    let with_components = Problem::new(machine, &components, &two).expect("a problem");
    group.bench_function("identify_location_components_2880", |b| {
        b.iter(|| {
            one_core.install(|| {
                black_box(fit::estimate(&with_components, &fit::Options::default()).expect("fits"))
            })
        })
    });
    let rated = |table, sphere_set: &str| {
        let setup = Setup {
            drift: mtwin::kinds::rtest::readings::Drift::Rate,
            ..Setup::default()
        };
        readings(table, sphere_set, machine, setup).expect("readings")
    };
    let higher_table = simulate(&scenario.twin, &higher, 8).expect("runs");
    let two_rated = [rated(&table, "bench"), rated(&higher_table, "bench higher")];
    group.bench_function("discover_2880", |b| {
        b.iter(|| {
            black_box(
                mtwin::estimate::discover::discover(machine, "location", &two_rated, true, |_| {})
                    .expect("selects"),
            )
        })
    });
    let options = fit::Options {
        trials: 1000,
        ..Default::default()
    };
    group.bench_function("monte_carlo_1000_one_core", |b| {
        b.iter(|| one_core.install(|| black_box(fit::estimate(&problem, &options).expect("fits"))))
    });

    let design = fit::start_design(&problem);
    let y: Vec<f64> = (0..design.nrows())
        .map(|i| ((i * 7919) % 1000) as f64 / 1000.0 - 0.5)
        .collect();
    write_design(&design, &y);
    let linear = Linear {
        design: &design,
        y: &y,
    };
    group.bench_function("linear_design_lm", |b| {
        b.iter(|| {
            black_box(
                lm::solve(&linear, &vec![0.0; design.ncols()], &lm::Options::default())
                    .expect("solves"),
            )
        })
    });
    group.finish();
}

/// The design and right-hand side for the scipy comparison: one row per reading, the
/// columns then `y` last.
fn write_design(design: &DMatrix<f64>, y: &[f64]) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/criterion");
    let dir = std::env::var_os("CARGO_TARGET_DIR")
        .map_or(dir, |t| std::path::PathBuf::from(t).join("criterion"));
    let _ = std::fs::create_dir_all(&dir);
    let mut text = String::new();
    for i in 0..design.nrows() {
        for j in 0..design.ncols() {
            text += &format!("{:e},", design[(i, j)]);
        }
        text += &format!("{:e}\n", y[i]);
    }
    let _ = std::fs::write(dir.join("estimate_design.csv"), text);
}

criterion_group!(benches, bench);
criterion_main!(benches);
