//! Which error parameters to estimate: `--params SPEC`, in ISO names or presets.
//!
//! A SPEC is a comma-separated list of items:
//!
//! | item | parameters |
//! |---|---|
//! | `location` | the position and orientation of every rotary axis line (`EX0C`, `EY0C`, `EA0C`, `EB0C`; `EY0A`, `EZ0A`, `EB0A`, `EC0A`; …): four per axis |
//! | `zero` | the zero-position errors of the rotary axes (`EC0C`, `EA0A`, `EB0B`) |
//! | `squareness` | `EC0Y`, `EB0Z`, `EA0Z` (those the machine's axes allow) |
//! | `tool` | `EXT`, `EYT`, `EZT` |
//! | `linear21` or `linear21:N` | the 18 component errors of the linear axes as polynomials of degree N (default 3) plus the 3 squareness errors |
//! | `EX0C`, `EC0Y`, … | one location, squareness or tool error (a constant) |
//! | `EXX`, `EXX:N` | one component error, a polynomial of degree N (default 3) |
//! | `reversal` | the lost motion of every linear axis: a reversal term in `EXX`, `EYY`, `EZZ` |
//! | `EXX.reversal`, `ECC.reversal` | the lost motion of one axis (linear or rotary) |
//! | `EXC`, `EXC:N` (a rotary axis's component error) | a Fourier series in the angle, orders 1 to N (default 3) |
//! | `EXC.harmonic[2]` | one Fourier order of a rotary axis's component error (joins `EXC:N` when both are given; `EXC.harmonic[1]` with `EYC.harmonic[1]` is the order-1 pair below) |
//! | `rotary_components`, `rotary_components:C`, `rotary_components:C:N`, `rotary_components:N` | the six component errors of every rotary axis (or of one), each a Fourier series of orders 1 to N (default 3) |
//!
//! A reversal term is the error model's [`ErrorFunction::Reversal`]: the axis lags the command
//! by half the lost motion against its direction of travel, so the readings of the two
//! directions differ by the lost motion (ISO 230-2's reversal value B of a positioning test,
//! less its scatter). It is added to the axis's positioning error beside the polynomial asked
//! for (`EXX:3,reversal`), or alone. Only tables that travel both ways see it: a positioning
//! test's two approaches, a ball-bar's two senses.
//!
//! Component errors are estimated **without their constant term**: a component error is taken
//! as zero at the axis zero, as the laser and ball-bar see it (a constant error motion of a
//! linear axis is a translation of the whole working volume that no relative measurement sees,
//! and it would only add null directions to the report). Straightness errors are estimated
//! **without their linear term** too: ISO 230-1 measures straightness from a reference line,
//! and the reference lines' slopes are the squareness errors. Their coefficients are scaled for the
//! solver and the identifiability report so that one unit is 1 µm (or, for angular errors,
//! the rotation moving a point at [`REFERENCE_LENGTH`] by 1 µm) at the end of
//! the axis travel.

use crate::errors::{ErrorFunction, ErrorModel, ErrorParameter, ParameterName};
use crate::machine::{Axis, Machine};
use crate::math::Real;

/// The lever arm that puts rotations and translations on one scale in the solver and in the
/// identifiability report: a rotation counts as the motion it gives a point this far away,
/// so 1 µrad counts as 0.1 µm (the distance of an R-test sphere or a probed artefact from the axes, in the literature's
/// studies; wave2-anchors §1.3).
pub const REFERENCE_LENGTH: Real = 0.1;

/// Default polynomial degree of a component error.
pub const DEFAULT_DEGREE: usize = 3;

/// Default highest Fourier order of a rotary axis's component error.
pub const DEFAULT_ORDER: usize = 3;

/// The parameters to estimate, bound to a machine: a template error model (every coefficient
/// zero), which of its coefficients are free, and their scales.
#[derive(Clone, Debug)]
pub struct ParameterSet {
    /// The template: the estimated parameters, every coefficient zero.
    pub model: ErrorModel,
    /// Indices (into [`ErrorModel::coefficients`]) of the free coefficients.
    pub free: Vec<usize>,
    /// One label per free coefficient: `EX0C`, `EXX.polynomial[2]`.
    pub labels: Vec<String>,
    /// SI per solver unit of each free coefficient: 1 µm, or the rotation moving a point at
    /// [`REFERENCE_LENGTH`] by 1 µm, and for a polynomial coefficient that much at the end of
    /// the travel.
    pub scales: Vec<Real>,
    /// Whether each free coefficient is a rotation (µrad in files) rather than a translation.
    pub rotation: Vec<bool>,
    /// The parameter (index into [`ErrorModel::parameters`]) each free coefficient belongs to.
    pub owner: Vec<usize>,
    /// The polynomial degree of each free coefficient (0 for a constant), or its Fourier
    /// order (a rotary axis's component error).
    pub degree: Vec<usize>,
    /// Further coefficients each free coefficient sets, besides its own (the order-1 radial
    /// and tilt terms of a rotary axis, see the module doc).
    pub tied: Vec<Vec<Tie>>,
}

/// A coefficient that a free coefficient also sets: `factor` × its value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tie {
    /// Index into [`ErrorModel::coefficients`].
    pub coefficient: usize,
    /// The factor (±1).
    pub factor: Real,
    /// The parameter (index into [`ErrorModel::parameters`]) the coefficient belongs to.
    pub owner: usize,
}

/// Why a SPEC cannot be used with a machine.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("--params {spec}: {message}")]
pub struct SpecError {
    /// The SPEC as given.
    pub spec: String,
    /// What is wrong.
    pub message: String,
}

impl ParameterSet {
    /// Parses `spec` for `machine`.
    pub fn parse(spec: &str, machine: &Machine) -> Result<ParameterSet, SpecError> {
        let fail = |message: String| SpecError {
            spec: spec.to_string(),
            message,
        };
        let mut wanted: Vec<(ParameterName, Option<usize>)> = Vec::new();
        let mut reversals: Vec<ParameterName> = Vec::new();
        let mut reversal = |name: ParameterName| {
            if !reversals.contains(&name) {
                reversals.push(name);
            }
        };
        let mut twice: Option<ParameterName> = None;
        let mut push = |name: ParameterName, degree: Option<usize>| match wanted
            .iter()
            .find(|(n, _)| *n == name)
        {
            None => wanted.push((name, degree)),
            Some((_, d)) if *d != degree => twice = Some(name),
            Some(_) => {}
        };
        let rotary: Vec<Axis> = machine.rotary_axes().map(|i| i.axis).collect();
        let linear: Vec<Axis> = [Axis::X, Axis::Y, Axis::Z]
            .into_iter()
            .filter(|a| machine.has_axis(*a))
            .collect();
        let squareness = || {
            [("EC0Y", Axis::Y), ("EB0Z", Axis::Z), ("EA0Z", Axis::Z)]
                .into_iter()
                .filter(|(_, a)| machine.has_axis(*a))
                .map(|(n, _)| n.parse::<ParameterName>().expect("a valid name"))
                .collect::<Vec<_>>()
        };
        // Single Fourier orders asked for by name (`EXC.harmonic[2]`), beside the series.
        let mut harmonics: Vec<(ParameterName, usize)> = Vec::new();
        for item in spec.split(',').map(str::trim) {
            if let Some((head, order)) = harmonic_item(item) {
                let (name, order) = harmonic_name(head, order, machine)
                    .map_err(|m| fail(format!("\"{item}\": {m}")))?;
                if !harmonics.contains(&(name, order)) {
                    harmonics.push((name, order));
                }
                continue;
            }
            if let Some(rest) = item.strip_prefix("rotary_components")
                && (rest.is_empty() || rest.starts_with(':'))
            {
                let (axes, order) = rotary_components(rest, &rotary, machine)
                    .map_err(|m| fail(format!("\"{item}\": {m}")))?;
                for axis in axes {
                    for motion in "XYZABC".chars() {
                        let name = format!("E{motion}{axis}").parse().expect("a valid name");
                        push(name, Some(order));
                    }
                }
                continue;
            }
            let (head, degree) = match item.split_once(':') {
                Some((head, degree)) => {
                    let degree: usize = degree.trim().parse().map_err(|_| {
                        fail(format!(
                            "\"{item}\": the degree after ':' must be a whole number from 1 to 9"
                        ))
                    })?;
                    if !(1..=9).contains(&degree) {
                        return Err(fail(format!(
                            "\"{item}\": the degree after ':' must be from 1 to 9"
                        )));
                    }
                    (head.trim(), Some(degree))
                }
                None => (item, None),
            };
            let straightness_degree = |name: &str, degree: Option<usize>| match degree {
                Some(1) => Err(fail(format!(
                    "\"{name}:1\": a straightness error starts at degree 2 (its linear term is the squareness error); give 2 or more"
                ))),
                _ => Ok(()),
            };
            if degree.is_some() && ["location", "zero", "squareness", "tool"].contains(&head) {
                return Err(fail(format!(
                    "\"{item}\": {head} errors are constants; a degree is for component errors (EXX:3, linear21:3)"
                )));
            }
            if degree.is_some() && (head == "reversal" || head.ends_with(".reversal")) {
                return Err(fail(format!(
                    "\"{item}\": a lost motion is one number per axis; a degree is for component errors (EXX:3)"
                )));
            }
            match head {
                "" => {
                    return Err(fail(
                        "an empty item; expected names or presets separated by commas".into(),
                    ));
                }
                "location" | "zero" => {
                    if rotary.is_empty() {
                        return Err(fail(format!(
                            "\"{head}\": machine \"{}\" has no rotary axis",
                            machine.name()
                        )));
                    }
                    for axis in &rotary {
                        for name in ParameterName::all() {
                            if let ParameterName::Location { motion, axis: a } = name
                                && a == *axis
                            {
                                let zero = motion.index() == axis.coordinate() + 3;
                                if zero == (head == "zero") {
                                    push(name, None);
                                }
                            }
                        }
                    }
                }
                "reversal" => {
                    if linear.is_empty() {
                        return Err(fail(format!(
                            "\"reversal\": machine \"{}\" has no linear axis (give ECC.reversal, …)",
                            machine.name()
                        )));
                    }
                    for &axis in &linear {
                        reversal(ParameterName::positioning(axis).expect("a linear axis"));
                    }
                }
                text if text.ends_with(".reversal") => {
                    let base = text.trim_end_matches(".reversal");
                    let name: ParameterName = base
                        .parse()
                        .map_err(|m: String| fail(format!("\"{text}\": {m}")))?;
                    let positioning = name
                        .axis()
                        .filter(|&axis| ParameterName::positioning(axis) == Some(name));
                    let Some(axis) = positioning else {
                        return Err(fail(format!(
                            "\"{text}\": a lost motion belongs to an axis's positioning error (EXX, EYY, EZZ, EAA, EBB, ECC)"
                        )));
                    };
                    if !machine.has_axis(axis) {
                        return Err(fail(format!(
                            "{name}: machine \"{}\" has no axis {axis}",
                            machine.name()
                        )));
                    }
                    reversal(name);
                }
                "squareness" => squareness().into_iter().for_each(|n| push(n, None)),
                "tool" => ["EXT", "EYT", "EZT"]
                    .into_iter()
                    .for_each(|n| push(n.parse().expect("a valid name"), None)),
                "linear21" => {
                    straightness_degree("linear21", degree)?;
                    if linear.len() < 3 {
                        return Err(fail(format!(
                            "\"linear21\": machine \"{}\" does not have the three linear axes X, Y, Z",
                            machine.name()
                        )));
                    }
                    for axis in &linear {
                        for motion in "XYZABC".chars() {
                            let name = format!("E{motion}{axis}").parse().expect("a valid name");
                            push(name, Some(degree.unwrap_or(DEFAULT_DEGREE)));
                        }
                    }
                    squareness().into_iter().for_each(|n| push(n, None));
                }
                text => {
                    let name: ParameterName = text.parse().map_err(|m: String| {
                        fail(format!(
                            "\"{text}\": {m}; or a preset: location, zero, squareness, tool, linear21, reversal, rotary_components"
                        ))
                    })?;
                    if let Some(axis) = name.axis().filter(|a| !machine.has_axis(*a)) {
                        return Err(fail(format!(
                            "{name}: machine \"{}\" has no axis {axis}",
                            machine.name()
                        )));
                    }
                    let component = matches!(name, ParameterName::Component { .. });
                    if degree.is_some() && !component {
                        return Err(fail(format!(
                            "{name}: location, squareness and tool errors are constants; a degree is for component errors (EXX:3)"
                        )));
                    }
                    if component && name.axis() == Some(Axis::S) {
                        return Err(fail(format!(
                            "{name}: the spindle's error motions are not calibration parameters (measure them with `analyze spindle`)"
                        )));
                    }
                    if first_degree(name) == 2 {
                        straightness_degree(text, degree)?;
                    }
                    let default = if is_rotary_component(name) {
                        DEFAULT_ORDER
                    } else {
                        DEFAULT_DEGREE
                    };
                    push(name, component.then(|| degree.unwrap_or(default)));
                }
            }
        }
        if let Some(name) = twice {
            return Err(fail(format!(
                "{name} is asked for twice with different degrees"
            )));
        }
        // A single order joins its component's series when that is asked for too, and makes
        // a series of its own otherwise (orders 0 to 0 and the single ones).
        for (name, _) in &harmonics {
            if !wanted.iter().any(|(n, _)| n == name) {
                wanted.push((*name, Some(0)));
            }
        }
        // A lost motion joins the axis's positioning error when that is asked for too, and is
        // its only term otherwise (after the others, in the order asked).
        for name in &reversals {
            if !wanted.iter().any(|(n, _)| n == name) {
                wanted.push((*name, None));
            }
        }
        let parameters = wanted
            .iter()
            .map(|(name, degree)| {
                let polynomial = |d: usize| ErrorFunction::Polynomial(vec![0.0; d + 1]);
                let function = match (degree, reversals.contains(name)) {
                    (Some(n), reversal) if is_rotary_component(*name) => {
                        let mut orders: Vec<usize> = (1..=*n).collect();
                        orders.extend(harmonics.iter().filter(|(h, _)| h == name).map(|(_, k)| *k));
                        orders.sort_unstable();
                        orders.dedup();
                        let mut terms = fourier_series(&orders);
                        if reversal {
                            terms.push(ErrorFunction::Reversal(0.0));
                        }
                        ErrorFunction::Sum(terms)
                    }
                    (Some(d), false) => polynomial(*d),
                    (Some(d), true) => {
                        ErrorFunction::Sum(vec![polynomial(*d), ErrorFunction::Reversal(0.0)])
                    }
                    (None, false) => ErrorFunction::Constant(0.0),
                    (None, true) => ErrorFunction::Reversal(0.0),
                };
                ErrorParameter {
                    name: *name,
                    function,
                }
            })
            .collect();
        let model = ErrorModel::new(machine, parameters).map_err(|e| fail(e.to_string()))?;
        Ok(ParameterSet::from_model(model, machine))
    }

    /// The free coefficients of a template `model` (polynomials without their constant term).
    fn from_model(model: ErrorModel, machine: &Machine) -> ParameterSet {
        let mut set = ParameterSet {
            model,
            free: Vec::new(),
            labels: Vec::new(),
            scales: Vec::new(),
            rotation: Vec::new(),
            owner: Vec::new(),
            degree: Vec::new(),
            tied: Vec::new(),
        };
        let mut index = 0;
        let parameters = set.model.parameters().to_vec();
        for (owner, parameter) in parameters.iter().enumerate() {
            let terms = match &parameter.function {
                ErrorFunction::Sum(terms) => terms.as_slice(),
                single => std::slice::from_ref(single),
            };
            for term in terms {
                index += set.push_term(term, parameter.name, owner, index, machine);
            }
        }
        set.tie_first_orders(machine);
        set
    }

    /// Keeps, of each order-1 radial and tilt pair of a rotary axis, only the part turning
    /// against the axis (see the module doc): `E_u.harmonic[1].cos` (Re N) also sets
    /// `E_v.harmonic[1].sin` to −s·Re N, `E_v.harmonic[1].cos` (Im N) sets `E_u.harmonic[1].sin`
    /// to s·Im N, with s = ±1 the joint's sense about its ISO direction; the two sines leave
    /// the unknowns.
    fn tie_first_orders(&mut self, machine: &Machine) {
        for info in machine.rotary_axes() {
            let along = info.joint_axis.dot(info.axis.unit());
            if (along.abs() - 1.0).abs() > 1e-9 {
                continue;
            }
            let sense = along.signum();
            let across = |first: usize, k: usize| {
                "XYZABC".as_bytes()[first + (info.axis.coordinate() + k) % 3] as char
            };
            for first in [0, 3] {
                let find = |motion: char, part: &str| {
                    let label = format!("E{motion}{}.harmonic[1].{part}", info.axis);
                    self.labels.iter().position(|l| *l == label)
                };
                let (u, v) = (across(first, 1), across(first, 2));
                let (Some(u_sin), Some(u_cos), Some(v_sin), Some(v_cos)) = (
                    find(u, "sin"),
                    find(u, "cos"),
                    find(v, "sin"),
                    find(v, "cos"),
                ) else {
                    continue;
                };
                let tie = |j: usize, factor: Real| Tie {
                    coefficient: self.free[j],
                    factor,
                    owner: self.owner[j],
                };
                let (re, im) = (tie(v_sin, -sense), tie(u_sin, sense));
                self.tied[u_cos].push(re);
                self.tied[v_cos].push(im);
                self.remove(u_sin.max(v_sin));
                self.remove(u_sin.min(v_sin));
            }
        }
    }

    /// Removes free coefficient `j`.
    fn remove(&mut self, j: usize) {
        self.free.remove(j);
        self.labels.remove(j);
        self.scales.remove(j);
        self.rotation.remove(j);
        self.owner.remove(j);
        self.degree.remove(j);
        self.tied.remove(j);
    }

    /// The parameters (indices into [`ErrorModel::parameters`]) free coefficient `j` sets: its
    /// own, then those of its ties.
    pub fn owners(&self, j: usize) -> impl Iterator<Item = usize> + '_ {
        std::iter::once(self.owner[j]).chain(self.tied[j].iter().map(|t| t.owner))
    }

    /// Adds the free coefficients of `term` (a polynomial without the degrees below
    /// [`first_degree`], a reversal, or a constant) of parameter `owner`, whose first
    /// coefficient is `index`; returns its number of coefficients.
    fn push_term(
        &mut self,
        term: &ErrorFunction,
        name: ParameterName,
        owner: usize,
        index: usize,
        machine: &Machine,
    ) -> usize {
        let rotation = !name.motion().is_translation();
        match term {
            ErrorFunction::Polynomial(c) => {
                let travel = travel_of(machine, name);
                for k in first_degree(name)..c.len() {
                    self.push(
                        index + k,
                        format!("{name}.polynomial[{k}]"),
                        scale(rotation) / travel.powi(k as i32),
                        (rotation, owner, k),
                    );
                }
            }
            ErrorFunction::Harmonic { period, .. } => {
                let order = order_of(*period);
                for (offset, part) in ["sin", "cos"].into_iter().enumerate() {
                    self.push(
                        index + offset,
                        format!("{name}.harmonic[{order}].{part}"),
                        scale(rotation),
                        (rotation, owner, order),
                    );
                }
            }
            ErrorFunction::Reversal(_) => self.push(
                index,
                format!("{name}.reversal"),
                scale(rotation),
                (rotation, owner, 0),
            ),
            _ => self.push(
                index,
                name.to_string(),
                scale(rotation),
                (rotation, owner, 0),
            ),
        }
        term.coefficient_count()
    }

    /// Adds free coefficient `index` with its label, scale, and (rotation, owner, degree).
    fn push(
        &mut self,
        index: usize,
        label: String,
        scale: Real,
        (rotation, owner, degree): (bool, usize, usize),
    ) {
        self.free.push(index);
        self.labels.push(label);
        self.scales.push(scale);
        self.rotation.push(rotation);
        self.owner.push(owner);
        self.degree.push(degree);
        self.tied.push(Vec::new());
    }

    /// The number of free coefficients.
    pub fn len(&self) -> usize {
        self.free.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.free.is_empty()
    }

    /// The error model with the free coefficients set to `values` (SI), the others zero.
    pub fn model_with(&self, values: &[Real]) -> ErrorModel {
        let mut model = self.model.clone();
        self.write(&mut model, values);
        model
    }

    /// Sets the free coefficients of `model` (a clone of the template) to `values` (SI).
    pub fn write(&self, model: &mut ErrorModel, values: &[Real]) {
        let mut all = vec![0.0; model.coefficient_count()];
        for ((&i, tied), &v) in self.free.iter().zip(&self.tied).zip(values) {
            all[i] += v;
            for tie in tied {
                all[tie.coefficient] += tie.factor * v;
            }
        }
        model.set_coefficients(&all);
    }
}

/// The lowest free degree of a component error's polynomial: 1 (zero at the axis zero), but 2
/// for a straightness error (EYX, EZX, EXY, EZY, EXZ, EYZ): ISO 230-1 measures straightness
/// from a reference line, whose slope is the squareness error, so a linear term would be the
/// squareness twice over (the two cannot be told apart by any measurement).
fn first_degree(name: ParameterName) -> usize {
    match name {
        ParameterName::Component { motion, axis }
            if axis.is_linear()
                && motion.is_translation()
                && motion.index() != axis.coordinate() =>
        {
            2
        }
        _ => 1,
    }
}

/// Whether `name` is a component error of a rotary axis (A, B, C): a Fourier series.
pub fn is_rotary_component(name: ParameterName) -> bool {
    matches!(name, ParameterName::Component { axis, .. } if matches!(axis, Axis::A | Axis::B | Axis::C))
}

/// The Fourier order (cycles per turn) of a harmonic of period `period` (rad).
pub fn order_of(period: Real) -> usize {
    (std::f64::consts::TAU / period).round() as usize
}

/// The Fourier series of `orders`: one harmonic of period 360°/k for each order k, zero.
fn fourier_series(orders: &[usize]) -> Vec<ErrorFunction> {
    orders
        .iter()
        .map(|&k| ErrorFunction::Harmonic {
            period: std::f64::consts::TAU / k as Real,
            amplitude: 0.0,
            phase: 0.0,
        })
        .collect()
}

/// `EXC.harmonic[2]` as (`EXC`, 2); `None` for an item of another form.
fn harmonic_item(item: &str) -> Option<(&str, &str)> {
    let (head, rest) = item.split_once(".harmonic[")?;
    Some((head.trim(), rest.strip_suffix(']')?))
}

/// The rotary axis's component error `head` whose single Fourier order `order` (1 to 9) is
/// asked for, on `machine`, and the order.
fn harmonic_name(
    head: &str,
    order: &str,
    machine: &Machine,
) -> Result<(ParameterName, usize), String> {
    let name: ParameterName = head.parse()?;
    if !is_rotary_component(name) {
        return Err(format!(
            "a single Fourier order belongs to a rotary axis's component error (EXC, ECA, …), not to {name}"
        ));
    }
    if let Some(axis) = name.axis().filter(|a| !machine.has_axis(*a)) {
        return Err(format!("machine \"{}\" has no axis {axis}", machine.name()));
    }
    match order.trim().parse::<usize>() {
        Ok(k) if (1..=9).contains(&k) => Ok((name, k)),
        _ => Err("the order in [ ] must be a whole number from 1 to 9".into()),
    }
}

/// The axes and order of `rotary_components[:AXIS][:ORDER]` (`rest` is what follows the
/// word): every rotary axis of the machine, or the one named, at [`DEFAULT_ORDER`] or the one
/// given (1 to 9).
fn rotary_components(
    rest: &str,
    rotary: &[Axis],
    machine: &Machine,
) -> Result<(Vec<Axis>, usize), String> {
    if rotary.is_empty() {
        return Err(format!("machine \"{}\" has no rotary axis", machine.name()));
    }
    let mut axes = rotary.to_vec();
    let mut order = DEFAULT_ORDER;
    let parts: Vec<&str> = rest.split(':').skip(1).map(str::trim).collect();
    if parts.len() > 2 {
        return Err(
            "expected rotary_components, rotary_components:C or rotary_components:C:3".into(),
        );
    }
    for (i, part) in parts.iter().enumerate() {
        if let Ok(n) = part.parse::<usize>() {
            if i + 1 != parts.len() {
                return Err("the order comes last (rotary_components:C:3)".into());
            }
            if !(1..=9).contains(&n) {
                return Err("the order after ':' must be from 1 to 9".into());
            }
            order = n;
        } else {
            let axis = match *part {
                "A" => Axis::A,
                "B" => Axis::B,
                "C" => Axis::C,
                other => {
                    return Err(format!(
                        "\"{other}\" is neither a rotary axis (A, B, C) nor an order (1 to 9)"
                    ));
                }
            };
            if i != 0 {
                return Err("the axis comes first (rotary_components:C:3)".into());
            }
            if !rotary.contains(&axis) {
                return Err(format!("machine \"{}\" has no axis {axis}", machine.name()));
            }
            axes = vec![axis];
        }
    }
    Ok((axes, order))
}

/// SI per solver unit of a constant: 1 µm, or the rotation that moves a point at the
/// reference length by 1 µm (10 µrad).
fn scale(rotation: bool) -> Real {
    if rotation {
        1e-6 / REFERENCE_LENGTH
    } else {
        1e-6
    }
}

/// The travel of the axis a component error belongs to (m or rad; 1 when unbounded).
fn travel_of(machine: &Machine, name: ParameterName) -> Real {
    name.axis()
        .and_then(|a| machine.axis(a))
        .and_then(|info| info.limits)
        .map(|(lower, upper)| lower.abs().max(upper.abs()))
        .filter(|t| *t > 0.0)
        .unwrap_or(1.0)
}
