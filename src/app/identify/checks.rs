//! The door between a fit and the files that drive a machine: before `identify` writes a
//! LinuxCNC table, an identified URDF or a compensated scenario, the fit must pass its own
//! checks. A fit fails when
//!
//! - χ²/dof exceeds [`MAX_CHI2_PER_DOF`]: the residuals are more than ten times the readings'
//!   stated standard uncertainty, so the model describes little of what was measured. Below
//!   that the fit scales its uncertainties by χ²/dof (Birge) and stays honest; above it the
//!   scaled figures would describe a model that is not the machine. Units (nm in a µm column,
//!   radians in a degree column), a mistyped set-up position and a term the model lacks
//!   (lost motion, drift) all land here;
//! - χ²/dof is below [`MIN_CHI2_PER_DOF`] with 20 degrees of freedom or more: the residuals
//!   are under a tenth of the stated uncertainty, which noise of that size does with a
//!   probability below 1e-19. The readings are in a unit 1000 times too large for their
//!   column's name (mm in a `_um` column: every estimate 1000 times too small), or the stated
//!   uncertainty is far too large (a noise-free simulation: state `--sigma-um`);
//! - an identified parameter reaches beyond what a scenario accepts (10 mm or 10 mrad over its
//!   axis's travel, [`crate::scenario::errors::LARGEST_ERROR`]): no machine error is that
//!   large, a unit or a set-up value is wrong;
//! - an estimate, an uncertainty or χ² is not a finite number (one reading of 1e300);
//! - one reading, or one row of three (a sphere centre, an R-test pose), makes the misfit:
//!   χ²/dof is above [`MIN_OUTLIER_CHI2_PER_DOF`] and beyond its noise's 99 % quantile, and
//!   falls within it when that block is left out ([`crate::estimate::influence`]). Birge
//!   scaling would spread one bad value over every estimate as if it were noise (a sphere
//!   20 µm off among 0.5 µm readings moved EY0C by 11 µm); the user should correct or remove
//!   it.
//!
//! Each problem says what was found against what limit, and the message names the likely
//! cause. With `--accept-implausible` the files are written all the same, with the problems
//! as warnings in the report and in `estimate.json` (`warnings`).

use crate::errors::ErrorModel;
use crate::estimate::Readings;
use crate::estimate::fit::Fit;
use crate::machine::Machine;
use crate::math::Real;

/// The largest χ²/dof a fit may have and still write compensation: residuals ten times the
/// readings' stated standard uncertainty (see the module doc).
pub const MAX_CHI2_PER_DOF: Real = 100.0;

/// The smallest χ²/dof a fit with at least 20 degrees of freedom may
/// have (see the module doc): residuals a tenth of the readings' stated uncertainty.
pub const MIN_CHI2_PER_DOF: Real = 0.01;

/// The χ²/dof from which one reading that makes the whole misfit refuses the fit: residuals
/// twice the stated uncertainty. Below it, one reading's excess changes the estimates by less
/// than their uncertainty.
pub const MIN_OUTLIER_CHI2_PER_DOF: Real = 4.0;

/// The degrees of freedom from which a too small χ² is judged.
const MIN_DOF_FOR_SMALL_CHI2: usize = 20;

/// A residual RMS above this (m) is no machine error a small-motion model misses: the data are
/// in another unit or the set-up is wrong.
const UNITS_RESIDUAL: Real = 1e-3;

/// What the checks found: each problem in a sentence, and the likely cause.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Findings {
    /// Each failed check, for people.
    pub problems: Vec<String>,
    /// The likely cause, when there are problems.
    pub cause: String,
}

impl Findings {
    /// Whether the fit passed every check.
    pub fn passed(&self) -> bool {
        self.problems.is_empty()
    }
}

/// Checks `fit` of `sets` (named by `sources`) and the `identified` model on `machine`.
pub fn check(
    fit: &Fit,
    sets: &[Readings],
    sources: &[String],
    identified: &ErrorModel,
    machine: &Machine,
) -> Findings {
    let mut problems = Vec::new();
    let mut units = false;
    let chi2_per_dof = fit.chi2 / fit.dof.max(1) as Real;
    if !chi2_per_dof.is_finite() || !fit.z.iter().all(|z| z.is_finite()) {
        problems.push(
            "the fit is not finite (χ² or an estimate is not a number): a reading is far beyond \
             any instrument's range"
                .to_string(),
        );
        units = true;
    } else if fit.dof > 0 && chi2_per_dof > MAX_CHI2_PER_DOF {
        // The table the model describes worst, by its residuals over its readings' σ.
        let worst = sets
            .iter()
            .enumerate()
            .map(|(k, set)| {
                let rms = fit.residual_rms.get(k).copied().unwrap_or(0.0);
                let sigma = set.mean_sigma();
                (k, rms, sigma)
            })
            .filter(|(_, rms, sigma)| rms.is_finite() && *sigma > 0.0)
            .max_by(|a, b| (a.1 / a.2).total_cmp(&(b.1 / b.2)));
        problems.push(format!(
            "χ²/dof = {} is above {MAX_CHI2_PER_DOF}: the residuals are {:.0} times the readings' \
             stated uncertainty, so the model does not describe these data{}",
            significant(chi2_per_dof),
            chi2_per_dof.sqrt(),
            worst.map_or_else(String::new, |(k, rms, sigma)| format!(
                " (worst: {}, residual RMS {} µm against its readings' {} µm)",
                sources.get(k).map_or(sets[k].kind, String::as_str),
                significant(rms * 1e6),
                significant(sigma * 1e6)
            ))
        ));
    } else if fit.dof >= MIN_DOF_FOR_SMALL_CHI2 && chi2_per_dof < MIN_CHI2_PER_DOF {
        problems.push(format!(
            "χ²/dof = {} is below {MIN_CHI2_PER_DOF} with {} degrees of freedom: the residuals are {} of the readings' stated uncertainty, far smaller than any noise of that size leaves (readings 1000 times too small for their column's unit, e.g. mm in a `_um` column, or the stated uncertainty far too large: --sigma-um)",
            significant(chi2_per_dof),
            fit.dof,
            significant(chi2_per_dof.sqrt())
        ));
        units = true;
    }
    for (k, set) in sets.iter().enumerate() {
        let rms = fit.residual_rms.get(k).copied().unwrap_or(0.0);
        let sigma = set.mean_sigma();
        if !rms.is_finite() {
            units = true;
            problems.push(format!(
                "{}: the residuals are not finite numbers (a reading beyond any instrument's range)",
                sources.get(k).map_or(set.kind, String::as_str)
            ));
        } else if rms > UNITS_RESIDUAL {
            units = true;
            problems.push(format!(
                "{}: residual RMS {} µm ({} times its readings' uncertainty of {} µm)",
                sources.get(k).map_or(set.kind, String::as_str),
                significant(rms * 1e6),
                significant(rms / sigma),
                significant(sigma * 1e6)
            ));
        }
    }
    let outlier = outlier(fit, sets, sources);
    problems.extend(outlier.clone());
    let infinite = (0..fit.z.len())
        .filter(|&j| fit.identified[j] && fit.uncertainty(j).is_none_or(|u| !u.is_finite()))
        .count();
    if infinite > 0 {
        problems.push(format!(
            "{infinite} of the {} identified unknowns have no finite uncertainty",
            fit.identified.iter().filter(|i| **i).count()
        ));
        units = true;
    }
    for parameter in identified.parameters() {
        if let Some(why) = crate::scenario::errors::implausible(parameter, machine) {
            problems.push(format!("{}: the estimate {why}", parameter.name));
            units = true;
        }
    }
    let cause = if problems.is_empty() {
        String::new()
    } else if outlier.is_some() {
        "likely cause: one reading mistyped or disturbed (a typo, a stylus re-qualified between \
         features, dirt on the sphere, a knock): correct or remove it and run again"
            .to_string()
    } else if units {
        "likely cause: units or set-up: a column in another unit than its name says (nm or mm \
         in a `_um` column, radians in a `_deg` column), a mistyped set-up position \
         (--rtest-sphere-mm, the preamble), or a table of another machine"
            .to_string()
    } else {
        "likely cause: a term the model lacks (lost motion, thermal drift during the test, a \
         component error not in --params), a set-up the model does not free (--free-setup), \
         columns swapped or of the opposite sign (dx/dy, a/c, target − reached), a plane or an \
         axis mislabelled, or readings' uncertainty stated too small (--sigma-um)"
            .to_string()
    };
    Findings { problems, cause }
}

/// The χ²/dof below which a fit that passes its checks (with 20 degrees of freedom or more)
/// is told to the user: residuals 0.55 of the stated uncertainty, which noise of that size
/// leaves with a probability below 1e-3 at 20 degrees of freedom and far less with more.
pub const SMALL_CHI2_PER_DOF: Real = 0.3;

/// What a fit that passes its checks should still say: residuals well below the readings'
/// stated uncertainty (above [`MIN_CHI2_PER_DOF`], which refuses). Either every uncertainty
/// printed is that much too large, or the readings are in a unit a few times smaller than
/// their column says (tenths of a thou, ÷2.54; counts of 0.1 µm read as µm are 10 times
/// larger and land above) and every estimate is that many times too small: the data cannot
/// tell which.
pub fn cautions(fit: &Fit) -> Vec<String> {
    let per_dof = fit.chi2 / fit.dof.max(1) as Real;
    if fit.dof >= MIN_DOF_FOR_SMALL_CHI2
        && (MIN_CHI2_PER_DOF..SMALL_CHI2_PER_DOF).contains(&per_dof)
    {
        vec![format!(
            "χ²/dof = {} with {} degrees of freedom: the residuals are {} of the readings' stated uncertainty, less than noise of that size leaves. Either the stated uncertainty is too large (--sigma-um; every u printed is then too large), or the readings are in a smaller unit than their column says (tenths of a thou in a `_um` column read 2.54 times small) and every estimate is too small by that factor",
            significant(per_dof),
            fit.dof,
            significant(per_dof.sqrt())
        )]
    } else {
        Vec::new()
    }
}

/// One reading, or one row of three, without which the misfit falls back to the noise's.
fn outlier(fit: &Fit, sets: &[Readings], sources: &[String]) -> Option<String> {
    use crate::estimate::fit::chi2_quantile_99;
    let per_dof = fit.chi2 / fit.dof.max(1) as Real;
    if fit.dof < 2
        || per_dof < MIN_OUTLIER_CHI2_PER_DOF
        || fit.chi2 <= chi2_quantile_99(fit.dof as Real)
    {
        return None;
    }
    let block = fit.influential.iter().find(|b| {
        fit.dof > b.count && b.chi2_without <= chi2_quantile_99((fit.dof - b.count) as Real)
    })?;
    let set = sets.get(block.set)?;
    let name = if block.count == 1 {
        set.model.reading_name(block.first)
    } else {
        let name = set.model.reading_name(block.first);
        name.split(" (").next().unwrap_or(&name).to_string()
    };
    Some(format!(
        "{}: {name} alone makes the misfit: without it χ²/dof falls from {} to {}; its residual is {} µm against the readings' {} µm, a mistyped or disturbed reading",
        sources.get(block.set).map_or(set.kind, String::as_str),
        significant(per_dof),
        significant(block.chi2_without / (fit.dof - block.count) as Real),
        significant(block.residual * 1e6),
        significant(set.mean_sigma() * 1e6)
    ))
}

/// A value with four significant digits, in scientific notation when large.
fn significant(value: Real) -> String {
    if !value.is_finite() {
        "not finite".into()
    } else if value.abs() >= 1e5 {
        format!("{value:.3e}")
    } else if value.abs() >= 100.0 {
        format!("{value:.0}")
    } else {
        format!("{value:.3}")
    }
}
