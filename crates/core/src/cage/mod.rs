//! Closed, outward-oriented triangle cages with their polygon faces.
//!
//! A [`Cage`] is built from polygon faces (triangles, quads or other planar polygons). Polygons
//! are triangulated as fans from their first corner, and each triangle remembers the polygon it
//! came from: the *Cages distance function (paper eq. 7) works on polygon faces.

mod crossing;
pub(crate) mod cube_symmetry;
mod error;
mod validate;

pub(crate) use crossing::cages_crossing;

/// Largest absolute cage coordinate accepted (in a cage file and in a scene): the operator and
/// the renderer work in 32-bit floats, and a coordinate this large already loses every digit
/// below 100.
pub const MAX_COORDINATE: f64 = 1e9;

pub use error::CageError;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::geometry::triangle_area_vector;

/// A polygon face of a cage: its corners and the triangles of its fan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CagePolygon {
    /// Corner vertex indices, counter-clockwise seen from outside.
    pub vertices: Vec<u32>,
    /// Index of the first fan triangle in [`Cage::triangles`].
    pub first_triangle: u32,
}

impl CagePolygon {
    /// Number of fan triangles (corners − 2).
    pub fn triangle_count(&self) -> usize {
        self.vertices.len().saturating_sub(2)
    }
}

/// A closed, manifold, outward-oriented triangle cage (normals point out).
///
/// Invariants, checked by [`Cage::from_polygons`]: at least 4 finite, distinct vertices, all
/// used; every edge has exactly two faces running it in opposite directions; positive volume;
/// no degenerate triangle.
#[derive(Debug, Clone, PartialEq)]
pub struct Cage {
    positions: Vec<DVec3>,
    polygons: Vec<CagePolygon>,
    triangles: Vec<[u32; 3]>,
    triangle_polygon: Vec<u32>,
    /// Unique undirected edges `(a, b)` with `a < b`.
    edges: Vec<[u32; 2]>,
    /// Per triangle `(i0, i1, i2)`: the edge indices of `(i0,i1)`, `(i1,i2)`, `(i2,i0)`.
    triangle_edges: Vec<[u32; 3]>,
}

impl Cage {
    /// Builds a cage from vertex positions and polygon faces, validating it.
    pub fn from_polygons(positions: Vec<DVec3>, faces: Vec<Vec<u32>>) -> Result<Self, CageError> {
        match validate::check(&positions, &faces).into_iter().next() {
            Some(problem) => Err(problem),
            None => Ok(Self::build_unchecked(positions, faces)),
        }
    }

    /// Builds a cage from triangles, validating it.
    pub fn from_triangles(
        positions: Vec<DVec3>,
        triangles: &[[u32; 3]],
    ) -> Result<Self, CageError> {
        Self::from_polygons(positions, triangles.iter().map(|t| t.to_vec()).collect())
    }

    /// Every problem of a polygon soup as a cage, in a stable order (empty when valid).
    pub fn diagnose(positions: &[DVec3], faces: &[Vec<u32>]) -> Vec<CageError> {
        validate::check(positions, faces)
    }

    fn build_unchecked(positions: Vec<DVec3>, faces: Vec<Vec<u32>>) -> Self {
        let mut polygons = Vec::with_capacity(faces.len());
        let mut triangles = Vec::new();
        let mut triangle_polygon = Vec::new();
        for (f, corners) in faces.into_iter().enumerate() {
            let first = triangles.len() as u32;
            for k in 1..corners.len() - 1 {
                triangles.push([corners[0], corners[k], corners[k + 1]]);
                triangle_polygon.push(f as u32);
            }
            polygons.push(CagePolygon {
                vertices: corners,
                first_triangle: first,
            });
        }
        let (edges, triangle_edges) = index_edges(&triangles);
        Self {
            positions,
            polygons,
            triangles,
            triangle_polygon,
            edges,
            triangle_edges,
        }
    }

    /// Rest positions of the cage vertices.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Polygon faces in input order.
    pub fn polygons(&self) -> &[CagePolygon] {
        &self.polygons
    }

    /// Triangles in fan order of the polygons (input order).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// For each triangle, the polygon it came from.
    pub fn triangle_polygon(&self) -> &[u32] {
        &self.triangle_polygon
    }

    /// Unique undirected edges, `(a, b)` with `a < b`.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Per triangle, the indices into [`Cage::edges`] of its edges `(i0,i1)`, `(i1,i2)`, `(i2,i0)`.
    pub fn triangle_edges(&self) -> &[[u32; 3]] {
        &self.triangle_edges
    }

    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        bounds_of(&self.positions)
    }

    /// Length of the bounding-box diagonal: the length scale for tolerances.
    pub fn diagonal(&self) -> f64 {
        let (lo, hi) = self.bounds();
        (hi - lo).length()
    }

    /// Unit outward normal of each triangle.
    pub fn triangle_normals(&self) -> Vec<DVec3> {
        self.triangle_normals_at(&self.positions)
    }

    /// Unit normals of each triangle for another set of positions of the same cage (a pose).
    pub fn triangle_normals_at(&self, positions: &[DVec3]) -> Vec<DVec3> {
        self.triangles
            .iter()
            .map(|&[a, b, c]| {
                triangle_area_vector(
                    positions[a as usize],
                    positions[b as usize],
                    positions[c as usize],
                )
                .normalize_or_zero()
            })
            .collect()
    }

    /// Signed volume (positive for an outward-oriented cage).
    pub fn volume(&self) -> f64 {
        signed_volume(&self.positions, &self.triangles)
    }

    /// Generalised winding number of `p` (1 inside, 0 outside, ½ on a face), from the sum of
    /// the triangles' solid angles.
    pub fn winding_number(&self, p: DVec3) -> f64 {
        let total: f64 = self
            .triangles
            .iter()
            .map(|&[a, b, c]| {
                crate::geometry::solid_angle(
                    self.positions[a as usize] - p,
                    self.positions[b as usize] - p,
                    self.positions[c as usize] - p,
                )
            })
            .sum();
        total / (4.0 * std::f64::consts::PI)
    }

    /// Whether `p` lies within `distance` of the cage surface: [`Cage::closest_point`]'s
    /// distance ≤ `distance`, with each triangle first tested against its bounds grown by
    /// `distance` (a point inside or outside a cage is rejected by every triangle at the cost of
    /// a few comparisons; placing points spends most of its time here).
    pub fn is_within(&self, p: DVec3, distance: f64) -> bool {
        self.triangles
            .iter()
            .any(|&t| self.triangle_is_within(t, p, distance))
    }

    /// [`Cage::is_within`] over the triangles `triangles` (indices) only.
    pub fn is_within_of(&self, p: DVec3, distance: f64, triangles: &[u32]) -> bool {
        triangles.iter().any(|&t| {
            self.triangles
                .get(t as usize)
                .is_some_and(|&t| self.triangle_is_within(t, p, distance))
        })
    }

    /// Whether `p` lies within `distance` of triangle `[a, b, c]` (its grown bounds first).
    fn triangle_is_within(&self, [a, b, c]: [u32; 3], p: DVec3, distance: f64) -> bool {
        let margin = DVec3::splat(distance);
        let [a, b, c] = [a, b, c].map(|k| self.positions[k as usize]);
        let (lo, hi) = (a.min(b).min(c) - margin, a.max(b).max(c) + margin);
        if p.cmplt(lo).any() || p.cmpgt(hi).any() {
            return false;
        }
        let (q, _) = crate::geometry::closest_point_on_triangle(p, a, b, c);
        q.distance(p) <= distance
    }

    /// The smallest t > 0 where the ray `origin + t·direction` meets the cage surface
    /// (infinity when it never does).
    pub fn ray_exit(&self, origin: DVec3, direction: DVec3) -> f64 {
        self.triangles
            .iter()
            .filter_map(|&[a, b, c]| {
                crate::geometry::ray_triangle(
                    origin,
                    direction,
                    self.positions[a as usize],
                    self.positions[b as usize],
                    self.positions[c as usize],
                )
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Closest point on the cage surface to `p`: `(triangle, barycentric, distance)`.
    pub fn closest_point(&self, p: DVec3) -> (usize, [f64; 3], f64) {
        let mut best = (0, [1.0, 0.0, 0.0], f64::INFINITY);
        for (t, &[a, b, c]) in self.triangles.iter().enumerate() {
            let (q, bary) = crate::geometry::closest_point_on_triangle(
                p,
                self.positions[a as usize],
                self.positions[b as usize],
                self.positions[c as usize],
            );
            let d = (q - p).length_squared();
            if d < best.2 {
                best = (t, bary, d);
            }
        }
        (best.0, best.1, best.2.sqrt())
    }

    /// The same cage with every face flipped (the fix for an inward-oriented cage).
    pub fn flipped_faces(faces: &[Vec<u32>]) -> Vec<Vec<u32>> {
        faces
            .iter()
            .map(|f| {
                let mut g = f.clone();
                g[1..].reverse();
                g
            })
            .collect()
    }
}

/// Axis-aligned bounds of a point set; `(ZERO, ZERO)` when empty.
pub fn bounds_of(points: &[DVec3]) -> (DVec3, DVec3) {
    if points.is_empty() {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}

/// Signed volume enclosed by triangles (divergence theorem).
pub(crate) fn signed_volume(positions: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|&[a, b, c]| {
            positions[a as usize].dot(positions[b as usize].cross(positions[c as usize]))
        })
        .sum::<f64>()
        / 6.0
}

fn index_edges(triangles: &[[u32; 3]]) -> (Vec<[u32; 2]>, Vec<[u32; 3]>) {
    let mut keyed: Vec<([u32; 2], usize)> = Vec::with_capacity(triangles.len() * 3);
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            keyed.push(([a.min(b), a.max(b)], t * 3 + k));
        }
    }
    keyed.sort_unstable();
    let mut edges: Vec<[u32; 2]> = Vec::new();
    let mut triangle_edges = vec![[0u32; 3]; triangles.len()];
    for (key, slot) in keyed {
        if edges.last() != Some(&key) {
            edges.push(key);
        }
        triangle_edges[slot / 3][slot % 3] = (edges.len() - 1) as u32;
    }
    (edges, triangle_edges)
}

/// Ready-made cages for tests, benchmarks and demos.
pub mod shapes {
    use super::Cage;
    use glam::DVec3;

    /// The six outward quad faces of a box whose corner `c` has bits (x, y, z) = (c & 1,
    /// c >> 1 & 1, c >> 2): vertex i = x + 2y + 4z. Faces: z = min, z = max, y = min, y = max,
    /// x = min, x = max.
    pub const BOX_FACES: [[usize; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];

    /// [`BOX_FACES`] over the given corner vertex indices.
    pub fn box_faces(corners: [u32; 8]) -> Vec<Vec<u32>> {
        BOX_FACES
            .iter()
            .map(|f| f.iter().map(|&c| corners[c]).collect())
            .collect()
    }

    /// Axis-aligned box from `min` to `max` with six quad faces, outward oriented.
    pub fn cuboid(min: DVec3, max: DVec3) -> Cage {
        let p = |x: usize, y: usize, z: usize| {
            DVec3::new(
                if x == 0 { min.x } else { max.x },
                if y == 0 { min.y } else { max.y },
                if z == 0 { min.z } else { max.z },
            )
        };
        let positions = (0..8)
            .map(|i| p(i & 1, (i >> 1) & 1, (i >> 2) & 1))
            .collect();
        // Vertex i = x + 2y + 4z.
        let faces = vec![
            vec![0, 2, 3, 1], // z = min
            vec![4, 5, 7, 6], // z = max
            vec![0, 1, 5, 4], // y = min
            vec![2, 6, 7, 3], // y = max
            vec![0, 4, 6, 2], // x = min
            vec![1, 3, 7, 5], // x = max
        ];
        Cage::from_polygons(positions, faces).expect("a box is a valid cage")
    }

    /// Prism over a simple planar polygon `outline` (counter-clockwise in xy), from z0 to z1.
    /// Side faces are quads; caps are fanned from an added vertex at `centre`, which must see
    /// every outline edge (lie in the outline's kernel).
    pub fn prism(outline: &[[f64; 2]], centre: [f64; 2], z0: f64, z1: f64) -> Cage {
        let n = outline.len() as u32;
        let mut positions: Vec<DVec3> =
            outline.iter().map(|q| DVec3::new(q[0], q[1], z0)).collect();
        positions.extend(outline.iter().map(|q| DVec3::new(q[0], q[1], z1)));
        let [cx, cy] = centre;
        positions.push(DVec3::new(cx, cy, z0));
        positions.push(DVec3::new(cx, cy, z1));
        let (bottom, top) = (2 * n, 2 * n + 1);
        let mut faces = Vec::new();
        for i in 0..n {
            let j = (i + 1) % n;
            faces.push(vec![i, j, n + j, n + i]);
            faces.push(vec![bottom, j, i]);
            faces.push(vec![top, n + i, n + j]);
        }
        Cage::from_polygons(positions, faces).expect("a prism over a star-shaped outline is valid")
    }

    /// L-shaped prism (non-convex), 2 × 2 × 1 with a 1 × 1 notch.
    pub fn l_prism() -> Cage {
        prism(
            &[
                [0.0, 0.0],
                [2.0, 0.0],
                [2.0, 1.0],
                [1.0, 1.0],
                [1.0, 2.0],
                [0.0, 2.0],
            ],
            [0.5, 0.5],
            0.0,
            1.0,
        )
    }

    /// Five-pointed star prism (strongly non-convex).
    pub fn star_prism() -> Cage {
        let outline: Vec<[f64; 2]> = (0..10)
            .map(|k| {
                let a = std::f64::consts::PI * k as f64 / 5.0;
                let r = if k % 2 == 0 { 1.0 } else { 0.4 };
                [r * a.cos(), r * a.sin()]
            })
            .collect();
        prism(&outline, [0.0, 0.0], -0.5, 0.5)
    }

    /// Regular icosahedron of radius `r` about the origin (convex, 12 vertices, 20 faces).
    pub fn icosahedron(r: f64) -> Cage {
        let (positions, faces) = icosahedron_soup(r);
        Cage::from_triangles(positions, &faces).expect("an icosahedron is a valid cage")
    }

    /// Icosphere soup: the icosahedron with each triangle split in four `subdivisions` times,
    /// vertices on the unit sphere (`subdivisions = 1`: 42 vertices, 80 triangles).
    pub fn icosphere_soup(subdivisions: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let (mut positions, mut faces) = icosahedron_soup(1.0);
        for _ in 0..subdivisions {
            let mut midpoint = std::collections::BTreeMap::new();
            let mut out = Vec::with_capacity(faces.len() * 4);
            for f in &faces {
                let mut mid = [0u32; 3];
                for k in 0..3 {
                    let (a, b) = (f[k].min(f[(k + 1) % 3]), f[k].max(f[(k + 1) % 3]));
                    mid[k] = *midpoint.entry((a, b)).or_insert_with(|| {
                        let m = (positions[a as usize] + positions[b as usize]) * 0.5;
                        positions.push(m.normalize());
                        positions.len() as u32 - 1
                    });
                }
                out.extend([
                    [f[0], mid[0], mid[2]],
                    [f[1], mid[1], mid[0]],
                    [f[2], mid[2], mid[1]],
                    mid,
                ]);
            }
            faces = out;
        }
        (positions, faces)
    }

    /// Vertex positions and outward triangles of a regular icosahedron.
    pub fn icosahedron_soup(r: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let t = (1.0 + 5f64.sqrt()) / 2.0;
        let raw = [
            [-1.0, t, 0.0],
            [1.0, t, 0.0],
            [-1.0, -t, 0.0],
            [1.0, -t, 0.0],
            [0.0, -1.0, t],
            [0.0, 1.0, t],
            [0.0, -1.0, -t],
            [0.0, 1.0, -t],
            [t, 0.0, -1.0],
            [t, 0.0, 1.0],
            [-t, 0.0, -1.0],
            [-t, 0.0, 1.0],
        ];
        let positions = raw
            .iter()
            .map(|v| DVec3::from_array(*v).normalize() * r)
            .collect();
        let faces = vec![
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        (positions, faces)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::shapes;

    /// `is_within` answers what `closest_point`'s distance says, on points inside, outside, on
    /// faces, edges and corners, and just off them on either side of the tolerance.
    #[test]
    fn is_within_agrees_with_the_closest_point_distance() {
        let cage = shapes::cuboid(DVec3::ZERO, DVec3::new(1.0, 2.0, 0.5));
        let mut checked = [0usize; 2];
        for i in -4..=24 {
            for j in -4..=44 {
                for k in -4..=14 {
                    let p = DVec3::new(i as f64, j as f64, k as f64) * 0.05 + DVec3::splat(1e-4);
                    for tolerance in [1e-3, 0.02, 0.1] {
                        let near = cage.closest_point(p).2 <= tolerance;
                        assert_eq!(cage.is_within(p, tolerance), near, "{p} within {tolerance}");
                        checked[usize::from(near)] += 1;
                    }
                }
            }
        }
        assert!(checked[0] > 1000 && checked[1] > 1000, "{checked:?}");
    }
}
