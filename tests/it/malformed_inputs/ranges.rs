//! Values beyond any instrument, machine or workshop (issue 42, item 2): each bundled scenario
//! with one value pushed out of its physical range is refused at that value's line, with the
//! key, the value as written (huge ones in scientific notation) and the range's reason.

use super::{
    VMC3, assert_at_joint, assert_names_file, exx_with, line_of, replace_once, scenario_error,
    urdf_error, write,
};
use mtwin::app::Scenario;
use mtwin::machine::MachineErrorKind;
use mtwin::scenario::ScenarioErrorKind;
use std::path::Path;
use tempfile::TempDir;

/// The bundled scenario `name` with `from` replaced by `to`, its machine given by absolute
/// path (it is loaded from a temporary folder).
fn bundled_with(name: &str, from: &str, to: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenarios").join(name)).unwrap();
    let models = format!("\"{}/", root.join("models").display());
    replace_once(&text.replace("\"../models/", &models), from, to)
}

/// The scenario `text` is refused as a value error at the line holding `at`, and its message
/// holds each of `expected`.
fn refused_at(text: &str, at: &str, expected: &[&str]) {
    let (error, path) = scenario_error(text);
    let message = error.to_string();
    assert_eq!(error.kind(), ScenarioErrorKind::Value, "{message}");
    let line = line_of(text, at);
    assert_eq!(error.line(), Some(line), "{message}");
    assert!(
        message.starts_with(&format!("{path}:{line}: ")),
        "{message}"
    );
    for part in expected {
        assert!(message.contains(part), "{message:?} should hold {part:?}");
    }
}

#[test]
fn laser_values_beyond_an_interferometer_are_refused_at_their_line() {
    let cases: [(&str, &str, &[&str]); 4] = [
        (
            "noise_nm = 20.0",
            "noise_nm = 1e300",
            &["laser.noise_nm: 1e300: expected 0 … 10000", "10 µm"],
        ),
        (
            "beam_offset_mm = [0.0, 0.0, 150.0]",
            "beam_offset_mm = [0.0, 0.0, 15000.0]",
            &["laser.beam_offset_mm: 15000: expected -5000 … 5000"],
        ),
        (
            "resolution_nm = 1.0",
            "resolution_nm = 1.0\nmisalignment_urad = [20000.0, 0.0]",
            &[
                "laser.misalignment_urad: 20000: expected -10000 … 10000",
                "leaves the optics",
            ],
        ),
        (
            "noise_nm = 20.0",
            "noise_nm = 20.0\nmaterial = { expansion_ppm_per_degc = 1170.0, temperature_degc = 20.0 }",
            &["laser.material.expansion_ppm_per_degc: 1170: expected -10 … 100"],
        ),
    ];
    for (from, to, expected) in cases {
        let text = bundled_with("teach_abbe.toml", from, to);
        let at = to.lines().last().unwrap();
        refused_at(&text, at, expected);
    }
}

#[test]
fn feeds_beyond_a_machine_are_refused_at_their_line() {
    let text = bundled_with(
        "teach_abbe.toml",
        "feed_mm_per_min = 6000.0",
        "feed_mm_per_min = 1e-9",
    );
    refused_at(
        &text,
        "feed_mm_per_min = 1e-9",
        &["iso230_2.feed_mm_per_min: 0.000000001: expected 0.1 … 200000"],
    );
    let text = bundled_with(
        "teach_warmup.toml",
        "feed_mm_per_min = 4800.0",
        "feed_mm_per_min = 1e9",
    );
    refused_at(
        &text,
        "feed_mm_per_min = 1e9",
        &["warmup.idle.feed_mm_per_min: 1000000000; expected 0.1 … 200000 mm/min"],
    );
}

#[test]
fn probe_values_beyond_a_touch_trigger_probe_are_refused_at_their_line() {
    let cases: [(&str, &str, &[&str]); 3] = [
        (
            "repeatability_um = 0.2",
            "repeatability_um = 5000.0",
            &[
                "probe.repeatability_um: 5000: expected 0 … 1000",
                "a millimetre late",
            ],
        ),
        (
            "latency_ms = 0.02",
            "latency_ms = 1e6",
            &["probe.latency_ms: 1000000: expected 0 … 1000"],
        ),
        (
            "feed_mm_per_min = 300.0",
            "feed_mm_per_min = 1e300",
            &["probe.feed_mm_per_min: 1e300: expected 0.1 … 200000"],
        ),
    ];
    for (from, to, expected) in cases {
        let text = bundled_with("headtable5_probe_sphere.toml", from, to);
        refused_at(&text, to, expected);
    }
}

#[test]
fn thermal_set_ups_beyond_a_workshop_are_refused_at_their_line() {
    // The nest's sensors: a displacement sensor noisier than 10 µm.
    let text = bundled_with(
        "vmc3_iso230_3_etve.toml",
        "noise_um = 0.02",
        "noise_um = 50.0",
    );
    refused_at(
        &text,
        "noise_um = 50.0",
        &["iso230_3_etve.nest.noise_um: 50: expected 0 … 10"],
    );
    // The air at its worst: 58.5 °C mean + 1.5 °C daily + 0.2 °C air conditioner = 60.2 °C.
    let text = bundled_with(
        "vmc3_iso230_3_etve.toml",
        "ambient_degc = 20.0",
        "ambient_degc = 58.5",
    );
    refused_at(
        &text,
        "ambient_degc = 58.5",
        &["the air would reach 56.8 … 60.2 °C; expected -10 … 60"],
    );
    // A step that leaves the workshop: 20 + 45 °C.
    let text = bundled_with(
        "vmc3_iso230_3_etve.toml",
        "max_interval_s = 60.0",
        "max_interval_s = 60.0\nsteps = [{ at_min = 60.0, by_degc = 45.0 }]",
    );
    refused_at(
        &text,
        "ambient_degc = 20.0",
        &["the air would reach 18.3 … 66.7 °C"],
    );
    // A thermometer lagging more than a week.
    let text = bundled_with("teach_warmup.toml", "lag_s = 20.0", "lag_s = 1e9");
    refused_at(
        &text,
        "lag_s = 1e9",
        &["thermal.sensors (x_nut).lag_s: 1000000000: expected 0 … 604800 (at most a week)"],
    );
}

#[test]
fn servo_and_error_motion_values_beyond_a_machine_are_refused_at_their_line() {
    let text = bundled_with(
        "teach_squareness_ballbar.toml",
        "X = { kv_per_s = 33.3 }",
        "X = { kv_per_s = 1e6 }",
    );
    refused_at(
        &text,
        "X = { kv_per_s = 1e6 }",
        &["servo.X: kv must be within 1 … 1000 1/s"],
    );
    let cases: [(&str, &str, &[&str]); 3] = [
        (
            "{ amplitude_um = 0.020, per_revolution = 4.6, phase_deg = 30.0 },  # ball pass, outer race",
            "{ amplitude_um = 0.020, per_revolution = 1e7, phase_deg = 30.0 },",
            &["errors.EXS.asynchronous[1].per_revolution: 10000000: expected 0 … 1000"],
        ),
        (
            "{ amplitude_um = 0.040, per_revolution = 0.43, phase_deg = 0.0 },  # cage",
            "{ amplitude_um = 1e5, per_revolution = 0.43, phase_deg = 0.0 },",
            &["errors.EXS.asynchronous[0].amplitude_um: 100000: expected -10000 … 10000"],
        ),
        (
            "bandwidth_hz = 10000.0",
            "bandwidth_hz = 5.0",
            &[
                "spindle.bandwidth_hz: probe \"x1\" filters at 5 Hz, below once per revolution at the fastest speed (10 Hz)",
            ],
        ),
    ];
    for (from, to, expected) in cases {
        let text = bundled_with("teach_spindle.toml", from, to);
        refused_at(&text, to, expected);
    }
    let text = bundled_with(
        "teach_spindle.toml",
        "random = { rms_um = 0.010, band_hz = [50.0, 1000.0] }\n\n[errors.EYS]",
        "random = { rms_um = 0.010, band_hz = [50.0, 1e9] }\n\n[errors.EYS]",
    );
    refused_at(
        &text,
        "band_hz = [50.0, 1e9]",
        &["errors.EXS.random.band_hz: 1000000000: expected 0 … 10000"],
    );
}

#[test]
fn error_terms_beyond_a_machine_are_refused_at_their_line() {
    let text = bundled_with(
        "vmc3_iso230_2.toml",
        "period_mm = 10.0",
        "period_mm = 0.000001",
    );
    refused_at(
        &text,
        "period_mm = 0.000001",
        &["errors.EXX.harmonic[0].period_mm: must be at least 0.001 mm"],
    );
    let cases: [(&str, &[&str]); 3] = [
        (
            "heating = [{ tau_min = 1e9, um = 1.0 }]",
            &["errors.EXX.heating[0].tau_min: 1000000000: expected 0 … 10080 (at most a week) min"],
        ),
        (
            "drift = [{ um_per_h = 1e6 }]",
            &["errors.EXX.drift[0].um_per_h: 1000000: expected -1000 … 1000"],
        ),
        (
            "heating = [{ tau_min = 10.0, um = 1.0, from_min = 1e300 }]",
            &["errors.EXX.heating[0].from_min: 1e300: expected 0 …"],
        ),
    ];
    for (term, expected) in cases {
        refused_at(&exx_with(term), term, expected);
    }
}

#[test]
fn temperature_terms_and_records_beyond_a_workshop_are_refused() {
    let dir = TempDir::new().unwrap();
    write(&dir, "t.csv", "time_min,temp_nut_degc\n0,20.0\n10,20.5\n");
    let with_record = |term: &str| {
        let text = exx_with(term);
        format!("{text}\n[inputs]\ntemperatures = \"t.csv\"\n")
    };
    let load = |text: &str| Scenario::load(write(&dir, "s.toml", text));
    // The reference is checked: a workshop's temperature.
    let good = with_record(
        "temperature = [{ sensor = \"nut\", reference_degc = 20.0, um_per_degc = 2.0 }]",
    );
    load(&good).expect("a valid temperature term");
    let term = "temperature = [{ sensor = \"nut\", reference_degc = 293.15, um_per_degc = 2.0 }]";
    let error = load(&with_record(term)).unwrap_err().to_string();
    assert!(
        error.contains("errors.EXX.temperature[0].reference_degc: 293.15: expected -10 … 60"),
        "{error}"
    );
    let term = "temperature = [{ sensor = \"nut\", reference_degc = 20.0, um_per_degc = 5000.0 }]";
    let error = load(&with_record(term)).unwrap_err().to_string();
    assert!(
        error.contains("errors.EXX.temperature[0].um_per_degc: 5000: expected -1000 … 1000"),
        "{error}"
    );
    // A record in kelvin-times-a-thousand: the thermometer's range, at the row.
    write(&dir, "t.csv", "time_min,temp_nut_degc\n0,20.0\n10,293150\n");
    let error = load(&good).unwrap_err().to_string();
    assert!(error.contains("t.csv:3"), "{error}");
    assert!(error.contains("293150 is beyond ±200"), "{error}");
}

#[test]
fn a_sphere_preset_off_by_millimetres_is_refused_at_its_line() {
    let text = bundled_with(
        "trunnion5_rtest.toml",
        "sphere_diameter_mm = 25.4",
        "sphere_diameter_mm = 25.4\nsphere_setup_um = [5000.0, 0.0, 0.0]",
    );
    refused_at(
        &text,
        "sphere_setup_um = [5000.0, 0.0, 0.0]",
        &[
            "rtest.sphere_setup_um: 5000: expected -1000 … 1000",
            "no preset",
        ],
    );
}

#[test]
fn a_model_larger_than_any_machine_is_refused_as_a_unit_slip() {
    // The X joint's offset written in millimetres (150 for 0.15 m) is fine; 350 000 is not.
    let text = replace_once(
        VMC3,
        r#"<origin xyz="0 0 0.15" rpy="0 0 0"/>"#,
        r#"<origin xyz="0 0 350000" rpy="0 0 0"/>"#,
    );
    let (error, path) = urdf_error(&text);
    assert!(matches!(error.kind(), MachineErrorKind::Implausible { .. }));
    assert_at_joint(&error, &path, &text, "X");
    let message = error.to_string();
    assert!(
        message.contains("joint \"X\" origin: 350000 is beyond ±100 m")
            && message.contains("millimetres"),
        "{message}"
    );
    // Travel in millimetres: 760 m of X.
    let text = replace_once(
        VMC3,
        r#"<limit lower="0" upper="0.76" effort="0" velocity="0.5"/>"#,
        r#"<limit lower="0" upper="760" effort="0" velocity="0.5"/>"#,
    );
    let (error, path) = urdf_error(&text);
    assert_at_joint(&error, &path, &text, "X");
    assert!(
        error
            .to_string()
            .contains("joint \"X\" limit: 760 is beyond ±100 m"),
        "{error}"
    );
    // A body placed a million kilometres away (fuzzing found its collision check never ends).
    let text = replace_once(
        VMC3,
        r#"<visual><origin xyz="0 -0.2 0.35"/>"#,
        r#"<visual><origin xyz="0 -0.2 1e9"/>"#,
    );
    let (error, path) = urdf_error(&text);
    assert_names_file(&error, &path);
    assert!(
        error
            .to_string()
            .contains("<visual>: 1000000000 is beyond ±100 m"),
        "{error}"
    );
}
