//! A whole scenario: the machine, its errors and every test kind's sections, loaded and checked
//! together (see [`crate::scenario`] for the file format and the shared sections).

use crate::errors::TemperatureRecord;
use crate::kinds::ScenarioLoader;
use crate::kinds::ballbar::{self, BallbarTest};
use crate::kinds::drift::{self, EtveTest, SpindleThermalTest};
use crate::kinds::positioning::{self, LaserTest};
use crate::kinds::probe::{self, ProbeTest};
use crate::kinds::rtest::{self, RTest};
use crate::kinds::spindle::{self, scenario::SpindleTest};
use crate::kinds::volumetric::{self, VolumetricSpec};
use crate::machine::Machine;
use crate::math::sha256_hex;
use crate::scenario::errors::error_model;
use crate::scenario::inputs::RawInputs;
use crate::scenario::lesson::RawLesson;
use crate::scenario::thermal::{RawThermal, thermal_setup};
use crate::scenario::{
    Context, ErrorSpec, Lesson, SCHEMA_VERSION, ScenarioError, ScenarioErrorKind, ThermalSetup,
};
use crate::thermal::ThermalErrors;
use crate::twin::Twin;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Spanned;

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

/// A scenario that extends another: its errors, measured inputs, servo (over the base's ball-bar
/// test) and description differ.
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
    inputs: Option<Spanned<RawInputs>>,
    /// Servo keys over the base's (its ball-bar test's servo).
    servo: Option<Spanned<ballbar::scenario::RawServo>>,
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
    inputs: Option<Spanned<RawInputs>>,
    volumetric: Option<Spanned<volumetric::scenario::RawVolumetric>>,
    iso230_2: Option<Spanned<positioning::scenario::RawIso230_2>>,
    warmup: Option<Spanned<positioning::scenario::thermal_tests::RawWarmup>>,
    iso230_3_linear: Option<Spanned<positioning::scenario::thermal_tests::RawLinearMotion>>,
    laser: Option<Spanned<positioning::scenario::RawLaser>>,
    thermal: Option<Spanned<RawThermal>>,
    iso230_3_etve: Option<Spanned<drift::scenario::RawEtve>>,
    iso230_3_spindle: Option<Spanned<drift::spindle_test::RawSpindleTest>>,
    ballbar: Option<Spanned<ballbar::scenario::RawBallbar>>,
    servo: Option<Spanned<ballbar::scenario::RawServo>>,
    rtest: Option<Spanned<rtest::scenario::RawRtest>>,
    probe: Option<Spanned<probe::scenario::RawProbe>>,
    spindle: Option<Spanned<spindle::scenario::RawSpindle>>,
    lesson: Option<Spanned<RawLesson>>,
    /// Read and checked by [`super::dataset`] (`mtwin dataset`); a run ignores it.
    #[serde(rename = "dataset")]
    _dataset: Option<toml::Value>,
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
    /// The machine's thermal model, if the scenario has one: the laser and ETVE tests then run
    /// through it (temperatures change the errors, sensors are read at each measurement).
    pub thermal: Option<ThermalSetup>,
    /// The ISO 230-3 ETVE test to simulate, if asked for.
    pub etve_test: Option<EtveTest>,
    /// The ISO 230-3 §6 spindle thermal test to simulate, if asked for.
    pub spindle_thermal_test: Option<SpindleThermalTest>,
    /// The ball-bar circular tests to simulate, if asked for.
    pub ballbar_test: Option<BallbarTest>,
    /// The R-test to simulate, if asked for.
    pub rtest: Option<RTest>,
    /// The touch-probe cycles to simulate, if asked for.
    pub probe_test: Option<ProbeTest>,
    /// The spindle error analyser's test of an axis of rotation (ISO 230-7), if asked for.
    pub spindle_test: Option<SpindleTest>,
    /// The explanation a teaching recording carries, if the scenario is a lesson.
    pub lesson: Option<Lesson>,
}

impl Scenario {
    /// Reads and validates a scenario file, its machine and its errors, without running it.
    ///
    /// A scenario with `extends = "BASE.toml"` (relative to itself) is the base scenario with
    /// its own `[errors.*]` sections replacing the base's of the same name (and its
    /// `description`, if given) and its `[inputs]` (a measured temperature record, see
    /// [`crate::scenario::inputs`]); nothing else may be set. This is how `mtwin discover
    /// --write-model` hands an extended model back to `mtwin run`.
    pub fn load(path: impl AsRef<Path>) -> Result<Scenario, ScenarioError> {
        Scenario::load_at(path.as_ref(), 0)
    }

    /// [`Scenario::load`], `depth` files down a chain of `extends`.
    fn load_at(path: &Path, depth: usize) -> Result<Scenario, ScenarioError> {
        Scenario::from_text(path, &read_text(path)?, depth, None)
    }

    /// The scenario whose text is `text`, as if read from `path` (files it names are found
    /// beside `path`). With `machine`, the machine model is that one (already read from the
    /// file the text names, `machine_file` with hash `machine_sha256`) instead of being read
    /// again: [`super::dataset`] builds many variants of one scenario this way.
    pub(crate) fn from_text(
        path: &Path,
        text: &str,
        depth: usize,
        machine: Option<(&Machine, &str)>,
    ) -> Result<Scenario, ScenarioError> {
        let file = path.display().to_string();
        let context = Context::new(file, text);
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
        let schema: SchemaOnly = toml::from_str(text).map_err(toml_error)?;
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
        let probe: ExtendsOnly = toml::from_str(text).map_err(toml_error)?;
        if probe.extends.is_some() {
            let raw: RawExtension = toml::from_str(text).map_err(toml_error)?;
            return Scenario::extend(path, text, &context, raw, depth);
        }
        let raw: RawScenario = toml::from_str(text).map_err(toml_error)?;

        let machine_file = path
            .parent()
            .unwrap_or(Path::new(""))
            .join(raw.machine.get_ref());
        let (machine, machine_sha256) = match machine {
            Some((machine, sha256)) => (machine.clone(), sha256.to_string()),
            None => read_machine(&context, &machine_file, raw.machine.span())?,
        };

        let record = temperature_record(&context, path, raw.inputs.as_ref())?;
        let (errors, error_specs) = error_model(
            &context,
            &machine,
            &raw.errors,
            None,
            raw.seed,
            record.as_ref(),
        )?;

        let volumetric = raw
            .volumetric
            .as_ref()
            .map(|v| volumetric::scenario::volumetric_spec(&context, &machine, v))
            .transpose()?;
        let mut thermal = raw
            .thermal
            .as_ref()
            .map(|t| thermal_setup(&context, &machine, t))
            .transpose()?;
        network_errors(&machine, raw.inputs.as_ref(), &mut thermal);
        let thermal_with_span = || thermal.as_ref().zip(raw.thermal.as_ref().map(|t| t.span()));
        let laser_test = positioning::scenario::sections(
            &context,
            &machine,
            raw.seed,
            positioning::scenario::RawSections {
                iso230_2: raw.iso230_2.as_ref(),
                warmup: raw.warmup.as_ref(),
                iso230_3_linear: raw.iso230_3_linear.as_ref(),
                laser: raw.laser.as_ref(),
                thermal: thermal_with_span(),
            },
        )?;
        let etve_test = drift::scenario::sections(
            &context,
            &machine,
            raw.iso230_3_etve.as_ref(),
            thermal_with_span(),
        )?;
        if let (Some(_), Some(section)) = (&laser_test, &raw.iso230_3_etve) {
            return Err(context.error(
                Some(section.span()),
                ScenarioErrorKind::Value,
                "iso230_3_etve: one thermal experiment per scenario: the ETVE test holds the machine still while a laser test moves it; give them a scenario each",
            ));
        }
        let spindle_thermal_test = drift::spindle_test::sections(
            &context,
            &machine,
            raw.iso230_3_spindle.as_ref(),
            thermal_with_span(),
        )?;
        if let Some(section) = &raw.iso230_3_spindle
            && (laser_test.is_some() || etve_test.is_some())
        {
            return Err(context.error(
                Some(section.span()),
                ScenarioErrorKind::Value,
                "iso230_3_spindle: one thermal experiment per scenario: the spindle test heats the machine with its spindle while a laser or ETVE test runs through the same thermal model; give them a scenario each",
            ));
        }
        if let (Some(section), None, None, None) =
            (&raw.thermal, &laser_test, &etve_test, &spindle_thermal_test)
        {
            return Err(context.error(
                Some(section.span()),
                ScenarioErrorKind::Nothing,
                "thermal: nothing in this scenario uses the thermal model; add a laser test ([iso230_2], [warmup] or [iso230_3_linear]), an [iso230_3_etve] or an [iso230_3_spindle] test",
            ));
        }
        let ballbar_test = ballbar::scenario::sections(
            &context,
            &machine,
            raw.ballbar.as_ref(),
            raw.servo.as_ref(),
        )?;
        let rtest = raw
            .rtest
            .as_ref()
            .map(|section| rtest::scenario::rtest(&context, &machine, section))
            .transpose()?;
        let scenario_dir = path.parent().unwrap_or(Path::new(""));
        let probe_test = raw
            .probe
            .as_ref()
            .map(|section| probe::scenario::probe_test(&context, &machine, section, scenario_dir))
            .transpose()?;
        let spindle_test = raw
            .spindle
            .as_ref()
            .map(|section| spindle::scenario::spindle_test(&context, &machine, section))
            .transpose()?;
        let lesson = raw
            .lesson
            .as_ref()
            .map(|section| crate::scenario::lesson::lesson(&context, section))
            .transpose()?;
        if volumetric.is_none()
            && laser_test.is_none()
            && ballbar_test.is_none()
            && etve_test.is_none()
            && spindle_thermal_test.is_none()
            && rtest.is_none()
            && probe_test.is_none()
            && spindle_test.is_none()
        {
            return Err(context.error(
                None,
                ScenarioErrorKind::Nothing,
                "nothing to compute: add a [volumetric], [iso230_2], [warmup], [iso230_3_linear], [iso230_3_etve], [iso230_3_spindle], [ballbar], [rtest], [probe] or [spindle] section",
            ));
        }

        Ok(Scenario {
            file: path.to_path_buf(),
            // A measured record is part of what the file means.
            sha256: match &record {
                Some(record) => sha256_hex(format!("{text}\n{}", record.sha256()).as_bytes()),
                None => sha256_hex(text.as_bytes()),
            },
            description: raw.description,
            seed: raw.seed,
            machine_sha256,
            machine_file,
            twin: Twin { machine, errors },
            error_specs,
            volumetric,
            laser_test,
            thermal,
            etve_test,
            spindle_thermal_test,
            ballbar_test,
            rtest,
            probe_test,
            spindle_test,
            lesson,
        })
    }
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
            context.error(Some(raw.extends.span()), e.kind(), format!("extends: {e}"))
        })?;
        let own_record = temperature_record(context, path, raw.inputs.as_ref())?;
        let record = own_record
            .clone()
            .or_else(|| base.twin.errors.temperature_record().cloned());
        let (errors, specs) = error_model(
            context,
            &base.twin.machine,
            &raw.errors,
            Some(&base.twin.errors),
            base.seed,
            record.as_ref(),
        )?;
        let mut error_specs = base.error_specs;
        error_specs.extend(specs);
        let mut thermal = base.thermal;
        network_errors(&base.twin.machine, raw.inputs.as_ref(), &mut thermal);
        let mut ballbar_test = base.ballbar_test;
        if let Some(servo) = &raw.servo {
            let Some(test) = ballbar_test.as_mut() else {
                return Err(context.error(
                    Some(servo.span()),
                    ScenarioErrorKind::Nothing,
                    "servo: the scenario this one extends has no [ballbar] test to use it",
                ));
            };
            test.servo = ballbar::scenario::servo_over(context, servo, test.servo.clone())?;
        }
        Ok(Scenario {
            file: path.to_path_buf(),
            // The base's content is part of what this file means.
            sha256: sha256_hex(
                format!(
                    "{text}\n{}{}",
                    base.sha256,
                    own_record.as_ref().map_or("", |r| r.sha256())
                )
                .as_bytes(),
            ),
            description: raw.description.or(base.description),
            twin: Twin {
                machine: base.twin.machine,
                errors,
            },
            error_specs,
            thermal,
            ballbar_test,
            ..base
        })
    }
}

/// The text of the scenario file at `path`.
pub(crate) fn read_text(path: &Path) -> Result<String, ScenarioError> {
    std::fs::read_to_string(path).map_err(|e| {
        Context::new(path.display().to_string(), "").error(
            None,
            ScenarioErrorKind::Io,
            format!("cannot read the scenario: {e}"),
        )
    })
}

/// The machine model at `file` (named by the `machine` key at `span`) and the SHA-256 of its
/// bytes.
fn read_machine(
    context: &Context<'_>,
    file: &Path,
    span: std::ops::Range<usize>,
) -> Result<(Machine, String), ScenarioError> {
    let machine_error = |message: String| {
        context.error(
            Some(span.clone()),
            ScenarioErrorKind::Machine,
            format!("machine: {message}"),
        )
    };
    let machine_text = std::fs::read(file)
        .map_err(|e| machine_error(format!("cannot read {}: {e}", file.display())))?;
    // Parse the very bytes that are hashed into the manifest.
    let source = std::str::from_utf8(&machine_text)
        .map_err(|e| machine_error(format!("{}: not UTF-8 text: {e}", file.display())))?;
    let machine = Machine::from_urdf_str(source, &file.display().to_string())
        .map_err(|e| machine_error(e.to_string()))?;
    Ok((machine, sha256_hex(&machine_text)))
}

/// The measured temperature record `[inputs] temperatures` names (relative to the scenario at
/// `path`), if any.
fn temperature_record(
    context: &Context<'_>,
    path: &Path,
    inputs: Option<&Spanned<RawInputs>>,
) -> Result<Option<Arc<TemperatureRecord>>, ScenarioError> {
    let Some(file) = inputs.and_then(|i| i.get_ref().temperatures.as_ref()) else {
        return Ok(None);
    };
    let record_path = path.parent().unwrap_or(Path::new("")).join(file.get_ref());
    crate::scenario::read_temperature_record(&record_path)
        .map(|record| Some(Arc::new(record)))
        .map_err(|e| {
            context.error(
                Some(file.span()),
                ScenarioErrorKind::Value,
                format!("inputs.temperatures: {e}"),
            )
        })
}

/// Switches the `[thermal]` network's error terms off when `[inputs] thermal_network_errors =
/// false` (the scenario's temperature terms replace them; the network still drives the
/// sensors). Without a network there is nothing to switch off.
fn network_errors(
    machine: &Machine,
    inputs: Option<&Spanned<RawInputs>>,
    thermal: &mut Option<ThermalSetup>,
) {
    let off = inputs
        .and_then(|i| i.get_ref().thermal_network_errors.as_ref())
        .is_some_and(|flag| !*flag.get_ref());
    if let (true, Some(setup)) = (off, thermal) {
        let nodes = setup.thermal.network.nodes().len();
        setup.thermal.errors =
            ThermalErrors::new(machine, nodes, Vec::new()).expect("no terms to check");
    }
}

impl Scenario {
    /// One line for each test the scenario asks for, as `mtwin check` lists them.
    pub fn describe(&self) -> Vec<String> {
        let mut lines = Vec::new();
        lines.extend(self.volumetric.as_ref().map(VolumetricSpec::describe));
        lines.extend(self.laser_test.as_ref().map(LaserTest::describe));
        lines.extend(self.etve_test.as_ref().map(EtveTest::describe));
        lines.extend(
            self.spindle_thermal_test
                .as_ref()
                .map(SpindleThermalTest::describe),
        );
        lines.extend(self.thermal.as_ref().map(ThermalSetup::describe));
        lines.extend(self.ballbar_test.iter().flat_map(BallbarTest::describe));
        lines.extend(self.rtest.iter().flat_map(RTest::describe));
        lines.extend(self.probe_test.iter().flat_map(ProbeTest::describe));
        lines.extend(self.spindle_test.iter().flat_map(SpindleTest::describe));
        if let Some(record) = self.twin.errors.temperature_record() {
            let (from, to) = record.span();
            lines.push(format!(
                "measured temperatures: {} ({}, {:.1}–{:.1} min)",
                record.file(),
                record.sensors().join(", "),
                from / 60.0,
                to / 60.0
            ));
        }
        lines
    }
}

/// Scenario files loaded whole with [`Scenario::load`]: what this layer lends the kinds'
/// verbs as their [`ScenarioLoader`], since the kinds sit below the whole scenario.
#[derive(Clone, Copy, Debug, Default)]
pub struct ScenarioFiles;

impl ScenarioLoader for ScenarioFiles {
    fn check(&self, path: &Path) -> anyhow::Result<()> {
        Scenario::load(path)?;
        Ok(())
    }

    fn ballbar_test(&self, path: &Path) -> anyhow::Result<Option<BallbarTest>> {
        Ok(Scenario::load(path)?.ballbar_test)
    }
}
