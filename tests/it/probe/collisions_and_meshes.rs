//! Cycles that collide, meshes and plates set on edge.

use super::*;

#[test]
fn a_cycle_that_drives_the_head_into_the_trunnion_is_refused_naming_the_bodies() {
    // The calibration sphere 100 mm in front of the C axis, probed with the table tilted: at
    // A = 95° the head clears the cradle (which stands on edge, 175 mm above the A axis), at
    // 110° the approach brings the head down onto it.
    let base = std::fs::read_to_string(scenarios().join("trunnion5_probe_sphere.toml")).unwrap();
    let at = |a: &str| {
        let start = base.find("rotary = [").unwrap();
        let end = start + base[start..].find("\n]").unwrap() + 2;
        let text = format!(
            "{}rotary = [{{ a_deg = {a}, c_deg = 0.0 }}]{}",
            &base[..start],
            &base[end..]
        )
        .replacen(
            "centre_mm = [60.0, 0.0, 150.0]",
            "centre_mm = [0.0, -100.0, 100.0]",
            1,
        );
        load_text(&text)
    };
    assert!(at("95.0").is_ok());
    let refused = at("110.0").unwrap_err().to_string();
    assert!(
        refused.contains("cycle 1, feature 1, point 1: the head (tool side) would touch the cradle (workpiece side)")
            && refused.contains("A 110.000°"),
        "{refused}"
    );
}

#[test]
fn mesh_points_are_probed_along_the_surface_normal_and_land_on_their_facet() {
    // The cube (40 mm, its corner at (−150, −50, 100) mm, turned 15° about z) on vmc3, probed
    // with an ideal probe on no errors: the surface point the analysis reports (latched centre
    // + r along the approach, in machine axes) plus vmc3's tool tip at axes zero, (−380, −205,
    // 100) mm from the table centre (the URDF), must lie on the facet's plane. For the third
    // point that is the face x' = 0 of the turned cube: n = −(cos 15°, sin 15°, 0) through the
    // corner.
    let (machine, mut test) = scenario("vmc3_probe_ring_mesh.toml");
    ideal(&mut test);
    let (_, evaluation) = run(&common::twin(&machine, &[]), &test);
    let json = evaluation.to_json();
    let surface = &json["mesh_points"][2]["surface_mm"];
    let p = Vector::new(
        surface[0].as_f64().unwrap() - 380.0,
        surface[1].as_f64().unwrap() - 205.0,
        surface[2].as_f64().unwrap() + 100.0,
    );
    let (c, s) = (15f64.to_radians().cos(), 15f64.to_radians().sin());
    let height = -(c * (p.x + 150.0) + s * (p.y + 50.0));
    assert!(height.abs() < 1e-6, "{height} mm off the face");
    // An approach 17° off the normal is refused: the radius would be compensated wrongly.
    let base = std::fs::read_to_string(scenarios().join("vmc3_probe_ring_mesh.toml")).unwrap();
    let off = base.replacen(
        "direction = [0.9659258263, 0.2588190451, 0.0]",
        "direction = [1.0, 0.0, 0.0]",
        1,
    );
    let error = load_text(&off).unwrap_err().to_string();
    assert!(
        error.contains("points[2].direction") && error.contains("15.00° off the surface normal"),
        "{error}"
    );
}

#[test]
fn the_25_point_pattern_is_refused_on_a_plate_set_on_edge() {
    // ISO 10360-5's 25 points cover the whole ball down to its equator all round; on a plate
    // standing on edge (put in the third placement here) the plate hides the back half.
    let base = std::fs::read_to_string(scenarios().join("vmc3_ballplate.toml")).unwrap();
    let upright = base.replacen("points = 5", "points = 25", 1).replacen(
        "{ origin_mm = [120.0, -160.0, 200.0], along_row = [0.0, 1.0, 0.0], across_rows = [-1.0, 0.0, 0.0] }",
        "{ origin_mm = [-160.0, 0.0, 130.0], along_row = [1.0, 0.0, 0.0], across_rows = [0.0, 0.0, 1.0] }",
        1,
    );
    assert!(upright.contains("across_rows = [0.0, 0.0, 1.0]"));
    let error = load_text(&upright).unwrap_err().to_string();
    assert!(
        error.contains("placements[2]") && error.contains("the plate hides its back half"),
        "{error}"
    );
}

#[test]
fn probing_a_plate_on_edge_from_above_is_refused_where_the_head_meets_the_balls_above() {
    // A 4-row plate standing on edge (rows 80 mm apart in z) probed with a vertical stylus:
    // while the lowest row is probed, the spindle head and the probe's body (from 50 mm above
    // the tip) come down in front of the balls 80 mm higher, 12 mm from their centres, which
    // a 10 mm ball and a 20 mm body cannot clear. The artefacts are colliders of the cycle
    // that probes them only (the plate is moved between placements).
    let base = std::fs::read_to_string(scenarios().join("vmc3_ballplate.toml")).unwrap();
    let upright = base.replacen(
        "{ origin_mm = [120.0, -160.0, 200.0], along_row = [0.0, 1.0, 0.0], across_rows = [-1.0, 0.0, 0.0] }",
        "{ origin_mm = [-160.0, 0.0, 130.0], along_row = [1.0, 0.0, 0.0], across_rows = [0.0, 0.0, 1.0] }",
        1,
    );
    let error = load_text(&upright).unwrap_err().to_string();
    assert!(
        error.contains("cycle 3, feature 1") && error.contains("would touch the plate ball"),
        "{error}"
    );
    assert!(load_text(&base).is_ok());
}
