//! A limb's twin that the cut left inside another limb. On a mesh symmetric across a
//! left-right plane, a grid not mirrored across it can part one limb of a pair from what it
//! grows from and leave the other inside a larger limb: TOSCA's sitting Dobermann (`dog0`)
//! had its left ear on the head's thick core, a limb of its own, while its right ear grew
//! from the ring of cells around that core that runs from the snout over the skull, and
//! stayed in that ring's limb (the head), with no control. Where a limb's mirror image lies
//! almost wholly in one larger limb, those cells become the twin: a limb of their own, cut
//! into the segments of the limb they mirror.

use std::collections::{BTreeMap, BTreeSet};

use super::parts::{Parts, Role};
use super::voxels::{Grid, component_cells};

/// The least share of a limb's mirrored cells that must be solid: the grid's cells are not
/// mirror images, so some fall outside (3 of the Dobermann's ear's 10).
const SOLID_SHARE: f64 = 0.6;

/// The least share of a limb's solid mirrored cells that must be in the one limb that
/// swallowed the twin.
const INSIDE_SHARE: f64 = 0.8;

/// How many times the twin's cells the limb that swallowed it must hold: the Dobermann's
/// head ring holds 89 cells, the ear 10. A limb about the twin's size is the twin itself,
/// cut a little differently.
const SWALLOWED_BY: usize = 3;

/// The role of the part labelled `label`.
fn role_of(parts: &Parts, label: Option<u32>) -> Option<Role> {
    parts.roles.get(label? as usize).copied()
}

/// Carves the twin of each limb on one side of the plane `plane` across `axis` (see the
/// module) out of the limb that swallowed it. Returns how many twins were carved.
pub(super) fn carve_missing_twins(
    grid: &Grid,
    parts: &mut Parts,
    axis: usize,
    plane: f64,
) -> usize {
    let limb_of = |label: Option<u32>, parts: &Parts| match role_of(parts, label) {
        Some(Role::Limb { limb, .. }) => Some(limb),
        _ => None,
    };
    let paired: BTreeSet<usize> = parts.pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
    let mut cells_of: BTreeMap<usize, Vec<(usize, usize)>> = BTreeMap::new();
    for (i, label) in parts.label.iter().enumerate() {
        if let Some(Role::Limb { limb, segment }) = role_of(parts, *label) {
            cells_of.entry(limb).or_default().push((i, segment));
        }
    }
    let plane_units = grid.units_along(axis, plane);
    let mut carved = 0;
    let mut touched: BTreeSet<usize> = BTreeSet::new();
    for (&limb, cells) in &cells_of {
        if paired.contains(&limb) || touched.contains(&limb) {
            continue;
        }
        // Wholly on one side: no cell holds the plane.
        let side = |i: usize| f64::from(grid.cell_of(i)[axis]) + 0.5 - plane_units;
        let first_side = cells.first().map_or(0.0, |&(i, _)| side(i).signum());
        if !cells.iter().all(|&(i, _)| side(i) * first_side >= 0.5) {
            continue;
        }
        // Each mirrored cell, with the lowest segment of the cells it mirrors.
        let mut mirrored: BTreeMap<usize, usize> = BTreeMap::new();
        let mut outside = 0usize;
        for &(i, segment) in cells {
            let mut p = grid.centre(grid.cell_of(i));
            p[axis] = 2.0 * plane - p[axis];
            // Not `cell_at`, which clamps a point beyond the grid into it.
            match grid.index(grid.units_of(p).floor().as_ivec3()) {
                Some(m) => {
                    let entry = mirrored.entry(m).or_insert(segment);
                    *entry = (*entry).min(segment);
                }
                None => outside += 1,
            }
        }
        let total = mirrored.len() + outside;
        let mut owners: BTreeMap<usize, usize> = BTreeMap::new();
        let mut solid = 0usize;
        for &m in mirrored.keys() {
            solid += usize::from(parts.label[m].is_some());
            if let Some(owner) = limb_of(parts.label[m], parts) {
                *owners.entry(owner).or_insert(0) += 1;
            }
        }
        let Some((&host, &inside)) = owners
            .iter()
            .max_by_key(|(l, n)| (**n, std::cmp::Reverse(**l)))
        else {
            continue;
        };
        if host == limb
            || paired.contains(&host)
            || touched.contains(&host)
            || (solid as f64) < SOLID_SHARE * total as f64
            || (inside as f64) < INSIDE_SHARE * solid as f64
        {
            continue;
        }
        let host_cells = cells_of.get(&host).map_or(0, Vec::len);
        if host_cells < SWALLOWED_BY * inside {
            continue;
        }
        let mut twin: BTreeMap<usize, usize> = mirrored
            .into_iter()
            .filter(|&(m, _)| limb_of(parts.label[m], parts) == Some(host))
            .collect();
        // The twin in one piece.
        if component_cells(grid, |i| twin.contains_key(&i)).len() != 1 {
            continue;
        }
        // The host left in one piece: the rest of the twin (cells whose mirror images fell
        // in empty cells) cut off from it joins the twin.
        let host_rest = |i: usize, twin: &BTreeMap<usize, usize>| {
            !twin.contains_key(&i) && limb_of(parts.label[i], parts) == Some(host)
        };
        let mut pieces = component_cells(grid, |i| host_rest(i, &twin));
        pieces.sort_by_key(|p| std::cmp::Reverse(p.len()));
        let cut_off: usize = pieces.iter().skip(1).map(Vec::len).sum();
        if cut_off > twin.len() {
            continue;
        }
        for piece in pieces.iter().skip(1) {
            let segment = piece
                .iter()
                .flat_map(|&i| grid.face_neighbours(i))
                .filter_map(|n| twin.get(&n).copied())
                .max();
            let Some(segment) = segment else {
                continue;
            };
            for &i in piece {
                twin.insert(i, segment);
            }
        }
        if component_cells(grid, |i| host_rest(i, &twin)).len() != 1 {
            continue;
        }
        // ... and still growing from what it grew from (a body, or its parent limb): a leg
        // holding both feet where they touch at the plane is no host to the other leg, whose
        // carving would leave the feet hanging from it.
        let parent = parts.parent_limb.get(&host).copied();
        let still_rooted = (0..grid.len()).filter(|&i| host_rest(i, &twin)).any(|i| {
            grid.face_neighbours(i)
                .any(|n| match role_of(parts, parts.label[n]) {
                    Some(Role::Body { .. }) => true,
                    Some(Role::Limb { limb, .. }) => Some(limb) == parent,
                    None => false,
                })
        });
        if !still_rooted {
            continue;
        }
        let new_limb = parts.unused_limb();
        let mut part_of_segment: BTreeMap<usize, u32> = BTreeMap::new();
        for (&m, &segment) in &twin {
            let part = *part_of_segment.entry(segment).or_insert_with(|| {
                parts.roles.push(Role::Limb {
                    limb: new_limb,
                    segment,
                });
                (parts.roles.len() - 1) as u32
            });
            parts.label[m] = Some(part);
        }
        if let Some(&parent) = parts.parent_limb.get(&limb) {
            parts.parent_limb.insert(new_limb, parent);
        }
        touched.extend([limb, host]);
        carved += 1;
    }
    if carved > 0 {
        super::parts::compact(parts);
        super::parts::split_disconnected(grid, parts);
    }
    carved
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    /// A head (limb 0) on a body with two ears across the plane x = 5: the right one (x > 5)
    /// a limb of its own in two segments (limb 1), the left one inside the head's limb, or a
    /// third limb where `left_ear_apart`. The grid's cells do not mirror across the plane.
    fn head_with_ears(grid: &Grid, left_ear_apart: bool) -> Parts {
        let in_box = |p: DVec3, lo: DVec3, hi: DVec3| p.cmpge(lo).all() && p.cmple(hi).all();
        let label = (0..grid.len())
            .map(|i| {
                let p = grid.centre(grid.cell_of(i));
                let ear = |x0: f64, x1: f64| {
                    in_box(p, DVec3::new(x0, 2.0, 6.0), DVec3::new(x1, 4.0, 10.0))
                };
                match () {
                    _ if in_box(p, DVec3::new(1.0, 1.0, -0.5), DVec3::new(9.0, 5.0, 0.99)) => {
                        Some(4)
                    }
                    _ if in_box(p, DVec3::new(1.0, 1.0, 1.0), DVec3::new(9.0, 5.0, 6.0)) => Some(0),
                    _ if ear(6.0, 8.0) && p.z < 8.0 => Some(1),
                    _ if ear(6.0, 8.0) => Some(2),
                    _ if ear(2.0, 4.0) => Some(if left_ear_apart { 3 } else { 0 }),
                    _ => None,
                }
            })
            .collect();
        // Parts 0-3 as (limb, segment), part 4 the body.
        let roles = [(0, 0), (1, 0), (1, 1), (2, 0)]
            .map(|(limb, segment)| Role::Limb { limb, segment })
            .into_iter()
            .chain([Role::Body { body: 0, slab: 0 }])
            .collect();
        Parts::of_roles(label, roles)
    }

    fn grid() -> Grid {
        Grid::around(
            DVec3::ZERO,
            DVec3::new(10.0, 6.0, 11.0),
            11,
            None,
            &[],
            None,
        )
    }

    #[test]
    fn an_ear_left_inside_the_head_becomes_the_twin_of_the_other_ear() {
        let grid = grid();
        let mut parts = head_with_ears(&grid, false);
        assert_eq!(carve_missing_twins(&grid, &mut parts, 0, 5.0), 1);
        // Every cell of the left ear is in one new limb, cut like the right ear: its lower
        // cells in the first segment, its upper in the second.
        let role_at = |p: DVec3| {
            let i = grid.index(grid.cell_at(p))?;
            parts.label[i].map(|l| parts.roles[l as usize])
        };
        let mut new_limb = None;
        for i in 0..grid.len() {
            let p = grid.centre(grid.cell_of(i));
            let in_left_ear =
                p.x >= 2.0 && p.x <= 4.0 && p.y >= 2.0 && p.y <= 4.0 && p.z > 6.0 && p.z <= 10.0;
            if !in_left_ear {
                continue;
            }
            let Some(Role::Limb { limb, segment }) = role_at(p) else {
                panic!("left ear cell at {p} is not in a limb");
            };
            assert!(
                limb != 0 && limb != 1,
                "left ear cell at {p} stayed in limb {limb}"
            );
            assert_eq!(*new_limb.get_or_insert(limb), limb);
            assert_eq!(
                segment,
                usize::from(p.z >= 8.0),
                "segment of the cell at {p}"
            );
        }
        assert!(new_limb.is_some());
        // The head keeps the rest, in one piece.
        let head: Vec<usize> = (0..grid.len())
            .filter(|&i| {
                matches!(
                    parts.label[i].map(|l| parts.roles[l as usize]),
                    Some(Role::Limb { limb: 0, .. })
                )
            })
            .collect();
        assert!(head.iter().all(|&i| grid.centre(grid.cell_of(i)).z <= 6.0));
        assert_eq!(component_cells(&grid, |i| head.contains(&i)).len(), 1);
    }

    #[test]
    fn an_ear_already_a_limb_or_a_shape_with_no_twin_is_left_alone() {
        let grid = grid();
        let mut apart = head_with_ears(&grid, true);
        let before = apart.clone();
        assert_eq!(carve_missing_twins(&grid, &mut apart, 0, 5.0), 0);
        assert_eq!(apart.label, before.label);
        // Across another plane the right ear's mirror image is empty or the ear itself.
        let mut parts = head_with_ears(&grid, false);
        assert_eq!(carve_missing_twins(&grid, &mut parts, 1, 3.0), 0);
        // A host hardly larger than the twin is the twin cut differently.
        let mut small_host = head_with_ears(&grid, false);
        for (i, l) in small_host.label.iter_mut().enumerate() {
            let p = grid.centre(grid.cell_of(i));
            let under_left_ear = (2.0..=4.0).contains(&p.x) && (2.0..=4.0).contains(&p.y);
            if *l == Some(0) && !under_left_ear {
                *l = None;
            }
        }
        assert_eq!(carve_missing_twins(&grid, &mut small_host, 0, 5.0), 0);
        // A host that would grow from nothing once the twin is carved (no body under it).
        let mut floating = head_with_ears(&grid, false);
        for l in floating.label.iter_mut() {
            if *l == Some(4) {
                *l = None;
            }
        }
        assert_eq!(carve_missing_twins(&grid, &mut floating, 0, 5.0), 0);
    }
}
