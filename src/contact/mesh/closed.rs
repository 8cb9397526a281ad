//! Welding a facet soup into indexed triangles (vertices with equal coordinates become one), and
//! the check that the surface is closed: no degenerate facet, every edge shared by exactly two
//! facets that run along it in opposite directions (consistent orientation), and a positive
//! enclosed volume (the facets face outward).

use super::{Facets, MeshError};
use crate::math::{Real, Vector};
use std::collections::HashMap;

/// Indexed triangles.
pub(crate) struct Welded {
    pub vertices: Vec<[Real; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

/// One vertex per distinct coordinate triple (−0 and +0 alike), in order of first use.
pub(crate) fn weld(facets: &Facets) -> Welded {
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    let mut vertices = Vec::new();
    let triangles = facets
        .triangles
        .iter()
        .map(|triangle| {
            triangle.map(|vertex| {
                let key = vertex.map(|x| (x + 0.0).to_bits());
                *index.entry(key).or_insert_with(|| {
                    vertices.push(vertex);
                    (vertices.len() - 1) as u32
                })
            })
        })
        .collect();
    Welded {
        vertices,
        triangles,
    }
}

/// The enclosed volume (file units³) of a closed, outward surface, or what is wrong with it.
pub(crate) fn check(welded: &Welded, facets: &Facets, file: &str) -> Result<Real, MeshError> {
    let point = |i: u32| Vector::from_array(welded.vertices[i as usize]);
    let show = |i: u32| {
        let v = welded.vertices[i as usize];
        format!("({} {} {})", v[0], v[1], v[2])
    };
    let at = |facet: usize, message: String| {
        let line = facets.lines.get(facet).copied().flatten();
        MeshError::new(file, line, None, message)
    };
    let mut edges: HashMap<(u32, u32), usize> = HashMap::with_capacity(3 * welded.triangles.len());
    let mut volume = 0.0;
    for (facet, &[a, b, c]) in welded.triangles.iter().enumerate() {
        let (pa, pb, pc) = (point(a), point(b), point(c));
        if (pb - pa).cross(pc - pa).length_squared() == 0.0 {
            return Err(at(
                facet,
                format!(
                    "facet {} is degenerate (no area): {} {} {}",
                    facet + 1,
                    show(a),
                    show(b),
                    show(c)
                ),
            ));
        }
        volume += pa.dot(pb.cross(pc)) / 6.0;
        for edge in [(a, b), (b, c), (c, a)] {
            if let Some(other) = edges.insert(edge, facet) {
                return Err(at(
                    facet,
                    format!(
                        "the edge {} – {} runs the same way in facets {} and {}: the facets are \
                         inconsistently oriented, or more than two facets share the edge",
                        show(edge.0),
                        show(edge.1),
                        other + 1,
                        facet + 1
                    ),
                ));
            }
        }
    }
    let mut open: Vec<(&(u32, u32), &usize)> = edges
        .iter()
        .filter(|(edge, _)| !edges.contains_key(&(edge.1, edge.0)))
        .collect();
    // By facet, then by edge: the message must not depend on the hash map's order.
    open.sort_by_key(|(edge, facet)| (**facet, **edge));
    if let Some(&(edge, &facet)) = open.first() {
        return Err(at(
            facet,
            format!(
                "the mesh is not closed: the edge {} – {} of facet {} belongs to no other facet \
                 ({} open edges in all)",
                show(edge.0),
                show(edge.1),
                facet + 1,
                open.len()
            ),
        ));
    }
    if volume <= 0.0 {
        return Err(MeshError::new(
            file,
            None,
            None,
            format!(
                "the facets face inward (the enclosed volume is {volume:e} units³): reverse their vertex order"
            ),
        ));
    }
    Ok(volume)
}
