//! One spindle-analyser record in memory: the samples, probe by probe, and where each probe
//! looks. SI inside (m, rad, s, rad/s); the `spindle` table ([`super::table`]) holds the same in
//! file units.
//!
//! # Frames and signs
//!
//! The **axis frame** has z along the nominal axis of rotation (positive by the right-hand rule
//! of the axis's positive rotation), x and y across it, its origin at the artefact's reference
//! point on the axis (a sphere's centre, a cylinder's lower probed section). For a fixed
//! sensitive direction it is fixed to the stator; for a rotating sensitive direction it turns
//! with the rotor and coincides with the stator frame at angle 0.
//!
//! A probe's [`SpindleProbe::direction`] is the unit vector along which a motion of the
//! artefact, relative to the probe, **increases** the reading: ISO 230-7 (A.7.2) counts motion
//! of the artefact *away from* the probe as positive, so a probe sitting on the +x side of a
//! sphere, facing −x, has direction −x. A reading is then `direction · d` for an artefact
//! displacement `d` at the probe's sensed point, plus the artefact's form and the probe's own
//! errors.

use crate::machine::Axis;
use crate::math::Real;

/// Whether the sensitive direction stays with the stator or turns with the rotor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sensing {
    /// Probes fixed, artefact turning (turning, ISO 230-7 §5.4): directions in the stator frame.
    Fixed,
    /// Probe turning with the axis, artefact fixed — or probes fixed and the analysis rotating
    /// their X/Y signals into the rotor frame (ISO 230-7 §5.3, formula (1)): directions in the
    /// rotor frame at angle 0.
    Rotating,
}

/// One displacement probe of the nest.
#[derive(Clone, Debug, PartialEq)]
pub struct SpindleProbe {
    /// Its name (the table's column is `<name>_um`).
    pub name: String,
    /// Unit vector, axis frame: artefact motion along it increases the reading.
    pub direction: [Real; 3],
    /// The nominal sensed point on the artefact's surface, axis frame (m): radius as x, y and
    /// height along the axis as z.
    pub position: [Real; 3],
    /// Frame of `direction` and `position`.
    pub sensing: Sensing,
}

/// One record: equal-length revolutions sampled on the once-per-revolution index.
///
/// Sample `i` belongs to revolution `revolution[i]` at angle `angle[i]`; every per-sample vector
/// has the same length, and `readings[p][i]` is probe `p`'s reading at sample `i`.
#[derive(Clone, Debug, PartialEq)]
pub struct SpindleRecord {
    /// The axis of rotation measured (`S`, `C`, `A` or `B`).
    pub axis: Axis,
    /// The probes, in column order.
    pub probes: Vec<SpindleProbe>,
    /// Set-up name of each sample (`""` when the table has no `setup` column): reversal and
    /// multi-step records hold several set-ups.
    pub setup: Vec<String>,
    /// Revolution index of each sample, from 0 within each set-up and speed.
    pub revolution: Vec<usize>,
    /// The axis angle at each sample (rad), from the index mark, within `[0, 2π)`.
    pub angle: Vec<Real>,
    /// Time of each sample (s).
    pub time: Vec<Real>,
    /// Commanded speed at each sample (rad/s, positive for positive rotation).
    pub speed: Vec<Real>,
    /// Readings (m), one vector per probe.
    pub readings: Vec<Vec<Real>>,
}

impl SpindleRecord {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.angle.len()
    }

    /// Whether the record holds no sample.
    pub fn is_empty(&self) -> bool {
        self.angle.is_empty()
    }

    /// The index of the probe named `name`.
    pub fn probe(&self, name: &str) -> Option<usize> {
        self.probes.iter().position(|p| p.name == name)
    }
}
