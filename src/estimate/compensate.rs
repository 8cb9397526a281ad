//! The identified machine written out for other tools: a corrected URDF whose nominal kinematics
//! are the identified actual kinematics ([`corrected_urdf`]), and LinuxCNC screw-compensation
//! tables for the positioning errors ([`linuxcnc_tables`]).
//!
//! # What folds into a URDF
//!
//! A URDF holds constant geometry, so it can hold every constant error: the location errors of
//! the rotary axes (position `EX0C`, `EY0C`, …, orientation `EA0C`, `EB0C`, …, zero position
//! `EC0C`, `EA0A`, `EB0B`), the squareness errors (`EC0Y`, `EB0Z`, `EA0Z`) and the tool errors
//! (`EXT`, `EYT`, `EZT`). Component errors are functions of the axis position (polynomials,
//! tables, harmonics, reversal): they cannot be in a URDF and are listed in
//! [`Corrected::not_folded`] with the reason; the positioning ones go to [`linuxcnc_tables`].
//!
//! # The fold, exactly
//!
//! Write a URDF joint as its origin `O = (R_O, t_O)` (the `<origin xyz rpy>`) followed by its
//! motion `J(a, q)`: `Trans(a·q)` for a prismatic joint, `Rot(a, q)` for a revolute one, `a` the
//! `<axis xyz>`. In mtwin's chain ([`ErrorModel::workpiece_from_tool_with`]) every joint's
//! actual motion after its origin has the form `P · J(b, q) · Q` with constant `P`, `Q`:
//!
//! - **Linear axis with squareness** `ε` (rotation vector `EA0·, EB0·, EC0·`, `E = Exp(ε)`): on
//!   the tool side the slot adds `(E·u − u)·q` after `Trans(u·q)`; on the workpiece side
//!   (`a = −u`) the slot motion is inverted and takes it off. Either way the joint moves by
//!   `Trans(E·a·q)`: `P = Q = I`, `b = E·a`, a tilted line of travel.
//! - **Rotary axis** with the axis line `L = Trans(δ)·Exp(ε)` (`δ`, `ε` from `EX0C`, `EY0C`,
//!   `EA0C`, `EB0C`, …) and the zero-position error `Z = Exp(e0·e)` (`e` the letter's unit
//!   vector): on the tool side the chain is `L·R·L⁻¹·R⁻¹ · Z · R = L · R(q) · L⁻¹·Z` (`Z` and `R`
//!   turn about the same line and commute), so `P = L`, `Q = L⁻¹·Z`; on the workpiece side the
//!   slot motion is inverted: `Z⁻¹·L·R·L⁻¹·R⁻¹ · R = Z⁻¹·L · R(q) · L⁻¹`, so `P = Z⁻¹·L`,
//!   `Q = L⁻¹`. `b = a`.
//! - **Tool errors** `Trans(δ_T)` act after the `tool` frame: they are appended to the `Q` of
//!   the joint into the link `tool`.
//!
//! Each link `ℓ` then gets a constant correction `C_ℓ`, the physical part's frame in the
//! corrected link frame: `actual world_from_ℓ = corrected world_from_ℓ · C_ℓ`, with
//! `C_root = I`. For a joint from `p` to `c` the corrected origin `O'` and axis `a'` must
//! satisfy `O'·J(a', q) = C_p·O·P · J(b, q) · Q·C_c⁻¹` for every `q`. With `K = C_p·O·P` and any
//! rotation `G`, `K·J(b, q) = K·G⁻¹ · J(G·b, q) · G`; choosing `R_G = R_O⁻¹·R_K`:
//!
//! - `O' = (R_O, t_K)`: the `rpy` is unchanged, only `xyz` moves;
//! - `a' = R_G·b`: orientation, squareness and upstream zero-position errors tilt the axis;
//! - `C_c = G·Q`, carried down to the joints below.
//!
//! So every moving joint's frame stays parallel to the bed at the home pose (mtwin's
//! convention, [`crate::machine`]), and the errors appear as moved origins and tilted axes. At
//! the two ends the correction must vanish (`C_tool = C_workpiece = I`, so that
//! `workpiece_from_tool` is exact): the fixed joint into `tool` or `workpiece` takes
//! `O' = K·Q`, rotation included, so its `rpy` changes when a zero-position error or a tilt is
//! left over there. Nothing is linearised: the corrected URDF reproduces the chain to
//! round-off (the tests measure it to 1 nm and 1 nrad over the travel at large rotary angles).
//!
//! **Zero-position errors are folded**, not left to the controller's home offset: in mtwin's
//! chain `EC0C` turns the axis about its *nominal* line at the slot, so with location errors
//! present it is not exactly "C reached C + EC0C" about the actual line (the two differ by
//! about `EC0C·|δ|`, nanometres); folding reproduces the chain exactly and keeps the URDF
//! self-contained. To use the controller's offset instead (LinuxCNC `[JOINT_n]HOME_OFFSET`),
//! leave the zero-position errors out of the model passed here. A zero-position error of an
//! axis that carries another one tilts that axis (`EA0A` tilts C at A = 0), and one on the
//! tool branch tilts the tool (`EB0B`): that is what the machine does.
//!
//! Everything else in the text is kept as written: links, visuals, collisions, inertials, names,
//! comments, and the `rpy` or `quat_xyzw` of every joint but the end ones. Visuals hang from the
//! corrected link frames, which differ from the physical parts by `C_ℓ` (micrometres).
//! Numbers are written in Rust's shortest round-trip form, so they read back bit for bit.

use crate::errors::{ErrorFunction, ErrorModel, ParameterName};
use crate::machine::{Axis, AxisInfo, AxisValues, Direction, Machine, Side, axis_unit_to_si};
use crate::math::{
    Pose, Real, Rotation, Vector, fixed, rigid_inverse, rotation_from_rpy, small_motion, trimmed,
};
use std::collections::{BTreeMap, HashMap};
use std::ops::Range;
use urdf_rs::JointType;

/// The identified machine as a URDF: constant errors folded into the joints.
#[derive(Clone, Debug, PartialEq)]
pub struct Corrected {
    /// The corrected URDF text.
    pub urdf: String,
    /// The parameters folded into it (location, squareness and tool errors).
    pub folded: Vec<ParameterName>,
    /// The parameters a URDF cannot hold, each with the reason and where it can go instead.
    pub not_folded: Vec<(ParameterName, String)>,
}

/// Why the identified machine could not be written out.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CompensateError {
    /// The URDF text could not be read.
    #[error("the URDF text could not be read: {0}")]
    Urdf(String),
    /// The URDF text, the machine and the error model do not describe the same machine.
    #[error("the URDF text is not the machine \"{machine}\" the errors belong to: {reason}")]
    OtherMachine {
        /// The machine's name.
        machine: String,
        /// What differs.
        reason: String,
    },
    /// Two `<joint>` elements share a name, so the one to correct cannot be told apart.
    #[error("two joints are named \"{0}\": the joint to correct cannot be told apart")]
    DuplicateJoint(String),
    /// An end link hangs directly from a moving joint that would need a correction after its
    /// motion.
    #[error(
        "link \"{link}\" hangs directly from the moving joint \"{joint}\": the correction after \
         its motion needs a fixed joint in between (add <joint type=\"fixed\"> from a new link to \
         \"{link}\")"
    )]
    MovingEndJoint {
        /// `tool` or `workpiece`.
        link: String,
        /// The moving joint.
        joint: String,
    },
    /// A table spacing that is not a positive finite number.
    #[error("axis {axis}: table spacing {spacing} (SI) is not a positive finite number")]
    Spacing {
        /// The axis.
        axis: Axis,
        /// The spacing given (m or rad).
        spacing: Real,
    },
    /// More table entries than LinuxCNC takes per joint.
    #[error(
        "axis {axis}: {entries} compensation entries at this spacing, but LinuxCNC takes at most \
         {LINUXCNC_MAX_ENTRIES} per joint: use a spacing of at least {minimum} {unit}"
    )]
    TooManyEntries {
        /// The axis.
        axis: Axis,
        /// Entries at the spacing asked for.
        entries: usize,
        /// The smallest spacing that fits (file units).
        minimum: String,
        /// `mm` or `deg`.
        unit: &'static str,
    },
    /// More interpolation points than a SINUMERIK table is written with.
    #[error(
        "axis {axis}: {points} interpolation points at this spacing, more than the {maximum} a \
         SINUMERIK compensation table is written with: use a larger spacing"
    )]
    TooManyPoints {
        /// The axis.
        axis: Axis,
        /// Points at the spacing asked for.
        points: usize,
        /// The most written.
        maximum: usize,
    },
}

/// The most entries LinuxCNC keeps per joint (`EMCMOT_COMP_SIZE` in `src/emc/motion/motion.h`).
pub const LINUXCNC_MAX_ENTRIES: usize = 256;

/// The constant errors of a model, sorted by what they do.
#[derive(Default)]
struct Constants {
    /// Rotary axis lines `(δ, ε)` by axis.
    line: BTreeMap<Axis, [Real; 6]>,
    /// Zero-position errors by rotary axis (rad).
    zero: BTreeMap<Axis, Real>,
    /// Squareness rotation vectors by linear axis.
    squareness: BTreeMap<Axis, Vector>,
    /// Tool-tip offset (tool frame, m).
    tool: Vector,
}

/// Writes the identified machine as a URDF whose nominal kinematics equal the actual
/// kinematics of `machine` with the constant errors of `errors` (see the [module
/// docs](self) for the derivation).
///
/// `urdf_text` is the URDF `machine` was loaded from; only the joints' `<origin>` and `<axis>`
/// elements whose values change are rewritten (an element a joint lacks is added). Component
/// errors are listed in [`Corrected::not_folded`].
pub fn corrected_urdf(
    urdf_text: &str,
    machine: &Machine,
    errors: &ErrorModel,
) -> Result<Corrected, CompensateError> {
    let other = |reason: String| CompensateError::OtherMachine {
        machine: machine.name().to_string(),
        reason,
    };
    // The text must be the machine the errors belong to.
    let reloaded = Machine::from_urdf_str(urdf_text, "the URDF text")
        .map_err(|e| CompensateError::Urdf(e.to_string()))?;
    same_machine(machine, &reloaded).map_err(other)?;
    let robot =
        urdf_rs::read_from_string(urdf_text).map_err(|e| CompensateError::Urdf(e.to_string()))?;
    for (i, joint) in robot.joints.iter().enumerate() {
        if robot.joints[..i].iter().any(|j| j.name == joint.name) {
            return Err(CompensateError::DuplicateJoint(joint.name.clone()));
        }
    }

    let mut constants = Constants::default();
    let mut folded = Vec::new();
    let mut not_folded = Vec::new();
    for parameter in errors.parameters() {
        let name = parameter.name;
        if let Some(axis) = name.axis()
            && !machine.has_axis(axis)
        {
            return Err(other(format!("{name} names axis {axis}, which it lacks")));
        }
        let value = || parameter.function.value(0.0, Direction::Positive);
        let index = name.motion().index();
        match name {
            ParameterName::Component { axis, .. } => {
                not_folded.push((name, why_not_folded(name, axis, &parameter.function)));
                continue;
            }
            ParameterName::Tool { .. } => constants.tool[index] += value(),
            ParameterName::Location { axis, .. } if axis.is_linear() => {
                constants.squareness.entry(axis).or_insert(Vector::ZERO)[index - 3] += value();
            }
            ParameterName::Location { axis, .. } if index == axis.coordinate() + 3 => {
                *constants.zero.entry(axis).or_insert(0.0) += value();
            }
            ParameterName::Location { axis, .. } => {
                constants.line.entry(axis).or_insert([0.0; 6])[index] += value();
            }
        }
        folded.push(name);
    }

    // Down the tree from the root: each link's correction C (physical part in corrected frame).
    let child_links: Vec<&str> = robot.joints.iter().map(|j| j.child.link.as_str()).collect();
    let root = robot
        .links
        .iter()
        .find(|l| !child_links.contains(&l.name.as_str()))
        .map(|l| l.name.as_str())
        .ok_or_else(|| CompensateError::Urdf("no root link".into()))?;
    let mut correction: HashMap<&str, Pose> = HashMap::from([(root, Pose::IDENTITY)]);
    let mut pending = vec![root];
    let mut new_joints: HashMap<&str, (Pose, Vector)> = HashMap::new();
    while let Some(link) = pending.pop() {
        let c_parent = correction[link];
        for joint in robot.joints.iter().filter(|j| j.parent.link == link) {
            let origin = joint_origin(joint);
            let a = Vector::from_array(joint.axis.xyz.0);
            let (p, b, mut q) = decompose(joint, machine, &constants, a);
            let child = joint.child.link.as_str();
            if child == "tool" {
                q *= Pose::from_translation(constants.tool);
            }
            let k = c_parent * origin * p;
            let (new_origin, new_axis, c_child) = if child == "tool" || child == "workpiece" {
                if joint.joint_type == JointType::Fixed {
                    (k * q, a, Pose::IDENTITY)
                } else if q.translation == Vector::ZERO {
                    // G = Q⁻¹, a rotation: C = G·Q = I.
                    (
                        k * q,
                        (q.matrix3.transpose() * b).normalize(),
                        Pose::IDENTITY,
                    )
                } else {
                    return Err(CompensateError::MovingEndJoint {
                        link: child.to_string(),
                        joint: joint.name.clone(),
                    });
                }
            } else {
                let r_g = origin.matrix3.transpose() * k.matrix3;
                let new_origin = Pose::from_mat3_translation(origin.matrix3, k.translation);
                let new_axis = if joint.joint_type == JointType::Fixed {
                    a
                } else {
                    (r_g * b).normalize()
                };
                (new_origin, new_axis, Pose::from_mat3(r_g) * q)
            };
            new_joints.insert(joint.name.as_str(), (new_origin, new_axis));
            correction.insert(child, c_child);
            pending.push(child);
        }
    }

    // Rewrite the changed <origin> and <axis> elements in the text.
    let tags = joint_tags(urdf_text)?;
    let mut edits: Vec<(Range<usize>, String)> = Vec::new();
    for joint in &robot.joints {
        let (new_origin, new_axis) = new_joints[joint.name.as_str()];
        let origin = joint_origin(joint);
        let Some(tag) = tags.get(&joint.name) else {
            return Err(CompensateError::Urdf(format!(
                "joint \"{}\" not found in the text",
                joint.name
            )));
        };
        let moved = new_origin.translation != origin.translation;
        let turned = new_origin.matrix3 != origin.matrix3;
        if moved || turned {
            let xyz = numbers(new_origin.translation.to_array());
            let rpy = turned.then(|| numbers(rpy_from_rotation(new_origin.matrix3)));
            let (range, text) = match &tag.origin {
                Some(element) => (
                    element.span.clone(),
                    element.rewrite(Some(&xyz), rpy.as_deref()),
                ),
                None => {
                    let mut text = format!("<origin xyz=\"{xyz}\"");
                    if let Some(rpy) = rpy {
                        text += &format!(" rpy=\"{rpy}\"");
                    }
                    (tag.inside..tag.inside, text + "/>")
                }
            };
            edits.push((range, text));
        }
        if joint.joint_type != JointType::Fixed && new_axis.to_array() != joint.axis.xyz.0 {
            let xyz = numbers(new_axis.to_array());
            let (range, text) = match &tag.axis {
                Some(element) => (element.span.clone(), element.rewrite(Some(&xyz), None)),
                None => (tag.inside..tag.inside, format!("<axis xyz=\"{xyz}\"/>")),
            };
            edits.push((range, text));
        }
    }
    edits.sort_by_key(|(range, _)| (range.start, range.end));
    let mut urdf = String::with_capacity(urdf_text.len() + 64 * edits.len());
    let mut at = 0;
    for (range, text) in edits {
        urdf.push_str(&urdf_text[at..range.start]);
        urdf.push_str(&text);
        at = range.end;
    }
    urdf.push_str(&urdf_text[at..]);
    Ok(Corrected {
        urdf,
        folded,
        not_folded,
    })
}

/// Whether two machines have the same axes, sides, joint axes and nominal poses.
fn same_machine(machine: &Machine, other: &Machine) -> Result<(), String> {
    let describe = |m: &Machine| {
        m.axes()
            .iter()
            .map(|info| format!("{} ({:?} side)", info.axis, info.side))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let same_axes = machine.axes().len() == other.axes().len()
        && machine
            .axes()
            .iter()
            .zip(other.axes())
            .all(|(a, b)| a.axis == b.axis && a.side == b.side && a.joint_axis == b.joint_axis);
    if !same_axes {
        return Err(format!(
            "its axes are {}, the machine's {}",
            describe(other),
            describe(machine)
        ));
    }
    let mut probe = AxisValues::ZERO;
    for info in machine.axes() {
        let (lower, upper) = info.limits.unwrap_or((0.0, 1.0));
        probe[info.axis] = lower + 0.37 * (upper - lower);
    }
    for position in [AxisValues::ZERO, probe] {
        let (a, b) = (
            machine.workpiece_from_tool(&position),
            other.workpiece_from_tool(&position),
        );
        if !a.abs_diff_eq(b, 1e-12) {
            return Err(format!(
                "its nominal tool pose differs by {:.3e} m",
                (a.translation - b.translation).length()
            ));
        }
    }
    Ok(())
}

/// Why a component error is not in the URDF, and where it can go instead.
fn why_not_folded(name: ParameterName, axis: Axis, function: &ErrorFunction) -> String {
    let what = if function.is_constant() {
        format!(
            "a component error of {axis}, constant here but applied at the moving slot as a \
             function of the {axis} position (if it really is constant, refit it as a location \
             error or set it as a controller offset)"
        )
    } else if function.value(0.0, Direction::Positive) != function.value(0.0, Direction::Negative) {
        format!("a function of the {axis} position and direction of travel")
    } else {
        format!("a function of the {axis} position")
    };
    if ParameterName::positioning(axis) == Some(name) {
        format!(
            "{what}: see the LinuxCNC, SINUMERIK and HEIDENHAIN compensation tables \
             (linuxcnc_{axis}.comp, sinumerik_{axis}_eec.ini, heidenhain_{axis}.com)"
        )
    } else if axis == Axis::S {
        format!("{what}: a spindle error motion, which no URDF or axis table holds")
    } else {
        format!(
            "{what}: a URDF holds constant geometry only, and a LinuxCNC screw table corrects \
             positioning along the axis only; it needs volumetric compensation in the controller"
        )
    }
}

/// A joint's actual motion as `P · J(b, q) · Q` (see the module docs).
fn decompose(
    joint: &urdf_rs::Joint,
    machine: &Machine,
    constants: &Constants,
    a: Vector,
) -> (Pose, Vector, Pose) {
    let identity = (Pose::IDENTITY, a, Pose::IDENTITY);
    if joint.joint_type == JointType::Fixed {
        return identity;
    }
    let Some(info) = single_letter(&joint.name).and_then(|axis| machine.axis(axis)) else {
        return identity;
    };
    let axis = info.axis;
    if axis.is_linear() {
        return match constants.squareness.get(&axis) {
            Some(&epsilon) => (
                Pose::IDENTITY,
                small_motion(Vector::ZERO, epsilon).matrix3 * a,
                Pose::IDENTITY,
            ),
            None => identity,
        };
    }
    if !axis.is_rotary() {
        return identity;
    }
    let l = constants.line.get(&axis).copied().unwrap_or([0.0; 6]);
    let line = small_motion(Vector::new(l[0], l[1], l[2]), Vector::new(l[3], l[4], l[5]));
    let e0 = constants.zero.get(&axis).copied().unwrap_or(0.0);
    let zero = small_motion(Vector::ZERO, axis.unit() * e0);
    match info.side {
        Side::Tool => (line, a, rigid_inverse(&line) * zero),
        Side::Workpiece => (rigid_inverse(&zero) * line, a, rigid_inverse(&line)),
    }
}

/// The axis named by a one-letter joint name.
fn single_letter(name: &str) -> Option<Axis> {
    let mut chars = name.chars();
    match (chars.next(), chars.next()) {
        (Some(letter), None) => Axis::from_letter(letter),
        _ => None,
    }
}

/// `parent_from_joint` of a URDF joint at zero motion (as the reader builds it).
fn joint_origin(joint: &urdf_rs::Joint) -> Pose {
    Pose::from_mat3_translation(
        rotation_from_rpy(joint.origin.rpy.0),
        Vector::from_array(joint.origin.xyz.0),
    )
}

/// URDF `rpy` of a rotation `Rz(yaw)·Ry(pitch)·Rx(roll)` (the inverse of
/// [`rotation_from_rpy`]; pitch by atan2, accurate near ±90° too).
fn rpy_from_rotation(r: Rotation) -> [Real; 3] {
    // glam is column-major: r.x_axis is column 0, so r.x_axis.z is row 2, column 0.
    let pitch = (-r.x_axis.z).atan2(r.x_axis.x.hypot(r.x_axis.y));
    let roll = r.y_axis.z.atan2(r.z_axis.z);
    let yaw = r.x_axis.y.atan2(r.x_axis.x);
    [roll, pitch, yaw]
}

/// Three numbers in Rust's shortest round-trip form (exponent notation outside
/// [1e-3, 1e6)), separated by spaces: they read back bit for bit.
fn numbers(values: [Real; 3]) -> String {
    let number = |v: Real| {
        if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
            format!("{v}")
        } else {
            format!("{v:e}")
        }
    };
    values.map(number).join(" ")
}

/// Where a joint's `<origin>` and `<axis>` are in the text.
struct JointTags {
    /// Just after the `<joint …>` start tag: where missing elements are inserted.
    inside: usize,
    origin: Option<Element>,
    axis: Option<Element>,
}

/// A start or empty tag in the text, with its attributes as written.
struct Element {
    span: Range<usize>,
    name: String,
    /// `(key, raw value)` in order.
    attributes: Vec<(String, String)>,
    empty: bool,
}

impl Element {
    /// The tag with `xyz` and the orientation (`rpy`, or `quat_xyzw` turned into `rpy`)
    /// replaced when given, every other attribute as written.
    fn rewrite(&self, xyz: Option<&str>, rpy: Option<&str>) -> String {
        let mut out = format!("<{}", self.name);
        let (mut xyz_done, mut rpy_done) = (xyz.is_none(), rpy.is_none());
        for (key, raw) in &self.attributes {
            match (key.as_str(), xyz, rpy) {
                ("xyz", Some(new), _) => {
                    out += &format!(" xyz=\"{new}\"");
                    xyz_done = true;
                }
                ("rpy" | "quat_xyzw", _, Some(new)) => {
                    if !rpy_done {
                        out += &format!(" rpy=\"{new}\"");
                        rpy_done = true;
                    }
                }
                _ => {
                    let quote = if raw.contains('"') { '\'' } else { '"' };
                    out += &format!(" {key}={quote}{raw}{quote}");
                }
            }
        }
        if let (false, Some(new)) = (xyz_done, xyz) {
            out += &format!(" xyz=\"{new}\"");
        }
        if let (false, Some(new)) = (rpy_done, rpy) {
            out += &format!(" rpy=\"{new}\"");
        }
        out + if self.empty { "/>" } else { ">" }
    }
}

/// Finds each top-level `<joint>`'s `<origin>` and `<axis>` in the text.
fn joint_tags(text: &str) -> Result<HashMap<String, JointTags>, CompensateError> {
    use quick_xml::events::{BytesStart, Event};
    let bad = |what: String| CompensateError::Urdf(what);
    let element = |start: &BytesStart<'_>, span: Range<usize>, empty: bool| -> Result<Element, _> {
        let name = String::from_utf8_lossy(start.name().as_ref()).into_owned();
        let attributes = start
            .attributes()
            .map(|a| {
                let a = a.map_err(|e| bad(e.to_string()))?;
                Ok((
                    String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                    String::from_utf8_lossy(&a.value).into_owned(),
                ))
            })
            .collect::<Result<Vec<_>, CompensateError>>()?;
        Ok(Element {
            span,
            name,
            attributes,
            empty,
        })
    };
    let mut reader = quick_xml::Reader::from_str(text);
    let mut stack: Vec<String> = Vec::new();
    let mut tags: HashMap<String, JointTags> = HashMap::new();
    let mut current: Option<String> = None;
    loop {
        let before = reader.buffer_position() as usize;
        let event = reader.read_event().map_err(|e| bad(e.to_string()))?;
        let after = reader.buffer_position() as usize;
        let (start, empty) = match event {
            Event::Start(start) => (start, false),
            Event::Empty(start) => (start, true),
            Event::End(_) => {
                stack.pop();
                if stack.len() < 2 {
                    current = None;
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let name = String::from_utf8_lossy(start.name().as_ref()).into_owned();
        if !text[before..].starts_with('<') || !text[..after].ends_with('>') {
            return Err(bad(format!("could not locate <{name}> in the text")));
        }
        let top_joint = name == "joint" && stack.len() == 1 && stack[0] == "robot";
        if top_joint {
            let tag = element(&start, before..after, empty)?;
            let joint_name = tag
                .attributes
                .iter()
                .find(|(k, _)| k == "name")
                .map(|(_, v)| v.clone())
                .unwrap_or_default();
            tags.insert(
                joint_name.clone(),
                JointTags {
                    inside: after,
                    origin: None,
                    axis: None,
                },
            );
            current = (!empty).then_some(joint_name);
        } else if let Some(joint) = current
            .as_ref()
            .filter(|_| stack.len() == 2 && (name == "origin" || name == "axis"))
        {
            let tag = element(&start, before..after, empty)?;
            let entry = tags.get_mut(joint).expect("inserted at its start");
            if name == "origin" {
                entry.origin = Some(tag);
            } else {
                entry.axis = Some(tag);
            }
        }
        if !empty {
            stack.push(name);
        }
    }
    Ok(tags)
}

// ---------------------------------------------------------------------------------------------
// LinuxCNC

/// LinuxCNC screw-compensation files for the positioning errors (`EXX`, `EYY`, `EZZ` and the
/// rotary `EAA`, `EBB`, `ECC`), one per axis that has one, in ISO order.
///
/// Each file is for `COMP_FILE_TYPE = 1` in the axis's `[JOINT_n]` section (`[AXIS_n]` before
/// LinuxCNC 2.8): one line per nominal position, `nominal forward_trim reverse_trim`, in machine
/// units (`LINEAR_UNITS = mm`, `ANGULAR_UNITS = degree`), nominal strictly increasing. The
/// controller adds the trim of the direction of travel, interpolated linearly, to the commanded
/// joint position (`motor_pos_cmd = pos_cmd + trim`), so a trim is the correction: `t` with
/// `t = −E(n + t)`, the axis commanded to `n + t` reaching `n` in mtwin's model (solved by fixed
/// point; to first order `t = −E(n)`, which is what LinuxCNC's own type 0 files amount to:
/// `trim = nominal − actual`). `E` of the positive direction gives the forward trim, of the
/// negative direction the reverse one, so a reversal error `r` makes them differ by `r`
/// (forward `+r/2`, reverse `−r/2`, as LinuxCNC does with `BACKLASH`, which it ignores once a
/// `COMP_FILE` is given).
///
/// Nominal positions are the multiples of the spacing (`spacing_m` for linear axes,
/// `spacing_rad` for rotary ones) inside the travel, plus both ends of the travel; a continuous
/// axis gets one turn, 0° to 360° (its errors repeat every turn; LinuxCNC holds the end values
/// beyond the table, so use it with `WRAPPED_ROTARY`). The files have no header or comment line:
/// LinuxCNC's reader stops at the first line that is not three numbers. At most
/// [`LINUXCNC_MAX_ENTRIES`] lines per file.
///
/// References: the LinuxCNC INI configuration manual, `[JOINT_<num>]` section, `COMP_FILE` and
/// `COMP_FILE_TYPE` (<https://linuxcnc.org/docs/html/config/ini-config.html>); the reader
/// `usrmotLoadComp` (`src/emc/motion/usrmotintf.cc`) and `compute_screw_comp`
/// (`src/emc/motion/control.c`) in the LinuxCNC sources.
pub fn linuxcnc_tables(
    machine: &Machine,
    errors: &ErrorModel,
    spacing_m: Real,
    spacing_rad: Real,
) -> Result<Vec<(Axis, String)>, CompensateError> {
    per_positioning_error(machine, errors, spacing_m, spacing_rad, table)
}

/// The spacings (linear, rotary; SI) at which every axis of `machine` fits
/// [`LINUXCNC_MAX_ENTRIES`]: those asked for, widened where an axis's travel (one turn for a
/// continuous axis) would need more entries (as [`CompensateError::TooManyEntries`] advises).
pub fn linuxcnc_spacings(machine: &Machine, spacing_m: Real, spacing_rad: Real) -> (Real, Real) {
    let widest = |linear: bool| {
        (machine.axes().iter())
            .filter(|info| info.axis.is_linear() == linear && info.axis != Axis::S)
            .map(|info| {
                let (lower, upper) = info.limits.unwrap_or((0.0, std::f64::consts::TAU));
                (upper - lower) / (LINUXCNC_MAX_ENTRIES - 2) as Real * 1.0001
            })
            .fold(0.0, Real::max)
    };
    (spacing_m.max(widest(true)), spacing_rad.max(widest(false)))
}

/// `write(axis, its positioning error, spacing)` for every axis of `machine` whose positioning
/// error (`EXX` … `ECC`) `errors` has, in ISO order, the spacing `spacing_m` for linear axes
/// and `spacing_rad` for rotary ones: the controller tables' common walk.
pub(super) fn per_positioning_error(
    machine: &Machine,
    errors: &ErrorModel,
    spacing_m: Real,
    spacing_rad: Real,
    write: impl Fn(&AxisInfo, &ErrorFunction, Real) -> Result<String, CompensateError>,
) -> Result<Vec<(Axis, String)>, CompensateError> {
    let mut tables = Vec::new();
    for info in machine.axes() {
        let Some(parameter) =
            ParameterName::positioning(info.axis).and_then(|name| errors.parameter(name))
        else {
            continue;
        };
        let spacing = if info.axis.is_linear() {
            spacing_m
        } else {
            spacing_rad
        };
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(CompensateError::Spacing {
                axis: info.axis,
                spacing,
            });
        }
        tables.push((info.axis, write(info, &parameter.function, spacing)?));
    }
    Ok(tables)
}

/// The number of intervals of `spacing` from `lower` that reach `upper` (the last point at or
/// beyond it, a billionth of a step of rounding forgiven; at least one): the controller
/// tables' points.
pub(super) fn intervals_to(lower: Real, upper: Real, spacing: Real) -> usize {
    ((upper - lower) / spacing - 1e-9).ceil().max(1.0) as usize
}

/// The positioning error `function` of the axis `info` at `q` (SI) travelling in a direction,
/// a continuous axis's position taken within its turn.
pub(super) fn error_at(
    info: &AxisInfo,
    function: &ErrorFunction,
    q: Real,
    direction: Direction,
) -> Real {
    let argument = if info.is_continuous() {
        q.rem_euclid(std::f64::consts::TAU)
    } else {
        q
    };
    function.value(argument, direction)
}

/// One axis's compensation file.
fn table(
    info: &AxisInfo,
    function: &ErrorFunction,
    spacing: Real,
) -> Result<String, CompensateError> {
    let axis = info.axis;
    let (lower, upper) = info.limits.unwrap_or((0.0, std::f64::consts::TAU));
    let unit = axis_unit_to_si(axis);
    let (unit_name, trim_decimals) = if axis.is_linear() {
        ("mm", 6) // 1 nm
    } else {
        ("deg", 8) // 0.2 nrad
    };
    // Nominal positions in file units, rounded as written (6 decimals).
    let round = |v: Real| (v / unit * 1e6).round() / 1e6;
    let tolerance = 1e-9 * spacing;
    let mut nominal = vec![round(lower)];
    let first = (lower / spacing).ceil() as i64;
    let last = (upper / spacing).floor() as i64;
    for k in first..=last {
        let v = k as Real * spacing;
        if v > lower + tolerance && v < upper - tolerance {
            nominal.push(round(v));
        }
    }
    nominal.push(round(upper));
    nominal.dedup();
    if nominal.len() > LINUXCNC_MAX_ENTRIES {
        let minimum = (upper - lower) / (LINUXCNC_MAX_ENTRIES - 2) as Real / unit;
        return Err(CompensateError::TooManyEntries {
            axis,
            entries: nominal.len(),
            minimum: trimmed(minimum * 1.0001, 6),
            unit: unit_name,
        });
    }
    let error = |q: Real, direction: Direction| error_at(info, function, q, direction);
    // The trim t with n + t + E(n + t) = n.
    let trim = |n: Real, direction: Direction| {
        let mut t = -error(n, direction);
        for _ in 0..50 {
            let next = -error(n + t, direction);
            if next == t {
                break;
            }
            t = next;
        }
        t
    };
    let mut out = String::new();
    for n in nominal {
        let q = n * unit;
        let forward = trim(q, Direction::Positive) / unit;
        let reverse = trim(q, Direction::Negative) / unit;
        out += &format!(
            "{} {} {}\n",
            trimmed(n, 6),
            fixed(forward, trim_decimals),
            fixed(reverse, trim_decimals)
        );
    }
    Ok(out)
}
