//! Speed-induced axis shift (ISO 230-7 §3.10.5, §3.10.6): the change of the axis's mean
//! position between the speeds of one record, test by test.
//!
//! **What it models.** §3.10.6 defines the value as the difference between the maximum and
//! the minimum displacement a sensor (or a combination, for tilt and face) measures at the
//! speeds asked. A test in a fixed sensitive direction (one probe, a tilt of two, formula
//! (4)) has, at each speed, the mean of its signal over the segment as its position: a
//! displacement (or angle) along that direction. The value is `max − min` over the speeds.
//!
//! Rotating sensitive directions get none: there a constant displacement of the axis reads as
//! 1 UPR, and so does half of any 2-UPR motion (`cos 2θ cos θ = (cos θ + cos 3θ)/2`), so the
//! signal cannot tell the axis's position from its synchronous motion, and the speed changes
//! both. The fixed probes of the pair give the shift along each of their directions.
//!
//! Segments are grouped by set-up and by the sense of rotation (a shift between directions is
//! not a speed effect); a test seen at two speeds or more gets a shift.
//!
//! **Left out.** Telling a speed effect from thermal drift: §3.10.6 asks that the time at each
//! speed be short and the speeds alternated, and this module trusts the record to be taken so
//! (the thermal twin and `mtwin discover spindle` separate the two from the record's time).

use super::{Segment, Test};
use crate::kinds::spindle::analysis::motion::Direction;
use crate::kinds::spindle::record::Sensing;
use crate::math::Real;

/// One test's position against speed.
#[derive(Clone, Debug)]
pub struct SpeedShift {
    /// The test's name, with its set-up in brackets when the record holds several.
    pub test: String,
    /// Its direction (the unit: m, or rad for tilt).
    pub direction: Direction,
    /// Whether the axis turns backwards in these segments.
    pub backwards: bool,
    /// `(speed (rad/s), mean position − the first speed's)`, in file order.
    pub points: Vec<(Real, Real)>,
    /// The speed-induced axis shift value: `max − min` of the mean positions.
    pub value: Real,
    /// Its expanded uncertainty (k = 2): a difference of two readings' means, so the widest
    /// single-value U of the test over the speeds (Annex F.6: device and environment; the
    /// drift between the speeds is what the environment term bounds).
    pub uncertainty: Real,
    /// Whether every budget it comes from is complete (else U is a lower bound).
    pub complete: bool,
}

/// The test's mean position in its segment (module docs).
fn position(test: &Test) -> Real {
    let values = test.signal.values();
    values.iter().sum::<Real>() / values.len() as Real
}

/// The shifts of every test in a fixed sensitive direction seen at two speeds or more in one
/// set-up and sense of rotation.
pub(super) fn speed_shifts(segments: &[Segment]) -> Vec<SpeedShift> {
    let several_setups = segments.iter().any(|s| s.setup != segments[0].setup);
    let mut out: Vec<SpeedShift> = Vec::new();
    for segment in segments {
        let backwards = segment.speed < 0.0;
        for test in segment.tests.iter().filter(|t| t.sensing == Sensing::Fixed) {
            let name = if several_setups {
                format!("{} ({})", test.name, segment.setup)
            } else {
                test.name.clone()
            };
            let p = position(test);
            match out
                .iter()
                .position(|s| s.test == name && s.backwards == backwards)
            {
                Some(i) => {
                    let shift = &mut out[i];
                    shift.points.push((segment.speed, p));
                    shift.uncertainty = shift.uncertainty.max(test.uncertainty.single);
                    shift.complete &= test.uncertainty.missing.is_empty();
                }
                None => out.push(SpeedShift {
                    test: name,
                    direction: test.direction,
                    backwards,
                    points: vec![(segment.speed, p)],
                    value: 0.0,
                    uncertainty: test.uncertainty.single,
                    complete: test.uncertainty.missing.is_empty(),
                }),
            }
        }
    }
    for shift in &mut out {
        let first = shift.points[0].1;
        let (mut low, mut high) = (Real::INFINITY, Real::NEG_INFINITY);
        for point in &mut shift.points {
            low = low.min(point.1);
            high = high.max(point.1);
            point.1 -= first;
        }
        shift.value = high - low;
    }
    // A speed that repeats (up and down again) is still one test at two speeds or more.
    out.retain(|s| s.points.iter().any(|(speed, _)| *speed != s.points[0].0));
    out
}
