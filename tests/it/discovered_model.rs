//! Discovered models that run (issue 15 item 4): error terms driven by a measured temperature
//! record and by time, checked against their closed forms; the round trip discover →
//! `--write-model` → `mtwin run` → `mtwin compare`; and bad input in the new keys and files.

use mtwin::app::Scenario;
use mtwin::kinds::positioning::{PositioningOptions, PositioningTable, discover_positioning};
use mtwin::machine::{Axis, MachineState};
use std::path::Path;
use std::process::Command;

use crate::common::mtwin;

fn machine_path() -> String {
    format!(
        "{:?}",
        format!("{}/models/vmc3.urdf", env!("CARGO_MANIFEST_DIR"))
    )
}

/// A scenario on vmc3 with `errors` (TOML) and a volumetric map, written into `dir` with a
/// temperature record `record` (CSV) beside it; loaded.
fn load(dir: &Path, record: &str, body: &str) -> Result<Scenario, String> {
    std::fs::write(dir.join("record.csv"), record).unwrap();
    let text = format!(
        "schema = 1\nmachine = {}\nseed = 1\n\n{body}\n\n[volumetric]\nmodel = \"chain\"\n",
        machine_path()
    );
    std::fs::write(dir.join("s.toml"), text).unwrap();
    Scenario::load(dir.join("s.toml")).map_err(|e| e.to_string())
}

/// A record of sensor `nut` rising at 0.1 °C/min from 20 °C for 200 min, sampled every minute.
fn ramp() -> String {
    let rows: String = (0..=200)
        .map(|k| format!("{k},{:.6}\n", 20.0 + 0.1 * k as f64))
        .collect();
    format!("time_min,temp_nut_degc\n{rows}")
}

/// The relative twist of `slot` at X = `x` m and time `t` s.
fn twist(scenario: &Scenario, slot: usize, x: f64, t: f64) -> [f64; 6] {
    let machine = &scenario.twin.machine;
    let mut state = MachineState::at(mtwin::machine::AxisValues::ZERO);
    state.position[Axis::X] = x;
    state.time = t;
    let mut relative = vec![[0.0; 6]; machine.slot_count()];
    let mut line = vec![[0.0; 6]; machine.slot_count()];
    scenario
        .twin
        .errors
        .slot_twists(&state, &mut relative, &mut line);
    relative[slot]
}

#[test]
fn temperature_heating_and_drift_terms_match_their_closed_forms() {
    let dir = tempfile::TempDir::new().unwrap();
    let scenario = load(
        dir.path(),
        &ramp(),
        r#"[inputs]
temperatures = "record.csv"

[errors.EXX]
temperature = [
  { sensor = "nut", reference_degc = 20.0, um_per_m_per_degc = 11.7, lag_min = 5.0 },
  { sensor = "nut", reference_degc = 21.0, um_per_degc = -0.8 },
]
heating = [{ um_per_m = 3.0, tau_min = 30.0, from_min = 10.0 }]
drift = [{ um_per_h = 0.6, from_min = 60.0 }]

[errors.EBX]
temperature = [{ sensor = "nut", reference_degc = 20.0, urad_per_degc = 2.0 }]
"#,
    )
    .unwrap();
    let slot = scenario.twin.machine.axis(Axis::X).unwrap().slot;
    let (x, rate) = (0.4, 0.1 / 60.0); // m, °C/s
    for t in [0.0_f64, 150.0, 600.0, 3000.0, 7230.0] {
        // Hand: a ramp from equilibrium lags by τr(1 − e^(−t/τ)) behind the sensor.
        let tau: f64 = 300.0;
        let sensor = 20.0 + rate * t;
        let lagged = sensor - tau * rate * (1.0 - (-t / tau).exp());
        let expansion = 11.7e-6 * x * (lagged - 20.0);
        let offset = -0.8e-6 * (sensor - 21.0);
        let heating = if t >= 600.0 {
            3.0e-6 * x * (1.0 - (-(t - 600.0) / 1800.0).exp())
        } else {
            0.0
        };
        let drift = 0.6e-6 * (t - 3600.0) / 3600.0;
        let got = twist(&scenario, slot, x, t);
        let want = expansion + offset + heating + drift;
        // The lag follows the record's linear pieces exactly, between samples too: rounding.
        assert!((got[0] - want).abs() < 1e-12, "t {t}: {} vs {want}", got[0]);
        assert!(
            (got[4] - 2.0e-6 * (sensor - 20.0)).abs() < 1e-12,
            "EBX at t {t}"
        );
    }
}

/// A sensor lagging the structure: the term reads `T + τ_s·dT/dt`. On the ramp (0.1 °C/min,
/// sampled every minute) every rate the record gives is 0.1 °C/min exactly (a line's
/// least-squares slope), so 10 min of sensor lag reads the sensor 1 °C ahead; with a 5-min lag
/// of the structure as well, that ramp 1 °C ahead lags by `τr(1 − e^(−t/τ))` as in the test
/// above.
#[test]
fn a_sensor_lag_reads_the_record_ahead_by_its_rate() {
    let dir = tempfile::TempDir::new().unwrap();
    let scenario = load(
        dir.path(),
        &ramp(),
        r#"[inputs]
temperatures = "record.csv"

[errors.EXX]
temperature = [{ sensor = "nut", reference_degc = 20.0, um_per_degc = 1.0, sensor_lag_min = 10.0 }]

[errors.EYX]
temperature = [{ sensor = "nut", reference_degc = 20.0, um_per_degc = 1.0, sensor_lag_min = 10.0, lag_min = 5.0 }]
"#,
    )
    .unwrap();
    let slot = scenario.twin.machine.axis(Axis::X).unwrap().slot;
    let rate = 0.1 / 60.0; // °C/s
    for t in [0.0_f64, 150.0, 600.0, 3000.0, 11_970.0] {
        let ahead = 20.0 + rate * t + 600.0 * rate;
        let tau: f64 = 300.0;
        let lagged = ahead - tau * rate * (1.0 - (-t / tau).exp());
        let got = twist(&scenario, slot, 0.2, t);
        assert!(
            (got[0] - 1e-6 * (ahead - 20.0)).abs() < 1e-12,
            "t {t}: EXX {} vs {}",
            got[0],
            1e-6 * (ahead - 20.0)
        );
        assert!(
            (got[1] - 1e-6 * (lagged - 20.0)).abs() < 1e-12,
            "t {t}: EYX {} vs {}",
            got[1],
            1e-6 * (lagged - 20.0)
        );
    }
    // A negative sensor lag is refused at its key.
    let e = load(
        dir.path(),
        &ramp(),
        "[inputs]\ntemperatures = \"record.csv\"\n\n[errors.EXX]\ntemperature = [{ sensor = \"nut\", reference_degc = 20.0, um_per_degc = 1.0, sensor_lag_min = -3.0 }]",
    )
    .unwrap_err();
    assert!(e.contains("sensor_lag_min: -3: expected 0 … 10080"), "{e}");
}

#[test]
fn bad_context_terms_and_records_are_refused_with_file_line_and_key() {
    let dir = tempfile::TempDir::new().unwrap();
    let with = |record: &str, body: &str| load(dir.path(), record, body).unwrap_err();
    let inputs = "[inputs]\ntemperatures = \"record.csv\"\n\n[errors.EXX]\n";
    // An unknown sensor: the line of `sensor`, the record's sensors listed.
    let e = with(
        &ramp(),
        &format!(
            "{inputs}constant_um = 1.0\ntemperature = [{{ sensor = \"screw\", reference_degc = 20.0, um_per_degc = 1.0 }}]"
        ),
    );
    assert!(
        e.contains("s.toml:10:") && e.contains("\"screw\"") && e.contains("it has nut"),
        "{e}"
    );
    // A temperature term without a record.
    let e = with(
        &ramp(),
        "[errors.EXX]\ntemperature = [{ sensor = \"nut\", reference_degc = 20.0, um_per_degc = 1.0 }]",
    );
    assert!(e.contains("[inputs] temperatures"), "{e}");
    // A rotation's coefficient in µm; two coefficients; per metre on a location error.
    let e = with(
        &ramp(),
        "[inputs]\ntemperatures = \"record.csv\"\n\n[errors.EBX]\ntemperature = [{ sensor = \"nut\", reference_degc = 20.0, um_per_degc = 1.0 }]",
    );
    assert!(e.contains("rotation") && e.contains("urad"), "{e}");
    let e = with(
        &ramp(),
        &format!("{inputs}drift = [{{ um_per_h = 1.0, um_per_m_per_h = 1.0 }}]"),
    );
    assert!(e.contains("not several"), "{e}");
    let e = with(
        &ramp(),
        "[inputs]\ntemperatures = \"record.csv\"\n\n[errors.EC0Y]\nheating = [{ urad_per_m = 1.0, tau_min = 10.0 }]",
    );
    assert!(e.contains("linear axis"), "{e}");
    let e = with(
        &ramp(),
        &format!("{inputs}heating = [{{ um = 1.0, tau_min = 0.0 }}]"),
    );
    assert!(
        e.contains("heating[0].tau_min") && e.contains("positive"),
        "{e}"
    );
    // Records with a gap, times out of order, no temperature column: the record's file and line.
    let e = with(
        "time_min,temp_nut_degc\n0,20\n1,\n",
        &format!("{inputs}drift = [{{ um_per_h = 1.0 }}]"),
    );
    assert!(
        e.contains("record.csv:3:")
            && e.contains("temp_nut_degc")
            && e.contains("inputs.temperatures"),
        "{e}"
    );
    let e = with(
        "time_min,temp_nut_degc\n0,20\n2,20\n1,20\n",
        &format!("{inputs}drift = [{{ um_per_h = 1.0 }}]"),
    );
    assert!(
        e.contains("record.csv:4:") && e.contains("must increase"),
        "{e}"
    );
}

/// The round trip of the issue: the warm-up laser test simulated; discovered (lost motion,
/// the screw's lag behind the sensor, its expansion); the model written and run with the
/// measured temperatures; compared with the original file. The simulation of the written model
/// must equal the discovery's fit at every reading within 0.05 µm RMS (2.5 × the laser's
/// 20 nm noise, which the rerun draws afresh), so `mtwin compare` reports the fit's residual.
#[test]
fn discover_write_run_and_compare_give_back_the_fit() {
    round_trip("vmc3_warmup_laser", "lag_min = ");
}

/// The round trip above with a sensor that lags the screw by 20 min: discovery names
/// `sensor_lag`, the model reads the record ahead by its rate (`sensor_lag_min`), and the
/// rerun reproduces the fit as closely.
#[test]
fn a_sensor_lag_is_written_run_and_compared_as_the_fit() {
    round_trip("vmc3_warmup_sensor_lag", "sensor_lag_min = ");
}

/// Runs the bundled scenario `name`, discovers, writes the model (which must contain
/// `key`), runs it and compares (see the tests above).
fn round_trip(name: &str, key: &str) {
    let dir = tempfile::TempDir::new().unwrap();
    let d = |name: &str| dir.path().join(name).display().to_string();
    let scenario = format!("{}/scenarios/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    mtwin(&["run", &scenario, "--out", &d("measured")]);
    let measured = d("measured/positioning.csv");
    mtwin(&[
        "discover",
        "positioning",
        &measured,
        "--write-model",
        &d("model.toml"),
        "--extends",
        &scenario,
    ]);
    let model = std::fs::read_to_string(d("model.toml")).unwrap();
    for key in ["temperature = [", key, "thermal_network_errors = false"] {
        assert!(model.contains(key), "{key} missing:\n{model}");
    }
    mtwin(&["run", &d("model.toml"), "--out", &d("simulated")]);
    let simulated_path = d("simulated/positioning.csv");

    let table = PositioningTable::read(&measured).unwrap();
    let discovery = discover_positioning(&table, PositioningOptions::default(), |_| {}).unwrap();
    let steps = discovery.residual_steps();
    let residuals = steps.last().unwrap().residuals;
    let simulated = PositioningTable::read(&simulated_path).unwrap();
    assert_eq!(simulated.readings.len(), table.readings.len());
    // The laser zeroes at the first reading of each run (the scenario's `zero`, default
    // `each_run`), so the rerun subtracts the model's value there from every reading of the
    // run: the fit, referenced the same way, is what the rerun must give.
    let fitted: Vec<f64> = table
        .readings
        .iter()
        .zip(residuals)
        .map(|(m, r)| m.deviation - r)
        .collect();
    let zero = |run: usize| fitted[table.readings.iter().position(|m| m.run == run).unwrap()];
    let mut sum = 0.0;
    for ((m, s), f) in table.readings.iter().zip(&simulated.readings).zip(&fitted) {
        assert_eq!((m.run, m.approach, m.target), (s.run, s.approach, s.target));
        sum += (f - zero(m.run) - s.deviation).powi(2);
        // The record replays the measured temperatures in the simulated table.
        assert!((m.temperatures[0] - s.temperatures[0]).abs() < 1e-5);
    }
    let rms_um = (sum / residuals.len() as f64).sqrt() * 1e6;
    let fit_rms_um = discovery.final_score().rms * 1e6;
    println!("simulated − fitted: RMS {rms_um:.4} µm; fit residual RMS {fit_rms_um:.3} µm");
    // What is left is the rerun's own laser noise, at each reading and at the zero reading:
    // 20 nm·√2 ≈ 0.028 µm.
    assert!(rms_um < 0.05, "{rms_um} µm\n{model}");

    let report: serde_json::Value =
        serde_json::from_str(&mtwin(&["compare", &measured, &simulated_path, "--json"])).unwrap();
    let overall = report["overall"]["rms_um"].as_f64().unwrap();
    assert!(
        (overall - fit_rms_um).abs() < 0.05,
        "{overall} vs {fit_rms_um}"
    );
    assert_eq!(report["overall"]["largest_time_difference_s"], 0.0);
    assert_eq!(report["runs"].as_array().unwrap().len(), 7);
}

/// `mtwin compare` on a missing file or a table that is not a positioning table: an error
/// naming the file, a non-zero exit, nothing on standard output.
#[test]
fn compare_refuses_what_it_cannot_read() {
    let dir = tempfile::TempDir::new().unwrap();
    let good = dir.path().join("good.csv");
    std::fs::write(&good, "run,direction,target_mm,deviation_um\n1,+,0,1.0\n").unwrap();
    let other = dir.path().join("other.csv");
    std::fs::write(&other, "time_min,temp_nut_degc\n0,20\n").unwrap();
    let missing = dir.path().join("missing.csv");
    for (a, b, expected) in [
        (&good, &missing, "missing.csv"),
        (&good, &other, "other.csv"),
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_mtwin"))
            .args(["compare"])
            .arg(a)
            .arg(b)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{stderr}");
        assert!(output.stdout.is_empty());
        assert!(stderr.contains(expected), "{stderr}");
    }
}
