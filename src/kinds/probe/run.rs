//! Running the probe cycles: every move through the twin and the virtual probe, giving the
//! `probe` table, and the controller's sphere fits of it, the `spheres` table; and the probe
//! and artefacts as injected, for the truth.

use super::analysis::{EvaluationError, evaluate};
use super::cycles::{CycleKind, Target};
use super::instrument::TouchError;
use super::scenario::ProbeTest;
use super::table::{ProbeConditions, ProbeTable, ProbeTouch, RowKey, SpheresTable};
use crate::machine::{Axis, Workspace};
use crate::math::{M_PER_MM, M_PER_UM, Real, Vector, seeded_rng};
use crate::twin::Twin;
use serde_json::{Value, json};

/// What a probe run wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeRun {
    /// Every touch (`probe.csv`).
    pub probe: ProbeTable,
    /// A sphere fit per sphere or plate-ball feature (`spheres.csv`).
    pub spheres: SpheresTable,
}

/// Why a probe run failed (the scenario's checks make this rare: an error model so large that
/// the actual stylus misses an artefact the nominal one reaches).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ProbeRunError {
    /// A touch could not be made.
    #[error("probe cycle {cycle} ({kind}), feature {feature}, point {point}: {error}")]
    Touch {
        /// The cycle (from 1).
        cycle: usize,
        /// Its kind.
        kind: &'static str,
        /// The feature (from 1).
        feature: usize,
        /// The point (from 1).
        point: usize,
        /// Why.
        error: TouchError,
    },
    /// The controller's fit of a feature failed.
    #[error(transparent)]
    Fit(#[from] EvaluationError),
}

/// Runs every cycle of `test` on `twin`: each cycle's trigger scatter from its own stream
/// (`seed`, "probe cycle N").
pub fn simulate(twin: &Twin, test: &ProbeTest, seed: u64) -> Result<ProbeRun, ProbeRunError> {
    let mut workspace = Workspace::new(&twin.machine);
    let mut touches = Vec::new();
    for (c, cycle) in test.cycles.iter().enumerate() {
        let mut rng = seeded_rng(seed, &format!("probe cycle {}", c + 1));
        for (f, feature) in cycle.features.iter().enumerate() {
            let mut rotary = [None; 3];
            for (slot, axis) in rotary.iter_mut().zip([Axis::A, Axis::B, Axis::C]) {
                if twin.machine.has_axis(axis) {
                    *slot = Some(feature.rotary[axis]);
                }
            }
            let key = RowKey {
                cycle: c + 1,
                kind: cycle.kind,
                feature: f + 1,
                rotary,
                calibrated_diameter: feature.calibrated_diameter,
                calibrated_centre: feature.calibrated_centre,
            };
            for (p, probing) in feature.moves.iter().enumerate() {
                let latched = test
                    .probe
                    .touch(twin, &mut workspace, &feature.target, probing, &mut rng)
                    .map_err(|error| ProbeRunError::Touch {
                        cycle: c + 1,
                        kind: cycle.kind.name(),
                        feature: f + 1,
                        point: p + 1,
                        error,
                    })?;
                let a = latched.axes;
                touches.push(ProbeTouch {
                    key,
                    point: p + 1,
                    position: Vector::new(a[Axis::X], a[Axis::Y], a[Axis::Z]),
                    approach: probing.direction,
                });
            }
        }
    }
    let conditions = ProbeConditions {
        stylus_radius: Some(test.probe.stylus_radius),
        feed: Some(test.probe.feed),
        machine: Some(test.machine.clone()),
        columns_not_read: Vec::new(),
    };
    let probe = ProbeTable {
        touches,
        conditions: conditions.clone(),
    };
    let spheres = evaluate(&probe, test.probe.stylus_radius)?.spheres_table(conditions);
    Ok(ProbeRun { probe, spheres })
}

/// In mm, rounded to 1 pm, so that positions summed from a placement and a grid
/// (−160 + 2 × 80 mm) do not carry their rounding residue (1e-17 m) into `truth.json`.
fn mm(v: Vector) -> [Real; 3] {
    (v / M_PER_MM).to_array().map(|x| (x * 1e9).round() / 1e9)
}

/// The probe and the artefacts as injected, in file units.
pub fn truth(test: &ProbeTest) -> Value {
    let p = &test.probe;
    let cycles: Vec<Value> = test
        .cycles
        .iter()
        .enumerate()
        .map(|(c, cycle)| {
            let features: Vec<Value> = cycle
                .features
                .iter()
                .enumerate()
                .map(|(f, feature)| {
                    let artefact = match &feature.target {
                        Target::Sphere(s) => json!({
                            "sphere": { "centre_mm": mm(s.centre), "diameter_mm": 2.0 * s.radius / M_PER_MM }
                        }),
                        Target::Ring(r) => json!({
                            "ring": { "centre_mm": mm(r.point), "axis": r.axis.to_array(), "diameter_mm": 2.0 * r.radius / M_PER_MM }
                        }),
                        Target::Plate(plate) => json!({
                            "ball": { "centre_mm": mm(plate.centres[f]), "diameter_mm": 2.0 * plate.radius / M_PER_MM }
                        }),
                        Target::Mesh(mesh) => json!({
                            "mesh": { "triangles": mesh.triangle_count(), "volume_mm3": mesh.volume() / M_PER_MM.powi(3) }
                        }),
                    };
                    let rotary = [Axis::A, Axis::B, Axis::C].map(|a| feature.rotary[a].to_degrees());
                    json!({
                        "feature": f + 1,
                        "rotary_deg": rotary,
                        "points": feature.moves.len(),
                        "artefact": artefact,
                    })
                })
                .collect();
            json!({ "cycle": c + 1, "kind": cycle.kind.name(), "features": features })
        })
        .collect();
    json!({
        "stylus_radius_mm": p.stylus_radius / M_PER_MM,
        "stylus_true_radius_mm": p.true_radius() / M_PER_MM,
        "stylus_radius_error_um": p.radius_error / M_PER_UM,
        "pretravel_um": p.pretravel / M_PER_UM,
        "lobing_um": p.lobing / M_PER_UM,
        "lobing_phase_deg": p.lobing_phase.to_degrees(),
        "pretravel_axial_um": p.pretravel_axial / M_PER_UM,
        "repeatability_um": p.repeatability / M_PER_UM,
        "feed_mm_per_min": p.feed / M_PER_MM * 60.0,
        "latency_ms": p.latency * 1e3,
        "latency_overrun_um": p.feed * p.latency / M_PER_UM,
        "cycles": cycles,
    })
}

/// One line for people: touches, spheres and their largest form deviation.
pub fn summary(run: &ProbeRun) -> String {
    let spheres = &run.spheres.spheres;
    let form = spheres.iter().map(|s| s.form).fold(0.0, Real::max);
    let rings = run
        .probe
        .touches
        .iter()
        .filter(|t| t.key.kind == CycleKind::Ring && t.point == 1)
        .count();
    format!(
        "probe: {} touches, {} sphere fits (largest form {:.3} µm), {rings} ring(s)",
        run.probe.touches.len(),
        spheres.len(),
        form / M_PER_UM
    )
}
