//! Model selection on the kinematic calibration (`identify --discover`,
//! [`mtwin::estimate::discover`]): an effect hidden in R-test tables — a 2-per-turn radial
//! error motion of C, C's lost motion, the pivot drifting in time — is found from the location
//! errors alone, named, and nothing else is taken; alone, in pairs and all three; tables with
//! none of them accept nothing; and the extended estimate recovers what was hidden.

use super::rotary_components::{probed_three_spheres, truth_of_label};
use super::*;
use mtwin::estimate::discover::{Discovery, Term, discover};
use mtwin::machine::Axis;

/// C turning twice per turn along X by 1.5 µm (a radial error motion of the table).
const WOBBLE: &str =
    "[errors.EXC]\nharmonic = [{ period_deg = 180.0, amplitude_um = 1.5, phase_deg = 30.0 }]\n";
/// C's lost motion: 20 µrad, 2 µm at the sphere 100 mm from C.
const REVERSAL: &str = "[errors.ECC]\nreversal_urad = 20.0\n";
/// The tool tip drifting 10 µm/h along X and 30 µm/h along Z (the spindle growing).
const DRIFT: &str =
    "[errors.EXT]\ndrift = [{ um_per_h = 10.0 }]\n[errors.EZT]\ndrift = [{ um_per_h = 30.0 }]\n";

/// The terms each hidden effect is named by.
const WOBBLE_TERM: Term = Term::Order {
    name: mtwin::errors::ParameterName::Component {
        motion: mtwin::errors::Motion::X,
        axis: Axis::C,
    },
    order: 2,
};
const REVERSAL_TERM: Term = Term::Reversal(Axis::C);

/// The bundled R-test (`scenarios/trunnion5_rtest.toml`: four K-tests, each its own datum,
/// eight location errors) with `hidden` added, a pose every 10 s and every test out and back
/// (C turns both ways, every test reads its start twice), on `seed`; its table read with a
/// drift rate (the library's drift term has its columns).
fn session(seed: u64, hidden: &str) -> (Scenario, Readings) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/trunnion5_rtest.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let mut text = text
        .replace("machine = \"../models/", "machine = \"MODELS/")
        .replace("seed = 7", &format!("seed = {seed}"))
        .replace("[rtest]\n", &format!("{hidden}\n[rtest]\n"))
        .replace(
            "calibration = \"six_point\"\n",
            "calibration = \"six_point\"\ndwell_s = 10.0\n",
        );
    for points in ["points = 37\n", "points = 19\n"] {
        assert!(text.contains(points), "the bundled tests have {points}");
        text = text.replace(points, &format!("{points}back = true\n"));
    }
    simulated(
        &text,
        Setup {
            drift: Drift::Rate,
            ..Setup::default()
        },
    )
}

/// Model selection from the location errors.
fn selected(scenario: &Scenario, set: &Readings) -> Discovery {
    discover(
        &scenario.twin.machine,
        "location",
        std::slice::from_ref(set),
        true,
        |_| {},
    )
    .unwrap()
}

/// The extended estimate (the discovered `--params`, a drift rate when accepted) on the
/// session's table read again as `identify` reads it: every identified error coefficient
/// within 4 u of the truth (the harmonics' by projection of the scenario's functions, the
/// lost motion its 20 µrad), the drift rates within 4 u of 10 and 30 µm/h, and χ²/dof within
/// 0.15 of 1 (390·2 readings: its standard deviation is 0.05).
fn extended_estimate_is_true(scenario: &Scenario, found: &Discovery, hidden: &str, what: &str) {
    let machine = &scenario.twin.machine;
    let table = simulate(scenario).unwrap().rtest.unwrap();
    let drift = if found.drift() {
        Drift::Rate
    } else {
        Drift::None
    };
    let set = readings(
        &table,
        "session",
        machine,
        Setup {
            drift,
            ..Setup::default()
        },
    )
    .unwrap();
    let (parameters, fit, scales, labels) =
        estimate(machine, &found.params(), std::slice::from_ref(&set), 0);
    let truth = |label: &str| match label {
        "ECC.reversal" if hidden.contains("reversal_urad") => 20e-6,
        "ECC.reversal" => 0.0,
        label => truth_of_label(scenario, label),
    };
    assert_within_four_u(
        (&fit, &scales, &labels),
        parameters.len(),
        Numbered::All,
        truth,
        what,
    );
    for (c, rate) in [("x", 10e-6), ("y", 0.0), ("z", 30e-6)] {
        let Some(j) = labels.iter().position(|l| *l == format!("drift_per_h.{c}")) else {
            continue;
        };
        let u = fit.uncertainty(j).unwrap() * scales[j];
        let value = fit.z[j] * scales[j];
        assert!(
            (value - rate).abs() <= 4.0 * u,
            "{what}: drift {c} {value:e} m/h, truth {rate:e}, u {u:e}"
        );
    }
    let misfit = fit.chi2 / fit.dof as Real;
    assert!((misfit - 1.0).abs() < 0.15, "{what}: χ²/dof {misfit}");
}

/// Each effect hidden alone, on two seeds: found, named by its term and nothing else, with a
/// held-out gain far beyond the rule's (measured: the held-out RMS from 0.57–1.03 µm to
/// 0.195–0.197, the noise's 0.2 µm less the zeros' share; z 29–70 against 3.2), and the
/// extended estimate true.
#[test]
fn each_effect_hidden_alone_is_found_named_and_estimated() {
    for (hidden, term) in [
        (WOBBLE, WOBBLE_TERM),
        (REVERSAL, REVERSAL_TERM),
        (DRIFT, Term::Drift),
    ] {
        for seed in 1..=2 {
            let (scenario, set) = session(seed, hidden);
            let found = selected(&scenario, &set);
            let what = format!("{} seed {seed}", term.id());
            assert_eq!(found.accepted(), [term], "{what}:\n{}", found.text());
            let step = &found.selection.steps[0];
            assert!(step.test.gain > 0.5, "{what}: gain {}", step.test.gain);
            extended_estimate_is_true(&scenario, &found, hidden, &what);
        }
    }
}

/// The effects in pairs and all three together: each found, and nothing else.
#[test]
fn effects_hidden_together_are_each_found() {
    let cases: [(&[(&str, Term)], u64); 4] = [
        (&[(WOBBLE, WOBBLE_TERM), (REVERSAL, REVERSAL_TERM)], 3),
        (&[(WOBBLE, WOBBLE_TERM), (DRIFT, Term::Drift)], 4),
        (&[(REVERSAL, REVERSAL_TERM), (DRIFT, Term::Drift)], 5),
        (
            &[
                (WOBBLE, WOBBLE_TERM),
                (REVERSAL, REVERSAL_TERM),
                (DRIFT, Term::Drift),
            ],
            6,
        ),
    ];
    for (effects, seed) in cases {
        let hidden: String = effects.iter().map(|(h, _)| *h).collect();
        let (scenario, set) = session(seed, &hidden);
        let found = selected(&scenario, &set);
        let mut accepted = found.accepted();
        accepted.sort();
        let mut expected: Vec<Term> = effects.iter().map(|(_, t)| *t).collect();
        expected.sort();
        let what = format!("seed {seed}, {expected:?}");
        assert_eq!(accepted, expected, "{what}:\n{}", found.text());
        extended_estimate_is_true(&scenario, &found, &hidden, &what);
    }
}

/// Tables with none of the effects (the location errors and the nest's noise only) accept
/// nothing, on five seeds: the rule's bound on a false acceptance is 2.5 % per round (the
/// measured rate is in the ignored test below).
#[test]
fn tables_without_the_effects_accept_nothing() {
    for seed in 11..=15 {
        let (scenario, set) = session(seed, "");
        let found = selected(&scenario, &set);
        assert!(
            found.accepted().is_empty(),
            "seed {seed}:\n{}",
            found.text()
        );
        assert_eq!(found.params(), "location");
    }
}

/// The false-acceptance rate measured (run on purpose: `cargo test --release -- --ignored
/// false_acceptance`): 100 seeds of tables without the effects, the share that accept any
/// term, against the rule's 2.5 % per round.
#[test]
#[ignore = "a measurement: 100 discoveries, run on purpose"]
fn false_acceptance_rate() {
    let accepted = (100..200)
        .filter(|&seed| {
            let (scenario, set) = session(seed, "");
            !selected(&scenario, &set).accepted().is_empty()
        })
        .count();
    println!("{accepted} of 100 noise-only sessions accepted a term");
    assert!(accepted <= 7, "{accepted} of 100");
}

/// A foreign table of `tests/data/rtest/` (`make_foreign_session.py`: an independent simulator
/// of four C checks out and back at A = 0, vendor layout, rounded to 0.1 µm), read with the
/// script's sphere and its noise (0.15 µm and the rounding's 0.1/√12 in quadrature) and a drift
/// rate.
fn foreign(name: &str) -> (Machine, Readings) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let table =
        mtwin::kinds::rtest::RtestTable::read(root.join("tests/data/rtest").join(name)).unwrap();
    let machine = Machine::from_urdf_file(root.join("models/trunnion5.urdf")).unwrap();
    let angle = 40f64.to_radians();
    let setup = Setup {
        sigma: (0.15f64.powi(2) + 0.1f64.powi(2) / 12.0).sqrt() * 1e-6,
        sphere: Some(mtwin::math::Vector::new(
            0.1 * angle.cos(),
            0.1 * angle.sin(),
            0.25,
        )),
        drift: Drift::Rate,
        ..Setup::default()
    };
    let set = readings(&table, name, &machine, setup).unwrap();
    (machine, set)
}

/// On data the twin did not make, each fault by a physical model of its own: an elliptical
/// journal (the table's centre moving along X by 1.5·cos(2θ + 30°) µm of the table's actual
/// angle), a worm gear's 20 µrad of backlash crossing over through a compliant mesh (not a
/// step), the spindle warming as 1 − e^(−t/120 min) over the session (10 and 30 µm/h at the
/// start, 18 % slower at the end: not one rate). From C's four location errors, model
/// selection takes exactly C's 2-per-turn radial motion along X, C's lost motion and a drift
/// rate (measured: held-out RMS 0.98 → 0.78 → 0.50 → 0.16 µm). The extended estimate, within
/// 4 u: the line's displacement (15, −10) µm and no tilt; the lost motion 20 µrad; the wobble
/// as mtwin's EXC, the tool's motion relative to the workpiece, so the table moving +X by
/// e reads EXC = −e = 1.5·sin(2q − 60°) µm: sin coefficient 0.75, cos −1.299; the drift rates
/// between the session's last and first (x 8.2–10, z 24.0–30 µm/h: e^(−27/120) = 0.80 over its
/// 27 min), y none. χ²/dof within 0.2 of 1 (four standard deviations for 854 degrees of
/// freedom; measured 1.06). The same session without the faults accepts nothing.
#[test]
fn a_foreign_session_shows_its_three_faults_and_the_clean_one_none() {
    let base = "EX0C,EY0C,EA0C,EB0C";
    let (machine, set) = foreign("foreign_session.csv");
    let found = discover(&machine, base, std::slice::from_ref(&set), true, |_| {}).unwrap();
    let mut accepted = found.accepted();
    accepted.sort();
    let mut expected = vec![WOBBLE_TERM, REVERSAL_TERM, Term::Drift];
    expected.sort();
    assert_eq!(accepted, expected, "{}", found.text());
    assert!(found.drift());
    let (parameters, fit, scales, labels) =
        estimate(&machine, &found.params(), std::slice::from_ref(&set), 0);
    let truth = |label: &str| match label {
        "EX0C" => 15e-6,
        "EY0C" => -10e-6,
        "ECC.reversal" => 20e-6,
        "EXC.harmonic[2].sin" => 1.5e-6 * (-60f64).to_radians().cos(),
        "EXC.harmonic[2].cos" => 1.5e-6 * (-60f64).to_radians().sin(),
        _ => 0.0,
    };
    assert_within_four_u(
        (&fit, &scales, &labels),
        parameters.len(),
        Numbered::All,
        truth,
        "foreign_session.csv",
    );
    for (c, low, high) in [("x", 8.2e-6, 10e-6), ("y", 0.0, 0.0), ("z", 24.0e-6, 30e-6)] {
        let j = labels
            .iter()
            .position(|l| *l == format!("drift_per_h.{c}"))
            .unwrap();
        let (value, u) = (
            fit.z[j] * scales[j],
            fit.uncertainty(j).unwrap() * scales[j],
        );
        assert!(
            value >= low - 4.0 * u && value <= high + 4.0 * u,
            "drift {c}: {value:e} m/h (u {u:e}) outside {low:e}…{high:e}"
        );
    }
    let misfit = fit.chi2 / fit.dof as Real;
    assert!((misfit - 1.0).abs() < 0.2, "χ²/dof {misfit}");
    let (machine, clean) = foreign("foreign_session_clean.csv");
    let found = discover(&machine, base, std::slice::from_ref(&clean), true, |_| {}).unwrap();
    assert!(found.accepted().is_empty(), "{}", found.text());
}

/// Probing instead of an R-test (three spheres at A = 0 and −30°,
/// [`probed_three_spheres`]): each sphere at each tilt a group (six), held out in turn
/// and predicted from the others (its centre from its other tilt). C's 2-per-turn radial
/// motion along X (1.5 µm) is found and nothing else, and its two coefficients come back
/// within 4 u; without it nothing is accepted (two seeds each). Measured on seed 1: held-out
/// RMS 0.73 → 0.42 µm, z 10.2 against 3.1; the report names C's tilt twice per turn about Y
/// (`EBC.harmonic[2]`) as an alternative 5.1 % behind, which the three spheres (two heights)
/// tell apart only weakly: the rule takes the better, and says so.
#[test]
fn probing_three_spheres_finds_the_wobble_and_nothing_else() {
    for seed in 1..=2 {
        let (scenario, set) = probed_three_spheres(seed, WOBBLE);
        let found = selected(&scenario, &set);
        assert_eq!(
            found.accepted(),
            [WOBBLE_TERM],
            "seed {seed}:\n{}",
            found.text()
        );
        assert_eq!(found.problem.groups(), 6);
        let machine = &scenario.twin.machine;
        let (parameters, fit, scales, labels) =
            estimate(machine, &found.params(), std::slice::from_ref(&set), 0);
        assert_within_four_u(
            (&fit, &scales, &labels),
            parameters.len(),
            Numbered::All,
            |label| truth_of_label(&scenario, label),
            &format!("probing seed {seed}"),
        );
        let (scenario, set) = probed_three_spheres(seed + 10, "");
        let found = selected(&scenario, &set);
        assert!(
            found.accepted().is_empty(),
            "seed {seed}:\n{}",
            found.text()
        );
    }
}

/// The R-test's design at the start from its own sensitivities (the chain's Jacobian, one pass
/// per reading) is the forward differences' (one prediction of every reading per unknown, step
/// 0.01 µm: truncation about 1e-7 of a column): every column within 1e-5 of its largest entry,
/// for the location errors, C's series to order 3 with the order-1 ties, lost motions,
/// squareness, each test's zero and the drift rate, and with the sphere free. Zero columns
/// (what the readings cannot see) are zero both ways, to 1e-9 of the design's largest entry.
#[test]
fn the_r_test_design_from_its_sensitivities_is_the_forward_differences() {
    let spec = "location,rotary_components:C:3,ECC.reversal,reversal,squareness";
    for free_sphere in [false, true] {
        let (scenario, _) = session(1, WOBBLE);
        let machine = &scenario.twin.machine;
        let table = simulate(&scenario).unwrap().rtest.unwrap();
        let setup = Setup {
            drift: Drift::Rate,
            free_sphere,
            ..Setup::default()
        };
        let set = readings(&table, "session", machine, setup).unwrap();
        let parameters = ParameterSet::parse(spec, machine).unwrap();
        let sets = [set];
        let problem = Problem::new(machine, &parameters, &sets).unwrap();
        let n = problem.unknowns();
        let analytic = fit::start_design(&problem);
        let differences = problem.design(&vec![0.0; n], &nalgebra::DMatrix::identity(n, n));
        let largest = differences.amax();
        for j in 0..n {
            let column = differences.column(j);
            let scale = column.amax().max(1e-4 * largest);
            let worst = (analytic.column(j) - column).amax();
            assert!(
                worst <= 1e-5 * scale,
                "free sphere {free_sphere}, {}: differs by {worst:e} of {scale:e}",
                problem.labels()[j]
            );
        }
    }
}
