//! `mtwin analyze probe`: the evaluation of a `probe` table, simulated or exported: a sphere
//! fit per sphere feature (centre, radius as measured and its error against the calibration,
//! form, and ISO 10360-5's P_FTU for 25 points), a circle fit per ring (diameter and its error,
//! roundness), the centre-distance errors of each ball-plate placement against the calibrated
//! plate, and the surface points of mesh cycles.
//!
//! The controller's compensation, as the evaluation applies it: a sphere's radius is the fit
//! of the stylus-ball centres minus the stylus radius (plus it for a bore); a mesh point is the
//! latched centre plus the stylus radius along the approach. Everything is in machine axis
//! coordinates; distances do not depend on the frame.

use super::cycles::CycleKind;
use super::fit::{FitError, fit_circle, fit_sphere};
use super::table::{ProbeTable, ProbeTouch, RowKey, SphereRow, SpheresTable};

pub use super::results::{DistanceError, PlateResult, RingResult, SphereResult, SurfacePoint};
use crate::math::{M_PER_MM, M_PER_UM, Real, Vector};
use nalgebra::{Matrix3, SymmetricEigen};
use serde_json::{Value, json};
use std::collections::HashMap;
use std::fmt::Write as _;

/// Why a table could not be evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EvaluationError {
    /// A feature's fit failed.
    #[error("cycle {cycle}, feature {feature}: {error}")]
    Fit {
        /// The cycle.
        cycle: usize,
        /// The feature.
        feature: usize,
        /// Why.
        error: FitError,
    },
    /// A feature's rows disagree on its kind or rotary angles.
    #[error("cycle {cycle}, feature {feature}: its rows disagree on the {what}")]
    Inconsistent {
        /// The cycle.
        cycle: usize,
        /// The feature.
        feature: usize,
        /// What differs.
        what: &'static str,
    },
    /// A ball plate with more calibrated balls than [`MOST_PLATE_BALLS`].
    #[error(
        "cycle {cycle}: a ball plate of {balls} calibrated balls; at most {MOST_PLATE_BALLS} are evaluated \
         (every pair's distance is reported: the list grows with the square of the balls)"
    )]
    TooManyBalls {
        /// The cycle.
        cycle: usize,
        /// Its calibrated balls.
        balls: usize,
    },
    /// The stylus radius is not known or not valid.
    #[error(
        "the stylus radius is needed: give the table a `# stylus_radius_mm = R` preamble or --stylus-radius-mm"
    )]
    NoStylusRadius,
}

/// Most calibrated balls on one plate: the distance of every pair is evaluated and reported,
/// n(n − 1)/2 of them (1 000 balls: 499 500 distances), far beyond the ball plates in use
/// (5 × 5 to 11 × 11 balls). Features are grouped in linear time, so their count has no limit
/// beyond the memory their rows take.
pub const MOST_PLATE_BALLS: usize = 1000;

/// The evaluation of a `probe` table.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeEvaluation {
    /// The stylus radius used (m).
    pub stylus_radius: Real,
    /// Sphere and plate-ball fits, in table order.
    pub spheres: Vec<SphereResult>,
    /// Ring fits.
    pub rings: Vec<RingResult>,
    /// Ball-plate placements.
    pub plates: Vec<PlateResult>,
    /// Mesh points.
    pub mesh_points: Vec<SurfacePoint>,
    /// What the touches say against the set-up ([`super::plausible`]), a sentence each.
    pub cautions: Vec<String>,
    /// Columns of the table its reader read past (no figure depends on them).
    pub columns_not_read: Vec<String>,
}

/// The rows of each (cycle, feature), in order of first appearance: one hash look-up per row,
/// so the grouping is linear in the rows whatever the number of features.
fn features(table: &ProbeTable) -> Result<Vec<Vec<&ProbeTouch>>, EvaluationError> {
    let mut groups: Vec<Vec<&ProbeTouch>> = Vec::new();
    let mut index: HashMap<(usize, usize), usize> = HashMap::new();
    for touch in &table.touches {
        let key = (touch.key.cycle, touch.key.feature);
        match index.get(&key).map(|&i| &mut groups[i]) {
            Some(group) => {
                let first = group[0].key;
                let what = if first.kind != touch.key.kind {
                    Some("kind")
                } else if first.rotary != touch.key.rotary {
                    Some("rotary angles")
                } else {
                    None
                };
                if let Some(what) = what {
                    return Err(EvaluationError::Inconsistent {
                        cycle: key.0,
                        feature: key.1,
                        what,
                    });
                }
                group.push(touch);
            }
            None => {
                index.insert(key, groups.len());
                groups.push(vec![touch]);
            }
        }
    }
    Ok(groups)
}

/// Evaluates `table` with the stylus radius `stylus_radius` (m).
pub fn evaluate(
    table: &ProbeTable,
    stylus_radius: Real,
) -> Result<ProbeEvaluation, EvaluationError> {
    if !(stylus_radius.is_finite() && stylus_radius >= 0.0) {
        return Err(EvaluationError::NoStylusRadius);
    }
    let mut evaluation = ProbeEvaluation {
        stylus_radius,
        spheres: Vec::new(),
        rings: Vec::new(),
        plates: Vec::new(),
        mesh_points: Vec::new(),
        cautions: Vec::new(),
        columns_not_read: table.conditions.columns_not_read.clone(),
    };
    for group in features(table)? {
        let key = group[0].key;
        let failed = |error| EvaluationError::Fit {
            cycle: key.cycle,
            feature: key.feature,
            error,
        };
        let points: Vec<Vector> = group.iter().map(|t| t.position).collect();
        match key.kind {
            CycleKind::Sphere | CycleKind::Plate => {
                let fit = fit_sphere(&points).map_err(failed)?;
                let radius = fit.radius - stylus_radius;
                let sphere = SphereResult { key, fit, radius };
                evaluation
                    .cautions
                    .extend(super::plausible::feature_cautions(
                        &format!("cycle {} feature {}", key.cycle, key.feature),
                        &group,
                        sphere.centre(),
                        sphere.radius_error().map(|e| 2.0 * e),
                        None,
                        &sphere.fit.residuals,
                    ));
                evaluation.spheres.push(sphere);
            }
            CycleKind::Ring => {
                let ring = ring(&group, key, stylus_radius).map_err(failed)?;
                evaluation
                    .cautions
                    .extend(super::plausible::feature_cautions(
                        &format!("cycle {} feature {}", key.cycle, key.feature),
                        &group,
                        ring.centre,
                        ring.diameter_error(),
                        Some(&ring.angles),
                        &ring.fit.residuals,
                    ));
                evaluation.rings.push(ring);
            }
            CycleKind::Mesh => {
                evaluation
                    .mesh_points
                    .extend(group.iter().map(|t| SurfacePoint {
                        key,
                        point: t.point,
                        surface: t.position + t.approach * stylus_radius,
                    }));
            }
        }
    }
    // The calibrated balls of each plate cycle, cycles in order of first appearance.
    let mut plates: Vec<(usize, Vec<&SphereResult>)> = Vec::new();
    let mut plate_of: HashMap<usize, usize> = HashMap::new();
    for s in &evaluation.spheres {
        if s.key.kind != CycleKind::Plate {
            continue;
        }
        let at = *plate_of.entry(s.key.cycle).or_insert_with(|| {
            plates.push((s.key.cycle, Vec::new()));
            plates.len() - 1
        });
        if s.key.calibrated_centre.is_some() {
            plates[at].1.push(s);
        }
    }
    if let Some((cycle, balls)) = plates.iter().find(|(_, b)| b.len() > MOST_PLATE_BALLS) {
        return Err(EvaluationError::TooManyBalls {
            cycle: *cycle,
            balls: balls.len(),
        });
    }
    let mut results = Vec::new();
    for (cycle, balls) in plates {
        let mut distances = Vec::new();
        for (n, a) in balls.iter().enumerate() {
            for b in &balls[n + 1..] {
                let (ca, cb) = (a.key.calibrated_centre, b.key.calibrated_centre);
                let calibrated = ca.zip(cb).map_or(0.0, |(ca, cb)| (ca - cb).length());
                distances.push(DistanceError {
                    balls: (a.key.feature, b.key.feature),
                    calibrated,
                    measured: (a.centre() - b.centre()).length(),
                });
            }
        }
        if !distances.is_empty() {
            results.push(PlateResult { cycle, distances });
        }
    }
    evaluation
        .cautions
        .extend(results.iter().filter_map(super::plausible::odd_plate_ball));
    evaluation
        .cautions
        .extend(super::plausible::odd_sphere_form(&evaluation.spheres));
    evaluation.plates = results;
    Ok(evaluation)
}

/// A ring: the plane across the approach vectors (the eigenvector of `Σ e·eᵀ` with the
/// smallest eigenvalue is its normal), the circle fit there.
fn ring(group: &[&ProbeTouch], key: RowKey, stylus_radius: Real) -> Result<RingResult, FitError> {
    let mut scatter = Matrix3::<Real>::zeros();
    for t in group {
        let e = nalgebra::Vector3::new(t.approach.x, t.approach.y, t.approach.z);
        scatter += e * e.transpose();
    }
    let eigen = SymmetricEigen::new(scatter);
    let smallest = eigen.eigenvalues.imin();
    let n = eigen.eigenvectors.column(smallest);
    let normal = Vector::new(n[0], n[1], n[2]).normalize();
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let n_points = group.len() as Real;
    let mean = group.iter().map(|t| t.position).sum::<Vector>() / n_points;
    let planar: Vec<[Real; 2]> = group
        .iter()
        .map(|t| {
            let d = t.position - mean;
            [d.dot(u), d.dot(v)]
        })
        .collect();
    let fit = fit_circle(&planar)?;
    let centre = mean + u * fit.centre[0] + v * fit.centre[1];
    let outward: Real = group
        .iter()
        .map(|t| t.approach.dot(t.position - centre))
        .sum();
    let bore = outward > 0.0;
    let diameter = 2.0 * (fit.radius + if bore { stylus_radius } else { -stylus_radius });
    let angles = planar
        .iter()
        .map(|p| (p[1] - fit.centre[1]).atan2(p[0] - fit.centre[0]))
        .collect();
    Ok(RingResult {
        key,
        fit,
        angles,
        centre,
        diameter,
        bore,
    })
}

fn mm(v: Vector) -> [Real; 3] {
    (v / M_PER_MM).to_array()
}

fn key_json(key: &RowKey) -> serde_json::Map<String, Value> {
    let mut map = serde_json::Map::new();
    map.insert("cycle".into(), json!(key.cycle));
    map.insert("kind".into(), json!(key.kind.name()));
    map.insert("feature".into(), json!(key.feature));
    for (angle, name) in key.rotary.iter().zip(["a_deg", "b_deg", "c_deg"]) {
        if let Some(a) = angle {
            map.insert(name.into(), json!(a.to_degrees()));
        }
    }
    map
}

impl ProbeEvaluation {
    /// The fitted spheres as a `spheres` table.
    pub fn spheres_table(&self, conditions: super::table::ProbeConditions) -> SpheresTable {
        SpheresTable {
            spheres: self
                .spheres
                .iter()
                .map(|s| SphereRow {
                    key: s.key,
                    centre: s.centre(),
                    radius: s.radius,
                    form: s.fit.form(),
                    points: s.fit.residuals.len(),
                })
                .collect(),
            conditions,
        }
    }

    /// The evaluation with stable keys (see `mtwin analyze probe --help`).
    pub fn to_json(&self) -> Value {
        let um = |v: Real| v / M_PER_UM;
        let spheres: Vec<Value> = self
            .spheres
            .iter()
            .map(|s| {
                let mut m = key_json(&s.key);
                m.insert("centre_mm".into(), json!(mm(s.centre())));
                m.insert("radius_mm".into(), json!(s.radius / M_PER_MM));
                m.insert("radius_error_um".into(), json!(s.radius_error().map(um)));
                m.insert("form_um".into(), json!(um(s.fit.form())));
                m.insert("rms_um".into(), json!(um(s.fit.rms())));
                m.insert("p_ftu_um".into(), json!(s.p_ftu().map(um)));
                m.insert("points".into(), json!(s.fit.residuals.len()));
                Value::Object(m)
            })
            .collect();
        let rings: Vec<Value> = self
            .rings
            .iter()
            .map(|r| {
                let mut m = key_json(&r.key);
                m.insert("side".into(), json!(if r.bore { "bore" } else { "plug" }));
                m.insert("centre_mm".into(), json!(mm(r.centre)));
                m.insert("diameter_mm".into(), json!(r.diameter / M_PER_MM));
                m.insert(
                    "diameter_error_um".into(),
                    json!(r.diameter_error().map(um)),
                );
                m.insert("roundness_um".into(), json!(um(r.fit.form())));
                m.insert("points".into(), json!(r.fit.residuals.len()));
                Value::Object(m)
            })
            .collect();
        let plates: Vec<Value> = self
            .plates
            .iter()
            .map(|p| {
                json!({
                    "cycle": p.cycle,
                    "pairs": p.distances.len(),
                    "max_abs_error_um": um(p.max_abs_error()),
                    "rms_error_um": um(p.rms_error()),
                    "distances": p.distances.iter().map(|d| json!({
                        "from": d.balls.0,
                        "to": d.balls.1,
                        "calibrated_mm": d.calibrated / M_PER_MM,
                        "measured_mm": d.measured / M_PER_MM,
                        "error_um": um(d.measured - d.calibrated),
                    })).collect::<Vec<_>>(),
                })
            })
            .collect();
        let mesh_points: Vec<Value> = self
            .mesh_points
            .iter()
            .map(|p| {
                json!({
                    "cycle": p.key.cycle,
                    "feature": p.key.feature,
                    "point": p.point,
                    "surface_mm": mm(p.surface),
                })
            })
            .collect();
        json!({
            "stylus_radius_mm": self.stylus_radius / M_PER_MM,
            "spheres": spheres,
            "rings": rings,
            "plates": plates,
            "mesh_points": mesh_points,
            "cautions": self.cautions,
            "columns_not_read": self.columns_not_read,
        })
    }

    /// The evaluation for people.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        let angles = |key: &RowKey| {
            key.rotary
                .iter()
                .zip(['A', 'B', 'C'])
                .filter_map(|(a, l)| a.map(|a| format!(" {l} {:.3}°", a.to_degrees())))
                .collect::<String>()
        };
        let optional =
            |v: Option<Real>| v.map_or("-".to_string(), |v| format!("{:+.3}", v / M_PER_UM));
        let _ = writeln!(out, "stylus radius {:.4} mm", self.stylus_radius / M_PER_MM);
        if !self.spheres.is_empty() {
            let _ = writeln!(
                out,
                "\nspheres (centre mm; radius mm; radius error, form µm):"
            );
            for s in &self.spheres {
                let c = mm(s.centre());
                let _ = writeln!(
                    out,
                    "  cycle {} {} {}{}: ({:.4}, {:.4}, {:.4}); R {:.4}; error {}; form {:.3}{} ({} points)",
                    s.key.cycle,
                    s.key.kind.name(),
                    s.key.feature,
                    angles(&s.key),
                    c[0],
                    c[1],
                    c[2],
                    s.radius / M_PER_MM,
                    optional(s.radius_error()),
                    s.fit.form() / M_PER_UM,
                    s.p_ftu()
                        .map_or(String::new(), |p| format!(" = P_FTU {:.3}", p / M_PER_UM)),
                    s.fit.residuals.len()
                );
            }
        }
        for r in &self.rings {
            let _ = writeln!(
                out,
                "\nring cycle {} ({}){}: diameter {:.4} mm, error {} µm, roundness {:.3} µm ({} points)",
                r.key.cycle,
                if r.bore { "bore" } else { "plug" },
                angles(&r.key),
                r.diameter / M_PER_MM,
                optional(r.diameter_error()),
                r.fit.form() / M_PER_UM,
                r.fit.residuals.len()
            );
        }
        for p in &self.plates {
            let _ = writeln!(
                out,
                "\nball plate cycle {}: {} centre distances, error max |{:.3}| µm, RMS {:.3} µm",
                p.cycle,
                p.distances.len(),
                p.max_abs_error() / M_PER_UM,
                p.rms_error() / M_PER_UM
            );
        }
        if !self.mesh_points.is_empty() {
            let _ = writeln!(
                out,
                "\nmesh: {} surface points (--json lists them)",
                self.mesh_points.len()
            );
        }
        for caution in &self.cautions {
            let _ = writeln!(out, "\nCAUTION: {caution}.");
        }
        out += &crate::io::not_read_line(&self.columns_not_read);
        out
    }
}
