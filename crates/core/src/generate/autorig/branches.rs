//! A limb region's branches: where one region of the solid outside the body holds several
//! limbs (a hip band carrying two legs and a tail, a head top carrying two ears, a palm
//! carrying fingers), it is split into one branch per limb, each knowing the branch it grows
//! from, and each branch cut into its own chain of segments.
//!
//! The method is a discrete Reeb graph of the geodesic distance d from the body: the region's
//! cells are grouped in bands of d a fraction of the limb's thickness wide, each band's
//! face-connected pieces are the graph's nodes, and every piece hangs from the piece of the
//! band below it that it shares most faces with. Where a node has two or more children
//! reaching [`FORK_LENGTH`] thicknesses beyond it, each such child starts a branch; shorter
//! children (bumps, a bar between two knees) stay in the branch they grow from.

use std::cmp::Reverse;
use std::collections::BTreeMap;

use super::voxels::{FACE_STEPS, Grid};

/// Band width, in thicknesses of the limb region.
const BAND: f64 = 0.5;

/// How far beyond a fork a continuation must reach, in thicknesses of the limb region, to be
/// a branch of its own.
pub(super) const FORK_LENGTH: f64 = 1.0;

/// ... and at least this many bands.
const FORK_BANDS: f64 = 2.0;

/// One branch of a limb region.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Branch {
    /// The branch it grows from (None: it grows from the body).
    pub parent: Option<usize>,
    /// Its cells (grid indices) and their geodesic distance from the branch's start.
    pub cells: Vec<(usize, f64)>,
}

/// The branches of the limb region made of `cells`, whose geodesic distance from the body is
/// `distance` (in cells) and whose thickness (diameter, in cells) is `thickness`. Branches come
/// parents first; every cell is in exactly one.
pub(super) fn branches(
    grid: &Grid,
    cells: &[usize],
    distance: &BTreeMap<usize, f64>,
    thickness: f64,
) -> Vec<Branch> {
    // At least a cell and a half: a band one cell wide falls apart across a staircase.
    let width = (BAND * thickness).max(1.5);
    let d = |i: usize| distance.get(&i).copied().unwrap_or(0.0);
    let band = |i: usize| (d(i) / width) as i64;
    // Nodes: face-connected pieces of one band.
    let mut node_of: BTreeMap<usize, usize> = BTreeMap::new();
    let mut nodes: Vec<Vec<usize>> = Vec::new();
    for &start in cells {
        if node_of.contains_key(&start) {
            continue;
        }
        let id = nodes.len();
        let mut members = vec![start];
        node_of.insert(start, id);
        let mut k = 0;
        while let Some(&i) = members.get(k) {
            k += 1;
            let c = grid.cell_of(i);
            for s in FACE_STEPS {
                if let Some(n) = grid.index(c + s)
                    && distance.contains_key(&n)
                    && !node_of.contains_key(&n)
                    && band(n) == band(i)
                {
                    node_of.insert(n, id);
                    members.push(n);
                }
            }
        }
        nodes.push(members);
    }
    let node_band: Vec<i64> = nodes.iter().map(|m| band(m[0])).collect();
    // Parent of each node: the node of a lower band it shares most faces with (the band just
    // below first).
    let mut contacts: Vec<BTreeMap<usize, usize>> = vec![BTreeMap::new(); nodes.len()];
    for (id, members) in nodes.iter().enumerate() {
        for &i in members {
            let c = grid.cell_of(i);
            for s in FACE_STEPS {
                if let Some(n) = grid.index(c + s)
                    && let Some(&m) = node_of.get(&n)
                    && node_band[m] < node_band[id]
                {
                    *contacts[id].entry(m).or_insert(0) += 1;
                }
            }
        }
    }
    let parent: Vec<Option<usize>> = contacts
        .iter()
        .map(|c| {
            c.iter()
                .max_by_key(|(m, n)| (node_band[**m], **n, Reverse(**m)))
                .map(|(m, _)| *m)
        })
        .collect();
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
    for (id, p) in parent.iter().enumerate() {
        if let Some(p) = p {
            children[*p].push(id);
        }
    }
    // Farthest distance reached by each node and what hangs from it (highest bands first:
    // a child's band is above its parent's).
    let mut order: Vec<usize> = (0..nodes.len()).collect();
    order.sort_by_key(|&id| (Reverse(node_band[id]), id));
    let mut reach: Vec<f64> = nodes
        .iter()
        .map(|m| m.iter().map(|&i| d(i)).fold(0.0, f64::max))
        .collect();
    for &id in &order {
        if let Some(p) = parent[id] {
            reach[p] = reach[p].max(reach[id]);
        }
    }
    let start_of = |id: usize| {
        nodes[id]
            .iter()
            .map(|&i| d(i))
            .fold(f64::INFINITY, f64::min)
    };
    // Branches top down (lowest bands first).
    let mut branch_of_node: Vec<Option<usize>> = vec![None; nodes.len()];
    let mut out: Vec<(Option<usize>, f64)> = Vec::new();
    for &id in order.iter().rev() {
        if branch_of_node[id].is_none() {
            // A root (or a node whose parent comes later, which cannot happen).
            branch_of_node[id] = Some(out.len());
            out.push((None, start_of(id)));
        }
        let Some(own) = branch_of_node[id] else {
            continue;
        };
        let long = |c: &usize| {
            reach[*c] - start_of(*c) >= (FORK_LENGTH * thickness).max(FORK_BANDS * width)
        };
        let fork = children[id].iter().filter(|c| long(c)).count() >= 2;
        for &c in &children[id] {
            branch_of_node[c] = Some(if fork && long(&c) {
                out.push((Some(own), start_of(c)));
                out.len() - 1
            } else {
                own
            });
        }
    }
    let mut result: Vec<Branch> = out
        .iter()
        .map(|&(parent, _)| Branch {
            parent,
            cells: Vec::new(),
        })
        .collect();
    for (id, members) in nodes.iter().enumerate() {
        let Some(b) = branch_of_node[id] else {
            continue;
        };
        let from = out[b].1;
        for &i in members {
            result[b].cells.push((i, (d(i) - from).max(0.0)));
        }
    }
    for b in &mut result {
        b.cells.sort_by_key(|&(i, _)| i);
    }
    result
}
