//! The rerun SDK as the scenes use it, under one name (`rr`): recording streams and blueprints
//! from `re_sdk`, archetypes and components from `re_sdk_types`.
//!
//! The scenes depend on these two crates, not on the `rerun` umbrella crate: even with only
//! its `sdk` feature, `rerun` builds the client of rerun's data platform, its entity database
//! and query engine, analytics and a TLS stack, none of which writing an `.rrd` file needs
//! (63 packages; a clean build of the tests on 2 cores took 18.4 min with it, 16.0 without:
//! README, first section).

pub use re_sdk::{
    EntityPath, RecordingStream, RecordingStreamBuilder, RecordingStreamError, TimelineName,
    blueprint, external, log,
};
pub use re_sdk_types::archetypes::{
    Arrows3D, Boxes3D, Capsules3D, Cylinders3D, Ellipsoids3D, LineStrips2D, LineStrips3D, Points2D,
    Points3D, Scalars, TextDocument, Transform3D, TransformAxes3D, ViewCoordinates,
};
pub use re_sdk_types::components::{self, Color, FillMode};
pub use re_sdk_types::datatypes::Quaternion;
