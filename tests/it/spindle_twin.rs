//! The virtual spindle error analyser through the twin (ISO 230-7): scenario → programme →
//! twin → probes → table, against closed forms derived here from the chain's small-displacement
//! form and the machines' geometry (the URDF comments), and against injected truth.
//!
//! Conventions (see `kinds::spindle::instrument`): a probe reads `d·(displacement of the
//! artefact's surface relative to it) − h`, positive when the surface moves away; a fixed
//! radial probe at stator azimuth φ has `d = −(cos φ, sin φ, 0)`, so it reads
//! `−(E_X cos φ + E_Y sin φ) − h(φ − θ)`. In the axis frame the rotor's displacement at a point
//! `p` is, to first order, `δ + ε × (p − pivot)`: at a radial section of height z,
//! `ΔX(z) = δx + (z − z_pivot)·εy`, `ΔY(z) = δy − (z − z_pivot)·εx`, and on a face at
//! `(R cos φ, R sin φ)` `ΔZ = δz − R cos φ·εy + R sin φ·εx` (ISO 230-7 A.2, A.3).
//!
//! - vmc3's spindle S is on the tool side: its component errors (tool relative to workpiece, in
//!   the S slot frame, the spindle head's, parallel to the machine axes) are the artefact's
//!   motion relative to the probes on the table; the axis frame is the machine frame; the pivot
//!   of EAS/EBS is the S joint origin, the gauge line, 150 mm above the tool tip where the
//!   artefact's reference point sits (URDF: `tool_holder` at z = −0.15).
//! - trunnion5's C is on the workpiece side, its joint axis −z: the axis frame has z = −Z,
//!   x = X, y = −Y, and the table (the rotor) moves by minus the tool-relative EXC, EYC, EZC:
//!   by (−EXC, +EYC, +EZC) in the axis frame.
//!
//! Tolerances: 1 nm for exact kinematics (the chain is exact; the second-order terms of errors
//! of a few µm and µrad over 0.2 m are below 1 pm); noise tests at 3σ of the estimator's own
//! sampling spread.

use mtwin::app::{Scenario, run_scenario, simulate};
use mtwin::kinds::spindle::instrument::{AxisChain, ChainScratch};
use mtwin::kinds::spindle::table::{SpindleTable, parse};
use mtwin::kinds::spindle::{SpindleRecord, run};
use mtwin::math::{Real, Vector};
use std::f64::consts::{PI, TAU};
use std::path::Path;

const UM: Real = 1e-6;
const URAD: Real = 1e-6;
const NM: Real = 1e-9;
/// Exact kinematics.
const EXACT: Real = 1e-9;

/// Loads a scenario written in a temporary folder (the machine by absolute path).
fn load(text: &str) -> Result<Scenario, String> {
    let dir = tempfile::tempdir().unwrap();
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let text = text.replace("MODELS", &models.display().to_string());
    let path = dir.path().join("s.toml");
    std::fs::write(&path, text).unwrap();
    Scenario::load(&path).map_err(|e| e.to_string())
}

/// A scenario on `machine` with `errors` and the `[spindle]` keys and sub-tables `spindle`;
/// the probes are exact (no noise, resolution or filter) unless `spindle` sets them.
fn text(machine: &str, errors: &str, spindle: &str) -> String {
    let exact = [
        "noise_nm = 0.0",
        "resolution_nm = 0.0",
        "bandwidth_hz = inf",
    ]
    .into_iter()
    .filter(|k| !spindle.contains(k.split(' ').next().unwrap()))
    .collect::<Vec<_>>()
    .join("\n");
    format!(
        "schema = 1\nmachine = \"MODELS/{machine}.urdf\"\nseed = 5\n{errors}\n[spindle]\n{exact}\n{spindle}\n"
    )
}

fn table(text: &str) -> SpindleTable {
    let scenario = load(text).unwrap();
    simulate(&scenario).unwrap().spindle.unwrap()
}

fn readings<'a>(record: &'a SpindleRecord, name: &str) -> &'a [Real] {
    &record.readings[record
        .probe(name)
        .unwrap_or_else(|| panic!("no probe {name}"))]
}

/// The largest |got − want(i)| over the record.
fn worst(got: &[Real], want: impl Fn(usize) -> Real) -> Real {
    got.iter()
        .enumerate()
        .map(|(i, g)| (g - want(i)).abs())
        .fold(0.0, Real::max)
}

#[track_caller]
fn within(error: Real, tolerance: Real, what: &str) {
    assert!(
        error <= tolerance,
        "{what}: off by {error:e} m (tolerance {tolerance:e})"
    );
}

const VMC3_PROBES: &str = r#"
[[spindle.probe]]
name = "x1"
kind = "radial"
azimuth_deg = 0.0
[[spindle.probe]]
name = "y1"
kind = "radial"
azimuth_deg = 90.0
[[spindle.probe]]
name = "a"
kind = "radial"
azimuth_deg = 37.0
height_mm = 50.0
[[spindle.probe]]
name = "b"
kind = "radial"
azimuth_deg = 200.0
height_mm = 80.0
[[spindle.probe]]
name = "x2"
kind = "radial"
azimuth_deg = 0.0
height_mm = 80.0
[[spindle.probe]]
name = "y2"
kind = "radial"
azimuth_deg = 90.0
height_mm = 80.0
[[spindle.probe]]
name = "z"
kind = "axial"
[[spindle.probe]]
name = "face"
kind = "face"
radius_mm = 10.0
azimuth_deg = 0.0
"#;

/// Radial probes' azimuths (rad) of `VMC3_PROBES`.
const RADIAL: [(&str, Real); 6] = [
    ("x1", 0.0),
    ("y1", 90.0),
    ("a", 37.0),
    ("b", 200.0),
    ("x2", 0.0),
    ("y2", 90.0),
];

fn spindle_keys(extra: &str, artefact: &str) -> String {
    format!(
        "speeds_rpm = [3000.0]\nrevolutions = 2\nsamples_per_revolution = 64\n{extra}\n[spindle.artefact]\nkind = \"cylinder\"\ndiameter_mm = 25.0\nlength_mm = 80.0\n{artefact}\n{VMC3_PROBES}"
    )
}

#[test]
fn pure_eccentricity_reads_minus_e_cos_phi_minus_theta_minus_alpha() {
    // e = (3, −2) µm on the rotor: |e| = √13 µm at α = atan2(−2, 3). A fixed probe at φ reads
    // −e·cos(φ − θ − α); a rotating probe (artefact on the stator) −e·cos(φ + θ − α); the axial
    // and face probes nothing (the cylinder's face is square to the axis).
    let (ex, ey) = (3.0 * UM, -2.0 * UM);
    let (e, alpha) = (ex.hypot(ey), ey.atan2(ex));
    for (machine, keys) in [
        ("vmc3", ""),
        ("trunnion5", "axis = \"C\"\nspeeds_rpm = [10.0]\n"),
    ] {
        for (sensing, sign) in [("fixed", -1.0), ("rotating", 1.0)] {
            let spindle = spindle_keys(
                &format!("sensing = \"{sensing}\""),
                "eccentricity_um = [3.0, -2.0]",
            )
            .replace(
                "speeds_rpm = [3000.0]\n",
                if keys.is_empty() {
                    "speeds_rpm = [3000.0]\n"
                } else {
                    keys
                },
            );
            let t = table(&text(machine, "", &spindle));
            let r = &t.record;
            assert_eq!(r.len(), 128);
            for (name, phi) in RADIAL {
                let phi = phi.to_radians();
                within(
                    worst(readings(r, name), |i| {
                        -e * (phi + sign * r.angle[i] - alpha).cos()
                    }),
                    EXACT,
                    &format!("{machine} {sensing} {name}"),
                );
            }
            for name in ["z", "face"] {
                within(worst(readings(r, name), |_| 0.0), EXACT, name);
            }
        }
    }
}

/// `amplitude·cos(k·θ)` as the error model's harmonic (`a·sin(360°·q/P + φ)`, P = 360°/k,
/// φ = 90°).
fn cosine(name: &str, k: u32, amplitude: Real, unit: &str) -> String {
    format!(
        "[errors.{name}]\nharmonic = [{{ period_deg = {}, amplitude_{unit} = {amplitude}, phase_deg = 90.0 }}]\n",
        360.0 / k as Real
    )
}

#[test]
fn radial_and_axial_error_motions_of_s_read_with_the_sign_of_the_chain() {
    // EXS = a cos 3θ, EYS = b cos 2θ, EZS = c cos θ (tool relative to workpiece = the artefact
    // relative to the probes): x1 = −EXS, y1 = −EYS, a probe at φ reads
    // −(EXS cos φ + EYS sin φ) at any height (no tilt), z = +EZS (away from the probe below),
    // the face probe +EZS.
    let (a, b, c) = (0.4, 0.25, 0.3);
    let errors =
        cosine("EXS", 3, a, "um") + &cosine("EYS", 2, b, "um") + &cosine("EZS", 1, c, "um");
    let t = table(&text("vmc3", &errors, &spindle_keys("", "")));
    let r = &t.record;
    let exs = |i: usize| a * UM * (3.0 * r.angle[i]).cos();
    let eys = |i: usize| b * UM * (2.0 * r.angle[i]).cos();
    let ezs = |i: usize| c * UM * r.angle[i].cos();
    for (name, phi) in RADIAL {
        let phi = phi.to_radians();
        within(
            worst(readings(r, name), |i| {
                -(exs(i) * phi.cos() + eys(i) * phi.sin())
            }),
            EXACT,
            name,
        );
    }
    within(worst(readings(r, "z"), ezs), EXACT, "z");
    within(worst(readings(r, "face"), ezs), EXACT, "face");
}

#[test]
fn tilt_error_motions_give_the_station_difference_and_the_face_closed_forms() {
    // EBS = b cos 2θ, EAS = c cos 3θ about the gauge line, z_pivot = +150 mm above the
    // reference point: ΔX(z) = (z − 0.15)·EBS, ΔY(z) = −(z − 0.15)·EAS.
    //   x1 = −ΔX(0) = +0.15·EBS, x2 − x1 = −L·EBS (L = 80 mm),
    //   y1 = +ΔY... = −ΔY(0) = −0.15·EAS, y2 − y1 = +L·EAS,
    //   face at (R, 0, 0): ΔZ = −R·EBS (A.3), read +ΔZ; z on the axis: 0.
    let (b, c) = (3.0, 2.0);
    let errors = cosine("EBS", 2, b, "urad") + &cosine("EAS", 3, c, "urad");
    let t = table(&text("vmc3", &errors, &spindle_keys("", "")));
    let r = &t.record;
    let ebs = |i: usize| b * URAD * (2.0 * r.angle[i]).cos();
    let eas = |i: usize| c * URAD * (3.0 * r.angle[i]).cos();
    let (pivot, length, face) = (0.150, 0.080, 0.010);
    let (x1, x2) = (readings(r, "x1"), readings(r, "x2"));
    let (y1, y2) = (readings(r, "y1"), readings(r, "y2"));
    within(worst(x1, |i| pivot * ebs(i)), EXACT, "x1");
    within(worst(y1, |i| -pivot * eas(i)), EXACT, "y1");
    let dx: Vec<Real> = x2.iter().zip(x1).map(|(a, b)| a - b).collect();
    let dy: Vec<Real> = y2.iter().zip(y1).map(|(a, b)| a - b).collect();
    within(worst(&dx, |i| -length * ebs(i)), EXACT, "x2 − x1");
    within(worst(&dy, |i| length * eas(i)), EXACT, "y2 − y1");
    within(
        worst(readings(r, "face"), |i| -face * ebs(i)),
        EXACT,
        "face",
    );
    within(worst(readings(r, "z"), |_| 0.0), EXACT, "z");
    // The tilt of an inclined probe station: probe a at 37°, 50 mm up.
    let phi = 37f64.to_radians();
    within(
        worst(readings(r, "a"), |i| {
            let z = 0.050 - pivot;
            -(z * ebs(i) * phi.cos() - z * eas(i) * phi.sin())
        }),
        EXACT,
        "a",
    );
}

#[test]
fn a_table_axis_moves_its_artefact_against_the_tool_relative_errors() {
    // trunnion5's C: the table (rotor) moves by (−EXC, +EYC, +EZC) in the axis frame, so
    // x1 = +EXC, y1 = −EYC, z = +EZC. EXC = a cos 2θ, EYC = b cos 3θ, EZC = c cos θ.
    let (a, b, c) = (1.2, 0.7, 0.5);
    let errors =
        cosine("EXC", 2, a, "um") + &cosine("EYC", 3, b, "um") + &cosine("EZC", 1, c, "um");
    let spindle = spindle_keys("axis = \"C\"\nx_mm = 325.0\ny_mm = 275.0\n", "")
        .replace("speeds_rpm = [3000.0]", "speeds_rpm = [10.0, -10.0]");
    let t = table(&text("trunnion5", &errors, &spindle));
    let r = &t.record;
    assert_eq!(r.len(), 2 * 128);
    // Backwards at −10 rpm: the angles run down.
    assert!((r.angle[129] - (TAU - TAU / 64.0)).abs() < 1e-12);
    let exc = |i: usize| a * UM * (2.0 * r.angle[i]).cos();
    let eyc = |i: usize| b * UM * (3.0 * r.angle[i]).cos();
    let ezc = |i: usize| c * UM * r.angle[i].cos();
    within(worst(readings(r, "x1"), exc), EXACT, "x1");
    within(worst(readings(r, "x2"), exc), EXACT, "x2");
    within(worst(readings(r, "y1"), |i| -eyc(i)), EXACT, "y1");
    within(worst(readings(r, "z"), ezc), EXACT, "z");
    within(worst(readings(r, "face"), ezc), EXACT, "face");
}

#[test]
fn donaldson_reversal_separates_the_form_exactly() {
    // A sphere with a 3-, 5- and 8-lobe form and a spindle with synchronous radial error
    // motion: set-up 1 reads r1 = −EXS − h(−θ) at φ = 0; set-up 2 (sphere turned 180°, probe at
    // φ = 180°) r2 = +EXS − h(−θ). So (r1 + r2)/2 = −h(−θ) and (r1 − r2)/2 = −EXS, exactly.
    let form = [(3u32, 40.0, 10.0), (5, 25.0, -70.0), (8, 10.0, 135.0)];
    let h = |psi: Real| -> Real {
        form.iter()
            .map(|&(k, a, p): &(u32, Real, Real)| a * NM * (k as Real * psi + p.to_radians()).sin())
            .sum()
    };
    let form_toml = form
        .iter()
        .map(|(k, a, p)| format!("{{ per_revolution = {k}, amplitude_nm = {a}, phase_deg = {p} }}"))
        .collect::<Vec<_>>()
        .join(", ");
    let errors = cosine("EXS", 2, 0.3, "um") + &cosine("EYS", 3, 0.2, "um");
    let spindle = format!(
        "speeds_rpm = [3000.0, 9000.0]\nrevolutions = 2\nsamples_per_revolution = 128\nsetups = [\"normal\", \"reversed\"]\n\
         [spindle.artefact]\nkind = \"sphere\"\ndiameter_mm = 25.4\nform = [{form_toml}]\n\
         [[spindle.probe]]\nname = \"x\"\nkind = \"radial\"\nazimuth_deg = 0.0\n\
         [[spindle.probe]]\nname = \"y\"\nkind = \"radial\"\nazimuth_deg = 90.0\n"
    );
    let t = table(&text("vmc3", &errors, &spindle));
    let r = &t.record;
    let half = r.len() / 2;
    assert_eq!(half, 2 * 2 * 128);
    assert!(r.setup[..half].iter().all(|s| s == "normal"));
    assert!(r.setup[half..].iter().all(|s| s == "reversed"));
    // The probe at φ reads −(EXS cos φ + EYS sin φ): x sees EXS, y sees EYS.
    let motion = |name: &str, t: Real| match name {
        "x" => 0.3 * UM * (2.0 * t).cos(),
        _ => 0.2 * UM * (3.0 * t).cos(),
    };
    for (name, phi) in [("x", 0.0), ("y", PI / 2.0)] {
        let v = readings(r, name);
        let (r1, r2) = v.split_at(half);
        assert_eq!(r.angle[..half], r.angle[half..]);
        let sum: Vec<Real> = r1.iter().zip(r2).map(|(a, b)| (a + b) / 2.0).collect();
        let diff: Vec<Real> = r1.iter().zip(r2).map(|(a, b)| (a - b) / 2.0).collect();
        within(
            worst(&sum, |i| -h(phi - r.angle[i])),
            EXACT,
            &format!("{name}: form"),
        );
        within(
            worst(&diff, |i| -motion(name, r.angle[i])),
            EXACT,
            &format!("{name}: motion"),
        );
    }
}

#[test]
fn an_asynchronous_line_shows_as_a_sine_in_time_through_speed_changes() {
    // EXS: a cage line a·sin(0.43·q + φ) on the unwrapped angle q and a structural line
    // b·sin(2π·437 Hz·t + ψ). The record runs 2000 rpm then 5000 rpm, no settling: q = ω₁t
    // until the end of the first record T₁ = 3 revolutions / f₁, then 2π·3 + ω₂(t − T₁).
    // Probe x1 reads −EXS.
    let (a, b, phi, psi) = (0.05, 0.02, 25f64.to_radians(), -40f64.to_radians());
    let errors = format!(
        "[errors.EXS]\nasynchronous = [{{ amplitude_um = {a}, per_revolution = 0.43, phase_deg = 25.0 }}, \
         {{ amplitude_um = {b}, frequency_hz = 437.0, phase_deg = -40.0 }}]\n"
    );
    let spindle = "speeds_rpm = [2000.0, 5000.0]\nrevolutions = 3\nsamples_per_revolution = 256\n\
                   [spindle.artefact]\nkind = \"sphere\"\n\
                   [[spindle.probe]]\nname = \"x1\"\nkind = \"radial\"\n";
    let t = table(&text("vmc3", &errors, spindle));
    let r = &t.record;
    let (w1, w2) = (2000.0 * TAU / 60.0, 5000.0 * TAU / 60.0);
    let t1 = 3.0 * TAU / w1;
    let q = |t: Real| {
        if t < t1 - 1e-12 {
            w1 * t
        } else {
            3.0 * TAU + w2 * (t - t1)
        }
    };
    // Time itself, independently: sample m of revolution k at t_start + (k + m/M)/f.
    assert!((r.time[256 * 3] - t1).abs() < 1e-15);
    assert!(
        (r.time[256 * 3 + 256 + 5] - (t1 + (1.0 + 5.0 / 256.0) / (5000.0 / 60.0))).abs() < 1e-14
    );
    within(
        worst(readings(r, "x1"), |i| {
            let t = r.time[i];
            -(a * UM * (0.43 * q(t) + phi).sin() + b * UM * (TAU * 437.0 * t + psi).sin())
        }),
        EXACT,
        "x1",
    );
    // Asynchronous: revolution to revolution the reading does not repeat (the cage line alone
    // changes by up to 2a·sin(0.43π) = 98 nm between revolutions).
    let x1 = readings(r, "x1");
    assert!(worst(&x1[..256], |m| x1[m + 256]) > 50.0 * NM);
}

#[test]
fn the_speed_factor_scales_the_synchronous_error_motion() {
    // EXS = a cos 2θ × factor(speed), factor 1 at 0 rpm, 2 at 6000 rpm, linear between: 1.5 at
    // 3000 rpm, 2 at 9000 rpm (held beyond the last knot).
    let errors =
        cosine("EXS", 2, 0.4, "um") + "speed = { rpm = [0.0, 6000.0], factor = [1.0, 2.0] }\n";
    let spindle = "speeds_rpm = [3000.0, 9000.0]\nrevolutions = 1\nsamples_per_revolution = 64\n\
                   [spindle.artefact]\nkind = \"sphere\"\n[[spindle.probe]]\nname = \"x1\"\nkind = \"radial\"\n";
    let t = table(&text("vmc3", &errors, spindle));
    let r = &t.record;
    within(
        worst(readings(r, "x1"), |i| {
            let factor = if i < 64 { 1.5 } else { 2.0 };
            -factor * 0.4 * UM * (2.0 * r.angle[i]).cos()
        }),
        EXACT,
        "x1",
    );
}

#[test]
fn noise_gain_and_bandwidth_are_the_probe_s_own() {
    // One line at 300 Hz of 1 µm in EXS, 6000 rpm (100 rev/s), 512 samples a revolution
    // (Δt = 1/51200 s), 20 revolutions: N = 10240 samples.
    let errors = "[errors.EXS]\nasynchronous = [{ amplitude_um = 1.0, frequency_hz = 300.0 }]\n";
    let probes = "[spindle.artefact]\nkind = \"sphere\"\n[[spindle.probe]]\nname = \"x1\"\nkind = \"radial\"\n";
    let run = |keys: &str| {
        let spindle = format!(
            "speeds_rpm = [6000.0]\nrevolutions = 20\nsamples_per_revolution = 512\n{keys}\n{probes}"
        );
        let t = table(&text("vmc3", errors, &spindle));
        (readings(&t.record, "x1").to_vec(), t.record.time.clone())
    };
    let (clean, time) = run("");
    let n = clean.len() as Real;
    assert_eq!(clean.len(), 10240);

    // Noise: white Gaussian σ after the filter; the sample RMS of the difference estimates σ
    // with a spread σ/√(2N), its mean 0 with σ/√N.
    let sigma = 5.0 * NM;
    let (noisy, _) = run("noise_nm = 5.0");
    let d: Vec<Real> = noisy.iter().zip(&clean).map(|(a, b)| a - b).collect();
    let mean = d.iter().sum::<Real>() / n;
    let rms = (d.iter().map(|v| v * v).sum::<Real>() / n).sqrt();
    assert!(mean.abs() < 3.0 * sigma / n.sqrt(), "mean {mean:e}");
    assert!(
        (rms - sigma).abs() < 3.0 * sigma / (2.0 * n).sqrt(),
        "rms {rms:e}"
    );

    // Gain: (1 + g) times the reading, to rounding.
    let spindle = format!(
        "speeds_rpm = [6000.0]\nrevolutions = 20\nsamples_per_revolution = 512\n{}",
        probes.replace(
            "kind = \"radial\"\n",
            "kind = \"radial\"\ngain_error = 0.01\n"
        )
    );
    let t = table(&text("vmc3", errors, &spindle));
    within(
        worst(readings(&t.record, "x1"), |i| 1.01 * clean[i]),
        1e-18,
        "gain",
    );

    // Resolution: every reading a multiple of it, within half of it of the exact one.
    let (coarse, _) = run("resolution_nm = 50.0");
    for (c, e) in coarse.iter().zip(&clean) {
        let steps = c / (50.0 * NM);
        assert!((steps - steps.round()).abs() < 1e-6 && (c - e).abs() <= 25.0 * NM + 1e-15);
    }

    // Bandwidth: a first-order low-pass at 500 Hz, discretised step-invariantly
    // (y += α(x − y), α = 1 − e^{−2π f_c Δt}), passes the 300 Hz line x = −sin(ωt) as
    // −|H| sin(ωt + arg H), H = α / (1 − (1 − α) e^{−iωΔt}). Settled for 20 ms (63 time constants).
    let (filtered, _) = run("bandwidth_hz = 500.0\nsettle_s = 0.02");
    let dt: Real = 1.0 / 51200.0;
    let alpha = 1.0 - (-TAU * 500.0 * dt).exp();
    let w = TAU * 300.0;
    let (re, im) = (
        1.0 - (1.0 - alpha) * (w * dt).cos(),
        (1.0 - alpha) * (w * dt).sin(),
    );
    let (gain, phase) = (alpha / re.hypot(im), -im.atan2(re));
    // Sanity of the closed form against the continuous filter: |H| ≈ 1/√(1 + (300/500)²).
    assert!((gain - 1.0 / (1.0 + 0.36_f64).sqrt()).abs() < 0.01);
    within(
        worst(&filtered, |i| -UM * gain * (w * time[i] + phase).sin()),
        EXACT,
        "filtered line",
    );
}

/// A twin with errors on every axis, location errors of the rotary axes and a spindle with
/// harmonics, asynchronous lines, random motion and a speed factor.
const MANY_ERRORS_TRUNNION: &str = r#"
[errors.EX0C]
constant_um = 12.0
[errors.EY0C]
constant_um = -8.0
[errors.EA0C]
constant_urad = 25.0
[errors.EB0C]
constant_urad = -15.0
[errors.EC0C]
constant_urad = 30.0
[errors.EY0A]
constant_um = 6.0
[errors.EB0A]
constant_urad = 20.0
[errors.EXC]
harmonic = [{ period_deg = 120.0, amplitude_um = 0.8, phase_deg = 10.0 }]
asynchronous = [{ amplitude_um = 0.1, per_revolution = 0.43 }]
random = { rms_um = 0.05, band_per_revolution = [1.5, 40.0] }
[errors.EBC]
harmonic = [{ period_deg = 180.0, amplitude_urad = 4.0, phase_deg = 0.0 }]
speed = { rpm = [0.0, 20.0], factor = [1.0, 3.0] }
[errors.EZC]
polynomial_um = [0.5]
[errors.EXX]
polynomial_um = [0.0, 0.01]
[errors.ECX]
polynomial_urad = [3.0]
[errors.EBZ]
polynomial_urad = [-4.0]
[errors.EC0Y]
constant_urad = 20.0
[errors.EXS]
harmonic = [{ period_deg = 180.0, amplitude_um = 0.3, phase_deg = 0.0 }]
[errors.EZT]
constant_um = 5.0
"#;

const MANY_ERRORS_VMC3: &str = r#"
[errors.EXS]
harmonic = [{ period_deg = 180.0, amplitude_um = 0.3, phase_deg = 20.0 }]
asynchronous = [{ amplitude_um = 0.05, per_revolution = 0.43 }, { amplitude_um = 0.02, frequency_hz = 437.0 }]
random = { rms_um = 0.01, band_hz = [50.0, 2000.0] }
speed = { rpm = [0.0, 6000.0, 12000.0], factor = [1.0, 1.5, 3.0] }
[errors.EYS]
harmonic = [{ period_deg = 120.0, amplitude_um = 0.2, phase_deg = 0.0 }]
[errors.EZS]
harmonic = [{ period_deg = 360.0, amplitude_um = 0.1, phase_deg = 0.0 }]
[errors.EAS]
harmonic = [{ period_deg = 180.0, amplitude_urad = 2.0, phase_deg = 0.0 }]
[errors.EBS]
harmonic = [{ period_deg = 120.0, amplitude_urad = 3.0, phase_deg = 40.0 }]
[errors.ECS]
harmonic = [{ period_deg = 360.0, amplitude_urad = 10.0, phase_deg = 0.0 }]
[errors.EXX]
polynomial_um = [1.0, 0.01]
[errors.EAX]
polynomial_urad = [2.0]
[errors.EBY]
polynomial_urad = [-3.0]
[errors.ECZ]
polynomial_urad = [5.0]
[errors.EC0Y]
constant_urad = 20.0
[errors.EB0Z]
constant_urad = -10.0
[errors.EZT]
constant_um = 5.0
"#;

#[test]
fn the_factored_chain_is_the_plain_chain() {
    // The rotor's pose along each record of a programme from the factored chain (tabled
    // synchronous part, asynchronous lines advanced by phase steps) and from
    // ErrorModel::workpiece_from_tool at the same states: the probes' points land within
    // 1e-12 m, sample by sample, in order and out of order. With an error in Hz on another axis
    // the chain is not factored (and so agrees).
    let cases = [
        (
            "vmc3",
            MANY_ERRORS_VMC3.to_string(),
            "speeds_rpm = [3000.0, -12000.0]",
            true,
        ),
        (
            "trunnion5",
            MANY_ERRORS_TRUNNION.to_string(),
            "axis = \"C\"\nx_mm = 325.0\ny_mm = 275.0\na_deg = -20.0\nspeeds_rpm = [10.0, -25.0]\n",
            true,
        ),
        (
            "trunnion5",
            MANY_ERRORS_TRUNNION.to_string(),
            "axis = \"S\"\na_deg = 30.0\nc_deg = 40.0\nspeeds_rpm = [3000.0]\n",
            true,
        ),
        (
            "vmc3",
            MANY_ERRORS_VMC3.replace(
                "[errors.EXX]\n",
                "[errors.EXX]\nasynchronous = [{ amplitude_um = 0.2, frequency_hz = 50.0 }]\n",
            ),
            "",
            false,
        ),
    ];
    for (machine, errors, keys, factored) in cases {
        let spindle = format!(
            "{keys}\nrevolutions = 3\nsamples_per_revolution = 128\nsettle_s = 0.01\n\
             [spindle.artefact]\nkind = \"cylinder\"\nstickout_mm = 30.0\neccentricity_um = [2.0, 1.0]\n"
        );
        let scenario = load(&text(machine, &errors, &spindle)).unwrap();
        let test = scenario.spindle_test.as_ref().unwrap();
        let twin = &scenario.twin;
        let chain = AxisChain::new(twin, test.axis, test.parked, test.artefact.stickout).unwrap();
        assert_eq!(chain.is_factored(), factored, "{machine} {keys}");
        let mut scratch = ChainScratch::new(twin);
        let points = [
            Vector::new(0.0125, 0.0, 0.0),
            Vector::new(0.0, -0.0125, 0.08),
            Vector::new(0.0, 0.0, -0.0125),
            Vector::new(-0.3, 0.2, 0.5),
        ];
        let mut largest: Real = 0.0;
        let mut compare = |fast: mtwin::math::Pose, plain: mtwin::math::Pose| {
            for p in points {
                largest =
                    largest.max((fast.transform_point3(p) - plain.transform_point3(p)).length());
            }
        };
        for block in test.blocks() {
            let mut along = chain.along(twin, &block);
            let count = block.sample_count();
            // In order, then jumping about.
            let order = (0..count).chain((0..count).rev().step_by(7));
            for j in order {
                let sample = block.sample(j);
                let fast = along.pose(j, &sample, &mut scratch);
                let state = chain.state(sample.position, block.speed, sample.time);
                let plain = chain.rotor_in_stator_plain(twin, &mut scratch, &state);
                compare(fast, plain);
            }
        }
        assert!(largest < 1e-12, "{machine} {keys}: {largest:e} m");
        // The chain's errors are there to compare: the rotor moves by micrometres.
        let block = test.blocks()[0];
        let sample = block.sample(5);
        let state = chain.state(sample.position, block.speed, sample.time);
        let plain = chain.rotor_in_stator_plain(twin, &mut scratch, &state);
        let nominal = mtwin::math::Pose::from_rotation_z(sample.position);
        assert!(
            (plain.transform_point3(points[0]) - nominal.transform_point3(points[0])).length()
                > 0.1 * UM
        );
    }
}

#[test]
fn on_a_perfect_machine_the_rotor_turns_about_the_axis_frame_z() {
    // No errors: M = Rot_z(θ) (the frames are on the axis, z along the joint axis), and every
    // probe reads 0.
    for (machine, keys) in [
        ("vmc3", ""),
        ("trunnion5", "axis = \"C\"\na_deg = -30.0\n"),
        ("trunnion5", "axis = \"S\"\na_deg = 45.0\nc_deg = 30.0\n"),
    ] {
        let scenario = load(&text(
            machine,
            "",
            &format!("{keys}\nrevolutions = 1\nsamples_per_revolution = 16\n"),
        ))
        .unwrap();
        let test = scenario.spindle_test.as_ref().unwrap();
        let chain = AxisChain::new(&scenario.twin, test.axis, test.parked, 0.02).unwrap();
        let mut scratch = ChainScratch::new(&scenario.twin);
        for block in test.blocks() {
            let mut along = chain.along(&scenario.twin, &block);
            for j in 0..block.sample_count() {
                let sample = block.sample(j);
                let m = along.pose(j, &sample, &mut scratch);
                let want = mtwin::math::Pose::from_rotation_z(sample.position);
                assert!(m.abs_diff_eq(want, 1e-14), "{machine} {keys} at {j}: {m:?}");
            }
        }
        let t = simulate(&scenario).unwrap().spindle.unwrap();
        for v in &t.record.readings {
            within(worst(v, |_| 0.0), 1e-15, machine);
        }
    }
}

#[test]
fn the_output_does_not_depend_on_the_thread_count() {
    let spindle = "speeds_rpm = [2000.0, 6000.0, 12000.0]\nrevolutions = 3\nsamples_per_revolution = 256\nnoise_nm = 3.0\nresolution_nm = 0.1\nbandwidth_hz = 10000.0\nsetups = [\"normal\", \"reversed\"]\n";
    let scenario = load(&text("vmc3", MANY_ERRORS_VMC3, spindle)).unwrap();
    let csv =
        |threads: usize| crate::common::on_threads(threads, || run_scenario(&scenario).unwrap());
    let (one, four) = (csv(1), csv(4));
    assert_eq!(one, four);
    let table = one.files.iter().find(|(n, _)| n == "spindle.csv").unwrap();
    assert!(table.1.len() > 100_000);
}

#[test]
fn the_table_reads_back_as_simulated() {
    // `mtwin run`'s spindle.csv through the table's reader: the record to the file's rounding
    // (readings 1 pm, angles 1e-6°, times 1 µs), the probes' geometry, the set-ups.
    let spindle = "speeds_rpm = [600.0, 1200.0]\nrevolutions = 2\nsamples_per_revolution = 64\nsetups = [\"normal\", \"reversed\"]\n";
    let scenario = load(&text("vmc3", MANY_ERRORS_VMC3, spindle)).unwrap();
    let simulated = simulate(&scenario).unwrap().spindle.unwrap();
    let output = run_scenario(&scenario).unwrap();
    let bytes = &output
        .files
        .iter()
        .find(|(n, _)| n == "spindle.csv")
        .unwrap()
        .1;
    let read = parse(bytes, "spindle.csv").unwrap();
    let (a, b) = (&simulated.record, &read.record);
    assert_eq!(read.samples_per_revolution, 64);
    for (p, q) in a.probes.iter().zip(&b.probes) {
        assert_eq!((&p.name, p.sensing), (&q.name, q.sensing));
        for k in 0..3 {
            assert!(
                (p.direction[k] - q.direction[k]).abs() < 1e-9,
                "{p:?} {q:?}"
            );
            assert!((p.position[k] - q.position[k]).abs() < 1e-9, "{p:?} {q:?}");
        }
    }
    assert_eq!((&a.setup, &a.revolution), (&b.setup, &b.revolution));
    for (x, y) in a.readings.iter().zip(&b.readings) {
        within(worst(y, |i| x[i]), 0.6e-12, "readings");
    }
    within(worst(&b.angle, |i| a.angle[i]), 1e-8, "angles");
    within(worst(&b.time, |i| a.time[i]), 0.6e-6, "times");
    within(worst(&b.speed, |i| a.speed[i]), 1e-3, "speeds");
    let truth: serde_json::Value = serde_json::from_slice(
        &output
            .files
            .iter()
            .find(|(n, _)| n == "truth.json")
            .unwrap()
            .1,
    )
    .unwrap();
    let spindle = &truth["spindle_test"];
    assert_eq!(spindle["axis"], "S");
    assert_eq!(spindle["frames"]["rotor_motion_sign"], 1.0);
    assert_eq!(spindle["frames"]["axis_from_slot"]["pivot_mm"][2], 150.0);
    assert_eq!(spindle["probes"].as_array().unwrap().len(), 5);
}

mod scenarios_and_refusals;
