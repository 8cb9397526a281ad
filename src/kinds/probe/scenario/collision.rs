//! Every probing move swept with the machine's bodies and the probe's against the workpiece
//! side and the artefacts: the first collision.

use crate::kinds::probe::cycles::{Cycle, Target};
use crate::machine::{Axis, Machine};
use crate::math::{Real, Vector};

/// The probe's body in the spindle: a cylinder of this radius (m) from [`PROBE_BODY_FROM`]
/// above the stylus tip to the spindle nose, 150 mm above it (a 50 mm stylus on a Ø 40 mm
/// probe). The stylus itself is not checked: touching the artefact is its job.
pub const PROBE_BODY_RADIUS: Real = 0.020;
/// Where the probe's body starts above the stylus tip (m).
pub const PROBE_BODY_FROM: Real = 0.050;
/// The radius (m) of a calibration sphere's stem, from the table surface up to the sphere.
pub const STEM_RADIUS: Real = 0.005;
/// The time (s) the programme takes to move from one probing move to the next.
pub(super) const REPOSITION_S: Real = 1.0;

/// Sweeps every probing move (from its start to its full travel, at the probing feed, the
/// machine repositioning in a straight line of axis values between moves) with the machine's
/// bodies and the probe's against the workpiece side and the artefacts (spheres on their
/// stems, plate balls, mesh workpieces; a ring gauge's body is not modelled); the first
/// collision, with its cycle, feature and point (1-based).
pub(super) fn collision(
    machine: &Machine,
    cycles: &[Cycle],
    feed: Real,
) -> Option<(usize, usize, usize, crate::collision::Collision)> {
    let mut time = 0.0;
    for (c, cycle) in cycles.iter().enumerate() {
        // One scene per cycle: its artefact is on the table for that cycle only (a ball plate
        // moves between its placements).
        let scene = cycle_scene(machine, cycle);
        let mut path = Vec::new();
        let mut labels = Vec::new();
        for (f, feature) in cycle.features.iter().enumerate() {
            for (m, probing) in feature.moves.iter().enumerate() {
                let mut end = probing.start;
                for (axis, component) in [Axis::X, Axis::Y, Axis::Z]
                    .into_iter()
                    .zip(probing.direction.to_array())
                {
                    end[axis] += component * probing.max_travel;
                }
                if time > 0.0 {
                    time += REPOSITION_S;
                }
                labels.push((time, (c + 1, f + 1, m + 1)));
                path.push((time, probing.start));
                time += probing.max_travel / feed;
                path.push((time, end));
            }
        }
        if let Err(hit) = scene.sweep(machine, &path) {
            let (_, (c, f, m)) = labels
                .iter()
                .rev()
                .find(|(t, _)| *t <= hit.time)
                .copied()
                .unwrap_or((0.0, (c + 1, 1, 1)));
            return Some((c, f, m, hit));
        }
    }
    None
}

/// The machine without its `tool` link, the probe's body in its place, and the artefacts of
/// `cycle` the stylus does not touch by design: the stems, and what the probe's body could
/// meet (a sphere, a plate's balls, a mesh workpiece).
fn cycle_scene(machine: &Machine, cycle: &Cycle) -> crate::collision::Scene {
    use crate::collision::{Mount, Scene, SharedShape, Solid};
    let at = crate::math::Pose::from_translation;
    let mut scene = Scene::of_machine(machine, &["tool"]);
    let length = 0.150 - PROBE_BODY_FROM;
    scene.attach(
        "probe body",
        Mount::Tool,
        at(Vector::new(0.0, 0.0, PROBE_BODY_FROM + length / 2.0)),
        Solid::Cylinder(PROBE_BODY_RADIUS, length),
    );
    for (f, feature) in cycle.features.iter().enumerate() {
        let name = format!("artefact {}", f + 1);
        match &feature.target {
            Target::Sphere(sphere) => {
                scene.attach(
                    &name,
                    Mount::Workpiece,
                    at(sphere.centre),
                    Solid::Sphere(sphere.radius),
                );
                let stem = sphere.centre.z - sphere.radius;
                if stem > 1e-6 {
                    scene.attach(
                        &format!("{name} stem"),
                        Mount::Workpiece,
                        at(Vector::new(sphere.centre.x, sphere.centre.y, stem / 2.0)),
                        Solid::Cylinder(STEM_RADIUS, stem),
                    );
                }
            }
            Target::Plate(plate) => {
                for centre in &plate.centres {
                    scene.attach(
                        "plate ball",
                        Mount::Workpiece,
                        at(*centre),
                        Solid::Sphere(plate.radius),
                    );
                }
            }
            Target::Mesh(mesh) => scene.attach_shape(
                "mesh workpiece",
                Mount::Workpiece,
                crate::math::Pose::IDENTITY,
                SharedShape::new(mesh.shape().clone()),
            ),
            Target::Ring(_) => {}
        }
    }
    scene
}
