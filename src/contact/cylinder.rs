//! A cylinder of infinite length: a plug touched from outside, or a bore (a ring gauge)
//! touched from inside. The end faces are not modelled (a simplification: a touch is always on
//! the cylindrical face).

use super::quadratic::{coefficients, entry, exit};
use super::{Approach, Artefact, ContactError, Touch, check_query, within};
use crate::math::{Real, Vector};

/// Which side of the cylindrical face holds the material.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CylinderSide {
    /// A plug (a shaft): material inside, the stylus outside.
    Plug,
    /// A bore (a ring gauge): material outside, the stylus inside.
    Bore,
}

/// A cylinder about the line through `point` along unit `axis`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    /// A point of the axis (m).
    pub point: Vector,
    /// The unit axis direction.
    pub axis: Vector,
    /// The radius of the face (m).
    pub radius: Real,
    /// Plug or bore.
    pub side: CylinderSide,
}

impl Artefact for Cylinder {
    /// The components of the start and direction across the axis against the face's radius
    /// dilated by `r` (plug: `R + r`, entry root) or eroded by it (bore: `R − r`, exit root); the
    /// normal is radial, outward for a plug and toward the axis for a bore.
    fn touch(
        &self,
        tip_radius: Real,
        approach: &Approach,
        max_travel: Real,
    ) -> Result<Option<Touch>, ContactError> {
        check_query(tip_radius, max_travel)?;
        let across = |v: Vector| v - self.axis * self.axis.dot(v);
        let m = across(approach.start() - self.point);
        let e = across(approach.direction());
        let (rho, sign) = match self.side {
            CylinderSide::Plug => (self.radius + tip_radius, 1.0),
            CylinderSide::Bore => (self.radius - tip_radius, -1.0),
        };
        if rho <= 0.0 {
            return Err(ContactError::StartsInContact); // the ball does not fit the bore
        }
        let (a, b, c) = coefficients(m, e, rho);
        let root = match self.side {
            CylinderSide::Plug if c < 0.0 => return Err(ContactError::StartsInContact),
            CylinderSide::Bore if c > 0.0 => return Err(ContactError::StartsInContact),
            CylinderSide::Plug => entry(a, b, c),
            CylinderSide::Bore => exit(a, b, c),
        };
        Ok(root.and_then(|t| {
            let normal = (m + e * t) / rho * sign;
            within(t, normal, max_travel)
        }))
    }
}
