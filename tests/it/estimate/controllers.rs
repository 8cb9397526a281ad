//! Controller compensation files read back by a reader written here from the vendors'
//! descriptions, and applied as the control applies them.

use super::*;
use mtwin::machine::Direction;

/// A SINUMERIK LEC file read back: `(min, step, max, modulo, values)` in file units.
fn read_lec(text: &str, axis: &str) -> (Real, Real, Real, bool, Vec<Real>) {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("%_N_AX_EEC_INI"));
    assert_eq!(lines.next(), Some("CHANDATA(1)"));
    assert_eq!(text.lines().last(), Some("M17"));
    let (mut min, mut step, mut max, mut modulo) = (None, None, None, None);
    let mut values: Vec<(usize, Real)> = Vec::new();
    for line in lines.filter(|l| !l.starts_with(';') && *l != "M17") {
        let (key, value) = line.split_once('=').unwrap();
        let value: Real = value.parse().unwrap();
        let inside = |prefix: &str| {
            key.strip_prefix(prefix)
                .and_then(|k| k.strip_suffix(']'))
                .map(|k| k.split(',').map(str::to_string).collect::<Vec<_>>())
        };
        if let Some(i) = inside("$AA_ENC_COMP[") {
            assert_eq!((i[0].as_str(), i[2].as_str()), ("0", axis), "{line}");
            values.push((i[1].parse().unwrap(), value));
        } else if let Some(i) = inside("$AA_ENC_COMP_STEP[") {
            assert_eq!(i, ["0", axis]);
            step = Some(value);
        } else if inside("$AA_ENC_COMP_MIN[").is_some() {
            min = Some(value);
        } else if inside("$AA_ENC_COMP_MAX[").is_some() {
            max = Some(value);
        } else if inside("$AA_ENC_COMP_IS_MODULO[").is_some() {
            modulo = Some(value == 1.0);
        } else {
            panic!("unexpected line {line}");
        }
    }
    for (k, (n, _)) in values.iter().enumerate() {
        assert_eq!(*n, k, "interpolation points in order");
    }
    let values: Vec<Real> = values.into_iter().map(|(_, v)| v).collect();
    let (min, step, max) = (min.unwrap(), step.unwrap(), max.unwrap());
    assert!((min + (values.len() - 1) as Real * step - max).abs() < 1e-9);
    (min, step, max, modulo.unwrap(), values)
}

/// The LEC value at axis position `q` as the control interpolates it: linearly between the
/// points, the first and last values held beyond the table.
fn lec_value((min, step, _, _, values): &(Real, Real, Real, bool, Vec<Real>), q: Real) -> Real {
    let x = ((q - min) / step).clamp(0.0, (values.len() - 1) as Real);
    let k = (x.floor() as usize).min(values.len() - 2);
    let w = x - k as Real;
    values[k] * (1.0 - w) + values[k + 1] * w
}

/// Where an axis commanded to `n` stops when the control corrects it by `value(q)` at its
/// position `q`: the fixed point of `q = n − value(q)` (a contraction for errors of µm per m).
fn stops_at(n: Real, value: impl Fn(Real) -> Real) -> Real {
    let mut q = n;
    for _ in 0..20 {
        q = n - value(q);
    }
    q
}

/// vmc3 with an X positioning error of a scale (12 µm/m), a curvature and 3 µm of lost motion.
fn vmc3_x_with_lost_motion() -> Scenario {
    load(
        "schema = 1\nmachine = \"MODELS/vmc3.urdf\"\nseed = 1\n\
        [errors.EXX]\npolynomial_um = [0.0, 0.012, -8.0e-6]\nreversal_um = 3.0\n\
        [volumetric]\nx_mm = { from = 0.0, to = 760.0, count = 2 }\n\
        y_mm = { from = 0.0, to = 410.0, count = 2 }\nz_mm = { from = 0.0, to = 520.0, count = 2 }\n",
    )
}

/// The one table written, for vmc3's X, and X's travel (m).
fn the_x_table<'a>(
    tables: &'a [(mtwin::machine::Axis, String)],
    scenario: &Scenario,
) -> (&'a str, (Real, Real)) {
    assert_eq!(tables.len(), 1);
    let (axis, file) = &tables[0];
    assert_eq!(*axis, mtwin::machine::Axis::X);
    let travel = scenario
        .twin
        .machine
        .axis(mtwin::machine::Axis::X)
        .unwrap()
        .limits
        .unwrap();
    (file, travel)
}

/// vmc3's X with a scale, a curvature and 3 µm of lost motion, compensated by the SINUMERIK
/// table mtwin writes, applied as the K3 manual describes it: the control adds the value to
/// the axis's actual position, so a positive value moves the axis negative, and the axis
/// commanded to `n` stops at `q` with `q + v(q) = n`. By hand, what is left at the tool is
/// then the direction-dependent half of the lost motion, −1.5 µm travelling up and +1.5 µm
/// down (which the backlash compensation the header names takes), to the table's linear
/// interpolation of the curvature (8·10⁻⁶ µm/mm² over 10 mm steps: 10⁻⁴ µm) and its 1 nm
/// rounding; the header states the lost motion, 0.003 mm.
#[test]
fn a_sinumerik_lec_table_leaves_only_the_lost_motion() {
    let scenario = vmc3_x_with_lost_motion();
    let machine = &scenario.twin.machine;
    let errors = &scenario.twin.errors;
    let tables = mtwin::estimate::sinumerik::lec_tables(machine, errors, 0.01, 0.01).unwrap();
    let (file, (lower, upper)) = the_x_table(&tables, &scenario);
    assert!(file.contains("; lost motion 0.003 mm"), "{file}");
    let table = read_lec(file, "X1");
    assert!(!table.3, "a linear axis is not modulo");
    let exx = &errors.parameter("EXX".parse().unwrap()).unwrap().function;
    for k in 0..=97 {
        let n = lower + (upper - lower) * k as Real / 97.0;
        for (direction, left_um) in [(Direction::Positive, -1.5), (Direction::Negative, 1.5)] {
            // The position the axis stops at (mm in the table, m in the model).
            let q = stops_at(n, |q| lec_value(&table, q * 1e3) * 1e-3);
            let at_tool = q + exx.value(q, direction) - n;
            assert!(
                (at_tool * 1e6 - left_um).abs() < 1.5e-3,
                "n = {n} m, {direction:?}: {} µm left",
                at_tool * 1e6
            );
        }
    }
}

/// trunnion5's C with an angular positioning error of 20 µrad once and 8 µrad twice a turn,
/// and `more` keys of ECC.
fn trunnion5_c_harmonics(more: &str) -> Scenario {
    load(&format!(
        "schema = 1\nmachine = \"MODELS/trunnion5.urdf\"\nseed = 1\n\
         [errors.ECC]\n{more}harmonic = [\
         {{ period_deg = 360.0, amplitude_urad = 20.0, phase_deg = 30.0 }}, \
         {{ period_deg = 180.0, amplitude_urad = 8.0, phase_deg = -45.0 }}]\n\
         [volumetric]\nx_mm = {{ from = 0.0, to = 100.0, count = 2 }}\n\
         y_mm = {{ from = 0.0, to = 100.0, count = 2 }}\nz_mm = {{ from = 0.0, to = 100.0, count = 2 }}\n"
    ))
}

/// trunnion5's C axis turns without end: its table spans one turn and is modulo, in degrees.
/// With an angular positioning error of 20 µrad once and 8 µrad twice a turn and 10 µrad of
/// lost motion, applied as above (the axis position within the turn), what is left is ∓5 µrad
/// by direction to the linear interpolation of the harmonics between 1° points (by hand:
/// curvature × step²/8 = (20 + 4·8) µrad × (π/180)²/8 ≈ 2·10⁻³ µrad) and the 0.2 nrad rounding.
#[test]
fn a_sinumerik_lec_table_of_a_continuous_axis_is_modulo() {
    let scenario = trunnion5_c_harmonics("reversal_urad = 10.0\n");
    let machine = &scenario.twin.machine;
    let errors = &scenario.twin.errors;
    let one_degree = 1f64.to_radians();
    let tables = mtwin::estimate::sinumerik::lec_tables(machine, errors, 0.01, one_degree).unwrap();
    let (axis, file) = &tables[0];
    assert_eq!((tables.len(), *axis), (1, mtwin::machine::Axis::C));
    let table = read_lec(file, "C1");
    assert!(table.3, "a continuous axis is modulo:\n{file}");
    assert_eq!((table.0, table.2, table.4.len()), (0.0, 360.0, 361));
    // One turn: the first and last values are the same position's.
    assert!((table.4[0] - table.4[360]).abs() < 1e-8);
    let ecc = &errors.parameter("ECC".parse().unwrap()).unwrap().function;
    for k in 0..=720 {
        let n = 2.0 * std::f64::consts::TAU * k as Real / 720.0 - 1.0;
        for (direction, left_urad) in [(Direction::Positive, -5.0), (Direction::Negative, 5.0)] {
            let within = |q: Real| q.rem_euclid(std::f64::consts::TAU).to_degrees();
            let q = stops_at(n, |q| lec_value(&table, within(q)).to_radians());
            let at_tool = q + ecc.value(q.rem_euclid(std::f64::consts::TAU), direction) - n;
            assert!(
                (at_tool * 1e6 - left_urad).abs() < 5e-3,
                "n = {n} rad, {direction:?}: {} µrad left",
                at_tool * 1e6
            );
        }
    }
}

/// A HEIDENHAIN `*.COM` table read back: `(positions, forward values, backward values)` in
/// file units (the backward ones the forward ones where there is no `BACKLASH` column).
pub(super) fn read_com(text: &str, axis: &str) -> (Vec<Real>, Vec<Real>, Vec<Real>) {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(format!("BEGIN {axis}.COM MM").as_str()));
    assert_eq!(text.lines().last(), Some("[END]"));
    let header: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
    assert_eq!(&header[..3], ["NR", "AXISPOS", axis], "{text}");
    let backlash = match &header[3..] {
        [] => false,
        ["BACKLASH"] => true,
        other => panic!("unexpected columns {other:?}"),
    };
    let (mut positions, mut forward, mut backward) = (Vec::new(), Vec::new(), Vec::new());
    for (k, line) in lines.take_while(|l| *l != "[END]").enumerate() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(fields.len(), header.len(), "{line}");
        assert_eq!(fields[0].parse::<usize>().unwrap(), k, "{line}");
        // Every value carries its sign, as the control's tables write them.
        assert!(
            fields[1..].iter().all(|f| f.starts_with(['+', '-'])),
            "{line}"
        );
        let value = |i: usize| fields[i].parse::<Real>().unwrap();
        positions.push(value(1));
        forward.push(value(2));
        backward.push(if backlash { value(3) } else { value(2) });
    }
    assert!(
        positions.windows(2).all(|w| w[1] > w[0]),
        "ascending points"
    );
    (positions, forward, backward)
}

/// Linear interpolation in a read table, the ends held beyond it.
fn com_value(positions: &[Real], values: &[Real], q: Real) -> Real {
    let k = positions
        .partition_point(|&p| p <= q)
        .clamp(1, positions.len() - 1);
    let (p0, p1) = (positions[k - 1], positions[k]);
    let w = ((q - p0) / (p1 - p0)).clamp(0.0, 1.0);
    values[k - 1] * (1.0 - w) + values[k] * w
}

/// vmc3's X of the SINUMERIK test above in a HEIDENHAIN table, applied as the manuals describe
/// it: the value is the error measured at the point (positive where the travel is too long),
/// the axis column's travelling positive and the `BACKLASH` column's travelling negative, and
/// the control corrects by the opposite amount (`q + v(q) = n`). Both directions' curves are
/// in the table, so what is left at the tool is, by hand, the linear interpolation of the
/// curvature (10⁻⁴ µm) and the 1 nm rounding, in both directions: the lost motion is gone too.
#[test]
fn a_heidenhain_com_table_leaves_nothing_in_either_direction() {
    let scenario = vmc3_x_with_lost_motion();
    let machine = &scenario.twin.machine;
    let errors = &scenario.twin.errors;
    let tables = mtwin::estimate::heidenhain::com_tables(machine, errors, 0.01, 0.01).unwrap();
    let (file, (lower, upper)) = the_x_table(&tables, &scenario);
    let (positions, forward, backward) = read_com(file, "X");
    let exx = &errors.parameter("EXX".parse().unwrap()).unwrap().function;
    // 10 mm points from the lower end of the travel, the last at or beyond the upper one.
    assert_eq!(positions[0], lower * 1e3);
    assert!((positions[1] - positions[0] - 10.0).abs() < 1e-9);
    assert!(*positions.last().unwrap() >= upper * 1e3 - 1e-9);
    // The two curves differ by the 3 µm lost motion everywhere.
    for (f, b) in forward.iter().zip(&backward) {
        assert!((b - f - 0.003).abs() < 1.5e-6, "{f} {b}");
    }
    for k in 0..=97 {
        let n = lower + (upper - lower) * k as Real / 97.0;
        for (direction, curve) in [
            (Direction::Positive, &forward),
            (Direction::Negative, &backward),
        ] {
            let q = stops_at(n, |q| com_value(&positions, curve, q * 1e3) * 1e-3);
            let at_tool = q + exx.value(q, direction) - n;
            assert!(
                (at_tool * 1e6).abs() < 1.5e-3,
                "n = {n} m, {direction:?}: {} µm left",
                at_tool * 1e6
            );
        }
    }
}

/// Without a reversal term the table has no `BACKLASH` column; trunnion5's continuous C gets a
/// table over 0–360°, and at 1° it would have 361 points, more than the 256 written: the points
/// are widened to 360°/255, and what is left is the interpolation of the harmonics over that
/// step (by hand (20 + 4·8) µrad × (1.41°·π/180)²/8 ≈ 4·10⁻³ µrad) and the rounding.
#[test]
fn a_heidenhain_com_table_of_a_continuous_axis_covers_one_turn_in_256_points() {
    let scenario = trunnion5_c_harmonics("");
    let machine = &scenario.twin.machine;
    let errors = &scenario.twin.errors;
    let one_degree = 1f64.to_radians();
    let tables =
        mtwin::estimate::heidenhain::com_tables(machine, errors, 0.01, one_degree).unwrap();
    let (axis, file) = &tables[0];
    assert_eq!((tables.len(), *axis), (1, mtwin::machine::Axis::C));
    let (positions, forward, backward) = read_com(file, "C");
    assert_eq!(
        forward, backward,
        "no BACKLASH column without a reversal term:\n{file}"
    );
    assert_eq!(positions.len(), 256, "the manual's limit");
    assert_eq!((positions[0], *positions.last().unwrap()), (0.0, 360.0));
    let ecc = &errors.parameter("ECC".parse().unwrap()).unwrap().function;
    for k in 0..=720 {
        let n = 2.0 * std::f64::consts::TAU * k as Real / 720.0 - 1.0;
        let within = |q: Real| q.rem_euclid(std::f64::consts::TAU).to_degrees();
        let q = stops_at(n, |q| {
            com_value(&positions, &forward, within(q)).to_radians()
        });
        let at_tool = q + ecc.value(q.rem_euclid(std::f64::consts::TAU), Direction::Positive) - n;
        assert!(
            (at_tool * 1e6).abs() < 6e-3,
            "n = {n} rad: {} µrad left",
            at_tool * 1e6
        );
    }
}
