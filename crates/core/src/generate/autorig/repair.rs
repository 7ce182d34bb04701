//! Makes every part, and every union of parts that meet at a grid vertex (the *Cages join
//! cages), a manifold solid: around each grid vertex, the cells of the set and the cells
//! outside it must each be face-connected within the 2×2×2 block (otherwise cells meet only
//! along an edge or at a corner and the surface is pinched there).
//!
//! Repairs change one cell at a time (an empty cell joins a part, or a cell moves to another
//! part of its block), each the change that leaves fewest pinches in the blocks around it;
//! where no change helps, the parts of the block are merged. Cells never become empty, so
//! every mesh vertex stays covered.

use std::collections::BTreeMap;

use glam::IVec3;

use crate::geometry::block_face_connected;

use super::parts::{Parts, compact, split_disconnected};
use super::voxels::Grid;

/// Rounds of repair before parts are merged wholesale.
const MAX_ROUNDS: usize = 64;

/// Repairs `parts` (see the module). Returns the number of merges it needed.
pub(super) fn make_manifold(grid: &Grid, parts: &mut Parts) -> usize {
    let mut merges = 0;
    for round in 0.. {
        split_disconnected(grid, parts);
        let pinched: Vec<IVec3> = grid_vertices(grid)
            .filter(|&v| pinches(grid, &parts.label, v) > 0)
            .collect();
        if pinched.is_empty() {
            return merges;
        }
        for v in pinched {
            if pinches(grid, &parts.label, v) == 0 {
                continue;
            }
            if round >= MAX_ROUNDS || !improve_block(grid, &mut parts.label, v) {
                merge_block(grid, parts, v);
                merges += 1;
            }
        }
        compact(parts);
    }
    merges
}

/// Every grid vertex, in a fixed order.
fn grid_vertices(grid: &Grid) -> impl Iterator<Item = IVec3> + '_ {
    let d = grid.dims;
    (0..=d.z)
        .flat_map(move |z| (0..=d.y).flat_map(move |y| (0..=d.x).map(move |x| IVec3::new(x, y, z))))
}

/// The cells of the block around grid vertex `v` (bit c = x + 2y + 4z), None outside the grid.
fn block(grid: &Grid, v: IVec3) -> [Option<usize>; 8] {
    std::array::from_fn(|c| {
        let c = c as i32;
        grid.index(v - IVec3::ONE + IVec3::new(c & 1, (c >> 1) & 1, c >> 2))
    })
}

/// How many sets (each part of the block and each union of them) are pinched at `v`.
fn pinches(grid: &Grid, label: &[Option<u32>], v: IVec3) -> usize {
    let cells = block(grid, v);
    let labels: [Option<u32>; 8] = cells.map(|c| c.and_then(|i| label[i]));
    pinches_of(&labels)
}

fn pinches_of(labels: &[Option<u32>; 8]) -> usize {
    let mut present: Vec<u32> = labels.iter().flatten().copied().collect();
    present.sort_unstable();
    present.dedup();
    if present.is_empty() {
        return 0;
    }
    let mut count = 0;
    for subset in 1u32..(1 << present.len()) {
        let mask: u8 = (0..8)
            .filter(|&c| {
                labels[c].is_some_and(|l| {
                    present
                        .iter()
                        .position(|&p| p == l)
                        .is_some_and(|k| subset & (1 << k) != 0)
                })
            })
            .fold(0, |m, c| m | (1 << c));
        if !(block_face_connected(mask) && block_face_connected(!mask)) {
            count += 1;
        }
    }
    count
}

/// Pinches in the blocks that hold cell `c`.
fn pinches_around(grid: &Grid, label: &[Option<u32>], c: IVec3) -> usize {
    (0..8)
        .map(|k| c + IVec3::new(k & 1, (k >> 1) & 1, k >> 2))
        .map(|v| pinches(grid, label, v))
        .sum()
}

/// Applies the single-cell change in the block around `v` that leaves the fewest pinches in
/// the blocks it touches, if that is fewer than now. Returns whether it changed anything.
fn improve_block(grid: &Grid, label: &mut [Option<u32>], v: IVec3) -> bool {
    let cells = block(grid, v);
    let mut present: Vec<u32> = cells.iter().flatten().filter_map(|&i| label[i]).collect();
    present.sort_unstable();
    present.dedup();
    let mut best: Option<(usize, usize, u32)> = None;
    for &i in cells.iter().flatten() {
        let c = grid.cell_of(i);
        let before = pinches_around(grid, label, c);
        let old = label[i];
        for &p in &present {
            if old == Some(p) {
                continue;
            }
            label[i] = Some(p);
            let after = pinches_around(grid, label, c);
            label[i] = old;
            let gain = before.saturating_sub(after);
            if after < before && best.is_none_or(|(g, _, _)| gain > g) {
                best = Some((gain, i, p));
            }
        }
    }
    match best {
        Some((_, i, p)) => {
            label[i] = Some(p);
            true
        }
        None => false,
    }
}

/// Merges every part of the block around `v` into the largest one (the lowest-numbered of
/// equals), and fills the block's empty cells with it when the block alone is still pinched.
/// The largest keeps its role: a body slab pinched against a leg's first segment stays body
/// (merged into the lower-numbered part, the leg, spot's middle slab at detail 4 with the
/// mirror became a thigh and cut its torso in two).
fn merge_block(grid: &Grid, parts: &mut Parts, v: IVec3) {
    let cells = block(grid, v);
    let merged: Vec<u32> = cells
        .iter()
        .flatten()
        .filter_map(|&i| parts.label[i])
        .collect();
    // Each merged part's cells, counted in one pass over the grid.
    let mut size: BTreeMap<u32, usize> = merged.iter().map(|&part| (part, 0)).collect();
    for l in parts.label.iter().flatten() {
        if let Some(count) = size.get_mut(l) {
            *count += 1;
        }
    }
    let Some(into) = size
        .iter()
        .max_by_key(|&(&part, &count)| (count, std::cmp::Reverse(part)))
        .map(|(&part, _)| part)
    else {
        return;
    };
    for l in parts.label.iter_mut().flatten() {
        if merged.contains(l) {
            *l = into;
        }
    }
    if pinches(grid, &parts.label, v) > 0 {
        for &i in cells.iter().flatten() {
            parts.label[i] = Some(into);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_pinched_along_an_edge_or_at_a_corner_are_found() {
        let none = [None; 8];
        assert_eq!(pinches_of(&none), 0);
        let mut edge = none;
        edge[0] = Some(0);
        edge[3] = Some(0); // cells 0 and 3 meet along an edge only
        assert_eq!(pinches_of(&edge), 1);
        let mut corner = none;
        corner[0] = Some(0);
        corner[7] = Some(1); // two parts meeting at a corner: their union is pinched
        assert_eq!(pinches_of(&corner), 1);
        let mut fine = none;
        fine[0] = Some(0);
        fine[1] = Some(1);
        assert_eq!(pinches_of(&fine), 0);
    }

    #[test]
    fn a_merge_keeps_the_largest_part_s_role() {
        // A limb's first segment (part 0, one cell) pinched at a corner against a body slab
        // (part 1, many cells): the merge keeps the slab, so the body is not cut in two by a
        // limb holding its middle (lowest-numbered first, spot at detail 4 with the mirror
        // lost its torso's middle to a thigh).
        use glam::DVec3;

        use super::super::parts::Role;

        let grid = Grid::around(DVec3::ZERO, DVec3::new(4.0, 4.0, 4.0), 6, None, &[], None);
        let v = grid.dims / 2;
        let corner = |c: i32| v - IVec3::ONE + IVec3::new(c & 1, (c >> 1) & 1, c >> 2);
        let mut label = vec![None; grid.len()];
        // The slab: the block's far corner and every cell beyond it.
        for (i, l) in label.iter_mut().enumerate() {
            if grid.cell_of(i).cmpge(corner(7)).all() {
                *l = Some(1);
            }
        }
        let limb_cell = grid.index(corner(0)).unwrap();
        label[limb_cell] = Some(0);
        let mut parts = Parts::of_roles(
            label,
            vec![
                Role::Limb {
                    limb: 0,
                    segment: 0,
                },
                Role::Body { body: 0, slab: 2 },
            ],
        );
        assert!(pinches(&grid, &parts.label, v) > 0);
        merge_block(&grid, &mut parts, v);
        assert_eq!(parts.label[limb_cell], Some(1));
        assert!(!parts.label.contains(&Some(0)));
    }
}
