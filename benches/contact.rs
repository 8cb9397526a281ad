//! Contact benchmarks: one touch of a stylus ball (r = 3 mm) with the twin's pose (trunnion5
//! with location errors of A and C: the actual `workpiece_from_tool` evaluated, then the
//! touch from the tool tip it gives):
//!
//! - `touch/sphere_closed_form`: pose + the closed form on a Ø 25 mm sphere;
//! - `touch/mesh_parry`: pose + parry's ball–mesh cast on a 12-triangle cube (STL);
//! - `touch/cylinder_parry_gjk`: pose + parry's GJK ball–cylinder cast, for comparison;
//! - `probe/touch`: one whole probe touch (the fixed point on the actual chain, a few pose
//!   evaluations, pre-travel, latency, scatter), as a cycle makes it;
//! - `probe/touch_mesh`: the same on the cube mesh (each step a parry cast).

use criterion::{Criterion, criterion_group, criterion_main};
use mtwin::contact::{Approach, Artefact, Mesh, Sphere};
use mtwin::errors::{ErrorFunction, ErrorModel, ErrorParameter};
use mtwin::kinds::probe::{LinearFrame, Target, TouchProbe};
use mtwin::machine::{Axis, AxisValues, Machine, MachineState, Workspace};
use mtwin::math::{Vector, seeded_rng};
use mtwin::twin::Twin;
use rapier3d_f64::parry::math::Pose as ParryPose;
use rapier3d_f64::parry::query::{ShapeCastOptions, cast_shapes};
use rapier3d_f64::parry::shape::{Ball, Cylinder};
use std::hint::black_box;

fn twin() -> Twin {
    let root = env!("CARGO_MANIFEST_DIR");
    let machine = Machine::from_urdf_file(format!("{root}/models/trunnion5.urdf")).unwrap();
    let parameters = [
        ("EY0C", 12e-6),
        ("EX0C", -8e-6),
        ("EB0C", 30e-6),
        ("EZ0A", 15e-6),
    ]
    .into_iter()
    .map(|(name, value)| ErrorParameter {
        name: name.parse().unwrap(),
        function: ErrorFunction::Constant(value),
    })
    .collect();
    let errors = ErrorModel::new(&machine, parameters).unwrap();
    Twin { machine, errors }
}

fn bench(c: &mut Criterion) {
    let twin = twin();
    let mut workspace = Workspace::new(&twin.machine);
    let r = 3e-3;
    let sphere = Sphere {
        centre: Vector::new(0.06, 0.0, 0.15),
        radius: 0.0125,
    };
    let frame = LinearFrame::at(&twin.machine, &AxisValues::ZERO).unwrap();
    let start_tip = sphere.centre + Vector::new(0.6, 0.0, 0.8) * (sphere.radius + r + 2e-3);
    let state = MachineState::at(frame.axes_for(start_tip));
    let direction = -Vector::new(0.6, 0.0, 0.8);

    let mut group = c.benchmark_group("touch");
    group.bench_function("sphere_closed_form", |b| {
        b.iter(|| {
            let pose =
                twin.errors
                    .workpiece_from_tool(&twin.machine, &mut workspace, black_box(&state));
            let approach = Approach::new(pose.translation, direction).unwrap();
            black_box(sphere.touch(r, &approach, 0.01).unwrap())
        })
    });
    let cube = std::sync::Arc::new(
        Mesh::read(
            concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/probe/cube.stl"),
            1e-3,
        )
        .unwrap()
        .placed(&mtwin::math::Pose::from_translation(Vector::new(
            -0.02, -0.02, 0.13,
        ))),
    );
    group.bench_function("mesh_parry", |b| {
        b.iter(|| {
            let pose =
                twin.errors
                    .workpiece_from_tool(&twin.machine, &mut workspace, black_box(&state));
            let approach = Approach::new(pose.translation, -Vector::X).unwrap();
            black_box(cube.touch(r, &approach, 0.1).unwrap())
        })
    });
    let cylinder = Cylinder::new(0.05, 0.02);
    let cylinder_pose = ParryPose::rotation(Vector::X * std::f64::consts::FRAC_PI_2)
        .prepend_translation(Vector::ZERO);
    let cylinder_pose = ParryPose::from_parts(Vector::new(0.02, 0.0, 0.15), cylinder_pose.rotation);
    group.bench_function("cylinder_parry_gjk", |b| {
        b.iter(|| {
            let pose =
                twin.errors
                    .workpiece_from_tool(&twin.machine, &mut workspace, black_box(&state));
            black_box(
                cast_shapes(
                    &ParryPose::from_translation(pose.translation),
                    -Vector::X,
                    &Ball::new(r),
                    &cylinder_pose,
                    Vector::ZERO,
                    &cylinder,
                    ShapeCastOptions::with_max_time_of_impact(0.1),
                )
                .unwrap(),
            )
        })
    });
    group.finish();

    let probe = TouchProbe {
        stylus_radius: r,
        radius_error: 0.5e-6,
        pretravel: 1e-6,
        lobing: 0.5e-6,
        lobing_phase: 0.0,
        pretravel_axial: 2e-6,
        repeatability: 0.25e-6,
        feed: 0.004,
        latency: 5e-5,
    };
    let probing = frame.move_from(start_tip, direction, 4e-3);
    assert_eq!(probing.start[Axis::A], 0.0);
    touch_bench(
        c,
        "probe/touch",
        &probe,
        &twin,
        &Target::Sphere(sphere),
        &probing,
    );
    // The same on the cube mesh, from 2 mm off its +X face: each fixed-point step a parry cast.
    let start = Vector::new(0.02 + r + 2e-3, 0.0, 0.15);
    let probing = frame.move_from(start, -Vector::X, 4e-3);
    let target = Target::Mesh(cube);
    touch_bench(c, "probe/touch_mesh", &probe, &twin, &target, &probing);
}

/// One whole probe touch of `target` along `probing`, as a cycle makes it.
fn touch_bench(
    c: &mut Criterion,
    name: &str,
    probe: &TouchProbe,
    twin: &Twin,
    target: &Target,
    probing: &mtwin::kinds::probe::ProbeMove,
) {
    let mut workspace = Workspace::new(&twin.machine);
    let mut rng = seeded_rng(1, "bench");
    c.bench_function(name, |b| {
        b.iter(|| {
            black_box(
                probe
                    .touch(twin, &mut workspace, target, black_box(probing), &mut rng)
                    .unwrap(),
            )
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
