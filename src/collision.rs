//! Collision checks of programmes: the machine's bodies and an instrument's, placed by the
//! forward kinematics along a path, checked pair by pair with parry (reached through rapier's
//! re-export) before a test runs.
//!
//! # What is checked
//!
//! Every body on the **tool side** (moved by an axis of the tool branch, or attached to the
//! `tool` frame) against every body on the **workpiece side** (moved by an axis of the workpiece
//! branch, or attached to the `workpiece` frame). Bodies fixed to the bed are not checked
//! against the sides: the URDF boxes of a column and its head or of a bed and its saddle
//! overlap by design, and the travel limits keep the carriages on their guideways.
//!
//! The shapes are the URDF `<visual>` primitives (boxes, cylinders, capsules, spheres); mesh
//! visuals are left out (said by [`Scene::skipped`]). parry's cylinders and capsules run along
//! y where URDF's run along z, and its cuboids take half-extents: both are converted here.
//!
//! # How a path is swept
//!
//! Between two samples the axes move linearly. Each segment is cut into steps over which no
//! point of a body moves more than [`MAX_STEP`] (linear travel plus rotary travel times the
//! reach of the machine), and the sweep advances conservatively: with a clearance `d` at one
//! step, the next `d` of motion cannot close it, so the pairs are checked again only there.
//! A contact thinner than [`MAX_STEP`] between two checked steps can pass unseen: this is a
//! check of programmes against gross collisions (a head into a trunnion), not a clearance
//! measurement.

use crate::machine::{Axis, AxisValues, Machine, Shape, Side, Workspace};
use crate::math::{Pose, Real, Vector};
use rapier3d_f64::parry::math::Pose as ParryPose;
use rapier3d_f64::parry::query;
pub use rapier3d_f64::parry::shape::SharedShape;
use rapier3d_f64::parry::shape::{Ball, Capsule, Cuboid, Cylinder};

/// The largest motion of any body point between two checked steps (m).
pub const MAX_STEP: Real = 0.5e-3;

/// A solid, in its own frame (cylinders and capsules along z, as in URDF).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Solid {
    /// A box with these side lengths (m).
    Box(Vector),
    /// A cylinder along z, centred on its origin (radius, length; m).
    Cylinder(Real, Real),
    /// A capsule along z (radius, length between the caps; m).
    Capsule(Real, Real),
    /// A sphere (radius, m).
    Sphere(Real),
}

/// Where a collider hangs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mount {
    /// A URDF body: its index in [`Machine::bodies`].
    Body(usize),
    /// The `tool` frame (an instrument in the spindle).
    Tool,
    /// The `workpiece` frame (an artefact or fixture on the table).
    Workpiece,
}

struct Collider {
    name: String,
    side: Side,
    mount: Mount,
    mount_from_shape: Pose,
    shape: SharedShape,
}

/// The bodies of a machine and an instrument, ready to be checked.
pub struct Scene {
    colliders: Vec<Collider>,
    skipped: Vec<String>,
    /// A bound on the distance of any body point from the machine's origin over the travel (m).
    reach: Real,
}

/// Two bodies touching at a sample of a path.
#[derive(Clone, Debug, PartialEq)]
pub struct Collision {
    /// Time along the path (s).
    pub time: Real,
    /// The tool-side body.
    pub tool_body: String,
    /// The workpiece-side body.
    pub workpiece_body: String,
    /// The axis values there (m, rad).
    pub position: AxisValues,
}

impl Collision {
    /// The axis values in file units (`X 325.000 mm, A -90.000°`), for messages.
    pub fn describe(&self, machine: &Machine) -> String {
        machine
            .axes()
            .iter()
            .filter(|info| info.axis != Axis::S)
            .map(|info| {
                let v = self.position[info.axis];
                if info.axis.is_linear() {
                    format!("{} {:.3} mm", info.axis, v * 1e3)
                } else {
                    format!("{} {:.3}°", info.axis, v.to_degrees())
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}

fn shared(solid: Solid) -> SharedShape {
    match solid {
        Solid::Box(size) => SharedShape::new(Cuboid::new(size / 2.0)),
        Solid::Cylinder(radius, length) => SharedShape::new(Cylinder::new(length / 2.0, radius)),
        Solid::Capsule(radius, length) => SharedShape::new(Capsule::new_y(length / 2.0, radius)),
        Solid::Sphere(radius) => SharedShape::new(Ball::new(radius)),
    }
}

/// parry's cylinders and capsules run along y: turn them onto URDF's z.
fn y_to_z(solid: Solid) -> Pose {
    match solid {
        Solid::Cylinder(..) | Solid::Capsule(..) => {
            Pose::from_rotation_x(std::f64::consts::FRAC_PI_2)
        }
        _ => Pose::IDENTITY,
    }
}

fn bounding_radius(solid: Solid) -> Real {
    match solid {
        Solid::Box(size) => size.length() / 2.0,
        Solid::Cylinder(r, l) => (r * r + l * l / 4.0).sqrt(),
        Solid::Capsule(r, l) => r + l / 2.0,
        Solid::Sphere(r) => r,
    }
}

impl Scene {
    /// The machine's bodies on the tool and workpiece sides, except the links named in
    /// `without` (e.g. the `tool` link when an instrument takes its place).
    pub fn of_machine(machine: &Machine, without: &[&str]) -> Scene {
        let mut scene = Scene {
            colliders: Vec::new(),
            skipped: Vec::new(),
            reach: 0.0,
        };
        let mut workspace = Workspace::new(machine);
        let mut frames = vec![Pose::IDENTITY; machine.bodies().len()];
        machine.world_from_bodies(&mut workspace, &AxisValues::ZERO, &mut frames);
        for (index, body) in machine.bodies().iter().enumerate() {
            let Some(side) = body
                .moved_by
                .and_then(|axis| machine.axis(axis))
                .map(|info| info.side)
            else {
                continue;
            };
            if without.contains(&body.link.as_str()) {
                continue;
            }
            for visual in &body.visuals {
                let solid = match &visual.shape {
                    Shape::Box { size } => Solid::Box(*size),
                    Shape::Cylinder { radius, length } => Solid::Cylinder(*radius, *length),
                    Shape::Capsule { radius, length } => Solid::Capsule(*radius, *length),
                    Shape::Sphere { radius } => Solid::Sphere(*radius),
                    Shape::Mesh { file, .. } => {
                        scene.skipped.push(format!("{} ({file})", body.link));
                        continue;
                    }
                };
                let at_home = frames[index] * visual.link_from_shape;
                scene.reach = scene
                    .reach
                    .max(at_home.translation.length() + bounding_radius(solid));
                scene.push(
                    body.link.clone(),
                    side,
                    Mount::Body(index),
                    visual.link_from_shape,
                    solid,
                );
            }
        }
        // The carriages carry everything up to their travel away from home.
        scene.reach += machine
            .axes()
            .iter()
            .filter(|info| info.axis.is_linear())
            .filter_map(|info| info.limits.map(|(lo, hi)| lo.abs().max(hi.abs())))
            .sum::<Real>();
        scene
    }

    fn push(&mut self, name: String, side: Side, mount: Mount, mount_from: Pose, solid: Solid) {
        self.colliders.push(Collider {
            name,
            side,
            mount,
            mount_from_shape: mount_from * y_to_z(solid),
            shape: shared(solid),
        });
    }

    /// Adds an instrument's body on the tool side (`end = Mount::Tool`) or the workpiece side
    /// (`Mount::Workpiece`), at `end_from_shape` in that frame.
    pub fn attach(&mut self, name: &str, end: Mount, end_from_shape: Pose, solid: Solid) {
        let side = match end {
            Mount::Tool => Side::Tool,
            Mount::Workpiece | Mount::Body(_) => Side::Workpiece,
        };
        self.reach = self
            .reach
            .max(end_from_shape.translation.length() + bounding_radius(solid));
        self.push(name.to_string(), side, end, end_from_shape, solid);
    }

    /// Adds an instrument's or a workpiece's body of any parry shape (a mesh workpiece) at
    /// `end_from_shape` in the frame of `end`.
    pub fn attach_shape(
        &mut self,
        name: &str,
        end: Mount,
        end_from_shape: Pose,
        shape: SharedShape,
    ) {
        let side = match end {
            Mount::Tool => Side::Tool,
            Mount::Workpiece | Mount::Body(_) => Side::Workpiece,
        };
        let aabb = shape.compute_local_aabb();
        let radius =
            (aabb.maxs - aabb.mins).length() / 2.0 + ((aabb.maxs + aabb.mins) / 2.0).length();
        self.reach = self.reach.max(end_from_shape.translation.length() + radius);
        self.colliders.push(Collider {
            name: name.to_string(),
            side,
            mount: end,
            mount_from_shape: end_from_shape,
            shape,
        });
    }

    /// The bodies left out of the check (mesh visuals).
    pub fn skipped(&self) -> &[String] {
        &self.skipped
    }

    /// The smallest distance between a tool-side and a workpiece-side body at `position`
    /// (0 when they touch or overlap), and the pair. `placed` is scratch, one pose per collider.
    fn clearance(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        position: &AxisValues,
        frames: &mut [Pose],
        placed: &mut [ParryPose],
    ) -> (Real, usize, usize) {
        machine.world_from_bodies(workspace, position, frames);
        let (world_from_tool, world_from_workpiece) = workspace.world_from_ends();
        for (collider, pose) in self.colliders.iter().zip(placed.iter_mut()) {
            let mount = match collider.mount {
                Mount::Body(index) => frames[index],
                Mount::Tool => world_from_tool,
                Mount::Workpiece => world_from_workpiece,
            };
            let world = mount * collider.mount_from_shape;
            *pose =
                ParryPose::from_parts(world.translation, glam::DQuat::from_mat3(&world.matrix3));
        }
        let mut best = (Real::INFINITY, 0, 0);
        for (i, a) in self.colliders.iter().enumerate() {
            if a.side != Side::Tool {
                continue;
            }
            for (j, b) in self.colliders.iter().enumerate() {
                if b.side != Side::Workpiece {
                    continue;
                }
                let d = query::distance(&placed[i], a.shape.as_ref(), &placed[j], b.shape.as_ref())
                    .map_or(0.0, |d| d.distance);
                if d < best.0 {
                    best = (d, i, j);
                }
            }
        }
        best
    }

    /// Sweeps `path` (time, axis values; the axes move linearly between samples): the first
    /// collision, or the smallest clearance at the steps checked (every sample of the path,
    /// and between samples wherever the clearance could have closed) with its pair and time.
    pub fn sweep(
        &self,
        machine: &Machine,
        path: &[(Real, AxisValues)],
    ) -> Result<Clearance, Collision> {
        let mut workspace = Workspace::new(machine);
        let mut frames = vec![Pose::IDENTITY; machine.bodies().len()];
        let mut placed = vec![ParryPose::IDENTITY; self.colliders.len()];
        let mut smallest = Clearance {
            distance: Real::INFINITY,
            tool_body: String::new(),
            workpiece_body: String::new(),
            time: 0.0,
        };
        // Motion since the last check, and the clearance found there.
        let mut moved = Real::INFINITY;
        let mut margin = 0.0;
        let mut previous: Option<(Real, AxisValues)> = None;
        for &(time, position) in path {
            let from = previous.unwrap_or((time, position));
            let span = self.motion_bound(machine, &from.1, &position);
            let steps = ((span / MAX_STEP).ceil() as usize).max(1);
            for k in 1..=steps {
                let f = k as Real / steps as Real;
                moved += span / steps as Real;
                // Every programmed sample is checked; between them, only where the clearance
                // could have closed.
                if moved < margin && k < steps {
                    continue;
                }
                let mut at = from.1;
                for info in machine.axes() {
                    at[info.axis] =
                        from.1[info.axis] + (position[info.axis] - from.1[info.axis]) * f;
                }
                let t = from.0 + (time - from.0) * f;
                let (d, i, j) =
                    self.clearance(machine, &mut workspace, &at, &mut frames, &mut placed);
                if d <= 0.0 {
                    return Err(Collision {
                        time: t,
                        tool_body: self.colliders[i].name.clone(),
                        workpiece_body: self.colliders[j].name.clone(),
                        position: at,
                    });
                }
                if d < smallest.distance {
                    smallest = Clearance {
                        distance: d,
                        tool_body: self.colliders[i].name.clone(),
                        workpiece_body: self.colliders[j].name.clone(),
                        time: t,
                    };
                }
                moved = 0.0;
                margin = d;
            }
            previous = Some((time, position));
        }
        Ok(smallest)
    }

    /// A bound on how far any body point moves relative to the other side between two axis
    /// values: linear travel plus rotary travel times the reach.
    fn motion_bound(&self, machine: &Machine, a: &AxisValues, b: &AxisValues) -> Real {
        machine
            .axes()
            .iter()
            .filter(|info| info.axis != Axis::S)
            .map(|info| {
                let change = (b[info.axis] - a[info.axis]).abs();
                if info.axis.is_linear() {
                    change
                } else {
                    change * self.reach
                }
            })
            .sum()
    }
}

/// The closest approach along a path that does not collide.
#[derive(Clone, Debug, PartialEq)]
pub struct Clearance {
    /// The smallest distance checked (m; infinite for an empty path).
    pub distance: Real,
    /// The tool-side body of the closest pair.
    pub tool_body: String,
    /// The workpiece-side body.
    pub workpiece_body: String,
    /// When (s).
    pub time: Real,
}
