//! Form separation (reversal, multi-probe), speed, noise, table-axis harmonics and reverse rotation through the chain.

use super::*;

/// `h(ψ) = Σ a·sin(kψ + φ)` for `(k, a, φ°)`.
fn form_at(form: &[(u32, Real, Real)], psi: Real) -> Real {
    form.iter()
        .map(|&(k, a, p)| a * (k as Real * psi + p.to_radians()).sin())
        .sum()
}

fn form_toml(form: &[(u32, Real, Real)]) -> String {
    let terms: Vec<String> = form
        .iter()
        .map(|(k, a, p)| {
            format!(
                "{{ per_revolution = {k}, amplitude_nm = {}, phase_deg = {p} }}",
                a / NM
            )
        })
        .collect();
    format!("form = [{}]", terms.join(", "))
}

#[test]
fn donaldson_reversal_returns_the_injected_form_and_motion() {
    // A sphere with a 5- and 7-lobe form h, set up (0.8, 0.3) µm off centre, on a spindle with
    // synchronous EXS (2, 3 UPR) and EYS (2 UPR); set-ups normal and reversed at two speeds.
    // For a probe at φ (digest §B, evaluate's reversal): r1 = −E_φ(θ) − h_c(φ − θ) and, with
    // the sphere turned 180° and the probe at φ + 180°, r2 = +E_φ(θ) − h_c(φ − θ), where
    // E_φ = EXS cos φ + EYS sin φ and h_c(ψ) = h(ψ) + e_x cos ψ + e_y sin ψ is the section's
    // outward deviation about the axis, its centring included (the centring follows the
    // artefact, so it comes out as form). Hence the separation's grid convention:
    //   form[m] = h_c(φ + ψ_m), ψ_m = 2πm/M  (for x at φ = 0: form[m] = h_c(2πm/M)),
    //   motion_x[m] = E_φ(θ_m),
    // both with zero mean on the grid already (harmonics 1…7 only).
    let form = [(5u32, 30.0 * NM, 20.0), (7, 20.0 * NM, -50.0)];
    let (ex, ey) = (0.8 * UM, 0.3 * UM);
    let h_c = |psi: Real| form_at(&form, psi) + ex * psi.cos() + ey * psi.sin();
    let exs =
        |t: Real| 0.12 * UM * (2.0 * t + 20f64.to_radians()).sin() + 0.05 * UM * (3.0 * t).sin();
    let eys = |t: Real| 0.08 * UM * (2.0 * t + 70f64.to_radians()).sin();
    let errors = harmonics(
        "EXS",
        &[harmonic(2, 0.12, 20.0, "um"), harmonic(3, 0.05, 0.0, "um")],
    ) + &harmonics("EYS", &[harmonic(2, 0.08, 70.0, "um")]);
    let spindle = format!(
        "speeds_rpm = [3000.0, 6000.0]\nrevolutions = 4\nsamples_per_revolution = {M}\n\
         setups = [\"normal\", \"reversed\"]\n\
         [spindle.artefact]\nkind = \"sphere\"\ndiameter_mm = 25.4\neccentricity_um = [0.8, 0.3]\n{}\n\
         [[spindle.probe]]\nname = \"x\"\nkind = \"radial\"\nazimuth_deg = 0.0\n\
         [[spindle.probe]]\nname = \"y\"\nkind = \"radial\"\nazimuth_deg = 90.0\n",
        form_toml(&form)
    );
    let s = load("vmc3", &errors, &spindle);
    let ev = evaluated(&s, 1);
    let setups: Vec<&str> = ev.segments.iter().map(|s| s.setup.as_str()).collect();
    assert_eq!(setups, ["normal", "normal", "reversed", "reversed"]);
    let reversals: Vec<_> = ev
        .separations
        .iter()
        .filter(|s| s.method == "reversal")
        .collect();
    assert_eq!(reversals.len(), 4, "two probes at two speeds");
    let theta = grid(M);
    for sep in reversals {
        let phi = match sep.probes.as_slice() {
            [p] if p == "x" => 0.0,
            [p] if p == "y" => FRAC_PI_2,
            other => panic!("{other:?}"),
        };
        assert_eq!(sep.form.len(), M);
        assert!(sep.motion_y.is_empty() && sep.blind.is_empty());
        let form_error = sep
            .form
            .iter()
            .zip(&theta)
            .map(|(f, &psi)| (f - h_c(phi + psi)).abs())
            .fold(0.0, Real::max);
        close(form_error, 0.0, EXACT, &format!("{:?}: form", sep.probes));
        let motion_error = sep
            .motion_x
            .iter()
            .zip(&theta)
            .map(|(v, &t)| (v - (exs(t) * phi.cos() + eys(t) * phi.sin())).abs())
            .fold(0.0, Real::max);
        close(
            motion_error,
            0.0,
            EXACT,
            &format!("{:?}: motion", sep.probes),
        );
    }
}

#[test]
fn multi_probe_separation_returns_the_form_and_lists_blind_harmonics() {
    // Four probes at 0, 1.0, π, 3.8 rad (scenarios/vmc3_spindle_multiprobe.toml), no noise:
    // the two-direction model holds any synchronous motion, so every harmonic that is not
    // blind comes back exactly: form[m] = h(ψ_m), motion_x = EXS, motion_y = EYS on the grid
    // (form harmonics 2, 3, 7; motion 2, 3, 4 UPR; none of them blind).
    let form = [
        (2u32, 20.0 * NM, 0.0),
        (3, 35.0 * NM, 50.0),
        (7, 12.0 * NM, -15.0),
    ];
    let exs = |t: Real| {
        0.10 * UM * (2.0 * t).sin()
            + 0.04 * UM * (3.0 * t + 30f64.to_radians()).sin()
            + 0.02 * UM * (4.0 * t - 20f64.to_radians()).sin()
    };
    let eys = |t: Real| {
        0.05 * UM * (2.0 * t + 60f64.to_radians()).sin()
            + 0.07 * UM * (3.0 * t - 45f64.to_radians()).sin()
    };
    let errors = harmonics(
        "EXS",
        &[
            harmonic(2, 0.10, 0.0, "um"),
            harmonic(3, 0.04, 30.0, "um"),
            harmonic(4, 0.02, -20.0, "um"),
        ],
    ) + &harmonics(
        "EYS",
        &[
            harmonic(2, 0.05, 60.0, "um"),
            harmonic(3, 0.07, -45.0, "um"),
        ],
    );
    let spindle = |form: &str, azimuths: &[Real]| {
        format!(
            "speeds_rpm = [4000.0]\nrevolutions = 4\nsamples_per_revolution = {M}\n\
             [spindle.artefact]\nkind = \"sphere\"\ndiameter_mm = 25.4\n{form}\n{}",
            radial_probes(azimuths)
        )
    };
    let theta = grid(M);
    let worst = |got: &[Real], want: &dyn Fn(Real) -> Real| {
        got.iter()
            .zip(&theta)
            .map(|(g, &t)| (g - want(t)).abs())
            .fold(0.0, Real::max)
    };

    let unequal = [0.0, 57.29577951308232, 180.0, 217.72395214971282];
    let s = load("vmc3", &errors, &spindle(&form_toml(&form), &unequal));
    let ev = evaluated(&s, 1);
    let seps: Vec<_> = ev
        .separations
        .iter()
        .filter(|s| s.method == "multi-probe")
        .collect();
    assert_eq!(seps.len(), 1);
    let sep = seps[0];
    assert_eq!(sep.probes, ["p1", "p2", "p3", "p4"]);
    for k in [2, 3, 4, 7] {
        assert!(
            !sep.blind.contains(&k),
            "harmonic {k} blind: {:?}",
            sep.blind
        );
    }
    close(
        worst(&sep.form, &|psi| form_at(&form, psi)),
        0.0,
        EXACT,
        "form",
    );
    close(worst(&sep.motion_x, &exs), 0.0, EXACT, "motion_x = EXS");
    close(worst(&sep.motion_y, &eys), 0.0, EXACT, "motion_y = EYS");

    // Three probes 120° apart: for k ≢ 0 (mod 3) the form column e^{−ikφ_j} is a combination
    // of the motion columns cos φ_j, sin φ_j (e^{−ikφ_j} = e^{∓iφ_j}), so every such harmonic
    // from 2 to k_max = ⌈M/2⌉ − 1 = 119 is blind; the multiples of 3 are seen. The form's 2 UPR
    // and the motion's 2 and 4 UPR are lost, its 3 and 6 UPR come back.
    let form3 = [
        (2u32, 20.0 * NM, 0.0),
        (3, 35.0 * NM, 50.0),
        (6, 10.0 * NM, 10.0),
    ];
    let s = load(
        "vmc3",
        &errors,
        &spindle(&form_toml(&form3), &[0.0, 120.0, 240.0]),
    );
    let ev = evaluated(&s, 1);
    let sep = ev
        .separations
        .iter()
        .find(|s| s.method == "multi-probe")
        .expect("a multi-probe separation");
    let expected: Vec<usize> = (2..=119).filter(|k| k % 3 != 0).collect();
    assert_eq!(sep.blind, expected);
    let note = format!(
        "multi-probe p1+p2+p3: the layout cannot see harmonics 2, 4, 5, 7, 8, 10, 11, 13, 14, 16, 17, 19, … ({} in all)",
        expected.len()
    );
    assert!(ev.notes.contains(&note), "{:?}", ev.notes);
    let seen = [form3[1], form3[2]];
    close(
        worst(&sep.form, &|psi| form_at(&seen, psi)),
        0.0,
        EXACT,
        "120°: form at k ≡ 0 mod 3",
    );
    close(
        worst(&sep.motion_x, &|t| {
            0.04 * UM * (3.0 * t + 30f64.to_radians()).sin()
        }),
        0.0,
        EXACT,
        "120°: motion_x, 3 UPR only",
    );
    close(
        worst(&sep.motion_y, &|t| {
            0.07 * UM * (3.0 * t - 45f64.to_radians()).sin()
        }),
        0.0,
        EXACT,
        "120°: motion_y, 3 UPR only",
    );
}

#[test]
fn the_synchronous_value_scales_with_the_speed_factor() {
    // EXS = a·sin(4θ + 30°) × factor(speed), factor 1, 1.5, 3 at 0, 6000, 12000 rpm, linear
    // between: 1.25 at 3000, 1.5 at 6000, 2.25 at 9000 rpm. The x1 LSC synchronous value is
    // 2a × factor at each speed, to rounding: the chain computes X·q − q at the sensed point
    // q (|q| = 12.7 mm), so a reading carries about |q|·2.2e-16 = 3e-18 m of rounding and a
    // range twice that, 1.4e-11 of the smallest value 2a·1.25; 1e-10 relative covers it.
    let a = 0.2 * UM;
    let errors = harmonics("EXS", &[harmonic(4, 0.2, 30.0, "um")])
        + "speed = { rpm = [0.0, 6000.0, 12000.0], factor = [1.0, 1.5, 3.0] }\n";
    let spindle = sphere("", "").replace(
        "speeds_rpm = [3000.0]",
        "speeds_rpm = [3000.0, 6000.0, 9000.0]",
    );
    let s = load("vmc3", &errors, &spindle);
    let ev = evaluated(&s, 1);
    assert_eq!(ev.segments.len(), 3);
    for (seg, (rpm, factor)) in
        ev.segments
            .iter()
            .zip([(3000.0, 1.25), (6000.0, 1.5), (9000.0, 2.25)])
    {
        close(seg.speed, rpm * TAU / 60.0, 1e-9, "speed");
        let want = 2.0 * a * factor;
        let v = about(find(seg, "radial x1"), Centre::Lsc);
        close(v.synchronous, want, 1e-10 * want, &format!("{rpm} rpm"));
    }
}

#[test]
fn noise_alone_reports_nothing_and_a_real_3_upr_is_recovered() {
    // Probes with white Gaussian noise σ = 2 nm (no filter, no resolution), K = 20
    // revolutions of M = 240 samples, five seeds; x1 and y1 each an independent draw.
    //
    // Bin means: S[m] = true + n[m], n[m] ~ N(0, σ_m²) independent, σ_m = σ/√K = 0.447 nm.
    // The LSC centre of the noise c = (2/M) Σ n[m](cos, sin) has components of σ_m·√(2/M);
    // |c| ≤ 5·√2·σ_m·√(2/M) = 0.65 σ_m but with probability e^{−12.5} = 4e-6.
    //
    // (1) Nothing injected: the LSC synchronous value is range(n − c·u), within range(n) ± 2|c|.
    // The range of 240 standard normals exceeds 10 with probability 4e-8 and falls below 3.5
    // with probability 1e-8 (P(R ≤ w) = n∫φ(x)[Φ(x+w) − Φ(x)]^{n−1}dx, evaluated numerically),
    // so 2 σ_m ≤ value ≤ 12 σ_m ("nothing reported where nothing was injected": ≤ 5.4 nm).
    // The asynchronous value is the largest, over 240 angles, of the range of K = 20 normals
    // of σ: each exceeds 9σ with probability 3.7e-8 and is below 4σ with probability 0.66, so
    // 4σ ≤ value ≤ 9σ fails with probability < 1e-4 over the 240 angles and ten draws.
    //
    // (2) EXS = a·sin(3θ + 45°), a = 100 nm (extremes on the grid: true value exactly 2a).
    // For any profiles g, ε: |range(g + ε) − range(g)| ≤ range(ε), so |value − 2a| ≤ 12 σ_m
    // (k = 12, as above). The 3-UPR spectral line is a plus a complex noise whose parts have
    // σ·√(2/N) each (N = K·M = 4800): |amplitude − a| ≤ 5σ√(2/N) = 0.2 nm fails with
    // probability e^{−12.5} = 4e-6.
    let sigma = 2.0 * NM;
    let k_count = 20.0;
    let sigma_m = sigma / Real::sqrt(k_count);
    let n = k_count * M as Real;
    let a = 100.0 * NM;
    let noisy = sphere("noise_nm = 2.0", "");
    let quiet = load("vmc3", "", &noisy);
    let loud = load(
        "vmc3",
        &harmonics("EXS", &[harmonic(3, 0.1, 45.0, "um")]),
        &noisy,
    );
    for seed in 1..=5 {
        let ev = evaluated(&quiet, seed);
        for name in ["radial x1", "radial y1"] {
            let v = about(find(&ev.segments[0], name), Centre::Lsc);
            let what = format!("seed {seed}, {name}, nothing injected");
            assert!(
                v.synchronous >= 2.0 * sigma_m && v.synchronous <= 12.0 * sigma_m,
                "{what}: synchronous {:e} m",
                v.synchronous
            );
            assert!(
                v.asynchronous >= 4.0 * sigma && v.asynchronous <= 9.0 * sigma,
                "{what}: asynchronous {:e} m",
                v.asynchronous
            );
        }
        let ev = evaluated(&loud, seed);
        let x1 = find(&ev.segments[0], "radial x1");
        let v = about(x1, Centre::Lsc);
        close(
            v.synchronous,
            2.0 * a,
            12.0 * sigma_m,
            &format!("seed {seed}: 3 UPR recovered"),
        );
        let line = x1
            .lines
            .iter()
            .find(|l| l.per_revolution == 3.0)
            .expect("the 3-UPR line among the largest");
        assert!(line.synchronous);
        close(
            line.amplitude,
            a,
            5.0 * sigma * (2.0 / n).sqrt(),
            &format!("seed {seed}: 3-UPR line"),
        );
        assert!(
            v.asynchronous >= 4.0 * sigma && v.asynchronous <= 9.0 * sigma,
            "seed {seed}: asynchronous {:e} m with a synchronous error",
            v.asynchronous
        );
    }
}

#[test]
fn a_c_table_harmonic_shows_in_radial_x_with_the_sign_of_the_frames() {
    // trunnion5's C (a table axis, 5 and 10 rpm), a sphere 100 mm above the table and probes
    // in the spindle (scenarios/trunnion5_c_axis.toml, without noise). EXC = a·sin(2θ + 30°),
    // EYC = b·sin(3θ + 45°), plus the location errors of the axis line (EX0C, EY0C, EA0C,
    // EB0C) and a set-up eccentricity, which only add a 1 UPR.
    //
    // The sign comes from the truth's frames: to first order the rotor (table) moves by
    // rotor_motion_sign · R · δ in the axis frame, R = axis_from_slot's rotation, δ = (EXC,
    // EYC, EZC); a fixed radial probe at 0° reads −ΔX, at 90° −ΔY. For C (z = −Z, x = X,
    // y = −Y, table side: sign −1) that is x = +EXC, y = −EYC (as tests/it/spindle_twin.rs).
    //
    // So the residual synchronous profile of `radial x` is +EXC and its LSC value 2a; `radial
    // y` −EYC, 2b. Tolerance 1 nm: the location errors (ε ≤ 12 µrad, d ≤ 5 µm) add
    // second-order terms ε²·|p − pivot| + ε·d ≤ (1.2e-5)²·0.3 m + 1.2e-5·5e-6 m ≈ 1e-10 m.
    let (a, b) = (0.3 * UM, 0.15 * UM);
    let exc = |t: Real| a * (2.0 * t + 30f64.to_radians()).sin();
    let eyc = |t: Real| b * (3.0 * t + 45f64.to_radians()).sin();
    let tolerance = 1e-9;
    let errors = harmonics("EXC", &[harmonic(2, 0.3, 30.0, "um")])
        + &harmonics("EYC", &[harmonic(3, 0.15, 45.0, "um")])
        + "[errors.EX0C]\nconstant_um = 4.0\n[errors.EY0C]\nconstant_um = -3.0\n\
           [errors.EA0C]\nconstant_urad = 10.0\n[errors.EB0C]\nconstant_urad = -6.0\n";
    let spindle = format!(
        "axis = \"C\"\nsensing = \"fixed\"\nspeeds_rpm = [5.0, 10.0]\nrevolutions = 20\n\
         samples_per_revolution = {M}\nx_mm = 325.0\ny_mm = 275.0\nz_mm = 150.0\na_deg = 0.0\n\
         [spindle.artefact]\nkind = \"sphere\"\ndiameter_mm = 25.4\nstickout_mm = 100.0\n\
         eccentricity_um = [2.0, 0.5]\n\
         [[spindle.probe]]\nname = \"x\"\nkind = \"radial\"\nazimuth_deg = 0.0\n\
         [[spindle.probe]]\nname = \"y\"\nkind = \"radial\"\nazimuth_deg = 90.0\n"
    );
    let s = load("trunnion5", &errors, &spindle);
    let test = s.spindle_test.as_ref().unwrap();
    let truth = run::truth(&s.twin, test);
    let frames = &truth["frames"];
    let sign = frames["rotor_motion_sign"].as_f64().unwrap();
    let r = |i: usize, j: usize| frames["axis_from_slot"]["rotation"][i][j].as_f64().unwrap();
    assert_eq!(frames["rotor_side"], "workpiece");
    // No cross-coupling of X and Y between the slot and the axis frame.
    assert!(r(0, 1).abs() < 1e-12 && r(1, 0).abs() < 1e-12);
    let (sx, sy) = (-sign * r(0, 0), -sign * r(1, 1));
    close(sx, 1.0, 1e-12, "x reads +EXC");
    close(sy, -1.0, 1e-12, "y reads −EYC");

    let ev = evaluated(&s, 1);
    assert_eq!(ev.segments.len(), 2);
    let theta = grid(M);
    for seg in &ev.segments {
        for (name, truth_of, amplitude) in [
            ("radial x", &exc as &dyn Fn(Real) -> Real, a),
            ("radial y", &eyc, b),
        ] {
            let sign = if name == "radial x" { sx } else { sy };
            let t = find(seg, name);
            let residual = decompose(&t.signal).residual;
            let error = residual
                .iter()
                .zip(&theta)
                .map(|(v, &th)| (v - sign * truth_of(th)).abs())
                .fold(0.0, Real::max);
            close(
                error,
                0.0,
                tolerance,
                &format!("{name} at {:.3} rad/s: residual = sign·E", seg.speed),
            );
            let v = about(t, Centre::Lsc);
            close(
                v.synchronous,
                2.0 * amplitude,
                tolerance,
                &format!("{name}: LSC value"),
            );
            close(v.asynchronous, 0.0, tolerance, &format!("{name}: async"));
            // The 1 UPR of the set-up and the axis line is there, and removed.
            assert!(
                v.fundamental > 1.0 * UM,
                "{name}: fundamental {:e}",
                v.fundamental
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Two library bugs these tests found, kept as regression tests now that they are fixed.
// ---------------------------------------------------------------------------------------------

#[test]
fn a_reverse_rotation_record_is_evaluated() {
    // Was a bug: a negative speed is accepted by `[spindle]` (ISO 230-7 §6 asks for both
    // directions on a rotary axis) and simulated with the angle running down within each
    // revolution, but `evaluate` compared the angles with the grid in sample order and
    // refused the record, and the table reader refused decreasing angles. Both now lay a
    // backwards record out on the angle travelled.
    //
    // Correct behaviour: a synchronous EXS = a·sin(3θ + 45°) is read as −EXS(θ) at every
    // sample whichever way the axis turns, so at −3000 rpm the x1 LSC synchronous value is 2a,
    // as at +3000 rpm.
    let a = 0.2 * UM;
    let errors = harmonics("EXS", &[harmonic(3, 0.2, 45.0, "um")]);
    let spindle = sphere("", "").replace("speeds_rpm = [3000.0]", "speeds_rpm = [3000.0, -3000.0]");
    let s = load("vmc3", &errors, &spindle);
    let test = s.spindle_test.as_ref().unwrap();
    let table = run::simulate(&s.twin, test, 1).unwrap();
    // The simulation itself is right: sample m of a backward revolution is at θ = −2πm/M.
    let back = 20 * M;
    close(
        table.record.angle[back + 1],
        TAU * (M - 1) as Real / M as Real,
        1e-12,
        "angle",
    );
    let x1 = &table.record.readings[table.record.probe("x1").unwrap()];
    let theta = table.record.angle[back + 7];
    close(
        x1[back + 7],
        -a * (3.0 * theta + PI / 4.0).sin(),
        EXACT,
        "x1 = −EXS(θ)",
    );
    let ev = evaluate(
        &table.record,
        table.samples_per_revolution,
        &Options::default(),
    )
    .unwrap_or_else(|e| panic!("a reverse-rotation record is not evaluated: {e}"));
    assert_eq!(ev.segments.len(), 2);
    for seg in &ev.segments {
        let v = about(find(seg, "radial x1"), Centre::Lsc);
        close(
            v.synchronous,
            2.0 * a,
            EXACT,
            &format!("{} rad/s", seg.speed),
        );
    }
}

#[test]
fn multi_probe_separation_of_a_reversed_set_up_keeps_the_motion_s_sign() {
    // Was a bug: `multiprobe` (src/kinds/spindle/evaluate.rs) separated every segment, the
    // "reversed" and "turned_<deg>" set-ups included, with the probe azimuths of the record's
    // header, which describe the normal set-up only; it now separates the normal set-up only. In the reversed set-up
    // the radial probes stand at φ + 180° and the artefact is turned 180°, so each reads
    // +E·u(φ) − h(φ − θ): solved with the normal azimuths, the "spindle motion" comes out as
    // −E (and a turned_β set-up's form as h(ψ − β)), unlabelled, next to the normal set-up's
    // +E at the same speed.
    //
    // Correct behaviour (either would pass): the spindle's motion does not depend on how the
    // artefact and the probes were set up, so every multi-probe separation reports
    // motion_x = EXS; or the separation is made on the normal set-up only.
    let exs = |t: Real| 0.1 * UM * (2.0 * t).sin();
    let errors = harmonics("EXS", &[harmonic(2, 0.1, 0.0, "um")]);
    let probes = radial_probes(&[0.0, 57.29577951308232, 180.0, 217.72395214971282]);
    let spindle = format!(
        "speeds_rpm = [4000.0]\nrevolutions = 2\nsamples_per_revolution = {M}\n\
         setups = [\"normal\", \"reversed\"]\n\
         [spindle.artefact]\nkind = \"sphere\"\n{}\n{probes}",
        form_toml(&[(3, 30.0 * NM, 0.0)])
    );
    let s = load("vmc3", &errors, &spindle);
    let ev = evaluated(&s, 1);
    let seps: Vec<_> = ev
        .separations
        .iter()
        .filter(|s| s.method == "multi-probe")
        .collect();
    // One separation: the normal set-up (the reversed one is not separated).
    assert_eq!(seps.len(), 1);
    let theta = grid(M);
    for (n, sep) in seps.iter().enumerate() {
        let error = sep
            .motion_x
            .iter()
            .zip(&theta)
            .map(|(v, &t)| (v - exs(t)).abs())
            .fold(0.0, Real::max);
        close(
            error,
            0.0,
            EXACT,
            &format!(
                "multi-probe separation {n} of {}: motion_x = EXS",
                seps.len()
            ),
        );
    }
}
