//! Contact geometry: where a stylus ball, moving in a straight line, first touches an artefact.
//!
//! The stylus ball (radius `r`) starts with its centre at `start` and moves along a unit
//! `direction` ([`Approach`]). A [`Touch`] is the travel of the centre at first contact and the
//! contact normal (the artefact's outward surface normal at the contact point, pointing from the
//! artefact toward the ball centre), so the contact point is `centre − r·normal`.
//!
//! Analytic artefacts are solved in closed form: a ray of the ball centre against the artefact
//! dilated by `r` (exact to rounding, a few nanoseconds a touch). Meshes go through parry's
//! shape cast of a ball against a triangle mesh (GJK; see [`mesh`]).
//!
//! | file | owns |
//! |---|---|
//! | `mod.rs` | [`Approach`], [`Touch`], [`ContactError`], the [`Artefact`] trait |
//! | `quadratic.rs` | the entry and exit roots of a ray against a dilated quadric, without cancellation |
//! | [`sphere`] | [`Sphere`] (touched from outside) and [`BallPlate`] (a grid of spheres) |
//! | [`plane`] | [`HalfSpace`] (a flat face) |
//! | [`cylinder`] | [`Cylinder`]: a plug touched from outside, a bore (ring gauge) from inside |
//! | [`mesh`] | [`Mesh`]: STL and OBJ readers, the closedness check, the parry shape cast |
//!
//! Frames: every vector of one query is in the same frame (the workpiece frame in the probe);
//! lengths are metres.

use crate::math::{Real, Vector};

pub mod cylinder;
pub mod mesh;
pub mod plane;
mod quadratic;
pub mod sphere;

pub use cylinder::{Cylinder, CylinderSide};
pub use mesh::{Mesh, MeshError};
pub use plane::HalfSpace;
pub use sphere::{BallPlate, Sphere};

/// A stylus-ball motion: the centre starts at `start` and moves along a unit `direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approach {
    start: Vector,
    direction: Vector,
}

impl Approach {
    /// The motion from `start` along `direction` (normalised here); a direction of zero length
    /// or with a component that is not finite, or a start that is not finite, is an error.
    pub fn new(start: Vector, direction: Vector) -> Result<Approach, ContactError> {
        if !start.is_finite() {
            return Err(ContactError::BadStart);
        }
        let length = direction.length();
        if !(length.is_finite() && length > 1e-300) {
            return Err(ContactError::BadDirection {
                direction: direction.to_array(),
            });
        }
        Ok(Approach {
            start,
            direction: direction / length,
        })
    }

    /// Where the ball centre starts (m).
    pub fn start(&self) -> Vector {
        self.start
    }

    /// The unit direction of motion.
    pub fn direction(&self) -> Vector {
        self.direction
    }

    /// The ball centre after `travel` (m).
    pub fn at(&self, travel: Real) -> Vector {
        self.start + self.direction * travel
    }
}

/// The first contact of a moving stylus ball with an artefact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Touch {
    /// Travel of the ball centre from the start to the contact (m, ≥ 0).
    pub travel: Real,
    /// The artefact's outward unit normal at the contact point, pointing toward the ball centre
    /// (for a bore: toward its axis).
    pub normal: Vector,
}

impl Touch {
    /// The contact point on the artefact's surface for a ball of radius `tip_radius` on
    /// `approach`.
    pub fn point(&self, approach: &Approach, tip_radius: Real) -> Vector {
        approach.at(self.travel) - self.normal * tip_radius
    }
}

/// A contact query that cannot be answered: bad input, not a miss (a miss is `Ok(None)`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ContactError {
    /// The approach direction has zero length or is not finite.
    #[error("the approach direction ({}, {}, {}) has zero length or is not finite", .direction[0], .direction[1], .direction[2])]
    BadDirection {
        /// The direction as given.
        direction: [Real; 3],
    },
    /// The start point is not finite.
    #[error("the approach start point is not finite")]
    BadStart,
    /// The stylus radius is negative or not finite.
    #[error("the stylus radius {0} m must be finite and ≥ 0")]
    BadRadius(Real),
    /// The maximum travel is not positive and finite.
    #[error("the maximum travel {0} m must be finite and positive")]
    BadTravel(Real),
    /// The stylus ball already overlaps the artefact where it starts.
    #[error("the stylus ball already overlaps the artefact at its start point")]
    StartsInContact,
    /// The geometry library could not answer the query.
    #[error("the shape cast failed: {0}")]
    Unsupported(String),
}

/// An artefact a stylus ball can touch.
pub trait Artefact {
    /// The first contact of a ball of radius `tip_radius` moving along `approach` within
    /// `max_travel` (m); `None` when it misses within that travel.
    fn touch(
        &self,
        tip_radius: Real,
        approach: &Approach,
        max_travel: Real,
    ) -> Result<Option<Touch>, ContactError>;
}

/// Checks the radius and travel of a query.
pub(crate) fn check_query(tip_radius: Real, max_travel: Real) -> Result<(), ContactError> {
    if !(tip_radius.is_finite() && tip_radius >= 0.0) {
        return Err(ContactError::BadRadius(tip_radius));
    }
    if !(max_travel.is_finite() && max_travel > 0.0) {
        return Err(ContactError::BadTravel(max_travel));
    }
    Ok(())
}

/// `Some(touch)` when `travel` is within `max_travel`, else `None`.
pub(crate) fn within(travel: Real, normal: Vector, max_travel: Real) -> Option<Touch> {
    (travel <= max_travel).then_some(Touch { travel, normal })
}
