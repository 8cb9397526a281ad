//! Remedies from candidate tests of every kind, cheapest first
//! (`mtwin::app::identify::candidates`), against what each instrument can see by hand:
//!
//! - A scale error common to X, Y and Z moves the tool tip by s·(x, y, z) about the machine's
//!   zero: a ball-bar's reading `|p − c| − L` becomes `s·L`, a constant its radius nuisance
//!   takes, so no circle in any plane sees it; a laser line along an axis reads `s·(x − x₀)`.
//! - Of two scale errors (X and Y) with Z exact, an XY circle sees only their difference (the
//!   ellipse); a circle in YZ or ZX sees Y's or X's own scale against Z's, so it separates
//!   them, as does a laser line.
//! - Time: each candidate costs the planning figures its kind states, its set-up not counted
//!   when the tables given were measured with it.

use mtwin::app::identify::candidates::{self, Candidate, Setup, Site};
use mtwin::estimate::fit::Problem;
use mtwin::estimate::spec::ParameterSet;
use mtwin::kinds::{ballbar, rtest};
use mtwin::machine::{AxisValues, Machine, Plane};
use mtwin::math::Vector;
use std::path::Path;

fn machine(name: &str) -> Machine {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("models/{name}.urdf"));
    Machine::from_urdf_file(path).unwrap()
}

/// Every linear axis at the middle of its travel.
fn middle(machine: &Machine) -> AxisValues {
    let mut middle = AxisValues::ZERO;
    for info in machine.axes() {
        if let (true, Some((l, u))) = (info.axis.is_linear(), info.limits) {
            middle[info.axis] = (l + u) / 2.0;
        }
    }
    middle
}

const SITE: Site = Site {
    sphere: None,
    rtest_sigma: 0.2e-6,
    free_sphere: false,
};

#[test]
fn a_common_scale_is_seen_by_laser_lines_only() {
    let machine = machine("vmc3");
    let set = ParameterSet::parse("EXX:1,EYY:1,EZZ:1", &machine).unwrap();
    let circles: Vec<_> = [Plane::XY, Plane::YZ, Plane::ZX]
        .into_iter()
        .map(|plane| {
            ballbar::readings::planned(&machine, plane, middle(&machine), 0.150, 72, 0.1e-6)
                .unwrap()
        })
        .collect();
    let problem = Problem::new(&machine, &set, &circles).unwrap();
    let tests = candidates::candidates(&machine, &set, &SITE, &["positioning", "ballbar"]);
    // Three laser lines per axis (the reflector at the tip, 100 mm along each other axis) and a
    // circle per plane.
    assert_eq!(tests.iter().filter(|c| c.kind == "positioning").count(), 9);
    assert_eq!(tests.iter().filter(|c| c.kind == "ballbar").count(), 3);
    let present: Vec<String> = [Plane::XY, Plane::YZ, Plane::ZX]
        .map(|p| candidates::setup_key(Setup::Ballbar(p)))
        .to_vec();
    let found = candidates::remedies(&set, &problem, &tests, &present);
    assert_eq!(found.len(), 1, "{found:?}");
    let remedy = &found[0];
    // The common scale, the three slopes alike.
    let terms: Vec<&str> = remedy.combination.split(['+', '−']).collect();
    assert_eq!(terms.len(), 3, "{}", remedy.combination);
    assert!(!remedy.combination.contains('−'), "{}", remedy.combination);
    // Every laser line sees it and no circle does; each line costs its set-up and its run.
    assert_eq!(remedy.tests.len(), 9, "{:?}", remedy.tests);
    for test in &remedy.tests {
        assert_eq!(test.kind, "positioning", "{test:?}");
        assert_eq!(test.minutes, 60.0, "{test:?}");
    }
    // Tied in time, the smallest uncertainty first.
    let u: Vec<f64> = remedy
        .tests
        .iter()
        .map(|t| t.standard_uncertainty)
        .collect();
    assert!(u.windows(2).all(|w| w[0] <= w[1]), "{u:?}");
    let text = candidates::remedies_text(&found);
    assert!(text.contains("cheapest: laser"), "{text}");
}

#[test]
fn of_two_scales_a_circle_in_another_plane_is_the_cheapest_remedy() {
    let machine = machine("vmc3");
    let set = ParameterSet::parse("EXX:1,EYY:1", &machine).unwrap();
    let xy = ballbar::readings::planned(&machine, Plane::XY, middle(&machine), 0.150, 72, 0.1e-6)
        .unwrap();
    let problem = Problem::new(&machine, &set, std::slice::from_ref(&xy)).unwrap();
    let tests = candidates::candidates(&machine, &set, &SITE, &["positioning", "ballbar"]);
    let present = vec![candidates::setup_key(Setup::Ballbar(Plane::XY))];
    let found = candidates::remedies(&set, &problem, &tests, &present);
    assert_eq!(found.len(), 1, "{found:?}");
    let remedy = &found[0];
    // X's and Y's scale together: the XY circle sees only their difference.
    assert!(!remedy.combination.contains('−'), "{}", remedy.combination);
    let kinds_and_minutes: Vec<(&str, f64)> =
        remedy.tests.iter().map(|t| (t.kind, t.minutes)).collect();
    // The YZ and ZX circles (a set-up of 10 min and a run of 10 each: not the XY circle's),
    // then the laser lines along X and along Y (60 min); a laser along Z sees neither scale.
    assert_eq!(
        &kinds_and_minutes[..2],
        &[("ballbar", 20.0), ("ballbar", 20.0)],
        "{:?}",
        remedy.tests
    );
    assert_eq!(remedy.tests.len(), 2 + 6, "{:?}", remedy.tests);
    assert!(
        remedy.tests[2..]
            .iter()
            .all(|t| t.kind == "positioning" && !t.test.starts_with("laser Z")),
        "{:?}",
        remedy.tests
    );
    let (cheapest, _) = remedy.cheapest_and_best().unwrap();
    assert!(cheapest.test.starts_with("ball-bar"), "{cheapest:?}");
}

/// A planned R-test of the candidate K-tests `names` with the sphere at `sphere`, each zeroed at
/// its start.
fn planned_r_test(machine: &Machine, names: &[&str], sphere: Vector) -> mtwin::estimate::Readings {
    let tests: Vec<_> = (rtest::readings::candidates(machine).into_iter())
        .filter(|t| names.contains(&t.name.as_str()))
        .collect();
    assert_eq!(tests.len(), names.len(), "{names:?}");
    rtest::readings::planned(
        machine,
        &tests,
        sphere,
        rtest::Zero::EachTest,
        rtest::readings::Setup::default(),
    )
    .unwrap()
}

/// The candidates of one kind at one place.
fn of_kind<'a>(tests: &'a [Candidate], kind: &str) -> Vec<&'a Candidate> {
    tests.iter().filter(|c| c.kind == kind).collect()
}

#[test]
fn a_set_up_already_made_is_free_and_changes_the_cheapest_not_what_is_seen() {
    let machine = machine("trunnion5");
    let set = ParameterSet::parse("location", &machine).unwrap();
    let sphere = Vector::new(0.100, 0.0, 0.250);
    // One C turn at A = 0: A's four location errors are unseen, as A stands at its zero, where
    // the location errors of its line move nothing.
    let base = planned_r_test(&machine, &["C turn at A = 0°"], sphere);
    let problem = Problem::new(&machine, &set, std::slice::from_ref(&base)).unwrap();
    let site = Site {
        sphere: Some(sphere),
        ..SITE
    };
    let tests = candidates::candidates(&machine, &set, &site, &["rtest", "spheres"]);
    let (rtests, probes) = (of_kind(&tests, "rtest"), of_kind(&tests, "spheres"));
    assert_eq!(rtests.len(), probes.len());
    assert!(rtests.len() > 4);
    let r_test_set_up = candidates::setup_key(Setup::Rtest(sphere));
    let with = candidates::remedies(&set, &problem, &tests, std::slice::from_ref(&r_test_set_up));
    let without = candidates::remedies(&set, &problem, &tests, &[]);
    let mut unseen: Vec<&str> = with.iter().map(|r| r.combination.as_str()).collect();
    unseen.sort();
    assert_eq!(unseen, ["EB0A", "EC0A", "EY0A", "EZ0A"]);
    for (with, without) in with.iter().zip(&without) {
        // The same tests reveal it, whatever is set up.
        let names = |r: &candidates::Remedy| {
            let mut n: Vec<String> = r.tests.iter().map(|t| t.test.clone()).collect();
            n.sort();
            n
        };
        assert_eq!(names(with), names(without));
        // Hand figures: an R-test of 13 static poses is 13 × 0.25 min once the nest and sphere
        // are in place, 20 min more before; a probing cycle of N positions 5 + N × 0.5 min
        // (N = 13, or 12 for a full turn, whose end is its start).
        let cheapest = &with.tests[0];
        assert_eq!(cheapest.kind, "rtest", "{:?}", with.tests);
        assert_eq!(cheapest.minutes, 3.25);
        let cheapest = &without.tests[0];
        assert_eq!(cheapest.kind, "spheres", "{:?}", without.tests);
        let positions: f64 = (cheapest.test.rsplit('(').next())
            .and_then(|tail| tail.strip_suffix(" positions)"))
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{}", cheapest.test));
        assert!(positions == 12.0 || positions == 13.0, "{}", cheapest.test);
        assert_eq!(cheapest.minutes, 5.0 + 0.5 * positions);
        let r_test = without.tests.iter().find(|t| t.kind == "rtest").unwrap();
        assert_eq!(r_test.minutes, 23.25);
    }
}

#[test]
fn no_instrument_of_the_twin_sees_a_tool_offset_that_never_turns() {
    // trunnion5 turns the workpiece only: the tool's offset is one translation of the tool tip
    // in the machine's frame at every pose. An R-test's zero takes it, a laser's travel and a
    // ball-bar's distance (its centre set where the machine put the tool) difference it away,
    // and a probing cycle measures with its own stylus.
    let machine = machine("trunnion5");
    let set = ParameterSet::parse("location,tool", &machine).unwrap();
    let sphere = Vector::new(0.100, 0.0, 0.250);
    let names = [
        "C turn at A = 0°",
        "C turn at A = -45°",
        "A sweep -60°..60° at C = 0°",
    ];
    let base = planned_r_test(&machine, &names, sphere);
    let problem = Problem::new(&machine, &set, std::slice::from_ref(&base)).unwrap();
    let site = Site {
        sphere: Some(sphere),
        ..SITE
    };
    let every = ["rtest", "spheres", "positioning", "ballbar"];
    let candidates = candidates::candidates(&machine, &set, &site, &every);
    for kind in every {
        assert!(candidates.iter().any(|c| c.kind == kind), "no {kind}");
    }
    let found = candidates::remedies(&set, &problem, &candidates, &[]);
    for tool in ["EXT", "EYT", "EZT"] {
        let remedy = found
            .iter()
            .find(|r| r.combination == tool)
            .unwrap_or_else(|| panic!("{tool} is seen: {found:?}"));
        assert!(remedy.tests.is_empty(), "{tool}: {:?}", remedy.tests);
    }
    let text = candidates::remedies_text(&found);
    assert!(
        text.contains("EZT: no single added test sees it (*)"),
        "{text}"
    );
    assert!(text.contains("a tool-length setter"), "{text}");
}
