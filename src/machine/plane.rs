//! The three planes of a circular test (ISO 230-4) and their angle and sense conventions.

use super::Axis;
use crate::math::Real;
use std::fmt;
use std::str::FromStr;

/// A plane of two linear axes, named first axis then second: `XY`, `YZ`, `ZX`.
///
/// The angle θ of a point about a centre is measured from the plane's **first** axis toward its
/// **second** (XY: from +X toward +Y; YZ: from +Y toward +Z; ZX: from +Z toward +X), so θ grows
/// counter-clockwise seen from the positive side of the plane's normal (+Z, +X, +Y): the
/// first × second axis. A point at angle θ and radius R sits at `R·cos θ` along the first axis
/// and `R·sin θ` along the second.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Plane {
    /// X then Y; normal +Z.
    XY,
    /// Y then Z; normal +X.
    YZ,
    /// Z then X; normal +Y.
    ZX,
}

impl Plane {
    /// All three, in the order ball-bar software tests them.
    pub const ALL: [Plane; 3] = [Plane::XY, Plane::YZ, Plane::ZX];

    /// The first axis (θ = 0 points along it).
    pub fn first(self) -> Axis {
        match self {
            Plane::XY => Axis::X,
            Plane::YZ => Axis::Y,
            Plane::ZX => Axis::Z,
        }
    }

    /// The second axis (θ = 90° points along it).
    pub fn second(self) -> Axis {
        match self {
            Plane::XY => Axis::Y,
            Plane::YZ => Axis::Z,
            Plane::ZX => Axis::X,
        }
    }

    /// The axis normal to the plane (the one held during the test).
    pub fn normal(self) -> Axis {
        match self {
            Plane::XY => Axis::Z,
            Plane::YZ => Axis::X,
            Plane::ZX => Axis::Y,
        }
    }

    /// Lower-case name for file names and JSON (`xy`, `yz`, `zx`).
    pub fn lower(self) -> &'static str {
        match self {
            Plane::XY => "xy",
            Plane::YZ => "yz",
            Plane::ZX => "zx",
        }
    }

    /// Where the upper half of a vertical plane starts (rad): the half on the +Z side of the
    /// centre, which a partial arc keeps to (the centre cup stands on the table). YZ: θ from 0
    /// to 180°; ZX: from 270° through 0 to 90°; XY (horizontal): 0.
    pub fn upper_half_start(self) -> Real {
        match self {
            Plane::XY | Plane::YZ => 0.0,
            Plane::ZX => -std::f64::consts::FRAC_PI_2,
        }
    }
}

impl fmt::Display for Plane {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Plane::XY => "XY",
            Plane::YZ => "YZ",
            Plane::ZX => "ZX",
        })
    }
}

impl FromStr for Plane {
    type Err = String;

    /// `XY`, `YZ` or `ZX` (either case); the reversed names (`YX`, `ZY`, `XZ`) are refused, as
    /// they would flip the angle and the sense of rotation.
    fn from_str(text: &str) -> Result<Plane, String> {
        match text.to_ascii_uppercase().as_str() {
            "XY" => Ok(Plane::XY),
            "YZ" => Ok(Plane::YZ),
            "ZX" => Ok(Plane::ZX),
            "YX" | "ZY" | "XZ" => Err(format!(
                "plane \"{text}\": name it first axis then second as XY, YZ or ZX (angles run from the first toward the second)"
            )),
            _ => Err(format!("plane \"{text}\": expected XY, YZ or ZX")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_normal_is_the_first_axis_cross_the_second() {
        for plane in Plane::ALL {
            let normal = plane.first().unit().cross(plane.second().unit());
            assert_eq!(normal, plane.normal().unit(), "{plane}");
        }
    }

    #[test]
    fn names_round_trip_and_reversed_names_are_refused() {
        for plane in Plane::ALL {
            assert_eq!(plane.to_string().parse::<Plane>(), Ok(plane));
            assert_eq!(plane.lower().parse::<Plane>(), Ok(plane));
        }
        assert!("XZ".parse::<Plane>().unwrap_err().contains("ZX"));
        assert!("XQ".parse::<Plane>().is_err());
    }
}
