//! The `[volumetric]` section: the grid of the volumetric error map and the model that
//! evaluates it.
//!
//! ```toml
//! [volumetric]                      # what to compute: the volumetric error map
//! model = "chain"                   # or "lu2012" (3-axis only)
//! x_mm = { from = 0.0, to = 760.0, count = 5 }   # default: the full travel, 5 points
//! ```
//!
//! Rotary grid axes default to 5 points over their travel, or 0, 90, 180, 270° for a
//! continuous axis.

use super::map::GridAxis;
use crate::machine::{Axis, Machine, axis_unit_to_si};
use crate::math::Real;
use crate::scenario::{Context, ScenarioError, ScenarioErrorKind};
use crate::twin::EvaluationModel;
use serde::Deserialize;
use toml::Spanned;

/// The most grid points a volumetric map may have: a million (100 per axis of a 3-axis
/// machine), so that the largest map runs in about 2.5 s and writes about 100 MB (ten million
/// took 24 s, 1.6 GB of memory and 0.9 GB of table on the 2-core machine of the README's figures).
pub const MAX_GRID_POINTS: usize = 1_000_000;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawVolumetric {
    model: Option<Spanned<String>>,
    x_mm: Option<Spanned<RawRange>>,
    y_mm: Option<Spanned<RawRange>>,
    z_mm: Option<Spanned<RawRange>>,
    a_deg: Option<Spanned<RawRange>>,
    b_deg: Option<Spanned<RawRange>>,
    c_deg: Option<Spanned<RawRange>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRange {
    from: Real,
    to: Real,
    count: usize,
}

/// The volumetric map a scenario asks for.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumetricSpec {
    /// Chain (truth) or the Lu (2012) summed model.
    pub model: EvaluationModel,
    /// The grid, outermost axis first (rotary axes, then X, Y, Z).
    pub grid: Vec<GridAxis>,
}

pub(crate) fn volumetric_spec(
    context: &Context<'_>,
    machine: &Machine,
    raw: &Spanned<RawVolumetric>,
) -> Result<VolumetricSpec, ScenarioError> {
    let v = raw.get_ref();
    let model = match &v.model {
        None => EvaluationModel::Chain,
        Some(name) => match name.get_ref().as_str() {
            "chain" => EvaluationModel::Chain,
            "lu2012" if machine.rotary_axes().next().is_some() => {
                return Err(context.error(
                    Some(name.span()),
                    ScenarioErrorKind::Model,
                    "volumetric.model: \"lu2012\" is the 21-component 3-axis model; this machine has rotary axes",
                ));
            }
            "lu2012" => EvaluationModel::Lu2012,
            other => {
                return Err(context.error(
                    Some(name.span()),
                    ScenarioErrorKind::Model,
                    format!("volumetric.model: \"{other}\" is not a model; expected \"chain\" or \"lu2012\""),
                ));
            }
        },
    };
    let given = [
        (Axis::A, "a_deg", &v.a_deg),
        (Axis::B, "b_deg", &v.b_deg),
        (Axis::C, "c_deg", &v.c_deg),
        (Axis::X, "x_mm", &v.x_mm),
        (Axis::Y, "y_mm", &v.y_mm),
        (Axis::Z, "z_mm", &v.z_mm),
    ];
    let mut grid = Vec::new();
    for (axis, key, range) in given {
        let info = machine.axis(axis);
        let range = match (info, range) {
            (None, None) => continue,
            (None, Some(range)) => {
                return Err(context.error(
                    Some(range.span()),
                    ScenarioErrorKind::Grid,
                    format!(
                        "volumetric.{key}: machine \"{}\" has no axis {axis}",
                        machine.name()
                    ),
                ));
            }
            (Some(info), None) => default_range(info.limits),
            (Some(info), Some(spanned)) => {
                let RawRange { from, to, count } = *spanned.get_ref();
                let fail = |message: String| {
                    context.error(
                        Some(spanned.span()),
                        ScenarioErrorKind::Grid,
                        format!("volumetric.{key}: {message}"),
                    )
                };
                if !(from.is_finite() && to.is_finite()) {
                    return Err(fail("from and to must be finite numbers".into()));
                }
                if count == 0 {
                    return Err(fail("count must be at least 1".into()));
                }
                let scale = axis_unit_to_si(axis);
                if let Some((lower, upper)) = info.limits {
                    for value in [from, to] {
                        if !info.within_travel(value * scale) {
                            return Err(fail(format!(
                                "{value} is outside the travel of {axis} ({} .. {} {})",
                                lower / scale,
                                upper / scale,
                                &key[2..]
                            )));
                        }
                    }
                }
                if count > MAX_GRID_POINTS {
                    return Err(fail(format!(
                        "count {count} is more than the {MAX_GRID_POINTS} points a map may have"
                    )));
                }
                (from * scale, to * scale, count)
            }
        };
        let (from, to, count) = range;
        let values = (0..count)
            .map(|i| {
                if count == 1 {
                    from
                } else {
                    from + (to - from) * i as Real / (count - 1) as Real
                }
            })
            .collect();
        grid.push(GridAxis { axis, values });
    }
    let points = grid
        .iter()
        .try_fold(1usize, |product, g| product.checked_mul(g.values.len()));
    if points.is_none_or(|p| p > MAX_GRID_POINTS) {
        return Err(context.error(
            Some(raw.span()),
            ScenarioErrorKind::Grid,
            format!(
                "volumetric: the grid has {} points; at most {MAX_GRID_POINTS}",
                grid.iter()
                    .map(|g| g.values.len().to_string())
                    .collect::<Vec<_>>()
                    .join(" × ")
            ),
        ));
    }
    Ok(VolumetricSpec { model, grid })
}

/// The full travel with 5 points; 0, 90, 180, 270° for a continuous axis.
fn default_range(limits: Option<(Real, Real)>) -> (Real, Real, usize) {
    match limits {
        Some((lower, upper)) => (lower, upper, 5),
        None => (0.0, 270.0 * crate::math::RAD_PER_DEG, 4),
    }
}

impl VolumetricSpec {
    /// `volumetric map: chain model, 225 grid points`, as `mtwin check` lists it.
    pub fn describe(&self) -> String {
        let points: usize = self.grid.iter().map(|g| g.values.len()).product();
        format!(
            "volumetric map: {} model, {points} grid points",
            self.model.name()
        )
    }
}
