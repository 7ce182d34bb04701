//! The regular grid local to a cage on which harmonic coordinates are discretised: which
//! nodes are unknowns (strictly inside), which carry Dirichlet values (outside or on the cage,
//! next to the inside, with the hat functions at their closest cage point).

use glam::{DVec3, UVec3};
use rayon::prelude::*;

use crate::cage::Cage;

/// Role of a grid node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum NodeRole {
    /// Far outside: never read.
    Unused,
    /// Strictly inside: an unknown of the Laplace system.
    Unknown,
    /// Dirichlet node, with its index into [`CageGrid::boundary`].
    Boundary(u32),
}

/// Dirichlet data of a boundary node: the hat functions at its closest cage point.
#[derive(Debug, Clone, Copy)]
pub(super) struct BoundaryValue {
    pub triangle: u32,
    pub bary: [f64; 3],
}

/// A cage's grid: geometry and node roles.
#[derive(Debug, Clone)]
pub(super) struct CageGrid {
    pub origin: DVec3,
    pub spacing: f64,
    pub dims: UVec3,
    pub roles: Vec<NodeRole>,
    pub boundary: Vec<BoundaryValue>,
    pub unknown_count: usize,
}

impl CageGrid {
    /// Linear index of node `(i, j, k)`.
    pub fn index(&self, i: u32, j: u32, k: u32) -> usize {
        (i + self.dims.x * (j + self.dims.y * k)) as usize
    }

    /// Grid with `resolution` cells along the cage's longest side, padded by two cells.
    /// `extra_corners` lists points whose cell corners must carry values (query points).
    pub fn build(cage: &Cage, resolution: u32, extra_points: &[DVec3]) -> Self {
        let (lo, hi) = cage.bounds();
        let extent = hi - lo;
        let spacing = extent.max_element() / resolution.max(2) as f64;
        let origin = lo - DVec3::splat(2.0 * spacing);
        let cells = (extent / spacing).ceil().as_uvec3() + UVec3::splat(4);
        let dims = cells + UVec3::ONE;
        let inside = classify_inside(cage, origin, spacing, dims);
        let mut grid = Self {
            origin,
            spacing,
            dims,
            roles: vec![NodeRole::Unused; inside.len()],
            boundary: Vec::new(),
            unknown_count: 0,
        };
        // Unknowns: inside nodes (padding guarantees none on the grid border).
        for (role, &is_inside) in grid.roles.iter_mut().zip(&inside) {
            if is_inside {
                *role = NodeRole::Unknown;
            }
        }
        grid.unknown_count = inside.iter().filter(|&&b| b).count();
        // Dirichlet band: non-inside nodes in the 26-neighbourhood of an inside node, and the
        // corners of every query point's cell.
        let mut band = vec![false; inside.len()];
        let d = dims.as_ivec3();
        for k in 0..d.z {
            for j in 0..d.y {
                for i in 0..d.x {
                    if !inside[grid.index(i as u32, j as u32, k as u32)] {
                        continue;
                    }
                    for dk in -1..=1 {
                        for dj in -1..=1 {
                            for di in -1..=1 {
                                let n = grid.index((i + di) as u32, (j + dj) as u32, (k + dk) as u32);
                                band[n] |= !inside[n];
                            }
                        }
                    }
                }
            }
        }
        for &p in extra_points {
            let (cell, _) = grid.cell_of(p);
            for c in 0..8u32 {
                let n = grid.index(cell.x + (c & 1), cell.y + ((c >> 1) & 1), cell.z + (c >> 2));
                band[n] |= !inside[n];
            }
        }
        let band_nodes: Vec<usize> = (0..band.len()).filter(|&n| band[n]).collect();
        grid.boundary = band_nodes
            .par_iter()
            .map(|&n| {
                let (t, bary, _) = cage.closest_point(grid.position_of(n));
                BoundaryValue {
                    triangle: t as u32,
                    bary,
                }
            })
            .collect();
        for (b, &n) in band_nodes.iter().enumerate() {
            grid.roles[n] = NodeRole::Boundary(b as u32);
        }
        grid
    }

    /// Position of node `n`.
    pub fn position_of(&self, n: usize) -> DVec3 {
        let n = n as u32;
        let i = n % self.dims.x;
        let j = (n / self.dims.x) % self.dims.y;
        let k = n / (self.dims.x * self.dims.y);
        self.origin + UVec3::new(i, j, k).as_dvec3() * self.spacing
    }

    /// The cell containing `p` (clamped into the grid) and `p`'s local coordinates in it.
    pub fn cell_of(&self, p: DVec3) -> (UVec3, DVec3) {
        let local = (p - self.origin) / self.spacing;
        let max_cell = (self.dims - UVec3::splat(2)).as_dvec3();
        let cell = local.floor().clamp(DVec3::ZERO, max_cell);
        let frac = (local - cell).clamp(DVec3::ZERO, DVec3::ONE);
        (cell.as_uvec3(), frac)
    }
}

/// Inside/outside of every node by casting a ray along +x per (j, k) grid line and counting
/// signed crossings of the cage's triangles. The line is nudged by a tiny irrational amount so
/// it does not run exactly through cage edges of grid-aligned cages.
fn classify_inside(cage: &Cage, origin: DVec3, spacing: f64, dims: UVec3) -> Vec<bool> {
    let positions = cage.positions();
    let nudge = spacing * 1e-7;
    let lines: Vec<(u32, u32)> = (0..dims.z).flat_map(|k| (0..dims.y).map(move |j| (j, k))).collect();
    let per_line: Vec<Vec<bool>> = lines
        .par_iter()
        .map(|&(j, k)| {
            let y = origin.y + j as f64 * spacing + nudge * std::f64::consts::SQRT_2;
            let z = origin.z + k as f64 * spacing + nudge * std::f64::consts::PI;
            let mut crossings: Vec<(f64, i32)> = Vec::new();
            for &[a, b, c] in cage.triangles() {
                let (pa, pb, pc) = (positions[a as usize], positions[b as usize], positions[c as usize]);
                // Barycentric coordinates of (y, z) in the triangle's yz projection.
                let det = (pb.y - pa.y) * (pc.z - pa.z) - (pc.y - pa.y) * (pb.z - pa.z);
                if det == 0.0 {
                    continue;
                }
                let wb = ((y - pa.y) * (pc.z - pa.z) - (pc.y - pa.y) * (z - pa.z)) / det;
                let wc = ((pb.y - pa.y) * (z - pa.z) - (y - pa.y) * (pb.z - pa.z)) / det;
                let wa = 1.0 - wb - wc;
                if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                    continue;
                }
                let x = wa * pa.x + wb * pb.x + wc * pc.x;
                // The normal's x component has the sign of det: entering when it points to −x.
                crossings.push((x, if det < 0.0 { 1 } else { -1 }));
            }
            crossings.sort_by(|p, q| p.0.total_cmp(&q.0));
            let mut inside = vec![false; dims.x as usize];
            let mut winding = 0;
            let mut next = 0;
            for (i, flag) in inside.iter_mut().enumerate() {
                let x = origin.x + i as f64 * spacing;
                while next < crossings.len() && crossings[next].0 <= x {
                    winding += crossings[next].1;
                    next += 1;
                }
                let on_crossing = next < crossings.len() && crossings[next].0 - x < nudge;
                *flag = winding > 0 && !on_crossing && (x - crossings[next.saturating_sub(1)].0) >= nudge;
            }
            inside
        })
        .collect();
    per_line.into_iter().flatten().collect()
}
