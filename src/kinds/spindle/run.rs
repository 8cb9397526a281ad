//! Running a spindle test through the twin: each record (set-up × speed) sample by sample,
//! read by the analyser's probes; the table, and the set-up as injected for the truth.
//!
//! Records run in parallel (rayon), each with its own noise streams (seeded per probe, set-up
//! and speed) and its own filter states, and are put together in programme order: the output
//! does not depend on the thread count.

use super::instrument::{
    AxisChain, ChainScratch, Channel, FrameError, Placement, ProbeKind, ProbeSpec, displacement,
};
use super::program::Block;
use super::record::{Sensing, SpindleRecord};
use super::scenario::SpindleTest;
use super::table::SpindleTable;
use crate::io::Conditions;
use crate::machine::{Machine, Side};
use crate::math::{
    M_PER_MM, M_PER_UM, Pose, Real, Rotation, Vector, rigid_inverse, seeded_rng, trimmed,
};
use crate::twin::Twin;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde_json::{Value, json};
use std::f64::consts::TAU;

/// Why a spindle test could not be simulated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SpindleRunError {
    /// The axis frames could not be placed.
    #[error("spindle test: {0}")]
    Frame(#[from] FrameError),
    /// A reading left the probe's range.
    #[error(
        "spindle test, set-up {setup} at {speed_rpm} rpm, revolution {revolution} at {angle_deg:.3}°: probe {probe} reads {reading_um:.3} µm, beyond its range of ±{range_um} µm (a larger eccentricity or error than the probe can follow: centre the artefact, or give range_um)"
    )]
    OutOfRange {
        /// The probe.
        probe: String,
        /// The set-up.
        setup: String,
        /// The speed (rpm).
        speed_rpm: Real,
        /// The revolution.
        revolution: usize,
        /// The angle (°).
        angle_deg: Real,
        /// The reading (µm).
        reading_um: Real,
        /// The probe's range (± µm).
        range_um: Real,
    },
    /// The twin gave a reading that is not a number.
    #[error(
        "spindle test, set-up {setup} at {time_s:.6} s: probe {probe}'s reading is not finite; check the error functions"
    )]
    NotFinite {
        /// The probe.
        probe: String,
        /// The set-up.
        setup: String,
        /// Time of the sample (s).
        time_s: Real,
    },
}

/// One record's samples.
struct BlockRecord {
    revolution: Vec<usize>,
    angle_index: Vec<usize>,
    time: Vec<Real>,
    readings: Vec<Vec<Real>>,
}

/// The rotation about z by the angle whose cosine and sine are given.
fn rot_z(cos: Real, sin: Real) -> Pose {
    Pose::from_mat3(Rotation::from_cols(
        Vector::new(cos, sin, 0.0),
        Vector::new(-sin, cos, 0.0),
        Vector::Z,
    ))
}

/// The spindle table of `test` on `twin`; the probes' noise seeded from `seed`.
pub fn simulate(
    twin: &Twin,
    test: &SpindleTest,
    seed: u64,
) -> Result<SpindleTable, SpindleRunError> {
    let chain = AxisChain::new(twin, test.axis, test.parked, test.artefact.stickout)?;
    let blocks = test.blocks();
    let records: Vec<BlockRecord> = blocks
        .par_iter()
        .map(|block| record(twin, test, &chain, block, seed))
        .collect::<Result<_, _>>()?;
    let total: usize = records.iter().map(|r| r.time.len()).sum();
    let names: Vec<String> = test.setups.iter().map(|s| s.name()).collect();
    let mut out = SpindleRecord {
        axis: test.axis,
        probes: test
            .probes
            .iter()
            .map(|p| p.record_probe(&test.artefact, test.sensing))
            .collect(),
        setup: Vec::with_capacity(total),
        revolution: Vec::with_capacity(total),
        angle: Vec::with_capacity(total),
        time: Vec::with_capacity(total),
        speed: Vec::with_capacity(total),
        readings: vec![Vec::with_capacity(total); test.probes.len()],
    };
    let per_rev = test.samples_per_revolution as Real;
    for (block, r) in blocks.iter().zip(records) {
        let n = r.time.len();
        out.setup
            .extend(std::iter::repeat_n(&names[block.setup], n).cloned());
        out.revolution.extend(r.revolution);
        out.angle
            .extend(r.angle_index.iter().map(|&i| TAU * i as Real / per_rev));
        out.time.extend(r.time);
        out.speed.extend(std::iter::repeat_n(block.speed, n));
        for (all, these) in out.readings.iter_mut().zip(r.readings) {
            all.extend(these);
        }
    }
    Ok(SpindleTable {
        record: out,
        conditions: conditions(test, &chain, &twin.machine),
        samples_per_revolution: test.samples_per_revolution,
        columns_not_read: Vec::new(),
    })
}

/// One record (set-up × speed): settling, then the recorded revolutions.
fn record(
    twin: &Twin,
    test: &SpindleTest,
    chain: &AxisChain,
    block: &Block,
    seed: u64,
) -> Result<BlockRecord, SpindleRunError> {
    let setup = test.setups[block.setup];
    let per_rev = block.samples_per_revolution;
    let turn = setup.artefact_turn();
    let artefact_pose = test.artefact.setup_pose(turn);
    // G·Rot_z(∓θ) at each grid angle: the artefact's set-up and the nominal turn taken back.
    let facing = match test.sensing {
        Sensing::Fixed => -1.0,
        Sensing::Rotating => 1.0,
    };
    let nominal: Vec<Pose> = (0..per_rev)
        .map(|i| {
            let (sin, cos) = (TAU * i as Real / per_rev as Real).sin_cos();
            artefact_pose * rot_z(cos, facing * sin)
        })
        .collect();
    let placements: Vec<Placement> = test
        .probes
        .iter()
        .map(|p| p.placement(&test.artefact, setup.probes_opposite()))
        .collect();
    // The form each radial probe faces at each grid angle: ψ = φ ∓ θ in the carrier's frame,
    // ψ − β in the artefact's.
    let forms: Vec<Vec<Real>> = placements
        .iter()
        .map(|p| match p.form_azimuth {
            Some(phi) if !test.artefact.form.is_empty() => (0..per_rev)
                .map(|i| {
                    let theta = TAU * i as Real / per_rev as Real;
                    test.artefact.form_at(phi + facing * theta - turn)
                })
                .collect(),
            _ => Vec::new(),
        })
        .collect();
    let mut channels: Vec<Channel<'_>> = test
        .probes
        .iter()
        .map(|p| Channel::new(p, block.interval()))
        .collect();
    let mut rngs: Vec<ChaCha8Rng> = test
        .probes
        .iter()
        .map(|p| {
            seeded_rng(
                seed,
                &format!(
                    "spindle probe {} set-up {} speed {}",
                    p.name,
                    setup.name(),
                    block.speed_index
                ),
            )
        })
        .collect();
    let recorded = block.revolutions * per_rev;
    let mut out = BlockRecord {
        revolution: Vec::with_capacity(recorded),
        angle_index: Vec::with_capacity(recorded),
        time: Vec::with_capacity(recorded),
        readings: vec![Vec::with_capacity(recorded); test.probes.len()],
    };
    let mut scratch = ChainScratch::new(twin);
    let mut along = chain.along(twin, block);
    for j in 0..block.sample_count() {
        let sample = block.sample(j);
        let m = along.pose(j, &sample, &mut scratch);
        let x = match test.sensing {
            Sensing::Fixed => m * nominal[sample.angle_index],
            Sensing::Rotating => rigid_inverse(&m) * nominal[sample.angle_index],
        };
        for p in 0..placements.len() {
            let form = forms[p].get(sample.angle_index).copied().unwrap_or(0.0);
            let y = channels[p].filter(displacement(&x, &placements[p]) - form);
            let Some(revolution) = sample.revolution else {
                continue;
            };
            let reading = channels[p].digitise(y, &mut rngs[p]);
            let probe = &test.probes[p];
            if !reading.is_finite() {
                return Err(SpindleRunError::NotFinite {
                    probe: probe.name.clone(),
                    setup: setup.name(),
                    time_s: sample.time,
                });
            }
            if reading.abs() > probe.range {
                return Err(SpindleRunError::OutOfRange {
                    probe: probe.name.clone(),
                    setup: setup.name(),
                    speed_rpm: block.speed * 60.0 / TAU,
                    revolution,
                    angle_deg: 360.0 * sample.angle_index as Real / per_rev as Real,
                    reading_um: reading / M_PER_UM,
                    range_um: probe.range / M_PER_UM,
                });
            }
            out.readings[p].push(reading);
        }
        if let Some(revolution) = sample.revolution {
            out.revolution.push(revolution);
            out.angle_index.push(sample.angle_index);
            out.time.push(sample.time);
        }
    }
    Ok(out)
}

/// The value all probes share, if they do.
fn shared<T: PartialEq + Copy>(probes: &[ProbeSpec], f: impl Fn(&ProbeSpec) -> T) -> Option<T> {
    let first = f(probes.first()?);
    probes.iter().all(|p| f(p) == first).then_some(first)
}

/// The preamble of the table (ISO 230-7 §5.2): what the analyser and the set-up were.
fn conditions(test: &SpindleTest, chain: &AxisChain, machine: &Machine) -> Conditions {
    let mut pairs: Vec<(String, String)> = vec![
        ("machine".into(), test.machine.clone()),
        ("artefact".into(), test.artefact.describe()),
        (
            "structural_loop".into(),
            match (chain.side, test.sensing) {
                (Side::Tool, Sensing::Fixed) => {
                    format!(
                        "artefact on the tool side ({}), probes on the workpiece side",
                        test.axis
                    )
                }
                (Side::Tool, Sensing::Rotating) => {
                    format!(
                        "probes on the tool side ({}), artefact on the workpiece side",
                        test.axis
                    )
                }
                (Side::Workpiece, Sensing::Fixed) => {
                    format!(
                        "artefact on the workpiece side ({}), probes on the tool side",
                        test.axis
                    )
                }
                (Side::Workpiece, Sensing::Rotating) => {
                    format!(
                        "probes on the workpiece side ({}), artefact on the tool side",
                        test.axis
                    )
                }
            },
        ),
        (
            "speeds_rpm".into(),
            test.speeds
                .iter()
                .map(|w| trimmed(w * 60.0 / TAU, 6))
                .collect::<Vec<_>>()
                .join(" "),
        ),
        ("revolutions".into(), test.revolutions.to_string()),
        (
            "setups".into(),
            test.setups
                .iter()
                .map(|s| s.name())
                .collect::<Vec<_>>()
                .join(" "),
        ),
    ];
    if test.setups.iter().any(|s| s.probes_opposite()) {
        pairs.push((
            "reversed_setup".into(),
            "artefact turned 180 deg on its carrier and radial probes at azimuth + 180 deg (the geometry keys give the normal set-up)".into(),
        ));
    }
    if test
        .setups
        .iter()
        .any(|s| matches!(s, super::program::Setup::Turned(_)))
    {
        pairs.push((
            "turned_setup".into(),
            "turned_<deg>: artefact turned by that angle on its carrier, probes unchanged".into(),
        ));
    }
    let heights: Vec<Real> = test
        .probes
        .iter()
        .filter_map(|p| match p.kind {
            ProbeKind::Radial { height, .. } => Some(height),
            _ => None,
        })
        .collect();
    let (low, high) = heights
        .iter()
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &z| {
            (l.min(z), h.max(z))
        });
    if high > low {
        pairs.push((
            "station_separation_mm".into(),
            trimmed((high - low) / M_PER_MM, 6),
        ));
    }
    if let Some(r) = test.probes.iter().find_map(|p| match p.kind {
        ProbeKind::Face { radius, .. } => Some(radius),
        _ => None,
    }) {
        pairs.push(("face_radius_mm".into(), trimmed(r / M_PER_MM, 6)));
    }
    match shared(&test.probes, |p| p.bandwidth) {
        Some(Some(f)) => pairs.push(("bandwidth_hz".into(), trimmed(f, 6))),
        Some(None) => pairs.push(("filter".into(), "none".into())),
        None => {
            for p in &test.probes {
                match p.bandwidth {
                    Some(f) => pairs.push((format!("{}_bandwidth_hz", p.name), trimmed(f, 6))),
                    None => pairs.push((format!("{}_filter", p.name), "none".into())),
                }
            }
        }
    }
    match shared(&test.probes, |p| p.resolution) {
        Some(r) => pairs.push(("resolution_nm".into(), trimmed(r * 1e9, 6))),
        None => {
            for p in &test.probes {
                pairs.push((
                    format!("{}_resolution_nm", p.name),
                    trimmed(p.resolution * 1e9, 6),
                ));
            }
        }
    }
    for info in machine.axes() {
        if info.axis == test.axis {
            continue;
        }
        let (scale, unit) = if info.axis.is_linear() {
            (M_PER_MM, "mm")
        } else {
            (crate::math::RAD_PER_DEG, "deg")
        };
        pairs.push((
            format!("{}_{unit}", info.axis.letter().to_ascii_lowercase()),
            trimmed(test.parked[info.axis] / scale, 6),
        ));
    }
    Conditions::from_pairs(pairs)
}

/// The set-up as injected, in file units: the analyser, the artefact, the programme and where
/// the axis's error parameters act in the axis frame.
pub fn truth(twin: &Twin, test: &SpindleTest) -> Value {
    let chain = AxisChain::new(twin, test.axis, test.parked, test.artefact.stickout).ok();
    let a = &test.artefact;
    let nm = |v: Real| v * 1e9;
    let um = |v: Real| v / M_PER_UM;
    let mm3 = |v: Vector| (v / M_PER_MM).to_array();
    let frames = chain.as_ref().map(|c| {
        let rows = |m: Rotation| {
            let t = m.transpose();
            [t.x_axis.to_array(), t.y_axis.to_array(), t.z_axis.to_array()]
        };
        json!({
            "rotor_side": if c.side == Side::Tool { "tool" } else { "workpiece" },
            "stator_end_from_axis": {
                "rotation": rows(c.stator_from_axis.matrix3),
                "origin_mm": mm3(c.stator_from_axis.translation),
            },
            "rotor_end_from_axis": {
                "rotation": rows(c.rotor_from_axis.matrix3),
                "origin_mm": mm3(c.rotor_from_axis.translation),
            },
            "axis_from_slot": {
                "rotation": rows(c.axis_from_slot.matrix3),
                "pivot_mm": mm3(c.axis_from_slot.translation),
            },
            "rotor_motion_sign": if c.side == Side::Tool { 1.0 } else { -1.0 },
            "note": "to first order the rotor's displacement relative to the stator at a point p of the axis frame is \
                     rotor_motion_sign · R · (δ + ε × (p_slot − pivot)), with (δ, ε) = (EX·, EY·, EZ·, EA·, EB·, EC·) of the axis \
                     in its slot frame and R the rotation of axis_from_slot (rows); component errors are tool-relative, so a \
                     table axis's rotor moves the other way",
        })
    });
    json!({
        "axis": test.axis.to_string(),
        "sensing": match test.sensing { Sensing::Fixed => "fixed", Sensing::Rotating => "rotating" },
        "speeds_rpm": test.speeds.iter().map(|w| w * 60.0 / TAU).collect::<Vec<_>>(),
        "revolutions": test.revolutions,
        "samples_per_revolution": test.samples_per_revolution,
        "settle_s": test.settle,
        "settle_revolutions": test.blocks().iter().take(test.speeds.len()).map(|b| b.settle_revolutions).collect::<Vec<_>>(),
        "setups": test.setups.iter().map(|s| json!({
            "name": s.name(),
            "artefact_turn_deg": s.artefact_turn().to_degrees(),
            "radial_probes_opposite": s.probes_opposite(),
        })).collect::<Vec<_>>(),
        "artefact": {
            "kind": a.kind.name(),
            "diameter_mm": 2.0 * a.radius / M_PER_MM,
            "separation_mm": match a.kind { super::instrument::ArtefactKind::TwoSpheres { separation } => Some(separation / M_PER_MM), _ => None },
            "length_mm": match a.kind { super::instrument::ArtefactKind::Cylinder { length } => Some(length / M_PER_MM), _ => None },
            "stickout_mm": a.stickout / M_PER_MM,
            "eccentricity_um": a.eccentricity.map(um),
            "tilt_urad": a.tilt.map(|t| t * 1e6),
            "form": a.form.iter().map(|h| json!({
                "per_revolution": h.per_revolution,
                "amplitude_nm": nm(h.amplitude),
                "phase_deg": h.phase.to_degrees(),
            })).collect::<Vec<_>>(),
            "form_definition": "outward deviation h(ψ) = Σ amplitude · sin(per_revolution · ψ + phase), ψ the azimuth in the artefact's own frame",
            "carrier": match test.sensing { Sensing::Fixed => "rotor", Sensing::Rotating => "stator" },
        },
        "probes": test.probes.iter().map(|p| {
            let (kind, azimuth, height, radius) = match p.kind {
                ProbeKind::Radial { azimuth, height } => ("radial", Some(azimuth.to_degrees()), Some(height / M_PER_MM), None),
                ProbeKind::Axial => ("axial", None, None, None),
                ProbeKind::Face { radius, azimuth } => ("face", Some(azimuth.to_degrees()), None, Some(radius / M_PER_MM)),
            };
            json!({
                "name": p.name,
                "kind": kind,
                "azimuth_deg": azimuth,
                "height_mm": height,
                "radius_mm": radius,
                "gain_error": p.gain_error,
                "noise_nm": nm(p.noise),
                "resolution_nm": nm(p.resolution),
                "bandwidth_hz": p.bandwidth,
                "range_um": um(p.range),
            })
        }).collect::<Vec<_>>(),
        "filter": "first-order low-pass, step-invariant: y += (1 - exp(-2π·f_c·Δt))·(x - y), causal in sample order, started at the first settling sample; then noise, then resolution",
        "frames": frames,
        "error_parameters": twin.errors.parameters().iter().map(|p| p.name)
            .chain(twin.errors.dynamics().iter().map(|d| d.name))
            .filter(|n| n.axis() == Some(test.axis))
            .map(|n| n.to_string())
            .collect::<std::collections::BTreeSet<_>>(),
        "convention": "reading = direction · (X·q − q) − h, positive when the artefact's surface moves away from the probe; \
                       fixed sensing X = M·G·Rot_z(−θ), rotating X = M⁻¹·G·Rot_z(θ); M the actual rotor axis frame in the \
                       stator axis frame, G the artefact's set-up pose on its carrier (see kinds::spindle::instrument)",
    })
}

/// One line for people: the records and the largest reading of each probe.
pub fn summary(table: &SpindleTable) -> String {
    let r = &table.record;
    let revolutions = r
        .len()
        .checked_div(table.samples_per_revolution)
        .unwrap_or(0);
    let spans: Vec<String> = r
        .probes
        .iter()
        .zip(&r.readings)
        .map(|(p, values)| {
            let (low, high) = values
                .iter()
                .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &v| {
                    (l.min(v), h.max(v))
                });
            format!("{} {:.3}", p.name, (high - low) / M_PER_UM)
        })
        .collect();
    format!(
        "spindle {}: {} revolutions of {} samples; peak-to-valley (µm) {}",
        r.axis,
        revolutions,
        table.samples_per_revolution,
        spans.join(", ")
    )
}
