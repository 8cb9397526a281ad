//! A fixed sensitive direction between two probes (ISO 230-7 formula (4)) and the
//! speed-induced axis shift (§3.10.6), and the two senses of a rotary table pooled (§6), against
//! closed forms of the injected errors.

use super::*;

/// Evaluates with fixed sensitive directions `degrees` asked besides the defaults.
fn evaluated_with(s: &Scenario, degrees: &[Real]) -> Evaluation {
    let test = s.spindle_test.as_ref().expect("a [spindle] section");
    let table = run::simulate(&s.twin, test, 1).unwrap();
    let options = Options {
        fixed_directions: degrees.iter().map(|d| d.to_radians()).collect(),
        ..Options::default()
    };
    evaluate(&table.record, table.samples_per_revolution, &options).unwrap()
}

#[test]
fn a_fixed_direction_at_30_degrees_is_formula_4_of_the_two_probes() {
    // EXS = 0.2 µm·sin 2θ, EYS = 0.1 µm·sin(3θ + 10°); probes x1 at 0°, y1 at 90° (the
    // default nest). Formula (4): r(θ) = ΔX cos 30° + ΔY sin 30°, by hand on the grid. It holds
    // no 1 UPR, so its value about every centre but PC is its range with the first harmonic
    // removed (computed here), and about PC its range.
    let errors = harmonics("EXS", &[harmonic(2, 0.2, 0.0, "um")])
        + &harmonics("EYS", &[harmonic(3, 0.1, 10.0, "um")]);
    let s = load("vmc3", &errors, &sphere("", ""));
    let ev = evaluated_with(&s, &[30.0, -45.0]);
    let segment = &ev.segments[0];
    let (c, s30) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let by_hand: Vec<Real> = grid(M)
        .iter()
        .map(|t| {
            0.2 * UM * (2.0 * t).sin() * c + 0.1 * UM * (3.0 * t + 10f64.to_radians()).sin() * s30
        })
        .collect();
    let test = find(segment, "radial x1+y1 fixed 30°");
    assert_eq!(test.sensing, Sensing::Fixed);
    assert_eq!(test.probes, ["x1", "y1"]);
    close(
        worst_over_signal(test, |t| {
            by_hand[(t / TAU * M as Real).round() as usize % M]
        }),
        0.0,
        EXACT,
        "signal = formula (4)",
    );
    close(
        about(test, Centre::Pc).synchronous,
        range(&by_hand),
        EXACT,
        "PC",
    );
    close(
        about(test, Centre::Lsc).synchronous,
        lsc_value(&by_hand),
        EXACT,
        "LSC",
    );
    // MRS is the minimum radial separation.
    assert!(about(test, Centre::Mrs).synchronous <= about(test, Centre::Lsc).synchronous + EXACT);
    // −45° is asked too: its own test, with its own signal.
    let other = find(segment, "radial x1+y1 fixed -45°");
    let (c, s45) = ((-45f64).to_radians().cos(), (-45f64).to_radians().sin());
    close(
        worst_over_signal(other, |t| {
            0.2 * UM * (2.0 * t).sin() * c + 0.1 * UM * (3.0 * t + 10f64.to_radians()).sin() * s45
        }),
        0.0,
        EXACT,
        "signal at −45°",
    );
    // Not asked, not there.
    assert!(
        evaluated(&s, 1).segments[0]
            .tests
            .iter()
            .all(|t| !t.name.contains("fixed"))
    );
}

#[test]
fn the_speed_induced_shift_is_the_change_of_the_mean_position_between_speeds() {
    // EXS = 0.5 µm constant, scaled by the speed factor 1, 1.5, 3 at 0, 6000, 12000 rpm
    // (linear between): 0.625, 0.75 and 1.125 µm at 3000, 6000 and 9000 rpm. x1 faces −X and
    // reads −EXS: its mean moves by 0, −0.125, −0.5 µm and the shift value is 0.5 µm; y1 reads
    // nothing; the direction at 30° sees EXS cos 30°.
    let errors = "[errors.EXS]\nconstant_um = 0.5\n\
                  speed = { rpm = [0.0, 6000.0, 12000.0], factor = [1.0, 1.5, 3.0] }\n";
    let spindle = sphere("", "").replace(
        "speeds_rpm = [3000.0]",
        "speeds_rpm = [3000.0, 6000.0, 9000.0]",
    );
    let ev = evaluated_with(&load("vmc3", errors, &spindle), &[30.0]);
    let shift = |name: &str| {
        ev.shifts
            .iter()
            .find(|s| s.test == name)
            .unwrap_or_else(|| {
                let names: Vec<&str> = ev.shifts.iter().map(|s| s.test.as_str()).collect();
                panic!("no shift of {name} among {names:?}")
            })
    };
    let x1 = shift("radial x1");
    assert!(!x1.backwards);
    let speeds: Vec<Real> = x1.points.iter().map(|p| p.0 * 60.0 / TAU).collect();
    for (got, want) in speeds.iter().zip([3000.0, 6000.0, 9000.0]) {
        close(*got, want, 1e-9, "speed");
    }
    for (point, want) in x1.points.iter().zip([0.0, -0.125 * UM, -0.5 * UM]) {
        close(point.1, want, EXACT, "x1 shift");
    }
    close(x1.value, 0.5 * UM, EXACT, "x1 value");
    // Its uncertainty is the test's single-value U, the widest over the speeds; nothing is
    // stated here, so it is a lower bound.
    let widest = ev
        .segments
        .iter()
        .map(|s| find(s, "radial x1").uncertainty.single)
        .fold(0.0, Real::max);
    assert_eq!(x1.uncertainty, widest);
    assert!(!x1.complete);
    close(shift("radial y1").value, 0.0, EXACT, "y1");
    close(
        shift("radial x1+y1 fixed 30°").value,
        0.5 * UM * 30f64.to_radians().cos(),
        EXACT,
        "30°",
    );
    // The rotating direction cannot tell a shift from motion: no shift is given for it.
    assert!(ev.shifts.iter().all(|s| !s.test.contains("rotating")));
    // One speed: no shift at all.
    assert!(
        evaluated(&load("vmc3", errors, &sphere("", "")), 1)
            .shifts
            .is_empty()
    );
}

#[test]
fn a_rotary_table_turned_both_ways_is_also_evaluated_as_one_record() {
    // The C table of trunnion5 at ±5 min⁻¹, exact probes, EXC = 0.2 µm·sin(3θ + 45°), a
    // function of the axis angle alone. ISO 230-7 §6 turns a table both ways: the pooled
    // segment lays the backward revolutions back on the axis angle, so its synchronous profile
    // is the forward one (a mirrored layout would average sin(3θ + 45°) with sin(−3θ + 45°),
    // a range of 2a·cos 45° instead of 2a) and nothing is asynchronous.
    let a = 0.2 * UM;
    let errors = harmonics("EXC", &[harmonic(3, 0.2, 45.0, "um")]);
    let spindle = "axis = \"C\"\nspeeds_rpm = [5.0, -5.0]\nrevolutions = 3\n\
                   samples_per_revolution = 240\nx_mm = 325.0\ny_mm = 275.0\nz_mm = 150.0\na_deg = 0.0\n\
                   [spindle.artefact]\nkind = \"sphere\"\ndiameter_mm = 25.4\nstickout_mm = 100.0\n\
                   [[spindle.probe]]\nname = \"x\"\nkind = \"radial\"\nazimuth_deg = 0.0\n";
    let ev = evaluated(&load("trunnion5", &errors, spindle), 1);
    let setups: Vec<(&str, bool)> = ev
        .segments
        .iter()
        .map(|s| (s.setup.as_str(), s.pooled))
        .collect();
    assert_eq!(setups.len(), 3, "{setups:?}");
    let pooled = ev
        .segments
        .iter()
        .find(|s| s.pooled)
        .expect("a pooled segment");
    assert!(pooled.setup.ends_with("(both senses)"), "{}", pooled.setup);
    assert_eq!(pooled.revolutions, 6);
    close(pooled.speed, 5.0 * TAU / 60.0, 1e-12, "the forward speed");
    let x = find(pooled, "radial x");
    assert_eq!(x.signal.count(), 6);
    let forward = find(&ev.segments[0], "radial x");
    for (p, f) in x.values.iter().zip(&forward.values) {
        close(
            p.synchronous,
            f.synchronous,
            EXACT,
            &format!("sync about {}", p.centre),
        );
        close(
            p.asynchronous,
            0.0,
            EXACT,
            &format!("async about {}", p.centre),
        );
    }
    close(
        about(x, Centre::Lsc).synchronous,
        range(&sampled_3(a)),
        EXACT,
        "2a sampled",
    );

    // A spindle turned both ways is not pooled (§5 tests a spindle one way at three speeds).
    let s = load(
        "vmc3",
        &harmonics("EXS", &[harmonic(3, 0.2, 45.0, "um")]),
        &sphere("", "").replace("speeds_rpm = [3000.0]", "speeds_rpm = [3000.0, -3000.0]"),
    );
    assert!(evaluated(&s, 1).segments.iter().all(|s| !s.pooled));
}

/// `a·sin(3θ_m + 45°)` on the 240-sample grid.
fn sampled_3(a: Real) -> Vec<Real> {
    grid(240)
        .iter()
        .map(|t| a * (3.0 * t + 45f64.to_radians()).sin())
        .collect()
}
