//! The touch probe end to end: the `[probe]` section and its checks, the virtual probe on the
//! twin, the tables, the fits and the evaluation, each number against something independent
//! (a hand derivation, a closed form, injected truth, a property).

use crate::common;

use mtwin::contact::Sphere;
use mtwin::errors::ErrorFunction;
use mtwin::kinds::probe::fit::{algebraic_sphere, fit_sphere};
use mtwin::kinds::probe::{
    CycleKind, LinearFrame, ProbeEvaluation, ProbeMove, ProbeTable, ProbeTest, RawProbe,
    SpheresTable, Target, TouchProbe, evaluate, probe_test, simulate, summary, truth,
};
use mtwin::machine::{Axis, Machine, MachineState, Workspace};
use mtwin::math::{M_PER_MM, Real, Vector, seeded_rng, standard_normal};
use mtwin::scenario::{Context, ScenarioError};
use mtwin::twin::Twin;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use toml::Spanned;

const UM: Real = 1e-6;
const NM: Real = 1e-9;

#[derive(Deserialize)]
struct Section {
    machine: String,
    probe: Spanned<RawProbe>,
}

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios")
}

/// The machine and the `[probe]` section of a scenario text (its other keys are not read
/// here), relative to the scenarios folder.
fn load_text(text: &str) -> Result<(Machine, ProbeTest), ScenarioError> {
    let section: Section = toml::from_str(text).unwrap();
    let dir = scenarios();
    let machine = Machine::from_urdf_file(dir.join(&section.machine)).unwrap();
    let context = Context::new("t.toml".into(), text);
    let test = probe_test(&context, &machine, &section.probe, &dir)?;
    Ok((machine, test))
}

fn scenario(name: &str) -> (Machine, ProbeTest) {
    let text = std::fs::read_to_string(scenarios().join(name)).unwrap();
    load_text(&text).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A probe with no errors of its own.
fn ideal(test: &mut ProbeTest) {
    let p = &mut test.probe;
    (p.radius_error, p.pretravel, p.lobing, p.pretravel_axial) = (0.0, 0.0, 0.0, 0.0);
    (p.repeatability, p.latency) = (0.0, 0.0);
}

fn run(twin: &Twin, test: &ProbeTest) -> (ProbeTable, ProbeEvaluation) {
    let run = simulate(twin, test, 7).unwrap();
    let evaluation = evaluate(&run.probe, test.probe.stylus_radius).unwrap();
    (run.probe, evaluation)
}

const SCENARIOS: [&str; 4] = [
    "trunnion5_probe_sphere.toml",
    "headtable5_probe_sphere.toml",
    "vmc3_ballplate.toml",
    "vmc3_probe_ring_mesh.toml",
];

#[test]
fn the_scenarios_load_run_and_describe_themselves() {
    for name in SCENARIOS {
        let (machine, test) = scenario(name);
        assert!(!test.describe().is_empty());
        let run = simulate(&common::twin(&machine, &[]), &test, 1).unwrap();
        let touches: usize = test
            .cycles
            .iter()
            .flat_map(|c| &c.features)
            .map(|f| f.moves.len())
            .sum();
        assert_eq!(run.probe.touches.len(), touches, "{name}");
        assert!(summary(&run).starts_with("probe: "), "{name}");
        assert_eq!(
            truth(&test)["cycles"].as_array().unwrap().len(),
            test.cycles.len()
        );
    }
}

#[test]
fn with_no_errors_the_fitted_centres_are_where_the_chain_puts_the_tip_on_the_sphere() {
    // Zero machine errors, an ideal probe: every radius is the sphere's, every form zero, and
    // forward kinematics at each fitted centre (axis values) puts the tool tip on the sphere's
    // centre, at every rotary position.
    for name in [
        "trunnion5_probe_sphere.toml",
        "headtable5_probe_sphere.toml",
    ] {
        let (machine, mut test) = scenario(name);
        ideal(&mut test);
        let (_, evaluation) = run(&common::twin(&machine, &[]), &test);
        let Target::Sphere(sphere) = &test.cycles[0].features[0].target else {
            panic!()
        };
        assert_eq!(evaluation.spheres.len(), 8);
        for s in &evaluation.spheres {
            assert!(
                (s.radius - sphere.radius).abs() < 1e-12,
                "{name}: {}",
                s.radius
            );
            assert!(s.fit.form() < 1e-12);
            let mut axes = test.cycles[0].features[s.key.feature - 1].rotary;
            let c = s.centre();
            (axes[Axis::X], axes[Axis::Y], axes[Axis::Z]) = (c.x, c.y, c.z);
            let tip = machine.workpiece_from_tool(&axes).translation;
            assert!((tip - sphere.centre).length() < 1e-12, "{name}: {tip:?}");
        }
    }
}

#[test]
fn location_errors_move_the_fitted_centres_to_where_the_actual_chain_reaches_the_sphere() {
    // With the rotary axes' location errors of the scenario and an ideal probe, the fitted
    // centre at each rotary position is the axis position at which the *actual* tool tip
    // (the twin's chain) sits on the sphere's centre: the latched positions are the
    // controller's, the contact the truth's.
    let (machine, mut test) = scenario("trunnion5_probe_sphere.toml");
    ideal(&mut test);
    let errors = [
        ("EY0C", ErrorFunction::Constant(12.0 * UM)),
        ("EX0C", ErrorFunction::Constant(-8.0 * UM)),
        ("EB0C", ErrorFunction::Constant(30e-6)),
        ("EZ0A", ErrorFunction::Constant(15.0 * UM)),
    ];
    let twin = common::twin(&machine, &errors);
    let (_, evaluation) = run(&twin, &test);
    let Target::Sphere(sphere) = &test.cycles[0].features[0].target else {
        panic!()
    };
    let mut workspace = Workspace::new(&machine);
    let mut moved: Real = 0.0;
    for s in &evaluation.spheres {
        let mut axes = test.cycles[0].features[s.key.feature - 1].rotary;
        let c = s.centre();
        (axes[Axis::X], axes[Axis::Y], axes[Axis::Z]) = (c.x, c.y, c.z);
        let actual =
            twin.errors
                .workpiece_from_tool(&machine, &mut workspace, &MachineState::at(axes));
        assert!((actual.translation - sphere.centre).length() < 0.01 * NM);
        moved =
            moved.max((machine.workpiece_from_tool(&axes).translation - sphere.centre).length());
        assert!((s.radius - sphere.radius).abs() < 0.01 * NM);
    }
    assert!(moved > 10.0 * UM, "the errors must show: {moved}");
}

#[test]
fn a_stylus_radius_error_moves_every_fitted_radius_and_no_centre() {
    // The true ball is larger by e: every sphere's stylus centres sit e further out, so the
    // measured artefact radius grows by e and the centre stays; a bore's diameter shrinks by 2e.
    let e = 2.0 * UM;
    for name in [
        "trunnion5_probe_sphere.toml",
        "vmc3_ballplate.toml",
        "vmc3_probe_ring_mesh.toml",
    ] {
        let (machine, mut test) = scenario(name);
        let twin = common::twin(
            &machine,
            &[("EX0C", ErrorFunction::Constant(5.0 * UM))]
                .into_iter()
                .filter(|_| machine.has_axis(Axis::C))
                .collect::<Vec<_>>(),
        );
        test.probe.radius_error = 0.0;
        let (_, before) = run(&twin, &test);
        test.probe.radius_error = e;
        let (_, after) = run(&twin, &test);
        for (a, b) in before.spheres.iter().zip(&after.spheres) {
            assert!((b.radius - a.radius - e).abs() < 1e-12, "{name}");
            assert!((b.centre() - a.centre()).length() < 1e-12, "{name}");
        }
        for (a, b) in before.rings.iter().zip(&after.rings) {
            assert!((b.diameter - a.diameter + 2.0 * e).abs() < 1e-12, "{name}");
            assert!((b.centre - a.centre).length() < 1e-12, "{name}");
        }
    }
}

#[test]
fn three_lobe_pretravel_shows_as_a_three_per_revolution_term_in_the_ring_fit() {
    // Probing a bore outward at azimuth θ (tool frame), the latched centre lies δ(θ) = δ0 +
    // δ3·cos 3(θ − θ0) beyond the contact: the circle fit takes δ0 into the radius and leaves
    // δ3·cos 3(θ − θ0) as the residual (k = 3 is orthogonal to k = 0, 1 on 36 points), so the
    // roundness is 2·δ3 and the diameter D + 2·δ0 − 2·e (e the radius error).
    let (machine, mut test) = scenario("vmc3_probe_ring_mesh.toml");
    test.probe.repeatability = 0.0;
    let p = test.probe;
    let (table, evaluation) = run(&common::twin(&machine, &[]), &test);
    let ring = &evaluation.rings[0];
    let moves = &test.cycles[0].features[0].moves;
    assert_eq!(ring.fit.residuals.len(), 36);
    for (residual, probing) in ring.fit.residuals.iter().zip(moves) {
        let theta = probing.tool_direction.y.atan2(probing.tool_direction.x);
        let expected = p.lobing * (3.0 * (theta - p.lobing_phase)).cos();
        assert!(
            (residual - expected).abs() < 1e-12,
            "{residual} vs {expected}"
        );
    }
    assert!((ring.fit.form() - 2.0 * p.lobing).abs() < 0.02 * p.lobing);
    let diameter = 50.0 * M_PER_MM + 2.0 * p.pretravel - 2.0 * p.radius_error;
    assert!(
        (ring.diameter - diameter).abs() < 1e-12,
        "{}",
        ring.diameter
    );
    assert!(
        (ring.diameter_error().unwrap() - (2.0 * p.pretravel - 2.0 * p.radius_error)).abs() < 1e-12
    );
    // The table carries the touches the evaluation used.
    assert_eq!(
        table
            .touches
            .iter()
            .filter(|t| t.key.kind == CycleKind::Ring)
            .count(),
        36
    );
}

#[test]
fn pre_travel_and_latency_add_along_the_motion() {
    // One touch on the pole of a sphere straight down the stylus (axial pre-travel δz) and one
    // across it at azimuth θ (lateral δ0 + δ3·cos 3(θ − θ0)): the latched axes are the contact
    // position plus (δ + v·t) along the motion. With no machine errors and the believed radius
    // true, the contact is `clearance` from the start.
    let machine = common::machine("vmc3");
    let twin = common::twin(&machine, &[]);
    let probe = TouchProbe {
        stylus_radius: 2.0 * M_PER_MM,
        radius_error: 0.0,
        pretravel: 1.0 * UM,
        lobing: 0.4 * UM,
        lobing_phase: 0.3,
        pretravel_axial: 3.0 * UM,
        repeatability: 0.0,
        feed: 0.004,
        latency: 1e-3,
    };
    let sphere = Sphere {
        centre: Vector::new(0.01, 0.02, 0.15),
        radius: 0.0125,
    };
    let frame = LinearFrame::at(&machine, &mtwin::machine::AxisValues::ZERO).unwrap();
    let clearance = 2.0 * M_PER_MM;
    let mut workspace = Workspace::new(&machine);
    let mut rng = seeded_rng(1, "test");
    for (normal, delta) in [
        (Vector::Z, probe.pretravel_axial),
        (
            Vector::new(0.6, 0.8, 0.0),
            probe.pretravel + probe.lobing * (3.0 * ((-0.8f64).atan2(-0.6) - 0.3)).cos(),
        ),
    ] {
        let start = sphere.centre + normal * (sphere.radius + probe.stylus_radius + clearance);
        let probing: ProbeMove = frame.move_from(start, -normal, 0.01);
        let latched = probe
            .touch(
                &twin,
                &mut workspace,
                &Target::Sphere(sphere),
                &probing,
                &mut rng,
            )
            .unwrap();
        let expected = clearance + delta + probe.feed * probe.latency;
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            let moved = latched.axes[axis] - probing.start[axis];
            let along = -normal[axis.coordinate()] * expected;
            assert!((moved - along).abs() < 1e-15, "{axis}: {moved} vs {along}");
        }
        assert!((latched.contact_travel - clearance).abs() < 1e-15);
        assert!(((latched.contact_point - sphere.centre).length() - sphere.radius).abs() < 1e-15);
    }
}

#[test]
fn repeatability_scatters_the_touches_with_its_standard_deviation() {
    // The scatter along the motion is σ·N(0, 1) from the cycle's stream: the latched positions
    // minus those of a scatter-free run, projected on the approach, are exactly σ times the
    // stream's normal draws.
    let (machine, mut test) = scenario("vmc3_probe_ring_mesh.toml");
    let twin = common::twin(&machine, &[]);
    let sigma = test.probe.repeatability;
    let noisy = simulate(&twin, &test, 11).unwrap().probe;
    test.probe.repeatability = 0.0;
    let clean = simulate(&twin, &test, 11).unwrap().probe;
    let mut rng = seeded_rng(11, "probe cycle 1");
    for (n, c) in noisy.touches.iter().zip(&clean.touches).take(36) {
        let along = (n.position - c.position).dot(n.approach);
        assert!((along - sigma * standard_normal(&mut rng)).abs() < 1e-15);
    }
    // Same seed, same table; another seed, another.
    test.probe.repeatability = sigma;
    assert_eq!(simulate(&twin, &test, 11).unwrap().probe, noisy);
    assert_ne!(simulate(&twin, &test, 12).unwrap().probe, noisy);
}

#[test]
fn a_machine_translation_error_moves_the_fitted_centre_by_minus_the_deviation() {
    // Constant component errors shift the actual tool tip by the deviation d everywhere: the
    // controller stops short by d, so the fitted centres (axis coordinates) move by −d (vmc3:
    // axis space is the workpiece frame) and the radii and distances do not change.
    let (machine, mut test) = scenario("vmc3_ballplate.toml");
    ideal(&mut test);
    let errors = [
        ("EXX", ErrorFunction::Constant(10.0 * UM)),
        ("EYY", ErrorFunction::Constant(-5.0 * UM)),
        ("EZZ", ErrorFunction::Constant(3.0 * UM)),
    ];
    let shifted = common::twin(&machine, &errors);
    let d = shifted
        .errors
        .deviation(
            &machine,
            &mut Workspace::new(&machine),
            &MachineState::default(),
        )
        .translation;
    assert!(d.length() > 5.0 * UM);
    let (_, nominal) = run(&common::twin(&machine, &[]), &test);
    let (_, actual) = run(&shifted, &test);
    for (a, b) in nominal.spheres.iter().zip(&actual.spheres) {
        assert!(
            (b.centre() - a.centre() + d).length() < 0.01 * NM,
            "{:?}",
            b.centre() - a.centre()
        );
        assert!((b.radius - a.radius).abs() < 0.01 * NM);
    }
    for plate in &actual.plates {
        assert!(plate.max_abs_error() < 0.01 * NM);
    }
}

#[test]
fn a_scale_error_shows_as_ball_plate_distance_errors() {
    // EXX = k·x: to put the actual tip at x_b the controller goes to x_b/(1 + k), so a distance
    // Δx along X measures Δx/(1 + k): error −k·Δx/(1 + k). The plate's calibration offsets are
    // the truth, so they cancel.
    let (machine, mut test) = scenario("vmc3_ballplate.toml");
    ideal(&mut test);
    let k = 8e-6;
    let (_, evaluation) = run(
        &common::twin(
            &machine,
            &[("EXX", ErrorFunction::Polynomial(vec![0.0, k]))],
        ),
        &test,
    );
    for plate in &evaluation.plates[..2] {
        // Balls 1 and 5: the ends of the first row, 320 mm apart along X (plus the calibrated
        // offsets, whose X difference is 0.6 µm).
        let pair = plate.distances.iter().find(|d| d.balls == (1, 5)).unwrap();
        let true_dx = 320.0 * M_PER_MM + 0.6 * UM;
        let expected = -k * true_dx / (1.0 + k);
        let error = pair.measured - pair.calibrated;
        assert!(
            (error - expected).abs() < 2e-12 + 1e-5 * expected.abs(),
            "{error} vs {expected}"
        );
        // Along Y (balls 1 and 16, column 0): no X travel, no error to first order.
        let pair = plate.distances.iter().find(|d| d.balls == (1, 16)).unwrap();
        assert!((pair.measured - pair.calibrated).abs() < 1e-11);
    }
}

/// An independent algebraic sphere fit: the 4×4 normal equations of `|p|² = 2c·p + k`,
/// solved by Gaussian elimination with partial pivoting.
#[allow(clippy::needless_range_loop)] // elimination reads best with indices
fn normal_equations_sphere(points: &[Vector]) -> (Vector, Real) {
    let mut m = [[0.0; 5]; 4];
    for p in points {
        let row = [2.0 * p.x, 2.0 * p.y, 2.0 * p.z, 1.0];
        let rhs = p.length_squared();
        for i in 0..4 {
            for j in 0..4 {
                m[i][j] += row[i] * row[j];
            }
            m[i][4] += row[i] * rhs;
        }
    }
    for col in 0..4 {
        let pivot = (col..4)
            .max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))
            .unwrap();
        m.swap(col, pivot);
        for row in 0..4 {
            if row != col {
                let f = m[row][col] / m[col][col];
                for j in col..5 {
                    m[row][j] -= f * m[col][j];
                }
            }
        }
    }
    let x: Vec<Real> = (0..4).map(|i| m[i][4] / m[i][i]).collect();
    let c = Vector::new(x[0], x[1], x[2]);
    (c, (x[3] + c.length_squared()).sqrt())
}

#[test]
fn sphere_fits_against_a_hand_computed_case_and_an_independent_algebraic_fit() {
    // Six points on the axes at R + e_k from c: to first order the geometric fit's centre is
    // c + ((e+x − e−x)/2, (e+y − e−y)/2, (e+z − e−z)/2) and its radius R + mean(e) (the
    // residuals of a symmetric pair are ±(e+ − e−)/2 about the mean), within e²/R.
    let c = Vector::new(0.1, -0.2, 0.3);
    let r = 0.0125;
    let e = [1.0, -0.5, 0.3, 0.8, -1.2, 0.4].map(|x| x * UM); // +x, −x, +y, −y, +z, −z
    let axes = [
        Vector::X,
        -Vector::X,
        Vector::Y,
        -Vector::Y,
        Vector::Z,
        -Vector::Z,
    ];
    let points: Vec<Vector> = axes.iter().zip(e).map(|(a, e)| c + *a * (r + e)).collect();
    let fit = fit_sphere(&points).unwrap();
    let expected_centre = c + Vector::new(e[0] - e[1], e[2] - e[3], e[4] - e[5]) / 2.0;
    let mean = e.iter().sum::<Real>() / 6.0;
    let second_order = 2.0 * UM * UM / r;
    assert!((Vector::from_array(fit.centre) - expected_centre).length() < second_order);
    assert!((fit.radius - (r + mean)).abs() < second_order);

    // Noisy points over a sphere: the library's Kåsa fit agrees with the normal-equation one,
    // and the geometric fit satisfies its own normal equations (Σ rᵢ = 0, Σ rᵢ·uᵢ = 0) and
    // is within σ²/R of the algebraic one.
    let mut rng = common::rng("sphere fit");
    let sigma = 1.0 * UM;
    let points: Vec<Vector> = (0..40)
        .map(|i| {
            let polar = 0.3 + 2.5 * (i as Real / 40.0);
            let azimuth = 2.4 * i as Real;
            let u = Vector::new(
                polar.sin() * azimuth.cos(),
                polar.sin() * azimuth.sin(),
                polar.cos(),
            );
            c + u * (r + sigma * standard_normal(&mut rng))
        })
        .collect();
    let (kc, kr) = algebraic_sphere(&points).unwrap();
    let (nc, nr) = normal_equations_sphere(&points);
    assert!((kc - nc).length() < 1e-12 && (kr - nr).abs() < 1e-12);
    let fit = fit_sphere(&points).unwrap();
    let centre = Vector::from_array(fit.centre);
    let sum: Real = fit.residuals.iter().sum();
    let moment: Vector = points
        .iter()
        .zip(&fit.residuals)
        .map(|(p, res)| (*p - centre).normalize() * *res)
        .sum();
    assert!(
        sum.abs() < 1e-15 && moment.length() < 1e-15,
        "{sum} {moment:?}"
    );
    assert!((centre - kc).length() < 10.0 * sigma * sigma / r);
    assert!(fit.rms() > 0.5 * sigma && fit.rms() < 1.5 * sigma);
}

#[test]
fn iso_10360_5_p_ftu_from_25_points() {
    // 25 points: the pole, 4 at 22.5°, 8 at 45°, 4 at 67.5°, 8 on the equator. P_FTU is the
    // range of the 25 radial distances from the fit; with an ideal probe it is zero, with
    // scatter it is the range of the residuals (and only 25-point features report it).
    let text = std::fs::read_to_string(scenarios().join("trunnion5_probe_sphere.toml"))
        .unwrap()
        .replace("points = 5", "points = 25");
    let (machine, test) = load_text(&text).unwrap();
    let moves = &test.cycles[0].features[0].moves;
    assert_eq!(moves.len(), 25);
    let mut polar: Vec<i64> = moves
        .iter()
        .map(|m| ((-m.tool_direction.z).acos().to_degrees() * 10.0).round() as i64)
        .collect();
    polar.sort();
    let count = |d: i64| polar.iter().filter(|p| **p == d).count();
    assert_eq!(
        [count(0), count(225), count(450), count(675), count(900)],
        [1, 4, 8, 4, 8]
    );
    // An ideal probe whose pre-travel is the same in every direction: every touch moves by
    // the same amount along its normal, the fitted radius absorbs it, P_FTU is zero.
    let mut even = test.clone();
    ideal(&mut even);
    (even.probe.pretravel, even.probe.pretravel_axial) = (1.0 * UM, 1.0 * UM);
    let (_, evaluation) = run(&common::twin(&machine, &[]), &even);
    for s in &evaluation.spheres {
        assert!(s.p_ftu().unwrap() < 1e-9, "{:?}", s.p_ftu());
    }
    // With the scenario's scatter and lobing: the range of the distances from the centre of an
    // independent algebraic fit (normal equations, in this file) of the 25 stylus centres.
    let (table, evaluation) = run(&common::twin(&machine, &[]), &test);
    for s in &evaluation.spheres {
        let centres: Vec<Vector> = table
            .touches
            .iter()
            .filter(|t| t.key.cycle == s.key.cycle && t.key.feature == s.key.feature)
            .map(|t| t.position)
            .collect();
        assert_eq!(centres.len(), 25);
        let (c, _) = normal_equations_sphere(&centres);
        let distances: Vec<Real> = centres.iter().map(|p| (*p - c).length()).collect();
        let range = distances.iter().copied().fold(Real::MIN, Real::max)
            - distances.iter().copied().fold(Real::MAX, Real::min);
        // The two fits' centres differ by far less than the scatter: 1 nm on a range of µm.
        let p = s.p_ftu().unwrap();
        assert!((p - range).abs() < 1e-9, "{p} vs {range}");
        assert!(p > test.probe.repeatability, "{p}");
    }
    let json = evaluation.to_json();
    assert!(json["spheres"][0]["p_ftu_um"].as_f64().is_some());
    let (_, five) = run(
        &common::twin(&machine, &[]),
        &scenario("trunnion5_probe_sphere.toml").1,
    );
    assert!(five.spheres[0].p_ftu().is_none());
}

#[test]
fn the_tables_read_back_and_bad_rows_name_their_line() {
    let (machine, test) = scenario("vmc3_ballplate.toml");
    let run = simulate(&common::twin(&machine, &[]), &test, 3).unwrap();
    let mut bytes = Vec::new();
    run.probe.write_csv(&mut bytes).unwrap();
    let back = ProbeTable::parse(&bytes, "probe.csv").unwrap();
    assert_eq!(back.touches.len(), run.probe.touches.len());
    assert_eq!(back.conditions, run.probe.conditions);
    for (a, b) in back.touches.iter().zip(&run.probe.touches) {
        assert!(
            (a.position - b.position).length() < 1e-9 && (a.approach - b.approach).length() < 1e-8
        );
        assert_eq!(
            (a.key.cycle, a.key.feature, a.point, a.key.kind),
            (b.key.cycle, b.key.feature, b.point, b.key.kind)
        );
        assert!(
            (a.key.calibrated_centre.unwrap() - b.key.calibrated_centre.unwrap()).length() < 1e-9
        );
    }
    // The evaluation of the file read back equals the controller's spheres table to rounding.
    let again = evaluate(&back, back.conditions.stylus_radius.unwrap()).unwrap();
    for (a, b) in again.spheres.iter().zip(&run.spheres.spheres) {
        assert!((a.centre() - b.centre).length() < 2e-9 && (a.radius - b.radius).abs() < 2e-9);
    }
    let mut bytes = Vec::new();
    run.spheres.write_csv(&mut bytes).unwrap();
    let spheres = SpheresTable::parse(&bytes, "spheres.csv").unwrap();
    assert_eq!(spheres.spheres.len(), 60);
    assert!((spheres.spheres[7].radius - run.spheres.spheres[7].radius).abs() < 1e-9);

    let header = "# stylus_radius_mm = 2\ncycle,kind,feature,point,x_mm,y_mm,z_mm,i,j,k\n";
    let bad = |rows: &str| {
        ProbeTable::parse(format!("{header}{rows}").as_bytes(), "t.csv")
            .unwrap_err()
            .to_string()
    };
    assert_eq!(
        bad("1,sphere,1,1,0,0,0,0,0,0.5\n"),
        "t.csv:3: columns `i`, `j`, `k`: (0, 0, 0.5) is not a unit approach vector"
    );
    assert!(bad("1,cone,1,1,0,0,0,0,0,1\n").starts_with("t.csv:3: column `kind`"));
    assert!(bad("1,sphere,0,1,0,0,0,0,0,1\n").contains("column `feature`"));
    assert!(bad("1,sphere,1,1,0,x,0,0,0,1\n").contains("column `y_mm`"));
    let unknown = ProbeTable::parse(
        b"cycle,kind,feature,point,x_mm,y_mm,z_mm,i,j,k,Q\n1,sphere,1,1,0,0,0,0,0,1,\n",
        "t.csv",
    )
    .unwrap();
    assert_eq!(unknown.conditions.columns_not_read, ["Q"]);
    let slip = ProbeTable::parse(
        b"cycle,kind,feature,point,X (mm),y_mm,z_mm,i,j,k\n",
        "t.csv",
    )
    .unwrap_err();
    assert!(
        slip.to_string()
            .starts_with("t.csv:1: column `X (mm)`: this reader reads `x_mm`"),
        "{slip}"
    );
    let missing = ProbeTable::parse(
        b"cycle,kind,feature,point,x_mm,y_mm,i,j,k\n1,sphere,1,1,0,0,0,0,1\n",
        "t.csv",
    )
    .unwrap_err();
    assert!(
        missing.to_string().contains("missing column `z_mm`"),
        "{missing}"
    );
    let partial = ProbeTable::parse(
        b"cycle,kind,feature,point,x_mm,y_mm,z_mm,i,j,k,cal_x_mm\n",
        "t.csv",
    )
    .unwrap_err();
    assert!(
        partial.to_string().contains("all three or none"),
        "{partial}"
    );
    // A sphere of three points cannot be fitted: the evaluation says which.
    let three = ProbeTable::parse(format!("{header}1,sphere,1,1,1,0,0,-1,0,0\n1,sphere,1,2,0,1,0,0,-1,0\n1,sphere,1,3,-1,0,0,1,0,0\n").as_bytes(), "t.csv").unwrap();
    let error = evaluate(&three, 0.002).unwrap_err().to_string();
    assert!(error.starts_with("cycle 1, feature 1: 3 points"), "{error}");
}

#[test]
fn bad_sections_are_refused_with_the_key_and_line() {
    let base = std::fs::read_to_string(scenarios().join("vmc3_probe_ring_mesh.toml")).unwrap();
    let refused = |from: &str, to: &str| -> String {
        assert!(base.contains(from), "{from}");
        load_text(&base.replacen(from, to, 1))
            .unwrap_err()
            .to_string()
    };
    let line_of =
        |text: &str, needle: &str| text.lines().position(|l| l.contains(needle)).unwrap() + 1;

    let zero = refused(
        "start_mm = [-125.0, -25.0, 150.0], direction = [0.0, 0.0, -1.0]",
        "start_mm = [-125.0, -25.0, 150.0], direction = [0.0, 0.0, 0.0]",
    );
    assert!(
        zero.contains("probe.mesh[0].points[1].direction: (0, 0, 0) has zero length"),
        "{zero}"
    );
    let axis = refused("points = 36", "points = 36\naxis = [0.0, 0.0, 0.0]");
    assert!(
        axis.contains("probe.ring[0].axis") && axis.contains("zero length"),
        "{axis}"
    );
    let far = refused(
        "centre_mm = [100.0, 50.0, 130.0]",
        "centre_mm = [100.0, 500.0, 130.0]",
    );
    assert!(
        far.contains("outside its travel") && far.contains("cannot be reached"),
        "{far}"
    );
    assert!(
        far.starts_with(&format!("t.toml:{}:", line_of(&base, "[[probe.ring]]"))),
        "{far}"
    );
    let open = refused("data/cube_40mm.stl", "../tests/data/probe/open_box.obj");
    assert!(
        open.contains("probe.mesh[0].file") && open.contains("not closed"),
        "{open}"
    );
    assert!(
        open.starts_with(&format!("t.toml:{}:", line_of(&base, "cube_40mm.stl"))),
        "{open}"
    );
    let parse = refused("data/cube_40mm.stl", "../tests/data/probe/bad_keyword.stl");
    assert!(
        parse.contains("bad_keyword.stl:5:7: expected `vertex`"),
        "{parse}"
    );
    let missing = refused("data/cube_40mm.stl", "../tests/data/probe/none.stl");
    assert!(missing.contains("cannot read"), "{missing}");
    let miss = refused(
        "start_mm = [-130.0, -30.0, 150.0]",
        "start_mm = [-300.0, -30.0, 150.0]",
    );
    assert!(miss.contains("does not reach the artefact"), "{miss}");
    let lobing = refused("lobing_um = 1.0", "lobing_um = 2.0");
    assert!(lobing.contains("probe.lobing_um"), "{lobing}");
    assert!(
        lobing.starts_with(&format!("t.toml:{}:", line_of(&base, "lobing_um"))),
        "{lobing}"
    );
    let points = refused("points = 36", "points = 2");
    assert!(
        points.contains("probe.ring[0].points: expected 3 … 360, got 2"),
        "{points}"
    );
    let small = refused("diameter_mm = 50.0", "diameter_mm = 2.0");
    assert!(small.contains("does not fit the bore"), "{small}");
    let stylus = refused("stylus_diameter_mm = 3.0", "stylus_diameter_mm = -3.0");
    assert!(stylus.contains("probe.stylus_diameter_mm"), "{stylus}");
    let rotary = refused("points = 36", "points = 36\nrotary = { a_deg = 10.0 }");
    assert!(rotary.contains("has no axis A"), "{rotary}");
    let units = refused("units = \"mm\"", "units = \"furlong\"");
    assert!(units.contains("probe.mesh[0].units"), "{units}");
    // An unknown key is refused by the section's reader.
    let unknown = toml::from_str::<Section>(&base.replace("feed_mm_per_min", "speed_mm_per_min"));
    assert!(
        unknown
            .err()
            .unwrap()
            .to_string()
            .contains("unknown field `speed_mm_per_min`")
    );
}

#[test]
fn the_analyze_verb_prints_the_figures_and_stable_json() {
    let (machine, test) = scenario("vmc3_probe_ring_mesh.toml");
    let run = simulate(&common::twin(&machine, &[]), &test, 1).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("probe.csv");
    let mut bytes = Vec::new();
    run.probe.write_csv(&mut bytes).unwrap();
    std::fs::write(&path, &bytes).unwrap();
    let verb = mtwin::kinds::probe::cli::KIND.analyze.unwrap();
    let call = |args: &[&str]| {
        let matches = (verb.command)().try_get_matches_from(args).unwrap();
        (verb.run)(&matches, &mut |_| {}, &mtwin::app::ScenarioFiles)
    };
    let file = path.to_str().unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&call(&["probe", file, "--json"]).unwrap()).unwrap();
    assert_eq!(json["stylus_radius_mm"], 1.5);
    for key in [
        "centre_mm",
        "diameter_mm",
        "diameter_error_um",
        "roundness_um",
        "side",
        "points",
    ] {
        assert!(json["rings"][0].get(key).is_some(), "{key}");
    }
    assert_eq!(json["rings"][0]["side"], "bore");
    assert_eq!(json["mesh_points"].as_array().unwrap().len(), 3);
    let text = call(&["probe", file]).unwrap();
    assert!(
        text.contains("ring cycle 1 (bore)") && text.contains("mesh: 3 surface points"),
        "{text}"
    );
    let disagree = call(&["probe", file, "--stylus-radius-mm", "2"]).unwrap_err();
    assert!(disagree.to_string().contains("disagrees"), "{disagree}");
    // Mesh points: the surface point is the latched centre plus r along the approach.
    let p = &run.probe.touches[36];
    let s = &json["mesh_points"][0]["surface_mm"];
    assert!((s[2].as_f64().unwrap() - (p.position.z / M_PER_MM - 1.5)).abs() < 1e-6);
}

mod collisions_and_meshes;
