//! A limb's last joint moved rather than lost: where a segment of a limb holds a piece of
//! surface that joins the rest only through another of its segments (the throat under a
//! horse's jaw, cut with its neck), [`super::pieces::merge_inseparable_pieces`] would merge the
//! two, and a limb of two segments would be left one, with no joint (TOSCA's horse: neck and
//! head one `head`). Moving cells between the two first (the piece's cells, or a few layers
//! of cells along their boundary) keeps both segments, each one piece of surface. A limb of
//! more segments merges as before: it keeps a joint, and moving cells there changed rigs
//! that needed no change (the beast's feet at detail 3 gained a segment).

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use super::parts::{Parts, Role};
use super::repair::make_manifold;
use super::surface_pieces::Surface;
use super::voxels::{Grid, component_cells};

/// A segment with fewer cells than this share of its limb's is a crumb.
const CRUMB_SHARE: f64 = 0.05;

/// The most layers of cells a boundary moves.
const MAX_LAYERS: usize = 3;

/// The parts with cells moved between `p` and `q`, two segments of a limb that has no other
/// (crumbs aside), so that each holds one piece of surface: first the cells of one's lesser
/// pieces (with what they cut off) given to the other, then one to [`MAX_LAYERS`] layers of
/// cells along their boundary, either way; a move takes less than half of the part that gives
/// it, the repairs after it ([`make_manifold`]) must split or merge no part, and it must
/// leave no more extra pieces over all parts than merging `p` and `q` would. None where no
/// move does. `by_part`: the mesh vertices of each part of `parts`
/// ([`Surface::vertices_by_part`]), which the merge's caller has at hand.
pub(super) fn moved_boundary(
    surface: &Surface,
    grid: &Grid,
    parts: &Parts,
    by_part: &BTreeMap<u32, Vec<usize>>,
    (p, q): (u32, u32),
    mark: &mut [bool],
) -> Option<Parts> {
    let (
        Some(&Role::Limb {
            limb: a,
            segment: sp,
        }),
        Some(&Role::Limb {
            limb: b,
            segment: sq,
        }),
    ) = (parts.roles.get(p as usize), parts.roles.get(q as usize))
    else {
        return None;
    };
    if a != b || sp == sq {
        return None;
    }
    // Only the limb's last joint: a limb of more segments keeps joints after the merge.
    // Segments are counted by their parts; crumbs (parts under [`CRUMB_SHARE`] of the limb's
    // cells, merged later by `crumbs`) do not count.
    let mut cells_by_part: BTreeMap<u32, usize> = BTreeMap::new();
    for &l in parts.label.iter().flatten() {
        if matches!(parts.roles.get(l as usize), Some(&Role::Limb { limb, .. }) if limb == a) {
            *cells_by_part.entry(l).or_default() += 1;
        }
    }
    let limb_cells: usize = cells_by_part.values().sum();
    let segments: BTreeSet<usize> = (cells_by_part.iter())
        .filter(|&(_, &n)| n as f64 >= CRUMB_SHARE * limb_cells as f64)
        .filter_map(|(&l, _)| match parts.roles.get(l as usize) {
            Some(&Role::Limb { segment, .. }) => Some(segment),
            _ => None,
        })
        .collect();
    if segments.len() > 2 {
        return None;
    }
    let extra_total = surface.extra_pieces_total(parts);
    let extra_of =
        |members: &[u32], mark: &mut [bool]| surface.extra_pieces(parts, by_part, members, mark);
    let separate = extra_of(&[p], mark) + extra_of(&[q], mark);
    // What the merge would leave: the pieces the two hold together.
    let merged_total = extra_total.saturating_sub(separate) + extra_of(&[p, q], mark);
    let sorted_roles = held_roles(parts);
    let accept = |moved: &[usize], to: u32, mark: &mut [bool]| -> Option<Parts> {
        let mut trial = parts.clone();
        for &i in moved {
            trial.label[i] = Some(to);
        }
        let repairs = make_manifold(grid, &mut trial);
        let roles = held_roles(&trial);
        if repairs > 0 || roles != sorted_roles {
            return None;
        }
        let trial_total = surface.extra_pieces_total(&trial);
        let by_trial = surface.vertices_by_part(&trial);
        // The two segments, found again by role (the repairs renumber parts).
        let both_whole = [(a, sp), (b, sq)]
            .iter()
            .filter_map(|&(limb, segment)| {
                (trial.roles.iter()).position(|r| *r == Role::Limb { limb, segment })
            })
            .all(|l| surface.extra_pieces(&trial, &by_trial, &[l as u32], mark) == 0);
        (trial_total <= merged_total && both_whole).then_some(trial)
    };
    for (from, to) in [(p, q), (q, p)] {
        let own = parts.label.iter().filter(|&&l| l == Some(from)).count();
        let small = |moved: &[usize]| !moved.is_empty() && 2 * moved.len() < own;
        // The cells holding `from`'s lesser pieces, and what they cut off the rest.
        let pieces = pieces_cells(surface, grid, parts, by_part, from, mark);
        if small(&pieces)
            && let Some(trial) = accept(&pieces, to, mark)
        {
            return Some(trial);
        }
        let layers = layers_from(grid, &parts.label, from, to);
        for k in 1..=MAX_LAYERS {
            let moved: Vec<usize> = (layers.iter().enumerate())
                .filter(|&(_, &layer)| layer.is_some_and(|layer| layer <= k))
                .map(|(i, _)| i)
                .collect();
            if !small(&moved) {
                break;
            }
            if let Some(trial) = accept(&moved, to, mark) {
                return Some(trial);
            }
        }
    }
    None
}

/// The roles of the parts that hold cells, one per part, sorted.
fn held_roles(parts: &Parts) -> Vec<Role> {
    let labels: BTreeSet<u32> = parts.label.iter().flatten().copied().collect();
    let mut roles: Vec<Role> = (labels.iter())
        .filter_map(|&l| parts.roles.get(l as usize).copied())
        .collect();
    roles.sort();
    roles
}

/// The cells of part `from` that hold vertices of its pieces of surface other than the
/// largest, with the cells of `from` that these cut off from its largest face-connected
/// piece of cells.
fn pieces_cells(
    surface: &Surface,
    grid: &Grid,
    parts: &Parts,
    by_part: &BTreeMap<u32, Vec<usize>>,
    from: u32,
    mark: &mut [bool],
) -> Vec<usize> {
    let mut pieces = surface.significant_pieces(parts, by_part, &[from], mark);
    pieces.sort_by_key(|piece| std::cmp::Reverse(piece.len()));
    let mut moved = vec![false; parts.label.len()];
    for &v in pieces.iter().skip(1).flatten() {
        if let Some(c) = surface.cell_of[v]
            && parts.label[c] == Some(from)
        {
            moved[c] = true;
        }
    }
    // What is left of `from`, by face-connected pieces of cells: all but the largest go too.
    let left = component_cells(grid, |i| parts.label[i] == Some(from) && !moved[i]);
    let largest = (0..left.len()).max_by_key(|&k| left[k].len());
    for (k, cells) in left.iter().enumerate() {
        if Some(k) != largest {
            for &i in cells {
                moved[i] = true;
            }
        }
    }
    (0..moved.len()).filter(|&i| moved[i]).collect()
}

/// For each cell of part `from`, its layer counted from part `to` (1: a face neighbour of a
/// cell of `to`), through cells of `from`; None elsewhere and where `from` does not reach.
fn layers_from(grid: &Grid, label: &[Option<u32>], from: u32, to: u32) -> Vec<Option<usize>> {
    let mut layer = vec![None; label.len()];
    let mut queue = VecDeque::new();
    for (i, &l) in label.iter().enumerate() {
        if l == Some(from) && grid.face_neighbours(i).any(|n| label[n] == Some(to)) {
            layer[i] = Some(1);
            queue.push_back(i);
        }
    }
    while let Some(i) = queue.pop_front() {
        let next = layer[i].map(|l| l + 1);
        for n in grid.face_neighbours(i) {
            if label[n] == Some(from) && layer[n].is_none() {
                layer[n] = next;
                queue.push_back(n);
            }
        }
    }
    layer
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::pieces::{extra_pieces_total, merge_inseparable_pieces};
    use super::super::surface::SurfaceMesh;
    use super::super::test_mirror::ribbons;
    use super::*;

    /// Every cell of a grid over (0, 0, 0)–(4, 1, 5) in a part of limb 0: segment 0 up to the
    /// layer of z = 1.45, segment 1 above it, and segment 2 right of x = `third_from`, if given.
    fn limb(grid: &Grid, third_from: Option<f64>) -> Parts {
        let bottom = grid.cell_at(DVec3::new(0.5, 0.5, 1.45)).z;
        let third = third_from.map_or(i32::MAX, |x| grid.cell_at(DVec3::new(x, 0.5, 0.5)).x);
        Parts {
            label: (0..grid.len())
                .map(|i| {
                    let cell = grid.cell_of(i);
                    Some(if cell.x >= third {
                        2
                    } else {
                        u32::from(cell.z > bottom)
                    })
                })
                .collect(),
            roles: (0..3)
                .map(|segment| Role::Limb { limb: 0, segment })
                .collect(),
            parent_limb: Default::default(),
            heads: Default::default(),
            crowns: Default::default(),
            halved: Default::default(),
            pairs: Vec::new(),
        }
    }

    fn segments(parts: &Parts) -> BTreeSet<usize> {
        (parts.label.iter().flatten())
            .filter_map(|&l| match parts.roles[l as usize] {
                Role::Limb { segment, .. } => Some(segment),
                Role::Body { .. } => None,
            })
            .collect()
    }

    /// A U of surface whose two columns are segment 1's and whose bottom is segment 0's: the
    /// columns join only through segment 0. The merge would leave the limb one segment; the
    /// boundary moves instead (one column goes to segment 0), and both are one piece. With a
    /// third segment the limb keeps a joint anyway, and the two merge as before.
    #[test]
    fn a_limbs_last_joint_moves_rather_than_merging_its_segments() {
        let u = [
            DVec3::new(0.5, 0.35, 4.45),
            DVec3::new(0.5, 0.35, 1.45),
            DVec3::new(2.5, 0.35, 1.45),
            DVec3::new(2.5, 0.35, 4.45),
        ];
        let mesh = ribbons(&[&u]);
        let surface = SurfaceMesh::new(&mesh);
        let grid = Grid::around(DVec3::ZERO, DVec3::new(4.0, 1.0, 5.0), 5, None, &[], None);

        // Two segments.
        let mut parts = limb(&grid, None);
        assert_eq!(segments(&parts), BTreeSet::from([0, 1]));
        assert_eq!(extra_pieces_total(&grid, &parts, &surface), 1);
        assert_eq!(
            merge_inseparable_pieces(&grid, &mut parts, &surface, None),
            0
        );
        assert_eq!(segments(&parts), BTreeSet::from([0, 1]));
        assert_eq!(extra_pieces_total(&grid, &parts, &surface), 0);

        // Three segments: 1 merges into 0.
        let mut parts = limb(&grid, Some(3.5));
        assert_eq!(segments(&parts), BTreeSet::from([0, 1, 2]));
        assert_eq!(
            merge_inseparable_pieces(&grid, &mut parts, &surface, None),
            1
        );
        assert_eq!(segments(&parts), BTreeSet::from([0, 2]));
        assert_eq!(extra_pieces_total(&grid, &parts, &surface), 0);
    }
}
