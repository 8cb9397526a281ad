//! The volumetric error map: the deviation of the tool from the workpiece over a grid of axis
//! positions, by the exact chain or by the Lu (2012) 21-component model.
//!
//! | file | owns |
//! |---|---|
//! | [`scenario`] | `[volumetric]` → [`VolumetricSpec`] |
//! | [`map`] | [`volumetric_map`] and its `volumetric.csv` |
//! | `scene` | the tour of the grid in the teaching scene (feature `viz`) |

pub mod map;
pub mod scenario;
#[cfg(feature = "viz")]
pub mod scene;

pub use map::{GridAxis, VolumetricMap, VolumetricRow, volumetric_map};
pub use scenario::{MAX_GRID_POINTS, VolumetricSpec};

/// This kind in the registry: a section and a table, no analysis of its own.
pub const KIND: super::Kind = super::Kind {
    name: "volumetric",
    tables_are: "volumetric maps",
    sections: &["volumetric"],
    tables: &["volumetric.csv"],
    analyze: None,
    discover: None,
};
