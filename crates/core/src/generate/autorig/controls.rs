//! The auto rig's controls: one internal box per limb segment, named `<limb>.<n>` from the
//! body out, turning about its joint (`pivot`: the centroid of the ring its segment shares
//! with the segment or body before it) and carrying the segments after it (forward
//! kinematics: each control owns the next one's box); one `root` control over everything. The
//! ring between two segments of a limb is the later control's `joint`: it turns half as far,
//! as a mitre (`hierarchy::JointFrame`), so a knee bends at the knee. The ring where a limb
//! meets its body stays with the body, so turning a limb moves nothing of the other limbs.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;

use super::parts::Role;
use crate::coords::CoordinateKind;
use crate::hierarchy::box_grid;
use crate::scene::{CageSet, InternalCage, LeafCage};
/// Name of the control over the whole rig.
pub const ROOT_CONTROL: &str = "root";

/// One limb's cages: its segments (leaf cage indices), in order from its root.
#[derive(Debug, Clone)]
pub(super) struct Limb {
    /// The limb it grows from (a branch: an ear on a head top, a leg from a hip band).
    pub parent: Option<usize>,
    /// Leaf cages of each segment, in order from the root.
    pub segments: Vec<Vec<usize>>,
}

/// Each limb's segments and the nearest ancestor that still has cages.
pub(super) fn limbs_of(
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
) -> BTreeMap<usize, Limb> {
    let mut by_segment: BTreeMap<usize, BTreeMap<usize, Vec<usize>>> = BTreeMap::new();
    for (leaf, role) in roles.iter().enumerate() {
        if let Role::Limb { limb, segment } = *role {
            by_segment
                .entry(limb)
                .or_default()
                .entry(segment)
                .or_default()
                .push(leaf);
        }
    }
    let present: BTreeSet<usize> = by_segment.keys().copied().collect();
    by_segment
        .into_iter()
        .map(|(limb, segments)| {
            // The nearest ancestor that still has cages (merges may have taken a parent's).
            let mut parent = parent_limb.get(&limb).copied();
            for _ in 0..=parent_limb.len() {
                match parent {
                    Some(p) if !present.contains(&p) => parent = parent_limb.get(&p).copied(),
                    _ => break,
                }
            }
            let limb_record = Limb {
                parent: parent.filter(|p| present.contains(p) && *p != limb),
                segments: segments.into_values().collect(),
            };
            (limb, limb_record)
        })
        .collect()
}

/// Each body's cage vertices (the union of its slabs' cages).
pub(super) fn body_vertices(cages: &CageSet, roles: &[Role]) -> BTreeMap<usize, BTreeSet<u32>> {
    let mut vertices: BTreeMap<usize, BTreeSet<u32>> = BTreeMap::new();
    for (leaf, role) in cages.leaves.iter().zip(roles) {
        if let Role::Body { body, .. } = role {
            vertices.entry(*body).or_default().extend(vertices_of(leaf));
        }
    }
    vertices
}

/// The main body: the one with most cage vertices (body 0 is the first found, not the
/// largest), the lowest number on a tie; not one of `heads` (bodies split off as heads: a
/// head may be larger than the torso it sits on) where there is another.
pub(super) fn main_body(
    body_vertices: &BTreeMap<usize, BTreeSet<u32>>,
    heads: &BTreeSet<usize>,
) -> Option<usize> {
    body_vertices
        .iter()
        .max_by_key(|(b, v)| (!heads.contains(b), v.len(), std::cmp::Reverse(**b)))
        .map(|(b, _)| *b)
}

/// A limb number no leaf, parent link or name uses yet (for a limb split off another).
pub(super) fn new_limb_id(
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
    names: &BTreeMap<usize, String>,
) -> usize {
    roles
        .iter()
        .filter_map(|r| match r {
            Role::Limb { limb, .. } => Some(*limb),
            Role::Body { .. } => None,
        })
        .chain(parent_limb.iter().flat_map(|(&c, &p)| [c, p]))
        .chain(names.keys().copied())
        .max()
        .map_or(0, |l| l + 1)
}

/// Each limb's cage vertices: the union of the cages of all its segments (indices past the
/// leaves are skipped).
pub(super) fn limb_vertex_sets(
    cages: &CageSet,
    limbs: &BTreeMap<usize, Limb>,
) -> BTreeMap<usize, BTreeSet<u32>> {
    segment_vertex_sets(cages, limbs, usize::MAX)
}

/// Each limb's cage vertices in its first `segments` segments (all of them for `usize::MAX`),
/// as [`limb_vertex_sets`].
pub(super) fn segment_vertex_sets(
    cages: &CageSet,
    limbs: &BTreeMap<usize, Limb>,
    segments: usize,
) -> BTreeMap<usize, BTreeSet<u32>> {
    limbs
        .iter()
        .map(|(&limb, record)| {
            let vertices = (record.segments.iter().take(segments).flatten())
                .filter_map(|&l| cages.leaves.get(l))
                .flat_map(vertices_of)
                .collect();
            (limb, vertices)
        })
        .collect()
}

/// The cage vertices a leaf cage's faces use.
pub(super) fn vertices_of(leaf: &LeafCage) -> BTreeSet<u32> {
    leaf.faces.iter().flatten().copied().collect()
}

/// The mean of `points` (None when there are none).
pub(super) fn centroid(points: impl Iterator<Item = DVec3>) -> Option<DVec3> {
    let (sum, n) = points.fold((DVec3::ZERO, 0usize), |(s, n), p| (s + p, n + 1));
    (n > 0).then(|| sum / n as f64)
}

/// Adds the controls (see the module): per limb and segment a box `<limb>.<n>` with its pivot
/// and joint ring, and `root` over the rest.
pub(super) fn add_controls(
    cages: &mut CageSet,
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
    names: &BTreeMap<usize, String>,
) {
    let limbs = limbs_of(roles, parent_limb);
    let body_vertices: BTreeSet<u32> = cages
        .leaves
        .iter()
        .zip(roles)
        .filter(|(_, r)| matches!(r, Role::Body { .. }))
        .flat_map(|(l, _)| vertices_of(l))
        .collect();
    let depth_of = |limb: usize| {
        let mut depth = 0;
        let mut at = limbs[&limb].parent;
        while let Some(p) = at {
            depth += 1;
            if depth > limbs.len() {
                break;
            }
            at = limbs[&p].parent;
        }
        depth
    };
    let mut order: Vec<usize> = limbs.keys().copied().collect();
    order.sort_by_key(|&l| (depth_of(l), l));
    // Each segment's control owns its cages' vertices that nothing before owns, parents first,
    // segments from the root: the ring between two segments goes to the earlier one.
    let mut owner: BTreeMap<u32, (usize, usize)> = BTreeMap::new();
    struct Segment {
        owned: Vec<u32>,
        pivot: DVec3,
        ring: Vec<u32>,
        /// Where its box goes: (limb, segment) of the control owning it, None for the root.
        parent: Option<(usize, usize)>,
    }
    // Where two limbs that do not grow one from the other touch (legs close together), the
    // vertices they share stay with the root: a turn of one moves nothing of the other.
    let ancestors_of = |limb: usize| {
        let mut chain = BTreeSet::new();
        let mut at = limbs[&limb].parent;
        while let Some(p) = at {
            if !chain.insert(p) {
                break;
            }
            at = limbs[&p].parent;
        }
        chain
    };
    let limb_vertices = limb_vertex_sets(cages, &limbs);
    let mut segments: BTreeMap<(usize, usize), Segment> = BTreeMap::new();
    for &limb in &order {
        let ancestors = ancestors_of(limb);
        let foreign: BTreeSet<u32> = limb_vertices
            .iter()
            .filter(|&(&other, _)| {
                other != limb && !ancestors.contains(&other) && !ancestors_of(other).contains(&limb)
            })
            .flat_map(|(_, v)| v.iter().copied())
            .collect();
        for (k, leaves) in limbs[&limb].segments.iter().enumerate() {
            let all: BTreeSet<u32> = leaves
                .iter()
                .flat_map(|&l| vertices_of(&cages.leaves[l]))
                .filter(|v| !foreign.contains(v))
                .collect();
            let owned: Vec<u32> = all
                .iter()
                .copied()
                .filter(|v| !owner.contains_key(v) && !body_vertices.contains(v))
                .collect();
            // The joint: what the segment shares with what comes before it.
            let before: Vec<u32> = all
                .iter()
                .copied()
                .filter(|v| owner.contains_key(v) || body_vertices.contains(v))
                .collect();
            let parent = if k > 0 {
                Some((limb, k - 1))
            } else {
                // A branch hangs from the control of the limb it grows from owning most of
                // its root ring; a limb growing from a body, from the root.
                let mut votes: BTreeMap<(usize, usize), usize> = BTreeMap::new();
                for v in &before {
                    if let Some(&o) = owner.get(v)
                        && ancestors.contains(&o.0)
                    {
                        *votes.entry(o).or_insert(0) += 1;
                    }
                }
                votes
                    .into_iter()
                    .max_by_key(|&(o, n)| (n, std::cmp::Reverse(o)))
                    .map(|(o, _)| o)
            };
            let ring: Vec<u32> = match parent {
                Some(p) => before
                    .iter()
                    .copied()
                    .filter(|v| owner.get(v) == Some(&p))
                    .collect(),
                // A limb growing from a body: its root ring is the body's, which the root
                // control owns.
                None => before
                    .iter()
                    .copied()
                    .filter(|v| !owner.contains_key(v))
                    .collect(),
            };
            let pivot = centroid(before.iter().map(|&v| cages.vertices[v as usize]))
                .or_else(|| centroid(all.iter().map(|&v| cages.vertices[v as usize])))
                .unwrap_or(DVec3::ZERO);
            for &v in &owned {
                owner.insert(v, (limb, k));
            }
            segments.insert(
                (limb, k),
                Segment {
                    owned,
                    pivot,
                    ring,
                    parent,
                },
            );
        }
    }
    let diagonal = {
        let (lo, hi) = crate::cage::bounds_of(&cages.vertices);
        (hi - lo).length()
    };
    // Boxes from the tips in, each owning its vertices and the boxes hanging from it.
    let mut boxes_under: BTreeMap<Option<(usize, usize)>, Vec<u32>> = BTreeMap::new();
    // A child's box is made before its parent's: longest chain of parents first.
    let mut keys: Vec<(usize, usize)> = segments.keys().copied().collect();
    let chain_length = |key: (usize, usize)| {
        let mut n = 0;
        let mut at = segments[&key].parent;
        while let Some(p) = at {
            n += 1;
            if n > segments.len() {
                break;
            }
            at = segments[&p].parent;
        }
        n
    };
    keys.sort_by_key(|&key| (std::cmp::Reverse(chain_length(key)), key));
    let mut made: Vec<InternalCage> = Vec::new();
    for key in keys {
        let Some(segment) = segments.remove(&key) else {
            continue;
        };
        let mut owns = segment.owned;
        owns.extend(boxes_under.remove(&Some(key)).unwrap_or_default());
        if owns.is_empty() {
            continue;
        }
        owns.sort_unstable();
        let name = format!(
            "{}.{}",
            names
                .get(&key.0)
                .cloned()
                .unwrap_or_else(|| format!("limb{}", key.0)),
            key.1 + 1
        );
        let first = cages.vertices.len() as u32;
        let mut control = push_box(cages, &name, &owns, 0.1, diagonal);
        control.pivot = Some(segment.pivot);
        control.joint = segment.ring;
        made.push(control);
        boxes_under
            .entry(segment.parent)
            .or_default()
            .extend(first..cages.vertices.len() as u32);
    }
    // A ring whose control's parent did not make a box (it owned nothing) cannot bend.
    let leaf_vertices: BTreeSet<u32> = cages.leaves.iter().flat_map(vertices_of).collect();
    let limb_owned: BTreeSet<u32> = made.iter().flat_map(|c| c.owns.iter().copied()).collect();
    let mut rest: Vec<u32> = leaf_vertices.difference(&limb_owned).copied().collect();
    rest.extend(boxes_under.into_values().flatten());
    rest.sort_unstable();
    rest.dedup();
    // Owners by index into `made`; the root control (made below, owning `rest`) is `made.len()`,
    // so a limb growing from the body bends at its root ring as at any other joint.
    let root = made.len();
    let owner_of: BTreeMap<u32, usize> = made
        .iter()
        .enumerate()
        .flat_map(|(i, c)| c.owns.iter().map(move |&v| (v, i)))
        .chain(rest.iter().map(|&v| (v, root)))
        .collect();
    // A vertex bends with one joint: where two branches share their root ring (legs from one
    // hip band meet at the crotch), the first claims it.
    let mut in_ring: BTreeSet<u32> = BTreeSet::new();
    for control in &mut made {
        let own: BTreeSet<u32> = control.faces.iter().flatten().copied().collect();
        let parent = own.iter().find_map(|v| owner_of.get(v)).copied();
        let ring: Vec<u32> = control
            .joint
            .iter()
            .copied()
            .filter(|v| parent.is_some() && owner_of.get(v).copied() == parent)
            .filter(|v| in_ring.insert(*v))
            .collect();
        control.joint = ring;
    }
    // Controls in the order an artist reads them: by limb name, then from the body out.
    made.sort_by(|a, b| a.name.cmp(&b.name));
    cages.internals.extend(made);
    if !rest.is_empty() {
        let mut root = push_box(cages, ROOT_CONTROL, &rest, 0.05, diagonal);
        // On the ground under the rig's middle, as a character's root bone.
        let leaves: Vec<DVec3> = leaf_vertices
            .iter()
            .map(|&v| cages.vertices[v as usize])
            .collect();
        let (lo, hi) = crate::cage::bounds_of(&leaves);
        root.pivot = Some(DVec3::new(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z));
        cages.internals.push(root);
    }
}

/// A box cage around `owned` (padded by `padding` of its largest side, at least a thousandth
/// of `diagonal`), owning them; its vertices are appended to `cages`, the cage returned.
fn push_box(
    cages: &mut CageSet,
    name: &str,
    owned: &[u32],
    padding: f64,
    diagonal: f64,
) -> InternalCage {
    let points: Vec<DVec3> = owned.iter().map(|&v| cages.vertices[v as usize]).collect();
    let (lo, hi) = crate::cage::bounds_of(&points);
    let margin = (padding * (hi - lo).max_element()).max(1e-3 * diagonal);
    let (positions, faces) = box_grid(
        lo - DVec3::splat(margin),
        hi + DVec3::splat(margin),
        [1, 1, 1],
    );
    let base = cages.vertices.len() as u32;
    cages.vertices.extend(positions);
    InternalCage {
        name: name.to_owned(),
        kind: CoordinateKind::MeanValue,
        faces: faces
            .into_iter()
            .map(|f| f.into_iter().map(|v| v + base).collect())
            .collect(),
        owns: owned.to_vec(),
        pivot: None,
        joint: Vec::new(),
    }
}
