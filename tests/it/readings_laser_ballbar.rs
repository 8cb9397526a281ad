//! The laser and ball-bar readings for the estimators against what they model: the twin's own
//! simulation of each instrument (scenarios run in-process with the noise off, the tables
//! written and read back as files, then predicted with the scenario's true errors and set-up),
//! and closed forms derived here by hand from the sign conventions of `mtwin::errors`.

use crate::common;

use mtwin::app::{Scenario, simulate};
use mtwin::errors::{ErrorFunction, ErrorModel, ErrorParameter};
use mtwin::estimate::Readings;
use mtwin::kinds::ballbar::readings as ballbar;
use mtwin::kinds::ballbar::{BallbarReading, BallbarTable, Sense, TestConditions};
use mtwin::kinds::positioning::PositioningTable;
use mtwin::kinds::positioning::readings as laser;
use mtwin::machine::{Axis, AxisValues, Machine, Plane, Workspace};
use mtwin::math::Real;
use std::f64::consts::FRAC_PI_2;
use std::path::Path;

const UM: Real = 1e-6;
const NM: Real = 1e-9;

/// Loads a scenario written in a temporary folder (the machine by absolute path).
fn load(text: &str) -> Scenario {
    let dir = tempfile::tempdir().unwrap();
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let text = text.replace("MODELS", &models.display().to_string());
    let path = dir.path().join("s.toml");
    std::fs::write(&path, text).unwrap();
    Scenario::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The model's prediction of every reading.
fn predict(
    readings: &Readings,
    machine: &Machine,
    errors: &ErrorModel,
    nuisance: &[Real],
    setup: &[Real],
) -> Vec<Real> {
    let mut workspace = Workspace::new(machine);
    let mut out = vec![Real::NAN; readings.len()];
    readings
        .model
        .predict(machine, &mut workspace, errors, nuisance, setup, &mut out);
    out
}

fn errors(machine: &Machine, parameters: &[(&str, ErrorFunction)]) -> ErrorModel {
    let parameters = parameters
        .iter()
        .map(|(name, function)| ErrorParameter {
            name: name.parse().unwrap(),
            function: function.clone(),
        })
        .collect();
    ErrorModel::new(machine, parameters).unwrap()
}

/// Three ISO 230-2 tests with the noise, resolution and air errors off: vmc3's X with a
/// reflector 30 mm to the side of and 60 mm above the tip (Abbe offsets for the pitch, yaw
/// and roll), zeroed once; vmc3's Z in the reverse set-up (interferometer on the spindle),
/// zeroed at each run; trunnion5's Y with the rotary axes stated.
const LASER_TESTS: [(&str, &str); 3] = [
    (
        "vmc3 X",
        r#"schema = 1
machine = "MODELS/vmc3.urdf"
seed = 1
[errors.EXX]
polynomial_um = [0.0, 0.012, -8.0e-6]
reversal_um = 3.0
harmonic = [{ period_mm = 10.0, amplitude_um = 0.4, phase_deg = 30.0 }]
[errors.EBX]
polynomial_urad = [0.0, 0.015]
[errors.ECX]
polynomial_urad = [2.0, -0.01]
[errors.EAX]
polynomial_urad = [0.0, 0.008]
[errors.EYX]
polynomial_um = [0.0, 0.01, -1.0e-5]
[errors.EC0Y]
constant_urad = 20.0
[errors.EYY]
reversal_um = 2.0
[iso230_2]
axis = "X"
targets_mm = { from = 10.0, to = 750.0, count = 9 }
runs = 3
y_mm = 205.0
z_mm = 100.0
[laser]
beam_offset_mm = [0.0, 30.0, 60.0]
resolution_nm = 0.0
noise_nm = 0.0
"#,
    ),
    (
        "vmc3 Z, interferometer on the tool",
        r#"schema = 1
machine = "MODELS/vmc3.urdf"
seed = 2
[errors.EZZ]
polynomial_um = [0.0, -0.01]
reversal_um = 4.0
[errors.EAZ]
polynomial_urad = [0.0, 0.02]
[errors.EBZ]
polynomial_urad = [1.0, -0.012]
[errors.EXZ]
polynomial_um = [0.0, 0.005]
[errors.EB0Z]
constant_urad = 15.0
[errors.EA0Z]
constant_urad = -12.0
[errors.EBX]
polynomial_urad = [0.0, 0.015]
[iso230_2]
axis = "Z"
targets_mm = { from = 20.0, to = 480.0, count = 7 }
runs = 2
x_mm = 300.0
y_mm = 150.0
[laser]
beam_offset_mm = [15.0, -10.0, 40.0]
interferometer_on = "tool"
zero = "each_run"
resolution_nm = 0.0
noise_nm = 0.0
"#,
    ),
    (
        "trunnion5 Y",
        r#"schema = 1
machine = "MODELS/trunnion5.urdf"
seed = 3
[errors.EYY]
polynomial_um = [0.0, 0.02, 1.0e-5]
reversal_um = 2.5
[errors.EXY]
polynomial_um = [0.0, -0.004]
[errors.ECY]
polynomial_urad = [0.0, 0.01]
[errors.EAY]
polynomial_urad = [-3.0, 0.02]
[errors.EX0C]
constant_um = 9.0
[iso230_2]
axis = "Y"
targets_mm = { from = 10.0, to = 540.0, count = 8 }
runs = 2
x_mm = 325.0
z_mm = 250.0
a_deg = 0.0
c_deg = 0.0
[laser]
beam_offset_mm = [0.0, 0.0, 50.0]
resolution_nm = 0.0
noise_nm = 0.0
"#,
    ),
];

#[test]
fn laser_readings_reproduce_the_simulated_tables_with_the_true_errors() {
    for (name, text) in LASER_TESTS {
        let scenario = load(text);
        let run = simulate(&scenario).unwrap().laser.unwrap();
        let mut bytes = Vec::new();
        run.table.write_csv(&mut bytes).unwrap();
        // The model reads what the file says: the line, the reflector, the mounting, the zero.
        let table = PositioningTable::parse(&bytes, "positioning.csv").unwrap();
        let machine = &scenario.twin.machine;
        let readings =
            laser::readings(&table, "positioning.csv", machine, &laser::Setup::default())
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(readings.kind, "positioning");
        assert_eq!(readings.machine.as_deref(), Some(machine.name()));
        assert_eq!(readings.len(), table.readings.len());
        // The laser's zero offset: one for the table, or one per run when re-zeroed each run.
        assert!(
            [1, table.runs.len()].contains(&readings.nuisance.len())
                && readings
                    .nuisance
                    .iter()
                    .all(|q| q.name.starts_with("laser.zero")),
            "{:?}",
            readings.nuisance
        );
        assert_eq!(readings.setup.len(), 3);
        assert!(readings.sigma.iter().all(|s| *s == laser::DEFAULT_SIGMA));
        let predicted = predict(
            &readings,
            machine,
            &scenario.twin.errors,
            &vec![0.0; readings.nuisance.len()],
            &[0.0; 3],
        );
        let worst = predicted
            .iter()
            .zip(&readings.measured)
            .map(|(p, m)| (p - m).abs())
            .fold(0.0, Real::max);
        let largest = readings
            .measured
            .iter()
            .map(|m| m.abs())
            .fold(0.0, Real::max);
        eprintln!(
            "{name}: {} readings up to {:.3} µm, model − table at most {:.2e} µm",
            readings.len(),
            largest / UM,
            worst / UM
        );
        assert!(largest > 1.0 * UM, "{name}: the errors show ({largest} m)");
        // The table prints deviations to 1 pm: rounding (0.5 pm) and the f64 chain.
        assert!(worst <= 1e-12, "{name}: model − table up to {worst} m");
        // The reflector offset is a set-up quantity the readings depend on (the Abbe offset
        // across the beam turns the axis's angular errors into readings).
        let moved = predict(
            &readings,
            machine,
            &scenario.twin.errors,
            &vec![0.0; readings.nuisance.len()],
            &[1e-3, 1e-3, 1e-3],
        );
        assert!(
            moved
                .iter()
                .zip(&predicted)
                .any(|(a, b)| (a - b).abs() > 1e-9),
            "{name}: moving the reflector changes the readings"
        );
    }
}

#[test]
fn laser_readings_follow_a_positioning_error_by_hand() {
    // vmc3 X with EXX = a1·x + a2·x² and lost motion r, the reflector at the tip: the laser,
    // zeroed at the first reading (target t0, approached +), reads EXX(t, dir) − EXX(t0, +),
    // the reversal term −sign(dir)·r/2 (mtwin::errors::ErrorFunction::Reversal).
    let machine = common::machine("vmc3");
    let (a1, a2, r) = (12e-6, -8e-6, 3e-6);
    let model = errors(
        &machine,
        &[(
            "EXX",
            ErrorFunction::Sum(vec![
                ErrorFunction::Polynomial(vec![0.0, a1, a2]),
                ErrorFunction::Reversal(r),
            ]),
        )],
    );
    let text = "# axis = X\n# y_mm = 205\n# z_mm = 100\nrun,direction,target_mm,deviation_um\n\
                1,+,10,0\n1,+,400,0\n1,+,750,0\n1,-,750,0\n1,-,400,0\n1,-,10,0\n";
    let table = PositioningTable::parse(text.as_bytes(), "hand.csv").unwrap();
    let readings = laser::readings(&table, "hand.csv", &machine, &laser::Setup::default()).unwrap();
    assert_eq!(readings.machine, None, "the file does not say");
    let predicted = predict(
        &readings,
        &machine,
        &model,
        &vec![0.0; readings.nuisance.len()],
        &[0.0; 3],
    );
    let exx = |t: Real, sign: Real| a1 * t + a2 * t * t - sign * r / 2.0;
    for (reading, p) in table.readings.iter().zip(&predicted) {
        let sign = if reading.approach == mtwin::program::Approach::Up {
            1.0
        } else {
            -1.0
        };
        let expected = exx(reading.target, sign) - exx(0.010, 1.0);
        assert!(
            (p - expected).abs() < 1e-13,
            "at {} mm {sign}: {p} vs {expected}",
            reading.target * 1e3
        );
    }
}

#[test]
fn laser_readings_need_the_line_of_the_test() {
    let machine = common::machine("vmc3");
    let text =
        "# axis = X\n# y_mm = 205\nrun,direction,target_mm,deviation_um\n1,+,10,0\n1,+,400,1\n";
    let table = PositioningTable::parse(text.as_bytes(), "bare.csv").unwrap();
    let error = laser::readings(&table, "bare.csv", &machine, &laser::Setup::default())
        .unwrap_err()
        .to_string();
    assert!(error.starts_with("bare.csv: "), "{error}");
    assert!(error.contains("`# z_mm = …`"), "{error}");
    // Given as an argument (a flag), it is used; one that contradicts the file is refused.
    let with_z = laser::Setup {
        axes: vec![(Axis::Z, 0.1)],
        ..Default::default()
    };
    assert!(laser::readings(&table, "bare.csv", &machine, &with_z).is_ok());
    let contradicting = laser::Setup {
        axes: vec![(Axis::Y, 0.2), (Axis::Z, 0.1)],
        ..Default::default()
    };
    let error = laser::readings(&table, "bare.csv", &machine, &contradicting)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("Y = 200 mm given, but the preamble says 205 mm"),
        "{error}"
    );
}

/// Three ball-bar circles on vmc3 (as vmc3_ballbar_3planes.toml, more errors) with the noise,
/// resolution and servo lag off: feed-forward 1 puts the axes on the interpolator's 1 ms
/// chords (0.2 nm inside the arc at 1000 mm/min on 150 mm), so the angles are where the axes
/// are.
const BALLBAR_TEST: &str = r#"schema = 1
machine = "MODELS/vmc3.urdf"
seed = 1
[errors.EC0Y]
constant_urad = -20.0
[errors.EA0Z]
constant_urad = 12.0
[errors.EB0Z]
constant_urad = 15.0
[errors.EXX]
polynomial_um = [0.0, 0.008]
reversal_um = 3.0
harmonic = [{ period_mm = 10.0, amplitude_um = 0.8, phase_deg = 0.0 }]
[errors.EYY]
polynomial_um = [0.0, -0.004]
reversal_um = 2.0
[errors.EZZ]
reversal_um = 6.0
[errors.EYX]
reversal_um = 1.5
polynomial_um = [-10.0, 0.05263157894736842, -6.925207756232687e-05]
[errors.EBX]
polynomial_urad = [0.0, 0.02]
[errors.EAY]
polynomial_urad = [3.0, -0.01]
[errors.ECZ]
polynomial_urad = [0.0, 0.01]
[ballbar]
planes = ["XY", "YZ", "ZX"]
length_mm = 150.0
feed_mm_per_min = 1000.0
centre_mm = { x = 380.0, y = 205.0, z = 300.0 }
setup_offset_um = [10.0, -5.0, 8.0]
calibration_um = 0.5
noise_um = 0.0
resolution_um = 0.0
[servo]
X = { kv_per_s = 33.3, feed_forward = 1.0 }
Y = { kv_per_s = 33.3, feed_forward = 1.0 }
Z = { kv_per_s = 30.0, feed_forward = 1.0 }
"#;

#[test]
fn ballbar_readings_reproduce_the_simulated_tables_with_the_true_errors_and_setup() {
    let scenario = load(BALLBAR_TEST);
    let tables = simulate(&scenario).unwrap().ballbar;
    let machine = &scenario.twin.machine;
    let test = scenario.ballbar_test.as_ref().unwrap();
    let offset = test.ballbar.setup_offset;
    let calibration = test.ballbar.calibration_error;
    let (radius, feed) = (0.15, 1.0 / 60.0);
    // An axis on the chords reverses where a chord's rate changes sign, up to one chord
    // (feed × 1 ms) from the programmed reversal: a reading in between has the other
    // direction in the simulation.
    let chord = feed * 1e-3 / radius;
    for (table, circle) in tables.iter().zip(&test.circles) {
        let plane = circle.plane;
        let file = format!("ballbar_{}.csv", plane.lower());
        let mut bytes = Vec::new();
        table.write_csv(&mut bytes).unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        assert!(
            text.contains("# centre_mm = 380 205 300\n"),
            "{}",
            &text[..300]
        );
        assert!(text.contains("# machine = vmc3\n"), "{}", &text[..300]);
        let table = BallbarTable::parse(&bytes, &file).unwrap();
        let readings = ballbar::readings(&table, &file, machine, &ballbar::Setup::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let (p, q, n) = (plane.first(), plane.second(), plane.normal());
        let letter = |a: Axis| a.letter().to_ascii_lowercase();
        let names: Vec<&str> = readings.nuisance.iter().map(|q| q.name.as_str()).collect();
        let pq = format!("{}{}", p.letter(), q.letter());
        assert_eq!(
            names,
            [
                format!("{pq}.centre.{}", letter(p)),
                format!("{pq}.centre.{}", letter(q)),
                format!("{pq}.radius")
            ]
        );
        assert_eq!(readings.setup[0].name, format!("{pq}.centre.{}", letter(n)));
        assert_eq!(readings.machine.as_deref(), Some("vmc3"));
        // vmc3's workpiece frame is along its axes: the centre offset is minus the set-up
        // offset of the centre ball, component by component.
        let along = |a: Axis| offset[a.coordinate()];
        let nuisance = [-along(p), -along(q), calibration];
        let setup = [-along(n)];
        let predicted = predict(&readings, machine, &scenario.twin.errors, &nuisance, &setup);
        let near_reversal = |angle: Real| {
            let k = (angle / FRAC_PI_2).round();
            (angle - k * FRAC_PI_2).abs() <= 2.0 * chord
        };
        let (mut worst, mut at_reversals, mut largest) = (0.0, 0, 0.0);
        for ((reading, p), m) in table
            .readings
            .iter()
            .zip(&predicted)
            .zip(&readings.measured)
        {
            let difference = (p - m).abs();
            largest = Real::max(largest, m.abs());
            if difference > 1.0 * NM {
                assert!(
                    near_reversal(reading.angle),
                    "{plane} {:?} at {:.6}°: model {p} vs table {m}",
                    reading.sense,
                    reading.angle.to_degrees()
                );
                at_reversals += 1;
            } else {
                worst = Real::max(worst, difference);
            }
        }
        eprintln!(
            "{plane}: {} readings up to {:.3} µm; model − table at most {:.3} nm, {} reading(s) within a chord of a reversal differ",
            readings.len(),
            largest / UM,
            worst / NM,
            at_reversals
        );
        assert!(largest > 5.0 * UM);
        assert!(at_reversals <= 12, "{at_reversals} readings off");
        assert!(worst <= 1.0 * NM);
    }
}

/// vmc3's XY circle of radius R about X 380, Y 205, Z 300 mm, read every 5° in both senses
/// (the values do not matter: only the model is used), its centre given as a flag would be.
fn hand_circle(radius: Real) -> (BallbarTable, ballbar::Setup) {
    let mut readings = Vec::new();
    for sense in [Sense::Ccw, Sense::Cw] {
        for k in 0..72 {
            readings.push(BallbarReading {
                sense,
                angle: (k as Real * 5.0).to_radians(),
                deviation: 0.0,
                time: None,
            });
        }
    }
    let table = BallbarTable {
        readings,
        conditions: TestConditions {
            plane: Some(Plane::XY),
            radius: Some(radius),
            ..Default::default()
        },
        machine: None,
        columns_not_read: Vec::new(),
    };
    let setup = ballbar::Setup {
        centre: Some(AxisValues::from_file_units(&[
            (Axis::X, 380.0),
            (Axis::Y, 205.0),
            (Axis::Z, 300.0),
        ])),
        ..Default::default()
    };
    (table, setup)
}

#[test]
fn squareness_in_xy_shortens_the_bar_on_the_diagonal_by_hand() {
    // mtwin::errors: EC0Y adds δx = −EC0Y·y to the tool relative to the workpiece, exactly a
    // turn of the Y line by EC0Y about Z: Y travel q moves the tool by q·(−sin ε, cos ε, 0).
    // The centre ball was set at the machine's own centre, so its shift (−ε·y_c) cancels: the
    // bar from the centre to the tool at θ is R·(cos θ − sin ε·sin θ, cos ε·sin θ), of length
    // R·√(1 − 2·sin ε·sin θ·cos θ): −ε·R·sin θ·cos θ to first order, the ellipse at 45°
    // that ball-bar software reads as squareness.
    let machine = common::machine("vmc3");
    let epsilon = 20e-6;
    let radius = 0.15;
    let model = errors(&machine, &[("EC0Y", ErrorFunction::Constant(epsilon))]);
    let (table, setup) = hand_circle(radius);
    let readings = ballbar::readings(&table, "hand.csv", &machine, &setup).unwrap();
    let predicted = predict(&readings, &machine, &model, &[0.0; 3], &[0.0]);
    let (mut first_worst, mut exact_worst) = (0.0, 0.0);
    for (reading, p) in table.readings.iter().zip(&predicted) {
        let (s, c) = reading.angle.sin_cos();
        let first_order = -epsilon * radius * s * c;
        let exact = radius * ((1.0 - 2.0 * epsilon.sin() * s * c).sqrt() - 1.0);
        first_worst = Real::max(first_worst, (p - first_order).abs());
        exact_worst = Real::max(exact_worst, (p - exact).abs());
    }
    eprintln!(
        "EC0Y {:.0} µrad on R {:.0} mm: first order within {:.3} nm, exact within {:.2e} nm",
        epsilon / 1e-6,
        radius * 1e3,
        first_worst / NM,
        exact_worst / NM
    );
    assert!(first_worst <= 1.0 * NM, "first order: {first_worst} m");
    assert!(exact_worst <= 1e-12, "exact: {exact_worst} m");
    // At 45° the bar is ε·R/2 = 1.5 µm short.
    let at_45 = predicted[9];
    assert!((at_45 + epsilon * radius / 2.0).abs() < 1.0 * NM, "{at_45}");
}

#[test]
fn the_centre_offset_adds_its_cosine_and_the_radius_its_value() {
    // c = centre of the machine's circle relative to the centre ball: the bar from the ball
    // to the tool is (R cos θ + c_x, R sin θ + c_y), of length R + c_x·cos θ + c_y·sin θ
    // + O(c²/R) (the ISO 230-4 centre offset); the calibration offset adds as it is; the
    // normal offset acts at second order only. On a machine without errors, so that nothing
    // but the set-up is in the bar.
    let machine = common::machine("vmc3");
    let radius = 0.15;
    let model = ErrorModel::empty(&machine);
    let (table, setup) = hand_circle(radius);
    let readings = ballbar::readings(&table, "hand.csv", &machine, &setup).unwrap();
    let base = predict(&readings, &machine, &model, &[0.0; 3], &[0.0]);
    let (ex, ey, r, ez) = (20.0 * UM, -12.0 * UM, 0.7 * UM, 15.0 * UM);
    let second_order = (ex * ex + ey * ey) / (2.0 * radius);
    let shifted = predict(&readings, &machine, &model, &[ex, ey, 0.0], &[0.0]);
    let mut worst: Real = 0.0;
    for ((reading, s), b) in table.readings.iter().zip(&shifted).zip(&base) {
        let first = ex * reading.angle.cos() + ey * reading.angle.sin();
        worst = worst.max((s - b - first).abs());
    }
    eprintln!(
        "centre offset ({} , {}) µm: first order within {:.3} nm (second-order size {:.3} nm)",
        ex / UM,
        ey / UM,
        worst / NM,
        second_order / NM
    );
    assert!(worst <= second_order * 1.01, "{worst} vs {second_order}");
    assert!(
        worst >= second_order * 0.5,
        "the second order is there: {worst}"
    );
    let lengthened = predict(&readings, &machine, &model, &[0.0, 0.0, r], &[0.0]);
    assert!(
        lengthened
            .iter()
            .zip(&base)
            .all(|(l, b)| (l - b - r).abs() < 1e-15)
    );
    let lifted = predict(&readings, &machine, &model, &[0.0; 3], &[ez]);
    let normal = ez * ez / (2.0 * radius);
    assert!(
        lifted
            .iter()
            .zip(&base)
            .all(|(l, b)| (l - b - normal).abs() < 0.01 * normal)
    );
    // The readings' angles and directions: the angles the table gives, both senses.
    assert_eq!(readings.len(), 144);
    assert!(readings.sigma.iter().all(|s| *s == ballbar::DEFAULT_SIGMA));
}

#[test]
fn ballbar_readings_need_the_centre_and_refuse_a_contradicting_one() {
    let machine = common::machine("vmc3");
    let (table, setup) = hand_circle(0.15);
    let error = ballbar::readings(&table, "b.csv", &machine, &ballbar::Setup::default())
        .unwrap_err()
        .to_string();
    assert!(error.contains("`# centre_mm = x y z`"), "{error}");
    let mut stated = table.clone();
    stated.conditions.centre = setup.centre;
    assert!(ballbar::readings(&stated, "b.csv", &machine, &ballbar::Setup::default()).is_ok());
    let mut other = setup;
    other.centre.as_mut().unwrap()[Axis::Y] = 0.2;
    let error = ballbar::readings(&stated, "b.csv", &machine, &other)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("the centre's Y = 200 mm given, but the preamble says 205 mm"),
        "{error}"
    );
    let mut no_plane = stated;
    no_plane.conditions.plane = None;
    let error = ballbar::readings(&no_plane, "b.csv", &machine, &ballbar::Setup::default())
        .unwrap_err()
        .to_string();
    assert!(error.contains("plane"), "{error}");
}
