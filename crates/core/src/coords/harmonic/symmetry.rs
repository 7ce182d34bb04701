//! Mirror and quarter-turn symmetries of one cage's discrete harmonic problem, so that a
//! symmetric cage solves one harmonic function per orbit of its vertices instead of one per
//! vertex (a limb's box cage, mirrored left to right and front to back, solves about a
//! quarter of them).
//!
//! If an isometry g maps the cage onto itself, vertex k onto vertex σ(k), then
//! u_σ(k)(g x) = u_k(x): both are harmonic with the hat function of σ(k) on the boundary.
//! The same holds for the discrete system when g maps the grid onto itself, which the grid's
//! centring on the cage's box gives for the 48 signed axis permutations (a cube's
//! symmetries), provided the dimensions they swap are equal. Round-off can still make the
//! discrete system differ from its image (a node classified on one side of the cage, a
//! crossing's θ), so a symmetry is used only after the system itself is checked: the unknown
//! mask, the diagonal and every right-hand side must map onto themselves to [`TOLERANCE`].

use std::collections::HashMap;

use glam::{DVec3, UVec3};

use super::grid::{BoundaryValue, CageGrid};
use crate::cage::Cage;
use crate::cage::cube_symmetry::CubeSymmetry;

/// Largest relative difference between the system and its image under a symmetry that still
/// counts as equal. The system's rounding asymmetry is about 1e-15 of its entries; a
/// difference δ moves the solution by at most about ‖L⁻¹‖ δ (a few hundred at the resolutions
/// allowed), far below the solver's tolerance.
const TOLERANCE: f64 = 1e-12;

/// A symmetry of the discrete problem: the axis map and where it takes each cage vertex.
#[derive(Debug, Clone)]
struct Symmetry {
    axes: CubeSymmetry,
    vertex: Vec<usize>,
}

/// How a cage's harmonic functions are obtained: the vertices solved, and each other vertex
/// from a solved one through a symmetry.
#[derive(Debug, Clone)]
pub(super) struct Orbits {
    /// The vertices whose functions are solved, ascending.
    pub solved: Vec<usize>,
    /// Per cage vertex, `None` when it is solved, else `(index into solved, symmetry)`.
    derived: Vec<Option<(usize, usize)>>,
    symmetries: Vec<Symmetry>,
}

impl Orbits {
    /// Every vertex solved (no symmetry used).
    pub fn none(vertex_count: usize) -> Self {
        Self {
            solved: (0..vertex_count).collect(),
            derived: vec![None; vertex_count],
            symmetries: Vec::new(),
        }
    }

    /// The cage's vertex count.
    pub fn vertex_count(&self) -> usize {
        self.derived.len()
    }

    /// Whether every vertex is solved.
    pub fn is_trivial(&self) -> bool {
        self.solved.len() == self.derived.len()
    }

    /// The orbits of `cage`'s vertices under the symmetries of its discrete problem on
    /// `grid` (unknown mask and diagonal per grid node, the interfaces' right-hand sides).
    pub fn find(cage: &Cage, grid: &CageGrid, unknown: &[bool], diagonal: &[f64]) -> Self {
        let n = cage.vertex_count();
        let candidates: Vec<Symmetry> = CubeSymmetry::all()
            .filter(|axes| *axes != CubeSymmetry::IDENTITY && axes.keeps_dims(grid.dims))
            .filter_map(|axes| {
                let vertex = vertex_map(cage, &axes)?;
                Some(Symmetry { axes, vertex })
            })
            .collect();
        if candidates.is_empty() {
            return Self::none(n);
        }
        let rhs = right_hand_sides(cage, grid);
        let symmetries: Vec<Symmetry> = candidates
            .into_iter()
            .filter(|s| keeps_system(s, grid.dims, unknown, diagonal, &rhs))
            .collect();
        let mut solved: Vec<usize> = Vec::new();
        let mut derived = vec![None; n];
        for j in 0..n {
            let from = symmetries.iter().enumerate().find_map(|(g, s)| {
                let r = solved.iter().position(|&r| s.vertex[r] == j)?;
                Some((r, g))
            });
            match from {
                Some(source) => derived[j] = Some(source),
                None => solved.push(j),
            }
        }
        Self {
            solved,
            derived,
            symmetries,
        }
    }

    /// Where vertex `j`'s function comes from: `(index into solved, symmetry)`, the symmetry
    /// none for a solved vertex.
    pub fn source(&self, j: usize) -> Option<(usize, Option<usize>)> {
        match self.derived.get(j)? {
            None => Some((self.solved.binary_search(&j).ok()?, None)),
            Some((r, g)) => Some((*r, Some(*g))),
        }
    }

    /// The symmetries in use.
    pub fn symmetry_count(&self) -> usize {
        self.symmetries.len()
    }

    /// Where symmetry `g` reads each node from: u_j(n) = u_r(g⁻¹ n) where g takes vertex r to
    /// j. None when the map leaves the grid (never for a checked symmetry).
    pub fn preimage_node(&self, g: usize, dims: UVec3, node: usize) -> Option<usize> {
        self.symmetries.get(g)?.axes.map_node(dims, node, true)
    }
}

/// Where `axes` (about the cage's box centre) takes each vertex, if it maps the vertices onto
/// themselves and the triangles onto triangles.
fn vertex_map(cage: &Cage, axes: &CubeSymmetry) -> Option<Vec<usize>> {
    let (lo, hi) = cage.bounds();
    let centre = 0.5 * (lo + hi);
    let quantum = 1e-9 * cage.diagonal().max(f64::MIN_POSITIVE);
    let key = |p: DVec3| ((p - centre) / quantum).round().as_i64vec3().to_array();
    let positions = cage.positions();
    let by_key: HashMap<[i64; 3], usize> = positions
        .iter()
        .enumerate()
        .map(|(k, &p)| (key(p), k))
        .collect();
    let mut map = Vec::with_capacity(positions.len());
    for &p in positions {
        let image = centre + axes.apply(p - centre);
        let found = by_key.get(&key(image)).copied()?;
        if positions[found].distance(image) > quantum {
            return None;
        }
        map.push(found);
    }
    let sorted = |t: [u32; 3]| {
        let mut t = t;
        t.sort_unstable();
        t
    };
    let triangles: std::collections::HashSet<[u32; 3]> =
        cage.triangles().iter().map(|&t| sorted(t)).collect();
    cage.triangles()
        .iter()
        .all(|t| triangles.contains(&sorted(t.map(|v| map[v as usize] as u32))))
        .then_some(map)
}

/// The right-hand sides' entries, by (grid node, cage vertex): Σ over the node's interfaces of
/// the hat function's value at the crossing over θ (eq. of Gibou et al., as in the solve).
fn right_hand_sides(cage: &Cage, grid: &CageGrid) -> HashMap<(u32, u32), f64> {
    let triangles = cage.triangles();
    let mut rhs: HashMap<(u32, u32), f64> = HashMap::new();
    for interface in &grid.interfaces {
        let BoundaryValue { triangle, bary } = interface.value;
        let Some(corners) = triangles.get(triangle as usize) else {
            continue;
        };
        for (&v, &b) in corners.iter().zip(&bary) {
            *rhs.entry((interface.node, v)).or_insert(0.0) += b / interface.theta;
        }
    }
    rhs
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOLERANCE * a.abs().max(b.abs()).max(1.0)
}

/// Whether `symmetry` maps the discrete system onto itself: unknowns onto unknowns with the
/// same diagonal, and vertex k's right-hand side onto vertex σ(k)'s.
fn keeps_system(
    symmetry: &Symmetry,
    dims: UVec3,
    unknown: &[bool],
    diagonal: &[f64],
    rhs: &HashMap<(u32, u32), f64>,
) -> bool {
    let image = |n: usize| symmetry.axes.map_node(dims, n, false);
    let mask_and_diagonal = (0..unknown.len()).all(|n| {
        let Some(m) = image(n) else {
            return false;
        };
        unknown.get(m) == Some(&unknown[n])
            && (!unknown[n] || diagonal.get(m).is_some_and(|&d| close(d, diagonal[n])))
    });
    if !mask_and_diagonal {
        return false;
    }
    let value = |node: usize, vertex: usize| {
        let key = (node as u32, vertex as u32);
        rhs.get(&key).copied().unwrap_or(0.0)
    };
    let mut preimage = vec![usize::MAX; symmetry.vertex.len()];
    for (k, &j) in symmetry.vertex.iter().enumerate() {
        if let Some(slot) = preimage.get_mut(j) {
            *slot = k;
        }
    }
    // Both ways, so that an entry present on one side only must be zero.
    rhs.iter().all(|(&(node, vertex), &v)| {
        let (node, vertex) = (node as usize, vertex as usize);
        let forward = image(node).zip(symmetry.vertex.get(vertex));
        let back = symmetry
            .axes
            .map_node(dims, node, true)
            .zip(preimage.get(vertex));
        forward.is_some_and(|(m, &j)| close(v, value(m, j)))
            && back.is_some_and(|(m, &k)| k != usize::MAX && close(v, value(m, k)))
    })
}
