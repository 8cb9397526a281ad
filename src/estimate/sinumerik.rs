//! SINUMERIK 840D sl leadscrew / measuring-system error compensation (LEC, "EEC") tables for
//! the identified positioning errors (`EXX`, `EYY`, `EZZ`, `EAA`, `EBB`, `ECC`).
//!
//! One file per axis, as the control's archive holds it (`%_N_AX_EEC_INI`): the compensation
//! value of every interpolation point `$AA_ENC_COMP[0,N,AXi]` (mm, or degrees for a rotary
//! axis), their distance `$AA_ENC_COMP_STEP[0,AXi]`, the positions of the first and last
//! `$AA_ENC_COMP_MIN[0,AXi]` and `$AA_ENC_COMP_MAX[0,AXi]`, and `$AA_ENC_COMP_IS_MODULO[0,AXi]`
//! (1 for a continuous rotary axis, whose table then spans one turn), the first measuring
//! system (`0`), the machine axis named `X1`, `Y1`, … (rename to the machine's own). The
//! function is enabled by MD32700 `$MA_ENC_COMP_ENABLE[0] = 1` and needs MD38000
//! `$MA_MM_ENC_COMP_MAX_POINTS` at least the number of points.
//!
//! **Sign.** The control changes the axis's actual position value by the compensation value,
//! and a positive value moves the machine axis in the negative direction. So the value at an
//! axis position `q` is the positioning error there, `E(q)` (actual − nominal, mtwin's sign):
//! an axis that overshoots by `E` is held back by `E`. (The table is indexed by the axis's
//! position; were it the compensated position `q + E`, the values would move by `E′·E`, below
//! 1 nm for errors of tens of µm per metre.)
//!
//! **Direction.** The LEC table holds one curve for both directions of travel: the mean of the
//! two directions' errors. A reversal term (lost motion `r`, the reverse approach reading `r`
//! beyond the forward one) is not in it; the file states `r` in its header comment for the
//! axis's backlash compensation (MD32450 `$MA_BACKLASH[0]`, positive for the usual lost motion).
//! Direction-dependent curves (two sag-compensation tables with `$AN_CEC_DIRECTION` ±1) are
//! not written.
//!
//! Reference: SINUMERIK 840D sl Function Manual Extended Functions, K3 Compensation,
//! "Interpolatory compensation: measuring system error compensation (MSEC)" (system variables
//! of the compensation table, the example `%_N_AX_EEC_INI` for axis X1, and "a positive
//! compensation value causes the corresponding machine axis to move in the negative
//! direction"); MD32450 BACKLASH in the same manual's "Backlash compensation".

use super::compensate::{CompensateError, error_at, intervals_to, per_positioning_error};
use crate::errors::{ErrorFunction, ErrorModel};
use crate::machine::{Axis, AxisInfo, Direction, Machine, axis_unit_to_si};
use crate::math::{Real, trimmed};

/// The largest number of interpolation points written per table (MD38000 allows up to 5 000
/// per axis in the manual's example configurations; the table is refused beyond it).
pub const SINUMERIK_MAX_POINTS: usize = 5000;

/// The LEC files of the positioning errors in `errors`, one per axis that has one, in ISO
/// order, with interpolation points every `spacing_m` (linear axes) or `spacing_rad` (rotary
/// ones) from the lower end of the travel (see the module documentation).
pub fn lec_tables(
    machine: &Machine,
    errors: &ErrorModel,
    spacing_m: Real,
    spacing_rad: Real,
) -> Result<Vec<(Axis, String)>, CompensateError> {
    per_positioning_error(machine, errors, spacing_m, spacing_rad, lec_table)
}

/// One axis's file.
fn lec_table(
    info: &AxisInfo,
    function: &ErrorFunction,
    spacing: Real,
) -> Result<String, CompensateError> {
    let axis = info.axis;
    let modulo = info.is_continuous();
    let (lower, upper) = info.limits.unwrap_or((0.0, std::f64::consts::TAU));
    let unit = axis_unit_to_si(axis);
    // Points from the lower end, the last one at or beyond the upper end (the control holds
    // the last value beyond MAX; a modulo table ends exactly one turn on).
    let intervals = intervals_to(lower, upper, spacing);
    let points = intervals + 1;
    if points > SINUMERIK_MAX_POINTS {
        return Err(CompensateError::TooManyPoints {
            axis,
            points,
            maximum: SINUMERIK_MAX_POINTS,
        });
    }
    let step = if modulo {
        (upper - lower) / intervals as Real
    } else {
        spacing
    };
    let error = |q: Real, direction: Direction| error_at(info, function, q, direction);
    let lost_motion = error(lower, Direction::Negative) - error(lower, Direction::Positive);
    let machine_axis = format!("{axis}1");
    let (unit_name, decimals) = if axis.is_linear() {
        ("mm", 6) // 1 nm
    } else {
        ("degree", 8) // 0.2 nrad
    };
    let mut out = String::from("%_N_AX_EEC_INI\nCHANDATA(1)\n");
    out += &format!(
        "; mtwin identify: measuring system error compensation of {machine_axis} (axis {axis}), \
         the mean of both directions' positioning errors, {unit_name}\n"
    );
    out += &format!(
        "; lost motion {} {unit_name} (reverse approach beyond forward): not in this table; \
         set it as MD32450 $MA_BACKLASH[0] of {machine_axis}\n",
        trimmed(lost_motion / unit, decimals)
    );
    for k in 0..points {
        let q = lower + k as Real * step;
        let value = 0.5 * (error(q, Direction::Positive) + error(q, Direction::Negative));
        out += &format!(
            "$AA_ENC_COMP[0,{k},{machine_axis}]={}\n",
            trimmed(value / unit, decimals)
        );
    }
    // Positions as REAL numbers with a decimal point, as the manual's example writes them.
    let position = |q: Real| {
        let text = trimmed(q / unit, 9);
        if text.contains('.') {
            text
        } else {
            text + ".0"
        }
    };
    out += &format!("$AA_ENC_COMP_STEP[0,{machine_axis}]={}\n", position(step));
    out += &format!("$AA_ENC_COMP_MIN[0,{machine_axis}]={}\n", position(lower));
    out += &format!(
        "$AA_ENC_COMP_MAX[0,{machine_axis}]={}\n",
        position(lower + intervals as Real * step)
    );
    out += &format!(
        "$AA_ENC_COMP_IS_MODULO[0,{machine_axis}]={}\nM17\n",
        u8::from(modulo)
    );
    Ok(out)
}
