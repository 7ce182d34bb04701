//! The mesh's solid as cells of a regular grid: the cells its surface passes through, the
//! cells inside it (fast generalised winding numbers), and each cell's distance to the outside.

use glam::{DVec3, IVec3};
use rayon::prelude::*;

use crate::mesh::Mesh;

/// A regular grid of cubic cells with an empty layer all around, except for an optional
/// [`Band`] of thin cells across one axis.
#[derive(Debug, Clone)]
pub(super) struct Grid {
    /// Position of grid vertex (0, 0, 0).
    pub origin: DVec3,
    /// Side of a cell (outside the band).
    pub cell: f64,
    /// Cells along x, y and z.
    pub dims: IVec3,
    /// Thin cells across one axis (legs closer than a cell), if any.
    pub band: Option<Band>,
}

/// Cells thinner than the others across one axis: grid planes `first..=last` along `axis` lie
/// evenly from `from` to `to`, the planes beyond them a cell apart. Grid coordinates ("units")
/// map to positions piecewise linearly, so a face, an edge or a cell of the grid keeps its
/// topology and only its size along `axis` changes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Band {
    /// The axis the band is thin across.
    pub axis: usize,
    /// The first grid plane of the band.
    pub first: i32,
    /// The last grid plane of the band (after `first`).
    pub last: i32,
    /// Position of plane `first` along `axis`.
    pub from: f64,
    /// Position of plane `last` along `axis`.
    pub to: f64,
}

/// Where [`Grid::around`] lays a [`Band`]: thin cells `width` wide in all across `axis`,
/// centred on the plane at `plane`: two columns of cells, one on either side of the plane, a
/// grid plane (the mirror's, where the grid mirrors across it; the plane between two legs,
/// where their crotch's slab is halved, `parts::plane_between_legs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct BandAt {
    /// The axis.
    pub axis: usize,
    /// The plane's coordinate along it.
    pub plane: f64,
    /// The band's width.
    pub width: f64,
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
    /// With `band`, the column (or the two columns, where the grid mirrors across the same
    /// plane) around its plane is that thin, every other cell as it would be.
    pub fn around(
        lo: DVec3,
        hi: DVec3,
        cells_along_longest: u32,
        mirror: Option<(usize, f64)>,
        centred: &[(usize, f64)],
        band: Option<BandAt>,
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
        let band = band
            .filter(|b| b.axis < 3 && b.width > 0.0 && b.plane.is_finite())
            .and_then(|b| {
                let a = b.axis;
                let mirrored = mirror.is_some_and(|(m, _)| m == a);
                // Two thin columns, a grid plane between them (the mirror's, with a mirror).
                let thin = 2;
                if b.width >= f64::from(thin) * cell {
                    return None;
                }
                let (from, to) = (b.plane - 0.5 * b.width, b.plane + 0.5 * b.width);
                // Whole cells beyond the band, reaching two cells past the bounds.
                let mut below = ((from - (lo[a] - 2.0 * cell)) / cell).ceil().max(1.0) as i32;
                let mut above = ((hi[a] + 2.0 * cell - to) / cell).ceil().max(1.0) as i32;
                if mirrored {
                    below = below.max(above);
                    above = below;
                }
                origin[a] = from - f64::from(below) * cell;
                dims[a] = below + thin + above;
                Some(Band {
                    axis: a,
                    first: below,
                    last: below + thin,
                    from,
                    to,
                })
            });
        Self {
            origin,
            cell,
            dims,
            band,
        }
    }

    /// The position along `axis` of grid coordinate `u` (a plane at a whole `u`).
    pub fn position_along(&self, axis: usize, u: f64) -> f64 {
        match self.band {
            Some(b) if b.axis == axis => {
                let (first, last) = (f64::from(b.first), f64::from(b.last));
                if u <= first {
                    b.from - (first - u) * self.cell
                } else if u >= last {
                    b.to + (u - last) * self.cell
                } else {
                    b.from + (u - first) / (last - first) * (b.to - b.from)
                }
            }
            _ => self.origin[axis] + u * self.cell,
        }
    }

    /// The grid coordinate along `axis` of position `x`: the inverse of
    /// [`Self::position_along`].
    pub fn units_along(&self, axis: usize, x: f64) -> f64 {
        match self.band {
            Some(b) if b.axis == axis => {
                let (first, last) = (f64::from(b.first), f64::from(b.last));
                if x <= b.from {
                    first - (b.from - x) / self.cell
                } else if x >= b.to {
                    last + (x - b.to) / self.cell
                } else {
                    first + (x - b.from) / (b.to - b.from) * (last - first)
                }
            }
            _ => (x - self.origin[axis]) / self.cell,
        }
    }

    /// A point in grid coordinates (cell `c` spans `c` to `c + 1`).
    pub fn units_of(&self, p: DVec3) -> DVec3 {
        DVec3::new(
            self.units_along(0, p.x),
            self.units_along(1, p.y),
            self.units_along(2, p.z),
        )
    }

    /// The position of a point given in grid coordinates.
    pub fn position_of(&self, q: DVec3) -> DVec3 {
        DVec3::new(
            self.position_along(0, q.x),
            self.position_along(1, q.y),
            self.position_along(2, q.z),
        )
    }

    /// The side of the thinnest cell whose extent overlaps the box `lo`..`hi` (a cell where
    /// the box stays clear of the band).
    pub fn thinnest_cell_near(&self, lo: DVec3, hi: DVec3) -> f64 {
        match self.band {
            Some(b) if lo[b.axis] <= b.to && hi[b.axis] >= b.from => {
                (b.to - b.from) / f64::from(b.last - b.first)
            }
            _ => self.cell,
        }
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
        self.units_of(p)
            .floor()
            .as_ivec3()
            .clamp(IVec3::ZERO, self.dims - IVec3::ONE)
    }

    /// Centre of a cell.
    pub fn centre(&self, c: IVec3) -> DVec3 {
        self.position_of(c.as_dvec3() + 0.5)
    }

    /// Position of a grid vertex.
    pub fn vertex(&self, v: IVec3) -> DVec3 {
        self.position_of(v.as_dvec3())
    }

    /// Face neighbours of a flat index that lie in the grid.
    pub fn face_neighbours(&self, index: usize) -> impl Iterator<Item = usize> + '_ {
        let c = self.cell_of(index);
        FACE_STEPS.iter().filter_map(move |s| self.index(c + *s))
    }
}

/// The cells of the mesh's solid: every cell its surface passes through and every cell inside
/// it: an empty cell whose generalised winding number is above ½ (so a mesh with holes still
/// fills), and every empty region the solid then encloses.
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
        let local = grid.units_of(p) - c.as_dvec3();
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
    for triangle in triangles {
        let Some([a, b, c]) = corners(positions, triangle) else {
            continue;
        };
        let spacing = 0.45 * grid.thinnest_cell_near(a.min(b).min(c), a.max(b).max(c));
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
        .filter(|&i| !occupied[i] && clusters.inside(grid, grid.cell_of(i)))
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

/// The mesh's triangles grouped by the cell holding their centroid, and those groups gathered
/// into ever coarser blocks of 2 × 2 × 2, for winding numbers at cell centres (Barill et al.
/// 2018's fast winding numbers): a cluster whose centre is at least β times its radius from the
/// point counts as one dipole (its area vector at its area-weighted centroid); the triangles of
/// a group nearer than that count exactly.
struct Clusters<'a> {
    positions: &'a [DVec3],
    triangles: &'a [[u32; 3]],
    /// Every cluster, groups first, then each coarser level in turn; the last is the root.
    clusters: Vec<Cluster>,
    /// How many of the clusters are groups.
    groups: usize,
}

/// A group of triangles (no children) or a block of clusters one level finer.
struct Cluster {
    /// The lowest cell holding one of its triangles' centroids: which block it joins.
    cell: IVec3,
    /// The sum of its triangles' area vectors.
    area: DVec3,
    /// The area-weighted centroid of its triangles.
    centre: DVec3,
    /// Total triangle area, the centroid's weight.
    weight: f64,
    /// The largest distance from the centre to a corner of its triangles.
    radius: f64,
    /// Its triangles (groups only).
    triangles: Vec<usize>,
    /// Its clusters one level finer (blocks only).
    children: Vec<usize>,
}

impl Cluster {
    fn empty(cell: IVec3) -> Self {
        Self {
            cell,
            area: DVec3::ZERO,
            centre: DVec3::ZERO,
            weight: 0.0,
            radius: 0.0,
            triangles: Vec::new(),
            children: Vec::new(),
        }
    }
}

impl<'a> Clusters<'a> {
    fn new(grid: &Grid, positions: &'a [DVec3], triangles: &'a [[u32; 3]]) -> Self {
        let mut by_cell: std::collections::BTreeMap<usize, Cluster> =
            std::collections::BTreeMap::new();
        for (t, triangle) in triangles.iter().enumerate() {
            let Some([a, b, c]) = corners(positions, triangle) else {
                continue;
            };
            let centroid = (a + b + c) / 3.0;
            let area = 0.5 * crate::geometry::triangle_area_vector(a, b, c);
            let at = grid.cell_at(centroid);
            let Some(cell) = grid.index(at) else {
                continue;
            };
            let group = by_cell.entry(cell).or_insert_with(|| Cluster::empty(at));
            group.area += area;
            group.centre += centroid * area.length();
            group.weight += area.length();
            group.triangles.push(t);
        }
        let mut clusters: Vec<Cluster> = by_cell
            .into_values()
            .map(|mut group| {
                group.centre = if group.weight > 0.0 {
                    group.centre / group.weight
                } else {
                    grid.centre(group.cell)
                };
                group.radius = group
                    .triangles
                    .iter()
                    .filter_map(|&t| corners(positions, &triangles[t]))
                    .flatten()
                    .map(|p| p.distance(group.centre))
                    .fold(0.0, f64::max);
                group
            })
            .collect();
        // Coarser levels, until one cluster holds all: each level's clusters gathered by their
        // lowest cell halved once more.
        let groups = clusters.len();
        let mut level = 0..groups;
        let mut shift: i32 = 1;
        while level.len() > 1 {
            let mut blocks: std::collections::BTreeMap<[i32; 3], Vec<usize>> =
                std::collections::BTreeMap::new();
            for i in level.clone() {
                let key = clusters[i].cell >> shift;
                blocks.entry(key.to_array()).or_default().push(i);
            }
            let first = clusters.len();
            for children in blocks.into_values() {
                let mut block = Cluster::empty(IVec3::MAX);
                for &c in &children {
                    let child = &clusters[c];
                    block.cell = block.cell.min(child.cell);
                    block.area += child.area;
                    block.centre += child.centre * child.weight;
                    block.weight += child.weight;
                }
                block.centre = if block.weight > 0.0 {
                    block.centre / block.weight
                } else {
                    clusters[children[0]].centre
                };
                block.radius = children
                    .iter()
                    .map(|&c| clusters[c].centre.distance(block.centre) + clusters[c].radius)
                    .fold(0.0, f64::max);
                block.children = children;
                clusters.push(block);
            }
            level = first..clusters.len();
            shift += 1;
        }
        Self {
            positions,
            triangles,
            clusters,
            groups,
        }
    }

    /// The generalised winding number at `p`, clusters at least `beta` times their radius
    /// away taken as dipoles (first order: a cluster's error falls as 1/β²).
    fn winding_number(&self, p: DVec3, beta: f64) -> f64 {
        let mut total = 0.0;
        let mut stack: Vec<usize> = self.clusters.len().checked_sub(1).into_iter().collect();
        while let Some(i) = stack.pop() {
            let cluster = &self.clusters[i];
            let r = cluster.centre - p;
            let distance = r.length();
            if distance > 0.0 && distance >= beta * cluster.radius {
                total += cluster.area.dot(r) / distance.powi(3);
            } else if cluster.children.is_empty() {
                total += self.solid_angle(cluster, p);
            } else {
                stack.extend_from_slice(&cluster.children);
            }
        }
        total / (4.0 * std::f64::consts::PI)
    }

    /// The solid angle a group's triangles subtend at `p`, triangle by triangle.
    fn solid_angle(&self, group: &Cluster, p: DVec3) -> f64 {
        group
            .triangles
            .iter()
            .map(|&t| {
                let [a, b, c] = self.triangles[t].map(|i| self.positions[i as usize] - p);
                crate::geometry::solid_angle(a, b, c)
            })
            .sum()
    }

    /// Whether the centre of `cell` is inside: a winding number above ½. Taken from dipoles
    /// at 2 radii ([`Self::winding_number`]; at most 0.17 off on the shared meshes) where that
    /// is more than [`UNSURE`] from ½; else from the groups alone, the triangles of those
    /// near it exact ([`Self::sure_winding_number`]).
    fn inside(&self, grid: &Grid, cell: IVec3) -> bool {
        let quick = self.winding_number(grid.centre(cell), 2.0);
        if (quick - 0.5).abs() > UNSURE {
            return quick > 0.5;
        }
        self.sure_winding_number(grid, cell) > 0.5
    }

    /// The winding number at the centre of `cell` from the groups alone: exact for the
    /// triangles of the groups within two cells or two radii, a dipole for every other group.
    fn sure_winding_number(&self, grid: &Grid, cell: IVec3) -> f64 {
        let p = grid.centre(cell);
        let mut total = 0.0;
        for group in self.clusters.iter().take(self.groups) {
            if (group.cell - cell).abs().max_element() <= 2
                || group.centre.distance(p) < 2.0 * group.radius
            {
                total += self.solid_angle(group, p);
            } else {
                let r = group.centre - p;
                total += group.area.dot(r) / r.length().powi(3);
            }
        }
        total / (4.0 * std::f64::consts::PI)
    }
}

/// How far from ½ a quick winding number must be to be taken.
const UNSURE: f64 = 0.3;

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

/// The cells of each face-connected component of `member` cells, in index order.
pub(super) fn component_cells(grid: &Grid, member: impl Fn(usize) -> bool) -> Vec<Vec<usize>> {
    let (component_of, count) = components(grid, member);
    let mut cells: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (i, c) in component_of.iter().enumerate() {
        if let Some(c) = *c {
            cells[c].push(i);
        }
    }
    cells
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::solid_angle;

    /// The planes along `axis` of `grid`, as positions.
    fn planes(grid: &Grid, axis: usize) -> Vec<f64> {
        (0..=grid.dims[axis])
            .map(|k| {
                let mut v = IVec3::ZERO;
                v[axis] = k;
                grid.vertex(v)[axis]
            })
            .collect()
    }

    #[test]
    fn a_band_makes_two_thin_columns_and_leaves_every_other_cell_whole() {
        let (lo, hi) = (DVec3::new(-1.0, -0.5, 0.0), DVec3::new(1.0, 0.5, 4.0));
        let plain = Grid::around(lo, hi, 40, None, &[], None);
        let band = BandAt {
            axis: 0,
            plane: 0.03,
            width: 0.02,
        };
        let grid = Grid::around(lo, hi, 40, None, &[], Some(band));
        let x = planes(&grid, 0);
        let widths: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        let thin: Vec<usize> = (0..widths.len())
            .filter(|&k| (widths[k] - grid.cell).abs() > 1e-9)
            .collect();
        // Two columns side by side, half the band each, a grid plane on the band's middle.
        assert_eq!(thin.len(), 2, "{widths:?}");
        let k = thin[0];
        assert_eq!(thin[1], k + 1);
        assert!((widths[k] - 0.01).abs() < 1e-12 && (widths[k + 1] - 0.01).abs() < 1e-12);
        assert!((x[k + 1] - 0.03).abs() < 1e-12, "{}", x[k + 1]);
        // Still two cells beyond the bounds (at least one and a half), the other axes as on
        // the plain grid.
        assert!(x[0] <= lo.x - 1.5 * grid.cell && x[x.len() - 1] >= hi.x + 1.5 * grid.cell);
        assert_eq!(planes(&grid, 1), planes(&plain, 1));
        assert_eq!(grid.cell, plain.cell);
        // Positions and grid coordinates are inverse; every cell holds its centre.
        for i in 0..grid.len() {
            let c = grid.cell_of(i);
            assert_eq!(grid.cell_at(grid.centre(c)), c);
            let q = c.as_dvec3() + DVec3::new(0.3, 0.7, 0.1);
            assert!((grid.units_of(grid.position_of(q)) - q).length() < 1e-9);
        }
        // A band as wide as the two cells it replaces is no band.
        let wide = BandAt { width: 0.2, ..band };
        assert!(
            Grid::around(lo, hi, 40, None, &[], Some(wide))
                .band
                .is_none()
        );
    }

    #[test]
    fn a_band_across_the_mirror_s_plane_is_two_thin_columns_mirroring_each_other() {
        let (lo, hi) = (DVec3::new(-1.0, -0.5, 0.0), DVec3::new(1.0, 0.5, 4.0));
        let band = BandAt {
            axis: 0,
            plane: 0.0,
            width: 0.16,
        };
        let grid = Grid::around(lo, hi, 40, Some((0, 0.0)), &[], Some(band));
        let half = grid.dims.x / 2;
        let x = planes(&grid, 0);
        assert_eq!(x[half as usize], 0.0);
        assert!((x[half as usize + 1] - 0.08).abs() < 1e-12);
        for k in 0..=half {
            let (above, below) = (x[(half + k) as usize], x[(half - k) as usize]);
            assert!(
                (above + below).abs() < 1e-12,
                "plane {k}: {above} against {below}"
            );
        }
        // Mirror images of grid vertices lie at exactly opposite offsets from the plane.
        let plane = super::super::symmetry::MirrorPlane::of(&grid, 0);
        for v in 0..=grid.dims.x {
            let p = super::super::symmetry::vertex_position(&grid, &plane, IVec3::new(v, 3, 5));
            let image = plane.vertex(IVec3::new(v, 3, 5));
            let q = super::super::symmetry::vertex_position(&grid, &plane, image);
            assert_eq!(p.x, -q.x);
        }
    }

    #[test]
    fn the_thin_column_between_two_close_walls_stays_empty() {
        // Two slabs 0.03 apart, a cell 0.1: on the plain grid a column holds both inner faces;
        // with a band 0.024 wide between them, no cell of it is solid below their bridge.
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for (from, to) in [
            (DVec3::new(-0.5, -0.5, 0.0), DVec3::new(-0.015, 0.5, 2.0)),
            (DVec3::new(0.015, -0.5, 0.0), DVec3::new(0.5, 0.5, 2.0)),
            (DVec3::new(-0.5, -0.5, 2.0), DVec3::new(0.5, 0.5, 2.5)),
        ] {
            let part = crate::generate::demo::box_mesh(from, to, [2, 2, 8]);
            let base = positions.len() as u32;
            positions.extend_from_slice(part.welded_positions());
            triangles.extend(part.welded_triangles().iter().map(|t| t.map(|k| k + base)));
        }
        let mesh = Mesh::new(positions, triangles, None, None).unwrap();
        let (lo, hi) = mesh.bounds();
        let band = BandAt {
            axis: 0,
            plane: 0.0,
            width: 0.024,
        };
        for (band, parted) in [(None, false), (Some(band), true)] {
            let grid = Grid::around(lo, hi, 25, None, &[(0, 0.0)], band);
            let occupied = solid_cells(&grid, &mesh);
            let column = grid.cell_at(DVec3::ZERO).x;
            let filled = (0..grid.len())
                .filter(|&i| occupied[i])
                .map(|i| grid.cell_of(i))
                .filter(|c| c.x == column && grid.centre(*c).z < 1.9)
                .count();
            assert_eq!(filled == 0, parted, "{filled} cells of the column filled");
        }
    }

    /// The winding number summed over every triangle, no dipoles.
    fn brute_force(positions: &[DVec3], triangles: &[[u32; 3]], p: DVec3) -> f64 {
        let total: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize] - p);
                solid_angle(a, b, c)
            })
            .sum();
        total / (4.0 * std::f64::consts::PI)
    }

    /// Checks every cell centre of a 16-cell grid around the mesh: the quick winding number
    /// within 0.2 of the brute-force one, and `inside` deciding as the brute-force one does
    /// wherever that is clear of ½.
    fn check(positions: &[DVec3], triangles: &[[u32; 3]]) -> usize {
        let lo = positions.iter().fold(DVec3::MAX, |m, p| m.min(*p));
        let hi = positions.iter().fold(DVec3::MIN, |m, p| m.max(*p));
        let grid = Grid::around(lo, hi, 16, None, &[], None);
        let clusters = Clusters::new(&grid, positions, triangles);
        let mut inside = 0;
        for i in 0..grid.len() {
            let cell = grid.cell_of(i);
            let p = grid.centre(cell);
            let exact = brute_force(positions, triangles, p);
            let quick = clusters.winding_number(p, 2.0);
            assert!(
                (quick - exact).abs() < 0.2,
                "{cell}: {quick} against {exact}"
            );
            if (exact - 0.5).abs() > 0.05 {
                assert_eq!(clusters.inside(&grid, cell), exact > 0.5, "{cell}: {exact}");
            }
            inside += usize::from(clusters.inside(&grid, cell));
        }
        inside
    }

    #[test]
    fn fast_winding_numbers_decide_as_the_exact_sum_on_fine_and_coarse_meshes() {
        // A fine, wavy closed surface.
        let field = |p: DVec3| p.length() - 0.8 + 0.1 * (7.0 * p.x).sin() * (5.0 * p.y).cos();
        let (positions, triangles) =
            crate::surface_nets::surface_nets(field, DVec3::splat(-1.0), DVec3::splat(1.0), 0.12);
        assert!(check(&positions, &triangles) > 300);
        // A box of 12 triangles, each many cells wide: a group's triangles reach far from the
        // cell holding their centroids, so its radius, not its cell, says when it is far.
        let cuboid = crate::cage::shapes::cuboid(DVec3::ZERO, DVec3::new(3.0, 1.0, 0.5));
        let (positions, triangles) = (cuboid.positions().to_vec(), cuboid.triangles().to_vec());
        assert_eq!(triangles.len(), 12);
        assert!(brute_force(&positions, &triangles, DVec3::new(1.5, 0.5, 0.25)) > 0.99);
        assert!(check(&positions, &triangles) > 50);
        // The box with its top open: the winding number passes ½ near the opening, where
        // `inside` falls back to the groups' sum.
        check(&positions, &triangles[..10]);
    }
}
