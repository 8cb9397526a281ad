//! Whether an error parameter is a plausible machine error at all: the bound that tells a
//! typing mistake (a unit off by 10³) from an error of the machine.

use crate::errors::{ErrorParameter, ParameterName};
use crate::machine::Machine;
use crate::math::{RAD_PER_URAD, Real};

/// The largest error the small-motion model is meant for: 10 mm or 10 mrad. Larger values are
/// typing mistakes (a unit off by 10³), not machine errors.
pub const LARGEST_ERROR: Real = 1e-2;

/// Why an error parameter is not a plausible machine error, if it is not: its largest value
/// over its axis's travel (or a turn, sampled at 1001 points) beyond [`LARGEST_ERROR`], or not
/// finite once in SI units (e.g. a period that underflows to zero).
pub fn implausible(parameter: &ErrorParameter, machine: &Machine) -> Option<String> {
    let (lower, upper) = match parameter.name {
        ParameterName::Component { axis, .. } => machine
            .axis(axis)
            .and_then(|info| info.limits)
            .unwrap_or((0.0, std::f64::consts::TAU)),
        _ => (0.0, 0.0),
    };
    let mut largest: Real = 0.0;
    for i in 0..=1000 {
        let q = lower + (upper - lower) * i as Real / 1000.0;
        for direction in [
            crate::machine::Direction::Positive,
            crate::machine::Direction::Negative,
        ] {
            let value = parameter.function.value(q, direction);
            if !value.is_finite() {
                return Some(format!(
                    "not a finite number at {q} (SI units) once converted"
                ));
            }
            largest = largest.max(value.abs());
        }
    }
    let unit = parameter.name.file_unit();
    (largest > LARGEST_ERROR).then(|| {
        format!(
            "reaches {:.0} {unit} over the travel, more than the {:.0} {unit} the small-motion error model is for",
            largest / RAD_PER_URAD,
            LARGEST_ERROR / RAD_PER_URAD
        )
    })
}
