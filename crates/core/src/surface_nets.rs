//! A closed triangle mesh of the zero level set of a scalar field (negative inside), by naive
//! surface nets: one vertex per grid cell the surface crosses, at the mean of the crossings on
//! the cell's edges, and one quad per grid edge the surface crosses, joining the four cells
//! around that edge. The demo meshes that are not simple parametric shapes (the `creature`)
//! come from here.

use glam::DVec3;
use rayon::prelude::*;

/// The offsets of a cell's 12 edges: (corner a, corner b), corners numbered x + 2y + 4z.
const CELL_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (2, 3),
    (4, 5),
    (6, 7),
    (0, 2),
    (1, 3),
    (4, 6),
    (5, 7),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// The triangles of the surface `field(p) = 0` inside the box `min..max`, sampled every
/// `spacing` (positions, triangles counter-clockwise seen from outside, where the field is
/// positive). The field must be positive on the box's boundary so the surface is closed.
/// Returns empty lists for a non-positive spacing or one that would need more than 2^28 samples.
pub fn surface_nets(
    field: impl Fn(DVec3) -> f64 + Sync,
    min: DVec3,
    max: DVec3,
    spacing: f64,
) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let usable = spacing > 0.0 && (max - min).cmpgt(DVec3::ZERO).all();
    if !usable {
        return (Vec::new(), Vec::new());
    }
    let cells = ((max - min) / spacing).ceil();
    if cells.x * cells.y * cells.z > f64::from(1u32 << 28) {
        return (Vec::new(), Vec::new());
    }
    let n = [cells.x as usize, cells.y as usize, cells.z as usize];
    let points = [n[0] + 1, n[1] + 1, n[2] + 1];
    let point_at =
        |i: usize, j: usize, k: usize| min + DVec3::new(i as f64, j as f64, k as f64) * spacing;
    let sample = |i: usize, j: usize, k: usize| i + points[0] * (j + points[1] * k);
    // The field at every grid point, one z slab per task.
    let values: Vec<f64> = (0..points[2])
        .into_par_iter()
        .flat_map_iter(|k| {
            let field = &field;
            (0..points[1]).flat_map(move |j| (0..points[0]).map(move |i| field(point_at(i, j, k))))
        })
        .collect();
    let inside = |s: usize| values.get(s).is_some_and(|v| *v < 0.0);
    // One vertex per crossed cell.
    let cell = |i: usize, j: usize, k: usize| i + n[0] * (j + n[1] * k);
    let mut vertex_of_cell = vec![u32::MAX; n[0] * n[1] * n[2]];
    let mut positions = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let corner = |c: usize| (i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                let corner_inside = |c: usize| {
                    let (a, b, d) = corner(c);
                    inside(sample(a, b, d))
                };
                let first = corner_inside(0);
                if (1..8).all(|c| corner_inside(c) == first) {
                    continue;
                }
                let mut sum = DVec3::ZERO;
                let mut count = 0.0;
                for (a, b) in CELL_EDGES {
                    if corner_inside(a) == corner_inside(b) {
                        continue;
                    }
                    let (pa, pb) = (corner(a), corner(b));
                    let (va, vb) = (
                        values[sample(pa.0, pa.1, pa.2)],
                        values[sample(pb.0, pb.1, pb.2)],
                    );
                    let t = (va / (va - vb)).clamp(0.0, 1.0);
                    sum += point_at(pa.0, pa.1, pa.2).lerp(point_at(pb.0, pb.1, pb.2), t);
                    count += 1.0;
                }
                vertex_of_cell[cell(i, j, k)] = positions.len() as u32;
                positions.push(sum / count);
            }
        }
    }
    // One quad per crossed grid edge that has four cells around it.
    let mut triangles = Vec::new();
    let mut quad = |corners: [u32; 4], outward: bool| {
        if corners.contains(&u32::MAX) {
            return;
        }
        let [a, b, c, d] = if outward {
            corners
        } else {
            [corners[3], corners[2], corners[1], corners[0]]
        };
        // Split along the shorter diagonal.
        let p = |v: u32| positions[v as usize];
        if p(a).distance_squared(p(c)) <= p(b).distance_squared(p(d)) {
            triangles.extend([[a, b, c], [a, c, d]]);
        } else {
            triangles.extend([[a, b, d], [b, c, d]]);
        }
    };
    for k in 0..points[2] {
        for j in 0..points[1] {
            for i in 0..points[0] {
                let g = [i, j, k];
                let here = inside(sample(i, j, k));
                for a in 0..3 {
                    let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                    // The edge must lie inside the grid with a cell on each side in b and c.
                    if g[a] >= n[a] || g[b] == 0 || g[b] >= n[b] || g[c] == 0 || g[c] >= n[c] {
                        continue;
                    }
                    let mut next = g;
                    next[a] += 1;
                    if here == inside(sample(next[0], next[1], next[2])) {
                        continue;
                    }
                    // The four cells around the edge, counter-clockwise about +a (a = b × c).
                    let around = |db: usize, dc: usize| {
                        let mut m = g;
                        m[b] -= db;
                        m[c] -= dc;
                        vertex_of_cell[cell(m[0], m[1], m[2])]
                    };
                    // Inside at the edge's lower end: the surface faces +a.
                    quad(
                        [around(1, 1), around(0, 1), around(0, 0), around(1, 0)],
                        here,
                    );
                }
            }
        }
    }
    (positions, triangles)
}
