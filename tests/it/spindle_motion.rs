//! ISO 230-7 decomposition, values and spectrum of one error-motion signal
//! (`kinds::spindle::analysis::{motion, spectrum}`), against closed forms, hand values and
//! properties that do not depend on the code under test.
//!
//! Tolerances: "rounding" is a few hundred ulps of the signal amplitude (sums over at most a
//! few thousand samples, and FFTs of that length, lose `O(log N)`–`O(N)` ulps), written as
//! `1e-12·a`. The linear-programme centres (MRS, MIC, MCC) get the same: their optimum is a
//! vertex, exact to rounding, and `polar` certifies feasibility to `1e-13·max|p|`.

use mtwin::kinds::spindle::analysis::motion::{
    Direction, MotionError, Revolutions, decompose, fixed_direction, resample, rotating_radial,
    tilt, values, values_about,
};
use mtwin::kinds::spindle::analysis::polar::Centre;
use mtwin::kinds::spindle::analysis::spectrum::spectrum;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};

/// `θ_m = 2πm/M`.
fn theta(m: usize, per_rev: usize) -> f64 {
    TAU * m as f64 / per_rev as f64
}

/// A record `s[k, m] = f(k, θ_m)`.
fn record(per_rev: usize, revs: usize, f: impl Fn(usize, f64) -> f64) -> Revolutions {
    let mut v = Vec::with_capacity(per_rev * revs);
    for k in 0..revs {
        for m in 0..per_rev {
            v.push(f(k, theta(m, per_rev)));
        }
    }
    Revolutions::new(per_rev, v).unwrap()
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:e}, want {want:e} (tol {tol:e}, off by {:e})",
        (got - want).abs()
    );
}

/// `|(1/K) Σ_k e^{i2πrk}|`: the fraction of an asynchronous sinusoid at `r` UPR that survives
/// averaging `K` revolutions, summed directly.
fn averaging_leak(r: f64, revs: usize) -> f64 {
    let (mut re, mut im) = (0.0, 0.0);
    for k in 0..revs {
        let p = TAU * r * k as f64;
        re += p.cos();
        im += p.sin();
    }
    re.hypot(im) / revs as f64
}

/// The band width `max_m (max_k − min_k)` of `a·sin(2πr(k + m/M) + φ)`, evaluated from the
/// formula (not from a record).
fn band_width(a: f64, r: f64, phi: f64, per_rev: usize, revs: usize) -> f64 {
    (0..per_rev)
        .map(|m| {
            let vals = (0..revs)
                .map(|k| a * (TAU * r * (k as f64 + m as f64 / per_rev as f64) + phi).sin());
            let (lo, hi) = vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(v), h.max(v))
            });
            hi - lo
        })
        .fold(0.0, f64::max)
}

/// Eccentricity alone (a 1-UPR radial signal, every revolution alike): about LSC every value but
/// the fundamental vanishes; about PC the value is the sampled peak-to-valley `2a` (between
/// `2a·cos(π/M)` and `2a` for an arbitrary phase, as the nearest bin is within `π/M` of each
/// extreme); the fundamental value is `2a` by orthogonality of the sampled cosine and sine.
#[test]
fn eccentricity_vanishes_about_lsc_and_reads_2a_about_pc() {
    let (a, phi, per_rev, revs) = (5e-6, 0.7, 360, 20);
    let r = record(per_rev, revs, |_, t| a * (t + phi).cos());
    let tol = 1e-12 * a;

    let lsc = values(&r, Direction::Radial, Centre::Lsc).unwrap();
    assert_eq!(lsc.centre, Centre::Lsc);
    assert_eq!(lsc.direction, Direction::Radial);
    // a·cos(θ + φ) = a cos φ·cos θ − a sin φ·sin θ: the LSC centre is (a cos φ, −a sin φ).
    close(lsc.offset[0], a * phi.cos(), tol, "LSC cx");
    close(lsc.offset[1], -a * phi.sin(), tol, "LSC cy");
    for (name, v) in [
        ("synchronous", lsc.synchronous),
        ("total", lsc.total),
        ("inner", lsc.inner),
        ("outer", lsc.outer),
        ("residual", lsc.residual),
        ("asynchronous", lsc.asynchronous),
    ] {
        close(v, 0.0, tol, name);
    }
    close(lsc.fundamental, 2.0 * a, tol, "fundamental");

    let pc = values(&r, Direction::Radial, Centre::Pc).unwrap();
    assert_eq!(pc.offset, [0.0, 0.0]);
    let floor = 2.0 * a * (PI / per_rev as f64).cos();
    for (name, v) in [("PC synchronous", pc.synchronous), ("PC total", pc.total)] {
        assert!(
            v >= floor - tol && v <= 2.0 * a + tol,
            "{name} {v:e} outside [{floor:e}, {:e}]",
            2.0 * a
        );
    }
    close(pc.fundamental, 2.0 * a, tol, "PC fundamental");
    close(pc.residual, 0.0, tol, "PC residual");
}

/// A 3-UPR synchronous error `a·cos(3(θ − θ0))` with `θ0` and its extremes on bins: about every
/// centre the synchronous value is `2a` — the three maxima (and minima) are 120° apart, so any
/// centre shift raises one maximum and lowers one minimum, and PC is the unique optimum of MRS,
/// MIC and MCC. No asynchronous part; the spectrum has one line, at 3 UPR, of amplitude `a`.
#[test]
fn three_upr_reads_2a_about_every_centre_and_one_synchronous_line() {
    let (a, per_rev, revs, lobes) = (2e-6, 360, 8, 3usize);
    let theta0 = theta(17, per_rev);
    let r = record(per_rev, revs, |_, t| {
        a * (lobes as f64 * (t - theta0)).cos()
    });
    for centre in Centre::ALL {
        let v = values(&r, Direction::Radial, centre).unwrap_or_else(|e| panic!("{centre}: {e}"));
        let tol = 1e-12 * a;
        close(
            v.synchronous,
            2.0 * a,
            tol,
            &format!("{centre} synchronous"),
        );
        close(v.total, 2.0 * a, tol, &format!("{centre} total"));
        close(
            v.asynchronous,
            0.0,
            1e-12 * a,
            &format!("{centre} asynchronous"),
        );
        close(
            v.fundamental,
            0.0,
            1e-12 * a,
            &format!("{centre} fundamental"),
        );
        close(
            v.residual,
            2.0 * a,
            1e-12 * a,
            &format!("{centre} residual"),
        );
    }

    let s = spectrum(&r);
    assert_eq!(s.revolutions, revs);
    assert_eq!(s.lines.len(), per_rev * revs / 2);
    let top = s.largest(1, None)[0];
    close(
        top.per_revolution,
        lobes as f64,
        1e-12,
        "line frequency (UPR)",
    );
    close(top.amplitude, a, 1e-12 * a, "line amplitude");
    assert!(top.synchronous);
    for l in &s.lines {
        if (l.per_revolution - lobes as f64).abs() > 1e-9 {
            assert!(l.amplitude < 1e-12 * a, "stray line {l:?}");
        }
    }
}

/// An asynchronous sinusoid at 4.6 UPR over K = 20 revolutions (4.6·20 = 92, on a line): the
/// average over the revolutions is bounded by the closed-form leak `a·|Σ_k e^{i2πrk}|/K` (zero
/// here, to rounding); the asynchronous value is the band width of the formula; the spectrum
/// holds one line, at 4.6 UPR, asynchronous, of amplitude `a`. M = 90 makes `K·M = 1800` not a
/// power of two.
#[test]
fn asynchronous_sine_on_a_line() {
    let (a, ratio, phi, per_rev, revs) = (1e-6, 4.6, 0.3, 90, 20);
    let r = record(per_rev, revs, |k, t| {
        a * (TAU * ratio * (k as f64 + t / TAU) + phi).sin()
    });
    let d = decompose(&r);
    let leak = a * averaging_leak(ratio, revs);
    assert!(
        leak < 1e-13 * a,
        "4.6 UPR over 20 revolutions averages out exactly"
    );
    for (m, s) in d.synchronous.iter().enumerate() {
        assert!(s.abs() <= leak + 1e-12 * a, "S[{m}] = {s:e}");
    }
    let v = values(&r, Direction::Radial, Centre::Lsc).unwrap();
    close(
        v.asynchronous,
        band_width(a, ratio, phi, per_rev, revs),
        1e-12 * a,
        "asynchronous value",
    );
    close(v.synchronous, 0.0, 1e-11 * a, "synchronous value");

    let s = spectrum(&r);
    let top = s.largest(1, None)[0];
    close(top.per_revolution, ratio, 1e-12, "line frequency (UPR)");
    close(top.amplitude, a, 1e-12 * a, "line amplitude");
    assert!(!top.synchronous);
    assert!(s.largest(1, Some(true))[0].amplitude < 1e-12 * a);
}

/// Off a line, averaging leaks: at 4.43 UPR over 20 revolutions `S[m]` is a sinusoid of
/// amplitude `a·L`, `L = |Σ_k e^{i2πrk}|/K`, so `max_m |S[m]|` lies between `a·L·cos(πr/M)`
/// (bins step the phase by `2πr/M`, and 4.43 UPR sweeps more than a cycle) and `a·L`. At
/// 0.43 UPR (a cage-like sub-harmonic) only the upper bound holds: one revolution sweeps less
/// than a cycle. The asynchronous value is the band width of the formula in both cases.
#[test]
fn asynchronous_sine_off_a_line_leaks_the_averaging_bound() {
    let (a, phi, per_rev, revs) = (1e-6, 1.1, 72, 20);
    for ratio in [4.43, 0.43] {
        let r = record(per_rev, revs, |k, t| {
            a * (TAU * ratio * (k as f64 + t / TAU) + phi).sin()
        });
        let d = decompose(&r);
        let leak = a * averaging_leak(ratio, revs);
        assert!(leak > 1e-3 * a, "{ratio}: the case must leak");
        let peak = d.synchronous.iter().fold(0.0, |p: f64, s| p.max(s.abs()));
        assert!(
            peak <= leak + 1e-12 * a,
            "{ratio}: peak {peak:e} > leak {leak:e}"
        );
        if ratio > 1.0 {
            let floor = leak * (PI * ratio / per_rev as f64).cos();
            assert!(
                peak >= floor - 1e-12 * a,
                "{ratio}: peak {peak:e} < {floor:e}"
            );
        }
        let v = values(&r, Direction::Radial, Centre::Pc).unwrap();
        close(
            v.asynchronous,
            band_width(a, ratio, phi, per_rev, revs),
            1e-12 * a,
            &format!("{ratio}: asynchronous value"),
        );
    }
}

/// Over many revolutions the band of a 0.43-UPR sinusoid fills: 0.43 = 43/100, so over
/// K ≥ 100 revolutions the phases `2π·0.43·k` at any one angle take all 100 values `2πj/100`,
/// one within `π/100` of each extreme, and the band width lies in `[2a·cos(π/100), 2a]`.
/// 0.43·200 = 86 is a line: the spectrum shows it at 0.43 UPR, asynchronous, amplitude `a`.
#[test]
fn asynchronous_band_tends_to_2a_for_many_revolutions() {
    let (a, ratio, phi, per_rev, revs) = (1e-6, 0.43, 0.2, 36, 200);
    let r = record(per_rev, revs, |k, t| {
        a * (TAU * ratio * (k as f64 + t / TAU) + phi).sin()
    });
    let v = values(&r, Direction::Radial, Centre::Lsc).unwrap();
    let floor = 2.0 * a * (PI / 100.0).cos();
    assert!(
        v.asynchronous >= floor - 1e-12 * a && v.asynchronous <= 2.0 * a + 1e-12 * a,
        "asynchronous value {:e} outside [{floor:e}, {:e}]",
        v.asynchronous,
        2.0 * a
    );
    let top = spectrum(&r).largest(1, None)[0];
    close(top.per_revolution, ratio, 1e-12, "cage line (UPR)");
    close(top.amplitude, a, 1e-12 * a, "cage line amplitude");
    assert!(!top.synchronous);
}

/// Axial (T6): a 1-UPR axial error `a·cos(θ − θ0)` (extremes on bins) is kept about PC, the
/// preferred centre: synchronous value `2a`, fundamental value `2a`, residual 0 — whereas LSC
/// would remove it (value 0). Tab 1 centres and the fundamental convention per direction.
#[test]
fn axial_fundamental_is_kept_about_pc() {
    let (a, per_rev, revs) = (0.8e-6, 360, 20);
    let theta0 = theta(41, per_rev);
    let r = record(per_rev, revs, |_, t| a * (t - theta0).cos());
    let tol = 1e-12 * a;

    assert_eq!(Direction::Axial.preferred_centre(), Centre::Pc);
    assert_eq!(Direction::Face.preferred_centre(), Centre::Pc);
    assert_eq!(Direction::Radial.preferred_centre(), Centre::Lsc);
    assert_eq!(Direction::Tilt.preferred_centre(), Centre::Lsc);
    assert!(!Direction::Axial.removes_fundamental() && !Direction::Face.removes_fundamental());
    assert!(Direction::Radial.removes_fundamental() && Direction::Tilt.removes_fundamental());
    assert_eq!(Direction::Axial.name(), "axial");

    let v = values(&r, Direction::Axial, Direction::Axial.preferred_centre()).unwrap();
    assert_eq!(v.centre, Centre::Pc);
    close(v.synchronous, 2.0 * a, tol, "axial synchronous (PC)");
    close(v.fundamental, 2.0 * a, tol, "axial fundamental");
    close(v.residual, 0.0, tol, "axial residual");
    close(v.asynchronous, 0.0, tol, "axial asynchronous");
    let lsc = values(&r, Direction::Axial, Centre::Lsc).unwrap();
    close(lsc.synchronous, 0.0, tol, "axial about LSC");
}

/// Tilt (formula (5), T8): two stations `L` apart with radial motions `e1` and
/// `e2 = e1 + L·β`: `(e2 − e1)/L` returns β to rounding. The LSC synchronous tilt value of
/// `β = b1·cos θ + b2·cos 2θ` (+ asynchronous) is then `2·b2` plus the band it carries: here β
/// is synchronous only, so exactly `2·b2` (extremes of cos 2θ on bins, M divisible by 4).
#[test]
fn tilt_of_two_stations_recovers_beta() {
    let (per_rev, revs, sep) = (360, 6, 0.08);
    let (b1, b2) = (3e-6, 0.7e-6);
    let n = per_rev * revs;
    let mut rng = ChaCha8Rng::from_seed([7; 32]);
    let mut e1 = Vec::with_capacity(n);
    let mut e2 = Vec::with_capacity(n);
    let mut beta = Vec::with_capacity(n);
    for k in 0..revs {
        for m in 0..per_rev {
            let t = theta(m, per_rev);
            let b = b1 * t.cos() + b2 * (2.0 * t).cos();
            let base = 2e-6 * (t + 0.4).cos()
                + 0.3e-6 * (5.0 * t).sin()
                + rng.random_range(-0.1e-6..0.1e-6)
                + 1e-8 * k as f64;
            beta.push(b);
            e1.push(base);
            e2.push(base + sep * b);
        }
    }
    let mut out = vec![0.0; n];
    tilt(&e1, &e2, sep, &mut out);
    for (i, (o, b)) in out.iter().zip(&beta).enumerate() {
        close(*o, *b, 1e-12 * (b1 + b2), &format!("β at sample {i}"));
    }
    let r = Revolutions::new(per_rev, out).unwrap();
    let v = values(&r, Direction::Tilt, Direction::Tilt.preferred_centre()).unwrap();
    close(v.synchronous, 2.0 * b2, 1e-12 * (b1 + b2), "LSC tilt value");
    close(
        v.fundamental,
        2.0 * b1,
        1e-12 * (b1 + b2),
        "fundamental tilt",
    );
}

/// Formula (1) and (4) against values worked by hand, and the two closed cases of the digest:
/// T1 (a centred-circle motion `ΔX = e cos θ, ΔY = e sin θ` reads the constant `e` in the RSD)
/// and T3 (structural asymmetry `ΔX = (e−δ) cos θ, ΔY = (e+δ) sin θ` reads `e − δ cos 2θ`, LSC
/// value `2δ`; in the fixed X direction it is the 1-UPR `(e−δ) cos θ`: LSC 0, PC `2(e−δ)`).
#[test]
fn rotating_and_fixed_direction_formulas() {
    let s3 = 3f64.sqrt();
    let s2 = 2f64.sqrt();
    let dx = [3.0, 3.0, 2.0, 2.0, s2];
    let dy = [7.0, 7.0, 5.0, 2.0 * s3, s2];
    let th = [0.0, PI / 2.0, PI, PI / 3.0, -PI / 4.0];
    // 3·1 + 7·0; 3·0 + 7·1; 2·(−1) + 5·0; 2·½ + 2√3·(√3/2) = 4; √2·(√2/2) − √2·(√2/2) = 0.
    let want = [3.0, 7.0, -2.0, 4.0, 0.0];
    let mut out = [0.0; 5];
    rotating_radial(&dx, &dy, &th, &mut out);
    for i in 0..5 {
        close(
            out[i],
            want[i],
            1e-15 * 8.0,
            &format!("formula (1) case {i}"),
        );
    }
    // Fixed direction at 30°: 2·(√3/2) + 4·½ = √3 + 2; at 0 it is ΔX; at 90° it is ΔY.
    let mut f = [0.0; 1];
    fixed_direction(&[2.0], &[4.0], PI / 6.0, &mut f);
    close(f[0], s3 + 2.0, 1e-15 * 8.0, "formula (4) at 30°");
    fixed_direction(&[2.0], &[4.0], 0.0, &mut f);
    assert_eq!(f[0], 2.0);
    fixed_direction(&[2.0], &[4.0], PI / 2.0, &mut f);
    close(f[0], 4.0, 1e-15 * 8.0, "formula (4) at 90°");

    let (e, delta, per_rev, revs) = (10e-6, 0.5e-6, 360, 5);
    let n = per_rev * revs;
    let angles: Vec<f64> = (0..n).map(|i| theta(i % per_rev, per_rev)).collect();
    let tol = 1e-12 * e;
    // T1.
    let cx: Vec<f64> = angles.iter().map(|t| e * t.cos()).collect();
    let cy: Vec<f64> = angles.iter().map(|t| e * t.sin()).collect();
    let mut r1 = vec![0.0; n];
    rotating_radial(&cx, &cy, &angles, &mut r1);
    assert!(r1.iter().all(|v| (v - e).abs() <= tol), "T1: RSD reads e");
    // T3.
    let ax: Vec<f64> = angles.iter().map(|t| (e - delta) * t.cos()).collect();
    let ay: Vec<f64> = angles.iter().map(|t| (e + delta) * t.sin()).collect();
    let mut rsd = vec![0.0; n];
    rotating_radial(&ax, &ay, &angles, &mut rsd);
    for (i, (v, t)) in rsd.iter().zip(&angles).enumerate() {
        close(
            *v,
            e - delta * (2.0 * t).cos(),
            tol,
            &format!("T3 RSD sample {i}"),
        );
    }
    let v = values(
        &Revolutions::new(per_rev, rsd).unwrap(),
        Direction::Radial,
        Centre::Lsc,
    )
    .unwrap();
    close(v.synchronous, 2.0 * delta, tol, "T3 RSD LSC value 2δ");
    let mut fsd = vec![0.0; n];
    fixed_direction(&ax, &ay, 0.0, &mut fsd);
    let fsd = Revolutions::new(per_rev, fsd).unwrap();
    let lsc = values(&fsd, Direction::Radial, Centre::Lsc).unwrap();
    close(lsc.synchronous, 0.0, tol, "T3 FSD-X LSC value");
    let pc = values(&fsd, Direction::Radial, Centre::Pc).unwrap();
    close(pc.synchronous, 2.0 * (e - delta), tol, "T3 FSD-X PC value");
}

/// Resampling jittered, off-grid samples of a known smooth, non-periodic function
/// `f(θ) = a cos(3θ + 0.4) + b sin(0.43θ + 1.1)` recovers it on the grid within the linear
/// interpolation bound `h²/8 · max|f''|`, `max|f''| ≤ 9a + 0.43²·b`, `h` the largest sample
/// spacing. The samples start at 0.3 rad and end at 5.5 turns, so the complete grid
/// revolutions are turns 1 to 4: four revolutions, revolution 0 starting at 2π.
#[test]
fn resample_recovers_a_smooth_function_within_the_interpolation_bound() {
    let (a, b) = (2e-6, 1e-6);
    let f = |t: f64| a * (3.0 * t + 0.4).cos() + b * (0.43 * t + 1.1).sin();
    let f2_max = 9.0 * a + 0.43 * 0.43 * b;
    let h0 = TAU / 500.0;
    let end = TAU * 5.5;
    let mut rng = ChaCha8Rng::from_seed([3; 32]);
    let mut angle = vec![0.3];
    loop {
        let next = angle.last().unwrap() + h0 * rng.random_range(0.4..1.6);
        if next >= end {
            angle.push(end);
            break;
        }
        angle.push(next);
    }
    let signal: Vec<f64> = angle.iter().map(|&t| f(t)).collect();
    let h = angle.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    let bound = h * h / 8.0 * f2_max + 1e-12 * (a + b);

    let per_rev = 64;
    let r = resample(&angle, &signal, per_rev).unwrap();
    assert_eq!(r.count(), 4);
    let mut worst: f64 = 0.0;
    for k in 0..r.count() {
        for (m, v) in r.revolution(k).iter().enumerate() {
            let t = TAU * (1 + k) as f64 + theta(m, per_rev);
            let err = (v - f(t)).abs();
            assert!(
                err <= bound,
                "rev {k} bin {m}: error {err:e} > bound {bound:e}"
            );
            worst = worst.max(err);
        }
    }
    // The bound is not vacuous: it is below a thousandth of the signal.
    assert!(bound < 1e-3 * (a + b), "bound {bound:e}");
    assert!(worst > 0.0);

    // A record sampled exactly on the grid over one revolution comes back unchanged.
    let n = 40;
    let grid: Vec<f64> = (0..n).map(|m| theta(m, n)).collect();
    let vals: Vec<f64> = grid.iter().map(|&t| f(t)).collect();
    let one = resample(&grid, &vals, n).unwrap();
    assert_eq!(one.count(), 1);
    for (m, (g, w)) in one.values().iter().zip(&vals).enumerate() {
        close(*g, *w, 1e-15 * (a + b), &format!("on-grid bin {m}"));
    }
}

/// Bad resampling inputs are errors, not panics.
#[test]
fn resample_rejects_bad_records() {
    let n = 200;
    let angle: Vec<f64> = (0..n).map(|i| TAU * 3.0 * i as f64 / n as f64).collect();
    let signal: Vec<f64> = angle.iter().map(|t| t.sin()).collect();
    assert!(resample(&angle, &signal, 16).is_ok());

    let mut back = angle.clone();
    back[5] = back[3];
    assert_eq!(
        resample(&back, &signal, 16),
        Err(MotionError::NonMonotoneAngle(5)),
        "an angle stepping back"
    );
    let mut flat = angle.clone();
    flat[9] = flat[8];
    assert_eq!(
        resample(&flat, &signal, 16),
        Err(MotionError::NonMonotoneAngle(9))
    );
    let mut nan = signal.clone();
    nan[17] = f64::NAN;
    assert_eq!(resample(&angle, &nan, 16), Err(MotionError::NonFinite(17)));
    let mut nan_angle = angle.clone();
    nan_angle[2] = f64::NAN;
    assert_eq!(
        resample(&nan_angle, &signal, 16),
        Err(MotionError::NonFinite(2))
    );
    assert!(matches!(
        resample(&angle[..10], &signal, 16),
        Err(MotionError::LengthMismatch { .. })
    ));
    // 1.4 turns from 0.5 rad: the grid revolution from 2π is not complete.
    let short: Vec<f64> = (0..100)
        .map(|i| 0.5 + TAU * 1.4 * i as f64 / 100.0)
        .collect();
    assert_eq!(
        resample(&short, &short, 16),
        Err(MotionError::NoCompleteRevolution)
    );
    assert_eq!(
        resample(&angle, &signal, 2),
        Err(MotionError::TooFewSamplesPerRevolution(2))
    );
    assert_eq!(resample(&[], &[], 16), Err(MotionError::Empty));
    // Two samples spanning 10¹² turns: refused, not a 10¹⁴-value allocation.
    assert!(matches!(
        resample(&[0.0, TAU * 1e12], &[0.0, 1.0], 100),
        Err(MotionError::TooLong(_))
    ));
}

/// Layout errors and accessors of `Revolutions`.
#[test]
fn revolutions_layout() {
    assert_eq!(
        Revolutions::new(2, vec![0.0; 4]),
        Err(MotionError::TooFewSamplesPerRevolution(2))
    );
    assert_eq!(Revolutions::new(4, vec![]), Err(MotionError::Empty));
    assert_eq!(
        Revolutions::new(4, vec![0.0; 10]),
        Err(MotionError::PartialRevolution {
            len: 10,
            per_revolution: 4
        })
    );
    let mut v: Vec<f64> = (0..12).map(f64::from).collect();
    v[7] = f64::INFINITY;
    assert_eq!(Revolutions::new(4, v), Err(MotionError::NonFinite(7)));
    let r = Revolutions::new(4, (0..12).map(f64::from).collect()).unwrap();
    assert_eq!(r.count(), 3);
    assert_eq!(r.samples_per_revolution(), 4);
    assert_eq!(r.revolution(1), &[4.0, 5.0, 6.0, 7.0]);
    assert_eq!(r.angles(), vec![0.0, PI / 2.0, PI, 3.0 * PI / 2.0]);
    assert_eq!(r.values().len(), 12);
}

/// Random records: `s = S + A` (to one rounding of the subtraction and addition),
/// `Σ_k A[k, m] = 0`, `I ≤ S ≤ O` (the mean lies between the extremes, to a rounding of the
/// sum); the residual keeps no mean and no 1-UPR part; and the values obey the orderings that
/// follow from the definitions about one centre: synchronous, inner, outer ≤ total (each of
/// those profiles lies inside the pooled cloud at every angle), asynchronous ≤ total (the
/// widest band at one angle is inside the pooled range), and the asynchronous value equals
/// the widest band computed by brute force from the raw samples.
#[test]
fn random_records_satisfy_the_decomposition_identities() {
    let mut rng = ChaCha8Rng::from_seed([11; 32]);
    for trial in 0..20 {
        let per_rev = rng.random_range(3..70);
        let revs = rng.random_range(1..30);
        let amp = 1e-6;
        let h: Vec<(f64, f64)> = (0..5)
            .map(|_| (rng.random_range(-amp..amp), rng.random_range(0.0..TAU)))
            .collect();
        let raw: Vec<f64> = (0..per_rev * revs)
            .map(|i| {
                let t = theta(i % per_rev, per_rev);
                h.iter()
                    .enumerate()
                    .map(|(n, (c, p))| c * (n as f64 * t + p).cos())
                    .sum::<f64>()
                    + rng.random_range(-0.2 * amp..0.2 * amp)
            })
            .collect();
        let r = Revolutions::new(per_rev, raw.clone()).unwrap();
        let d = decompose(&r);
        let eps = f64::EPSILON;
        let peak = raw.iter().fold(0.0, |p: f64, v| p.max(v.abs()));
        for k in 0..revs {
            for m in 0..per_rev {
                let s = raw[k * per_rev + m];
                let (sy, as_) = (d.synchronous[m], d.asynchronous[k * per_rev + m]);
                let tol = 2.0 * eps * (s.abs() + sy.abs());
                assert!((sy + as_ - s).abs() <= tol, "trial {trial}: s ≠ S + A");
            }
        }
        let mut band: f64 = 0.0;
        for m in 0..per_rev {
            let sum: f64 = (0..revs).map(|k| d.asynchronous[k * per_rev + m]).sum();
            assert!(
                sum.abs() <= 1e-12 * amp * revs as f64,
                "trial {trial}: Σ_k A ≠ 0"
            );
            let slack = 8.0 * eps * revs as f64 * peak;
            assert!(
                d.inner[m] <= d.synchronous[m] + slack,
                "trial {trial}: I > S"
            );
            assert!(
                d.synchronous[m] <= d.outer[m] + slack,
                "trial {trial}: S > O"
            );
            let col = (0..revs).map(|k| raw[k * per_rev + m]);
            let lo = col.clone().fold(f64::INFINITY, f64::min);
            let hi = col.fold(f64::NEG_INFINITY, f64::max);
            assert_eq!((lo, hi), (d.inner[m], d.outer[m]), "trial {trial}: I, O");
            band = band.max(hi - lo);
        }
        let (mut rc, mut rs, mut rm) = (0.0, 0.0, 0.0);
        for (m, v) in d.residual.iter().enumerate() {
            let t = theta(m, per_rev);
            rc += v * t.cos();
            rs += v * t.sin();
            rm += v;
        }
        for (name, x) in [("mean", rm), ("cos", rc), ("sin", rs)] {
            assert!(
                x.abs() <= 1e-12 * amp * per_rev as f64,
                "trial {trial}: residual {name}"
            );
        }
        for centre in [Centre::Pc, Centre::Lsc] {
            let v = values(&r, Direction::Radial, centre).unwrap();
            let tol = 1e-12 * amp;
            assert_eq!(v.asynchronous, band, "trial {trial}: asynchronous value");
            for (name, x) in [
                ("synchronous", v.synchronous),
                ("inner", v.inner),
                ("outer", v.outer),
                ("asynchronous", v.asynchronous),
            ] {
                assert!(x <= v.total + tol, "trial {trial} {centre}: {name} > total");
            }
        }
    }
}

/// The spectrum against brute force: the synchronous lines `j = hK` carry exactly the
/// harmonics `h` of the revolution-averaged profile (DFT of `S` summed directly), and the
/// amplitudes satisfy Parseval, `mean(x²) = mean(x)² + Σ_{j<N/2} A_j²/2 (+ A_{N/2}² if N is
/// even)`. Record lengths odd (7 × 45 = 315) and even (6 × 50 = 300), neither a power of two.
#[test]
fn spectrum_matches_brute_force_harmonics_and_parseval() {
    let mut rng = ChaCha8Rng::from_seed([5; 32]);
    for (per_rev, revs) in [(45, 7), (50, 6)] {
        let n = per_rev * revs;
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = theta(i % per_rev, per_rev);
                1e-6 * (0.3 + (2.0 * t).cos() - 0.5 * (7.0 * t + 1.0).sin())
                    + rng.random_range(-0.3e-6..0.3e-6)
            })
            .collect();
        let r = Revolutions::new(per_rev, x.clone()).unwrap();
        let s = spectrum(&r);
        assert_eq!(s.lines.len(), n / 2);
        let sync = decompose(&r).synchronous;
        for hh in 1..=per_rev / 2 {
            let (mut re, mut im) = (0.0, 0.0);
            for (m, v) in sync.iter().enumerate() {
                let p = hh as f64 * theta(m, per_rev);
                re += v * p.cos();
                im -= v * p.sin();
            }
            let c = re.hypot(im) / per_rev as f64;
            let want = if 2 * hh == per_rev { c } else { 2.0 * c };
            let line = s.lines[hh * revs - 1];
            assert!(line.synchronous);
            close(line.per_revolution, hh as f64, 1e-12, "harmonic frequency");
            close(
                line.amplitude,
                want,
                1e-12 * 1e-6,
                &format!("harmonic {hh}"),
            );
        }
        let async_count = s.lines.iter().filter(|l| !l.synchronous).count();
        assert_eq!(async_count, n / 2 - per_rev / 2);

        let mean = x.iter().sum::<f64>() / n as f64;
        let power = x.iter().map(|v| v * v).sum::<f64>() / n as f64;
        let lines: f64 = s
            .lines
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let j = i + 1;
                if 2 * j == n {
                    l.amplitude * l.amplitude
                } else {
                    l.amplitude * l.amplitude / 2.0
                }
            })
            .sum();
        close(mean * mean + lines, power, 1e-12 * power, "Parseval");
    }
}

/// `largest` ranks and filters; `hz` scales UPR by the speed. Lines placed on bins with known
/// amplitudes: 2 UPR (3 µm) and 5 UPR (1 µm) synchronous, 1.5 UPR (2 µm) and 0.25 UPR
/// (0.5 µm) asynchronous, over 4 revolutions of 64.
#[test]
fn largest_lines_and_hertz() {
    let um = 1e-6;
    let r = record(64, 4, |k, t| {
        let u = TAU * k as f64 + t;
        um * (3.0 * (2.0 * u).cos()
            + 1.0 * (5.0 * u + 0.3).sin()
            + 2.0 * (1.5 * u + 1.0).cos()
            + 0.5 * (0.25 * u).sin())
    });
    let s = spectrum(&r);
    let top = s.largest(2, None);
    close(top[0].per_revolution, 2.0, 1e-12, "largest");
    close(top[0].amplitude, 3.0 * um, 1e-12 * um, "largest amplitude");
    close(top[1].per_revolution, 1.5, 1e-12, "second");
    close(top[1].amplitude, 2.0 * um, 1e-12 * um, "second amplitude");
    let sync = s.largest(5, Some(true));
    assert_eq!(sync.len(), 5);
    assert!(sync.iter().all(|l| l.synchronous));
    close(sync[1].per_revolution, 5.0, 1e-12, "second synchronous");
    assert!(sync.windows(2).all(|w| w[0].amplitude >= w[1].amplitude));
    let asy = s.largest(2, Some(false));
    close(asy[0].per_revolution, 1.5, 1e-12, "first asynchronous");
    close(asy[1].per_revolution, 0.25, 1e-12, "second asynchronous");
    close(asy[1].amplitude, 0.5 * um, 1e-12 * um, "cage amplitude");
    assert!(s.largest(0, None).is_empty());
    assert_eq!(s.largest(usize::MAX, None).len(), s.lines.len());
    assert_eq!(s.largest(usize::MAX, Some(true)).len(), 32);
    // 6 000 r/min = 100 rev/s: 2 UPR at 200 Hz, the 0.25-UPR line at 25 Hz.
    close(s.hz(&top[0], 100.0), 200.0, 1e-9, "2 UPR in Hz");
    close(s.hz(&asy[1], 100.0), 25.0, 1e-9, "0.25 UPR in Hz");
}

#[test]
fn values_about_every_centre_agree_with_one_at_a_time_and_pooled_ranges() {
    // values_about decomposes once and takes the total from the contours; the pooled range of
    // every sample about the same offset (polar::range_about over all revolutions) is the
    // definition (§3.8.2), and values() one centre at a time must give the same numbers.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let coefficients: Vec<(f64, f64)> = (0..12)
        .map(|_| (rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5))
        .collect();
    let r = record(256, 7, |k, t| {
        let synchronous: f64 = coefficients
            .iter()
            .enumerate()
            .map(|(h, (a, b))| {
                (a * (h as f64 * t).cos() + b * (h as f64 * t).sin()) / (h + 1) as f64
            })
            .sum();
        synchronous + 0.05 * (TAU * 0.43 * (k as f64 + t / TAU)).sin()
    });
    let all = values_about(&r, Direction::Radial, &Centre::ALL).unwrap();
    for (v, centre) in all.iter().zip(Centre::ALL) {
        let one = values(&r, Direction::Radial, centre).unwrap();
        assert_eq!(v.offset, one.offset, "{centre}");
        let (lo, hi) =
            mtwin::kinds::spindle::analysis::polar::range_about(r.values(), &r.angles(), v.offset);
        // 1e-12: the same sums in another order.
        close(v.total, hi - lo, 1e-12, &format!("{centre} total"));
        close(
            one.total,
            v.total,
            1e-12,
            &format!("{centre} one at a time"),
        );
        close(
            one.synchronous,
            v.synchronous,
            1e-12,
            &format!("{centre} synchronous"),
        );
    }
}

mod own_centres;
