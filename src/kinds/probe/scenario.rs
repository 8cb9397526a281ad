//! The `[probe]` section: a touch-trigger probe in the spindle and the cycles it runs.
//!
//! ```toml
//! [probe]
//! stylus_diameter_mm = 6.0          # the diameter the controller uses (its calibrated value)
//! stylus_radius_error_um = 0.0      # true − believed stylus radius
//! pretravel_um = 1.0                # lateral pre-travel δ0
//! lobing_um = 0.5                   # 3-lobe amplitude δ3: δ(θ) = δ0 + δ3·cos 3(θ − θ0)
//! lobing_phase_deg = 0.0            # θ0, from the tool frame's x axis
//! pretravel_axial_um = 2.0          # pre-travel along the stylus axis
//! repeatability_um = 0.25           # trigger scatter, 1σ along the motion
//! feed_mm_per_min = 240.0           # approach speed
//! latency_ms = 0.0                  # trigger latency: the axes latch v·t further on
//! clearance_mm = 2.0                # each approach starts this far from the nominal surface
//! overtravel_mm = 2.0               # and may go this far past it before "no touch"
//!
//! [[probe.sphere]]                  # a calibration sphere (KinematicsOpt cycle 451 style)
//! diameter_mm = 25.0                # calibrated diameter
//! centre_mm = [100.0, 0.0, 150.0]   # on the table (workpiece frame)
//! points = 5                        # 4–24: (points − 1) around the tool axis + the pole; 25: ISO 10360-5
//! incidence_deg = 30.0              # elevation of the side points above the equator
//! rotary = [{ a_deg = 0.0, c_deg = 0.0 }, { a_deg = 0.0, c_deg = 90.0 }]   # default: all at 0
//!
//! [[probe.ring]]                    # a ring gauge: diameter and roundness
//! diameter_mm = 50.0
//! centre_mm = [0.0, 100.0, 120.0]   # the bore's centre at the probing height
//! points = 12
//! axis = [0.0, 0.0, 1.0]            # the bore's axis (default: the tool axis)
//! rotary = { c_deg = 0.0 }
//!
//! [[probe.ballplate]]               # a ball plate, set at one or more placements
//! rows = 4
//! columns = 5
//! pitch_mm = 80.0
//! ball_diameter_mm = 20.0
//! points = 5
//! incidence_deg = 30.0
//! placements = [{ origin_mm = [-160.0, -120.0, 60.0], along_row = [1, 0, 0], across_rows = [0, 1, 0] }]
//! ball_offsets_um = [[0.5, -0.2, 0.0], …]   # optional: each ball's offset from the grid, plate frame, as calibrated
//!
//! [[probe.mesh]]                    # points on a mesh workpiece
//! file = "data/part.stl"            # STL or OBJ, relative to the scenario; closed
//! units = "mm"                      # mm, m or in
//! origin_mm = [0.0, 0.0, 0.0]       # where the mesh's origin sits (workpiece frame)
//! rotation_deg = 0.0                # about the workpiece z axis
//! max_travel_mm = 10.0
//! points = [{ start_mm = [0.0, 0.0, 80.0], direction = [0.0, 0.0, -1.0] }]   # along the surface normal (within 1 mrad)
//! ```
//!
//! Every move is checked on the nominal chain: it must touch its artefact within its travel,
//! and start and end within every axis's travel.

use super::cycles::{
    Cycle, CycleKind, Feature, LinearFrame, ProbeMove, Target, ring_pattern, sphere_pattern,
};
use super::instrument::TouchProbe;
use crate::contact::{Approach, BallPlate, Cylinder, CylinderSide, Mesh, Sphere};
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, Rotation, Vector};
use crate::scenario::bounds::{self, Bound};
use crate::scenario::{Checker, Context, ScenarioError, ScenarioErrorKind};
use serde::Deserialize;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;
use toml::Spanned;

/// The raw `[probe]` section.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawProbe {
    stylus_diameter_mm: Spanned<Real>,
    stylus_radius_error_um: Option<Spanned<Real>>,
    pretravel_um: Option<Spanned<Real>>,
    lobing_um: Option<Spanned<Real>>,
    lobing_phase_deg: Option<Spanned<Real>>,
    pretravel_axial_um: Option<Spanned<Real>>,
    repeatability_um: Option<Spanned<Real>>,
    feed_mm_per_min: Option<Spanned<Real>>,
    latency_ms: Option<Spanned<Real>>,
    clearance_mm: Option<Spanned<Real>>,
    overtravel_mm: Option<Spanned<Real>>,
    #[serde(default)]
    sphere: Vec<Spanned<RawSphere>>,
    #[serde(default)]
    ring: Vec<Spanned<RawRing>>,
    #[serde(default)]
    ballplate: Vec<Spanned<RawPlate>>,
    #[serde(default)]
    mesh: Vec<Spanned<RawMesh>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct RawRotary {
    a_deg: Option<Real>,
    b_deg: Option<Real>,
    c_deg: Option<Real>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSphere {
    diameter_mm: Spanned<Real>,
    centre_mm: Spanned<[Real; 3]>,
    points: Option<Spanned<i64>>,
    incidence_deg: Option<Spanned<Real>>,
    rotary: Option<Spanned<Vec<RawRotary>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRing {
    diameter_mm: Spanned<Real>,
    centre_mm: Spanned<[Real; 3]>,
    points: Option<Spanned<i64>>,
    axis: Option<Spanned<[Real; 3]>>,
    rotary: Option<Spanned<RawRotary>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPlate {
    rows: Spanned<i64>,
    columns: Spanned<i64>,
    pitch_mm: Spanned<Real>,
    ball_diameter_mm: Spanned<Real>,
    points: Option<Spanned<i64>>,
    incidence_deg: Option<Spanned<Real>>,
    placements: Spanned<Vec<RawPlacement>>,
    ball_offsets_um: Option<Spanned<Vec<[Real; 3]>>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct RawPlacement {
    origin_mm: [Real; 3],
    along_row: Option<[Real; 3]>,
    across_rows: Option<[Real; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMesh {
    file: Spanned<String>,
    units: Option<Spanned<String>>,
    origin_mm: Option<Spanned<[Real; 3]>>,
    rotation_deg: Option<Spanned<Real>>,
    max_travel_mm: Option<Spanned<Real>>,
    rotary: Option<Spanned<RawRotary>>,
    points: Spanned<Vec<RawMeshPoint>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct RawMeshPoint {
    start_mm: [Real; 3],
    direction: [Real; 3],
}

/// A probe and the cycles it runs.
#[derive(Clone, Debug)]
pub struct ProbeTest {
    /// The instrument.
    pub probe: TouchProbe,
    /// The cycles, in the order of the section (spheres, rings, plate placements, meshes).
    pub cycles: Vec<Cycle>,
    /// The machine's name (for the tables' preamble).
    pub machine: String,
}

/// A finite value ≥ `min` (or > `min` when `strict`), with its default.
fn value(
    check: &Checker<'_>,
    v: &Option<Spanned<Real>>,
    key: &str,
    default: Real,
    min: Real,
    strict: bool,
) -> Result<Real, ScenarioError> {
    check.value(v, key, default, |x| {
        if x.is_finite() && (x > min || (!strict && x == min)) {
            Ok(x)
        } else {
            let relation = if strict { ">" } else { "≥" };
            Err(format!(
                "expected a finite number {relation} {min}, got {x}"
            ))
        }
    })
}

/// A value within `bound`, `default` when absent.
fn bounded(
    check: &Checker<'_>,
    v: &Option<Spanned<Real>>,
    key: &str,
    default: Real,
    bound: Bound,
) -> Result<Real, ScenarioError> {
    check.value(v, key, default, |x| bound.check(x))
}

/// How far a probe's trigger can lag, scatter or lobe (µm).
const TRIGGER_UM: Bound = Bound {
    lo: 0.0,
    hi: 1000.0,
    why: "a probe that triggers a millimetre late is not a probe",
};

/// A finite value, 0 by default.
fn finite(
    check: &Checker<'_>,
    v: &Option<Spanned<Real>>,
    key: &str,
) -> Result<Real, ScenarioError> {
    value(check, v, key, 0.0, Real::MIN, false)
}

/// A whole number within `range`, with its default.
fn count(
    check: &Checker<'_>,
    v: &Option<Spanned<i64>>,
    key: &str,
    default: usize,
    range: (usize, usize),
) -> Result<usize, ScenarioError> {
    check.value(v, key, default, |n| {
        if n >= range.0 as i64 && n <= range.1 as i64 {
            Ok(n as usize)
        } else {
            Err(format!("expected {} … {}, got {n}", range.0, range.1))
        }
    })
}

/// A point given in mm, in m.
fn point(check: &Checker<'_>, v: &Spanned<[Real; 3]>, key: &str) -> Result<Vector, ScenarioError> {
    let p = Vector::from_array(*v.get_ref());
    if p.is_finite() {
        Ok(p * M_PER_MM)
    } else {
        Err(check.fail(Some(v.span()), key, "expected three finite numbers (mm)"))
    }
}

/// The unit vector along `v`, which must have a length.
fn direction(
    check: &Checker<'_>,
    v: [Real; 3],
    span: Range<usize>,
    key: &str,
) -> Result<Vector, ScenarioError> {
    let d = Vector::from_array(v);
    if d.is_finite() && d.length() > 1e-12 {
        Ok(d.normalize())
    } else {
        Err(check.fail(
            Some(span),
            key,
            format!(
                "({}, {}, {}) has zero length or is not finite: an approach needs a direction",
                v[0], v[1], v[2]
            ),
        ))
    }
}

/// The probe test of a `[probe]` section; `scenario_dir` is the folder mesh files are relative
/// to.
pub fn probe_test(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawProbe>,
    scenario_dir: &Path,
) -> Result<ProbeTest, ScenarioError> {
    let p = raw.get_ref();
    let check = Checker::new(context, raw.span(), "probe");
    let diameter = *p.stylus_diameter_mm.get_ref();
    if !(diameter.is_finite() && diameter > 0.0 && diameter <= 100.0) {
        return Err(check.fail(
            Some(p.stylus_diameter_mm.span()),
            "stylus_diameter_mm",
            format!(
                "expected a positive diameter up to 100 mm, got {}",
                crate::math::readable(diameter)
            ),
        ));
    }
    let stylus_radius = diameter / 2.0 * M_PER_MM;
    let radius_error = bounded(
        &check,
        &p.stylus_radius_error_um,
        "stylus_radius_error_um",
        0.0,
        Bound::symmetric(1000.0, "a stylus a millimetre off its calibration"),
    )? * M_PER_UM;
    if stylus_radius + radius_error <= 0.0 {
        return Err(check.fail(
            p.stylus_radius_error_um.as_ref().map(|v| v.span()),
            "stylus_radius_error_um",
            "leaves no stylus ball",
        ));
    }
    let probe = TouchProbe {
        stylus_radius,
        radius_error,
        pretravel: bounded(&check, &p.pretravel_um, "pretravel_um", 0.0, TRIGGER_UM)? * M_PER_UM,
        lobing: bounded(&check, &p.lobing_um, "lobing_um", 0.0, TRIGGER_UM)? * M_PER_UM,
        lobing_phase: bounded(
            &check,
            &p.lobing_phase_deg,
            "lobing_phase_deg",
            0.0,
            Bound::symmetric(360.0, "a phase within one turn"),
        )? * RAD_PER_DEG,
        pretravel_axial: bounded(
            &check,
            &p.pretravel_axial_um,
            "pretravel_axial_um",
            0.0,
            TRIGGER_UM,
        )? * M_PER_UM,
        repeatability: bounded(
            &check,
            &p.repeatability_um,
            "repeatability_um",
            0.0,
            TRIGGER_UM,
        )? * M_PER_UM,
        feed: bounded(
            &check,
            &p.feed_mm_per_min,
            "feed_mm_per_min",
            240.0,
            bounds::FEED_MM_PER_MIN,
        )? * M_PER_MM
            / 60.0,
        latency: bounded(
            &check,
            &p.latency_ms,
            "latency_ms",
            0.0,
            Bound {
                lo: 0.0,
                hi: 1000.0,
                why: "a trigger latched a second late",
            },
        )? * 1e-3,
    };
    if probe.lobing > probe.pretravel {
        return Err(check.fail(
            p.lobing_um.as_ref().map(|v| v.span()),
            "lobing_um",
            "is larger than pretravel_um: the pre-travel would be negative in some directions",
        ));
    }
    let approach = Bound {
        lo: 0.001,
        hi: 100.0,
        why: "1 µm to 100 mm of approach: a probing move, not a traverse",
    };
    let clearance = bounded(&check, &p.clearance_mm, "clearance_mm", 2.0, approach)? * M_PER_MM;
    let overtravel = bounded(&check, &p.overtravel_mm, "overtravel_mm", 2.0, approach)? * M_PER_MM;
    let plan = Plan {
        check: &check,
        machine,
        r: stylus_radius,
        clearance,
        overtravel,
    };
    let mut cycles = Vec::new();
    for (n, sphere) in p.sphere.iter().enumerate() {
        cycles.push(plan.sphere(sphere, &format!("sphere[{n}]"))?);
    }
    for (n, ring) in p.ring.iter().enumerate() {
        cycles.push(plan.ring(ring, &format!("ring[{n}]"))?);
    }
    for (n, plate) in p.ballplate.iter().enumerate() {
        cycles.extend(plan.plate(plate, &format!("ballplate[{n}]"))?);
    }
    for (n, mesh) in p.mesh.iter().enumerate() {
        cycles.push(plan.mesh(mesh, &format!("mesh[{n}]"), scenario_dir)?);
    }
    if cycles.is_empty() {
        return Err(context.error(Some(raw.span()), ScenarioErrorKind::Nothing, "probe: no cycle: add a [[probe.sphere]], [[probe.ring]], [[probe.ballplate]] or [[probe.mesh]]"));
    }
    if let Some((cycle, feature, point, hit)) = collision(machine, &cycles, probe.feed) {
        return Err(context.error(
            Some(raw.span()),
            ScenarioErrorKind::Value,
            format!(
                "probe: cycle {cycle}, feature {feature}, point {point}: the {} (tool side) would touch the {} (workpiece side), {:.2} s into the probing, at {}",
                hit.tool_body,
                hit.workpiece_body,
                hit.time,
                hit.describe(machine)
            ),
        ));
    }
    Ok(ProbeTest {
        probe,
        cycles,
        machine: machine.name().to_string(),
    })
}

/// How far (rad) a mesh point's approach may be from the surface normal: 1 mrad leaves
/// `r·θ²/2` (under 1 nm for a 3 mm stylus) along the normal.
pub const MESH_NORMAL_TOLERANCE: Real = 1e-3;

/// The probe's body in the spindle: a cylinder of this radius (m) from [`PROBE_BODY_FROM`]
/// above the stylus tip to the spindle nose, 150 mm above it (a 50 mm stylus on a Ø 40 mm
/// probe). The stylus itself is not checked: touching the artefact is its job.
pub const PROBE_BODY_RADIUS: Real = 0.020;
/// Where the probe's body starts above the stylus tip (m).
pub const PROBE_BODY_FROM: Real = 0.050;
/// The radius (m) of a calibration sphere's stem, from the table surface up to the sphere.
pub const STEM_RADIUS: Real = 0.005;
/// The time (s) the programme takes to move from one probing move to the next.
const REPOSITION_S: Real = 1.0;

/// Sweeps every probing move (from its start to its full travel, at the probing feed, the
/// machine repositioning in a straight line of axis values between moves) with the machine's
/// bodies and the probe's against the workpiece side and the artefacts (spheres on their
/// stems, plate balls, mesh workpieces; a ring gauge's body is not modelled); the first
/// collision, with its cycle, feature and point (1-based).
fn collision(
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

/// Planning the cycles with the checks.
struct Plan<'a> {
    check: &'a Checker<'a>,
    machine: &'a Machine,
    r: Real,
    clearance: Real,
    overtravel: Real,
}

impl Plan<'_> {
    /// The rotary angles of `raw` (absent: 0), each on an axis the machine has, within travel.
    fn rotary(
        &self,
        raw: Option<RawRotary>,
        span: Range<usize>,
        key: &str,
    ) -> Result<AxisValues, ScenarioError> {
        let mut values = AxisValues::ZERO;
        let Some(raw) = raw else { return Ok(values) };
        for (axis, given) in [
            (Axis::A, raw.a_deg),
            (Axis::B, raw.b_deg),
            (Axis::C, raw.c_deg),
        ] {
            let Some(deg) = given else { continue };
            let Some(info) = self.machine.axis(axis) else {
                return Err(self.check.fail(
                    Some(span),
                    key,
                    format!("machine \"{}\" has no axis {axis}", self.machine.name()),
                ));
            };
            let value = deg * RAD_PER_DEG;
            if !info.within_travel(value) {
                return Err(self.check.fail(
                    Some(span),
                    key,
                    format!(
                        "{axis} {deg}° is outside its travel, {}",
                        info.scenario_travel_text()
                    ),
                ));
            }
            values[axis] = value;
        }
        Ok(values)
    }

    /// The linear axes' frame at `rotary`, which must not be degenerate.
    fn frame(
        &self,
        rotary: &AxisValues,
        span: Range<usize>,
        key: &str,
    ) -> Result<LinearFrame, ScenarioError> {
        LinearFrame::at(self.machine, rotary).ok_or_else(|| {
            self.check.fail(
                Some(span),
                key,
                "the linear axes are degenerate at these rotary angles",
            )
        })
    }

    /// Checks a planned move on the nominal chain: it touches `target` within its travel, and
    /// starts and ends (`overtravel` past the touch) within every axis's travel.
    #[allow(clippy::too_many_arguments)]
    fn checked_move(
        &self,
        frame: &LinearFrame,
        target: &Target,
        start: Vector,
        direction: Vector,
        max_travel: Real,
        span: Range<usize>,
        key: &str,
    ) -> Result<ProbeMove, ScenarioError> {
        let (r, overtravel) = (self.r, self.overtravel);
        let probing = frame.move_from(start, direction, max_travel);
        let at = |s: Real| {
            let mut axes = probing.start;
            for (axis, c) in [
                (Axis::X, probing.direction.x),
                (Axis::Y, probing.direction.y),
                (Axis::Z, probing.direction.z),
            ] {
                axes[axis] += c * s;
            }
            axes
        };
        let mm = |v: Vector| {
            format!(
                "({:.3}, {:.3}, {:.3}) mm",
                v.x / M_PER_MM,
                v.y / M_PER_MM,
                v.z / M_PER_MM
            )
        };
        let approach = Approach::new(start, direction)
            .map_err(|e| self.check.fail(Some(span.clone()), key, e))?;
        let touch = match target.touch(r, &approach, max_travel) {
            Ok(Some(t)) => t,
            Ok(None) => {
                return Err(self.check.fail(Some(span), key, format!(
                    "the approach from {} along ({:.4}, {:.4}, {:.4}) does not reach the artefact within {:.3} mm",
                    mm(start), direction.x, direction.y, direction.z, max_travel / M_PER_MM
                )));
            }
            Err(e) => {
                return Err(self.check.fail(
                    Some(span),
                    key,
                    format!("the approach from {}: {e}", mm(start)),
                ));
            }
        };
        for (what, axes) in [("starts", at(0.0)), ("ends", at(touch.travel + overtravel))] {
            if let Err((axis, value, (lower, upper))) = self.machine.check_limits(&axes) {
                let unit = if axis.is_linear() {
                    (M_PER_MM, "mm")
                } else {
                    (RAD_PER_DEG, "°")
                };
                return Err(self.check.fail(Some(span), key, format!(
                    "the approach toward the artefact {what} with {axis} at {:.3} {}, outside its travel {:.3} … {:.3}: the artefact cannot be reached there",
                    value / unit.0, unit.1, lower / unit.0, upper / unit.0
                )));
            }
        }
        Ok(probing)
    }

    fn diameter(&self, v: &Spanned<Real>, key: &str) -> Result<Real, ScenarioError> {
        let d = *v.get_ref();
        if d.is_finite() && d > 0.0 {
            Ok(d * M_PER_MM)
        } else {
            Err(self.check.fail(
                Some(v.span()),
                key,
                format!("expected a positive diameter, got {d}"),
            ))
        }
    }

    fn incidence(&self, v: &Option<Spanned<Real>>, key: &str) -> Result<Real, ScenarioError> {
        let deg = value(self.check, v, key, 0.0, 0.0, false)?;
        if deg >= 90.0 {
            return Err(self.check.fail(
                v.as_ref().map(|v| v.span()),
                key,
                format!("{deg}° is not below the pole (expected 0 ≤ incidence < 90)"),
            ));
        }
        Ok(deg * RAD_PER_DEG)
    }

    /// The moves of a sphere pattern on `target`, about the sphere `centre` of radius `radius`.
    #[allow(clippy::too_many_arguments)]
    fn sphere_moves(
        &self,
        frame: &LinearFrame,
        target: &Target,
        centre: Vector,
        radius: Real,
        points: usize,
        elevation: Real,
        facing: Option<Vector>,
        span: Range<usize>,
        key: &str,
    ) -> Result<Vec<ProbeMove>, ScenarioError> {
        let tool = frame.tool;
        sphere_pattern(points, elevation, tool.z_axis, tool.x_axis, facing)
            .into_iter()
            .map(|n| {
                let start = centre + n * (radius + self.r + self.clearance);
                let travel = self.clearance + self.overtravel;
                self.checked_move(frame, target, start, -n, travel, span.clone(), key)
            })
            .collect()
    }

    fn sphere(&self, raw: &Spanned<RawSphere>, key: &str) -> Result<Cycle, ScenarioError> {
        let s = raw.get_ref();
        let diameter = self.diameter(&s.diameter_mm, &format!("{key}.diameter_mm"))?;
        let centre = point(self.check, &s.centre_mm, &format!("{key}.centre_mm"))?;
        let points = count(self.check, &s.points, &format!("{key}.points"), 5, (4, 25))?;
        let elevation = self.incidence(&s.incidence_deg, &format!("{key}.incidence_deg"))?;
        let sphere = Sphere {
            centre,
            radius: diameter / 2.0,
        };
        let target = Target::Sphere(sphere);
        let positions: Vec<Option<RawRotary>> = match &s.rotary {
            None => vec![None],
            Some(list) if list.get_ref().is_empty() => {
                return Err(self.check.fail(
                    Some(list.span()),
                    &format!("{key}.rotary"),
                    "give at least one rotary position",
                ));
            }
            Some(list) => list.get_ref().iter().copied().map(Some).collect(),
        };
        let span = s.rotary.as_ref().map_or(raw.span(), |r| r.span());
        let mut features = Vec::new();
        for (n, position) in positions.into_iter().enumerate() {
            let key = format!("{key}.rotary[{n}]");
            let rotary = self.rotary(position, span.clone(), &key)?;
            let frame = self.frame(&rotary, span.clone(), &key)?;
            let moves = self.sphere_moves(
                &frame,
                &target,
                centre,
                sphere.radius,
                points,
                elevation,
                None,
                span.clone(),
                &key,
            )?;
            features.push(Feature {
                rotary,
                target: target.clone(),
                moves,
                calibrated_diameter: Some(diameter),
                calibrated_centre: None,
            });
        }
        Ok(Cycle {
            kind: CycleKind::Sphere,
            features,
        })
    }

    fn ring(&self, raw: &Spanned<RawRing>, key: &str) -> Result<Cycle, ScenarioError> {
        let g = raw.get_ref();
        let diameter = self.diameter(&g.diameter_mm, &format!("{key}.diameter_mm"))?;
        let centre = point(self.check, &g.centre_mm, &format!("{key}.centre_mm"))?;
        let points = count(self.check, &g.points, &format!("{key}.points"), 8, (3, 360))?;
        let span = g.rotary.as_ref().map_or(raw.span(), |r| r.span());
        let rotary = self.rotary(
            g.rotary.as_ref().map(|r| *r.get_ref()),
            span.clone(),
            &format!("{key}.rotary"),
        )?;
        let frame = self.frame(&rotary, span.clone(), &format!("{key}.rotary"))?;
        let axis = match &g.axis {
            Some(a) => direction(self.check, *a.get_ref(), a.span(), &format!("{key}.axis"))?,
            None => frame.tool.z_axis,
        };
        let radius = diameter / 2.0;
        let free = radius - self.r;
        if free <= 0.0 {
            return Err(self.check.fail(
                Some(g.diameter_mm.span()),
                &format!("{key}.diameter_mm"),
                "the stylus ball does not fit the bore",
            ));
        }
        let target = Target::Ring(Cylinder {
            point: centre,
            axis,
            radius,
            side: CylinderSide::Bore,
        });
        let offset = (free - self.clearance).max(0.0);
        let moves = ring_pattern(points, axis, frame.tool.x_axis)
            .into_iter()
            .map(|u| {
                let travel = free - offset + self.overtravel;
                self.checked_move(
                    &frame,
                    &target,
                    centre + u * offset,
                    u,
                    travel,
                    raw.span(),
                    key,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Cycle {
            kind: CycleKind::Ring,
            features: vec![Feature {
                rotary,
                target,
                moves,
                calibrated_diameter: Some(diameter),
                calibrated_centre: None,
            }],
        })
    }

    fn plate(&self, raw: &Spanned<RawPlate>, key: &str) -> Result<Vec<Cycle>, ScenarioError> {
        let b = raw.get_ref();
        let size = |v: &Spanned<i64>, name: &str| -> Result<usize, ScenarioError> {
            count(
                self.check,
                &Some(v.clone()),
                &format!("{key}.{name}"),
                1,
                (1, 100),
            )
        };
        let (rows, columns) = (size(&b.rows, "rows")?, size(&b.columns, "columns")?);
        let pitch = self.diameter(&b.pitch_mm, &format!("{key}.pitch_mm"))?;
        let ball = self.diameter(&b.ball_diameter_mm, &format!("{key}.ball_diameter_mm"))?;
        if ball + 2.0 * (self.r + self.clearance) >= pitch {
            return Err(self.check.fail(
                Some(b.pitch_mm.span()),
                &format!("{key}.pitch_mm"),
                "the balls are too close for the stylus to pass between them",
            ));
        }
        let points = count(self.check, &b.points, &format!("{key}.points"), 5, (4, 25))?;
        let elevation = self.incidence(&b.incidence_deg, &format!("{key}.incidence_deg"))?;
        let offsets: Vec<Vector> = match &b.ball_offsets_um {
            None => vec![Vector::ZERO; rows * columns],
            Some(list) => {
                let given = list.get_ref();
                if given.len() != rows * columns || given.iter().flatten().any(|x| !x.is_finite()) {
                    return Err(self.check.fail(Some(list.span()), &format!("{key}.ball_offsets_um"), format!("expected {} finite [x, y, z] offsets (rows × columns, row by row), got {}", rows * columns, given.len())));
                }
                given
                    .iter()
                    .map(|o| Vector::from_array(*o) * M_PER_UM)
                    .collect()
            }
        };
        let placements = b.placements.get_ref();
        let span = b.placements.span();
        if placements.is_empty() {
            return Err(self.check.fail(
                Some(span),
                &format!("{key}.placements"),
                "give at least one placement",
            ));
        }
        let frame = self.frame(&AxisValues::ZERO, span.clone(), key)?;
        let mut cycles = Vec::new();
        for (n, place) in placements.iter().enumerate() {
            let key = format!("{key}.placements[{n}]");
            let origin = Vector::from_array(place.origin_mm) * M_PER_MM;
            if !origin.is_finite() {
                return Err(self.check.fail(
                    Some(span.clone()),
                    &format!("{key}.origin_mm"),
                    "expected three finite numbers (mm)",
                ));
            }
            let along = direction(
                self.check,
                place.along_row.unwrap_or([1.0, 0.0, 0.0]),
                span.clone(),
                &format!("{key}.along_row"),
            )?;
            let across = direction(
                self.check,
                place.across_rows.unwrap_or([0.0, 1.0, 0.0]),
                span.clone(),
                &format!("{key}.across_rows"),
            )?;
            if along.dot(across).abs() > 1e-6 {
                return Err(self.check.fail(
                    Some(span.clone()),
                    &format!("{key}.across_rows"),
                    "must be perpendicular to along_row",
                ));
            }
            let normal = along.cross(across);
            let tool_axis = frame.tool.z_axis;
            if normal.dot(tool_axis) < -1e-9 {
                return Err(self.check.fail(Some(span.clone()), &key, "the plate faces away from the probe (along_row × across_rows points down the tool axis)"));
            }
            let facing = (normal.cross(tool_axis).length() > 1e-9).then_some(normal);
            if facing.is_some() && points == 25 {
                return Err(self.check.fail(
                    Some(span.clone()),
                    &key,
                    "the 25-point ISO 10360-5 pattern covers the whole ball, but on a plate set on \
                     edge the plate hides its back half: use 4 to 24 points there",
                ));
            }
            let plate_from = Rotation::from_cols(along, across, normal);
            let grid = BallPlate::grid(origin, along, across, pitch, rows, columns, ball / 2.0);
            let calibrated: Vec<Vector> = grid
                .centres
                .iter()
                .zip(&offsets)
                .map(|(c, o)| plate_from.transpose() * (*c - origin) + *o)
                .collect();
            let plate = Arc::new(BallPlate {
                radius: ball / 2.0,
                centres: calibrated
                    .iter()
                    .map(|c| origin + plate_from * *c)
                    .collect(),
            });
            let target = Target::Plate(plate.clone());
            let mut features = Vec::new();
            for (index, centre) in plate.centres.iter().enumerate() {
                let moves = self.sphere_moves(
                    &frame,
                    &target,
                    *centre,
                    plate.radius,
                    points,
                    elevation,
                    facing,
                    span.clone(),
                    &format!("{key} ball {}", index + 1),
                )?;
                features.push(Feature {
                    rotary: AxisValues::ZERO,
                    target: target.clone(),
                    moves,
                    calibrated_diameter: Some(ball),
                    calibrated_centre: Some(calibrated[index]),
                });
            }
            cycles.push(Cycle {
                kind: CycleKind::Plate,
                features,
            });
        }
        Ok(cycles)
    }

    fn mesh(&self, raw: &Spanned<RawMesh>, key: &str, dir: &Path) -> Result<Cycle, ScenarioError> {
        let m = raw.get_ref();
        let unit = match m.units.as_ref().map(|u| u.get_ref().as_str()) {
            None | Some("mm") => M_PER_MM,
            Some("m") => 1.0,
            Some("in") => 0.0254,
            Some(other) => {
                return Err(self.check.fail(
                    m.units.as_ref().map(|u| u.span()),
                    &format!("{key}.units"),
                    format!("\"{other}\": expected \"mm\", \"m\" or \"in\""),
                ));
            }
        };
        let path = dir.join(m.file.get_ref());
        let mesh = Mesh::read(&path, unit).map_err(|e| {
            self.check
                .fail(Some(m.file.span()), &format!("{key}.file"), e)
        })?;
        let origin = match &m.origin_mm {
            Some(o) => point(self.check, o, &format!("{key}.origin_mm"))?,
            None => Vector::ZERO,
        };
        let turn =
            finite(self.check, &m.rotation_deg, &format!("{key}.rotation_deg"))? * RAD_PER_DEG;
        let placed = mesh.placed(&crate::math::Pose::from_mat3_translation(
            Rotation::from_rotation_z(turn),
            origin,
        ));
        let max_travel = value(
            self.check,
            &m.max_travel_mm,
            &format!("{key}.max_travel_mm"),
            10.0,
            0.0,
            true,
        )? * M_PER_MM;
        let span = m.rotary.as_ref().map_or(raw.span(), |r| r.span());
        let rotary = self.rotary(
            m.rotary.as_ref().map(|r| *r.get_ref()),
            span.clone(),
            &format!("{key}.rotary"),
        )?;
        let frame = self.frame(&rotary, span, &format!("{key}.rotary"))?;
        let target = Target::Mesh(Arc::new(placed));
        let points = m.points.get_ref();
        if points.is_empty() {
            return Err(self.check.fail(
                Some(m.points.span()),
                &format!("{key}.points"),
                "give at least one point",
            ));
        }
        let mut moves = Vec::new();
        for (n, point) in points.iter().enumerate() {
            let key = format!("{key}.points[{n}]");
            let start = Vector::from_array(point.start_mm) * M_PER_MM;
            if !start.is_finite() {
                return Err(self.check.fail(
                    Some(m.points.span()),
                    &format!("{key}.start_mm"),
                    "expected three finite numbers (mm)",
                ));
            }
            let direction = direction(
                self.check,
                point.direction,
                m.points.span(),
                &format!("{key}.direction"),
            )?;
            moves.push(self.checked_move(
                &frame,
                &target,
                start,
                direction,
                max_travel,
                m.points.span(),
                &key,
            )?);
            // Vector probing: the controller compensates the stylus radius along the approach,
            // which is the surface point only when the approach is along the surface normal.
            if let Ok(Ok(Some(touch))) = Approach::new(start, direction)
                .map(|approach| target.touch(self.r, &approach, max_travel))
            {
                let off = (-touch.normal).angle_between(direction);
                if off > MESH_NORMAL_TOLERANCE {
                    let n = touch.normal;
                    return Err(self.check.fail(
                        Some(m.points.span()),
                        &format!("{key}.direction"),
                        format!(
                            "the approach is {:.2}° off the surface normal ({:.4}, {:.4}, {:.4}) at the planned contact: mesh points are probed along the normal (vector probing), since the stylus radius is compensated along the approach",
                            off.to_degrees(), n.x, n.y, n.z
                        ),
                    ));
                }
            }
        }
        Ok(Cycle {
            kind: CycleKind::Mesh,
            features: vec![Feature {
                rotary,
                target,
                moves,
                calibrated_diameter: None,
                calibrated_centre: None,
            }],
        })
    }
}

impl ProbeTest {
    /// One line per cycle, as `mtwin check` lists them.
    pub fn describe(&self) -> Vec<String> {
        self.cycles
            .iter()
            .map(|c| {
                let touches: usize = c.features.iter().map(|f| f.moves.len()).sum();
                format!(
                    "probe: {} cycle, {} feature(s), {touches} touches, stylus Ø {:.3} mm at {:.0} mm/min",
                    c.kind.name(),
                    c.features.len(),
                    2.0 * self.probe.stylus_radius / M_PER_MM,
                    self.probe.feed / M_PER_MM * 60.0
                )
            })
            .collect()
    }
}
