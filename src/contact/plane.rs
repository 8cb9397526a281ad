//! A flat face: the half-space of material below a plane.

use super::{Approach, Artefact, ContactError, Touch, check_query, within};
use crate::math::{Real, Vector};

/// The material `{x : normal·(x − point) ≤ 0}` under a flat face; `normal` is the face's outward
/// unit normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfSpace {
    /// A point of the face (m).
    pub point: Vector,
    /// The outward unit normal.
    pub normal: Vector,
}

impl Artefact for HalfSpace {
    /// The ray of the ball centre against the face lifted by `r`: `t = h / (−n·d)` with `h` the
    /// height of the centre above the lifted face; `None` when moving parallel to it or away.
    fn touch(
        &self,
        tip_radius: Real,
        approach: &Approach,
        max_travel: Real,
    ) -> Result<Option<Touch>, ContactError> {
        check_query(tip_radius, max_travel)?;
        let height = self.normal.dot(approach.start() - self.point) - tip_radius;
        if height < 0.0 {
            return Err(ContactError::StartsInContact);
        }
        let closing = -self.normal.dot(approach.direction());
        if closing <= 0.0 {
            return Ok(None);
        }
        Ok(within(height / closing, self.normal, max_travel))
    }
}
