//! Candidate tests of every kind `identify` reads, for the remedies of its report and for
//! `plan`: R-tests (K-tests about the sphere), probing cycles on the same sphere at the same
//! rotary positions, laser lines along each linear axis and ball-bar circles in each plane, each
//! as its design on the errors with its own set-up profiled out ([`fit::profiled_design`]) and
//! its time.
//!
//! # Time
//! Each candidate costs its instrument's set-up, unless the tables already given were measured
//! with that set-up (the same sphere where it stood, a laser already aligned along the axis, the
//! bar already in the plane), plus its run. The figures are the planning figures each kind
//! states beside its `planned` function (typical of the instruments as their makers describe
//! them, not measured here): they rank candidates against each other, so a user with other
//! figures reads the ranking accordingly. The cheapest remedy of an unseen combination is then
//! the candidate that makes it identifiable in the least time, the best the one that leaves it
//! the smallest uncertainty.
//!
//! # What each instrument sees
//! What the twin's model of its readings says, with one exception: a probing cycle measures
//! with the probe's stylus, whose offsets are calibrated apart, so it is given no information
//! on the tool's offsets (EXT, EYT, EZT) of the other tables. The instruments differ in what
//! their set-up hides: an R-test reads relative to its zero (a constant in the machine's frame),
//! a probing cycle absolute axis positions of a sphere whose place on the table is unknown
//! (a vector turning with the table), a laser a displacement along its line, a ball-bar a
//! distance (its length a nuisance): so a probing cycle can see what no single R-test does and
//! the reverse (`tests/it/estimate/rotary_components.rs`, `tests/it/estimate/remedies.rs`).
//!
//! # What is left out
//! Instruments the project does not model (an electronic level, a tool-length setter, a
//! laser's angular or straightness optics, diagonal lines) are no candidates, so a combination
//! only they would reveal is reported as seen by no single added test.

use crate::estimate::fit::{self, Problem};
use crate::estimate::spec::ParameterSet;
use crate::estimate::{Readings, ReadingsError};
use crate::kinds::{ballbar, positioning, probe, rtest};
use crate::machine::{Axis, AxisValues, Machine, Plane};
use crate::math::{M_PER_MM, Real, Vector, trimmed};
use nalgebra::DMatrix;

/// A candidate test: its design on the errors and what it takes.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// For people, unique among the candidates: `R-test C turn at A = 0°`.
    pub name: String,
    /// The table kind it would give (`rtest`, `spheres`, `positioning`, `ballbar`).
    pub kind: &'static str,
    /// The set-up it needs ([`setup_key`]): tests sharing one share its time.
    pub setup: String,
    /// Minutes to set that up.
    pub setup_minutes: Real,
    /// Minutes to run it, once set up.
    pub run_minutes: Real,
    /// Its design on the errors (weighted, scaled; the set-up profiled out).
    pub design: DMatrix<Real>,
}

impl Candidate {
    /// Its time (minutes) on top of tables measured with the set-ups `present`.
    pub fn minutes(&self, present: &[String]) -> Real {
        let setup = if present.contains(&self.setup) {
            0.0
        } else {
            self.setup_minutes
        };
        setup + self.run_minutes
    }
}

/// The set-ups a candidate can need, named as the given tables' are ([`setup_key`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Setup {
    /// The R-test's nest in the spindle, its sphere on the table at this point (workpiece
    /// frame, m).
    Rtest(Vector),
    /// A calibration sphere on the table at this point, the touch probe in the spindle.
    Probe(Vector),
    /// The laser's optics aligned along this linear axis.
    Laser(Axis),
    /// The ball-bar's centre cup set for this plane.
    Ballbar(Plane),
}

/// The name of a set-up: what makes two tests share it.
pub fn setup_key(setup: Setup) -> String {
    let mm = |v: Vector| v.to_array().map(|c| trimmed(c / M_PER_MM, 3)).join(" ");
    match setup {
        Setup::Rtest(sphere) => format!("R-test, sphere at {} mm", mm(sphere)),
        Setup::Probe(sphere) => format!("touch probe, sphere at {} mm", mm(sphere)),
        Setup::Laser(axis) => format!("laser along {axis}"),
        Setup::Ballbar(plane) => format!("ball-bar in {plane}"),
    }
}

/// Where the candidates are taken and how well they read.
#[derive(Clone, Copy, Debug)]
pub struct Site {
    /// The sphere of the R-tests and probing cycles (workpiece frame, m); none: no such
    /// candidate.
    pub sphere: Option<Vector>,
    /// Standard uncertainty of an R-test reading (m).
    pub rtest_sigma: Real,
    /// Whether the R-test's sphere position is unknown (no preset at the first pose).
    pub free_sphere: bool,
}

/// The candidate tests of every kind on `machine` for the errors of `set` (see the module
/// documentation). When `set` has component errors of a rotary axis, which one sphere cannot
/// separate, the R-tests and probing cycles are candidates with the sphere 80 mm higher and
/// 60 mm further from the table's centre too (where the machine can reach them): a second
/// height reveals the tilt motions, a second radius the angular one
/// (`tests/it/estimate/rotary_components.rs`). A test the machine cannot follow is left out,
/// and so is a kind not in `kinds` (table kinds, [`super::TABLE_KINDS`]).
pub fn candidates(
    machine: &Machine,
    set: &ParameterSet,
    site: &Site,
    kinds: &[&str],
) -> Vec<Candidate> {
    let mut out = Vec::new();
    let mut add =
        |name: String, kind: &'static str, setup: Setup, minutes: (Real, Real), readings| {
            if !kinds.contains(&kind) {
                return;
            }
            if let Some(mut design) = design(machine, set, readings) {
                // A probing cycle measures with the probe's stylus, whose offsets are calibrated
                // apart (on a ring or a reference sphere): it tells nothing of another tool's.
                if kind == "spheres" {
                    for (j, label) in set.labels.iter().enumerate() {
                        if TOOL_OFFSETS.contains(&label.as_str()) {
                            design.column_mut(j).fill(0.0);
                        }
                    }
                }
                out.push(Candidate {
                    name,
                    kind,
                    setup: setup_key(setup),
                    setup_minutes: minutes.0,
                    run_minutes: minutes.1,
                    design,
                });
            }
        };
    if let Some(sphere) = site.sphere {
        let rotary_components = (set.model.parameters().iter())
            .any(|p| crate::estimate::spec::is_rotary_component(p.name));
        let mut spheres = vec![(sphere, String::new())];
        if rotary_components {
            let up = Vector::new(0.0, 0.0, 0.080);
            spheres.push((sphere + up, " with the sphere 80 mm higher".to_string()));
            let across = Vector::new(sphere.x, sphere.y, 0.0);
            if across.length() > 1e-3 {
                let further = sphere + across.normalize() * 0.060;
                spheres.push((further, " with the sphere 60 mm further out".to_string()));
            }
        }
        let setup = rtest::readings::Setup {
            sigma: site.rtest_sigma,
            free_sphere: site.free_sphere,
            ..Default::default()
        };
        let tests = rtest::readings::candidates(machine);
        for (at, moved) in &spheres {
            for test in tests.iter().filter(|_| kinds.contains(&"rtest")) {
                let readings = rtest::readings::planned(
                    machine,
                    std::slice::from_ref(test),
                    *at,
                    rtest::Zero::EachTest,
                    setup,
                );
                let minutes = (
                    rtest::readings::PLANNED_SETUP_MINUTES,
                    rtest::readings::PLANNED_MINUTES_PER_POSE * test.pose_count() as Real,
                );
                let name = format!("R-test {}{moved}", test.name);
                add(name, "rtest", Setup::Rtest(*at), minutes, readings);
            }
            for test in tests.iter().filter(|_| kinds.contains(&"spheres")) {
                let poses = test.pose_count();
                let mut positions: Vec<AxisValues> = (0..poses)
                    .map(|k| test.angles_at(machine, k as Real / (poses - 1) as Real))
                    .collect();
                // A full turn's last pose is its first: an R-test reads it again to close the
                // circle, a probing cycle does not probe it twice.
                let same = |a: &AxisValues, b: &AxisValues| {
                    machine.rotary_axes().all(|info| {
                        let turns = (a[info.axis] - b[info.axis]) / std::f64::consts::TAU;
                        (turns - turns.round()).abs() < 1e-12
                    })
                };
                if positions.len() > 1 && same(&positions[0], &positions[positions.len() - 1]) {
                    positions.pop();
                }
                let count = positions.len();
                let readings = probe::readings::planned(
                    machine,
                    &positions,
                    *at,
                    probe::readings::DEFAULT_SIGMA,
                );
                let minutes = (
                    probe::readings::PLANNED_SETUP_MINUTES,
                    probe::readings::PLANNED_MINUTES_PER_POSITION * count as Real,
                );
                let name = format!("probing {}{moved} ({count} positions)", test.name);
                add(name, "spheres", Setup::Probe(*at), minutes, readings);
            }
        }
    }
    let middle = middle_of_travel(machine);
    let linear: Vec<Axis> = [Axis::X, Axis::Y, Axis::Z]
        .into_iter()
        .filter(|&a| machine.has_axis(a))
        .collect();
    for &axis in linear.iter().filter(|_| kinds.contains(&"positioning")) {
        let Some((lower, upper)) = machine.axis(axis).and_then(|info| info.limits) else {
            continue;
        };
        // Eleven targets over the travel less 5 % at each end, five bidirectional runs.
        let margin = 0.05 * (upper - lower);
        let targets: Vec<Real> = (0..11)
            .map(|k| lower + margin + (upper - lower - 2.0 * margin) * k as Real / 10.0)
            .collect();
        let mut offsets = vec![(Vector::ZERO, "at the tool tip".to_string())];
        for other in linear.iter().filter(|&&o| o != axis) {
            offsets.push((
                other.unit() * LASER_OFFSET,
                format!("{} mm along {other}", trimmed(LASER_OFFSET / M_PER_MM, 3)),
            ));
        }
        for (offset, said) in offsets {
            let readings = positioning::readings::planned(
                machine,
                axis,
                &targets,
                5,
                &middle,
                offset,
                positioning::readings::DEFAULT_SIGMA,
            );
            let minutes = (
                positioning::readings::PLANNED_SETUP_MINUTES,
                positioning::readings::PLANNED_RUN_MINUTES,
            );
            let name = format!("laser {axis} line, reflector {said}");
            add(name, "positioning", Setup::Laser(axis), minutes, readings);
        }
    }
    for plane in [Plane::XY, Plane::YZ, Plane::ZX]
        .into_iter()
        .filter(|_| kinds.contains(&"ballbar"))
    {
        let (p, q) = (plane.first(), plane.second());
        let half = |a: Axis| {
            machine
                .axis(a)
                .and_then(|info| info.limits)
                .map(|(l, u)| (u - l) / 2.0)
        };
        let (Some(hp), Some(hq)) = (half(p), half(q)) else {
            continue;
        };
        // The longest of the usual bars (150, 100, 50 mm) the travel holds with 10 mm to spare.
        let Some(radius) = [0.150, 0.100, 0.050]
            .into_iter()
            .find(|&r| r + 0.010 <= hp.min(hq))
        else {
            continue;
        };
        let readings = ballbar::readings::planned(
            machine,
            plane,
            middle,
            radius,
            72,
            ballbar::readings::DEFAULT_SIGMA,
        );
        let minutes = (
            ballbar::readings::PLANNED_SETUP_MINUTES,
            ballbar::readings::PLANNED_RUN_MINUTES,
        );
        let name = format!(
            "ball-bar {plane} circle, {} mm",
            trimmed(radius / M_PER_MM, 3)
        );
        add(name, "ballbar", Setup::Ballbar(plane), minutes, readings);
    }
    out
}

/// The tool's offsets ([`crate::estimate::spec`]'s `tool` preset), which a probing cycle
/// does not see: its stylus is its own tool.
const TOOL_OFFSETS: [&str; 3] = ["EXT", "EYT", "EZT"];

/// The reflector's offset from the tool tip on the offset laser lines (m): 100 mm, about where
/// a reflector clamped to the spindle nose sits (the Abbe offset that makes a line see its
/// axis's angular errors).
pub const LASER_OFFSET: Real = 0.100;

/// Every linear axis at the middle of its travel, the rotary axes at 0.
fn middle_of_travel(machine: &Machine) -> AxisValues {
    let mut middle = AxisValues::ZERO;
    for info in machine.axes() {
        if info.axis.is_linear()
            && let Some((lower, upper)) = info.limits
        {
            middle[info.axis] = (lower + upper) / 2.0;
        }
    }
    middle
}

/// The design of `readings` on the errors of `set`, its set-up profiled out; `None` when the
/// test cannot be planned (the machine cannot follow it) or its problem cannot be made.
fn design(
    machine: &Machine,
    set: &ParameterSet,
    readings: Result<Readings, ReadingsError>,
) -> Option<DMatrix<Real>> {
    let sets = [readings.ok()?];
    let problem = Problem::new(machine, set, &sets).ok()?;
    Some(fit::profiled_design(&problem))
}

/// For each combination the tables cannot see (on the errors, the set-up profiled out), the
/// candidates that would make it identifiable, each with its time on top of the set-ups
/// `present` (minutes) and the uncertainty the combination would then have (µm-eq), cheapest
/// first (ties: the smaller uncertainty first).
pub fn remedies(
    set: &ParameterSet,
    problem: &Problem<'_>,
    candidates: &[Candidate],
    present: &[String],
) -> Vec<Remedy> {
    let options = crate::estimate::identifiability::Options::default();
    let base = fit::profiled_design(problem);
    let report = crate::estimate::identifiability::analyse(&base, &set.labels, &options);
    if report.null_combinations.is_empty() {
        return Vec::new();
    }
    let designs: Vec<(String, DMatrix<Real>)> = candidates
        .iter()
        .map(|c| (c.name.clone(), c.design.clone()))
        .collect();
    let found = crate::estimate::identifiability::remedies(
        &base,
        &report.null_combinations,
        &designs,
        &options,
    );
    report
        .null_combinations
        .iter()
        .zip(found)
        .map(|(combination, tests)| {
            let mut tests: Vec<RemedyTest> = tests
                .into_iter()
                .map(|(name, u)| {
                    let candidate = candidates
                        .iter()
                        .find(|c| c.name == name)
                        .expect("a remedy is one of the candidates");
                    RemedyTest {
                        test: name,
                        kind: candidate.kind,
                        minutes: candidate.minutes(present),
                        standard_uncertainty: u,
                    }
                })
                .collect();
            tests.sort_by(|a, b| {
                a.minutes
                    .total_cmp(&b.minutes)
                    .then(a.standard_uncertainty.total_cmp(&b.standard_uncertainty))
            });
            Remedy {
                combination: combination.describe(&set.labels),
                tests,
            }
        })
        .collect()
}

/// What would make one unseen combination identifiable.
#[derive(Clone, Debug, PartialEq)]
pub struct Remedy {
    /// The combination, as the report describes it (`EA0A − EA0C`).
    pub combination: String,
    /// The single added tests that would, cheapest first.
    pub tests: Vec<RemedyTest>,
}

/// One added test that would make a combination identifiable.
#[derive(Clone, Debug, PartialEq)]
pub struct RemedyTest {
    /// The candidate's name.
    pub test: String,
    /// Its table kind.
    pub kind: &'static str,
    /// Its time on top of the tables given (minutes).
    pub minutes: Real,
    /// The combination's standard uncertainty then (µm-eq, largest coefficient 1).
    pub standard_uncertainty: Real,
}

impl Remedy {
    /// The cheapest test, and the one leaving the smallest uncertainty when another.
    pub fn cheapest_and_best(&self) -> Option<(&RemedyTest, Option<&RemedyTest>)> {
        let cheapest = self.tests.first()?;
        let best = self
            .tests
            .iter()
            .min_by(|a, b| a.standard_uncertainty.total_cmp(&b.standard_uncertainty))
            .filter(|b| b.test != cheapest.test);
        Some((cheapest, best))
    }

    /// For `estimate.json`.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "combination": self.combination,
            "tests": self.tests.iter().map(|t| serde_json::json!({
                "test": t.test,
                "kind": t.kind,
                "minutes": t.minutes,
                "standard_uncertainty_um": t.standard_uncertainty,
            })).collect::<Vec<_>>(),
        })
    }
}

/// The remedies for people.
pub fn remedies_text(remedies: &[Remedy]) -> String {
    if remedies.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "what would make the unseen combinations identifiable (one more test; minutes are planning figures, set-ups already made are free):\n",
    );
    let minutes = |t: &RemedyTest| trimmed(t.minutes, 2);
    let mut unseen = false;
    for remedy in remedies {
        let name = &remedy.combination;
        match remedy.cheapest_and_best() {
            Some((cheapest, best)) => {
                out += &format!(
                    "  {name}: cheapest: {} ({} min, then u = {:.3} µm-eq)",
                    cheapest.test,
                    minutes(cheapest),
                    cheapest.standard_uncertainty
                );
                if let Some(best) = best {
                    out += &format!(
                        "; best: {} ({} min, u = {:.3})",
                        best.test,
                        minutes(best),
                        best.standard_uncertainty
                    );
                }
                out += "\n";
            }
            None => {
                unseen = true;
                out += &format!("  {name}: no single added test sees it (*)\n");
            }
        }
    }
    if unseen {
        out += "  (*) it needs several tests (e.g. a second sphere height and a second radius for a rotary axis's component errors), or an instrument the twin does not model (a level, a tool-length setter, a laser's angular optics)\n";
    }
    out
}
