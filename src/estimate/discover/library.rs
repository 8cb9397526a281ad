//! The library of terms model selection may add to a kinematic calibration ([`Term`]): each
//! with its `--params` items, the columns it brings, and its name for people.

use crate::errors::{Motion, ParameterName};
use crate::estimate::spec::{DEFAULT_ORDER, ParameterSet};
use crate::machine::{Axis, Machine};

/// A term of the library.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Term {
    /// One Fourier order of one component error of a rotary axis: orders 2 and up of each,
    /// and order 1 of the axial (`EZC`) and angular positioning (`ECC`) ones.
    Order {
        /// The component error (`EXC`).
        name: ParameterName,
        /// Cycles per turn.
        order: usize,
    },
    /// Order 1 of a rotary axis's radial pair (`EXC`, `EYC`) or tilt pair (`EAC`, `EBC`):
    /// the part turning against the axis, which no location error gives (the part turning
    /// with it is the axis line's offset or tilt, [`crate::estimate::spec`]).
    FirstOrder {
        /// The rotary axis.
        axis: Axis,
        /// The tilt pair rather than the radial one.
        tilt: bool,
    },
    /// The lost motion of an axis (a reversal term in its positioning error).
    Reversal(Axis),
    /// A squareness error (`EC0Y`).
    Squareness(ParameterName),
    /// The pivot drifting at one rate through each R-test table
    /// ([`crate::kinds::rtest::readings::Drift::Rate`]).
    Drift,
}

/// The suffix of a drift rate's nuisance names (`drift_per_h.x`).
pub const DRIFT_NUISANCE: &str = "drift_per_h.";

/// The two motions across rotary `axis` (the radial pair, or with `tilt` the tilt pair), in
/// the order of the right-handed frame (for C: X, Y).
fn across(axis: Axis, tilt: bool) -> [Motion; 2] {
    let first = if tilt { 3 } else { 0 };
    let motion = |k: usize| Motion::ALL[first + (axis.coordinate() + k) % 3];
    [motion(1), motion(2)]
}

/// The component error `motion` of `axis`.
fn component(motion: Motion, axis: Axis) -> ParameterName {
    ParameterName::Component { motion, axis }
}

impl Term {
    /// Its `--params` items.
    pub fn spec_items(self) -> Vec<String> {
        match self {
            Term::Order { name, order } => vec![format!("{name}.harmonic[{order}]")],
            Term::FirstOrder { axis, tilt } => across(axis, tilt)
                .iter()
                .map(|&m| format!("{}.harmonic[1]", component(m, axis)))
                .collect(),
            Term::Reversal(axis) => vec![format!(
                "{}.reversal",
                ParameterName::positioning(axis).expect("a machine axis")
            )],
            Term::Squareness(name) => vec![name.to_string()],
            Term::Drift => Vec::new(),
        }
    }

    /// The labels of its unknowns in a [`ParameterSet`] that has it (the drift's are
    /// nuisances: [`DRIFT_NUISANCE`]).
    pub fn labels(self) -> Vec<String> {
        match self {
            Term::Order { name, order } => ["sin", "cos"]
                .map(|part| format!("{name}.harmonic[{order}].{part}"))
                .to_vec(),
            Term::FirstOrder { axis, tilt } => across(axis, tilt)
                .iter()
                .map(|&m| format!("{}.harmonic[1].cos", component(m, axis)))
                .collect(),
            Term::Reversal(_) | Term::Squareness(_) => self.spec_items(),
            Term::Drift => Vec::new(),
        }
    }

    /// Its short name (`EXC.harmonic[2]`, `EXC+EYC.harmonic[1]`, `ECC.reversal`, `EC0Y`,
    /// `drift_rate`).
    pub fn id(self) -> String {
        match self {
            Term::FirstOrder { axis, tilt } => {
                let [u, v] = across(axis, tilt);
                format!("{}+{}.harmonic[1]", component(u, axis), component(v, axis))
            }
            Term::Drift => "drift_rate".into(),
            _ => self.spec_items().join(","),
        }
    }

    /// What it is in ISO 230-1's words, for people.
    pub fn cause(self) -> String {
        let per_turn = |order: usize| match order {
            1 => "once per turn".to_string(),
            k => format!("{k} times per turn"),
        };
        match self {
            Term::Order { name, order } => {
                let axis = name.axis().expect("a component error has an axis");
                let motion = name.motion();
                let what = if motion.index() == axis.coordinate() + 3 {
                    "angular positioning error".to_string()
                } else if motion.index() == axis.coordinate() {
                    "axial error motion".to_string()
                } else if motion.is_translation() {
                    format!("radial error motion along {}", Axis::ALL[motion.index()])
                } else {
                    format!("tilt error motion about {}", Axis::ALL[motion.index() - 3])
                };
                format!("{axis}'s {what}, {}", per_turn(order))
            }
            Term::FirstOrder { axis, tilt } => format!(
                "{axis}'s {} error motion once per turn against the turn (not the axis line's {})",
                if tilt { "tilt" } else { "radial" },
                if tilt { "tilt" } else { "offset" }
            ),
            Term::Reversal(axis) => format!("{axis}'s lost motion (reversal)"),
            Term::Squareness(name) => format!("squareness {name}"),
            Term::Drift => {
                "the R-test pivot drifting in time, at one rate through each table".into()
            }
        }
    }
}

/// Every term of the library for `machine` that `base` does not hold yet: per rotary axis,
/// its component errors order by order up to [`DEFAULT_ORDER`] (order 1 of the radial and
/// tilt pairs as the part turning against the axis, and not when `base` has one of the pair's
/// order 1 alone) and its lost motion; the lost motion of each linear axis; the squareness
/// errors the axes allow; and with `drift`, the pivot's drift rate.
pub fn library(machine: &Machine, base: &ParameterSet, drift: bool) -> Vec<Term> {
    let has = |label: &str| base.labels.iter().any(|l| l == label);
    let mut terms = Vec::new();
    for info in machine.rotary_axes() {
        let axis = info.axis;
        for tilt in [false, true] {
            let pair = across(axis, tilt);
            let any_first = pair.iter().any(|&m| {
                ["sin", "cos"]
                    .iter()
                    .any(|p| has(&format!("{}.harmonic[1].{p}", component(m, axis))))
            });
            if !any_first {
                terms.push(Term::FirstOrder { axis, tilt });
            }
        }
        for motion in Motion::ALL {
            let along = motion.index() % 3 == axis.coordinate();
            let first = if along { 1 } else { 2 };
            for order in first..=DEFAULT_ORDER {
                terms.push(Term::Order {
                    name: component(motion, axis),
                    order,
                });
            }
        }
        terms.push(Term::Reversal(axis));
    }
    for axis in [Axis::X, Axis::Y, Axis::Z] {
        if machine.has_axis(axis) {
            terms.push(Term::Reversal(axis));
        }
    }
    for (name, axis) in [("EC0Y", Axis::Y), ("EB0Z", Axis::Z), ("EA0Z", Axis::Z)] {
        if machine.has_axis(axis) {
            terms.push(Term::Squareness(name.parse().expect("a valid name")));
        }
    }
    terms.retain(|t| t.labels().is_empty() || !t.labels().iter().all(|l| has(l)));
    if drift {
        terms.push(Term::Drift);
    }
    terms
}
