//! Malformed visuals and lesson sections.

use super::*;

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
