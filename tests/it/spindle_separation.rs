//! Error separation of spindle records (ISO 230-7 Annex B and the multi-probe family):
//! Donaldson and face reversal, multi-probe separation under the two-direction and the
//! single-whirl models, the blind harmonics of a probe layout, tilt from two stations.
//!
//! Every synthetic reading is written here from the geometry, independently of the library:
//! a probe fixed at stator azimuth φ reads `−(E_X cos φ + E_Y sin φ) − h(φ − θ)` (positive when
//! the surface moves away), `h` the artefact's outward form in the rotor frame, `E` the
//! artefact centre's displacement.

use std::f64::consts::{PI, TAU};

use mtwin::kinds::spindle::analysis::separation::{
    Complex, Model, Options, SeparationError, blind_harmonics, blind_with_content,
    condition_numbers, donaldson_reversal, face_reversal, separate, tilt_from_stations,
};
use mtwin::math::{seeded_rng, standard_normal};

type Real = f64;

/// A real Fourier series `Σ a cos(k x + p)` given as `(k, a, p)` terms.
#[derive(Clone, Debug, Default)]
struct Series(Vec<(usize, Real, Real)>);

impl Series {
    fn at(&self, x: Real) -> Real {
        self.0
            .iter()
            .map(|&(k, a, p)| a * (k as Real * x + p).cos())
            .sum()
    }

    /// The complex coefficient `c_k` of `e^{ikx}`: `a cos(kx + p) = (a/2)e^{ip}e^{ikx} + c.c.`.
    fn coefficient(&self, k: usize) -> Complex {
        self.0
            .iter()
            .filter(|t| t.0 == k)
            .map(|&(_, a, p)| Complex::from_polar(0.5 * a, p))
            .sum()
    }

    /// The same series without the listed harmonics.
    fn without(&self, harmonics: &[usize]) -> Series {
        Series(
            self.0
                .iter()
                .copied()
                .filter(|t| !harmonics.contains(&t.0))
                .collect(),
        )
    }
}

/// Deterministic, irregular amplitudes and phases for harmonics `ks`.
fn series(ks: impl Iterator<Item = usize>, scale: Real, seed: Real) -> Series {
    Series(
        ks.map(|k| {
            let kf = k as Real;
            // Amplitudes between 0.5 and 1.5 of scale/√k, phases spread over the circle.
            let a = scale * (1.0 + 0.5 * (seed * kf * 1.7).sin()) / kf.sqrt();
            let p = (seed * 3.1 + kf * 2.39996).rem_euclid(TAU);
            (k, a, p)
        })
        .collect(),
    )
}

fn theta(m: usize, samples: usize) -> Real {
    TAU * m as Real / samples as Real
}

/// A probe at azimuth `phi` on an artefact of rotor-frame form `h`, centre moving by `(ex, ey)`.
fn probe(
    phi: Real,
    samples: usize,
    ex: &Series,
    ey: &Series,
    h: &dyn Fn(Real) -> Real,
) -> Vec<Real> {
    (0..samples)
        .map(|m| {
            let t = theta(m, samples);
            -(ex.at(t) * phi.cos() + ey.at(t) * phi.sin()) - h(phi - t)
        })
        .collect()
}

fn max_abs(v: impl IntoIterator<Item = Real>) -> Real {
    v.into_iter().fold(0.0, |m, x| m.max(x.abs()))
}

// ---------------------------------------------------------------------------------------------
// Reversal
// ---------------------------------------------------------------------------------------------

/// Set-up 1: probe at 0; set-up 2: artefact turned 180° on the rotor (form h(ψ − π) in the
/// rotor frame) and probe at π. Noise-free, so both come back to round-off: the values are
/// ~1e-6 m and the arithmetic is a half-sum, so 1e-12 relative is ~1e4 ulp of margin.
#[test]
fn donaldson_reversal_recovers_motion_and_form() {
    let samples = 1024;
    let ex = series([1, 2, 3, 5, 7, 11, 13, 24].into_iter(), 2e-6, 0.7);
    let ey = series([1, 2, 4, 9].into_iter(), 1.5e-6, 1.9); // must not matter: sin 0 = sin π = 0
    let form = series(2..=30, 80e-9, 0.3);
    let (zero1, zero2) = (3.2e-6, -1.1e-6); // probe zeros differ between set-ups
    let h1 = |psi: Real| form.at(psi);
    let h2 = |psi: Real| form.at(psi - PI);
    let r1: Vec<Real> = probe(0.0, samples, &ex, &ey, &h1)
        .into_iter()
        .map(|r| r + zero1)
        .collect();
    let r2: Vec<Real> = probe(PI, samples, &ex, &ey, &h2)
        .into_iter()
        .map(|r| r + zero2)
        .collect();

    let rev = donaldson_reversal(&r1, &r2).unwrap();
    assert_eq!(rev.motion.len(), samples);
    assert_eq!(rev.form.len(), samples);
    let motion_true: Vec<Real> = (0..samples).map(|m| ex.at(theta(m, samples))).collect();
    let form_true: Vec<Real> = (0..samples).map(|m| form.at(theta(m, samples))).collect();
    let motion_err = max_abs(rev.motion.iter().zip(&motion_true).map(|(a, b)| a - b));
    let form_err = max_abs(rev.form.iter().zip(&form_true).map(|(a, b)| a - b));
    assert!(
        motion_err <= 1e-12 * max_abs(motion_true.iter().copied()),
        "motion {motion_err:e}"
    );
    assert!(
        form_err <= 1e-12 * max_abs(form_true.iter().copied()),
        "form {form_err:e}"
    );
}

/// An artefact mounted off-centre by c at rotor angle α turns with the artefact in the
/// reversal: its centre is at +R(θ)c in set-up 1 and −R(θ)c in set-up 2 (the brief's E includes
/// it). The reversal must give the spindle's own motion as motion and the centring as the
/// form's first harmonic c·cos(ψ − α) (the off-centre circle seen from the axis).
#[test]
fn donaldson_reversal_keeps_artefact_centring_in_the_form() {
    let samples = 360;
    let spindle_x = series([1, 3, 4].into_iter(), 1e-6, 0.2);
    let form = series(2..=12, 50e-9, 1.1);
    let (c, alpha) = (4e-6, 0.6);
    let r = |setup: Real, phi: Real, m: usize| {
        let t = theta(m, samples);
        // Centre of the artefact: spindle motion ± the rotated offset.
        let ex = spindle_x.at(t) + setup * c * (t + alpha).cos();
        let ey = setup * c * (t + alpha).sin();
        let h = if setup > 0.0 {
            form.at(phi - t)
        } else {
            form.at(phi - t - PI)
        };
        -(ex * phi.cos() + ey * phi.sin()) - h
    };
    let r1: Vec<Real> = (0..samples).map(|m| r(1.0, 0.0, m)).collect();
    let r2: Vec<Real> = (0..samples).map(|m| r(-1.0, PI, m)).collect();
    let rev = donaldson_reversal(&r1, &r2).unwrap();
    for m in 0..samples {
        let t = theta(m, samples);
        assert!((rev.motion[m] - spindle_x.at(t)).abs() <= 1e-12 * 4e-6);
        let expected = form.at(t) + c * (t - alpha).cos();
        assert!((rev.form[m] - expected).abs() <= 1e-12 * 4e-6, "m {m}");
    }
}

/// Face reversal on a face of outward normal +z probed at radius R from above. The face point
/// at azimuth φ moves by d = T + ω × p (p = (R cos φ, R sin φ, 0), ω = (E_A, E_B, 0)), computed
/// here with the cross product; the probe reads −d_z − g(φ − θ). The reversing part must be
/// −R·E_B, the form with the on-axis record g, without it g(ψ) + E_Z(−ψ).
#[test]
fn face_reversal_separates_tilt_form_and_axial() {
    let samples = 512;
    let radius = 0.02;
    let ez = series([1, 2, 5].into_iter(), 0.3e-6, 0.4);
    let ea = series([1, 2, 3].into_iter(), 2e-6, 1.3); // rad
    let eb = series([1, 3, 6].into_iter(), 3e-6, 2.1); // rad
    let face = series(2..=20, 40e-9, 0.9);
    let dz = |phi: Real, t: Real| {
        let p = [radius * phi.cos(), radius * phi.sin(), 0.0];
        let w = [ea.at(t), eb.at(t), 0.0];
        ez.at(t) + (w[0] * p[1] - w[1] * p[0]) // z of T + ω × p
    };
    let r1: Vec<Real> = (0..samples)
        .map(|m| {
            let t = theta(m, samples);
            -dz(0.0, t) - face.at(-t)
        })
        .collect();
    let r2: Vec<Real> = (0..samples)
        .map(|m| {
            let t = theta(m, samples);
            // Artefact turned 180°: its form is g(ψ − π); the probe at π sees ψ = π − θ.
            -dz(PI, t) - face.at(PI - t - PI)
        })
        .collect();
    let axial: Vec<Real> = (0..samples)
        .map(|m| -ez.at(theta(m, samples)) + 7e-6)
        .collect();

    let with = face_reversal(&r1, &r2, Some(&axial)).unwrap();
    let without = face_reversal(&r1, &r2, None).unwrap();
    assert!(with.axial_removed && !without.axial_removed);
    let scale = 1e-7;
    for m in 0..samples {
        let t = theta(m, samples);
        assert!((with.tilt[m] - (-radius * eb.at(t))).abs() <= 1e-12 * scale);
        assert!((with.form[m] - face.at(t)).abs() <= 1e-12 * scale, "m {m}");
        assert!((without.form[m] - (face.at(t) + ez.at(-t))).abs() <= 1e-12 * scale);
    }
}

/// A rigid small motion: translation T(θ) and rotation ω(θ) = (E_A, E_B, 0). The axis point at
/// height z moves by T + ω × (0, 0, z), written out here with the cross product.
#[test]
fn tilt_from_two_stations() {
    let samples = 256;
    let tx = series([1, 2].into_iter(), 1e-6, 0.1);
    let ty = series([1, 3].into_iter(), 1e-6, 0.5);
    let ea = series([1, 2, 4].into_iter(), 5e-6, 0.8);
    let eb = series([1, 5].into_iter(), 4e-6, 1.6);
    let (z1, z2) = (0.01, 0.09);
    let at = |z: Real| -> (Vec<Real>, Vec<Real>) {
        (0..samples)
            .map(|m| {
                let t = theta(m, samples);
                let w = [ea.at(t), eb.at(t), 0.0];
                let p = [0.0, 0.0, z];
                let cross = [w[1] * p[2] - w[2] * p[1], w[2] * p[0] - w[0] * p[2]];
                (tx.at(t) + cross[0], ty.at(t) + cross[1])
            })
            .unzip()
    };
    let (x1, y1) = at(z1);
    let (x2, y2) = at(z2);
    let tilt = tilt_from_stations((&x1, &y1), (&x2, &y2), z1, z2).unwrap();
    for m in 0..samples {
        let t = theta(m, samples);
        // Motions ~1e-6 m over 0.08 m: differences lose ~1e-16·1e-6/0.08 ≈ 1e-21 rad.
        assert!((tilt.about_x[m] - ea.at(t)).abs() <= 1e-12 * 5e-6);
        assert!((tilt.about_y[m] - eb.at(t)).abs() <= 1e-12 * 5e-6);
    }
}

// ---------------------------------------------------------------------------------------------
// Multi-probe separation
// ---------------------------------------------------------------------------------------------

fn deg(d: Real) -> Real {
    d.to_radians()
}

/// Known form k = 2..40 and an elliptical error motion (X and Y with different amplitudes and
/// phases per harmonic, 1..40) on two unequal layouts: every non-blind harmonic comes back.
/// Tolerance 1e-9 relative to each harmonic's own amplitude: the round-off in a coefficient is
/// about 1e-16 × (signal RMS / that amplitude ≤ 1e2) × condition (≤ 1e3) ≈ 1e-11.
#[test]
fn two_direction_model_recovers_elliptical_motion_and_form() {
    let samples = 2048;
    let form = series(2..=40, 100e-9, 0.37);
    let ex = series(1..=40, 0.5e-6, 1.23);
    let ey = series(1..=40, 0.3e-6, 2.71);
    let layouts: [&[Real]; 2] = [&[0.0, deg(99.8), deg(202.5)], &[0.0, 1.0, PI, 3.8]];
    for azimuths in layouts {
        let readings: Vec<Vec<Real>> = azimuths
            .iter()
            .map(|&phi| probe(phi, samples, &ex, &ey, &|psi| form.at(psi)))
            .collect();
        let sep = separate(&readings, azimuths, Model::TwoDirection, Options::default()).unwrap();
        assert_eq!(sep.k_max, samples / 2 - 1);
        // Most harmonics must be seen, or the recovery check below would be vacuous.
        let blind_low: Vec<usize> = sep.blind.iter().copied().filter(|&k| k <= 40).collect();
        assert!(blind_low.len() <= 3, "{azimuths:?}: blind {blind_low:?}");
        for k in 1..=40 {
            if sep.blind.contains(&k) {
                assert_eq!(sep.form_spectrum[k], Complex::new(0.0, 0.0));
                assert_eq!(sep.motion_x_spectrum[k], Complex::new(0.0, 0.0));
                continue;
            }
            for (what, got, want) in [
                ("X", sep.motion_x_spectrum[k], ex.coefficient(k)),
                ("Y", sep.motion_y_spectrum[k], ey.coefficient(k)),
                ("H", sep.form_spectrum[k], form.coefficient(k)),
            ] {
                // At k = 1 the form is zero by convention and must come back exactly zero.
                assert!(
                    (got - want).norm() <= 1e-9 * want.norm(),
                    "{azimuths:?} k {k} {what}: got {got}, want {want}"
                );
            }
        }
        // Nothing injected above 40: estimates there are round-off.
        let floor = 1e-12 * 0.5e-6;
        for k in 41..=sep.k_max {
            assert!(sep.form_spectrum[k].norm() <= floor, "k {k}");
            assert!(sep.motion_x_spectrum[k].norm() <= floor, "k {k}");
            assert!(sep.motion_y_spectrum[k].norm() <= floor, "k {k}");
        }
        // Time domain: the truth without its blind harmonics.
        let (f, x, y) = (
            form.without(&sep.blind),
            ex.without(&sep.blind),
            ey.without(&sep.blind),
        );
        for m in 0..samples {
            let t = theta(m, samples);
            assert!((sep.form[m] - f.at(t)).abs() <= 1e-9 * 100e-9);
            assert!((sep.motion_x[m] - x.at(t)).abs() <= 1e-9 * 0.5e-6);
            assert!((sep.motion_y[m] - y.at(t)).abs() <= 1e-9 * 0.5e-6);
        }
        // Consistent data: nothing unexplained (a real check for the 4-probe layout, which has
        // one redundant equation per harmonic).
        assert!(
            sep.residual_rms <= 1e-12 * 0.5e-6,
            "residual {:e}",
            sep.residual_rms
        );
    }
}

/// The form's first harmonic (the artefact's centring, c·cos(ψ − α)) cannot be told from the
/// fundamental motion; by convention it is the motion: a probe sees −c·cos(φ − θ − α), the same
/// as a centre at c·(cos(θ + α), sin(θ + α)).
#[test]
fn form_first_harmonic_is_assigned_to_the_motion() {
    let samples = 256;
    let (c, alpha) = (3e-6, 0.9);
    let form = Series(vec![(1, c, -alpha), (2, 50e-9, 0.3), (5, 20e-9, 1.0)]);
    let zero = Series::default();
    let azimuths = [0.0, 1.0, PI, 3.8];
    for model in [Model::TwoDirection, Model::SingleWhirl] {
        let readings: Vec<Vec<Real>> = azimuths
            .iter()
            .map(|&phi| probe(phi, samples, &zero, &zero, &|psi| form.at(psi)))
            .collect();
        let sep = separate(&readings, &azimuths, model, Options::default()).unwrap();
        assert!(sep.blind.is_empty());
        assert_eq!(sep.form_spectrum[1], Complex::new(0.0, 0.0));
        for m in 0..samples {
            let t = theta(m, samples);
            assert!((sep.motion_x[m] - c * (t + alpha).cos()).abs() <= 1e-12 * c);
            assert!((sep.motion_y[m] - c * (t + alpha).sin()).abs() <= 1e-12 * c);
            assert!((sep.form[m] - form.without(&[1]).at(t)).abs() <= 1e-12 * c);
        }
    }
}

/// Least squares of `b` on two complex columns `u`, `v` by the normal equations and Cramer's
/// rule — a different algorithm from the library's scaled SVD.
fn lstsq2(u: &[Complex], v: &[Complex], b: &[Complex]) -> (Complex, Complex) {
    let dot = |a: &[Complex], c: &[Complex]| -> Complex {
        a.iter().zip(c).map(|(x, y)| x.conj() * y).sum()
    };
    let (uu, uv, vu, vv) = (dot(u, u), dot(u, v), dot(v, u), dot(v, v));
    let (ub, vb) = (dot(u, b), dot(v, b));
    let det = uu * vv - uv * vu;
    ((ub * vv - uv * vb) / det, (uu * vb - vu * ub) / det)
}

/// A pure-X 3-UPR motion x = a·cos 3θ, y = 0 is half forward, half backward whirl. The
/// single-whirl model holds only the forward one and leaks the rest into the form (the
/// anchors report 0.45 of the amplitude on pyOutRun's layout); the two-direction model
/// recovers it with no form at all.
#[test]
fn single_whirl_model_leaks_a_non_circular_motion_into_the_form() {
    let samples = 720;
    let a = 1e-6;
    let ex = Series(vec![(3, a, 0.0)]);
    let zero = Series::default();
    let azimuths = [0.0, 1.0, PI, 3.8];
    let readings: Vec<Vec<Real>> = azimuths
        .iter()
        .map(|&phi| probe(phi, samples, &ex, &zero, &|_| 0.0))
        .collect();

    let single = separate(&readings, &azimuths, Model::SingleWhirl, Options::default()).unwrap();
    let leak = 2.0 * single.form_spectrum[3].norm(); // peak amplitude of the 3-lobe form
    assert!(leak > 0.1 * a, "leak {:.3} of the amplitude", leak / a);
    // The anchors' own numpy re-implementation found 0.45 on this layout (two digits quoted).
    assert!((leak / a - 0.45).abs() < 0.005, "leak {:.4}", leak / a);
    assert!(
        single.residual_rms > 0.01 * a,
        "residual {:e}",
        single.residual_rms
    );

    // The same fit done by hand: R_j3 = −X_3 cos φ_j with X_3 = a/2, columns −e^{−iφ_j} (the
    // forward whirl) and −e^{−3iφ_j} (the form coefficient H_{−3}); H_3 = conj(H_{−3}).
    let u: Vec<Complex> = azimuths
        .iter()
        .map(|&p| -Complex::from_polar(1.0, -p))
        .collect();
    let v: Vec<Complex> = azimuths
        .iter()
        .map(|&p| -Complex::from_polar(1.0, -3.0 * p))
        .collect();
    let b: Vec<Complex> = azimuths
        .iter()
        .map(|&p| Complex::new(-0.5 * a * p.cos(), 0.0))
        .collect();
    let (whirl, g) = lstsq2(&u, &v, &b);
    assert!((single.form_spectrum[3] - g.conj()).norm() <= 1e-9 * a);
    assert!((single.motion_x_spectrum[3] - whirl).norm() <= 1e-9 * a);
    assert!((single.motion_y_spectrum[3] - (-Complex::i() * whirl)).norm() <= 1e-9 * a);

    let general = separate(
        &readings,
        &azimuths,
        Model::TwoDirection,
        Options::default(),
    )
    .unwrap();
    assert!(max_abs(general.form.iter().copied()) <= 1e-12 * a);
    assert!(max_abs(general.motion_y.iter().copied()) <= 1e-12 * a);
    for m in 0..samples {
        assert!((general.motion_x[m] - ex.at(theta(m, samples))).abs() <= 1e-12 * a);
    }
}

/// Noise of σ on each probe, independent: each complex Fourier coefficient has E|c|² = σ²/M,
/// and a least-squares fit of P equations with n unknowns leaves (P − n) of those P degrees
/// of freedom, so E[residual²] = (2/(P M)) Σ_k (P − n_k) σ² over the harmonics estimated
/// (n_1 = 2, n_k = 3). About 4000 real degrees of freedom: the RMS scatters by ~1.1 %; 5 %
/// is the tolerance.
#[test]
fn residual_rms_follows_the_redundancy() {
    let samples = 4096;
    let sigma = 10e-9;
    let mut rng = seeded_rng(7, "spindle-separation-noise");
    let form = series(2..=20, 100e-9, 0.5);
    let ex = series(1..=10, 0.5e-6, 0.8);
    let ey = series(1..=10, 0.2e-6, 1.4);
    let noisy = |azimuths: &[Real], rng: &mut _| -> Vec<Vec<Real>> {
        azimuths
            .iter()
            .map(|&phi| {
                probe(phi, samples, &ex, &ey, &|psi| form.at(psi))
                    .into_iter()
                    .map(|r| r + sigma * standard_normal(rng))
                    .collect()
            })
            .collect()
    };
    let four = [0.0, 1.0, PI, 3.8];
    let sep = separate(
        &noisy(&four, &mut rng),
        &four,
        Model::TwoDirection,
        Options::default(),
    )
    .unwrap();
    let p = four.len() as Real;
    let seen_above_1 = (2..=sep.k_max).filter(|k| !sep.blind.contains(k)).count() as Real;
    let expected_ms =
        2.0 * sigma * sigma / (p * samples as Real) * ((p - 2.0) + seen_above_1 * (p - 3.0));
    let ratio = sep.residual_rms / expected_ms.sqrt();
    assert!((ratio - 1.0).abs() < 0.05, "ratio {ratio}");

    // Three probes: square at k ≥ 2, so only the fundamental (unknowns X_1, Y_1, three
    // equations) leaves a residual: the component of the k = 1 coefficients b_j along
    // w = (cos φ_j) × (sin φ_j), the real vector orthogonal to both columns, i.e.
    // ‖r_1‖ = |w·b| / ‖w‖, and residual_rms = √(2/P)·‖r_1‖ (Parseval).
    let three = [0.0, deg(99.8), deg(202.5)];
    let readings3 = noisy(&three, &mut rng);
    let sep3 = separate(&readings3, &three, Model::TwoDirection, Options::default()).unwrap();
    let c: Vec<Real> = three.iter().map(|p| p.cos()).collect();
    let s: Vec<Real> = three.iter().map(|p| p.sin()).collect();
    let w = [
        c[1] * s[2] - c[2] * s[1],
        c[2] * s[0] - c[0] * s[2],
        c[0] * s[1] - c[1] * s[0],
    ];
    let b1: Vec<Complex> = readings3
        .iter()
        .map(|r| {
            r.iter()
                .enumerate()
                .map(|(m, &x)| Complex::from_polar(x, -theta(m, samples)))
                .sum::<Complex>()
                / samples as Real
        })
        .collect();
    let wb: Complex = w.iter().zip(&b1).map(|(wi, bi)| bi * *wi).sum();
    let wn = w.iter().map(|x| x * x).sum::<Real>().sqrt();
    let expected3 = (2.0 / 3.0 as Real).sqrt() * wb.norm() / wn;
    assert!(
        (sep3.residual_rms - expected3).abs() <= 1e-9 * expected3,
        "{:e} vs {expected3:e}",
        sep3.residual_rms
    );
}

// ---------------------------------------------------------------------------------------------
// Blind harmonics
// ---------------------------------------------------------------------------------------------

fn det3(m: [[Complex; 3]; 3]) -> Complex {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Probes at 0, 120°, 240°. Since cos φ = (e^{iφ} + e^{−iφ})/2 and sin φ = (e^{iφ} − e^{−iφ})/2i,
/// the two-direction columns span the same space as e^{iφ_j}, e^{−iφ_j}, e^{−ikφ_j}. On three
/// equally spaced probes the vectors (e^{iqφ_j})_j depend only on q mod 3 and are orthogonal
/// for different residues, so the design is singular unless −k ≢ ±1, i.e. blind at every
/// k ≢ 0 (mod 3); for k ≡ 0 the scaled columns are orthonormal and the condition number is 1.
/// Single whirl (columns e^{−iφ_j}, e^{−ikφ_j}): singular iff −k ≡ −1, i.e. k ≡ 1 (mod 3).
/// The rule is also checked against the determinant computed here by cofactors.
#[test]
fn equal_spacing_blind_rules() {
    let k_max = 100;
    let azimuths = [0.0, TAU / 3.0, 2.0 * TAU / 3.0];
    let two = blind_harmonics(&azimuths, Model::TwoDirection, k_max, 1e3);
    let single = blind_harmonics(&azimuths, Model::SingleWhirl, k_max, 1e3);
    let rule_two: Vec<usize> = (2..=k_max).filter(|k| k % 3 != 0).collect();
    let rule_single: Vec<usize> = (2..=k_max).filter(|k| k % 3 == 1).collect();
    assert_eq!(two, rule_two);
    assert_eq!(single, rule_single);

    let e = |q: Real, phi: Real| Complex::from_polar(1.0, q * phi);
    let singular_by_det: Vec<usize> = (2..=k_max)
        .filter(|&k| {
            let rows: Vec<[Complex; 3]> = azimuths
                .iter()
                .map(|&p| [e(1.0, p), e(-1.0, p), e(-(k as Real), p)])
                .collect();
            let d = det3([rows[0], rows[1], rows[2]]).norm();
            // Non-singular: |det| of the Vandermonde of the cube roots of unity, 3^{3/2}.
            assert!(
                d < 1e-9 || (d - 27f64.sqrt()).abs() < 1e-9,
                "k {k}: |det| {d}"
            );
            d < 1e-9
        })
        .collect();
    assert_eq!(two, singular_by_det);

    let cond = condition_numbers(&azimuths, Model::TwoDirection, k_max);
    for k in (3..=k_max).step_by(3) {
        assert!((cond[k] - 1.0).abs() < 1e-12, "k {k}: {}", cond[k]);
    }
}

/// Probes at 0, 90°, 225°, single whirl. Two columns u = (e^{−iφ_j}), v = (e^{−ikφ_j}) of
/// norm √3: after scaling the Gram matrix is [[1, ρ], [ρ̄, 1]] with
/// |ρ| = |Σ_j e^{i(1−k)φ_j}| / 3, so κ = √((1 + |ρ|)/(1 − |ρ|)) and the design is singular iff
/// all (k − 1)φ_j agree mod 2π: (k − 1)·90° and (k − 1)·225° multiples of 360°, i.e.
/// k ≡ 1 (mod 8): blind at 9, 17, 25, … as the anchors report.
#[test]
fn zero_ninety_225_blind_harmonics() {
    let k_max = 100;
    let azimuths = [0.0, deg(90.0), deg(225.0)];
    let blind = blind_harmonics(&azimuths, Model::SingleWhirl, k_max, 1e3);
    let rule: Vec<usize> = (2..=k_max).filter(|k| k % 8 == 1).collect();
    assert_eq!(blind, rule);
    assert_eq!(&blind[..3], &[9, 17, 25]);

    // Two-direction model on the same layout (square, three unknowns): e^{−ikφ_j} equals
    // e^{−iφ_j} when k ≡ 1 and e^{+iφ_j} when k ≡ −1 (mod 8), so it is blind at k ≡ ±1 (mod 8),
    // 24 harmonics up to 100 as the anchors count; the cofactor determinant confirms that no
    // other k is singular.
    let two = blind_harmonics(&azimuths, Model::TwoDirection, k_max, 1e3);
    let rule_two: Vec<usize> = (2..=k_max).filter(|k| k % 8 == 1 || k % 8 == 7).collect();
    assert_eq!(two, rule_two);
    assert_eq!(two.len(), 24);
    let e = |q: Real, phi: Real| Complex::from_polar(1.0, q * phi);
    for k in 2..=k_max {
        let rows: Vec<[Complex; 3]> = azimuths
            .iter()
            .map(|&p| [e(1.0, p), e(-1.0, p), e(-(k as Real), p)])
            .collect();
        let d = det3([rows[0], rows[1], rows[2]]).norm();
        assert_eq!(d < 1e-9, rule_two.contains(&k), "k {k}: |det| {d}");
    }

    let cond = condition_numbers(&azimuths, Model::SingleWhirl, k_max);
    assert_eq!(cond.len(), k_max + 1);
    for (k, &cond_k) in cond.iter().enumerate().skip(2) {
        let rho = azimuths
            .iter()
            .map(|&p| Complex::from_polar(1.0, (1.0 - k as Real) * p))
            .sum::<Complex>()
            .norm()
            / 3.0;
        if k % 8 == 1 {
            assert!((rho - 1.0).abs() < 1e-12);
            assert!(cond_k > 1e12, "k {k}: {cond_k}");
        } else {
            let closed = ((1.0 + rho) / (1.0 - rho)).sqrt();
            assert!(
                (cond_k / closed - 1.0).abs() < 1e-9,
                "k {k}: {cond_k} vs {closed}"
            );
        }
    }
}

/// A raised limit turns blind harmonics back on only when their condition number allows it,
/// and probes all on one line (sin φ_j = 0) cannot even see E_Y: harmonic 1 is blind too.
#[test]
fn limit_and_degenerate_layouts() {
    let azimuths = [0.0, deg(99.8), deg(202.5)];
    let cond = condition_numbers(&azimuths, Model::TwoDirection, 60);
    for limit in [10.0, 1e2, 1e3] {
        let expect: Vec<usize> = (1..=60)
            .filter(|&k| cond[k].is_nan() || cond[k] > limit)
            .collect();
        assert_eq!(
            blind_harmonics(&azimuths, Model::TwoDirection, 60, limit),
            expect
        );
    }
    let collinear = [0.0, PI, 0.0];
    let blind = blind_harmonics(&collinear, Model::TwoDirection, 10, 1e3);
    assert_eq!(blind, (1..=10).collect::<Vec<_>>());
    // Two probes: fewer equations than unknowns at every harmonic from 2.
    let two = blind_harmonics(&[0.0, 1.0], Model::TwoDirection, 10, 1e3);
    assert_eq!(two, (2..=10).collect::<Vec<_>>());
}

// ---------------------------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------------------------

#[test]
fn bad_input_is_an_error() {
    let ok = vec![0.0; 64];
    let az = [0.0, 1.0, 2.5];
    let three = vec![ok.clone(), ok.clone(), ok.clone()];
    let opts = Options::default();
    let m = Model::TwoDirection;

    assert!(matches!(
        separate(&three[..2], &az[..2], m, opts),
        Err(SeparationError::TooFewProbes(2))
    ));
    assert!(matches!(
        separate(&three, &az[..2], m, opts),
        Err(SeparationError::LengthMismatch { .. })
    ));
    let ragged = vec![ok.clone(), ok.clone(), vec![0.0; 63]];
    assert!(matches!(
        separate(&ragged, &az, m, opts),
        Err(SeparationError::LengthMismatch { .. })
    ));
    let mut nan = three.clone();
    nan[1][5] = Real::NAN;
    assert!(matches!(
        separate(&nan, &az, m, opts),
        Err(SeparationError::NotFinite { index: 5, .. })
    ));
    assert!(matches!(
        separate(&three, &[0.0, Real::NAN, 2.0], m, opts),
        Err(SeparationError::NotFinite { .. })
    ));
    let tiny = vec![vec![0.0; 4]; 3];
    assert!(matches!(
        separate(&tiny, &az, m, opts),
        Err(SeparationError::TooFewSamples { samples: 4, .. })
    ));
    for k_max in [1, 32, 40] {
        let o = Options {
            k_max: Some(k_max),
            ..opts
        };
        assert!(matches!(
            separate(&three, &az, m, o),
            Err(SeparationError::HarmonicRange { .. })
        ));
    }
    assert!(
        separate(
            &three,
            &az,
            m,
            Options {
                k_max: Some(31),
                ..opts
            }
        )
        .is_ok()
    );
    for limit in [Real::NAN, Real::INFINITY, 0.5] {
        let o = Options {
            condition_limit: limit,
            ..opts
        };
        assert!(matches!(
            separate(&three, &az, m, o),
            Err(SeparationError::BadLimit(_))
        ));
    }

    assert!(matches!(
        donaldson_reversal(&ok, &ok[..10]),
        Err(SeparationError::LengthMismatch { .. })
    ));
    assert!(matches!(
        donaldson_reversal(&[], &[]),
        Err(SeparationError::TooFewSamples { .. })
    ));
    assert!(matches!(
        donaldson_reversal(&ok, &nan[1]),
        Err(SeparationError::NotFinite {
            what: "setup2",
            index: 5
        })
    ));
    assert!(matches!(
        face_reversal(&ok, &ok, Some(&ok[..3])),
        Err(SeparationError::LengthMismatch { .. })
    ));
    assert!(matches!(
        tilt_from_stations((&ok, &ok), (&ok, &ok), 0.1, 0.1),
        Err(SeparationError::Stations(..))
    ));
    assert!(matches!(
        tilt_from_stations((&ok, &ok), (&ok, &ok[..3]), 0.0, 0.1),
        Err(SeparationError::LengthMismatch { .. })
    ));
    // Errors render a message naming the problem.
    assert!(
        SeparationError::TooFewProbes(2)
            .to_string()
            .contains("at least 3")
    );
}

/// Three probes of 256 samples with 1 nm of noise, blind at 2, 4 and 5: a 5 nm tone at 4 UPR
/// in one probe is flagged in every record, and noise alone flags a harmonic in at most about
/// 5 % of 400 (200 noise-only records, and the other harmonics of 200 with the tone): the
/// threshold's promise, with room for the binomial spread (40 of 400 would be 4.6 σ over 5 %).
#[test]
fn blind_harmonics_with_content_are_told_from_noise() {
    let m = 256;
    let sigma = 1e-9;
    let mut rng = seeded_rng(11, "blind-content-noise");
    let blind = [2, 4, 5];
    let mut false_alarms = 0;
    for _ in 0..200 {
        let noise: Vec<Vec<Real>> = (0..3)
            .map(|_| (0..m).map(|_| sigma * standard_normal(&mut rng)).collect())
            .collect();
        if !blind_with_content(&noise, &blind).is_empty() {
            false_alarms += 1;
        }
        let mut tone = noise.clone();
        for (i, v) in tone[1].iter_mut().enumerate() {
            *v += 5e-9 * (4.0 * TAU * i as Real / m as Real + 0.3).cos();
        }
        let flagged = blind_with_content(&tone, &blind);
        assert!(flagged.contains(&4), "{flagged:?}");
        if flagged.iter().any(|&k| k != 4) {
            false_alarms += 1;
        }
    }
    println!("{false_alarms} of 400 records flagged a blind harmonic with noise alone");
    assert!(
        false_alarms <= 40,
        "{false_alarms} of 400 records flagged a harmonic with noise alone"
    );
}
