//! ISO 230-2:2014 evaluation against figures computed by hand, and the positioning-table
//! reader on hand-written files (any column order, bad input named by line and column).

use mtwin::kinds::positioning::PositioningTable;
use mtwin::kinds::positioning::iso230_2::{Iso230_2Error, evaluate};
use mtwin::program::Approach;

/// 1 pm: the figures are sums and square roots of µm values.
const TOLERANCE_UM: f64 = 1e-6;

fn parse(text: &str) -> PositioningTable {
    PositioningTable::parse(text.as_bytes(), "hand.csv").unwrap()
}

#[track_caller]
fn close(got: Option<f64>, want: f64, what: &str) {
    let got = got.unwrap_or_else(|| panic!("{what}: missing")) * 1e6;
    assert!(
        (got - want).abs() < TOLERANCE_UM,
        "{what}: got {got} µm, want {want} µm"
    );
}

/// 8 irregular targets, 5 bidirectional runs of a linear cycle, columns in an unusual order.
/// At target i the up runs read u_i + k·d_i and the down runs w_i + k·e_i (µm) for
/// k = -2, -1, 0, 1, 2, so x̄↑ = u_i, x̄↓ = w_i and s = d_i·√(10/4) = d_i·√10/2.
fn eight_by_five() -> String {
    let targets = [0.0, 95.2, 193.1, 301.7, 398.4, 512.9, 601.3, 700.0];
    let u = [0.0, 1.2, 2.5, 1.8, -0.6, -1.9, 0.4, 3.1];
    let w = [-2.0, -0.5, 0.3, -0.4, -2.9, -4.0, -1.5, 0.9];
    let d = [0.2, 0.1, 0.3, 0.2, 0.1, 0.2, 0.4, 0.1];
    let e = [0.1, 0.3, 0.2, 0.1, 0.2, 0.1, 0.1, 0.3];
    let mut text = String::from("direction,run,deviation_um,axis,target_mm\n");
    for (j, k) in [-2.0, -1.0, 0.0, 1.0, 2.0].iter().enumerate() {
        for i in 0..8 {
            text += &format!("+,r{},{},X,{}\n", j + 1, u[i] + k * d[i], targets[i]);
        }
        for i in (0..8).rev() {
            text += &format!("-,r{},{},X,{}\n", j + 1, w[i] + k * e[i], targets[i]);
        }
    }
    text
}

#[test]
fn eight_targets_five_bidirectional_runs_match_hand_figures() {
    // By hand (µm), with c = √10 (so 2s = c·d):
    //   Bᵢ = u - w = 2.0 1.7 2.2 2.2 2.3 2.1 1.9 2.2 → B = 2.3, B̄ = 16.6 / 8 = 2.075
    //   E↑ = 3.1 - (-1.9) = 5.0; E↓ = 0.9 - (-4.0) = 4.9; E = 3.1 - (-4.0) = 7.1
    //   x̄ᵢ = -1.0 0.35 1.4 0.7 -1.75 -2.95 -0.55 2.0 → M = 2.0 + 2.95 = 4.95
    //   A↑ = (2.5 + 0.3c) - (-1.9 - 0.2c) = 4.4 + 0.5c; A↓ = (0.9 + 0.3c) - (-4.0 - 0.1c) = 4.9 + 0.4c
    //   A = (2.5 + 0.3c) - (-4.0 - 0.1c) = 6.5 + 0.4c
    //   R↑ = 4·0.4·c/2 = 0.8c; R↓ = 0.6c; R = max(c·(dᵢ + eᵢ) + |Bᵢ|) = 2.2 + 0.5c (at 193.1 mm)
    let table = parse(&eight_by_five());
    assert_eq!(table.runs, ["r1", "r2", "r3", "r4", "r5"]);
    let result = evaluate(&table).unwrap();
    let c = 10f64.sqrt();
    let both = result.both.unwrap();
    let (up, down) = (result.up.unwrap(), result.down.unwrap());
    close(Some(both.reversal), 2.3, "B");
    close(Some(both.mean_reversal), 2.075, "B̄");
    close(Some(up.systematic), 5.0, "E↑");
    close(Some(down.systematic), 4.9, "E↓");
    close(Some(both.systematic), 7.1, "E");
    close(Some(both.mean), 4.95, "M");
    close(Some(up.accuracy), 4.4 + 0.5 * c, "A↑");
    close(Some(down.accuracy), 4.9 + 0.4 * c, "A↓");
    close(Some(both.accuracy), 6.5 + 0.4 * c, "A");
    close(Some(up.repeatability), 0.8 * c, "R↑");
    close(Some(down.repeatability), 0.6 * c, "R↓");
    close(Some(both.repeatability), 2.2 + 0.5 * c, "R");
    // Per target, e.g. the third (193.1 mm): s↑ = 0.3·c/2, Bᵢ = 2.2, Rᵢ = 2.2 + 0.5c.
    let third = &result.targets[2];
    assert!((third.target - 0.1931).abs() < 1e-12);
    assert_eq!((third.up.unwrap().n, third.down.unwrap().n), (5, 5));
    close(third.up.map(|d| d.s), 0.15 * c, "s↑ at 193.1");
    close(third.down.map(|d| d.s), 0.1 * c, "s↓ at 193.1");
    close(third.both.map(|b| b.reversal), 2.2, "B at 193.1");
    close(third.both.map(|b| b.mean), 1.4, "x̄ at 193.1");
    close(
        third.both.map(|b| b.repeatability),
        2.2 + 0.5 * c,
        "R at 193.1",
    );

    // The JSON keys of the issue, in µm.
    let json = result.to_json(&table);
    for key in [
        "E_um",
        "E_up_um",
        "E_down_um",
        "M_um",
        "A_um",
        "A_up_um",
        "A_down_um",
        "R_um",
        "R_up_um",
        "R_down_um",
        "B_um",
        "B_mean_um",
    ] {
        assert!(json[key].is_f64(), "{key} in {json}");
    }
    assert!((json["E_um"].as_f64().unwrap() - 7.1).abs() < TOLERANCE_UM);
    assert_eq!(json["targets"].as_array().unwrap().len(), 8);
    assert_eq!(json["n_runs"], 5);
    assert_eq!(json["axis"], "X");
    assert_eq!(json["bidirectional"], true);
}

#[test]
fn one_direction_gives_unidirectional_figures_and_says_so() {
    // No direction and no run column: four readings per target are runs 1..4.
    //   0 mm:   1 2 3 2   → x̄ = 2,   s = √(2/3)
    //   100 mm: -1 -1 -1 -1 → x̄ = -1, s = 0
    //   250 mm: 4 5 4 5   → x̄ = 4.5, s = √(1/3)
    //   E↑ = 5.5; R↑ = 4√(2/3); A↑ = (4.5 + 2√(1/3)) - (-1 - 0) = 5.5 + 2/√3
    let text = "target_mm,deviation_um\n0,1\n100,-1\n250,4\n0,2\n100,-1\n250,5\n0,3\n100,-1\n250,4\n0,2\n100,-1\n250,5\n";
    let table = parse(text);
    assert_eq!(table.runs.len(), 4);
    let result = evaluate(&table).unwrap();
    let up = result.up.unwrap();
    close(Some(up.systematic), 5.5, "E↑");
    close(Some(up.repeatability), 4.0 * (2.0f64 / 3.0).sqrt(), "R↑");
    close(Some(up.accuracy), 5.5 + 2.0 / 3f64.sqrt(), "A↑");
    assert!(result.down.is_none() && result.both.is_none());
    let json = result.to_json(&table);
    assert!(json["E_um"].is_null() && json["B_um"].is_null() && json["R_down_um"].is_null());
    assert!(
        json["note"].as_str().unwrap().contains("direction only"),
        "{json}"
    );
    assert!(result.to_text(&table).contains("Note:"));
}

#[test]
fn reader_accepts_hand_written_files() {
    // Any column order, spaces around values, a comment line, temperatures and time.
    let text = "# exported by hand\n time_min , temp_nut_degc , deviation_um , target_mm , direction , run , temp_air_degc\n\
                0.5, 21.0, 1.5, 10, +, cold, 20.1\n\
                1.0, 21.1, -0.5, 10, -, cold, 20.1\n";
    let table = parse(text);
    assert_eq!(table.sensors, ["nut", "air"]);
    assert_eq!(table.runs, ["cold"]);
    assert!(table.has_direction && table.axis.is_none());
    let second = &table.readings[1];
    assert_eq!(second.approach, Approach::Down);
    assert!((second.target - 0.010).abs() < 1e-15 && (second.deviation + 0.5e-6).abs() < 1e-18);
    assert_eq!(second.time, Some(60.0));
    assert_eq!(second.temperatures, [21.1, 20.1]);
}

#[test]
fn reader_names_the_line_and_column_of_bad_input() {
    let cases = [
        ("deviation_um\n1.0\n", Some(1), "target_mm"), // missing required column
        (
            "target_mm,deviation_um,Time (min)\n0,1,2\n",
            Some(1),
            "column `Time (min)`: this reader reads `time_min`",
        ), // a known column spelt another way (an unknown one is read past)
        (
            "target_mm,deviation_um\n0,1\n10,nan\n",
            Some(3),
            "deviation_um",
        ), // not finite
        ("target_mm,deviation_um\n0,abc\n", Some(2), "deviation_um"), // not a number
        (
            "target_mm,deviation_um,direction\n0,1,up\n",
            Some(2),
            "direction",
        ),
        (
            "target_mm,deviation_um,axis\n0,1,X\n10,1,Y\n",
            Some(3),
            "axis",
        ), // two axes
        ("target_mm,deviation_um\n0,1,2\n", Some(2), "CSV"), // ragged row
        ("target_mm,deviation_um\n", None, "no readings"),
    ];
    for (text, line, words) in cases {
        let error = PositioningTable::parse(text.as_bytes(), "bad.csv").unwrap_err();
        let message = error.to_string();
        assert_eq!(error.line(), line, "{message}");
        assert!(message.starts_with("bad.csv"), "{message}");
        assert!(message.contains(words), "{message} should mention {words}");
    }
}

#[test]
fn evaluation_refuses_what_it_cannot_evaluate() {
    let one_target = parse("target_mm,deviation_um\n5,1\n5,2\n");
    assert_eq!(evaluate(&one_target), Err(Iso230_2Error::TooFewTargets(1)));
    let one_run = parse("target_mm,deviation_um\n5,1\n10,2\n");
    assert!(matches!(
        evaluate(&one_run),
        Err(Iso230_2Error::TooFewRuns { n: 1, .. })
    ));
    let lopsided =
        parse("target_mm,deviation_um,direction\n0,1,+\n0,1,+\n0,1,-\n0,1,-\n10,1,+\n10,2,+\n");
    assert!(matches!(
        evaluate(&lopsided),
        Err(Iso230_2Error::MissingDirection { .. })
    ));
}

#[test]
fn analyze_command_prints_the_report_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.csv");
    std::fs::write(&path, eight_by_five()).unwrap();
    let run = |json: bool| {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_mtwin"));
        command.args(["analyze", "positioning"]).arg(&path);
        if json {
            command.arg("--json");
        }
        command.output().unwrap()
    };
    let text = run(false);
    assert!(text.status.success());
    assert!(String::from_utf8_lossy(&text.stdout).contains("reversal value B (µm)"));
    let json = run(true);
    let value: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert!((value["B_um"].as_f64().unwrap() - 2.3).abs() < TOLERANCE_UM);
    // Bad input: non-zero exit, the file named.
    std::fs::write(&path, "target_mm\n1\n").unwrap();
    let bad = run(true);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("x.csv"));
}

#[test]
fn thermal_series_reports_each_run_and_the_drift_of_every_target() {
    // Three runs at nut temperatures 22, 24, 26 °C (times 0, 60, 120 min); the axis expands by
    // 11.7 µm/m/°C from its origin: deviation = 2 + 0.0117·x_mm·(T - 22) µm. By hand: the drift
    // at 600 mm in the last run is 0.0117·600·4 = 28.08 µm, its slope 7.02 µm/°C, and the
    // target at 0 mm does not drift.
    let mut text = String::from("run,time_min,temp_nut_degc,target_mm,deviation_um\n");
    for (run, (time, temp)) in [(0.0, 22.0), (60.0, 24.0), (120.0, 26.0)]
        .iter()
        .enumerate()
    {
        for x in [0.0, 300.0, 600.0] {
            let deviation = 2.0 + 0.0117 * x * (temp - 22.0);
            text += &format!("warm{run},{time},{temp},{x},{deviation}\n");
        }
    }
    let table = parse(&text);
    let json = evaluate(&table).unwrap().to_json(&table);
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 3);
    assert_eq!(runs[2]["run"], "warm2");
    assert_eq!(runs[2]["time_min"], 120.0);
    assert_eq!(runs[2]["temperatures_degc"]["nut"], 26.0);
    let drift = json["drift"].as_array().unwrap();
    let at = |x: f64| drift.iter().find(|d| d["target_mm"] == x).unwrap();
    assert!((at(600.0)["range_um"].as_f64().unwrap() - 28.08).abs() < TOLERANCE_UM);
    assert!((at(600.0)["values"][2]["drift_um"].as_f64().unwrap() - 28.08).abs() < TOLERANCE_UM);
    assert!((at(600.0)["slope_um_per_degc"]["nut"].as_f64().unwrap() - 7.02).abs() < TOLERANCE_UM);
    assert!((at(300.0)["slope_um_per_degc"]["nut"].as_f64().unwrap() - 3.51).abs() < TOLERANCE_UM);
    assert_eq!(at(0.0)["range_um"], 0.0);
    // Not a thermal series without time or temperature: no `runs`, no `drift`.
    let plain = parse(&eight_by_five());
    assert!(
        evaluate(&plain)
            .unwrap()
            .to_json(&plain)
            .get("runs")
            .is_none()
    );
}

#[test]
fn bidirectional_repeatability_takes_the_unidirectional_one_when_larger() {
    // At 0 mm: up -2 -1 0 1 2 µm (s↑ = √2.5, R↑ᵢ = 4√2.5 = 6.325), down 0 0 0 0 0 (s↓ = 0),
    // Bᵢ = 0, so 2s↑ + 2s↓ + |Bᵢ| = 2√2.5 = 3.162 < R↑ᵢ: Rᵢ = R↑ᵢ. At 100 mm all zero. R = 6.325.
    let mut text = String::from("target_mm,deviation_um,direction,run\n");
    for (run, up) in [-2.0, -1.0, 0.0, 1.0, 2.0].iter().enumerate() {
        text += &format!("0,{up},+,{run}\n100,0,+,{run}\n100,0,-,{run}\n0,0,-,{run}\n");
    }
    let result = evaluate(&parse(&text)).unwrap();
    let r = 4.0 * 2.5f64.sqrt();
    close(
        result.targets[0].both.map(|b| b.repeatability),
        r,
        "Rᵢ at 0 mm",
    );
    close(result.both.map(|b| b.repeatability), r, "R");
}

#[test]
fn a_run_reading_a_target_twice_the_same_way_is_refused() {
    let text = "target_mm,deviation_um,run\n0,1,a\n0,2,a\n10,1,a\n0,1,b\n10,1,b\n";
    assert!(matches!(
        evaluate(&parse(text)),
        Err(Iso230_2Error::RepeatedReading { .. })
    ));
    let duplicate = PositioningTable::parse(
        b"target_mm,deviation_um,temp_a_degc,temp_a_degc\n0,1,20,20\n",
        "d.csv",
    );
    assert!(duplicate.unwrap_err().to_string().contains("twice"));
}
