//! Tables whose own data contradict counting them as given: `identify` refuses to write
//! compensation from them, naming the file and what the data show.

use super::{failed, mtwin, ok, refused_by_the_door, refused_by_the_reader, root, run_into};
use std::ffi::OsStr;

#[test]
fn a_sphere_a_few_micrometres_off_or_a_test_pasted_twice_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(&root("scenarios/trunnion5_rtest.toml"), dir.path(), "run");
    let clean = std::fs::read_to_string(run.join("rtest.csv")).unwrap();
    let machine = root("models/trunnion5.urdf");
    let identify = |table: &OsStr, name: &str, expected: &[&str], by_door: bool| {
        let args: [&OsStr; 5] = [
            "--machine".as_ref(),
            machine.as_os_str(),
            "--params".as_ref(),
            "location".as_ref(),
            table,
        ];
        let out = dir.path().join(name);
        if by_door {
            refused_by_the_door(&args, &out, expected, "contradict counting them");
        } else {
            refused_by_the_reader(&args, &out, expected);
        }
    };
    // The preamble's sphere 30 µm off in X: far inside the 0.1 mm a controller's own
    // kinematics may put the tip off the sphere, but the same 30 µm at every pose (a
    // controller's parameters would turn with the axes). Fitted, it read as EX0C ≈ 30 µm off
    // the truth.
    let line = "# sphere_mm = 100 0 250";
    assert!(clean.contains(line), "the preamble's sphere line");
    let typo = dir.path().join("typo.csv");
    std::fs::write(&typo, clean.replacen(line, "# sphere_mm = 100.03 0 250", 1)).unwrap();
    identify(
        typo.as_os_str(),
        "typo",
        &[
            "typo.csv",
            "30 µm from the stated sphere at 100.03 0 250 mm",
            "mistyped",
        ],
        false,
    );
    // The first test exported again under another name: its readings, noise included,
    // repeat reading for reading, which no nest does twice.
    let first = clean
        .lines()
        .find(|l| !l.starts_with('#') && !l.starts_with("test,"))
        .and_then(|l| l.split(',').next())
        .unwrap()
        .to_string();
    let again: String = clean
        .lines()
        .filter(|l| l.starts_with(&format!("{first},")))
        .map(|l| format!("{first} again{}\n", &l[first.len()..]))
        .collect();
    let pasted = dir.path().join("pasted.csv");
    std::fs::write(&pasted, clean.clone() + &again).unwrap();
    identify(
        pasted.as_os_str(),
        "pasted",
        &[
            "pasted.csv",
            &format!("test \"{first} again\" holds the same"),
            &format!("as test \"{first}\""),
        ],
        true,
    );
    // The clean table passes.
    ok(&mtwin(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        machine.as_os_str(),
        "--params".as_ref(),
        "location".as_ref(),
        run.join("rtest.csv").as_os_str(),
    ]));
}

#[test]
fn a_ball_bar_of_one_sense_a_mistyped_radius_or_whole_micrometres_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("bar.toml");
    std::fs::write(
        &scenario,
        format!(
            "schema = 1\nmachine = \"{}\"\nseed = 3\n[errors.EC0Y]\nconstant_urad = -20.0\n\
             [ballbar]\nplanes = [\"XY\"]\nlength_mm = 150.0\nfeed_mm_per_min = 500.0\n\
             centre_mm = {{ x = 380.0, y = 205.0, z = 300.0 }}\nnoise_um = 0.1\nresolution_um = 0.1\n",
            root("models/vmc3.urdf").display()
        ),
    )
    .unwrap();
    let run = run_into(&scenario, dir.path(), "run");
    let table = run.join("ballbar_xy.csv");
    let machine = root("models/vmc3.urdf");
    let identify = |table: &OsStr| {
        mtwin(&[
            "identify".as_ref(),
            "--machine".as_ref(),
            machine.as_os_str(),
            "--params".as_ref(),
            "EC0Y".as_ref(),
            table,
        ])
    };
    ok(&identify(table.as_os_str()));
    // The counter-clockwise sense alone: a servo mismatch Δτ has the shape of a squareness
    // there, v·Δτ/R = (500/60 mm/s · 1 ms)/150 mm = 55.6 µm/m per millisecond, unknowable
    // from one sense.
    let text = std::fs::read_to_string(&table).unwrap();
    let ccw: String = text
        .lines()
        .filter(|l| !l.starts_with("cw,"))
        .map(|l| format!("{l}\n"))
        .collect();
    let one = dir.path().join("ccw_only.csv");
    std::fs::write(&one, ccw).unwrap();
    let message = failed(&identify(one.as_os_str()));
    for expected in [
        "ccw_only.csv",
        "only the ccw sense",
        "55.6 µm/m",
        "fail their own checks, so no fit is made",
        "a ball-bar's other sense",
    ] {
        assert!(
            message.contains(expected),
            "should name {expected}: {message}"
        );
    }
    // The preamble's radius typed 100 for 150: the angles against time_s turn at
    // (500/60)/150 = 0.0556 rad/s, not the 0.0833 the preamble's 500 mm/min on 100 mm says.
    let line = "# radius_mm = 150";
    assert!(text.contains(line), "the preamble's radius");
    let typo = dir.path().join("radius.csv");
    std::fs::write(&typo, text.replacen(line, "# radius_mm = 100", 1)).unwrap();
    let message = failed(&identify(typo.as_os_str()));
    for expected in [
        "radius.csv",
        "turn at 0.0556 rad/s",
        "says 0.0833 rad/s",
        "mistyped",
    ] {
        assert!(
            message.contains(expected),
            "should name {expected}: {message}"
        );
    }
    // Exported rounded to whole µm: the rounding (1/√12 = 0.289 µm) is three times the bar's
    // stated 0.104 µm and does not average out along the trace.
    let rounded = dir.path().join("rounded.csv");
    std::fs::write(
        &rounded,
        super::with_column(&text, "deviation_um", f64::round),
    )
    .unwrap();
    let message = failed(&identify(rounded.as_os_str()));
    for expected in [
        "rounded.csv",
        "whole multiple of 1 µm",
        "(0.289 µm) exceeds",
        "(0.104 µm)",
    ] {
        assert!(
            message.contains(expected),
            "should name {expected}: {message}"
        );
    }
}

#[test]
fn a_laser_table_in_inches_is_refused_for_covering_a_sliver_of_its_axis() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(&root("scenarios/vmc3_iso230_2.toml"), dir.path(), "run");
    let text = std::fs::read_to_string(run.join("positioning.csv")).unwrap();
    // An export in inch mode: the targets (and the preamble's list of them) in inches in the
    // mm columns. 10 … 750 mm read 0.3937 … 29.5276: 29.134 mm of X's 760 mm of travel, so a
    // compensation would be extrapolated over 96 % of the axis.
    let inches = |v: f64| v / 25.4;
    let mut converted = String::new();
    for line in super::with_column(&text, "target_mm", inches).lines() {
        match line.strip_prefix("# targets_mm = ") {
            Some(list) => {
                let list: Vec<String> = list
                    .split(',')
                    .map(|t| format!("{}", inches(t.trim().parse::<f64>().unwrap())))
                    .collect();
                converted += &format!("# targets_mm = {}\n", list.join(", "));
            }
            None => converted += &format!("{line}\n"),
        }
    }
    let table = dir.path().join("inch.csv");
    std::fs::write(&table, converted).unwrap();
    let machine = root("models/vmc3.urdf");
    refused_by_the_door(
        &[
            "--machine".as_ref(),
            machine.as_os_str(),
            "--params".as_ref(),
            "EXX:2".as_ref(),
            table.as_os_str(),
        ],
        &dir.path().join("id"),
        &[
            "inch.csv",
            "the targets cover 29.134 mm of X's 760 mm of travel",
            "inches or metres in the mm column?",
        ],
        "correct the column's unit",
    );
}

#[test]
fn one_sphere_centre_off_is_named_and_laser_readings_below_their_noise_are_cautioned() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(
        &root("scenarios/trunnion5_probe_sphere.toml"),
        dir.path(),
        "run",
    );
    let clean = std::fs::read_to_string(run.join("spheres.csv")).unwrap();
    let machine = root("models/trunnion5.urdf");
    // The stylus re-qualified before the sixth sphere: its centre 20 µm high, the others as
    // measured (0.5 µm each). Birge scaling would spread it over every estimate as noise;
    // without it χ² falls back to its noise's.
    let mut row = 0;
    let moved: String = clean
        .lines()
        .map(|line| {
            let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
            if fields.get(1).is_some_and(|k| k == "sphere") {
                row += 1;
                if row == 6 {
                    fields[7] = format!("{:.6}", fields[7].parse::<f64>().unwrap() + 0.020);
                }
            }
            fields.join(",") + "\n"
        })
        .collect();
    assert_eq!(
        row,
        clean.lines().filter(|l| l.contains(",sphere,")).count()
    );
    let table = dir.path().join("moved.csv");
    std::fs::write(&table, moved).unwrap();
    let args: [&OsStr; 5] = [
        "--machine".as_ref(),
        machine.as_os_str(),
        "--params".as_ref(),
        "location".as_ref(),
        table.as_os_str(),
    ];
    refused_by_the_door(
        &args,
        &dir.path().join("id"),
        &[
            "moved.csv: sphere centre 6 in file order (z) alone makes the misfit",
            "without it χ²/dof falls from",
        ],
        "one reading mistyped or disturbed",
    );

    // A laser table written in tenths of a thou (µm ÷ 2.54): the 20 nm noise reads 7.9 nm, and
    // χ²/dof falls to about 1/2.54² = 0.155 of the stated 20 nm. The fit passes (the
    // estimates are plausible, 2.54 times small) and says so.
    let scenario = dir.path().join("laser.toml");
    std::fs::write(
        &scenario,
        format!(
            "schema = 1\nmachine = \"{}\"\nseed = 1\n[errors.EXX]\npolynomial_um = [0.0, 0.012, -8.0e-6]\n\
             [iso230_2]\naxis = \"X\"\ntargets_mm = {{ from = 10.0, to = 750, count = 11 }}\nruns = 5\n\
             overrun_mm = 5.0\nfeed_mm_per_min = 2000.0\ndwell_s = 2.0\ny_mm = 205.0\nz_mm = 100.0\n\
             [laser]\nbeam_offset_mm = [0.0, 0.0, 0.0]\nresolution_nm = 1.0\nnoise_nm = 20.0\ncompensation = \"off\"\n",
            root("models/vmc3.urdf").display()
        ),
    )
    .unwrap();
    let laser = run_into(&scenario, dir.path(), "laser");
    let text = std::fs::read_to_string(laser.join("positioning.csv")).unwrap();
    let identify = |table: &std::path::Path, out: &str| {
        mtwin(&[
            "identify".as_ref(),
            "--machine".as_ref(),
            root("models/vmc3.urdf").as_os_str(),
            "--params".as_ref(),
            "EXX:2".as_ref(),
            table.as_os_str(),
            "--out".as_ref(),
            dir.path().join(out).as_os_str(),
        ])
    };
    let report = ok(&identify(&laser.join("positioning.csv"), "clean"));
    assert!(!report.contains("CAUTION"), "{report}");
    // The same rows listed last to first (an export sorted newest first), times intact: the
    // laser was zeroed on the first reading in time, not in the file, and the estimate is the
    // same to the last digit but the summation's rounding.
    let mut lines: Vec<&str> = text.lines().collect();
    let header = lines.iter().position(|l| !l.starts_with('#')).unwrap();
    lines[header + 1..].reverse();
    let reversed = dir.path().join("reversed.csv");
    std::fs::write(&reversed, lines.join("\n") + "\n").unwrap();
    ok(&identify(&reversed, "reversed"));
    let coefficients = |out: &str| -> Vec<f64> {
        let json: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join(out).join("estimate.json")).unwrap(),
        )
        .unwrap();
        json["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["value_si"].as_f64().unwrap())
            .collect()
    };
    let (clean, reversed) = (coefficients("clean"), coefficients("reversed"));
    // EXX's two coefficients and the laser's zero offset (a nuisance), each to 1e-9 of itself
    // or, for the offset, of the largest reading: a least-squares solution's rounding is
    // relative to the data it is fitted from, not to a component that happens to be near zero
    // (the offset here is 2 nm; the row order changes the rounding of the solver's QR).
    assert_eq!(clean.len(), 3);
    let largest = std::cell::Cell::new(0.0_f64);
    super::with_column(&text, "deviation_um", |v| {
        largest.set(largest.get().max(v.abs()));
        v
    });
    let largest_m = largest.get() * 1e-6;
    assert!(largest_m > 1e-6, "{largest_m}");
    for (k, (a, b)) in clean.iter().zip(&reversed).enumerate() {
        let scale = if k == 2 {
            a.abs().max(largest_m)
        } else {
            a.abs()
        };
        assert!(
            (a - b).abs() <= 1e-9 * scale,
            "{clean:?} against {reversed:?}"
        );
    }
    // The laser datumed elsewhere than at the first reading (a test that starts with the minus
    // pass, zeroed at the near end before it): every reading moves by one constant, 4.36 µm.
    // The zero is fitted as an offset, so EXX comes back the same and the offset takes it all.
    let datum = dir.path().join("datum.csv");
    std::fs::write(
        &datum,
        super::with_column(&text, "deviation_um", |v| v + 4.36),
    )
    .unwrap();
    ok(&identify(&datum, "datum"));
    let moved = coefficients("datum");
    for (a, b) in clean[..2].iter().zip(&moved) {
        assert!(
            (a - b).abs() <= 1e-9 * a.abs(),
            "{clean:?} against {moved:?}"
        );
    }
    assert!(
        (moved[2] - clean[2] - 4.36e-6).abs() < 1e-12,
        "{clean:?} against {moved:?}"
    );
    let tenths = dir.path().join("tenths.csv");
    std::fs::write(
        &tenths,
        super::with_column(&text, "deviation_um", |v| v / 2.54),
    )
    .unwrap();
    let report = ok(&identify(&tenths, "tenths"));
    assert!(
        report.contains("CAUTION: χ²/dof = 0.1") && report.contains("tenths of a thou"),
        "{report}"
    );
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("tenths/estimate.json")).unwrap(),
    )
    .unwrap();
    assert!(json["cautions"][0].as_str().unwrap().contains("2.54"));

    // The table's own cautions travel into the estimate: the same readings with the air
    // logged at 24.1 °C by a laser that compensated nothing (3.8 ppm of scale it read).
    let preamble: String = text
        .lines()
        .take(header)
        .filter(|l| !l.starts_with("# compensation"))
        .map(|l| format!("{l}\n"))
        .collect();
    let rows: String = text
        .lines()
        .skip(header)
        .enumerate()
        .map(|(i, l)| match i {
            0 => format!("{l},temp_air_degc\n"),
            _ => format!("{l},24.1\n"),
        })
        .collect();
    let warm = dir.path().join("warm.csv");
    std::fs::write(&warm, format!("{preamble}# compensation = none\n{rows}")).unwrap();
    let report = ok(&identify(&warm, "warm"));
    assert!(
        report.contains("warm.csv: compensation = none: the laser did not correct for the air"),
        "{report}"
    );
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("warm/estimate.json")).unwrap(),
    )
    .unwrap();
    assert!(
        json["cautions"]
            .as_array()
            .unwrap()
            .iter()
            .any(|c| c.as_str().unwrap().contains("did not correct for the air")),
        "{json}"
    );
}
