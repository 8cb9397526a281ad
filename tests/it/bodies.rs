//! The machine's drawn parts: links placed by hand from the URDF origins, and the end links
//! where the kinematics put them.

use mtwin::machine::{Axis, AxisValues, Machine, Shape, Workspace};
use mtwin::math::{Pose, Vector};

fn frames(machine: &Machine, position: &AxisValues) -> Vec<(String, Pose)> {
    let mut workspace = Workspace::new(machine);
    let mut out = vec![Pose::IDENTITY; machine.bodies().len()];
    machine.world_from_bodies(&mut workspace, position, &mut out);
    machine
        .bodies()
        .iter()
        .map(|b| b.link.clone())
        .zip(out)
        .collect()
}

fn close(a: Vector, b: Vector) -> bool {
    (a - b).length() < 1e-12
}

#[test]
fn vmc3_links_sit_where_the_urdf_puts_them() {
    let machine = Machine::from_urdf_file("models/vmc3.urdf").unwrap();
    let links: Vec<(&str, Option<Axis>)> = machine
        .bodies()
        .iter()
        .map(|b| (b.link.as_str(), b.moved_by))
        .collect();
    assert_eq!(
        links,
        [
            ("bed", None),
            ("saddle", Some(Axis::Y)),
            ("table", Some(Axis::X)),
            ("workpiece", Some(Axis::X)),
            ("column", None),
            ("head", Some(Axis::Z)),
            ("spindle", Some(Axis::S)),
            ("tool", Some(Axis::S)),
        ]
    );
    let table = &machine.bodies()[2];
    assert_eq!(table.visuals.len(), 1);
    assert_eq!(
        table.visuals[0].shape,
        Shape::Box {
            size: Vector::new(1.0, 0.5, 0.1)
        }
    );
    assert!(close(
        table.visuals[0].link_from_shape.translation,
        Vector::new(0.0, 0.0, 0.05)
    ));
    // X = 0.3, Y = 0.1, Z = 0.2 m. By hand from the joint origins: saddle (0, -Y, 0.75)
    // (axis -y); table 0.15 higher and -X; workpiece 0.10 above the table; column
    // (-0.38, -0.555, 0); head 1.40 + Z up the column; spindle (0, 0.35, -0.15) from the head;
    // tool 0.15 below the spindle.
    let position =
        AxisValues::from_file_units(&[(Axis::X, 300.0), (Axis::Y, 100.0), (Axis::Z, 200.0)]);
    let expected = [
        ("bed", Vector::ZERO),
        ("saddle", Vector::new(0.0, -0.1, 0.75)),
        ("table", Vector::new(-0.3, -0.1, 0.9)),
        ("workpiece", Vector::new(-0.3, -0.1, 1.0)),
        ("column", Vector::new(-0.38, -0.555, 0.0)),
        ("head", Vector::new(-0.38, -0.555, 1.6)),
        ("spindle", Vector::new(-0.38, -0.205, 1.45)),
        ("tool", Vector::new(-0.38, -0.205, 1.3)),
    ];
    for ((link, frame), (name, translation)) in frames(&machine, &position).iter().zip(expected) {
        assert_eq!(link, name);
        assert!(
            close(frame.translation, translation),
            "{link}: {:?}, expected {translation:?}",
            frame.translation
        );
    }
}

#[test]
fn a_rotary_axis_turns_the_links_it_carries() {
    // trunnion5: the cradle turns about -x (joint axis) by A; at A = 30° a vector along its
    // y ends at (0, cos 30°, -sin 30°) in the bed frame, and the cradle's origin stays
    // 0.25 m above the X table.
    let machine = Machine::from_urdf_file("models/trunnion5.urdf").unwrap();
    let position = AxisValues::from_file_units(&[(Axis::A, 30.0)]);
    let frames = frames(&machine, &position);
    let (_, cradle) = frames.iter().find(|(l, _)| l == "cradle").unwrap();
    let (_, table) = frames.iter().find(|(l, _)| l == "table").unwrap();
    let (s, c) = 30f64.to_radians().sin_cos();
    assert!(close(cradle.matrix3 * Vector::Y, Vector::new(0.0, c, -s)));
    assert!(close(
        cradle.translation,
        table.translation + Vector::new(0.0, 0.0, 0.25)
    ));
}

#[test]
fn the_end_links_are_where_the_kinematics_put_them() {
    // Every machine, a few positions: the `tool` and `workpiece` bodies coincide with the
    // forward kinematics' ends, and their relative pose is the tool pose seen from the workpiece.
    for model in ["vmc3", "trunnion5", "headtable5"] {
        let machine = Machine::from_urdf_file(format!("models/{model}.urdf")).unwrap();
        let mut position = AxisValues::ZERO;
        for (k, info) in machine.axes().iter().enumerate() {
            let (low, high) = info.limits.unwrap_or((-3.0, 3.0));
            position[info.axis] = low + (high - low) * (0.2 + 0.1 * k as f64);
        }
        let frames = frames(&machine, &position);
        let find = |name: &str| frames.iter().find(|(l, _)| l == name).unwrap().1;
        let (tool, workpiece) = (find("tool"), find("workpiece"));
        let mut workspace = Workspace::new(&machine);
        let relative = workspace.workpiece_from_tool(&machine, &position, None);
        let (world_tool, world_workpiece) = workspace.world_from_ends();
        assert!(close(tool.translation, world_tool.translation), "{model}");
        assert!(
            close(workpiece.translation, world_workpiece.translation),
            "{model}"
        );
        let seen = mtwin::math::rigid_inverse(&workpiece) * tool;
        assert!(close(seen.translation, relative.translation), "{model}");
        assert!(seen.matrix3.abs_diff_eq(relative.matrix3, 1e-12), "{model}");
    }
}
