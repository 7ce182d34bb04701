//! What "one piece of the surface" means to the auto rig: mesh vertices joined by mesh edges,
//! and also by the surfaces of separate components that pass through each other (an eye set
//! into its socket, a spike stuck into a body, a button sewn onto a coat). Such components are
//! one piece as a set of points — no cage boundary can pass between them where they cross — so
//! the rig neither tries to split them nor counts them as two parts in one cage. Components
//! that only come close (two fingers that touch) stay separate pieces.

use std::collections::HashMap;

use glam::{DVec3, IVec3};

use crate::geometry::ray_triangle;
use crate::mesh::Mesh;

/// Grid cells one triangle's bounding box may cover, on average, before the cells grow: keeps
/// the spatial hash linear in the triangles whatever their sizes.
const CELLS_PER_TRIANGLE: usize = 16;

/// Triangle pairs tested for crossing at most: a file of many components stacked on each other
/// cannot make the test quadratic (pairs beyond are not linked).
const MAX_PAIR_TESTS: usize = 20_000_000;

/// A mesh with the adjacency of its surface, found once per rig (the crossing test is the costly
/// part) and read by every step that counts pieces.
pub(crate) struct SurfaceMesh<'a> {
    pub mesh: &'a Mesh,
    /// [`surface_neighbours`] of the mesh.
    pub neighbours: Vec<Vec<u32>>,
}

impl<'a> SurfaceMesh<'a> {
    pub fn new(mesh: &'a Mesh) -> Self {
        Self {
            mesh,
            neighbours: surface_neighbours(mesh),
        }
    }
}

/// At each welded mesh vertex, the vertices it is joined to: its mesh edges, then the corners
/// of triangles of other components that cross one of its triangles.
pub(super) fn surface_neighbours(mesh: &Mesh) -> Vec<Vec<u32>> {
    let points = mesh.welded_positions();
    let triangles = mesh.welded_triangles();
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); points.len()];
    for &[a, b, c] in triangles {
        for (x, y) in [(a, b), (b, c), (c, a)] {
            if (x as usize) < points.len() && (y as usize) < points.len() {
                neighbours[x as usize].push(y);
                neighbours[y as usize].push(x);
            }
        }
    }
    for (s, t) in crossing_triangles(points, triangles, &neighbours) {
        for &x in &triangles[s] {
            for &y in &triangles[t] {
                neighbours[x as usize].push(y);
                neighbours[y as usize].push(x);
            }
        }
    }
    neighbours
}

/// Pairs of triangles of different connected components (by `edges`) whose surfaces cross, in
/// a deterministic order; none when the mesh is one component.
fn crossing_triangles(
    points: &[DVec3],
    triangles: &[[u32; 3]],
    edges: &[Vec<u32>],
) -> Vec<(usize, usize)> {
    let component = components(edges);
    let valid = |t: &[u32; 3]| t.iter().all(|&v| (v as usize) < points.len());
    let first = triangles
        .iter()
        .find(|t| valid(t))
        .map(|t| component[t[0] as usize]);
    let several = triangles
        .iter()
        .filter(|t| valid(t))
        .any(|t| Some(component[t[0] as usize]) != first);
    if !several {
        return Vec::new();
    }
    let corners = |t: &[u32; 3]| t.map(|v| points[v as usize]);
    let bounds = |t: &[u32; 3]| {
        let [a, b, c] = corners(t);
        (a.min(b).min(c), a.max(b).max(c))
    };
    // Cells about twice the mean edge, grown until the triangles' boxes cover few enough.
    let mean_edge = {
        let (sum, n) = triangles
            .iter()
            .filter(|t| valid(t))
            .fold((0.0, 0), |(s, n), t| {
                let [a, b, c] = corners(t);
                (s + a.distance(b) + b.distance(c) + c.distance(a), n + 3)
            });
        sum / f64::from(n.max(1))
    };
    let mut cell = (2.0 * mean_edge).max(f64::MIN_POSITIVE);
    let span = |lo: DVec3, hi: DVec3, cell: f64| {
        let (l, h) = ((lo / cell).floor(), (hi / cell).floor());
        (l, h, ((h - l) + DVec3::ONE).element_product())
    };
    let budget = (CELLS_PER_TRIANGLE * triangles.len()) as f64;
    while triangles
        .iter()
        .filter(|t| valid(t))
        .map(|t| {
            let (lo, hi) = bounds(t);
            span(lo, hi, cell).2
        })
        .sum::<f64>()
        > budget
    {
        cell *= 2.0;
    }
    let mut in_cell: HashMap<IVec3, Vec<usize>> = HashMap::new();
    for (i, t) in triangles.iter().enumerate().filter(|(_, t)| valid(t)) {
        let (lo, hi) = bounds(t);
        let (l, h, _) = span(lo, hi, cell);
        let (l, h) = (l.as_ivec3(), h.as_ivec3());
        for z in l.z..=h.z {
            for y in l.y..=h.y {
                for x in l.x..=h.x {
                    in_cell.entry(IVec3::new(x, y, z)).or_default().push(i);
                }
            }
        }
    }
    let mut cells: Vec<(&IVec3, &Vec<usize>)> = in_cell.iter().collect();
    cells.sort_unstable_by_key(|(key, _)| key.to_array());
    let mut pairs = Vec::new();
    let mut tests = 0usize;
    'cells: for (_, members) in cells {
        for (k, &s) in members.iter().enumerate() {
            for &t in &members[k + 1..] {
                let (ts, tt) = (&triangles[s], &triangles[t]);
                if component[ts[0] as usize] == component[tt[0] as usize] {
                    continue;
                }
                tests += 1;
                if tests > MAX_PAIR_TESTS {
                    break 'cells;
                }
                if cross(corners(ts), corners(tt)) {
                    pairs.push((s.min(t), s.max(t)));
                }
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// Whether two triangles' surfaces cross: an edge of one passes through the other (coplanar
/// overlaps, which no edge crosses, are not counted).
fn cross(s: [DVec3; 3], t: [DVec3; 3]) -> bool {
    let edge_through = |p: [DVec3; 3], q: [DVec3; 3]| {
        (0..3).any(|i| {
            let (a, b) = (p[i], p[(i + 1) % 3]);
            ray_triangle(a, b - a, q[0], q[1], q[2]).is_some_and(|u| u <= 1.0)
        })
    };
    edge_through(s, t) || edge_through(t, s)
}

/// The connected component (a representative vertex) of each vertex by `edges`.
fn components(edges: &[Vec<u32>]) -> Vec<u32> {
    let mut component = vec![u32::MAX; edges.len()];
    let mut stack = Vec::new();
    for start in 0..edges.len() {
        if component[start] != u32::MAX {
            continue;
        }
        component[start] = start as u32;
        stack.push(start);
        while let Some(v) = stack.pop() {
            for &n in &edges[v] {
                if component[n as usize] == u32::MAX {
                    component[n as usize] = start as u32;
                    stack.push(n as usize);
                }
            }
        }
    }
    component
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An axis-aligned box's 12 triangles, outward, offset by `at` and indexed from `base`.
    fn cube(at: DVec3, size: f64, base: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let p = (0..8)
            .map(|i| {
                at + size
                    * DVec3::new(
                        f64::from(i & 1),
                        f64::from((i >> 1) & 1),
                        f64::from((i >> 2) & 1),
                    )
            })
            .collect();
        let t = crate::cage::shapes::BOX_FACES
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .map(|t| t.map(|v| v as u32 + base))
            .collect();
        (p, t)
    }

    fn two_cubes(offset: DVec3) -> Mesh {
        let (mut p, mut t) = cube(DVec3::ZERO, 1.0, 0);
        let (p2, t2) = cube(offset, 1.0, 8);
        p.extend(p2);
        t.extend(t2);
        Mesh::new(p, t, None, None).unwrap()
    }

    fn joined(mesh: &Mesh) -> bool {
        components(&surface_neighbours(mesh))
            .iter()
            .all(|&c| c == 0)
    }

    #[test]
    fn components_that_pass_through_each_other_are_one_piece() {
        assert!(joined(&two_cubes(DVec3::new(0.5, 0.3, 0.2))));
        // Apart, or only close (a gap of a hundredth): two pieces.
        assert!(!joined(&two_cubes(DVec3::new(2.0, 0.0, 0.0))));
        assert!(!joined(&two_cubes(DVec3::new(1.01, 0.0, 0.0))));
    }

    #[test]
    fn a_component_inside_another_without_crossing_stays_apart() {
        let (mut p, mut t) = cube(DVec3::ZERO, 1.0, 0);
        let (p2, t2) = cube(DVec3::splat(0.25), 0.5, 8);
        p.extend(p2);
        t.extend(t2);
        assert!(!joined(&Mesh::new(p, t, None, None).unwrap()));
    }
}
