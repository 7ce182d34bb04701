//! Mesh vertices by grid cell, and the pieces of surface (vertices joined by mesh edges) that
//! a part or a few hold: what [`super::pieces`] splits and merges parts by, and what
//! [`super::segment_boundary`] moves a joint by.

use std::collections::{BTreeMap, VecDeque};

use super::SLIVER_VERTICES;
use super::parts::Parts;
use super::surface::SurfaceMesh;
use super::voxels::Grid;

/// Mesh vertices by grid cell and mesh edges, for counting the pieces of surface of parts.
pub(super) struct Surface<'a> {
    /// Cell (grid index) of each welded mesh vertex.
    pub cell_of: Vec<Option<usize>>,
    /// Mesh edges at each welded vertex, and links where components cross
    /// ([`super::surface::surface_neighbours`]).
    pub neighbours: &'a [Vec<u32>],
}

impl<'a> Surface<'a> {
    pub fn new(grid: &Grid, surface: &'a SurfaceMesh) -> Self {
        Self {
            cell_of: surface
                .mesh
                .welded_positions()
                .iter()
                .map(|&p| grid.index(grid.cell_at(p)))
                .collect(),
            neighbours: &surface.neighbours,
        }
    }

    /// The mesh vertices of each part.
    pub fn vertices_by_part(&self, parts: &Parts) -> BTreeMap<u32, Vec<usize>> {
        let mut by_part: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
        for (v, c) in self.cell_of.iter().enumerate() {
            if let Some(p) = c.and_then(|c| parts.label[c]) {
                by_part.entry(p).or_default().push(v);
            }
        }
        by_part
    }

    /// The pieces (mesh vertices connected by edges) among the mesh vertices of `members` (a
    /// part or a few), slivers (under [`SLIVER_VERTICES`] or 1 % of the vertices held) left
    /// out. `mark` is scratch space of one entry per mesh vertex, all false.
    pub(super) fn significant_pieces(
        &self,
        parts: &Parts,
        by_part: &BTreeMap<u32, Vec<usize>>,
        members: &[u32],
        mark: &mut [bool],
    ) -> Vec<Vec<usize>> {
        let inside = |v: usize| {
            self.cell_of[v]
                .and_then(|c| parts.label[c])
                .is_some_and(|p| members.contains(&p))
        };
        let vertices: Vec<usize> = members
            .iter()
            .filter_map(|p| by_part.get(p))
            .flatten()
            .copied()
            .collect();
        let sliver = SLIVER_VERTICES.max(vertices.len() / 100);
        let mut pieces = Vec::new();
        for &start in &vertices {
            if mark[start] {
                continue;
            }
            mark[start] = true;
            let mut piece = vec![start];
            let mut next = 0;
            while let Some(&v) = piece.get(next) {
                next += 1;
                for &n in &self.neighbours[v] {
                    let n = n as usize;
                    if !mark[n] && inside(n) {
                        mark[n] = true;
                        piece.push(n);
                    }
                }
            }
            if piece.len() >= sliver {
                pieces.push(piece);
            }
        }
        for &v in &vertices {
            mark[v] = false;
        }
        pieces
    }

    /// [`extra_pieces_total`].
    pub(super) fn extra_pieces_total(&self, parts: &Parts) -> usize {
        let mut mark = vec![false; self.cell_of.len()];
        let by_part = self.vertices_by_part(parts);
        by_part
            .keys()
            .map(|&p| self.extra_pieces(parts, &by_part, &[p], &mut mark))
            .sum()
    }

    /// Pieces beyond the first among the mesh vertices of `members` (see
    /// [`Self::significant_pieces`]).
    pub(super) fn extra_pieces(
        &self,
        parts: &Parts,
        by_part: &BTreeMap<u32, Vec<usize>>,
        members: &[u32],
        mark: &mut [bool],
    ) -> usize {
        self.significant_pieces(parts, by_part, members, mark)
            .len()
            .saturating_sub(1)
    }

    /// The parts along the shortest path of mesh edges outside `p` that joins two of its
    /// pieces (the palm between two fingers).
    pub(super) fn parts_joining(&self, parts: &Parts, p: u32, pieces: &[Vec<usize>]) -> Vec<u32> {
        let part_of = |v: usize| self.cell_of[v].and_then(|c| parts.label[c]);
        let mut joined: Vec<u32> = self
            .path_joining(parts, p, pieces)
            .into_iter()
            .filter_map(part_of)
            .filter(|&q| q != p)
            .collect();
        joined.sort_unstable();
        joined.dedup();
        joined
    }

    /// The mesh vertices along the shortest path of mesh edges outside `p` that joins two of
    /// its pieces, ends included: a breadth-first search grown from every piece at once,
    /// stopped where two fronts meet. Empty where no path joins them.
    pub(super) fn path_joining(&self, parts: &Parts, p: u32, pieces: &[Vec<usize>]) -> Vec<usize> {
        let part_of = |v: usize| self.cell_of[v].and_then(|c| parts.label[c]);
        let mut source = vec![usize::MAX; self.cell_of.len()];
        let mut parent = vec![usize::MAX; self.cell_of.len()];
        let mut queue = VecDeque::new();
        for (k, piece) in pieces.iter().enumerate() {
            for &v in piece {
                source[v] = k;
                queue.push_back(v);
            }
        }
        let path_to_source = |mut v: usize, parent: &[usize]| {
            let mut path = Vec::new();
            while v != usize::MAX {
                path.push(v);
                v = parent[v];
            }
            path
        };
        while let Some(v) = queue.pop_front() {
            for &n in &self.neighbours[v] {
                let n = n as usize;
                if part_of(n) == Some(p) && source[n] == usize::MAX {
                    // A vertex of p outside the significant pieces (a sliver): not a way through.
                    continue;
                }
                if source[n] == usize::MAX {
                    source[n] = source[v];
                    parent[n] = v;
                    queue.push_back(n);
                } else if source[n] != source[v] {
                    let mut path = path_to_source(v, &parent);
                    path.extend(path_to_source(n, &parent));
                    return path;
                }
            }
        }
        Vec::new()
    }
}
