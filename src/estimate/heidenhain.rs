//! HEIDENHAIN nonlinear axis-error compensation tables (`*.COM`) for the identified
//! positioning errors (`EXX`, `EYY`, `EZZ`, `EAA`, `EBB`, `ECC`).
//!
//! One table per axis, in the control's table format: a `BEGIN <name>.COM MM` line, a header
//! line of column names, one line per compensation point, `[END]`. The columns:
//!
//! - `NR`: the line number from 0;
//! - `AXISPOS`: the compensation point, the axis position (mm, or degrees for a rotary axis)
//!   from the machine datum, here the axis position as the machine model has it;
//! - the axis's own column (`X`, `Y`, …, the key of `CfgAxes/axisList`): the compensation value
//!   of the dependency `X = F(X)`, the positioning error measured travelling in the positive
//!   direction;
//! - `BACKLASH`: the compensation value measured travelling in the negative direction, written
//!   only where the two directions differ (a reversal term was identified).
//!
//! The table is assigned to its axis in the assignment table `config.cma` (column `X`, entry
//! `X.COM`, `*` in `ACTIVE`); mtwin does not write that file, which holds the machine's other
//! tables too.
//!
//! **Sign.** A value is the error measured at the point, actual − nominal (mtwin's sign): the
//! manual's linear axis-error compensation takes "the axis error, with the correct sign,
//! positive if the travel is too long", and the nonlinear table the error curve measured with a
//! comparator. The control corrects by the opposite amount, so the axis commanded to `n` stops
//! at `q` with `q + v(q) = n`.
//!
//! **What is not confirmed from the manuals at hand.** The `BACKLASH` column is read here as
//! the manual words it ("the compensation values measured in the negative direction of
//! traverse"), a second curve, not the difference between the directions. A control that reads
//! it as a difference would compensate the negative direction by the error curve twice over;
//! check on the machine (one reversal at one point) before relying on it, or leave the column
//! out and set the lost motion as the backlash parameter `MP_backLash`. The table's entry
//! limit is the one of the oldest manual (256 points): the spacing is widened to the travel
//! over 255 intervals where the one asked for would exceed it. A rotary axis's table covers 0
//! to 360° (a continuous axis's position is taken within the turn).
//!
//! References: HEIDENHAIN Technical Manual MANUALplus 620, "Nonlinear axis error
//! compensation" (`*.COM` columns AXISPOS, BACKLASH and the axis column; `*.CMA` assignment);
//! HEIDENHAIN Technical Manual TNC 407/415/425, "Linear axis-error compensation" (MP720 sign)
//! and "Nonlinear axis-error compensation" (one table per axis and dependency, 256 entries,
//! 0–360° for an axis of rotation).

use super::compensate::{CompensateError, error_at, intervals_to, per_positioning_error};
use crate::errors::{ErrorFunction, ErrorModel};
use crate::machine::{Axis, AxisInfo, Direction, Machine, axis_unit_to_si};
use crate::math::Real;

/// The most compensation points written per table.
pub const HEIDENHAIN_MAX_POINTS: usize = 256;

/// The `*.COM` tables of the positioning errors in `errors`, one per axis that has one, in
/// ISO order, with compensation points every `spacing_m` (linear axes) or `spacing_rad`
/// (rotary ones) from the lower end of the travel, or wider where the table would exceed
/// [`HEIDENHAIN_MAX_POINTS`] (see the module documentation).
pub fn com_tables(
    machine: &Machine,
    errors: &ErrorModel,
    spacing_m: Real,
    spacing_rad: Real,
) -> Result<Vec<(Axis, String)>, CompensateError> {
    per_positioning_error(machine, errors, spacing_m, spacing_rad, com_table)
}

/// One axis's table.
fn com_table(
    info: &AxisInfo,
    function: &ErrorFunction,
    spacing: Real,
) -> Result<String, CompensateError> {
    let axis = info.axis;
    let (lower, upper) = if info.is_continuous() {
        (0.0, std::f64::consts::TAU)
    } else {
        info.limits.unwrap_or((0.0, std::f64::consts::TAU))
    };
    let unit = axis_unit_to_si(axis);
    let wanted = intervals_to(lower, upper, spacing);
    let intervals = wanted.min(HEIDENHAIN_MAX_POINTS - 1);
    let step = if intervals < wanted || info.is_continuous() {
        (upper - lower) / intervals as Real
    } else {
        spacing
    };
    let error = |q: Real, direction: Direction| error_at(info, function, q, direction);
    let points: Vec<Real> = (0..=intervals).map(|k| lower + k as Real * step).collect();
    let two_curves = points
        .iter()
        .any(|&q| error(q, Direction::Positive) != error(q, Direction::Negative));
    let decimals = if axis.is_linear() { 6 } else { 8 }; // 1 nm, 0.2 nrad
    // One line of columns: NR 6 wide, AXISPOS and the axis's 16, BACKLASH last.
    let line = |nr: String, position: String, forward: String, backward: String| {
        let text = format!("{nr:<6}{position:<16}{forward:<16}{backward}");
        text.trim_end().to_string() + "\n"
    };
    let mut out = format!("BEGIN {axis}.COM MM\n");
    let backlash = if two_curves { "BACKLASH" } else { "" };
    out += &line(
        "NR".into(),
        "AXISPOS".into(),
        axis.to_string(),
        backlash.into(),
    );
    for (k, &q) in points.iter().enumerate() {
        let value = |direction| format!("{:+.decimals$}", error(q, direction) / unit);
        let backward = if two_curves {
            value(Direction::Negative)
        } else {
            String::new()
        };
        out += &line(
            k.to_string(),
            format!("{:+.9}", q / unit),
            value(Direction::Positive),
            backward,
        );
    }
    out += "[END]\n";
    Ok(out)
}
