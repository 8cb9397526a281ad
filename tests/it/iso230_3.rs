//! ISO 230-3 evaluations against closed forms: the stop criterion of a first-order drift
//! (t > 60 min + τ·ln(1/0.15) = 60 min + 1.897 τ), drift ranges with their sign, and the ETVE
//! window of a record built so that its worst hour is known.

use mtwin::kinds::drift::iso230_3::{drift_ranges, etve, signed_range, stop_time};

/// A record sampled every minute for `minutes`, in seconds.
fn record(minutes: usize, d: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..=minutes)
        .map(|m| (m as f64 * 60.0, d(m as f64 * 60.0)))
        .collect()
}

#[test]
fn a_first_order_drift_may_stop_after_sixty_minutes_plus_1_897_tau() {
    // d = d∞(1 - e^(-t/τ)): |d(t) - d(t - 60)| / d(60) = e^(-(t - 60 min)/τ) < 0.15 once
    // t > 60 min + τ·ln(1/0.15). With τ = 50 min: 154.9 min, i.e. the first minute sample 155.
    let tau = 50.0 * 60.0;
    let drift = record(300, |t| 12e-6 * (1.0 - (-t / tau).exp()));
    let expected_minutes = 60.0 + 50.0 * (1.0f64 / 0.15).ln();
    assert!((expected_minutes - 154.86).abs() < 0.01);
    // The record is checked from two hours on, so the first allowed sample is minute 155.
    assert_eq!(stop_time(&drift), Some(155.0 * 60.0));
    // τ = 120 min: 60 + 227.7 = 287.7 min — within a 300 min record; τ = 200 min: never.
    assert_eq!(
        stop_time(&record(300, |t| 12e-6 * (1.0 - (-t / 7200.0f64).exp()))),
        Some(288.0 * 60.0)
    );
    assert_eq!(
        stop_time(&record(300, |t| 12e-6 * (1.0 - (-t / 12000.0f64).exp()))),
        None
    );
}

#[test]
fn drift_ranges_carry_the_sign_of_the_larger_excursion() {
    // Falls to -61 µm in the first 40 min, recovers to -20 µm by 4 h: the first-hour range is
    // -61 µm (downwards), the whole-test range also -61 µm.
    let drift = record(240, |t| {
        let m = t / 60.0;
        if m <= 40.0 {
            -61e-6 * m / 40.0
        } else {
            -61e-6 + 41e-6 * (m - 40.0) / 200.0
        }
    });
    let (first_hour, whole) = drift_ranges(&drift).unwrap();
    assert!(
        (first_hour + 61e-6).abs() < 1e-12 && (whole + 61e-6).abs() < 1e-12,
        "{first_hour} {whole}"
    );
    // A rise of 5 µm with a 1 µm dip: +6 µm range, positive.
    let up = [(0.0, 0.0), (60.0, -1e-6), (120.0, 5e-6)];
    assert!((signed_range(&up, 0.0, 120.0).unwrap() - 6e-6).abs() < 1e-18);
}

#[test]
fn etve_finds_the_worst_window() {
    // Flat at 0.2 µm, except a ramp of 1.5 µm from 90 to 150 min (the worked example of
    // ISO 230-3 Figure 4, ETVE(X) = 0.0015 mm for a one-hour test, window 90-150 min).
    let drift = record(300, |t| {
        let m = t / 60.0;
        0.2e-6 + 1.5e-6 * ((m - 90.0) / 60.0).clamp(0.0, 1.0)
    });
    let (value, start) = etve(&drift, 3600.0).unwrap();
    assert!((value - 1.5e-6).abs() < 1e-15, "{value}");
    assert_eq!(start, 90.0 * 60.0);
    // A two-hour test sees the same 1.5 µm (no other change), from the first window holding it.
    assert!((etve(&drift, 7200.0).unwrap().0 - 1.5e-6).abs() < 1e-15);
}

#[test]
fn analyze_drift_reproduces_the_iso_230_3_etve_example() {
    // ISO 230-3 Figure 4, as far as its printed values go: ETVE(X; 1,1 °C) = 0,0015 mm in the
    // window 90-150 min and ETVE(A) = 3″ = 14.5 µrad in 110-170 min, for a one-hour test.
    // Built here as ramps in those windows (flat elsewhere), the air rising 1.1 °C over 90-150.
    use mtwin::kinds::drift::DriftTable;
    use mtwin::kinds::drift::iso230_3::drift_report;
    let mut text = String::from("time_min,x1_um,a_urad,temp_air_degc\n");
    for m in (0..=300).step_by(5) {
        let m = m as f64;
        let ramp = |from: f64| ((m - from) / 60.0).clamp(0.0, 1.0);
        text += &format!(
            "{m},{},{},{}\n",
            0.2 + 1.5 * ramp(90.0),
            14.5 * ramp(110.0),
            20.0 + 1.1 * ramp(90.0)
        );
    }
    let table = DriftTable::parse(text.as_bytes(), "etve.csv").unwrap();
    let report = drift_report(&table, 3600.0, None);
    let x = &report["channels"][0];
    assert_eq!(
        (x["name"].as_str(), x["unit"].as_str()),
        (Some("x1"), Some("um"))
    );
    assert!((x["etve_um"].as_f64().unwrap() - 1.5).abs() < 1e-9);
    assert_eq!(x["etve_window_min"], serde_json::json!([90.0, 150.0]));
    assert!((x["etve_ambient_range_degc"].as_f64().unwrap() - 1.1).abs() < 1e-9);
    let a = &report["channels"][1];
    assert!((a["etve_urad"].as_f64().unwrap() - 14.5).abs() < 1e-9 && a["unit"] == "urad");
    assert_eq!(a["etve_window_min"], serde_json::json!([110.0, 170.0]));
}

#[test]
fn drift_tables_name_their_bad_input() {
    use mtwin::kinds::drift::DriftTable;
    for (text, words) in [
        ("x_um\n1\n2\n", "time_min"),
        ("time_min,x\n0,1\n1,2\n", "column `x` has no unit"),
        ("time_min,x_nm\n0,1\n1,2\n", "column `x_nm` is in nm"),
        ("time_min,time_s,x_um\n0,0,1\n1,60,2\n", "two clocks"),
        ("time_min\n0\n1\n", "no displacement column"),
        ("time_min,x_um\n0,1\n0,2\n", "a second reading at 0 min"),
        ("time_min,x_um\n0,1\n1,nan\n", "finite"),
        ("time_min,x_um\n0,1\n", "two rows"),
    ] {
        let error = DriftTable::parse(text.as_bytes(), "d.csv")
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with("d.csv") && error.contains(words),
            "{error} should mention {words}"
        );
    }
}

#[test]
fn etve_covers_the_window_that_ends_at_the_last_sample() {
    // Samples every 7 min from 0 to 98 min, flat but for +10 µm at the last one; a 50 min test.
    // The window 48-98 min (ending at the last sample, starting between samples) holds the
    // step: ETVE = 10 µm.
    let drift: Vec<(f64, f64)> = (0..=14)
        .map(|k| (k as f64 * 420.0, if k == 14 { 10e-6 } else { 0.0 }))
        .collect();
    let (value, start) = etve(&drift, 3000.0).unwrap();
    assert!((value - 10e-6).abs() < 1e-15, "{value}");
    assert!((start - (5880.0 - 3000.0)).abs() < 1e-6, "{start}");
}

#[test]
fn an_oscillation_that_never_settles_never_meets_the_stop_criterion() {
    // ±10 µm with a 60 min period: d(t) = d(t - 60 min) at every t, but within each hour the
    // drift still changes by 20 µm, more than 15 % of the first hour's 10 µm.
    let drift = record(300, |t| 10e-6 * (std::f64::consts::TAU * t / 3600.0).sin());
    assert_eq!(stop_time(&drift), None);
}
