//! Teaching scenes in [rerun](https://rerun.io) (feature `viz`): the machine from its URDF
//! moving through a scenario's programme, its nominal and actual tool and workpiece frames,
//! the tool-tip error magnified, the volumetric map, the laser and ball-bar tests with their
//! curves and diagnostics, and discovery's residual before and after each effect.
//!
//! Everything is logged on one timeline, [`TIMELINE`] (programme time, s). The tests of a
//! scenario follow each other on it, 1 s apart: the laser test from 0, then each ball-bar circle, then a
//! tour of the volumetric grid; each starts from the machine as the scenario defines it (the
//! thermal model starts cold for the laser test only, as in `mtwin run`). The 3D scene is in
//! the bed frame (`world`, metres, z up); errors in it are enlarged by the magnification in
//! their entity names (`…_x1000`: 1 µm drawn as 1 mm). The 2D plots (entity roots `laser_plot`,
//! `ballbar_<plane>`, `discovery_*`) draw deviations with their own scale, stated in the
//! `lesson` text, y upward.
//!
//! Simplified: shapes are the URDF boxes, cylinders, capsules and spheres (meshes are listed in
//! the text panel, not drawn); the machine is drawn nominal (its errors are far too small to
//! see) and only the frames and arrows carry the magnified errors. During a laser test with a
//! thermal model the actual frames are known at the readings only (the temperatures are
//! integrated there), so they and the error arrow change at the readings and hold in between;
//! without one they follow every frame, with each axis's direction of travel from the path.

mod ballbar;
mod convert;
mod discovery;
mod laser;
mod machine;
mod plot;
mod volumetric;

use crate::io::{Scenario, Simulation};
use crate::math::Real;
use machine::MachineScene;
use std::path::Path;

pub use rerun::RecordingStream;

/// The timeline every scene is logged on: programme time (s).
pub const TIMELINE: &str = "program_time";
/// The lesson's explanation and the scene's legend (a Markdown text document).
pub const LESSON: &str = "lesson";
/// The 3D scene root, the machine bed frame (m, z up).
pub const WORLD: &str = "world";
/// The machine's links: `world/machine/<link>` (transform) with `…/visual_<i>` (shapes).
pub const MACHINE: &str = "world/machine";
/// The nominal tool frame (tool tip, z into the spindle) in the bed frame.
pub const TOOL_NOMINAL: &str = "world/tool_nominal";
/// The nominal workpiece frame in the bed frame; the arrows and maps of tool-tip errors are
/// its children, in its coordinates.
pub const WORKPIECE_NOMINAL: &str = "world/workpiece_nominal";
/// Time series of the tool-tip deviation (µm, workpiece frame): `…/dx`, `…/dy`, `…/dz`.
pub const TOOL_TIP_ERROR_UM: &str = "tool_tip_error_um";

/// `world/tool_actual_x<m>`: the actual tool frame with its error from nominal enlarged.
pub fn tool_actual(magnification: Real) -> String {
    format!("world/tool_actual_{}", factor(magnification))
}

/// `world/workpiece_actual_x<m>`: the actual workpiece frame, its error enlarged.
pub fn workpiece_actual(magnification: Real) -> String {
    format!("world/workpiece_actual_{}", factor(magnification))
}

/// `world/workpiece_nominal/tool_tip_error_x<m>`: an arrow from the nominal tool tip, the
/// deviation (actual − nominal, workpiece frame) times the magnification.
pub fn tool_tip_error(magnification: Real) -> String {
    format!(
        "{WORKPIECE_NOMINAL}/tool_tip_error_{}",
        factor(magnification)
    )
}

/// `x1000` for 1000, `x2_5` for 2.5.
fn factor(magnification: Real) -> String {
    format!("x{magnification}").replace('.', "_")
}

/// Why a recording failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VizError {
    /// The recording could not be written.
    #[error("recording: {0}")]
    Recording(String),
}

impl From<rerun::RecordingStreamError> for VizError {
    fn from(e: rerun::RecordingStreamError) -> VizError {
        VizError::Recording(e.to_string())
    }
}

/// Logs every scene of `scenario` and its `simulation` to `rec`; `progress` hears about the
/// long parts (discovery).
pub fn record(
    rec: &RecordingStream,
    scenario: &Scenario,
    simulation: &Simulation,
    progress: &mut dyn FnMut(&str),
) -> Result<(), VizError> {
    let magnification = scenario
        .lesson
        .as_ref()
        .map_or(crate::io::Lesson::DEFAULT_MAGNIFICATION, |l| {
            l.magnification
        });
    let mut legend = Vec::new();
    let mut scene = MachineScene::new(&scenario.twin, magnification);
    scene.log_static(rec, &mut legend)?;
    let mut start = 0.0;
    if let (Some(test), Some(run)) = (&scenario.laser_test, &simulation.laser) {
        start = laser::record(rec, &mut scene, scenario, test, run, &mut legend)? + 1.0;
        progress("discovery on the laser table");
        discovery::positioning(rec, &run.table, &mut legend, progress)?;
    }
    if let Some(test) = &scenario.ballbar_test {
        for (circle, table) in test.circles.iter().zip(&simulation.ballbar) {
            let end = ballbar::record(rec, &mut scene, test, circle, table, start, &mut legend)?;
            progress(&format!("discovery on the {} ball-bar table", circle.plane));
            discovery::ballbar(rec, circle, table, &mut legend, progress)?;
            start = end + 1.0;
        }
    }
    if let Some(map) = &simulation.volumetric {
        volumetric::record(rec, &mut scene, map, start, &mut legend)?;
    }
    let text = lesson_text(scenario, magnification, &legend);
    rec.log_static(LESSON, &rerun::TextDocument::from_markdown(text))?;
    layout(scenario, simulation).send(
        rec,
        rerun::blueprint::BlueprintActivation {
            make_active: true,
            make_default: true,
        },
    )?;
    Ok(())
}

/// The viewer's layout: the machine and the time series on the left, the lesson and the 2D
/// plots (one tab each) on the right.
fn layout(scenario: &Scenario, simulation: &Simulation) -> rerun::blueprint::Blueprint {
    use rerun::blueprint::{
        Blueprint, ContainerLike, Horizontal, Spatial2DView, Spatial3DView, Tabs, TextDocumentView,
        TimeSeriesView, Vertical,
    };
    let series_view = |name: &str, origin: String| -> ContainerLike {
        TimeSeriesView::new(name).with_origin(origin).into()
    };
    let plot_view = |name: &str, origin: String| -> ContainerLike {
        Spatial2DView::new(name).with_origin(origin).into()
    };
    let mut series = vec![series_view(
        "tool-tip deviation (µm)",
        format!("/{TOOL_TIP_ERROR_UM}"),
    )];
    let mut plots = Vec::new();
    if simulation.laser.is_some() {
        plots.push(plot_view(
            "laser: deviation against position",
            format!("/{}", laser::LASER_PLOT),
        ));
        plots.push(plot_view(
            "discovery: positioning residual",
            format!("/{}", discovery::DISCOVERY_POSITIONING),
        ));
        series.insert(
            0,
            series_view("laser (µm)", format!("/{}", laser::LASER_UM)),
        );
        if scenario.thermal.is_some() {
            series.insert(
                1,
                series_view(
                    "temperatures (°C)",
                    format!("/{}", laser::TEMPERATURES_DEGC),
                ),
            );
        }
    }
    for circle in scenario.ballbar_test.iter().flat_map(|t| &t.circles) {
        let plane = circle.plane;
        plots.push(plot_view(
            &format!("ball-bar {plane}"),
            format!("/{}", ballbar::plot_root(circle)),
        ));
        plots.push(plot_view(
            &format!("discovery: ball-bar {plane} residual"),
            format!("/{}", discovery::ballbar_root(circle)),
        ));
        let root = ballbar::series_root(circle);
        series.insert(
            0,
            series_view(&format!("ball-bar {plane} (µm)"), format!("/{root}")),
        );
    }
    let left = Vertical::new([
        Spatial3DView::new("machine (bed frame, m)")
            .with_origin(format!("/{WORLD}"))
            .into(),
        Tabs::new(series).into(),
    ])
    .with_row_shares([2.0, 1.0]);
    let mut right = vec![
        TextDocumentView::new("lesson")
            .with_origin(format!("/{LESSON}"))
            .into(),
    ];
    if !plots.is_empty() {
        right.push(Tabs::new(plots).into());
    }
    let collapsed = rerun::blueprint::components::PanelState::Collapsed;
    Blueprint::new(Horizontal::new([left.into(), Vertical::new(right).into()]))
        .with_blueprint_panel(rerun::blueprint::BlueprintPanel::from_state(collapsed))
        .with_selection_panel(rerun::blueprint::SelectionPanel::from_state(collapsed))
        .with_time_panel(rerun::blueprint::TimePanel::new().with_timeline(TIMELINE))
}

/// Records `scenario` into the file `path` (`.rrd`), replacing it.
pub fn save(
    path: &Path,
    scenario: &Scenario,
    simulation: &Simulation,
    progress: &mut dyn FnMut(&str),
) -> Result<(), VizError> {
    let rec = rerun::RecordingStreamBuilder::new("mtwin")
        .enabled(true)
        .save(path)
        .map_err(|e| VizError::Recording(format!("{}: {e}", path.display())))?;
    record(&rec, scenario, simulation, progress)?;
    rec.flush_blocking()
        .map_err(|e| VizError::Recording(format!("{}: {e}", path.display())))?;
    Ok(())
}

/// The lesson (or the scenario's description) followed by the legend of what was drawn.
fn lesson_text(scenario: &Scenario, magnification: Real, legend: &[String]) -> String {
    let mut text = match &scenario.lesson {
        Some(lesson) => format!("# {}\n\n{}\n", lesson.title, lesson.text.trim()),
        None => format!(
            "# {}\n\n{}\n",
            scenario.twin.machine.name(),
            scenario.description.as_deref().unwrap_or("").trim()
        ),
    };
    text += &format!(
        "\n## In this recording\n\nTimeline `{TIMELINE}` (s). 3D scene `{WORLD}`: the bed frame, metres, z up. \
         Errors in it are drawn {magnification} times enlarged (entity names end in `_{}`).\n\n",
        factor(magnification)
    );
    for line in legend {
        text += &format!("- {line}\n");
    }
    text
}
