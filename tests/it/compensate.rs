//! The identified machine written out: the corrected URDF and the LinuxCNC tables.
//!
//! The corrected URDF is checked against the exact chain of the error model by an independent
//! forward kinematics of the URDF text written here (URDF semantics: origin `xyz rpy`, then
//! translation along or rotation about the normalised `<axis>`), over a grid of axis positions
//! with large rotary angles: the nominal pose of the corrected URDF must equal the actual pose of
//! the identified machine to 1 nm and 1 nrad. Where mtwin's own reader accepts the corrected
//! URDF, the machine it loads must do the same. The LinuxCNC tables are checked against hand
//! values of a polynomial positioning error with reversal.

use crate::common::*;
use mtwin::errors::{ErrorFunction, ErrorModel, ErrorParameter, ParameterName};
use mtwin::estimate::compensate::{
    CompensateError, LINUXCNC_MAX_ENTRIES, corrected_urdf, linuxcnc_tables,
};
use mtwin::machine::{Axis, AxisValues, Machine, MachineState, Workspace};
use mtwin::math::{M_PER_UM, Pose, RAD_PER_DEG, RAD_PER_URAD, Real, Vector};

/// The exactness required of the corrected URDF: position (m) and orientation (rad).
const NM: Real = 1e-9;
const NRAD: Real = 1e-9;

fn urdf_text(name: &str) -> String {
    std::fs::read_to_string(format!("{}/models/{name}.urdf", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// An error model of constant errors given in file units (µm, µrad).
fn constants(machine: &Machine, errors: &[(&str, Real)]) -> ErrorModel {
    let parameters = errors
        .iter()
        .map(|&(name, value)| {
            let name: ParameterName = name.parse().unwrap();
            let unit = if name.file_unit() == "um" {
                M_PER_UM
            } else {
                RAD_PER_URAD
            };
            ErrorParameter {
                name,
                function: ErrorFunction::Constant(value * unit),
            }
        })
        .collect();
    ErrorModel::new(machine, parameters).unwrap()
}

/// Every constant location, squareness and tool error each machine has, 5–90 µm and µrad,
/// mixed signs.
fn all_constant_errors(name: &str) -> Vec<(&'static str, Real)> {
    let mut errors = vec![
        ("EC0Y", 35.0),
        ("EB0Z", -60.0),
        ("EA0Z", 20.0),
        ("EXT", 12.0),
        ("EYT", -8.0),
        ("EZT", 25.0),
    ];
    match name {
        "trunnion5" => errors.extend([
            ("EY0A", 18.0),
            ("EZ0A", -27.0),
            ("EB0A", 45.0),
            ("EC0A", -80.0),
            ("EA0A", 30.0),
            ("EX0C", -12.0),
            ("EY0C", 40.0),
            ("EA0C", 55.0),
            ("EB0C", -25.0),
            ("EC0C", 70.0),
        ]),
        "headtable5" => errors.extend([
            ("EX0B", 22.0),
            ("EZ0B", -15.0),
            ("EA0B", -40.0),
            ("EC0B", 65.0),
            ("EB0B", -35.0),
            ("EX0C", 9.0),
            ("EY0C", -33.0),
            ("EA0C", 12.0),
            ("EB0C", 90.0),
            ("EC0C", -50.0),
        ]),
        _ => {}
    }
    errors
}

/// The constant errors whose fold moves origins only (positions of rotary axis lines, tool
/// errors, and the zero position of a rotary axis that carries nothing but the workpiece).
fn origin_only_errors(name: &str) -> Vec<(&'static str, Real)> {
    let mut errors = vec![("EXT", 12.0), ("EYT", -8.0), ("EZT", 25.0)];
    match name {
        "trunnion5" => errors.extend([
            ("EY0A", 18.0),
            ("EZ0A", -27.0),
            ("EX0C", -12.0),
            ("EY0C", 40.0),
            ("EC0C", 70.0),
        ]),
        "headtable5" => errors.extend([
            ("EX0B", 22.0),
            ("EZ0B", -15.0),
            ("EX0C", 9.0),
            ("EY0C", -33.0),
            ("EC0C", -50.0),
        ]),
        _ => {}
    }
    errors
}

/// Axis positions over the travel: linear axes at both ends and the middle, rotary axes at
/// large angles, the spindle at two angles.
fn grid(machine: &Machine) -> Vec<AxisValues> {
    let mut grid = vec![AxisValues::ZERO];
    for info in machine.axes() {
        let values: Vec<Real> = match info.axis {
            Axis::X | Axis::Y | Axis::Z => {
                let (lower, upper) = info.limits.unwrap();
                vec![lower, 0.5 * (lower + upper), upper]
            }
            Axis::A => [-90.0, -30.0, 0.0, 45.0].map(|d| d * RAD_PER_DEG).to_vec(),
            Axis::B => [-100.0, -30.0, 0.0, 60.0].map(|d| d * RAD_PER_DEG).to_vec(),
            Axis::C => [0.0, 77.0, 180.0, 300.0].map(|d| d * RAD_PER_DEG).to_vec(),
            Axis::S => vec![0.0, 2.1],
        };
        grid = grid
            .iter()
            .flat_map(|position| {
                values.iter().map(move |&v| {
                    let mut p = *position;
                    p[info.axis] = v;
                    p
                })
            })
            .collect();
    }
    grid
}

/// A rigid transform written out: rotation rows and translation.
#[derive(Clone, Copy, Debug)]
struct Frame {
    r: M3,
    t: Vector,
}

impl Frame {
    const IDENTITY: Frame = Frame {
        r: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        t: Vector::ZERO,
    };

    fn then(self, other: Frame) -> Frame {
        Frame {
            r: mul(self.r, other.r),
            t: self.t + apply(self.r, other.t),
        }
    }

    /// `self⁻¹ · other`.
    fn inverse_then(self, other: Frame) -> Frame {
        let rt = transpose(self.r);
        Frame {
            r: mul(rt, other.r),
            t: apply(rt, other.t - self.t),
        }
    }
}

fn transpose(m: M3) -> M3 {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in m.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            out[j][i] = *v;
        }
    }
    out
}

/// Rotation by `angle` about the unit vector `k` (Rodrigues), written out.
fn about(k: Vector, angle: Real) -> M3 {
    let (s, c) = angle.sin_cos();
    let k = k.to_array();
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = (1.0 - c) * k[i] * k[j] + if i == j { c } else { 0.0 };
        }
    }
    r[0][1] -= s * k[2];
    r[0][2] += s * k[1];
    r[1][0] += s * k[2];
    r[1][2] -= s * k[0];
    r[2][0] -= s * k[1];
    r[2][1] += s * k[0];
    r
}

/// `world_from_link` of a URDF by its own semantics, independent of mtwin's reader: each joint
/// is `Trans(xyz) · Rz(yaw)·Ry(pitch)·Rx(roll)` then its motion along or about the normalised
/// axis, the value of an axis named by its letter.
fn urdf_world_from(robot: &urdf_rs::Robot, link: &str, position: &AxisValues) -> Frame {
    let mut path = Vec::new();
    let mut at = link;
    while let Some(joint) = robot.joints.iter().find(|j| j.child.link == at) {
        path.push(joint);
        at = &joint.parent.link;
    }
    path.reverse();
    let mut frame = Frame::IDENTITY;
    for joint in path {
        let [roll, pitch, yaw] = joint.origin.rpy.0;
        frame = frame.then(Frame {
            r: mul(rz(yaw), mul(ry(pitch), rx(roll))),
            t: Vector::from_array(joint.origin.xyz.0),
        });
        let axis = Vector::from_array(joint.axis.xyz.0).normalize();
        let value = || {
            let letter = joint.name.chars().next().unwrap();
            position[Axis::from_letter(letter).unwrap()]
        };
        let motion = match joint.joint_type {
            urdf_rs::JointType::Fixed => Frame::IDENTITY,
            urdf_rs::JointType::Prismatic => Frame {
                r: Frame::IDENTITY.r,
                t: axis * value(),
            },
            _ => Frame {
                r: about(axis, value()),
                t: Vector::ZERO,
            },
        };
        frame = frame.then(motion);
    }
    frame
}

/// `workpiece_from_tool` of URDF text by [`urdf_world_from`].
fn urdf_workpiece_from_tool(robot: &urdf_rs::Robot, position: &AxisValues) -> Frame {
    let world_from_workpiece = urdf_world_from(robot, "workpiece", position);
    world_from_workpiece.inverse_then(urdf_world_from(robot, "tool", position))
}

/// Position and orientation differences (m, rad: largest rotation-matrix element) between a
/// pose and a written-out frame.
fn difference(pose: &Pose, frame: &Frame) -> (Real, Real) {
    let position = (pose.translation - frame.t).length();
    let mut orientation: Real = 0.0;
    for (i, row) in frame.r.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            orientation = orientation.max((pose.matrix3.col(j)[i] - v).abs());
        }
    }
    (position, orientation)
}

fn as_frame(pose: &Pose) -> Frame {
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = pose.matrix3.col(j)[i];
        }
    }
    Frame {
        r,
        t: pose.translation,
    }
}

/// The largest position and orientation differences over the grid between the actual pose of
/// the identified machine and `corrected`, a nominal pose per position.
fn largest_difference(
    machine: &Machine,
    errors: &ErrorModel,
    mut corrected: impl FnMut(&AxisValues) -> Frame,
) -> (Real, Real) {
    let mut workspace = Workspace::new(machine);
    let mut worst: (Real, Real) = (0.0, 0.0);
    for position in grid(machine) {
        let actual =
            errors.workpiece_from_tool(machine, &mut workspace, &MachineState::at(position));
        let (dp, dr) = difference(&actual, &corrected(&position));
        worst = (worst.0.max(dp), worst.1.max(dr));
    }
    worst
}

#[test]
fn corrected_urdf_has_the_identified_machine_as_its_nominal_kinematics() {
    for name in MACHINES {
        let machine = machine(name);
        let text = urdf_text(name);
        let errors = constants(&machine, &all_constant_errors(name));
        let corrected = corrected_urdf(&text, &machine, &errors).unwrap();
        assert_eq!(corrected.folded.len(), errors.parameters().len(), "{name}");
        assert!(corrected.not_folded.is_empty(), "{name}");
        let robot = urdf_rs::read_from_string(&corrected.urdf).unwrap();
        let (dp, dr) = largest_difference(&machine, &errors, |position| {
            urdf_workpiece_from_tool(&robot, position)
        });
        eprintln!(
            "{name}: corrected URDF (URDF semantics) vs identified machine: {dp:.3e} m, {dr:.3e} rad"
        );
        assert!(dp <= NM && dr <= NRAD, "{name}: {dp:e} m, {dr:e} rad");
        // The errors are there to be folded: the original URDF is micrometres off.
        let original = urdf_rs::read_from_string(&text).unwrap();
        let (dp, _) = largest_difference(&machine, &errors, |position| {
            urdf_workpiece_from_tool(&original, position)
        });
        assert!(
            dp > 10e-6,
            "{name}: the errors move the tool by {dp:e} m only"
        );
    }
}

#[test]
fn corrected_urdf_keeps_the_rest_of_the_text() {
    for name in MACHINES {
        let machine = machine(name);
        let text = urdf_text(name);
        let errors = constants(&machine, &all_constant_errors(name));
        let corrected = corrected_urdf(&text, &machine, &errors).unwrap().urdf;
        assert_eq!(corrected.lines().count(), text.lines().count(), "{name}");
        let mut changed = 0;
        for (old, new) in text.lines().zip(corrected.lines()) {
            if old != new {
                changed += 1;
                let tag = |line: &str| line.trim().split(' ').next().unwrap().to_string();
                assert_eq!(tag(old), tag(new), "{name}: {old} → {new}");
                assert!(
                    ["<origin", "<axis"].contains(&tag(old).as_str()),
                    "{name}: {old} → {new}"
                );
            }
        }
        assert!(changed > 0, "{name}");
        // Moving joints keep their rpy (frames parallel to the bed) and get unit axes.
        let robot = urdf_rs::read_from_string(&corrected).unwrap();
        let original = urdf_rs::read_from_string(&text).unwrap();
        for joint in &robot.joints {
            if joint.joint_type != urdf_rs::JointType::Fixed {
                let before = original
                    .joints
                    .iter()
                    .find(|j| j.name == joint.name)
                    .unwrap();
                assert_eq!(
                    joint.origin.rpy.0, before.origin.rpy.0,
                    "{name} {}",
                    joint.name
                );
                let length = Vector::from_array(joint.axis.xyz.0).length();
                assert!((length - 1.0).abs() < 1e-15, "{name} {}", joint.name);
            }
        }
    }
}

#[test]
fn corrected_urdf_with_moved_origins_loads_back_in_mtwin_and_reproduces_the_machine() {
    for name in MACHINES {
        let machine = machine(name);
        let text = urdf_text(name);
        let errors = constants(&machine, &origin_only_errors(name));
        let corrected = corrected_urdf(&text, &machine, &errors).unwrap();
        let reloaded = Machine::from_urdf_str(&corrected.urdf, "corrected").unwrap();
        let mut workspace = Workspace::new(&reloaded);
        let (dp, dr) = largest_difference(&machine, &errors, |position| {
            as_frame(&workspace.workpiece_from_tool(&reloaded, position, None))
        });
        eprintln!("{name}: reloaded by mtwin (moved origins only): {dp:.3e} m, {dr:.3e} rad");
        assert!(dp <= NM && dr <= NRAD, "{name}: {dp:e} m, {dr:e} rad");
    }
}

#[test]
fn corrected_urdf_with_tilted_axes_loads_back_in_mtwin_and_reproduces_the_machine() {
    for name in MACHINES {
        let machine = machine(name);
        let text = urdf_text(name);
        let errors = constants(&machine, &all_constant_errors(name));
        let corrected = corrected_urdf(&text, &machine, &errors).unwrap();
        let reloaded = Machine::from_urdf_str(&corrected.urdf, "corrected").unwrap();
        let mut workspace = Workspace::new(&reloaded);
        let (dp, dr) = largest_difference(&machine, &errors, |position| {
            as_frame(&workspace.workpiece_from_tool(&reloaded, position, None))
        });
        eprintln!("{name}: reloaded by mtwin (all constant errors): {dp:.3e} m, {dr:.3e} rad");
        assert!(dp <= NM && dr <= NRAD, "{name}: {dp:e} m, {dr:e} rad");
    }
}

#[test]
fn zero_errors_give_the_same_urdf_and_the_same_poses() {
    for name in MACHINES {
        let machine = machine(name);
        let text = urdf_text(name);
        for errors in [
            ErrorModel::empty(&machine),
            constants(&machine, &[("EC0Y", 0.0), ("EXT", 0.0)]),
        ] {
            let corrected = corrected_urdf(&text, &machine, &errors).unwrap();
            assert_eq!(corrected.urdf, text, "{name}");
            let reloaded = Machine::from_urdf_str(&corrected.urdf, "corrected").unwrap();
            for position in grid(&machine) {
                assert_eq!(
                    reloaded.workpiece_from_tool(&position),
                    machine.workpiece_from_tool(&position),
                    "{name} at {}",
                    describe(&position)
                );
            }
        }
    }
}

#[test]
fn component_errors_are_not_folded_and_say_why() {
    let machine = machine("trunnion5");
    let text = urdf_text("trunnion5");
    let errors = ErrorModel::new(
        &machine,
        vec![
            ErrorParameter {
                name: "EXX".parse().unwrap(),
                function: ErrorFunction::Polynomial(vec![2e-6, 1e-5]),
            },
            ErrorParameter {
                name: "EYX".parse().unwrap(),
                function: ErrorFunction::Polynomial(vec![0.0, 0.0, 3e-5]),
            },
            ErrorParameter {
                name: "EX0C".parse().unwrap(),
                function: ErrorFunction::Constant(10e-6),
            },
        ],
    )
    .unwrap();
    let corrected = corrected_urdf(&text, &machine, &errors).unwrap();
    assert_eq!(corrected.folded, vec!["EX0C".parse().unwrap()]);
    let reason = |name: &str| {
        let name: ParameterName = name.parse().unwrap();
        corrected
            .not_folded
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, why)| why.clone())
            .unwrap_or_else(|| panic!("{name} not listed: {:?}", corrected.not_folded))
    };
    let exx = reason("EXX");
    assert!(
        exx.contains("function of the X position") && exx.contains("LinuxCNC"),
        "{exx}"
    );
    let eyx = reason("EYX");
    assert!(
        eyx.contains("function of the X position") && eyx.contains("volumetric"),
        "{eyx}"
    );
}

#[test]
fn corrected_urdf_refuses_another_machine() {
    let machine = machine("trunnion5");
    let errors = constants(&machine, &[("EX0C", 5.0)]);
    let error = corrected_urdf(&urdf_text("headtable5"), &machine, &errors).unwrap_err();
    assert!(
        matches!(error, CompensateError::OtherMachine { .. }),
        "{error}"
    );
    assert!(error.to_string().contains("trunnion5"), "{error}");
}

/// `(nominal, forward, reverse)` per line; every line three numbers.
fn parse_table(text: &str) -> Vec<[Real; 3]> {
    text.lines()
        .map(|line| {
            let values: Vec<Real> = line
                .split_whitespace()
                .map(|v| {
                    v.parse()
                        .unwrap_or_else(|_| panic!("not a number in {line:?}"))
                })
                .collect();
            assert_eq!(values.len(), 3, "{line:?}");
            [values[0], values[1], values[2]]
        })
        .collect()
}

#[test]
fn linuxcnc_table_trims_a_linear_positioning_error_with_reversal() {
    // EXX = a + b·x with a reversal r: moving +, E = a + b·x − r/2; moving −, a + b·x + r/2.
    let (a, b, r) = (3e-6, 15e-6, 4e-6);
    let machine = machine("vmc3");
    let errors = ErrorModel::new(
        &machine,
        vec![ErrorParameter {
            name: "EXX".parse().unwrap(),
            function: ErrorFunction::Sum(vec![
                ErrorFunction::Polynomial(vec![a, b]),
                ErrorFunction::Reversal(r),
            ]),
        }],
    )
    .unwrap();
    let tables = linuxcnc_tables(&machine, &errors, 0.050, 5.0 * RAD_PER_DEG).unwrap();
    assert_eq!(tables.len(), 1, "only X has a positioning error");
    assert_eq!(tables[0].0, Axis::X);
    let rows = parse_table(&tables[0].1);
    // 0, 50, …, 750 and the end of travel 760 mm.
    assert_eq!(rows.len(), 17);
    assert_eq!(rows[0][0], 0.0);
    assert_eq!(rows[16][0], 760.0);
    assert!(
        rows.windows(2).all(|w| w[1][0] > w[0][0]),
        "nominal increases"
    );
    // Hand values (mm): the trim is minus the error there (to 1 nm; the exact trim
    // −E/(1 + b) differs by b·E ≈ 0.2 nm).
    for (nominal, forward, reverse) in [
        (0.0, -0.001, -0.005),
        (400.0, -0.007, -0.011),
        (760.0, -0.0124, -0.0164),
    ] {
        let row = rows.iter().find(|row| row[0] == nominal).unwrap();
        assert!((row[1] - forward).abs() <= 1e-6, "{nominal}: {row:?}");
        assert!((row[2] - reverse).abs() <= 1e-6, "{nominal}: {row:?}");
        // Forward and reverse differ by the reversal (LinuxCNC: +backlash/2, −backlash/2).
        assert!(
            (row[1] - row[2] - r / 1e-3).abs() <= 2e-6,
            "{nominal}: {row:?}"
        );
    }
    // The trim makes the axis reach the nominal in the model: n + t + E(n + t) = n.
    let function = &errors.parameters()[0].function;
    for row in &rows {
        let (n, t) = (row[0] * 1e-3, row[1] * 1e-3);
        let reached = n + t + function.value(n + t, mtwin::machine::Direction::Positive);
        assert!((reached - n).abs() <= 1e-9, "{row:?}: reached {reached}");
    }
}

#[test]
fn linuxcnc_table_for_a_continuous_rotary_axis_spans_one_turn_in_degrees() {
    let machine = machine("trunnion5");
    let amplitude = 20e-6;
    let errors = ErrorModel::new(
        &machine,
        vec![ErrorParameter {
            name: "ECC".parse().unwrap(),
            function: ErrorFunction::Harmonic {
                period: std::f64::consts::PI,
                amplitude,
                phase: 0.0,
            },
        }],
    )
    .unwrap();
    let tables = linuxcnc_tables(&machine, &errors, 0.025, 10.0 * RAD_PER_DEG).unwrap();
    assert_eq!(tables.len(), 1);
    assert_eq!(tables[0].0, Axis::C);
    let rows = parse_table(&tables[0].1);
    assert_eq!(rows.len(), 37);
    assert_eq!((rows[0][0], rows[36][0]), (0.0, 360.0));
    for row in &rows {
        // −20 µrad · sin(2θ) in degrees, no reversal (to first order: the exact trim solves
        // t = −E(θ + t), which differs by E·E′ ≤ 0.8 nrad = 5e-8°).
        let expected = -amplitude * (2.0 * row[0] * RAD_PER_DEG).sin() / RAD_PER_DEG;
        assert!((row[1] - expected).abs() <= 1e-7, "{row:?} vs {expected}");
        assert_eq!(row[1], row[2], "{row:?}");
    }
}

#[test]
fn linuxcnc_tables_refuse_more_entries_than_linuxcnc_takes() {
    let machine = machine("vmc3");
    let errors = constants(&machine, &[]);
    assert!(
        linuxcnc_tables(&machine, &errors, 0.001, 0.1)
            .unwrap()
            .is_empty()
    );
    let errors = ErrorModel::new(
        &machine,
        vec![ErrorParameter {
            name: "EYY".parse().unwrap(),
            function: ErrorFunction::Polynomial(vec![0.0, 1e-5]),
        }],
    )
    .unwrap();
    let error = linuxcnc_tables(&machine, &errors, 0.001, 0.1).unwrap_err();
    assert!(
        matches!(error, CompensateError::TooManyEntries { axis: Axis::Y, .. }),
        "{error}"
    );
    assert!(
        error
            .to_string()
            .contains(&LINUXCNC_MAX_ENTRIES.to_string()),
        "{error}"
    );
    let error = linuxcnc_tables(&machine, &errors, 0.0, 0.1).unwrap_err();
    assert!(matches!(error, CompensateError::Spacing { .. }), "{error}");
}

/// One turn of trunnion5's continuous C at 1° is 361 entries, beyond LinuxCNC's 256: the
/// spacings `identify` writes at are widened to the turn over 254 intervals (by hand 1.4173°),
/// the linear ones left at 10 mm (vmc3's longest travel, 650 mm, is 66 entries), and the
/// table then holds C's error in at most 256 lines.
#[test]
fn the_linuxcnc_spacing_is_widened_to_hold_a_turn() {
    let trunnion = machine("trunnion5");
    let (linear, rotary) =
        mtwin::estimate::compensate::linuxcnc_spacings(&trunnion, 0.01, 1f64.to_radians());
    assert_eq!(linear, 0.01);
    assert!(
        (rotary.to_degrees() - 360.0 / 254.0).abs() < 1e-3,
        "{}",
        rotary.to_degrees()
    );
    let errors = ErrorModel::new(
        &trunnion,
        vec![ErrorParameter {
            name: "ECC".parse().unwrap(),
            function: ErrorFunction::Harmonic {
                period: std::f64::consts::PI,
                amplitude: 6e-6,
                phase: 0.2,
            },
        }],
    )
    .unwrap();
    assert!(linuxcnc_tables(&trunnion, &errors, linear, 1f64.to_radians()).is_err());
    let tables = linuxcnc_tables(&trunnion, &errors, linear, rotary).unwrap();
    let (axis, text) = &tables[0];
    assert_eq!(*axis, Axis::C);
    let lines = text.lines().count();
    assert!((250..=LINUXCNC_MAX_ENTRIES).contains(&lines), "{lines}");
}
