//! Whether a limb branch runs along a grid axis: its cells' distances from the body grow
//! along one, so its joints can be flat grid layers (`parts::straightened`) and its
//! cross-sections measured layer by layer (`narrowings`).

use glam::{DMat3, DVec3};

use super::voxels::Grid;
use crate::geometry::scatter_about;

/// The grid axis a branch runs along and its direction (away from where it starts), as
/// `parts::straightened` finds it.
pub(super) fn straight_axis(grid: &Grid, cells: &[(usize, f64)]) -> Option<(usize, f64)> {
    let g = DistanceFit::of(grid, cells)?.gradient;
    let axis = (0..3)
        .max_by(|&a, &b| g[a].abs().total_cmp(&g[b].abs()))
        .unwrap_or(2);
    (g[axis].abs() >= STRAIGHT_COS * g.length()).then(|| (axis, g[axis].signum()))
}

/// A straight branch's grid layers: each cell's layer counted from the branch's first, and the
/// branch's smallest distance from where it starts, so that a cell in layer `l` is at about
/// `first + l` from there.
pub(super) struct Layers {
    pub axis: usize,
    /// +1 or −1: the direction along `axis` away from where the branch starts.
    pub sign: f64,
    start: f64,
    pub first: f64,
}

impl Layers {
    /// The layers of a branch (cells with their distance from where it starts), None where it
    /// does not run along a grid axis ([`straight_axis`]).
    pub(super) fn of(grid: &Grid, cells: &[(usize, f64)]) -> Option<Self> {
        let (axis, sign) = straight_axis(grid, cells)?;
        let along = |i: usize| sign * f64::from(grid.cell_of(i)[axis]);
        let start = cells
            .iter()
            .map(|&(i, _)| along(i))
            .fold(f64::INFINITY, f64::min);
        let first = cells.iter().map(|&(_, d)| d).fold(f64::INFINITY, f64::min);
        Some(Self {
            axis,
            sign,
            start,
            first,
        })
    }

    /// Cell `i`'s layer, 0 for the branch's first.
    pub(super) fn layer_of(&self, grid: &Grid, i: usize) -> f64 {
        self.sign * f64::from(grid.cell_of(i)[self.axis]) - self.start
    }
}

/// The best affine fit of a branch's geodesic distances over its cells' grid coordinates (a
/// cell's lowest corner): `distance ≈ mean_distance + gradient · (cell − mean_cell)`.
pub(super) struct DistanceFit {
    mean_cell: DVec3,
    mean_distance: f64,
    /// The scatter of the cells' corners about `mean_cell`: their spreads along and across
    /// the branch.
    pub cell_scatter: DMat3,
    /// Distance gained per grid unit; its direction is the branch's, away from where it starts.
    pub gradient: DVec3,
}

impl DistanceFit {
    /// None for fewer than 8 cells, cells in one plane, or no gradient.
    pub(super) fn of(grid: &Grid, cells: &[(usize, f64)]) -> Option<Self> {
        let n = cells.len() as f64;
        if cells.len() < 8 {
            return None;
        }
        let p = |i: usize| grid.cell_of(i).as_dvec3();
        let mean_cell = cells.iter().map(|&(i, _)| p(i)).sum::<DVec3>() / n;
        let mean_distance = cells.iter().map(|&(_, d)| d).sum::<f64>() / n;
        let cov = scatter_about(cells.iter().map(|&(i, _)| p(i)), mean_cell);
        let cross = (cells.iter())
            .map(|&(i, d)| (p(i) - mean_cell) * (d - mean_distance))
            .sum::<DVec3>();
        if cov.determinant().abs() < 1e-9 {
            return None;
        }
        let gradient = cov.inverse() * cross;
        (gradient.length() >= 1e-9).then_some(Self {
            mean_cell,
            mean_distance,
            cell_scatter: cov,
            gradient,
        })
    }

    /// The fitted distance at a cell's lowest corner `cell` (grid coordinates).
    pub(super) fn at(&self, cell: DVec3) -> f64 {
        self.mean_distance + self.gradient.dot(cell - self.mean_cell)
    }

    /// What the fitted distance gains at `cell` (a lowest corner) from the branch's mean
    /// across the unit direction `length`: the tilt of its level sets from square to it.
    pub(super) fn across(&self, cell: DVec3, length: DVec3) -> f64 {
        let across = self.gradient - length * self.gradient.dot(length);
        across.dot(cell - self.mean_cell)
    }
}

/// The most a cell's layer distance may differ from its geodesic one to be used, in cells.
pub(super) const STRAIGHT_SLACK: f64 = 2.0;

/// How close to a grid axis a branch's direction must be to be cut in grid layers (the cosine
/// of about 25°: a leg whose distance from the body also grows sideways at the hip).
pub(super) const STRAIGHT_COS: f64 = 0.9;
