//! Separations of records written the way other instruments write them — a vendor header,
//! readings rounded to 1 nm, probes given by their angle alone or by conventional names, noise
//! — from a model written here, apart from the twin; and the inputs of their uncertainty.

use super::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::Normal;

/// Samples per revolution and revolutions of both records.
const M: usize = 360;
const K: usize = 8;
/// Probe noise (µm, standard deviation per sample), before rounding to 0.001 µm.
const SIGMA: f64 = 0.002;

/// The model (µm, rad): artefact form `h(ψ)`, synchronous motion `(E_X, E_Y)(θ)` with a 2 µm
/// centring at 40°, and an asynchronous line along X at 4.4 UPR on the unwrapped angle `q`.
fn form(psi: f64) -> f64 {
    0.05 * (2.0 * psi + 0.3).cos() + 0.03 * (5.0 * psi - 1.0).cos()
}
fn motion(q: f64) -> (f64, f64) {
    let theta = q.rem_euclid(TAU);
    let centring = 40f64.to_radians();
    let x = 0.12 * (2.0 * theta + 0.5).cos() + 2.0 * (theta + centring).cos();
    let y = 0.08 * (3.0 * theta - 0.2).sin() + 2.0 * (theta + centring).sin();
    (x + 0.03 * (4.4 * q + 0.9).cos(), y)
}

/// `[a_k, b_k]` of `A cos(kθ + α)`.
fn cos_coefficients(amplitude: f64, alpha: f64) -> [f64; 2] {
    [amplitude * alpha.cos(), -amplitude * alpha.sin()]
}

/// The reading of a probe at stator azimuth `phi` facing the axis (positive when the surface
/// moves away): `−(E_X cos φ + E_Y sin φ) − h(φ − θ − turn)`, with noise, rounded to 1 nm.
fn reading(phi: f64, q: f64, turn: f64, rng: &mut ChaCha8Rng) -> f64 {
    let (x, y) = motion(q);
    let exact = -(x * phi.cos() + y * phi.sin()) - form(phi - q - turn);
    let noisy = exact + rng.sample(Normal::new(0.0, SIGMA).unwrap());
    (noisy * 1e3).round() / 1e3
}

/// Rows `revolution (from 1), angle_deg, time_s, readings…` of one set-up at 3000 min⁻¹.
fn rows(setup: Option<&str>, start: usize, reads: &mut dyn FnMut(f64) -> Vec<f64>) -> String {
    let mut out = String::new();
    for k in 0..K {
        for m in 0..M {
            let q = TAU * (k * M + m) as f64 / M as f64;
            let time = (start + k * M + m) as f64 / (M as f64 * 50.0);
            let cells: Vec<String> = reads(q).iter().map(|v| format!("{v:.3}")).collect();
            let setup = setup.map(|s| format!("{s},")).unwrap_or_default();
            out += &format!("{setup}{},{m},{time:.7},{}\r\n", k + 1, cells.join(","));
        }
    }
    out
}

fn number(value: &Value) -> f64 {
    value
        .as_f64()
        .unwrap_or_else(|| panic!("not a number: {value}"))
}

/// The harmonic `k` (≥ 2) of a JSON `harmonics_um`.
fn harmonic(harmonics: &Value, k: usize) -> [f64; 2] {
    assert_eq!(harmonics["from"], 2);
    [
        number(&harmonics["a"][k - 2]),
        number(&harmonics["b"][k - 2]),
    ]
}

#[track_caller]
fn near(got: [f64; 2], want: [f64; 2], tolerance: f64, what: &str) {
    let off = (got[0] - want[0]).hypot(got[1] - want[1]);
    assert!(
        off <= tolerance,
        "{what}: {got:?}, want {want:?} (off by {off:e})"
    );
}

/// The range of `f` over the record's grid.
fn grid_range(f: impl Fn(f64) -> f64) -> f64 {
    let v: Vec<f64> = (0..M).map(|m| f(TAU * m as f64 / M as f64)).collect();
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - v.iter().copied().fold(f64::INFINITY, f64::min)
}

// Tolerances. Noise of σ = 2 nm per sample averages over the K·M = 2880 samples of a probe to
// σ·√(2/KM) = 5e-5 µm per Fourier coefficient; rounding to 1 nm adds 0.29 nm per sample, less
// again. A separated coefficient combines three or four probes' coefficients with weights of
// order one, so 1e-3 µm is about 20 standard deviations: a wrong sign, a wrong harmonic or a
// wrong angle convention is off by 1e-2 µm or more. A value (a range over M samples of the
// separated profile) carries the profile's noise at its two extremes: about σ·√(2/K) = 1 nm
// per sample, so 0.01 µm bounds it.
const COEFFICIENT: f64 = 1e-3;
const VALUE: f64 = 0.01;

#[test]
fn a_foreign_multi_probe_export_with_probes_given_by_angle_is_separated() {
    let dir = tempfile::tempdir().unwrap();
    let azimuths = [0.0, 57.3, 180.0, 217.7];
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let mut header = String::from(
        "# MP-4 multi-probe roundness export\r\n# Operator: QA lab 2\r\n# Spindle speed 3000 rpm\r\n",
    );
    for (j, a) in azimuths.iter().enumerate() {
        header += &format!("# p{}_azimuth_deg = {a}\r\n", j + 1);
    }
    header += "revolution,angle_deg,time_s,p1_um,p2_um,p3_um,p4_um\r\n";
    let body = rows(None, 0, &mut |q| {
        azimuths
            .iter()
            .map(|a: &f64| reading(a.to_radians(), q, 0.0, &mut rng))
            .collect()
    });
    let path = dir.path().join("mp4.csv");
    std::fs::write(&path, header + &body).unwrap();
    let json = analyze_json(&path, &[]);
    assert_eq!(json["setup"]["preamble_not_used"], serde_json::json!([]));
    let separation = &json["separations"][0];
    assert_eq!(separation["method"], "multi-probe", "{json}");
    assert_eq!(separation["unknown"], serde_json::json!([]), "{separation}");
    for k in [2, 3, 5] {
        assert!(!array(&separation["blind"]).contains(&serde_json::json!(k)));
    }
    // The form: 2 and 5 UPR as modelled, nothing at 3 UPR; its 1 UPR went to the motion.
    let form_harmonics = &separation["form"]["harmonics_um"];
    near(
        harmonic(form_harmonics, 2),
        cos_coefficients(0.05, 0.3),
        COEFFICIENT,
        "form 2 UPR",
    );
    near(
        harmonic(form_harmonics, 5),
        cos_coefficients(0.03, -1.0),
        COEFFICIENT,
        "form 5 UPR",
    );
    near(
        harmonic(form_harmonics, 3),
        [0.0, 0.0],
        COEFFICIENT,
        "form 3 UPR",
    );
    assert!(separation["form"]["first_harmonic_um"].is_null());
    // Its roundness about LSC: the range of the model's form on the grid.
    let lsc = &separation["form"]["values"][0];
    assert_eq!(lsc["centre"], "LSC");
    let want = grid_range(form);
    assert!(
        (number(&lsc["value"]) - want).abs() <= VALUE,
        "{lsc} vs {want}"
    );

    // The motion: X holds the centring at 1 UPR and 0.12 µm at 2 UPR, Y 0.08 µm at 3 UPR.
    let x = &separation["motion"][0];
    let y = &separation["motion"][1];
    assert_eq!(
        (x["axis"].as_str(), y["axis"].as_str()),
        (Some("X"), Some("Y"))
    );
    let centring = 40f64.to_radians();
    let first: Vec<f64> = array(&x["first_harmonic_um"]).iter().map(number).collect();
    near(
        [first[0], first[1]],
        cos_coefficients(2.0, centring),
        COEFFICIENT,
        "X 1 UPR",
    );
    near(
        harmonic(&x["harmonics_um"], 2),
        cos_coefficients(0.12, 0.5),
        COEFFICIENT,
        "X 2 UPR",
    );
    near(
        harmonic(&y["harmonics_um"], 3),
        [-0.08 * 0.2f64.sin(), 0.08 * 0.2f64.cos()],
        COEFFICIENT,
        "Y 3 UPR",
    );
    // Values about LSC: the centring does not count, the 2 UPR does (its range on the grid).
    let x_lsc = &x["values"][0];
    let want = grid_range(|t| 0.12 * (2.0 * t + 0.5).cos());
    assert!(
        (number(&x_lsc["synchronous"]) - want).abs() <= VALUE,
        "{x_lsc} vs {want}"
    );
    // About PC the centring counts: about 4 µm.
    let x_pc = array(&x["values"])
        .iter()
        .find(|v| v["centre"] == "PC")
        .unwrap();
    assert!((number(&x_pc["synchronous"]) - 4.0).abs() < 0.2, "{x_pc}");
    // The asynchronous line is along X: its band over 8 revolutions, from the model, against
    // the noise alone along Y.
    let band = (0..M)
        .map(|m| {
            let at: Vec<f64> = (0..K)
                .map(|k| 0.03 * (4.4 * TAU * (k as f64 + m as f64 / M as f64) + 0.9).cos())
                .collect();
            at.iter().copied().fold(f64::NEG_INFINITY, f64::max)
                - at.iter().copied().fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    let x_async = number(&x["asynchronous_um"]);
    assert!(
        (x_async - band).abs() <= VALUE,
        "X asynchronous {x_async} vs {band}"
    );
    let y_async = number(&y["asynchronous_um"]);
    assert!(y_async < 0.3 * band, "Y asynchronous {y_async}: noise only");
}

#[test]
fn a_foreign_reversal_export_by_conventional_name_is_separated() {
    // Probe `x` by its conventional name reads +x motion: it sits at azimuth 180°. For the
    // reversal the artefact is turned 180° on the rotor and the probe moved to 0°. The motion
    // separated is along the probe, −X (the model's 1 UPR is the axis's, it does not turn with
    // the artefact, so it stays in the motion); the form is h(π + ψ) on the ψ grid.
    let dir = tempfile::tempdir().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(38);
    let header = "# SEA data export\r\n# Target: sphere 25.4 mm, reversal (Donaldson)\r\n\
                  setup,revolution,angle_deg,time_s,x_um\r\n";
    let normal = rows(Some("normal"), 0, &mut |q| {
        vec![reading(PI, q, 0.0, &mut rng)]
    });
    let reversed = rows(Some("reversed"), K * M, &mut |q| {
        vec![reading(0.0, q, PI, &mut rng)]
    });
    let path = dir.path().join("reversal.csv");
    std::fs::write(&path, header.to_string() + &normal + &reversed).unwrap();
    let json = analyze_json(&path, &[]);
    let separation = array(&json["separations"])
        .iter()
        .find(|s| s["method"] == "reversal")
        .unwrap_or_else(|| panic!("no reversal in {json}"));
    assert_eq!(separation["probes"], serde_json::json!(["x"]));
    let motion = &separation["motion"][0];
    assert_eq!(motion["axis"], "−X");
    // Along −X: minus E_X's harmonics.
    let [a, b] = cos_coefficients(0.12, 0.5);
    near(
        harmonic(&motion["harmonics_um"], 2),
        [-a, -b],
        COEFFICIENT,
        "−X 2 UPR",
    );
    let first: Vec<f64> = array(&motion["first_harmonic_um"])
        .iter()
        .map(number)
        .collect();
    let [a, b] = cos_coefficients(2.0, 40f64.to_radians());
    near([first[0], first[1]], [-a, -b], COEFFICIENT, "−X 1 UPR");
    // Nothing turned with the artefact at 1 UPR.
    let form_first: Vec<f64> = array(&separation["form"]["first_harmonic_um"])
        .iter()
        .map(number)
        .collect();
    near(
        [form_first[0], form_first[1]],
        [0.0, 0.0],
        COEFFICIENT,
        "form 1 UPR",
    );
    // The form h(π + ψ): harmonic k picks up (−1)^k.
    let form_harmonics = &separation["form"]["harmonics_um"];
    near(
        harmonic(form_harmonics, 2),
        cos_coefficients(0.05, 0.3),
        COEFFICIENT,
        "form 2 UPR",
    );
    let [a, b] = cos_coefficients(0.03, -1.0);
    near(
        harmonic(form_harmonics, 5),
        [-a, -b],
        COEFFICIENT,
        "form 5 UPR",
    );
    let lsc = &separation["form"]["values"][0];
    let want = grid_range(form);
    assert!(
        (number(&lsc["value"]) - want).abs() <= VALUE,
        "{lsc} vs {want}"
    );
    // The asynchronous motion of the normal set-up along the probe: the 4.4 UPR line.
    let async_value = number(&motion["asynchronous_um"]);
    assert!((async_value - 0.06).abs() < 0.015, "{async_value}");
}

/// The Annex F inputs: from the preamble, overridden by the flags; a bad one refused.
#[test]
fn the_uncertainty_inputs_come_from_the_preamble_or_the_flags() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(39);
    let header = "# SEA data export\r\n# device_range_um = 0.05\r\n# drift_um = 0.02\r\n\
                  revolution,angle_deg,time_s,x_um\r\n";
    let body = rows(None, 0, &mut |q| vec![reading(PI, q, 0.0, &mut rng)]);
    let path = dir.path().join("x.csv");
    std::fs::write(&path, header.to_string() + &body).unwrap();
    let u = |json: &Value| json["segments"][0]["tests"][0]["uncertainty"].clone();

    // Stated: F.2 and F.3, complete. The readings are rounded to 0.001 µm, but a stated
    // device term includes the resolution (ISO/TR 230-9 C.3).
    let stated = u(&analyze_json(&path, &[]));
    assert_eq!(stated["complete"], true, "{stated}");
    assert_eq!(stated["k"], 2);
    let sources: Vec<&str> = array(&stated["contributions"])
        .iter()
        .map(|c| c["source"].as_str().unwrap())
        .collect();
    assert!(
        sources[0].contains("F.2") && sources[1].contains("F.3"),
        "{sources:?}"
    );
    // 1.4·√((0.6·0.05)² + (0.6·0.02)²/8): no centring term (the probe is put on the axis).
    let want = 1.4 * ((0.6f64 * 0.05).powi(2) + (0.6f64 * 0.02).powi(2) / 8.0).sqrt();
    assert!(
        (number(&stated["synchronous"]) - want).abs() < 2e-6,
        "{stated} vs {want}"
    );

    // The flag overrides the preamble's range.
    let flagged = u(&analyze_json(
        &path,
        &["--device-range-um".as_ref(), "0.5".as_ref()],
    ));
    let want = 1.4 * ((0.6f64 * 0.5).powi(2) + (0.6f64 * 0.02).powi(2) / 8.0).sqrt();
    assert!(
        (number(&flagged["synchronous"]) - want).abs() < 2e-6,
        "{flagged}"
    );

    // Nothing stated: a lower bound, the resolution read from the rounding (1 nm).
    let bare = dir.path().join("bare.csv");
    std::fs::write(
        &bare,
        "revolution,angle_deg,time_s,x_um\r\n".to_string() + &body,
    )
    .unwrap();
    let lower = u(&analyze_json(&bare, &[]));
    assert_eq!(lower["complete"], false);
    assert!(
        array(&lower["contributions"])[0]["source"]
            .as_str()
            .unwrap()
            .starts_with("resolution 1.000 nm")
    );

    let refused = analyze(&path, &["--drift-um=-1".as_ref()]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(refused.stdout.is_empty());
    assert!(
        text(&refused.stderr).contains("--drift-um"),
        "{}",
        text(&refused.stderr)
    );
}
