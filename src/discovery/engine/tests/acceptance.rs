//! The acceptance test of a move ([`Test`]): its held-out z by hand and on noise, the
//! numbering of the condition it fails, and the in-sample route of files of few folds.

use super::*;

#[test]
fn normal_quantile_matches_the_tables() {
    // Standard normal tables: 0.975 → 1.959964, 0.995 → 2.575829, 0.9975 → 2.807034,
    // 0.999 → 3.090232, 0.025 → −1.959964.
    for (p, z) in [
        (0.975, 1.959964),
        (0.995, 2.575829),
        (0.9975, 2.807034),
        (0.999, 3.090232),
        (0.025, -1.959964),
        (0.5, 0.0),
    ] {
        assert!((normal_quantile(p) - z).abs() < 2e-6, "{p}");
    }
}

/// Two folds of three readings: the gain, z and rest gain by hand.
#[test]
fn the_test_matches_a_hand_computation() {
    let folds = Folds::new("two".into(), vec![0, 0, 0, 1, 1, 1], 2);
    let score = |held_out: Vec<Real>| {
        let n = held_out.len() as Real;
        Score {
            rms: 0.0,
            cv_rms: (held_out.iter().map(|r| r * r).sum::<Real>() / n).sqrt(),
            fold_mse: vec![],
            held_out,
            fold_ss: vec![],
            fold_lag_one: vec![],
            parameters: None,
        }
    };
    let current = score(vec![2.0, -1.0, 3.0, 1.0, 2.0, -2.0]);
    let candidate = score(vec![1.0, 1.0, -1.0, 1.0, 1.0, 1.0]);
    let test = Test::new(&current, &candidate, &folds, 1);
    // Fold 0: r1 = (1, 1, −1), σ² = 1, lag-one (1 − 1)/3 = 0: ρ = 0, δ = (1, −2, 4),
    // δᵀδ = 21. Fold 1: r1 = (1, 1, 1), σ² = 1, ρ = 2/3, δ = (0, 1, −3):
    // Σδ² + 2ρ(δ1δ2 + δ2δ3) + 2ρ²δ1δ3 = 10 − 4 = 6. Gains: 14 − 3 = 11 and 9 − 3 = 6.
    let rho: Real = 2.0 / 3.0;
    let second = 10.0 + 2.0 * rho * (0.0 - 3.0);
    // Weights Σδ²/(2√(δᵀRδ)) with Σδ² = 21 and 10, σ² = 1 in both folds.
    let (d0, d1) = (2.0 * 21.0_f64.sqrt(), 2.0 * second.sqrt());
    let (z0, z1) = (11.0 / d0, 6.0 / d1);
    let (w0, w1) = (21.0 / d0, 10.0 / d1);
    let z = (w0 * z0 + w1 * z1) / (w0 * w0 + w1 * w1).sqrt();
    assert!((test.z - z).abs() < 1e-12, "{} {z}", test.z);
    // Without the fold that contributes most, the other alone (its own z).
    let rest = if w0 * z0 >= w1 * z1 { z1 } else { z0 };
    assert!((test.rest_z - rest).abs() < 1e-12);
    assert!((test.gain - (1.0 - 1.0 / (23.0_f64 / 6.0).sqrt())).abs() < 1e-12);
    assert!((test.threshold - 1.959964).abs() < 2e-6);
}

/// The derivation's claim: when the candidate's term is not in the data (δ fixed by the
/// training folds, the held-out residual noise independent of it), z exceeds Φ⁻¹(0.975)
/// at most 2.5 % of the time — for white noise, and for first-order correlated noise
/// (ρ = 0.8) that a white-noise standard error would under-state. 4000 draws of 5 folds of
/// 30 readings; the binomial standard deviation of a 2.5 % rate is 0.25 %.
#[test]
fn on_noise_z_rarely_passes_even_with_correlated_residuals() {
    use crate::math::{seeded_rng, standard_normal};
    let folds = Folds::new("five".into(), (0..150).map(|i| i / 30).collect(), 5);
    for rho in [0.0, 0.8] {
        let mut rng = seeded_rng(7, "engine null");
        let mut passes = 0;
        let draws = 4000;
        for _ in 0..draws {
            // A smooth spurious prediction change per fold and correlated noise.
            let slope = 0.05 * standard_normal(&mut rng);
            let mut noise = 0.0;
            let (mut r0, mut r1) = (Vec::new(), Vec::new());
            for i in 0..150 {
                let fresh = standard_normal(&mut rng);
                noise = if i % 30 == 0 {
                    fresh
                } else {
                    rho * noise + (1.0 - rho * rho).sqrt() * fresh
                };
                let delta = slope * ((i % 30) as Real - 14.5) / 15.0;
                r0.push(noise);
                r1.push(noise - delta);
            }
            let score = |held_out: Vec<Real>| Score {
                rms: 0.0,
                cv_rms: 1.0,
                fold_mse: vec![],
                held_out,
                fold_ss: vec![],
                fold_lag_one: vec![],
                parameters: None,
            };
            if Test::new(&score(r0), &score(r1), &folds, 1).z >= normal_quantile(0.975) {
                passes += 1;
            }
        }
        let rate = passes as Real / draws as Real;
        println!("ρ = {rho}: z ≥ 1.96 in {:.2} %", 100.0 * rate);
        assert!(rate <= 0.025 + 3.0 * 0.0025, "ρ = {rho}: {rate}");
    }
}

/// The condition a test fails is numbered as in [`RULE`], looked at in the order 2, 3, 1, and
/// a NaN fails the condition it is in.
#[test]
fn the_failed_condition_is_numbered_as_the_rule_states_it() {
    let passing = Test {
        gain: 0.2,
        z: 4.0,
        threshold: 2.5,
        rest_z: 3.0,
        in_sample: None,
    };
    let with = |gain: Real, z: Real, rest_z: Real| Test {
        gain,
        z,
        rest_z,
        ..passing
    };
    assert_eq!(passing.failed_condition(), None);
    assert_eq!(with(0.01, 4.0, 3.0).failed_condition(), Some(1));
    assert_eq!(with(0.2, 2.0, 3.0).failed_condition(), Some(2));
    assert_eq!(with(0.2, 4.0, 2.0).failed_condition(), Some(3));
    assert_eq!(with(0.01, 2.0, 2.0).failed_condition(), Some(2));
    assert_eq!(with(0.01, 4.0, 2.0).failed_condition(), Some(3));
    assert_eq!(with(Real::NAN, 4.0, 3.0).failed_condition(), Some(1));
    assert_eq!(with(0.2, Real::NAN, 3.0).failed_condition(), Some(2));
    assert_eq!(with(0.2, 4.0, Real::NAN).failed_condition(), Some(3));
    // On a file of few folds the in-sample route can meet (2) and (3) in the held-out
    // test's place, never (1).
    let in_sample = |z: Real, rest_z: Real| InSample {
        z,
        rest_z,
        threshold: 3.5,
        grid: 24.0,
    };
    let few = |gain: Real, s: InSample| Test {
        in_sample: Some(s),
        ..with(gain, 2.0, 1.0)
    };
    assert_eq!(few(0.2, in_sample(5.0, 4.0)).failed_condition(), None);
    assert_eq!(few(0.2, in_sample(5.0, 4.0)).evidence(), Some("in-sample"));
    assert_eq!(few(0.01, in_sample(5.0, 4.0)).failed_condition(), Some(1));
    assert_eq!(few(0.2, in_sample(5.0, 3.0)).failed_condition(), Some(3));
    assert_eq!(few(0.2, in_sample(3.0, 3.0)).failed_condition(), Some(2));
    assert_eq!(passing.evidence(), Some("held-out"));
    assert!(RULE.contains("(1) lower the pooled held-out RMS by at least 5 %"));
    assert!(RULE.contains("(3) still reach it without the fold that contributes most"));
    // A test among more candidates keeps its numbers and asks more: Φ⁻¹(1 − 0.025/6).
    let six = passing.among(6);
    assert_eq!((six.gain, six.z, six.rest_z), (0.2, 4.0, 3.0));
    assert!(
        (six.threshold - 2.638_257).abs() < 1e-6,
        "{}",
        six.threshold
    );
}

/// Paulson's z of F against exact quantiles: F(2, d2) has the closed upper tail
/// (1 + 2F/d2)^(−d2/2), and F(1, d2) = t² (t quantiles of d2 = 60: 2.000, 2.660, 3.460 at
/// 97.5, 99.5 and 99.95 %). Within 0.04 of the normal quantile to p = 0.999; beyond, the z
/// errs low (against acceptance), by less than 0.1 at p = 0.9999.
#[test]
fn f_as_normal_matches_exact_f_quantiles() {
    for d2 in [20, 60, 120] {
        for p in [0.95, 0.99, 0.999, 0.9999] {
            let f = d2 as Real / 2.0 * ((1.0 - p as Real).powf(-2.0 / d2 as Real) - 1.0);
            let error = f_as_normal(f, 2, d2) - normal_quantile(p);
            if p <= 0.999 {
                assert!(error.abs() < 0.04, "F(2, {d2}) at {p}: {error}");
            } else {
                assert!(error < 0.0 && error > -0.1, "F(2, {d2}) at {p}: {error}");
            }
        }
    }
    for (t, p) in [(2.000, 0.95), (2.660, 0.99), (3.460, 0.999)] {
        let error = f_as_normal(t * t, 1, 60) - normal_quantile(p);
        assert!(error.abs() < 0.04, "F(1, 60) at {p}: {error}");
    }
}

/// Three folds of four readings: the in-sample route by hand, and no route with four folds.
#[test]
fn the_in_sample_route_matches_a_hand_computation() {
    let folds = Folds::new("three".into(), (0..12).map(|i| i / 4).collect(), 3);
    let score = |fold_ss: Vec<Real>, lag_one: Vec<Real>, count: usize, grid: Real| Score {
        rms: 0.0,
        cv_rms: 1.0,
        fold_mse: vec![1.0; 3],
        held_out: vec![0.0; 12],
        fold_ss,
        fold_lag_one: lag_one,
        parameters: Some(Parameters { count, grid }),
    };
    // n = 12 readings; a candidate of 2 parameters on a model of 1, one of them searched on a
    // grid of 24: dof = 12 − 2 = 10 (the least allowed).
    let current = score(vec![9.0, 4.0, 5.0], vec![0.0; 3], 1, 1.0);
    let candidate = score(vec![1.0, 1.5, 0.5], vec![0.3, 0.0, 0.0], 2, 24.0);
    let test = Test::new(&current, &candidate, &folds, 4);
    let s = test.in_sample.expect("three folds");
    // SS₁ = 3, ρ = 0.3/3 = 0.1, s² = 3/10·1.1/0.9; gains 8, 2.5, 4.5: F = 15/s², and
    // without the first fold F = 7/s².
    let variance = 3.0 / 10.0 * 1.1 / 0.9;
    assert!((s.z - f_as_normal(15.0 / variance, 1, 10)).abs() < 1e-12);
    assert!((s.rest_z - f_as_normal(7.0 / variance, 1, 10)).abs() < 1e-12);
    assert_eq!(s.grid, 24.0);
    assert!((s.threshold - normal_quantile(1.0 - 0.025 / 96.0)).abs() < 1e-12);
    let one = test.among(1).in_sample.unwrap();
    assert!((one.threshold - normal_quantile(1.0 - 0.025 / 24.0)).abs() < 1e-12);
    // The held-out residuals are all zero: no held-out route, and the in-sample one decides.
    assert!(!test.held_out_significant());
    assert_eq!(test.significant(), s.significant());
    // Four folds: the held-out test alone.
    let four = Folds::new("four".into(), (0..12).map(|i| i / 3).collect(), 4);
    let widen = |s: &Score| Score {
        fold_ss: vec![0.0; 4],
        fold_lag_one: vec![0.0; 4],
        ..s.clone()
    };
    assert_eq!(
        Test::new(&widen(&current), &widen(&candidate), &four, 4).in_sample,
        None
    );
}
