//! Messages as precise as the best ones: each names the place and what was expected.

use mtwin::app::Scenario;
use mtwin::machine::Machine;

fn vmc3_urdf() -> String {
    std::fs::read_to_string(format!("{}/models/vmc3.urdf", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

#[test]
fn a_urdf_with_a_joint_deleted_names_the_link_left_without_one() {
    let text = vmc3_urdf();
    let start = text.find("<joint name=\"Y\"").unwrap();
    let end = start + text[start..].find("</joint>").unwrap() + "</joint>".len();
    let broken = format!("{}{}", &text[..start], &text[end..]);
    let error = Machine::from_urdf_str(&broken, "noY.urdf")
        .unwrap_err()
        .to_string();
    // Y carries the saddle on the bed (models/vmc3.urdf).
    assert!(
        error.contains("link \"saddle\" has no parent joint"),
        "{error}"
    );
    assert!(error.contains("(the bed, \"bed\" here)"), "{error}");
}

#[test]
fn a_truncated_urdf_gives_the_xml_line_and_column() {
    let text = "<robot name=\"x\">\n  <link name=\"a\"/>\n  <link name=\"b\"\n";
    let error = Machine::from_urdf_str(text, "cut.urdf")
        .unwrap_err()
        .to_string();
    // The third line's tag is never closed: it starts at column 3.
    assert!(error.starts_with("cut.urdf:3: "), "{error}");
    assert!(error.contains("column 3"), "{error}");
    let unclosed = "<robot name=\"x\">\n  <link name=\"a\">\n";
    let error = Machine::from_urdf_str(unclosed, "open.urdf")
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("the document ends inside <link> (opened on line 2)"),
        "{error}"
    );
    let mismatched = "<robot name=\"x\">\n  <link name=\"a\">\n  </lnk>\n</robot>\n";
    let error = Machine::from_urdf_str(mismatched, "m.urdf")
        .unwrap_err()
        .to_string();
    assert!(error.starts_with("m.urdf:3: "), "{error}");
    assert!(error.contains("`</link>`"), "{error}");
}

#[test]
fn warmup_idle_names_the_field_and_the_value() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = std::fs::read_to_string(format!(
        "{}/scenarios/vmc3_warmup_laser.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replace(
        "machine = \"../models/",
        &format!("machine = \"{}/models/", env!("CARGO_MANIFEST_DIR")),
    );
    for (from, to, expected) in [
        (
            "to_mm = 750.0, feed",
            "to_mm = 950.0, feed",
            "warmup.idle.to_mm: 950; expected a position within the travel of X (0 .. 760 mm)",
        ),
        (
            "minutes = 45.0",
            "minutes = -45.0",
            "warmup.idle.minutes: -45; expected 0 to 14400 minutes",
        ),
        (
            "feed_mm_per_min = 4800.0",
            "feed_mm_per_min = 0.0",
            "warmup.idle.feed_mm_per_min: 0; expected 0.1 … 200000 mm/min",
        ),
    ] {
        assert!(scenario.contains(from), "{from}");
        let path = dir.path().join("warmup.toml");
        std::fs::write(&path, scenario.replace(from, to)).unwrap();
        let error = Scenario::load(&path).unwrap_err().to_string();
        assert!(error.contains(expected), "{error}");
    }
}
