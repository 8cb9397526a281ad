//! The evaluation context: error parameters that vary with time and axis speed (asynchronous
//! sinusoids, band-limited random motion, speed factors), written in a scenario and evaluated
//! through the exact chain, against closed forms.

use mtwin::app::Scenario;
use mtwin::machine::{Axis, AxisValues, MachineState, Workspace};
use mtwin::math::Real;
use std::f64::consts::TAU;
use std::path::PathBuf;

/// Writes `body` under a vmc3 header (with a one-point map, as a scenario must compute
/// something) into a temporary scenario and loads it.
fn load(name: &str, body: &str) -> Result<Scenario, String> {
    let dir = std::env::temp_dir().join(format!("mtwin-dynamics-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let models = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("models");
    let text = format!(
        "schema = 1\nmachine = \"{}\"\nseed = 3\n{body}\n[volumetric]\n\
         x_mm = {{ from = 0.0, to = 0.0, count = 1 }}\ny_mm = {{ from = 0.0, to = 0.0, count = 1 }}\n\
         z_mm = {{ from = 0.0, to = 0.0, count = 1 }}\n",
        models.join("vmc3.urdf").display()
    );
    let path = dir.join("s.toml");
    std::fs::write(&path, text).unwrap();
    let scenario = Scenario::load(&path).map_err(|e| e.to_string());
    std::fs::remove_dir_all(&dir).unwrap();
    scenario
}

/// The tool-tip deviation along X (µm) at spindle angle `theta` (unwrapped), time and speed.
fn dx_um(scenario: &Scenario, theta: Real, time: Real, speed: Real) -> Real {
    let twin = &scenario.twin;
    let mut workspace = Workspace::new(&twin.machine);
    let position = AxisValues::from_file_units(&[(Axis::X, 100.0), (Axis::Z, 50.0)]);
    let state = MachineState::at(position.with(Axis::S, theta))
        .at_time(time)
        .with_velocity(Axis::S, speed);
    twin.errors
        .deviation(&twin.machine, &mut workspace, &state)
        .translation
        .x
        * 1e6
}

#[test]
fn asynchronous_lines_enter_the_chain_at_the_spindle() {
    // EXS acts at the spindle's slot, before its rotation: a pure translation of the tool
    // along X relative to the workpiece, so the tip's X deviation is the value itself.
    let s = load(
        "async",
        "[errors.EXS]\nasynchronous = [{ amplitude_um = 0.5, per_revolution = 0.43, phase_deg = 30 }, \
         { amplitude_um = 0.2, frequency_hz = 437.0 }]\n",
    )
    .unwrap();
    for (theta, t) in [(0.0, 0.0), (1.0, 0.01), (37.3, 0.123), (250.0, 2.5)] {
        let expected =
            0.5 * (0.43 * theta + 30f64.to_radians()).sin() + 0.2 * (TAU * 437.0 * t).sin();
        // 1e-9 µm: the chain's exact composition of one translation (rounding only).
        assert!(
            (dx_um(&s, theta, t, 100.0) - expected).abs() < 1e-9,
            "θ = {theta}, t = {t}"
        );
    }
    // The per-revolution line follows the unwrapped angle: not periodic over one turn.
    assert!((dx_um(&s, 1.0, 0.0, 0.0) - dx_um(&s, 1.0 + TAU, 0.0, 0.0)).abs() > 0.1);
}

#[test]
fn a_speed_factor_scales_synchronous_and_asynchronous_content() {
    let s = load(
        "speed",
        "[errors.EXS]\nharmonic = [{ period_deg = 120, amplitude_um = 0.3 }]\n\
         asynchronous = [{ amplitude_um = 0.1, frequency_hz = 50.0 }]\n\
         speed = { rpm = [0, 6000, 12000], factor = [1, 1, 4] }\n",
    )
    .unwrap();
    let rpm = TAU / 60.0;
    let (theta, t): (Real, Real) = (0.7, 0.013);
    let bare = 0.3 * (3.0 * theta).sin() + 0.1 * (TAU * 50.0 * t).sin();
    // 9000 min⁻¹ lies half-way between 6000 (×1) and 12000 (×4): ×2.5; beyond the table ×4;
    // a negative speed (reverse rotation) uses its magnitude.
    for (speed, factor) in [
        (0.0, 1.0),
        (3000.0, 1.0),
        (9000.0, 2.5),
        (20000.0, 4.0),
        (-9000.0, 2.5),
    ] {
        let got = dx_um(&s, theta, t, speed * rpm);
        assert!(
            (got - factor * bare).abs() < 1e-9,
            "{speed} rpm: {got} vs {}",
            factor * bare
        );
    }
}

#[test]
fn random_motion_has_the_rms_asked_and_is_seeded() {
    let body = "[errors.EYS]\nrandom = { rms_um = 0.05, band_hz = [200, 1200] }\n";
    let s = load("random", body).unwrap();
    let dy = |s: &Scenario, t: Real| {
        let twin = &s.twin;
        let mut workspace = Workspace::new(&twin.machine);
        let state = MachineState::at(AxisValues::ZERO).at_time(t);
        twin.errors
            .deviation(&twin.machine, &mut workspace, &state)
            .translation
            .y
            * 1e6
    };
    // 10 s at 20 kHz: the band's slowest line makes ≥ 2000 periods, so the mean square of the
    // 64 lines is Σ a²/2 = rms² up to cross terms; 5 % covers those for any draw.
    let n = 200_000;
    let ms = (0..n)
        .map(|i| dy(&s, i as Real * 5e-5).powi(2))
        .sum::<Real>()
        / n as Real;
    assert!(
        (ms.sqrt() / 0.05 - 1.0).abs() < 0.05,
        "rms {} µm",
        ms.sqrt()
    );
    // The same scenario gives the same realisation.
    let again = load("random2", body).unwrap();
    assert_eq!(dy(&s, 0.123), dy(&again, 0.123));
}

#[test]
fn bad_dynamic_terms_are_refused_with_their_key() {
    let cases = [
        (
            "[errors.EXX]\nasynchronous = [{ amplitude_um = 0.1, per_revolution = 2.5 }]\n",
            "errors.EXX.asynchronous[0].per_revolution",
        ),
        (
            "[errors.EXS]\nasynchronous = [{ amplitude_um = 0.1 }]\n",
            "errors.EXS.asynchronous[0].frequency_hz",
        ),
        (
            "[errors.EXS]\nasynchronous = [{ amplitude_urad = 0.1, frequency_hz = 5 }]\n",
            "errors.EXS.asynchronous[0].amplitude_urad",
        ),
        (
            "[errors.EXS]\nrandom = { rms_um = 0.1, band_hz = [500, 100] }\n",
            "errors.EXS.random.band_hz",
        ),
        (
            "[errors.EXS]\nspeed = { mm_per_min = [0, 1], factor = [1, 2] }\n",
            "errors.EXS.speed.rpm",
        ),
        (
            "[errors.EXS]\nspeed = { rpm = [0, 1000], factor = [1, -2] }\n",
            "errors.EXS.speed.factor: value 2: -2: expected 0 … 1000",
        ),
        (
            "[errors.EC0Y]\nconstant_urad = 1.0\nasynchronous = [{ amplitude_urad = 0.1, frequency_hz = 5 }]\n",
            "errors.EC0Y.asynchronous",
        ),
    ];
    for (i, (body, key)) in cases.iter().enumerate() {
        let message = load(&format!("bad{i}"), body).unwrap_err();
        assert!(message.contains(key), "{key} not in: {message}");
    }
}
