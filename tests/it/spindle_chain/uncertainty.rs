//! ISO 230-7 Annex F budgets of each test's values, against the formulas F.1–F.7 evaluated
//! here by hand from the stated inputs and the injected errors.

use super::*;
use mtwin::kinds::spindle::evaluate::{Budget, rounding_step};

/// Evaluates with the Annex F inputs `budget`.
fn evaluated_with(s: &Scenario, budget: Budget) -> Evaluation {
    let test = s.spindle_test.as_ref().expect("a [spindle] section");
    let table = run::simulate(&s.twin, test, 1).unwrap();
    let options = Options {
        budget,
        ..Options::default()
    };
    evaluate(&table.record, table.samples_per_revolution, &options).unwrap()
}

#[test]
fn a_stated_budget_gives_the_annex_f_values() {
    // U_DEVICE = 0.05 µm (F.1), E_VE = 0.1 µm (F.3, U_EVE = 0.06 µm), 20 revolutions; the
    // sphere (R = 12.7 mm) 0.8, 0.3 µm off centre: the limaçon's 2-UPR error has range e²/2R,
    // U = 0.6·e²/2R. F.5–F.7: U(sync value) = 1.4·√(U_D² + U_c² + U_EVE²/n), U(single
    // value) = 1.4·√(U_D² + U_c² + U_EVE²).
    let s = load("vmc3", "", &sphere("", "eccentricity_um = [0.8, 0.3]"));
    let budget = Budget {
        device: Some(0.05 * UM),
        drift: Some(0.1 * UM),
        ..Budget::default()
    };
    let ev = evaluated_with(&s, budget.clone());
    let x1 = find(&ev.segments[0], "radial x1");
    assert_eq!(x1.signal.count(), 20);
    let e2 = (0.8 * UM).powi(2) + (0.3 * UM).powi(2);
    let centring = 0.6 * e2 / (2.0 * 12.7e-3);
    let (device, drift) = (0.05 * UM, 0.06 * UM);
    let sync = 1.4 * (device.powi(2) + centring.powi(2) + drift.powi(2) / 20.0).sqrt();
    let single = 1.4 * (device.powi(2) + centring.powi(2) + drift.powi(2)).sqrt();
    let u = &x1.uncertainty;
    assert!(u.missing.is_empty(), "{:?}", u.missing);
    assert_eq!(u.contributions.len(), 3, "{:?}", u.contributions);
    close(u.synchronous, sync, 1e-15, "U(sync value)");
    close(u.single, single, 1e-15, "U(single value)");

    // The axial probe: no centring term (not radial).
    let z = find(&ev.segments[0], "axial z");
    close(
        z.uncertainty.synchronous,
        1.4 * (device.powi(2) + drift.powi(2) / 20.0).sqrt(),
        1e-15,
        "axial",
    );
    // Two orthogonal probes in the rotating direction: weights (cos θ, sin θ), norm 1; the
    // centring is the probes' own.
    let rotating = find(&ev.segments[0], "radial x1+y1 rotating");
    close(
        rotating.uncertainty.single,
        1.4 * (device.powi(2) + centring.powi(2) + drift.powi(2)).sqrt(),
        1e-15,
        "rotating",
    );

    // F.2: a stated error range of 0.1 µm is U_DEVICE = 0.06 µm.
    let ev = evaluated_with(
        &s,
        Budget {
            device: None,
            device_range: Some(0.1 * UM),
            ..budget
        },
    );
    let u = &find(&ev.segments[0], "radial x1").uncertainty;
    close(
        u.synchronous,
        1.4 * ((0.06 * UM).powi(2) + centring.powi(2) + drift.powi(2) / 20.0).sqrt(),
        1e-15,
        "F.2 then F.7",
    );
}

#[test]
fn a_tilt_divides_two_probes_by_their_separation() {
    // Parallel probes x1, x2 80 mm apart: (upper − lower)/L, weights ±1/L, norm √2/L. With
    // U_DEVICE = 0.05 µm and E_VE = 0.1 µm each probe's terms widen by √2/0.08 per metre.
    let s = load("vmc3", "", &cylinder("", ""));
    let ev = evaluated_with(
        &s,
        Budget {
            device: Some(0.05 * UM),
            drift: Some(0.1 * UM),
            ..Budget::default()
        },
    );
    let tilt = find(&ev.segments[0], "tilt x1-x2");
    let w = 2f64.sqrt() / 0.080;
    let want = 1.4 * ((w * 0.05 * UM).powi(2) + (w * 0.06 * UM).powi(2) / 20.0).sqrt();
    close(tilt.uncertainty.synchronous, want, 1e-15, "tilt U (rad)");
}

#[test]
fn without_a_device_term_the_budget_says_it_is_a_lower_bound() {
    // Nothing stated: the device term is missing (listed), the resolution stands in for it and
    // the drift is read from the record: 0.6 × the range of the revolution means, computed
    // here from the signal. The twin's probes here are exact (no resolution): the readings are
    // floats, so no rounding step is found and no resolution term is given.
    let errors = "[errors.EXS]\nasynchronous = [{ amplitude_um = 0.05, frequency_hz = 0.2 }]\n";
    let s = load("vmc3", errors, &sphere("", ""));
    let ev = evaluated_with(&s, Budget::default());
    let x1 = find(&ev.segments[0], "radial x1");
    let u = &x1.uncertainty;
    assert_eq!(u.missing.len(), 2, "device and drift test: {:?}", u.missing);
    assert!(u.missing[0].contains("device"));
    let m = x1.signal.samples_per_revolution();
    let means: Vec<Real> = (0..x1.signal.count())
        .map(|k| x1.signal.revolution(k).iter().sum::<Real>() / m as Real)
        .collect();
    let drift = 0.6 * range(&means);
    assert!(drift > 0.01 * UM, "a slow line moves the means: {drift:e}");
    // The centring term is there, and nil on a centred sphere (below 1e-17 m).
    assert_eq!(u.contributions.len(), 2, "{:?}", u.contributions);
    assert!(u.contributions[1].source.starts_with("centring") && u.contributions[1].u < 1e-17);
    close(u.single, 1.4 * drift, 1e-15, "single: the drift alone");
    close(
        u.synchronous,
        1.4 * drift / 20f64.sqrt(),
        1e-15,
        "synchronous: averaged",
    );

    // A stated resolution of 1 nm stands in for the device: 2q/√12.
    let ev = evaluated_with(
        &s,
        Budget {
            resolution: Some(1e-9),
            drift: Some(0.0),
            ..Budget::default()
        },
    );
    let u = &find(&ev.segments[0], "axial z").uncertainty;
    close(
        u.single,
        1.4 * 2.0 * 1e-9 / 12f64.sqrt(),
        1e-18,
        "resolution",
    );
    assert_eq!(u.missing.len(), 1);
}

#[test]
fn the_rounding_step_is_found_from_the_readings() {
    let nm = |v: &[f64]| -> Vec<Real> { v.iter().map(|x| x * 1e-9).collect() };
    assert_eq!(
        rounding_step(&[nm(&[1.0, -3.0, 120.0]), nm(&[7.0])]),
        Some(1e-9)
    );
    assert_eq!(rounding_step(&[nm(&[1.5, -3.2, 120.0])]), Some(1e-10));
    assert_eq!(rounding_step(&[nm(&[1000.0, 3000.0])]), Some(1e-6));
    assert_eq!(rounding_step(&[vec![1.234_567_891_234e-7]]), None);
    assert_eq!(rounding_step(&[]), None);
}

/// Student's t at 95 %: the table's values (GUM Table G.2) and monotone between them.
#[test]
fn student_t_is_the_gum_table() {
    use mtwin::kinds::spindle::evaluate::student_t95;
    for (dof, t) in [
        (1.0, 12.706),
        (2.0, 4.303),
        (5.0, 2.571),
        (10.0, 2.228),
        (30.0, 2.042),
    ] {
        close(student_t95(dof), t, 1e-12, &format!("t95({dof})"));
    }
    close(student_t95(Real::INFINITY), 1.96, 1e-12, "the normal limit");
    assert!((student_t95(1e9) - 1.96).abs() < 1e-6);
    let mut last = Real::INFINITY;
    for i in 2..400 {
        let t = student_t95(i as Real / 4.0);
        assert!(t <= last, "decreasing at {}", i as Real / 4.0);
        last = t;
    }
}
