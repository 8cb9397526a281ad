//! The ISO 230-1 names of error parameters ([`ParameterName`]: component, location and tool
//! errors, see the module doc's "Names") and the six motion components ([`Motion`]).

use crate::machine::Axis;
use std::fmt;
use std::str::FromStr;

/// One of the six motion components: translation along or rotation about x, y, z.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Motion {
    /// Translation along x.
    X,
    /// Translation along y.
    Y,
    /// Translation along z.
    Z,
    /// Rotation about x.
    A,
    /// Rotation about y.
    B,
    /// Rotation about z.
    C,
}

impl Motion {
    /// The six, in twist order.
    pub const ALL: [Motion; 6] = [
        Motion::X,
        Motion::Y,
        Motion::Z,
        Motion::A,
        Motion::B,
        Motion::C,
    ];

    /// Index in a twist (δx, δy, δz, εx, εy, εz).
    pub fn index(self) -> usize {
        self as usize
    }

    /// Whether it is a translation (value in m) rather than a rotation (rad).
    pub fn is_translation(self) -> bool {
        self.index() < 3
    }

    fn letter(self) -> char {
        ['X', 'Y', 'Z', 'A', 'B', 'C'][self.index()]
    }

    fn from_letter(letter: char) -> Option<Motion> {
        Motion::ALL.into_iter().find(|m| m.letter() == letter)
    }
}

/// The ISO 230-1 name of an error parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ParameterName {
    /// `E<motion><axis>`: component error (error motion) of an axis, a function of its position.
    Component {
        /// Direction of the error.
        motion: Motion,
        /// The moving axis.
        axis: Axis,
    },
    /// `E<motion>0<axis>`: location error of a rotary axis or squareness of a linear axis.
    Location {
        /// Direction of the error.
        motion: Motion,
        /// The axis.
        axis: Axis,
    },
    /// `E<motion>T`: tool-tip offset (X, Y) or tool length (Z) error in the tool frame.
    Tool {
        /// Direction of the error.
        motion: Motion,
    },
}

impl ParameterName {
    /// The motion component it acts on.
    pub fn motion(self) -> Motion {
        match self {
            ParameterName::Component { motion, .. }
            | ParameterName::Location { motion, .. }
            | ParameterName::Tool { motion } => motion,
        }
    }

    /// The positioning error of `axis` (`EXX`, `EYY`, `EZZ`, `EAA`, `EBB`, `ECC`): its motion
    /// along or about the axis's own direction; none for the spindle.
    pub fn positioning(axis: Axis) -> Option<ParameterName> {
        let motion = match axis {
            Axis::X => Motion::X,
            Axis::Y => Motion::Y,
            Axis::Z => Motion::Z,
            Axis::A => Motion::A,
            Axis::B => Motion::B,
            Axis::C => Motion::C,
            Axis::S => return None,
        };
        Some(ParameterName::Component { motion, axis })
    }

    /// The axis it belongs to (`None` for tool errors).
    pub fn axis(self) -> Option<Axis> {
        match self {
            ParameterName::Component { axis, .. } | ParameterName::Location { axis, .. } => {
                Some(axis)
            }
            ParameterName::Tool { .. } => None,
        }
    }

    /// Unit in files: `um` for translations, `urad` for rotations.
    pub fn file_unit(self) -> &'static str {
        if self.motion().is_translation() {
            "um"
        } else {
            "urad"
        }
    }

    /// Whether this name is a parameter at all (independent of the machine): tool errors are
    /// translations; a rotary axis has no location error along itself; a linear axis's only
    /// location errors are the squareness errors EC0Y, EB0Z, EA0Z.
    pub(super) fn check(self) -> Result<(), String> {
        match self {
            ParameterName::Tool { motion } if !motion.is_translation() => {
                Err("tool errors are translations: EXT, EYT, EZT".to_string())
            }
            ParameterName::Location { motion, axis } if axis.is_linear() => {
                let squareness = matches!(
                    (motion, axis),
                    (Motion::C, Axis::Y) | (Motion::B, Axis::Z) | (Motion::A, Axis::Z)
                );
                if squareness {
                    Ok(())
                } else {
                    Err("the location errors of linear axes are the squareness errors EC0Y, EB0Z and EA0Z \
                         (X is the reference direction and X-Y the reference plane)".to_string())
                }
            }
            ParameterName::Location { motion, axis }
                if motion.is_translation() && motion.index() == axis.coordinate() =>
            {
                Err(
                    "the position of a rotary axis along itself is not a location error"
                        .to_string(),
                )
            }
            ParameterName::Location { axis: Axis::S, .. } => Err(
                "the spindle has component errors (error motions), not location errors".to_string(),
            ),
            _ => Ok(()),
        }
    }
}

impl fmt::Display for ParameterName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParameterName::Component { motion, axis } => {
                write!(f, "E{}{}", motion.letter(), axis.letter())
            }
            ParameterName::Location { motion, axis } => {
                write!(f, "E{}0{}", motion.letter(), axis.letter())
            }
            ParameterName::Tool { motion } => write!(f, "E{}T", motion.letter()),
        }
    }
}

impl ParameterName {
    /// Every valid name.
    pub fn all() -> Vec<ParameterName> {
        let mut names = Vec::new();
        for motion in Motion::ALL {
            names.push(ParameterName::Tool { motion });
            for axis in Axis::ALL {
                names.push(ParameterName::Component { motion, axis });
                names.push(ParameterName::Location { motion, axis });
            }
        }
        names.retain(|n| n.check().is_ok());
        names
    }

    /// The valid name one keystroke from `text` (a letter replaced, added or dropped, or any
    /// case), preferring a replacement (`ECOY` → `EC0Y`); none when it is not unique.
    fn nearest(text: &str) -> Option<ParameterName> {
        let text: Vec<char> = text.to_ascii_uppercase().chars().collect();
        let names = ParameterName::all();
        // 0: the name in other case; 1: one letter replaced; 2: one added or dropped.
        let near = |stage: usize| -> Vec<ParameterName> {
            names
                .iter()
                .copied()
                .filter(|n| {
                    let name: Vec<char> = n.to_string().chars().collect();
                    if stage < 2 {
                        name.len() == text.len()
                            && name.iter().zip(&text).filter(|(a, b)| a != b).count() == stage
                    } else {
                        let (long, short) = if name.len() > text.len() {
                            (&name, &text)
                        } else {
                            (&text, &name)
                        };
                        long.len() == short.len() + 1
                            && (0..long.len()).any(|skip| {
                                long.iter()
                                    .enumerate()
                                    .filter(|(i, _)| *i != skip)
                                    .map(|(_, c)| c)
                                    .eq(short.iter())
                            })
                    }
                })
                .collect()
        };
        (0..3)
            .map(near)
            .find(|found| !found.is_empty())
            .and_then(|found| (found.len() == 1).then(|| found[0]))
    }
}

impl FromStr for ParameterName {
    type Err = String;

    fn from_str(text: &str) -> Result<ParameterName, String> {
        let unknown = || {
            let mut message = "not an error parameter: expected a component error such as EXX or \
                 ECC, a location error such as EX0C or EC0Y, or a tool error EXT, EYT, EZT"
                .to_string();
            if let Some(near) = ParameterName::nearest(text) {
                message += &format!("; did you mean {near}?");
            }
            message
        };
        let chars: Vec<char> = text.chars().collect();
        let name = match chars[..] {
            ['E', m, 'T'] => ParameterName::Tool {
                motion: Motion::from_letter(m).ok_or_else(unknown)?,
            },
            ['E', m, a] => ParameterName::Component {
                motion: Motion::from_letter(m).ok_or_else(unknown)?,
                axis: Axis::from_letter(a).ok_or_else(unknown)?,
            },
            ['E', m, '0', a] => ParameterName::Location {
                motion: Motion::from_letter(m).ok_or_else(unknown)?,
                axis: Axis::from_letter(a).ok_or_else(unknown)?,
            },
            _ => return Err(unknown()),
        };
        name.check()?;
        Ok(name)
    }
}
