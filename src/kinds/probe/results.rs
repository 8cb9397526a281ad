//! What the evaluation of a `probe` table finds per feature: a sphere's fit ([`SphereResult`]),
//! a ring's ([`RingResult`]), a ball-plate placement's centre distances ([`PlateResult`]) and a
//! mesh workpiece's surface points ([`SurfacePoint`]); gathered in
//! [`ProbeEvaluation`](super::analysis::ProbeEvaluation).

use super::fit::{CircleFit, SphereFit};
use super::table::RowKey;
use crate::math::{Real, Vector};

/// A sphere feature's fit.
#[derive(Clone, Debug, PartialEq)]
pub struct SphereResult {
    /// Cycle, feature, angles, calibration.
    pub key: RowKey,
    /// The fit of the stylus-ball centres.
    pub fit: SphereFit,
    /// The artefact's radius as measured (fit − stylus radius, m).
    pub radius: Real,
}

impl SphereResult {
    /// The fitted centre (axis coordinates, m).
    pub fn centre(&self) -> Vector {
        Vector::from_array(self.fit.centre)
    }

    /// Measured − calibrated radius (m), when calibrated.
    pub fn radius_error(&self) -> Option<Real> {
        self.key.calibrated_diameter.map(|d| self.radius - d / 2.0)
    }

    /// ISO 10360-5 P_FTU (the range of the 25 radii), for a 25-point feature.
    pub fn p_ftu(&self) -> Option<Real> {
        (self.fit.residuals.len() == 25).then(|| self.fit.form())
    }
}

/// A ring feature's fit, in the plane across the approach vectors.
#[derive(Clone, Debug, PartialEq)]
pub struct RingResult {
    /// Cycle, feature, angles, calibration.
    pub key: RowKey,
    /// The fit of the stylus-ball centres in the plane.
    pub fit: CircleFit,
    /// Each point's angle in the plane (rad, from the plane's first axis), in fit order.
    pub angles: Vec<Real>,
    /// The centre (axis coordinates, m).
    pub centre: Vector,
    /// The diameter as measured (m).
    pub diameter: Real,
    /// Whether it is a bore (approaches outward) rather than a plug.
    pub bore: bool,
}

impl RingResult {
    /// Measured − calibrated diameter (m), when calibrated.
    pub fn diameter_error(&self) -> Option<Real> {
        self.key.calibrated_diameter.map(|d| self.diameter - d)
    }
}

/// One centre distance of a ball plate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceError {
    /// The two features (balls).
    pub balls: (usize, usize),
    /// The calibrated distance (m).
    pub calibrated: Real,
    /// The measured distance (m).
    pub measured: Real,
}

/// A ball-plate placement's centre distances.
#[derive(Clone, Debug, PartialEq)]
pub struct PlateResult {
    /// The cycle.
    pub cycle: usize,
    /// Every pair of calibrated balls.
    pub distances: Vec<DistanceError>,
}

impl PlateResult {
    /// The largest |measured − calibrated| (m).
    pub fn max_abs_error(&self) -> Real {
        self.distances
            .iter()
            .map(|d| (d.measured - d.calibrated).abs())
            .fold(0.0, Real::max)
    }

    /// The RMS of measured − calibrated (m).
    pub fn rms_error(&self) -> Real {
        let n = self.distances.len().max(1) as Real;
        (self
            .distances
            .iter()
            .map(|d| (d.measured - d.calibrated).powi(2))
            .sum::<Real>()
            / n)
            .sqrt()
    }
}

/// A point on a mesh workpiece as the controller reports it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Cycle, feature.
    pub key: RowKey,
    /// The point's number.
    pub point: usize,
    /// Latched centre + stylus radius along the approach (axis coordinates, m).
    pub surface: Vector,
}
