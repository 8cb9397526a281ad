//! The drift report, determinism and refused sections.

use super::*;

#[test]
fn analyze_drift_reports_the_tables_own_ranges_and_stop_criterion() {
    let twin = twin();
    let (test, setup) = bundled(&twin.machine);
    let run = spindle_test::simulate(&twin, &test, &setup, 1);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("drift.csv");
    let mut bytes = Vec::new();
    run.table.write_csv(&mut bytes).unwrap();
    std::fs::write(&path, &bytes).unwrap();
    // `mtwin analyze drift FILE --json`, through the verb the command line runs.
    let verb = mtwin::kinds::drift::cli::KIND.analyze.unwrap();
    let path_text = path.to_str().unwrap();
    let matches = (verb.command)().get_matches_from(["drift", path_text, "--json"]);
    let printed = (verb.run)(&matches, &mut |_| {}, &mtwin::app::ScenarioFiles).unwrap();
    let report: serde_json::Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(report["kind"], "drift");
    assert_eq!(report["test"], "iso230_3_spindle");
    assert_eq!(report["ambient_sensor"], "air");
    assert_eq!(report["spacing_mm"], 150.0);
    // Every key the twin wrote is read and said again; none is left unused.
    let said = &report["conditions"];
    assert_eq!(said["control"], "hold");
    assert_eq!(said["hold_mm"], "x 380, y 205, z 260");
    assert_eq!(said["programme"], "constant");
    assert_eq!(said["speed_rpm"], 6000.0);
    assert_eq!(said["run_min"], 240.0);
    assert_eq!(said["stop_min"], 60.0);
    assert_eq!(report["preamble_not_used"], serde_json::json!([]));
    assert_eq!(report["cautions"], serde_json::json!([]));
    // The file by hand: its conditions and its columns.
    let text = String::from_utf8(bytes).unwrap();
    let Csv {
        names,
        columns,
        preamble,
    } = csv_columns(&text);
    let said = |key: &str| {
        preamble
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    };
    assert_eq!(said("test"), Some("iso230_3_spindle"));
    assert_eq!(said("programme"), Some("constant"));
    assert_eq!(said("speed_rpm"), Some("6000"));
    assert_eq!(said("run_min"), Some("240"));
    assert_eq!(said("stop_min"), Some("60"));
    assert_eq!(said("control"), Some("hold"));
    assert_eq!(said("hold_mm"), Some("x 380, y 205, z 260"));
    assert_eq!(
        names,
        [
            "time_min",
            "x1_um",
            "y1_um",
            "x2_um",
            "y2_um",
            "z_um",
            "temp_air_degc",
            "temp_bearing_degc",
            "temp_spindle_degc"
        ]
    );
    let column = |name: &str| &columns[names.iter().position(|n| n == name).unwrap()];
    let times = column("time_min");
    let l_mm = 150.0;
    let mut series: Vec<(String, Vec<f64>)> = ["x1", "y1", "x2", "y2", "z"]
        .iter()
        .map(|n| (n.to_string(), column(&format!("{n}_um")).clone()))
        .collect();
    // The tilts from the pairs (µm / mm = mrad → ×1000 µrad): A = (Y1 − Y2)/l, B = (X2 − X1)/l.
    let pair = |p: &str, q: &str| -> Vec<f64> {
        column(p)
            .iter()
            .zip(column(q))
            .map(|(a, b)| (a - b) / l_mm * 1e3)
            .collect()
    };
    series.push(("a".into(), pair("y1_um", "y2_um")));
    series.push(("b".into(), pair("x2_um", "x1_um")));
    let entries = report["channels"].as_array().unwrap();
    assert_eq!(entries.len(), 7);
    for (name, values) in &series {
        let entry = entries.iter().find(|c| c["name"] == name.as_str()).unwrap();
        let unit = entry["unit"].as_str().unwrap();
        let first = signed(times, values, 60.0);
        let whole = signed(times, values, f64::INFINITY);
        // The report rounds to 1e-6 of its unit; the tilts come from CSV values rounded to 1 pm.
        let close = |reported: &serde_json::Value, mine: f64| {
            (reported.as_f64().unwrap() - mine).abs() <= 2e-6
        };
        assert!(
            close(&entry[format!("range_60_{unit}")], first),
            "{name}: {} vs {first}",
            entry[format!("range_60_{unit}")]
        );
        assert!(
            close(&entry[format!("range_{unit}")], whole),
            "{name}: {} vs {whole}",
            entry[format!("range_{unit}")]
        );
        // d(·)_t over the running period the preamble states (run_min = 240), not the record.
        let running = signed(times, values, 240.0);
        assert!(
            close(&entry[format!("range_run_{unit}")], running),
            "{name}: {} vs {running}",
            entry[format!("range_run_{unit}")]
        );
        // The 15 % rule (ISO 230-3 §6.2) by brute force: the first reading at or after 120 min
        // whose last 60 min (readings on the minute grid, so t − 60 min is a reading) vary less
        // than 15 % of the largest |d − d(0)| in the first hour.
        let first_hour = times
            .iter()
            .zip(values)
            .filter(|(t, _)| **t <= 60.0)
            .map(|(_, v)| (v - values[0]).abs())
            .fold(0.0, f64::max);
        let stop = times
            .iter()
            .enumerate()
            .filter(|(_, t)| **t >= 120.0 - 1e-9)
            .find_map(|(k, t)| {
                let window: Vec<f64> = (0..=k)
                    .filter(|&j| times[j] >= t - 60.0 - 1e-9)
                    .map(|j| values[j])
                    .collect();
                let lo = window.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = window.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                (hi - lo < 0.15 * first_hour).then_some(*t)
            });
        match (entry["stop_min"].as_f64(), stop) {
            (Some(reported), Some(mine)) => assert!(
                (reported - mine).abs() < 1e-6,
                "{name}: stop {reported} vs {mine}"
            ),
            (None, None) => {}
            other => panic!("{name}: stop criterion {other:?}"),
        }
    }
    // The Z drift meets the criterion while the spindle runs: the housing settles within the
    // 4 h (slow time constant about half an hour), so the standard would let it stop early.
    let z = entries.iter().find(|c| c["name"] == "z").unwrap();
    let z_stop = z["stop_min"].as_f64().unwrap();
    assert!((120.0..240.0).contains(&z_stop), "Z stop {z_stop} min");
    // The spindle pushes the tool down: negative Z drift, several micrometres.
    assert!(z["range_um"].as_f64().unwrap() < -1.0, "{z}");
    // truth.json's running-period range (Table 1's d(ZOC)_t) against the noise-free channel,
    // and the measured table within the nest's noise of it.
    let truth = spindle_test::truth(&test, &run);
    let z_truth = truth["true_channels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "z")
        .unwrap();
    let true_z = channel(&run, "z", true);
    let true_minutes: Vec<f64> = run.table.times.iter().map(|t| t / 60.0).collect();
    let running = signed(&true_minutes, true_z, 240.0) * 1e6;
    assert!((z_truth["range_run_um"].as_f64().unwrap() - running).abs() < 1e-9);
    // A noisy range differs from the true one by at most twice the largest noise value plus a
    // resolution step: 4.5 σ over the 1 505 nest draws.
    let (sigma_um, step_um) = (test.nest.noise * 1e6, test.nest.resolution * 1e6);
    let bound = 2.0 * 4.5 * sigma_um + step_um;
    for key in ["range_60_um", "range_um"] {
        let (measured, truth) = (z[key].as_f64().unwrap(), z_truth[key].as_f64().unwrap());
        assert!(
            (measured - truth).abs() <= bound,
            "Z {key}: {measured} µm, true {truth} µm ± {bound}"
        );
    }
    // The tilt A (the column's, about X) the same way: a pair's difference has √2 σ, over l.
    let a = entries.iter().find(|c| c["name"] == "a").unwrap();
    let a_truth = truth["true_channels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "a")
        .unwrap();
    let tilt_bound = (2.0 * 4.5 * 2f64.sqrt() * sigma_um + 2.0 * step_um) / l_mm * 1e3;
    let (measured, true_a) = (
        a["range_urad"].as_f64().unwrap(),
        a_truth["range_urad"].as_f64().unwrap(),
    );
    assert!(
        (measured - true_a).abs() <= tilt_bound,
        "A: {measured} µrad, true {true_a} µrad ± {tilt_bound}"
    );
    assert!(
        true_a > 2.0 * tilt_bound,
        "A {true_a} µrad is above the pair noise {tilt_bound}"
    );
    assert_eq!(truth["speed_rpm_at_readings"][0], 0.0);
    assert_eq!(truth["speed_rpm_at_readings"][240], 6000.0);
    assert_eq!(truth["speed_rpm_at_readings"][241], 0.0);
    // The text report for people has the stop column (the ETVE's does not).
    let matches = (verb.command)().get_matches_from(["drift", path_text]);
    let people = (verb.run)(&matches, &mut |_| {}, &mtwin::app::ScenarioFiles).unwrap();
    assert!(people.contains("stop min"), "{people}");
    // The table reads back whole.
    let back = DriftTable::read(&path).unwrap();
    assert_eq!(back.conditions.test.as_deref(), Some("iso230_3_spindle"));
    println!("{}\n{people}", run.summary());
}

#[test]
fn the_same_seed_gives_the_same_bytes_and_another_seed_other_noise() {
    let twin = twin();
    let (test, setup) = bundled(&twin.machine);
    let bytes = |seed: u64| {
        let run = spindle_test::simulate(&twin, &test, &setup, seed);
        let mut out = Vec::new();
        run.table.write_csv(&mut out).unwrap();
        let truth = serde_json::to_vec(&spindle_test::truth(&test, &run)).unwrap();
        (out, truth, run.true_channels)
    };
    let (a, truth_a, true_a) = bytes(1);
    let (b, truth_b, true_b) = bytes(1);
    assert!(a == b && truth_a == truth_b, "same seed, different bytes");
    let (c, _, true_c) = bytes(2);
    assert_ne!(a, c, "another seed draws other noise");
    // The truth does not depend on the seed.
    assert_eq!(true_a, true_b);
    assert_eq!(true_a, true_c);
    // Parsing the same text twice gives the same test.
    let (again, _) = bundled(&twin.machine);
    assert_eq!(test, again);
}

#[test]
fn bad_sections_are_refused_with_the_key_and_line() {
    let twin = twin();
    let constant = "constant = { speed_rpm = 6000.0, run_min = 240.0, stop_min = 60.0 }\n";
    // The section's header is line 8 of `with_section`'s text, its first key line 9.
    let cases: Vec<(String, &str, usize)> = vec![
        (
            format!("{HOLD}{NEST}"),
            "iso230_3_spindle.constant or spectrum: give the spindle speed programme",
            8,
        ),
        (
            format!("{HOLD}constant = {{ speed_rpm = -5.0 }}\n{NEST}"),
            "iso230_3_spindle.constant.speed_rpm: -5 rpm; expected a spindle speed above 0",
            10,
        ),
        (
            format!("{HOLD}constant = {{ speed_rpm = 0.0 }}\n{NEST}"),
            "constant.speed_rpm: 0 rpm",
            10,
        ),
        (
            format!("{HOLD}constant = {{ speed_rpm = 6000.0, run_min = 0.0 }}\n{NEST}"),
            "iso230_3_spindle.constant.run_min: 0 min; expected more than 0",
            10,
        ),
        (
            format!("{HOLD}constant = {{ speed_rpm = 6000.0, stop_min = 30.0 }}\n{NEST}"),
            "iso230_3_spindle.constant.stop_min: 30 min; ISO 230-3 §6.2 stops the spindle for at least 1 h",
            10,
        ),
        (
            format!("{HOLD}{constant}stop_min = 60.0\n{NEST}"),
            "iso230_3_spindle.stop_min: with constant, give the stop inside it",
            11,
        ),
        (
            format!(
                "{HOLD}{constant}spectrum = [{{ speed_rpm = 1.0, duration_min = 1.0 }}]\n{NEST}"
            ),
            "iso230_3_spindle.spectrum: give constant or spectrum, not both",
            11,
        ),
        (
            format!("{HOLD}spectrum = []\n{NEST}"),
            "iso230_3_spindle.spectrum: empty",
            10,
        ),
        (
            format!(
                "{HOLD}spectrum = [\n  {{ speed_rpm = 3000.0, duration_min = 20.0 }},\n  {{ speed_rpm = 0.0, duration_min = 0.0 }},\n]\n{NEST}"
            ),
            "iso230_3_spindle.spectrum[1].duration_min: 0 min; expected more than 0",
            12,
        ),
        (
            format!(
                "{HOLD}spectrum = [\n  {{ speed_rpm = 3000.0, duration_min = 20.0 }},\n  {{ speed_rpm = -1.0, duration_min = 5.0 }},\n]\n{NEST}"
            ),
            "iso230_3_spindle.spectrum[1].speed_rpm: -1 rpm; expected 0 (a stop)",
            12,
        ),
        (
            format!("{HOLD}spectrum = [{{ speed_rpm = 0.0, duration_min = 5.0 }}]\n{NEST}"),
            "spectrum: every step is a stop",
            10,
        ),
        (
            format!(
                "{HOLD}spectrum = [{{ speed_rpm = 100.0, duration_min = 5.0 }}]\nstop_min = 59.0\n{NEST}"
            ),
            "iso230_3_spindle.stop_min: 59 min; ISO 230-3 §6.2",
            11,
        ),
        (
            format!("{HOLD}{constant}sample_min = 6.0\n{NEST}"),
            "iso230_3_spindle.sample_min: 6 min; ISO 230-3 §6.2 asks for a reading at least every 5 min",
            11,
        ),
        (
            format!("hold_mm = {{ x = 900.0 }}\n{constant}{NEST}"),
            "iso230_3_spindle.hold_mm.x: 900 mm is outside the travel of X",
            9,
        ),
        (
            format!("hold_mm = {{ q = 1.0 }}\n{constant}{NEST}"),
            "iso230_3_spindle.hold_mm.q: expected x, y or z",
            9,
        ),
        (
            format!("{HOLD}{constant}nest = {{ first_mm = 20.0, spacing_mm = 0.0 }}\n"),
            "iso230_3_spindle.nest.spacing_mm: 0: expected 1 … 1000 (a test mandrel is at most a metre long)",
            11,
        ),
        (
            format!("{HOLD}{constant}{NEST}air = {{ noise_degc = -1.0 }}\n"),
            "iso230_3_spindle.air.noise_degc: -1: expected 0 … 5",
            12,
        ),
    ];
    for (section, message, line) in cases {
        let error = spindle_test::parse_sections("t.toml", &with_section(&section), &twin.machine)
            .unwrap_err();
        let text = error.to_string();
        assert!(
            text.contains(message),
            "{section}\n→ {text}\n(expected {message})"
        );
        assert_eq!(error.line(), Some(line), "{section}\n→ {text}");
        assert!(text.starts_with(&format!("t.toml:{line}: ")), "{text}");
    }
    // A type error and an unknown key: TOML's own message, at the line.
    let error = spindle_test::parse_sections(
        "t.toml",
        &with_section(&format!(
            "{HOLD}constant = {{ speed_rpm = \"fast\" }}\n{NEST}"
        )),
        &twin.machine,
    )
    .unwrap_err();
    assert_eq!(error.line(), Some(10), "{error}");
    let error = spindle_test::parse_sections(
        "t.toml",
        &with_section(&format!("{HOLD}{constant}{NEST}speed = 3\n")),
        &twin.machine,
    )
    .unwrap_err();
    assert!(
        error.to_string().contains("unknown field `speed`"),
        "{error}"
    );
    assert_eq!(error.line(), Some(12), "{error}");
    // No [thermal]: the test has nothing to run through.
    let text = format!("schema = 1\nseed = 1\n\n[iso230_3_spindle]\n{HOLD}{constant}{NEST}");
    let error = spindle_test::parse_sections("t.toml", &text, &twin.machine).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("iso230_3_spindle is a thermal test: add a [thermal] section"),
        "{error}"
    );
    assert_eq!(error.line(), Some(4));
    // A [thermal] sensor named like the ambient thermometer.
    let text = format!(
        "schema = 1\n\n[thermal]\nsensors = [{{ node = \"spindle_housing\", name = \"air\" }}]\n\n[iso230_3_spindle]\n{HOLD}{constant}{NEST}"
    );
    let error = spindle_test::parse_sections("t.toml", &text, &twin.machine).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("the name of the spindle test's ambient thermometer"),
        "{error}"
    );
    // Without the section: nothing, and no error.
    let text = "schema = 1\n\n[thermal]\nambient_degc = 20.0\n";
    assert!(
        spindle_test::parse_sections("t.toml", text, &twin.machine)
            .unwrap()
            .is_none()
    );
}
