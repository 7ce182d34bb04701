//! A joint's region: the mesh triangles with a corner in a row its ring moves, the loops of
//! their border, and the volume they enclose closed over those loops.

use glam::{DVec3, Vec3};

/// The triangles of a region and what closes them.
pub(super) struct Region {
    /// Welded triangles with a corner in a row the ring moves.
    pub(super) triangles: Vec<[u32; 3]>,
    /// The loops of their border: each loop's vertices, and its edges as the triangles run
    /// them.
    pub(super) loops: Vec<(Vec<u32>, Vec<[u32; 2]>)>,
    /// Every row the triangles use, sorted.
    pub(super) rows: Vec<u32>,
    /// Every edge of the triangles once, smaller end first.
    pub(super) edges: Vec<[u32; 2]>,
}

/// The triangles around each mesh row (CSR), to gather a region from its rows.
pub(super) struct TrianglesOfRow {
    start: Vec<u32>,
    triangle: Vec<u32>,
}

impl TrianglesOfRow {
    /// The index of `triangles` (those with a corner beyond `row_count` left out).
    pub(super) fn new(triangles: &[[u32; 3]], row_count: usize) -> Self {
        let valid = |t: &[u32; 3]| t.iter().all(|&c| (c as usize) < row_count);
        let mut start = vec![0u32; row_count + 1];
        for t in triangles.iter().filter(|t| valid(t)) {
            for &c in t {
                start[c as usize + 1] += 1;
            }
        }
        for r in 0..row_count {
            start[r + 1] += start[r];
        }
        let mut next = start.clone();
        let mut triangle = vec![0u32; start[row_count] as usize];
        for (i, t) in triangles.iter().enumerate().filter(|(_, t)| valid(t)) {
            for &c in t {
                triangle[next[c as usize] as usize] = i as u32;
                next[c as usize] += 1;
            }
        }
        Self { start, triangle }
    }

    fn of(&self, row: u32) -> &[u32] {
        let (a, b) = (self.start[row as usize], self.start[row as usize + 1]);
        &self.triangle[a as usize..b as usize]
    }
}

impl Region {
    /// The triangles with a corner in `touched` (rows below the mesh's row count), their
    /// border loops and rows; `taken` marks triangles (all false on entry and on return).
    pub(super) fn of_rows(
        touched: &[u32],
        triangles: &[[u32; 3]],
        around: &TrianglesOfRow,
        taken: &mut [bool],
    ) -> Self {
        let mut picked: Vec<u32> = Vec::new();
        for &r in touched
            .iter()
            .filter(|&&r| (r as usize) + 1 < around.start.len())
        {
            for &t in around.of(r) {
                if !std::mem::replace(&mut taken[t as usize], true) {
                    picked.push(t);
                }
            }
        }
        picked.sort_unstable();
        for &t in &picked {
            taken[t as usize] = false;
        }
        let triangles: Vec<[u32; 3]> = picked.iter().map(|&t| triangles[t as usize]).collect();
        // Each edge once, undirected, with +1 for each triangle running it from its smaller
        // end and −1 the other way: where the sum is not 0 it is on the border.
        let mut edges: Vec<(u64, i32)> = triangles
            .iter()
            .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
            .map(|[a, b]| {
                let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
                (key, if a < b { 1 } else { -1 })
            })
            .collect();
        edges.sort_unstable_by_key(|&(key, _)| key);
        let mut border = Vec::new();
        let mut every = Vec::new();
        for run in edges.chunk_by(|x, y| x.0 == y.0) {
            let sum: i32 = run.iter().map(|&(_, d)| d).sum();
            let (low, high) = ((run[0].0 >> 32) as u32, run[0].0 as u32);
            every.push([low, high]);
            match sum.signum() {
                1 => border.push([low, high]),
                -1 => border.push([high, low]),
                _ => {}
            }
        }
        let mut rows: Vec<u32> = triangles.iter().flatten().copied().collect();
        rows.sort_unstable();
        rows.dedup();
        Self {
            loops: border_loops(&border, &rows),
            triangles,
            rows,
            edges: every,
        }
    }
}

/// The most any of `edges` is longer in `mesh` than its length in `lengths` (edges whose
/// length there is 0 left out); 1 when none is longer.
pub(super) fn most_stretch(mesh: &[Vec3], edges: &[[u32; 2]], lengths: &[f32]) -> f32 {
    edges
        .iter()
        .zip(lengths)
        .filter(|&(_, &l)| l > 0.0)
        .map(|(&[a, b], &l)| mesh[a as usize].distance(mesh[b as usize]) / l)
        .fold(1.0, f32::max)
}

/// The lengths of `edges` in `mesh`.
pub(super) fn edge_lengths(mesh: &[Vec3], edges: &[[u32; 2]]) -> Vec<f32> {
    edges
        .iter()
        .map(|&[a, b]| mesh[a as usize].distance(mesh[b as usize]))
        .collect()
}

/// Border edges grouped by connected loop (union-find over their vertices), each with its
/// vertices.
fn border_loops(border: &[[u32; 2]], rows: &[u32]) -> Vec<(Vec<u32>, Vec<[u32; 2]>)> {
    let index = |v: u32| rows.binary_search(&v).unwrap_or(0);
    let mut root: Vec<usize> = (0..rows.len()).collect();
    fn find(root: &mut [usize], mut i: usize) -> usize {
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    for &[a, b] in border {
        let (ra, rb) = (find(&mut root, index(a)), find(&mut root, index(b)));
        root[ra] = rb;
    }
    let mut by_root: std::collections::BTreeMap<usize, (Vec<u32>, Vec<[u32; 2]>)> =
        std::collections::BTreeMap::new();
    for &[a, b] in border {
        let r = find(&mut root, index(a));
        let entry = by_root.entry(r).or_default();
        entry.0.extend([a, b]);
        entry.1.push([a, b]);
    }
    by_root
        .into_values()
        .map(|(mut vertices, edges)| {
            vertices.sort_unstable();
            vertices.dedup();
            (vertices, edges)
        })
        .collect()
}

/// The volume enclosed by `triangles` closed by a fan from each border loop's centroid: the
/// sum of signed tetrahedra from one apex, which does not matter for a closed surface.
pub(super) fn region_volume(
    mesh: &[Vec3],
    triangles: &[[u32; 3]],
    loops: &[(Vec<u32>, Vec<[u32; 2]>)],
) -> f64 {
    let at = |v: u32| mesh[v as usize].as_dvec3();
    let Some(&[first, ..]) = triangles.first() else {
        return 0.0;
    };
    let apex = at(first);
    let tetra = |a: DVec3, b: DVec3, c: DVec3| (a - apex).dot((b - apex).cross(c - apex)) / 6.0;
    let mut volume: f64 = triangles
        .iter()
        .map(|&[a, b, c]| tetra(at(a), at(b), at(c)))
        .sum();
    for (vertices, edges) in loops {
        let centre = vertices.iter().map(|&v| at(v)).sum::<DVec3>() / vertices.len() as f64;
        // The cap runs each border edge backwards to close the surface.
        volume += edges
            .iter()
            .map(|&[a, b]| tetra(at(b), at(a), centre))
            .sum::<f64>();
    }
    volume
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube's 12 outward triangles (corner i at (i & 1, i >> 1 & 1, i >> 2)).
    fn cube() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let corners = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, (i >> 1 & 1) as f32, (i >> 2) as f32))
            .collect();
        let mut triangles = Vec::new();
        for [a, b, c, d] in crate::cage::shapes::BOX_FACES {
            let [a, b, c, d] = [a, b, c, d].map(|k| k as u32);
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
        (corners, triangles)
    }

    #[test]
    fn an_open_region_closed_over_its_border_encloses_what_the_whole_did() {
        let (corners, mut triangles) = cube();
        // The top face (z = 1: corners 4..8) open: its border is one loop of four edges.
        triangles.retain(|t| !t.iter().all(|&c| c >= 4));
        let around = TrianglesOfRow::new(&triangles, corners.len());
        let mut taken = vec![false; triangles.len()];
        let all: Vec<u32> = (0..8).collect();
        let region = Region::of_rows(&all, &triangles, &around, &mut taken);
        assert_eq!(region.triangles.len(), 10);
        assert_eq!(region.loops.len(), 1);
        assert_eq!(region.loops[0].1.len(), 4);
        assert!(taken.iter().all(|&t| !t), "the marks are cleared");
        let volume = region_volume(&corners, &region.triangles, &region.loops);
        assert!((volume - 1.0).abs() < 1e-6, "{volume}");
        // Moved rigidly, the same.
        let moved: Vec<Vec3> = corners
            .iter()
            .map(|&p| p + Vec3::new(3.0, -2.0, 5.0))
            .collect();
        let volume = region_volume(&moved, &region.triangles, &region.loops);
        assert!((volume - 1.0).abs() < 1e-5, "{volume}");
        // The rows of the bottom corners only: the triangles touching them, still closed.
        let bottom: Vec<u32> = (0..4).collect();
        let region = Region::of_rows(&bottom, &triangles, &around, &mut taken);
        let volume = region_volume(&corners, &region.triangles, &region.loops);
        assert!((volume - 1.0).abs() < 1e-6, "{volume}");
    }
}
