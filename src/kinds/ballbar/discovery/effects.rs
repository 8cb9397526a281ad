//! The effects ball-bar discovery can add to the base model ([`BallbarEffect`]): their
//! diagnostic terms, axes, names and likely causes.

use crate::kinds::ballbar::iso230_4::Term;
use crate::machine::{Axis, Plane};

/// The effects ball-bar discovery can add to the base model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum BallbarEffect {
    /// Different lags of p and q: σ·(v·Δτ/2)·sin 2θ.
    ServoMismatch,
    /// Lost motion of p: +σ·sgn(sin θ)·cos θ·b_p/2.
    BacklashP,
    /// Lost motion of q: −σ·sgn(cos θ)·sin θ·b_q/2.
    BacklashQ,
    /// The p carriage shifting along q on reversal: +σ·|sin θ|·l_p/2.
    LateralPlayP,
    /// The q carriage shifting along p on reversal: −σ·|cos θ|·l_q/2.
    LateralPlayQ,
    /// A decaying bump after each reversal of p; decay searched.
    ReversalSpikeP,
    /// A decaying bump after each reversal of q; decay searched.
    ReversalSpikeQ,
    /// A bow of p along q: S_p·sin³θ.
    StraightnessP,
    /// A bow of q along p: S_q·cos³θ.
    StraightnessQ,
    /// A periodic error of p along p; period searched.
    CyclicP,
    /// A periodic error of q along q; period searched.
    CyclicQ,
    /// k lobes per turn at fixed angles: a·sin kθ + b·cos kθ, k ≥ 3 searched.
    Lobes,
    /// The radius changing linearly with time (rate).
    RadiusDrift,
    /// The ccw trace's radius minus the cw trace's: σ·Δ/2.
    SenseRadius,
}

/// Effect names that carry an axis letter: stem, then the name for X, Y and Z.
const LETTERED: [[&str; 3]; 5] = [
    ["backlash_x", "backlash_y", "backlash_z"],
    ["lateral_play_x", "lateral_play_y", "lateral_play_z"],
    ["reversal_spike_x", "reversal_spike_y", "reversal_spike_z"],
    ["straightness_x", "straightness_y", "straightness_z"],
    ["cyclic_x", "cyclic_y", "cyclic_z"],
];

impl BallbarEffect {
    /// Every effect, in the order they are reported.
    pub const ALL: [BallbarEffect; 14] = [
        BallbarEffect::ServoMismatch,
        BallbarEffect::BacklashP,
        BallbarEffect::BacklashQ,
        BallbarEffect::LateralPlayP,
        BallbarEffect::LateralPlayQ,
        BallbarEffect::ReversalSpikeP,
        BallbarEffect::ReversalSpikeQ,
        BallbarEffect::StraightnessP,
        BallbarEffect::StraightnessQ,
        BallbarEffect::CyclicP,
        BallbarEffect::CyclicQ,
        BallbarEffect::Lobes,
        BallbarEffect::RadiusDrift,
        BallbarEffect::SenseRadius,
    ];

    /// The model term it adds.
    pub fn term(self) -> Term {
        match self {
            BallbarEffect::ServoMismatch => Term::ServoMismatch,
            BallbarEffect::BacklashP => Term::BacklashP,
            BallbarEffect::BacklashQ => Term::BacklashQ,
            BallbarEffect::LateralPlayP => Term::LateralPlayP,
            BallbarEffect::LateralPlayQ => Term::LateralPlayQ,
            BallbarEffect::ReversalSpikeP => Term::ReversalSpikeP,
            BallbarEffect::ReversalSpikeQ => Term::ReversalSpikeQ,
            BallbarEffect::StraightnessP => Term::StraightnessP,
            BallbarEffect::StraightnessQ => Term::StraightnessQ,
            BallbarEffect::CyclicP => Term::CyclicP,
            BallbarEffect::CyclicQ => Term::CyclicQ,
            BallbarEffect::Lobes => Term::Lobes,
            BallbarEffect::RadiusDrift => Term::RadiusDrift,
            BallbarEffect::SenseRadius => Term::SenseRadius,
        }
    }

    /// The axis it belongs to in `plane`, if it belongs to one.
    pub fn axis(self, plane: Plane) -> Option<Axis> {
        match self {
            BallbarEffect::BacklashP
            | BallbarEffect::LateralPlayP
            | BallbarEffect::ReversalSpikeP
            | BallbarEffect::StraightnessP
            | BallbarEffect::CyclicP => Some(plane.first()),
            BallbarEffect::BacklashQ
            | BallbarEffect::LateralPlayQ
            | BallbarEffect::ReversalSpikeQ
            | BallbarEffect::StraightnessQ
            | BallbarEffect::CyclicQ => Some(plane.second()),
            _ => None,
        }
    }

    /// The stable identifier in `plane`, with the axis letter where the effect has an axis
    /// (`backlash_y`, `servo_mismatch`).
    pub fn id(self, plane: Plane) -> &'static str {
        let stem = match self {
            BallbarEffect::BacklashP | BallbarEffect::BacklashQ => 0,
            BallbarEffect::LateralPlayP | BallbarEffect::LateralPlayQ => 1,
            BallbarEffect::ReversalSpikeP | BallbarEffect::ReversalSpikeQ => 2,
            BallbarEffect::StraightnessP | BallbarEffect::StraightnessQ => 3,
            BallbarEffect::CyclicP | BallbarEffect::CyclicQ => 4,
            BallbarEffect::ServoMismatch => return "servo_mismatch",
            BallbarEffect::Lobes => return "lobes",
            BallbarEffect::RadiusDrift => return "radius_drift",
            BallbarEffect::SenseRadius => return "sense_radius",
        };
        let axis = match self.axis(plane) {
            Some(Axis::X) => 0,
            Some(Axis::Y) => 1,
            _ => 2,
        };
        LETTERED[stem][axis]
    }

    /// The physical cause and what to check, as a service engineer would name them.
    pub fn cause(self) -> &'static str {
        match self {
            BallbarEffect::ServoMismatch => {
                "the two axes follow their commands with different lags: position-loop gains (Kv) or feed-forward set differently; match the servo tuning of the two axes"
            }
            BallbarEffect::BacklashP | BallbarEffect::BacklashQ => {
                "lost motion when the axis reverses: worn ball-screw nut or thrust-bearing float, a loose coupling; check the pre-load and the backlash compensation"
            }
            BallbarEffect::LateralPlayP | BallbarEffect::LateralPlayQ => {
                "the carriage shifts sideways when the axis reverses: play in the guideways (worn gibs or strips, linear bearings without pre-load); check and adjust the guideways"
            }
            BallbarEffect::ReversalSpikeP | BallbarEffect::ReversalSpikeQ => {
                "the axis sticks when it reverses and catches up late: friction (stick-slip) in the guideways or the screw, or a friction/backlash compensation pulse that is too small, too late or too short; check lubrication and the reversal compensation"
            }
            BallbarEffect::StraightnessP | BallbarEffect::StraightnessQ => {
                "the axis does not travel straight: a bowed guideway (wear, a twisted bed, foundation or levelling); check the levelling, then the guideway"
            }
            BallbarEffect::CyclicP | BallbarEffect::CyclicQ => {
                "a periodic error of the axis with the period of its drive or scale: ball-screw lead error per turn, a bent or eccentric screw, encoder or scale interpolation error"
            }
            BallbarEffect::Lobes => {
                "a trace with k lobes per turn at the same angles in both senses: the control interpolating the circle by segments, a disturbance locked to the path (motor cogging), or a lobed or loose ball or magnetic cup of the set-up"
            }
            BallbarEffect::RadiusDrift => {
                "the radius changes steadily during the test: thermal growth of the machine (spindle, structure) or of the bar while the circles run; let the machine and the bar settle, check the bar's temperature compensation"
            }
            BallbarEffect::SenseRadius => {
                "the circle is larger in one sense than in the other: a contouring error that depends on the sense of rotation (friction or acceleration feed-forward set differently for G02 and G03), or the cups' friction pulling the bar"
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lettered_ids_follow_the_plane() {
        assert_eq!(BallbarEffect::BacklashQ.id(Plane::XY), "backlash_y");
        assert_eq!(BallbarEffect::BacklashQ.id(Plane::YZ), "backlash_z");
        assert_eq!(BallbarEffect::CyclicP.id(Plane::ZX), "cyclic_z");
        assert_eq!(BallbarEffect::LateralPlayQ.id(Plane::ZX), "lateral_play_x");
        assert_eq!(BallbarEffect::Lobes.id(Plane::ZX), "lobes");
    }
}
