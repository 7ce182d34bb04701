//! Small bodies inside a limb given back to it. The opening that finds bodies
//! (`parts::body_cells`) keeps any region thick enough, so a knobbly knee or a bulging
//! shoulder can be a body of its own (the beast's knees and right shoulder: 33 cells each,
//! against its trunk's 780). Such a limb then reaches from the trunk only to that body, and
//! the rest of it grows from the small body instead: the leg is two limbs, and a pair of legs
//! is not counted as a pair. A small body is given back when it is a joint of a limb, not an
//! end: seen from the trunk, what lies beyond it holds more cells than it does (a shin and a
//! foot past a knee, an arm past a shoulder), where a head holds more than its ears or horns.

use std::collections::BTreeSet;

use super::voxels::{Grid, components};

/// The largest body that can be a limb's joint, as a share of the trunk's cells (the beast's
/// knees: 0.04; the smallest trunk-grown head met, the horse's: 0.05, kept as the end it is).
const JOINT_BODY_SHARE: f64 = 0.1;

/// Turns each small body that is a limb's joint (see the module) into limb cells: `body`
/// loses its cells. Bodies holding a cell of `heads` and the trunk (the largest other body)
/// stay. Returns how many bodies were given back.
pub(super) fn fold_joint_bodies(
    grid: &Grid,
    occupied: &[bool],
    body: &mut [bool],
    heads: &[bool],
) -> usize {
    let (body_of, bodies) = components(grid, |i| body[i]);
    let (limb_of, limbs) = components(grid, |i| occupied[i] && !body[i]);
    // Nodes: bodies 0..bodies, then limb regions; a node's size in cells.
    let mut size = vec![0usize; bodies + limbs];
    let mut is_head = vec![false; bodies];
    let mut touching: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); bodies + limbs];
    for i in 0..grid.len() {
        if let Some(b) = body_of[i] {
            size[b] += 1;
            is_head[b] |= heads.get(i).copied().unwrap_or(false);
            for n in grid.face_neighbours(i) {
                if let Some(l) = limb_of[n] {
                    touching[b].insert(bodies + l);
                    touching[bodies + l].insert(b);
                }
            }
        } else if let Some(l) = limb_of[i] {
            size[bodies + l] += 1;
        }
    }
    let Some(trunk) = (0..bodies)
        .filter(|&b| !is_head[b])
        .max_by_key(|&b| size[b])
    else {
        return 0;
    };
    let joints: Vec<usize> = (0..bodies)
        .filter(|&b| b != trunk && !is_head[b])
        .filter(|&b| (size[b] as f64) < JOINT_BODY_SHARE * size[trunk] as f64)
        .filter(|&b| {
            let from_trunk = reached(&touching, trunk, b);
            let beyond = reached(&touching, b, usize::MAX);
            let toward_trunk = touching[b].iter().any(|n| from_trunk[*n]);
            let cells_beyond: usize = (0..size.len())
                .filter(|&n| n != b && beyond[n] && !from_trunk[n])
                .map(|n| size[n])
                .sum();
            toward_trunk && cells_beyond > size[b]
        })
        .collect();
    for (i, b) in body_of.iter().enumerate() {
        if b.is_some_and(|b| joints.contains(&b)) {
            body[i] = false;
        }
    }
    joints.len()
}

/// The nodes connected to `start` without passing through `without`.
fn reached(touching: &[BTreeSet<usize>], start: usize, without: usize) -> Vec<bool> {
    let mut seen = vec![false; touching.len()];
    let mut stack = vec![start];
    seen[start] = true;
    while let Some(n) = stack.pop() {
        for &m in &touching[n] {
            if m != without && !seen[m] {
                seen[m] = true;
                stack.push(m);
            }
        }
    }
    seen
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    /// A row of cells one thick along x, 40 long: per span of x (in cells from the row's
    /// start), whether its cells are body cells; cells past the spans are empty. Returns the
    /// grid, the occupied cells, the body cells and the cell index of each x.
    fn row(spans: &[(std::ops::Range<i32>, bool)]) -> (Grid, Vec<bool>, Vec<bool>, Vec<usize>) {
        let grid = Grid::around(DVec3::ZERO, DVec3::new(40.0, 1.0, 1.0), 40, None, &[], None);
        let at: Vec<usize> = (0..40)
            .filter_map(|x| grid.index(grid.cell_at(DVec3::new(f64::from(x) + 0.5, 0.5, 0.5))))
            .collect();
        assert_eq!(at.len(), 40);
        let (mut occupied, mut body) = (vec![false; grid.len()], vec![false; grid.len()]);
        for (span, is_body) in spans {
            for x in span.clone() {
                occupied[at[x as usize]] = true;
                body[at[x as usize]] = *is_body;
            }
        }
        (grid, occupied, body, at)
    }

    #[test]
    fn a_knee_with_a_shin_beyond_it_rejoins_its_leg() {
        // Trunk (20 cells), thigh, knee (1 cell: a twentieth of the trunk), shin of 7.
        let (grid, occupied, mut body, at) = row(&[
            (0..20, true),
            (20..24, false),
            (24..25, true),
            (25..32, false),
        ]);
        let heads = vec![false; grid.len()];
        assert_eq!(fold_joint_bodies(&grid, &occupied, &mut body, &heads), 1);
        assert!(!body[at[24]]);
        assert!((0..20).all(|x| body[at[x]]), "the trunk stays");
    }

    #[test]
    fn a_head_with_only_an_ear_beyond_it_stays_a_body() {
        // Trunk, neck, a head of 2 cells and an ear of 1 past it: what lies beyond the head
        // is smaller than the head.
        let (grid, occupied, mut body, at) = row(&[
            (0..20, true),
            (20..24, false),
            (24..26, true),
            (26..27, false),
        ]);
        let before = body.clone();
        assert_eq!(
            fold_joint_bodies(&grid, &occupied, &mut body, &vec![false; grid.len()]),
            0
        );
        assert_eq!(body, before);
        assert!(body[at[24]] && body[at[25]]);
        // The knee's layout, but the small body is a head split off (a head on a long horn).
        let (grid, occupied, mut body, at_knee) = row(&[
            (0..20, true),
            (20..24, false),
            (24..25, true),
            (25..32, false),
        ]);
        let mut heads = vec![false; grid.len()];
        heads[at_knee[24]] = true;
        assert_eq!(fold_joint_bodies(&grid, &occupied, &mut body, &heads), 0);
        assert!(body[at_knee[24]]);
    }

    #[test]
    fn a_body_over_a_tenth_of_the_trunk_stays_though_a_limb_lies_beyond_it() {
        // A 3-cell body against a trunk of 20 (0.15), with 10 limb cells beyond it.
        let (grid, occupied, mut body, at) = row(&[
            (0..20, true),
            (20..23, false),
            (23..26, true),
            (26..36, false),
        ]);
        assert_eq!(
            fold_joint_bodies(&grid, &occupied, &mut body, &vec![false; grid.len()]),
            0
        );
        assert!((23..26).all(|x| body[at[x]]));
    }
}
