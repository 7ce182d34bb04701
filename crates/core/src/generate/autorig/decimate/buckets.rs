//! The complex's triangles by the blocks of grid cells their bounding boxes overlap, so that
//! a collapse's new triangles are tested against the triangles near them instead of every
//! triangle (`meets_other_edges` scanned them all: a fifth of the bunny's auto rig).
//!
//! The blocks hold the triangles as they were when they were last sorted in, dead ones too (an
//! undo revives them). Triangles appended since, and triangles whose corners a collapse moved
//! since, are listed apart and always returned; they are sorted in again once they make a
//! quarter of the rest. A triangle is returned where any of its shapes since it was sorted in
//! overlaps the box asked about, so the caller's exact test sees every triangle it would have
//! seen in a scan, and a few more.

use std::collections::HashMap;

use glam::I64Vec3;

use super::Triangle;

/// Side of a block, in grid cells.
const BLOCK: i64 = 4;

/// Sorted-in triangles below which the extra list is not sorted in again.
const LEAST_REBUILD: usize = 256;

pub(super) struct TriangleBuckets {
    /// Triangles `0..sorted` are in `blocks` with the shape they had then.
    sorted: usize,
    blocks: HashMap<[i64; 3], Vec<u32>>,
    /// Triangles below `sorted` whose corners moved since.
    moved: Vec<u32>,
    /// Per triangle, the last query that returned it (to return each once without a sort).
    seen: Vec<u32>,
    query: u32,
}

impl TriangleBuckets {
    pub(super) fn new() -> Self {
        Self {
            sorted: 0,
            blocks: HashMap::new(),
            moved: Vec::new(),
            seen: Vec::new(),
            query: 0,
        }
    }

    /// Sorts every triangle in again where those appended or moved since the last time make
    /// a quarter of the sorted ones, or where triangles were taken away below `sorted`.
    pub(super) fn refresh(&mut self, triangles: &[Triangle], position: &[I64Vec3]) {
        let extra = triangles.len().saturating_sub(self.sorted) + self.moved.len();
        let shrunk = triangles.len() < self.sorted;
        if !shrunk && extra <= (self.sorted / 4).max(LEAST_REBUILD) {
            return;
        }
        self.blocks.clear();
        self.moved.clear();
        for (t, triangle) in triangles.iter().enumerate() {
            let (lo, hi) = bounds(triangle.corners, position);
            for key in blocks_of(lo, hi) {
                self.blocks.entry(key).or_default().push(t as u32);
            }
        }
        self.sorted = triangles.len();
    }

    /// Triangle `t`'s corners moved.
    pub(super) fn moved(&mut self, t: usize) {
        if t < self.sorted {
            self.moved.push(t as u32);
        }
    }

    /// The triangles that may overlap the box `lo..=hi` (each once), of the `count` there
    /// are now.
    pub(super) fn near(&mut self, lo: I64Vec3, hi: I64Vec3, count: usize) -> Vec<usize> {
        self.seen.resize(count.max(self.seen.len()), 0);
        self.query = self.query.wrapping_add(1);
        if self.query == 0 {
            self.seen.fill(0);
            self.query = 1;
        }
        let mut near = Vec::new();
        let listed = blocks_of(lo, hi)
            .filter_map(|key| self.blocks.get(&key))
            .flatten()
            .chain(&self.moved);
        for &t in listed {
            if let Some(seen) = self
                .seen
                .get_mut(t as usize)
                .filter(|_| (t as usize) < count)
                && *seen != self.query
            {
                *seen = self.query;
                near.push(t as usize);
            }
        }
        near.extend(self.sorted.min(count)..count);
        near
    }
}

/// The bounding box of the triangle with these corners.
pub(super) fn bounds(corners: [u32; 3], position: &[I64Vec3]) -> (I64Vec3, I64Vec3) {
    let [a, b, c] = corners.map(|i| position[i as usize]);
    (a.min(b).min(c), a.max(b).max(c))
}

/// The blocks the box `lo..=hi` overlaps.
fn blocks_of(lo: I64Vec3, hi: I64Vec3) -> impl Iterator<Item = [i64; 3]> {
    let (lo, hi) = (
        lo.div_euclid(I64Vec3::splat(BLOCK)),
        hi.div_euclid(I64Vec3::splat(BLOCK)),
    );
    (lo.z..=hi.z)
        .flat_map(move |z| (lo.y..=hi.y).flat_map(move |y| (lo.x..=hi.x).map(move |x| [x, y, z])))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle(corners: [u32; 3]) -> Triangle {
        Triangle {
            corners,
            front: Some(0),
            back: None,
            alive: true,
        }
    }

    #[test]
    fn near_returns_every_triangle_whose_box_overlaps_through_moves_and_appends() {
        let position: Vec<I64Vec3> = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [40, 40, 40], [41, 40, 40]]
            .into_iter()
            .map(I64Vec3::from_array)
            .collect();
        let mut triangles = vec![triangle([0, 1, 2]), triangle([3, 4, 2])];
        let mut buckets = TriangleBuckets::new();
        let near = |b: &mut TriangleBuckets, (lo, hi): (I64Vec3, I64Vec3), count| {
            let mut n = b.near(lo, hi, count);
            n.sort_unstable();
            n
        };
        buckets.sorted = usize::MAX; // force a sort
        buckets.refresh(&triangles, &position);
        assert_eq!(buckets.sorted, 2);
        let far = (I64Vec3::splat(39), I64Vec3::splat(42));
        let near_origin = (I64Vec3::ZERO, I64Vec3::ONE);
        // The long triangle reaches both corners of the box; the small one only the origin.
        assert_eq!(near(&mut buckets, far, 2), vec![1]);
        assert_eq!(near(&mut buckets, near_origin, 2), vec![0, 1]);
        // Moved far away, the small one is still returned near the origin, and now far.
        triangles[0].corners = [3, 4, 4];
        buckets.moved(0);
        assert_eq!(near(&mut buckets, far, 2), vec![0, 1]);
        // Appended triangles are returned until sorted in.
        triangles.push(triangle([0, 1, 2]));
        assert_eq!(near(&mut buckets, far, 3), vec![0, 1, 2]);
        // Taken away again (a respan's undo), it is not returned.
        triangles.pop();
        assert_eq!(near(&mut buckets, far, 2), vec![0, 1]);
        // Sorted in again, each where it is now.
        buckets.sorted = usize::MAX;
        buckets.refresh(&triangles, &position);
        assert_eq!(near(&mut buckets, far, 2), vec![0, 1]);
        assert_eq!(near(&mut buckets, near_origin, 2), vec![1]);
    }
}
