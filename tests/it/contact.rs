//! Contact geometry against independent derivations: the touch of a stylus ball on a sphere, a
//! plane, a cylinder bore and plug, a ball plate and a mesh facet from arbitrary approach
//! vectors, each checked against a formula derived here (the textbook foot-of-perpendicular
//! forms, not the library's cancellation-free ones); the GJK tripwire (parry's ball–cylinder
//! cast within 50 nm of the closed form); the mesh readers and the closedness check; bad input.

use crate::common;

use mtwin::contact::{
    Approach, Artefact, BallPlate, ContactError, Cylinder, CylinderSide, HalfSpace, Mesh, Sphere,
};
use mtwin::math::{Real, Vector};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rapier3d_f64::parry::math::Pose as ParryPose;
use rapier3d_f64::parry::query::{ShapeCastOptions, cast_shapes};
use rapier3d_f64::parry::shape::{Ball, Cylinder as ParryCylinder};

const MM: Real = 1e-3;
const NM: Real = 1e-9;

fn data(name: &str) -> String {
    format!("{}/tests/data/probe/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn unit(rng: &mut ChaCha8Rng) -> Vector {
    loop {
        let v = Vector::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.length() > 0.1 && v.length() < 1.0 {
            return v.normalize();
        }
    }
}

#[test]
fn a_stylus_ball_touches_a_sphere_where_the_foot_of_the_perpendicular_says() {
    // The centre line meets the sphere of radius R + r at t = t⊥ − √((R + r)² − h²), with t⊥
    // the foot of the perpendicular from the sphere's centre on the line and h its distance.
    let mut rng = common::rng("sphere touch");
    let sphere = Sphere {
        centre: Vector::new(0.1, -0.05, 0.12),
        radius: 12.5 * MM,
    };
    let r = 1.5 * MM;
    for _ in 0..200 {
        let d = unit(&mut rng);
        // Aim at a point of the sphere's disc across d, start 20 mm back.
        let u = unit(&mut rng);
        let aim = sphere.centre + (u - d * d.dot(u)) * 5.0 * MM;
        let start = aim - d * 40.0 * MM;
        let to_centre = sphere.centre - start;
        let foot = d.dot(to_centre);
        let h2 = to_centre.length_squared() - foot * foot;
        let rho = sphere.radius + r;
        let approach = Approach::new(start, d * 3.0).unwrap(); // any length: normalised
        let touch = sphere.touch(r, &approach, 0.1).unwrap();
        if h2 >= rho * rho {
            assert!(touch.is_none());
            continue;
        }
        let touch = touch.expect("a hit");
        let expected = foot - (rho * rho - h2).sqrt();
        assert!(
            (touch.travel - expected).abs() < 1e-15,
            "{} vs {expected}",
            touch.travel
        );
        // The contact point is on the sphere, r from the ball centre, along the normal.
        let point = touch.point(&approach, r);
        assert!(((point - sphere.centre).length() - sphere.radius).abs() < 1e-15);
        assert!(((approach.at(touch.travel) - point).length() - r).abs() < 1e-15);
        assert!((touch.normal - (point - sphere.centre) / sphere.radius).length() < 1e-12);
    }
}

#[test]
fn a_stylus_ball_touches_a_plane_at_its_height_over_the_closing_speed() {
    let mut rng = common::rng("plane touch");
    let r = 2.0 * MM;
    for _ in 0..200 {
        let normal = unit(&mut rng);
        let face = HalfSpace {
            point: Vector::new(0.2, 0.1, -0.3),
            normal,
        };
        let d = unit(&mut rng);
        let start = face.point + normal * 10.0 * MM + unit(&mut rng) * 5.0 * MM;
        let approach = Approach::new(start, d).unwrap();
        let touch = face.touch(r, &approach, 1.0).unwrap();
        let height = normal.dot(start - face.point) - r;
        if normal.dot(d) >= 0.0 {
            assert!(touch.is_none(), "moving away never touches");
            continue;
        }
        let expected = height / -normal.dot(d);
        let touch = touch.expect("a hit");
        assert!((touch.travel - expected).abs() < 1e-14 * expected.max(1e-3));
        // The contact point lies on the plane.
        assert!(normal.dot(touch.point(&approach, r) - face.point).abs() < 1e-15);
    }
}

/// The line `s + t·d` across the axis meets the circle of radius ρ at the roots of
/// `|d⊥|² t² + 2 (s⊥·d⊥) t + |s⊥|² − ρ² = 0`: the textbook quadratic formula.
fn textbook_roots(cyl: &Cylinder, start: Vector, d: Vector, rho: Real) -> Option<(Real, Real)> {
    let across = |v: Vector| v - cyl.axis * cyl.axis.dot(v);
    let (s, e) = (across(start - cyl.point), across(d));
    let (a, b, c) = (e.dot(e), 2.0 * s.dot(e), s.dot(s) - rho * rho);
    let disc = b * b - 4.0 * a * c;
    (disc >= 0.0 && a > 0.0).then(|| {
        (
            (-b - disc.sqrt()) / (2.0 * a),
            (-b + disc.sqrt()) / (2.0 * a),
        )
    })
}

#[test]
fn a_stylus_ball_touches_a_ring_gauge_bore_and_a_plug() {
    let mut rng = common::rng("cylinder touch");
    let r = 1.5 * MM;
    for _ in 0..200 {
        let axis = unit(&mut rng);
        let mut bore = Cylinder {
            point: Vector::new(0.05, 0.02, 0.1),
            axis,
            radius: 25.0 * MM,
            side: CylinderSide::Bore,
        };
        // Inside the bore, anywhere the ball fits, any direction not along the axis.
        let offset = unit(&mut rng) * rng.random_range(0.0..20.0) * MM;
        let start = bore.point + offset;
        let d = unit(&mut rng);
        let approach = Approach::new(start, d).unwrap();
        let touch = bore.touch(r, &approach, 1.0).unwrap().expect("the wall");
        let (_, exit) = textbook_roots(&bore, start, d, bore.radius - r).unwrap();
        assert!(
            (touch.travel - exit).abs() < 1e-14,
            "{} vs {exit}",
            touch.travel
        );
        // The contact point is on the wall; the normal points to the axis.
        let point = touch.point(&approach, r);
        let radial = (point - bore.point) - axis * axis.dot(point - bore.point);
        assert!((radial.length() - bore.radius).abs() < 1e-14);
        assert!((touch.normal + radial / bore.radius).length() < 1e-9);

        // The same cylinder as a plug, from 60 mm out toward a point near the axis.
        bore.side = CylinderSide::Plug;
        let aim = bore.point + unit(&mut rng) * 10.0 * MM;
        let start = aim - d * 60.0 * MM;
        let radial = (start - bore.point) - axis * axis.dot(start - bore.point);
        if radial.length() <= bore.radius + r {
            continue; // a start along the axis, inside the plug
        }
        let approach = Approach::new(start, d).unwrap();
        match (
            bore.touch(r, &approach, 1.0).unwrap(),
            textbook_roots(&bore, start, d, bore.radius + r),
        ) {
            (Some(touch), Some((entry, _))) if entry >= 0.0 => {
                assert!(
                    (touch.travel - entry).abs() < 1e-12,
                    "{} vs {entry}",
                    touch.travel
                )
            }
            (None, None) => {}
            (None, Some((entry, _))) => assert!(entry < 0.0),
            (touch, roots) => panic!("{touch:?} vs {roots:?}"),
        }
    }
}

#[test]
fn the_ball_plate_reports_the_first_ball_on_the_way() {
    let plate = BallPlate::grid(
        Vector::ZERO,
        Vector::X,
        Vector::Y,
        80.0 * MM,
        3,
        4,
        10.0 * MM,
    );
    assert_eq!(plate.centres.len(), 12);
    assert_eq!(plate.centres[5], Vector::new(0.08, 0.08, 0.0)); // row 1, column 1
    // Along row 1 from beyond its last ball toward −x: ball 7 (row 1, column 3) first, at
    // 400 − 240 − 12 mm.
    let r = 2.0 * MM;
    let approach = Approach::new(Vector::new(0.4, 0.08, 0.0), -Vector::X).unwrap();
    let (index, touch) = plate.touch_indexed(r, &approach, 1.0).unwrap().unwrap();
    assert_eq!(index, 7);
    assert!((touch.travel - (0.4 - 0.24 - 0.012)).abs() < 1e-15);
    // Between the rows: nothing.
    let approach = Approach::new(Vector::new(0.4, 0.04, 0.0), -Vector::X).unwrap();
    assert!(plate.touch(r, &approach, 1.0).unwrap().is_none());
}

#[test]
fn a_stylus_ball_touches_an_oblique_mesh_facet_where_its_plane_says() {
    // The tetrahedron's oblique facet x/60 + y/50 + z/40 = 1 (mm): unit normal n ∝ (1/60,
    // 1/50, 1/40), plane n·x = h. A ball touching the facet's interior has its centre at
    // height r: t = (n·s − h − r)/(−n·d), and its contact point inside the triangle.
    let mesh = Mesh::read(data("tetra.obj"), MM).unwrap();
    let g = Vector::new(1.0 / 60.0, 1.0 / 50.0, 1.0 / 40.0);
    let n = g.normalize();
    let h = MM / g.length();
    let corners = [
        Vector::new(60.0, 0.0, 0.0) * MM,
        Vector::new(0.0, 50.0, 0.0) * MM,
        Vector::new(0.0, 0.0, 40.0) * MM,
    ];
    let centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
    let mut rng = common::rng("mesh facet");
    let r = 1.5 * MM;
    let mut worst: Real = 0.0;
    let mut tested = 0;
    for _ in 0..300 {
        let d = unit(&mut rng);
        if n.dot(d) > -0.3 {
            continue; // grazing or away
        }
        let u = unit(&mut rng);
        let aim = centroid + (u - n * n.dot(u)) * 6.0 * MM;
        let start = aim + n * r - d * 20.0 * MM;
        let approach = Approach::new(start, d).unwrap();
        let expected = (n.dot(start) - h - r) / -n.dot(d);
        let point = start + d * expected - n * r;
        // Inside the triangle, 1 mm clear of its edges (a touch there is on the face).
        let inside = (0..3).all(|k| {
            let (a, b) = (corners[k], corners[(k + 1) % 3]);
            let inward = n.cross(b - a).normalize();
            inward.dot(point - a) > 1.0 * MM
        });
        if !inside {
            continue;
        }
        let touch = mesh.touch(r, &approach, 0.1).unwrap().expect("the facet");
        worst = worst.max((touch.travel - expected).abs());
        assert!((touch.normal - n).length() < 1e-6, "{:?}", touch.normal);
        tested += 1;
    }
    assert!(tested > 50, "{tested}");
    eprintln!("mesh facet: worst |parry − plane| {worst:.3e} m over {tested} touches");
    assert!(worst < 1.0 * NM, "worst {:.3e} m", worst);
}

#[test]
fn the_mesh_cube_agrees_with_its_flat_faces() {
    // The cube's +z face from above at any angle: the half-space z ≤ 40 mm.
    let face = HalfSpace {
        point: Vector::new(0.0, 0.0, 40.0 * MM),
        normal: Vector::Z,
    };
    let mut rng = common::rng("mesh cube");
    for file in ["cube.stl", "cube_binary.stl", "cube.obj"] {
        let mesh = Mesh::read(data(file), MM).unwrap();
        assert_eq!(mesh.triangle_count(), 12, "{file}");
        assert!(
            (mesh.volume() - 64e-6).abs() < 1e-18,
            "{file}: {}",
            mesh.volume()
        );
        for _ in 0..50 {
            let mut d = unit(&mut rng);
            d.z = -d.z.abs().max(0.5);
            let d = d.normalize();
            let target = Vector::new(
                rng.random_range(10.0..30.0),
                rng.random_range(10.0..30.0),
                40.0,
            ) * MM;
            let start = target + Vector::Z * 2.0 * MM - d * 5.0 * MM;
            let approach = Approach::new(start, d).unwrap();
            let a = face.touch(2.0 * MM, &approach, 0.1).unwrap().unwrap();
            let m = mesh.touch(2.0 * MM, &approach, 0.1).unwrap().unwrap();
            assert!((a.travel - m.travel).abs() < 1.0 * NM, "{file}");
        }
        // Zero radius: the ray cast.
        let approach = Approach::new(Vector::new(0.02, 0.02, 0.05), -Vector::Z).unwrap();
        let touch = mesh.touch(0.0, &approach, 0.1).unwrap().unwrap();
        assert!((touch.travel - 0.01).abs() < 1e-12 && (touch.normal - Vector::Z).length() < 1e-9);
    }
}

#[test]
fn tripwire_parry_gjk_ball_against_cylinder_within_50_nm_of_the_closed_form() {
    // parry's cylinder axis is Y, URDF's and ours Z: the parry cylinder is turned +90° about
    // X (Y → Z). Approaches across the axis at mid-height, so the end faces play no part.
    let radius = 20.0 * MM;
    let half_height = 50.0 * MM;
    let analytic = Cylinder {
        point: Vector::ZERO,
        axis: Vector::Z,
        radius,
        side: CylinderSide::Plug,
    };
    let pose = ParryPose::rotation(Vector::X * std::f64::consts::FRAC_PI_2);
    assert!((pose.rotation * Vector::Y - Vector::Z).length() < 1e-15);
    let shape = ParryCylinder::new(half_height, radius);
    let r = 1.5 * MM;
    let mut rng = common::rng("tripwire");
    let mut worst: Real = 0.0;
    let mut tested = 0;
    for _ in 0..300 {
        let d = unit(&mut rng);
        if d.z.abs() > 0.3 {
            continue;
        }
        let aim = Vector::new(
            rng.random_range(-15.0..15.0),
            rng.random_range(-15.0..15.0),
            rng.random_range(-10.0..10.0),
        ) * MM;
        let start = aim - d * 60.0 * MM;
        let approach = Approach::new(start, d).unwrap();
        let exact = analytic
            .touch(r, &approach, 1.0)
            .unwrap_or_else(|e| panic!("{e}: start {start:?} d {d:?} aim {aim:?}"))
            .expect("a hit");
        if (approach.at(exact.travel).z).abs() > 30.0 * MM {
            continue;
        }
        let hit = cast_shapes(
            &ParryPose::from_translation(start),
            d,
            &Ball::new(r),
            &pose,
            Vector::ZERO,
            &shape,
            ShapeCastOptions::with_max_time_of_impact(1.0),
        )
        .unwrap()
        .expect("parry hits too");
        worst = worst.max((hit.time_of_impact - exact.travel).abs());
        tested += 1;
    }
    assert!(tested > 30, "{tested}");
    eprintln!("tripwire: worst |GJK − closed form| {worst:.3e} m");
    assert!(
        worst < 50.0 * NM,
        "GJK ball–cylinder off by {:.3e} m",
        worst
    );
}

#[test]
fn bad_queries_are_errors_not_panics() {
    let sphere = Sphere {
        centre: Vector::ZERO,
        radius: 0.01,
    };
    for d in [
        Vector::ZERO,
        Vector::new(Real::NAN, 0.0, 1.0),
        Vector::new(Real::INFINITY, 0.0, 0.0),
    ] {
        assert!(matches!(
            Approach::new(Vector::X, d),
            Err(ContactError::BadDirection { .. })
        ));
    }
    assert_eq!(
        Approach::new(Vector::new(Real::NAN, 0.0, 0.0), Vector::X),
        Err(ContactError::BadStart)
    );
    let approach = Approach::new(Vector::new(0.1, 0.0, 0.0), -Vector::X).unwrap();
    assert_eq!(
        sphere.touch(-1.0, &approach, 1.0),
        Err(ContactError::BadRadius(-1.0))
    );
    assert_eq!(
        sphere.touch(0.001, &approach, 0.0),
        Err(ContactError::BadTravel(0.0))
    );
    // Starting inside: an error; a miss within the travel: none.
    let inside = Approach::new(Vector::new(0.005, 0.0, 0.0), Vector::X).unwrap();
    assert_eq!(
        sphere.touch(0.001, &inside, 1.0),
        Err(ContactError::StartsInContact)
    );
    assert_eq!(sphere.touch(0.001, &approach, 0.05), Ok(None));
    let ring = Cylinder {
        point: Vector::ZERO,
        axis: Vector::Z,
        radius: 0.01,
        side: CylinderSide::Bore,
    };
    // A ball that does not fit, and one along the axis (never reaches the wall).
    let along = Approach::new(Vector::ZERO, Vector::Z).unwrap();
    assert_eq!(
        ring.touch(0.02, &along, 1.0),
        Err(ContactError::StartsInContact)
    );
    assert_eq!(ring.touch(0.001, &along, 1.0), Ok(None));
}

#[test]
fn meshes_that_do_not_parse_or_are_not_closed_are_refused_with_the_place() {
    let error = |name: &str| Mesh::read(data(name), MM).unwrap_err().to_string();
    let open = error("open_box.obj");
    assert!(
        open.contains("open_box.obj:") && open.contains("not closed"),
        "{open}"
    );
    let flipped = error("flipped.obj");
    assert!(flipped.contains("inconsistently oriented"), "{flipped}");
    let inward = error("inside_out.obj");
    assert!(inward.contains("face inward"), "{inward}");
    let index = Mesh::read(data("bad_index.obj"), MM).unwrap_err();
    assert_eq!((index.line, index.column), (Some(4), Some(7)), "{index}");
    assert!(index.to_string().contains("vertex index 9"), "{index}");
    let keyword = Mesh::read(data("bad_keyword.stl"), MM).unwrap_err();
    assert_eq!(
        (keyword.line, keyword.column),
        (Some(5), Some(7)),
        "{keyword}"
    );
    assert!(
        keyword
            .to_string()
            .contains("expected `vertex`, found `vertx`")
    );
    assert!(error("nowhere.stl").contains("cannot read"));
    let format = Mesh::from_obj(b"v 0 0 0\ncurv 0 1 1 2\n", "x.obj", MM).unwrap_err();
    assert_eq!(format.line, Some(2));
    // A truncated binary STL is neither binary nor text.
    let mut bytes = std::fs::read(data("cube_binary.stl")).unwrap();
    bytes.truncate(600);
    bytes[0] = 0xff;
    let truncated = Mesh::from_stl(&bytes, "cut.stl", MM).unwrap_err();
    assert!(
        truncated.to_string().contains("neither a binary STL"),
        "{truncated}"
    );
    // Degenerate facet.
    let flat = Mesh::from_obj(b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "flat.obj", MM).unwrap_err();
    assert!(flat.to_string().contains("degenerate"), "{flat}");
}
