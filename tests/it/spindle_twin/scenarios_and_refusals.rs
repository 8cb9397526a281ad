//! The bundled spindle scenarios and refused values.

use super::*;

#[test]
fn the_bundled_scenarios_run_with_their_programmes() {
    // Samples: set-ups × speeds × revolutions × samples per revolution.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    for (file, samples, probes) in [
        ("vmc3_spindle.toml", 3 * 20 * 1024, 5),
        ("trunnion5_c_axis.toml", 2 * 20 * 720, 5),
        ("vmc3_spindle_reversal.toml", 2 * 20 * 1024, 3),
        ("vmc3_spindle_multiprobe.toml", 20 * 1024, 4),
    ] {
        let scenario = Scenario::load(dir.join(file)).unwrap();
        let t = simulate(&scenario).unwrap().spindle.unwrap();
        assert_eq!(t.record.len(), samples, "{file}");
        assert_eq!(t.record.probes.len(), probes, "{file}");
        assert!(!run::summary(&t).is_empty());
    }
}

/// The error of a scenario whose `[spindle]` section is `spindle`.
fn error_of(machine: &str, spindle: &str) -> String {
    load(&text(machine, "", spindle)).unwrap_err()
}

#[test]
fn bad_values_are_refused_naming_the_key_and_line() {
    // Line numbers: the header takes 4 lines, then [spindle] on line 5 and the three exact
    // probe keys on lines 6-8; the section's own keys start on line 9.
    let cases: &[(&str, &str, &str, usize)] = &[
        (
            "vmc3",
            "axis = \"X\"",
            "spindle.axis: expected an axis of rotation",
            9,
        ),
        (
            "vmc3",
            "axis = \"C\"",
            "spindle.axis: machine \"vmc3\" has no axis C",
            9,
        ),
        ("vmc3", "sensing = \"both\"", "spindle.sensing", 9),
        (
            "trunnion5",
            "axis = \"A\"",
            "spindle.axis: A has a limited travel",
            9,
        ),
        (
            "vmc3",
            "speeds_rpm = [1000.0, 0.0]",
            "spindle.speeds_rpm: 0",
            9,
        ),
        ("vmc3", "revolutions = 0", "spindle.revolutions", 9),
        (
            "vmc3",
            "samples_per_revolution = 4",
            "spindle.samples_per_revolution",
            9,
        ),
        (
            "vmc3",
            "setups = [\"normal\", \"sideways\"]",
            "spindle.setups: \"sideways\"",
            9,
        ),
        (
            "vmc3",
            "setups = [\"normal\", \"normal\"]",
            "given twice",
            9,
        ),
        (
            "vmc3",
            "s_deg = 10.0",
            "spindle.s_deg: S is the axis under test",
            9,
        ),
        (
            "vmc3",
            "x_mm = 900.0",
            "spindle.x_mm: 900 is outside the travel",
            9,
        ),
        (
            "vmc3",
            "a_deg = 10.0",
            "spindle.a_deg: machine \"vmc3\" has no axis A",
            9,
        ),
        (
            "vmc3",
            "revolutions = 100000\nsamples_per_revolution = 1024",
            "spindle.revolutions: the test takes",
            9,
        ),
        ("vmc3", "settle_s = -1.0", "spindle.settle_s", 9),
        (
            "vmc3",
            "\n[spindle.artefact]\nkind = \"cube\"",
            "spindle.artefact.kind",
            11,
        ),
        (
            "vmc3",
            "\n[spindle.artefact]\nkind = \"sphere\"\nlength_mm = 30.0",
            "spindle.artefact.length_mm: only a cylinder",
            12,
        ),
        (
            "vmc3",
            "\n[spindle.artefact]\nform = [{ per_revolution = 1, amplitude_nm = 5.0 }]",
            "spindle.artefact.form[0].per_revolution: 1: 1 undulation per revolution is the artefact's eccentricity",
            11,
        ),
        (
            "vmc3",
            "\n[spindle.artefact]\nkind = \"two_spheres\"\ndiameter_mm = 25.0\nseparation_mm = 20.0",
            "spindle.artefact.separation_mm: the spheres",
            13,
        ),
        (
            "vmc3",
            "\n[spindle.artefact]\nkind = \"sphere\"\n[[spindle.probe]]\nname = \"x\"\nkind = \"radial\"\nheight_mm = 10.0",
            "spindle.probe[0].height_mm: 10 mm: a radial probe on a sphere",
            15,
        ),
        (
            "vmc3",
            "\n[spindle.artefact]\nkind = \"sphere\"\n[[spindle.probe]]\nname = \"f\"\nkind = \"face\"\nradius_mm = 5.0",
            "spindle.probe[0].kind: a face probe needs a flat end face",
            14,
        ),
        (
            "vmc3",
            "[[spindle.probe]]\nname = \"f\"\nkind = \"face\"\nradius_mm = 20.0",
            "spindle.probe[0].radius_mm: 20 mm is off the end face",
            12,
        ),
        (
            "vmc3",
            "[[spindle.probe]]\nname = \"X1\"\nkind = \"radial\"",
            "spindle.probe[0].name: \"X1\"",
            10,
        ),
        (
            "vmc3",
            "[[spindle.probe]]\nname = \"x\"\nkind = \"radial\"\n[[spindle.probe]]\nname = \"x\"\nkind = \"axial\"",
            "spindle.probe[1].name: \"x\" is given twice",
            13,
        ),
        (
            "vmc3",
            "[[spindle.probe]]\nname = \"z\"\nkind = \"axial\"\nazimuth_deg = 30.0",
            "spindle.probe[0].azimuth_deg: an axial probe has no azimuth_deg",
            12,
        ),
        (
            "vmc3",
            "[[spindle.probe]]\nname = \"x\"\nkind = \"radial\"\nbandwidth_hz = -3.0",
            "spindle.probe[0].bandwidth_hz",
            11, // the section's own bandwidth_hz = inf is left out: one line less
        ),
        (
            "vmc3",
            "[[spindle.probe]]\nname = \"x\"\nkind = \"radial\"\ngain_error = 2.0",
            "spindle.probe[0].gain_error",
            12,
        ),
    ];
    for &(machine, spindle, expected, line) in cases {
        let message = error_of(machine, spindle);
        assert!(
            message.contains(expected),
            "{spindle:?}: {message} (expected {expected:?})"
        );
        assert!(
            message.contains(&format!("s.toml:{line}:")),
            "{spindle:?}: {message} (expected line {line})"
        );
    }
    // An unknown key is a TOML error naming it.
    let message = error_of("vmc3", "speed_rpm = [100.0]");
    assert!(message.contains("speed_rpm"), "{message}");
}
