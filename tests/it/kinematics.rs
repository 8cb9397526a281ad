//! Forward kinematics of the bundled machines against transforms composed by hand from the
//! geometry their URDF headers document, the URDF `rpy`/axis conventions against an
//! independent rotation composition, and the closed-form inverse kinematics by round trip.

use crate::common::*;
use mtwin::machine::{
    Axis, AxisValues, InverseKinematicsError, Machine, TiltBranch, ToolTarget, Workspace,
};
use mtwin::math::{RAD_PER_DEG, Vector};
use std::f64::consts::PI;

/// Exact kinematics agree to round-off: positions are ~1 m, so 1 pm is ~10⁴ ulps.
const EXACT_M: f64 = 1e-12;

#[test]
fn vmc3_tip_is_home_offset_plus_commanded_position() {
    // Header: at X = Y = Z = 0 the tip is at (-380, -205, 100) mm from the table centre, and
    // a positive command moves the tool positively relative to the workpiece.
    let machine = machine("vmc3");
    let mut rng = rng("vmc3 fk");
    for _ in 0..100 {
        let q = random_position(&machine, &mut rng);
        let pose = machine.workpiece_from_tool(&q);
        let expected = Vector::new(-0.38 + q[Axis::X], -0.205 + q[Axis::Y], 0.10 + q[Axis::Z]);
        assert_close(pose.translation, expected, EXACT_M, &describe(&q));
        assert_close(pose.matrix3.z_axis, Vector::Z, 1e-15, "tool axis");
    }
}

#[test]
fn trunnion5_matches_hand_composition() {
    // world_from_workpiece = Trans(-x, -y, 1.15) · Rx(-a) · Trans(0, 0, -0.05) · Rz(-c) and the
    // tip in the world at (-0.325, -0.275, 1.20 + z), so
    // tip_wp = Rz(c) · (Rx(a) · (tip - (-x, -y, 1.15)) + (0, 0, 0.05)), k = Rz(c)·Rx(a)·e_z.
    let machine = machine("trunnion5");
    let mut rng = rng("trunnion5 fk");
    for _ in 0..100 {
        let q = random_position(&machine, &mut rng);
        let (x, y, z, a, c) = (q[Axis::X], q[Axis::Y], q[Axis::Z], q[Axis::A], q[Axis::C]);
        let tip_world = Vector::new(-0.325, -0.275, 1.20 + z);
        let a_axis = Vector::new(-x, -y, 1.15);
        let expected = apply(
            rz(c),
            apply(rx(a), tip_world - a_axis) + Vector::new(0.0, 0.0, 0.05),
        );
        let pose = machine.workpiece_from_tool(&q);
        assert_close(pose.translation, expected, EXACT_M, &describe(&q));
        assert_close(
            pose.matrix3.z_axis,
            apply(mul(rz(c), rx(a)), Vector::Z),
            1e-15,
            "tool axis",
        );
    }
}

#[test]
fn headtable5_matches_hand_composition() {
    // Tool: B pivot at (-0.40, -0.30, 1.40 + z), tip = pivot + Ry(b)·(0, 0, -0.25).
    // Workpiece: C table centre at (-x, -y, 1.02) turned by Rz(-c).
    let machine = machine("headtable5");
    let mut rng = rng("headtable5 fk");
    for _ in 0..100 {
        let q = random_position(&machine, &mut rng);
        let (x, y, z, b, c) = (q[Axis::X], q[Axis::Y], q[Axis::Z], q[Axis::B], q[Axis::C]);
        let pivot = Vector::new(-0.40, -0.30, 1.40 + z);
        let tip_world = pivot + apply(ry(b), Vector::new(0.0, 0.0, -0.25));
        let expected = apply(rz(c), tip_world - Vector::new(-x, -y, 1.02));
        let pose = machine.workpiece_from_tool(&q);
        assert_close(pose.translation, expected, EXACT_M, &describe(&q));
        assert_close(
            pose.matrix3.z_axis,
            apply(mul(rz(c), ry(b)), Vector::Z),
            1e-15,
            "tool axis",
        );
    }
}

#[test]
fn positive_rotary_commands_turn_the_tool_positively_relative_to_the_workpiece() {
    // ISO 841: +A turns the tool about +X relative to the workpiece, so the tool axis e_z goes
    // to (0, -sin A, cos A); +C about +Z; +B about +Y (e_z → (sin B, 0, cos B)).
    let a30 = AxisValues::from_file_units(&[(Axis::A, 30.0)]);
    let k = machine("trunnion5")
        .workpiece_from_tool(&a30)
        .matrix3
        .z_axis;
    assert_close(
        k,
        Vector::new(0.0, -0.5, 3f64.sqrt() / 2.0),
        1e-15,
        "A = +30°",
    );
    let b30 = AxisValues::from_file_units(&[(Axis::B, 30.0)]);
    let k = machine("headtable5")
        .workpiece_from_tool(&b30)
        .matrix3
        .z_axis;
    assert_close(
        k,
        Vector::new(0.5, 0.0, 3f64.sqrt() / 2.0),
        1e-15,
        "B = +30°",
    );
    // C = +90° on trunnion5: the tip at (-325, -275) mm turns by +90° about the table centre.
    let c90 = AxisValues::from_file_units(&[(Axis::C, 90.0)]);
    let tip = machine("trunnion5").workpiece_from_tool(&c90).translation;
    assert_close(tip, Vector::new(0.275, -0.325, 0.10), EXACT_M, "C = +90°");
}

#[test]
fn urdf_rpy_and_origin_follow_the_fixed_axis_convention() {
    // The workpiece is mounted by a fixed joint with rpy = (r, p, y), i.e. world_from_workpiece
    // has the rotation R = Rz(y)·Ry(p)·Rx(r), written out here element by element, and its xyz
    // as translation. The tool (a prismatic X, Y, Z stack from the bed origin) is at (x, y, z),
    // so workpiece_from_tool = (Rᵀ, Rᵀ·((x, y, z) - xyz)).
    let (r, p, yaw): (f64, f64, f64) = (0.3, -0.5, 1.2);
    let urdf = format!(
        r#"<robot name="rpy">
  <link name="bed"/><link name="x"/><link name="y"/><link name="z"/><link name="tool"/><link name="workpiece"/>
  <joint name="X" type="prismatic"><parent link="bed"/><child link="x"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" velocity="1"/></joint>
  <joint name="Y" type="prismatic"><parent link="x"/><child link="y"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1"/></joint>
  <joint name="Z" type="prismatic"><parent link="y"/><child link="z"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1"/></joint>
  <joint name="holder" type="fixed"><parent link="z"/><child link="tool"/></joint>
  <joint name="mount" type="fixed"><parent link="bed"/><child link="workpiece"/><origin xyz="0.1 0.2 0.3" rpy="{r} {p} {yaw}"/></joint>
</robot>"#
    );
    let machine = Machine::from_urdf_str(&urdf, "rpy.urdf").unwrap();
    let (sr, cr) = r.sin_cos();
    let (sp, cp) = p.sin_cos();
    let (sy, cy) = yaw.sin_cos();
    let rotation = [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ];
    let transposed: M3 = std::array::from_fn(|i| std::array::from_fn(|j| rotation[j][i]));
    let q = AxisValues::from_file_units(&[(Axis::X, 10.0), (Axis::Y, -20.0), (Axis::Z, 30.0)]);
    let pose = machine.workpiece_from_tool(&q);
    for (i, row) in transposed.iter().enumerate() {
        for (j, value) in row.iter().enumerate() {
            assert!(
                (pose.matrix3.col(j)[i] - value).abs() < 1e-15,
                "Rᵀ[{i}][{j}]"
            );
        }
    }
    let expected = apply(transposed, Vector::new(0.01 - 0.1, -0.02 - 0.2, 0.03 - 0.3));
    assert_close(
        pose.translation,
        expected,
        EXACT_M,
        "origin xyz and axis travel",
    );
}

/// `text` with every joint's `<axis xyz="…">` replaced by `change` of its components.
fn with_axes(text: &str, change: impl Fn([f64; 3]) -> String) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(start) = rest.find("<axis xyz=\"") {
        let (before, after) = rest.split_at(start + "<axis xyz=\"".len());
        let end = after.find('"').expect("a closing quote");
        let v: Vec<f64> = after[..end]
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        out += before;
        out += &change([v[0], v[1], v[2]]);
        rest = &after[end..];
    }
    out + rest
}

/// A joint's `<axis xyz>` is a direction: the URDF specification asks for a unit vector, but
/// a hand-written one need not be one (`2 0 0`, or a measured tilt written as read, `0 1e-4
/// -1`, 5·10⁻⁹ longer than a unit). Every bundled machine with every axis doubled gives the
/// poses of its unit axes to the bit (a doubled vector normalises back exactly); trunnion5
/// with C tilted by `0 1e-4 -1` gives the poses of the same tilt written as a unit vector
/// within [`EXACT_M`] (taken as written, the turn would be about a vector 5·10⁻⁹ too long:
/// a rotation matrix off by that much, nanometres at the table's radius).
#[test]
fn joint_axes_are_directions_whatever_their_length() {
    let mut rng = rng("axis length");
    for name in ["vmc3", "trunnion5", "headtable5"] {
        let file = format!("{}/models/{name}.urdf", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&file).unwrap();
        let doubled = with_axes(&text, |v| {
            format!("{} {} {}", 2.0 * v[0], 2.0 * v[1], 2.0 * v[2])
        });
        assert_ne!(doubled, text);
        let (unit, long) = (
            Machine::from_urdf_str(&text, &file).unwrap(),
            Machine::from_urdf_str(&doubled, "doubled.urdf").unwrap(),
        );
        for _ in 0..50 {
            let q = random_position(&unit, &mut rng);
            assert_eq!(
                unit.workpiece_from_tool(&q),
                long.workpiece_from_tool(&q),
                "{name}"
            );
        }
    }
    let text = std::fs::read_to_string(format!(
        "{}/models/trunnion5.urdf",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    // C is trunnion5's only `0 0 -1` axis.
    let tilt = |v: [f64; 3], written: &str| {
        if v == [0.0, 0.0, -1.0] {
            written.to_string()
        } else {
            format!("{} {} {}", v[0], v[1], v[2])
        }
    };
    let norm = (1.0f64 + 1e-8).sqrt();
    let as_read = with_axes(&text, |v| tilt(v, "0 1e-4 -1"));
    let as_unit = with_axes(&text, |v| {
        tilt(v, &format!("0 {:e} {:e}", 1e-4 / norm, -1.0 / norm))
    });
    let (read, unit) = (
        Machine::from_urdf_str(&as_read, "as_read.urdf").unwrap(),
        Machine::from_urdf_str(&as_unit, "as_unit.urdf").unwrap(),
    );
    for _ in 0..100 {
        let q = random_position(&read, &mut rng);
        let (a, b) = (read.workpiece_from_tool(&q), unit.workpiece_from_tool(&q));
        assert_close(a.translation, b.translation, EXACT_M, &describe(&q));
        for (x, y) in a
            .matrix3
            .to_cols_array()
            .iter()
            .zip(b.matrix3.to_cols_array())
        {
            assert!((x - y).abs() < 1e-15, "{x} vs {y} at {}", describe(&q));
        }
    }
}

/// The tilting axis of a 5-axis machine.
fn tilt_axis(machine: &Machine) -> Option<Axis> {
    [Axis::A, Axis::B]
        .into_iter()
        .find(|a| machine.has_axis(*a))
}

#[test]
fn inverse_kinematics_round_trips_on_every_machine() {
    for name in MACHINES {
        let machine = machine(name);
        let tilt = tilt_axis(&machine);
        let mut rng = rng(&format!("{name} ik"));
        let mut workspace = Workspace::new(&machine);
        let mut other_branch_checked = 0;
        for _ in 0..300 {
            let mut q = random_position(&machine, &mut rng);
            q[Axis::S] = 0.0;
            if tilt.is_some_and(|t| q[t].abs() < 2.0 * RAD_PER_DEG) {
                continue; // the tilt-zero singularity leaves C free; tested separately
            }
            let pose = workspace.workpiece_from_tool(&machine, &q, None);
            let target = ToolTarget {
                position: pose.translation,
                axis: tilt.map(|_| pose.matrix3.z_axis),
            };
            let branch = match tilt {
                Some(t) if q[t] < 0.0 => TiltBranch::Negative,
                _ => TiltBranch::Positive,
            };
            let solution = machine.inverse_kinematics(&target, branch).unwrap();
            for info in machine.axes().iter().filter(|i| i.axis != Axis::S) {
                let (got, want) = (solution[info.axis], q[info.axis]);
                let error = if info.axis.is_linear() {
                    (got - want).abs()
                } else {
                    ((got - want + PI).rem_euclid(2.0 * PI) - PI).abs()
                };
                // 1 nm on linear axes, 1 nrad on rotary ones: closed form, round-off only.
                assert!(
                    error < 1e-9,
                    "{name} axis {}: got {got}, want {want} ({})",
                    info.axis,
                    describe(&q)
                );
            }
            // The other branch reaches the same pose when it lies inside the travel.
            let other = if branch == TiltBranch::Positive {
                TiltBranch::Negative
            } else {
                TiltBranch::Positive
            };
            if tilt.is_some()
                && let Ok(alternative) = machine.inverse_kinematics(&target, other)
            {
                let reached = workspace.workpiece_from_tool(&machine, &alternative, None);
                assert_close(
                    reached.translation,
                    target.position,
                    1e-9,
                    "other branch position",
                );
                assert_close(
                    reached.matrix3.z_axis,
                    target.axis.unwrap(),
                    1e-12,
                    "other branch axis",
                );
                assert!(
                    alternative[tilt.unwrap()] * q[tilt.unwrap()] <= 0.0,
                    "other branch flips the tilt"
                );
                other_branch_checked += 1;
            }
        }
        if tilt.is_some() {
            assert!(
                other_branch_checked > 10,
                "{name}: the alternative branch was exercised"
            );
        }
    }
}

#[test]
fn inverse_kinematics_at_zero_tilt_reaches_the_point() {
    // Tool axis along the C axis: the tilt is zero and C is free; any solution must reach it.
    let machine = machine("trunnion5");
    let target = ToolTarget {
        position: Vector::new(0.05, -0.02, 0.12),
        axis: Some(Vector::Z),
    };
    let solution = machine
        .inverse_kinematics(&target, TiltBranch::Positive)
        .unwrap();
    assert!(solution[Axis::A].abs() < 1e-12);
    let reached = machine.workpiece_from_tool(&solution);
    assert_close(reached.translation, target.position, 1e-12, "position");
}

#[test]
fn inverse_kinematics_refuses_what_cannot_be_reached() {
    // trunnion5: tool axis -Z needs A = ±180°, beyond ±110° (the point under the upturned
    // table, z = -100 mm, is within the linear travels there).
    let trunnion = machine("trunnion5");
    let down = ToolTarget {
        position: Vector::new(0.0, 0.0, -0.1),
        axis: Some(-Vector::Z),
    };
    assert!(matches!(
        trunnion.inverse_kinematics(&down, TiltBranch::Positive),
        Err(InverseKinematicsError::OutOfTravel { axis: Axis::A, .. })
    ));
    // vmc3: the tool axis is fixed along +Z.
    let vmc = machine("vmc3");
    let sideways = ToolTarget {
        position: Vector::new(0.0, 0.0, 0.1),
        axis: Some(Vector::X),
    };
    assert!(matches!(
        vmc.inverse_kinematics(&sideways, TiltBranch::Positive),
        Err(InverseKinematicsError::UnreachableDirection { .. })
    ));
    // vmc3: X travel is -380 .. +380 mm about the table centre.
    let far = ToolTarget {
        position: Vector::new(0.5, 0.0, 0.1),
        axis: None,
    };
    assert!(matches!(
        vmc.inverse_kinematics(&far, TiltBranch::Positive),
        Err(InverseKinematicsError::OutOfTravel { axis: Axis::X, .. })
    ));
    // Not a number.
    let nan = ToolTarget {
        position: Vector::new(f64::NAN, 0.0, 0.1),
        axis: None,
    };
    assert_eq!(
        vmc.inverse_kinematics(&nan, TiltBranch::Positive),
        Err(InverseKinematicsError::NotFinite)
    );
    let nan_axis = ToolTarget {
        position: Vector::ZERO,
        axis: Some(Vector::new(f64::NAN, 0.0, 1.0)),
    };
    assert_eq!(
        trunnion.inverse_kinematics(&nan_axis, TiltBranch::Positive),
        Err(InverseKinematicsError::BadAxis)
    );
    // A 5-axis target without a tool-axis direction.
    let missing = ToolTarget {
        position: Vector::ZERO,
        axis: None,
    };
    assert_eq!(
        trunnion.inverse_kinematics(&missing, TiltBranch::Positive),
        Err(InverseKinematicsError::BadAxis)
    );
}

#[test]
fn batch_forward_kinematics_equals_single_poses() {
    let machine = machine("trunnion5");
    let mut rng = rng("batch");
    let positions: Vec<AxisValues> = (0..50)
        .map(|_| random_position(&machine, &mut rng))
        .collect();
    let mut out = vec![mtwin::math::Pose::IDENTITY; positions.len()];
    let mut workspace = Workspace::new(&machine);
    workspace.workpiece_from_tool_batch(&machine, &positions, &mut out);
    for (q, pose) in positions.iter().zip(&out) {
        assert_eq!(*pose, machine.workpiece_from_tool(q));
    }
}
