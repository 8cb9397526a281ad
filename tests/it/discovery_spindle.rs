//! `mtwin discover spindle`: effects hidden in spindle records are found, named and measured
//! against the values put in (closed-form records, the twin, and records written by an
//! independent Python model); clean records add nothing.

use mtwin::app::{Scenario, simulate};
use mtwin::kinds::spindle::discovery::bearing::Bearing;
use mtwin::kinds::spindle::discovery::{
    Options, Searched, SpindleDiscovery, SpindleEffect, discover_spindle,
};
use mtwin::kinds::spindle::table;
use mtwin::kinds::spindle::{Sensing, SpindleProbe, SpindleRecord};
use mtwin::machine::Axis;
use rand::{RngExt, SeedableRng};
use std::f64::consts::TAU;
use std::path::Path;

/// Probe noise of the closed-form records (m).
const SIGMA: f64 = 5e-9;

/// One sample of a closed-form record, for the model's function.
struct At {
    /// Probe index (0 = x1 along X, 1 = y1 along Y, 2 = z).
    probe: usize,
    theta: f64,
    /// Turns since the segment's first index.
    turns: f64,
    /// Time (s).
    time: f64,
    /// Speed (rpm).
    rpm: f64,
}

/// A record of x1, y1 (radial, 90° apart) and z (axial) at `speeds_rpm`, `revolutions` of
/// `m` samples each, readings `model(at)` plus Gaussian noise σ = [`SIGMA`].
fn record(
    speeds_rpm: &[f64],
    revolutions: usize,
    m: usize,
    seed: u64,
    model: impl Fn(&At) -> f64,
) -> SpindleRecord {
    let probe = |name: &str, direction: [f64; 3], position: [f64; 3]| SpindleProbe {
        name: name.into(),
        direction,
        position,
        sensing: Sensing::Fixed,
    };
    let probes = vec![
        probe("x1", [-1.0, 0.0, 0.0], [0.0125, 0.0, 0.0]),
        probe("y1", [0.0, -1.0, 0.0], [0.0, 0.0125, 0.0]),
        probe("z", [0.0, 0.0, -1.0], [0.0, 0.0, -0.0125]),
    ];
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut r = SpindleRecord {
        axis: Axis::S,
        probes,
        setup: Vec::new(),
        revolution: Vec::new(),
        angle: Vec::new(),
        time: Vec::new(),
        speed: Vec::new(),
        readings: vec![Vec::new(); 3],
    };
    let mut time = 0.0;
    for &rpm in speeds_rpm {
        let step = 60.0 / rpm / m as f64;
        for i in 0..revolutions * m {
            let theta = TAU * (i % m) as f64 / m as f64;
            r.setup.push(String::new());
            r.revolution.push(i / m);
            r.angle.push(theta);
            r.time.push(time);
            r.speed.push(rpm * TAU / 60.0);
            for p in 0..3 {
                let at = At {
                    probe: p,
                    theta,
                    turns: i as f64 / m as f64,
                    time,
                    rpm,
                };
                r.readings[p].push(model(&at) + SIGMA * gaussian(&mut rng));
            }
            time += step;
        }
    }
    r
}

/// A standard normal deviate (Box–Muller).
fn gaussian(rng: &mut rand_chacha::ChaCha8Rng) -> f64 {
    let u: f64 = 1.0 - rng.random::<f64>();
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (TAU * v).cos()
}

/// The base model's content: a 2 µm set-up eccentricity and an elliptical 2-UPR orbit in the
/// radial probes, a 1-UPR axial term in z.
fn base(at: &At) -> f64 {
    match at.probe {
        0 => 2e-6 * (at.theta + 0.4).cos() + 0.15e-6 * (2.0 * at.theta + 0.2).cos(),
        1 => 2e-6 * (at.theta + 0.4).sin() + 0.09e-6 * (2.0 * at.theta + 0.2).sin(),
        _ => 0.06e-6 * (at.theta + 1.0).cos(),
    }
}

fn discover(record: &SpindleRecord, m: usize, options: &Options) -> SpindleDiscovery {
    discover_spindle(record, m, options, |_| {}).expect("a valid record")
}

/// The final model's searched value of `effect`.
fn searched(d: &SpindleDiscovery, effect: SpindleEffect) -> Searched {
    d.searched(effect)
        .unwrap_or_else(|| panic!("{effect:?} not accepted: {:?}", d.accepted()))
}

/// The final fit's amplitude of a cos/sin pair for probe `p`, from the JSON report (µm).
fn json_amplitude(d: &SpindleDiscovery, effect: &str, probe: &str) -> f64 {
    let json = d.to_json();
    let amplitude = &json["final"]["params"][effect]["amplitude"][format!("{probe}_um")];
    amplitude
        .as_f64()
        .or_else(|| amplitude[0].as_f64())
        .unwrap_or_else(|| panic!("no amplitude for {effect} {probe}: {json}"))
}

/// A forward whirl at `ratio` × the rotation, `amplitude` in X and Y.
fn whirl(at: &At, ratio: f64, amplitude: f64) -> f64 {
    let phase = TAU * ratio * at.turns + 0.3;
    match at.probe {
        0 => amplitude * phase.cos(),
        1 => amplitude * phase.sin(),
        _ => 0.0,
    }
}

#[test]
fn an_asynchronous_line_is_found_and_named_by_its_ratio() {
    // A whirl at 0.43 × the rotation (a cage), 0.07 µm in X and Y, 20 revolutions at 3000 rpm.
    for seed in 1..=3 {
        let r = record(&[3000.0], 20, 256, seed, |at| {
            base(at) + whirl(at, 0.43, 0.07e-6)
        });
        let d = discover(&r, 256, &Options::default());
        assert_eq!(
            d.accepted()[0],
            SpindleEffect::AsynchronousLine(0),
            "seed {seed}"
        );
        let Searched::Line(f, _) = searched(&d, SpindleEffect::AsynchronousLine(0)) else {
            panic!("a line has a frequency")
        };
        // The line spacing is 1/20 UPR; the frequency comes back within a tenth of it.
        assert!((f - 0.43).abs() < 0.005, "seed {seed}: {f} UPR");
        let name = d.line_name(SpindleEffect::AsynchronousLine(0)).unwrap();
        assert!(name.starts_with("0.430 × the rotation"), "{name}");
        for probe in ["x1", "y1"] {
            let a = json_amplitude(&d, "asynchronous_line", probe);
            assert!((a - 0.07).abs() < 0.007, "seed {seed} {probe}: {a} µm");
        }
        // Nothing else: the held-out RMS ends at the noise (within 20 %).
        assert_eq!(d.accepted().len(), 1, "seed {seed}: {:?}", d.accepted());
        let cv = d.final_score().cv_rms;
        assert!(cv < 1.2 * SIGMA, "seed {seed}: held-out RMS {cv}");
    }
}

#[test]
fn a_line_at_a_bearing_frequency_is_named_by_the_bearing() {
    // A 6205-size bearing (9 balls of 7.94 mm on a 39.04 mm pitch): BPFO = 3.5848 UPR; the
    // line is put 0.5 % slow (cage slip).
    let bearing = Bearing::new(9, 7.94e-3, 39.04e-3, 0.0).unwrap();
    let bpfo = 4.5 * (1.0 - 7.94 / 39.04) * 0.995;
    let r = record(&[6000.0], 20, 256, 7, |at| {
        base(at) + whirl(at, bpfo, 0.04e-6)
    });
    let options = Options {
        bearing: Some(bearing),
        ..Options::default()
    };
    let d = discover(&r, 256, &options);
    let name = d.line_name(SpindleEffect::AsynchronousLine(0)).unwrap();
    assert!(name.starts_with("BPFO"), "{name}");
    let json = d.to_json();
    let hz = json["final"]["params"]["asynchronous_line"]["hz"][0]
        .as_f64()
        .unwrap();
    // 100 rev/s × 3.5669 UPR.
    assert!((hz - 100.0 * bpfo).abs() < 0.5, "{hz} Hz");
}

#[test]
fn a_harmonic_beyond_the_base_is_found() {
    // A 7-lobed synchronous motion of 0.05 µm in X only.
    for seed in 1..=2 {
        let r = record(&[3000.0], 10, 256, seed, |at| {
            base(at)
                + if at.probe == 0 {
                    0.05e-6 * (7.0 * at.theta - 0.5).cos()
                } else {
                    0.0
                }
        });
        let d = discover(&r, 256, &Options::default());
        assert_eq!(
            d.accepted(),
            vec![SpindleEffect::Harmonic(0)],
            "seed {seed}"
        );
        assert_eq!(searched(&d, SpindleEffect::Harmonic(0)), Searched::Order(7));
        let a = json_amplitude(&d, "harmonic", "x1");
        // σ·√(2/n) ≈ 0.1 nm of noise on the amplitude: 2 % is 10 times that.
        assert!((a - 0.05).abs() < 0.001, "{a} µm");
        assert!(json_amplitude(&d, "harmonic", "y1") < 0.001);
    }
}

#[test]
fn a_drift_of_the_axial_mean_is_found_and_measured() {
    // The spindle grows 0.2 µm along its axis during the record (first order, τ = 2 s over a
    // 6 s record at 300 rpm): 0.2·(1 − e^{−3}) = 0.190 µm over the record.
    let r = record(&[300.0], 30, 128, 3, |at| {
        base(at)
            + if at.probe == 2 {
                0.2e-6 * (1.0 - (-at.time / 2.0).exp())
            } else {
                0.0
            }
    });
    let d = discover(&r, 128, &Options::default());
    assert_eq!(d.accepted(), vec![SpindleEffect::Drift]);
    let Searched::TimeConstant(Some(tau)) = searched(&d, SpindleEffect::Drift) else {
        panic!("a first-order drift")
    };
    assert!((tau - 2.0).abs() < 0.1, "τ = {tau} s");
    let drift = d.to_json()["final"]["params"]["drift"]["drift"]["z_um"]
        .as_f64()
        .unwrap();
    let truth = 0.2 * (1.0 - (-6.0 * (1.0 - 1.0 / 3840.0) / 2.0_f64).exp());
    assert!((drift - truth).abs() < 0.005, "{drift} µm against {truth}");
    // Inside what the search reaches (the grid 6/16 to 24 s refined within a factor of 2:
    // 6/32 to 48 s): a measured time constant, no note. At either end (within 1 % in
    // logarithm), the record holds no time constant the search can take: the note says which.
    let note = &d.to_json()["final"]["params"]["drift"]["time_constant_note"];
    assert!(note.is_null(), "{note}");
    let at_end = |tau: f64| d.problem().time_constant_at_range_end(tau);
    let span = 6.0 * (1.0 - 1.0 / 3840.0);
    assert!(at_end(8.0 * span).unwrap().contains("longest"));
    assert!(at_end(10.0 * span).unwrap().contains("longest"));
    assert!(at_end(span / 32.0).unwrap().contains("shortest"));
    for tau in [span / 30.0, 2.0, 7.8 * span] {
        assert_eq!(at_end(tau), None, "{tau} s");
    }
}

#[test]
fn a_synchronous_motion_growing_with_speed_is_found() {
    // Unbalance: a 1-UPR motion of 0.15 µm × (n / 12000 rpm)² on top of the set-up, at 3000,
    // 6000 and 12000 rpm: 0.009, 0.038 and 0.15 µm.
    let r = record(&[3000.0, 6000.0, 12000.0], 10, 128, 5, |at| {
        let unbalance = 0.15e-6 * (at.rpm / 12000.0).powi(2);
        base(at)
            + match at.probe {
                0 => unbalance * (at.theta - 1.0).cos(),
                1 => unbalance * (at.theta - 1.0).sin(),
                _ => 0.0,
            }
    });
    let d = discover(&r, 128, &Options::default());
    assert_eq!(d.accepted(), vec![SpindleEffect::SpeedDependence]);
    // The 1-UPR amplitude at each speed: the set-up's 2 µm and the unbalance add as phasors.
    let json = d.to_json();
    let at = &json["final"]["params"]["speed_dependence"]["amplitude"]["x1_um"]["upr_1"];
    for (s, rpm) in [3000.0, 6000.0, 12000.0_f64].iter().enumerate() {
        let u = 0.15 * (rpm / 12000.0).powi(2);
        let truth = (2.0 * 0.4_f64.cos() + u * 1.0_f64.cos())
            .hypot(2.0 * 0.4_f64.sin() - u * 1.0_f64.sin());
        let got = at[s].as_f64().unwrap();
        assert!(
            (got - truth).abs() < 0.002,
            "{rpm} rpm: {got} µm against {truth}"
        );
    }
}

#[test]
fn clean_records_add_nothing() {
    // The base model's content and white noise only: every acceptance is a false one.
    let mut accepted = 0;
    for seed in 100..120 {
        let r = record(&[3000.0], 10, 128, seed, base);
        let d = discover(&r, 128, &Options::default());
        accepted += d.accepted().len();
        assert!(d.final_score().cv_rms < 1.2 * SIGMA);
    }
    assert_eq!(accepted, 0, "false acceptances in 20 clean records");
}

/// A scenario of `scenarios/` with its machine path made absolute and `edits` applied, written
/// to a temporary folder.
fn scenario(name: &str, edits: &[(&str, &str)]) -> (tempfile::TempDir, Scenario) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut text = std::fs::read_to_string(root.join("scenarios").join(name)).unwrap();
    text = text.replace("\"../models/", &format!("\"{}/models/", root.display()));
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    let s = Scenario::load(&path).unwrap();
    (dir, s)
}

#[test]
fn the_twin_spindle_hides_what_the_scenario_put_in() {
    // scenarios/vmc3_spindle.toml at 256 samples a revolution: its 3-UPR races, its cage at
    // 0.43 and outer-race ball pass at 4.6 × the rotation, and amplitudes growing with speed.
    let (_dir, s) = scenario(
        "vmc3_spindle.toml",
        &[(
            "samples_per_revolution = 1024",
            "samples_per_revolution = 256",
        )],
    );
    let sim = simulate(&s).unwrap();
    let t = sim.spindle.as_ref().unwrap();
    let d = discover(&t.record, t.samples_per_revolution, &Options::default());
    let accepted = d.accepted();
    assert!(
        accepted.contains(&SpindleEffect::SpeedDependence),
        "{accepted:?}"
    );
    let mut orders = Vec::new();
    let mut lines = Vec::new();
    for e in &accepted {
        match searched(&d, *e) {
            Searched::Order(k) => orders.push(k),
            Searched::Line(f, _) => lines.push(f),
            _ => {}
        }
    }
    assert!(orders.contains(&3), "{orders:?}");
    for truth in [0.43, 4.6] {
        assert!(
            lines.iter().any(|f| (f - truth).abs() < 0.01),
            "{truth}: {lines:?}"
        );
    }
}

/// The foreign records' folder.
fn foreign(name: &str) -> table::SpindleTable {
    table::read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/spindle/foreign")
            .join(name),
    )
    .unwrap()
}

#[test]
fn an_impact_train_and_a_thermal_transient_from_another_model_are_found() {
    // tests/data/spindle/foreign/make_defect_drift.py: a 5-lobe motion of 0.08 µm, an
    // outer-race defect's impacts (half-sines of 0.06 µm over 20 % of each pass, passes at
    // 0.99 × BPFO = 3.5490 UPR), an axial transient 0.30·(1 − e^{−t/3 s}) µm, 3 nm noise,
    // rounded to 1 nm.
    let t = foreign("defect_drift.csv");
    let options = Options {
        bearing: Some(Bearing::new(9, 7.94e-3, 39.04e-3, 0.0).unwrap()),
        ..Options::default()
    };
    let d = discover(&t.record, t.samples_per_revolution, &options);
    assert_eq!(searched(&d, SpindleEffect::Harmonic(0)), Searched::Order(5));
    for probe in ["x1", "y1"] {
        let a = json_amplitude(&d, "harmonic", probe);
        assert!((a - 0.08).abs() < 0.002, "{probe}: {a} µm");
    }
    let Searched::TimeConstant(Some(tau)) = searched(&d, SpindleEffect::Drift) else {
        panic!("a first-order drift")
    };
    assert!((tau - 3.0).abs() < 0.15, "τ = {tau} s");
    let json = d.to_json();
    let drift = json["final"]["params"]["drift"]["drift"]["z_um"]
        .as_f64()
        .unwrap();
    // Over the record's 8 s less one sample step (1/640 s).
    let truth = 0.30 * (1.0 - (-(8.0 - 1.0 / 640.0) / 3.0_f64).exp());
    assert!((drift - truth).abs() < 0.005, "{drift} µm against {truth}");
    let Searched::Line(f, _) = searched(&d, SpindleEffect::AsynchronousLine(0)) else {
        panic!("a line")
    };
    let passes = 0.99 * 4.5 * (1.0 - 7.94 / 39.04);
    assert!((f - passes).abs() < 0.0025, "{f} UPR against {passes}");
    let name = d.line_name(SpindleEffect::AsynchronousLine(0)).unwrap();
    assert!(name.starts_with("BPFO"), "{name}");
    // The impact train's fundamental: A·(4w/π)·cos(πw)/(1 − 4w²) with w = 0.2.
    let w: f64 = 0.2;
    let fundamental = 0.06 * 4.0 * w / std::f64::consts::PI * (std::f64::consts::PI * w).cos()
        / (1.0 - 4.0 * w * w);
    let a = json_amplitude(&d, "asynchronous_line", "x1");
    assert!(
        (a - fundamental).abs() < 0.1 * fundamental,
        "{a} µm against {fundamental}"
    );
    // What is left is the noise and the rounding: √(3² + 1/12) nm, within 20 %.
    let floor = (9.0_f64 + 1.0 / 12.0).sqrt() * 1e-9;
    assert!(
        d.final_score().cv_rms < 1.2 * floor,
        "{}",
        d.final_score().cv_rms
    );
}

#[test]
fn a_time_sampled_export_with_a_bearing_line_in_hz_is_read_and_searched() {
    // tests/data/spindle/foreign/make_sea_time.py: 3-UPR lobes of 0.22 (X) and 0.15 µm (Y), a
    // forward whirl of 0.06 µm at 440 Hz (4.4 × the mean rotation, with a 0.3 % speed ripple),
    // 4 nm noise, sampled on time, not on the index.
    let t = foreign("sea_time.csv");
    let d = discover(&t.record, t.samples_per_revolution, &Options::default());
    assert_eq!(searched(&d, SpindleEffect::Harmonic(0)), Searched::Order(3));
    assert!((json_amplitude(&d, "harmonic", "x1") - 0.22).abs() < 0.005);
    assert!((json_amplitude(&d, "harmonic", "y1") - 0.15).abs() < 0.005);
    let json = d.to_json();
    let hz = json["final"]["params"]["asynchronous_line"]["hz"][0]
        .as_f64()
        .unwrap();
    assert!((hz - 440.0).abs() < 1.0, "{hz} Hz");
    for probe in ["x1", "y1"] {
        let a = json_amplitude(&d, "asynchronous_line", probe);
        assert!((a - 0.06).abs() < 0.006, "{probe}: {a} µm");
    }
    assert!(
        d.final_score().cv_rms < 1.2 * 4e-9,
        "{}",
        d.final_score().cv_rms
    );
}

/// The false-acceptance rate the README states: clean records (the base model's content and
/// white noise) of three shapes, 100 seeds each. Run with `--release -- --ignored
/// --nocapture`; it prints the counts (asserting only that they stay within the 5 % the rule
/// is built for).
#[test]
#[ignore = "a measurement over 300 records: run on purpose"]
fn false_acceptance_rate() {
    let shapes: [(&str, &[f64], usize); 3] = [
        ("one speed, 10 revolutions", &[3000.0], 10),
        ("one speed, 3 revolutions (3 folds)", &[3000.0], 3),
        ("three speeds, 5 revolutions", &[3000.0, 6000.0, 12000.0], 5),
    ];
    for (what, speeds, revolutions) in shapes {
        let (mut records, mut effects) = (0, 0);
        for seed in 1000..1100 {
            let r = record(speeds, revolutions, 128, seed, base);
            let d = discover(&r, 128, &Options::default());
            records += usize::from(!d.accepted().is_empty());
            effects += d.accepted().len();
        }
        println!("{what}: {records} of 100 clean records accept something ({effects} effects)");
        assert!(records <= 5, "{what}: {records}");
    }
}

// ---------------------------------------------------------------------------------------------
// Bounds and statistics that cannot be formed (issue 42).

#[test]
fn base_harmonics_beyond_the_record_or_the_ceiling_are_refused() {
    use mtwin::kinds::spindle::discovery::{MOST_BASE_HARMONICS, SpindleDiscoveryError};
    // 16 samples a revolution: the Nyquist order is 8, the highest searchable harmonic 7, so a
    // base of 6 leaves order 7 to search and a base of 7 leaves nothing.
    let r = record(&[3000.0], 5, 16, 7, base);
    let with = |k: usize| Options {
        base_harmonics: k,
        ..Options::default()
    };
    assert!(discover_spindle(&r, 16, &with(6), |_| {}).is_ok());
    let error = discover_spindle(&r, 16, &with(7), |_| {}).unwrap_err();
    assert_eq!(
        error,
        SpindleDiscoveryError::BaseHarmonics {
            harmonics: 7,
            samples: 16
        }
    );
    assert!(error.to_string().contains("at most 6"), "{error}");
    // The fixed ceiling holds whatever the record could resolve (1024 samples: up to 510).
    let wide = record(&[3000.0], 5, 1024, 7, base);
    let error = discover_spindle(&wide, 1024, &with(MOST_BASE_HARMONICS + 1), |_| {}).unwrap_err();
    assert_eq!(
        error,
        SpindleDiscoveryError::TooManyBaseHarmonics(MOST_BASE_HARMONICS + 1)
    );

    // Through the binary: refused (not clamped), naming the file and the flag, nothing printed.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("sixteen.csv");
    let t = table::SpindleTable {
        record: r,
        conditions: mtwin::io::Conditions::default(),
        samples_per_revolution: 16,
        columns_not_read: Vec::new(),
    };
    std::fs::write(&file, table::write_csv(&t)).unwrap();
    for (k, words) in [("7", "at most 6"), ("1000000", "at most 64")] {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_mtwin"))
            .args(["discover", "spindle"])
            .arg(&file)
            .args(["--base-harmonics", k])
            .output()
            .unwrap();
        assert!(!output.status.success());
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            stderr.contains("sixteen.csv")
                && stderr.contains(&format!("--base-harmonics {k}"))
                && stderr.contains(words),
            "{stderr}"
        );
        assert!(output.stdout.is_empty());
    }
}

#[test]
fn a_flat_probe_column_is_refused_in_words_not_scored() {
    // A record whose z probe reads 1.5 µm at every sample (a dead or saturated channel),
    // written to a file as an analyser would export it. Its residual under the base model is
    // round-off (1e-22 m), from which t, F and z come out as numbers that mean nothing (before
    // this check: `t = inf`, or effects "accepted" on round-off): it is refused by name.
    let mut r = record(&[3000.0, 6000.0], 10, 64, 11, base);
    r.readings[2].fill(1.5e-6);
    let error = discover_spindle(&r, 64, &Options::default(), |_| {}).unwrap_err();
    assert!(
        matches!(&error, mtwin::kinds::spindle::discovery::SpindleDiscoveryError::FlatProbe { probe, .. } if probe == "z"),
        "{error}"
    );
    let mut alone = r.clone();
    alone.probes.drain(..2);
    alone.readings.drain(..2);
    let dir = tempfile::tempdir().unwrap();
    for (name, record) in [("with_others.csv", r), ("flat_only.csv", alone)] {
        let file = dir.path().join(name);
        let t = table::SpindleTable {
            record,
            conditions: mtwin::io::Conditions::default(),
            samples_per_revolution: 64,
            columns_not_read: Vec::new(),
        };
        std::fs::write(&file, table::write_csv(&t)).unwrap();
        for json in [false, true] {
            let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_mtwin"));
            command.args(["discover", "spindle"]).arg(&file);
            if json {
                command.arg("--json");
            }
            let output = command.output().unwrap();
            assert!(!output.status.success(), "{name}");
            let stderr = String::from_utf8_lossy(&output.stderr);
            assert!(
                stderr.contains(name)
                    && stderr.contains("probe z reads 1.500000 µm at every sample")
                    && stderr.contains("no statistic (t, F, z) can be formed"),
                "{stderr}"
            );
            assert!(output.stdout.is_empty(), "{name}: nothing printed");
        }
    }
}

/// Issue 36, item 3: on every shape of record the reader accepts (one speed or several, with
/// a time column or without: every sample then has one time), each effect planted alone at
/// ten times the noise is taken up by its own terms (the fit with it leaves at most half of
/// what the base model leaves beyond the noise's expected n·σ²), or the problem names it
/// untestable with a reason; which are
/// testable is written here from what the shape holds (a drift needs time, a change with
/// speed two speeds).
#[test]
fn every_effect_acts_or_is_named_untestable_on_every_record_shape() {
    use crate::common::discovery_rss;
    use mtwin::discovery::engine::Problem;
    use mtwin::kinds::spindle::discovery::SpindleProblem;
    let effects = [
        SpindleEffect::Harmonic(0),
        SpindleEffect::AsynchronousLine(0),
        SpindleEffect::Drift,
        SpindleEffect::SpeedDependence,
    ];
    let planted = |effect: SpindleEffect, at: &At, duration: f64| -> f64 {
        let radial = |amplitude: f64, phase: f64| match at.probe {
            0 => amplitude * phase.cos(),
            1 => amplitude * phase.sin(),
            _ => 0.0,
        };
        match effect {
            SpindleEffect::Harmonic(_) => radial(50e-9, 5.0 * at.theta + 0.7),
            SpindleEffect::AsynchronousLine(_) => whirl(at, 0.43, 50e-9),
            SpindleEffect::Drift => {
                if at.probe == 2 {
                    100e-9 * at.time / duration
                } else {
                    0.0
                }
            }
            SpindleEffect::SpeedDependence => {
                radial(50e-9 * (at.rpm / 6000.0).powi(2), 2.0 * at.theta - 0.4)
            }
        }
    };
    for speeds in [&[3000.0][..], &[3000.0, 6000.0][..]] {
        for timed in [true, false] {
            let shape = format!("{} speed(s), timed {timed}", speeds.len());
            for effect in effects {
                let duration: f64 = speeds.iter().map(|rpm| 10.0 * 60.0 / rpm).sum();
                let mut r = record(speeds, 10, 64, 7, |at| {
                    base(at) + planted(effect, at, duration)
                });
                if !timed {
                    r.time.iter_mut().for_each(|t| *t = 0.0);
                }
                let problem = SpindleProblem::new(&r, 64, &Options::default()).unwrap();
                let expected = match effect {
                    SpindleEffect::Drift => timed,
                    SpindleEffect::SpeedDependence => speeds.len() > 1,
                    _ => true,
                };
                let reason = problem
                    .untestable()
                    .iter()
                    .find(|(e, _)| *e == effect)
                    .map(|(_, why)| why.clone());
                if expected {
                    assert!(
                        reason.is_none(),
                        "{shape}: {effect:?} untestable: {reason:?}"
                    );
                    let rss = |effects: &[SpindleEffect]| discovery_rss(&problem, effects);
                    // What each model leaves beyond the noise's own sum of squares.
                    let noise = problem.n_samples() as f64 * SIGMA * SIGMA;
                    let (base, with) = (rss(&[]) - noise, rss(&[effect]) - noise);
                    println!(
                        "{shape}: {effect:?} excess {base:.3e} → {with:.3e} (noise {noise:.3e})"
                    );
                    assert!(with <= 0.5 * base, "{shape}: {effect:?} {base} → {with}");
                } else {
                    let reason = reason.unwrap_or_else(|| {
                        panic!("{shape}: {effect:?} cannot show here but is testable")
                    });
                    println!("{shape}: {effect:?} untestable: {reason}");
                    assert!(!reason.is_empty());
                }
            }
        }
    }
}
