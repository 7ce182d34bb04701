//! *Cages topology (section 3.1): adjacency, borders B_{c_i c_j}, boundaries B_{c_i}, boundary
//! vertices, the join cage jc(v) of each boundary vertex (the union of the cages incident at v
//! with their shared faces removed), and the interior / non-interior classification of v.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use glam::DVec3;
use thiserror::Error;

use crate::cage::CageError;
use crate::coords::CoordinateKind;
use crate::scene::{CageSet, JoinPolicy, LocalCage};

/// Why the cage set cannot be used for *Cages.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TopologyError {
    /// A leaf cage is invalid (the scene should have been validated first).
    #[error("cage '{cage}': {problem}")]
    Cage {
        /// The cage.
        cage: String,
        /// Its problem.
        problem: CageError,
    },
    /// A join cage is not a closed manifold: cages meet at a vertex only along an edge or at
    /// the vertex itself.
    #[error(
        "the join cage of cage vertex {vertex} (the union of cages {cages}) is not a valid cage: {problem}; \
         cages meeting at a vertex must also share faces there (fill the gap with a cage, or split the vertex)"
    )]
    JoinCage {
        /// The boundary vertex.
        vertex: u32,
        /// The incident cages' names.
        cages: String,
        /// The join cage's problem.
        problem: CageError,
    },
}

/// A border between two leaf cages: the other cage and the shared vertices.
#[derive(Debug, Clone, PartialEq)]
pub struct Border {
    /// The neighbouring cage.
    pub other: usize,
    /// Vertices of the shared faces (B_{c_i c_j}).
    pub vertices: Vec<u32>,
}

/// The join cage of a boundary vertex.
#[derive(Debug, Clone)]
pub struct JoinCage {
    /// The boundary vertex v.
    pub vertex: u32,
    /// Leaf cages incident at v.
    pub cages: Vec<usize>,
    /// The union as a cage (vertices numbered locally; `global` maps back), shared by every
    /// boundary vertex with the same incident cages.
    pub local: Arc<LocalCage>,
    /// Its polygon faces over shared vertex indices (shared as `local` is).
    pub polygons: Arc<Vec<Vec<u32>>>,
    /// Whether v is inside jc(v) (no face of jc(v) contains it).
    pub interior: bool,
    /// Coordinates of T_{jc(v)} (eqs. 9, 10) by the scene's join policy.
    pub kind: CoordinateKind,
    /// Whether the join cage is convex (decides the automatic policy, Fig. 10).
    pub convex: bool,
}

/// The whole topology of a leaf-cage set.
#[derive(Debug, Clone)]
pub struct Topology {
    /// Leaf cages as validated local cages.
    pub leaves: Vec<LocalCage>,
    /// Per leaf cage, its borders.
    pub borders: Vec<Vec<Border>>,
    /// Per leaf cage, its boundary vertices (union of its borders' vertices), sorted.
    pub boundary: Vec<Vec<u32>>,
    /// Join cages by boundary vertex.
    pub joins: BTreeMap<u32, JoinCage>,
    /// Per boundary vertex v, the interior vertices sharing a leaf cage with v, v itself
    /// among them when it is interior: one list shared by every vertex with the same
    /// incident cages (a subdivided border holds thousands). [`Topology::interior_neighbours`]
    /// leaves v out (Int(jc(v)) − {v} in eq. 8).
    pub interior_near: BTreeMap<u32, Arc<[u32]>>,
}

impl Topology {
    /// The interior vertices u ≠ v sharing a leaf cage with boundary vertex v (Int(jc(v)) −
    /// {v} in eq. 8), increasing.
    pub fn interior_neighbours(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.interior_near
            .get(&v)
            .into_iter()
            .flat_map(|near| near.iter().copied())
            .filter(move |&u| u != v)
    }

    /// Builds the topology of the leaf cages of `set`.
    pub fn new(set: &CageSet, policy: JoinPolicy) -> Result<Self, TopologyError> {
        let leaves = set
            .leaves
            .iter()
            .map(|c| {
                LocalCage::new(&set.vertices, &c.faces).map_err(|problem| TopologyError::Cage {
                    cage: c.name.clone(),
                    problem,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let n = set.leaves.len();
        let mut borders: Vec<Vec<Border>> = vec![Vec::new(); n];
        for adjacency in set.adjacency() {
            let (i, j) = (adjacency.first, adjacency.second);
            let mut vertices: Vec<u32> = adjacency
                .faces
                .iter()
                .flat_map(|&(fi, _)| set.leaves[i].faces[fi].iter().copied())
                .collect();
            vertices.sort_unstable();
            vertices.dedup();
            borders[i].push(Border {
                other: j,
                vertices: vertices.clone(),
            });
            borders[j].push(Border { other: i, vertices });
        }
        let boundary: Vec<Vec<u32>> = borders
            .iter()
            .map(|bs| {
                let set: BTreeSet<u32> =
                    bs.iter().flat_map(|b| b.vertices.iter().copied()).collect();
                set.into_iter().collect()
            })
            .collect();
        let cage_vertices: Vec<BTreeSet<u32>> = set
            .leaves
            .iter()
            .map(|c| c.faces.iter().flatten().copied().collect())
            .collect();
        let all_boundary: BTreeSet<u32> = boundary.iter().flatten().copied().collect();
        let mut joins = BTreeMap::new();
        // The border vertices of one border share their incident cages, so their join cages are
        // one cage: built and validated once per set of cages.
        let mut built: BTreeMap<Vec<usize>, BuiltJoin> = BTreeMap::new();
        for &v in &all_boundary {
            let cages: Vec<usize> = (0..n).filter(|&c| cage_vertices[c].contains(&v)).collect();
            if !built.contains_key(&cages) {
                let (local, polygons) =
                    join_cage_of(set, &cages).map_err(|problem| TopologyError::JoinCage {
                        vertex: v,
                        cages: cages
                            .iter()
                            .map(|&c| set.leaves[c].name.as_str())
                            .collect::<Vec<_>>()
                            .join(", "),
                        problem,
                    })?;
                let convex = is_convex(&local);
                let mut on_faces: Vec<u32> = polygons.iter().flatten().copied().collect();
                on_faces.sort_unstable();
                on_faces.dedup();
                built.insert(
                    cages.clone(),
                    BuiltJoin {
                        local: Arc::new(local),
                        polygons: Arc::new(polygons),
                        convex,
                        on_faces,
                    },
                );
            }
            let Some(built) = built.get(&cages) else {
                continue;
            };
            let (local, polygons, convex, interior) = (
                Arc::clone(&built.local),
                Arc::clone(&built.polygons),
                built.convex,
                built.on_faces.binary_search(&v).is_err(),
            );
            let kind = match policy {
                JoinPolicy::Auto => {
                    if convex {
                        CoordinateKind::MeanValue
                    } else {
                        CoordinateKind::Harmonic
                    }
                }
                JoinPolicy::Mvc => CoordinateKind::MeanValue,
                JoinPolicy::Hc => CoordinateKind::Harmonic,
                JoinPolicy::Gc => CoordinateKind::Green,
            };
            joins.insert(
                v,
                JoinCage {
                    vertex: v,
                    cages,
                    local,
                    polygons,
                    interior,
                    kind,
                    convex,
                },
            );
        }
        // Interior vertices by leaf cage, then their union per set of incident cages.
        let mut interior_in_cage: Vec<Vec<u32>> = vec![Vec::new(); n];
        for join in joins.values().filter(|j| j.interior) {
            // A join cage's cages are those holding its vertex.
            for &c in &join.cages {
                interior_in_cage[c].push(join.vertex);
            }
        }
        let mut near_of_cages: BTreeMap<&[usize], Arc<[u32]>> = BTreeMap::new();
        let mut interior_near = BTreeMap::new();
        for (&v, join) in &joins {
            let near = near_of_cages
                .entry(join.cages.as_slice())
                .or_insert_with(|| {
                    let mut near: Vec<u32> = join
                        .cages
                        .iter()
                        .flat_map(|&c| interior_in_cage[c].iter().copied())
                        .collect();
                    near.sort_unstable();
                    near.dedup();
                    near.into()
                });
            interior_near.insert(v, Arc::clone(near));
        }
        Ok(Self {
            leaves,
            borders,
            boundary,
            joins,
            interior_near,
        })
    }
}

/// A join cage built once for its set of leaf cages: the cage, its polygons, whether convex.
/// A join cage as built once for every boundary vertex with the same incident cages.
struct BuiltJoin {
    local: Arc<LocalCage>,
    polygons: Arc<Vec<Vec<u32>>>,
    convex: bool,
    /// The vertices on its faces, increasing (a vertex not among them is interior).
    on_faces: Vec<u32>,
}

/// The union of the leaf cages `cages`, the faces shared by two of them removed (eq. 8's
/// jc(v)), as a validated cage and its polygons.
fn join_cage_of(set: &CageSet, cages: &[usize]) -> Result<(LocalCage, Vec<Vec<u32>>), CageError> {
    let mut count: BTreeMap<Vec<u32>, usize> = BTreeMap::new();
    for &c in cages {
        for face in &set.leaves[c].faces {
            let mut key = face.clone();
            key.sort_unstable();
            *count.entry(key).or_default() += 1;
        }
    }
    let polygons: Vec<Vec<u32>> = cages
        .iter()
        .flat_map(|&c| set.leaves[c].faces.iter())
        .filter(|face| {
            let mut key = (*face).clone();
            key.sort_unstable();
            count[&key] == 1
        })
        .cloned()
        .collect();
    let local = LocalCage::new(&set.vertices, &polygons)?;
    Ok((local, polygons))
}

/// Whether every vertex lies behind (or on, within 1e-9 of the diagonal) every face plane.
///
/// First edge by edge: across each edge, the far corner of the triangle beyond must lie behind
/// the triangle's plane; a corner in front fails the whole test too, so a concave cage is
/// answered in linear time. A cage convex at every edge is convex (a closed, connected, locally
/// convex surface bounds a convex solid: Tietze's theorem), so every vertex against every plane
/// is only checked while that takes at most [`CONVEXITY_BUDGET`] products; beyond it (a box
/// subdivided six times: 3.2 billion) the edges decide.
fn is_convex(local: &LocalCage) -> bool {
    let cage = &local.cage;
    let p = cage.positions();
    let tolerance = 1e-9 * cage.diagonal();
    let triangles = cage.triangles();
    let normals = cage.triangle_normals();
    let behind = |t: usize, x: DVec3| {
        let a = p[triangles[t][0] as usize];
        normals[t].dot(x - a) <= tolerance
    };
    // Each triangle's edges, by their corners in increasing order: the two triangles on an
    // edge sort next to each other.
    let mut edges: Vec<([u32; 2], usize)> = triangles
        .iter()
        .enumerate()
        .flat_map(|(t, tri)| (0..3).map(move |k| (sorted_pair(tri[k], tri[(k + 1) % 3]), t)))
        .collect();
    edges.sort_unstable();
    let far_corner = |t: usize, edge: [u32; 2]| {
        triangles[t]
            .iter()
            .find(|c| !edge.contains(c))
            .map(|&c| p[c as usize])
    };
    for pair in edges.windows(2) {
        let [(edge, t), (other_edge, u)] = [pair[0], pair[1]];
        if edge != other_edge {
            continue;
        }
        let (Some(beyond_t), Some(beyond_u)) = (far_corner(u, edge), far_corner(t, edge)) else {
            continue;
        };
        if !behind(t, beyond_t) || !behind(u, beyond_u) {
            return false;
        }
    }
    if triangles.len().saturating_mul(p.len()) > CONVEXITY_BUDGET {
        return true;
    }
    (0..triangles.len()).all(|t| p.iter().all(|&x| behind(t, x)))
}

/// Vertex-against-plane products [`is_convex`] spends at most beyond its edge test.
const CONVEXITY_BUDGET: usize = 50_000_000;

fn sorted_pair(a: u32, b: u32) -> [u32; 2] {
    [a.min(b), a.max(b)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::demo::demo_scene;

    #[test]
    fn egg_has_two_interior_vertices_and_bar_none() {
        let egg = demo_scene("egg", 0.2).unwrap();
        let t = Topology::new(&egg.cages, JoinPolicy::Auto).unwrap();
        let interior: Vec<u32> = t
            .joins
            .values()
            .filter(|j| j.interior)
            .map(|j| j.vertex)
            .collect();
        assert_eq!(interior.len(), 2, "{interior:?}");
        for &v in &interior {
            assert_eq!(t.joins[&v].cages.len(), 8);
            assert!(t.joins[&v].convex);
            assert_eq!(t.joins[&v].kind, CoordinateKind::MeanValue);
        }
        let bar = demo_scene("bar", 0.2).unwrap();
        let t = Topology::new(&bar.cages, JoinPolicy::Auto).unwrap();
        assert_eq!(t.joins.len(), 4);
        assert!(t.joins.values().all(|j| !j.interior && j.cages.len() == 2));
        assert_eq!(t.boundary[0].len(), 4);
    }

    /// A box with 32 × 32 quads a face (12,288 triangles: every vertex against every plane
    /// would be 75 million products, over the budget, so the edges decide) is convex; with one
    /// vertex pushed in, it is not.
    #[test]
    fn convexity_of_a_finely_divided_box_is_answered_from_its_edges() {
        let mesh = crate::generate::demo::box_mesh(DVec3::ZERO, DVec3::ONE, [32; 3]);
        let mut positions = mesh.welded_positions().to_vec();
        let faces: Vec<Vec<u32>> = mesh.welded_triangles().iter().map(|t| t.to_vec()).collect();
        assert!(faces.len() * positions.len() > CONVEXITY_BUDGET);
        let cage = LocalCage::new(&positions, &faces).unwrap();
        assert!(is_convex(&cage));
        let centre = positions
            .iter()
            .position(|p| p.distance(DVec3::new(0.5, 0.5, 1.0)) < 1e-9)
            .unwrap();
        positions[centre].z -= 0.01;
        let dented = LocalCage::new(&positions, &faces).unwrap();
        assert!(!is_convex(&dented));
    }

    #[test]
    fn concave_join_cages_get_harmonic_coordinates_automatically() {
        // Three boxes in an L: the corner vertex's join cage is L-shaped (concave).
        use crate::cage::shapes::box_faces;
        use crate::scene::LeafCage;
        use glam::DVec3;
        let mut set = CageSet::default();
        for z in [0.0, 1.0] {
            for y in [0.0, 1.0, 2.0] {
                for x in [0.0, 1.0, 2.0] {
                    set.vertices.push(DVec3::new(x, y, z));
                }
            }
        }
        let id = |i: u32, j: u32, k: u32| i + 3 * j + 9 * k;
        for (i, j) in [(0, 0), (1, 0), (0, 1)] {
            set.leaves.push(LeafCage {
                name: format!("c{i}{j}"),
                kind: CoordinateKind::MeanValue,
                h: None,
                border_h: BTreeMap::new(),
                faces: box_faces(std::array::from_fn(|c| {
                    let c = c as u32;
                    id(i + (c & 1), j + ((c >> 1) & 1), c >> 2)
                })),
            });
        }
        let t = Topology::new(&set, JoinPolicy::Auto).unwrap();
        let corner = t.joins.get(&id(1, 1, 0)).unwrap();
        assert_eq!(corner.cages.len(), 3);
        assert!(!corner.convex);
        assert_eq!(corner.kind, CoordinateKind::Harmonic);
        assert!(
            t.joins
                .values()
                .filter(|j| j.cages.len() == 2)
                .all(|j| j.convex && j.kind == CoordinateKind::MeanValue)
        );
        let forced = Topology::new(&set, JoinPolicy::Gc).unwrap();
        assert!(
            forced
                .joins
                .values()
                .all(|j| j.kind == CoordinateKind::Green)
        );
    }
}
