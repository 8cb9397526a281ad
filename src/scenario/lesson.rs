//! The `[lesson]` section: what a teaching recording explains.

use super::{Context, ScenarioError, ScenarioErrorKind};
use crate::math::Real;
use serde::Deserialize;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLesson {
    title: String,
    text: String,
    #[serde(default = "default_magnification")]
    magnification: Real,
}

fn default_magnification() -> Real {
    Lesson::DEFAULT_MAGNIFICATION
}

/// What a teaching recording (`mtwin run --rrd`) explains and how much it magnifies errors.
#[derive(Clone, Debug, PartialEq)]
pub struct Lesson {
    /// A short title.
    pub title: String,
    /// What to look at and why (Markdown), logged as a text document.
    pub text: String,
    /// How many times errors are enlarged in the scenes (arrows, actual frames, traces).
    pub magnification: Real,
}

impl Lesson {
    /// The magnification of scenes without a `[lesson]`: 1 µm drawn as 1 mm.
    pub const DEFAULT_MAGNIFICATION: Real = 1000.0;
}

/// The `[lesson]` section, checked: a title, a text and a positive magnification.
pub(crate) fn lesson(
    context: &Context<'_>,
    section: &Spanned<RawLesson>,
) -> Result<Lesson, ScenarioError> {
    let l = section.get_ref();
    let problem = if l.title.trim().is_empty() {
        Some("lesson.title: empty; expected a short title")
    } else if l.text.trim().is_empty() {
        Some("lesson.text: empty; expected what to look at and why (Markdown)")
    } else if !(l.magnification.is_finite() && l.magnification > 0.0) {
        Some("lesson.magnification: expected a positive number (e.g. 1000: 1 µm drawn as 1 mm)")
    } else {
        None
    };
    if let Some(message) = problem {
        return Err(context.section_error(
            section.span(),
            ScenarioErrorKind::Value,
            "",
            message.to_string(),
        ));
    }
    Ok(Lesson {
        title: l.title.trim().to_string(),
        text: l.text.clone(),
        magnification: l.magnification,
    })
}
