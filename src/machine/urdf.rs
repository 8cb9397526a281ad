//! URDF → [`Machine`]: parsing (urdf-rs), then validation of the tree, the axis names and
//! directions and the supported configurations.

use super::{Axis, AxisInfo, Body, Branch, ChainJoint, Machine, Shape, Side, Visual};
use crate::math::{Pose, Real, Vector, rotation_from_rpy};
use std::collections::BTreeMap;
use std::path::Path;
use urdf_rs::JointType;

/// How far a joint axis (and the tool's z) may turn from its letter's direction: 1 mrad. The
/// machines of `models/` have exact directions; an identified machine (`mtwin identify`'s
/// corrected URDF) has its axes tilted by its orientation and squareness errors, µrad.
pub const AXIS_TILT: Real = 1e-3;

mod error;
pub use error::{LARGEST_MACHINE, LARGEST_TURN, MachineError, MachineErrorKind};

impl Machine {
    /// Loads and validates a URDF file.
    pub fn from_urdf_file(path: impl AsRef<Path>) -> Result<Machine, MachineError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| MachineError {
            file: file.clone(),
            line: None,
            kind: MachineErrorKind::Io(e.to_string()),
        })?;
        Machine::from_urdf_str(&text, &file)
    }

    /// Loads and validates URDF text; `file` names it in error messages.
    pub fn from_urdf_str(text: &str, file: &str) -> Result<Machine, MachineError> {
        if let Some((offset, message)) = xml_problem(text) {
            let (line, column) = line_and_column(text, offset);
            return Err(MachineError {
                file: file.to_string(),
                line: Some(line),
                kind: MachineErrorKind::Xml(format!("column {column}: {message}")),
            });
        }
        let robot = urdf_rs::read_from_string(text).map_err(|e| MachineError {
            file: file.to_string(),
            line: None,
            kind: MachineErrorKind::Xml(e.to_string()),
        })?;
        // Errors about a joint point at its own `<joint>` element: the n-th of that name when
        // names repeat.
        let fail = |joint: Option<&urdf_rs::Joint>, kind: MachineErrorKind| MachineError {
            file: file.to_string(),
            line: joint.and_then(|joint| {
                let index = robot.joints.iter().position(|j| std::ptr::eq(j, joint))?;
                let occurrence = robot.joints[..index]
                    .iter()
                    .filter(|j| j.name == joint.name)
                    .count();
                line_of_element(text, "joint", &joint.name, occurrence)
            }),
            kind,
        };

        let link_names: Vec<&str> = robot.links.iter().map(|l| l.name.as_str()).collect();
        for end in ["tool", "workpiece"] {
            if !link_names.contains(&end) {
                return Err(fail(None, MachineErrorKind::MissingEndLink(end)));
            }
        }

        // Tree: every link has at most one parent joint; exactly one root.
        let mut parent_joint: BTreeMap<&str, usize> = BTreeMap::new();
        for (index, joint) in robot.joints.iter().enumerate() {
            for link in [&joint.parent.link, &joint.child.link] {
                if !link_names.contains(&link.as_str()) {
                    return Err(fail(
                        Some(joint),
                        MachineErrorKind::UnknownLink {
                            joint: joint.name.clone(),
                            link: link.clone(),
                        },
                    ));
                }
            }
            if let Some(first) = parent_joint.insert(joint.child.link.as_str(), index) {
                return Err(fail(
                    Some(joint),
                    MachineErrorKind::ClosedLoop {
                        link: joint.child.link.clone(),
                        joints: [robot.joints[first].name.clone(), joint.name.clone()],
                    },
                ));
            }
        }
        let roots: Vec<String> = link_names
            .iter()
            .filter(|l| !parent_joint.contains_key(*l))
            .map(|l| l.to_string())
            .collect();
        // The links that hang from `root`, itself included (each link has one parent at most,
        // so the walk cannot loop).
        let hanging_from = |root: &str| {
            let mut found = vec![root.to_string()];
            let mut next = 0;
            while next < found.len() {
                let parent = found[next].clone();
                found.extend(
                    robot
                        .joints
                        .iter()
                        .filter(|j| j.parent.link == parent)
                        .map(|j| j.child.link.clone()),
                );
                next += 1;
            }
            found
        };
        if roots.len() != 1 {
            // The root is the link most others hang from (the bed): list it first.
            let mut roots = roots;
            roots.sort_by_key(|r| std::cmp::Reverse(hanging_from(r).len()));
            return Err(fail(None, MachineErrorKind::Roots(roots)));
        }
        // Every link must hang from the root; a cycle elsewhere has no parentless link of its own.
        let reachable = hanging_from(&roots[0]);
        let cut_off: Vec<String> = link_names
            .iter()
            .filter(|l| !reachable.iter().any(|r| r == *l))
            .map(|l| l.to_string())
            .collect();
        if !cut_off.is_empty() {
            return Err(fail(None, MachineErrorKind::Cycle(cut_off)));
        }

        // Joint checks, independent of the branch.
        let mut seen_axes: Vec<Axis> = Vec::new();
        for joint in &robot.joints {
            let finite = joint
                .origin
                .xyz
                .0
                .iter()
                .chain(&joint.origin.rpy.0)
                .chain(&joint.axis.xyz.0)
                .all(|v| v.is_finite());
            if !finite {
                return Err(fail(
                    Some(joint),
                    MachineErrorKind::NotFinite {
                        joint: joint.name.clone(),
                    },
                ));
            }
            if let Some(found) = largest_beyond(&joint.origin.xyz.0, LARGEST_MACHINE) {
                return Err(fail(
                    Some(joint),
                    MachineErrorKind::Implausible {
                        element: format!("joint \"{}\" origin", joint.name),
                        found,
                        limit: "±100 m",
                    },
                ));
            }
            let type_name = format!("{:?}", joint.joint_type).to_lowercase();
            let unsupported = matches!(
                joint.joint_type,
                JointType::Floating | JointType::Planar | JointType::Spherical
            );
            if unsupported || joint.mimic.is_some() {
                let joint_type = if unsupported {
                    type_name
                } else {
                    "a mimic joint".to_string()
                };
                return Err(fail(
                    Some(joint),
                    MachineErrorKind::UnsupportedJoint {
                        joint: joint.name.clone(),
                        joint_type,
                    },
                ));
            }
            if joint.joint_type == JointType::Fixed {
                continue;
            }
            let axis = single_letter(&joint.name).ok_or_else(|| {
                fail(
                    Some(joint),
                    MachineErrorKind::AxisName {
                        joint: joint.name.clone(),
                    },
                )
            })?;
            if seen_axes.contains(&axis) {
                return Err(fail(Some(joint), MachineErrorKind::DuplicateAxis(axis)));
            }
            seen_axes.push(axis);
            let type_ok = match axis {
                Axis::X | Axis::Y | Axis::Z => joint.joint_type == JointType::Prismatic,
                Axis::S => joint.joint_type == JointType::Continuous,
                _ => matches!(
                    joint.joint_type,
                    JointType::Revolute | JointType::Continuous
                ),
            };
            if !type_ok {
                return Err(fail(
                    Some(joint),
                    MachineErrorKind::AxisType {
                        axis,
                        joint_type: type_name,
                    },
                ));
            }
        }

        // Branches: walk up from each end link to the root.
        let path_to = |end: &str| -> Vec<usize> {
            let mut path = Vec::new();
            let mut link = end;
            while let Some(&index) = parent_joint.get(link) {
                path.push(index);
                link = robot.joints[index].parent.link.as_str();
            }
            path.reverse();
            path
        };
        let tool_path = path_to("tool");
        let work_path = path_to("workpiece");

        let mut axes: Vec<AxisInfo> = Vec::new();
        for joint in robot
            .joints
            .iter()
            .filter(|j| j.joint_type != JointType::Fixed)
        {
            let axis = single_letter(&joint.name).expect("checked above");
            let index = robot
                .joints
                .iter()
                .position(|j| j.name == joint.name)
                .expect("present");
            let on_tool = tool_path.contains(&index);
            let on_work = work_path.contains(&index);
            let side = match (on_tool, on_work) {
                (true, false) => Side::Tool,
                (false, true) => Side::Workpiece,
                (true, true) => {
                    return Err(fail(Some(joint), MachineErrorKind::SharedBranch { axis }));
                }
                (false, false) => {
                    return Err(fail(Some(joint), MachineErrorKind::OffBranch { axis }));
                }
            };
            if axis == Axis::S && side != Side::Tool {
                return Err(fail(Some(joint), MachineErrorKind::SpindleSide));
            }
            // The joint frame parallel to the bed at the home pose, and the axis along its letter
            // with the ISO 841 sign of its side (either sign for the spindle).
            let world_from_joint = home_rotation(
                &robot.joints,
                if on_tool { &tool_path } else { &work_path },
                index,
            );
            if !world_from_joint.abs_diff_eq(crate::math::Rotation::IDENTITY, 1e-12) {
                return Err(fail(Some(joint), MachineErrorKind::JointFrame { axis }));
            }
            let found = joint.axis.xyz.0;
            let found_vector = joint_unit(joint);
            let expected = axis.unit() * if side == Side::Tool { 1.0 } else { -1.0 };
            // Along its letter, or tilted from it by at most AXIS_TILT (an identified machine's
            // axes, as `mtwin identify` writes them: µrad, not a modelling mistake).
            let direction_ok = (found_vector - expected).length() < AXIS_TILT
                || (axis == Axis::S && (found_vector + expected).length() < AXIS_TILT);
            if !direction_ok {
                return Err(fail(
                    Some(joint),
                    MachineErrorKind::AxisDirection {
                        axis,
                        found,
                        expected: expected.to_array(),
                    },
                ));
            }
            let limits = if joint.joint_type == JointType::Continuous {
                None
            } else {
                let (lower, upper) = (joint.limit.lower, joint.limit.upper);
                if !(lower.is_finite() && upper.is_finite() && lower < upper) {
                    return Err(fail(Some(joint), MachineErrorKind::Limits { axis }));
                }
                let (largest, limit) = match axis.is_linear() {
                    true => (LARGEST_MACHINE, "±100 m"),
                    false => (LARGEST_TURN, "±62.8 rad (ten turns)"),
                };
                if let Some(found) = largest_beyond(&[lower, upper], largest) {
                    return Err(fail(
                        Some(joint),
                        MachineErrorKind::Implausible {
                            element: format!("joint \"{axis}\" limit"),
                            found,
                            limit,
                        },
                    ));
                }
                Some((lower, upper))
            };
            axes.push(AxisInfo {
                axis,
                side,
                limits,
                joint_axis: found_vector,
                slot: 0,
            });
        }
        axes.sort_by_key(|info| info.axis);
        for (slot, info) in axes.iter_mut().enumerate() {
            info.slot = slot;
        }
        check_configuration(&axes)
            .map_err(|message| fail(None, MachineErrorKind::Configuration(message)))?;
        // ISO 841: Z is the spindle axis; the tool frame's z runs from the tip into the spindle.
        let tool_z = tool_path
            .iter()
            .fold(crate::math::Rotation::IDENTITY, |r, &i| {
                r * rotation_from_rpy(robot.joints[i].origin.rpy.0)
            })
            * Vector::Z;
        if (tool_z - Vector::Z).length() > AXIS_TILT {
            return Err(fail(
                None,
                MachineErrorKind::ToolAxis {
                    found: tool_z.to_array(),
                },
            ));
        }

        let branch = |path: &[usize]| -> Branch {
            let mut joints = Vec::new();
            let mut pending = Pose::IDENTITY;
            for &index in path {
                let joint = &robot.joints[index];
                pending *= joint_origin(joint);
                if joint.joint_type != JointType::Fixed {
                    let axis = single_letter(&joint.name).expect("checked above");
                    let slot = axes
                        .iter()
                        .position(|info| info.axis == axis)
                        .expect("listed");
                    joints.push(ChainJoint::new(pending, axis, joint_unit(joint), slot));
                    pending = Pose::IDENTITY;
                }
            }
            Branch {
                joints,
                end: pending,
                end_is_translation: pending.matrix3 == glam::DMat3::IDENTITY,
                end_is_identity: pending == Pose::IDENTITY,
            }
        };
        let mut bodies = Vec::with_capacity(robot.links.len());
        for link in &robot.links {
            let visuals = link
                .visual
                .iter()
                .map(|v| visual(v, &link.name))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|kind| MachineError {
                    file: file.to_string(),
                    line: line_of_element(text, "link", &link.name, 0),
                    kind,
                })?;
            // Up through fixed joints to the first moving one (or the root).
            let mut joint_from_link = Pose::IDENTITY;
            let mut moved_by = None;
            let mut unit = Vector::Z;
            let mut name = link.name.as_str();
            while let Some(&index) = parent_joint.get(name) {
                let joint = &robot.joints[index];
                if joint.joint_type != JointType::Fixed {
                    moved_by = single_letter(&joint.name);
                    unit = joint_unit(joint);
                    break;
                }
                joint_from_link = joint_origin(joint) * joint_from_link;
                name = joint.parent.link.as_str();
            }
            bodies.push(Body {
                link: link.name.clone(),
                moved_by,
                visuals,
                joint_from_link,
                unit,
            });
        }
        let (tool_branch, work_branch) = (branch(&tool_path), branch(&work_path));
        let rotary_joints = tool_branch
            .joints
            .iter()
            .chain(&work_branch.joints)
            .filter(|joint| !joint.axis.is_linear())
            .cloned()
            .collect();
        Ok(Machine {
            name: robot.name.clone(),
            tool_branch,
            work_branch,
            rotary_joints,
            axes,
            bodies,
        })
    }
}

/// The direction a URDF joint moves along or turns about, in its frame: its `<axis xyz>` made a
/// unit vector (the URDF specification asks for a normalised one but readers do not enforce
/// it; a tilted axis written by hand, `0 1e-4 -1`, is 5·10⁻⁹ long of unit, and `2 0 0` would
/// double every travel). Zero for a zero vector, which the direction check refuses.
fn joint_unit(joint: &urdf_rs::Joint) -> Vector {
    Vector::from_array(joint.axis.xyz.0).normalize_or_zero()
}

/// `parent_from_joint` of a URDF joint at zero motion.
fn joint_origin(joint: &urdf_rs::Joint) -> Pose {
    Pose::from_mat3_translation(
        rotation_from_rpy(joint.origin.rpy.0),
        Vector::from_array(joint.origin.xyz.0),
    )
}

/// The first of `values` whose magnitude is beyond `limit`, if any.
fn largest_beyond(values: &[Real], limit: Real) -> Option<Real> {
    values.iter().copied().find(|v| v.abs() > limit)
}

/// A URDF `<visual>` of `link`, its sizes checked.
fn visual(visual: &urdf_rs::Visual, link: &str) -> Result<Visual, MachineErrorKind> {
    use urdf_rs::Geometry;
    let bad = |found: String| MachineErrorKind::Geometry {
        link: link.to_string(),
        found,
    };
    let positive = |v: Real| v.is_finite() && v > 0.0;
    let shape = match &visual.geometry {
        Geometry::Box { size } if size.0.iter().all(|v| positive(*v)) => Shape::Box {
            size: Vector::from_array(size.0),
        },
        Geometry::Cylinder { radius, length } if positive(*radius) && positive(*length) => {
            Shape::Cylinder {
                radius: *radius,
                length: *length,
            }
        }
        Geometry::Capsule { radius, length } if positive(*radius) && positive(*length) => {
            Shape::Capsule {
                radius: *radius,
                length: *length,
            }
        }
        Geometry::Sphere { radius } if positive(*radius) => Shape::Sphere { radius: *radius },
        Geometry::Mesh { filename, scale } => {
            let scale = scale.as_ref().map_or([1.0; 3], |s| s.0);
            if !scale.iter().all(|v| positive(*v)) {
                return Err(bad(format!("mesh scale {scale:?}")));
            }
            Shape::Mesh {
                file: filename.clone(),
                scale: Vector::from_array(scale),
            }
        }
        other => return Err(bad(format!("{other:?}"))),
    };
    let origin = &visual.origin;
    if !origin
        .xyz
        .0
        .iter()
        .chain(&origin.rpy.0)
        .all(|v| v.is_finite())
    {
        return Err(bad(format!("origin {:?} {:?}", origin.xyz.0, origin.rpy.0)));
    }
    let sizes: Vec<Real> = match &shape {
        Shape::Box { size } => size.to_array().to_vec(),
        Shape::Cylinder { radius, length } | Shape::Capsule { radius, length } => {
            vec![*radius, *length]
        }
        Shape::Sphere { radius } => vec![*radius],
        Shape::Mesh { .. } => Vec::new(),
    };
    if let Some(found) = largest_beyond(&[&origin.xyz.0[..], &sizes].concat(), LARGEST_MACHINE) {
        return Err(MachineErrorKind::Implausible {
            element: format!("link \"{link}\" <visual>"),
            found,
            limit: "±100 m",
        });
    }
    Ok(Visual {
        link_from_shape: Pose::from_mat3_translation(
            rotation_from_rpy(origin.rpy.0),
            Vector::from_array(origin.xyz.0),
        ),
        shape,
    })
}

/// The rotation `world_from_joint` of joint `index` at the home pose (every axis at zero),
/// `path` being the joints from the root to it.
fn home_rotation(joints: &[urdf_rs::Joint], path: &[usize], index: usize) -> crate::math::Rotation {
    let mut rotation = crate::math::Rotation::IDENTITY;
    for &i in path {
        rotation *= rotation_from_rpy(joints[i].origin.rpy.0);
        if i == index {
            break;
        }
    }
    rotation
}

/// Exactly X, Y, Z; none or two of A, B, C; at most one spindle.
fn check_configuration(axes: &[AxisInfo]) -> Result<(), String> {
    let has = |axis: Axis| axes.iter().any(|info| info.axis == axis);
    let missing: Vec<String> = [Axis::X, Axis::Y, Axis::Z]
        .into_iter()
        .filter(|a| !has(*a))
        .map(|a| a.to_string())
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "linear axes {} are missing: mtwin models 3-axis and 5-axis machines with X, Y and Z",
            missing.join(", ")
        ));
    }
    let rotary = [Axis::A, Axis::B, Axis::C]
        .into_iter()
        .filter(|a| has(*a))
        .count();
    if rotary == 1 || rotary == 3 {
        return Err(format!(
            "{rotary} rotary axes: expected none (3-axis) or two of A, B, C (5-axis)"
        ));
    }
    Ok(())
}

/// The axis named by a one-letter joint name.
fn single_letter(name: &str) -> Option<Axis> {
    let mut chars = name.chars();
    match (chars.next(), chars.next()) {
        (Some(letter), None) => Axis::from_letter(letter),
        _ => None,
    }
}

/// The 1-based line of the `occurrence`-th (from 0) `<element …>` named `name`, its
/// attributes possibly spread over several lines.
fn line_of_element(text: &str, element: &str, name: &str, occurrence: usize) -> Option<usize> {
    let quoted = [format!("\"{name}\""), format!("'{name}'")];
    text.match_indices(&format!("<{element}"))
        .filter(|(start, _)| {
            let tag = &text[*start..];
            let tag = &tag[..tag.find('>').unwrap_or(tag.len())];
            tag.match_indices("name").any(|(at, _)| {
                let rest = tag[at + 4..].trim_start();
                rest.strip_prefix('=')
                    .map(str::trim_start)
                    .is_some_and(|value| quoted.iter().any(|q| value.starts_with(q.as_str())))
            })
        })
        .nth(occurrence)
        .map(|(start, _)| text[..start].matches('\n').count() + 1)
}

/// Where `text` stops being well-formed XML, if it does: the byte offset and what is wrong
/// (an unclosed element, a mismatched end tag, a truncated tag, …).
fn xml_problem(text: &str) -> Option<(usize, String)> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(text);
    reader.config_mut().check_end_names = true;
    let mut open: Vec<(String, usize)> = Vec::new();
    loop {
        let before = reader.buffer_position() as usize;
        match reader.read_event() {
            Ok(Event::Start(start)) => {
                let name = String::from_utf8_lossy(start.name().as_ref()).into_owned();
                open.push((name, before));
            }
            Ok(Event::End(_)) => {
                open.pop();
            }
            Ok(Event::Eof) => {
                return open.last().map(|(name, at)| {
                    (
                        text.len(),
                        format!(
                            "the document ends inside <{name}> (opened on line {})",
                            line_and_column(text, *at).0
                        ),
                    )
                });
            }
            Ok(_) => {}
            Err(e) => return Some((reader.error_position() as usize, e.to_string())),
        }
    }
}

/// The 1-based line and column (in characters) of byte `offset` of `text`.
fn line_and_column(text: &str, offset: usize) -> (usize, usize) {
    let mut end = offset.min(text.len());
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    let before = &text[..end];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}
