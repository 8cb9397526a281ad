//! Datasets (`mtwin dataset`): many machines drawn from the priors of a scenario's
//! `[dataset]` section, each run through the twin like `mtwin run`, written as Parquet with
//! the ground truth beside the measurements.
//!
//! A **case** is one machine and condition: the scenario with every prior's value drawn for
//! it and its own seed for every noise stream. Case `k` depends on the master seed and `k`
//! alone ([`Dataset::case`]), so a case is the same whatever the shard layout or the thread
//! count. Cases are grouped into shards (shard `i` of `n` holds cases `[i·N/n, (i+1)·N/n)`),
//! the unit of work, of publication and of resumption ([`generate`]).
//!
//! The `[dataset]` section:
//!
//! ```toml
//! [dataset]
//! count = 1000                 # cases, unless --count says otherwise
//! shards = 4                   # shard layout, unless --shards says otherwise (default 1 per 10 000 cases)
//! tests = ["volumetric"]       # the scenario's tests each case runs (default: all)
//! test_fraction = 0.2          # cases (never rows) in the test split; or, to test extrapolation:
//! # split_by = { parameter = "servo.X.kv_per_s", test_above = 34.0 }
//!
//! [dataset.priors]             # any number in the scenario, by its path
//! "errors.EC0Y.constant_urad" = { normal = [0.0, 15.0], bounds = [-60.0, 60.0] }
//! "errors.EXX.polynomial_um[1]" = { uniform = [-0.01, 0.01] }
//! "ballbar.noise_um" = { lognormal = [0.1, 0.3] }      # median, sd of ln
//! "servo.X.kv_per_s" = { fixed = 33.3 }
//!
//! [[dataset.families]]         # one prior for a term of every member of a family
//! family = "straightness"      # positioning, straightness, angular, squareness, rotary_location
//! polynomial_um = [{ fixed = 0.0 }, { normal = [0.0, 0.004] }, { normal = [0.0, 1e-5] }, { normal = [0.0, 2e-8] }]
//! ```
//!
//! Every prior is checked when the dataset is loaded, before anything runs: its distribution
//! (a positive spread, bounds that hold the centre and keep at least
//! [`priors::LEAST_MASS`] of it) and its path (the scenario with the value set to the
//! prior's centre must load, so an unknown parameter, key or axis is refused at the prior's
//! line with the scenario's own message).

mod card;
mod error;
mod guard;
mod options;
pub mod priors;
mod shard;
pub mod spec;
mod table;

pub use card::counted;
pub use error::DatasetError;
pub use options::Options;
pub use shard::{Progress, Summary, generate, record_name};
pub use spec::{Prior, Section, SplitRule};
pub use table::{ColumnKind, TableSchema};

use super::scenario::Scenario;
use crate::machine::Machine;
use crate::math::seeded_rng;
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind};
use rand::RngExt;
use std::path::Path;

/// The version of the dataset layout (tables, columns, files); it changes when a reader would
/// need to change. 2: `shard=N` folders unpadded, a vector preamble line (`centre_mm`) as one
/// column per component, units in each column's Parquet field metadata.
pub const SCHEMA_VERSION: u32 = 2;

/// Cases per shard when neither `--shards` nor `[dataset] shards` says.
pub const CASES_PER_SHARD: u64 = 10_000;

/// The scenario's tests, each with the sections only it uses (removed with it when a dataset's
/// `tests` leaves it out).
const TESTS: &[(&str, &[&str])] = &[
    ("volumetric", &[]),
    ("iso230_2", &["laser"]),
    ("warmup", &["laser"]),
    ("iso230_3_linear", &["laser"]),
    ("iso230_3_etve", &[]),
    ("iso230_3_spindle", &[]),
    ("ballbar", &["servo"]),
    ("rtest", &[]),
    ("probe", &[]),
    ("spindle", &[]),
];

/// The tests that use `[thermal]`.
const THERMAL_TESTS: &[&str] = &[
    "iso230_2",
    "warmup",
    "iso230_3_linear",
    "iso230_3_etve",
    "iso230_3_spindle",
];

/// Whether the scenario at `path` has a `[dataset]` section (false if it cannot be read: its
/// loading says why).
pub fn declared(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| toml::from_str::<spec::DatasetOnly>(&text).ok())
        .is_some_and(|only| only.dataset.is_some())
}

/// A scenario with a `[dataset]` section, checked and ready to make cases.
#[derive(Clone, Debug)]
pub struct Dataset {
    /// The scenario as written (its own seed and values: the run `mtwin run` makes).
    pub scenario: Scenario,
    /// The checked `[dataset]` section.
    pub section: Section,
    /// The tests each case runs.
    pub tests: Vec<String>,
    /// The machine's name (its file's stem), the `machine=` partition key.
    pub machine_name: String,
    /// The scenario as a table, without `[dataset]`, `[lesson]` and the tests left out.
    base: toml::Table,
}

/// One case: its identity, its split and its drawn values (in the order of
/// [`Section::priors`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// Its index, 0-based.
    pub id: u64,
    /// The seed of its every random stream (below 2⁶³, a TOML integer).
    pub seed: u64,
    /// Whether it is in the test split.
    pub test: bool,
    /// Each prior's value.
    pub values: Vec<f64>,
}

impl Case {
    /// Its split's name, the `split=` partition key.
    pub fn split(&self) -> &'static str {
        if self.test { "test" } else { "train" }
    }
}

impl Dataset {
    /// Loads a scenario and its `[dataset]` section, and checks every prior.
    pub fn load(path: impl AsRef<Path>) -> Result<Dataset, ScenarioError> {
        let path = path.as_ref();
        let scenario = Scenario::load(path)?;
        let text = super::scenario::read_text(path)?;
        let context = Context::new(path.display().to_string(), &text);
        let syntax = |e: toml::de::Error| {
            context.error(e.span(), ScenarioErrorKind::Syntax, e.message().trim())
        };
        let only: spec::DatasetOnly = toml::from_str(&text).map_err(syntax)?;
        let Some(raw) = only.dataset else {
            return Err(context.error(
                None,
                ScenarioErrorKind::Nothing,
                "no [dataset] section: add one with the priors to draw (see `mtwin dataset --help`)",
            ));
        };
        let section = spec::section(&context, &raw, &scenario.twin.machine, scenario.seed)?;
        let mut base: toml::Table = toml::from_str(&text).map_err(syntax)?;
        base.remove("dataset");
        base.remove("lesson");
        let present: Vec<String> = TESTS
            .iter()
            .filter(|(name, _)| base.contains_key(*name))
            .map(|(name, _)| name.to_string())
            .collect();
        let tests = match &section.tests {
            None => present.clone(),
            Some(asked) => {
                for name in asked {
                    if !present.contains(name) {
                        return Err(context.error(
                            Some(raw.span()),
                            ScenarioErrorKind::Value,
                            format!(
                                "dataset.tests: `{name}` is not a test of this scenario (it has {})",
                                present.join(", ")
                            ),
                        ));
                    }
                }
                present
                    .iter()
                    .filter(|t| asked.contains(t))
                    .cloned()
                    .collect()
            }
        };
        for (name, own) in TESTS {
            if !tests.iter().any(|t| t == name) {
                base.remove(*name);
                for section in *own {
                    let used = TESTS
                        .iter()
                        .any(|(other, s)| s.contains(section) && tests.iter().any(|t| t == other));
                    if !used {
                        base.remove(*section);
                    }
                }
            }
        }
        if !tests.iter().any(|t| THERMAL_TESTS.contains(&t.as_str())) {
            base.remove("thermal");
        }
        let machine_name = scenario
            .machine_file
            .file_stem()
            .map_or_else(|| "machine".into(), |s| s.to_string_lossy().into_owned());
        let dataset = Dataset {
            scenario,
            section,
            tests,
            machine_name,
            base,
        };
        dataset.check_priors(&context)?;
        Ok(dataset)
    }

    /// Refuses, at its line, a prior whose path the scenario does not accept: the scenario
    /// with every prior at its centre must load; if it does not, each prior alone is tried to
    /// name the culprit.
    fn check_priors(&self, context: &Context<'_>) -> Result<(), ScenarioError> {
        let centres: Vec<f64> = (self.section.priors.iter())
            .map(|p| p.law.distribution.centre())
            .collect();
        let all = self.build(self.scenario.seed, &centres, None);
        let Err(first) = all else {
            self.check_reach(context)?;
            return self.check_split(context);
        };
        for (index, prior) in self.section.priors.iter().enumerate() {
            if let Err(message) =
                self.build(self.scenario.seed, &centres[index..=index], Some(index))
            {
                return Err(context.error(
                    Some(prior.span.clone()),
                    ScenarioErrorKind::Value,
                    format!(
                        "dataset: {} = {} (the prior's centre) does not make a valid scenario: {message}",
                        prior.path.as_str(),
                        centres[index]
                    ),
                ));
            }
        }
        Err(context.error(
            None,
            ScenarioErrorKind::Value,
            format!("dataset: the priors' centres together do not make a valid scenario: {first}"),
        ))
    }

    /// Refuses, at its line, a prior whose draws can leave what the scenario accepts: each prior
    /// alone at each end of its reach ([`priors::Law::reach`]) must make a valid
    /// scenario, so that no case fails part-way through a dataset.
    fn check_reach(&self, context: &Context<'_>) -> Result<(), ScenarioError> {
        for (index, prior) in self.section.priors.iter().enumerate() {
            let Some((low, high)) = prior.law.reach() else {
                continue;
            };
            for (end, value) in [("lower", low), ("upper", high)] {
                // To 12 significant digits, so that messages quote −0.145, not −0.14500000000000002.
                let value = format!("{value:.11e}").parse::<f64>().unwrap_or(value);
                if let Err(message) = self.build(self.scenario.seed, &[value], Some(index)) {
                    return Err(context.error(
                        Some(prior.span.clone()),
                        ScenarioErrorKind::Value,
                        format!(
                            "dataset: {} can reach {} (the {end} end of its prior{}), which does not make a valid scenario: {message}; narrow the prior or give it bounds",
                            prior.path.as_str(),
                            crate::math::readable(value),
                            if prior.law.bounds.is_some() || matches!(prior.law.distribution, priors::Distribution::Uniform { .. }) {
                                ""
                            } else {
                                ", 4.9 standard deviations out"
                            }
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Refuses, at the split's line, a split that leaves `train` or `test` empty: a threshold
    /// beyond the reach of its prior ([`priors::Law::reach`]) or on a fixed value, or, when the
    /// section gives the count, the cases themselves.
    fn check_split(&self, context: &Context<'_>) -> Result<(), ScenarioError> {
        let key = match self.section.split {
            SplitRule::Fraction(_) => "test_fraction",
            SplitRule::Threshold { .. } => "split_by",
        };
        let fail = |message: String| {
            context.error(
                Some(self.section.split_span.clone()),
                ScenarioErrorKind::Value,
                format!("dataset.{key}: {message}"),
            )
        };
        if let SplitRule::Threshold {
            prior,
            value,
            above,
        } = self.section.split
        {
            let p = &self.section.priors[prior];
            let (low, high) = p.law.reach().unwrap_or_else(|| {
                let v = p.law.distribution.centre();
                (v, v)
            });
            let (test, train) = if above {
                (high > value, low <= value)
            } else {
                (low < value, high >= value)
            };
            if !(test && train) {
                return Err(fail(format!(
                    "{} {} {} leaves `{}` empty: its prior reaches {} … {}",
                    p.path.column(),
                    if above { ">" } else { "<" },
                    crate::math::readable(value),
                    if test { "train" } else { "test" },
                    crate::math::readable(low),
                    crate::math::readable(high)
                )));
            }
        }
        if let Some(message) = self.section.count.and_then(|n| self.empty_split(n)) {
            return Err(fail(message));
        }
        Ok(())
    }

    /// How many of the cases `0..count` fall in `train` and in `test`.
    pub fn split_counts(&self, count: u64) -> (u64, u64) {
        let test = (0..count).filter(|id| self.case(*id).test).count() as u64;
        (count - test, test)
    }

    /// Why the cases `0..count` leave `train` or `test` empty, if they do (a test fraction of
    /// 0 asks for no test split and is not refused).
    pub fn empty_split(&self, count: u64) -> Option<String> {
        if self.section.split == SplitRule::Fraction(0.0) {
            return None;
        }
        let (train, test) = self.split_counts(count);
        let empty = match (train, test) {
            (0, _) => "train",
            (_, 0) => "test",
            _ => return None,
        };
        let rule = match self.section.split {
            SplitRule::Fraction(f) => format!("test_fraction = {f}"),
            SplitRule::Threshold { .. } => "the threshold".into(),
        };
        Some(format!(
            "of the {}, none falls in `{empty}` with {rule}: more cases or another split",
            card::counted(count, "case", "cases")
        ))
    }

    /// Case `id`: its seed, its values and its split.
    pub fn case(&self, id: u64) -> Case {
        let seed =
            seeded_rng(self.section.seed, &format!("dataset case {id}")).random::<u64>() >> 1;
        let values: Vec<f64> = (self.section.priors.iter())
            .map(|prior| prior.law.sample(seed, prior.path.as_str()))
            .collect();
        let test = match self.section.split {
            SplitRule::Fraction(fraction) => seeded_rng(seed, "split").random::<f64>() < fraction,
            SplitRule::Threshold {
                prior,
                value,
                above,
            } => {
                if above {
                    values[prior] > value
                } else {
                    values[prior] < value
                }
            }
        };
        Case {
            id,
            seed,
            test,
            values,
        }
    }

    /// The scenario of `case`.
    pub fn scenario_of(&self, case: &Case) -> Result<Scenario, DatasetError> {
        self.build(case.seed, &case.values, None)
            .map_err(|message| DatasetError::Case {
                id: case.id,
                message,
            })
    }

    /// The scenario with seed `seed` and `values` set (every prior's, or with `only`, that
    /// prior's alone), or the scenario's message.
    fn build(&self, seed: u64, values: &[f64], only: Option<usize>) -> Result<Scenario, String> {
        let mut table = self.base.clone();
        table.insert("seed".into(), toml::Value::Integer(seed as i64));
        let priors = match only {
            Some(index) => &self.section.priors[index..=index],
            None => &self.section.priors[..],
        };
        for (prior, value) in priors.iter().zip(values) {
            prior.path.set(&mut table, *value)?;
        }
        let text = toml::to_string(&table).map_err(|e| e.to_string())?;
        let machine: (&Machine, &str) =
            (&self.scenario.twin.machine, &self.scenario.machine_sha256);
        Scenario::from_text(&self.scenario.file, &text, 0, Some(machine))
            .map_err(|e| e.message().to_string())
    }

    /// One line for `mtwin check`: the priors, the tests and the split.
    pub fn describe(&self) -> String {
        let split = match self.section.split {
            SplitRule::Fraction(f) => format!("test split {f} of the cases"),
            SplitRule::Threshold {
                prior,
                value,
                above,
            } => format!(
                "test split: {} {} {value}",
                self.section.priors[prior].path.column(),
                if above { ">" } else { "<" }
            ),
        };
        format!(
            "dataset: {} drawn values, tests {}, {split}, master seed {}{}",
            self.section.priors.len(),
            self.tests.join(", "),
            self.section.seed,
            self.section
                .count
                .map_or(String::new(), |n| format!(", {n} cases"))
        )
    }

    /// The shard layout for `count` cases when none is given.
    pub fn default_shards(&self, count: u64) -> u64 {
        self.section
            .shards
            .unwrap_or_else(|| count.div_ceil(CASES_PER_SHARD).max(1))
    }
}
