//! One piece of surface per part: a part whose cells hold two separate pieces of the mesh's
//! surface (two fingers in one slice of a hand, an ear beside the head) is split between them,
//! each cell going to the piece whose vertices it holds or, holding none, to the nearest one.
//! Pieces that share a cell cannot be told apart at this grid's resolution: their part merges
//! with the neighbour through which they connect (fingers that touch, with their palm; the lips
//! of a closed mouth, with the head's side), so that the cage holds one piece; a head whose
//! pieces join below it (a jaw cut by the neck layer) takes the cells between them instead.

use std::cmp::Reverse;
use std::collections::{BTreeMap, BTreeSet, VecDeque};

use super::SLIVER_VERTICES;
use super::parts::{Parts, Role, compact, contacts_of, split_disconnected};
use super::repair::make_manifold;
use super::segment_boundary::moved_boundary;
use super::surface::SurfaceMesh;
use super::surface_pieces::Surface;
use super::symmetry::MirrorPlane;
use super::voxels::Grid;

/// Splits the parts whose cells hold more than one piece of the surface (see the module).
/// Returns how many parts were split.
pub(super) fn split_by_surface_pieces(
    grid: &Grid,
    parts: &mut Parts,
    surface: &SurfaceMesh,
) -> usize {
    let Surface {
        cell_of,
        neighbours,
    } = Surface::new(grid, surface);
    let points = surface.mesh.welded_positions();
    let part_of = |v: usize| cell_of[v].and_then(|c| parts.label[c]);
    // Pieces: mesh vertices connected through edges whose ends are in the same part.
    let mut piece = vec![usize::MAX; points.len()];
    let mut piece_part = Vec::new();
    let mut piece_size = Vec::new();
    for start in 0..points.len() {
        if piece[start] != usize::MAX {
            continue;
        }
        let Some(p) = part_of(start) else { continue };
        let id = piece_part.len();
        piece[start] = id;
        let mut stack = vec![start];
        let mut size = 0;
        while let Some(v) = stack.pop() {
            size += 1;
            for &n in &neighbours[v] {
                let n = n as usize;
                if piece[n] == usize::MAX && part_of(n) == Some(p) {
                    piece[n] = id;
                    stack.push(n);
                }
            }
        }
        piece_part.push(p);
        piece_size.push(size);
    }
    let mut held: BTreeMap<u32, usize> = BTreeMap::new();
    for (k, &p) in piece_part.iter().enumerate() {
        *held.entry(p).or_insert(0) += piece_size[k];
    }
    let significant = |k: usize| piece_size[k] >= SLIVER_VERTICES.max(held[&piece_part[k]] / 100);
    let mut pieces_of: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for k in (0..piece_part.len()).filter(|&k| significant(k)) {
        pieces_of.entry(piece_part[k]).or_default().push(k);
    }
    let mut split = 0;
    let mut next_label = parts.roles.len() as u32;
    for (&p, list) in pieces_of.iter().filter(|(_, l)| l.len() > 1) {
        // Each cell of the part to the significant piece whose vertices it holds (None where
        // it holds two: the pieces touch at this resolution).
        let mut owner: BTreeMap<usize, Option<usize>> = BTreeMap::new();
        for (v, &c) in cell_of.iter().enumerate() {
            let (Some(c), k) = (c, piece[v]) else {
                continue;
            };
            if parts.label[c] != Some(p) || !list.contains(&k) {
                continue;
            }
            owner
                .entry(c)
                .and_modify(|o| {
                    if *o != Some(k) {
                        *o = None;
                    }
                })
                .or_insert(Some(k));
        }
        if owner.values().all(Option::is_none) {
            continue;
        }
        // The other cells of the part go to the nearest owned cell (breadth first).
        let mut assigned: BTreeMap<usize, usize> = owner
            .iter()
            .filter_map(|(&c, o)| o.map(|k| (c, k)))
            .collect();
        let mut queue: VecDeque<usize> = assigned.keys().copied().collect();
        while let Some(c) = queue.pop_front() {
            let k = assigned[&c];
            for n in grid.face_neighbours(c) {
                if parts.label[n] == Some(p) && !assigned.contains_key(&n) {
                    assigned.insert(n, k);
                    queue.push_back(n);
                }
            }
        }
        // The first piece keeps the part's label; the others get new ones, same role.
        let role = parts.roles[p as usize];
        let mut label_of: BTreeMap<usize, u32> = BTreeMap::new();
        label_of.insert(list[0], p);
        for &k in &list[1..] {
            label_of.insert(k, next_label);
            parts.roles.push(role);
            next_label += 1;
        }
        for (c, k) in assigned {
            parts.label[c] = Some(label_of[&k]);
        }
        split += 1;
    }
    if split > 0 {
        split_disconnected(grid, parts);
    }
    split
}

impl Surface<'_> {
    /// The labels with the cells of other parts along the shortest way over the surface
    /// between two of `p`'s pieces ([`Self::path_joining`]) given to `p` ([`give_cells`]).
    fn annexing_path(
        &self,
        grid: &Grid,
        parts: &Parts,
        by_part: &BTreeMap<u32, Vec<usize>>,
        p: u32,
        mirror: Option<&MirrorPlane>,
        mark: &mut [bool],
    ) -> Option<Vec<Option<u32>>> {
        let pieces = self.significant_pieces(parts, by_part, &[p], mark);
        let cells = self.path_joining(parts, p, &pieces).into_iter();
        give_cells(
            grid,
            parts,
            cells.filter_map(|v| self.cell_of[v]),
            p,
            mirror,
        )
    }

    /// The labels with the cells of `q` holding its pieces but the largest given to `p`
    /// ([`give_cells`]): what taking cells from `q` cut off from the rest of it.
    fn annexing_pieces(
        &self,
        grid: &Grid,
        parts: &Parts,
        by_part: &BTreeMap<u32, Vec<usize>>,
        (q, p): (u32, u32),
        mirror: Option<&MirrorPlane>,
        mark: &mut [bool],
    ) -> Option<Vec<Option<u32>>> {
        let mut pieces = self.significant_pieces(parts, by_part, &[q], mark);
        pieces.sort_by_key(|piece| Reverse(piece.len()));
        let cut_off = pieces.iter().skip(1).flatten();
        let cells = cut_off.filter_map(|&v| self.cell_of[v]);
        give_cells(
            grid,
            parts,
            cells.filter(|&c| parts.label[c] == Some(q)),
            p,
            mirror,
        )
    }
}

/// The pieces of the surface beyond one per part, over all parts (slivers left out as in
/// [`merge_inseparable_pieces`]): 0 when every part holds one piece.
pub(super) fn extra_pieces_total(grid: &Grid, parts: &Parts, surface: &SurfaceMesh) -> usize {
    Surface::new(grid, surface).extra_pieces_total(parts)
}

/// The limb parts of the low side that reach the mirror plane while no piece of the surface in
/// them continues across it: no mesh edge joins a vertex in one of their cells to a vertex in
/// the image of one (a foot touching its twin at the plane: Cheburashka's feet). Mirrored as
/// parts that cross the plane, the two feet would be one part holding two pieces of surface,
/// and the merge that makes it one piece took both into the body.
pub(super) fn limbs_stopping_at_plane(
    grid: &Grid,
    parts: &Parts,
    surface: &SurfaceMesh,
    plane: &MirrorPlane,
) -> BTreeSet<u32> {
    let surface = Surface::new(grid, surface);
    // Limb parts holding a piece of surface (not a sliver) that touches the plane: some of
    // its vertices lie in the part's cells beside the plane.
    let mut held: BTreeMap<u32, (usize, bool)> = BTreeMap::new();
    for &c in surface.cell_of.iter().flatten() {
        let cell = grid.cell_of(c);
        if let Some(p) = parts.label[c]
            && plane.is_low_cell(cell)
            && matches!(parts.roles[p as usize], Role::Limb { .. })
        {
            let entry = held.entry(p).or_insert((0, false));
            entry.0 += 1;
            entry.1 |= cell[plane.axis] == plane.half - 1;
        }
    }
    let reaches: BTreeSet<u32> = (held.into_iter())
        .filter(|&(_, (count, touches))| touches && count >= SLIVER_VERTICES)
        .map(|(p, _)| p)
        .collect();
    // The part a vertex lies in as seen from the low side: its cell's, or its cell's image's
    // on the high side.
    let low_part = |v: usize| {
        let c = surface.cell_of[v]?;
        let cell = grid.cell_of(c);
        let low = if plane.is_low_cell(cell) {
            c
        } else {
            grid.index(plane.cell(cell))?
        };
        Some((parts.label[low]?, plane.is_low_cell(cell)))
    };
    let mut crossing = BTreeSet::new();
    for (v, next) in surface.neighbours.iter().enumerate() {
        let Some((p, true)) = low_part(v) else {
            continue;
        };
        if reaches.contains(&p)
            && next
                .iter()
                .any(|&n| low_part(n as usize) == Some((p, false)))
        {
            crossing.insert(p);
        }
    }
    reaches.difference(&crossing).copied().collect()
}

/// Merges each part that still holds more than one piece of the surface (pieces sharing cells,
/// which [`split_by_surface_pieces`] cannot separate) with the neighbour part that removes most
/// extra pieces or, where no one neighbour does (two fingers meeting only at the palm), with
/// the parts along the shortest way over the surface between two of its pieces; as long as a
/// merge removes extra pieces. Returns the number of merges.
pub(super) fn merge_inseparable_pieces(
    grid: &Grid,
    parts: &mut Parts,
    surface: &SurfaceMesh,
    mirror: Option<&MirrorPlane>,
) -> usize {
    let surface = Surface::new(grid, surface);
    let mut mark = vec![false; surface.cell_of.len()];
    let mut merges = 0;
    loop {
        let by_part = surface.vertices_by_part(parts);
        let extra: BTreeMap<u32, usize> = by_part
            .keys()
            .map(|&p| (p, surface.extra_pieces(parts, &by_part, &[p], &mut mark)))
            .collect();
        let extra_of = |members: &[u32]| members.iter().filter_map(|q| extra.get(q)).sum::<usize>();
        // A head's pieces joined through a few cells of the body (a jaw reaching below the
        // neck layer: Homer's) take those cells rather than merging the head into the body,
        // which would leave it no control. Not a crown's: pieces of a crown joined below it
        // are the top of a head whose face lies lower, and it merges as before.
        let annexed = extra.iter().filter(|&(_, &e)| e > 0).find_map(|(&p, _)| {
            let head = matches!(
                parts.roles.get(p as usize),
                Some(Role::Body { body, .. })
                    if parts.heads.contains(body) && !parts.crowns.contains(body)
            );
            if !head {
                return None;
            }
            // Taking the cells may bring in a piece of their own, or cut one off the part they
            // came from: up to ANNEX_ROUNDS takings, as long as all they take stays within
            // ANNEX_SHARE of the head's cells.
            let own = parts.label.iter().filter(|&&l| l == Some(p)).count();
            let mut trial = parts.clone();
            for _ in 0..ANNEX_ROUNDS {
                let by_trial = surface.vertices_by_part(&trial);
                let label = if surface.extra_pieces(&trial, &by_trial, &[p], &mut mark) > 0 {
                    surface.annexing_path(grid, &trial, &by_trial, p, mirror, &mut mark)
                } else {
                    // A part the cells came from, left with a piece cut off (a chin's front).
                    let donors: BTreeSet<u32> = (trial.label.iter().zip(&parts.label))
                        .filter(|(a, b)| a != b)
                        .filter_map(|(_, b)| *b)
                        .collect();
                    donors.into_iter().find_map(|q| {
                        let now = surface.extra_pieces(&trial, &by_trial, &[q], &mut mark);
                        (now > extra.get(&q).copied().unwrap_or(0)).then(|| {
                            let pair = (q, p);
                            surface
                                .annexing_pieces(grid, &trial, &by_trial, pair, mirror, &mut mark)
                        })?
                    })
                };
                match label {
                    Some(label) => trial.label = label,
                    None => break,
                }
            }
            let taken = (trial.label.iter().zip(&parts.label))
                .filter(|(a, b)| a != b)
                .count();
            if taken == 0 || taken as f64 > ANNEX_SHARE * own as f64 {
                return None;
            }
            let before: usize = extra.values().sum();
            let by_trial = surface.vertices_by_part(&trial);
            let after: usize = by_trial
                .keys()
                .map(|&q| surface.extra_pieces(&trial, &by_trial, &[q], &mut mark))
                .sum();
            (after < before).then_some(trial.label)
        });
        if let Some(label) = annexed {
            parts.label = label;
            compact(parts);
            continue;
        }
        // The first part with extra pieces that a merge improves, merged with its best
        // neighbour (most extra pieces removed, then most faces shared, then lowest label), or
        // with the parts joining two of its pieces.
        let merge = extra.iter().filter(|&(_, &e)| e > 0).find_map(|(&p, _)| {
            let best_neighbour = contacts_of(grid, &parts.label, p)
                .into_iter()
                .filter_map(|(q, faces)| {
                    let before = extra_of(&[p, q]);
                    let after = surface.extra_pieces(parts, &by_part, &[p, q], &mut mark);
                    (after < before).then(|| (before - after, faces, Reverse(q)))
                })
                .max()
                .map(|(_, _, Reverse(q))| vec![p, q]);
            best_neighbour.or_else(|| {
                let pieces = surface.significant_pieces(parts, &by_part, &[p], &mut mark);
                let mut members = vec![p];
                members.extend(surface.parts_joining(parts, p, &pieces));
                let after = surface.extra_pieces(parts, &by_part, &members, &mut mark);
                (members.len() > 1 && after < extra_of(&members)).then_some(members)
            })
        });
        let Some(members) = merge else {
            return merges;
        };
        // A merge that would take a whole limb into a slab of the trunk, because the slab
        // holds a sliver of the limb's surface (Cheburashka's bottom slab, of a foot), first
        // tries that sliver's cells alone: the slab gives them to the limb. Not into a smaller
        // body at a limb's end: that body grown is what it is (the horse's neck at detail 4
        // merged into the body at its muzzle, named a head; ceding left the neck's chain
        // holding the head, named `neck`). Not from the limb to the slab: that left the
        // armadillo's shoulder top at detail 2 with an ear, as a crown named `head`.
        let trunk = trunk_of(parts);
        let of_trunk = |q: u32| matches!(parts.roles[q as usize], Role::Body { body, .. } if Some(body) == trunk);
        if let [p, q] = members[..]
            && of_trunk(p)
            && erases_a_limb(parts, &members)
            && let Some(ceded) = ceding(&surface, grid, parts, &by_part, (p, q), mirror, &mut mark)
        {
            *parts = ceded;
            compact(parts);
            continue;
        }
        // Two consecutive segments of one limb: their joint moves, where that makes each one
        // piece, rather than the limb losing one.
        if let [p, q] = members[..]
            && let Some(moved) = moved_boundary(&surface, grid, parts, &by_part, (p, q), &mut mark)
        {
            *parts = moved;
            compact(parts);
            continue;
        }
        // The merged part keeps the role nearest the body (a body slab, or the lowest segment)
        // and the first member's label.
        let Some(role) = members.iter().map(|&q| parts.roles[q as usize]).min() else {
            return merges;
        };
        let into = members[0];
        parts.roles[into as usize] = role;
        for l in parts.label.iter_mut().flatten() {
            if members.contains(l) {
                *l = into;
            }
        }
        compact(parts);
        merges += 1;
    }
}

/// The trunk: the body with most cells that is not a head.
fn trunk_of(parts: &Parts) -> Option<usize> {
    let mut cells: BTreeMap<usize, usize> = BTreeMap::new();
    for l in parts.label.iter().flatten() {
        if let Some(Role::Body { body, .. }) = parts.roles.get(*l as usize)
            && !parts.heads.contains(body)
        {
            *cells.entry(*body).or_insert(0) += 1;
        }
    }
    cells
        .into_iter()
        .max_by_key(|&(body, n)| (n, Reverse(body)))
        .map(|(body, _)| body)
}

/// Whether merging `members` into one part takes a limb's root (a part of its first segment)
/// into a part of another role: the merged part keeps one role, the nearest the body, and
/// the limb loses that root's chain (a second root becomes a limb of its own later,
/// [`super::parts::one_limb_per_root`]).
fn erases_a_limb(parts: &Parts, members: &[u32]) -> bool {
    let Some(kept) = members.iter().map(|&q| parts.roles[q as usize]).min() else {
        return false;
    };
    let first_segment = |limb: usize| {
        (parts.roles.iter())
            .filter_map(|r| match r {
                Role::Limb { limb: l, segment } if *l == limb => Some(*segment),
                _ => None,
            })
            .min()
    };
    members.iter().any(|&q| match parts.roles[q as usize] {
        role @ Role::Limb { limb, segment } => role != kept && first_segment(limb) == Some(segment),
        Role::Body { .. } => false,
    })
}

/// The parts with the cells of `p`'s pieces but its largest given to `q`
/// ([`Surface::annexing_pieces`]), then repaired ([`make_manifold`]), where that gives `q` at
/// most [`ANNEX_SHARE`] of its own cells, the repairs merge no parts and fewer extra pieces are
/// left over all parts; None otherwise.
fn ceding(
    surface: &Surface,
    grid: &Grid,
    parts: &Parts,
    by_part: &BTreeMap<u32, Vec<usize>>,
    (p, q): (u32, u32),
    mirror: Option<&MirrorPlane>,
    mark: &mut [bool],
) -> Option<Parts> {
    let label = surface.annexing_pieces(grid, parts, by_part, (p, q), mirror, mark)?;
    let own = parts.label.iter().filter(|&&l| l == Some(q)).count();
    let taken = (label.iter().zip(&parts.label))
        .filter(|(a, b)| a != b)
        .count();
    if taken == 0 || taken as f64 > ANNEX_SHARE * own as f64 {
        return None;
    }
    // The repairs have run: a part pinched by the cells it gave or took is repaired here, by
    // moving cells only (a pinched part makes a non-manifold cage; ManHead at detail 2 then had
    // no valid rig).
    let mut trial = Parts {
        label,
        ..parts.clone()
    };
    if make_manifold(grid, &mut trial) > 0 || trial.roles != parts.roles {
        return None;
    }
    (surface.extra_pieces_total(&trial) < surface.extra_pieces_total(parts)).then_some(trial)
}

/// The most cells a head takes from other parts to be one piece, as a share of its own.
const ANNEX_SHARE: f64 = 0.25;

/// The most takings of cells (a way between two pieces, or pieces cut off) for a head to be one
/// piece.
const ANNEX_ROUNDS: usize = 4;

/// The labels with `cells` given to `p` and their images across `mirror` to `p`'s twin (so
/// that a mirrored rig stays symmetric; until session 48 the images went to `p` too, which cut
/// a part off the plane in two and refused every such taking), where they belong to other
/// parts and `p`, its twin and every part they come from stay one face-connected piece of
/// cells. None where no cell moves or one would not.
fn give_cells(
    grid: &Grid,
    parts: &Parts,
    cells: impl Iterator<Item = usize>,
    p: u32,
    mirror: Option<&MirrorPlane>,
) -> Option<Vec<Option<u32>>> {
    let image_of = |c: usize| mirror.and_then(|m| grid.index(m.cell(grid.cell_of(c))));
    // The cells' images go to p's image: the part holding the images of p's cells (p itself
    // where it crosses the plane; a foot's twin on the other side).
    let p_image = (parts.label.iter().position(|&l| l == Some(p)))
        .and_then(image_of)
        .and_then(|c| parts.label[c])
        .unwrap_or(p);
    let cells: BTreeSet<(usize, u32)> = cells
        .flat_map(|c| std::iter::once((c, p)).chain(image_of(c).map(|i| (i, p_image))))
        .filter(|&(c, to)| parts.label[c].is_some_and(|q| q != to))
        .collect();
    if cells.is_empty() {
        return None;
    }
    let donors: BTreeSet<u32> = cells.iter().filter_map(|&(c, _)| parts.label[c]).collect();
    let mut label = parts.label.clone();
    for &(c, to) in &cells {
        label[c] = Some(to);
    }
    [p, p_image]
        .into_iter()
        .chain(donors)
        .all(|q| face_connected(grid, &label, q))
        .then_some(label)
}

/// Whether the cells labelled `p` are one face-connected piece (true where there are none).
fn face_connected(grid: &Grid, label: &[Option<u32>], p: u32) -> bool {
    let Some(start) = label.iter().position(|&l| l == Some(p)) else {
        return true;
    };
    let mut seen = BTreeSet::from([start]);
    let mut stack = vec![start];
    while let Some(c) = stack.pop() {
        for n in grid.face_neighbours(c) {
            if label[n] == Some(p) && seen.insert(n) {
                stack.push(n);
            }
        }
    }
    seen.len() == label.iter().filter(|&&l| l == Some(p)).count()
}

#[cfg(test)]
mod tests {
    use glam::{DVec3, IVec3};

    use super::super::symmetry::mirror_parts;
    use super::super::test_mirror::{limb_at_the_plane, ribbons};
    use super::*;
    use crate::mesh::Mesh;

    /// A ribbon along a U: down one column, across the bottom, up the other (0.1 apart along
    /// it, 0.3 wide across y), inside a box from the origin to (4, 1, 5).
    fn u_ribbon() -> Mesh {
        let mut path = Vec::new();
        for k in 0..31 {
            path.push(DVec3::new(0.5, 0.35, 4.45 - 0.1 * f64::from(k)));
        }
        for k in 1..20 {
            path.push(DVec3::new(0.5 + 0.1 * f64::from(k), 0.35, 1.45));
        }
        for k in 0..31 {
            path.push(DVec3::new(2.5, 0.35, 1.45 + 0.1 * f64::from(k)));
        }
        let across = DVec3::new(0.0, 0.3, 0.0);
        let positions: Vec<DVec3> = path.iter().flat_map(|&p| [p, p + across]).collect();
        let triangles = (0..path.len() as u32 - 1)
            .flat_map(|k| {
                [
                    [2 * k, 2 * k + 2, 2 * k + 1],
                    [2 * k + 1, 2 * k + 2, 2 * k + 3],
                ]
            })
            .collect();
        Mesh::new(positions, triangles, None, None).unwrap()
    }

    /// Every cell of the grid in a part: the head above the U's bottom layer, the body below.
    fn head_over_body(grid: &Grid, heads: BTreeSet<usize>) -> Parts {
        let bottom = grid.cell_at(DVec3::new(0.5, 0.5, 1.45)).z;
        Parts {
            label: (0..grid.len())
                .map(|i| Some(u32::from(grid.cell_of(i).z > bottom)))
                .collect(),
            roles: vec![
                Role::Body { body: 0, slab: 0 },
                Role::Body { body: 1, slab: 0 },
            ],
            parent_limb: BTreeMap::new(),
            heads,
            crowns: BTreeSet::new(),
            halved: BTreeMap::new(),
            pairs: Vec::new(),
        }
    }

    #[test]
    fn a_heads_pieces_joined_under_it_take_the_cells_between_them_instead_of_merging() {
        // The head's cells hold both columns of the U, joined only across its bottom, in the
        // body's layer (Homer's lower jaw, joined to his face under the neck layer).
        let mesh = u_ribbon();
        let surface = SurfaceMesh::new(&mesh);
        let grid = Grid::around(DVec3::ZERO, DVec3::new(4.0, 1.0, 5.0), 5, None, &[], None);
        let before = head_over_body(&grid, BTreeSet::from([1]));
        assert_eq!(extra_pieces_total(&grid, &before, &surface), 1);
        let mut parts = before.clone();
        assert_eq!(
            merge_inseparable_pieces(&grid, &mut parts, &surface, None),
            0
        );
        assert_eq!(extra_pieces_total(&grid, &parts, &surface), 0);
        // The head keeps its role; it took the cells of the U's bottom, the body the rest.
        assert_eq!(parts.roles.len(), 2);
        let moved: Vec<usize> = (0..grid.len())
            .filter(|&i| parts.label[i] != before.label[i])
            .collect();
        let bottom = grid.cell_at(DVec3::new(0.5, 0.5, 1.45));
        assert!(!moved.is_empty() && moved.len() <= 3, "{moved:?}");
        for &i in &moved {
            assert_eq!(before.label[i], Some(0));
            assert_eq!(parts.label[i], Some(1));
            assert_eq!(grid.cell_of(i).z, bottom.z);
        }
        // Not a head, or a crown (the top of a head whose face lies lower): the two parts
        // merge into one, as two fingers do with their palm.
        let crown = Parts {
            crowns: BTreeSet::from([1]),
            ..head_over_body(&grid, BTreeSet::from([1]))
        };
        for mut parts in [head_over_body(&grid, BTreeSet::new()), crown] {
            assert_eq!(
                merge_inseparable_pieces(&grid, &mut parts, &surface, None),
                1
            );
            assert_eq!(parts.roles, vec![Role::Body { body: 0, slab: 0 }]);
        }
    }

    #[test]
    fn a_limb_reaching_the_mirror_plane_is_apart_only_where_its_surface_does_not_cross_it() {
        // The grid mirrors across x = 2. The limb holds the low side's cells from x = 1 up to
        // the plane, the body the rest.
        let (grid, plane, parts) = limb_at_the_plane(2.0, 10.0);
        let strip = |from: f64, to: f64| [DVec3::new(from, 0.3, 1.0), DVec3::new(to, 0.3, 1.0)];
        // Two feet touching at the plane, each its own piece of surface: apart.
        let feet = ribbons(&[&strip(1.0, 1.98), &strip(2.02, 3.0)]);
        let apart = limbs_stopping_at_plane(&grid, &parts, &SurfaceMesh::new(&feet), &plane);
        assert_eq!(apart, BTreeSet::from([1]));
        // One strip across the plane (a tail on the centre line): it crosses.
        let tail = ribbons(&[&strip(1.0, 3.0)]);
        let apart = limbs_stopping_at_plane(&grid, &parts, &SurfaceMesh::new(&tail), &plane);
        assert!(apart.is_empty(), "{apart:?}");
        // Mirrored, the feet are two limbs; the tail stays one part across the plane.
        for (apart, expected_limbs) in [(BTreeSet::from([1]), 2), (BTreeSet::new(), 1)] {
            let mut mirrored = parts.clone();
            mirror_parts(&grid, &plane, &mut mirrored, &apart);
            let limbs: BTreeSet<usize> = (mirrored.roles.iter())
                .filter_map(|r| match r {
                    Role::Limb { limb, .. } => Some(*limb),
                    Role::Body { .. } => None,
                })
                .collect();
            assert_eq!(limbs.len(), expected_limbs, "{:?}", mirrored.roles);
        }
    }

    #[test]
    fn cells_given_to_a_part_off_the_mirror_plane_give_their_images_to_its_twin() {
        // The limb beside the plane, mirrored apart: the high side holds its twin.
        let (grid, plane, mut parts) = limb_at_the_plane(2.0, 10.0);
        mirror_parts(&grid, &plane, &mut parts, &BTreeSet::from([1]));
        let limb = parts.part_at(&grid, DVec3::new(1.5, 0.5, 1.0)).unwrap();
        let twin = parts.part_at(&grid, DVec3::new(2.5, 0.5, 1.0)).unwrap();
        assert_ne!(limb, twin);
        // A body cell beside the limb, and its image beside the twin.
        let cell = grid.cell_at(DVec3::new(1.0, 0.5, 1.0)) - IVec3::X;
        let index = grid.index(cell).unwrap();
        let image = grid.index(plane.cell(cell)).unwrap();
        assert!(parts.label[index].is_some_and(|q| q != limb));
        let label = give_cells(&grid, &parts, std::iter::once(index), limb, Some(&plane))
            .expect("the limb and its twin each stay one piece");
        assert_eq!(label[index], Some(limb));
        assert_eq!(label[image], Some(twin));
        let changed = (label.iter().zip(&parts.label))
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(changed, 2);
    }

    #[test]
    fn a_limb_takes_the_cells_of_its_surface_a_body_holds_instead_of_merging_into_it() {
        // The body holds the U's left column, its bottom and the top of its right column (two
        // cells, 30 mesh vertices, a piece of their own); the limb beside it the rest of the
        // right column, which joins that top to the body's bottom (Cheburashka's bottom slab
        // held a sliver of his foot, joined to the rest of the body through the foot).
        let mesh = u_ribbon();
        let surface = SurfaceMesh::new(&mesh);
        let grid = Grid::around(DVec3::ZERO, DVec3::new(8.0, 1.0, 5.0), 8, None, &[], None);
        let right = grid.cell_at(DVec3::new(2.5, 0.5, 3.5));
        let bottom = grid.cell_at(DVec3::new(0.5, 0.5, 1.45)).z;
        let top_of_right_column = |c: IVec3| c.x == right.x && c.z >= right.z;
        let body_and_limb = |limb: Role| {
            Parts::of_roles(
                (0..grid.len())
                    .map(|i| {
                        let c = grid.cell_of(i);
                        let body = c.x < right.x || c.z <= bottom || top_of_right_column(c);
                        Some(u32::from(!body))
                    })
                    .collect(),
                vec![Role::Body { body: 0, slab: 0 }, limb],
            )
        };
        let foot = Role::Limb {
            limb: 0,
            segment: 0,
        };
        let before = body_and_limb(foot);
        assert_eq!(extra_pieces_total(&grid, &before, &surface), 1);
        let mut parts = before.clone();
        assert_eq!(
            merge_inseparable_pieces(&grid, &mut parts, &surface, None),
            0
        );
        assert_eq!(extra_pieces_total(&grid, &parts, &surface), 0);
        assert_eq!(parts.roles, before.roles);
        let moved: Vec<IVec3> = (0..grid.len())
            .filter(|&i| parts.label[i] != before.label[i])
            .map(|i| grid.cell_of(i))
            .collect();
        assert_eq!(moved, vec![right, right + IVec3::Z]);
        assert!(
            moved
                .iter()
                .all(|&c| parts.part_at(&grid, grid.centre(c)) == Some(1))
        );
        // Two body slabs merge as before: no limb is lost.
        let mut slabs = body_and_limb(Role::Body { body: 0, slab: 1 });
        assert_eq!(
            merge_inseparable_pieces(&grid, &mut slabs, &surface, None),
            1
        );
        assert_eq!(slabs.roles, vec![Role::Body { body: 0, slab: 0 }]);
    }
}
