//! ISO 230-7 polar-plot centres (PC, LSC, MRS, MIC, MCC) and values, checked against closed
//! forms, the alternation and KKT conditions, brute-force vertex enumeration and an
//! independent least-squares solve (nalgebra).
//!
//! Profiles are in metres at the µm scale of real spindles. "Relative" tolerances are relative
//! to the profile's largest value; the solver's own pricing tolerance is 1e-13 of it, and
//! residual rounding about 1e-16 of it.

use std::f64::consts::{PI, TAU};

use mtwin::kinds::spindle::analysis::polar::{
    self, Angles, Centre, CentreFit, MAX_ANGLE_GAP, PolarError,
};
use mtwin::math::{Real, seeded_rng};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix4, Vector3, Vector4};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

const UM: Real = 1e-6;

fn equal_angles(m: usize) -> Vec<Real> {
    (0..m).map(|i| TAU * i as Real / m as Real).collect()
}

/// Full-circle angles, each jittered by up to ±0.45 of the spacing (gaps < 2 spacings).
fn irregular_angles(rng: &mut ChaCha8Rng, m: usize) -> Vec<Real> {
    (0..m)
        .map(|i| TAU * (i as Real + rng.random_range(-0.45..0.45)) / m as Real)
        .collect()
}

/// Sorted random angles on `[start, start + arc]`, both ends included.
fn arc_angles(rng: &mut ChaCha8Rng, m: usize, start: Real, arc: Real) -> Vec<Real> {
    let mut a: Vec<Real> = (0..m - 2).map(|_| rng.random_range(0.0..arc)).collect();
    a.push(0.0);
    a.push(arc);
    a.sort_by(|x, y| x.total_cmp(y));
    a.iter().map(|x| start + x).collect()
}

/// A synchronous-like profile: harmonics 2–15 with random amplitudes (≤ 1 µm / k^0.5) and
/// phases, plus a random offset.
fn random_profile(rng: &mut ChaCha8Rng, angles: &[Real]) -> Vec<Real> {
    let harmonics: Vec<(Real, Real, Real)> = (2..=15)
        .map(|k| {
            (
                k as Real,
                rng.random_range(0.0..1.0) * UM / (k as Real).sqrt(),
                rng.random_range(0.0..TAU),
            )
        })
        .collect();
    let dc = rng.random_range(-2.0..2.0) * UM;
    angles
        .iter()
        .map(|&t| {
            dc + harmonics
                .iter()
                .map(|&(k, a, phi)| a * (k * t + phi).cos())
                .sum::<Real>()
        })
        .collect()
}

/// A π-periodic profile (harmonics 2, 4, 6, 8 only): on an even number of equally spaced
/// angles the antipodal samples are equal, which makes MCC and MIC optima segments.
fn random_even_profile(rng: &mut ChaCha8Rng, angles: &[Real]) -> Vec<Real> {
    let harmonics: Vec<(Real, Real, Real)> = [2.0, 4.0, 6.0, 8.0]
        .into_iter()
        .map(|k| {
            (
                k,
                rng.random_range(0.0..1.0) * UM,
                rng.random_range(0.0..TAU),
            )
        })
        .collect();
    angles
        .iter()
        .map(|&t| {
            harmonics
                .iter()
                .map(|&(k, a, phi)| a * (k * t + phi).cos())
                .sum()
        })
        .collect()
}

fn scale(p: &[Real]) -> Real {
    p.iter().fold(0.0, |m: Real, v| m.max(v.abs()))
}

fn fit(p: &[Real], angles: &[Real], centre: Centre) -> CentreFit {
    polar::fit(p, angles, centre).unwrap_or_else(|e| panic!("{centre}: {e}"))
}

/// Residuals about an offset, computed here independently of the module.
fn residuals(p: &[Real], angles: &[Real], c: [Real; 2]) -> Vec<Real> {
    p.iter()
        .zip(angles)
        .map(|(v, t)| v - c[0] * t.cos() - c[1] * t.sin())
        .collect()
}

fn range(r: &[Real]) -> (Real, Real) {
    r.iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        })
}

/// Brute force for MCC (`sigma = 1`) or MIC (`sigma = −1`): every vertex of the LP
/// `min t s.t. t ≥ σρ_c[m]` is fixed by 3 points with equal `σρ`; solve each triple, keep the
/// feasible ones, take the smallest `t`. Returns `t*` and the centres of all optimal vertices
/// (within 1e-12 of the scale): one centre unless the optimum is a segment.
fn brute_one_sided(p: &[Real], angles: &[Real], sigma: Real) -> (Real, Vec<[Real; 2]>) {
    let m = p.len();
    let tol = 1e-12 * scale(p);
    let mut vertices = Vec::new();
    for i in 0..m {
        for j in i + 1..m {
            for k in j + 1..m {
                let row = |n: usize| [1.0, sigma * angles[n].cos(), sigma * angles[n].sin()];
                let (ri, rj, rk) = (row(i), row(j), row(k));
                let a = Matrix3::new(
                    ri[0], ri[1], ri[2], rj[0], rj[1], rj[2], rk[0], rk[1], rk[2],
                );
                let b = Vector3::new(sigma * p[i], sigma * p[j], sigma * p[k]);
                let Some(x) = a.lu().solve(&b) else { continue };
                let (t, c) = (x[0], [x[1], x[2]]);
                if !t.is_finite() {
                    continue;
                }
                let worst = residuals(p, angles, c)
                    .iter()
                    .fold(Real::NEG_INFINITY, |w, r| w.max(sigma * r));
                if worst <= t + tol {
                    vertices.push((t, c));
                }
            }
        }
    }
    let best = vertices.iter().fold(Real::INFINITY, |b, v| b.min(v.0));
    let centres = vertices
        .into_iter()
        .filter(|v| v.0 <= best + tol)
        .map(|v| v.1)
        .collect();
    (best, centres)
}

/// Brute force for the MCC/MIC tie-break: the largest `l` with `σρ_c[m] ≥ l` for all m among
/// the centres with `σρ_c[m] ≤ t*` for all m. Every vertex of this LP in `(cx, cy, l)` is
/// fixed by 3 tight constraints, each either an upper one (`σρ_c[m] = t*`) or a lower one
/// (`σρ_c[m] = l`); enumerate all triples, keep the feasible, take the largest `l`. Returns
/// the value `t* − l*`.
fn brute_tie_break(p: &[Real], angles: &[Real], sigma: Real, t_star: Real) -> Real {
    let m = p.len();
    let tol = 1e-12 * scale(p);
    // Constraint 2n (lower): σp_n − σu_n·c − l = 0; 2n+1 (upper): σp_n − σu_n·c = t*.
    let row = |k: usize| {
        let n = k / 2;
        let lower = if k.is_multiple_of(2) { 1.0 } else { 0.0 };
        let rhs = sigma * p[n] - if k.is_multiple_of(2) { 0.0 } else { t_star };
        (
            [sigma * angles[n].cos(), sigma * angles[n].sin(), lower],
            rhs,
        )
    };
    let mut best = Real::NEG_INFINITY;
    for a in 0..2 * m {
        for b in a + 1..2 * m {
            for c in b + 1..2 * m {
                let (ra, rb, rc) = (row(a), row(b), row(c));
                let mat = Matrix3::new(
                    ra.0[0], ra.0[1], ra.0[2], rb.0[0], rb.0[1], rb.0[2], rc.0[0], rc.0[1], rc.0[2],
                );
                let Some(x) = mat.lu().solve(&Vector3::new(ra.1, rb.1, rc.1)) else {
                    continue;
                };
                let (centre, l) = ([x[0], x[1]], x[2]);
                if !l.is_finite() || l <= best {
                    continue;
                }
                let feasible = residuals(p, angles, centre)
                    .iter()
                    .all(|r| sigma * r <= t_star + tol && sigma * r >= l - tol);
                if feasible {
                    best = l;
                }
            }
        }
    }
    t_star - best
}

/// Brute force for MRS, primal: every vertex of `min t s.t. |ρ_c[m] − a0| ≤ t` is fixed by 4
/// points with `s_i (ρ_c[i] − a0) = t` for some signs; enumerate all quadruples and all 16 sign
/// patterns, keep feasible vertices, take the smallest `t`. Returns `(2 t*, centre)`.
fn brute_mrs_vertices(p: &[Real], angles: &[Real]) -> (Real, [Real; 2]) {
    let m = p.len();
    let feasible_tol = 1e-12 * scale(p);
    let mut best = (Real::INFINITY, [0.0, 0.0]);
    let idx: Vec<[usize; 4]> = (0..m)
        .flat_map(|a| {
            (a + 1..m).flat_map(move |b| {
                (b + 1..m).flat_map(move |c| (c + 1..m).map(move |d| [a, b, c, d]))
            })
        })
        .collect();
    for q in idx {
        for signs in 0..16u32 {
            let mut a = Matrix4::zeros();
            let mut rhs = Vector4::zeros();
            for (r, &n) in q.iter().enumerate() {
                let s = if signs >> r & 1 == 0 { 1.0 } else { -1.0 };
                // unknowns (t, a0, cx, cy): t + s a0 + s cx cos + s cy sin = s p
                a[(r, 0)] = 1.0;
                a[(r, 1)] = s;
                a[(r, 2)] = s * angles[n].cos();
                a[(r, 3)] = s * angles[n].sin();
                rhs[r] = s * p[n];
            }
            let Some(x) = a.lu().solve(&rhs) else {
                continue;
            };
            let t = x[0];
            if !(0.0..best.0 / 2.0).contains(&t) {
                continue;
            }
            let c = [x[2], x[3]];
            let worst = residuals(p, angles, c)
                .iter()
                .fold(0.0, |w: Real, r| w.max((r - x[1]).abs()));
            if worst <= t + feasible_tol {
                best = (2.0 * t, c);
            }
        }
    }
    best
}

/// Brute force for MRS, dual (de la Vallée Poussin): for a Haar system the minimax error is
/// the largest, over all 4-point subsets, of the subset's levelled error
/// `|Σ μ_i p_i| / Σ |μ_i|`, μ the null vector of `[(1, cos θ_i, sin θ_i)]`. Returns `2 h*`.
fn brute_mrs_levelled(p: &[Real], angles: &[Real]) -> Real {
    let m = p.len();
    let mut best: Real = 0.0;
    for a in 0..m {
        for b in a + 1..m {
            for c in b + 1..m {
                for d in c + 1..m {
                    let q = [a, b, c, d];
                    let col = |n: usize| Vector3::new(1.0, angles[n].cos(), angles[n].sin());
                    let mat = Matrix3::from_columns(&[col(q[0]), col(q[1]), col(q[2])]);
                    let Some(x) = mat.lu().solve(&(-col(q[3]))) else {
                        continue;
                    };
                    let mu = [x[0], x[1], x[2], 1.0];
                    let num: Real = mu.iter().zip(q).map(|(u, n)| u * p[n]).sum();
                    let den: Real = mu.iter().map(|u| u.abs()).sum();
                    best = best.max(num.abs() / den);
                }
            }
        }
    }
    2.0 * best
}

/// Angle of a direction in [0, 2π).
fn wrapped(t: Real) -> Real {
    t.rem_euclid(TAU)
}

/// Largest circular gap between sorted angles (by sorting, independent of the module).
fn sorted_gap(angles: &[Real]) -> Real {
    let mut a: Vec<Real> = angles.iter().map(|&t| wrapped(t)).collect();
    a.sort_by(|x, y| x.total_cmp(y));
    let mut gap = a[0] + TAU - a[a.len() - 1];
    for w in a.windows(2) {
        gap = gap.max(w[1] - w[0]);
    }
    gap
}

#[test]
fn one_upr_sinusoid_pc_value_is_twice_the_amplitude_and_centred_values_vanish() {
    let m = 720;
    let angles = equal_angles(m);
    let a = 3.7 * UM;
    // Phase on a sample (index 37), so the maximum a and minimum −a (index 397) are samples.
    let phi = angles[37];
    let p: Vec<Real> = angles.iter().map(|t| a * (t - phi).cos()).collect();
    let pc = fit(&p, &angles, Centre::Pc);
    // Rounding of cos at 1e-16 relative: 1e-12·a is far above it.
    assert!(
        (pc.value() - 2.0 * a).abs() <= 1e-12 * a,
        "PC {}",
        pc.value()
    );
    for centre in [Centre::Lsc, Centre::Mrs, Centre::Mic, Centre::Mcc] {
        let f = fit(&p, &angles, centre);
        assert!(f.value().abs() <= 1e-12 * a, "{centre}: {}", f.value());
        // The eccentricity is a·(cos φ, sin φ); it is the unique zero-value centre (any other
        // offset leaves a 1-UPR residual of range 2|Δc|). A value ≤ 1e-12·a pins it to about
        // 1e-12·a; 1e-10·a allows for the conditioning of the contact points.
        let expected = [a * phi.cos(), a * phi.sin()];
        for (got, want) in f.offset.iter().zip(expected) {
            assert!((got - want).abs() <= 1e-10 * a, "{centre}: {got} vs {want}");
        }
    }
}

#[test]
fn pure_k_harmonic_has_value_two_a_about_every_centre() {
    // Closed form. Let p = a cos kθ with k ≥ 2, sampled so that its k maxima θ_j = 2πj/k and k
    // minima (2j+1)π/k are samples (M divisible by 2k). For any offset c the residuals at the
    // maxima are a − u_j·c, and Σ_j u_j = 0 (k-th roots of unity, k ≥ 2), so their mean is a
    // and max ρ ≥ a; likewise min ρ ≤ −a. So no offset gives a range below 2a, c = 0 gives
    // exactly 2a, and every centre (which also reaches max ρ = a and min ρ = −a at c = 0, and
    // for LSC has c = 0 by orthogonality of cos kθ to cos θ, sin θ) has value 2a — including
    // the sampled k = 2 ellipse, whose smallest circumscribed circle is reached by a segment of
    // centres (the MCC/MIC tie-break must pick c = 0).
    let m = 720;
    let angles = equal_angles(m);
    let a = 2.5 * UM;
    for k in [2, 3, 4, 5, 6, 8, 9, 10, 12, 15] {
        assert_eq!(m % (2 * k), 0);
        let p: Vec<Real> = angles.iter().map(|t| a * (k as Real * t).cos()).collect();
        for centre in Centre::ALL {
            let f = fit(&p, &angles, centre);
            // Rounding of the samples and of the offset: 1e-12·a.
            assert!(
                (f.value() - 2.0 * a).abs() <= 1e-12 * a,
                "k = {k}, {centre}: {} vs {}",
                f.value(),
                2.0 * a
            );
            // c = 0 is the unique optimum for MRS, MIC and MCC (with the tie-break) here.
            assert!(
                f.offset[0].hypot(f.offset[1]) <= 1e-12 * a,
                "k = {k}, {centre}: offset {:?}",
                f.offset
            );
        }
    }
}

#[test]
fn eccentricity_leaves_the_centred_values_unchanged() {
    let mut rng = seeded_rng(11, "polar eccentricity");
    for trial in 0..40 {
        let angles = if trial % 2 == 0 {
            equal_angles(512)
        } else {
            irregular_angles(&mut rng, 300)
        };
        let p = random_profile(&mut rng, &angles);
        let e = rng.random_range(0.0..3.0) * UM;
        let phi = rng.random_range(0.0..TAU);
        let q: Vec<Real> = p
            .iter()
            .zip(&angles)
            .map(|(v, t)| v + e * (t - phi).cos())
            .collect();
        for centre in [Centre::Lsc, Centre::Mrs, Centre::Mic, Centre::Mcc] {
            let (a, b) = (fit(&p, &angles, centre), fit(&q, &angles, centre));
            // A 1-UPR term is exactly a centre shift, so the optimum moves by (e cos φ, e sin φ)
            // and its value is unchanged up to rounding (1e-16) and the pricing tolerance
            // (1e-13 of the profile's scale): 1e-12 relative.
            assert!(
                (a.value() - b.value()).abs() <= 1e-12 * a.value(),
                "trial {trial}, {centre}: {} vs {}",
                a.value(),
                b.value()
            );
            let shift = [b.offset[0] - a.offset[0], b.offset[1] - a.offset[1]];
            let want = [e * phi.cos(), e * phi.sin()];
            // The LSC centre is linear in p; the LP centres are unique for generic profiles.
            // 1e-9 of the shift allows for the conditioning of the contact points.
            for (got, w) in shift.iter().zip(want) {
                assert!(
                    (got - w).abs() <= 1e-9 * e.max(UM),
                    "trial {trial}, {centre}: shift {got} vs {w}"
                );
            }
        }
    }
}

#[test]
fn mrs_is_never_above_lsc_mic_or_mcc_on_200_random_profiles() {
    let mut rng = seeded_rng(2307, "polar random profiles");
    let angles = Angles::equally_spaced(720).expect("720 angles");
    let theta = equal_angles(720);
    let mut ratios = Vec::new();
    for trial in 0..200 {
        let p = random_profile(&mut rng, &theta);
        let value = |c| angles.fit(&p, c).expect("fit").value();
        let (mrs, lsc, mic, mcc) = (
            value(Centre::Mrs),
            value(Centre::Lsc),
            value(Centre::Mic),
            value(Centre::Mcc),
        );
        // MRS minimises the value over all centres; rounding allowance 1e-12 relative.
        for (name, other) in [("LSC", lsc), ("MIC", mic), ("MCC", mcc)] {
            assert!(
                mrs <= other * (1.0 + 1e-12),
                "trial {trial}: MRS {mrs} > {name} {other}"
            );
        }
        ratios.push(mrs / lsc);
    }
    let mean = ratios.iter().sum::<Real>() / ratios.len() as Real;
    let lowest = ratios.iter().fold(1.0, |m: Real, &r| m.min(r));
    eprintln!("MRS/LSC over 200 profiles: mean {mean:.3}, lowest {lowest:.3}");
}

#[test]
fn mic_and_mcc_match_vertex_enumeration() {
    let mut rng = seeded_rng(3, "polar brute one-sided");
    let (mut unique, mut segments) = (0, 0);
    for trial in 0..16 {
        let angles = match trial % 4 {
            0 | 3 => equal_angles(30),
            1 => irregular_angles(&mut rng, 30),
            // A 240° arc: a 120° gap still surrounds the centre.
            _ => arc_angles(&mut rng, 30, 1.0, 240.0_f64.to_radians()),
        };
        let p = if trial % 4 == 3 {
            random_even_profile(&mut rng, &angles)
        } else {
            random_profile(&mut rng, &angles)
        };
        let mrs = fit(&p, &angles, Centre::Mrs).value();
        for (centre, sigma) in [(Centre::Mcc, 1.0), (Centre::Mic, -1.0)] {
            let f = fit(&p, &angles, centre);
            let (t_brute, optimal) = brute_one_sided(&p, &angles, sigma);
            // The optimal circle: MCC's max ρ (MIC's min ρ) equals the best vertex's level.
            let level = if sigma > 0.0 { f.high } else { -f.low };
            // Same vertex solved two ways: rounding of a 3×3 solve, 1e-12 relative.
            let tol = 1e-12 * scale(&p);
            assert!(
                level <= t_brute + tol && t_brute <= level + tol,
                "trial {trial}, {centre}: LP {level} vs brute {t_brute}"
            );
            let values: Vec<Real> = optimal
                .iter()
                .map(|&c| {
                    let (lo, hi) = range(&residuals(&p, &angles, c));
                    hi - lo
                })
                .collect();
            let spread = optimal
                .iter()
                .map(|c| (c[0] - optimal[0][0]).hypot(c[1] - optimal[0][1]))
                .fold(0.0, Real::max);
            if spread <= 1e-9 * scale(&p) {
                // A unique optimal centre: the value about it agrees.
                unique += 1;
                assert!(
                    (f.value() - values[0]).abs() <= tol,
                    "trial {trial}, {centre}: value LP {} vs brute {}",
                    f.value(),
                    values[0]
                );
            } else {
                // A segment of optimal centres: the tie-break takes the smallest value on it.
                // Checked against the tie-break LP's vertex enumeration; the solver relaxes
                // t* by its pricing tolerance (1e-13 of the scale), which may lower the value
                // by that times the contacts' conditioning: 1e-11 of the scale.
                segments += 1;
                let brute = brute_tie_break(&p, &angles, sigma, t_brute);
                let smallest = values.iter().fold(Real::INFINITY, |m, &v| m.min(v));
                assert!(
                    (f.value() - brute).abs() <= 1e-11 * scale(&p)
                        && brute <= smallest + tol
                        && mrs <= f.value() + tol,
                    "trial {trial}, {centre}: tie-broken {} vs brute {brute}, vertices \
                     {smallest}, MRS {mrs}",
                    f.value()
                );
            }
        }
    }
    // Both branches must have run: generic profiles have a unique optimum, the π-periodic
    // ones on 30 equally spaced angles a segment.
    eprintln!("MIC/MCC optima: {unique} unique, {segments} segments");
    assert!(
        unique >= 16 && segments >= 4,
        "{unique} unique, {segments} segments"
    );
}

#[test]
fn mrs_matches_vertex_enumeration_and_the_levelled_reference_bound() {
    let mut rng = seeded_rng(5, "polar brute mrs");
    for trial in 0..6 {
        let angles = match trial % 3 {
            0 => equal_angles(24),
            1 => irregular_angles(&mut rng, 24),
            // A 90° arc: MRS is still a bounded LP (1, cos, sin is a Haar system on any arc).
            _ => arc_angles(&mut rng, 24, -0.3, 0.5 * PI),
        };
        let p = random_profile(&mut rng, &angles);
        let f = fit(&p, &angles, Centre::Mrs);
        let (v_primal, c_primal) = brute_mrs_vertices(&p, &angles);
        let v_dual = brute_mrs_levelled(&p, &angles);
        // Three exact methods; they differ by the rounding of 4×4 solves, whose condition
        // grows on a 90° arc (about 1e3): 1e-11 of the scale.
        let tol = 1e-11 * scale(&p);
        for (name, v) in [("vertices", v_primal), ("levelled", v_dual)] {
            assert!(
                (f.value() - v).abs() <= tol,
                "trial {trial}: LP {} vs {name} {v}",
                f.value()
            );
        }
        // The MRS centre is unique (Haar): the best vertex's centre, to the conditioning of
        // the contacts (1e-6 of the scale covers the 90° arc, where offsets are ~100× the
        // profile).
        for (got, want) in f.offset.iter().zip(c_primal) {
            assert!(
                (got - want).abs() <= 1e-6 * scale(&p),
                "trial {trial}: offset {got} vs {want}"
            );
        }
    }
}

#[test]
fn lsc_matches_an_independent_least_squares_solve() {
    let mut rng = seeded_rng(7, "polar lsc");
    let cases: Vec<Vec<Real>> = vec![
        equal_angles(360),
        irregular_angles(&mut rng, 257),
        arc_angles(&mut rng, 200, 0.4, 200.0_f64.to_radians()),
        arc_angles(&mut rng, 100, -1.0, 60.0_f64.to_radians()),
    ];
    for (case, angles) in cases.iter().enumerate() {
        let p = random_profile(&mut rng, angles);
        let m = angles.len();
        let a = DMatrix::from_fn(m, 3, |i, j| match j {
            0 => 1.0,
            1 => angles[i].cos(),
            _ => angles[i].sin(),
        });
        let svd = mtwin_kernels::linalg::svd(a.clone(), true, true);
        let x = mtwin_kernels::linalg::svd_solve(&svd, &DVector::from_column_slice(&p), 1e-14)
            .expect("svd solve");
        let f = fit(&p, angles, Centre::Lsc);
        // Two least-squares solutions of the same problem: agree to the conditioning of the
        // design (about 1e2 on the 60° arc) times rounding: 1e-10 of the scale.
        let tol = 1e-10 * scale(&p);
        assert!(
            (f.offset[0] - x[1]).abs() <= tol && (f.offset[1] - x[2]).abs() <= tol,
            "case {case}: {:?} vs ({}, {})",
            f.offset,
            x[1],
            x[2]
        );
        let (lo, hi) = range(&residuals(&p, angles, [x[1], x[2]]));
        assert!((f.value() - (hi - lo)).abs() <= tol, "case {case}: value");
    }
    // Equally spaced full circle: the closed form 2/M Σ p cos θ, 2/M Σ p sin θ.
    let angles = equal_angles(4096);
    let p = random_profile(&mut rng, &angles);
    let cx = 2.0 / 4096.0
        * p.iter()
            .zip(&angles)
            .map(|(v, t)| v * t.cos())
            .sum::<Real>();
    let cy = 2.0 / 4096.0
        * p.iter()
            .zip(&angles)
            .map(|(v, t)| v * t.sin())
            .sum::<Real>();
    let f = fit(&p, &angles, Centre::Lsc);
    // Summation rounding over 4096 terms: 1e-13 of the scale.
    assert!((f.offset[0] - cx).abs() <= 1e-13 * scale(&p));
    assert!((f.offset[1] - cy).abs() <= 1e-13 * scale(&p));
}

#[test]
fn contacts_satisfy_the_alternation_and_kkt_conditions() {
    let mut rng = seeded_rng(13, "polar contacts");
    for trial in 0..20 {
        let angles = if trial % 2 == 0 {
            equal_angles(1024)
        } else {
            irregular_angles(&mut rng, 777)
        };
        let p = random_profile(&mut rng, &angles);
        let tol = 1e-12 * scale(&p);

        // MRS: 4 contacts, alternately on the outer and inner circle around the circle
        // (alternation theorem for the Haar system 1, cos, sin: n + 1 = 4 points).
        let f = fit(&p, &angles, Centre::Mrs);
        let rho = residuals(&p, &angles, f.offset);
        assert_eq!(f.contacts.len(), 4, "trial {trial}: {:?}", f.contacts);
        let mut by_angle: Vec<(Real, bool)> = f
            .contacts
            .iter()
            .map(|&i| {
                let outer = (rho[i] - f.high).abs() <= tol;
                let inner = (rho[i] - f.low).abs() <= tol;
                assert!(
                    outer != inner,
                    "trial {trial}: contact {i} not on one circle"
                );
                (wrapped(angles[i]), outer)
            })
            .collect();
        by_angle.sort_by(|a, b| a.0.total_cmp(&b.0));
        for k in 0..4 {
            assert_ne!(by_angle[k].1, by_angle[(k + 1) % 4].1, "trial {trial}");
        }

        // MCC (MIC): the outer (inner) contacts surround the centre, i.e. no half-plane holds
        // all their directions (KKT of min max ρ: 0 in the hull of the contact directions).
        for (centre, outer) in [(Centre::Mcc, true), (Centre::Mic, false)] {
            let f = fit(&p, &angles, centre);
            let rho = residuals(&p, &angles, f.offset);
            let (lo, hi) = range(&rho);
            assert!((lo - f.low).abs() <= tol && (hi - f.high).abs() <= tol);
            let on_circle: Vec<Real> = f
                .contacts
                .iter()
                .filter(|&&i| {
                    assert!(
                        (rho[i] - f.high).abs() <= tol || (rho[i] - f.low).abs() <= tol,
                        "trial {trial}, {centre}: contact {i} on no circle"
                    );
                    (rho[i] - if outer { f.high } else { f.low }).abs() <= tol
                })
                .map(|&i| angles[i])
                .collect();
            assert!(on_circle.len() >= 3, "trial {trial}, {centre}");
            assert!(
                sorted_gap(&on_circle) <= PI,
                "trial {trial}, {centre}: contacts do not surround the centre"
            );
        }
    }
}

#[test]
fn partial_arcs_refuse_mic_and_mcc_but_not_lsc_and_mrs() {
    let mut rng = seeded_rng(17, "polar arcs");
    for (arc_deg, surrounds) in [(90.0, false), (180.0, false), (182.0, true), (300.0, true)] {
        let angles: Vec<Real> = (0..=180)
            .map(|i| (arc_deg as Real).to_radians() * i as Real / 180.0)
            .collect();
        let p = random_profile(&mut rng, &angles);
        let table = Angles::new(&angles).expect("angles");
        // Closed form: the gap left by an arc is 360° − arc.
        let gap = table.largest_gap().to_degrees();
        assert!(
            (gap - (360.0 - arc_deg)).abs() < 1e-9,
            "{arc_deg}°: gap {gap}"
        );
        assert_eq!(table.surround_centre(), surrounds);
        assert_eq!(table.largest_gap() <= MAX_ANGLE_GAP, surrounds);
        for centre in [Centre::Mic, Centre::Mcc] {
            match polar::fit(&p, &angles, centre) {
                Err(PolarError::NotSurrounded { gap_deg, .. }) => {
                    assert!(!surrounds && (gap_deg - gap).abs() < 1e-9)
                }
                Ok(f) => assert!(surrounds && f.value().is_finite()),
                Err(e) => panic!("{arc_deg}°, {centre}: {e}"),
            }
        }
        // PC, LSC and MRS are defined on any arc; MRS is the smallest value of all centres
        // (1e-12 relative for rounding).
        let mrs = fit(&p, &angles, Centre::Mrs).value();
        for centre in [Centre::Pc, Centre::Lsc] {
            let v = fit(&p, &angles, centre).value();
            assert!(
                mrs <= v * (1.0 + 1e-12),
                "{arc_deg}°: MRS {mrs} > {centre} {v}"
            );
        }
    }
}

#[test]
fn largest_gap_matches_sorting() {
    let mut rng = seeded_rng(19, "polar gaps");
    for trial in 0..50 {
        let m = rng.random_range(3..200);
        let mut angles: Vec<Real> = (0..m).map(|_| rng.random_range(-20.0..20.0)).collect();
        if trial % 5 == 0 {
            let first = angles[0];
            angles.push(first + TAU); // a repeated direction
        }
        let gap = Angles::new(&angles).expect("angles").largest_gap();
        // Both are differences of the same wrapped angles: rounding of rem_euclid.
        assert!((gap - sorted_gap(&angles)).abs() <= 1e-12, "trial {trial}");
    }
    // Equally spaced: 2π/M (closed form) through the buckets, and `equally_spaced` gives the
    // same angles as building them by hand (same fits to rounding, 1e-15 of the scale).
    let by_hand = Angles::new(&equal_angles(4096)).expect("4096");
    assert!((by_hand.largest_gap() - TAU / 4096.0).abs() <= 1e-12);
    let table = Angles::equally_spaced(4096).expect("4096");
    assert!((table.largest_gap() - TAU / 4096.0).abs() <= 1e-12);
    let p = random_profile(&mut rng, &equal_angles(4096));
    for centre in Centre::ALL {
        let (a, b) = (
            table.fit(&p, centre).expect("fit"),
            by_hand.fit(&p, centre).expect("fit"),
        );
        assert!(
            (a.value() - b.value()).abs() <= 1e-15 * scale(&p),
            "{centre}"
        );
    }
    assert!(matches!(
        Angles::equally_spaced(2),
        Err(PolarError::TooFew(2))
    ));
}

mod edges;
