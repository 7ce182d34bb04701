//! The mesh's solid as cells of a regular grid: the cells its surface passes through, the
//! cells inside it (generalised winding number, one evaluation per enclosed region), and each
//! cell's distance to the outside.

use glam::{DVec3, IVec3};
use rayon::prelude::*;

use crate::mesh::Mesh;

/// A regular grid of cubic cells with an empty layer all around.
#[derive(Debug, Clone)]
pub(super) struct Grid {
    /// Position of grid vertex (0, 0, 0).
    pub origin: DVec3,
    /// Side of a cell.
    pub cell: f64,
    /// Cells along x, y and z.
    pub dims: IVec3,
}

/// The 6 face neighbours of a cell.
pub(super) const FACE_STEPS: [IVec3; 6] = [
    IVec3::new(-1, 0, 0),
    IVec3::new(1, 0, 0),
    IVec3::new(0, -1, 0),
    IVec3::new(0, 1, 0),
    IVec3::new(0, 0, -1),
    IVec3::new(0, 0, 1),
];

impl Grid {
    /// A grid over the mesh's bounds with `cells_along_longest` cells along its longest side,
    /// two empty cells beyond the bounds on every side. With `mirror` (an axis and a coordinate
    /// along it), the grid is placed so that that plane is a grid plane and the cells on either
    /// side of it mirror each other, covering the bounds and their mirror image.
    /// Each of the `centred` planes (an axis and a coordinate along it, other than the mirror's
    /// axis) passes through the middle of a column of cells: a symmetric figure's legs a little
    /// more than a cell apart then leave that column empty, where a cell face on or near the
    /// plane puts both legs' inner surfaces in the cells beside it and joins them.
    pub fn around(
        lo: DVec3,
        hi: DVec3,
        cells_along_longest: u32,
        mirror: Option<(usize, f64)>,
        centred: &[(usize, f64)],
    ) -> Self {
        let extent = (hi - lo).max(DVec3::splat(1e-12));
        let cell = extent.max_element() / f64::from(cells_along_longest.max(1));
        // Off-grid start so that mesh vertices on round coordinates do not sit on cell faces.
        let jitter = DVec3::new(0.2137, 0.3271, 0.1193) * cell;
        let mut origin = lo - DVec3::splat(2.0 * cell) - jitter;
        let mut dims = ((hi - origin) / cell).ceil().as_ivec3() + IVec3::splat(2);
        if let Some((a, plane)) = mirror {
            // Symmetric around the plane: an even number of cells, the plane between two.
            let below = plane - origin[a];
            let above = hi[a] + 2.0 * cell - plane;
            let half = (below.max(above) / cell).ceil() as i32;
            origin[a] = plane - f64::from(half) * cell;
            dims[a] = 2 * half;
        }
        for &(a, plane) in centred {
            if mirror.is_some_and(|(m, _)| m == a) || a > 2 {
                continue;
            }
            // The plane half a cell past a cell face, the grid still reaching two cells
            // beyond the bounds.
            let below = ((plane - origin[a]) / cell - 0.5).ceil();
            origin[a] = plane - (below + 0.5) * cell;
            dims[a] = ((hi[a] - origin[a]) / cell).ceil() as i32 + 2;
        }
        Self { origin, cell, dims }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        (self.dims.x * self.dims.y * self.dims.z) as usize
    }

    /// Flat index of a cell inside the grid.
    pub fn index(&self, c: IVec3) -> Option<usize> {
        (c.cmpge(IVec3::ZERO).all() && c.cmplt(self.dims).all())
            .then(|| (c.x + self.dims.x * (c.y + self.dims.y * c.z)) as usize)
    }

    /// The cell of a flat index.
    pub fn cell_of(&self, index: usize) -> IVec3 {
        let i = index as i32;
        IVec3::new(
            i % self.dims.x,
            (i / self.dims.x) % self.dims.y,
            i / (self.dims.x * self.dims.y),
        )
    }

    /// The cell holding `p` (clamped into the grid).
    pub fn cell_at(&self, p: DVec3) -> IVec3 {
        ((p - self.origin) / self.cell)
            .floor()
            .as_ivec3()
            .clamp(IVec3::ZERO, self.dims - IVec3::ONE)
    }

    /// Centre of a cell.
    pub fn centre(&self, c: IVec3) -> DVec3 {
        self.origin + (c.as_dvec3() + 0.5) * self.cell
    }

    /// Position of a grid vertex.
    pub fn vertex(&self, v: IVec3) -> DVec3 {
        self.origin + v.as_dvec3() * self.cell
    }

    /// Face neighbours of a flat index that lie in the grid.
    pub fn face_neighbours(&self, index: usize) -> impl Iterator<Item = usize> + '_ {
        let c = self.cell_of(index);
        FACE_STEPS.iter().filter_map(move |s| self.index(c + *s))
    }
}

/// The cells of the mesh's solid: every cell its surface passes through and every cell inside
/// it. Cells holding no surface are grouped into face-connected regions; a region touching the
/// grid's border is outside, any other is inside when the mesh's generalised winding number
/// at its cells is above ½ (sampled at a few of them), so a mesh with holes still fills.
pub(super) fn solid_cells(grid: &Grid, mesh: &Mesh) -> Vec<bool> {
    let mut occupied = vec![false; grid.len()];
    let positions = mesh.welded_positions();
    let triangles = mesh.welded_triangles();
    let mark = |p: DVec3, occupied: &mut Vec<bool>| {
        let c = grid.cell_at(p);
        if let Some(i) = grid.index(c) {
            occupied[i] = true;
        }
        // A point within a hair of a cell face marks the cell beyond it too, so that no mesh
        // vertex ends up on the surface of the solid.
        let local = (p - grid.origin) / grid.cell - c.as_dvec3();
        for axis in 0..3 {
            let mut step = IVec3::ZERO;
            if local[axis] < 1e-6 {
                step[axis] = -1;
            } else if local[axis] > 1.0 - 1e-6 {
                step[axis] = 1;
            } else {
                continue;
            }
            if let Some(i) = grid.index(c + step) {
                occupied[i] = true;
            }
        }
    };
    for &p in positions {
        mark(p, &mut occupied);
    }
    // Triangles larger than a cell pass through cells that hold none of their corners.
    let spacing = 0.45 * grid.cell;
    for triangle in triangles {
        let Some([a, b, c]) = corners(positions, triangle) else {
            continue;
        };
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        let n = (longest / spacing).ceil().min(4096.0) as u32;
        if n <= 1 {
            continue;
        }
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                mark(a + (b - a) * u + (c - a) * v, &mut occupied);
            }
        }
    }
    fill_enclosed(grid, &mut occupied, positions, triangles);
    occupied
}

/// Marks the empty cells inside the mesh: every empty cell whose generalised winding number is
/// above ½ (so a mesh with holes fills too), then every empty region the solid encloses.
fn fill_enclosed(grid: &Grid, occupied: &mut [bool], positions: &[DVec3], triangles: &[[u32; 3]]) {
    let clusters = Clusters::new(grid, positions, triangles);
    let inside: Vec<usize> = (0..grid.len())
        .into_par_iter()
        .filter(|&i| !occupied[i] && clusters.winding_number(grid, grid.cell_of(i)) > 0.5)
        .collect();
    for i in inside {
        occupied[i] = true;
    }
    let (regions, count) = components(grid, |i| !occupied[i]);
    let mut outside = vec![false; count];
    for (i, region) in regions.iter().enumerate() {
        let c = grid.cell_of(i);
        if let Some(r) = *region
            && (c.cmpeq(IVec3::ZERO).any() || c.cmpeq(grid.dims - IVec3::ONE).any())
        {
            outside[r] = true;
        }
    }
    for (i, region) in regions.iter().enumerate() {
        if region.is_some_and(|r| !outside[r]) {
            occupied[i] = true;
        }
    }
}

/// The mesh's triangles grouped by the cell holding their centroid, for winding numbers at cell
/// centres: exact for the groups near the point, a dipole (the group's area vector at its
/// centroid) for the far ones (Barill et al. 2018's fast winding numbers, one level deep).
struct Clusters<'a> {
    positions: &'a [DVec3],
    triangles: &'a [[u32; 3]],
    /// Per group: its cell, the sum of its triangles' area vectors, its area-weighted centroid
    /// and its triangles.
    groups: Vec<(IVec3, DVec3, DVec3, Vec<usize>)>,
}

impl<'a> Clusters<'a> {
    fn new(grid: &Grid, positions: &'a [DVec3], triangles: &'a [[u32; 3]]) -> Self {
        let mut by_cell: std::collections::BTreeMap<usize, (DVec3, DVec3, f64, Vec<usize>)> =
            std::collections::BTreeMap::new();
        for (t, triangle) in triangles.iter().enumerate() {
            let Some([a, b, c]) = corners(positions, triangle) else {
                continue;
            };
            let centroid = (a + b + c) / 3.0;
            let area = 0.5 * crate::geometry::triangle_area_vector(a, b, c);
            let Some(cell) = grid.index(grid.cell_at(centroid)) else {
                continue;
            };
            let entry = by_cell
                .entry(cell)
                .or_insert((DVec3::ZERO, DVec3::ZERO, 0.0, Vec::new()));
            entry.0 += area;
            entry.1 += centroid * area.length();
            entry.2 += area.length();
            entry.3.push(t);
        }
        let groups = by_cell
            .into_iter()
            .map(|(cell, (area, weighted, total, list))| {
                let centre = if total > 0.0 {
                    weighted / total
                } else {
                    grid.centre(grid.cell_of(cell))
                };
                (grid.cell_of(cell), area, centre, list)
            })
            .collect();
        Self {
            positions,
            triangles,
            groups,
        }
    }

    fn winding_number(&self, grid: &Grid, cell: IVec3) -> f64 {
        let p = grid.centre(cell);
        let mut total = 0.0;
        for (at, area, centre, list) in &self.groups {
            if (*at - cell).abs().max_element() <= 2 {
                for &t in list {
                    let [a, b, c] = self.triangles[t];
                    total += crate::geometry::solid_angle(
                        self.positions[a as usize] - p,
                        self.positions[b as usize] - p,
                        self.positions[c as usize] - p,
                    );
                }
            } else {
                let r = *centre - p;
                total += area.dot(r) / r.length().powi(3);
            }
        }
        total / (4.0 * std::f64::consts::PI)
    }
}

/// The corner positions of a triangle (None where it names a vertex that does not exist).
fn corners(positions: &[DVec3], triangle: &[u32; 3]) -> Option<[DVec3; 3]> {
    let [a, b, c] = triangle.map(|v| positions.get(v as usize).copied());
    Some([a?, b?, c?])
}

/// Face-connected components of the cells for which `member` holds: per cell its component
/// (None outside), and the number of components. Components are numbered in the order of
/// their first cell, so the result does not depend on threads.
pub(super) fn components(
    grid: &Grid,
    member: impl Fn(usize) -> bool,
) -> (Vec<Option<usize>>, usize) {
    let mut label = vec![None; grid.len()];
    let mut count = 0;
    let mut stack = Vec::new();
    for start in 0..grid.len() {
        if label[start].is_some() || !member(start) {
            continue;
        }
        label[start] = Some(count);
        stack.push(start);
        while let Some(i) = stack.pop() {
            for n in grid.face_neighbours(i) {
                if label[n].is_none() && member(n) {
                    label[n] = Some(count);
                    stack.push(n);
                }
            }
        }
        count += 1;
    }
    (label, count)
}

/// Distance (in cells) from each occupied cell's centre to the nearest empty cell's centre,
/// by a two-pass 26-neighbour chamfer (weights 1, √2, √3); 0 for empty cells.
pub(super) fn distance_to_outside(grid: &Grid, occupied: &[bool]) -> Vec<f64> {
    let mut d: Vec<f64> = occupied
        .iter()
        .map(|&o| if o { f64::INFINITY } else { 0.0 })
        .collect();
    let steps: Vec<(IVec3, f64)> = (-1..=1)
        .flat_map(|z| (-1..=1).flat_map(move |y| (-1..=1).map(move |x| IVec3::new(x, y, z))))
        .filter(|s| *s != IVec3::ZERO)
        .map(|s| (s, s.as_dvec3().length()))
        .collect();
    // Steps to cells earlier in raster order, and to later ones.
    let (before, after): (Vec<_>, Vec<_>) = steps
        .into_iter()
        .partition(|(s, _)| (s.z, s.y, s.x) < (0, 0, 0));
    let relax = |d: &mut Vec<f64>, i: usize, steps: &[(IVec3, f64)]| {
        if d[i] == 0.0 {
            return;
        }
        let c = grid.cell_of(i);
        for (s, w) in steps {
            // Outside the grid counts as empty.
            let n = grid.index(c + *s).map_or(0.0, |n| d[n]);
            if n + w < d[i] {
                d[i] = n + w;
            }
        }
    };
    for i in 0..grid.len() {
        relax(&mut d, i, &before);
    }
    for i in (0..grid.len()).rev() {
        relax(&mut d, i, &after);
    }
    d
}
