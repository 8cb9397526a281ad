//! What a probe table's own touches say against its set-up, as cautions on the report, each
//! naming the feature and the likely slip:
//!
//! - **Approach vectors off the feature's normal.** A sphere or a ring is probed along its
//!   radius, so each touch's `i, j, k` lies along the line from the fitted centre to the
//!   touch. When they lie on average more than [`LARGEST_TILT`] off it, the columns are
//!   swapped or their signs flipped, and the stylus radius is added in the wrong direction
//!   (a bore read as a plug).
//! - **A size far from the calibration.** A measured diameter more than [`LARGEST_SIZE_ERROR`]
//!   from `cal_diameter_mm` is no probing error: the stylus's diameter given as its radius,
//!   positions in inches, or the radius in the diameter column.
//! - **One touch far off the fit** ([`OUTLIER`]): a mistyped or dirty touch.
//! - **One ball of a plate off the others** ([`odd_plate_ball`]): a calibrated centre
//!   mistyped.
//! - **One sphere's form far above the others'** ([`odd_sphere_form`]): one touch off.
//! - **A short arc.** A ring probed over less than [`SHORTEST_ARC`] gives its diameter from an
//!   arc too short to fix it.

use super::results::{DistanceError, PlateResult, SphereResult};
use super::table::ProbeTouch;
use crate::math::{M_PER_MM, Real, Vector, trimmed};
use std::f64::consts::{PI, TAU};

/// The largest mean angle between the touches' approach vectors and the feature's radius
/// (rad): 25°. A probing cycle approaches along the nominal normal; only a feature far off
/// its nominal position tilts the approach this much against the measured radius.
pub const LARGEST_TILT: Real = 25.0 * crate::math::RAD_PER_DEG;

/// The largest difference between a measured and a calibrated diameter that probing can make
/// (m): 0.2 mm. An uncompensated pre-travel, lobing and the machine's own errors together
/// stay within tens of µm; a slip of the stylus radius, of units or of the calibration
/// column is millimetres.
pub const LARGEST_SIZE_ERROR: Real = 0.2e-3;

/// The shortest arc of a ring whose diameter is worth reporting without comment (rad): 180°.
pub const SHORTEST_ARC: Real = PI;

/// The smallest residual (m) a single touch must have to stand out: 10 µm, beyond the lobing
/// and form a probing cycle sees on a calibrated artefact.
pub const OUTLIER: Real = 10e-6;

/// The smallest form (m) of one sphere that stands out from the others': 5 µm, beyond a
/// calibrated sphere's form and a probing system's lobing (a few µm at most).
pub const ODD_FORM: Real = 5e-6;

/// The sphere (or plate ball) whose form (range of the fit's radii) is more than [`ODD_FORM`]
/// and ten times the median form of the table's other spheres: one touch off (dirt, a typo),
/// which a fit of a few points spreads over all its touches rather than leaving on one, so
/// the centre and the size move with it. At least three spheres.
pub fn odd_sphere_form(spheres: &[SphereResult]) -> Option<String> {
    if spheres.len() < 3 {
        return None;
    }
    let forms: Vec<Real> = spheres.iter().map(|s| s.fit.form()).collect();
    let (k, worst) = forms
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let others: Vec<Real> = (forms.iter().enumerate())
        .filter(|&(j, _)| j != k)
        .map(|(_, f)| *f)
        .collect();
    let middle = crate::io::plausible::median(others)?;
    (worst > ODD_FORM && worst > 10.0 * middle).then(|| {
        let key = &spheres[k].key;
        format!(
            "cycle {} feature {}: the touches' radii span {} µm where the other spheres' span {} µm (median): one touch off (dirt, a typo)? A fit of a few touches spreads it, so the centre and the size move with it",
            key.cycle,
            key.feature,
            trimmed(worst * 1e6, 4),
            trimmed(middle * 1e6, 3)
        )
    })
}

/// The ball of a plate placement whose distances to the others are off by more than
/// [`OUTLIER`] and ten times the other pairs' errors (medians): its calibrated centre
/// mistyped (a certificate transcribed wrong) or the ball disturbed. A machine's errors
/// change the distances smoothly over the plate; one ball alone off is not the machine.
pub fn odd_plate_ball(plate: &PlateResult) -> Option<String> {
    let error = |d: &DistanceError| (d.measured - d.calibrated).abs();
    let mut balls: Vec<usize> = plate
        .distances
        .iter()
        .flat_map(|d| [d.balls.0, d.balls.1])
        .collect();
    balls.sort_unstable();
    balls.dedup();
    if balls.len() < 4 {
        return None;
    }
    let (ball, own, others) = balls
        .iter()
        .filter_map(|&b| {
            let (with, without): (Vec<_>, Vec<_>) = plate
                .distances
                .iter()
                .partition(|d| d.balls.0 == b || d.balls.1 == b);
            let own = crate::io::plausible::median(with.iter().map(&error).collect())?;
            let others = crate::io::plausible::median(without.iter().map(&error).collect())?;
            Some((b, own, others))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    (own > OUTLIER && own > 10.0 * others).then(|| {
        format!(
            "cycle {}: ball {ball}'s distances to the other balls are off by {} µm (median) while the other balls' agree within {} µm: its calibrated centre (cal_x_mm, cal_y_mm, cal_z_mm) mistyped, or the ball disturbed? It sets the placement's largest errors",
            plate.cycle,
            trimmed(own * 1e6, 4),
            trimmed(others * 1e6, 3)
        )
    })
}

/// The touch whose residual from the fit is above [`OUTLIER`] and ten times the median of the
/// residuals' magnitudes: a mistyped or dirty touch, which sets the form and pulls the size.
fn outlier(label: &str, touches: &[&ProbeTouch], residuals: &[Real]) -> Option<String> {
    if residuals.len() != touches.len() || residuals.len() < 5 {
        return None;
    }
    let magnitudes: Vec<Real> = residuals.iter().map(|r| r.abs()).collect();
    let middle = crate::io::plausible::median(magnitudes.clone())?;
    let (k, worst) = magnitudes
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    (worst > OUTLIER && worst > 10.0 * middle).then(|| {
        format!(
            "{label}: point {} lies {} µm off the fit, more than ten times the touches' median of {} µm: a mistyped or dirty touch? It sets the form and pulls the size",
            touches[k].point,
            trimmed(worst * 1e6, 3),
            trimmed(middle * 1e6, 3)
        )
    })
}

/// The cautions for one feature (`label` names it): its `touches`, the fitted `centre`, the
/// measured − calibrated diameter when calibrated, and for a ring the touches' angles in its
/// plane, and the fit's residual at each touch (in `touches`' order).
pub fn feature_cautions(
    label: &str,
    touches: &[&ProbeTouch],
    centre: Vector,
    diameter_error: Option<Real>,
    ring_angles: Option<&[Real]>,
    residuals: &[Real],
) -> Vec<String> {
    let mut found = Vec::new();
    found.extend(outlier(label, touches, residuals));
    let alignments: Vec<Real> = touches
        .iter()
        .filter_map(|t| {
            let radial = t.position - centre;
            (radial.length() > 0.0).then(|| t.approach.dot(radial.normalize()).abs().min(1.0))
        })
        .collect();
    if !alignments.is_empty() {
        let mean_angle =
            alignments.iter().map(|c| c.acos()).sum::<Real>() / alignments.len() as Real;
        if mean_angle > LARGEST_TILT {
            found.push(format!(
                "{label}: the approach vectors (i, j, k) lie {}° off the feature's radius on average (a probing cycle approaches along it, within {}°): i, j, k swapped or a sign flipped? The stylus radius is applied along them, so the size and the side (bore or plug) are not to be trusted",
                trimmed(mean_angle.to_degrees(), 1),
                trimmed(LARGEST_TILT.to_degrees(), 0)
            ));
        }
    }
    if let Some(error) = diameter_error.filter(|e| e.abs() > LARGEST_SIZE_ERROR) {
        found.push(format!(
            "{label}: the measured diameter differs from cal_diameter_mm by {} mm, far beyond any probing error (tens of µm): the stylus's diameter given as its radius, positions in inches, or a radius in the diameter column?",
            trimmed(error / M_PER_MM, 4)
        ));
    }
    if let Some(angles) = ring_angles.filter(|a| a.len() >= 2) {
        let mut sorted: Vec<Real> = angles.iter().map(|a| a.rem_euclid(TAU)).collect();
        sorted.sort_by(Real::total_cmp);
        let widest_gap = sorted
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(sorted[0] + TAU - sorted[sorted.len() - 1], Real::max);
        let arc = TAU - widest_gap;
        if arc < SHORTEST_ARC {
            found.push(format!(
                "{label}: the touches span only {}° of the ring (at least {}° fix a diameter): its diameter and centre rest on a short arc",
                trimmed(arc.to_degrees(), 1),
                trimmed(SHORTEST_ARC.to_degrees(), 0)
            ));
        }
    }
    found
}
