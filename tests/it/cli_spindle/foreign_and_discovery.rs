//! Foreign time-sampled exports and `mtwin discover spindle` on the command line.

use super::*;

/// The model of `tests/data/spindle/foreign/make_sea_time.py` (µm, rad; see its docstring):
/// X = e cos(θ+δ) + p cos(θ+γ) + a2 cos(2θ+α2) + a3 cos(3θ+α3) + A_b cos(2π f_b t + ψ_b) + noise,
/// Y = e sin(θ+δ) + q sin(θ+γ) + b2 sin(2θ+α2) + b3 sin(3θ+β3) + A_b sin(2π f_b t + ψ_b) + noise.
mod sea {
    pub const E: f64 = 4.0;
    pub const DELTA: f64 = 0.7;
    pub const P: f64 = 0.30;
    pub const Q: f64 = 0.18;
    pub const GAMMA: f64 = -0.4;
    pub const A2: f64 = 0.40;
    pub const B2: f64 = 0.25;
    pub const ALPHA2: f64 = 0.5;
    pub const A3: f64 = 0.22;
    pub const ALPHA3: f64 = 1.1;
    pub const B3: f64 = 0.15;
    pub const BETA3: f64 = -0.6;
    /// The bearing line: amplitude (µm) and frequency over the mean rotation frequency.
    pub const A_B: f64 = 0.06;
    pub const BEARING_UPR: f64 = 4.4;
    /// Probe noise (µm, standard deviation per sample).
    pub const SIGMA: f64 = 0.004;
    pub const RPM: f64 = 6000.0;
    pub const SAMPLES_PER_REVOLUTION: usize = 256;
    /// Revolutions in the file.
    pub const REVOLUTIONS: usize = 11;

    /// The synchronous motion (X, Y) at angle θ.
    pub fn synchronous(theta: f64) -> (f64, f64) {
        let x = E * (theta + DELTA).cos()
            + P * (theta + GAMMA).cos()
            + A2 * (2.0 * theta + ALPHA2).cos()
            + A3 * (3.0 * theta + ALPHA3).cos();
        let y = E * (theta + DELTA).sin()
            + Q * (theta + GAMMA).sin()
            + B2 * (2.0 * theta + ALPHA2).sin()
            + B3 * (3.0 * theta + BETA3).sin();
        (x, y)
    }
}

/// `|Σ a_i e^{iφ_i}|`: the amplitude of a sum of sinusoids of one frequency.
fn phasor_sum(terms: &[(f64, f64)]) -> f64 {
    let (re, im) = terms.iter().fold((0.0, 0.0), |(re, im), (a, phi)| {
        (re + a * phi.cos(), im + a * phi.sin())
    });
    re.hypot(im)
}

/// The range over a fine grid (36 000 points: the sampled maximum of these trigonometric
/// polynomials of degree ≤ 4 and amplitude < 5 µm is within 2e-7 µm of the true one).
fn fine_range(f: impl Fn(f64) -> f64) -> f64 {
    let n = 36_000;
    let values: Vec<f64> = (0..n).map(|i| f(TAU * i as f64 / n as f64)).collect();
    range(&values)
}

#[test]
fn the_foreign_time_sampled_fixture_is_what_the_generator_says() {
    let path = data("foreign/sea_time.csv");
    let bytes = std::fs::read(&path).unwrap();
    assert!(bytes.len() < 300_000, "a small fixture: {}", bytes.len());
    let content = String::from_utf8(bytes).unwrap();
    assert!(
        content.split_inclusive('\n').all(|l| l.ends_with("\r\n")),
        "CRLF"
    );
    let csv = Csv::read(&path);
    assert_eq!(
        csv.header,
        ["y1_um", "time_s", "x1_um", "revolution", "angle_deg"]
    );
    assert!(
        csv.keys.iter().all(|(k, _)| !k.ends_with("_direction")
            && !k.ends_with("_position_mm")
            && k != "samples_per_revolution"),
        "no geometry in the preamble: {:?}",
        csv.keys
    );
    let m = sea::SAMPLES_PER_REVOLUTION;
    assert_eq!(csv.rows.len(), sea::REVOLUTIONS * m);
    let (revolution, angle) = (csv.column("revolution"), csv.column("angle_deg"));
    let step = 360.0 / m as f64;
    for (i, row) in csv.rows.iter().enumerate() {
        // 1-based revolutions of 256 samples each, none of them on the index grid (the
        // nearest grid angle at least 0.4° away: half a step, 0.70°, less the ripple's 0.25°).
        assert_eq!(row[revolution], (i / m + 1).to_string(), "row {i}");
        let a = csv.value(i, angle);
        let off = (a / step - (a / step).round()).abs() * step;
        assert!(off > 0.4, "row {i}: {a}° is {off}° from the grid");
        // Readings to 1 nm.
        for column in ["x1_um", "y1_um"] {
            let cell = &row[csv.column(column)];
            assert_eq!(cell.split('.').nth(1).map(str::len), Some(3), "{cell}");
        }
    }
}

#[test]
fn a_time_sampled_foreign_export_is_resampled_and_its_values_are_the_models() {
    let path = data("foreign/sea_time.csv");
    let json = analyze_json(&path, &[]);
    assert_eq!(json["samples_per_revolution"], sea::SAMPLES_PER_REVOLUTION);
    let notes: Vec<&str> = array(&json["notes"])
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    assert!(
        notes
            .iter()
            .any(|n| n.contains("resampled") && n.contains("256 per revolution")),
        "{notes:?}"
    );
    let segments = array(&json["segments"]);
    assert_eq!(segments.len(), 1, "one speed, the ripple notwithstanding");
    let segment = &segments[0];
    assert_eq!(segment["setup"], "");
    // No speed column: the speed is the slope of angle against time. The 0.3 % ripple at 70 Hz
    // over 0.11 s biases a straight-line fit by about 1e-4: 0.1 % allowed.
    let rpm = number(&segment["speed_rpm"]);
    assert!((rpm - sea::RPM).abs() < 6.0, "{rpm}");
    // The first sample comes 0.7° after the index: the first revolution has no sample at or
    // before angle 0 to interpolate from and is dropped (motion::resample keeps whole
    // revolutions only).
    assert_eq!(segment["revolutions"], sea::REVOLUTIONS - 1);

    let tests = array(&segment["tests"]);
    let by_probes = |probes: &[&str], sensing: &str| {
        tests
            .iter()
            .find(|t| {
                t["sensing"] == sensing && {
                    let p: BTreeSet<&str> = array(&t["probes"])
                        .iter()
                        .map(|v| v.as_str().unwrap())
                        .collect();
                    p == set(probes)
                }
            })
            .unwrap_or_else(|| panic!("no {sensing} test of {probes:?}"))
    };
    let x1 = by_probes(&["x1"], "fixed");
    let y1 = by_probes(&["y1"], "fixed");
    let rotating = by_probes(&["x1", "y1"], "rotating");
    assert_eq!(tests.len(), 3, "two radial probes at one height, no more");
    for test in tests {
        assert_eq!(test["direction"], "radial");
        assert_eq!(test["unit"], "um");
        assert_eq!(test["values"][0]["centre"], "LSC");
    }

    // The closed forms.
    // Fixed sensitive direction along X: the synchronous profile is X(θ); LSC removes its first
    // harmonic (the artefact's eccentricity e and the 1-UPR orbit p), so the value is the range
    // of a2 cos(2θ+α2) + a3 cos(3θ+α3).
    let x1_lsc = fine_range(|t| {
        sea::A2 * (2.0 * t + sea::ALPHA2).cos() + sea::A3 * (3.0 * t + sea::ALPHA3).cos()
    });
    let y1_lsc = fine_range(|t| {
        sea::B2 * (2.0 * t + sea::ALPHA2).sin() + sea::B3 * (3.0 * t + sea::BETA3).sin()
    });
    // Rotating sensitive direction (formula (1)): r(θ) = X cos θ + Y sin θ; its first harmonic
    // is removed on a fine grid (exact for this trigonometric polynomial).
    let rotating_lsc = {
        let n = 36_000;
        let angles: Vec<f64> = (0..n).map(|i| TAU * i as f64 / n as f64).collect();
        let r: Vec<f64> = angles
            .iter()
            .map(|&t| {
                let (x, y) = sea::synchronous(t);
                x * t.cos() + y * t.sin()
            })
            .collect();
        range(&without_first_harmonic(&r, &angles))
    };
    // Error budget of the analyser's synchronous LSC value against these: the noise of the
    // 10-revolution mean (σ/√10 = 1.3 nm per point, so the two extremes within ±4σ each:
    // 10 nm), linear interpolation (h²/8·max|s''| with h = 2π/256, max|s''| < 10 µm/rad²:
    // 0.75 nm per point, 1.5 nm on a range), the 256-point grid missing the extremes (0.5 nm),
    // the bearing line's phase wobble from the speed ripple (A_b·4.4·0.0043 rad = 1.1 nm per
    // point, 2.3 nm on a range), rounding to 1 nm (0.3 nm rms). In all 15 nm.
    const SYNC_TOL: f64 = 0.015;
    let lsc = |test: &Value| number(&test["values"][0]["synchronous"]);
    for (name, test, model) in [
        ("radial x1", x1, x1_lsc),
        ("radial y1", y1, y1_lsc),
        ("radial x1+y1 rotating", rotating, rotating_lsc),
    ] {
        assert!(
            (lsc(test) - model).abs() < SYNC_TOL,
            "{name}: LSC synchronous {} against the model's {model}",
            lsc(test)
        );
    }
    // The fundamental (2·|1-UPR|) of the fixed X direction: the eccentricity and the 1-UPR
    // orbit together; tolerance twice a line's (below).
    let x1_first = phasor_sum(&[(sea::E, sea::DELTA), (sea::P, sea::GAMMA)]);
    let y1_first = phasor_sum(&[(sea::E, sea::DELTA), (sea::Q, sea::GAMMA)]);
    for (test, first) in [(x1, x1_first), (y1, y1_first)] {
        let fundamental = number(&test["values"][0]["fundamental"]);
        assert!(
            (fundamental - 2.0 * first).abs() < 0.004,
            "{fundamental} against {}",
            2.0 * first
        );
    }
    // The asynchronous value (the widest band at one angle): the bearing line over 10
    // revolutions at 4.4 UPR puts 5 equally spaced phases at every angle, a band between
    // 2 cos(π/5 / 2)·A_b (at best) and 2·A_b, widened or narrowed by the noise (±4σ at each end).
    let band_low = 2.0 * (PI / 10.0).cos() * sea::A_B - 8.0 * sea::SIGMA;
    let band_high = 2.0 * sea::A_B + 8.0 * sea::SIGMA;
    for test in [x1, y1, rotating] {
        let asynchronous = number(&test["values"][0]["asynchronous"]);
        assert!(
            (band_low..band_high).contains(&asynchronous),
            "{}: {asynchronous} not in [{band_low}, {band_high}]",
            test["name"]
        );
    }

    // The spectrum: each line of the model at its frequency with its amplitude. Tolerance
    // 2 nm: the noise spread over 2560 lines (< 0.2 nm a line), linear interpolation's
    // attenuation ((n·h)²/8 of the amplitude: 0.3 nm at 1 UPR of 4.1 µm, 0.1 nm at 4.4 UPR).
    // The bearing whirls forward at 4.4 times the rotation, so a probe turning with the rotor
    // (the rotating sensitive direction) sees it at 3.4 UPR. In the rotating direction
    // r = X cos θ + Y sin θ has, by the product-to-sum formulas, the lines
    //   1 UPR (a2+b2)/2, 2 UPR |(p−q)/2·e^{iγ} + a3/2·e^{iα3} + b3/2·e^{iβ3}|,
    //   3 UPR (a2−b2)/2, 4 UPR |a3/2·e^{iα3} − b3/2·e^{iβ3}|,
    // and the eccentricity only a constant (e cos δ).
    // (test, [(UPR, amplitude µm, synchronous)]).
    type Lines<'a> = (&'a Value, Vec<(f64, f64, bool)>);
    let expected_lines: [Lines<'_>; 3] = [
        (
            x1,
            vec![
                (1.0, x1_first, true),
                (2.0, sea::A2, true),
                (3.0, sea::A3, true),
                (sea::BEARING_UPR, sea::A_B, false),
            ],
        ),
        (
            y1,
            vec![
                (1.0, y1_first, true),
                (2.0, sea::B2, true),
                (3.0, sea::B3, true),
                (sea::BEARING_UPR, sea::A_B, false),
            ],
        ),
        (
            rotating,
            vec![
                (1.0, (sea::A2 + sea::B2) / 2.0, true),
                (
                    2.0,
                    phasor_sum(&[
                        ((sea::P - sea::Q) / 2.0, sea::GAMMA),
                        (sea::A3 / 2.0, sea::ALPHA3),
                        (sea::B3 / 2.0, sea::BETA3),
                    ]),
                    true,
                ),
                (3.0, (sea::A2 - sea::B2) / 2.0, true),
                (
                    4.0,
                    phasor_sum(&[(sea::A3 / 2.0, sea::ALPHA3), (-sea::B3 / 2.0, sea::BETA3)]),
                    true,
                ),
                (sea::BEARING_UPR - 1.0, sea::A_B, false),
            ],
        ),
    ];
    for (test, expected) in &expected_lines {
        let lines = array(&test["lines"]);
        for &(upr, amplitude, synchronous) in expected {
            let line = lines
                .iter()
                .find(|l| (number(&l["per_revolution"]) - upr).abs() < 1e-9)
                .unwrap_or_else(|| panic!("{}: no line at {upr} UPR in {lines:?}", test["name"]));
            assert_eq!(line["synchronous"], synchronous, "{line}");
            let got = number(&line["amplitude"]);
            assert!(
                (got - amplitude).abs() < 0.002,
                "{} at {upr} UPR: {got} against the model's {amplitude}",
                test["name"]
            );
            // In Hz at the mean speed: 100 rev/s, within the speed's 0.1 %.
            let hz = upr * sea::RPM / 60.0;
            assert!(
                (number(&line["hz"]) - hz).abs() < hz * 1e-3,
                "{line} against {hz} Hz"
            );
        }
        // The bearing line is the largest asynchronous line.
        let first_async = lines.iter().find(|l| l["synchronous"] == false).unwrap();
        assert!(
            (number(&first_async["amplitude"]) - sea::A_B).abs() < 0.002,
            "{first_async}"
        );
    }

    // The report for people says so too.
    let output = analyze(&path, &[]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let report = text(&output.stdout);
    assert!(
        report.contains("note: samples off the index grid: resampled"),
        "{report}"
    );
    assert!(report.contains("6000 min⁻¹, 10 revolutions"), "{report}");
}

// ---------------------------------------------------------------------------------------------
// 6. `discover spindle`.

/// `mtwin discover spindle FILE EXTRA…`.
fn discover(file: &Path, extra: &[&OsStr]) -> Output {
    let mut args: Vec<&OsStr> = vec!["discover".as_ref(), "spindle".as_ref(), file.as_os_str()];
    args.extend_from_slice(extra);
    mtwin(&args)
}

#[test]
fn discover_reports_the_documented_keys_on_a_foreign_export() {
    let output = discover(&data("foreign/sea_time.csv"), &["--json".as_ref()]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let json: Value = serde_json::from_slice(&output.stdout).expect("JSON on stdout");
    assert_eq!(
        keys(&json),
        set(&[
            "kind",
            "setup",
            "other_setups",
            "probes",
            "samples_per_revolution",
            "speeds_rpm",
            "revolutions",
            "n_samples",
            "validation",
            "baseline",
            "steps",
            "rejected",
            "untestable",
            "final",
            "cautions",
            "columns_not_read",
        ])
    );
    // A foreign export's extra columns and its own cautions: none here.
    assert_eq!(json["cautions"], serde_json::json!([]));
    assert_eq!(json["columns_not_read"], serde_json::json!([]));
    assert_eq!(keys(&json["validation"]), set(&["scheme", "folds", "rule"]));
    assert_eq!(
        keys(&json["baseline"]),
        set(&[
            "model",
            "base_harmonics",
            "rms_um",
            "cv_rms_um",
            "fold_cv_rms_um",
            "evidence"
        ])
    );
    let steps = array(&json["steps"]);
    let ids: Vec<&str> = steps
        .iter()
        .map(|s| s["effect"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["harmonic", "asynchronous_line"]);
    for step in steps {
        assert_eq!(
            keys(step),
            set(&[
                "effect",
                "together_with",
                "cause",
                "evidence",
                "params",
                "rms_um",
                "cv_rms_um",
                "fold_cv_rms_um",
                "gain_um",
                "gain_pct",
                "gain_z",
                "rest_z",
                "z_needed",
                "passed_on"
            ])
        );
        // Five folds: no in-sample route, so the held-out test is what it passed.
        assert_eq!(step["passed_on"], "held-out");
        // One held-out RMS per fold: 11 revolutions in min(5, 11) blocks.
        let folds: Vec<f64> = array(&step["fold_cv_rms_um"]).iter().map(number).collect();
        assert_eq!(folds.len(), 5);
        // Accepted: the combined z and the z without the best fold reach the z needed.
        assert!(number(&step["gain_z"]) >= number(&step["z_needed"]));
        assert!(number(&step["rest_z"]) >= number(&step["z_needed"]));
    }
    for rejected in array(&json["rejected"]) {
        assert_eq!(
            keys(rejected),
            set(&[
                "effect",
                "cv_rms_um",
                "fold_cv_rms_um",
                "gain_z",
                "rest_z",
                "z_needed",
                "fails"
            ])
        );
    }
    assert_eq!(
        keys(&steps[1]["params"]),
        set(&["per_revolution", "harmonics", "name", "hz", "amplitude"])
    );
    assert_eq!(
        keys(&json["final"]),
        set(&["model", "params", "rms_um", "cv_rms_um", "fold_cv_rms_um"])
    );
    // The 11 revolutions × 256 samples × 2 probes.
    assert_eq!(number(&json["n_samples"]), (11 * 256 * 2) as f64);
    // The text report names the same effects.
    let output = discover(&data("foreign/sea_time.csv"), &[]);
    let report = text(&output.stdout);
    assert!(
        report.contains("+ harmonic: 3 UPR") && report.contains("+ asynchronous_line: 4.400 UPR"),
        "{report}"
    );
}

#[test]
fn discover_refuses_what_it_cannot_search_with_the_file_named() {
    let sea = data("foreign/sea_time.csv");
    let small = data("small.csv");
    // (file, flags, what the message says, whether it is about the file)
    let cases: [(&Path, Vec<&str>, &str, bool); 4] = [
        (
            &sea,
            vec!["--setup", "reversed"],
            "set-up `reversed` is not in the record",
            true,
        ),
        (
            &sea,
            vec![
                "--bearing-elements",
                "9",
                "--bearing-element-diameter-mm",
                "40",
                "--bearing-pitch-diameter-mm",
                "39",
            ],
            "bearing geometry",
            false,
        ),
        (
            &sea,
            vec!["--bearing-elements", "9"],
            "--bearing-element-diameter-mm",
            false,
        ),
        // small.csv holds 2 revolutions: none could be held out.
        (&small, vec![], "at least 3", true),
    ];
    for (file, extra, what, about_the_file) in cases {
        let args: Vec<&OsStr> = extra.iter().map(|a| a.as_ref()).collect();
        let output = discover(file, &args);
        assert!(!output.status.success(), "{extra:?}");
        assert!(
            output.stdout.is_empty(),
            "{extra:?}: {}",
            text(&output.stdout)
        );
        let stderr = text(&output.stderr);
        assert!(
            stderr.contains(what),
            "{extra:?}: expected `{what}` in {stderr}"
        );
        if about_the_file {
            let name = file.file_name().unwrap().to_str().unwrap();
            assert!(
                stderr.contains(name),
                "{extra:?}: the file named in {stderr}"
            );
        }
    }
}
