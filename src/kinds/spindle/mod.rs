//! Axes of rotation (ISO 230-7): a virtual spindle error analyser and its analysis.
//!
//! Capacitive or inductive displacement probes sense a precision artefact (a sphere, two
//! spheres or a cylinder) turning with an axis of rotation — the spindle `S` or a rotary axis
//! `C`, `A`, `B` — sampled on a once-per-revolution index, the arrangement of Lion Precision's
//! Spindle Error Analyzer and of IBS's spindle analysers.
//!
//! | file | owns |
//! |---|---|
//! | [`record`] | [`SpindleRecord`]: the samples of one record, probe by probe, with the probe geometry |
//! | [`scenario`] | the `[spindle]` section |
//! | [`program`] | what the axis does: speeds, revolutions, set-ups, the sample times and angles |
//! | [`instrument`] | the virtual analyser: artefact (eccentricity, form), probes (gain, noise, resolution, bandwidth) |
//! | [`run`] | the record through the twin, and its truth |
//! | [`table`] | the `spindle` table |
//! | [`stated`] | the preamble's `revolutions`, `speeds_rpm` and `setups` checked against the rows |
//! | [`analysis`] | ISO 230-7 evaluation: synchronous / asynchronous decomposition, the five polar-plot centres, values, spectrum, error separation |
//! | [`evaluate`] | which tests the probes allow (radial, axial, face, tilt; fixed or rotating sensitive direction), scored per set-up and speed, and the form separations |
//! | [`cli`] | `mtwin analyze spindle`: text, JSON and SVG |
//! | [`plot`] | the SVG polar plots, spectra and value-against-speed charts |
//! | [`discovery`] | `mtwin discover spindle`: what the synchronous model of a record leaves (asynchronous lines, harmonics, drift, speed dependence) |
//! | `scene` | the teaching scene (feature `viz`) |

pub mod analysis;
pub mod cli;
pub mod discovery;
pub mod evaluate;
pub mod instrument;
pub mod plausible;
pub mod plot;
pub mod program;
pub mod record;
pub mod run;
pub mod scenario;
#[cfg(feature = "viz")]
pub mod scene;
pub mod stated;
pub mod table;

pub use record::{Sensing, SpindleProbe, SpindleRecord};
