//! OBJ files: `v x y z [w]` vertices and `f` faces (`i`, `i/t`, `i//n`, `i/t/n`; negative
//! indices count back from the last vertex). A polygon of more than three vertices is fanned
//! into triangles from its first vertex (right for the convex, planar faces exporters write).
//! Normals, texture coordinates, groups, objects, smoothing and materials are ignored; free-form
//! geometry and lines are refused.

use super::{Facets, MeshError};
use crate::math::Real;

const IGNORED: [&str; 9] = ["vn", "vt", "vp", "o", "g", "s", "usemtl", "mtllib", "p"];

/// The facets of an OBJ file.
pub(crate) fn parse(bytes: &[u8], file: &str) -> Result<Facets, MeshError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| MeshError::new(file, None, None, format!("not UTF-8 text: {e}")))?;
    let mut vertices: Vec<[Real; 3]> = Vec::new();
    let (mut triangles, mut lines) = (Vec::new(), Vec::new());
    for (index, line) in text.lines().enumerate() {
        let number = index as u64 + 1;
        let content = line.split('#').next().unwrap_or_default();
        let mut words = super::words(content).into_iter();
        let Some((_, keyword)) = words.next() else {
            continue;
        };
        let error = |column: u64, message: String| {
            MeshError::new(file, Some(number), Some(column), message)
        };
        match keyword {
            "v" => {
                let values: Vec<(u64, &str)> = words.collect();
                if values.len() < 3 || values.len() > 4 {
                    return Err(error(
                        1,
                        format!(
                            "`v` takes 3 coordinates (and an optional w), found {}",
                            values.len()
                        ),
                    ));
                }
                let mut vertex = [0.0; 3];
                for (value, &(column, word)) in vertex.iter_mut().zip(&values) {
                    *value = word
                        .parse::<Real>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| {
                            error(column, format!("expected a finite number, found `{word}`"))
                        })?;
                }
                vertices.push(vertex);
            }
            "f" => {
                let mut polygon = Vec::new();
                for (column, word) in words {
                    let index_text = word.split('/').next().unwrap_or_default();
                    let given: i64 = index_text.parse().map_err(|_| {
                        error(column, format!("expected a vertex index, found `{word}`"))
                    })?;
                    let count = vertices.len() as i64;
                    let resolved = if given > 0 { given - 1 } else { count + given };
                    if given == 0 || !(0..count).contains(&resolved) {
                        return Err(error(
                            column,
                            format!(
                                "vertex index {given} does not name one of the {count} vertices defined so far"
                            ),
                        ));
                    }
                    polygon.push(vertices[resolved as usize]);
                }
                if polygon.len() < 3 {
                    return Err(error(
                        1,
                        format!("a face needs at least 3 vertices, found {}", polygon.len()),
                    ));
                }
                for k in 1..polygon.len() - 1 {
                    triangles.push([polygon[0], polygon[k], polygon[k + 1]]);
                    lines.push(Some(number));
                }
            }
            k if IGNORED.contains(&k) => {}
            other => {
                return Err(error(
                    1,
                    format!(
                        "unsupported statement `{other}`: this reader takes v and f (vn, vt, o, g, s, usemtl, mtllib ignored)"
                    ),
                ));
            }
        }
    }
    if triangles.is_empty() {
        return Err(MeshError::new(
            file,
            None,
            None,
            "no faces (`f` statements)".into(),
        ));
    }
    Ok(Facets { triangles, lines })
}
