//! Malformed scenarios: values, grids and models; URDF frames and tools.

use super::*;

#[test]
fn scenario_value_inf() {
    let text = exx_with("polynomial_um = [0.0, inf]");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("polynomial_um"),
        Some("errors.EXX.polynomial_um"),
    );
}

#[test]
fn scenario_value_table_not_increasing() {
    let text =
        exx_with("table = { positions_mm = [0.0, 100.0, 100.0], values_um = [0.0, 1.0, 2.0] }");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("positions_mm"),
        Some("errors.EXX.table.positions_mm"),
    );
}

#[test]
fn scenario_value_period_zero() {
    let text = exx_with("harmonic = [{ period_mm = 0.0, amplitude_um = 0.4 }]");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("period_mm"),
        Some("errors.EXX.harmonic[0].period_mm"),
    );
}

#[test]
fn scenario_value_empty_error_table() {
    let text = exx_with("");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("[errors.EXX]"),
        Some("errors.EXX"),
    );
}

#[test]
fn scenario_value_polynomial_on_squareness() {
    let text = vmc3_with(
        "[errors.EXX]\nconstant_um = 1.0",
        "[errors.EC0Y]\npolynomial_urad = [1.0, 2.0]",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("polynomial_urad"),
        Some("errors.EC0Y.polynomial_urad"),
    );
}

#[test]
fn scenario_grid_outside_travel() {
    // X travels 0..760 mm on vmc3.
    let text = vmc3_with(
        "model = \"chain\"",
        "model = \"chain\"\nx_mm = { from = 0.0, to = 800.0, count = 5 }",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Grid,
        &text,
        Some("x_mm"),
        Some("volumetric.x_mm"),
    );
}

#[test]
fn scenario_grid_axis_machine_lacks() {
    let text = vmc3_with(
        "model = \"chain\"",
        "model = \"chain\"\na_deg = { from = 0.0, to = 90.0, count = 3 }",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Grid,
        &text,
        Some("a_deg"),
        Some("volumetric.a_deg"),
    );
}

#[test]
fn scenario_grid_count_zero() {
    let text = vmc3_with(
        "model = \"chain\"",
        "model = \"chain\"\ny_mm = { from = 0.0, to = 100.0, count = 0 }",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Grid,
        &text,
        Some("y_mm"),
        Some("volumetric.y_mm"),
    );
}

#[test]
fn scenario_model_unknown_name() {
    let text = vmc3_with("model = \"chain\"", "model = \"kinematic\"");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Model,
        &text,
        Some("model ="),
        Some("volumetric.model"),
    );
}

#[test]
fn scenario_model_lu2012_on_five_axis() {
    let text = replace_once(
        &minimal("trunnion5.urdf"),
        "model = \"chain\"",
        "model = \"lu2012\"",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Model,
        &text,
        Some("model ="),
        Some("volumetric.model"),
    );
}

#[test]
fn scenario_nothing_to_compute() {
    let text = vmc3_with("[volumetric]\nmodel = \"chain\"\n", "");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Nothing,
        &text,
        None,
        Some("[volumetric]"),
    );
}

// ---------------------------------------------------------------------------------------
// Checks added after review: joint frames, the tool axis, cycles, shared joints, grid size,
// implausible values, periodic axes, NaN targets.
// ---------------------------------------------------------------------------------------

#[test]
fn urdf_joint_frame_turned_at_home() {
    // X's frame yawed by π with its axis flipped still moves the table along -X, but EYX would
    // then act along -Y: refused.
    let text = replace_once(
        VMC3,
        "<origin xyz=\"0 0 0.15\" rpy=\"0 0 0\"/>\n    <axis xyz=\"-1 0 0\"/>",
        "<origin xyz=\"0 0 0.15\" rpy=\"0 0 3.141592653589793\"/>\n    <axis xyz=\"1 0 0\"/>",
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::JointFrame { axis: Axis::X }
    );
    assert_at_joint(&error, &path, &text, "X");
}

#[test]
fn urdf_tool_axis_not_along_z() {
    // A tool holder turned upside down: the tool frame's z points down at home.
    let text = replace_once(
        VMC3,
        "<origin xyz=\"0 0 -0.15\" rpy=\"0 0 0\"/>\n  </joint>\n</robot>",
        "<origin xyz=\"0 0 -0.15\" rpy=\"3.141592653589793 0 0\"/>\n  </joint>\n</robot>",
    );
    let (error, path) = urdf_error(&text);
    assert!(
        matches!(error.kind(), MachineErrorKind::ToolAxis { found } if found[2] < -0.99),
        "{error}"
    );
    assert_names_file(&error, &path);
}

#[test]
fn urdf_cycle_apart_from_the_rooted_tree() {
    // The root (bed) has no parent, so the roots check passes; `m` and `tool` hang from each
    // other. Loading must stop with an error, not loop.
    let text = r#"<robot name="cycle">
  <link name="bed"/><link name="m"/><link name="tool"/><link name="workpiece"/>
  <joint name="mount" type="fixed"><parent link="bed"/><child link="workpiece"/></joint>
  <joint name="a" type="fixed"><parent link="tool"/><child link="m"/></joint>
  <joint name="b" type="fixed"><parent link="m"/><child link="tool"/></joint>
</robot>"#;
    let (error, path) = urdf_error(text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::Cycle(vec!["m".into(), "tool".into()])
    );
    assert_names_file(&error, &path);
}

#[test]
fn urdf_joint_above_the_branch_split() {
    // A Y axis moving the whole machine (bed → frame) carries both tool and workpiece.
    let text = VMC3
        .replace(
            "<parent link=\"bed\"/><child link=\"saddle\"/>",
            "<parent link=\"frame\"/><child link=\"saddle\"/>",
        )
        .replace(
            "<parent link=\"bed\"/><child link=\"column\"/>",
            "<parent link=\"frame\"/><child link=\"column\"/>",
        )
        .replace(
            "<joint name=\"Y\" type=\"prismatic\">",
            "<joint name=\"lift\" type=\"fixed\">",
        );
    let text = before_robot_end(
        &text,
        r#"  <link name="frame"/>
  <joint name="Y" type="prismatic"><parent link="bed"/><child link="frame"/><axis xyz="0 1 0"/><limit lower="0" upper="0.4" velocity="1"/></joint>"#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::SharedBranch { axis: Axis::Y }
    );
    assert_at_joint(&error, &path, &text, "Y");
}

#[test]
fn scenario_grid_too_large() {
    // 4 194 304³ points would overflow; 3000³ = 2.7e10 is beyond the cap of 1e7.
    for count in ["3000", "4194304"] {
        let grid = format!(
            "model = \"chain\"\nx_mm = {{ from = 0.0, to = 700.0, count = {count} }}\n\
             y_mm = {{ from = 0.0, to = 400.0, count = {count} }}\nz_mm = {{ from = 0.0, to = 500.0, count = {count} }}"
        );
        let text = vmc3_with("model = \"chain\"", &grid);
        let (error, _) = scenario_error(&text);
        assert_eq!(error.kind(), ScenarioErrorKind::Grid, "{error}");
        assert!(error.to_string().contains("volumetric"), "{error}");
    }
}

#[test]
fn scenario_value_implausibly_large() {
    // 5e6 µrad (5 rad) of squareness is a unit slip, not a machine error.
    let text = replace_once(
        &minimal("vmc3.urdf"),
        "[errors.EXX]\nconstant_um = 1.0",
        "[errors.EC0Y]\nconstant_urad = 5.0e6",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("[errors.EC0Y]"),
        Some("errors.EC0Y"),
    );
    // A polynomial that grows beyond 10 mm over the travel: 1e300 µm/mm.
    let text = exx_with("polynomial_um = [0.0, 1e300]");
    let (error, _) = scenario_error(&text);
    assert_eq!(error.kind(), ScenarioErrorKind::Value, "{error}");
}

#[test]
fn scenario_value_period_underflows() {
    // 1e-322 mm is finite in the file but zero in metres.
    let text = exx_with("harmonic = [{ period_mm = 1e-322, amplitude_um = 1.0 }]");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("period_mm"),
        Some("errors.EXX.harmonic[0].period_mm"),
    );
}

#[test]
fn scenario_value_not_periodic_on_a_continuous_axis() {
    // C of trunnion5 turns without end: a slope in the angle would jump at 360°.
    let text = replace_once(
        &minimal("trunnion5.urdf"),
        "[errors.EXX]\nconstant_um = 1.0",
        "[errors.ECC]\npolynomial_urad = [0.0, 0.1]",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("[errors.ECC]"),
        Some("errors.ECC"),
    );
}

#[test]
fn scenario_units_second_harmonic_is_found_on_its_line() {
    // The second entry spells its period in degrees on a linear axis.
    let text = exx_with(
        "harmonic = [\n  { period_mm = 10.0, amplitude_um = 1.0 },\n  { period_deg = 5.0, amplitude_um = 1.0 },\n]",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Units,
        &text,
        Some("period_deg"),
        Some("errors.EXX.harmonic[1].period_deg"),
    );
}

/// A valid warm-up scenario on vmc3 (lines: 5 `[thermal]`, 6 sensors, 8 `[warmup]`).
fn warmup_scenario() -> String {
    format!(
        "schema = 1\n\
         machine = '{}'\n\
         seed = 1\n\
         \n\
         [thermal]\n\
         sensors = [{{ node = \"x_nut\" }}]\n\
         \n\
         [warmup]\n\
         axis = \"X\"\n\
         targets_mm = {{ from = 10.0, to = 710.0, step = 100.0 }}\n\
         runs = 2\n\
         idle = {{ from_mm = 0.0, to_mm = 750.0, feed_mm_per_min = 4800.0, minutes = 10.0 }}\n",
        model("vmc3.urdf")
    )
}

#[test]
fn warmup_scenario_is_valid_and_its_mistakes_are_named() {
    let dir = TempDir::new().unwrap();
    Scenario::load(write(&dir, "ok.toml", &warmup_scenario())).unwrap();
    // Without [thermal] a warm-up has nothing to warm.
    let text = replace_once(
        &warmup_scenario(),
        "[thermal]\nsensors = [{ node = \"x_nut\" }]\n",
        "",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("[warmup]"),
        Some("[thermal]"),
    );
    // A sensor on a node the network lacks names the nodes there are.
    let text = replace_once(&warmup_scenario(), "node = \"x_nut\"", "node = \"x_nutt\"");
    let (error, _) = scenario_error(&text);
    assert_eq!(error.kind(), ScenarioErrorKind::Value);
    assert!(
        error.to_string().contains("x_nutt") && error.to_string().contains("x_screw"),
        "{error}"
    );
    // Targets whose overrun leaves the travel (X starts at 0 mm).
    let text = replace_once(
        &warmup_scenario(),
        "from = 10.0, to = 710.0",
        "from = 0.0, to = 700.0",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("targets_mm"),
        Some("warmup.targets_mm"),
    );
}

#[test]
fn one_laser_test_per_scenario_and_a_laser_needs_one() {
    let iso = "[iso230_2]\naxis = \"X\"\ntargets_mm = { from = 10.0, to = 700.0, count = 5 }\n";
    let text = format!("{}{iso}", warmup_scenario());
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("[warmup]"),
        Some("one laser test"),
    );
    let text = format!("{}\n[laser]\nnoise_nm = 5.0\n", minimal("vmc3.urdf"));
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Nothing,
        &text,
        Some("[laser]"),
        Some("laser"),
    );
}

#[test]
fn drift_tests_refuse_laser_settings_that_would_spoil_them() {
    // ISO 230-3 §7.2.5: air compensation on, NDE off. A linear-motion test with
    // `compensation = "off"` is refused at that key's line.
    let text = format!(
        "schema = 1\nmachine = '{}'\nseed = 1\n\n[thermal]\n\n[iso230_3_linear]\naxis = \"X\"\ntargets_mm = [20.0, 740.0]\ncycling_min = 130.0\n\n[laser]\ncompensation = \"off\"\n",
        model("vmc3.urdf")
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("compensation = \"off\""),
        Some("laser.compensation"),
    );
    // With [thermal] the laser's air is the machine's: an air temperature in [laser] is refused.
    let text = text.replace(
        "compensation = \"off\"",
        "air = { temperature_degc = 25.0 }",
    );
    let (error, _) = scenario_error(&text);
    assert!(
        error.to_string().contains("laser.air.temperature_degc"),
        "{error}"
    );
}

#[test]
fn thermal_section_errors_point_at_their_key() {
    // A bad key inside [thermal] or [warmup] is reported at its own line, not the section's.
    let text = replace_once(
        &warmup_scenario(),
        "[thermal]\n",
        "[thermal]\nmax_interval_s = 0.0\n",
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("max_interval_s = 0.0"),
        Some("thermal.max_interval_s"),
    );
    let text = replace_once(&warmup_scenario(), "runs = 2", "runs = 1");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("runs = 1"),
        Some("warmup.runs"),
    );
}

// ---------------------------------------------------------------------------------------
// Scenarios that extend another (`extends`)
// ---------------------------------------------------------------------------------------

/// Loads `text` as `extension.toml` beside a copy of the shipped vmc3 volumetric scenario
/// (`base.toml`, with the machine path adjusted); returns the result and the extension's path.
fn load_extension(text: &str) -> (Result<Scenario, ScenarioError>, String) {
    let dir = TempDir::new().unwrap();
    let base = include_str!("../../../scenarios/vmc3_volumetric.toml");
    let machine = format!("{}/models/vmc3.urdf", env!("CARGO_MANIFEST_DIR"));
    let base = replace_once(base, "\"../models/vmc3.urdf\"", &format!("{machine:?}"));
    write(&dir, "base.toml", &base);
    let path = write(&dir, "extension.toml", text);
    (Scenario::load(&path), path)
}

#[test]
fn extension_replaces_the_base_errors_by_name() {
    let text = "schema = 1\nextends = \"base.toml\"\n\n[errors.EXX]\nreversal_um = 3.0\n";
    let (scenario, _) = load_extension(text);
    let scenario = scenario.expect("a valid extension");
    let exx = scenario
        .twin
        .errors
        .parameters()
        .iter()
        .find(|p| p.name.to_string() == "EXX")
        .expect("EXX");
    // Only the extension's term: the reversal moves the reading by −v/2 travelling positive.
    let up = exx.function.value(0.1, mtwin::machine::Direction::Positive);
    assert!((up + 1.5e-6).abs() < 1e-15, "{up}");
    assert!(scenario.volumetric.is_some(), "the rest is inherited");
}

#[test]
fn extension_with_a_key_it_may_not_set() {
    let text = "schema = 1\nextends = \"base.toml\"\nseed = 4\n";
    let (error, path) = load_extension(text);
    let error = error.expect_err("seed belongs to the base");
    assert_eq!(error.kind(), ScenarioErrorKind::UnknownKey);
    assert!(
        error.to_string().contains(&path) && error.to_string().contains("seed"),
        "{error}"
    );
}

#[test]
fn extension_of_a_missing_base() {
    let text = "schema = 1\nextends = \"nowhere.toml\"\n";
    let (error, path) = load_extension(text);
    let error = error.expect_err("no base");
    assert_eq!(error.kind(), ScenarioErrorKind::Io);
    assert_eq!(error.line(), Some(2));
    let message = error.to_string();
    assert!(
        message.contains(&path) && message.contains("nowhere.toml"),
        "{message}"
    );
}

#[test]
fn extension_with_a_bad_error_names_its_own_line() {
    let text = "schema = 1\nextends = \"base.toml\"\n\n[errors.EXX]\nreversal_urad = 3.0\n";
    let (error, path) = load_extension(text);
    let error = error.expect_err("wrong unit");
    assert_eq!(error.kind(), ScenarioErrorKind::Units);
    assert_eq!(error.line(), Some(line_of(text, "reversal_urad")));
    assert!(error.to_string().contains(&path), "{error}");
}

#[test]
fn extension_that_extends_itself() {
    let text = "schema = 1\nextends = \"extension.toml\"\n";
    let (error, _) = load_extension(text);
    let error = error.expect_err("a cycle");
    assert_eq!(error.kind(), ScenarioErrorKind::Value);
    assert!(error.to_string().contains("deep"), "{error}");
}

// ---------------------------------------------------------------------------------------
// Ball-bar tests ([ballbar], [servo]) and ball-bar tables
// ---------------------------------------------------------------------------------------

/// A valid ball-bar scenario on vmc3 with `from` replaced by `to`.
fn ballbar_with(from: &str, to: &str) -> String {
    let text = format!(
        "schema = 1\n\
         machine = '{}'\n\
         seed = 1\n\
         \n\
         [ballbar]\n\
         planes = [\"XY\"]\n\
         length_mm = 150.0\n\
         feed_mm_per_min = 1000.0\n\
         centre_mm = {{ x = 380.0, y = 205.0, z = 300.0 }}\n\
         overshoot_deg = 180.0\n\
         \n\
         [servo]\n\
         X = {{ kv_per_s = 33.3 }}\n",
        model("vmc3.urdf")
    );
    replace_once(&text, from, to)
}

#[test]
fn ballbar_scenario_is_valid() {
    let dir = TempDir::new().unwrap();
    let text = ballbar_with("seed = 1", "seed = 1");
    let scenario = Scenario::load(write(&dir, "ok.toml", &text)).unwrap();
    assert_eq!(scenario.ballbar_test.unwrap().circles.len(), 1);
}

#[test]
fn ballbar_length_not_a_bar_of_the_kit() {
    let text = ballbar_with("length_mm = 150.0", "length_mm = 120.0");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("length_mm"),
        Some("ballbar.length_mm"),
    );
    assert!(error.to_string().contains("50, 100, 150 or 300"), "{error}");
}

#[test]
fn ballbar_plane_named_backwards() {
    let text = ballbar_with("planes = [\"XY\"]", "planes = [\"XZ\"]");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("planes"),
        Some("ballbar.planes"),
    );
    assert!(error.to_string().contains("ZX"), "{error}");
}

#[test]
fn ballbar_circle_beyond_the_travel() {
    // X from 50 − 150 mm: below the travel's 0.
    let text = ballbar_with("x = 380.0", "x = 50.0");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("centre_mm"),
        Some("ballbar.centre_mm"),
    );
    assert!(error.to_string().contains("outside its travel"), "{error}");
}

#[test]
fn ballbar_ramp_longer_than_the_overshoot() {
    let text = ballbar_with("overshoot_deg = 180.0", "overshoot_deg = 0.0");
    let (error, path) = scenario_error(&text);
    assert_eq!(error.kind(), ScenarioErrorKind::Value);
    assert!(error.to_string().starts_with(&path), "{error}");
    assert!(error.to_string().contains("overshoot arc"), "{error}");
}

#[test]
fn ballbar_unknown_key() {
    let text = ballbar_with("feed_mm_per_min", "feed_mm_min");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::UnknownKey,
        &text,
        Some("feed_mm_min"),
        Some("feed_mm_min"),
    );
}

#[test]
fn servo_gain_not_positive() {
    let text = ballbar_with("kv_per_s = 33.3", "kv_per_s = -5.0");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("kv_per_s"),
        Some("servo.X"),
    );
}

#[test]
fn servo_without_a_ballbar_test() {
    let text = format!(
        "{}\n[servo]\nX = {{ kv_per_s = 30.0 }}\n",
        minimal("vmc3.urdf")
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Nothing,
        &text,
        Some("[servo]"),
        Some("servo"),
    );
}

fn ballbar_table_error(text: &str) -> String {
    let error = mtwin::kinds::ballbar::BallbarTable::parse(text.as_bytes(), "bb.csv")
        .expect_err("the table must be rejected");
    error.to_string()
}

#[test]
fn ballbar_table_bad_values_name_the_line_and_column() {
    let header = "direction,angle_deg,deviation_um\n";
    for (row, column) in [
        ("up,10,1.0", "direction"),
        ("ccw,360,1.0", "angle_deg"),
        ("ccw,-1,1.0", "angle_deg"),
        ("ccw,10,NaN", "deviation_um"),
        ("cw,ten,1.0", "angle_deg"),
    ] {
        let message = ballbar_table_error(&format!("{header}ccw,0,0.5\n{row}\n"));
        assert!(
            message.starts_with("bb.csv:3: ") && message.contains(column),
            "{row}: {message}"
        );
    }
}

#[test]
fn ballbar_table_missing_or_unknown_columns() {
    let message = ballbar_table_error("direction,angle_deg\nccw,0\n");
    assert!(
        message.starts_with("bb.csv:1: ") && message.contains("deviation_um"),
        "{message}"
    );
    // A column the reader does not read is read past and listed; one like a column it reads,
    // in another unit, is refused by name.
    let table = mtwin::kinds::ballbar::BallbarTable::parse(
        b"direction,angle_deg,deviation_um,radius_mm\nccw,0,1,150\n",
        "bb.csv",
    )
    .unwrap();
    assert_eq!(table.columns_not_read, ["radius_mm"]);
    assert_eq!(table.readings.len(), 1);
    let message = ballbar_table_error("direction,angle_deg,deviation_nm\nccw,0,1000\n");
    assert!(
        message.starts_with(
            "bb.csv:1: column `deviation_nm` is in nm, but this reader reads it as `deviation_um`"
        ),
        "{message}"
    );
    let message = ballbar_table_error("direction,angle_deg,deviation_um\n");
    assert!(message.contains("no readings"), "{message}");
}
