//! The volumetric figure: the tool-tip deviation over a grid of the working volume, of the
//! truth alone and compensated by the estimate (see the module doc for the grid).

use crate::errors::{ErrorFunction, ErrorModel, ParameterName};
use crate::machine::{Axis, AxisValues, Direction, Machine, MachineState, Workspace};
use crate::math::{RAD_PER_URAD, Real};
use std::collections::BTreeSet;

/// Points per linear axis in the volumetric grid.
const LINEAR_POINTS: usize = 5;

/// The tool-tip deviation over the working volume (see the module doc for the grid), µm.
#[derive(Debug, Clone, PartialEq)]
pub struct Volumetric {
    /// Number of machine states evaluated (grid points × direction combinations).
    pub points: usize,
    /// RMS of `|dev_truth|`.
    pub uncompensated_rms_um: Real,
    /// Largest `|dev_truth|`.
    pub uncompensated_max_um: Real,
    /// RMS of `|dev_truth − dev_estimate|`.
    pub compensated_rms_um: Real,
    /// Largest `|dev_truth − dev_estimate|`.
    pub compensated_max_um: Real,
}

/// The positions of the volumetric grid (see the module doc), SI, the first axis of
/// [`Machine::axes`] varying slowest.
pub fn volumetric_grid(machine: &Machine) -> Vec<AxisValues> {
    let per_axis: Vec<(Axis, Vec<Real>)> = machine
        .axes()
        .iter()
        .map(|info| {
            let values = if info.axis == Axis::S {
                vec![0.0]
            } else if info.axis.is_linear() {
                match info.limits {
                    Some((low, high)) => (0..LINEAR_POINTS)
                        .map(|i| low + (high - low) * i as Real / (LINEAR_POINTS - 1) as Real)
                        .collect(),
                    None => vec![0.0],
                }
            } else {
                match info.limits {
                    Some((low, high)) => {
                        let mut v = vec![low];
                        if low < 0.0 && 0.0 < high {
                            v.push(0.0);
                        }
                        if high > low {
                            v.push(high);
                        }
                        v
                    }
                    None => (0..4)
                        .map(|i| i as Real * std::f64::consts::FRAC_PI_2)
                        .collect(),
                }
            };
            (info.axis, values)
        })
        .collect();
    let mut grid = vec![AxisValues::ZERO];
    for (axis, values) in per_axis {
        grid = grid
            .iter()
            .flat_map(|base| {
                values.iter().map(move |&v| {
                    let mut p = *base;
                    p[axis] = v;
                    p
                })
            })
            .collect();
    }
    grid
}

/// The axes whose component errors have a reversal term.
fn reversal_axes(model: &ErrorModel, out: &mut BTreeSet<Axis>) {
    fn has_reversal(f: &ErrorFunction) -> bool {
        match f {
            ErrorFunction::Reversal(_) => true,
            ErrorFunction::Sum(terms) => terms.iter().any(has_reversal),
            _ => false,
        }
    }
    for p in model.parameters() {
        if let ParameterName::Component { axis, .. } = p.name
            && has_reversal(&p.function)
        {
            out.insert(axis);
        }
    }
}

/// The volumetric figure of `truth` compensated by `estimate`, two models of `machine`: the
/// deviations over [`volumetric_grid`] in the directions the module doc describes.
pub fn volumetric(machine: &Machine, truth: &ErrorModel, estimate: &ErrorModel) -> Volumetric {
    let mut reversing = BTreeSet::new();
    reversal_axes(truth, &mut reversing);
    reversal_axes(estimate, &mut reversing);
    let reversing: Vec<Axis> = reversing.into_iter().collect();
    let mut workspace = Workspace::new(machine);
    let (mut count, mut sum_raw, mut max_raw, mut sum_comp, mut max_comp) =
        (0usize, 0.0, 0.0 as Real, 0.0, 0.0 as Real);
    for position in volumetric_grid(machine) {
        for combination in 0..1usize << reversing.len() {
            let mut state = MachineState::at(position);
            for (bit, axis) in reversing.iter().enumerate() {
                if combination >> bit & 1 == 1 {
                    state.direction[axis.index()] = Direction::Negative;
                }
            }
            let d_truth = truth.deviation(machine, &mut workspace, &state).translation;
            let d_estimate = estimate
                .deviation(machine, &mut workspace, &state)
                .translation;
            let raw = d_truth.length() / RAD_PER_URAD;
            let compensated = (d_truth - d_estimate).length() / RAD_PER_URAD;
            count += 1;
            sum_raw += raw * raw;
            sum_comp += compensated * compensated;
            max_raw = max_raw.max(raw);
            max_comp = max_comp.max(compensated);
        }
    }
    let rms = |sum: Real| (sum / count.max(1) as Real).sqrt();
    Volumetric {
        points: count,
        uncompensated_rms_um: rms(sum_raw),
        uncompensated_max_um: max_raw,
        compensated_rms_um: rms(sum_comp),
        compensated_max_um: max_comp,
    }
}
