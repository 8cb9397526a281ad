//! ISO 230-2:2014 evaluation of a positioning table: per target x̄↑, x̄↓, s↑, s↓, Bᵢ, R↑ᵢ,
//! R↓ᵢ, Rᵢ; per axis E↑, E↓, E, M, A↑, A↓, A, R↑, R↓, R, B, B̄.
//!
//! With `xᵢⱼ` the deviation (reached − target) of run j at target i, n runs per direction:
//!
//! ```text
//! x̄↑ᵢ = Σⱼ xᵢⱼ↑ / n            s↑ᵢ = √(Σⱼ (xᵢⱼ↑ − x̄↑ᵢ)² / (n − 1))     R↑ᵢ = 4 s↑ᵢ
//! x̄ᵢ = (x̄↑ᵢ + x̄↓ᵢ) / 2         Bᵢ = x̄↑ᵢ − x̄↓ᵢ
//! Rᵢ = max(2s↑ᵢ + 2s↓ᵢ + |Bᵢ|, R↑ᵢ, R↓ᵢ)
//! B = max |Bᵢ|                  B̄ = Σᵢ Bᵢ / m
//! R↑ = max R↑ᵢ                  R = max Rᵢ
//! E↑ = max x̄↑ᵢ − min x̄↑ᵢ        E = max(x̄↑ᵢ, x̄↓ᵢ) − min(x̄↑ᵢ, x̄↓ᵢ)
//! M = max x̄ᵢ − min x̄ᵢ
//! A↑ = max(x̄↑ᵢ + 2s↑ᵢ) − min(x̄↑ᵢ − 2s↑ᵢ)
//! A = max(x̄↑ᵢ + 2s↑ᵢ, x̄↓ᵢ + 2s↓ᵢ) − min(x̄↑ᵢ − 2s↑ᵢ, x̄↓ᵢ − 2s↓ᵢ)
//! ```
//!
//! A file with readings in one direction only gets that direction's figures; the
//! bidirectional ones (E, M, A, R, B, B̄, x̄ᵢ, Bᵢ, Rᵢ) are absent. SI inside (m).

use crate::kinds::positioning::table::PositioningTable;
use crate::math::Real;
use crate::program::Approach;

/// The figures of one direction at one target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionFigures {
    /// Number of readings (runs).
    pub n: usize,
    /// Mean positional deviation x̄ᵢ (m).
    pub mean: Real,
    /// Standard deviation estimator sᵢ, with n − 1 (m).
    pub s: Real,
    /// Unidirectional repeatability Rᵢ = 4 sᵢ (m).
    pub repeatability: Real,
}

/// The figures at one target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TargetFigures {
    /// Target position (m).
    pub target: Real,
    /// Approaching in the positive direction (↑), if measured.
    pub up: Option<DirectionFigures>,
    /// Approaching in the negative direction (↓), if measured.
    pub down: Option<DirectionFigures>,
    /// Bidirectional figures, when both directions were measured.
    pub both: Option<BidirectionalFigures>,
}

/// The bidirectional figures at one target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BidirectionalFigures {
    /// Mean bidirectional positional deviation x̄ᵢ (m).
    pub mean: Real,
    /// Reversal value Bᵢ = x̄↑ᵢ − x̄↓ᵢ (m).
    pub reversal: Real,
    /// Bidirectional repeatability Rᵢ (m).
    pub repeatability: Real,
}

/// The figures of one direction over the axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisDirectionFigures {
    /// Unidirectional systematic positional deviation E↑ or E↓ (m).
    pub systematic: Real,
    /// Unidirectional accuracy A↑ or A↓ (m).
    pub accuracy: Real,
    /// Unidirectional repeatability R↑ or R↓ (m).
    pub repeatability: Real,
}

/// The bidirectional figures of the axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisBidirectionalFigures {
    /// Bidirectional systematic positional deviation E (m).
    pub systematic: Real,
    /// Mean bidirectional positional deviation M (m).
    pub mean: Real,
    /// Bidirectional accuracy A (m).
    pub accuracy: Real,
    /// Bidirectional repeatability R (m).
    pub repeatability: Real,
    /// Reversal value B = max |Bᵢ| (m).
    pub reversal: Real,
    /// Mean reversal value B̄ (m).
    pub mean_reversal: Real,
}

/// The ISO 230-2 evaluation of one axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Iso230_2 {
    /// Per target, in increasing target position.
    pub targets: Vec<TargetFigures>,
    /// Over the axis, positive direction.
    pub up: Option<AxisDirectionFigures>,
    /// Over the axis, negative direction.
    pub down: Option<AxisDirectionFigures>,
    /// Over the axis, both directions.
    pub both: Option<AxisBidirectionalFigures>,
}

/// Why a table cannot be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Iso230_2Error {
    /// A run reads a target twice in the same direction (ISO 230-2: one reading per run).
    #[error(
        "run \"{run}\" reads target {target_mm} mm twice in the {direction} direction: ISO 230-2 takes one reading per run"
    )]
    RepeatedReading {
        /// The run label.
        run: String,
        /// The target (mm).
        target_mm: Real,
        /// `+` or `-`.
        direction: char,
    },
    /// Fewer than two targets.
    #[error("{0} target position(s): an evaluation needs at least two")]
    TooFewTargets(usize),
    /// Fewer than two readings at a target in a direction: no repeatability.
    #[error(
        "target {target_mm} mm has {n} reading(s) in the {direction} direction: repeatability needs at least two runs"
    )]
    TooFewRuns {
        /// The target (mm).
        target_mm: Real,
        /// Its direction (`+` or `-`).
        direction: char,
        /// How many readings it has.
        n: usize,
    },
    /// A target measured in one direction only in a file with both directions.
    #[error(
        "target {target_mm} mm has readings in one direction only, {}",
        if *with_both == 0 {
            "and so has every other target (each approached from one side, as in an ISO 230-3 \
             linear-motion test): ISO 230-2 needs every target in both directions".to_string()
        } else {
            format!("while {with_both} other target{} both", if *with_both == 1 { " has" } else { "s have" })
        }
    )]
    MissingDirection {
        /// The target (mm).
        target_mm: Real,
        /// How many targets have readings in both directions.
        with_both: usize,
    },
}

/// Targets closer than this (m) are the same target (values written with different rounding).
const SAME_TARGET: Real = 1e-9;

/// Evaluates a positioning table to ISO 230-2:2014.
pub fn evaluate(table: &PositioningTable) -> Result<Iso230_2, Iso230_2Error> {
    let mut positions: Vec<Real> = table.readings.iter().map(|r| r.target).collect();
    positions.sort_by(Real::total_cmp);
    positions.dedup_by(|a, b| (*a - *b).abs() < SAME_TARGET);
    if positions.len() < 2 {
        return Err(Iso230_2Error::TooFewTargets(positions.len()));
    }
    // One reading per run, target and direction.
    for (k, a) in table.readings.iter().enumerate() {
        if let Some(b) = table.readings[..k].iter().find(|b| {
            b.run == a.run && b.approach == a.approach && (b.target - a.target).abs() < SAME_TARGET
        }) {
            return Err(Iso230_2Error::RepeatedReading {
                run: table.runs[b.run].clone(),
                target_mm: a.target * 1e3,
                direction: if a.approach == Approach::Up { '+' } else { '-' },
            });
        }
    }
    let directions: Vec<Approach> = [Approach::Up, Approach::Down]
        .into_iter()
        .filter(|a| table.readings.iter().any(|r| r.approach == *a))
        .collect();

    let mut targets = Vec::with_capacity(positions.len());
    for &target in &positions {
        let figures_for = |approach: Approach| -> Result<Option<DirectionFigures>, Iso230_2Error> {
            if !directions.contains(&approach) {
                return Ok(None);
            }
            let values: Vec<Real> = table
                .readings
                .iter()
                .filter(|r| r.approach == approach && (r.target - target).abs() < SAME_TARGET)
                .map(|r| r.deviation)
                .collect();
            let n = values.len();
            if n == 0 && directions.len() == 2 {
                let has = |p: Real, a: Approach| {
                    table
                        .readings
                        .iter()
                        .any(|r| r.approach == a && (r.target - p).abs() < SAME_TARGET)
                };
                let with_both = positions
                    .iter()
                    .filter(|&&p| has(p, Approach::Up) && has(p, Approach::Down))
                    .count();
                return Err(Iso230_2Error::MissingDirection {
                    target_mm: target * 1e3,
                    with_both,
                });
            }
            if n < 2 {
                let direction = if approach == Approach::Up { '+' } else { '-' };
                return Err(Iso230_2Error::TooFewRuns {
                    target_mm: target * 1e3,
                    direction,
                    n,
                });
            }
            let mean = values.iter().sum::<Real>() / n as Real;
            let s =
                (values.iter().map(|x| (x - mean).powi(2)).sum::<Real>() / (n - 1) as Real).sqrt();
            Ok(Some(DirectionFigures {
                n,
                mean,
                s,
                repeatability: 4.0 * s,
            }))
        };
        let up = figures_for(Approach::Up)?;
        let down = figures_for(Approach::Down)?;
        let both = match (up, down) {
            (Some(u), Some(d)) => {
                let reversal = u.mean - d.mean;
                Some(BidirectionalFigures {
                    mean: (u.mean + d.mean) / 2.0,
                    reversal,
                    repeatability: (2.0 * u.s + 2.0 * d.s + reversal.abs())
                        .max(u.repeatability)
                        .max(d.repeatability),
                })
            }
            _ => None,
        };
        targets.push(TargetFigures {
            target,
            up,
            down,
            both,
        });
    }

    let axis_direction =
        |pick: fn(&TargetFigures) -> Option<DirectionFigures>| -> Option<AxisDirectionFigures> {
            let values: Vec<DirectionFigures> = targets.iter().filter_map(pick).collect();
            (!values.is_empty()).then(|| AxisDirectionFigures {
                systematic: range(values.iter().map(|v| v.mean)),
                accuracy: max(values.iter().map(|v| v.mean + 2.0 * v.s))
                    - min(values.iter().map(|v| v.mean - 2.0 * v.s)),
                repeatability: max(values.iter().map(|v| v.repeatability)),
            })
        };
    let up = axis_direction(|t| t.up);
    let down = axis_direction(|t| t.down);
    let both = (up.is_some() && down.is_some()).then(|| {
        let means = || targets.iter().flat_map(|t| [t.up, t.down]).flatten();
        let bidirectional = || targets.iter().filter_map(|t| t.both);
        AxisBidirectionalFigures {
            systematic: range(means().map(|v| v.mean)),
            mean: range(bidirectional().map(|b| b.mean)),
            accuracy: max(means().map(|v| v.mean + 2.0 * v.s))
                - min(means().map(|v| v.mean - 2.0 * v.s)),
            repeatability: max(bidirectional().map(|b| b.repeatability)),
            reversal: max(bidirectional().map(|b| b.reversal.abs())),
            mean_reversal: bidirectional().map(|b| b.reversal).sum::<Real>()
                / targets.len() as Real,
        }
    });
    Ok(Iso230_2 {
        targets,
        up,
        down,
        both,
    })
}

fn max(values: impl Iterator<Item = Real>) -> Real {
    values.fold(Real::NEG_INFINITY, Real::max)
}

fn min(values: impl Iterator<Item = Real>) -> Real {
    values.fold(Real::INFINITY, Real::min)
}

fn range(values: impl Iterator<Item = Real> + Clone) -> Real {
    max(values.clone()) - min(values)
}

/// µm, rounded to 1 pm so that reports do not carry binary noise.
fn um(value: Real) -> Real {
    (value * 1e12).round() / 1e6
}

impl Iso230_2 {
    /// The JSON report. Stable keys (µm): `E_um, E_up_um, E_down_um, M_um, A_um, A_up_um,
    /// A_down_um, R_um, R_up_um, R_down_um, B_um, B_mean_um` (null when the file lacks the
    /// direction they need), `targets` (per target: `target_mm, n_up, n_down, mean_up_um,
    /// mean_down_um, s_up_um, s_down_um, R_up_um, R_down_um, mean_um, B_um, R_um`), and `kind`,
    /// `standard`, `axis`, `n_targets`, `n_runs`, `bidirectional`, `note`, `conditions` (what the
    /// preamble said: [`super::conditions::PositioningConditions::report`]), `preamble_not_used`, `columns_not_read`,
    /// `cautions` ([`super::plausible::cautions`]); for a thermal series
    /// (see [`super::thermal_series`]) also `runs` and `drift`.
    pub fn to_json(&self, table: &PositioningTable) -> serde_json::Value {
        use serde_json::json;
        let option = |value: Option<Real>| value.map(um);
        let targets: Vec<serde_json::Value> = self
            .targets
            .iter()
            .map(|t| {
                json!({
                    "target_mm": (t.target * 1e9).round() / 1e6,
                    "n_up": t.up.map_or(0, |d| d.n),
                    "n_down": t.down.map_or(0, |d| d.n),
                    "mean_up_um": option(t.up.map(|d| d.mean)),
                    "mean_down_um": option(t.down.map(|d| d.mean)),
                    "s_up_um": option(t.up.map(|d| d.s)),
                    "s_down_um": option(t.down.map(|d| d.s)),
                    "R_up_um": option(t.up.map(|d| d.repeatability)),
                    "R_down_um": option(t.down.map(|d| d.repeatability)),
                    "mean_um": option(t.both.map(|b| b.mean)),
                    "B_um": option(t.both.map(|b| b.reversal)),
                    "R_um": option(t.both.map(|b| b.repeatability)),
                })
            })
            .collect();
        let mut report = json!({
            "kind": "positioning",
            "standard": "ISO 230-2:2014",
            "axis": table.axis.map(|a| a.to_string()),
            "n_targets": self.targets.len(),
            "n_runs": table.runs.len(),
            "bidirectional": self.both.is_some(),
            "note": self.note(),
            "E_um": option(self.both.map(|b| b.systematic)),
            "E_up_um": option(self.up.map(|d| d.systematic)),
            "E_down_um": option(self.down.map(|d| d.systematic)),
            "M_um": option(self.both.map(|b| b.mean)),
            "A_um": option(self.both.map(|b| b.accuracy)),
            "A_up_um": option(self.up.map(|d| d.accuracy)),
            "A_down_um": option(self.down.map(|d| d.accuracy)),
            "R_um": option(self.both.map(|b| b.repeatability)),
            "R_up_um": option(self.up.map(|d| d.repeatability)),
            "R_down_um": option(self.down.map(|d| d.repeatability)),
            "B_um": option(self.both.map(|b| b.reversal)),
            "B_mean_um": option(self.both.map(|b| b.mean_reversal)),
            "targets": targets,
            "conditions": table.conditions.report().0,
            "preamble_not_used": table.conditions.not_used,
            "columns_not_read": table.columns_not_read,
            "cautions": super::plausible::cautions(table),
        });
        if let Some(series) = super::thermal_series::thermal_series(table) {
            let (runs, drift) = series.to_json();
            report["runs"] = runs;
            report["drift"] = drift;
        }
        report
    }

    /// What the evaluation could not give, if anything.
    fn note(&self) -> Option<String> {
        match (self.up.is_some(), self.down.is_some()) {
            (true, true) => None,
            (up, _) => Some(format!(
                "readings in the {} direction only: unidirectional figures only; E, M, A, R, B and B̄ need both directions",
                if up { "+" } else { "-" }
            )),
        }
    }

    /// The report for people, a thermal series' runs compact (see [`Self::to_text_with`]).
    pub fn to_text(&self, table: &PositioningTable) -> String {
        self.to_text_with(table, false)
    }

    /// The report for people; `verbose` lists every run of a thermal series.
    pub fn to_text_with(&self, table: &PositioningTable, verbose: bool) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        let axis = table
            .axis
            .map_or_else(|| "axis".to_string(), |a| format!("axis {a}"));
        let _ = writeln!(
            out,
            "ISO 230-2:2014 positioning, {axis}: {} targets, {} runs{}",
            self.targets.len(),
            table.runs.len(),
            if self.both.is_some() {
                ", bidirectional"
            } else {
                ""
            }
        );
        out += &table.conditions.report().1;
        let cell = |v: Option<Real>| {
            v.map_or_else(|| format!("{:>9}", "-"), |v| format!("{:>9.3}", um(v)))
        };
        let _ = writeln!(
            out,
            "\n{:>12} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
            "target mm", "x̄↑ µm", "x̄↓ µm", "s↑ µm", "s↓ µm", "Bᵢ µm", "R↑ᵢ µm", "R↓ᵢ µm", "Rᵢ µm"
        );
        for t in &self.targets {
            let _ = writeln!(
                out,
                "{:>12.4} {} {} {} {} {} {} {} {}",
                t.target * 1e3,
                cell(t.up.map(|d| d.mean)),
                cell(t.down.map(|d| d.mean)),
                cell(t.up.map(|d| d.s)),
                cell(t.down.map(|d| d.s)),
                cell(t.both.map(|b| b.reversal)),
                cell(t.up.map(|d| d.repeatability)),
                cell(t.down.map(|d| d.repeatability)),
                cell(t.both.map(|b| b.repeatability)),
            );
        }
        let line = |name: &str, v: Option<Real>| format!("  {name:<48}{}\n", cell(v));
        out.push('\n');
        out += &line(
            "systematic positional deviation E↑ (µm)",
            self.up.map(|d| d.systematic),
        );
        out += &line(
            "systematic positional deviation E↓ (µm)",
            self.down.map(|d| d.systematic),
        );
        out += &line(
            "systematic positional deviation E (µm)",
            self.both.map(|b| b.systematic),
        );
        out += &line(
            "mean bidirectional positional deviation M (µm)",
            self.both.map(|b| b.mean),
        );
        out += &line("accuracy A↑ (µm)", self.up.map(|d| d.accuracy));
        out += &line("accuracy A↓ (µm)", self.down.map(|d| d.accuracy));
        out += &line("accuracy A (µm)", self.both.map(|b| b.accuracy));
        out += &line("repeatability R↑ (µm)", self.up.map(|d| d.repeatability));
        out += &line("repeatability R↓ (µm)", self.down.map(|d| d.repeatability));
        out += &line("repeatability R (µm)", self.both.map(|b| b.repeatability));
        out += &line("reversal value B (µm)", self.both.map(|b| b.reversal));
        out += &line(
            "mean reversal value B̄ (µm)",
            self.both.map(|b| b.mean_reversal),
        );
        for caution in super::plausible::cautions(table) {
            let _ = writeln!(out, "\nCAUTION: {caution}.");
        }
        if let Some(series) = super::thermal_series::thermal_series(table) {
            out += &series.to_text_with(verbose);
        }
        if let Some(note) = self.note() {
            let _ = writeln!(out, "\nNote: {note}.");
        }
        out += &crate::io::not_used_line(&table.conditions.not_used);
        out += &crate::io::not_read_line(&table.columns_not_read);
        out
    }
}
