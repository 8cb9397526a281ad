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

pub(crate) mod convert;
pub(crate) mod machine;
pub(crate) mod plot;

use crate::math::Real;

pub mod rr;

pub use rr::RecordingStream;

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
pub(crate) fn factor(magnification: Real) -> String {
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

impl From<rr::RecordingStreamError> for VizError {
    fn from(e: rr::RecordingStreamError) -> VizError {
        VizError::Recording(e.to_string())
    }
}
