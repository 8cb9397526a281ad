//! The spheres table as readings for the estimators ([`crate::estimate`]): a calibration
//! sphere probed at several rotary positions (KinematicsOpt's cycle 451, Siemens CYCLE996),
//! its fitted centre in axis coordinates at each.
//!
//! The reading of a feature is the linear axis values `q` at which the actual tool tip
//! (the stylus centre) sits on the sphere centre `p` at the feature's rotary angles:
//! `actual_tip(q, angles) = p`. The model solves it on the twin's chain by fixed-point steps
//! through the nominal linear frame ([`super::LinearFrame`]), which converge by a factor of
//! the errors' size (1e-4) per step. The sphere centre `p` (workpiece frame) is a nuisance of
//! each cycle (`sphereN.offset.x…`: its offset from where the nominal chain puts the first
//! feature's centre, the start): a sphere probed
//! at the rotary axes' zero pins it, because every location error vanishes there.
//!
//! Simplifications, stated: the fitted centre is taken as the point the probe's stylus centre
//! reaches, so the pre-travel's lobes and the latency, which average out over a symmetric
//! pattern to first order, are left in the residuals; only sphere cycles are read (ring and
//! plate cycles measure the linear axes, mesh points the workpiece).

use super::cycles::{CycleKind, LinearFrame};
use super::table::SpheresTable;
use crate::errors::ErrorModel;
use crate::estimate::{Quantity, ReadingModel, Readings, ReadingsError};
use crate::machine::{Axis, AxisValues, Machine, MachineState, Workspace};
use crate::math::{Real, Vector};

/// Default standard uncertainty of a fitted centre coordinate: 0.5 µm (a five-point fit with
/// a probe repeatable to 0.25 µm, pre-travel variation included).
pub const DEFAULT_SIGMA: Real = 0.5e-6;

/// Fixed-point steps of the touch solve: each gains a factor of the errors' relative size.
const STEPS: usize = 4;

#[derive(Clone, Debug)]
struct Feature {
    frame: LinearFrame,
    /// Index of its cycle.
    cycle: usize,
    /// Index of its group for held-out checks: its cycle at its tilt ([`ReadingModel::group`]).
    group: usize,
}

#[derive(Clone, Debug)]
struct SpheresModel {
    features: Vec<Feature>,
    /// Each cycle's start for its sphere centre (workpiece frame).
    starts: Vec<Vector>,
}

impl ReadingModel for SpheresModel {
    fn per_row(&self) -> usize {
        3
    }

    /// A sphere at one tilt (the angles of A and B; C turning): what a K-test is to an
    /// R-test. Held out, its centres are predicted from the same sphere at the other tilts
    /// and from the other spheres.
    fn group(&self, i: usize) -> usize {
        self.features[i / 3].group
    }

    fn reading_name(&self, i: usize) -> String {
        format!(
            "sphere centre {} in file order ({})",
            i / 3 + 1,
            ["x", "y", "z"][i % 3]
        )
    }

    fn predict(
        &self,
        machine: &Machine,
        workspace: &mut Workspace,
        errors: &ErrorModel,
        nuisance: &[Real],
        _setup: &[Real],
        out: &mut [Real],
    ) {
        for (i, feature) in self.features.iter().enumerate() {
            let n = &nuisance[3 * feature.cycle..3 * feature.cycle + 3];
            let p = self.starts[feature.cycle] + Vector::new(n[0], n[1], n[2]);
            let mut target = p;
            let mut axes = feature.frame.axes_for(target);
            for _ in 0..STEPS {
                let tip = errors
                    .workpiece_from_tool(machine, workspace, &MachineState::at(axes))
                    .translation;
                target += p - tip;
                axes = feature.frame.axes_for(target);
            }
            out[3 * i..3 * i + 3].copy_from_slice(&[axes[Axis::X], axes[Axis::Y], axes[Axis::Z]]);
        }
    }
}

/// The readings of the sphere cycles of a spheres table measured on `machine`; `sigma` is
/// each centre coordinate's standard uncertainty (m).
pub fn readings(
    table: &SpheresTable,
    file: &str,
    machine: &Machine,
    sigma: Real,
) -> Result<Readings, ReadingsError> {
    let fail = |message: String| ReadingsError::new(file, message);
    let mut features = Vec::new();
    let mut measured = Vec::new();
    let mut cycles: Vec<usize> = Vec::new();
    let mut index_of: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let mut starts = Vec::new();
    let mut groups: Vec<(usize, [u64; 2])> = Vec::new();
    for (row, sphere) in table.spheres.iter().enumerate() {
        if sphere.key.kind != CycleKind::Sphere {
            continue;
        }
        let mut rotary = AxisValues::ZERO;
        for (angle, axis) in sphere.key.rotary.iter().zip([Axis::A, Axis::B, Axis::C]) {
            if let Some(angle) = angle {
                if !machine.has_axis(axis) {
                    return Err(fail(format!(
                        "row {}: an angle of {axis}, which machine \"{}\" does not have",
                        row + 1,
                        machine.name()
                    )));
                }
                rotary[axis] = *angle;
            }
        }
        let frame = LinearFrame::at(machine, &rotary).ok_or_else(|| {
            fail(format!(
                "row {}: the linear axes cannot reach every direction at these angles",
                row + 1
            ))
        })?;
        let cycle = match index_of.get(&sphere.key.cycle) {
            Some(&index) => index,
            None => {
                index_of.insert(sphere.key.cycle, cycles.len());
                cycles.push(sphere.key.cycle);
                let mut axes = rotary;
                axes[Axis::X] = sphere.centre.x;
                axes[Axis::Y] = sphere.centre.y;
                axes[Axis::Z] = sphere.centre.z;
                starts.push(machine.workpiece_from_tool(&axes).translation);
                cycles.len() - 1
            }
        };
        let key = (
            cycle,
            [rotary[Axis::A].to_bits(), rotary[Axis::B].to_bits()],
        );
        let group = groups.iter().position(|g| *g == key).unwrap_or_else(|| {
            groups.push(key);
            groups.len() - 1
        });
        features.push(Feature {
            frame,
            cycle,
            group,
        });
        measured.extend_from_slice(&sphere.centre.to_array());
    }
    if features.is_empty() {
        return Err(fail(
            "no sphere cycle: the estimators read the centres of a sphere probed at several rotary positions".into(),
        ));
    }
    let nuisance = cycles
        .iter()
        .flat_map(|c| {
            ["x", "y", "z"].map(|axis| Quantity {
                name: format!("sphere{c}.offset.{axis}"),
                translation: true,
                start: 0.0,
                uncertainty: 0.0,
            })
        })
        .collect();
    Ok(Readings {
        source: file.to_string(),
        kind: "spheres",
        machine: table.conditions.machine.clone(),
        sigma: vec![sigma; measured.len()],
        measured,
        nuisance,
        setup: Vec::new(),
        model: Box::new(SpheresModel { features, starts }),
    })
}

/// Planning figures of a probing cycle on a calibration sphere (minutes; [`planned`]): placing
/// and clamping the sphere and calling the cycle, and each rotary position probed (five
/// touches and the moves between them). Typical of a KinematicsOpt or CYCLE996 measurement as
/// their makers describe it (a few minutes for a whole cycle), not measured here: they rank
/// candidate tests against each other.
pub const PLANNED_SETUP_MINUTES: Real = 5.0;
/// See [`PLANNED_SETUP_MINUTES`].
pub const PLANNED_MINUTES_PER_POSITION: Real = 0.5;

/// A planned probing cycle (no measurements), for identifiability and test design: a sphere at
/// `sphere` (workpiece frame, m) probed at each of `positions` (their rotary angles; the
/// linear entries are ignored), its centre read in axis coordinates as [`readings`] has it.
pub fn planned(
    machine: &Machine,
    positions: &[AxisValues],
    sphere: Vector,
    sigma: Real,
) -> Result<Readings, ReadingsError> {
    use super::table::{RowKey, SphereRow};
    let fail = |message: String| ReadingsError::new("planned probing cycle", message);
    let mut table = SpheresTable::default();
    for (k, position) in positions.iter().enumerate() {
        let mut rotary = [None; 3];
        for info in machine.rotary_axes() {
            rotary[info.axis.coordinate()] = Some(position[info.axis]);
        }
        let frame = LinearFrame::at(machine, position).ok_or_else(|| {
            fail(format!(
                "position {}: the linear axes cannot reach every direction",
                k + 1
            ))
        })?;
        let axes = frame.axes_for(sphere);
        if let Some(outside) = machine.outside_travel(&axes) {
            return Err(fail(format!("position {}: {outside}", k + 1)));
        }
        table.spheres.push(SphereRow {
            key: RowKey {
                cycle: 1,
                kind: CycleKind::Sphere,
                feature: k + 1,
                rotary,
                calibrated_diameter: None,
                calibrated_centre: None,
            },
            centre: Vector::new(axes[Axis::X], axes[Axis::Y], axes[Axis::Z]),
            radius: 0.0,
            form: 0.0,
            points: 5,
        });
    }
    let mut readings = readings(&table, "planned probing cycle", machine, sigma)?;
    readings.measured.clear();
    Ok(readings)
}
