//! What a spindle record's own error motions say against its units, as cautions for the
//! ISO 230-7 report: a total error motion beyond [`LARGEST_MOTION`] (nm in the µm columns),
//! or the largest below [`SMALLEST_MOTION`] (mm in them).

use super::analysis::motion::Direction;
use super::evaluate::Evaluation;
use crate::math::{Real, trimmed};

/// The largest total error motion of a machine tool's axis of rotation (m): 100 µm. A worn
/// rolling-bearing spindle shows tens of µm, a good one a few; nm written in the µm columns
/// read 1000 times larger.
pub const LARGEST_MOTION: Real = 100e-6;

/// The smallest total error motion the worst direction of an axis of rotation shows to a probe
/// (m): 5 nm. The best air-bearing spindles run at tens of nm, and a probe's noise alone over
/// the record gives a few; mm written in the µm columns read 1000 times smaller.
pub const SMALLEST_MOTION: Real = 5e-9;

/// Every caution for the report of `evaluation`.
pub fn cautions(evaluation: &Evaluation) -> Vec<String> {
    let mut found = Vec::new();
    let totals: Vec<(String, Real)> = evaluation
        .segments
        .iter()
        .flat_map(|s| &s.tests)
        .filter(|t| t.direction != Direction::Tilt)
        .filter_map(|t| t.values.first().map(|v| (t.name.clone(), v.total)))
        .collect();
    if let Some((name, largest)) = totals
        .iter()
        .filter(|(_, v)| *v > LARGEST_MOTION)
        .max_by(|a, b| a.1.total_cmp(&b.1))
    {
        found.push(format!(
            "{name}: a total error motion of {} µm, more than the {} µm of any machine tool's spindle or rotary axis: nm in the µm columns?",
            trimmed(largest * 1e6, 3),
            trimmed(LARGEST_MOTION * 1e6, 3)
        ));
    }
    if !totals.is_empty() && totals.iter().all(|(_, v)| *v < SMALLEST_MOTION) {
        found.push(format!(
            "every total error motion is below {} µm, less than the best air-bearing spindle shows (tens of nm): mm in the µm columns?",
            trimmed(SMALLEST_MOTION * 1e6, 4)
        ));
    }
    found
}
