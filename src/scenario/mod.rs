//! Scenario files, the parts every test kind shares: TOML, versioned (`schema = 1`), unknown keys rejected, every error naming
//! the file, the line and the key.
//!
//! ```toml
//! schema = 1
//! description = "what this scenario is for"
//! machine = "../models/vmc3.urdf"   # relative to this file
//! seed = 1
//!
//! [errors.EXX]                      # ISO 230-1 name; µm for translations, µrad for rotations
//! polynomial_um = [0.0, 0.010]      # c0 + c1·x (x in mm; mm or deg as the axis is)
//! reversal_um = 2.0                 # lost motion
//! harmonic = [{ period_mm = 10.0, amplitude_um = 0.4, phase_deg = 0.0 }]
//!
//! [errors.ECX]
//! table = { positions_mm = [0, 380, 760], values_urad = [0, 8, 3], interpolation = "cubic" }
//!
//! [errors.EC0Y]
//! constant_urad = 25.0
//!
//! [volumetric]                      # what to compute: the volumetric error map
//! model = "chain"                   # or "lu2012" (3-axis only)
//! x_mm = { from = 0.0, to = 760.0, count = 5 }   # default: the full travel, 5 points
//! ```
//!
//! The terms given for one parameter are summed. Rotary grid axes default to 5 points over
//! their travel, or 0, 90, 180, 270° for a continuous axis.
//!
//! A scenario may instead extend another (`schema = 1`, `extends = "base.toml"`, then only
//! `description`, `[errors.*]` and `[inputs]`): the base with those error sections replacing its own of the
//! same name (see [`crate::app::Scenario::load`]).
//!
//! This module holds what every section shares: located errors ([`ScenarioError`]), the key
//! finder that points an error at its line ([`Context`]), the located checks of a section read
//! with spans ([`Checker`]), the physical range of each kind of value ([`bounds`]), where the axes a test holds stand ([`parked`]), the `[errors.*]`
//! sections ([`errors`]), measured inputs and the temperature, heating and drift terms they
//! drive ([`inputs`]), the machine's thermal model (`[thermal]`, [`thermal`]) and the
//! teaching text (`[lesson]`, [`lesson`]). Each test kind reads its own sections in its folder
//! (`crate::kinds::<kind>::scenario`); [`crate::app::Scenario`] assembles them.

use std::fmt;

pub mod bounds;
pub mod checker;
pub mod error_spec;
pub mod errors;
pub mod inputs;
pub mod lesson;
pub mod parked;
pub mod record;
pub mod thermal;

pub use bounds::Bound;
pub use checker::Checker;
pub use errors::{ErrorSpec, HarmonicSpec, InterpolationSpec, TableSpec, function_of, spec_of};
pub use inputs::{DriftTermSpec, HeatingTermSpec, TemperatureTermSpec};
pub use lesson::Lesson;
pub use record::{parse_temperature_record, read_temperature_record};
pub use thermal::ThermalSetup;

/// The scenario schema this version reads.
pub const SCHEMA_VERSION: i64 = 1;

/// What went wrong with a scenario; the message names the file, line and key.
#[derive(Debug, thiserror::Error)]
#[error("{file}{}: {message}", .line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct ScenarioError {
    file: String,
    line: Option<usize>,
    kind: ScenarioErrorKind,
    message: String,
}

impl ScenarioError {
    /// Which check failed.
    pub fn kind(&self) -> ScenarioErrorKind {
        self.kind
    }

    /// What is wrong, without the file and line.
    pub fn message(&self) -> &str {
        &self.message
    }

    /// The 1-based line the error is at, when it has one.
    pub fn line(&self) -> Option<usize> {
        self.line
    }
}

/// The checks a scenario must pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ScenarioErrorKind {
    /// The file could not be read.
    Io,
    /// Not valid TOML, or a value of the wrong type or a missing key.
    Syntax,
    /// A key the schema does not know.
    UnknownKey,
    /// A missing or unsupported `schema` version.
    Schema,
    /// The machine model could not be loaded.
    Machine,
    /// An error parameter name that is not ISO 230-1 or not on this machine.
    Parameter,
    /// A value in the wrong unit for its parameter or axis.
    Units,
    /// An impossible value (not finite, a table out of order, a non-positive period, …).
    Value,
    /// A grid outside the travel or for an axis the machine lacks.
    Grid,
    /// An evaluation model that does not exist or does not fit the machine.
    Model,
    /// The scenario asks for nothing to compute.
    Nothing,
}

/// A scenario file being read: its name and text, to locate errors in it.
pub struct Context<'a> {
    file: String,
    text: &'a str,
}

impl<'a> Context<'a> {
    /// The file named `file` (as messages name it), whose text is `text`.
    pub fn new(file: String, text: &'a str) -> Context<'a> {
        Context { file, text }
    }
}

impl Context<'_> {
    /// An error of `kind` at the line `span` starts on (no line without a span).
    pub fn error(
        &self,
        span: Option<std::ops::Range<usize>>,
        kind: ScenarioErrorKind,
        message: impl fmt::Display,
    ) -> ScenarioError {
        ScenarioError {
            file: self.file.clone(),
            line: span.map(|s| {
                self.text[..s.start.min(self.text.len())]
                    .matches('\n')
                    .count()
                    + 1
            }),
            kind,
            message: message.to_string(),
        }
    }
}

impl Context<'_> {
    /// An error about the key its message starts with (`key: …`, `key.field: …` or
    /// `key must …`), at that key's line in the section starting at `section.start` (the
    /// section's own line if the key is not found there).
    pub fn section_error(
        &self,
        section: std::ops::Range<usize>,
        kind: ScenarioErrorKind,
        prefix: &str,
        message: String,
    ) -> ScenarioError {
        let key: String = message
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '.')
            .collect();
        let mut error = self.error(Some(section.clone()), kind, format!("{prefix}{message}"));
        if let Some(line) = (!key.is_empty())
            .then(|| self.key_line(section.start, &key))
            .flatten()
        {
            error.line = Some(line);
        }
        error
    }

    /// The 1-based line of `key` (a path inside a table such as `table.positions_mm` or
    /// `harmonic[1].period_mm`; its last field is searched for, from the line of its first
    /// field on, so that `asynchronous[0].amplitude_um` is not a harmonic's amplitude) in the
    /// table that starts at byte `table_start`: the table's own lines, up to the next
    /// `[header]`.
    pub fn key_line(&self, table_start: usize, key: &str) -> Option<usize> {
        let field = key.rsplit('.').next()?.split('[').next()?;
        let occurrence: usize = key
            .rsplit_once('[')
            .and_then(|(_, rest)| rest.split(']').next()?.parse().ok())
            .unwrap_or(0);
        let first_line = self.text[..table_start.min(self.text.len())]
            .matches('\n')
            .count();
        let parent = key.split(['.', '[']).next().filter(|p| *p != field);
        let from = match parent {
            Some(parent) => self
                .field_line(first_line, parent, 0)
                .map_or(first_line, |line| line - 1),
            None => first_line,
        };
        self.field_line(from, field, occurrence)
    }

    /// The 1-based line of the `occurrence`-th `field = …` from the 0-based line `first_line`
    /// on, within its table (or the last one seen, when there are fewer).
    fn field_line(&self, first_line: usize, field: &str, occurrence: usize) -> Option<usize> {
        let mut seen = 0;
        let mut last_seen = None;
        for (index, line) in self.text.lines().enumerate().skip(first_line) {
            let trimmed = line.trim_start();
            if index > first_line && trimmed.starts_with('[') && !trimmed.contains('=') {
                break; // the next table
            }
            for (position, _) in line.match_indices(field) {
                let before = line[..position].chars().next_back();
                let after = line[position + field.len()..].trim_start();
                let starts_key = before.is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
                if starts_key && after.starts_with('=') {
                    if seen == occurrence {
                        return Some(index + 1);
                    }
                    seen += 1;
                    last_seen = Some(index + 1);
                }
            }
        }
        // Fewer occurrences than the entry's index: entries may spell the field differently.
        last_seen
    }
}
