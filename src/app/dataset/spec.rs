//! The `[dataset]` section as written, and its checks: priors by path and by family, the tests
//! each case runs, the split and the shard layout.

use super::priors::{Law, ParamPath, RawPrior};
use crate::errors::ParameterName;
use crate::machine::Machine;
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind};
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

/// The top level of a scenario, as far as datasets are concerned.
#[derive(Deserialize)]
pub(super) struct DatasetOnly {
    pub dataset: Option<Spanned<RawDataset>>,
}

/// `[dataset]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDataset {
    /// Master seed (default: the scenario's `seed`).
    seed: Option<u64>,
    /// Number of cases, if `--count` does not say.
    count: Option<Spanned<i64>>,
    /// Shard layout, if `--shards` does not say.
    shards: Option<Spanned<i64>>,
    /// The scenario's tests each case runs (default: all).
    tests: Option<Spanned<Vec<String>>>,
    /// Share of cases in the test split (default 0.2).
    test_fraction: Option<Spanned<f64>>,
    /// An extrapolation split instead: the test split is the cases beyond a threshold.
    split_by: Option<Spanned<RawSplitBy>>,
    #[serde(default)]
    priors: BTreeMap<Spanned<String>, Spanned<RawPrior>>,
    #[serde(default)]
    families: Vec<Spanned<RawFamily>>,
}

/// `split_by = { parameter = "…", test_above = X }` (or `test_below`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSplitBy {
    parameter: String,
    test_above: Option<f64>,
    test_below: Option<f64>,
}

/// `[[dataset.families]]`: one prior for a term of every member of a family of ISO 230-1
/// parameters.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFamily {
    family: String,
    constant_um: Option<RawPrior>,
    constant_urad: Option<RawPrior>,
    reversal_um: Option<RawPrior>,
    reversal_urad: Option<RawPrior>,
    polynomial_um: Option<Vec<RawPrior>>,
    polynomial_urad: Option<Vec<RawPrior>>,
}

/// The families `[[dataset.families]]` knows, with which parameters of a machine belong.
pub const FAMILIES: &[(&str, &str)] = &[
    (
        "positioning",
        "EXX, EYY, EZZ: the positioning error of each linear axis",
    ),
    (
        "straightness",
        "EYX, EZX, EXY, EZY, EXZ, EYZ: the straightness errors of each linear axis",
    ),
    (
        "angular",
        "EAX, EBX, ECX, …: roll, pitch and yaw of each linear axis",
    ),
    ("squareness", "EC0Y, EB0Z, EA0Z"),
    (
        "rotary_location",
        "EX0C, EY0C, EA0C, EB0C, …: the location errors of each axis of rotation",
    ),
];

/// Whether `name` is in `family` on a machine with these axes.
fn member(family: &str, name: ParameterName, machine: &Machine) -> bool {
    let Some(axis) = name.axis() else {
        return false;
    };
    if !machine.axes().iter().any(|info| info.axis == axis) {
        return false;
    }
    let motion = name.motion();
    let own = motion.is_translation() && motion.index() == axis.coordinate();
    match (family, name) {
        ("positioning", ParameterName::Component { .. }) => axis.is_linear() && own,
        ("straightness", ParameterName::Component { .. }) => {
            axis.is_linear() && motion.is_translation() && !own
        }
        ("angular", ParameterName::Component { .. }) => {
            axis.is_linear() && !motion.is_translation()
        }
        ("squareness", ParameterName::Location { .. }) => axis.is_linear(),
        ("rotary_location", ParameterName::Location { .. }) => !axis.is_linear(),
        _ => false,
    }
}

/// A checked prior: where its value goes, how it is drawn, and the line that set it.
#[derive(Clone, Debug)]
pub struct Prior {
    /// Where the value goes.
    pub path: ParamPath,
    /// How it is drawn.
    pub law: Law,
    /// The span of what set it (a `[dataset.priors]` key or a family), for messages.
    pub(super) span: std::ops::Range<usize>,
}

/// Which split a case belongs to.
#[derive(Clone, Debug, PartialEq)]
pub enum SplitRule {
    /// A share of the cases, drawn per case (per machine and condition, never per row).
    Fraction(f64),
    /// The cases whose value of a prior lies beyond a threshold (extrapolation).
    Threshold {
        /// Index of the prior in [`Section::priors`].
        prior: usize,
        /// The threshold.
        value: f64,
        /// Whether the test split is above (else below) it.
        above: bool,
    },
}

/// The checked `[dataset]` section.
#[derive(Clone, Debug)]
pub struct Section {
    /// Master seed.
    pub seed: u64,
    /// Number of cases, if given.
    pub count: Option<u64>,
    /// Shard layout, if given.
    pub shards: Option<u64>,
    /// Which of the scenario's tests each case runs (section names), in the file's order.
    pub tests: Option<Vec<String>>,
    /// Priors, sorted by path.
    pub priors: Vec<Prior>,
    /// The split.
    pub split: SplitRule,
    /// Where the split is set (`split_by` or `test_fraction`, else the section), for messages.
    pub(super) split_span: std::ops::Range<usize>,
}

/// Checks `raw` (the `[dataset]` section of the scenario of `context`, whose seed is
/// `scenario_seed`) for `machine`.
pub(super) fn section(
    context: &Context<'_>,
    raw: &Spanned<RawDataset>,
    machine: &Machine,
    scenario_seed: u64,
) -> Result<Section, ScenarioError> {
    let span = raw.span();
    let raw = raw.get_ref();
    let fail = |span: std::ops::Range<usize>, message: String| {
        context.error(Some(span), ScenarioErrorKind::Value, message)
    };
    let positive =
        |value: &Option<Spanned<i64>>, key: &str| -> Result<Option<u64>, ScenarioError> {
            value
                .as_ref()
                .map(|v| {
                    u64::try_from(*v.get_ref())
                        .ok()
                        .filter(|n| *n > 0)
                        .ok_or_else(|| {
                            fail(
                                v.span(),
                                format!(
                                    "dataset.{key}: {} is not a positive whole number",
                                    v.get_ref()
                                ),
                            )
                        })
                })
                .transpose()
        };
    let count = positive(&raw.count, "count")?;
    let shards = positive(&raw.shards, "shards")?;

    let mut by_path: BTreeMap<ParamPath, Prior> = BTreeMap::new();
    for family in &raw.families {
        for prior in family_priors(context, family, machine)? {
            if let Some(earlier) = by_path.get(&prior.path) {
                let line = context.error(Some(earlier.span.clone()), ScenarioErrorKind::Value, "");
                return Err(fail(
                    family.span(),
                    format!(
                        "dataset.families: {} already has a prior from the family at line {}",
                        prior.path.as_str(),
                        line.line().unwrap_or(0)
                    ),
                ));
            }
            by_path.insert(prior.path.clone(), prior);
        }
    }
    // A prior by path replaces a family's for the same value.
    for (key, value) in &raw.priors {
        let located = |message: String| {
            fail(
                key.span(),
                format!("dataset.priors.\"{}\": {message}", key.get_ref()),
            )
        };
        let path = ParamPath::parse(key.get_ref()).map_err(located)?;
        let law = value.get_ref().law().map_err(located)?;
        by_path.insert(
            path.clone(),
            Prior {
                path,
                law,
                span: key.span(),
            },
        );
    }
    let priors: Vec<Prior> = by_path.into_values().collect();
    let mut columns = BTreeMap::new();
    for prior in &priors {
        if let Some(other) = columns.insert(prior.path.column(), prior.path.as_str()) {
            return Err(fail(
                prior.span.clone(),
                format!(
                    "dataset.priors: {} and {other} would share the column {}",
                    prior.path.as_str(),
                    prior.path.column()
                ),
            ));
        }
    }

    let split_span = match (&raw.split_by, &raw.test_fraction) {
        (Some(by), _) => by.span(),
        (None, Some(fraction)) => fraction.span(),
        (None, None) => span.clone(),
    };
    let split = match (&raw.split_by, &raw.test_fraction) {
        (Some(_), Some(fraction)) => {
            return Err(fail(
                fraction.span(),
                "dataset: give test_fraction or split_by, not both".into(),
            ));
        }
        (Some(by), None) => {
            let rule = by.get_ref();
            let prior = priors
                .iter()
                .position(|p| p.path.as_str() == rule.parameter || p.path.column() == rule.parameter)
                .ok_or_else(|| {
                    fail(
                        by.span(),
                        format!(
                            "dataset.split_by.parameter: `{}` has no prior; the split is by a sampled value",
                            rule.parameter
                        ),
                    )
                })?;
            let (value, above) = match (rule.test_above, rule.test_below) {
                (Some(v), None) => (v, true),
                (None, Some(v)) => (v, false),
                _ => {
                    return Err(fail(
                        by.span(),
                        "dataset.split_by: give one of test_above = X or test_below = X".into(),
                    ));
                }
            };
            if !value.is_finite() {
                return Err(fail(
                    by.span(),
                    "dataset.split_by: the threshold is not a finite number".into(),
                ));
            }
            SplitRule::Threshold {
                prior,
                value,
                above,
            }
        }
        (None, fraction) => {
            let value = fraction.as_ref().map_or(0.2, |f| *f.get_ref());
            if !(0.0..1.0).contains(&value) {
                let span = fraction.as_ref().map_or(span.clone(), |f| f.span());
                return Err(fail(
                    span,
                    format!("dataset.test_fraction: {value} is not in [0, 1)"),
                ));
            }
            SplitRule::Fraction(value)
        }
    };
    Ok(Section {
        seed: raw.seed.unwrap_or(scenario_seed),
        count,
        shards,
        tests: raw.tests.as_ref().map(|t| t.get_ref().clone()),
        priors,
        split,
        split_span,
    })
}

/// The priors one `[[dataset.families]]` entry sets: each of its terms for every member of
/// the family on this machine whose unit matches the term's (`_um` translations, `_urad`
/// rotations).
fn family_priors(
    context: &Context<'_>,
    family: &Spanned<RawFamily>,
    machine: &Machine,
) -> Result<Vec<Prior>, ScenarioError> {
    let raw = family.get_ref();
    let fail = |message: String| {
        context.error(
            Some(family.span()),
            ScenarioErrorKind::Value,
            format!("dataset.families (family = \"{}\"): {message}", raw.family),
        )
    };
    if !FAMILIES.iter().any(|(name, _)| *name == raw.family) {
        let known: Vec<&str> = FAMILIES.iter().map(|(name, _)| *name).collect();
        return Err(fail(format!(
            "unknown family; expected one of {}",
            known.join(", ")
        )));
    }
    let members: Vec<ParameterName> = ParameterName::all()
        .into_iter()
        .filter(|name| member(&raw.family, *name, machine))
        .collect();
    let mut terms: Vec<(&str, Option<usize>, &RawPrior)> = Vec::new();
    for (key, prior) in [
        ("constant_um", &raw.constant_um),
        ("constant_urad", &raw.constant_urad),
        ("reversal_um", &raw.reversal_um),
        ("reversal_urad", &raw.reversal_urad),
    ] {
        terms.extend(prior.as_ref().map(|p| (key, None, p)));
    }
    for (key, list) in [
        ("polynomial_um", &raw.polynomial_um),
        ("polynomial_urad", &raw.polynomial_urad),
    ] {
        for (degree, prior) in list.iter().flatten().enumerate() {
            terms.push((key, Some(degree), prior));
        }
    }
    if terms.is_empty() {
        return Err(fail(
            "no terms: give constant_um, reversal_um, polynomial_um = [prior, …] (or their _urad forms)".into(),
        ));
    }
    let mut priors = Vec::new();
    for (key, index, prior) in terms {
        let law = prior.law().map_err(|m| fail(format!("{key}: {m}")))?;
        let translation = key.ends_with("_um");
        let matching: Vec<&ParameterName> = members
            .iter()
            .filter(|name| name.motion().is_translation() == translation)
            .collect();
        if matching.is_empty() {
            return Err(fail(format!(
                "{key}: no member of this family on this machine is a {}",
                if translation {
                    "translation (_um)"
                } else {
                    "rotation (_urad)"
                }
            )));
        }
        for name in matching {
            let text = match index {
                Some(i) => format!("errors.{name}.{key}[{i}]"),
                None => format!("errors.{name}.{key}"),
            };
            priors.push(Prior {
                path: ParamPath::parse(&text).expect("a well-formed path"),
                law,
                span: family.span(),
            });
        }
    }
    Ok(priors)
}
