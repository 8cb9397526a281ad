//! # mtwin — a digital twin of a machine tool for metrology
//!
//! A virtual machine tool whose errors are known exactly. Machines come from URDF
//! ([`machine`]); ISO 230-1 geometric errors are injected ([`errors`]), and thermal drift
//! ([`thermal`]); the twin evaluates the tool pose relative to the workpiece, nominal and
//! actual ([`twin`]); each test kind ([`kinds`]) measures it with a virtual instrument, writes
//! its table and computes the standards' figures from tables, simulated or real; discovery
//! extends the model where measured data show it wrong ([`discovery`]); [`app`] loads and
//! runs whole scenarios.
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
//!
//! # Layout
//!
//! Modules are layers: each uses only those above it in this list, and no two files import
//! each other.
//!
//! | layer | owns |
//! |---|---|
//! | [`math`] | `Real = f64`, glam aliases, unit constants, seeded random streams, small searches |
//! | [`machine`] | URDF → [`machine::Machine`], kinematics, inverse kinematics, planes, bodies |
//! | [`errors`] | ISO 230-1 error parameters and functions, where each enters the chain |
//! | [`thermal`] | the lumped thermal network, heat sources, sensors, thermal error terms |
//! | [`program`] | what the machine does over time (moves, dwells, warm-up strokes, visits) and the servo loops |
//! | [`twin`] | machine + errors (+ thermal) → actual poses, the ground truth |
//! | [`io`] | file primitives: the CSV dialect and header, located table errors, writing whole |
//! | [`contact`] | where a stylus ball touches an artefact: closed forms for analytic artefacts, parry for meshes |
//! | [`collision`] | collision checks of programmes: the machine's and an instrument's bodies swept with parry |
//! | [`scenario`] | scenario-file primitives: located errors, `[errors.*]`, `[thermal]`, `[lesson]` |
//! | [`discovery`] | the discovery engine (problems, folds, forward selection) |
//! | `viz` | rerun helpers and conventions (feature `viz`) |
//! | [`kinds`] | one folder per test kind: section, programme, instrument, table, run, analysis, discovery, command line, scene |
//! | [`app`] | a whole scenario: loading it from every kind's sections, running it, its output files and recording |
//!
//! `main.rs` is a thin command line: `run` and `check` over [`app`], and the `analyze` and
//! `discover` subcommands of every kind in [`kinds::KINDS`]. The guide to adding a test kind
//! is in [`kinds`].
//!
//! Running a scenario and analysing what it wrote:
//!
//! ```
//! use mtwin::app::{Scenario, simulate};
//! use mtwin::kinds::ballbar::{CircularTest, iso230_4};
//! let scenario = Scenario::load("scenarios/teach_squareness_ballbar.toml").unwrap();
//! let simulation = simulate(&scenario).unwrap();
//! let circle = &scenario.ballbar_test.as_ref().unwrap().circles[0];
//! let test = CircularTest { plane: circle.plane, radius: 0.1, feed: circle.feed };
//! let evaluation = iso230_4::evaluate(&simulation.ballbar[0], &test).unwrap();
//! // The lesson injects EC0Y = −40 µrad: the ball-bar reads squareness (R·s/2)·sin 2θ.
//! let squareness = evaluation.to_json()["diagnostics"]["squareness_um_per_m"]["value"]
//!     .as_f64()
//!     .unwrap();
//! assert!((squareness - 40.0).abs() < 2.0, "{squareness}");
//! ```

pub mod app;
pub mod collision;
pub mod contact;
pub mod discovery;
pub mod errors;
pub mod estimate;
pub mod io;
pub mod kinds;
pub mod machine;
pub mod math;
pub mod program;
pub mod scenario;
pub mod thermal;
pub mod twin;
#[cfg(feature = "viz")]
pub mod viz;
