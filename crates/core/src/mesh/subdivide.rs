//! Uniform subdivision of a mesh's welded surface: every edge cut into `n` equal segments and
//! every triangle into n² (the scale series of `bench --scale`: the same shape at 1, 4, 25,
//! 100 × the vertices). Positions stay on the original flat triangles, so the subdivided mesh
//! lies inside every cage the original does.

use std::collections::HashMap;

use glam::DVec3;

use super::{Mesh, MeshError};

/// Most segments per edge `subdivided` accepts (n² triangles per triangle).
pub const MAX_SEGMENTS: u32 = 64;

impl Mesh {
    /// The welded surface with every edge cut into `segments` (1 to [`MAX_SEGMENTS`]) equal
    /// parts and every triangle into segments²; normals and UVs are not carried (a scale
    /// series needs positions only). Points shared by two triangles (edge points) are one
    /// vertex, so the result is as connected as the welded original.
    pub fn subdivided(&self, segments: u32) -> Result<Mesh, MeshError> {
        let n = segments.clamp(1, MAX_SEGMENTS);
        let corners = self.welded_positions();
        let mut positions: Vec<DVec3> = corners.to_vec();
        // Edge (low, high) → its n − 1 inner points, from low to high.
        let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
        let mut edge_points = |a: u32, b: u32, positions: &mut Vec<DVec3>| -> (u32, bool) {
            let key = (a.min(b), a.max(b));
            let first = *edges.entry(key).or_insert_with(|| {
                let first = positions.len() as u32;
                let (p, q) = (corners[key.0 as usize], corners[key.1 as usize]);
                positions.extend((1..n).map(|k| p.lerp(q, f64::from(k) / f64::from(n))));
                first
            });
            (first, a > b)
        };
        let mut triangles = Vec::with_capacity(self.welded_triangles().len() * (n * n) as usize);
        let mut grid: Vec<u32> = Vec::new();
        for &[a, b, c] in self.welded_triangles() {
            // Point (i, j) = a + i/n (b − a) + j/n (c − a), i + j ≤ n, row-major over j.
            let ab = edge_points(a, b, &mut positions);
            let ac = edge_points(a, c, &mut positions);
            let bc = edge_points(b, c, &mut positions);
            let on_edge = |(first, reversed): (u32, bool), k: u32| {
                first + if reversed { n - 1 - k } else { k - 1 }
            };
            let index = |i: u32, j: u32| (j * (2 * n + 3 - j) / 2 + i) as usize;
            grid.clear();
            grid.resize(((n + 1) * (n + 2) / 2) as usize, 0);
            let (pa, pb, pc) = (
                corners[a as usize],
                corners[b as usize],
                corners[c as usize],
            );
            for j in 0..=n {
                for i in 0..=(n - j) {
                    grid[index(i, j)] = match (i, j) {
                        (0, 0) => a,
                        (i, 0) if i == n => b,
                        (0, j) if j == n => c,
                        (i, 0) => on_edge(ab, i),
                        (0, j) => on_edge(ac, j),
                        (i, j) if i + j == n => on_edge(bc, j),
                        (i, j) => {
                            let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                            positions.push(pa + (pb - pa) * u + (pc - pa) * v);
                            positions.len() as u32 - 1
                        }
                    };
                }
            }
            for j in 0..n {
                for i in 0..(n - j) {
                    let (p, q, r) = (
                        grid[index(i, j)],
                        grid[index(i + 1, j)],
                        grid[index(i, j + 1)],
                    );
                    triangles.push([p, q, r]);
                    if i + j + 1 < n {
                        triangles.push([q, grid[index(i + 1, j + 1)], r]);
                    }
                }
            }
        }
        Mesh::new(positions, triangles, None, None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> Mesh {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        Mesh::new(
            p,
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
            None,
            None,
        )
        .unwrap()
    }

    /// Sum of (a × b)·c / 6 over triangles: the enclosed volume of a closed surface.
    fn volume(m: &Mesh) -> f64 {
        let p = m.positions();
        m.triangles()
            .iter()
            .map(|t| {
                p[t[0] as usize]
                    .cross(p[t[1] as usize])
                    .dot(p[t[2] as usize])
                    / 6.0
            })
            .sum()
    }

    #[test]
    fn segments_give_n_squared_triangles_a_closed_surface_and_the_same_shape() {
        let mesh = tetrahedron();
        for n in [1, 2, 3, 5] {
            let fine = mesh.subdivided(n).unwrap();
            assert_eq!(fine.triangles().len(), 4 * (n * n) as usize);
            // Euler: V − E + F = 2 with E = 3F/2 on a closed triangle mesh.
            let (v, f) = (fine.positions().len() as i64, fine.triangles().len() as i64);
            assert_eq!(v - 3 * f / 2 + f, 2, "n = {n}: not one closed surface");
            assert!((volume(&fine) - volume(&mesh)).abs() < 1e-12, "n = {n}");
            assert_eq!(fine.bounds(), mesh.bounds());
            // Every edge is used by exactly two triangles, in opposite directions.
            let mut directed = std::collections::BTreeSet::new();
            for t in fine.triangles() {
                for k in 0..3 {
                    assert!(
                        directed.insert((t[k], t[(k + 1) % 3])),
                        "n = {n}: edge twice"
                    );
                }
            }
            for &(a, b) in &directed {
                assert!(directed.contains(&(b, a)), "n = {n}: open edge");
            }
        }
    }
}
