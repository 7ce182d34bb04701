//! Harmonic Coordinates (Joshi, Meyer, DeRose, Green & Sanocki 2007, "Harmonic coordinates for
//! character articulation").
//!
//! w_i is the harmonic function inside the cage (Δw_i = 0) whose boundary values are the
//! piecewise-linear hat function of cage vertex i. We discretise on a regular grid local to
//! the cage (`resolution` cells along its longest side): strictly inside nodes are unknowns of
//! the 7-point Laplacian, and where a grid edge leaves the cage the boundary condition is
//! imposed exactly where it crosses the cage (Gibou, Fedkiw, Cheng & Kang 2002, "A second-order-
//! accurate symmetric discretization of the Poisson equation on irregular domains"), with the
//! hat functions' exact values at that crossing. All vertices' systems share one matrix, solved
//! eight right-hand sides at a time by multigrid-preconditioned CG ([`multigrid`]); weights at
//! a point are the trilinear interpolation of the grid values (outside nodes next to the cage
//! carry the hat functions at their closest cage point), blended within one cell of the
//! cage into the exact hat values at the closest cage point so that weights on the cage are
//! exactly the boundary data (and agree with MVC there).
//!
//! Properties: the matrix is a symmetric M-matrix, so the discrete maximum principle makes
//! every weight lie in [0, 1]; rows sum to 1; linear functions are reproduced exactly at grid
//! nodes, so linear precision holds up to the interpolation error near the cage (O(h) within a
//! cell of it, second order deeper inside).
//! Outside the cage HC are undefined: [`CoordError::OutsideCage`] names the points.

// Loops over the K right-hand-side columns index several rows at once; ranges read best.
#![allow(clippy::needless_range_loop)]

mod field;
#[cfg(test)]
pub(crate) use field::{functions_solved_of, solves_of};
mod grid;
mod multigrid;
mod symmetry;

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{BindControl, CoordError};
use crate::cage::Cage;
use grid::NodeRole;
use multigrid::{K, Row};

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

/// Limits of [`HarmonicSettings`]: memory and time grow with the cube of the resolution (an
/// 8-vertex box at resolution 256 needed 7 GB), and a solver that cannot reach its tolerance
/// must stop.
pub mod limits {
    /// Fewest grid cells along a cage's longest side (coarser grids miss the cage's shape).
    pub const MIN_RESOLUTION: u32 = 4;
    /// Most grid cells along a cage's longest side (about 2 million grid nodes).
    pub const MAX_RESOLUTION: u32 = 128;
    /// Smallest relative residual asked of the solver (round-off stops progress below it).
    pub const MIN_TOLERANCE: f64 = 1e-14;
    /// Largest relative residual accepted (coarser answers are not coordinates).
    pub const MAX_TOLERANCE: f64 = 1e-2;
    /// Most solver iterations per batch of right-hand sides.
    pub const MAX_ITERATIONS: u32 = 10_000;
}

impl HarmonicSettings {
    /// Grid cells along a cage's longest side for a quick preview (an eighth of the default's
    /// unknowns): what the editor binds first while the full resolution follows.
    pub const PREVIEW_RESOLUTION: u32 = 24;

    /// These settings at the preview resolution, or unchanged when they are that coarse
    /// already.
    pub fn preview(&self) -> Self {
        Self {
            resolution: self.resolution.min(Self::PREVIEW_RESOLUTION),
            ..*self
        }
    }

    /// Checks the settings against the `limits` below; the error says which value and the range.
    pub fn check(&self) -> Result<(), String> {
        use limits::*;
        if !(MIN_RESOLUTION..=MAX_RESOLUTION).contains(&self.resolution) {
            return Err(format!(
                "harmonic resolution {} is out of range; use {MIN_RESOLUTION} to {MAX_RESOLUTION} \
                 grid cells along a cage's longest side",
                self.resolution
            ));
        }
        if !(MIN_TOLERANCE..=MAX_TOLERANCE).contains(&self.tolerance) {
            return Err(format!(
                "harmonic tolerance {} is out of range; use a relative residual from \
                 {MIN_TOLERANCE:e} to {MAX_TOLERANCE:e} (1e-8 is the default)",
                self.tolerance
            ));
        }
        if !(1..=MAX_ITERATIONS).contains(&self.max_iterations) {
            return Err(format!(
                "harmonic max_iterations {} is out of range; use 1 to {MAX_ITERATIONS}",
                self.max_iterations
            ));
        }
        Ok(())
    }
}

impl Default for HarmonicSettings {
    fn default() -> Self {
        Self {
            resolution: 48,
            tolerance: 1e-8,
            max_iterations: 200,
        }
    }
}

/// Drops the solved harmonic fields this process keeps for re-binds (about 512 MiB at most):
/// what a benchmark calls before timing a bind from scratch.
pub fn clear_harmonic_cache() {
    field::clear_cache();
}

/// Relative distance (to the cage diagonal) under which a point counts as on the cage.
const ON_CAGE: f64 = 1e-9;

enum Site {
    Inside { distance: f64 },
    OnCage { closest: (usize, [f64; 3]) },
}

/// Harmonic coordinates of `points` (row-major, points × cage vertices): where each point
/// lies, the cage's solved grid field, the hat values the points' cells and the cage's
/// surface contribute, then the field interpolated K vertices at a time and the rows
/// renormalised.
pub(crate) fn harmonic_bind(
    cage: &Cage,
    points: &[DVec3],
    settings: &HarmonicSettings,
    control: &BindControl,
) -> Result<Vec<f64>, CoordError> {
    settings.check().map_err(CoordError::Settings)?;
    // No points, no rows: the field is not solved for nothing (a chunk of a streamed bind
    // may hold no point of this cage).
    if points.is_empty() {
        return Ok(Vec::new());
    }
    let sites = sites_of(cage, points)?;
    let field = field::cached_field(cage, settings, control)?;
    control.check()?;
    let far = FarCorners::of(cage, &field.grid, points, &sites);
    let surface = surface_values(cage, &field.grid, points, &sites);
    let n = cage.vertex_count();
    let mut out = vec![0.0; points.len() * n];
    let chunks = n.div_ceil(K);
    control.set_total(chunks);
    for chunk in 0..chunks {
        control.check()?;
        let at = Interpolation {
            cage,
            field: &field,
            far: &far,
            chunk,
        };
        at.fill(&mut out, points, &sites, &surface);
        control.advance();
    }
    renormalise_rows(&mut out, n);
    Ok(out)
}

/// Where each point lies: on the cage (its closest face and barycentric coordinates) or
/// inside it (its distance to the cage); an error naming the points outside, where HC are
/// undefined.
fn sites_of(cage: &Cage, points: &[DVec3]) -> Result<Vec<Site>, CoordError> {
    let on_cage = ON_CAGE * cage.diagonal();
    let sites: Vec<Option<Site>> = points
        .par_iter()
        .map(|&p| {
            let (t, bary, distance) = cage.closest_point(p);
            if distance <= on_cage {
                Some(Site::OnCage { closest: (t, bary) })
            } else if cage.winding_number(p) > 0.5 {
                Some(Site::Inside { distance })
            } else {
                None
            }
        })
        .collect();
    let outside: Vec<usize> = (0..points.len()).filter(|&i| sites[i].is_none()).collect();
    if !outside.is_empty() {
        return Err(CoordError::outside(outside));
    }
    Ok(sites.into_iter().flatten().collect())
}

/// Corners of the points' cells outside the field's band (far out in a cell the cage
/// crosses), sorted, with the hat functions at their closest cage point.
struct FarCorners {
    nodes: Vec<usize>,
    values: Vec<grid::BoundaryValue>,
}

impl FarCorners {
    fn of(cage: &Cage, grid: &grid::CageGrid, points: &[DVec3], sites: &[Site]) -> Self {
        let mut nodes: Vec<usize> = points
            .iter()
            .zip(sites)
            .filter(|(_, s)| matches!(s, Site::Inside { .. }))
            .flat_map(|(&p, _)| {
                let (cell, _) = grid.cell_of(p);
                (0..8u32).map(move |c| (cell, c))
            })
            .map(|(cell, c)| {
                grid.index(cell.x + (c & 1), cell.y + ((c >> 1) & 1), cell.z + (c >> 2))
            })
            .filter(|&node| grid.roles[node] == NodeRole::Unused)
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        let values = nodes
            .par_iter()
            .map(|&node| {
                let (t, bary, _) = cage.closest_point(grid.position_of(node));
                grid::BoundaryValue {
                    triangle: t as u32,
                    bary,
                }
            })
            .collect();
        Self { nodes, values }
    }

    fn value_at(&self, node: usize) -> Option<&grid::BoundaryValue> {
        self.nodes
            .binary_search(&node)
            .ok()
            .map(|k| &self.values[k])
    }
}

/// The cage value each point blends towards: exact on the cage, and off it (within a cell) a
/// distance-weighted average over the nearby faces, so it stays continuous where the closest
/// face changes (a single closest point jumps there); empty deeper inside.
fn surface_values(
    cage: &Cage,
    grid: &grid::CageGrid,
    points: &[DVec3],
    sites: &[Site],
) -> Vec<Vec<(u32, f64)>> {
    let triangles = cage.triangles();
    points
        .par_iter()
        .zip(sites)
        .map(|(&p, site)| match site {
            Site::OnCage { closest } => {
                let tri = triangles[closest.0];
                (0..3).map(|k| (tri[k], closest.1[k])).collect()
            }
            Site::Inside { distance } if *distance < grid.spacing => {
                near_surface_value(cage, p, *distance, grid.spacing)
            }
            Site::Inside { .. } => Vec::new(),
        })
        .collect()
}

/// The grid field of K cage vertices (batch `chunk`) read at points: trilinear in the grid
/// values (unknowns solved, boundary and far nodes carrying the hat functions), blended within
/// one cell of the cage into the exact hat values there.
struct Interpolation<'a> {
    cage: &'a Cage,
    field: &'a field::HarmonicField,
    far: &'a FarCorners,
    chunk: usize,
}

impl Interpolation<'_> {
    /// The K hat values of the batch at a boundary value (0 past the last vertex).
    fn hats(&self, value: &grid::BoundaryValue) -> Row {
        let first = self.chunk * K;
        let n = self.cage.vertex_count();
        let triangles = self.cage.triangles();
        std::array::from_fn(|c| {
            if first + c < n {
                value.hat(triangles, first + c)
            } else {
                0.0
            }
        })
    }

    /// The batch's values at grid node `node`.
    fn node_row(&self, node: usize) -> Row {
        let grid = &self.field.grid;
        match grid.roles[node] {
            NodeRole::Unknown => self
                .field
                .unknown_value(self.chunk, node)
                .unwrap_or([0.0; K]),
            NodeRole::Boundary(b) => self.hats(&grid.boundary[b as usize]),
            NodeRole::Unused => self.far.value_at(node).map_or([0.0; K], |v| self.hats(v)),
        }
    }

    /// Writes the batch's columns of every point's row in `out` (points × cage vertices).
    fn fill(&self, out: &mut [f64], points: &[DVec3], sites: &[Site], surface: &[Vec<(u32, f64)>]) {
        let grid = &self.field.grid;
        let n = self.cage.vertex_count();
        let first = self.chunk * K;
        let columns = (n - first).min(K);
        out.par_chunks_mut(n)
            .zip(points.par_iter().zip(sites).zip(surface))
            .for_each(|(row, ((&p, site), surface))| {
                let blend = match site {
                    Site::OnCage { .. } => 0.0,
                    Site::Inside { distance } => (distance / grid.spacing).min(1.0),
                };
                let mut value = [0.0; K];
                if blend > 0.0 {
                    let (cell, f) = grid.cell_of(p);
                    for corner in 0..8u32 {
                        let (di, dj, dk) = (corner & 1, (corner >> 1) & 1, corner >> 2);
                        let w = (if di == 1 { f.x } else { 1.0 - f.x })
                            * (if dj == 1 { f.y } else { 1.0 - f.y })
                            * (if dk == 1 { f.z } else { 1.0 - f.z });
                        let r = self.node_row(grid.index(cell.x + di, cell.y + dj, cell.z + dk));
                        for c in 0..K {
                            value[c] += w * r[c];
                        }
                    }
                }
                for c in 0..columns {
                    let v = (first + c) as u32;
                    let exact: f64 = surface
                        .iter()
                        .filter(|(u, _)| *u == v)
                        .map(|(_, w)| w)
                        .sum();
                    row[v as usize] = blend * value[c] + (1.0 - blend) * exact;
                }
            });
    }
}

/// The solver stops at a tolerance: clips round-off negatives and renormalises each row of
/// `n` weights to sum to 1.
fn renormalise_rows(out: &mut [f64], n: usize) {
    out.par_chunks_mut(n).for_each(|row| {
        row.iter_mut().for_each(|w| *w = w.max(0.0));
        let sum: f64 = row.iter().sum();
        if sum > 0.0 {
            row.iter_mut().for_each(|w| *w /= sum);
        }
    });
}

/// Hat-function values of the cage seen from `p` at distance `nearest` from it: faces t within
/// two cells weighted by (nearest / d_t)⁴ times a C1 cutoff from one to two cells, so the
/// result is continuous in p, a partition of unity, non-negative, and exactly the hat values
/// of the face p approaches.
fn near_surface_value(cage: &Cage, p: DVec3, nearest: f64, cell: f64) -> Vec<(u32, f64)> {
    let positions = cage.positions();
    let mut value: Vec<(u32, f64)> = Vec::new();
    let mut total = 0.0;
    for tri in cage.triangles() {
        let [a, b, c] = tri.map(|v| positions[v as usize]);
        let (q, bary) = crate::geometry::closest_point_on_triangle(p, a, b, c);
        let d = q.distance(p);
        if d >= 2.0 * cell {
            continue;
        }
        let x = ((d / cell) - 1.0).clamp(0.0, 1.0);
        let cutoff = 1.0 - x * x * (3.0 - 2.0 * x);
        let kappa = (nearest / d.max(nearest)).powi(4) * cutoff;
        if kappa <= 0.0 {
            continue;
        }
        total += kappa;
        for k in 0..3 {
            value.push((tri[k], kappa * bary[k]));
        }
    }
    if total > 0.0 {
        value.iter_mut().for_each(|(_, w)| *w /= total);
    }
    value
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::shapes;

    #[test]
    fn cube_centre_is_reproduced_with_the_fans_symmetry() {
        // The quads are fanned from their first corner, so hat functions (and HC) are only
        // symmetric under the point reflection p -> 1 - p, which maps vertex i to 7 - i and
        // every fan diagonal to another.
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
        for i in 0..8 {
            assert!((w[i] - w[7 - i]).abs() < 1e-7, "{w:?}");
        }
        let p: DVec3 = w.iter().zip(cage.positions()).map(|(&w, &v)| w * v).sum();
        assert!((p - DVec3::splat(0.5)).length() < 1e-7, "{p}");
    }

    #[test]
    fn a_second_bind_of_the_same_cage_reads_the_solved_field_and_gives_the_same_rows() {
        let cage = shapes::cuboid(DVec3::new(-0.3, 0.1, 0.0), DVec3::new(1.1, 0.9, 0.7));
        let settings = HarmonicSettings {
            resolution: 12,
            ..Default::default()
        };
        let control = BindControl::default();
        let points: Vec<DVec3> = (0..30)
            .map(|i| {
                let t = f64::from(i) / 30.0;
                DVec3::new(-0.29 + 1.38 * t, 0.1 + 0.79 * (7.0 * t).fract(), 0.69 * t)
            })
            .collect();
        let n = cage.vertex_count();
        let all = harmonic_bind(&cage, &points, &settings, &control).unwrap();
        let hits = field::cache_hits();
        let some = harmonic_bind(&cage, &points[10..20], &settings, &control).unwrap();
        assert_eq!(
            field::cache_hits(),
            hits + 1,
            "the second bind solved again"
        );
        assert_eq!(
            some,
            all[10 * n..20 * n].to_vec(),
            "rows differ from the first bind's"
        );
        // Negative control: a cage moved by one ulp is solved afresh.
        let moved = shapes::cuboid(
            DVec3::new(-0.3, 0.1, f64::from_bits(1)),
            DVec3::new(1.1, 0.9, 0.7),
        );
        let hits = field::cache_hits();
        harmonic_bind(&moved, &points[10..20], &settings, &control).unwrap();
        assert_eq!(field::cache_hits(), hits);
    }
}
