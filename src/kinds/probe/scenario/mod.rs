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

// The files, in reading order: `raw` (the section as written), `values` (its values checked
// one by one), `plan` (the cycles planned with their checks) and `collision` (the moves swept
// against the machine and the artefacts).
mod collision;
mod plan;
mod raw;
mod values;

pub use collision::{PROBE_BODY_FROM, PROBE_BODY_RADIUS, STEM_RADIUS};
pub use plan::MESH_NORMAL_TOLERANCE;
pub use raw::RawProbe;

use collision::collision;
use plan::Plan;
use values::bounded;

use super::cycles::Cycle;
use super::instrument::TouchProbe;
use crate::machine::Machine;
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG};
use crate::scenario::bounds::{self, Bound};
use crate::scenario::{Checker, Context, ScenarioError, ScenarioErrorKind};
use std::path::Path;
use toml::Spanned;

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

/// How far a probe's trigger can lag, scatter or lobe (µm).
const TRIGGER_UM: Bound = Bound {
    lo: 0.0,
    hi: 1000.0,
    why: "a probe that triggers a millimetre late is not a probe",
};

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
