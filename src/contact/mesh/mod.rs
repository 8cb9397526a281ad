//! Triangle meshes (a workpiece from an STL or OBJ file): reading, the closedness check, and the
//! touch of a stylus ball by parry's shape cast (GJK, ball against [`TriMesh`]).
//!
//! | file | owns |
//! |---|---|
//! | `mod.rs` | [`Mesh`], [`MeshError`], the touch |
//! | `stl.rs` | STL, ASCII and binary (told apart by the binary size rule) |
//! | `obj.rs` | OBJ: `v` and `f` statements (polygons fanned into triangles), others ignored or refused |
//! | `closed.rs` | welding equal vertices, and the check that the surface is closed and outward |
//!
//! The readers are minimal: they read what the formats define for geometry and refuse the rest
//! with the file, line and column (binary STL: the facet and its byte offset).
//!
//! Accuracy: the cast is GJK, so a touch on a facet is exact to about 1e-10 m and no better
//! (see `tests/it/contact.rs`); analytic artefacts have closed forms in the sibling modules.

mod closed;
mod obj;
mod stl;

use super::{Approach, Artefact, ContactError, Touch, check_query, within};
use crate::math::{Pose, Real, Vector};
use rapier3d_f64::parry::math::Pose as ParryPose;
use rapier3d_f64::parry::query::{Ray, RayCast, ShapeCastOptions, ShapeCastStatus, cast_shapes};
use rapier3d_f64::parry::shape::{Ball, TriMesh};
use std::fmt;
use std::path::Path;

/// A mesh that could not be read or is not a closed surface; the message names the file and,
/// where the problem has one, the line and column.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct MeshError {
    /// The file.
    pub file: String,
    /// The 1-based line, when the problem has one.
    pub line: Option<u64>,
    /// The 1-based column, when the problem has one.
    pub column: Option<u64>,
    /// What is wrong.
    pub message: String,
}

impl MeshError {
    pub(crate) fn new(file: &str, line: Option<u64>, column: Option<u64>, message: String) -> Self {
        MeshError {
            file: file.to_string(),
            line,
            column,
            message,
        }
    }
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        write!(f, ": {}", self.message)
    }
}

/// The whitespace-separated words of a line, each with its 1-based column (in characters).
pub(crate) fn words(line: &str) -> Vec<(u64, &str)> {
    let mut out = Vec::new();
    let mut start: Option<(usize, u64)> = None;
    let ends = line
        .char_indices()
        .chain(std::iter::once((line.len(), ' ')));
    for (count, (at, c)) in ends.enumerate() {
        if c.is_whitespace() {
            if let Some((s, column)) = start.take() {
                out.push((column, &line[s..at]));
            }
        } else if start.is_none() {
            start = Some((at, count as u64 + 1));
        }
    }
    out
}

/// Triangles as read, in file units, each with the line it was defined on (text formats).
pub(crate) struct Facets {
    pub triangles: Vec<[[Real; 3]; 3]>,
    pub lines: Vec<Option<u64>>,
}

/// A closed, outward-oriented triangle mesh placed in the artefact frame.
#[derive(Clone)]
pub struct Mesh {
    shape: TriMesh,
    pose: ParryPose,
    volume: Real,
}

impl fmt::Debug for Mesh {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Mesh")
            .field("triangles", &self.shape.indices().len())
            .field("volume_m3", &self.volume)
            .finish()
    }
}

impl Mesh {
    /// Reads an STL (`.stl`) or OBJ (`.obj`) file whose coordinates are in units of
    /// `metres_per_unit` (1e-3 for millimetres), and checks that it is closed.
    pub fn read(path: impl AsRef<Path>, metres_per_unit: Real) -> Result<Mesh, MeshError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let bytes = std::fs::read(path)
            .map_err(|e| MeshError::new(&file, None, None, format!("cannot read: {e}")))?;
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("stl") => Mesh::from_stl(&bytes, &file, metres_per_unit),
            Some("obj") => Mesh::from_obj(&bytes, &file, metres_per_unit),
            _ => Err(MeshError::new(
                &file,
                None,
                None,
                "unknown mesh format: expected a .stl or .obj file".into(),
            )),
        }
    }

    /// An STL file's bytes (ASCII or binary); `file` names it in messages.
    pub fn from_stl(bytes: &[u8], file: &str, metres_per_unit: Real) -> Result<Mesh, MeshError> {
        Mesh::from_facets(stl::parse(bytes, file)?, file, metres_per_unit)
    }

    /// An OBJ file's bytes; `file` names it in messages.
    pub fn from_obj(bytes: &[u8], file: &str, metres_per_unit: Real) -> Result<Mesh, MeshError> {
        Mesh::from_facets(obj::parse(bytes, file)?, file, metres_per_unit)
    }

    fn from_facets(facets: Facets, file: &str, metres_per_unit: Real) -> Result<Mesh, MeshError> {
        if !(metres_per_unit.is_finite() && metres_per_unit > 0.0) {
            return Err(MeshError::new(
                file,
                None,
                None,
                format!("the unit {metres_per_unit} m must be finite and positive"),
            ));
        }
        let welded = closed::weld(&facets);
        let volume = closed::check(&welded, &facets, file)? * metres_per_unit.powi(3);
        let vertices = welded
            .vertices
            .iter()
            .map(|v| Vector::from_array(*v) * metres_per_unit)
            .collect();
        let shape = TriMesh::new(vertices, welded.triangles)
            .map_err(|e| MeshError::new(file, None, None, e.to_string()))?;
        Ok(Mesh {
            shape,
            pose: ParryPose::IDENTITY,
            volume,
        })
    }

    /// The mesh placed by `frame_from_mesh` (a rigid transform into the frame the touches are
    /// asked in).
    pub fn placed(mut self, frame_from_mesh: &Pose) -> Mesh {
        let rotation = glam::DQuat::from_mat3(&frame_from_mesh.matrix3).normalize();
        self.pose = ParryPose::from_parts(frame_from_mesh.translation, rotation);
        self
    }

    /// The number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.shape.indices().len()
    }

    /// The enclosed volume (m³, positive: the facets face outward).
    pub fn volume(&self) -> Real {
        self.volume
    }

    /// The parry shape, in the mesh's own frame.
    pub fn shape(&self) -> &TriMesh {
        &self.shape
    }
}

impl Artefact for Mesh {
    /// parry's `cast_shapes` of a [`Ball`] of radius `r` against the mesh (a ray cast for
    /// `r = 0`); the normal is the mesh's outward normal at the witness point. A start already
    /// touching the surface is an error; a start inside the solid is not detected (the cast
    /// sees a surface).
    fn touch(
        &self,
        tip_radius: Real,
        approach: &Approach,
        max_travel: Real,
    ) -> Result<Option<Touch>, ContactError> {
        check_query(tip_radius, max_travel)?;
        if tip_radius == 0.0 {
            let ray = Ray::new(approach.start(), approach.direction());
            let hit = self
                .shape
                .cast_ray_and_get_normal(&self.pose, &ray, max_travel, true);
            return Ok(hit.and_then(|h| within(h.time_of_impact, h.normal, max_travel)));
        }
        let hit = cast_shapes(
            &ParryPose::from_translation(approach.start()),
            approach.direction(),
            &Ball::new(tip_radius),
            &self.pose,
            Vector::ZERO,
            &self.shape,
            ShapeCastOptions::with_max_time_of_impact(max_travel),
        )
        .map_err(|e| ContactError::Unsupported(format!("{e:?}")))?;
        let Some(hit) = hit else { return Ok(None) };
        match hit.status {
            ShapeCastStatus::PenetratingOrWithinTargetDist => Err(ContactError::StartsInContact),
            ShapeCastStatus::Failed => Err(ContactError::Unsupported(
                "the ball-mesh cast did not converge".into(),
            )),
            _ => {
                let normal = self.pose.rotation * hit.normal2;
                Ok(within(hit.time_of_impact, normal, max_travel))
            }
        }
    }
}
