//! # mtwin — a digital twin of a machine tool for metrology
//!
//! A virtual machine tool whose errors are known exactly. Machines come from URDF
//! ([`machine`]); ISO 230-1 geometric errors are injected ([`errors`]); the twin evaluates the
//! tool pose relative to the workpiece, nominal and actual ([`twin`]); analyses compute the
//! standards' figures from measurement tables ([`analysis`]); discovery extends the model
//! where measured data show it wrong ([`discovery`]); scenarios, tables and outputs are files
//! ([`io`]).
//!
//! Conventions (see `design.md`): SI and `f64` inside, mm/µm/µrad/° at the file boundary with
//! the unit in every name; a deviation is actual − nominal; frames are named `a_from_b`.
//!
//! ```
//! use mtwin::machine::{Axis, AxisValues, Machine};
//! let machine = Machine::from_urdf_file("models/vmc3.urdf").unwrap();
//! let position = AxisValues::from_file_units(&[(Axis::X, 100.0), (Axis::Z, 50.0)]);
//! let tool = machine.workpiece_from_tool(&position);
//! // At X = Y = Z = 0 the tool tip is at (-380, -205, 100) mm from the table centre.
//! assert!((tool.translation.x - (-0.28)).abs() < 1e-12);
//! ```

pub mod analysis;
pub mod discovery;
pub mod errors;
pub mod instruments;
pub mod io;
pub mod machine;
pub mod math;
pub mod program;
pub mod thermal;
pub mod twin;
#[cfg(feature = "viz")]
pub mod viz;
