//! The cycles planned on the nominal chain with their checks ([`Plan`]): each move must touch
//! its artefact within its travel, and start and end within every axis's travel.

use super::raw::{RawMesh, RawPlate, RawRing, RawRotary, RawSphere};
use super::values::{count, direction, finite, point, value};
use crate::contact::{Approach, BallPlate, Cylinder, CylinderSide, Mesh, Sphere};
use crate::kinds::probe::cycles::{
    Cycle, CycleKind, Feature, LinearFrame, ProbeMove, Target, ring_pattern, sphere_pattern,
};
use crate::machine::{Axis, AxisValues, Machine};
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, Rotation, Vector};
use crate::scenario::{Checker, ScenarioError};
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;
use toml::Spanned;

/// How far (rad) a mesh point's approach may be from the surface normal: 1 mrad leaves
/// `r·θ²/2` (under 1 nm for a 3 mm stylus) along the normal.
pub const MESH_NORMAL_TOLERANCE: Real = 1e-3;

/// Planning the cycles with the checks.
pub(super) struct Plan<'a> {
    pub(super) check: &'a Checker<'a>,
    pub(super) machine: &'a Machine,
    pub(super) r: Real,
    pub(super) clearance: Real,
    pub(super) overtravel: Real,
}

impl Plan<'_> {
    /// The rotary angles of `raw` (absent: 0), each on an axis the machine has, within travel.
    pub(super) fn rotary(
        &self,
        raw: Option<RawRotary>,
        span: Range<usize>,
        key: &str,
    ) -> Result<AxisValues, ScenarioError> {
        let mut values = AxisValues::ZERO;
        let Some(raw) = raw else { return Ok(values) };
        for (axis, given) in [
            (Axis::A, raw.a_deg),
            (Axis::B, raw.b_deg),
            (Axis::C, raw.c_deg),
        ] {
            let Some(deg) = given else { continue };
            let Some(info) = self.machine.axis(axis) else {
                return Err(self.check.fail(
                    Some(span),
                    key,
                    format!("machine \"{}\" has no axis {axis}", self.machine.name()),
                ));
            };
            let value = deg * RAD_PER_DEG;
            if !info.within_travel(value) {
                return Err(self.check.fail(
                    Some(span),
                    key,
                    format!(
                        "{axis} {deg}° is outside its travel, {}",
                        info.scenario_travel_text()
                    ),
                ));
            }
            values[axis] = value;
        }
        Ok(values)
    }

    /// The linear axes' frame at `rotary`, which must not be degenerate.
    pub(super) fn frame(
        &self,
        rotary: &AxisValues,
        span: Range<usize>,
        key: &str,
    ) -> Result<LinearFrame, ScenarioError> {
        LinearFrame::at(self.machine, rotary).ok_or_else(|| {
            self.check.fail(
                Some(span),
                key,
                "the linear axes are degenerate at these rotary angles",
            )
        })
    }

    /// Checks a planned move on the nominal chain: it touches `target` within its travel, and
    /// starts and ends (`overtravel` past the touch) within every axis's travel.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn checked_move(
        &self,
        frame: &LinearFrame,
        target: &Target,
        start: Vector,
        direction: Vector,
        max_travel: Real,
        span: Range<usize>,
        key: &str,
    ) -> Result<ProbeMove, ScenarioError> {
        let (r, overtravel) = (self.r, self.overtravel);
        let probing = frame.move_from(start, direction, max_travel);
        let at = |s: Real| {
            let mut axes = probing.start;
            for (axis, c) in [
                (Axis::X, probing.direction.x),
                (Axis::Y, probing.direction.y),
                (Axis::Z, probing.direction.z),
            ] {
                axes[axis] += c * s;
            }
            axes
        };
        let mm = |v: Vector| {
            format!(
                "({:.3}, {:.3}, {:.3}) mm",
                v.x / M_PER_MM,
                v.y / M_PER_MM,
                v.z / M_PER_MM
            )
        };
        let approach = Approach::new(start, direction)
            .map_err(|e| self.check.fail(Some(span.clone()), key, e))?;
        let touch = match target.touch(r, &approach, max_travel) {
            Ok(Some(t)) => t,
            Ok(None) => {
                return Err(self.check.fail(Some(span), key, format!(
                    "the approach from {} along ({:.4}, {:.4}, {:.4}) does not reach the artefact within {:.3} mm",
                    mm(start), direction.x, direction.y, direction.z, max_travel / M_PER_MM
                )));
            }
            Err(e) => {
                return Err(self.check.fail(
                    Some(span),
                    key,
                    format!("the approach from {}: {e}", mm(start)),
                ));
            }
        };
        for (what, axes) in [("starts", at(0.0)), ("ends", at(touch.travel + overtravel))] {
            if let Err((axis, value, (lower, upper))) = self.machine.check_limits(&axes) {
                let unit = if axis.is_linear() {
                    (M_PER_MM, "mm")
                } else {
                    (RAD_PER_DEG, "°")
                };
                return Err(self.check.fail(Some(span), key, format!(
                    "the approach toward the artefact {what} with {axis} at {:.3} {}, outside its travel {:.3} … {:.3}: the artefact cannot be reached there",
                    value / unit.0, unit.1, lower / unit.0, upper / unit.0
                )));
            }
        }
        Ok(probing)
    }

    pub(super) fn diameter(&self, v: &Spanned<Real>, key: &str) -> Result<Real, ScenarioError> {
        let d = *v.get_ref();
        if d.is_finite() && d > 0.0 {
            Ok(d * M_PER_MM)
        } else {
            Err(self.check.fail(
                Some(v.span()),
                key,
                format!("expected a positive diameter, got {d}"),
            ))
        }
    }

    pub(super) fn incidence(
        &self,
        v: &Option<Spanned<Real>>,
        key: &str,
    ) -> Result<Real, ScenarioError> {
        let deg = value(self.check, v, key, 0.0, 0.0, false)?;
        if deg >= 90.0 {
            return Err(self.check.fail(
                v.as_ref().map(|v| v.span()),
                key,
                format!("{deg}° is not below the pole (expected 0 ≤ incidence < 90)"),
            ));
        }
        Ok(deg * RAD_PER_DEG)
    }

    /// The moves of a sphere pattern on `target`, about the sphere `centre` of radius `radius`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn sphere_moves(
        &self,
        frame: &LinearFrame,
        target: &Target,
        centre: Vector,
        radius: Real,
        points: usize,
        elevation: Real,
        facing: Option<Vector>,
        span: Range<usize>,
        key: &str,
    ) -> Result<Vec<ProbeMove>, ScenarioError> {
        let tool = frame.tool;
        sphere_pattern(points, elevation, tool.z_axis, tool.x_axis, facing)
            .into_iter()
            .map(|n| {
                let start = centre + n * (radius + self.r + self.clearance);
                let travel = self.clearance + self.overtravel;
                self.checked_move(frame, target, start, -n, travel, span.clone(), key)
            })
            .collect()
    }

    pub(super) fn sphere(
        &self,
        raw: &Spanned<RawSphere>,
        key: &str,
    ) -> Result<Cycle, ScenarioError> {
        let s = raw.get_ref();
        let diameter = self.diameter(&s.diameter_mm, &format!("{key}.diameter_mm"))?;
        let centre = point(self.check, &s.centre_mm, &format!("{key}.centre_mm"))?;
        let points = count(self.check, &s.points, &format!("{key}.points"), 5, (4, 25))?;
        let elevation = self.incidence(&s.incidence_deg, &format!("{key}.incidence_deg"))?;
        let sphere = Sphere {
            centre,
            radius: diameter / 2.0,
        };
        let target = Target::Sphere(sphere);
        let positions: Vec<Option<RawRotary>> = match &s.rotary {
            None => vec![None],
            Some(list) if list.get_ref().is_empty() => {
                return Err(self.check.fail(
                    Some(list.span()),
                    &format!("{key}.rotary"),
                    "give at least one rotary position",
                ));
            }
            Some(list) => list.get_ref().iter().copied().map(Some).collect(),
        };
        let span = s.rotary.as_ref().map_or(raw.span(), |r| r.span());
        let mut features = Vec::new();
        for (n, position) in positions.into_iter().enumerate() {
            let key = format!("{key}.rotary[{n}]");
            let rotary = self.rotary(position, span.clone(), &key)?;
            let frame = self.frame(&rotary, span.clone(), &key)?;
            let moves = self.sphere_moves(
                &frame,
                &target,
                centre,
                sphere.radius,
                points,
                elevation,
                None,
                span.clone(),
                &key,
            )?;
            features.push(Feature {
                rotary,
                target: target.clone(),
                moves,
                calibrated_diameter: Some(diameter),
                calibrated_centre: None,
            });
        }
        Ok(Cycle {
            kind: CycleKind::Sphere,
            features,
        })
    }

    pub(super) fn ring(&self, raw: &Spanned<RawRing>, key: &str) -> Result<Cycle, ScenarioError> {
        let g = raw.get_ref();
        let diameter = self.diameter(&g.diameter_mm, &format!("{key}.diameter_mm"))?;
        let centre = point(self.check, &g.centre_mm, &format!("{key}.centre_mm"))?;
        let points = count(self.check, &g.points, &format!("{key}.points"), 8, (3, 360))?;
        let span = g.rotary.as_ref().map_or(raw.span(), |r| r.span());
        let rotary = self.rotary(
            g.rotary.as_ref().map(|r| *r.get_ref()),
            span.clone(),
            &format!("{key}.rotary"),
        )?;
        let frame = self.frame(&rotary, span.clone(), &format!("{key}.rotary"))?;
        let axis = match &g.axis {
            Some(a) => direction(self.check, *a.get_ref(), a.span(), &format!("{key}.axis"))?,
            None => frame.tool.z_axis,
        };
        let radius = diameter / 2.0;
        let free = radius - self.r;
        if free <= 0.0 {
            return Err(self.check.fail(
                Some(g.diameter_mm.span()),
                &format!("{key}.diameter_mm"),
                "the stylus ball does not fit the bore",
            ));
        }
        let target = Target::Ring(Cylinder {
            point: centre,
            axis,
            radius,
            side: CylinderSide::Bore,
        });
        let offset = (free - self.clearance).max(0.0);
        let moves = ring_pattern(points, axis, frame.tool.x_axis)
            .into_iter()
            .map(|u| {
                let travel = free - offset + self.overtravel;
                self.checked_move(
                    &frame,
                    &target,
                    centre + u * offset,
                    u,
                    travel,
                    raw.span(),
                    key,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Cycle {
            kind: CycleKind::Ring,
            features: vec![Feature {
                rotary,
                target,
                moves,
                calibrated_diameter: Some(diameter),
                calibrated_centre: None,
            }],
        })
    }

    pub(super) fn plate(
        &self,
        raw: &Spanned<RawPlate>,
        key: &str,
    ) -> Result<Vec<Cycle>, ScenarioError> {
        let b = raw.get_ref();
        let size = |v: &Spanned<i64>, name: &str| -> Result<usize, ScenarioError> {
            count(
                self.check,
                &Some(v.clone()),
                &format!("{key}.{name}"),
                1,
                (1, 100),
            )
        };
        let (rows, columns) = (size(&b.rows, "rows")?, size(&b.columns, "columns")?);
        let pitch = self.diameter(&b.pitch_mm, &format!("{key}.pitch_mm"))?;
        let ball = self.diameter(&b.ball_diameter_mm, &format!("{key}.ball_diameter_mm"))?;
        if ball + 2.0 * (self.r + self.clearance) >= pitch {
            return Err(self.check.fail(
                Some(b.pitch_mm.span()),
                &format!("{key}.pitch_mm"),
                "the balls are too close for the stylus to pass between them",
            ));
        }
        let points = count(self.check, &b.points, &format!("{key}.points"), 5, (4, 25))?;
        let elevation = self.incidence(&b.incidence_deg, &format!("{key}.incidence_deg"))?;
        let offsets: Vec<Vector> = match &b.ball_offsets_um {
            None => vec![Vector::ZERO; rows * columns],
            Some(list) => {
                let given = list.get_ref();
                if given.len() != rows * columns || given.iter().flatten().any(|x| !x.is_finite()) {
                    return Err(self.check.fail(Some(list.span()), &format!("{key}.ball_offsets_um"), format!("expected {} finite [x, y, z] offsets (rows × columns, row by row), got {}", rows * columns, given.len())));
                }
                given
                    .iter()
                    .map(|o| Vector::from_array(*o) * M_PER_UM)
                    .collect()
            }
        };
        let placements = b.placements.get_ref();
        let span = b.placements.span();
        if placements.is_empty() {
            return Err(self.check.fail(
                Some(span),
                &format!("{key}.placements"),
                "give at least one placement",
            ));
        }
        let frame = self.frame(&AxisValues::ZERO, span.clone(), key)?;
        let mut cycles = Vec::new();
        for (n, place) in placements.iter().enumerate() {
            let key = format!("{key}.placements[{n}]");
            let origin = Vector::from_array(place.origin_mm) * M_PER_MM;
            if !origin.is_finite() {
                return Err(self.check.fail(
                    Some(span.clone()),
                    &format!("{key}.origin_mm"),
                    "expected three finite numbers (mm)",
                ));
            }
            let along = direction(
                self.check,
                place.along_row.unwrap_or([1.0, 0.0, 0.0]),
                span.clone(),
                &format!("{key}.along_row"),
            )?;
            let across = direction(
                self.check,
                place.across_rows.unwrap_or([0.0, 1.0, 0.0]),
                span.clone(),
                &format!("{key}.across_rows"),
            )?;
            if along.dot(across).abs() > 1e-6 {
                return Err(self.check.fail(
                    Some(span.clone()),
                    &format!("{key}.across_rows"),
                    "must be perpendicular to along_row",
                ));
            }
            let normal = along.cross(across);
            let tool_axis = frame.tool.z_axis;
            if normal.dot(tool_axis) < -1e-9 {
                return Err(self.check.fail(Some(span.clone()), &key, "the plate faces away from the probe (along_row × across_rows points down the tool axis)"));
            }
            let facing = (normal.cross(tool_axis).length() > 1e-9).then_some(normal);
            if facing.is_some() && points == 25 {
                return Err(self.check.fail(
                    Some(span.clone()),
                    &key,
                    "the 25-point ISO 10360-5 pattern covers the whole ball, but on a plate set on \
                     edge the plate hides its back half: use 4 to 24 points there",
                ));
            }
            let plate_from = Rotation::from_cols(along, across, normal);
            let grid = BallPlate::grid(origin, along, across, pitch, rows, columns, ball / 2.0);
            let calibrated: Vec<Vector> = grid
                .centres
                .iter()
                .zip(&offsets)
                .map(|(c, o)| plate_from.transpose() * (*c - origin) + *o)
                .collect();
            let plate = Arc::new(BallPlate {
                radius: ball / 2.0,
                centres: calibrated
                    .iter()
                    .map(|c| origin + plate_from * *c)
                    .collect(),
            });
            let target = Target::Plate(plate.clone());
            let mut features = Vec::new();
            for (index, centre) in plate.centres.iter().enumerate() {
                let moves = self.sphere_moves(
                    &frame,
                    &target,
                    *centre,
                    plate.radius,
                    points,
                    elevation,
                    facing,
                    span.clone(),
                    &format!("{key} ball {}", index + 1),
                )?;
                features.push(Feature {
                    rotary: AxisValues::ZERO,
                    target: target.clone(),
                    moves,
                    calibrated_diameter: Some(ball),
                    calibrated_centre: Some(calibrated[index]),
                });
            }
            cycles.push(Cycle {
                kind: CycleKind::Plate,
                features,
            });
        }
        Ok(cycles)
    }

    pub(super) fn mesh(
        &self,
        raw: &Spanned<RawMesh>,
        key: &str,
        dir: &Path,
    ) -> Result<Cycle, ScenarioError> {
        let m = raw.get_ref();
        let unit = match m.units.as_ref().map(|u| u.get_ref().as_str()) {
            None | Some("mm") => M_PER_MM,
            Some("m") => 1.0,
            Some("in") => 0.0254,
            Some(other) => {
                return Err(self.check.fail(
                    m.units.as_ref().map(|u| u.span()),
                    &format!("{key}.units"),
                    format!("\"{other}\": expected \"mm\", \"m\" or \"in\""),
                ));
            }
        };
        let path = dir.join(m.file.get_ref());
        let mesh = Mesh::read(&path, unit).map_err(|e| {
            self.check
                .fail(Some(m.file.span()), &format!("{key}.file"), e)
        })?;
        let origin = match &m.origin_mm {
            Some(o) => point(self.check, o, &format!("{key}.origin_mm"))?,
            None => Vector::ZERO,
        };
        let turn =
            finite(self.check, &m.rotation_deg, &format!("{key}.rotation_deg"))? * RAD_PER_DEG;
        let placed = mesh.placed(&crate::math::Pose::from_mat3_translation(
            Rotation::from_rotation_z(turn),
            origin,
        ));
        let max_travel = value(
            self.check,
            &m.max_travel_mm,
            &format!("{key}.max_travel_mm"),
            10.0,
            0.0,
            true,
        )? * M_PER_MM;
        let span = m.rotary.as_ref().map_or(raw.span(), |r| r.span());
        let rotary = self.rotary(
            m.rotary.as_ref().map(|r| *r.get_ref()),
            span.clone(),
            &format!("{key}.rotary"),
        )?;
        let frame = self.frame(&rotary, span, &format!("{key}.rotary"))?;
        let target = Target::Mesh(Arc::new(placed));
        let points = m.points.get_ref();
        if points.is_empty() {
            return Err(self.check.fail(
                Some(m.points.span()),
                &format!("{key}.points"),
                "give at least one point",
            ));
        }
        let mut moves = Vec::new();
        for (n, point) in points.iter().enumerate() {
            let key = format!("{key}.points[{n}]");
            let start = Vector::from_array(point.start_mm) * M_PER_MM;
            if !start.is_finite() {
                return Err(self.check.fail(
                    Some(m.points.span()),
                    &format!("{key}.start_mm"),
                    "expected three finite numbers (mm)",
                ));
            }
            let direction = direction(
                self.check,
                point.direction,
                m.points.span(),
                &format!("{key}.direction"),
            )?;
            moves.push(self.checked_move(
                &frame,
                &target,
                start,
                direction,
                max_travel,
                m.points.span(),
                &key,
            )?);
            // Vector probing: the controller compensates the stylus radius along the approach,
            // which is the surface point only when the approach is along the surface normal.
            if let Ok(Ok(Some(touch))) = Approach::new(start, direction)
                .map(|approach| target.touch(self.r, &approach, max_travel))
            {
                let off = (-touch.normal).angle_between(direction);
                if off > MESH_NORMAL_TOLERANCE {
                    let n = touch.normal;
                    return Err(self.check.fail(
                        Some(m.points.span()),
                        &format!("{key}.direction"),
                        format!(
                            "the approach is {:.2}° off the surface normal ({:.4}, {:.4}, {:.4}) at the planned contact: mesh points are probed along the normal (vector probing), since the stylus radius is compensated along the approach",
                            off.to_degrees(), n.x, n.y, n.z
                        ),
                    ));
                }
            }
        }
        Ok(Cycle {
            kind: CycleKind::Mesh,
            features: vec![Feature {
                rotary,
                target,
                moves,
                calibrated_diameter: None,
                calibrated_centre: None,
            }],
        })
    }
}
