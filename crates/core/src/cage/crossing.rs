//! Edges that pass through triangles: a cage through itself, or one cage through another.
//!
//! Two triangles that are not coplanar intersect exactly when an edge of one passes through
//! the other, so testing every edge against the triangles near it finds every crossing. Only
//! strict crossings count: an edge that ends on a triangle, runs along its plane or touches it
//! at an edge or corner is how neighbouring faces (and neighbouring cages) meet.

use glam::DVec3;

/// Relative tolerance (to the larger cage's bounding-box diagonal) inside which an edge end
/// counts as touching a triangle's plane, and a crossing point as touching its border.
const TOUCH_TOLERANCE: f64 = 1e-9;

/// Triangles bucketed in a uniform grid over their bounds, to find those near a segment.
struct TriangleGrid {
    lo: DVec3,
    cell_size: DVec3,
    dims: [usize; 3],
    /// Triangle indices per cell, x fastest.
    cells: Vec<Vec<u32>>,
}

impl TriangleGrid {
    fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        let (lo, hi) = super::bounds_of(positions);
        // About one triangle per cell.
        let per_axis = (triangles.len() as f64).cbrt().ceil().clamp(1.0, 64.0) as usize;
        let extent = (hi - lo).max(DVec3::splat(f64::MIN_POSITIVE));
        let mut grid = Self {
            lo,
            cell_size: extent / per_axis as f64,
            dims: [per_axis; 3],
            cells: vec![Vec::new(); per_axis * per_axis * per_axis],
        };
        for (t, tri) in triangles.iter().enumerate() {
            let corners = tri.map(|v| positions[v as usize]);
            let (a, b) = (
                corners[0].min(corners[1]).min(corners[2]),
                corners[0].max(corners[1]).max(corners[2]),
            );
            grid.for_cells(a, b, |cell| cell.push(t as u32));
        }
        grid
    }

    fn cell_range(&self, lo: DVec3, hi: DVec3) -> [std::ops::RangeInclusive<usize>; 3] {
        let index = |p: DVec3, axis: usize| {
            let x = ((p[axis] - self.lo[axis]) / self.cell_size[axis]).floor();
            x.clamp(0.0, (self.dims[axis] - 1) as f64) as usize
        };
        [0, 1, 2].map(|axis| index(lo, axis)..=index(hi, axis))
    }

    fn for_cells(&mut self, lo: DVec3, hi: DVec3, mut visit: impl FnMut(&mut Vec<u32>)) {
        let [xs, ys, zs] = self.cell_range(lo, hi);
        for z in zs {
            for y in ys.clone() {
                for x in xs.clone() {
                    let i = x + self.dims[0] * (y + self.dims[1] * z);
                    if let Some(cell) = self.cells.get_mut(i) {
                        visit(cell);
                    }
                }
            }
        }
    }

    /// Triangles whose cells overlap the box `lo..hi`, each once, in `out` (cleared first).
    fn near(&self, lo: DVec3, hi: DVec3, out: &mut Vec<u32>) {
        out.clear();
        let [xs, ys, zs] = self.cell_range(lo, hi);
        for z in zs {
            for y in ys.clone() {
                for x in xs.clone() {
                    let i = x + self.dims[0] * (y + self.dims[1] * z);
                    out.extend(self.cells.get(i).into_iter().flatten());
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}

/// Whether the segment `p`–`q` passes through the inside of triangle `a b c`: its ends lie
/// strictly on opposite sides of the plane and the crossing point strictly inside the
/// triangle, both by more than `tolerance` (a length).
pub(crate) fn segment_pierces_triangle(
    p: DVec3,
    q: DVec3,
    [a, b, c]: [DVec3; 3],
    tolerance: f64,
) -> bool {
    let normal = (b - a).cross(c - a);
    let length = normal.length();
    if length <= tolerance * tolerance {
        return false; // degenerate triangle: reported on its own
    }
    let unit = normal / length;
    let (sp, sq) = (unit.dot(p - a), unit.dot(q - a));
    let opposite = (sp > tolerance && sq < -tolerance) || (sp < -tolerance && sq > tolerance);
    if !opposite {
        return false;
    }
    let x = p + (q - p) * (sp / (sp - sq));
    // Distance of the crossing point from each edge's line, signed positive inside.
    [(a, b), (b, c), (c, a)].iter().all(|&(s, e)| {
        let edge = e - s;
        unit.cross(edge).dot(x - s) / edge.length() > tolerance
    })
}

/// A crossing: edge `(a, b)` (vertex indices of the first cage) passes through triangle
/// `triangle` of the second.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Crossing {
    pub edge: [u32; 2],
    pub triangle: usize,
}

/// The first edge of `edges` (over `edge_positions`) that passes through a triangle of
/// `triangles` (over `positions`), skipping triangles that have an end of the edge as a corner
/// when `same_cage` (the vertex indices then name the same vertices).
fn first_crossing(
    edge_positions: &[DVec3],
    edges: &[[u32; 2]],
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    same_cage: bool,
    tolerance: f64,
) -> Option<Crossing> {
    let grid = TriangleGrid::new(positions, triangles);
    let mut near = Vec::new();
    for &[i, j] in edges {
        let (p, q) = (edge_positions[i as usize], edge_positions[j as usize]);
        grid.near(p.min(q), p.max(q), &mut near);
        for &t in &near {
            let tri = triangles[t as usize];
            if same_cage && (tri.contains(&i) || tri.contains(&j)) {
                continue;
            }
            if segment_pierces_triangle(p, q, tri.map(|v| positions[v as usize]), tolerance) {
                return Some(Crossing {
                    edge: [i, j],
                    triangle: t as usize,
                });
            }
        }
    }
    None
}

fn unique_edges(triangles: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let mut edges: Vec<[u32; 2]> = triangles
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// The first place where a cage passes through itself, if any.
pub(crate) fn self_crossing(positions: &[DVec3], triangles: &[[u32; 3]]) -> Option<Crossing> {
    let (lo, hi) = super::bounds_of(positions);
    let tolerance = TOUCH_TOLERANCE * (hi - lo).length();
    first_crossing(
        positions,
        &unique_edges(triangles),
        positions,
        triangles,
        true,
        tolerance,
    )
}

/// The first place where cage `first` passes through cage `second` or the other way round:
/// `(true, crossing)` when an edge of `first` crosses a triangle of `second`, `(false, ..)`
/// for the reverse. Cages that only meet at shared faces, edges or vertices do not cross.
pub(crate) fn cages_crossing(
    first: (&[DVec3], &[[u32; 3]]),
    second: (&[DVec3], &[[u32; 3]]),
) -> Option<(bool, Crossing)> {
    let (lo_a, hi_a) = super::bounds_of(first.0);
    let (lo_b, hi_b) = super::bounds_of(second.0);
    if lo_a.cmpgt(hi_b).any() || lo_b.cmpgt(hi_a).any() {
        return None;
    }
    let tolerance = TOUCH_TOLERANCE * (hi_a - lo_a).length().max((hi_b - lo_b).length());
    let forward = first_crossing(
        first.0,
        &unique_edges(first.1),
        second.0,
        second.1,
        false,
        tolerance,
    );
    forward.map(|c| (true, c)).or_else(|| {
        first_crossing(
            second.0,
            &unique_edges(second.1),
            first.0,
            first.1,
            false,
            tolerance,
        )
        .map(|c| (false, c))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::shapes;

    #[test]
    fn a_segment_through_the_middle_pierces_and_touching_ones_do_not() {
        let tri = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let (above, below) = (DVec3::new(0.2, 0.2, 1.0), DVec3::new(0.2, 0.2, -1.0));
        assert!(segment_pierces_triangle(above, below, tri, 1e-9));
        // Ends on the triangle, runs in its plane, passes through its edge or corner, misses.
        assert!(!segment_pierces_triangle(
            above,
            DVec3::new(0.2, 0.2, 0.0),
            tri,
            1e-9
        ));
        assert!(!segment_pierces_triangle(
            DVec3::new(-1.0, 0.2, 0.0),
            DVec3::new(2.0, 0.2, 0.0),
            tri,
            1e-9
        ));
        assert!(!segment_pierces_triangle(
            DVec3::new(0.5, 0.0, 1.0),
            DVec3::new(0.5, 0.0, -1.0),
            tri,
            1e-9
        ));
        assert!(!segment_pierces_triangle(DVec3::Z, -DVec3::Z, tri, 1e-9));
        assert!(!segment_pierces_triangle(
            DVec3::new(2.0, 2.0, 1.0),
            DVec3::new(2.0, 2.0, -1.0),
            tri,
            1e-9
        ));
    }

    #[test]
    fn a_valid_cage_does_not_cross_itself_and_a_pushed_through_corner_does() {
        let cube = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
        assert_eq!(self_crossing(cube.positions(), cube.triangles()), None);
        let star = shapes::star_prism();
        assert_eq!(self_crossing(star.positions(), star.triangles()), None);
        // Push one corner through the opposite face.
        let mut positions = cube.positions().to_vec();
        let corner = positions
            .iter()
            .position(|p| *p == DVec3::ONE)
            .expect("the cube has the corner (1, 1, 1)");
        positions[corner] = DVec3::new(0.6, 0.7, -0.5);
        assert!(self_crossing(&positions, cube.triangles()).is_some());
    }

    #[test]
    fn neighbours_meeting_at_a_face_do_not_cross_and_interpenetrating_boxes_do() {
        let a = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
        let b = shapes::cuboid(DVec3::X, DVec3::new(2.0, 1.0, 1.0));
        let touching_corner = shapes::cuboid(DVec3::ONE, DVec3::splat(2.0));
        assert_eq!(
            cages_crossing(
                (a.positions(), a.triangles()),
                (b.positions(), b.triangles())
            ),
            None
        );
        assert_eq!(
            cages_crossing(
                (a.positions(), a.triangles()),
                (touching_corner.positions(), touching_corner.triangles())
            ),
            None
        );
        // A plus sign: neither box has a vertex inside the other, yet they overlap.
        let long_x = shapes::cuboid(DVec3::new(-1.0, 0.4, 0.4), DVec3::new(2.0, 0.6, 0.6));
        let long_y = shapes::cuboid(DVec3::new(0.4, -1.0, 0.3), DVec3::new(0.6, 2.0, 0.7));
        let crossing = cages_crossing(
            (long_x.positions(), long_x.triangles()),
            (long_y.positions(), long_y.triangles()),
        );
        assert!(crossing.is_some(), "the plus sign overlaps");
    }
}
