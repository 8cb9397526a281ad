//! The volumetric error map: an arrow per grid point from the nominal tool tip (workpiece
//! frame), the deviation enlarged and coloured by its size, and a tour of the grid.

use crate::kinds::volumetric::map::VolumetricMap;
use crate::machine::MachineState;
use crate::math::Real;
use crate::viz::convert::{cold_to_warm, vec3};
use crate::viz::machine::MachineScene;
use crate::viz::rr;
use crate::viz::{TIMELINE, VizError, WORKPIECE_NOMINAL};
use rr::RecordingStream;

/// How long the tour stands at each grid point (s), and the most points it visits.
const TOUR_STEP_S: Real = 0.5;
const TOUR_MAX_POINTS: usize = 2000;

/// `world/workpiece_nominal/volumetric_map_x<m>`.
pub fn map_path(magnification: Real) -> String {
    format!(
        "{WORKPIECE_NOMINAL}/volumetric_map_{}",
        crate::viz::factor(magnification)
    )
}

/// Logs the map (static) and the tour from programme time `start`; returns when it ends.
pub(crate) fn record(
    rec: &RecordingStream,
    scene: &mut MachineScene<'_>,
    map: &VolumetricMap,
    start: Real,
    legend: &mut Vec<String>,
) -> Result<Real, VizError> {
    let m = scene.magnification();
    let machine = &scene.twin().machine;
    let tips: Vec<_> = map
        .rows
        .iter()
        .map(|row| machine.workpiece_from_tool(&row.position).translation)
        .collect();
    let largest = map
        .rows
        .iter()
        .map(|r| r.deviation.translation.length())
        .fold(0.0, Real::max);
    let colours: Vec<rr::Color> = map
        .rows
        .iter()
        .map(|r| {
            cold_to_warm(if largest > 0.0 {
                r.deviation.translation.length() / largest
            } else {
                0.0
            })
        })
        .collect();
    rec.log_static(
        map_path(m),
        &rr::Arrows3D::from_vectors(map.rows.iter().map(|r| vec3(r.deviation.translation * m)))
            .with_origins(tips.iter().map(|t| vec3(*t)))
            .with_colors(colours),
    )?;
    let stride = map.rows.len().div_ceil(TOUR_MAX_POINTS).max(1);
    let mut time = start;
    for row in map.rows.iter().step_by(stride) {
        rec.set_duration_secs(TIMELINE, time);
        let state = MachineState::at(row.position);
        scene.log_nominal(rec, &state)?;
        let ends = scene.ends(&state, None);
        scene.log_actual(rec, &ends)?;
        time += TOUR_STEP_S;
    }
    legend.push(format!(
        "`{}`: the volumetric map ({} points): from each nominal tool tip (workpiece frame) the deviation, enlarged, blue small to red {:.2} µm; from {start:.1} s the machine tours the grid ({TOUR_STEP_S} s per point{}), its error arrow from the exact chain.",
        map_path(m),
        map.rows.len(),
        largest * 1e6,
        if stride > 1 { format!(", every {stride}th") } else { String::new() }
    ));
    Ok(time)
}
