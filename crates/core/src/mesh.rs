//! The mesh being deformed: the original vertex layout (with optional normals and UVs) kept
//! for export, and a welded view in which vertices at the same position are one vertex, which
//! is what gets bound and deformed.

use std::collections::HashMap;

use glam::{DVec3, Vec2, Vec3};
use thiserror::Error;

pub mod look;
mod subdivide;
pub use subdivide::MAX_SEGMENTS as MAX_SUBDIVISION_SEGMENTS;

/// Why vertex and triangle arrays are not a mesh.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    /// The mesh has no triangle.
    #[error("the mesh has no triangles")]
    Empty,
    /// A vertex coordinate is NaN or infinite.
    #[error("mesh vertex {vertex} has a non-finite coordinate; fix or remove it")]
    NonFiniteVertex {
        /// The vertex.
        vertex: usize,
    },
    /// A vertex coordinate beyond [`crate::cage::MAX_COORDINATE`].
    #[error(
        "mesh vertex {vertex} has a coordinate of magnitude {value:e}, beyond ±{max:e} (the \
         deformation is computed in 32-bit floats); fix that vertex or scale the model down",
        max = crate::cage::MAX_COORDINATE
    )]
    CoordinateTooLarge {
        /// The vertex.
        vertex: usize,
        /// Its largest absolute coordinate.
        value: f64,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("mesh triangle {triangle} refers to vertex {vertex}, but there are only {count}")]
    VertexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The missing vertex.
        vertex: usize,
        /// Number of vertices.
        count: usize,
    },
    /// Normals or UVs do not match the vertex count.
    #[error("the mesh has {count} {attribute} for {vertices} vertices")]
    AttributeLength {
        /// `normals` or `uvs`.
        attribute: &'static str,
        /// Their number.
        count: usize,
        /// Number of vertices.
        vertices: usize,
    },
}

/// One part of a mesh read from a file with several (a glTF primitive): its vertices and
/// triangles are consecutive in the mesh's original layout.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MeshPart {
    /// Its vertices in the original layout.
    pub vertices: std::ops::Range<u32>,
    /// Its triangles (whose corners lie in `vertices`).
    pub triangles: std::ops::Range<u32>,
}

/// Coincident positions welded: per position its welded vertex, numbered in order of first
/// occurrence, and the welded positions. By a parallel sort of the positions' bits (a hash
/// map of millions of corners was most of reading a large STL file, and a sort cannot be
/// driven quadratic by crafted positions).
///
/// `known[i]`, where given, is a vertex at or before `i` that the reader knows coincides with
/// it (a file's shared position split by normals or UVs): only those representatives are
/// sorted, the rest follow them.
fn weld_coincident(positions: &[DVec3], known: Option<&[u32]>) -> (Vec<u32>, Vec<DVec3>) {
    use rayon::prelude::*;
    // -0.0 and 0.0 coincide. Keys sit beside their index, so sorting reads no other array.
    let key = |i: u32| {
        let p = positions[i as usize] + DVec3::ZERO;
        (p.to_array().map(f64::to_bits), i)
    };
    let mut sorted: Vec<([u64; 3], u32)> = match known {
        Some(known) => (0..positions.len() as u32)
            .into_par_iter()
            .filter(|&i| known[i as usize] == i)
            .map(key)
            .collect(),
        None => (0..positions.len() as u32)
            .into_par_iter()
            .map(key)
            .collect(),
    };
    sorted.par_sort_unstable();
    // Each position's first occurrence (ties sort by index: the group's first).
    let mut first = vec![0u32; positions.len()];
    for group in sorted.chunk_by(|a, b| a.0 == b.0) {
        for &(_, i) in group {
            first[i as usize] = group[0].1;
        }
    }
    if let Some(known) = known {
        // Representatives come first, so theirs is already set.
        for i in 0..positions.len() {
            first[i] = first[known[i] as usize];
        }
    }
    let mut welded_of = vec![0u32; positions.len()];
    let mut welded_positions = Vec::new();
    let weld = (0..positions.len())
        .map(|i| {
            let f = first[i] as usize;
            if f == i {
                welded_of[i] = welded_positions.len() as u32;
                welded_positions.push(positions[i]);
            }
            welded_of[f]
        })
        .collect();
    (weld, welded_positions)
}

/// A triangle mesh: original layout plus its welded view.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// The parts of the source file (glTF primitives), in order; empty for one part.
    parts: Vec<MeshPart>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    /// Original vertex → welded vertex.
    weld: Vec<u32>,
    welded_positions: Vec<DVec3>,
    welded_triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Bytes of the positions, triangles and weld map held in both layouts (normals and UVs
    /// left out): what a bind's memory is measured against.
    pub fn byte_size(&self) -> usize {
        (self.positions.len() + self.welded_positions.len()) * 24
            + (self.triangles.len() + self.welded_triangles.len()) * 12
            + self.weld.len() * 4
    }

    /// Builds a mesh, validating indices and values and welding coincident vertices.
    pub fn new(
        positions: Vec<DVec3>,
        triangles: Vec<[u32; 3]>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
    ) -> Result<Self, MeshError> {
        Self::new_with_known_coincident(positions, triangles, normals, uvs, None)
    }

    /// [`Self::new`] where the reader knows some coincident vertices already: `known[i]` is a
    /// vertex at or before `i` at exactly the same position (the file's one position split by
    /// per-corner normals or UVs), which spares sorting them when welding. A `known` that is
    /// not such a map (wrong length, a later vertex, another position) is ignored.
    pub fn new_with_known_coincident(
        positions: Vec<DVec3>,
        triangles: Vec<[u32; 3]>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
        known: Option<Vec<u32>>,
    ) -> Result<Self, MeshError> {
        if triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFiniteVertex { vertex });
        }
        let too_large = |p: &DVec3| p.abs().max_element() > crate::cage::MAX_COORDINATE;
        if let Some(vertex) = positions.iter().position(too_large) {
            return Err(MeshError::CoordinateTooLarge {
                vertex,
                value: positions[vertex].abs().max_element(),
            });
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&v) = tri.iter().find(|&&v| v as usize >= positions.len()) {
                return Err(MeshError::VertexOutOfRange {
                    triangle: t,
                    vertex: v as usize,
                    count: positions.len(),
                });
            }
        }
        for (attribute, count) in [
            ("normals", normals.as_ref().map(Vec::len)),
            ("uvs", uvs.as_ref().map(Vec::len)),
        ] {
            if let Some(count) = count.filter(|&c| c != positions.len()) {
                return Err(MeshError::AttributeLength {
                    attribute,
                    count,
                    vertices: positions.len(),
                });
            }
        }
        let known = known.filter(|known| {
            known.len() == positions.len()
                && known.iter().enumerate().all(|(i, &k)| {
                    (k as usize) <= i
                        && known[k as usize] == k
                        && positions[k as usize] == positions[i]
                })
        });
        let (weld, welded_positions) = weld_coincident(&positions, known.as_deref());
        let welded_triangles = triangles
            .iter()
            .map(|t| t.map(|v| weld[v as usize]))
            .collect();
        Ok(Self {
            positions,
            triangles,
            parts: Vec::new(),
            normals,
            uvs,
            weld,
            welded_positions,
            welded_triangles,
        })
    }

    /// This mesh split into `parts` (a glTF file's primitives, written back as such); parts
    /// that do not tile the vertices and triangles in order, each triangle inside its part's
    /// vertices, are ignored.
    pub fn with_parts(mut self, parts: Vec<MeshPart>) -> Self {
        let tiles = |ends: &mut dyn Iterator<Item = std::ops::Range<u32>>, total: usize| {
            let mut next = 0;
            for r in ends {
                if r.start != next || r.end < r.start {
                    return false;
                }
                next = r.end;
            }
            next as usize == total
        };
        let inside = parts.iter().all(|p| {
            self.triangles
                .get(p.triangles.start as usize..p.triangles.end as usize)
                .is_some_and(|ts| ts.iter().flatten().all(|v| p.vertices.contains(v)))
        });
        if parts.len() > 1
            && tiles(
                &mut parts.iter().map(|p| p.vertices.clone()),
                self.positions.len(),
            )
            && tiles(
                &mut parts.iter().map(|p| p.triangles.clone()),
                self.triangles.len(),
            )
            && inside
        {
            self.parts = parts;
        }
        self
    }

    /// This mesh with every position (original and welded) and normal mapped by `axes`, which
    /// must keep coincident points coincident and distinct points distinct (a permutation of
    /// the axes with signs, as turning a file's up axis to the scene's): the weld, triangles,
    /// UVs and parts stay as they are, so nothing is welded again.
    pub fn with_axes_mapped(mut self, axes: impl Fn(DVec3) -> DVec3) -> Self {
        for p in self
            .positions
            .iter_mut()
            .chain(self.welded_positions.iter_mut())
        {
            *p = axes(*p);
        }
        if let Some(normals) = &mut self.normals {
            for n in normals.iter_mut() {
                *n = axes(n.as_dvec3()).as_vec3();
            }
        }
        self
    }

    /// The parts of the source file (empty: one part).
    pub fn parts(&self) -> &[MeshPart] {
        &self.parts
    }

    /// Original vertex positions (export layout).
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Triangles over the original vertices.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Original normals, if the file had them.
    pub fn normals(&self) -> Option<&[Vec3]> {
        self.normals.as_deref()
    }

    /// Original texture coordinates, if the file had them.
    pub fn uvs(&self) -> Option<&[Vec2]> {
        self.uvs.as_deref()
    }

    /// Original vertex → welded vertex.
    pub fn weld_map(&self) -> &[u32] {
        &self.weld
    }

    /// Positions of the welded vertices: what is bound and deformed.
    pub fn welded_positions(&self) -> &[DVec3] {
        &self.welded_positions
    }

    /// The welded vertices in f32, as the renderer and the GPU use them.
    pub fn welded_positions_f32(&self) -> Vec<glam::Vec3> {
        self.welded_positions.iter().map(|p| p.as_vec3()).collect()
    }

    /// Triangles over the welded vertices.
    pub fn welded_triangles(&self) -> &[[u32; 3]] {
        &self.welded_triangles
    }

    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        crate::cage::bounds_of(&self.welded_positions)
    }

    /// Original-layout positions from welded positions (e.g. deformed ones).
    pub fn unweld(&self, welded: &[DVec3]) -> Vec<DVec3> {
        self.weld.iter().map(|&w| welded[w as usize]).collect()
    }

    /// Area-weighted vertex normals of the original layout for `positions` (original layout).
    /// Faces are smoothed across every vertex that shares the welded position and, when the
    /// mesh came with normals, the same original normal: hard edges stay hard, UV seams do not
    /// show.
    pub fn recompute_normals(&self, positions: &[DVec3]) -> Vec<Vec3> {
        let group_of: Vec<usize> = match &self.normals {
            None => self.weld.iter().map(|&w| w as usize).collect(),
            Some(normals) => {
                let mut groups: HashMap<(u32, [u32; 3]), usize> = HashMap::new();
                self.weld
                    .iter()
                    .zip(normals)
                    .map(|(&w, n)| {
                        let next = groups.len();
                        *groups
                            .entry((w, n.to_array().map(f32::to_bits)))
                            .or_insert(next)
                    })
                    .collect()
            }
        };
        let groups = group_of.iter().copied().max().map_or(0, |m| m + 1);
        let mut sums = vec![DVec3::ZERO; groups];
        for tri in &self.triangles {
            let [a, b, c] = tri.map(|v| positions[v as usize]);
            let area_normal = (b - a).cross(c - a);
            for &v in tri {
                sums[group_of[v as usize]] += area_normal;
            }
        }
        group_of
            .iter()
            .map(|&g| sums[g].normalize_or_zero().as_vec3())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sort-based weld numbers welded vertices in order of first occurrence, exactly as a
    /// map from position to first index would, on many duplicates in scrambled order.
    #[test]
    fn the_weld_numbers_vertices_by_first_occurrence() {
        let pool: Vec<DVec3> = (0..97)
            .map(|k| DVec3::new(f64::from(k % 7), f64::from(k), -0.5))
            .collect();
        let positions: Vec<DVec3> = (0..20_000u32)
            .map(|i| pool[(i.wrapping_mul(2_654_435_761) >> 7) as usize % pool.len()])
            .collect();
        let (weld, welded) = weld_coincident(&positions, None);
        let mut index = HashMap::new();
        let mut expected_positions = Vec::new();
        let expected: Vec<u32> = positions
            .iter()
            .map(|p| {
                *index
                    .entry(p.to_array().map(f64::to_bits))
                    .or_insert_with(|| {
                        expected_positions.push(*p);
                        expected_positions.len() as u32 - 1
                    })
            })
            .collect();
        assert_eq!(weld, expected);
        assert_eq!(welded, expected_positions);
        assert_eq!(welded.len(), pool.len());
    }

    #[test]
    fn welds_coincident_vertices_and_keeps_layout() {
        // Two triangles of a quad with the diagonal's vertices duplicated (a UV seam).
        let p = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::Y,
            DVec3::new(-0.0, 0.0, 0.0),
        ];
        let mesh = Mesh::new(p, vec![[0, 1, 2], [3, 4, 5]], None, None).unwrap();
        assert_eq!(mesh.welded_positions().len(), 4);
        assert_eq!(mesh.welded_triangles(), &[[0, 1, 2], [2, 3, 0]]);
        let normals = mesh.recompute_normals(mesh.positions());
        assert!(normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
        assert_eq!(mesh.unweld(mesh.welded_positions()), mesh.positions());
    }

    /// A reader's known coincident vertices give the weld a full sort gives (coincident
    /// vertices it did not know about, at other file positions, still weld); a map that is not
    /// one (a vertex said to coincide with another elsewhere) is ignored.
    #[test]
    fn known_coincident_vertices_weld_as_a_full_sort_does() {
        // Vertices 0-1 and 3-4 share a file position each; 5 lies where 0 does without the
        // reader knowing.
        let p = vec![
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::Y,
            DVec3::ZERO,
        ];
        let triangles = vec![[0, 2, 3], [1, 4, 2], [5, 2, 4]];
        let full = Mesh::new(p.clone(), triangles.clone(), None, None).unwrap();
        let known = vec![0, 0, 2, 3, 3, 5];
        let told =
            Mesh::new_with_known_coincident(p.clone(), triangles.clone(), None, None, Some(known))
                .unwrap();
        assert_eq!(told, full);
        assert_eq!(told.welded_positions().len(), 3);
        let wrong = vec![0, 0, 0, 3, 3, 5]; // vertex 2 is not at vertex 0
        let ignored =
            Mesh::new_with_known_coincident(p, triangles, None, None, Some(wrong)).unwrap();
        assert_eq!(ignored, full);
    }

    /// Turning a mesh's axes keeps its weld, and gives what welding the turned positions
    /// afresh gives.
    #[test]
    fn mapping_the_axes_keeps_the_weld_of_a_fresh_mesh() {
        let p = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(-0.0, 1.0, 0.0),
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(0.0, 0.0, -0.0),
        ];
        let triangles = vec![[0, 1, 2], [3, 2, 4]];
        let turn = |v: DVec3| DVec3::new(v.x, -v.z, v.y);
        let mesh = Mesh::new(p.clone(), triangles.clone(), None, None).unwrap();
        let turned = mesh.with_axes_mapped(turn);
        let fresh = Mesh::new(p.into_iter().map(turn).collect(), triangles, None, None).unwrap();
        assert_eq!(turned.weld_map(), fresh.weld_map());
        assert_eq!(turned.welded_triangles(), fresh.welded_triangles());
        for (a, b) in turned
            .welded_positions()
            .iter()
            .zip(fresh.welded_positions())
        {
            assert_eq!(*a, *b);
        }
    }

    #[test]
    fn rejects_bad_arrays() {
        assert_eq!(
            Mesh::new(vec![DVec3::ZERO], vec![], None, None),
            Err(MeshError::Empty)
        );
        let bad = Mesh::new(vec![DVec3::ZERO; 3], vec![[0, 1, 3]], None, None);
        assert!(matches!(
            bad,
            Err(MeshError::VertexOutOfRange { vertex: 3, .. })
        ));
        let nan = Mesh::new(
            vec![DVec3::ZERO, DVec3::NAN, DVec3::X],
            vec![[0, 1, 2]],
            None,
            None,
        );
        assert_eq!(nan, Err(MeshError::NonFiniteVertex { vertex: 1 }));
    }
}
