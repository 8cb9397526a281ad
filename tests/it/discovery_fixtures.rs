//! Realistic fixtures for positioning discovery (issue 15, item 7): warm-up laser records made
//! by the twin itself (its thermal network, its laser), exported as a real instrument would
//! export them, and given to `discover_positioning`.
//!
//! Every fixture is a `[warmup]` scenario on vmc3 written into a temporary folder and run
//! through `mtwin::app::simulate`: the first run is cold (the reference run of the base model),
//! the axis then idles over its stroke at 4 800 mm/min between runs, the nut warms by
//! 3–4 °C (most of it in the first idle interval) and the screw follows it through the
//! network (the screw lags the nut, and also takes heat from the motor the nut does not see).
//! The laser is zeroed once, at the first reading, as in a drift test. The export adds
//! 0.5–1 µm of reading noise (seeded: `seeded_rng(seed, "reading noise")`), rounds deviations to
//! 0.01 µm and times to 0.01 min, and keeps the sensor's own reading (0.01 °C noise and
//! resolution) — no preamble, as a plain CSV from an instrument.
//!
//! Truth comes from the twin, never from discovery: the injected lost motion, expansion
//! coefficient and fixed end, and the true node temperatures at every reading (the screw's
//! temperature for the expansion an unseen heat source causes, the nut's and the screw's for
//! the lag). Linear parameters must lie within 4 standard errors of the truth, the standard
//! errors the closed form of least squares for the fixture's layout and noise
//! ([`standard_errors`]). Each null fixture is the same scenario and the same noise draws with
//! the effect removed: it must add nothing.
//!
//! Where the file cannot tell two causes apart (a screw lagging the nut sensor reads, on a
//! warm-up record, like a heat source the sensor misses), the fixture asks what the twin
//! allows rather than one expected set ([`Description`]): the accepted model, refitted to the
//! twin's noise-free deviations, must describe them as well as the best description the
//! library has, within four standard errors; each of its effects must be needed for that; and
//! each value must be that description's on the truth within four standard errors.
//!
//! Several fixtures fail with today's selection; they are `#[ignore]`d with what happens (run
//! them with `cargo test --release --test it discovery_fixtures:: -- --ignored --nocapture`).

use PositioningEffect as E;
use mtwin::app::{Scenario, simulate};
use mtwin::kinds::positioning::{
    PositioningDiscovery, PositioningEffect, PositioningOptions, PositioningTable,
    discover_positioning,
};
use mtwin::math::{local_rates, seeded_rng, standard_normal};
use mtwin::program::Approach;
use nalgebra::DMatrix;

/// Seeds of every fixture (the scenario seed: the sensor's noise; and the export's noise).
const SEEDS: std::ops::RangeInclusive<u64> = 1..=4;
/// Nominal expansion coefficient of the base model (µm/(m·°C)).
const NOMINAL_PPM: f64 = 11.7;
/// The temperature sensor's noise and resolution (°C), as written into the scenario.
const SENSOR_NOISE_DEGC: f64 = 0.01;
const SENSOR_RESOLUTION_DEGC: f64 = 0.01;
/// Tolerance of a linear parameter, in standard errors.
const STANDARD_ERRORS: f64 = 4.0;

/// A warm-up laser test on vmc3 and how its table is exported.
#[derive(Clone, Debug)]
struct Fixture {
    /// `X` or `Z`.
    axis: &'static str,
    runs: usize,
    /// Targets `(from, to, step)` (mm).
    targets_mm: (f64, f64, f64),
    /// Idle stroke between runs (mm) and its duration (min), at 4 800 mm/min.
    idle_mm: (f64, f64),
    idle_min: f64,
    /// Where the other axes stand (TOML lines).
    park: &'static str,
    /// The node the one temperature sensor is on, and its own time constant (s).
    sensor_node: &'static str,
    sensor_lag_s: f64,
    /// The screw's true expansion coefficient (µm/(m·°C)) and its fixed end (mm).
    expansion_ppm: f64,
    fixed_end_mm: f64,
    /// Injected lost motion of the axis (µm).
    reversal_um: f64,
    /// Reading noise added by the export (µm, standard deviation).
    noise_um: f64,
    /// Whether the axis's motor heats (the default network: 150 W per m/s into the motor
    /// node, which passes it to the screw and the sensor does not see it).
    motor_heat: bool,
}

impl Fixture {
    /// The X axis of the Lu (2012) warm-up record: 16 targets over 750 mm, 7 runs over about
    /// 5 h (45 min idle between runs), the nut sensor, 4 µm of lost motion.
    fn x_axis() -> Fixture {
        Fixture {
            axis: "X",
            runs: 7,
            targets_mm: (5.0, 755.0, 50.0),
            idle_mm: (0.0, 750.0),
            idle_min: 45.0,
            park: "y_mm = 205.0\nz_mm = 100.0",
            sensor_node: "x_nut",
            sensor_lag_s: 20.0,
            expansion_ppm: NOMINAL_PPM,
            fixed_end_mm: 0.0,
            reversal_um: 4.0,
            noise_um: 0.7,
            motor_heat: true,
        }
    }

    /// The Z axis of issue 15: 9 targets over 400 mm, 5 runs over 140 min (33 min idle
    /// between runs), the nut warming by 4 °C, no lost motion.
    fn z_axis() -> Fixture {
        Fixture {
            axis: "Z",
            runs: 5,
            targets_mm: (10.0, 410.0, 50.0),
            idle_mm: (0.0, 500.0),
            idle_min: 33.0,
            park: "x_mm = 380.0\ny_mm = 205.0",
            sensor_node: "z_nut",
            sensor_lag_s: 20.0,
            expansion_ppm: NOMINAL_PPM,
            fixed_end_mm: 0.0,
            reversal_um: 0.0,
            noise_um: 0.7,
            motor_heat: true,
        }
    }

    /// This fixture with the sensor on the axis's screw (5 s of its own lag: a sensor in good
    /// contact), so that the measured temperature is the one that expands the axis.
    fn sensor_on_screw(self) -> Fixture {
        let node = if self.axis == "X" {
            "x_screw"
        } else {
            "z_screw"
        };
        Fixture {
            sensor_node: node,
            sensor_lag_s: 5.0,
            ..self
        }
    }

    fn toml(&self, seed: u64) -> String {
        let a = self.axis.to_ascii_lowercase();
        let machine = format!("{}/models/vmc3.urdf", env!("CARGO_MANIFEST_DIR"));
        let reversal = if self.reversal_um != 0.0 {
            format!("reversal_um = {}", self.reversal_um)
        } else {
            String::new()
        };
        format!(
            r#"schema = 1
machine = {machine:?}
seed = {seed}

[errors.E{ax}{ax}]
polynomial_um = [0.0, 0.006, -0.000008]   # cold positioning error: 6 µm/m and a bow
{reversal}

[thermal]
ambient_degc = 20.0
fixed_end_mm = {{ {a} = {fixed} }}
expansion_ppm_per_degc = {{ {a} = {expansion} }}
max_interval_s = 60.0
sensors = [{{ node = "{node}", noise_degc = {noise}, resolution_degc = {resolution}, lag_s = {lag} }}]

[warmup]
axis = "{ax}"
targets_mm = {{ from = {t0}, to = {t1}, step = {ts} }}
runs = {runs}
overrun_mm = 5.0
feed_mm_per_min = 2000.0
dwell_s = 4.0
idle = {{ from_mm = {i0}, to_mm = {i1}, feed_mm_per_min = 4800.0, minutes = {minutes} }}
{park}

[laser]
resolution_nm = 1.0
noise_nm = 0.0
compensation = "sensors"
zero = "once"
"#,
            ax = self.axis,
            fixed = self.fixed_end_mm,
            expansion = self.expansion_ppm,
            node = self.sensor_node,
            noise = SENSOR_NOISE_DEGC,
            resolution = SENSOR_RESOLUTION_DEGC,
            lag = self.sensor_lag_s,
            t0 = self.targets_mm.0,
            t1 = self.targets_mm.1,
            ts = self.targets_mm.2,
            runs = self.runs,
            i0 = self.idle_mm.0,
            i1 = self.idle_mm.1,
            minutes = self.idle_min,
            park = self.park,
        )
    }

    /// Runs the scenario (seed `seed`) through the twin.
    fn simulate(&self, seed: u64) -> Simulated {
        let dir = tempfile::TempDir::new().unwrap();
        let path = dir.path().join("fixture.toml");
        std::fs::write(&path, self.toml(seed)).unwrap();
        let mut scenario = Scenario::load(&path).unwrap();
        let thermal = &mut scenario
            .thermal
            .as_mut()
            .expect("a [thermal] section")
            .thermal;
        if !self.motor_heat {
            let motor = format!("{}_motor", self.axis.to_ascii_lowercase());
            let motor = thermal.network.node(&motor).expect("the motor node");
            thermal.sources.retain(|s| s.node != motor);
        }
        let nodes = thermal
            .network
            .nodes()
            .iter()
            .map(|n| n.name.clone())
            .collect();
        let run = simulate(&scenario).unwrap().laser.expect("a laser test");
        let temperatures = run
            .thermal
            .expect("run through the thermal model")
            .into_iter()
            .map(|r| r.temperatures)
            .collect();
        Simulated {
            table: run.table,
            nodes,
            temperatures,
        }
    }

    /// The table as an instrument exports it: reading noise `noise_um` (seeded), deviations
    /// rounded to 0.01 µm, times to 0.01 min, temperatures as the sensor read them; no preamble.
    fn export(&self, simulated: &Simulated, seed: u64, noise_um: f64) -> PositioningTable {
        let mut rng = seeded_rng(seed, "reading noise");
        let table = &simulated.table;
        let mut csv = String::from("axis,run,direction,target_mm,deviation_um,time_min");
        for sensor in &table.sensors {
            csv.push_str(&format!(",temp_{sensor}_degc"));
        }
        csv.push('\n');
        for r in &table.readings {
            let deviation_um = r.deviation * 1e6 + noise_um * standard_normal(&mut rng);
            let direction = if r.approach == Approach::Up { "+" } else { "-" };
            csv.push_str(&format!(
                "{},{},{direction},{:.3},{deviation_um:.2},{:.2}",
                self.axis,
                r.run + 1,
                r.target * 1e3,
                r.time.expect("the twin records time") / 60.0
            ));
            for t in &r.temperatures {
                csv.push_str(&format!(",{t:.2}"));
            }
            csv.push('\n');
        }
        PositioningTable::parse(csv.as_bytes(), "export.csv").expect("a valid export")
    }

    /// Simulates, exports with this fixture's noise and discovers.
    fn discover(&self, seed: u64) -> Found {
        let simulated = self.simulate(seed);
        let table = self.export(&simulated, seed, self.noise_um);
        let discovery = discover_positioning(&table, PositioningOptions::default(), |_| {})
            .expect("discovery runs");
        Found {
            simulated,
            table,
            discovery,
        }
    }

    /// The reading noise left once every term is known: the export's noise and rounding, and
    /// the sensor's noise and resolution carried by `ppm` µm/(m·°C) of expansion over the
    /// farthest target from the fixed end and `offset` µm/°C of origin drift (µm).
    fn noise_with_sensor(&self, ppm: f64, offset: f64) -> f64 {
        let sensor = (SENSOR_NOISE_DEGC.powi(2) + SENSOR_RESOLUTION_DEGC.powi(2) / 12.0).sqrt();
        let reach_m = (self.targets_mm.1 - self.fixed_end_mm)
            .abs()
            .max((self.targets_mm.0 - self.fixed_end_mm).abs())
            * 1e-3;
        let rounding = 0.01 / 12f64.sqrt();
        (self.noise_um.powi(2)
            + rounding.powi(2)
            + ((ppm * reach_m + offset.abs()) * sensor).powi(2))
        .sqrt()
    }
}

/// A simulated laser test and the truth at each reading.
struct Simulated {
    /// The twin's table (no reading noise yet).
    table: PositioningTable,
    /// The thermal network's node names.
    nodes: Vec<String>,
    /// Every node's true temperature (°C) at each reading.
    temperatures: Vec<Vec<f64>>,
}

impl Simulated {
    /// The true temperature of `node` at each reading (°C).
    fn node(&self, node: &str) -> Vec<f64> {
        let k = self.nodes.iter().position(|n| n == node).expect("a node");
        self.temperatures.iter().map(|t| t[k]).collect()
    }

    /// Each reading's time (s).
    fn times(&self) -> Vec<f64> {
        self.table
            .readings
            .iter()
            .map(|r| r.time.expect("timed"))
            .collect()
    }

    /// The mean of `values` over each run's readings.
    fn run_means(&self, values: &[f64]) -> Vec<f64> {
        let runs = self.table.runs.len();
        let mut sum = vec![0.0; runs];
        let mut count = vec![0.0; runs];
        for (r, v) in self.table.readings.iter().zip(values) {
            sum[r.run] += v;
            count[r.run] += 1.0;
        }
        sum.iter().zip(&count).map(|(s, c)| s / c).collect()
    }
}

/// A fixture's discovery with what it was made from.
struct Found {
    simulated: Simulated,
    table: PositioningTable,
    discovery: PositioningDiscovery,
}

impl Found {
    fn param(&self, effect: PositioningEffect, key: &str) -> f64 {
        self.discovery
            .final_params(effect)
            .unwrap_or_else(|| panic!("{} not accepted", effect.id()))[key]
    }

    /// The measured temperature (the file's one sensor) at each reading (°C).
    fn sensor(&self) -> Vec<f64> {
        self.table
            .readings
            .iter()
            .map(|r| r.temperatures[0])
            .collect()
    }
}

/// A term of the linear model whose coefficient's standard error is wanted (deviations in µm,
/// positions in m, temperatures in °C).
enum Column {
    /// Lost motion `−s/2` (µm).
    Reversal,
    /// Expansion `x·T` of the given temperature (µm/(m·°C) = ppm/°C).
    Scale(Vec<f64>),
    /// Origin drift `T` (µm/°C).
    Offset(Vec<f64>),
    /// Expansion `x·g` of an activity response `g` (µm/m).
    Growth(Vec<f64>),
}

/// Standard errors of the coefficients of `columns` in the least-squares fit of `table` by a
/// profile (one value per target, every reading being at a target) plus `columns`, for white
/// reading noise of `sigma_um`: `σ·√diag((AᵀA)⁻¹)`. The closed form of least squares, computed
/// here from the layout of the file.
fn standard_errors(table: &PositioningTable, columns: &[Column], sigma_um: f64) -> Vec<f64> {
    let (a, k) = design(table, columns);
    let inverse = mtwin_kernels::linalg::try_inverse(a.transpose() * &a)
        .expect("the columns are independent of the profile");
    (0..columns.len())
        .map(|j| sigma_um * inverse[(k + j, k + j)].sqrt())
        .collect()
}

/// The design matrix of a profile (one value per target, every reading being at a target)
/// plus `columns`, one row per reading of `table`, and the number of targets.
fn design(table: &PositioningTable, columns: &[Column]) -> (DMatrix<f64>, usize) {
    let mut targets: Vec<f64> = Vec::new();
    for r in &table.readings {
        if targets.iter().all(|t| (t - r.target).abs() > 1e-9) {
            targets.push(r.target);
        }
    }
    let (n, k) = (table.readings.len(), targets.len());
    let a = DMatrix::from_fn(n, k + columns.len(), |i, j| {
        let r = &table.readings[i];
        if j < k {
            return f64::from(u8::from((targets[j] - r.target).abs() <= 1e-9));
        }
        let s = if r.approach == Approach::Up {
            1.0
        } else {
            -1.0
        };
        match &columns[j - k] {
            Column::Reversal => -s / 2.0,
            Column::Scale(t) => r.target * t[i],
            Column::Offset(t) => t[i],
            Column::Growth(g) => r.target * g[i],
        }
    });
    (a, k)
}

/// First-order lag (time constant `tau` s) of a record taken at `times`, linear between
/// samples, starting at its first value: the exact response to each linear segment.
fn lagged(times: &[f64], values: &[f64], tau: f64) -> Vec<f64> {
    let mut out = vec![values[0]; values.len()];
    for i in 1..values.len() {
        let dt = times[i] - times[i - 1];
        let slope = (values[i] - values[i - 1]) / dt.max(1e-12);
        let decay = (-dt / tau).exp();
        // y' = (u − y)/τ with u = u₀ + slope·t: y(dt) = u(dt) − slope·τ + (y₀ − u₀ + slope·τ)·e^(−dt/τ).
        out[i] = values[i] - slope * tau + (out[i - 1] - values[i - 1] + slope * tau) * decay;
    }
    out
}

/// How a response `u` describes a true temperature rise `v` (°C) at the readings, with a gain
/// and a constant refitted by least squares (the profile takes `x` times any constant): the
/// RMS misfit (°C).
fn misfit(u: &[f64], v: &[f64]) -> f64 {
    let n = u.len() as f64;
    let (mu, mv) = (u.iter().sum::<f64>() / n, v.iter().sum::<f64>() / n);
    let cu: Vec<f64> = u.iter().map(|a| a - mu).collect();
    let cv: Vec<f64> = v.iter().map(|b| b - mv).collect();
    let gain = dot(&cu, &cv) / dot(&cu, &cu);
    (cu.iter()
        .zip(&cv)
        .map(|(a, b)| (b - gain * a).powi(2))
        .sum::<f64>()
        / n)
        .sqrt()
}

/// The time constants a search on the file can be expected to return, for a response
/// `response(τ)` of a true rise `v` (°C) that expands the axis by `ppm` µm/(m·°C) at positions
/// `x` (m), with reading noise `sigma_um`: τ (min, on a 0.25 min grid from 1 to 300 min) with
/// the least misfit `m₀`, and the interval of τ around it whose misfit `m(τ)` raises the sum of
/// squares of the deviations by less than 16 σ² (four standard errors of a one-parameter fit),
/// that sum growing by `n·ppm²·mean(x²)·(m(τ)² − m₀²)`. Returns (best, low, high) in minutes.
fn tau_interval(
    response: impl Fn(f64) -> Vec<f64>,
    v: &[f64],
    ppm: f64,
    x: &[f64],
    sigma_um: f64,
) -> (f64, f64, f64) {
    let grid: Vec<f64> = (0..=1196).map(|k| 1.0 + 0.25 * k as f64).collect();
    let misfits: Vec<f64> = grid
        .iter()
        .map(|t| misfit(&response(t * 60.0), v))
        .collect();
    let best = (0..grid.len())
        .min_by(|&a, &b| misfits[a].total_cmp(&misfits[b]))
        .unwrap();
    let x2 = dot(x, x) / x.len() as f64;
    let allowed =
        misfits[best].powi(2) + 16.0 * sigma_um.powi(2) / (x.len() as f64 * ppm * ppm * x2);
    let inside = |k: &usize| misfits[*k].powi(2) <= allowed;
    let low = (0..=best).rev().take_while(inside).last().unwrap();
    let high = (best..grid.len()).take_while(inside).last().unwrap();
    (grid[best], grid[low], grid[high])
}

/// `1 − e^(−(t − t₀)/τ)` from the first reading.
fn activity(times: &[f64], tau: f64) -> Vec<f64> {
    times
        .iter()
        .map(|t| 1.0 - (-(t - times[0]) / tau).exp())
        .collect()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn within(value: f64, truth: f64, tolerance: f64, what: &str, seed: u64) {
    println!("    {what}: {value:.3} (truth {truth:.3} ± {tolerance:.3})");
    assert!(
        (value - truth).abs() <= tolerance,
        "seed {seed}: {what} {value} vs {truth} ± {tolerance}"
    );
}

/// The lost motion found must be the injected one within [`STANDARD_ERRORS`] of its standard
/// error `se` (µm).
fn assert_lost_motion(found: &Found, fixture: &Fixture, se: f64, seed: u64) {
    within(
        found.param(E::Reversal, "lost_motion_um"),
        fixture.reversal_um,
        STANDARD_ERRORS * se,
        "lost motion µm",
        seed,
    );
}

/// The accepted effects, in any order, must be `expected`.
fn assert_accepted(found: &Found, expected: &[PositioningEffect], seed: u64) {
    let mut accepted = found.discovery.accepted();
    let mut expected = expected.to_vec();
    accepted.sort();
    expected.sort();
    assert_eq!(
        accepted,
        expected,
        "seed {seed}:\n{}",
        found.discovery.to_text()
    );
}

/// The held-out RMS of every fold, before (base model) and after (final model), from the JSON
/// report: one per run held out, their quadratic mean the pooled held-out RMS (the runs have
/// the same number of readings), every step reported with its own. Printed, and returned as
/// (before, after) per fold.
fn held_out_per_fold(found: &Found, seed: u64) -> Vec<(f64, f64)> {
    let json = found.discovery.to_json();
    let runs = found.table.runs.len();
    assert_eq!(json["validation"]["scheme"], "leave-one-run-out");
    let folds = |v: &serde_json::Value| -> Vec<f64> {
        let folds: Vec<f64> = v["fold_cv_rms_um"]
            .as_array()
            .expect("fold_cv_rms_um")
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(folds.len(), runs, "one held-out RMS per run");
        let pooled = (folds.iter().map(|f| f * f).sum::<f64>() / runs as f64).sqrt();
        let stated = v["cv_rms_um"].as_f64().unwrap();
        assert!(
            (pooled - stated).abs() < 2e-3,
            "folds {folds:?} against {stated}"
        );
        folds
    };
    let before = folds(&json["baseline"]);
    for step in json["steps"].as_array().unwrap() {
        folds(step);
        assert!(step["cause"].as_str().is_some_and(|c| !c.is_empty()));
    }
    let after = folds(&json["final"]);
    let text: Vec<String> = before
        .iter()
        .zip(&after)
        .map(|(b, a)| format!("{b:.2}→{a:.2}"))
        .collect();
    println!(
        "  seed {seed}: {} | held-out RMS {} → {} µm; per run held out: {}",
        json["final"]["model"].as_str().unwrap(),
        json["baseline"]["cv_rms_um"],
        json["final"]["cv_rms_um"],
        text.join(" ")
    );
    before.into_iter().zip(after).collect()
}

/// The final model gains in every fold (each run held out is predicted better than by the
/// base model) and its RMS on all readings is at the noise: a model with every true term
/// leaves σ·√((n − p)/n) ≤ σ, and with n ≥ 54 readings the RMS of the noise varies by about
/// σ/√(2n) ≤ 0.1·σ, so 1.2·σ is above what the true model leaves with room for the sensor's
/// share that `sigma_um` bounds.
fn assert_explained(found: &Found, folds: &[(f64, f64)], sigma_um: f64, seed: u64) {
    for (k, (before, after)) in folds.iter().enumerate() {
        assert!(
            after < before,
            "seed {seed}: run {} held out gains nothing ({before} → {after})\n{}",
            k + 1,
            found.discovery.to_text()
        );
    }
    let rms = found.discovery.final_score().rms * 1e6;
    assert!(
        rms <= 1.2 * sigma_um,
        "seed {seed}: final RMS {rms:.3} µm, noise {sigma_um:.3} µm\n{}",
        found.discovery.to_text()
    );
}

/// The null fixture (same scenario and noise draws, the effect removed) accepts exactly
/// `expected`.
fn assert_null(fixture: &Fixture, expected: &[PositioningEffect]) {
    for seed in SEEDS {
        let found = fixture.discover(seed);
        held_out_per_fold(&found, seed);
        assert_accepted(&found, expected, seed);
    }
}

// ---------------------------------------------------------------------------------------
// The Z axis of issue 15 with the expansion twice the nominal: 5 runs, the first one cold.

/// The Z axis with the sensor on the screw and a screw expanding at 23.4 µm/(m·°C), twice
/// the nominal steel value (another material, or a control compensating the wrong way).
fn z_twice_nominal(runs: usize, idle_min: f64, noise_um: f64) -> Fixture {
    Fixture {
        runs,
        idle_min,
        noise_um,
        expansion_ppm: 2.0 * NOMINAL_PPM,
        ..Fixture::z_axis().sensor_on_screw()
    }
}

/// `thermal_scale` must be accepted alone, its change within 4 standard errors of the
/// injected 23.4 − 11.7 = 11.7 µm/(m·°C), every run held out (the cold one too) predicted
/// better, and the null (nominal expansion) must accept nothing.
fn expansion_twice_nominal(fixture: Fixture, seeds: &[u64]) {
    let truth = fixture.expansion_ppm - NOMINAL_PPM;
    let sigma = fixture.noise_with_sensor(fixture.expansion_ppm, 0.0);
    for &seed in seeds {
        let found = fixture.discover(seed);
        let folds = held_out_per_fold(&found, seed);
        assert_accepted(&found, &[E::ThermalScale], seed);
        let se = standard_errors(&found.table, &[Column::Scale(found.sensor())], sigma);
        within(
            found.param(E::ThermalScale, "expansion_change_ppm_per_degc"),
            truth,
            STANDARD_ERRORS * se[0],
            "expansion change ppm/°C",
            seed,
        );
        assert_explained(&found, &folds, sigma, seed);
    }
    assert_null(
        &Fixture {
            expansion_ppm: NOMINAL_PPM,
            ..fixture
        },
        &[],
    );
}

#[test]
fn z_axis_expansion_twice_nominal_is_found_though_the_cold_run_is_the_reference() {
    expansion_twice_nominal(z_twice_nominal(5, 33.0, 0.7), &[1, 2, 3, 4]);
}

/// Issue 15: three-run files with a thermal effect accepted nothing (the middle run, held
/// out, is interpolated by the other two). Three Z runs an hour apart, 1 µm of noise. Seeds 1,
/// 3 and 4 here; seed 2, which sits at the threshold, in the test below.
#[test]
fn three_z_runs_find_the_expansion_twice_nominal() {
    expansion_twice_nominal(z_twice_nominal(3, 60.0, 1.0), &[1, 3, 4]);
}

/// Seed 2 of the fixture above. `thermal_scale` lowers every run held out (6.16 → 1.71,
/// 1.49 → 1.28, 5.35 → 1.50 µm) but its z without the fold that contributes most is 2.7x:
/// it passed against 2.73 (Bonferroni over the 8 singles this file can test) and misses
/// 2.77 since `sensor_lag` made them 9, and nothing was accepted (the block `thermal_scale` +
/// `thermal_lag` no longer enters since each effect of a block must pass its own test). On
/// three runs the in-sample route (issue 36 item 5) now speaks for it: the scale's fit to
/// all readings is far beyond noise with and without the run that gains most, and the test
/// checks that the step says so.
#[test]
fn three_z_runs_find_the_expansion_twice_nominal_seed_2() {
    expansion_twice_nominal(z_twice_nominal(3, 60.0, 1.0), &[2]);
    let json = z_twice_nominal(3, 60.0, 1.0)
        .discover(2)
        .discovery
        .to_json();
    let step = &json["steps"][0];
    assert_eq!(step["effect"], "thermal_scale", "{step}");
    assert_eq!(step["passed_on"], "in-sample", "{step}");
}

// ---------------------------------------------------------------------------------------
// A heat source the sensor does not see.

/// The X axis of Lu 2012 with the sensor on the machine bed (as a laser's material sensor
/// often is): it reads the air, while the screw warms by 2.2 °C from the nut and the motor.
fn x_unseen_heat(runs: usize, idle_min: f64, noise_um: f64) -> Fixture {
    Fixture {
        runs,
        idle_min,
        noise_um,
        sensor_node: "bed",
        ..Fixture::x_axis()
    }
}

/// `reversal` and `second_heat_source` must be accepted, nothing else. Truth: the lost motion
/// injected; the expansion the screw's true temperature causes between the first and the last
/// run, 11.7 µm/(m·°C) × its rise, against the model's `b·(ḡ_last − ḡ_first)`; the time
/// constant within the interval a search can return for the true screw temperature
/// ([`tau_interval`] of the single exponential).
fn unseen_heat_source(fixture: Fixture) {
    let sigma = fixture.noise_with_sensor(NOMINAL_PPM, 0.0);
    for seed in SEEDS {
        let found = fixture.discover(seed);
        let folds = held_out_per_fold(&found, seed);
        assert_accepted(&found, &[E::Reversal, E::SecondHeatSource], seed);
        let simulated = &found.simulated;
        let times = simulated.times();
        let screw = simulated.node("x_screw");
        let x: Vec<f64> = found.table.readings.iter().map(|r| r.target).collect();
        let (tau_best, tau_low, tau_high) =
            tau_interval(|tau| activity(&times, tau), &screw, NOMINAL_PPM, &x, sigma);
        let g = activity(&times, tau_best * 60.0);
        let se = standard_errors(
            &found.table,
            &[Column::Reversal, Column::Growth(g.clone())],
            sigma,
        );
        assert_lost_motion(&found, &fixture, se[0], seed);
        // The expansion grown over the test (µm/m), the model's `b·(ḡ_last − ḡ_first)` against
        // the screw's `11.7 µm/(m·°C) × (T̄_last − T̄_first)`. The single exponential misses the
        // true rise by `m₀` °C RMS at best, so the growth between two runs it gives may be off
        // by about twice that, on top of four standard errors.
        let screw_runs = simulated.run_means(&screw);
        let truth = NOMINAL_PPM * (screw_runs[screw_runs.len() - 1] - screw_runs[0]);
        let b = found.param(E::SecondHeatSource, "expansion_um_per_m");
        let tau = found.param(E::SecondHeatSource, "tau_min");
        let model_g = simulated.run_means(&activity(&times, tau * 60.0));
        let grown = b * (model_g[model_g.len() - 1] - model_g[0]);
        let truth_g = simulated.run_means(&g);
        let se_grown = se[1] * (truth_g[truth_g.len() - 1] - truth_g[0]);
        let m0 = misfit(&g, &screw);
        within(
            grown,
            truth,
            STANDARD_ERRORS * se_grown + 2.0 * NOMINAL_PPM * m0,
            "expansion grown from the first to the last run µm/m",
            seed,
        );
        println!(
            "    heat source τ: {tau:.1} min, expected {tau_low}–{tau_high} (best {tau_best})"
        );
        assert!(
            (tau_low..=tau_high).contains(&tau),
            "seed {seed}: τ {tau} min outside {tau_low}–{tau_high}"
        );
        assert_explained(&found, &folds, sigma, seed);
    }
    // Null: the sensor on the screw sees the heat; only the lost motion is left.
    assert_null(&fixture.sensor_on_screw(), &[E::Reversal]);
}

#[test]
fn a_heat_source_the_sensor_does_not_see_is_found_with_the_lost_motion() {
    unseen_heat_source(x_unseen_heat(7, 45.0, 0.5));
}

// ---------------------------------------------------------------------------------------
// Origin drift and several thermal terms at once.

mod thermal_causes;
