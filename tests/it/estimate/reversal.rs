//! Lost motion as a parameter (`reversal`, `EXX.reversal`): what the SPEC accepts, the lost
//! motion identified from a laser table against the injected truth, and written out; a rotary
//! axis's from R-tests turned both ways.

use super::*;

/// vmc3's X positioning error: a scale and a curvature (µm/mm^k) and the lost motion.
const POLYNOMIAL_UM: [Real; 3] = [0.0, 0.012, -8.0e-6];

/// An ISO 230-2 laser test of vmc3's X axis (5 bidirectional runs, 11 targets, the beam
/// through the tool tip, 20 nm of noise) with `reversal_um` of lost motion.
fn x_laser_text(seed: u64, reversal_um: Real) -> String {
    format!(
        "schema = 1\nmachine = \"MODELS/vmc3.urdf\"\nseed = {seed}\n\
         [errors.EXX]\npolynomial_um = {POLYNOMIAL_UM:?}\nreversal_um = {reversal_um}\n\
         [iso230_2]\naxis = \"X\"\ntargets_mm = {{ from = 10.0, to = 750.0, count = 11 }}\nruns = 5\n\
         overrun_mm = 5.0\nfeed_mm_per_min = 2000.0\ndwell_s = 2.0\ny_mm = 205.0\nz_mm = 100.0\n\
         [laser]\nbeam_offset_mm = [0.0, 0.0, 0.0]\nresolution_nm = 1.0\nnoise_nm = 20.0\ncompensation = \"off\"\n"
    )
}

fn x_laser(seed: u64, reversal_um: Real) -> (Scenario, Readings) {
    let scenario = load(&x_laser_text(seed, reversal_um));
    let run = simulate(&scenario).unwrap().laser.unwrap();
    let set = mtwin::kinds::positioning::readings::readings(
        &run.table,
        "simulated",
        &scenario.twin.machine,
        &Default::default(),
    )
    .unwrap();
    (scenario, set)
}

/// The truth of a label in SI, by hand from the scenario's numbers: a polynomial coefficient
/// of degree k in µm/mm^k is 10⁻⁶/10⁻³ᵏ of it in m/m^k; the lost motion is the injected one.
fn truth(reversal_um: Real, label: &str) -> Real {
    if let Some(rest) = label.strip_prefix("EXX.polynomial[") {
        let k: usize = rest.trim_end_matches(']').parse().unwrap();
        return POLYNOMIAL_UM[k] * 1e-6 / 1e-3f64.powi(k as i32);
    }
    assert_eq!(label, "EXX.reversal");
    reversal_um * 1e-6
}

/// With 3 µm of lost motion, `EXX:2` alone fits a laser table at χ²/dof in the thousands (by
/// hand: half the lost motion, 1.5 µm, against 20 nm of noise, (1.5/0.02)² ≈ 5 600, less
/// what the offset takes), and `EXX:2,EXX.reversal` at the noise, with the lost motion and
/// the polynomial within 4 u of the truth on three seeds.
#[test]
fn lost_motion_is_identified_from_a_laser_table() {
    let machine = x_laser(1, 3.0).0.twin.machine.clone();
    for seed in 1..=3 {
        let (_, set) = x_laser(seed, 3.0);
        let sets = [set];
        let (_, without, _, _) = estimate(&machine, "EXX:2", &sets, 0);
        let chi2 = |fit: &Fit| fit.chi2 / fit.dof as Real;
        assert!(chi2(&without) > 1000.0, "χ²/dof {}", chi2(&without));
        let (set, fit, scales, labels) = estimate(&machine, "EXX:2,EXX.reversal", &sets, 0);
        assert_eq!(
            labels[..set.len()],
            ["EXX.polynomial[1]", "EXX.polynomial[2]", "EXX.reversal"]
        );
        assert!(fit.birge_scaled.is_none(), "χ²/dof {}", chi2(&fit));
        let what = format!("seed {seed}");
        let truth = |label: &str| truth(3.0, label);
        assert_within_four_u(
            (&fit, &scales, &labels),
            set.len(),
            Numbered::All,
            truth,
            &what,
        );
    }
}

/// The SPEC: `reversal` is each linear axis's lost motion; `EXX.reversal` one axis's, beside
/// its polynomial or alone; a lost motion of anything but a positioning error, with a degree,
/// or of an axis the machine lacks, is refused saying why.
#[test]
fn the_spec_names_lost_motions_and_refuses_what_is_not_one() {
    let machine = x_laser(1, 3.0).0.twin.machine.clone();
    let labels = |spec: &str| ParameterSet::parse(spec, &machine).unwrap().labels;
    assert_eq!(
        labels("reversal"),
        ["EXX.reversal", "EYY.reversal", "EZZ.reversal"]
    );
    // In ISO order, EYY's polynomial and lost motion together.
    assert_eq!(
        labels("EYY:1,reversal"),
        [
            "EXX.reversal",
            "EYY.polynomial[1]",
            "EYY.reversal",
            "EZZ.reversal"
        ]
    );
    let refused = |spec: &str| ParameterSet::parse(spec, &machine).unwrap_err().to_string();
    assert!(
        refused("EXY.reversal").contains("positioning error"),
        "{}",
        refused("EXY.reversal")
    );
    assert!(refused("EXX.reversal:2").contains("one number per axis"));
    assert!(refused("ECC.reversal").contains("has no axis C"));
}

/// The loop through the command line: `identify --params EXX:2,EXX.reversal` on the simulated
/// table writes the lost motion in estimate.json (within 4 u of the injected 3 µm), which
/// `score` sets against the run's truth, and in the LinuxCNC table, whose forward and reverse trims differ by it on every line (by hand: the
/// reverse approach reads the lost motion beyond the forward one, so the trims, each the
/// negated error of its direction, differ by it) and in the HEIDENHAIN table's BACKLASH
/// column, which reads it beyond the axis column; and the scenario compensated with the
/// estimate, simulated again, reverses by what is left of the lost motion: its ISO 230-2
/// reversal value B falls below a tenth of the uncompensated one.
#[test]
fn lost_motion_is_written_out_and_compensated() {
    use crate::common::mtwin_output as mtwin;
    let dir = tempfile::tempdir().unwrap();
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let scenario = dir.path().join("x.toml");
    let text = x_laser_text(1, 3.0).replace("MODELS", &models.display().to_string());
    std::fs::write(&scenario, text).unwrap();
    let ok = |args: &[&std::ffi::OsStr]| {
        let output = mtwin(args);
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        String::from_utf8_lossy(&output.stdout).into_owned()
    };
    let run = |scenario: &Path, name: &str| {
        let out = dir.path().join(name);
        ok(&[
            "run".as_ref(),
            scenario.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        out.join("positioning.csv")
    };
    let table = run(&scenario, "run");
    let id = dir.path().join("id");
    ok(&[
        "identify".as_ref(),
        "--machine".as_ref(),
        models.join("vmc3.urdf").as_os_str(),
        "--params".as_ref(),
        "EXX:2,EXX.reversal".as_ref(),
        table.as_os_str(),
        "--scenario".as_ref(),
        scenario.as_os_str(),
        "--out".as_ref(),
        id.as_os_str(),
    ]);
    let estimate: serde_json::Value =
        serde_json::from_slice(&std::fs::read(id.join("estimate.json")).unwrap()).unwrap();
    let exx = &estimate["errors"]["EXX"];
    let r = exx["terms"]["reversal_um"].as_f64().unwrap();
    let u = exx["standard_uncertainty"]["reversal_um"].as_f64().unwrap();
    assert!((r - 3.0).abs() <= 4.0 * u, "{r} ± {u} µm against 3 µm");
    // `score` compares it with the truth the run wrote, term for term.
    let score: serde_json::Value = serde_json::from_str(&ok(&[
        "score".as_ref(),
        id.join("estimate.json").as_os_str(),
        table.with_file_name("truth.json").as_os_str(),
        "--json".as_ref(),
    ]))
    .unwrap();
    let scored = score["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "EXX.reversal_um")
        .unwrap_or_else(|| panic!("{score:#}"));
    assert_eq!(scored["truth"].as_f64(), Some(3.0), "{scored}");
    assert!((scored["estimate"].as_f64().unwrap() - r).abs() < 1e-12);
    let comp = std::fs::read_to_string(id.join("linuxcnc_X.comp")).unwrap();
    let mut lines = 0;
    for line in comp.lines() {
        let v: Vec<Real> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        // Trims in mm, written to 1 nm.
        assert!(
            ((v[1] - v[2]) * 1e3 - r).abs() < 2e-3,
            "{line}: forward − reverse against {r} µm"
        );
        lines += 1;
    }
    assert!(lines > 2, "{comp}");
    // The HEIDENHAIN table holds both directions' curves: the BACKLASH column (travelling
    // negative) reads the lost motion beyond the axis column on every line.
    let com = std::fs::read_to_string(id.join("heidenhain_X.com")).unwrap();
    let (positions, forward, backward) = super::controllers::read_com(&com, "X");
    assert!(positions.len() > 2, "{com}");
    for (f, b) in forward.iter().zip(&backward) {
        assert!(((b - f) * 1e3 - r).abs() < 2e-3, "{f} {b} against {r} µm");
    }
    let reversal_value = |table: &Path| {
        let json: serde_json::Value = serde_json::from_str(&ok(&[
            "analyze".as_ref(),
            "positioning".as_ref(),
            table.as_os_str(),
            "--json".as_ref(),
        ]))
        .unwrap();
        json["B_um"].as_f64().unwrap_or_else(|| panic!("{json:#}"))
    };
    let compensated = run(&id.join("compensated.toml"), "compensated");
    let (before, after) = (reversal_value(&table), reversal_value(&compensated));
    assert!(before > 2.5, "B = {before} µm before");
    assert!(after < 0.1 * before, "B = {before} µm → {after} µm");
}

/// A ball-bar trace in XY (vmc3, 150 mm bar, both senses, 0.1 µm of noise) with 4 µm of lost
/// motion in X and 2 µm in Y, a squareness and the axes' scales and curvatures: the preset
/// `reversal` finds both lost motions within 4 u and the fit comes down to the noise (χ²/dof
/// about 114 without them: the steps at the quadrants, half the lost motion each, against
/// 0.1 µm), while Z's, which an XY trace never moves, is not seen at all. The scales stay
/// unseen as without the lost motion (a bar of unknown length reads their common part).
#[test]
fn lost_motion_is_identified_from_a_ballbar_trace() {
    let text = "schema = 1\nmachine = \"MODELS/vmc3.urdf\"\nseed = 1\n\
        [errors.EC0Y]\nconstant_urad = -20.0\n\
        [errors.EXX]\npolynomial_um = [0.0, 0.012, -8.0e-6]\nreversal_um = 4.0\n\
        [errors.EYY]\npolynomial_um = [0.0, -0.010, 6.0e-6]\nreversal_um = 2.0\n\
        [ballbar]\nplanes = [\"XY\"]\nlength_mm = 150.0\nfeed_mm_per_min = 500.0\n\
        centre_mm = { x = 380.0, y = 205.0, z = 300.0 }\nsetup_offset_um = [10.0, -5.0, 8.0]\n\
        noise_um = 0.1\nresolution_um = 0.1\n";
    let scenario = load(text);
    let machine = &scenario.twin.machine;
    let sets = ballbar_readings(&scenario);
    let (set, fit, scales, labels) = estimate(machine, "EC0Y,EXX:2,EYY:2,reversal", &sets, 0);
    assert!(
        fit.birge_scaled.is_none(),
        "χ²/dof {}",
        fit.chi2 / fit.dof as Real
    );
    let unidentified: Vec<&str> = fit
        .identifiability
        .unidentifiable
        .iter()
        .filter(|&&j| j < set.len())
        .map(|&j| labels[j].as_str())
        .collect();
    assert_eq!(
        unidentified,
        ["EXX.polynomial[1]", "EYY.polynomial[1]", "EZZ.reversal"],
        "{}",
        fit.identifiability.report()
    );
    let truth = |label: &str| -> Real {
        match label {
            "EC0Y" => -20e-6,
            "EXX.reversal" => 4e-6,
            "EYY.reversal" => 2e-6,
            // µm/mm² as m/m²: 10⁻⁶ / 10⁻⁶.
            "EXX.polynomial[2]" => -8.0e-6 * 1e-6 / 1e-3f64.powi(2),
            "EYY.polynomial[2]" => 6.0e-6 * 1e-6 / 1e-3f64.powi(2),
            other => panic!("{other} has a number"),
        }
    };
    assert_within_four_u(
        (&fit, &scales, &labels),
        set.len(),
        Numbered::Identified,
        truth,
        "ball-bar XY",
    );
}

/// trunnion5's C with 20 µrad of lost motion and a 15 µrad zero error, on top of the R-test
/// location errors, read by `tests` (one datum for the sequence).
fn c_lost_motion_rtest(seed: u64, tests: &[(&str, &str, &str, usize)]) -> (Scenario, Readings) {
    let text = trunnion_rtest(seed, 0.2, "[100.0, 0.0, 250.0]", tests)
        + "[errors.ECC]\nreversal_urad = 20.0\n[errors.EC0C]\nconstant_urad = 15.0\n";
    simulated(&text, Setup::default())
}

/// The C circles of [`TWO_CIRCLES`] and the circle at A = 0 turned back (C from 360° to 0°).
const CIRCLES_BOTH_WAYS: [(&str, &str, &str, usize); 3] = [
    ("CK1 A0", "A = 0.0, C = 0.0", "C = 360.0", 19),
    ("CK1 A0 back", "A = 0.0, C = 360.0", "C = 0.0", 19),
    ("CK1 A-45", "A = -45.0, C = 0.0", "C = 360.0", 19),
];

/// A rotary axis's lost motion from R-tests. Travelling one way, C's lost motion (±r/2 by
/// direction) is a constant angle, as its zero error is, and a constant angle of C moves the
/// one sphere as the C axis line's offset in Y and the datum do (by hand: δ·ẑ × R(C)·s is the
/// rotating part of the sphere's motion about a line offset by −δ·ẑ × s): with the circles all
/// turned one way the lost motion gets no number. With the circle at A = 0 turned back as well,
/// the sphere at 100 mm from C sits r·100 mm (2 µm for 20 µrad) further round the circle one
/// way than the other, which no constant explains: the lost motion comes back within 4 u of
/// the truth (20 µrad) on three seeds, beside the location errors, while the zero error (15
/// µrad) stays in its combination with the line's offset in Y and the datum, as it must.
#[test]
fn a_rotary_axis_lost_motion_is_identified_from_r_tests_turned_both_ways() {
    let spec = "location,EC0C,ECC.reversal";
    let truth = |scenario: &Scenario, label: &str| match label {
        "ECC.reversal" => 20e-6,
        label => truth_of(scenario, label),
    };
    let (scenario, one_way) = c_lost_motion_rtest(1, &TWO_CIRCLES);
    let machine = scenario.twin.machine.clone();
    let (_, fit, _, labels) = estimate(&machine, spec, std::slice::from_ref(&one_way), 0);
    for name in ["EC0C", "ECC.reversal"] {
        let j = labels.iter().position(|l| l == name).unwrap();
        assert!(
            fit.uncertainty(j).is_none(),
            "{name} has a number from circles turned one way: {}",
            fit.identifiability.report()
        );
    }
    for seed in 1..=3 {
        let (scenario, both) = c_lost_motion_rtest(seed, &CIRCLES_BOTH_WAYS);
        let (set, fit, scales, labels) = estimate(&machine, spec, std::slice::from_ref(&both), 0);
        let unidentified: Vec<&str> = (0..labels.len())
            .filter(|&j| fit.uncertainty(j).is_none())
            .map(|j| labels[j].as_str())
            .collect();
        assert_eq!(
            unidentified,
            ["EC0C", "EY0A", "EY0C", "datum.zero.y"],
            "{}",
            fit.identifiability.report()
        );
        let j = labels.iter().position(|l| l == "ECC.reversal").unwrap();
        let u = fit.uncertainty(j).unwrap() * scales[j];
        assert!(u < 2e-6, "u(ECC.reversal) = {u:e} rad");
        assert_within_four_u(
            (&fit, &scales, &labels),
            set.len(),
            Numbered::Identified,
            |label| truth(&scenario, label),
            &format!("seed {seed}"),
        );
    }
}

/// The bundled R-test (`scenarios/trunnion5_rtest.toml`: four K-tests, each with its own datum)
/// with 20 µrad of lost motion on C, and its circle at A = 0 turned one way or, with
/// `back = true`, out and back in one test.
fn bundled_rtest_with_c_lost_motion(back: bool) -> (Scenario, Readings) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/trunnion5_rtest.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let circle =
        "name = \"CK1 A0\"\nfrom_deg = { A = 0.0, C = 0.0 }\nto_deg = { C = 360.0 }\npoints = 37\n";
    assert!(text.contains(circle), "the bundled circle at A = 0");
    let text = text
        .replace("machine = \"../models/", "machine = \"MODELS/")
        .replace(circle, &format!("{circle}back = {back}\n"))
        .replace(
            "[rtest]\n",
            "[errors.ECC]\nreversal_urad = 20.0\n\n[rtest]\n",
        );
    simulated(&text, Setup::default())
}

/// Each test with its own datum, a lost motion of C read from one way only is a constant angle
/// each test's zero and the C line absorb: no number. With the circle at A = 0 out and back in
/// one test (`back = true`), each C angle is read both ways against the same datum, and the
/// lost motion comes back within 4 u of the 20 µrad beside the eight location errors, all
/// identified (the bundled tests identify them, `mtwin identify --params location`).
#[test]
fn a_test_out_and_back_reads_a_rotary_lost_motion_against_its_own_datum() {
    let spec = "location,ECC.reversal";
    let (scenario, one_way) = bundled_rtest_with_c_lost_motion(false);
    let machine = scenario.twin.machine.clone();
    let (_, fit, _, labels) = estimate(&machine, spec, std::slice::from_ref(&one_way), 0);
    let j = labels.iter().position(|l| l == "ECC.reversal").unwrap();
    assert!(
        fit.uncertainty(j).is_none(),
        "{}",
        fit.identifiability.report()
    );
    let (scenario, both) = bundled_rtest_with_c_lost_motion(true);
    // Three readings a pose: the circle at A = 0 out and back (2·37 − 1), then 37, 19, 37.
    assert_eq!(both.measured.len(), 3 * (73 + 37 + 19 + 37));
    let (set, fit, scales, labels) = estimate(&machine, spec, std::slice::from_ref(&both), 0);
    assert!(
        fit.identifiability.null_combinations.is_empty(),
        "{}",
        fit.identifiability.report()
    );
    let truth = |label: &str| match label {
        "ECC.reversal" => 20e-6,
        label => truth_of(&scenario, label),
    };
    assert_within_four_u(
        (&fit, &scales, &labels),
        set.len(),
        Numbered::All,
        truth,
        "out and back",
    );
}
