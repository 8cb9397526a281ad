//! Collision checks of programmes against a clearance worked out by hand from trunnion5's URDF.
//!
//! At A = −90° the trunnion's cradle (a 500 × 350 × 40 mm box 90 mm below the A axis in its own
//! frame) stands on edge: A turns the cradle by Rot(X, +90°), which takes the cradle's (x, y, z)
//! to (x, −z, y), so its top face lies 175 mm above the A axis, at machine y 70 … 110 mm in
//! front of it. World heights from the joint origins: the A axis at 0.75 + 0.15 + 0.25 =
//! 1.15 m; the tool tip at 1.50 − 0.15 − 0.15 + Z = 1.20 m + Z. The tool (a 16 mm cylinder
//! from the tip up) over the middle of that face (X = 325 mm puts the table's x under the
//! tool; Y = 365 mm puts the face's middle at the tool's y = −275 mm) therefore clears the
//! cradle by Z − 125 mm, and nothing else comes closer.

use mtwin::collision::{MAX_STEP, Mount, Scene, Solid};
use mtwin::machine::{Axis, AxisValues, Machine};
use mtwin::math::{Pose, Real, Vector};

fn trunnion() -> Machine {
    Machine::from_urdf_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/models/trunnion5.urdf"
    ))
    .unwrap()
}

fn over_the_cradle(z: Real) -> AxisValues {
    AxisValues::from_file_units(&[
        (Axis::X, 325.0),
        (Axis::Y, 365.0),
        (Axis::Z, z),
        (Axis::A, -90.0),
    ])
}

#[test]
fn a_descent_that_clears_the_trunnion_by_a_millimetre_runs() {
    let machine = trunnion();
    let scene = Scene::of_machine(&machine, &[]);
    let path = [
        (0.0, over_the_cradle(400.0)),
        (10.0, over_the_cradle(126.0)),
    ];
    let clearance = scene.sweep(&machine, &path).unwrap();
    assert_eq!(
        (
            clearance.tool_body.as_str(),
            clearance.workpiece_body.as_str()
        ),
        ("tool", "cradle")
    );
    // The last sample is checked: the hand clearance within parry's distance accuracy.
    assert!(
        (clearance.distance - 1e-3).abs() < 1e-9,
        "{}",
        clearance.distance
    );
    assert!((clearance.time - 10.0).abs() < 1e-12);
}

#[test]
fn a_descent_into_the_trunnion_is_refused_with_the_bodies_the_time_and_the_axes() {
    let machine = trunnion();
    let scene = Scene::of_machine(&machine, &[]);
    let path = [
        (0.0, over_the_cradle(400.0)),
        (10.0, over_the_cradle(124.0)),
    ];
    let collision = scene.sweep(&machine, &path).unwrap_err();
    assert_eq!(
        (
            collision.tool_body.as_str(),
            collision.workpiece_body.as_str()
        ),
        ("tool", "cradle")
    );
    // Contact at Z = 125 mm: t = 10 s · (400 − 125)/(400 − 124), found within one step.
    let expected = 10.0 * 275.0 / 276.0;
    let step_time = 10.0 * MAX_STEP / 0.276;
    assert!(
        (collision.time - expected).abs() <= step_time,
        "{} vs {expected}",
        collision.time
    );
    let z = collision.position[Axis::Z];
    assert!(z <= 0.125 && z > 0.125 - MAX_STEP, "{z}");
    let said = collision.describe(&machine);
    assert!(
        said.contains("A -90.000°") && said.contains("Z 12"),
        "{said}"
    );
}

#[test]
fn an_instrument_on_the_table_is_checked_against_the_spindle_side() {
    // A 20 mm ball on the C table 110 mm above its surface (workpiece frame), the tool
    // descending onto it at A = 0: the tool tip is 100 mm above the table at Z = 0 (the URDF
    // comment), so the tip meets the ball's top (120 mm) at Z = 20 mm.
    let machine = trunnion();
    let mut scene = Scene::of_machine(&machine, &[]);
    scene.attach(
        "sphere",
        Mount::Workpiece,
        Pose::from_translation(Vector::new(0.0, 0.0, 0.110)),
        Solid::Sphere(0.010),
    );
    let at =
        |z: Real| AxisValues::from_file_units(&[(Axis::X, 325.0), (Axis::Y, 275.0), (Axis::Z, z)]);
    let clear = scene
        .sweep(&machine, &[(0.0, at(300.0)), (1.0, at(21.0))])
        .unwrap();
    assert_eq!(clear.workpiece_body, "sphere");
    assert!((clear.distance - 1e-3).abs() < 1e-9, "{}", clear.distance);
    let hit = scene
        .sweep(&machine, &[(0.0, at(300.0)), (1.0, at(19.0))])
        .unwrap_err();
    assert_eq!(
        (hit.tool_body.as_str(), hit.workpiece_body.as_str()),
        ("tool", "sphere")
    );
}
