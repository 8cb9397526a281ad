//! What a separation reports beyond its profiles: the harmonic coefficients of the form and of
//! the motion, and their values about every centre, synchronous and asynchronous, against
//! closed forms of the injected errors.

use super::*;
use mtwin::kinds::spindle::evaluate::{Separated, SeparatedMotion};

/// `[a_k, b_k]` of `A·sin(kθ + φ)`: `A sin φ` on the cosine, `A cos φ` on the sine.
fn coefficients(amplitude: Real, phase_deg: Real) -> [Real; 2] {
    let p = phase_deg.to_radians();
    [amplitude * p.sin(), amplitude * p.cos()]
}

/// Every harmonic of `got` (entry k − 1 for harmonic k) is `want(k)` within 1 pm.
#[track_caller]
fn harmonics_are(got: &[[Real; 2]], want: impl Fn(usize) -> [Real; 2], what: &str) {
    for (i, [a, b]) in got.iter().enumerate() {
        let [wa, wb] = want(i + 1);
        close(*a, wa, EXACT, &format!("{what}: a_{}", i + 1));
        close(*b, wb, EXACT, &format!("{what}: b_{}", i + 1));
    }
}

/// `A·sin(kθ_m + φ)` on the grid.
fn sampled(k: Real, amplitude: Real, phase_deg: Real) -> Vec<Real> {
    grid(M)
        .iter()
        .map(|t| amplitude * (k * t + phase_deg.to_radians()).sin())
        .collect()
}

/// Four radial probes p1…p4 at 0°, 57.3°, 180° and 217.7° (none of harmonics 2–7 blind).
fn unequal_layout() -> String {
    radial_probes(&[0.0, 57.29577951308232, 180.0, 217.72395214971282])
}

fn motion<'a>(sep: &'a Separated, axis: &str) -> &'a SeparatedMotion {
    sep.motions
        .iter()
        .find(|m| m.axis == axis)
        .unwrap_or_else(|| panic!("no motion {axis} in {:?}", sep.probes))
}

/// The synchronous value about every centre is `want`; so is the residual about every centre
/// but PC, where it is `want` too for a profile without 1 UPR.
#[track_caller]
fn synchronous_everywhere(m: &SeparatedMotion, want: Real, what: &str) {
    assert_eq!(m.values.len(), 5, "{what}: every centre");
    for v in &m.values {
        close(
            v.synchronous,
            want,
            EXACT,
            &format!("{what} about {}", v.centre),
        );
        close(
            v.residual,
            want,
            EXACT,
            &format!("{what}: residual about {}", v.centre),
        );
    }
}

/// An asynchronous line at 0.5 UPR over an even number of revolutions averages to nothing, and
/// its band at angle m is `2a·|sin(πm/M + φ)|` for a phase φ the record's start sets: at least
/// `2a·cos(π/2M)` (some bin lies within π/2M of the peak), at most `2a`.
#[track_caller]
fn half_upr_band(got: Real, a: Real, what: &str) {
    let low = 2.0 * a * (PI / (2.0 * M as Real)).cos();
    assert!(
        got >= low - EXACT && got <= 2.0 * a + EXACT,
        "{what}: asynchronous {got:e} outside [{low:e}, {:e}]",
        2.0 * a
    );
}

#[test]
fn a_reversal_reports_the_harmonics_and_the_values_of_its_form_and_motion() {
    // A 3-lobe sphere (40 nm at 20°) 0.8, 0.3 µm off centre; EXS = 0.12 µm at 2 UPR (20°) plus
    // a 0.02 µm asynchronous line at 0.5 UPR; EYS = 0.08 µm at 2 UPR (70°); 4 revolutions per
    // set-up. Probe x (φ = 0) separates (evaluate/separated.rs):
    //   form  h_c(ψ) = 40 nm·sin(3ψ + 20°) + 0.8 µm cos ψ + 0.3 µm sin ψ (centring as form),
    //   motion E_X(θ) = 0.12 µm·sin(2θ + 20°), revolution by revolution plus the line.
    let (a_async, k_count) = (0.02 * UM, 4);
    let errors = format!(
        "[errors.EXS]\nharmonic = [{}]\nasynchronous = [{{ amplitude_um = 0.02, per_revolution = 0.5, phase_deg = 10 }}]\n{}",
        harmonic(2, 0.12, 20.0, "um"),
        harmonics("EYS", &[harmonic(2, 0.08, 70.0, "um")])
    );
    let spindle = format!(
        "speeds_rpm = [3000.0]\nrevolutions = {k_count}\nsamples_per_revolution = {M}\n\
         setups = [\"normal\", \"reversed\"]\n\
         [spindle.artefact]\nkind = \"sphere\"\ndiameter_mm = 25.4\neccentricity_um = [0.8, 0.3]\n\
         form = [{{ per_revolution = 3, amplitude_nm = 40.0, phase_deg = 20.0 }}]\n\
         [[spindle.probe]]\nname = \"x\"\nkind = \"radial\"\nazimuth_deg = 0.0\n"
    );
    let ev = evaluated(&load("vmc3", &errors, &spindle), 1);
    let sep = ev
        .separations
        .iter()
        .find(|s| s.method == "reversal")
        .expect("a reversal");
    assert_eq!(sep.k_max, (M - 1) / 2);
    assert_eq!(sep.form_harmonics.len(), sep.k_max);

    // Harmonics: the centring is the form's 1 UPR, the lobes its 3 UPR, nothing else.
    harmonics_are(
        &sep.form_harmonics,
        |k| match k {
            1 => [0.8 * UM, 0.3 * UM],
            3 => coefficients(40.0 * NM, 20.0),
            _ => [0.0, 0.0],
        },
        "form",
    );
    assert_eq!(sep.motions.len(), 1);
    let x = motion(sep, "X");
    assert_eq!(x.azimuth, Some(0.0));
    harmonics_are(
        &x.harmonics,
        |k| {
            if k == 2 {
                coefficients(0.12 * UM, 20.0)
            } else {
                [0.0, 0.0]
            }
        },
        "motion X",
    );

    // The form about every centre: PC counts the centring (the sampled range of h_c, here
    // from the closed form), LSC, MRS, MIC and MCC do not (the 3-lobe's sampled range: the
    // grid keeps its 3-fold symmetry, so each centre is at its middle).
    let lobes = sampled(3.0, 40.0 * NM, 20.0);
    let h_c: Vec<Real> = lobes
        .iter()
        .zip(grid(M))
        .map(|(h, t)| h + 0.8 * UM * t.cos() + 0.3 * UM * t.sin())
        .collect();
    assert_eq!(sep.form_values.len(), 5);
    for f in &sep.form_values {
        let want = if f.centre == Centre::Pc {
            range(&h_c)
        } else {
            range(&lobes)
        };
        close(f.value(), want, EXACT, &format!("form about {}", f.centre));
    }
    assert!(
        range(&h_c) > 1.5 * UM,
        "the centring is large against the lobes"
    );

    // The motion: a pure 2 UPR, whose sampled range is its value about every centre.
    synchronous_everywhere(x, range(&sampled(2.0, 0.12 * UM, 20.0)), "motion X");
    // The line is the motion's asynchronous part, read in full, and the probe's own.
    let probe = find(&ev.segments[0], "radial x");
    for v in &x.values {
        half_upr_band(
            v.asynchronous,
            a_async,
            &format!("motion X about {}", v.centre),
        );
        close(
            v.asynchronous,
            probe.values[0].asynchronous,
            EXACT,
            "the probe's band",
        );
        assert!(
            v.total >= v.synchronous - EXACT && v.total <= v.synchronous + v.asynchronous + EXACT
        );
    }
    assert_eq!(x.signal.count(), k_count);
}

#[test]
fn a_multi_probe_layout_reports_x_y_and_rotating_motion_with_their_asynchronous_parts() {
    // Four probes at unequal azimuths (none of harmonics 2–7 blind), a 3-lobe form (35 nm at
    // 50°); EXS = 0.10 µm at 2 UPR plus a 0.02 µm line at 0.5 UPR, EYS = 0.07 µm at 3 UPR
    // (−45°). Harmonic 1 goes to the motion, so the form starts at 2 UPR; the line is along X
    // only, so the least-squares asynchronous motion along Y is nil.
    let a_async = 0.02 * UM;
    let errors = format!(
        "[errors.EXS]\nharmonic = [{}]\nasynchronous = [{{ amplitude_um = 0.02, per_revolution = 0.5, phase_deg = 40 }}]\n{}",
        harmonic(2, 0.10, 0.0, "um"),
        harmonics("EYS", &[harmonic(3, 0.07, -45.0, "um")])
    );
    let probes = unequal_layout();
    let spindle = format!(
        "speeds_rpm = [4000.0]\nrevolutions = 4\nsamples_per_revolution = {M}\n\
         [spindle.artefact]\nkind = \"sphere\"\ndiameter_mm = 25.4\n\
         form = [{{ per_revolution = 3, amplitude_nm = 35.0, phase_deg = 50.0 }}]\n{probes}"
    );
    let ev = evaluated(&load("vmc3", &errors, &spindle), 1);
    let sep = ev
        .separations
        .iter()
        .find(|s| s.method == "multi-probe")
        .expect("a multi-probe separation");
    assert!(
        sep.blind.is_empty() && sep.unknown.is_empty(),
        "{:?}",
        sep.blind
    );

    harmonics_are(
        &sep.form_harmonics,
        |k| {
            if k == 3 {
                coefficients(35.0 * NM, 50.0)
            } else {
                [0.0, 0.0]
            }
        },
        "form",
    );
    let axes: Vec<&str> = sep.motions.iter().map(|m| m.axis.as_str()).collect();
    assert_eq!(axes, ["X", "Y", "rotating"]);
    let (x, y, rotating) = (motion(sep, "X"), motion(sep, "Y"), motion(sep, "rotating"));
    harmonics_are(
        &x.harmonics,
        |k| {
            if k == 2 {
                coefficients(0.10 * UM, 0.0)
            } else {
                [0.0, 0.0]
            }
        },
        "motion X",
    );
    harmonics_are(
        &y.harmonics,
        |k| {
            if k == 3 {
                coefficients(0.07 * UM, -45.0)
            } else {
                [0.0, 0.0]
            }
        },
        "motion Y",
    );
    // Formula (1) on the separated X and Y: E_X cos θ + E_Y sin θ, from the closed forms.
    let ex = sampled(2.0, 0.10 * UM, 0.0);
    let ey = sampled(3.0, 0.07 * UM, -45.0);
    let turning: Vec<Real> = grid(M)
        .iter()
        .enumerate()
        .map(|(m, t)| ex[m] * t.cos() + ey[m] * t.sin())
        .collect();
    let rotating_sync = mtwin::kinds::spindle::analysis::motion::synchronous(&rotating.signal);
    for (m, (got, want)) in rotating_sync.iter().zip(&turning).enumerate() {
        close(*got, *want, EXACT, &format!("rotating at m = {m}"));
    }

    let form = sampled(3.0, 35.0 * NM, 50.0);
    for f in &sep.form_values {
        close(
            f.value(),
            range(&form),
            EXACT,
            &format!("form about {}", f.centre),
        );
    }
    synchronous_everywhere(x, range(&ex), "motion X");
    synchronous_everywhere(y, range(&ey), "motion Y");
    for v in &x.values {
        half_upr_band(v.asynchronous, a_async, "motion X");
    }
    for v in &y.values {
        close(v.asynchronous, 0.0, EXACT, "motion Y: no asynchronous part");
        close(
            v.total,
            v.synchronous,
            EXACT,
            "motion Y: total is synchronous",
        );
    }
}

#[test]
fn a_misplaced_probe_shows_in_the_layout_s_misfit_and_its_uncertainty_covers_the_error() {
    // The layout of the multi-probe test, noise-free, a 3-lobe form of 35 nm and 0.10 µm of
    // 2-UPR motion along X. Exact, the model of form and motion holds the readings: no misfit.
    // With a probe misplaced or its gain wrong it no longer does: the misfit enters the budget
    // and the separated values' errors against the injected truth stay within U.
    let errors = harmonics("EXS", &[harmonic(2, 0.10, 0.0, "um")]);
    let probes = unequal_layout();
    let spindle = format!(
        "speeds_rpm = [4000.0]\nrevolutions = 4\nsamples_per_revolution = {M}\n\
         [spindle.artefact]\nkind = \"sphere\"\ndiameter_mm = 25.4\n\
         form = [{{ per_revolution = 3, amplitude_nm = 35.0, phase_deg = 50.0 }}]\n{probes}"
    );
    let s = load("vmc3", &errors, &spindle);
    let test = s.spindle_test.as_ref().unwrap();
    let table = run::simulate(&s.twin, test, 1).unwrap();
    let separated = |table: &mtwin::kinds::spindle::table::SpindleTable| {
        let ev = evaluate(
            &table.record,
            table.samples_per_revolution,
            &Options::default(),
        )
        .unwrap();
        ev.separations
            .into_iter()
            .find(|s| s.method == "multi-probe")
            .unwrap()
    };
    let misfit = |sep: &Separated| {
        let last = sep.uncertainty.contributions.last().unwrap();
        assert!(last.source.starts_with("separation"), "{}", last.source);
        last.u
    };
    let exact = separated(&table);
    assert!(misfit(&exact) < 1e-15, "exact layout: {:e}", misfit(&exact));

    let form_truth = range(&sampled(3.0, 35.0 * NM, 50.0));
    let motion_truth = range(&sampled(2.0, 0.10 * UM, 0.0));
    // Four faults a real layout has: a probe 1° or −2° from its stated azimuth, a gain 1 %
    // high or 2 % low. Each shows in the misfit; U (with Student's factor for the few degrees
    // of freedom a misfit in two harmonics has) covers the error it makes.
    let faults: [(&str, Real, Real); 4] = [
        ("p2", 1.0, 1.0),
        ("p3", -2.0, 1.0),
        ("p1", 0.0, 1.01),
        ("p4", 0.0, 0.98),
    ];
    for (name, degrees, gain) in faults {
        let mut faulty = table.clone();
        let i = faulty.record.probe(name).unwrap();
        let d = faulty.record.probes[i].direction;
        let phi = (-d[1]).atan2(-d[0]) + degrees.to_radians();
        faulty.record.probes[i].direction = [-phi.cos(), -phi.sin(), 0.0];
        faulty.record.readings[i]
            .iter_mut()
            .for_each(|r| *r *= gain);
        let off = separated(&faulty);
        let what = format!("{name} {degrees}° ×{gain}");
        assert!(
            misfit(&off) > 1e-10,
            "{what}: the fault shows: {:e}",
            misfit(&off)
        );
        let form_error = (off.form_values[0].value() - form_truth).abs();
        let motion_error = (motion(&off, "X").values[0].synchronous - motion_truth).abs();
        let u = off.uncertainty.synchronous;
        assert!(
            form_error <= u,
            "{what}: form off by {form_error:e}, U {u:e}"
        );
        assert!(
            motion_error <= u,
            "{what}: motion off by {motion_error:e}, U {u:e}"
        );
        assert!(
            form_error > 1e-10 || motion_error > 1e-10,
            "{what}: the error is real"
        );
    }
}

#[test]
fn a_face_reversal_separates_the_tilt_from_the_face_and_the_axial_motion() {
    // A cylinder's end face probed at R = 10 mm on +x (probe `f`, reading +z), a probe `z` on
    // the axis; EBS = 2 µrad·sin(2θ + 30°), EZS = 0.05 µm·sin 3θ; set-ups normal and reversed
    // (the artefact turned 180°, the face probe moved to 180°). A tilt E_B about y moves the
    // face point (±R, 0, 0) along z by ∓R·E_B, so f reads r1 = E_Z − R·E_B, then
    // r2 = E_Z + R·E_B: the part that reverses is W = (r2 − r1)/2 = R·E_B, the rest
    // −(r1 + r2)/2 = −E_Z, which the axial probe (reading E_Z) takes out, leaving the face
    // form: none here.
    let errors = harmonics("EBS", &[harmonic(2, 2.0, 30.0, "urad")])
        + &harmonics("EZS", &[harmonic(3, 0.05, 0.0, "um")]);
    let spindle = |axial: bool| {
        format!(
            "speeds_rpm = [3000.0]\nrevolutions = 2\nsamples_per_revolution = {M}\n\
             setups = [\"normal\", \"reversed\"]\n\
             [spindle.artefact]\nkind = \"cylinder\"\ndiameter_mm = 25.0\nlength_mm = 80.0\n\
             [[spindle.probe]]\nname = \"f\"\nkind = \"face\"\nradius_mm = 10.0\nazimuth_deg = 0.0\n{}",
            if axial {
                "[[spindle.probe]]\nname = \"z\"\nkind = \"axial\"\n"
            } else {
                ""
            }
        )
    };
    let ev = evaluated(&load("vmc3", &errors, &spindle(true)), 1);
    let sep = ev
        .separations
        .iter()
        .find(|s| s.method == "face reversal")
        .unwrap_or_else(|| {
            panic!(
                "no face reversal: {:?}",
                ev.separations.iter().map(|s| s.method).collect::<Vec<_>>()
            )
        });
    assert_eq!(sep.probes, ["f"]);
    let r = 10e-3;
    let tilt = &sep.motions[0];
    assert_eq!(tilt.azimuth, Some(0.0));
    harmonics_are(
        &tilt.harmonics,
        |k| {
            if k == 2 {
                coefficients(r * 2.0 * URAD, 30.0)
            } else {
                [0.0, 0.0]
            }
        },
        "W = R·E_B",
    );
    synchronous_everywhere(tilt, range(&sampled(2.0, r * 2.0 * URAD, 30.0)), "W");
    harmonics_are(&sep.form_harmonics, |_| [0.0, 0.0], "no face form");

    // Without the axial probe the form keeps −E_Z(−ψ) = 0.05 µm·sin 3ψ, and says so.
    let ev = evaluated(&load("vmc3", &errors, &spindle(false)), 1);
    let sep = ev
        .separations
        .iter()
        .find(|s| s.method == "face reversal with axial motion")
        .expect("a face reversal without the axial probe");
    harmonics_are(
        &sep.form_harmonics,
        |k| {
            if k == 3 {
                coefficients(0.05 * UM, 0.0)
            } else {
                [0.0, 0.0]
            }
        },
        "the axial motion in the form",
    );
}
