//! One piece of surface per part: a part whose cells hold two separate pieces of the mesh's
//! surface (two fingers in one slice of a hand, an ear beside the head) is split between them,
//! each cell going to the piece whose vertices it holds or, holding none, to the nearest one.
//! Pieces that share a cell cannot be told apart at this grid's resolution and stay together.

use std::collections::{BTreeMap, VecDeque};

use super::SLIVER_VERTICES;
use super::parts::{Parts, split_disconnected};
use super::voxels::Grid;
use crate::mesh::Mesh;

/// Splits the parts whose cells hold more than one piece of the surface (see the module).
/// Returns how many parts were split.
pub(super) fn split_by_surface_pieces(grid: &Grid, parts: &mut Parts, mesh: &Mesh) -> usize {
    let points = mesh.welded_positions();
    let cell_of: Vec<Option<usize>> = points
        .iter()
        .map(|&p| grid.index(grid.cell_at(p)))
        .collect();
    let part_of = |v: usize| cell_of[v].and_then(|c| parts.label[c]);
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); points.len()];
    for &[a, b, c] in mesh.welded_triangles() {
        for (x, y) in [(a, b), (b, c), (c, a)] {
            if (x as usize) < points.len() && (y as usize) < points.len() {
                neighbours[x as usize].push(y);
                neighbours[y as usize].push(x);
            }
        }
    }
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
