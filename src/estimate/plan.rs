//! Test design: which of the candidate tests to run, in which order, to identify every
//! parameter and then to pin it best within a budget of readings.
//!
//! # Criterion
//! Greedy D-optimality with a weak prior. The information of a design `J` (weighted by 1/σ per
//! reading, columns in µm-equivalents: see [`identifiability`]) is `M = JᵀJ + p·I`, with the
//! prior precision `p = 1/largest_uncertainty²` per µm-eq² (1e-6 at the default 1000 µm-eq: each
//! parameter known beforehand to ±1 mm, the same bound beyond which the rank rule calls a
//! direction unidentifiable). The prior keeps `log det M` finite before the design identifies
//! everything, and a direction that a test moves from the prior to a well-seen value gains
//! `ln(s²/p)`, far more than any improvement of an already identified one, so the first steps
//! go to identifiability. `log det M = Σ ln(s_i² + p)` over the `n` singular values of `J` (zeros
//! included), computed from the SVD rather than a Cholesky factor of `M`.
//!
//! # Selection
//! **Greedy.** Starting from the base design (or none), each step adds the candidate with the
//! largest gain of `log det M` per reading among those not chosen yet (each candidate at most
//! once: list a test twice to allow repeating it) whose readings fit in what remains of the
//! budget; ties go to the candidate listed first. It stops when no candidate fits or none gains
//! more than [`MIN_GAIN`]. So it goes on after every parameter is identifiable, while the budget
//! lasts.
//!
//! **Exchange** (Fedorov's algorithm, on whole tests). Greedy can be beaten at equal budget: a
//! test that sees two parameters together can gain most per reading first, and two tests that
//! see each on its own are then worth more than it and one of them (see
//! [`choose`]'s example). So, from the greedy set, every exchange of one chosen test for one
//! not chosen that fits the budget is scored, and the one that raises `log det M` most (by
//! more than [`MIN_EXCHANGE_GAIN`]) is made, followed by the greedy additions the freed readings allow;
//! this repeats until no exchange gains. Each move raises `log det M`, so it ends. The plan
//! reports each exchange and what it gained over the greedy set ([`Plan::exchanges`]).
//!
//! **Costs.** The budget is in readings ([`choose`]) or in another unit with set-ups
//! ([`choose_within`], [`Costs`]: minutes of testing, an instrument's set-up paid once for
//! every test made on it). The greedy steps then take the largest gain per cost on top of what
//! is chosen (a test on a set-up already made costs its run only), and each exchange is scored
//! with the greedy additions it allows: moving a test onto a set-up already made frees the
//! other set-up's time for more tests.
//!
//! The final set is listed in greedy order (each test the one gaining most per reading, or per
//! unit of cost, given those before it): [`Plan::identifiable_after`] gives the step at which
//! identifiability was reached. After each step the predicted standard uncertainty of every
//! parameter comes from [`identifiability::analyse`] of the stacked design (no prior), `None`
//! while a parameter is unidentifiable.

use super::identifiability::{self, Combination, Options, compress, significant, stack};
use crate::math::Real;
use nalgebra::DMatrix;
use serde_json::{Value, json};
use std::fmt::Write;

/// A candidate must raise `log det M` by more than this (nats, in total) to be chosen.
pub const MIN_GAIN: Real = 1e-9;

/// Gains (nats) closer than this are a tie, which goes to the candidate listed first: tests
/// alike by symmetry (a C turn at A = ±45°) give the same gain but for round-off (1e-13), and
/// the plan must not depend on it.
const TIE: Real = 1e-9;

/// An exchange must raise `log det M` by more than this (nats): 0.1 % of det M. Tests alike by
/// symmetry (a sweep at C = 0° and at C = 180°) hold the same information, and their designs,
/// made by forward differences (about 1e-7 of a column), differ in `log det M` by 1e-6 or
/// less; an exchange between them would move nothing.
pub const MIN_EXCHANGE_GAIN: Real = 1e-3;

/// One chosen test.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// The candidate's name.
    pub test: String,
    /// Its number of readings (rows of its design).
    pub readings: usize,
    /// What it cost on top of the steps before it, in the plan's unit ([`Costs`]): its run,
    /// and its set-up when no step before it made that.
    pub cost: Real,
    /// `log det(JᵀJ + p·I)` of the design after this step (J in 1/µm-eq, p per µm-eq²).
    pub log_det: Real,
    /// The predicted standard uncertainty (µm-eq) of each parameter after this step; `None`
    /// while unidentifiable.
    pub uncertainties: Vec<Option<Real>>,
}

/// The chosen tests in order.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The chosen tests, in the order chosen.
    pub steps: Vec<Step>,
    /// Whether every parameter is identifiable after the last step.
    pub identifiable: bool,
    /// The parameters' names.
    pub labels: Vec<String>,
    /// The prior precision `p` used (per µm-eq²).
    pub prior_precision: Real,
    /// `log det(JᵀJ + p·I)` of the base design (`n·ln p` without one).
    pub base_log_det: Real,
    /// The number of steps after which every parameter was identifiable (0: the base alone
    /// identifies them); `None` when never.
    pub identifiable_after: Option<usize>,
    /// The predicted standard uncertainty (µm-eq) of each parameter from the base design alone.
    pub base_uncertainties: Vec<Option<Real>>,
    /// The budget, in [`Plan::unit`].
    pub budget: Real,
    /// The unit of the costs and the budget ([`Costs::unit`]).
    pub unit: &'static str,
    /// The combinations no candidate test sees, not even every one of them together with the
    /// base: blind spots of the tests themselves, which no budget removes (empty when every
    /// test together identifies every parameter).
    pub structural: Vec<Combination>,
    /// What every candidate together costs ([`Plan::unit`]): they would identify every
    /// parameter when the budget is what stops the plan.
    pub every_test_cost: Real,
    /// `log det(JᵀJ + p·I)` of the greedy set, before the exchanges.
    pub greedy_log_det: Real,
    /// The exchanges made after the greedy pass, in order (empty when none gains).
    pub exchanges: Vec<Exchange>,
}

/// One exchange of the plan's search (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Exchange {
    /// The test taken out.
    pub removed: String,
    /// The test put in.
    pub added: String,
    /// What it raised `log det(JᵀJ + p·I)` by (nats), with the additions that followed it.
    pub gain: Real,
}

/// Why a plan leaves parameters unidentifiable, if it does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// No candidate test, nor all of them, sees some combination (see [`Plan::structural`]).
    Structure,
    /// Every test together would identify every parameter; the budget does not reach them.
    Budget,
}

/// The prior precision (per µm-eq²) for `options`: `1/largest_uncertainty²`, or 1e-12 when that
/// is not a positive finite number.
pub fn prior_precision(options: &Options) -> Real {
    let p = 1.0 / (options.largest_uncertainty * options.largest_uncertainty);
    if p > 0.0 && p.is_finite() { p } else { 1e-12 }
}

/// `log det(JᵀJ + p·I) = Σ ln(s_i² + p)` over all `n` singular values of `design`.
pub fn log_det(design: &DMatrix<Real>, prior_precision: Real) -> Real {
    let n = design.ncols();
    if design.nrows() == 0 {
        return n as Real * prior_precision.ln();
    }
    let s = mtwin_kernels::linalg::svd(design.clone(), false, false).singular_values;
    let seen: Real = s.iter().map(|s| (s * s + prior_precision).ln()).sum();
    seen + (n - s.len()) as Real * prior_precision.ln()
}

/// What tests cost, for a plan's budget: each candidate's own cost (its readings, or the
/// minutes of its run) and the set-up it needs, paid once for every chosen test on it and not
/// at all when already made (an instrument already in place).
#[derive(Debug, Clone, PartialEq)]
pub struct Costs {
    /// Per candidate: its own cost.
    pub run: Vec<Real>,
    /// Per candidate: the set-up it needs and that set-up's cost; `None` for none.
    pub setup: Vec<Option<(String, Real)>>,
    /// The set-ups already made.
    pub present: Vec<String>,
    /// The unit, for reports (`readings`, `min`).
    pub unit: &'static str,
}

impl Costs {
    /// Each candidate costs its readings (the rows of its design), with no set-up.
    pub fn readings(candidates: &[(String, DMatrix<Real>)]) -> Costs {
        Costs {
            run: candidates.iter().map(|(_, d)| d.nrows() as Real).collect(),
            setup: vec![None; candidates.len()],
            present: Vec::new(),
            unit: "readings",
        }
    }

    /// What the candidates `set` cost together: their runs, and each set-up they need once
    /// unless already made.
    pub fn of(&self, set: &[usize]) -> Real {
        let mut paid: Vec<&str> = Vec::new();
        let mut total = 0.0;
        for &i in set {
            total += self.run[i];
            if let Some((name, cost)) = &self.setup[i]
                && !self.present.contains(name)
                && !paid.contains(&name.as_str())
            {
                paid.push(name);
                total += cost;
            }
        }
        total
    }
}

/// Chooses tests greedily from `candidates` (name, weighted scaled design with the columns
/// `labels`) on top of `base`, spending at most `budget_readings` readings (criterion in the
/// module documentation).
///
/// # Panics
/// When a design's columns differ from `labels`, or a design holds a non-finite value.
pub fn choose(
    base: Option<&DMatrix<Real>>,
    candidates: &[(String, DMatrix<Real>)],
    labels: &[String],
    budget_readings: usize,
    options: &Options,
) -> Plan {
    let costs = Costs::readings(candidates);
    choose_within(
        base,
        candidates,
        &costs,
        labels,
        budget_readings as Real,
        options,
    )
}

/// [`choose`] with the tests' `costs` (one per candidate) and a `budget` in their unit: the
/// greedy steps take the largest gain per cost on top of what is chosen (a test on a set-up
/// already made costs its run only).
///
/// # Panics
/// When a design's columns differ from `labels`, `costs` has another number of candidates, or
/// a design holds a non-finite value.
pub fn choose_within(
    base: Option<&DMatrix<Real>>,
    candidates: &[(String, DMatrix<Real>)],
    costs: &Costs,
    labels: &[String],
    budget: Real,
    options: &Options,
) -> Plan {
    assert!(
        costs.run.len() == candidates.len() && costs.setup.len() == candidates.len(),
        "plan: {} costs for {} candidates",
        costs.run.len(),
        candidates.len()
    );
    let n = labels.len();
    let p = prior_precision(options);
    let base_design = compress(base.cloned().unwrap_or_else(|| DMatrix::zeros(0, n)));
    assert_eq!(
        base_design.ncols(),
        n,
        "plan: the base design has {} columns for {n} labels",
        base_design.ncols()
    );
    for (name, design) in candidates {
        assert_eq!(
            design.ncols(),
            n,
            "plan: candidate {name} has {} columns for {n} labels",
            design.ncols()
        );
    }
    let base_log_det = log_det(&base_design, p);
    let base_analysis = identifiability::analyse(&base_design, labels, options);
    let mut identifiable_after = base_analysis.all_identifiable().then_some(0);
    let design_of = |set: &[usize]| {
        set.iter().fold(base_design.clone(), |all, &i| {
            compress(stack(&all, &candidates[i].1))
        })
    };
    // Greedy, then exchanges of one test for another while one raises log det M.
    let mut set = greedy(&base_design, candidates, costs, &[], &[], budget, p);
    let greedy_log_det = log_det(&design_of(&set), p);
    let mut current_log_det = greedy_log_det;
    let mut exchanges = Vec::new();
    let shared = costs.setup.iter().any(Option::is_some);
    loop {
        let mut best: Option<(usize, usize, Real)> = None;
        for position in 0..set.len() {
            let mut without = set.clone();
            without.remove(position);
            let rest = design_of(&without);
            for (j, (_, design)) in candidates.iter().enumerate() {
                let rows = design.nrows();
                let cost = costs.of(&[without.as_slice(), &[j]].concat());
                if set.contains(&j) || rows == 0 || cost > budget {
                    continue;
                }
                // With shared set-ups an exchange can free a set-up's time: it is scored with
                // the greedy additions that time allows.
                let value = if shared {
                    let mut trial = without.clone();
                    trial.push(j);
                    let more = greedy(
                        &design_of(&trial),
                        candidates,
                        costs,
                        &trial,
                        &trial,
                        budget,
                        p,
                    );
                    trial.extend(more);
                    log_det(&design_of(&trial), p)
                } else {
                    log_det(&stack(&rest, design), p)
                };
                if value > current_log_det + MIN_EXCHANGE_GAIN
                    && best.is_none_or(|b| value > b.2 + TIE)
                {
                    best = Some((position, j, value));
                }
            }
        }
        let Some((position, j, _)) = best else {
            break;
        };
        let removed = std::mem::replace(&mut set[position], j);
        let more = greedy(&design_of(&set), candidates, costs, &set, &set, budget, p);
        set.extend(more);
        let value = log_det(&design_of(&set), p);
        exchanges.push(Exchange {
            removed: candidates[removed].0.clone(),
            added: candidates[j].0.clone(),
            gain: value - current_log_det,
        });
        current_log_det = value;
    }
    // The final set in greedy order, step by step.
    let others: Vec<usize> = (0..candidates.len()).filter(|i| !set.contains(i)).collect();
    let order = greedy(
        &base_design,
        candidates,
        costs,
        &[],
        &others,
        Real::INFINITY,
        p,
    );
    let mut steps = Vec::new();
    let mut design = base_design.clone();
    for (k, &i) in order.iter().enumerate() {
        design = compress(stack(&design, &candidates[i].1));
        let analysis = identifiability::analyse(&design, labels, options);
        steps.push(Step {
            test: candidates[i].0.clone(),
            readings: candidates[i].1.nrows(),
            cost: costs.of(&order[..=k]) - costs.of(&order[..k]),
            log_det: log_det(&design, p),
            uncertainties: analysis.standard_uncertainty.clone(),
        });
        if identifiable_after.is_none() && analysis.all_identifiable() {
            identifiable_after = Some(steps.len());
        }
    }
    // Every candidate together, whatever the budget: what no budget can identify.
    let every_test = candidates.iter().fold(
        compress(base.cloned().unwrap_or_else(|| DMatrix::zeros(0, n))),
        |all, (_, d)| compress(stack(&all, d)),
    );
    let structural = identifiability::analyse(&every_test, labels, options).null_combinations;
    let every_test_cost = costs.of(&(0..candidates.len()).collect::<Vec<_>>());
    let identifiable = steps
        .last()
        .map_or(base_analysis.all_identifiable(), |s: &Step| {
            s.uncertainties.iter().all(Option::is_some)
        });
    Plan {
        identifiable,
        steps,
        labels: labels.to_vec(),
        prior_precision: p,
        base_log_det,
        identifiable_after,
        base_uncertainties: base_analysis.standard_uncertainty,
        budget,
        unit: costs.unit,
        structural,
        every_test_cost,
        greedy_log_det,
        exchanges,
    }
}

/// The greedy choice (see the module documentation) on top of `base`, which holds the
/// candidates `already` chosen, among the candidates not in `excluded`, with everything chosen
/// costing at most `budget`: the newly chosen candidates in order.
fn greedy(
    base: &DMatrix<Real>,
    candidates: &[(String, DMatrix<Real>)],
    costs: &Costs,
    already: &[usize],
    excluded: &[usize],
    budget: Real,
    p: Real,
) -> Vec<usize> {
    let mut current = base.clone();
    let mut current_log_det = log_det(&current, p);
    let mut chosen = Vec::new();
    loop {
        let spent = costs.of(&[already, &chosen].concat());
        let mut best: Option<(usize, Real, Real, DMatrix<Real>)> = None;
        for (i, (_, design)) in candidates.iter().enumerate() {
            let rows = design.nrows();
            if chosen.contains(&i) || excluded.contains(&i) || rows == 0 {
                continue;
            }
            let total = costs.of(&[already, &chosen, &[i]].concat());
            if total > budget {
                continue;
            }
            let stacked = stack(&current, design);
            let new_log_det = log_det(&stacked, p);
            let gain = new_log_det - current_log_det;
            if gain <= MIN_GAIN {
                continue;
            }
            // Per unit of cost; a test costing nothing more (no run) gains without limit.
            let per_cost = gain / (total - spent);
            if best.as_ref().is_none_or(|b| per_cost > b.1 + TIE) {
                best = Some((i, per_cost, new_log_det, stacked));
            }
        }
        let Some((i, _, new_log_det, stacked)) = best else {
            return chosen;
        };
        chosen.push(i);
        current = compress(stacked);
        current_log_det = new_log_det;
    }
}

/// Three significant figures for the tables (`—` for none).
fn figure(x: Option<Real>) -> String {
    x.map_or_else(|| "—".into(), significant)
}

/// Left-aligned columns, two spaces apart.
pub(crate) fn table(rows: &[Vec<String>]) -> String {
    let columns = rows.iter().map(Vec::len).max().unwrap_or(0);
    let widths: Vec<usize> = (0..columns)
        .map(|c| {
            rows.iter()
                .filter_map(|r| r.get(c))
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut text = String::new();
    for row in rows {
        let mut line = String::new();
        for (c, cell) in row.iter().enumerate() {
            let pad = widths[c] - cell.chars().count();
            let _ = write!(line, "{cell}{}  ", " ".repeat(pad));
        }
        let _ = writeln!(text, "{}", line.trim_end());
    }
    text
}

impl Plan {
    /// The readings the chosen tests spend.
    pub fn readings(&self) -> usize {
        self.steps.iter().map(|s| s.readings).sum()
    }

    /// What the chosen tests cost together ([`Plan::unit`]).
    pub fn spent(&self) -> Real {
        self.steps.iter().map(|s| s.cost).sum()
    }

    /// What stops the plan short of identifying every parameter, if anything.
    pub fn limit(&self) -> Option<Limit> {
        match (self.identifiable, self.structural.is_empty()) {
            (true, _) => None,
            (false, false) => Some(Limit::Structure),
            (false, true) => Some(Limit::Budget),
        }
    }

    /// A text for people: the criterion, the chosen tests in order with `log det` and how many
    /// parameters are identifiable, and the predicted standard uncertainty of each parameter
    /// after each step (`—`: unidentifiable).
    pub fn report(&self) -> String {
        let n = self.labels.len();
        let mut text = String::new();
        let _ = writeln!(
            text,
            "test plan: D-optimal (greedy, then exchanges), log det(JᵀJ + p·I) with p = {} per µm-eq²; {} tests, {} of {} {}",
            figure(Some(self.prior_precision)),
            self.steps.len(),
            crate::math::trimmed(self.spent(), 2),
            crate::math::trimmed(self.budget, 2),
            self.unit
        );
        if self.exchanges.is_empty() {
            let _ = writeln!(
                text,
                "no exchange of a chosen test for another raises log det: the greedy choice stands"
            );
        } else {
            let list: Vec<String> = (self.exchanges.iter())
                .map(|e| format!("{} for {} (+{:.3})", e.added, e.removed, e.gain))
                .collect();
            let _ = writeln!(
                text,
                "exchanges after the greedy pass (log det {:.3} → {:.3}): {}",
                self.greedy_log_det,
                self.steps.last().map_or(self.base_log_det, |s| s.log_det),
                list.join(", ")
            );
        }
        let _ = writeln!(
            text,
            "{}",
            match self.identifiable_after {
                Some(0) => "every parameter is identifiable from the base design".to_string(),
                Some(k) => format!("every parameter identifiable after step {k}"),
                None => match self.limit() {
                    Some(Limit::Structure) => format!(
                        "not every parameter is identifiable with these tests, whatever the budget: no test sees {}",
                        self.structural
                            .iter()
                            .map(|c| c.describe(&self.labels))
                            .collect::<Vec<_>>()
                            .join("; ")
                    ),
                    _ => format!(
                        "not every parameter is identifiable within the budget of {} {unit}; every test together ({} {unit}) would identify them all",
                        crate::math::trimmed(self.budget, 2),
                        crate::math::trimmed(self.every_test_cost, 2),
                        unit = self.unit
                    ),
                },
            }
        );
        // A cost other than readings gets a column of its own.
        let own_unit = self.unit != "readings";
        let mut header = vec!["step".to_string(), "test".into(), "readings".into()];
        if own_unit {
            header.push(self.unit.into());
        }
        header.extend(["log det".into(), "identifiable".into()]);
        let mut rows = vec![header];
        let mut base = vec!["0".into(), "(base)".into(), "".into()];
        if own_unit {
            base.push("".into());
        }
        base.extend([
            format!("{:.3}", self.base_log_det),
            format!(
                "{} of {n}",
                self.base_uncertainties.iter().flatten().count()
            ),
        ]);
        rows.push(base);
        for (k, s) in self.steps.iter().enumerate() {
            let mut row = vec![(k + 1).to_string(), s.test.clone(), s.readings.to_string()];
            if own_unit {
                row.push(crate::math::trimmed(s.cost, 2));
            }
            row.extend([
                format!("{:.3}", s.log_det),
                format!("{} of {n}", s.uncertainties.iter().flatten().count()),
            ]);
            rows.push(row);
        }
        text.push_str(&table(&rows));
        let _ = writeln!(
            text,
            "predicted standard uncertainty (µm-eq) after each step:"
        );
        let mut rows = vec![
            std::iter::once("parameter".to_string())
                .chain((0..=self.steps.len()).map(|k| k.to_string()))
                .collect::<Vec<_>>(),
        ];
        for (j, name) in self.labels.iter().enumerate() {
            rows.push(
                std::iter::once(name.clone())
                    .chain(std::iter::once(figure(self.base_uncertainties[j])))
                    .chain(self.steps.iter().map(|s| figure(s.uncertainties[j])))
                    .collect(),
            );
        }
        text.push_str(&table(&rows));
        text
    }

    /// The plan with stable keys: `criterion` (`"d_optimal_greedy_exchange"`),
    /// `greedy_log_det` and `exchanges` ({`removed`, `added`, `log_det_gain`} each),
    /// `prior_precision_per_um_eq2`, `cost_unit` (`readings` or `min`), `budget` and `spent` in
    /// it, `readings`, `parameters` (names),
    /// `identifiable`, `identifiable_after_steps` (`null` when never), `base_log_det`,
    /// `base_standard_uncertainty_um_eq` (per parameter, `null` when unidentifiable),
    /// `limited_by` (`"structure"`, `"budget"` or `null`: [`Plan::limit`]),
    /// `structural_null_combinations` (what no test sees, as the identifiability report gives
    /// combinations), `every_test_cost`, and `steps`: per chosen test {`test`, `readings`, `cost`,
    /// `log_det`, `identifiable`, `standard_uncertainty_um_eq`}.
    pub fn to_json(&self) -> Value {
        let steps: Vec<Value> = self
            .steps
            .iter()
            .map(|s| {
                json!({
                    "test": s.test,
                    "readings": s.readings,
                    "cost": s.cost,
                    "log_det": s.log_det,
                    "identifiable": s.uncertainties.iter().all(Option::is_some),
                    "standard_uncertainty_um_eq": s.uncertainties,
                })
            })
            .collect();
        json!({
            "criterion": "d_optimal_greedy_exchange",
            "greedy_log_det": self.greedy_log_det,
            "exchanges": self.exchanges.iter().map(|e| json!({
                "removed": e.removed,
                "added": e.added,
                "log_det_gain": e.gain,
            })).collect::<Vec<_>>(),
            "prior_precision_per_um_eq2": self.prior_precision,
            "cost_unit": self.unit,
            "budget": self.budget,
            "spent": self.spent(),
            "readings": self.readings(),
            "parameters": self.labels,
            "identifiable": self.identifiable,
            "identifiable_after_steps": self.identifiable_after,
            "base_log_det": self.base_log_det,
            "base_standard_uncertainty_um_eq": self.base_uncertainties,
            "limited_by": match self.limit() {
                None => Value::Null,
                Some(Limit::Structure) => "structure".into(),
                Some(Limit::Budget) => "budget".into(),
            },
            "structural_null_combinations": self
                .structural
                .iter()
                .map(|c| c.to_json(&self.labels))
                .collect::<Vec<_>>(),
            "every_test_cost": self.every_test_cost,
            "steps": steps,
        })
    }
}
