//! Shared test helpers: the bundled machines, random axis values inside their travel, and
//! rotations written out element by element (independent of the crate's own constructors).

#![allow(dead_code)] // each test file uses a different subset

use std::ffi::OsStr;
use std::path::Path;
use std::process::{Command, Output};

use mtwin::errors::{ErrorFunction, ErrorModel, ErrorParameter};
use mtwin::machine::{Axis, AxisValues, Machine};
use mtwin::math::{Real, Vector, seeded_rng};
use mtwin::twin::Twin;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// The checkout: where `models/`, `scenarios/` and `tests/data/` are.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Runs the `mtwin` binary with `args` and returns what it printed and its status, whether it
/// succeeded or not.
pub fn mtwin_output<S: AsRef<OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// `f` run on a rayon pool of `threads` threads (for tests that a result does not depend on
/// the thread count).
pub fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

/// The bundled machines.
pub const MACHINES: [&str; 3] = ["vmc3", "trunnion5", "headtable5"];

/// Loads `models/NAME.urdf`.
pub fn machine(name: &str) -> Machine {
    Machine::from_urdf_file(format!("{}/models/{name}.urdf", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// The twin of `machine` with `errors` (ISO 230-1 name, function).
pub fn twin(machine: &Machine, errors: &[(&str, ErrorFunction)]) -> Twin {
    let parameters = errors
        .iter()
        .map(|(name, function)| ErrorParameter {
            name: name.parse().unwrap(),
            function: function.clone(),
        })
        .collect();
    Twin {
        machine: machine.clone(),
        errors: ErrorModel::new(machine, parameters).unwrap(),
    }
}

/// A deterministic generator for one test.
pub fn rng(test: &str) -> ChaCha8Rng {
    seeded_rng(2026, test)
}

/// Random axis values inside the travel (continuous axes over a full turn; the spindle at a
/// random angle).
pub fn random_position(machine: &Machine, rng: &mut ChaCha8Rng) -> AxisValues {
    let mut position = AxisValues::ZERO;
    for info in machine.axes() {
        let (lower, upper) = info
            .limits
            .unwrap_or((-std::f64::consts::PI, std::f64::consts::PI));
        position[info.axis] = rng.random_range(lower..upper);
    }
    position
}

/// A 3×3 matrix as rows.
pub type M3 = [[Real; 3]; 3];

/// Rotation about x by `a` (right-handed), written out.
pub fn rx(a: Real) -> M3 {
    let (s, c) = a.sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}

/// Rotation about y by `a`, written out.
pub fn ry(a: Real) -> M3 {
    let (s, c) = a.sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

/// Rotation about z by `a`, written out.
pub fn rz(a: Real) -> M3 {
    let (s, c) = a.sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

/// Matrix product.
pub fn mul(a: M3, b: M3) -> M3 {
    let mut out = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            out[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

/// Matrix times vector.
pub fn apply(m: M3, v: Vector) -> Vector {
    let v = v.to_array();
    Vector::new(
        (0..3).map(|k| m[0][k] * v[k]).sum(),
        (0..3).map(|k| m[1][k] * v[k]).sum(),
        (0..3).map(|k| m[2][k] * v[k]).sum(),
    )
}

/// Asserts two vectors agree within `tolerance` (m or rad).
#[track_caller]
pub fn assert_close(actual: Vector, expected: Vector, tolerance: Real, what: &str) {
    let error = (actual - expected).abs().max_element();
    assert!(
        error <= tolerance,
        "{what}: got {actual:?}, expected {expected:?} (off by {error:e}, tolerance {tolerance:e})"
    );
}

/// Axis letter → value, for messages.
pub fn describe(position: &AxisValues) -> String {
    Axis::ALL
        .iter()
        .map(|a| format!("{a}={:.6}", position[*a]))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs the `mtwin` binary with `args`; panics with its standard error when it fails, else
/// returns its standard output.
pub fn mtwin(args: &[&str]) -> String {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "mtwin {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

/// The residual sum of squares of a discovery problem's base model plus `effects`, fitted to
/// every sample.
pub fn discovery_rss<P: mtwin::discovery::engine::Problem>(
    problem: &P,
    effects: &[P::Effect],
) -> Real {
    let all = vec![true; problem.n_samples()];
    let fit = problem.fit(effects, &all);
    problem.residuals(&fit).iter().map(|v| v * v).sum()
}
