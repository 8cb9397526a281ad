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

mod scenario_values;
mod visuals_and_lessons;
