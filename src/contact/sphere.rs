//! Spheres touched from outside: a calibration sphere, and a ball plate (a grid of spheres, the
//! first one the stylus meets).

use super::quadratic::{coefficients, entry};
use super::{Approach, Artefact, ContactError, Touch, check_query, within};
use crate::math::{Real, Vector};

/// A sphere (a calibration sphere, a ball of a ball plate), touched from outside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Its centre (m).
    pub centre: Vector,
    /// Its radius (m).
    pub radius: Real,
}

impl Artefact for Sphere {
    /// The ray of the ball centre against the sphere of radius `R + r`: the entry root of
    /// `|s − c + t·d|² = (R + r)²`, the normal along the centre-to-centre line.
    fn touch(
        &self,
        tip_radius: Real,
        approach: &Approach,
        max_travel: Real,
    ) -> Result<Option<Touch>, ContactError> {
        check_query(tip_radius, max_travel)?;
        let m = approach.start() - self.centre;
        let rho = self.radius + tip_radius;
        let (a, b, c) = coefficients(m, approach.direction(), rho);
        if c < 0.0 {
            return Err(ContactError::StartsInContact);
        }
        Ok(entry(a, b, c).and_then(|t| {
            let normal = (approach.at(t) - self.centre) / rho;
            within(t, normal, max_travel)
        }))
    }
}

/// A ball plate: spheres of one radius at given centres (the plate itself and the balls' stems
/// are not modelled: a simplification, the stylus touches balls only).
#[derive(Clone, Debug, PartialEq)]
pub struct BallPlate {
    /// The ball radius (m).
    pub radius: Real,
    /// The ball centres (m), in the order the plate numbers them.
    pub centres: Vec<Vector>,
}

impl BallPlate {
    /// A `rows × columns` grid of balls at `pitch` (m) from `origin` (ball 0): ball `(i, j)` (row
    /// `i`, column `j`) at `origin + along_row·pitch·j + across_rows·pitch·i` (unit vectors),
    /// numbered row by row (index `i·columns + j`).
    pub fn grid(
        origin: Vector,
        along_row: Vector,
        across_rows: Vector,
        pitch: Real,
        rows: usize,
        columns: usize,
        radius: Real,
    ) -> BallPlate {
        let centres = (0..rows)
            .flat_map(|i| {
                (0..columns).map(move |j| {
                    origin + across_rows * (pitch * i as Real) + along_row * (pitch * j as Real)
                })
            })
            .collect();
        BallPlate { radius, centres }
    }

    /// The first contact with any ball and that ball's index.
    pub fn touch_indexed(
        &self,
        tip_radius: Real,
        approach: &Approach,
        max_travel: Real,
    ) -> Result<Option<(usize, Touch)>, ContactError> {
        let mut first: Option<(usize, Touch)> = None;
        for (index, &centre) in self.centres.iter().enumerate() {
            let sphere = Sphere {
                centre,
                radius: self.radius,
            };
            if let Some(touch) = sphere.touch(tip_radius, approach, max_travel)?
                && first.is_none_or(|(_, best)| touch.travel < best.travel)
            {
                first = Some((index, touch));
            }
        }
        Ok(first)
    }
}

impl Artefact for BallPlate {
    /// The first ball met (see [`BallPlate::touch_indexed`]).
    fn touch(
        &self,
        tip_radius: Real,
        approach: &Approach,
        max_travel: Real,
    ) -> Result<Option<Touch>, ContactError> {
        Ok(self
            .touch_indexed(tip_radius, approach, max_travel)?
            .map(|(_, t)| t))
    }
}
