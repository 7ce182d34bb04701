//! The cage set: one array of cage vertices shared by every cage; leaf cages (which bind the
//! mesh) and internal cages (which own lower-level cage vertices) as polygon faces over it.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::cage::{Cage, CageError};
use crate::coords::CoordinateKind;

/// A leaf cage: binds the mesh vertices inside it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LeafCage {
    /// Unique name.
    pub name: String,
    /// Coordinates of T_c (eq. 2).
    pub kind: CoordinateKind,
    /// h of this cage in (0, 1]; the scene default when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub h: Option<f64>,
    /// Per border (named by the neighbouring cage), an h override.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub border_h: BTreeMap<String, f64>,
    /// Polygon faces, counter-clockwise seen from outside, over the shared vertex array.
    pub faces: Vec<Vec<u32>>,
}

/// An internal cage: drives the lower-level cage vertices it owns (section 3.4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InternalCage {
    /// Unique name (among leaf and internal cages).
    pub name: String,
    /// Coordinates used for the owned vertices.
    pub kind: CoordinateKind,
    /// Polygon faces over the shared vertex array.
    pub faces: Vec<Vec<u32>>,
    /// Vertices of lower-level cages it owns (each vertex has at most one parent).
    pub owns: Vec<u32>,
    /// The joint this cage turns about when it is a control (a rest position): `rotate` and
    /// `scale` edits turn about it (carried along as the control moves), and the editor's
    /// pivot is there. Absent: the centroid of the cage's vertices.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pivot: Option<DVec3>,
    /// The joint's ring: leaf vertices owned by the cage that owns this one (its parent
    /// control), which turn half as far as this cage does relative to its parent, about the
    /// pivot, and stretch so that the two sides meet as a mitre (docs/math.md, "Joints").
    /// Empty: no ring bends with this cage.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joint: Vec<u32>,
}

/// All cages of a scene over one vertex array (rest positions).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct CageSet {
    /// Rest positions of every cage vertex.
    pub vertices: Vec<DVec3>,
    /// Leaf cages.
    pub leaves: Vec<LeafCage>,
    /// Internal cages.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub internals: Vec<InternalCage>,
}

/// Two adjacent leaf cages and their shared faces.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Adjacency {
    /// The lower cage index.
    pub first: usize,
    /// The higher cage index.
    pub second: usize,
    /// Shared faces: (index in `first`'s faces, index in `second`'s faces).
    pub faces: Vec<(usize, usize)>,
}

/// One cage of the set as a validated [`Cage`] over its own vertices, with the map back.
#[derive(Debug, Clone)]
pub struct LocalCage {
    /// The cage, vertices numbered locally.
    pub cage: Cage,
    /// Local vertex → shared vertex.
    pub global: Vec<u32>,
}

impl LocalCage {
    /// Builds the local cage of `faces` over `vertices` (positions of the shared array).
    pub fn new(vertices: &[DVec3], faces: &[Vec<u32>]) -> Result<Self, CageError> {
        let mut global: Vec<u32> = faces.iter().flatten().copied().collect();
        global.sort_unstable();
        global.dedup();
        if let Some(&v) = global.iter().find(|&&v| v as usize >= vertices.len()) {
            let face = faces.iter().position(|f| f.contains(&v)).unwrap_or(0);
            return Err(CageError::VertexOutOfRange {
                face,
                vertex: v as usize,
                count: vertices.len(),
            });
        }
        let local_of = |v: u32| global.binary_search(&v).map_or(0, |i| i as u32);
        let local_faces = faces
            .iter()
            .map(|f| f.iter().map(|&v| local_of(v)).collect())
            .collect();
        let positions = global.iter().map(|&v| vertices[v as usize]).collect();
        let cage =
            Cage::from_polygons(positions, local_faces).map_err(|e| globalise(e, &global))?;
        Ok(Self { cage, global })
    }
}

/// Rewrites local vertex indices of a cage error into shared-array indices.
fn globalise(error: CageError, global: &[u32]) -> CageError {
    let g = |v: usize| global.get(v).map_or(v, |&x| x as usize);
    match error {
        CageError::NonFiniteVertex { vertex, x, y, z } => CageError::NonFiniteVertex {
            vertex: g(vertex),
            x,
            y,
            z,
        },
        CageError::RepeatedCorner { face, vertex } => CageError::RepeatedCorner {
            face,
            vertex: g(vertex),
        },
        CageError::DuplicateVertex { first, second } => CageError::DuplicateVertex {
            first: g(first),
            second: g(second),
        },
        CageError::UnusedVertex { vertex } => CageError::UnusedVertex { vertex: g(vertex) },
        CageError::OpenEdge { a, b, face } => CageError::OpenEdge {
            a: g(a),
            b: g(b),
            face,
        },
        CageError::NonManifoldEdge { a, b, faces } => CageError::NonManifoldEdge {
            a: g(a),
            b: g(b),
            faces,
        },
        CageError::InconsistentOrientation {
            first,
            second,
            a,
            b,
        } => CageError::InconsistentOrientation {
            first,
            second,
            a: g(a),
            b: g(b),
        },
        other => other,
    }
}

impl CageSet {
    /// Leaf-cage faces grouped by their (sorted) vertex set: `(cage, face)` pairs per set.
    pub fn faces_by_vertex_set(&self) -> BTreeMap<Vec<u32>, Vec<(usize, usize)>> {
        let mut by_set: BTreeMap<Vec<u32>, Vec<(usize, usize)>> = BTreeMap::new();
        for (c, cage) in self.leaves.iter().enumerate() {
            for (f, face) in cage.faces.iter().enumerate() {
                let mut key = face.clone();
                key.sort_unstable();
                by_set.entry(key).or_default().push((c, f));
            }
        }
        by_set
    }

    /// The vertices of the leaf or internal cage called `name`, sorted.
    pub fn cage_vertices(&self, name: &str) -> Option<Vec<u32>> {
        let faces = self
            .leaves
            .iter()
            .find(|c| c.name == name)
            .map(|c| &c.faces)
            .or_else(|| {
                self.internals
                    .iter()
                    .find(|c| c.name == name)
                    .map(|c| &c.faces)
            })?;
        let mut vertices: Vec<u32> = faces.iter().flatten().copied().collect();
        vertices.sort_unstable();
        vertices.dedup();
        Some(vertices)
    }

    /// The vertices some cage (leaf or internal) uses in a face.
    pub fn used_vertices(&self) -> BTreeSet<u32> {
        self.leaves
            .iter()
            .flat_map(|c| c.faces.iter().flatten())
            .chain(self.internals.iter().flat_map(|c| c.faces.iter().flatten()))
            .copied()
            .collect()
    }

    /// Names of every cage, leaves first.
    pub fn cage_names(&self) -> Vec<&str> {
        self.leaves
            .iter()
            .map(|c| c.name.as_str())
            .chain(self.internals.iter().map(|c| c.name.as_str()))
            .collect()
    }

    /// Index of the leaf cage called `name`.
    pub fn leaf_index(&self, name: &str) -> Option<usize> {
        self.leaves.iter().position(|c| c.name == name)
    }

    /// Pairs of adjacent leaf cages (sharing at least one face, opposite orientation), with
    /// the shared faces as indices into each cage's face list.
    pub fn adjacency(&self) -> Vec<Adjacency> {
        let by_set = self.faces_by_vertex_set();
        let mut pairs: BTreeMap<(usize, usize), Vec<(usize, usize)>> = BTreeMap::new();
        for sharing in by_set.values() {
            if let [(ci, fi), (cj, fj)] = sharing[..]
                && ci != cj
                && is_reversed(&self.leaves[ci].faces[fi], &self.leaves[cj].faces[fj])
            {
                let (a, b) = if ci < cj {
                    ((ci, fi), (cj, fj))
                } else {
                    ((cj, fj), (ci, fi))
                };
                pairs.entry((a.0, b.0)).or_default().push((a.1, b.1));
            }
        }
        pairs
            .into_iter()
            .map(|((first, second), faces)| Adjacency {
                first,
                second,
                faces,
            })
            .collect()
    }
}

/// Whether polygon `b` is polygon `a` run backwards (same cycle, opposite direction).
pub fn is_reversed(a: &[u32], b: &[u32]) -> bool {
    if a.len() != b.len() || a.is_empty() {
        return false;
    }
    let Some(start) = b.iter().position(|&v| v == a[0]) else {
        return false;
    };
    let n = a.len();
    (0..n).all(|k| a[k] == b[(start + n - k) % n])
}

/// Whether polygon `b` is polygon `a` with the same direction (any starting corner).
pub fn is_same_cycle(a: &[u32], b: &[u32]) -> bool {
    if a.len() != b.len() || a.is_empty() {
        return false;
    }
    let Some(start) = b.iter().position(|&v| v == a[0]) else {
        return false;
    };
    let n = a.len();
    (0..n).all(|k| a[k] == b[(start + k) % n])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycles() {
        assert!(is_reversed(&[0, 1, 2, 3], &[2, 1, 0, 3]));
        assert!(!is_reversed(&[0, 1, 2, 3], &[1, 2, 3, 0]));
        assert!(is_same_cycle(&[0, 1, 2, 3], &[2, 3, 0, 1]));
    }
}
