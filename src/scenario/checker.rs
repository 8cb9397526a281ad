//! The located checks of one section: a value is refused at its own line, under its own key.
//!
//! [`Context::section_error`] finds a key's line by searching the section's text, for checks
//! that only have the section's span; a [`Checker`] is for sections read with a span on every
//! value (`toml::Spanned`), whose errors point at the value itself and fall back on the
//! section's own line when a value has no span (a default, or an absent key).

use super::{Context, ScenarioError, ScenarioErrorKind};
use std::fmt;
use std::ops::Range;
use toml::Spanned;

/// The checks of one section (`[spindle]`, `[probe]`, …): its errors are
/// [`ScenarioErrorKind::Value`] errors reading `<section>.<key>: <message>`.
pub struct Checker<'a> {
    context: &'a Context<'a>,
    section: Range<usize>,
    name: &'a str,
}

impl<'a> Checker<'a> {
    /// The checks of the section `name` (as messages name it, `spindle`) at `section` (its
    /// span in the file of `context`).
    pub fn new(context: &'a Context<'a>, section: Range<usize>, name: &'a str) -> Checker<'a> {
        Checker {
            context,
            section,
            name,
        }
    }

    /// The error about `key` (a path inside the section, `artefact.form[0].phase_deg`) at the
    /// line `span` starts on, or at the section's own line without a span (or with an empty
    /// one).
    pub fn fail(
        &self,
        span: Option<Range<usize>>,
        key: &str,
        message: impl fmt::Display,
    ) -> ScenarioError {
        let span = span
            .filter(|s| !s.is_empty())
            .unwrap_or(self.section.clone());
        self.context.error(
            Some(span),
            ScenarioErrorKind::Value,
            format!("{}.{key}: {message}", self.name),
        )
    }

    /// The value of `key` as `accept` takes it (or why not: the message of the error, at the
    /// value's line), or `default` when the key is absent.
    pub fn value<T: Copy, U>(
        &self,
        value: &Option<Spanned<T>>,
        key: &str,
        default: U,
        accept: impl FnOnce(T) -> Result<U, String>,
    ) -> Result<U, ScenarioError> {
        match value {
            None => Ok(default),
            Some(v) => {
                accept(*v.get_ref()).map_err(|message| self.fail(Some(v.span()), key, message))
            }
        }
    }
}
