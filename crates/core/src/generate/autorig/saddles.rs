//! A body with two summits of thickness joined through a narrower saddle (a cow's head on a
//! thick neck, which neither narrows the body across its longest axis nor stands above
//! shoulders) split between them, so that the smaller end becomes a body of its own (a head
//! with a control) and the saddle a limb between the two.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::union_find::find;
use super::voxels::{Grid, component_cells};

/// The most a saddle's depth may be, as a share of the lower summit's depth, for the body to
/// split there (spot's head: 4.0 cells over 6.0, 0.67; the beast's and the Ogre's heads, which
/// [`super::parts`] splits above the shoulders, 0.80 and 0.85; a torso's bumps more).
const SADDLE_SHARE: f64 = 0.7;

/// The least depth of the lower summit, as a share of its body's deepest cell: a head is
/// nearly as thick as the torso it sits on (spot's: 0.78), a lump of a scan is not.
const SUMMIT_SHARE: f64 = 0.5;

/// The fewest cells the lower summit's side holds above the saddle's depth.
const SUMMIT_CELLS: usize = 27;

/// Splits each body (face-connected `body` cells) not marked in `done` at its deepest saddle
/// (see the module): the cells of the lower summit's basin that touch the other basin leave
/// the body. Basins grow from each summit's cells above the saddle down through the body in
/// order of depth (a watershed). Returns which cells are in the smaller end of a body split so.
pub(super) fn split_at_saddles(
    grid: &Grid,
    depth: &[f64],
    body: &mut [bool],
    done: &[bool],
) -> Vec<bool> {
    let mut ends = vec![false; grid.len()];
    let members = component_cells(grid, |i| body[i]);
    for cells in members {
        if cells.iter().any(|&i| done.get(i).copied().unwrap_or(true)) {
            continue;
        }
        let Some(saddle) = deepest_saddle(grid, depth, &cells) else {
            continue;
        };
        let basin = watershed(grid, depth, &cells, &saddle.seeds);
        for &i in &cells {
            if basin[i] == Some(1) {
                if grid.face_neighbours(i).any(|n| basin[n] == Some(0)) {
                    body[i] = false;
                } else {
                    ends[i] = true;
                }
            }
        }
    }
    ends
}

/// Where a body's two summits meet: the cells of each side at or above the saddle's depth,
/// the deeper summit's side first.
struct Saddle {
    seeds: [Vec<usize>; 2],
}

/// The saddle of a body's merge tree (its cells joined in order of depth, deepest first) that
/// is lowest against the lower of the two summits it joins, where that share is at most
/// [`SADDLE_SHARE`], the lower summit is [`SUMMIT_SHARE`] of the body's depth and its side
/// holds [`SUMMIT_CELLS`].
fn deepest_saddle(grid: &Grid, depth: &[f64], cells: &[usize]) -> Option<Saddle> {
    let mut order = cells.to_vec();
    order.sort_by(|&a, &b| depth[b].total_cmp(&depth[a]).then(a.cmp(&b)));
    let deepest = order.first().map(|&i| depth[i])?;
    // Union-find over positions in `order`, each root with its summit's depth and its size.
    let mut position = vec![usize::MAX; grid.len()];
    let mut parent: Vec<usize> = Vec::with_capacity(order.len());
    let mut summit: Vec<f64> = Vec::with_capacity(order.len());
    let mut size: Vec<usize> = Vec::with_capacity(order.len());
    // The lowest share so far, and the two sides' cells at that merge.
    let mut best: Option<(f64, [Vec<usize>; 2])> = None;
    for (k, &i) in order.iter().enumerate() {
        position[i] = k;
        parent.push(k);
        summit.push(depth[i]);
        size.push(1);
        for n in grid.face_neighbours(i) {
            let m = position[n];
            if m == usize::MAX || m >= k {
                continue;
            }
            let (a, b) = (find(&mut parent, k), find(&mut parent, m));
            if a == b {
                continue;
            }
            let (high, low) = if summit[a] >= summit[b] {
                (a, b)
            } else {
                (b, a)
            };
            let level = depth[i];
            let share = level / summit[low].max(1e-12);
            if summit[low] >= SUMMIT_SHARE * deepest
                && size[low] >= SUMMIT_CELLS
                && share <= SADDLE_SHARE
                && best.as_ref().is_none_or(|(s, _)| share < *s)
            {
                let mut sides = [Vec::new(), Vec::new()];
                for (q, &c) in order.iter().enumerate().take(k) {
                    let r = find(&mut parent, q);
                    if r == high {
                        sides[0].push(c);
                    } else if r == low {
                        sides[1].push(c);
                    }
                }
                best = Some((share, sides));
            }
            parent[low] = high;
            size[high] += size[low];
        }
    }
    best.map(|(_, seeds)| Saddle { seeds })
}

/// Each body cell's basin (0 or 1): the seeds', grown through the body's `cells` deepest
/// first, a cell taking the basin of the neighbour it is reached from.
fn watershed(
    grid: &Grid,
    depth: &[f64],
    cells: &[usize],
    seeds: &[Vec<usize>; 2],
) -> Vec<Option<u8>> {
    let mut member = vec![false; grid.len()];
    for &i in cells {
        member[i] = true;
    }
    let mut basin: Vec<Option<u8>> = vec![None; grid.len()];
    let mut heap = BinaryHeap::new();
    for (b, side) in seeds.iter().enumerate() {
        for &i in side {
            basin[i] = Some(b as u8);
        }
    }
    for side in seeds {
        for &i in side {
            for n in grid.face_neighbours(i) {
                if member[n] && basin[n].is_none() {
                    heap.push((depth[n].to_bits(), Reverse(n), basin[i]));
                }
            }
        }
    }
    while let Some((_, Reverse(i), from)) = heap.pop() {
        if basin[i].is_some() {
            continue;
        }
        basin[i] = from;
        for n in grid.face_neighbours(i) {
            if member[n] && basin[n].is_none() {
                heap.push((depth[n].to_bits(), Reverse(n), from));
            }
        }
    }
    basin
}
