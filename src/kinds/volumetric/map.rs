//! The volumetric error map: the deviation over a grid of axis positions.

use crate::errors::{Deviation, Lu2012Error};
use crate::machine::{Axis, AxisValues, MachineState, Workspace, axis_unit_to_si};
use crate::math::{M_PER_UM, RAD_PER_URAD, Real, fixed};
use crate::twin::{EvaluationModel, Twin};
use std::io::Write;

/// The values one axis takes on the grid (SI).
#[derive(Clone, Debug, PartialEq)]
pub struct GridAxis {
    /// The axis.
    pub axis: Axis,
    /// Its values (m or rad).
    pub values: Vec<Real>,
}

/// One grid point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumetricRow {
    /// Commanded axis values (SI).
    pub position: AxisValues,
    /// Actual − nominal tool pose, workpiece frame.
    pub deviation: Deviation,
}

/// A volumetric map: the grid axes and one row per grid point, the last grid axis varying
/// fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumetricMap {
    /// The axes of the grid, in the order they vary (outermost first).
    pub axes: Vec<Axis>,
    /// Whether the tool-axis tilt columns are written (machines with rotary axes).
    pub with_tilt: bool,
    /// The rows.
    pub rows: Vec<VolumetricRow>,
}

/// Evaluates `model` over the product of the `grid` axes (outermost first). Axes not on the grid
/// stay at zero; every axis moves in the positive direction.
pub fn volumetric_map(
    twin: &Twin,
    grid: &[GridAxis],
    model: EvaluationModel,
) -> Result<VolumetricMap, Lu2012Error> {
    let mut workspace = Workspace::new(&twin.machine);
    let count: usize = grid.iter().map(|g| g.values.len()).product();
    let mut rows = Vec::with_capacity(count);
    let mut index = vec![0usize; grid.len()];
    for _ in 0..count {
        let mut position = AxisValues::ZERO;
        for (g, &i) in grid.iter().zip(&index) {
            position[g.axis] = g.values[i];
        }
        let deviation = twin.deviation(&mut workspace, &MachineState::at(position), model)?;
        rows.push(VolumetricRow {
            position,
            deviation,
        });
        // Odometer increment, last axis fastest.
        for k in (0..grid.len()).rev() {
            index[k] += 1;
            if index[k] < grid[k].values.len() {
                break;
            }
            index[k] = 0;
        }
    }
    Ok(VolumetricMap {
        axes: grid.iter().map(|g| g.axis).collect(),
        with_tilt: twin.machine.rotary_axes().next().is_some(),
        rows,
    })
}

impl VolumetricMap {
    /// Writes `volumetric.csv`: `x_mm, y_mm, z_mm` (then `a_deg`/`b_deg`/`c_deg` as the grid
    /// has them), `dx_um, dy_um, dz_um` and, on machines with rotary axes, `ti_urad, tj_urad`.
    /// Positions to 1 nm / 1 µ°, deviations to 1 pm / 1 prad: fixed decimals, so the same map
    /// gives the same bytes.
    pub fn write_csv(&self, out: impl Write) -> csv::Result<()> {
        let mut linear: Vec<Axis> = self
            .axes
            .iter()
            .copied()
            .filter(|a| a.is_linear())
            .collect();
        let mut rotary: Vec<Axis> = self
            .axes
            .iter()
            .copied()
            .filter(|a| !a.is_linear())
            .collect();
        linear.sort();
        rotary.sort();
        let mut writer = csv::Writer::from_writer(out);
        let mut header: Vec<String> = linear
            .iter()
            .map(|a| format!("{}_mm", a.letter().to_ascii_lowercase()))
            .collect();
        header.extend(
            rotary
                .iter()
                .map(|a| format!("{}_deg", a.letter().to_ascii_lowercase())),
        );
        header.extend(["dx_um", "dy_um", "dz_um"].map(String::from));
        if self.with_tilt {
            header.extend(["ti_urad", "tj_urad"].map(String::from));
        }
        writer.write_record(&header)?;
        for row in &self.rows {
            let mut record: Vec<String> = Vec::with_capacity(header.len());
            for &axis in linear.iter().chain(&rotary) {
                record.push(fixed(row.position[axis] / axis_unit_to_si(axis), 6));
            }
            for value in row.deviation.translation.to_array() {
                record.push(fixed(value / M_PER_UM, 6));
            }
            if self.with_tilt {
                for value in row.deviation.tilt {
                    record.push(fixed(value / RAD_PER_URAD, 6));
                }
            }
            writer.write_record(&record)?;
        }
        writer.flush()?;
        Ok(())
    }
}

impl VolumetricMap {
    /// One line for people: the grid's size and the largest and RMS tool-tip deviation.
    pub fn summary(&self) -> String {
        let lengths: Vec<Real> = self
            .rows
            .iter()
            .map(|r| r.deviation.translation.length())
            .collect();
        let largest = lengths.iter().copied().fold(0.0, Real::max);
        let rms =
            (lengths.iter().map(|l| l * l).sum::<Real>() / lengths.len().max(1) as Real).sqrt();
        format!(
            "volumetric map: {} points, largest deviation {:.3} µm, RMS {:.3} µm",
            self.rows.len(),
            largest * 1e6,
            rms * 1e6
        )
    }
}
