//! The spindle error analyser through the whole chain: scenario → twin → virtual analyser
//! (`kinds::spindle::run::simulate`) → ISO 230-7 evaluation (`kinds::spindle::evaluate`),
//! against closed forms derived here and against the injected truth.
//!
//! Conventions (module docs of `kinds::spindle::instrument` and `tests/it/spindle_twin.rs`):
//!
//! - vmc3's spindle S is on the tool side; its component errors (tool relative to workpiece,
//!   in the S slot frame, parallel to the machine axes) are the artefact's motion `E` relative
//!   to the probes on the table. A fixed radial probe at stator azimuth φ reads
//!   `−(E_X cos φ + E_Y sin φ) − h(φ − θ)`, so `x1 = −EXS`, `y1 = −EYS`; the axial probe reads
//!   `+EZS`. Tilt about the gauge line (150 mm above the artefact's reference point):
//!   `x2 − x1 = −L·EBS`, `y2 − y1 = +L·EAS` (L the station separation).
//! - A harmonic `{ period_deg = 360/k, amplitude, phase_deg = φ }` is `a·sin(kθ + φ)` of the
//!   axis angle; an asynchronous line `{ per_revolution = r }` is `a·sin(r·q + φ)` of the
//!   unwrapped angle `q`, which starts at 0 with the first record (no settling here:
//!   `bandwidth_hz = inf` and `settle_s = 0`).
//! - The evaluation's grid is `θ_m = 2πm/M`; every closed form below is evaluated on it.
//!
//! Most records use `M = 240` samples a revolution: 240 is divisible by 2k for k = 2, 3, 4, 5,
//! 6, so with the phases chosen here (`(90° − φ)/k` a multiple of the 1.5° step) every peak
//! and trough of an injected k-UPR harmonic falls on a sample, and its sampled range is
//! exactly `2a` — no grid allowance is needed except where stated.
//!
//! Tolerances:
//! - `EXACT = 1e-12 m` for translations: a translation error, an eccentricity and the artefact
//!   form enter the reading exactly (rigid translations, no second-order term); what is left
//!   is the rounding of poses whose translations are under 1 m (about 1e-16 m a sample), four
//!   orders below the tolerance.
//! - Rotations (tilt, location errors of a table axis) add second-order terms
//!   `ε²·|r|/2` and `ε·d`, stated at each test.
//! - Noise: multiples of σ/√K (a bin mean) or σ√(2/N) (a spectral line), with the probability
//!   of a false failure stated.

use mtwin::app::Scenario;
use mtwin::kinds::spindle::analysis::motion::{Direction, ErrorMotionValues, decompose};
use mtwin::kinds::spindle::analysis::polar::Centre;
use mtwin::kinds::spindle::evaluate::{Evaluation, Options, Segment, Test, evaluate};
use mtwin::kinds::spindle::{Sensing, run};
use mtwin::math::Real;
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::path::Path;

const UM: Real = 1e-6;
const NM: Real = 1e-9;
const URAD: Real = 1e-6;
/// Exact kinematics of translations (see the module docs).
const EXACT: Real = 1e-12;
/// Samples per revolution of most records (see the module docs).
const M: usize = 240;

/// A scenario on `machine` with `errors` and the `[spindle]` keys and sub-tables `spindle`,
/// written into a temporary folder (the machine by absolute path). The probes are exact (no
/// noise, resolution or filter) and nothing settles unless `spindle` says otherwise.
fn load(machine: &str, errors: &str, spindle: &str) -> Scenario {
    let exact = [
        "noise_nm = 0.0",
        "resolution_nm = 0.0",
        "bandwidth_hz = inf",
        "settle_s = 0.0",
    ]
    .into_iter()
    .filter(|k| !spindle.contains(k.split(' ').next().unwrap()))
    .collect::<Vec<_>>()
    .join("\n");
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let text = format!(
        "schema = 1\nmachine = \"{}\"\nseed = 5\n{errors}\n[spindle]\n{exact}\n{spindle}\n",
        models.join(format!("{machine}.urdf")).display()
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.toml");
    std::fs::write(&path, &text).unwrap();
    Scenario::load(&path).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Simulates the scenario's spindle test with noise seed `seed` and evaluates the record with
/// the default options (all five centres).
fn evaluated(s: &Scenario, seed: u64) -> Evaluation {
    let test = s.spindle_test.as_ref().expect("a [spindle] section");
    let table = run::simulate(&s.twin, test, seed).unwrap();
    assert_eq!(table.samples_per_revolution, test.samples_per_revolution);
    evaluate(
        &table.record,
        table.samples_per_revolution,
        &Options::default(),
    )
    .unwrap()
}

fn find<'a>(segment: &'a Segment, name: &str) -> &'a Test {
    segment
        .tests
        .iter()
        .find(|t| t.name == name)
        .unwrap_or_else(|| {
            let names: Vec<&str> = segment.tests.iter().map(|t| t.name.as_str()).collect();
            panic!("no test {name:?} among {names:?}")
        })
}

fn about(test: &Test, centre: Centre) -> &ErrorMotionValues {
    test.values
        .iter()
        .find(|v| v.centre == centre)
        .unwrap_or_else(|| panic!("{}: no value about {centre}", test.name))
}

/// `a·sin(kθ + φ)` as an error-model harmonic (period 360°/k).
fn harmonic(k: u32, amplitude: Real, phase_deg: Real, unit: &str) -> String {
    format!(
        "{{ period_deg = {}, amplitude_{unit} = {amplitude}, phase_deg = {phase_deg} }}",
        360.0 / k as Real
    )
}

/// An `[errors.NAME]` section of harmonics.
fn harmonics(name: &str, terms: &[String]) -> String {
    format!("[errors.{name}]\nharmonic = [{}]\n", terms.join(", "))
}

/// The grid `θ_m = 2πm/M`.
fn grid(m: usize) -> Vec<Real> {
    (0..m).map(|i| TAU * i as Real / m as Real).collect()
}

fn range(v: &[Real]) -> Real {
    let (lo, hi) = v
        .iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &x| {
            (l.min(x), h.max(x))
        });
    hi - lo
}

/// The 1-UPR Fourier coefficients `(2/M) Σ p cos θ_m`, `(2/M) Σ p sin θ_m` of a profile on the
/// full grid: the LSC offset of ISO 230-7 §3.7.4 in the limaçon model (digest §2.7), computed
/// here on its own.
fn first_harmonic(p: &[Real]) -> [Real; 2] {
    let n = p.len() as Real;
    let (mut a, mut b) = (0.0, 0.0);
    for (&v, t) in p.iter().zip(grid(p.len())) {
        a += v * t.cos();
        b += v * t.sin();
    }
    [2.0 * a / n, 2.0 * b / n]
}

/// The range of `p` about the centre `c`: `max − min` of `p[m] − c·(cos θ_m, sin θ_m)`.
fn range_about(p: &[Real], c: [Real; 2]) -> Real {
    let rho: Vec<Real> = p
        .iter()
        .zip(grid(p.len()))
        .map(|(v, t)| v - c[0] * t.cos() - c[1] * t.sin())
        .collect();
    range(&rho)
}

/// The LSC value of a synchronous profile: its range with the first harmonic removed.
fn lsc_value(p: &[Real]) -> Real {
    range_about(p, first_harmonic(p))
}

#[track_caller]
fn close(got: Real, want: Real, tolerance: Real, what: &str) {
    assert!(
        (got - want).abs() <= tolerance,
        "{what}: {got:e}, expected {want:e} (off by {:e}, tolerance {tolerance:e})",
        (got - want).abs()
    );
}

/// The largest |signal − want(θ_m)| over every revolution of a test's signal.
fn worst_over_signal(test: &Test, want: impl Fn(Real) -> Real) -> Real {
    let m = test.signal.samples_per_revolution();
    let angles = grid(m);
    test.signal
        .values()
        .iter()
        .enumerate()
        .map(|(i, v)| (v - want(angles[i % m])).abs())
        .fold(0.0, Real::max)
}

/// Every value of `test` about every centre is zero: synchronous, total, asynchronous,
/// fundamental, residual, inner, outer.
#[track_caller]
fn all_zero(test: &Test, tolerance: Real) {
    for v in &test.values {
        for (what, x) in [
            ("synchronous", v.synchronous),
            ("total", v.total),
            ("asynchronous", v.asynchronous),
            ("fundamental", v.fundamental),
            ("residual", v.residual),
            ("inner", v.inner),
            ("outer", v.outer),
        ] {
            close(
                x,
                0.0,
                tolerance,
                &format!("{} {what} about {}", test.name, v.centre),
            );
        }
    }
}

/// `[[spindle.probe]]` blocks of radial probes p1, p2, … at `azimuths` (°).
fn radial_probes(azimuths: &[Real]) -> String {
    azimuths
        .iter()
        .enumerate()
        .map(|(i, a)| {
            format!(
                "[[spindle.probe]]\nname = \"p{}\"\nkind = \"radial\"\nazimuth_deg = {a}\n",
                i + 1
            )
        })
        .collect()
}

/// `radial …` on a sphere with the default nest (x1 at 0°, y1 at 90°, z on the axis).
fn sphere(extra: &str, artefact: &str) -> String {
    format!(
        "speeds_rpm = [3000.0]\nrevolutions = 20\nsamples_per_revolution = {M}\n{extra}\n\
         [spindle.artefact]\nkind = \"sphere\"\ndiameter_mm = 25.4\n{artefact}\n"
    )
}

/// The default five-probe nest on a 25 × 80 mm cylinder: x1, y1 at its free end, x2, y2 80 mm
/// up, z on the axis.
fn cylinder(extra: &str, artefact: &str) -> String {
    format!(
        "speeds_rpm = [3000.0]\nrevolutions = 20\nsamples_per_revolution = {M}\n{extra}\n\
         [spindle.artefact]\nkind = \"cylinder\"\ndiameter_mm = 25.0\nlength_mm = 80.0\n{artefact}\n"
    )
}

#[test]
fn pure_eccentricity_is_all_fundamental() {
    // The artefact 1.5 µm, −0.8 µm off centre on the rotor, a perfect spindle. A fixed probe at
    // φ reads −e·cos(φ − θ − α), |e| = 1.7 µm at α = atan2(−0.8, 1.5): a pure 1-UPR sinusoid.
    // ISO 230-7 (digest §2.7): every profile centre (LSC, MRS, MIC, MCC) absorbs a 1-UPR term,
    // so all values about them are 0; about PC the synchronous value is the sampled range,
    // 2e·cos(δ) ≥ 2e·cos(π/M) for the grid's worst phase δ ≤ π/M, and the fundamental (the
    // DFT's exact 1-UPR amplitude) is 2e. In the rotating sensitive direction (formula (1))
    // the eccentric circle is a constant, `E_X cos θ + E_Y sin θ = e·cos α`: no value at all.
    let (ex, ey) = (1.5 * UM, -0.8 * UM);
    let (e, alpha) = (ex.hypot(ey), ey.atan2(ex));
    let s = load("vmc3", "", &cylinder("", "eccentricity_um = [1.5, -0.8]"));
    let ev = evaluated(&s, 1);
    assert_eq!(ev.segments.len(), 1);
    let seg = &ev.segments[0];
    let names: Vec<&str> = seg.tests.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "radial x1",
            "radial y1",
            "radial x2",
            "radial y2",
            "axial z",
            "radial x1+y1 rotating",
            "radial x2+y2 rotating",
            "tilt x1-x2",
            "tilt y1-y2",
            "tilt x1+y1-x2+y2 rotating",
        ]
    );
    let theta = grid(M);
    let grid_deficit = 2.0 * e * (1.0 - (PI / M as Real).cos());
    for (name, phi) in [
        ("radial x1", 0.0),
        ("radial y1", FRAC_PI_2),
        ("radial x2", 0.0),
        ("radial y2", FRAC_PI_2),
    ] {
        let t = find(seg, name);
        assert_eq!(t.direction, Direction::Radial);
        assert_eq!(t.values[0].centre, Centre::Lsc, "{name}: preferred centre");
        assert_eq!(t.values.len(), 5);
        let reading: Vec<Real> = theta
            .iter()
            .map(|&t| -e * (phi - t - alpha).cos())
            .collect();
        close(
            worst_over_signal(t, |t| -e * (phi - t - alpha).cos()),
            0.0,
            EXACT,
            &format!("{name}: signal"),
        );
        for v in &t.values {
            let what = format!("{name} about {}", v.centre);
            close(v.asynchronous, 0.0, EXACT, &format!("{what}: asynchronous"));
            close(
                v.fundamental,
                2.0 * e,
                EXACT,
                &format!("{what}: fundamental"),
            );
            close(v.residual, 0.0, EXACT, &format!("{what}: residual"));
            if v.centre == Centre::Pc {
                close(v.offset[0].hypot(v.offset[1]), 0.0, 0.0, &what);
                close(
                    v.synchronous,
                    range(&reading),
                    EXACT,
                    &format!("{what}: sync"),
                );
                close(v.total, range(&reading), EXACT, &format!("{what}: total"));
                assert!(
                    v.synchronous <= 2.0 * e + EXACT
                        && v.synchronous >= 2.0 * e - grid_deficit - EXACT,
                    "{what}: {:e} not within the grid bound of 2e = {:e}",
                    v.synchronous,
                    2.0 * e
                );
            } else {
                close(v.synchronous, 0.0, EXACT, &format!("{what}: synchronous"));
                close(v.total, 0.0, EXACT, &format!("{what}: total"));
                close(v.inner, 0.0, EXACT, &format!("{what}: inner"));
                close(v.outer, 0.0, EXACT, &format!("{what}: outer"));
                // The centre found is the eccentric circle's: the reading's 1-UPR coefficients
                // −e·cos(φ − θ − α) = −e cos(φ−α) cos θ − e sin(φ−α) sin θ.
                close(v.offset[0], -e * (phi - alpha).cos(), EXACT, &what);
                close(v.offset[1], -e * (phi - alpha).sin(), EXACT, &what);
            }
        }
    }
    for name in ["radial x1+y1 rotating", "radial x2+y2 rotating"] {
        let t = find(seg, name);
        close(
            worst_over_signal(t, |_| e * alpha.cos()),
            0.0,
            EXACT,
            &format!("{name}: e·cos α"),
        );
        all_zero(t, EXACT);
    }
    // Nothing axial, no tilt: the cylinder's face is square and the two stations see the same.
    all_zero(find(seg, "axial z"), EXACT);
    for name in ["tilt x1-x2", "tilt y1-y2", "tilt x1+y1-x2+y2 rotating"] {
        // rad: the station difference is exactly 0, divided by 80 mm.
        all_zero(find(seg, name), EXACT / 0.08);
    }
}

#[test]
fn a_k_per_revolution_error_has_value_2a_about_every_centre() {
    // EXS = a·sin(kθ + φ), peaks and troughs on the grid (module docs). Fixed x1 reads −EXS:
    // for k ≥ 2 no centre can shrink it: a centre c shifts the plot by −c·u(θ), and over the k
    // equally spaced peaks (or troughs) the unit vectors u sum to zero, so c·u ≤ 0 at one peak
    // and ≥ 0 at one trough: the range about any c is at least 2a, and 2a about c = 0. So the
    // synchronous value is 2a about PC, LSC, MRS, MIC and MCC; nothing asynchronous; the
    // spectrum's largest line is k UPR of amplitude a. y1 reads −EYS = 0.
    //
    // Rotating sensitive direction (formula (1)): r = E_X cos θ = a·sin(kθ + φ)·cos θ
    //   = (a/2)·[sin((k+1)θ + φ) + sin((k−1)θ + φ)],
    // harmonics k ± 1; for k = 2 the second is 1 UPR, which the LSC removes, leaving
    // (a/2)·sin(3θ + φ): value a (to the grid: its peaks fall between samples). The LSC value
    // is checked against these harmonics and against the product evaluated on the grid with
    // its own first harmonic removed.
    let a = 0.2 * UM;
    for (k, phase) in [(2u32, 30.0), (3, 45.0), (5, 30.0)] {
        let kf = k as Real;
        let phi = (phase as Real).to_radians();
        let errors = harmonics("EXS", &[harmonic(k, 0.2, phase, "um")]);
        let s = load("vmc3", &errors, &sphere("", ""));
        let ev = evaluated(&s, 1);
        let seg = &ev.segments[0];
        let exs = |t: Real| a * (kf * t + phi).sin();
        // The phase puts the extremes on the grid: the sampled range is 2a to rounding.
        let sampled: Vec<Real> = grid(M).into_iter().map(exs).collect();
        close(range(&sampled), 2.0 * a, 1e-20, "grid choice");

        let x1 = find(seg, "radial x1");
        close(
            worst_over_signal(x1, |t| -exs(t)),
            0.0,
            EXACT,
            &format!("k = {k}: x1 = −EXS"),
        );
        for v in &x1.values {
            let what = format!("k = {k}: x1 about {}", v.centre);
            close(
                v.synchronous,
                2.0 * a,
                EXACT,
                &format!("{what}: synchronous"),
            );
            close(v.total, 2.0 * a, EXACT, &format!("{what}: total"));
            close(v.asynchronous, 0.0, EXACT, &format!("{what}: asynchronous"));
            close(v.fundamental, 0.0, EXACT, &format!("{what}: fundamental"));
            close(v.residual, 2.0 * a, EXACT, &format!("{what}: residual"));
        }
        let top = x1.lines[0];
        assert!(
            top.synchronous && top.per_revolution == kf,
            "k = {k}: {top:?}"
        );
        close(top.amplitude, a, EXACT, &format!("k = {k}: line amplitude"));
        close(x1.lines[1].amplitude, 0.0, EXACT, "second line");

        let y1 = find(seg, "radial y1");
        close(worst_over_signal(y1, |_| 0.0), 0.0, EXACT, "y1 reads 0");
        all_zero(y1, EXACT);

        let rot = find(seg, "radial x1+y1 rotating");
        close(
            worst_over_signal(rot, |t| exs(t) * t.cos()),
            0.0,
            EXACT,
            &format!("k = {k}: E_X cos θ"),
        );
        // The product as its two harmonics, the 1-UPR one left out for k = 2 (LSC).
        let product: Vec<Real> = grid(M)
            .into_iter()
            .map(|t| {
                let upper = 0.5 * a * ((kf + 1.0) * t + phi).sin();
                let lower = if k >= 3 {
                    0.5 * a * ((kf - 1.0) * t + phi).sin()
                } else {
                    0.0
                };
                upper + lower
            })
            .collect();
        let lsc = about(rot, Centre::Lsc);
        close(
            lsc.synchronous,
            range(&product),
            EXACT,
            &format!("k = {k}: rotating LSC value"),
        );
        let direct: Vec<Real> = grid(M).into_iter().map(|t| exs(t) * t.cos()).collect();
        close(
            lsc.synchronous,
            lsc_value(&direct),
            EXACT,
            "rotating LSC value, direct",
        );
        if k == 2 {
            // (a/2)·sin(3θ + 30°) peaks at 20°, between samples (1.5° apart): its sampled range
            // is a within the grid's a·(1 − cos(3π/M)) = 1.5e-10 m.
            let grid_deficit = a * (1.0 - (3.0 * PI / M as Real).cos());
            assert!(
                lsc.synchronous <= a + EXACT && lsc.synchronous >= a - grid_deficit,
                "k = 2: rotating LSC value {:e}, a = {a:e}",
                lsc.synchronous
            );
            close(lsc.fundamental, a, EXACT, "k = 2: the 1-UPR (a/2) term");
        } else {
            close(lsc.fundamental, 0.0, EXACT, "k ≥ 3: no 1-UPR");
        }
    }
}

#[test]
fn an_elliptical_fundamental_shows_only_in_the_rotating_direction() {
    // ISO 230-7 A.7.6 (digest §2.9): EXS = (e − δ) cos θ, EYS = (e + δ) sin θ, the symmetric
    // forward whirl e and the asymmetric backward whirl δ. Each fixed probe reads a pure 1-UPR
    // sinusoid: nothing about LSC, MRS, MIC, MCC; 2(e ∓ δ) about PC (extremes at 0°, 90°, …
    // on the grid) and as the fundamental. Rotating: r = (e − δ) cos²θ + (e + δ) sin²θ
    // = e − δ·cos 2θ: synchronous value 2δ about every centre (its extremes at 0° and 90°),
    // no fundamental, and its mean (the LSC radius less r0) is e.
    let (e, d) = (0.3 * UM, 0.1 * UM);
    let errors = harmonics("EXS", &[harmonic(1, 0.2, 90.0, "um")])
        + &harmonics("EYS", &[harmonic(1, 0.4, 0.0, "um")]);
    let s = load("vmc3", &errors, &sphere("", ""));
    let ev = evaluated(&s, 1);
    let seg = &ev.segments[0];
    for (name, amplitude) in [("radial x1", e - d), ("radial y1", e + d)] {
        let t = find(seg, name);
        for v in &t.values {
            let what = format!("{name} about {}", v.centre);
            let want = if v.centre == Centre::Pc {
                2.0 * amplitude
            } else {
                0.0
            };
            close(v.synchronous, want, EXACT, &format!("{what}: synchronous"));
            close(v.total, want, EXACT, &format!("{what}: total"));
            close(v.asynchronous, 0.0, EXACT, &format!("{what}: asynchronous"));
            close(
                v.fundamental,
                2.0 * amplitude,
                EXACT,
                &format!("{what}: fundamental"),
            );
        }
    }
    let rot = find(seg, "radial x1+y1 rotating");
    close(
        worst_over_signal(rot, |t| e - d * (2.0 * t).cos()),
        0.0,
        EXACT,
        "r = e − δ cos 2θ",
    );
    let mean = rot.signal.values().iter().sum::<Real>() / rot.signal.values().len() as Real;
    close(mean, e, EXACT, "the LSC radius: e");
    for v in &rot.values {
        let what = format!("rotating about {}", v.centre);
        close(v.synchronous, 2.0 * d, EXACT, &format!("{what}: 2δ"));
        close(v.total, 2.0 * d, EXACT, &format!("{what}: total"));
        close(v.asynchronous, 0.0, EXACT, &format!("{what}: asynchronous"));
        close(v.fundamental, 0.0, EXACT, &format!("{what}: fundamental"));
    }

    // The same spindle read by probes turning with it (sensing = "rotating", the artefact on
    // the table): X = M⁻¹·Rot_z(θ) = Trans(−Rot_z(−θ)·E) for M = Trans(E)·Rot_z(θ), so a probe
    // at rotor azimuth φ, direction −(cos φ, sin φ), reads E_X cos(φ + θ) + E_Y sin(φ + θ):
    // at φ = 0 formula (1) itself, e − δ cos 2θ; at φ = 90°
    // −(e − δ) cos θ sin θ + (e + δ) sin θ cos θ = δ sin 2θ. Both: 2δ about every centre.
    let s = load("vmc3", &errors, &sphere("sensing = \"rotating\"", ""));
    let ev = evaluated(&s, 1);
    let seg = &ev.segments[0];
    let x_rotating = |t: Real| e - d * (2.0 * t).cos();
    let y_rotating = |t: Real| d * (2.0 * t).sin();
    for (name, want) in [
        ("radial x1 rotating", &x_rotating as &dyn Fn(Real) -> Real),
        ("radial y1 rotating", &y_rotating),
    ] {
        let t = find(seg, name);
        assert_eq!(t.sensing, Sensing::Rotating);
        close(worst_over_signal(t, want), 0.0, EXACT, name);
        for v in &t.values {
            let what = format!("{name} about {}", v.centre);
            close(v.synchronous, 2.0 * d, EXACT, &format!("{what}: 2δ"));
            close(v.fundamental, 0.0, EXACT, &format!("{what}: fundamental"));
        }
    }
}

#[test]
fn an_asynchronous_line_gives_the_closed_form_band_and_leaks_only_by_averaging() {
    // EXS = a·sin(r·q + φ) on the unwrapped angle q = 2π(k + m/M) (the record starts at q = 0,
    // nothing settles): x1 reads s[k, m] = −a·sin(2πr(k + m/M) + φ). ISO 230-7 §3.8.4: the
    // asynchronous value is the widest band at one angle, max_m (max_k s − min_k s), computed
    // here from the closed form. The synchronous profile S[m] = (1/K) Σ_k s[k, m] keeps what
    // averaging lets through: |S[m]| ≤ a·|Σ_k e^{i2πrk}|/K (the leak), so its PC value is at
    // most twice that; its exact values are computed from the closed form here too.
    let (a, phase) = (0.1 * UM, 25.0);
    let phi = (phase as Real).to_radians();
    let k_count = 20;
    for r in [0.43, 0.45] {
        let errors = format!(
            "[errors.EXS]\nasynchronous = [{{ amplitude_um = 0.1, per_revolution = {r}, phase_deg = {phase} }}]\n"
        );
        let s = load("vmc3", &errors, &sphere("", ""));
        let ev = evaluated(&s, 1);
        let x1 = find(&ev.segments[0], "radial x1");
        assert_eq!(x1.signal.count(), k_count);
        let reading =
            |k: usize, m: usize| -a * (TAU * r * (k as Real + m as Real / M as Real) + phi).sin();
        close(
            x1.signal
                .values()
                .iter()
                .enumerate()
                .map(|(i, v)| (v - reading(i / M, i % M)).abs())
                .fold(0.0, Real::max),
            0.0,
            EXACT,
            &format!("r = {r}: x1 = −EXS"),
        );
        let band = (0..M)
            .map(|m| range(&(0..k_count).map(|k| reading(k, m)).collect::<Vec<_>>()))
            .fold(0.0, Real::max);
        let synchronous: Vec<Real> = (0..M)
            .map(|m| (0..k_count).map(|k| reading(k, m)).sum::<Real>() / k_count as Real)
            .collect();
        let leak = {
            let (re, im) = (0..k_count).fold((0.0, 0.0), |(re, im), k| {
                let x = TAU * r * k as Real;
                (re + x.cos(), im + x.sin())
            });
            a * re.hypot(im) / k_count as Real
        };
        let c = first_harmonic(&synchronous);
        let all: Vec<Real> = x1.signal.values().to_vec();
        for v in &x1.values {
            let what = format!("r = {r}: x1 about {}", v.centre);
            close(
                v.asynchronous,
                band,
                EXACT,
                &format!("{what}: asynchronous"),
            );
            match v.centre {
                Centre::Pc => {
                    close(v.synchronous, range(&synchronous), EXACT, &what);
                    assert!(
                        v.synchronous <= 2.0 * leak + EXACT,
                        "{what}: beyond the leak"
                    );
                    close(v.total, range(&all), EXACT, &format!("{what}: total"));
                }
                Centre::Lsc => {
                    close(v.synchronous, lsc_value(&synchronous), EXACT, &what);
                    // The total about the same centre, every revolution pooled.
                    let shifted: Vec<Real> = all
                        .iter()
                        .enumerate()
                        .map(|(i, x)| {
                            let t = TAU * (i % M) as Real / M as Real;
                            x - c[0] * t.cos() - c[1] * t.sin()
                        })
                        .collect();
                    close(v.total, range(&shifted), EXACT, &format!("{what}: total"));
                }
                // The minimum zone is at most any other centre's value (digest §2.7).
                Centre::Mrs => assert!(
                    v.synchronous <= lsc_value(&synchronous) + EXACT
                        && v.synchronous <= range(&synchronous) + EXACT,
                    "{what}"
                ),
                _ => assert!(
                    v.synchronous >= about(x1, Centre::Mrs).synchronous - EXACT,
                    "{what}"
                ),
            }
            close(v.fundamental, 2.0 * c[0].hypot(c[1]), EXACT, &what);
        }
        if r == 0.45 {
            // 0.45 × 20 = 9 whole cycles over the record: the average over the revolutions
            // cancels exactly (Σ_k e^{i2π·0.45k} = 0), and the line falls on bin 9 = 0.45 UPR
            // with amplitude a, marked asynchronous.
            close(leak, 0.0, 1e-20, "no leak");
            for v in &x1.values {
                close(v.synchronous, 0.0, EXACT, "r = 0.45: synchronous");
                close(v.fundamental, 0.0, EXACT, "r = 0.45: fundamental");
            }
            let top = x1.lines[0];
            assert!(!top.synchronous && top.per_revolution == 0.45, "{top:?}");
            close(top.amplitude, a, EXACT, "r = 0.45: line amplitude");
            close(x1.lines[1].amplitude, 0.0, EXACT, "r = 0.45: one line only");
        } else {
            // 0.43 leaks about 4.9 % of a into the synchronous average.
            assert!(leak > 0.04 * a && leak < 0.06 * a, "leak {leak:e}");
            assert!(about(x1, Centre::Pc).synchronous > 0.5 * leak);
        }
    }
}

#[test]
fn the_axial_fundamental_is_kept_and_a_4_upr_term_adds_its_own_2b() {
    // EZS = a·sin θ (+ b·sin(4θ + 30°)); the axial probe reads +EZS. ISO 230-7 Tab 1: axial
    // about PC, the fundamental kept (§5.3.4.3): PC synchronous value 2a for the 1-UPR term
    // alone (extremes at 90° and 270°, on the grid), fundamental value 2a. The 4-UPR term
    // adds its own 2b as the residual value and as the LSC value (which removes the 1 UPR);
    // the PC value of the sum is its range, evaluated on the grid here.
    let (a, b) = (0.06 * UM, 0.02 * UM);
    let z_only = harmonics("EZS", &[harmonic(1, 0.06, 0.0, "um")]);
    let both = harmonics(
        "EZS",
        &[harmonic(1, 0.06, 0.0, "um"), harmonic(4, 0.02, 30.0, "um")],
    );
    for (errors, with_b) in [(z_only, false), (both, true)] {
        let s = load("vmc3", &errors, &cylinder("", ""));
        let ev = evaluated(&s, 1);
        let seg = &ev.segments[0];
        let ezs = |t: Real| {
            a * t.sin()
                + if with_b {
                    b * (4.0 * t + 30f64.to_radians()).sin()
                } else {
                    0.0
                }
        };
        let z = find(seg, "axial z");
        assert_eq!(z.direction, Direction::Axial);
        assert_eq!(z.values[0].centre, Centre::Pc, "axial: PC preferred");
        close(worst_over_signal(z, ezs), 0.0, EXACT, "z = +EZS");
        let profile: Vec<Real> = grid(M).into_iter().map(ezs).collect();
        let pc = about(z, Centre::Pc);
        let lsc = about(z, Centre::Lsc);
        close(pc.fundamental, 2.0 * a, EXACT, "fundamental 2a");
        close(pc.asynchronous, 0.0, EXACT, "asynchronous");
        close(
            pc.synchronous,
            range(&profile),
            EXACT,
            "PC value on the grid",
        );
        if with_b {
            close(pc.residual, 2.0 * b, EXACT, "residual 2b");
            close(lsc.synchronous, 2.0 * b, EXACT, "LSC value 2b");
        } else {
            close(pc.synchronous, 2.0 * a, EXACT, "PC value 2a");
            close(pc.residual, 0.0, EXACT, "no residual");
            close(lsc.synchronous, 0.0, EXACT, "LSC removes it all");
        }
        // The radial probes see nothing of an axial motion.
        all_zero(find(seg, "radial x1"), EXACT);
        all_zero(find(seg, "radial y2"), EXACT);
    }
}

#[test]
fn a_2_upr_tilt_gives_2_beta_in_the_fixed_tilt_test() {
    // EBS = β·sin(2θ + 30°) about the gauge line; the stations x1 (z = 0) and x2 (z = 80 mm)
    // read x2 − x1 = −L·EBS, so `tilt x1-x2` = (x2 − x1)/L = −EBS: synchronous value 2β about
    // every centre (extremes on the grid), nothing asynchronous. `tilt y1-y2` = +EAS = 0.
    // Rotating (Method 2): (ΔX(z2) − ΔX(z1))/L·cos θ + (ΔY(z2) − ΔY(z1))/L·sin θ
    //   = EBS cos θ − EAS sin θ = (β/2)[sin(3θ + 30°) + sin(θ + 30°)]: LSC value β.
    //
    // Tolerance: the rotation is exact (a rotation vector), so the linear reading
    // −(R·(p − pivot) − (p − pivot))·x differs from −ε × (p − pivot) by the second-order
    // ½|ε|²·|p − pivot| ≤ ½·(1e-6)²·0.25 m ≈ 1.3e-13 m a station, 3e-12 rad after the
    // difference over L = 0.08 m; 1e-11 rad covers it.
    let beta = 1.0 * URAD;
    let tolerance = 1e-11;
    let phi = 30f64.to_radians();
    let errors = harmonics("EBS", &[harmonic(2, 1.0, 30.0, "urad")]);
    let s = load("vmc3", &errors, &cylinder("", ""));
    let ev = evaluated(&s, 1);
    let seg = &ev.segments[0];
    let ebs = |t: Real| beta * (2.0 * t + phi).sin();
    let tilt = find(seg, "tilt x1-x2");
    assert_eq!(tilt.direction, Direction::Tilt);
    assert_eq!(tilt.values[0].centre, Centre::Lsc, "tilt: LSC preferred");
    close(
        worst_over_signal(tilt, |t| -ebs(t)),
        0.0,
        tolerance,
        "tilt = −EBS",
    );
    for v in &tilt.values {
        let what = format!("tilt x1-x2 about {}", v.centre);
        close(v.synchronous, 2.0 * beta, tolerance, &format!("{what}: 2β"));
        close(v.total, 2.0 * beta, tolerance, &format!("{what}: total"));
        close(v.asynchronous, 0.0, tolerance, &format!("{what}: async"));
    }
    all_zero(find(seg, "tilt y1-y2"), tolerance);
    let rotating = find(seg, "tilt x1+y1-x2+y2 rotating");
    close(
        worst_over_signal(rotating, |t| ebs(t) * t.cos()),
        0.0,
        tolerance,
        "rotating tilt = EBS cos θ",
    );
    // (β/2)·sin(3θ + 30°) peaks at 20°, between samples: the LSC value is its sampled range,
    // β within the grid's β·(1 − cos(3π/M)).
    let upper: Vec<Real> = grid(M)
        .into_iter()
        .map(|t| 0.5 * beta * (3.0 * t + phi).sin())
        .collect();
    let lsc = about(rotating, Centre::Lsc).synchronous;
    close(lsc, range(&upper), tolerance, "rotating tilt LSC value");
    assert!(
        lsc <= beta + tolerance && lsc >= beta * (3.0 * PI / M as Real).cos() - tolerance,
        "rotating tilt LSC value {lsc:e}, β = {beta:e}"
    );
}

mod directions_and_shifts;
mod separated_values;
mod separation_and_records;
mod uncertainty;
