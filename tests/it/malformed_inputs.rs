//! Malformed machine models and scenarios: one test per [`MachineErrorKind`] and
//! [`ScenarioErrorKind`] variant (and per distinct way of reaching it). Each test starts from
//! a valid input (the real `models/vmc3.urdf` text, or a minimal scenario written here), breaks
//! exactly one thing, loads it from a temporary file, and checks the error kind and that the
//! message names the file and, where the error belongs to one place, the line of the broken
//! element (found in the input text by the test itself) and the joint name or the dotted key.

use mtwin::app::Scenario;
use mtwin::machine::{Axis, Machine, MachineError, MachineErrorKind};
use mtwin::scenario::{ScenarioError, ScenarioErrorKind};
use std::path::Path;
use tempfile::TempDir;

mod ranges;

mod plausible;

mod glitches;

mod columns;

const VMC3: &str = include_str!("../../models/vmc3.urdf");

/// `text` with the single occurrence of `from` replaced by `to`.
fn replace_once(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "{from:?} must occur once");
    text.replacen(from, to, 1)
}

/// `text` with `insertion` put just before `</robot>`.
fn before_robot_end(text: &str, insertion: &str) -> String {
    replace_once(text, "</robot>", &format!("{insertion}\n</robot>"))
}

/// The 1-based number of the only line of `text` that contains `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    let lines: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, line)| line.contains(needle))
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(lines.len(), 1, "{needle:?} must be on exactly one line");
    lines[0]
}

fn write(dir: &TempDir, name: &str, text: &str) -> String {
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

// ---------------------------------------------------------------------------------------
// Machine models
// ---------------------------------------------------------------------------------------

/// Loads `text` from a temporary `broken.urdf`; returns the error and the file's path.
fn urdf_error(text: &str) -> (MachineError, String) {
    let dir = TempDir::new().unwrap();
    let path = write(&dir, "broken.urdf", text);
    let error = Machine::from_urdf_file(&path).expect_err("the model must be rejected");
    (error, path)
}

/// A joint-level error: the message is `FILE:LINE: …"JOINT"…`, LINE that of `<joint name="JOINT"`.
fn assert_at_joint(error: &MachineError, path: &str, text: &str, joint: &str) {
    let message = error.to_string();
    let line = line_of(text, &format!("<joint name=\"{joint}\""));
    let mut problems = Vec::new();
    if !message.starts_with(&format!("{path}:{line}: ")) {
        problems.push(format!("should start with {path}:{line}:"));
    }
    if !message.contains(&format!("\"{joint}\"")) {
        problems.push(format!("should name joint \"{joint}\""));
    }
    assert!(problems.is_empty(), "{message:?}: {}", problems.join("; "));
}

/// A model-level error: the message starts with the file name.
fn assert_names_file(error: &MachineError, path: &str) {
    let message = error.to_string();
    assert!(
        message.starts_with(path),
        "{message:?} should start with {path}"
    );
}

#[test]
fn vmc3_urdf_text_is_valid() {
    let dir = TempDir::new().unwrap();
    let path = write(&dir, "vmc3.urdf", VMC3);
    let machine = Machine::from_urdf_file(&path).unwrap();
    assert_eq!(machine.name(), "vmc3");
}

#[test]
fn urdf_io_missing_file() {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join("absent.urdf").display().to_string();
    let error = Machine::from_urdf_file(&path).unwrap_err();
    assert!(matches!(error.kind(), MachineErrorKind::Io(_)));
    assert_names_file(&error, &path);
}

#[test]
fn urdf_xml_not_well_formed() {
    let (error, path) = urdf_error(&replace_once(VMC3, "</robot>", ""));
    assert!(matches!(error.kind(), MachineErrorKind::Xml(_)));
    assert_names_file(&error, &path);
}

#[test]
fn urdf_missing_tool_link() {
    let (error, path) = urdf_error(&VMC3.replace("\"tool\"", "\"tip\""));
    assert_eq!(error.kind(), &MachineErrorKind::MissingEndLink("tool"));
    assert_names_file(&error, &path);
    assert!(error.to_string().contains("\"tool\""));
}

#[test]
fn urdf_missing_workpiece_link() {
    let (error, path) = urdf_error(&VMC3.replace("\"workpiece\"", "\"part\""));
    assert_eq!(error.kind(), &MachineErrorKind::MissingEndLink("workpiece"));
    assert_names_file(&error, &path);
    assert!(error.to_string().contains("\"workpiece\""));
}

#[test]
fn urdf_unknown_link() {
    let text = replace_once(VMC3, "<child link=\"table\"/>", "<child link=\"tabel\"/>");
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::UnknownLink {
            joint: "X".into(),
            link: "tabel".into()
        }
    );
    assert_at_joint(&error, &path, &text, "X");
    assert!(error.to_string().contains("\"tabel\""));
}

#[test]
fn urdf_closed_loop() {
    let text = before_robot_end(
        VMC3,
        r#"  <joint name="brace" type="fixed"><parent link="column"/><child link="table"/></joint>"#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::ClosedLoop {
            link: "table".into(),
            joints: ["X".into(), "brace".into()],
        }
    );
    assert_at_joint(&error, &path, &text, "brace");
    assert!(error.to_string().contains("\"X\""), "{error}");
}

#[test]
fn urdf_two_roots() {
    let text = before_robot_end(VMC3, r#"  <link name="stray"/>"#);
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::Roots(vec!["bed".into(), "stray".into()])
    );
    assert_names_file(&error, &path);
    assert!(error.to_string().contains("\"stray\""));
}

#[test]
fn urdf_cycle_has_no_root() {
    let text = before_robot_end(
        VMC3,
        r#"  <joint name="loop" type="fixed"><parent link="tool"/><child link="bed"/></joint>"#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(error.kind(), &MachineErrorKind::Roots(vec![]));
    assert_names_file(&error, &path);
}

#[test]
fn urdf_floating_joint() {
    let text = replace_once(
        VMC3,
        r#"<joint name="column_mount" type="fixed">"#,
        r#"<joint name="column_mount" type="floating">"#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::UnsupportedJoint {
            joint: "column_mount".into(),
            joint_type: "floating".into()
        }
    );
    assert_at_joint(&error, &path, &text, "column_mount");
}

#[test]
fn urdf_mimic_joint() {
    let text = replace_once(
        VMC3,
        r#"<axis xyz="0 -1 0"/>"#,
        r#"<axis xyz="0 -1 0"/><mimic joint="X"/>"#,
    );
    let (error, path) = urdf_error(&text);
    assert!(matches!(
        error.kind(),
        MachineErrorKind::UnsupportedJoint { joint, .. } if joint == "Y"
    ));
    assert_at_joint(&error, &path, &text, "Y");
    assert!(error.to_string().contains("mimic"));
}

#[test]
fn urdf_moving_joint_not_named_after_an_axis() {
    let text = replace_once(VMC3, r#"<joint name="Z""#, r#"<joint name="Zed""#);
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::AxisName {
            joint: "Zed".into()
        }
    );
    assert_at_joint(&error, &path, &text, "Zed");
}

#[test]
fn urdf_duplicate_axis_points_at_the_second_joint() {
    // The Z joint renamed X: the second joint named X (the old Z, later in the file) is the
    // duplicate, so the message should point at its line, not at the first X.
    let second_x_line = line_of(VMC3, r#"<joint name="Z""#);
    let text = replace_once(VMC3, r#"<joint name="Z""#, r#"<joint name="X""#);
    let (error, path) = urdf_error(&text);
    assert_eq!(error.kind(), &MachineErrorKind::DuplicateAxis(Axis::X));
    let message = error.to_string();
    assert!(
        message.starts_with(&format!("{path}:{second_x_line}: ")),
        "{message:?} should point at line {second_x_line}"
    );
    assert!(message.contains("\"X\""));
}

#[test]
fn urdf_axis_type_revolute_z() {
    let text = replace_once(
        VMC3,
        r#"<joint name="Z" type="prismatic">"#,
        r#"<joint name="Z" type="revolute">"#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::AxisType {
            axis: Axis::Z,
            joint_type: "revolute".into()
        }
    );
    assert_at_joint(&error, &path, &text, "Z");
}

#[test]
fn urdf_axis_direction_wrong_coordinate() {
    // Z is on the tool branch and must point along +z; it points along +y.
    let z_origin = r#"<origin xyz="0 0 1.40" rpy="0 0 0"/>"#;
    let text = replace_once(
        VMC3,
        &format!("{z_origin}\n    <axis xyz=\"0 0 1\"/>"),
        &format!("{z_origin}\n    <axis xyz=\"0 1 0\"/>"),
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::AxisDirection {
            axis: Axis::Z,
            found: [0.0, 1.0, 0.0],
            expected: [0.0, 0.0, 1.0]
        }
    );
    assert_at_joint(&error, &path, &text, "Z");
}

#[test]
fn urdf_axis_direction_workpiece_joint_points_plus() {
    // X moves the table (workpiece branch): ISO 841 needs -x there, the file says +x.
    let text = replace_once(VMC3, r#"<axis xyz="-1 0 0"/>"#, r#"<axis xyz="1 0 0"/>"#);
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::AxisDirection {
            axis: Axis::X,
            found: [1.0, 0.0, 0.0],
            expected: [-1.0, 0.0, 0.0]
        }
    );
    assert_at_joint(&error, &path, &text, "X");
}

#[test]
fn urdf_limits_lower_above_upper() {
    let text = replace_once(
        VMC3,
        r#"lower="0" upper="0.76""#,
        r#"lower="0.76" upper="0""#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(error.kind(), &MachineErrorKind::Limits { axis: Axis::X });
    assert_at_joint(&error, &path, &text, "X");
}

#[test]
fn urdf_joint_off_both_branches() {
    // A C axis turning a tool carousel hung on the bed moves neither tool nor workpiece.
    let text = before_robot_end(
        VMC3,
        r#"  <link name="carousel"/>
  <joint name="C" type="continuous">
    <parent link="bed"/><child link="carousel"/>
    <axis xyz="0 0 1"/>
  </joint>"#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(error.kind(), &MachineErrorKind::OffBranch { axis: Axis::C });
    assert_at_joint(&error, &path, &text, "C");
}

#[test]
fn urdf_spindle_on_workpiece_branch() {
    let text = replace_once(
        VMC3,
        r#"<joint name="S" type="continuous">"#,
        r#"<joint name="spindle_lock" type="fixed">"#,
    );
    let text = replace_once(
        &text,
        r#"<joint name="table_surface" type="fixed">"#,
        r#"<joint name="S" type="continuous">"#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(error.kind(), &MachineErrorKind::SpindleSide);
    assert_at_joint(&error, &path, &text, "S");
}

#[test]
fn urdf_non_finite_origin() {
    let text = replace_once(
        VMC3,
        r#"<origin xyz="0 0 0.15" rpy="0 0 0"/>"#,
        r#"<origin xyz="0 0 inf" rpy="0 0 0"/>"#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::NotFinite { joint: "X".into() }
    );
    assert_at_joint(&error, &path, &text, "X");
}

#[test]
fn urdf_error_line_is_the_joint_not_a_link_of_the_same_name() {
    // URDF joints and links have separate names; a fixed joint named after its child link is
    // common. The error must point at the `<joint>`, not at the `<link>` of that name.
    let text = replace_once(
        VMC3,
        r#"<joint name="tool_holder" type="fixed">"#,
        r#"<joint name="tool" type="fixed">"#,
    );
    let text = replace_once(
        &text,
        r#"<origin xyz="0 0 -0.15" rpy="0 0 0"/>"#,
        r#"<origin xyz="0 0 -inf" rpy="0 0 0"/>"#,
    );
    let (error, path) = urdf_error(&text);
    assert_eq!(
        error.kind(),
        &MachineErrorKind::NotFinite {
            joint: "tool".into()
        }
    );
    assert_at_joint(&error, &path, &text, "tool");
}

#[test]
fn urdf_configuration_without_z() {
    let text = replace_once(
        VMC3,
        r#"<joint name="Z" type="prismatic">"#,
        r#"<joint name="Z" type="fixed">"#,
    );
    let (error, path) = urdf_error(&text);
    assert!(
        matches!(error.kind(), MachineErrorKind::Configuration(m) if m.contains('Z')),
        "{error}"
    );
    assert_names_file(&error, &path);
}

#[test]
fn urdf_configuration_one_rotary_axis() {
    // The fixed table-to-workpiece joint becomes a C rotary table (pointing -z, as the
    // workpiece branch requires): one rotary axis is neither a 3- nor a 5-axis machine.
    let text = replace_once(
        VMC3,
        r#"<joint name="table_surface" type="fixed">"#,
        r#"<joint name="C" type="continuous"><axis xyz="0 0 -1"/>"#,
    );
    let (error, path) = urdf_error(&text);
    assert!(
        matches!(error.kind(), MachineErrorKind::Configuration(m) if m.contains("rotary")),
        "{error}"
    );
    assert_names_file(&error, &path);
}

// ---------------------------------------------------------------------------------------
// Scenarios
// ---------------------------------------------------------------------------------------

fn model(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("models")
        .join(name)
        .display()
        .to_string()
}

/// A valid scenario on `machine` (a file in models/): line 5 `[errors.EXX]`, line 6 its
/// term, line 8 `[volumetric]`, line 9 its model.
fn minimal(machine: &str) -> String {
    format!(
        "schema = 1\n\
         machine = '{}'\n\
         seed = 1\n\
         \n\
         [errors.EXX]\n\
         constant_um = 1.0\n\
         \n\
         [volumetric]\n\
         model = \"chain\"\n",
        model(machine)
    )
}

/// Loads `text` from a temporary `broken.toml`; returns the error and the file's path.
fn scenario_error(text: &str) -> (ScenarioError, String) {
    let dir = TempDir::new().unwrap();
    let path = write(&dir, "broken.toml", text);
    let error = Scenario::load(&path).expect_err("the scenario must be rejected");
    (error, path)
}

/// The error is `kind`, at the line of `text` holding `broken` (no line if `None`), and its
/// message is `FILE[:LINE]: …KEY…` (KEY not checked if `None`). Every mismatch is reported.
fn assert_scenario(
    error: &ScenarioError,
    path: &str,
    kind: ScenarioErrorKind,
    text: &str,
    broken: Option<&str>,
    key: Option<&str>,
) {
    let message = error.to_string();
    let line = broken.map(|needle| line_of(text, needle));
    let mut problems = Vec::new();
    if error.kind() != kind {
        problems.push(format!("kind is {:?}, expected {kind:?}", error.kind()));
    }
    if error.line() != line {
        problems.push(format!("line() is {:?}, expected {line:?}", error.line()));
    }
    let prefix = match line {
        Some(line) => format!("{path}:{line}: "),
        None => format!("{path}: "),
    };
    if !message.starts_with(&prefix) {
        problems.push(format!("should start with {prefix:?}"));
    }
    if let Some(key) = key.filter(|key| !message.contains(key)) {
        problems.push(format!("should name the key {key}"));
    }
    assert!(problems.is_empty(), "{message:?}: {}", problems.join("; "));
}

/// `minimal("vmc3.urdf")` with one line replaced.
fn vmc3_with(from: &str, to: &str) -> String {
    replace_once(&minimal("vmc3.urdf"), from, to)
}

/// `minimal("vmc3.urdf")` with `[errors.EXX]`'s term replaced by `term`.
fn exx_with(term: &str) -> String {
    vmc3_with("constant_um = 1.0", term)
}

#[test]
fn minimal_scenario_is_valid() {
    let text = minimal("vmc3.urdf");
    assert_eq!(line_of(&text, "[errors.EXX]"), 5);
    assert_eq!(line_of(&text, "[volumetric]"), 8);
    let dir = TempDir::new().unwrap();
    let scenario = Scenario::load(write(&dir, "ok.toml", &text)).unwrap();
    assert_eq!(scenario.twin.machine.name(), "vmc3");
}

#[test]
fn scenario_io_missing_file() {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join("absent.toml").display().to_string();
    let error = Scenario::load(&path).unwrap_err();
    assert_eq!(error.kind(), ScenarioErrorKind::Io);
    assert_eq!(error.line(), None);
    assert!(error.to_string().starts_with(&format!("{path}: ")));
}

#[test]
fn scenario_syntax_wrong_type() {
    let text = vmc3_with("seed = 1", "seed = \"one\"");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Syntax,
        &text,
        Some("seed ="),
        Some("seed"),
    );
}

#[test]
fn scenario_syntax_unclosed_table_header() {
    let text = vmc3_with("[volumetric]", "[volumetric");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Syntax,
        &text,
        Some("[volumetric"),
        None,
    );
}

#[test]
fn scenario_unknown_key_top_level() {
    let text = vmc3_with("seed = 1", "seed = 1\ncolour = \"red\"");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::UnknownKey,
        &text,
        Some("colour"),
        Some("colour"),
    );
}

#[test]
fn scenario_unknown_key_in_error_parameter() {
    let text = exx_with("constant_nm = 1.0");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::UnknownKey,
        &text,
        Some("constant_nm"),
        Some("errors.EXX.constant_nm"),
    );
}

#[test]
fn scenario_unknown_key_in_volumetric() {
    let text = vmc3_with("model = \"chain\"", "model = \"chain\"\nstep_mm = 10.0");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::UnknownKey,
        &text,
        Some("step_mm"),
        Some("volumetric.step_mm"),
    );
}

#[test]
fn scenario_schema_missing() {
    let text = vmc3_with("schema = 1\n", "");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Schema,
        &text,
        None,
        Some("schema"),
    );
}

#[test]
fn scenario_schema_2() {
    let text = vmc3_with("schema = 1", "schema = 2");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Schema,
        &text,
        Some("schema = 2"),
        Some("schema"),
    );
}

#[test]
fn scenario_machine_file_missing() {
    let text = vmc3_with(&model("vmc3.urdf"), "absent.urdf");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Machine,
        &text,
        Some("machine ="),
        Some("machine"),
    );
    assert!(error.to_string().contains("absent.urdf"));
}

#[test]
fn scenario_machine_urdf_broken() {
    // The machine, next to the scenario and named relative to it, has X pointing + on the
    // workpiece branch.
    let dir = TempDir::new().unwrap();
    let urdf = replace_once(VMC3, r#"<axis xyz="-1 0 0"/>"#, r#"<axis xyz="1 0 0"/>"#);
    let urdf_path = write(&dir, "bent.urdf", &urdf);
    let text = vmc3_with(&model("vmc3.urdf"), "bent.urdf");
    let path = write(&dir, "broken.toml", &text);
    let error = Scenario::load(&path).unwrap_err();
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Machine,
        &text,
        Some("machine ="),
        Some("machine"),
    );
    let x_line = line_of(&urdf, r#"<joint name="X""#);
    assert!(
        error
            .to_string()
            .contains(&format!("{urdf_path}:{x_line}:")),
        "{error}"
    );
}

#[test]
fn scenario_parameter_not_a_name() {
    let text = vmc3_with("[errors.EXX]", "[errors.EQX]");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Parameter,
        &text,
        Some("[errors.EQX]"),
        Some("errors.EQX"),
    );
}

#[test]
fn scenario_parameter_axis_machine_lacks() {
    let text = vmc3_with("[errors.EXX]", "[errors.EXA]");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Parameter,
        &text,
        Some("[errors.EXA]"),
        Some("errors.EXA"),
    );
}

#[test]
fn scenario_parameter_bad_location_name() {
    let text = vmc3_with("[errors.EXX]", "[errors.EX0X]");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Parameter,
        &text,
        Some("[errors.EX0X]"),
        Some("errors.EX0X"),
    );
}

#[test]
fn scenario_units_constant_urad_on_translation() {
    let text = exx_with("constant_urad = 1.0");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Units,
        &text,
        Some("constant_urad"),
        Some("errors.EXX.constant_urad"),
    );
}

#[test]
fn scenario_units_positions_deg_on_linear_axis() {
    let text = exx_with("table = { positions_deg = [0.0, 10.0], values_um = [0.0, 1.0] }");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Units,
        &text,
        Some("positions_deg"),
        Some("errors.EXX.table.positions_deg"),
    );
}

#[test]
fn scenario_units_period_deg_on_linear_axis() {
    let text = exx_with("harmonic = [{ period_deg = 10.0, amplitude_um = 0.4 }]");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Units,
        &text,
        Some("period_deg"),
        Some("errors.EXX.harmonic[0].period_deg"),
    );
}

#[test]
fn scenario_value_nan() {
    let text = exx_with("constant_um = nan");
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("constant_um = nan"),
        Some("errors.EXX.constant_um"),
    );
}

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
    let base = include_str!("../../scenarios/vmc3_volumetric.toml");
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

#[test]
fn urdf_visual_with_a_negative_size_names_its_link() {
    let text = replace_once(
        VMC3,
        r#"<box size="1.0 0.5 0.1"/>"#,
        r#"<box size="1.0 -0.5 0.1"/>"#,
    );
    let (error, path) = urdf_error(&text);
    assert!(
        matches!(error.kind(), MachineErrorKind::Geometry { link, .. } if link == "table"),
        "{:?}",
        error.kind()
    );
    let line = line_of(&text, r#"<link name="table">"#);
    let message = error.to_string();
    assert!(
        message.starts_with(&format!("{path}:{line}: ")) && message.contains("positive"),
        "{message}"
    );
}

#[test]
fn scenario_lesson_magnification_must_be_positive() {
    let text = format!(
        "{}\n[lesson]\ntitle = \"t\"\ntext = \"look\"\nmagnification = -5.0\n",
        minimal("vmc3.urdf")
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("magnification = -5.0"),
        Some("lesson.magnification"),
    );
}

#[test]
fn scenario_lesson_text_must_not_be_empty() {
    let text = format!(
        "{}\n[lesson]\ntitle = \"t\"\ntext = \"  \"\n",
        minimal("vmc3.urdf")
    );
    let (error, path) = scenario_error(&text);
    assert_scenario(
        &error,
        &path,
        ScenarioErrorKind::Value,
        &text,
        Some("text = "),
        Some("lesson.text"),
    );
}
