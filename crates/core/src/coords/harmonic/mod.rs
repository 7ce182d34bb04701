//! Harmonic Coordinates (Joshi, Meyer, DeRose, Green & Sanocki 2007, "Harmonic coordinates for
//! character articulation").
//!
//! w_i is the harmonic function inside the cage (Δw_i = 0) whose boundary values are the
//! piecewise-linear hat function of cage vertex i. We discretise on a regular grid local to
//! the cage (`resolution` cells along its longest side): strictly inside nodes are unknowns of
//! the 7-point Laplacian; outside or on-cage nodes next to them carry the hat functions at
//! their closest cage point (Dirichlet data). All vertices' systems share one matrix, solved
//! eight right-hand sides at a time by multigrid-preconditioned CG ([`multigrid`]); weights at
//! a point are the trilinear interpolation of the grid values, blended within one cell of the
//! cage into the exact hat values at the closest cage point so that weights on the cage are
//! exactly the boundary data (and agree with MVC there).
//!
//! Properties: the discrete maximum principle makes every weight lie in [0, 1]; rows sum to 1
//! (every Dirichlet row does); linear precision holds up to the O(h) discretisation error.
//! Outside the cage HC are undefined: [`CoordError::OutsideCage`] names the points.

mod grid;
mod multigrid;

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{BindControl, CoordError};
use crate::cage::Cage;
use grid::{CageGrid, NodeRole};
use multigrid::{Hierarchy, K, Row};

/// Settings of the harmonic coordinates' discretisation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct HarmonicSettings {
    /// Grid cells along the cage's longest bounding-box side.
    pub resolution: u32,
    /// Relative residual at which the solver stops.
    pub tolerance: f64,
    /// Iteration cap of the solver per batch of right-hand sides.
    pub max_iterations: u32,
}

impl Default for HarmonicSettings {
    fn default() -> Self {
        Self {
            resolution: 64,
            tolerance: 1e-9,
            max_iterations: 200,
        }
    }
}

/// Relative distance (to the cage diagonal) under which a point counts as on the cage.
const ON_CAGE: f64 = 1e-9;

enum Site {
    Inside { closest: (usize, [f64; 3]), distance: f64 },
    OnCage { closest: (usize, [f64; 3]) },
}

/// Harmonic coordinates of `points` (row-major, points × cage vertices).
pub(crate) fn harmonic_bind(
    cage: &Cage,
    points: &[DVec3],
    settings: &HarmonicSettings,
    control: &BindControl,
) -> Result<Vec<f64>, CoordError> {
    let n = cage.vertex_count();
    let on_cage = ON_CAGE * cage.diagonal();
    let sites: Vec<Option<Site>> = points
        .par_iter()
        .map(|&p| {
            let (t, bary, distance) = cage.closest_point(p);
            if distance <= on_cage {
                Some(Site::OnCage { closest: (t, bary) })
            } else if cage.winding_number(p) > 0.5 {
                Some(Site::Inside {
                    closest: (t, bary),
                    distance,
                })
            } else {
                None
            }
        })
        .collect();
    let outside: Vec<usize> = (0..points.len()).filter(|&i| sites[i].is_none()).collect();
    if !outside.is_empty() {
        return Err(CoordError::outside(outside));
    }
    let inside_points: Vec<DVec3> = points
        .iter()
        .zip(&sites)
        .filter(|(_, s)| matches!(s, Some(Site::Inside { .. })))
        .map(|(p, _)| *p)
        .collect();
    let grid = CageGrid::build(cage, settings.resolution, &inside_points);
    control.check()?;
    let unknown: Vec<bool> = grid.roles.iter().map(|r| *r == NodeRole::Unknown).collect();
    let hierarchy = Hierarchy::new(grid.dims, &unknown);
    // Dirichlet neighbours of every unknown: (slot, boundary index).
    let links = dirichlet_links(&grid, &hierarchy);
    let triangles = cage.triangles();
    let hat = |b: usize, vertex: usize| -> f64 {
        let value = grid.boundary[b];
        let tri = triangles[value.triangle as usize];
        (0..3).filter(|&k| tri[k] as usize == vertex).map(|k| value.bary[k]).sum()
    };
    let mut out = vec![0.0; points.len() * n];
    let chunks = n.div_ceil(K);
    control.set_total(chunks);
    let mut x = vec![[0.0; K]; hierarchy.fine_len()];
    for chunk in 0..chunks {
        control.check()?;
        let first = chunk * K;
        let columns = (n - first).min(K);
        let mut b = vec![[0.0; K]; hierarchy.fine_len()];
        for &(slot, boundary) in &links {
            for c in 0..columns {
                b[slot as usize][c] += hat(boundary as usize, first + c);
            }
        }
        hierarchy.solve(&b, &mut x, settings.tolerance, settings.max_iterations as usize);
        let node_row = |node: usize| -> Row {
            match grid.roles[node] {
                NodeRole::Unknown => hierarchy.fine_slot(node).map_or([0.0; K], |s| x[s]),
                NodeRole::Boundary(b) => std::array::from_fn(|c| {
                    if c < columns { hat(b as usize, first + c) } else { 0.0 }
                }),
                NodeRole::Unused => [0.0; K],
            }
        };
        out.par_chunks_mut(n).zip(points.par_iter().zip(&sites)).for_each(|(row, (&p, site))| {
            let (closest, blend) = match site {
                Some(Site::OnCage { closest }) => (*closest, 0.0),
                Some(Site::Inside { closest, distance }) => (*closest, (distance / grid.spacing).min(1.0)),
                None => return,
            };
            let mut value = [0.0; K];
            if blend > 0.0 {
                let (cell, f) = grid.cell_of(p);
                for corner in 0..8u32 {
                    let (di, dj, dk) = (corner & 1, (corner >> 1) & 1, corner >> 2);
                    let w = (if di == 1 { f.x } else { 1.0 - f.x })
                        * (if dj == 1 { f.y } else { 1.0 - f.y })
                        * (if dk == 1 { f.z } else { 1.0 - f.z });
                    let r = node_row(grid.index(cell.x + di, cell.y + dj, cell.z + dk));
                    for c in 0..K {
                        value[c] += w * r[c];
                    }
                }
            }
            let tri = triangles[closest.0];
            for c in 0..columns {
                let v = first + c;
                let exact: f64 = (0..3).filter(|&k| tri[k] as usize == v).map(|k| closest.1[k]).sum();
                row[v] = blend * value[c] + (1.0 - blend) * exact;
            }
        });
        control.advance();
    }
    // The solver stops at a tolerance: clip round-off negatives and renormalise rows.
    out.par_chunks_mut(n).for_each(|row| {
        row.iter_mut().for_each(|w| *w = w.max(0.0));
        let sum: f64 = row.iter().sum();
        if sum > 0.0 {
            row.iter_mut().for_each(|w| *w /= sum);
        }
    });
    Ok(out)
}

fn dirichlet_links(grid: &CageGrid, hierarchy: &Hierarchy) -> Vec<(u32, u32)> {
    let (sx, sy) = (1usize, grid.dims.x as usize);
    let sz = sy * grid.dims.y as usize;
    let mut links = Vec::new();
    for slot in 0..hierarchy.fine_len() {
        let Some(node) = hierarchy.fine_node_of_slot(slot) else {
            continue;
        };
        for m in [node - sx, node + sx, node - sy, node + sy, node - sz, node + sz] {
            if let NodeRole::Boundary(b) = grid.roles[m] {
                links.push((slot as u32, b));
            }
        }
    }
    links
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::shapes;

    #[test]
    fn cube_centre_weights_are_equal() {
        let cage = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
        let w = harmonic_bind(
            &cage,
            &[DVec3::splat(0.5)],
            &HarmonicSettings {
                resolution: 16,
                ..Default::default()
            },
            &BindControl::default(),
        )
        .unwrap();
        for v in &w {
            assert!((v - 0.125).abs() < 2e-3, "{w:?}");
        }
    }
}
