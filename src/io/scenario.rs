//! Scenario files: TOML, versioned (`schema = 1`), unknown keys rejected, every error naming
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
//! `description` and `[errors.*]`): the base with those error sections replacing its own of the
//! same name (see [`Scenario::load`]).

use crate::errors::{
    ErrorFunction, ErrorModel, ErrorModelError, ErrorParameter, Interpolation, ParameterName,
    Table, TableError,
};
use crate::machine::{Axis, Machine, axis_unit_to_si};
use crate::math::{RAD_PER_URAD, Real, sha256_hex};
use crate::twin::{EvaluationModel, GridAxis, Twin};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use toml::Spanned;

mod ballbar_test;
mod laser_test;
mod thermal_test;
pub use ballbar_test::BallbarTest;
pub use laser_test::LaserTest;
pub use thermal_test::ThermalSetup;

/// The most grid points a volumetric map may have (its rows are held in memory).
pub const MAX_GRID_POINTS: usize = 10_000_000;

/// The largest error the small-motion model is meant for: 10 mm or 10 mrad. Larger values are
/// typing mistakes (a unit off by 10³), not machine errors.
const LARGEST_ERROR: Real = 1e-2;

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

/// The terms of one error parameter, in file units (the `[errors.NAME]` table).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorSpec {
    /// Constant (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub constant_um: Option<Real>,
    /// Constant (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub constant_urad: Option<Real>,
    /// Polynomial coefficients from degree 0, in µm per (mm or deg)^k.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polynomial_um: Option<Vec<Real>>,
    /// Polynomial coefficients from degree 0, in µrad per (mm or deg)^k.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polynomial_urad: Option<Vec<Real>>,
    /// Lost motion (the axis lags the command by half of it against its direction of travel).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reversal_um: Option<Real>,
    /// Angular lost motion.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reversal_urad: Option<Real>,
    /// Cyclic errors.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub harmonic: Vec<HarmonicSpec>,
    /// A measured map.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub table: Option<TableSpec>,
}

/// `amplitude · sin(360° · q / period + phase)`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HarmonicSpec {
    /// Period along a linear axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_mm: Option<Real>,
    /// Period about a rotary axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_deg: Option<Real>,
    /// Amplitude (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_um: Option<Real>,
    /// Amplitude (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_urad: Option<Real>,
    /// Phase at q = 0.
    #[serde(default)]
    pub phase_deg: Real,
}

/// Values at knots, interpolated linearly or by a natural cubic spline; end values held
/// outside.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    /// Knots along a linear axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub positions_mm: Option<Vec<Real>>,
    /// Knots about a rotary axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub positions_deg: Option<Vec<Real>>,
    /// Values (translations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub values_um: Option<Vec<Real>>,
    /// Values (rotations).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub values_urad: Option<Vec<Real>>,
    /// `linear` (default) or `cubic`.
    #[serde(default)]
    pub interpolation: InterpolationSpec,
}

/// Table interpolation as written in files.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InterpolationSpec {
    /// Straight lines.
    #[default]
    Linear,
    /// Natural cubic spline.
    Cubic,
}

#[derive(Deserialize)]
struct SchemaOnly {
    schema: Option<Spanned<toml::Value>>,
}

#[derive(Deserialize)]
struct ExtendsOnly {
    extends: Option<toml::Value>,
}

/// How many scenarios deep `extends` may go.
const MAX_EXTENDS_DEPTH: usize = 8;

/// A scenario that extends another: only its errors (and description) differ.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawExtension {
    /// Checked before this struct is read.
    #[serde(rename = "schema")]
    _schema: i64,
    extends: Spanned<String>,
    #[serde(default)]
    description: Option<String>,
    #[serde(default)]
    errors: BTreeMap<Spanned<String>, Spanned<ErrorSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScenario {
    /// Checked before this struct is read.
    #[serde(rename = "schema")]
    _schema: i64,
    #[serde(default)]
    description: Option<String>,
    machine: Spanned<String>,
    seed: u64,
    #[serde(default)]
    errors: BTreeMap<Spanned<String>, Spanned<ErrorSpec>>,
    volumetric: Option<Spanned<RawVolumetric>>,
    iso230_2: Option<Spanned<laser_test::RawIso230_2>>,
    warmup: Option<Spanned<thermal_test::RawWarmup>>,
    iso230_3_linear: Option<Spanned<thermal_test::RawLinearMotion>>,
    laser: Option<Spanned<laser_test::RawLaser>>,
    thermal: Option<Spanned<thermal_test::RawThermal>>,
    ballbar: Option<Spanned<ballbar_test::RawBallbar>>,
    servo: Option<Spanned<ballbar_test::RawServo>>,
    lesson: Option<Spanned<RawLesson>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLesson {
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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawVolumetric {
    model: Option<Spanned<String>>,
    x_mm: Option<Spanned<RawRange>>,
    y_mm: Option<Spanned<RawRange>>,
    z_mm: Option<Spanned<RawRange>>,
    a_deg: Option<Spanned<RawRange>>,
    b_deg: Option<Spanned<RawRange>>,
    c_deg: Option<Spanned<RawRange>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRange {
    from: Real,
    to: Real,
    count: usize,
}

/// The volumetric map a scenario asks for.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumetricSpec {
    /// Chain (truth) or the Lu (2012) summed model.
    pub model: EvaluationModel,
    /// The grid, outermost axis first (rotary axes, then X, Y, Z).
    pub grid: Vec<GridAxis>,
}

/// A loaded and validated scenario.
#[derive(Clone, Debug)]
pub struct Scenario {
    /// The scenario file.
    pub file: PathBuf,
    /// SHA-256 of its bytes.
    pub sha256: String,
    /// Free text.
    pub description: Option<String>,
    /// Seed of every random stream.
    pub seed: u64,
    /// The machine model file.
    pub machine_file: PathBuf,
    /// SHA-256 of the machine model file.
    pub machine_sha256: String,
    /// Machine and injected errors.
    pub twin: Twin,
    /// The injected errors as written (file units), by name.
    pub error_specs: BTreeMap<String, ErrorSpec>,
    /// The volumetric map to compute, if asked for.
    pub volumetric: Option<VolumetricSpec>,
    /// The laser positioning test to simulate, if asked for.
    pub laser_test: Option<LaserTest>,
    /// The machine's thermal model, if the scenario has one: the laser test then runs through
    /// it (temperatures change the errors, sensors are read at each measurement).
    pub thermal: Option<ThermalSetup>,
    /// The ball-bar circular tests to simulate, if asked for.
    pub ballbar_test: Option<BallbarTest>,
    /// The explanation a teaching recording carries, if the scenario is a lesson.
    pub lesson: Option<Lesson>,
}

pub(super) struct Context<'a> {
    file: String,
    text: &'a str,
}

impl Context<'_> {
    pub(super) fn error(
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
    pub(super) fn section_error(
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
    /// `harmonic[1].period_mm`; its last field is searched for) in the table that starts at byte
    /// `table_start`: the table's own lines, up to the next `[header]`.
    pub(super) fn key_line(&self, table_start: usize, key: &str) -> Option<usize> {
        let field = key.rsplit('.').next()?.split('[').next()?;
        let occurrence: usize = key
            .split_once("harmonic[")
            .and_then(|(_, rest)| rest.split(']').next()?.parse().ok())
            .unwrap_or(0);
        let first_line = self.text[..table_start.min(self.text.len())]
            .matches('\n')
            .count();
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

impl Scenario {
    /// Reads and validates a scenario file, its machine and its errors, without running it.
    ///
    /// A scenario with `extends = "BASE.toml"` (relative to itself) is the base scenario with
    /// its own `[errors.*]` sections replacing the base's of the same name (and its
    /// `description`, if given); nothing else may be set. This is how `mtwin discover
    /// --write-model` hands an extended model back to `mtwin run`.
    pub fn load(path: impl AsRef<Path>) -> Result<Scenario, ScenarioError> {
        Scenario::load_at(path.as_ref(), 0)
    }

    /// [`Scenario::load`], `depth` files down a chain of `extends`.
    fn load_at(path: &Path, depth: usize) -> Result<Scenario, ScenarioError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ScenarioError {
            file: file.clone(),
            line: None,
            kind: ScenarioErrorKind::Io,
            message: format!("cannot read the scenario: {e}"),
        })?;
        let context = Context { file, text: &text };
        let toml_error = |mut e: toml::de::Error| {
            let message = e.message().trim().to_string();
            let kind = if message.starts_with("unknown field") {
                ScenarioErrorKind::UnknownKey
            } else {
                ScenarioErrorKind::Syntax
            };
            let span = e.span();
            // The key path is private to the error but printed when it has no input to quote.
            e.set_input(None);
            let rendered = e.to_string();
            let mut path = rendered
                .lines()
                .find_map(|l| l.strip_prefix("in `").and_then(|l| l.strip_suffix('`')))
                .unwrap_or_default()
                .to_string();
            if kind == ScenarioErrorKind::UnknownKey
                && let Some(field) = message.split('`').nth(1)
            {
                path = if path.is_empty() {
                    field.to_string()
                } else {
                    format!("{path}.{field}")
                };
            }
            let message = if path.is_empty() {
                message
            } else {
                format!("{path}: {message}")
            };
            context.error(span, kind, message)
        };
        let schema: SchemaOnly = toml::from_str(&text).map_err(toml_error)?;
        match schema.schema {
            None => {
                return Err(context.error(
                    None,
                    ScenarioErrorKind::Schema,
                    format!("schema: missing; expected `schema = {SCHEMA_VERSION}` at the top"),
                ));
            }
            Some(value) if value.get_ref().as_integer() != Some(SCHEMA_VERSION) => {
                return Err(context.error(
                    Some(value.span()),
                    ScenarioErrorKind::Schema,
                    format!(
                        "schema: {} is not supported; this mtwin reads schema {SCHEMA_VERSION}",
                        value.get_ref()
                    ),
                ));
            }
            Some(_) => {}
        }
        let probe: ExtendsOnly = toml::from_str(&text).map_err(toml_error)?;
        if probe.extends.is_some() {
            let raw: RawExtension = toml::from_str(&text).map_err(toml_error)?;
            return Scenario::extend(path, &text, &context, raw, depth);
        }
        let raw: RawScenario = toml::from_str(&text).map_err(toml_error)?;

        let machine_file = path
            .parent()
            .unwrap_or(Path::new(""))
            .join(raw.machine.get_ref());
        let machine_text = std::fs::read(&machine_file).map_err(|e| {
            context.error(
                Some(raw.machine.span()),
                ScenarioErrorKind::Machine,
                format!("machine: cannot read {}: {e}", machine_file.display()),
            )
        })?;
        // Parse the very bytes that are hashed into the manifest.
        let machine_error = |message: String| {
            context.error(
                Some(raw.machine.span()),
                ScenarioErrorKind::Machine,
                format!("machine: {message}"),
            )
        };
        let machine_source = std::str::from_utf8(&machine_text).map_err(|e| {
            machine_error(format!("{}: not UTF-8 text: {e}", machine_file.display()))
        })?;
        let machine = Machine::from_urdf_str(machine_source, &machine_file.display().to_string())
            .map_err(|e| machine_error(e.to_string()))?;

        let (errors, error_specs) = error_model(&context, &machine, &raw.errors, Vec::new())?;

        let volumetric = raw
            .volumetric
            .as_ref()
            .map(|v| volumetric_spec(&context, &machine, v))
            .transpose()?;
        let tests = [
            raw.iso230_2.as_ref().map(|t| t.span()),
            raw.warmup.as_ref().map(|t| t.span()),
            raw.iso230_3_linear.as_ref().map(|t| t.span()),
        ];
        let given: Vec<_> = tests.iter().flatten().collect();
        if let (true, Some(laser)) = (given.is_empty(), &raw.laser) {
            return Err(context.error(
                Some(laser.span()),
                ScenarioErrorKind::Nothing,
                "laser: a laser needs a test to measure; add an [iso230_2], [warmup] or [iso230_3_linear] section",
            ));
        }
        if given.len() > 1 {
            return Err(context.error(
                Some(given[1].clone()),
                ScenarioErrorKind::Value,
                "one laser test per scenario: [iso230_2], [warmup] or [iso230_3_linear]",
            ));
        }
        let thermal = raw
            .thermal
            .as_ref()
            .map(|t| thermal_test::thermal_setup(&context, &machine, t))
            .transpose()?;
        if let (Some(span), None) = (tests[1].clone().or(tests[2].clone()), &thermal) {
            return Err(context.error(
                Some(span),
                ScenarioErrorKind::Value,
                "warmup and iso230_3_linear are thermal tests: add a [thermal] section with the machine's thermal model",
            ));
        }
        let laser = raw.laser.as_ref();
        let laser_test = if let Some(test) = &raw.iso230_2 {
            Some(laser_test::laser_test(
                &context, &machine, raw.seed, test, laser,
            )?)
        } else if let Some(warmup) = &raw.warmup {
            Some(thermal_test::warmup_test(
                &context, &machine, warmup, laser,
            )?)
        } else if let Some(linear) = &raw.iso230_3_linear {
            Some(thermal_test::linear_motion_test(
                &context, &machine, linear, laser,
            )?)
        } else {
            None
        };
        if let (Some(setup), Some(test)) = (&thermal, &laser_test) {
            let duration: Real = test
                .program
                .timeline(Real::INFINITY)
                .iter()
                .map(|e| match e {
                    crate::program::Event::Interval(i) => i.duration,
                    crate::program::Event::Measure(_) => 0.0,
                })
                .sum();
            if duration / setup.max_interval > 5e6 {
                return Err(context.error(
                    raw.thermal.as_ref().map(|t| t.span()),
                    ScenarioErrorKind::Value,
                    format!(
                        "thermal.max_interval_s: {:.1} h in steps of {} s is more than five million steps",
                        duration / 3600.0,
                        setup.max_interval
                    ),
                ));
            }
        }
        if let (Some(_), Some(span)) = (
            &thermal,
            raw.laser
                .as_ref()
                .and_then(laser_test::air_temperature_given),
        ) {
            return Err(context.error(
                Some(span),
                ScenarioErrorKind::Value,
                "laser.air.temperature_degc: with [thermal] the laser's air is the machine's air (its ambient); set it there",
            ));
        }
        if let (Some(section), None) = (&raw.thermal, &laser_test) {
            return Err(context.error(
                Some(section.span()),
                ScenarioErrorKind::Nothing,
                "thermal: nothing in this scenario uses the thermal model; add a laser test ([iso230_2], [warmup] or [iso230_3_linear])",
            ));
        }
        if let Some((node, _)) = laser_test.as_ref().and_then(|t| t.material_sensor.as_ref()) {
            let known = thermal
                .as_ref()
                .is_some_and(|t| t.thermal.network.node(node).is_some());
            if !known {
                let span = raw.laser.as_ref().map(|l| l.span());
                return Err(context.error(
                    span,
                    ScenarioErrorKind::Value,
                    format!("laser.material.node: \"{node}\" is not a node of the [thermal] model (a material sensor on a node needs one)"),
                ));
            }
        }
        let ballbar_test = raw
            .ballbar
            .as_ref()
            .map(|b| ballbar_test::ballbar_test(&context, &machine, b, raw.servo.as_ref()))
            .transpose()?;
        if let (Some(servo), None) = (&raw.servo, &ballbar_test) {
            return Err(context.error(
                Some(servo.span()),
                ScenarioErrorKind::Nothing,
                "servo: nothing in this scenario uses the servo model; add a [ballbar] test",
            ));
        }
        let lesson = match &raw.lesson {
            None => None,
            Some(section) => {
                let l = section.get_ref();
                let problem = if l.title.trim().is_empty() {
                    Some("lesson.title: empty; expected a short title")
                } else if l.text.trim().is_empty() {
                    Some("lesson.text: empty; expected what to look at and why (Markdown)")
                } else if !(l.magnification.is_finite() && l.magnification > 0.0) {
                    Some(
                        "lesson.magnification: expected a positive number (e.g. 1000: 1 µm drawn as 1 mm)",
                    )
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
                Some(Lesson {
                    title: l.title.trim().to_string(),
                    text: l.text.clone(),
                    magnification: l.magnification,
                })
            }
        };
        if volumetric.is_none() && laser_test.is_none() && ballbar_test.is_none() {
            return Err(context.error(
                None,
                ScenarioErrorKind::Nothing,
                "nothing to compute: add a [volumetric], [iso230_2], [warmup], [iso230_3_linear] or [ballbar] section",
            ));
        }

        Ok(Scenario {
            file: path.to_path_buf(),
            sha256: sha256_hex(text.as_bytes()),
            description: raw.description,
            seed: raw.seed,
            machine_sha256: sha256_hex(&machine_text),
            machine_file,
            twin: Twin { machine, errors },
            error_specs,
            volumetric,
            laser_test,
            thermal,
            ballbar_test,
            lesson,
        })
    }
}

/// Builds the error model of `machine` from the `[errors.*]` sections of one file (messages
/// name it through `context`), on top of `inherited` parameters (an extended scenario's), which
/// the sections replace by name. Returns the model and the specs as written.
fn error_model(
    context: &Context<'_>,
    machine: &Machine,
    errors_raw: &BTreeMap<Spanned<String>, Spanned<ErrorSpec>>,
    inherited: Vec<ErrorParameter>,
) -> Result<(ErrorModel, BTreeMap<String, ErrorSpec>), ScenarioError> {
    let mut parameters = Vec::new();
    let mut error_specs = BTreeMap::new();
    for (name, spec) in errors_raw {
        let at = Some(name.span());
        let parameter: ParameterName = name.get_ref().parse().map_err(|message| {
            context.error(
                at.clone(),
                ScenarioErrorKind::Parameter,
                format!("errors.{}: {message}", name.get_ref()),
            )
        })?;
        let argument = parameter
            .axis()
            .filter(|_| matches!(parameter, ParameterName::Component { .. }));
        if let Some(axis) = parameter.axis().filter(|axis| !machine.has_axis(*axis)) {
            return Err(context.error(
                at,
                ScenarioErrorKind::Parameter,
                format!(
                    "errors.{parameter}: machine \"{}\" has no axis {axis}",
                    machine.name()
                ),
            ));
        }
        if *spec.get_ref() == ErrorSpec::default() {
            let unit = parameter.file_unit();
            return Err(context.error(
                Some(spec.span()),
                ScenarioErrorKind::Value,
                format!(
                    "errors.{parameter}: no term given; expected one or more of constant_{unit}, \
                     polynomial_{unit}, reversal_{unit}, harmonic, table"
                ),
            ));
        }
        let key_error = |kind, key: &str, message: String| {
            let line = context.key_line(spec.span().start, key);
            let mut error = context.error(
                Some(spec.span()),
                kind,
                format!("errors.{parameter}.{key}: {message}"),
            );
            error.line = line.or(error.line);
            error
        };
        let function = spec_to_function(spec.get_ref(), parameter, argument)
            .map_err(|(kind, key, message)| key_error(kind, &key, message))?;
        if argument.is_none() && !function.is_constant() {
            return Err(key_error(
                ScenarioErrorKind::Value,
                varying_key(spec.get_ref()),
                format!(
                    "location, squareness and tool errors are constants; use constant_{}",
                    parameter.file_unit()
                ),
            ));
        }
        parameters.push(ErrorParameter {
            name: parameter,
            function,
        });
        error_specs.insert(parameter.to_string(), spec.get_ref().clone());
    }
    let mut all: Vec<ErrorParameter> = inherited
        .into_iter()
        .filter(|p| !error_specs.contains_key(&p.name.to_string()))
        .collect();
    all.extend(parameters);
    let errors = ErrorModel::new(machine, all).map_err(|e| {
        let name = e.parameter().to_string();
        let span = errors_raw
            .iter()
            .find(|(key, _)| *key.get_ref() == name)
            .map(|(_, spec)| spec.span());
        let kind = match e {
            ErrorModelError::NotPeriodic { .. } | ErrorModelError::NotConstant(_) => {
                ScenarioErrorKind::Value
            }
            _ => ScenarioErrorKind::Parameter,
        };
        context.error(span, kind, format!("errors.{e}"))
    })?;
    for parameter in errors.parameters() {
        if let Some(message) = implausible(parameter, machine) {
            let spec = errors_raw
                .iter()
                .find(|(key, _)| *key.get_ref() == parameter.name.to_string());
            return Err(context.error(
                spec.map(|(_, spec)| spec.span()),
                ScenarioErrorKind::Value,
                format!("errors.{}: {message}", parameter.name),
            ));
        }
    }
    Ok((errors, error_specs))
}

impl Scenario {
    /// The scenario `raw` (read from `path`, whose text is `text`) extends.
    fn extend(
        path: &Path,
        text: &str,
        context: &Context<'_>,
        raw: RawExtension,
        depth: usize,
    ) -> Result<Scenario, ScenarioError> {
        if depth >= MAX_EXTENDS_DEPTH {
            return Err(context.error(
                Some(raw.extends.span()),
                ScenarioErrorKind::Value,
                format!("extends: more than {MAX_EXTENDS_DEPTH} scenarios deep (do they extend each other?)"),
            ));
        }
        let base_path = path
            .parent()
            .unwrap_or(Path::new(""))
            .join(raw.extends.get_ref());
        let base = Scenario::load_at(&base_path, depth + 1).map_err(|e| {
            context.error(Some(raw.extends.span()), e.kind, format!("extends: {e}"))
        })?;
        let inherited = base.twin.errors.parameters().to_vec();
        let (errors, specs) = error_model(context, &base.twin.machine, &raw.errors, inherited)?;
        let mut error_specs = base.error_specs;
        error_specs.extend(specs);
        Ok(Scenario {
            file: path.to_path_buf(),
            // The base's content is part of what this file means.
            sha256: sha256_hex(format!("{text}\n{}", base.sha256).as_bytes()),
            description: raw.description.or(base.description),
            twin: Twin {
                machine: base.twin.machine,
                errors,
            },
            error_specs,
            ..base
        })
    }
}

fn volumetric_spec(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawVolumetric>,
) -> Result<VolumetricSpec, ScenarioError> {
    let v = raw.get_ref();
    let model = match &v.model {
        None => EvaluationModel::Chain,
        Some(name) => match name.get_ref().as_str() {
            "chain" => EvaluationModel::Chain,
            "lu2012" if machine.rotary_axes().next().is_some() => {
                return Err(context.error(
                    Some(name.span()),
                    ScenarioErrorKind::Model,
                    "volumetric.model: \"lu2012\" is the 21-component 3-axis model; this machine has rotary axes",
                ));
            }
            "lu2012" => EvaluationModel::Lu2012,
            other => {
                return Err(context.error(
                    Some(name.span()),
                    ScenarioErrorKind::Model,
                    format!("volumetric.model: \"{other}\" is not a model; expected \"chain\" or \"lu2012\""),
                ));
            }
        },
    };
    let given = [
        (Axis::A, "a_deg", &v.a_deg),
        (Axis::B, "b_deg", &v.b_deg),
        (Axis::C, "c_deg", &v.c_deg),
        (Axis::X, "x_mm", &v.x_mm),
        (Axis::Y, "y_mm", &v.y_mm),
        (Axis::Z, "z_mm", &v.z_mm),
    ];
    let mut grid = Vec::new();
    for (axis, key, range) in given {
        let info = machine.axis(axis);
        let range = match (info, range) {
            (None, None) => continue,
            (None, Some(range)) => {
                return Err(context.error(
                    Some(range.span()),
                    ScenarioErrorKind::Grid,
                    format!(
                        "volumetric.{key}: machine \"{}\" has no axis {axis}",
                        machine.name()
                    ),
                ));
            }
            (Some(info), None) => default_range(info.limits),
            (Some(info), Some(spanned)) => {
                let RawRange { from, to, count } = *spanned.get_ref();
                let fail = |message: String| {
                    context.error(
                        Some(spanned.span()),
                        ScenarioErrorKind::Grid,
                        format!("volumetric.{key}: {message}"),
                    )
                };
                if !(from.is_finite() && to.is_finite()) {
                    return Err(fail("from and to must be finite numbers".into()));
                }
                if count == 0 {
                    return Err(fail("count must be at least 1".into()));
                }
                let scale = axis_unit_to_si(axis);
                if let Some((lower, upper)) = info.limits {
                    for value in [from, to] {
                        if !info.within_travel(value * scale) {
                            return Err(fail(format!(
                                "{value} is outside the travel of {axis} ({} .. {} {})",
                                lower / scale,
                                upper / scale,
                                &key[2..]
                            )));
                        }
                    }
                }
                if count > MAX_GRID_POINTS {
                    return Err(fail(format!(
                        "count {count} is more than the {MAX_GRID_POINTS} points a map may have"
                    )));
                }
                (from * scale, to * scale, count)
            }
        };
        let (from, to, count) = range;
        let values = (0..count)
            .map(|i| {
                if count == 1 {
                    from
                } else {
                    from + (to - from) * i as Real / (count - 1) as Real
                }
            })
            .collect();
        grid.push(GridAxis { axis, values });
    }
    let points = grid
        .iter()
        .try_fold(1usize, |product, g| product.checked_mul(g.values.len()));
    if points.is_none_or(|p| p > MAX_GRID_POINTS) {
        return Err(context.error(
            Some(raw.span()),
            ScenarioErrorKind::Grid,
            format!(
                "volumetric: the grid has {} points; at most {MAX_GRID_POINTS}",
                grid.iter()
                    .map(|g| g.values.len().to_string())
                    .collect::<Vec<_>>()
                    .join(" × ")
            ),
        ));
    }
    Ok(VolumetricSpec { model, grid })
}

/// The full travel with 5 points; 0, 90, 180, 270° for a continuous axis.
fn default_range(limits: Option<(Real, Real)>) -> (Real, Real, usize) {
    match limits {
        Some((lower, upper)) => (lower, upper, 5),
        None => (0.0, 270.0 * crate::math::RAD_PER_DEG, 4),
    }
}

/// What is wrong with one key of an `[errors.NAME]` table: the kind, the key's path inside the
/// table (e.g. `table.positions_deg`) and the message.
type SpecError = (ScenarioErrorKind, String, String);

/// Turns the terms of `[errors.NAME]` into a function (SI), checking units and values.
/// `argument` is the axis whose position the function takes (component errors only).
fn spec_to_function(
    spec: &ErrorSpec,
    name: ParameterName,
    argument: Option<Axis>,
) -> Result<ErrorFunction, SpecError> {
    use ScenarioErrorKind::{Units, Value};
    let translation = name.motion().is_translation();
    let (value_unit, other_unit) = if translation {
        ("um", "urad")
    } else {
        ("urad", "um")
    };
    let (position_unit, other_position_unit) = match argument {
        Some(axis) if !axis.is_linear() => ("deg", "mm"),
        _ => ("mm", "deg"),
    };
    let position_scale = argument.map_or(crate::math::M_PER_MM, axis_unit_to_si);
    let value_scale = RAD_PER_URAD; // µm → m and µrad → rad are the same factor
    fn fail<T>(kind: ScenarioErrorKind, key: String, message: String) -> Result<T, SpecError> {
        Err((kind, key, message))
    }
    let wrong_value_unit = |key: &str| -> SpecError {
        let what = if translation {
            "a translation"
        } else {
            "a rotation"
        };
        (
            Units,
            format!("{key}_{other_unit}"),
            format!("{name} is {what}; give it in {value_unit} as {key}_{value_unit}"),
        )
    };
    let wrong_position_unit = |key: &str| -> SpecError {
        (
            Units,
            format!("{key}_{other_position_unit}"),
            format!("the axis is measured in {position_unit}; give {key}_{position_unit}"),
        )
    };
    let finite = |key: String, values: &[Real]| -> Result<(), SpecError> {
        match values.iter().position(|v| !v.is_finite()) {
            Some(i) if values.len() > 1 => fail(
                Value,
                key,
                format!("value {} is not a finite number", i + 1),
            ),
            Some(_) => fail(Value, key, "not a finite number".into()),
            None => Ok(()),
        }
    };
    let by_unit = |um: &Option<Real>, urad: &Option<Real>| {
        if translation {
            (*um, *urad)
        } else {
            (*urad, *um)
        }
    };

    let mut terms = Vec::new();
    let (constant, constant_other) = by_unit(&spec.constant_um, &spec.constant_urad);
    if constant_other.is_some() {
        return Err(wrong_value_unit("constant"));
    }
    if let Some(c) = constant {
        finite(format!("constant_{value_unit}"), &[c])?;
        terms.push(ErrorFunction::Constant(c * value_scale));
    }
    let (polynomial, polynomial_other) = if translation {
        (&spec.polynomial_um, &spec.polynomial_urad)
    } else {
        (&spec.polynomial_urad, &spec.polynomial_um)
    };
    if polynomial_other.is_some() {
        return Err(wrong_value_unit("polynomial"));
    }
    if let Some(coefficients) = polynomial {
        let key = format!("polynomial_{value_unit}");
        finite(key.clone(), coefficients)?;
        if coefficients.is_empty() {
            return fail(Value, key, "give at least one coefficient".into());
        }
        let si = coefficients
            .iter()
            .enumerate()
            .map(|(k, c)| c * value_scale / position_scale.powi(k as i32))
            .collect();
        terms.push(ErrorFunction::Polynomial(si));
    }
    let (reversal, reversal_other) = by_unit(&spec.reversal_um, &spec.reversal_urad);
    if reversal_other.is_some() {
        return Err(wrong_value_unit("reversal"));
    }
    if let Some(r) = reversal {
        finite(format!("reversal_{value_unit}"), &[r])?;
        terms.push(ErrorFunction::Reversal(r * value_scale));
    }
    for (i, h) in spec.harmonic.iter().enumerate() {
        let key = |field: &str| format!("harmonic[{i}].{field}");
        let (period, period_other) = if position_unit == "mm" {
            (h.period_mm, h.period_deg)
        } else {
            (h.period_deg, h.period_mm)
        };
        if period_other.is_some() {
            let (kind, field, message) = wrong_position_unit("period");
            return fail(kind, key(&field), message);
        }
        let (amplitude, amplitude_other) = by_unit(&h.amplitude_um, &h.amplitude_urad);
        if amplitude_other.is_some() {
            let (kind, field, message) = wrong_value_unit("amplitude");
            return fail(kind, key(&field), message);
        }
        let period_key = key(&format!("period_{position_unit}"));
        let Some(period) = period else {
            return fail(Value, period_key, "required".into());
        };
        let amplitude_key = key(&format!("amplitude_{value_unit}"));
        let Some(amplitude) = amplitude else {
            return fail(Value, amplitude_key, "required".into());
        };
        finite(period_key.clone(), &[period])?;
        finite(amplitude_key, &[amplitude])?;
        finite(key("phase_deg"), &[h.phase_deg])?;
        if (period * position_scale).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return fail(Value, period_key, format!("must be positive, got {period}"));
        }
        terms.push(ErrorFunction::Harmonic {
            period: period * position_scale,
            amplitude: amplitude * value_scale,
            phase: h.phase_deg * crate::math::RAD_PER_DEG,
        });
    }
    if let Some(t) = &spec.table {
        let key = |field: &str| format!("table.{field}");
        let (positions, positions_other) = if position_unit == "mm" {
            (&t.positions_mm, &t.positions_deg)
        } else {
            (&t.positions_deg, &t.positions_mm)
        };
        if positions_other.is_some() {
            let (kind, field, message) = wrong_position_unit("positions");
            return fail(kind, key(&field), message);
        }
        let (values, values_other) = if translation {
            (&t.values_um, &t.values_urad)
        } else {
            (&t.values_urad, &t.values_um)
        };
        if values_other.is_some() {
            let (kind, field, message) = wrong_value_unit("values");
            return fail(kind, key(&field), message);
        }
        let positions_key = key(&format!("positions_{position_unit}"));
        let values_key = key(&format!("values_{value_unit}"));
        let Some(positions) = positions else {
            return fail(Value, positions_key, "required".into());
        };
        let Some(values) = values else {
            return fail(Value, values_key, "required".into());
        };
        finite(positions_key.clone(), positions)?;
        finite(values_key.clone(), values)?;
        let interpolation = match t.interpolation {
            InterpolationSpec::Linear => Interpolation::Linear,
            InterpolationSpec::Cubic => Interpolation::Cubic,
        };
        let table = Table::new(
            positions.iter().map(|p| p * position_scale).collect(),
            values.iter().map(|v| v * value_scale).collect(),
            interpolation,
        );
        match table {
            Ok(table) => terms.push(ErrorFunction::Table(table)),
            Err(e @ TableError::Shape { .. }) => return fail(Value, key("values"), e.to_string()),
            Err(e @ TableError::Order(_)) => return fail(Value, positions_key, e.to_string()),
            Err(e @ TableError::Value(_)) => return fail(Value, values_key, e.to_string()),
        }
    }
    match terms.len() {
        1 => Ok(terms.pop().expect("one term")),
        _ => Ok(ErrorFunction::Sum(terms)),
    }
}

/// Why an error parameter is not a plausible machine error, if it is not: its largest value
/// over its axis's travel (or a turn, sampled at 1001 points) beyond [`LARGEST_ERROR`], or not
/// finite once in SI units (e.g. a period that underflows to zero).
fn implausible(parameter: &ErrorParameter, machine: &Machine) -> Option<String> {
    let (lower, upper) = match parameter.name {
        ParameterName::Component { axis, .. } => machine
            .axis(axis)
            .and_then(|info| info.limits)
            .unwrap_or((0.0, std::f64::consts::TAU)),
        _ => (0.0, 0.0),
    };
    let mut largest: Real = 0.0;
    for i in 0..=1000 {
        let q = lower + (upper - lower) * i as Real / 1000.0;
        for direction in [
            crate::machine::Direction::Positive,
            crate::machine::Direction::Negative,
        ] {
            let value = parameter.function.value(q, direction);
            if !value.is_finite() {
                return Some(format!(
                    "not a finite number at {q} (SI units) once converted"
                ));
            }
            largest = largest.max(value.abs());
        }
    }
    let unit = parameter.name.file_unit();
    (largest > LARGEST_ERROR).then(|| {
        format!(
            "reaches {:.0} {unit} over the travel, more than the {:.0} {unit} the small-motion error model is for",
            largest / RAD_PER_URAD,
            LARGEST_ERROR / RAD_PER_URAD
        )
    })
}

/// The first key of a spec that makes it vary with position or direction (to name it when a
/// constant is required).
fn varying_key(spec: &ErrorSpec) -> &'static str {
    let candidates: [(&'static str, bool); 7] = [
        (
            "polynomial_um",
            spec.polynomial_um.as_ref().is_some_and(|c| c.len() > 1),
        ),
        (
            "polynomial_urad",
            spec.polynomial_urad.as_ref().is_some_and(|c| c.len() > 1),
        ),
        ("reversal_um", spec.reversal_um.is_some()),
        ("reversal_urad", spec.reversal_urad.is_some()),
        ("harmonic", !spec.harmonic.is_empty()),
        ("table", spec.table.is_some()),
        ("", true),
    ];
    candidates
        .into_iter()
        .find(|(_, present)| *present)
        .map_or("", |(key, _)| key)
}
