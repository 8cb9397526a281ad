//! Test kinds: one folder each, owning everything about one kind of measurement.
//!
//! | kind | folder | sections | tables | verbs |
//! |---|---|---|---|---|
//! | laser positioning (ISO 230-2, and the ISO 230-3 / warm-up tests measured by laser) | [`positioning`] | `[iso230_2]`, `[warmup]`, `[iso230_3_linear]`, `[laser]` | `positioning.csv` | `analyze`, `discover` |
//! | ball-bar (ISO 230-4) | [`ballbar`] | `[ballbar]`, `[servo]` | `ballbar_<plane>.csv` | `analyze`, `discover` |
//! | drift records (ISO 230-3) | [`drift`] | — | `drift` tables from other instruments | `analyze` |
//! | volumetric map | [`volumetric`] | `[volumetric]` | `volumetric.csv` | — |
//! | R-test (ISO 10791-6) | [`rtest`] | `[rtest]` | `rtest.csv` | `analyze` |
//! | touch probe on artefacts | [`probe`] | `[probe]` | `probe.csv`, `spheres.csv` | `analyze` |
//! | axes of rotation (ISO 230-7) | [`spindle`] | `[spindle]` | `spindle.csv` | `analyze` |
//!
//! A kind's folder holds, each in its own file: its scenario sections (`scenario.rs`: the
//! raw TOML structs and their checks, errors located by [`crate::scenario::Context`]), its
//! programme (what the machine does: `program.rs`), its instrument, its table schema
//! (`table.rs`: reader and writer, on [`crate::io`]'s CSV primitives), the run that turns a
//! section into tables and truth (`run.rs`), its analysis, its discovery problem (on
//! [`crate::discovery::engine`]), its command line (`cli.rs`) and its teaching scene
//! (`scene.rs`, feature `viz`, on `crate::viz`'s helpers).
//!
//! Layers: a kind's files use the shared layers below them (math, machine, errors, thermal,
//! program, twin, io, scenario, discovery, viz) and its own siblings, never another kind.
//! [`crate::app`] sits above every kind: it assembles a [`crate::app::Scenario`] from the
//! kinds' sections and runs it. A kind's `cli.rs` is the binary's layer; a verb that needs a
//! whole scenario (the one a discovered model extends) has it loaded by the layer above,
//! through the [`ScenarioLoader`] it is handed; nothing below imports it.
//!
//! # Adding a test kind (the ball-bar as the example)
//!
//! 1. **Folder.** `src/kinds/ballbar/mod.rs` declares the files and re-exports the kind's main
//!    types ([`ballbar::BallbarTable`], [`ballbar::BallbarTest`], …).
//! 2. **Section.** `scenario.rs`: `RawBallbar` and `RawServo` (`#[serde(deny_unknown_fields)]`,
//!    `toml::Spanned` where a message must point at a line) and `ballbar_test(context,
//!    machine, raw, servo) -> Result<BallbarTest, ScenarioError>`, which checks every value and
//!    names the key and line through `context.section_error`.
//! 3. **Programme and instrument.** `program.rs` ([`ballbar::CircularInterpolation`] and
//!    [`ballbar::run_circle`] through [`crate::program::AxisLoop`]s), `instrument.rs` (the
//!    virtual [`ballbar::Ballbar`] measuring the [`crate::twin::Twin`] at the servo's actual
//!    positions).
//! 4. **Table.** `table.rs`: columns with units in their names, `read`/`parse` (errors with
//!    file, line and column) and `write_csv`; the same reader serves simulated and real files.
//! 5. **Run.** `run.rs`: `simulate(twin, test, seed)` (random streams from
//!    [`crate::math::seeded_rng`] named after the component) and `truth(test)` for
//!    `truth.json`.
//! 6. **Analysis and discovery.** `iso230_4/` (the standard's figures and the diagnostics) and
//!    `discovery.rs` (a [`crate::discovery::engine::Problem`]).
//! 7. **Command line.** `cli.rs`: a [`Kind`] constant naming the kind, its sections and
//!    tables, and a [`Verb`] for each of `analyze`/`discover` it serves (flags as a
//!    `clap::Args` struct, the run returning what to print).
//! 8. **Registration.** The kind's [`Kind`] in [`KINDS`] (one line) puts its verbs on the
//!    command line; its section in [`crate::app::Scenario`] (a field, the raw section in
//!    `RawScenario`, one call in `Scenario::load`) and its run in [`crate::app::simulate`] and
//!    `Simulation::output` make `mtwin run` simulate it; `scene.rs` with one call in
//!    `app::record` draws it.

pub mod ballbar;
pub mod drift;
pub mod positioning;
pub mod probe;
pub mod rtest;
pub mod spindle;
pub mod volumetric;

use std::path::Path;

/// A test kind as the command line sees it.
#[derive(Clone, Copy)]
pub struct Kind {
    /// Its name on the command line (`mtwin analyze NAME`).
    pub name: &'static str,
    /// What its tables are, for people (`ball-bar tables`).
    pub tables_are: &'static str,
    /// The scenario sections it reads.
    pub sections: &'static [&'static str],
    /// The tables `mtwin run` writes for it.
    pub tables: &'static [&'static str],
    /// `mtwin analyze NAME`: the standards' figures from one of its tables.
    pub analyze: Option<Verb>,
    /// `mtwin discover NAME`: what the model of one of its tables gets wrong.
    pub discover: Option<Verb>,
}

/// A subcommand a kind serves.
#[derive(Clone, Copy)]
pub struct Verb {
    /// The subcommand, named after the kind, with its flags and help.
    pub command: fn() -> clap::Command,
    /// Runs it on the parsed flags and returns what to print on standard output; `progress`
    /// hears about long work, `scenarios` loads a scenario the flags name.
    pub run: VerbRun,
}

/// How a [`Verb`] runs: on the parsed flags, with a progress callback and the layer above's
/// [`ScenarioLoader`], returning what to print.
pub type VerbRun =
    fn(&clap::ArgMatches, &mut dyn FnMut(&str), &dyn ScenarioLoader) -> anyhow::Result<String>;

/// What a verb may ask of the layer above the kinds, where a whole scenario is assembled from
/// the shared sections and every kind's own ([`crate::app::Scenario`]): a verb whose output
/// extends a scenario (`discover --extends SCENARIO.toml`) has it loaded through this, so no
/// kind imports that layer.
pub trait ScenarioLoader {
    /// Loads the scenario at `path` and checks it whole, as `mtwin run` would.
    fn check(&self, path: &Path) -> anyhow::Result<()>;
    /// Loads the scenario at `path` as [`ScenarioLoader::check`] does and hands back its
    /// ball-bar test, if it has one.
    fn ballbar_test(&self, path: &Path) -> anyhow::Result<Option<ballbar::BallbarTest>>;
}

/// Every test kind, in the order the command line lists them.
pub const KINDS: &[Kind] = &[
    positioning::cli::KIND,
    drift::cli::KIND,
    ballbar::cli::KIND,
    volumetric::KIND,
    rtest::cli::KIND,
    probe::cli::KIND,
    spindle::cli::KIND,
];
