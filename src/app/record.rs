//! The teaching recording of a whole scenario (feature `viz`): every test kind's scene on one
//! timeline, the lesson text with the legend of what was drawn, and the viewer's layout. The
//! conventions are in [`crate::viz`].

use super::{Scenario, Simulation};
use crate::kinds::{ballbar, positioning, probe, rtest, spindle, volumetric};
use crate::math::Real;
use crate::viz::machine::MachineScene;
use crate::viz::rr;
use crate::viz::{LESSON, RecordingStream, TIMELINE, TOOL_TIP_ERROR_UM, VizError, WORLD, factor};
use std::path::Path;

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
        .map_or(crate::scenario::Lesson::DEFAULT_MAGNIFICATION, |l| {
            l.magnification
        });
    let mut legend = Vec::new();
    let mut scene = MachineScene::new(&scenario.twin, magnification);
    scene.log_static(rec, &mut legend)?;
    let mut start = 0.0;
    if let (Some(test), Some(run)) = (&scenario.laser_test, &simulation.laser) {
        start = positioning::scene::record(
            rec,
            &mut scene,
            scenario.thermal.as_ref(),
            test,
            run,
            &mut legend,
        )? + 1.0;
        progress("discovery on the laser table");
        positioning::scene::discovery(rec, &run.table, &mut legend, progress)?;
    }
    if let Some(test) = &scenario.ballbar_test {
        for (circle, table) in test.circles.iter().zip(&simulation.ballbar) {
            let end =
                ballbar::scene::record(rec, &mut scene, test, circle, table, start, &mut legend)?;
            progress(&format!("discovery on the {} ball-bar table", circle.plane));
            ballbar::scene::discovery(rec, circle, table, &mut legend, progress)?;
            start = end + 1.0;
        }
    }
    if let (Some(test), Some(table)) = (&scenario.rtest, &simulation.rtest) {
        start = rtest::scene::record(rec, &mut scene, test, table, start, &mut legend)? + 1.0;
    }
    if let (Some(test), Some(run)) = (&scenario.probe_test, &simulation.probe) {
        start = probe::scene::record(rec, &mut scene, test, run, start, &mut legend)? + 1.0;
    }
    if let (Some(test), Some(table)) = (&scenario.spindle_test, &simulation.spindle) {
        start = spindle::scene::record(rec, &mut scene, test, table, start, &mut legend)? + 1.0;
    }
    if let Some(map) = &simulation.volumetric {
        volumetric::scene::record(rec, &mut scene, map, start, &mut legend)?;
    }
    let text = lesson_text(scenario, magnification, &legend);
    rec.log_static(LESSON, &rr::TextDocument::from_markdown(text))?;
    layout(scenario, simulation).send(
        rec,
        rr::blueprint::BlueprintActivation {
            make_active: true,
            make_default: true,
        },
    )?;
    Ok(())
}

/// The viewer's layout: the machine and the time series on the left, the lesson and the 2D
/// plots (one tab each) on the right.
fn layout(scenario: &Scenario, simulation: &Simulation) -> rr::blueprint::Blueprint {
    use rr::blueprint::{
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
            format!("/{}", positioning::scene::LASER_PLOT),
        ));
        plots.push(plot_view(
            "discovery: positioning residual",
            format!("/{}", positioning::scene::DISCOVERY_POSITIONING),
        ));
        series.insert(
            0,
            series_view("laser (µm)", format!("/{}", positioning::scene::LASER_UM)),
        );
        if scenario.thermal.is_some() {
            series.insert(
                1,
                series_view(
                    "temperatures (°C)",
                    format!("/{}", positioning::scene::TEMPERATURES_DEGC),
                ),
            );
        }
    }
    for circle in scenario.ballbar_test.iter().flat_map(|t| &t.circles) {
        let plane = circle.plane;
        plots.push(plot_view(
            &format!("ball-bar {plane}"),
            format!("/{}", ballbar::scene::plot_root(circle)),
        ));
        plots.push(plot_view(
            &format!("discovery: ball-bar {plane} residual"),
            format!("/{}", ballbar::scene::discovery_root(circle)),
        ));
        let root = ballbar::scene::series_root(circle);
        series.insert(
            0,
            series_view(&format!("ball-bar {plane} (µm)"), format!("/{root}")),
        );
    }
    if simulation.rtest.is_some() {
        series.insert(
            0,
            series_view("R-test (µm)", format!("/{}", rtest::scene::SERIES)),
        );
    }
    if simulation.probe.is_some() {
        series.insert(
            0,
            series_view("probe (µm)", format!("/{}", probe::scene::SERIES)),
        );
    }
    if simulation.spindle.is_some() {
        plots.push(plot_view(
            "spindle: polar plots",
            format!("/{}", spindle::scene::PLOT),
        ));
        series.insert(
            0,
            series_view(
                "spindle probes (µm)",
                format!("/{}", spindle::scene::SERIES),
            ),
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
    let collapsed = rr::blueprint::components::PanelState::Collapsed;
    Blueprint::new(Horizontal::new([left.into(), Vertical::new(right).into()]))
        .with_blueprint_panel(rr::blueprint::BlueprintPanel::from_state(collapsed))
        .with_selection_panel(rr::blueprint::SelectionPanel::from_state(collapsed))
        .with_time_panel(rr::blueprint::TimePanel::new().with_timeline(TIMELINE))
}

/// Records `scenario` into the file `path` (`.rrd`), replacing it.
pub fn save(
    path: &Path,
    scenario: &Scenario,
    simulation: &Simulation,
    progress: &mut dyn FnMut(&str),
) -> Result<(), VizError> {
    let rec = rr::RecordingStreamBuilder::new("mtwin")
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
