//! Rolling-bearing defect frequencies, to name an asynchronous line by the bearing part that
//! makes it.
//!
//! For a bearing whose inner ring turns with the shaft and whose outer ring stands still, with
//! `Z` rolling elements of diameter `d` on a pitch diameter `D` at contact angle `α`
//! (kinematics without slip; e.g. Harris, *Rolling Bearing Analysis*, ch. 8), in cycles per
//! revolution of the shaft (UPR):
//!
//! ```text
//! cage (FTF)                 ½ (1 − (d/D) cos α)
//! ball pass, outer (BPFO)    (Z/2) (1 − (d/D) cos α)
//! ball pass, inner (BPFI)    (Z/2) (1 + (d/D) cos α)
//! ball spin (BSF)            (D/2d) (1 − ((d/D) cos α)²)
//! ```
//!
//! A real bearing's cage slips behind this by up to a few per cent, so a line is matched within
//! 2 % of the frequency or one line spacing of the record, whichever is wider.

use crate::math::Real;

/// A bearing's geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bearing {
    /// Number of rolling elements.
    pub elements: usize,
    /// Rolling-element diameter (m).
    pub element_diameter: Real,
    /// Pitch diameter (m).
    pub pitch_diameter: Real,
    /// Contact angle (rad).
    pub contact_angle: Real,
}

/// Slip allowed between a measured line and a kinematic bearing frequency (relative).
const SLIP: Real = 0.02;

/// Why a bearing geometry is impossible.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum BearingError {
    /// Values that describe no bearing.
    #[error(
        "bearing geometry: {0} (needs at least 3 elements, 0 < element diameter < pitch diameter, contact angle in [0°, 90°))"
    )]
    Impossible(String),
}

impl Bearing {
    /// Checks the geometry.
    pub fn new(
        elements: usize,
        element_diameter: Real,
        pitch_diameter: Real,
        contact_angle: Real,
    ) -> Result<Bearing, BearingError> {
        let ok = elements >= 3
            && element_diameter.is_finite()
            && pitch_diameter.is_finite()
            && element_diameter > 0.0
            && element_diameter < pitch_diameter
            && (0.0..Real::to_radians(90.0)).contains(&contact_angle);
        if !ok {
            return Err(BearingError::Impossible(format!(
                "{elements} elements of {:.3} mm on {:.3} mm at {:.1}°",
                element_diameter * 1e3,
                pitch_diameter * 1e3,
                contact_angle.to_degrees()
            )));
        }
        Ok(Bearing {
            elements,
            element_diameter,
            pitch_diameter,
            contact_angle,
        })
    }

    /// The defect frequencies (UPR), each with its short and long name.
    pub fn frequencies(&self) -> [(&'static str, &'static str, Real); 4] {
        let ratio = self.element_diameter / self.pitch_diameter * self.contact_angle.cos();
        let z = self.elements as Real;
        [
            ("FTF", "cage (fundamental train)", 0.5 * (1.0 - ratio)),
            ("BPFO", "ball pass, outer race", 0.5 * z * (1.0 - ratio)),
            ("BPFI", "ball pass, inner race", 0.5 * z * (1.0 + ratio)),
            (
                "BSF",
                "ball spin",
                self.pitch_diameter / (2.0 * self.element_diameter) * (1.0 - ratio * ratio),
            ),
        ]
    }

    /// The bearing frequency a line at `per_revolution` matches, with its harmonic (1 for the
    /// frequency itself, up to 3): the closest within the slip or `spacing` (UPR).
    pub fn name(&self, per_revolution: Real, spacing: Real) -> Option<String> {
        self.frequencies()
            .iter()
            .flat_map(|&(short, long, f)| (1..=3).map(move |h| (short, long, h, h as Real * f)))
            .map(|(short, long, h, f)| (short, long, h, f, (per_revolution - f).abs()))
            .filter(|&(_, _, _, f, distance)| distance <= (SLIP * f).max(spacing))
            .min_by(|a, b| a.4.total_cmp(&b.4))
            .map(|(short, long, h, f, _)| {
                let times = if h == 1 {
                    String::new()
                } else {
                    format!("{h} × ")
                };
                format!("{times}{short} ({long}, {f:.3} UPR from the geometry)")
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_6205_bearing_has_its_catalogue_frequencies() {
        // SKF 6205: 9 balls of 7.94 mm on a 39.04 mm pitch, 0°: BPFO 3.585, BPFI 5.415,
        // FTF 0.398, BSF 2.357 × the shaft (vibration-analysis tables).
        let b = Bearing::new(9, 7.94e-3, 39.04e-3, 0.0).unwrap();
        let f = b.frequencies();
        assert!((f[0].2 - 0.398).abs() < 1e-3);
        assert!((f[1].2 - 3.585).abs() < 1e-3);
        assert!((f[2].2 - 5.415).abs() < 1e-3);
        assert!((f[3].2 - 2.357).abs() < 1e-3);
        assert!(b.name(3.57, 0.05).unwrap().starts_with("BPFO"));
        assert!(b.name(2.0 * 3.585, 0.05).unwrap().starts_with("2 × BPFO"));
        assert_eq!(b.name(1.7, 0.05), None);
        assert!(Bearing::new(9, 40e-3, 39e-3, 0.0).is_err());
    }
}
