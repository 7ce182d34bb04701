//! Point-in-cage tests for many points at once. A grid over the cage's bounds marks the cells
//! that its surface (grown by the on-cage tolerance) may reach; every other cell lies wholly
//! inside or wholly outside, and so does each face-connected region of such cells, whose one
//! winding number is computed once. A point in such a cell is answered by a lookup; only points
//! in marked cells pay for the exact tests (distance to the surface, winding number). The
//! answers are those of the exact tests: no surface passes through an unmarked cell, so the
//! winding number is constant there and the distance exceeds the tolerance.

use glam::{DVec3, IVec3};

use crate::cage::Cage;

/// Where a point lies with respect to one cage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    Outside,
    Inside,
    /// Within the tolerance of the surface.
    OnSurface,
}

/// Cells along the longest side: eight per cube root of the triangle count (up to 128), so the
/// marked shell stays thin for large cages while small cages get a grid worth building. With
/// four (up to 64), more points fell in the thicker shell, each paying the exact tests over
/// every triangle (docs/performance.md, "Design measurements").
fn cells_along_longest_side(triangles: usize) -> f64 {
    (8.0 * (triangles as f64).cbrt()).clamp(8.0, 128.0)
}

/// Cells along the longest side for `points` points in the cage's bounds: twice the cube root
/// of their number (at most 160), so that a cage with many points to place (a big mesh's) has
/// a thinner marked shell, each of whose points pays a winding number over every triangle.
/// The 625k-vertex armadillo's auto rig: 8 per cube root of the triangles put 30 % of the
/// points in the shell; with this, placing its vertices (`validate`, OBJ reading included) took
/// 1.5–1.7 s against 1.7–1.9 s before, 1.5 times the cube root 1.5–1.7 s, 3 times 1.7–1.8 s
/// (each cell costs its marking and labelling).
fn cells_for_points(points: usize) -> f64 {
    (2.0 * (points as f64).cbrt()).min(160.0)
}

/// A cell nobody marked, and the region it belongs to.
const NEAR: u32 = u32::MAX;

/// One cage's grid for [`Location`] queries.
pub struct CageLocator<'a> {
    cage: &'a Cage,
    tolerance: f64,
    origin: DVec3,
    cell: f64,
    dims: IVec3,
    /// Per cell: [`NEAR`] or the index of its region in `inside`.
    region: Vec<u32>,
    inside: Vec<bool>,
    /// The marked cells (indices, increasing) and, per marked cell, the triangles that
    /// marked it (`near_triangles[near_start[k]..near_start[k + 1]]`): every triangle within
    /// the tolerance of a point in the cell is among them, so the distance test reads only
    /// those (over every triangle it was most of placing a big mesh's vertices).
    near_cells: Vec<u32>,
    near_start: Vec<u32>,
    near_triangles: Vec<u32>,
}

impl<'a> CageLocator<'a> {
    /// The locator of `cage` for about `points` points in its bounds, with points within
    /// `tolerance` of its surface on it.
    pub fn for_points(cage: &'a Cage, tolerance: f64, points: usize) -> Self {
        let (lo, hi) = cage.bounds();
        let cells_along_longest =
            cells_along_longest_side(cage.triangles().len()).max(cells_for_points(points));
        let margin = DVec3::splat(tolerance);
        let (lo, hi) = (lo - margin, hi + margin);
        let extent = hi - lo;
        let cell = (extent.max_element() / cells_along_longest).max(f64::MIN_POSITIVE);
        let dims = (extent / cell).ceil().as_ivec3().max(IVec3::ONE);
        let mut locator = Self {
            cage,
            tolerance,
            origin: lo,
            cell,
            dims,
            region: vec![0; (dims.x * dims.y * dims.z) as usize],
            inside: Vec::new(),
            near_cells: Vec::new(),
            near_start: Vec::new(),
            near_triangles: Vec::new(),
        };
        locator.mark_near_cells();
        locator.label_regions();
        locator
    }

    fn index(&self, c: IVec3) -> usize {
        ((c.z * self.dims.y + c.y) * self.dims.x + c.x) as usize
    }

    fn cell_of(&self, p: DVec3) -> IVec3 {
        ((p - self.origin) / self.cell)
            .floor()
            .as_ivec3()
            .clamp(IVec3::ZERO, self.dims - IVec3::ONE)
    }

    fn centre(&self, c: IVec3) -> DVec3 {
        self.origin + (c.as_dvec3() + DVec3::splat(0.5)) * self.cell
    }

    /// Marks every cell the surface, grown by the tolerance, may reach: the cells of each
    /// triangle's grown bounds whose centre is within half a cell diagonal of its plane. A
    /// point within the tolerance of a triangle lies in its grown bounds and within half a cell
    /// diagonal and the tolerance of its plane from its cell's centre: that cell is one it
    /// marks, and lists it.
    fn mark_near_cells(&mut self) {
        let mut marks: Vec<(u32, u32)> = Vec::new();
        let positions = self.cage.positions();
        // A little more than the tolerance, against rounding in the cell arithmetic.
        let reach = self.tolerance + 1e-9 * self.cell;
        let half_diagonal = 0.5 * self.cell * 3f64.sqrt();
        for (t, &[a, b, c]) in self.cage.triangles().iter().enumerate() {
            let [a, b, c] = [a, b, c].map(|k| positions[k as usize]);
            let grow = DVec3::splat(reach);
            let first = self.cell_of(a.min(b).min(c) - grow);
            let last = self.cell_of(a.max(b).max(c) + grow);
            let normal = (b - a).cross(c - a).normalize_or_zero();
            for z in first.z..=last.z {
                for y in first.y..=last.y {
                    for x in first.x..=last.x {
                        let cell = IVec3::new(x, y, z);
                        let off_plane = normal.dot(self.centre(cell) - a).abs();
                        if normal == DVec3::ZERO || off_plane <= half_diagonal + reach {
                            let index = self.index(cell);
                            self.region[index] = NEAR;
                            marks.push((index as u32, t as u32));
                        }
                    }
                }
            }
        }
        marks.sort_unstable();
        for (k, &(cell, triangle)) in marks.iter().enumerate() {
            if k == 0 || marks[k - 1].0 != cell {
                self.near_cells.push(cell);
                self.near_start.push(self.near_triangles.len() as u32);
            }
            self.near_triangles.push(triangle);
        }
        self.near_start.push(self.near_triangles.len() as u32);
    }

    /// The triangles that marked cell `index` (none for an unmarked cell).
    fn triangles_near(&self, index: usize) -> &[u32] {
        match self.near_cells.binary_search(&(index as u32)) {
            Ok(k) => {
                &self.near_triangles[self.near_start[k] as usize..self.near_start[k + 1] as usize]
            }
            Err(_) => &[],
        }
    }

    /// Numbers the face-connected regions of unmarked cells and decides each by the winding
    /// number at one of its cell centres.
    fn label_regions(&mut self) {
        const UNLABELLED: u32 = 0;
        let mut stack = Vec::new();
        let mut next = 0u32;
        for start in 0..self.region.len() {
            if self.region[start] != UNLABELLED {
                continue;
            }
            // Regions are stored from 1 while labelling, as index + 1.
            next += 1;
            let first = self.cell_at_index(start);
            self.inside
                .push(self.cage.winding_number(self.centre(first)) > 0.5);
            self.region[start] = next;
            stack.push(first);
            while let Some(c) = stack.pop() {
                for step in [IVec3::X, IVec3::Y, IVec3::Z] {
                    for n in [c - step, c + step] {
                        if n.cmplt(IVec3::ZERO).any() || n.cmpge(self.dims).any() {
                            continue;
                        }
                        let index = self.index(n);
                        if self.region[index] == UNLABELLED {
                            self.region[index] = next;
                            stack.push(n);
                        }
                    }
                }
            }
        }
        for region in &mut self.region {
            if *region != NEAR {
                *region -= 1;
            }
        }
    }

    fn cell_at_index(&self, index: usize) -> IVec3 {
        let index = index as i32;
        IVec3::new(
            index % self.dims.x,
            (index / self.dims.x) % self.dims.y,
            index / (self.dims.x * self.dims.y),
        )
    }

    /// Where `p` lies: on the surface within the tolerance, else inside by winding number
    /// (> ½), else outside.
    pub fn locate(&self, p: DVec3) -> Location {
        // The grid covers the cage's bounds grown by the tolerance: beyond it is outside.
        let (lo, hi) = (self.origin, self.origin + self.dims.as_dvec3() * self.cell);
        if p.cmplt(lo).any() || p.cmpgt(hi).any() || !p.is_finite() {
            return Location::Outside;
        }
        let index = self.index(self.cell_of(p));
        match self.region[index] {
            NEAR => {
                if self
                    .cage
                    .is_within_of(p, self.tolerance, self.triangles_near(index))
                {
                    Location::OnSurface
                } else if self.cage.winding_number(p) > 0.5 {
                    Location::Inside
                } else {
                    Location::Outside
                }
            }
            region if self.inside[region as usize] => Location::Inside,
            _ => Location::Outside,
        }
    }
}

/// The exact tests: distance to the surface first (at a vertex or edge the winding number is
/// ill-defined), then the winding number.
pub fn exact(cage: &Cage, p: DVec3, tolerance: f64) -> Location {
    if cage.is_within(p, tolerance) {
        Location::OnSurface
    } else if cage.winding_number(p) > 0.5 {
        Location::Inside
    } else {
        Location::Outside
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An L-shaped (concave) cage: the locator answers as the exact tests do on a lattice of
    /// points inside, outside, on faces, edges and corners and just off them, and most points
    /// are answered without the exact tests; on its coarsest grid and on the finest (for many
    /// points, whose marked cells each list a few triangles for the distance test).
    #[test]
    fn the_locator_answers_as_the_exact_tests_do() {
        let l_shape = crate::cage::shapes::l_prism();
        for (tolerance, points) in [(1e-9, 0), (0.03, 0), (1e-9, 1 << 30), (0.03, 1 << 30)] {
            let locator = CageLocator::for_points(&l_shape, tolerance, points);
            let fine = cells_for_points(points) > cells_along_longest_side(12);
            assert_eq!(fine, points > 0);
            let mut counts = [0usize; 3];
            let mut looked_up = 0;
            for i in -3..=43 {
                for j in -3..=43 {
                    for k in -3..=23 {
                        let p = DVec3::new(i as f64, j as f64, k as f64) * 0.05;
                        let expected = exact(&l_shape, p, tolerance);
                        assert_eq!(locator.locate(p), expected, "{p}, {tolerance}, {points}");
                        counts[expected as usize] += 1;
                        let cell = locator.cell_of(p);
                        looked_up += usize::from(locator.region[locator.index(cell)] != NEAR);
                    }
                }
            }
            assert!(counts.iter().all(|&n| n > 500), "{counts:?}");
            assert!(looked_up > 20_000, "{looked_up} answered by lookup");
        }
    }
}
