//! Priors: where a case's sampled value goes in the scenario (a [`ParamPath`]) and how it is
//! drawn (a [`Distribution`], optionally truncated to bounds).
//!
//! A value is drawn from its own random stream, seeded by the case's seed and the path, so
//! adding or removing one prior leaves every other prior's values unchanged.

use crate::math::{Real, seeded_rng, standard_normal};
use crate::scenario::errors::MAX_POLYNOMIAL_DEGREE;
use rand::RngExt;
use serde::Deserialize;

/// The fewest draws in a thousand that truncation bounds must keep: below it a prior's bounds
/// are taken for a mistake (they leave almost nothing of the distribution), and rejection
/// sampling would also be slow.
pub const LEAST_MASS: Real = 1e-3;

/// A distribution of one parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Distribution {
    /// Always this value.
    Fixed(Real),
    /// Uniform on `[low, high)`.
    Uniform {
        /// Lower end.
        low: Real,
        /// Upper end.
        high: Real,
    },
    /// Normal.
    Normal {
        /// Mean.
        mean: Real,
        /// Standard deviation (> 0).
        sd: Real,
    },
    /// Log-normal: `ln x` is normal with mean `ln median` and standard deviation `sigma`.
    LogNormal {
        /// The median (> 0).
        median: Real,
        /// Standard deviation of `ln x` (> 0).
        sigma: Real,
    },
}

/// A prior as written: one of `fixed = v`, `uniform = [low, high]`, `normal = [mean, sd]`,
/// `lognormal = [median, sigma_of_ln]`, with optional `bounds = [low, high]` (truncation of a
/// normal or log-normal).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawPrior {
    fixed: Option<Real>,
    uniform: Option<[Real; 2]>,
    normal: Option<[Real; 2]>,
    lognormal: Option<[Real; 2]>,
    bounds: Option<[Real; 2]>,
}

/// A checked distribution with its truncation bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Law {
    /// The distribution.
    pub distribution: Distribution,
    /// Draws outside `[low, high]` are redrawn.
    pub bounds: Option<(Real, Real)>,
}

impl RawPrior {
    /// The distribution it describes, or what is wrong with it.
    pub fn law(&self) -> Result<Law, String> {
        let given = [
            self.fixed.is_some(),
            self.uniform.is_some(),
            self.normal.is_some(),
            self.lognormal.is_some(),
        ];
        if given.iter().filter(|g| **g).count() != 1 {
            return Err("give exactly one of fixed = V, uniform = [LOW, HIGH], normal = [MEAN, SD], lognormal = [MEDIAN, SIGMA_OF_LN]".into());
        }
        let finite = |values: &[Real]| values.iter().all(|v| v.is_finite());
        let distribution = if let Some(value) = self.fixed {
            if !value.is_finite() {
                return Err(format!("fixed = {value}: not a finite number"));
            }
            Distribution::Fixed(value)
        } else if let Some([low, high]) = self.uniform {
            if !finite(&[low, high]) || low >= high {
                return Err(format!(
                    "uniform = [{low}, {high}]: expected two finite numbers, the lower first"
                ));
            }
            Distribution::Uniform { low, high }
        } else if let Some([mean, sd]) = self.normal {
            if !finite(&[mean, sd]) || sd <= 0.0 {
                return Err(format!(
                    "normal = [{mean}, {sd}]: expected a finite mean and a positive standard deviation (use fixed = V for none)"
                ));
            }
            Distribution::Normal { mean, sd }
        } else {
            let [median, sigma] = self.lognormal.expect("one of the four is given");
            if !finite(&[median, sigma]) || median <= 0.0 || sigma <= 0.0 {
                return Err(format!(
                    "lognormal = [{median}, {sigma}]: expected a positive median and a positive standard deviation of its logarithm"
                ));
            }
            Distribution::LogNormal { median, sigma }
        };
        let bounds = match self.bounds {
            None => None,
            Some([low, high]) => {
                if !finite(&[low, high]) || low >= high {
                    return Err(format!(
                        "bounds = [{low}, {high}]: expected two finite numbers, the lower first"
                    ));
                }
                let centre = match distribution {
                    Distribution::Normal { mean, .. } => mean,
                    Distribution::LogNormal { median, .. } => median,
                    _ => {
                        return Err(
                            "bounds truncate a normal or log-normal prior; a uniform prior has its own and a fixed one needs none"
                                .into(),
                        );
                    }
                };
                if !(low..=high).contains(&centre) {
                    return Err(format!(
                        "bounds = [{low}, {high}] exclude the prior's centre {centre}"
                    ));
                }
                let mass = distribution.mass(low, high);
                if mass < LEAST_MASS {
                    return Err(format!(
                        "bounds = [{low}, {high}] keep {mass:.1e} of the distribution (at least {LEAST_MASS} is needed)"
                    ));
                }
                Some((low, high))
            }
        };
        Ok(Law {
            distribution,
            bounds,
        })
    }
}

/// How far an unbounded normal or log-normal prior reaches, in standard deviations (of `ln x`
/// for a log-normal): the one-in-a-million quantiles (Φ(−4.9) = 4.8e-7 each side), so a
/// dataset of up to a million cases stays inside what `check` tried.
pub const REACH_SD: Real = 4.9;

impl Law {
    /// The ends a draw can reach: the bounds, a uniform's ends, or [`REACH_SD`] standard
    /// deviations each side; `None` for a fixed value (its centre is all it draws).
    pub fn reach(&self) -> Option<(Real, Real)> {
        if let Some(bounds) = self.bounds {
            return Some(bounds);
        }
        match self.distribution {
            Distribution::Fixed(_) => None,
            Distribution::Uniform { low, high } => Some((low, high)),
            Distribution::Normal { mean, sd } => Some((mean - REACH_SD * sd, mean + REACH_SD * sd)),
            Distribution::LogNormal { median, sigma } => Some((
                median * (-REACH_SD * sigma).exp(),
                median * (REACH_SD * sigma).exp(),
            )),
        }
    }
}

impl Distribution {
    /// Its centre: the value, the midpoint, the mean or the median.
    pub fn centre(self) -> Real {
        match self {
            Distribution::Fixed(value) => value,
            Distribution::Uniform { low, high } => 0.5 * (low + high),
            Distribution::Normal { mean, .. } => mean,
            Distribution::LogNormal { median, .. } => median,
        }
    }

    /// The probability of `[low, high]` (normal CDF by [`normal_cdf`]; used to refuse bounds
    /// that keep almost nothing, not in sampling).
    fn mass(self, low: Real, high: Real) -> Real {
        match self {
            Distribution::Normal { mean, sd } => {
                normal_cdf((high - mean) / sd) - normal_cdf((low - mean) / sd)
            }
            Distribution::LogNormal { median, sigma } => {
                let z = |x: Real| {
                    if x <= 0.0 {
                        Real::NEG_INFINITY
                    } else {
                        (x / median).ln() / sigma
                    }
                };
                normal_cdf(z(high)) - normal_cdf(z(low))
            }
            Distribution::Fixed(value) => Real::from(u8::from((low..=high).contains(&value))),
            Distribution::Uniform { low: a, high: b } => {
                ((high.min(b) - low.max(a)) / (b - a)).max(0.0)
            }
        }
    }
}

impl Law {
    /// One draw for the case of seed `case_seed`, from the stream named `stream`.
    pub fn sample(&self, case_seed: u64, stream: &str) -> Real {
        let mut rng = seeded_rng(case_seed, stream);
        // Bounds keep at least LEAST_MASS of the distribution (checked when read), so this
        // loop ends after 1/LEAST_MASS draws on average.
        loop {
            let value = match self.distribution {
                Distribution::Fixed(value) => value,
                Distribution::Uniform { low, high } => low + (high - low) * rng.random::<Real>(),
                Distribution::Normal { mean, sd } => mean + sd * standard_normal(&mut rng),
                Distribution::LogNormal { median, sigma } => {
                    median * (sigma * standard_normal(&mut rng)).exp()
                }
            };
            match self.bounds {
                Some((low, high)) if !(low..=high).contains(&value) => continue,
                _ => return value,
            }
        }
    }
}

/// The standard normal CDF, `erfc(-z/√2)/2`, with the complementary error function of
/// Numerical Recipes' `erfcc` (Chebyshev fit, fractional error below 1.2e-7 everywhere).
pub fn normal_cdf(z: Real) -> Real {
    let x = -z / std::f64::consts::SQRT_2;
    let t = 1.0 / (1.0 + 0.5 * x.abs());
    let poly = -x * x - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let erfc = t * poly.exp();
    0.5 * if x >= 0.0 { erfc } else { 2.0 - erfc }
}

/// Where a value goes in the scenario: a dotted path of keys, each optionally indexing a list
/// (`errors.EXX.polynomial_um[1]`, `servo.X.kv_per_s`, `ballbar.setup_offset_um[0]`).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct ParamPath {
    text: String,
    segments: Vec<(String, Option<usize>)>,
}

impl ParamPath {
    /// Reads a path, or says what is wrong with it.
    pub fn parse(text: &str) -> Result<ParamPath, String> {
        let mut segments = Vec::new();
        for part in text.split('.') {
            let (name, index) = match part.split_once('[') {
                None => (part, None),
                Some((name, rest)) => {
                    let index = rest
                        .strip_suffix(']')
                        .and_then(|i| i.parse::<usize>().ok())
                        .ok_or_else(|| {
                            format!("`{text}`: `{part}` should be NAME or NAME[INDEX]")
                        })?;
                    (name, Some(index))
                }
            };
            let valid = !name.is_empty()
                && name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            if !valid {
                return Err(format!(
                    "`{text}`: expected keys of letters, digits and `_` joined by `.`, as in errors.EXX.polynomial_um[1]"
                ));
            }
            segments.push((name.to_string(), index));
        }
        if segments.len() < 2 {
            return Err(format!(
                "`{text}`: expected a section and a key, as in servo.X.kv_per_s or errors.EC0Y.constant_urad"
            ));
        }
        Ok(ParamPath {
            text: text.to_string(),
            segments,
        })
    }

    /// The path as written.
    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// The column of the `cases` table: the path without a leading `errors.`, keys joined by
    /// `_` and indices appended (`EXX_polynomial_um_1`, `servo_X_kv_per_s`).
    pub fn column(&self) -> String {
        let skip = usize::from(self.segments[0].0 == "errors");
        let mut parts = Vec::new();
        for (name, index) in &self.segments[skip..] {
            parts.push(name.clone());
            parts.extend(index.map(|i| i.to_string()));
        }
        parts.join("_")
    }

    /// The value's unit, from its key's suffix (`_um` µm, `_urad` µrad, `_per_s` 1/s, …); a
    /// polynomial coefficient of degree k is per mm^k (linear axes) or per deg^k (axes of
    /// rotation). Empty when the key names none.
    pub fn unit(&self) -> String {
        let (key, index) = self.segments.last().expect("at least two segments");
        let base = unit_of_key(key);
        let degree = index.filter(|_| key.starts_with("polynomial_"));
        match (degree, self.segments.get(1)) {
            (Some(0), _) | (None, _) => base.to_string(),
            (Some(k), Some((name, _))) if self.segments[0].0 == "errors" => {
                let per = if name.ends_with(['X', 'Y', 'Z']) {
                    "mm"
                } else {
                    "deg"
                };
                if k == 1 {
                    format!("{base}/{per}")
                } else {
                    format!("{base}/{per}^{k}")
                }
            }
            _ => base.to_string(),
        }
    }

    /// Writes `value` at the path in `table`, creating the tables and list entries it needs
    /// (missing list entries before the index become 0).
    pub fn set(&self, table: &mut toml::Table, value: Real) -> Result<(), String> {
        let mut current = table;
        let last = self.segments.len() - 1;
        for (depth, (name, index)) in self.segments.iter().enumerate() {
            let here = || {
                let mut p: Vec<&str> = Vec::new();
                for (n, _) in &self.segments[..=depth] {
                    p.push(n);
                }
                p.join(".")
            };
            let is_last = depth == last;
            let leaf = || toml::Value::Float(value);
            match index {
                None if is_last => {
                    if let Some(existing) = current.get(name)
                        && !matches!(existing, toml::Value::Float(_) | toml::Value::Integer(_))
                    {
                        return Err(format!(
                            "`{}`: the scenario has a {} there, not a number",
                            self.text,
                            existing.type_str()
                        ));
                    }
                    current.insert(name.clone(), leaf());
                    return Ok(());
                }
                None => {
                    let entry = current
                        .entry(name.clone())
                        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
                    current = entry.as_table_mut().ok_or_else(|| {
                        format!("`{}`: {} is not a table in the scenario", self.text, here())
                    })?;
                }
                Some(index) => {
                    let entry = current
                        .entry(name.clone())
                        .or_insert_with(|| toml::Value::Array(Vec::new()));
                    let list = entry.as_array_mut().ok_or_else(|| {
                        format!("`{}`: {} is not a list in the scenario", self.text, here())
                    })?;
                    // Only a polynomial grows to take a new coefficient (the ones below it are
                    // zero), up to the degree a scenario accepts; any other list has the
                    // entries it has (a 3-vector has no [7]).
                    if is_last && name.starts_with("polynomial_") {
                        if *index > MAX_POLYNOMIAL_DEGREE {
                            return Err(format!(
                                "`{}`: degree {index} is above the limit of a polynomial, {MAX_POLYNOMIAL_DEGREE}",
                                self.text
                            ));
                        }
                    } else if *index >= list.len() {
                        return Err(format!(
                            "`{}`: {} has {} entries in the scenario; [{index}] does not exist",
                            self.text,
                            here(),
                            list.len()
                        ));
                    }
                    while list.len() <= *index {
                        list.push(if is_last {
                            toml::Value::Float(0.0)
                        } else {
                            toml::Value::Table(toml::Table::new())
                        });
                    }
                    if is_last {
                        if !matches!(
                            list[*index],
                            toml::Value::Float(_) | toml::Value::Integer(_)
                        ) {
                            return Err(format!(
                                "`{}`: the scenario has a {} there, not a number",
                                self.text,
                                list[*index].type_str()
                            ));
                        }
                        list[*index] = leaf();
                        return Ok(());
                    }
                    current = list[*index].as_table_mut().ok_or_else(|| {
                        format!(
                            "`{}`: {}[{index}] is not a table in the scenario",
                            self.text,
                            here()
                        )
                    })?;
                }
            }
        }
        unreachable!("the last segment returns")
    }
}

/// The unit suffixes of scenario keys and column names, with their units (the longer first
/// where one ends another).
const SUFFIXES: &[(&str, &str)] = &[
    ("_mm_per_min", "mm/min"),
    ("_per_s", "1/s"),
    ("_um", "µm"),
    ("_urad", "µrad"),
    ("_mm", "mm"),
    ("_deg", "deg"),
    ("_ms", "ms"),
    ("_min", "min"),
    ("_hz", "Hz"),
    ("_rpm", "1/min"),
    ("_degc", "°C"),
    ("_c", "°C"),
    ("_w", "W"),
    ("_s", "s"),
];

/// The unit a scenario key's suffix names.
pub(super) fn unit_of_key(key: &str) -> &'static str {
    SUFFIXES
        .iter()
        .find(|(suffix, _)| key.ends_with(suffix))
        .map_or("", |(_, unit)| unit)
}

/// The unit suffix a key ends with (`_mm` of `centre_mm`), if any.
pub(super) fn unit_suffix(key: &str) -> Option<&'static str> {
    SUFFIXES
        .iter()
        .find(|(suffix, _)| key.ends_with(suffix) && key.len() > suffix.len())
        .map(|(suffix, _)| *suffix)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(text: &str) -> Result<Law, String> {
        toml::from_str::<RawPrior>(text).unwrap().law()
    }

    #[test]
    fn normal_cdf_matches_tabulated_values() {
        // Abramowitz & Stegun Table 26.1.
        for (z, p) in [
            (0.0, 0.5),
            (1.0, 0.841_344_746),
            (1.96, 0.975_002_105),
            (-2.5, 0.006_209_665),
            (3.0, 0.998_650_102),
        ] {
            assert!((normal_cdf(z) - p).abs() < 2e-7, "Φ({z})");
        }
    }

    #[test]
    fn bad_priors_are_refused_with_the_reason() {
        assert!(
            law("normal = [0.0, -1.0]")
                .unwrap_err()
                .contains("positive")
        );
        assert!(
            law("normal = [5.0, 1.0]\nbounds = [6.0, 9.0]")
                .unwrap_err()
                .contains("exclude")
        );
        assert!(
            law("normal = [0.0, 1.0]\nbounds = [-0.0001, 0.0001]")
                .unwrap_err()
                .contains("keep")
        );
        assert!(law("uniform = [2.0, 1.0]").unwrap_err().contains("lower"));
        assert!(
            law("fixed = 1.0\nnormal = [0.0, 1.0]")
                .unwrap_err()
                .contains("exactly one")
        );
        assert!(
            law("lognormal = [-1.0, 0.1]")
                .unwrap_err()
                .contains("median")
        );
        assert!(law("uniform = [0.0, 1.0]\nbounds = [0.0, 1.0]").is_err());
    }

    #[test]
    fn paths_name_columns_and_units() {
        let p = ParamPath::parse("errors.EXX.polynomial_um[2]").unwrap();
        assert_eq!(p.column(), "EXX_polynomial_um_2");
        assert_eq!(p.unit(), "µm/mm^2");
        let p = ParamPath::parse("errors.EC0Y.constant_urad").unwrap();
        assert_eq!(
            (p.column().as_str(), p.unit().as_str()),
            ("EC0Y_constant_urad", "µrad")
        );
        let p = ParamPath::parse("servo.X.kv_per_s").unwrap();
        assert_eq!(
            (p.column().as_str(), p.unit().as_str()),
            ("servo_X_kv_per_s", "1/s")
        );
        let p = ParamPath::parse("errors.ECC.polynomial_urad[1]").unwrap();
        assert_eq!(p.unit(), "µrad/deg");
        assert!(ParamPath::parse("ballbar").is_err());
        assert!(ParamPath::parse("errors.EXX.polynomial_um[x]").is_err());
    }

    #[test]
    fn set_creates_and_replaces_values() {
        let mut table: toml::Table = toml::from_str("[errors.EXX]\npolynomial_um = [1.0]").unwrap();
        ParamPath::parse("errors.EXX.polynomial_um[2]")
            .unwrap()
            .set(&mut table, 0.5)
            .unwrap();
        ParamPath::parse("servo.X.kv_per_s")
            .unwrap()
            .set(&mut table, 30.0)
            .unwrap();
        let expected: toml::Table = toml::from_str(
            "[errors.EXX]\npolynomial_um = [1.0, 0.0, 0.5]\n[servo.X]\nkv_per_s = 30.0",
        )
        .unwrap();
        assert_eq!(table, expected);
        let mut table: toml::Table = toml::from_str("[ballbar]\nplanes = [\"XY\"]").unwrap();
        let error = ParamPath::parse("ballbar.planes[0]")
            .unwrap()
            .set(&mut table, 1.0)
            .unwrap_err();
        assert!(error.contains("not a number"), "{error}");
    }

    /// Mean and standard deviation of `n` draws of `law`, one per case seed.
    fn moments(law: &Law, n: u64) -> (Real, Real, Vec<Real>) {
        let draws: Vec<Real> = (0..n).map(|k| law.sample(k, "p")).collect();
        let mean = draws.iter().sum::<Real>() / n as Real;
        let var = draws.iter().map(|x| (x - mean).powi(2)).sum::<Real>() / (n - 1) as Real;
        (mean, var.sqrt(), draws)
    }

    #[test]
    fn sample_moments_match_the_definitions() {
        const N: u64 = 40_000;
        let n = N as Real;
        // Tolerances: 4 standard errors of the statistic (sd/√n for a mean, sd/√(2n) for an
        // sd of a normal sample), so a correct sampler fails one check in ~16 000.
        let normal = law("normal = [3.0, 2.0]").unwrap();
        let (mean, sd, _) = moments(&normal, N);
        assert!((mean - 3.0).abs() < 4.0 * 2.0 / n.sqrt(), "{mean}");
        assert!((sd - 2.0).abs() < 4.0 * 2.0 / (2.0 * n).sqrt(), "{sd}");

        // Uniform on [a, b): mean (a+b)/2, sd (b−a)/√12 (the sd's standard error for a
        // uniform is below that of a normal of the same sd).
        let uniform = law("uniform = [-1.0, 5.0]").unwrap();
        let (mean, sd, draws) = moments(&uniform, N);
        let sd_true = 6.0 / 12f64.sqrt();
        assert!((mean - 2.0).abs() < 4.0 * sd_true / n.sqrt(), "{mean}");
        assert!(
            (sd - sd_true).abs() < 4.0 * sd_true / (2.0 * n).sqrt(),
            "{sd}"
        );
        assert!(draws.iter().all(|x| (-1.0..5.0).contains(x)));

        // Log-normal: ln x is N(ln median, sigma).
        let lognormal = law("lognormal = [0.5, 0.3]").unwrap();
        let logs: Vec<Real> = (0..N).map(|k| lognormal.sample(k, "p").ln()).collect();
        let mean = logs.iter().sum::<Real>() / n;
        let sd = (logs.iter().map(|x| (x - mean).powi(2)).sum::<Real>() / (n - 1.0)).sqrt();
        assert!((mean - 0.5f64.ln()).abs() < 4.0 * 0.3 / n.sqrt(), "{mean}");
        assert!((sd - 0.3).abs() < 4.0 * 0.3 / (2.0 * n).sqrt(), "{sd}");

        // Truncated normal on [α, β] (standardised): mean μ + σ (φ(α) − φ(β)) / (Φ(β) − Φ(α)).
        let truncated = law("normal = [0.0, 1.0]\nbounds = [-0.5, 2.0]").unwrap();
        let (mean, sd, draws) = moments(&truncated, N);
        let phi = |z: Real| (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
        let expected = (phi(-0.5) - phi(2.0)) / (normal_cdf(2.0) - normal_cdf(-0.5));
        assert!(
            (mean - expected).abs() < 4.0 * sd / n.sqrt(),
            "{mean} vs {expected}"
        );
        assert!(draws.iter().all(|x| (-0.5..=2.0).contains(x)));
        assert_eq!(law("fixed = 7.5").unwrap().sample(3, "p"), 7.5);
    }

    #[test]
    fn draws_depend_on_the_case_seed_and_stream_only() {
        let normal = law("normal = [0.0, 1.0]").unwrap();
        assert_eq!(normal.sample(11, "a"), normal.sample(11, "a"));
        assert_ne!(normal.sample(11, "a"), normal.sample(11, "b"));
        assert_ne!(normal.sample(11, "a"), normal.sample(12, "a"));
    }
}
