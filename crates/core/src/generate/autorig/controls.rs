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

/// Every body but the largest (a head as thick as the torso, a horse's head, a creature's hips)
/// as a limb of one segment, so that it is named and gets a control like a limb: it grows from
/// the limb it shares most vertices with where that is more than it shares with the main body
/// (a head on a neck; never from a limb rooted on it), and a limb rooted on it grows from it
/// (legs on hips). A neck found as two halves is joined into one chain from the torso, and a
/// thick joint inside a limb (a beast's knee) becomes one of its segments. Returns the roles
/// and the limbs' parents, and which limbs are still such bodies.
pub(super) fn bodies_as_limbs(
    cages: &CageSet,
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
) -> (Vec<Role>, BTreeMap<usize, usize>, BTreeSet<usize>) {
    let roles = separate_bodies(cages, roles);
    let parent_limb = present_parents(&roles, parent_limb);
    let (roles, parent_limb) = join_limbs_between_bodies(cages, &roles, &parent_limb);
    attach_bodies(cages, &roles, &parent_limb)
}

/// Each limb's parent as the nearest ancestor that still has cages (merges may have taken a
/// parent's), for the limbs that have cages.
fn present_parents(roles: &[Role], parent_limb: &BTreeMap<usize, usize>) -> BTreeMap<usize, usize> {
    limbs_of(roles, parent_limb)
        .into_iter()
        .filter_map(|(limb, record)| record.parent.map(|p| (limb, p)))
        .collect()
}

/// One body per connected group of its cages: a mirrored rig gives a thick region's twin (the
/// right knee of a left one) the same body, and the two would be named, parented and turned
/// as one (the mirrored beast's knees were one `head` carrying both shins).
fn separate_bodies(cages: &CageSet, roles: &[Role]) -> Vec<Role> {
    let mut roles = roles.to_vec();
    let mut next_body = roles
        .iter()
        .filter_map(|r| match r {
            Role::Body { body, .. } => Some(body + 1),
            Role::Limb { .. } => None,
        })
        .max()
        .unwrap_or(0);
    let mut leaves_of: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (leaf, role) in roles.iter().enumerate() {
        if let Role::Body { body, .. } = *role {
            leaves_of.entry(body).or_default().push(leaf);
        }
    }
    for leaves in leaves_of.values() {
        let vertices: Vec<BTreeSet<u32>> = leaves
            .iter()
            .map(|&l| cages.leaves.get(l).map(vertices_of).unwrap_or_default())
            .collect();
        // Groups by shared vertices, grown from each unvisited cage.
        let mut group = vec![usize::MAX; leaves.len()];
        let mut groups = 0;
        for start in 0..leaves.len() {
            if group[start] != usize::MAX {
                continue;
            }
            group[start] = groups;
            let mut stack = vec![start];
            while let Some(a) = stack.pop() {
                for b in 0..leaves.len() {
                    if group[b] == usize::MAX && !vertices[a].is_disjoint(&vertices[b]) {
                        group[b] = groups;
                        stack.push(b);
                    }
                }
            }
            groups += 1;
        }
        for g in 1..groups {
            for (k, &leaf) in leaves.iter().enumerate() {
                if group[k] == g
                    && let Role::Body { slab, .. } = roles[leaf]
                {
                    roles[leaf] = Role::Body {
                        body: next_body,
                        slab,
                    };
                }
            }
            next_body += 1;
        }
    }
    roles
}

/// A limb between the main body and a body that does not touch it (a neck up to a thick
/// head) is found as two limbs, each growing from its own end (limbs grow by distance from
/// any body): the half from the head is joined to the half from the torso, its segments
/// reversed, so that the neck is one chain from the torso carrying the head.
fn join_limbs_between_bodies(
    cages: &CageSet,
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
) -> (Vec<Role>, BTreeMap<usize, usize>) {
    let mut body_vertices: BTreeMap<usize, BTreeSet<u32>> = BTreeMap::new();
    // Per limb and segment, its vertices.
    let mut segments: BTreeMap<usize, BTreeMap<usize, BTreeSet<u32>>> = BTreeMap::new();
    for (leaf, role) in cages.leaves.iter().zip(roles) {
        match *role {
            Role::Body { body, .. } => body_vertices
                .entry(body)
                .or_default()
                .extend(vertices_of(leaf)),
            Role::Limb { limb, segment } => segments
                .entry(limb)
                .or_default()
                .entry(segment)
                .or_default()
                .extend(vertices_of(leaf)),
        }
    }
    let mut roles = roles.to_vec();
    let mut parents = parent_limb.clone();
    let Some(main) = body_vertices
        .iter()
        .max_by_key(|(b, v)| (v.len(), std::cmp::Reverse(**b)))
        .map(|(b, _)| *b)
    else {
        return (roles, parents);
    };
    let shared = |a: &BTreeSet<u32>, b: &BTreeSet<u32>| a.intersection(b).count();
    let main_vertices = &body_vertices[&main];
    type Segments = BTreeMap<usize, BTreeMap<usize, BTreeSet<u32>>>;
    fn first_of(segments: &Segments, limb: usize) -> Option<&BTreeSet<u32>> {
        segments.get(&limb).and_then(|s| s.values().next())
    }
    for (&outer, outer_vertices) in &body_vertices {
        if outer == main || shared(outer_vertices, main_vertices) > 0 {
            continue;
        }
        // The half growing from the outer body: rooted on it, touching neither the torso nor
        // anything it grows from.
        let halves: Vec<usize> = segments
            .keys()
            .copied()
            .filter(|&l| {
                !parents.contains_key(&l)
                    && first_of(&segments, l).is_some_and(|f| {
                        shared(f, outer_vertices) > 0 && shared(f, main_vertices) == 0
                    })
            })
            .collect();
        for half in halves {
            let Some((half_last, last_vertices)) = segments
                .get(&half)
                .and_then(|s| s.iter().next_back())
                .map(|(k, v)| (*k, v.clone()))
            else {
                continue;
            };
            // The half from the torso that its far end meets.
            let Some((n, from_torso)) = segments
                .iter()
                .filter(|(l, _)| **l != half)
                // Not a limb reaching the outer body itself (a neck from the torso to the
                // head: what grows from the head towards it is the head's, a muzzle).
                .filter(|(_, segs)| !segs.values().any(|v| shared(v, outer_vertices) > 0))
                .filter(|(l, _)| {
                    first_of(&segments, **l).is_some_and(|f| shared(f, main_vertices) > 0)
                })
                .map(|(&l, segs)| {
                    let all: BTreeSet<u32> = segs.values().flatten().copied().collect();
                    (shared(&all, &last_vertices), l)
                })
                .max()
            else {
                continue;
            };
            if n == 0 {
                continue;
            }
            let torso_last = segments[&from_torso]
                .keys()
                .next_back()
                .copied()
                .unwrap_or(0);
            for role in roles.iter_mut() {
                if let Role::Limb { limb, segment } = role
                    && *limb == half
                {
                    *role = Role::Limb {
                        limb: from_torso,
                        segment: torso_last + 1 + (half_last - *segment),
                    };
                }
            }
            for parent in parents.values_mut() {
                if *parent == half {
                    *parent = from_torso;
                }
            }
            let moved = segments.remove(&half).unwrap_or_default();
            let target = segments.entry(from_torso).or_default();
            for (segment, vertices) in moved {
                target
                    .entry(torso_last + 1 + (half_last - segment))
                    .or_default()
                    .extend(vertices);
            }
        }
    }
    (roles, parents)
}

/// See [`bodies_as_limbs`].
fn attach_bodies(
    cages: &CageSet,
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
) -> (Vec<Role>, BTreeMap<usize, usize>, BTreeSet<usize>) {
    let mut body_vertices: BTreeMap<usize, BTreeSet<u32>> = BTreeMap::new();
    for (leaf, role) in cages.leaves.iter().zip(roles) {
        if let Role::Body { body, .. } = role {
            body_vertices
                .entry(*body)
                .or_default()
                .extend(vertices_of(leaf));
        }
    }
    let Some(main) = body_vertices
        .iter()
        .max_by_key(|(b, v)| (v.len(), std::cmp::Reverse(**b)))
        .map(|(b, _)| *b)
    else {
        return (roles.to_vec(), parent_limb.clone(), BTreeSet::new());
    };
    let next_limb = roles
        .iter()
        .filter_map(|r| match r {
            Role::Limb { limb, .. } => Some(limb + 1),
            Role::Body { .. } => None,
        })
        .chain(parent_limb.iter().map(|(c, p)| c.max(p) + 1))
        .max()
        .unwrap_or(0);
    let pseudo = |body: usize| next_limb + body;
    let mut limb_vertices: BTreeMap<usize, BTreeSet<u32>> = BTreeMap::new();
    let mut first_segment: BTreeMap<usize, (usize, BTreeSet<u32>)> = BTreeMap::new();
    for (leaf, role) in cages.leaves.iter().zip(roles) {
        if let Role::Limb { limb, segment } = *role {
            let vertices = vertices_of(leaf);
            limb_vertices.entry(limb).or_default().extend(&vertices);
            let entry = first_segment
                .entry(limb)
                .or_insert((segment, BTreeSet::new()));
            if segment < entry.0 {
                *entry = (segment, BTreeSet::new());
            }
            if segment == entry.0 {
                entry.1.extend(vertices);
            }
        }
    }
    let mut parents = parent_limb.clone();
    let shared = |a: &BTreeSet<u32>, b: &BTreeSet<u32>| a.intersection(b).count();
    // The body each limb's first segment shares most vertices with (where it is rooted); a
    // limb touching the main body is not rooted on a body further out that does not (a neck
    // touching the torso and a head).
    let touches_main: BTreeSet<usize> = body_vertices
        .iter()
        .filter(|(b, v)| **b == main || shared(v, &body_vertices[&main]) > 0)
        .map(|(b, _)| *b)
        .collect();
    let rooted_on: BTreeMap<usize, usize> = first_segment
        .iter()
        .filter_map(|(&limb, (_, first))| {
            let on_main = shared(first, &body_vertices[&main]) > 0;
            body_vertices
                .iter()
                .filter(|(b, _)| !on_main || touches_main.contains(b))
                .map(|(&b, v)| (shared(first, v), std::cmp::Reverse(b)))
                .max()
                .filter(|(n, _)| *n > 0)
                .map(|(_, std::cmp::Reverse(b))| (limb, b))
        })
        .collect();
    // A body on a limb (a head on a neck, a thick knee on a thigh) grows from that limb; not
    // from a limb rooted on the body itself (the shin under that knee), which grows from it.
    let mut on_limb: BTreeSet<usize> = BTreeSet::new();
    for (&body, vertices) in body_vertices.iter().filter(|(b, _)| **b != main) {
        let with_main = shared(vertices, &body_vertices[&main]);
        let best = limb_vertices
            .iter()
            .filter(|(l, _)| rooted_on.get(l) != Some(&body))
            .map(|(&l, v)| (shared(vertices, v), l))
            .max();
        if let Some((n, limb)) = best
            && n > with_main
        {
            parents.insert(pseudo(body), limb);
            on_limb.insert(body);
        }
    }
    // A root limb rooted on another body grows from that body (legs on hips, a shin under a
    // thick knee, a muzzle on a head).
    for (&limb, &body) in &rooted_on {
        if !parents.contains_key(&limb) && body != main {
            parents.insert(limb, pseudo(body));
        }
    }
    // No limb may end up its own ancestor (a branch of a limb rooted on the body it carries).
    let keys: Vec<usize> = parents.keys().copied().collect();
    for start in keys {
        let mut at = parents.get(&start).copied();
        for _ in 0..parents.len() {
            match at {
                Some(p) if p == start => {
                    parents.remove(&start);
                    break;
                }
                Some(p) => at = parents.get(&p).copied(),
                None => break,
            }
        }
    }
    let mut roles: Vec<Role> = roles
        .iter()
        .map(|&role| match role {
            Role::Body { body, .. } if body != main => Role::Limb {
                limb: pseudo(body),
                segment: 0,
            },
            other => other,
        })
        .collect();
    let mut bodies: BTreeSet<usize> = body_vertices
        .keys()
        .filter(|&&b| b != main)
        .map(|&b| pseudo(b))
        .collect();
    for body in on_limb {
        merge_through_thick_joint(&mut roles, &mut parents, &mut bodies, pseudo(body));
    }
    // A thick thigh on the torso carrying one leg to the ground is the leg's first segment.
    let (lo, hi) = crate::cage::bounds_of(&cages.vertices);
    let ground = lo.z + 0.2 * (hi.z - lo.z);
    let reaches_ground = |roles: &[Role], limb: usize| {
        cages.leaves.iter().zip(roles).any(|(leaf, role)| {
            matches!(role, Role::Limb { limb: l, .. } if *l == limb)
                && vertices_of(leaf)
                    .iter()
                    .any(|&v| cages.vertices.get(v as usize).is_some_and(|p| p.z < ground))
        })
    };
    for body in bodies.clone() {
        if parents.contains_key(&body) {
            continue;
        }
        let children: Vec<usize> = parents
            .iter()
            .filter(|(_, p)| **p == body)
            .map(|(c, _)| *c)
            .collect();
        let [leg] = children[..] else { continue };
        if reaches_ground(&roles, leg) && !bodies.contains(&leg) {
            append_limb(&mut roles, &mut parents, body, leg, 2);
            bodies.remove(&body);
        }
    }
    legs_from_hip_pieces(cages, &mut roles, &mut parents, &bodies, &reaches_ground);
    (roles, parents, bodies)
}

/// Legs touching at the crotch grow from a hip band outside the body that the rig cuts into
/// one piece per side (one limb of one segment each, the legs hanging from one of them): each
/// piece touching exactly one leg becomes that leg's first segment, so a standing human's legs
/// are `leg.L.1 …` from the hip instead of `arm.R.1` carrying both legs and a loose `arm.L.001`.
fn legs_from_hip_pieces(
    cages: &CageSet,
    roles: &mut [Role],
    parents: &mut BTreeMap<usize, usize>,
    bodies: &BTreeSet<usize>,
    reaches_ground: &dyn Fn(&[Role], usize) -> bool,
) {
    let mut vertices: BTreeMap<usize, BTreeSet<u32>> = BTreeMap::new();
    let mut segments: BTreeMap<usize, BTreeSet<usize>> = BTreeMap::new();
    for (leaf, role) in cages.leaves.iter().zip(roles.iter()) {
        if let Role::Limb { limb, segment } = *role {
            vertices.entry(limb).or_default().extend(vertices_of(leaf));
            segments.entry(limb).or_default().insert(segment);
        }
    }
    let mut legs: BTreeSet<usize> = vertices
        .keys()
        .copied()
        .filter(|&l| !bodies.contains(&l) && reaches_ground(roles, l))
        .collect();
    // Hip pieces: root limbs of one segment above the ground whose children are all legs.
    let pieces: Vec<usize> = vertices
        .keys()
        .copied()
        .filter(|&p| {
            !bodies.contains(&p)
                && !parents.contains_key(&p)
                && !legs.contains(&p)
                && segments.get(&p).is_some_and(|s| s.len() == 1)
                && parents
                    .iter()
                    .filter(|(_, q)| **q == p)
                    .all(|(c, _)| legs.contains(c))
        })
        .collect();
    let piece_set: BTreeSet<usize> = pieces.iter().copied().collect();
    for piece in pieces {
        let touching: Vec<usize> = legs
            .iter()
            .copied()
            .filter(|l| parents.get(l).is_none_or(|q| piece_set.contains(q)))
            .filter(|l| !vertices[l].is_disjoint(&vertices[&piece]))
            .collect();
        if let [leg] = touching[..]
            && append_limb(roles, parents, piece, leg, 1)
        {
            legs.remove(&leg);
        }
    }
}

/// Appends limb `lower`'s segments (at least `min_segments` of them) after limb `upper`'s last,
/// in order, and hangs what grew from `lower` from `upper`. Returns whether it did.
fn append_limb(
    roles: &mut [Role],
    parents: &mut BTreeMap<usize, usize>,
    upper: usize,
    lower: usize,
    min_segments: usize,
) -> bool {
    let segments_of = |roles: &[Role], limb: usize| -> BTreeSet<usize> {
        roles
            .iter()
            .filter_map(|r| match *r {
                Role::Limb { limb: l, segment } if l == limb => Some(segment),
                _ => None,
            })
            .collect()
    };
    let lower_segments = segments_of(roles, lower);
    let (Some(&upper_last), Some(&lower_first)) =
        (segments_of(roles, upper).last(), lower_segments.first())
    else {
        return false;
    };
    if lower_segments.len() < min_segments {
        return false;
    }
    for role in roles.iter_mut() {
        if let Role::Limb { limb, segment } = role
            && *limb == lower
        {
            *role = Role::Limb {
                limb: upper,
                segment: upper_last + 1 + (*segment - lower_first),
            };
        }
    }
    parents.remove(&lower);
    for parent in parents.values_mut() {
        if *parent == lower {
            *parent = upper;
        }
    }
    true
}

/// A thick joint inside one limb (a beast's knee or elbow, thick enough to be a body): where
/// `body` grows from a limb that carries nothing else and carries exactly one limb of two or
/// more segments (the shin, the forearm; not a short muzzle on a head), the three are one limb,
/// the body a segment between the other two, so that the leg is named and turned as one chain
/// (`leg.L.1` the thigh, `.2` the knee, `.3` the shin …).
fn merge_through_thick_joint(
    roles: &mut [Role],
    parents: &mut BTreeMap<usize, usize>,
    bodies: &mut BTreeSet<usize>,
    body: usize,
) {
    let Some(&upper) = parents.get(&body) else {
        return;
    };
    let children_of = |limb: usize| -> Vec<usize> {
        parents
            .iter()
            .filter(|(_, p)| **p == limb)
            .map(|(c, _)| *c)
            .collect()
    };
    let (Ok([from_upper]), Ok([lower])) = (
        <[usize; 1]>::try_from(children_of(upper)),
        <[usize; 1]>::try_from(children_of(body)),
    ) else {
        return;
    };
    if from_upper != body || bodies.contains(&lower) {
        return;
    }
    let joined = roles
        .iter()
        .any(|r| matches!(r, Role::Limb { limb, .. } if *limb == lower))
        && {
            // The body's one segment after the upper limb, then the lower limb after it.
            let mut trial = roles.to_vec();
            let mut trial_parents = parents.clone();
            append_limb(&mut trial, &mut trial_parents, body, lower, 2)
                && append_limb(&mut trial, &mut trial_parents, upper, body, 1)
                && {
                    roles.copy_from_slice(&trial);
                    *parents = trial_parents;
                    true
                }
        };
    if joined {
        bodies.remove(&body);
    }
}

/// Name of the control over the whole rig.
pub const ROOT_CONTROL: &str = "root";

/// One limb's cages: its segments (leaf cage indices), in order from its root.
#[derive(Debug, Clone)]
struct Limb {
    /// The limb it grows from (a branch: an ear on a head top, a leg from a hip band).
    parent: Option<usize>,
    /// Leaf cages of each segment, in order from the root.
    segments: Vec<Vec<usize>>,
}

fn limbs_of(roles: &[Role], parent_limb: &BTreeMap<usize, usize>) -> BTreeMap<usize, Limb> {
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

fn vertices_of(leaf: &LeafCage) -> BTreeSet<u32> {
    leaf.faces.iter().flatten().copied().collect()
}

fn centroid(points: impl Iterator<Item = DVec3>) -> Option<DVec3> {
    let (sum, n) = points.fold((DVec3::ZERO, 0usize), |(s, n), p| (s + p, n + 1));
    (n > 0).then(|| sum / n as f64)
}

/// The rig's axes for naming, in its Z-up frame: the sign along the lateral (left–right) axis
/// that is the figure's left, the axis a lying body runs along with the head's sign, and
/// where the main body and the whole rig lie.
struct Frame {
    left_sign: f64,
    /// The horizontal axis a lying body (a quadruped's) runs along, with the head's sign.
    forward: Option<(usize, f64)>,
    body_lo: DVec3,
    body_hi: DVec3,
    mesh_lo: DVec3,
    mesh_hi: DVec3,
}

/// Names every limb by role and side, Blender's way: `leg.L`, `arm.R`, `leg.front.L` …
/// `leg.back.R` on a quadruped, `tail`, `head`, `ear.L`; any other limb `limb.N`. Sides from
/// the rig's lateral axis (`mirror` where given), `.L` on +X as in Blender (a figure facing
/// −Y has its left on +X).
pub(super) fn limb_names(
    cages: &CageSet,
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
    bodies: &BTreeSet<usize>,
    mirror: Option<(usize, f64)>,
) -> BTreeMap<usize, String> {
    let limbs = limbs_of(roles, parent_limb);
    let point = |v: &u32| cages.vertices[*v as usize];
    let (mesh_lo, mesh_hi) = crate::cage::bounds_of(&cages.vertices);
    // The main body: the body with most vertices (body 0 is the first found, not the largest).
    let mut body_sizes: BTreeMap<usize, BTreeSet<u32>> = BTreeMap::new();
    for (leaf, role) in cages.leaves.iter().zip(roles) {
        if let Role::Body { body, .. } = role {
            body_sizes
                .entry(*body)
                .or_default()
                .extend(vertices_of(leaf));
        }
    }
    let main_key = body_sizes
        .iter()
        .max_by_key(|(b, s)| (s.len(), std::cmp::Reverse(**b)))
        .map(|(b, _)| *b);
    let main_body: Vec<DVec3> = main_key
        .and_then(|b| body_sizes.get(&b))
        .map(|s| s.iter().map(point).collect())
        .unwrap_or_else(|| cages.vertices.clone());
    // A second thick region beside a lying body is its head (a horse's, a cow's): the largest
    // body other than the main one, whether still a body or already one of `bodies`.
    let second_body = body_sizes
        .iter()
        .filter(|(b, _)| Some(**b) != main_key)
        .map(|(_, s)| s.clone())
        .chain(bodies.iter().map(|limb| {
            cages
                .leaves
                .iter()
                .zip(roles)
                .filter(|(_, r)| matches!(r, Role::Limb { limb: l, .. } if l == limb))
                .flat_map(|(leaf, _)| vertices_of(leaf))
                .collect::<BTreeSet<u32>>()
        }))
        .max_by_key(BTreeSet::len)
        .and_then(|s| centroid(s.iter().map(point)));
    let (body_lo, body_hi) = crate::cage::bounds_of(&main_body);
    let body_extent = body_hi - body_lo;
    let lying = body_extent.x.max(body_extent.y) > body_extent.z;
    let mesh_extent = mesh_hi - mesh_lo;
    let lateral = match mirror {
        Some((axis, _)) if axis < 2 => axis,
        _ if lying && body_extent.x >= body_extent.y => 1,
        _ if lying => 0,
        _ if mesh_extent.y > mesh_extent.x => 1,
        _ => 0,
    };
    let body_centre = 0.5 * (body_lo + body_hi);
    let centre = match mirror {
        Some((axis, plane)) if axis == lateral => plane,
        _ => body_centre[lateral],
    };
    // Per limb: where it starts (the ring it shares with what it grows from), where it ends.
    struct Shape {
        root: DVec3,
        /// The centroid of the limb's vertices and their extent along the lateral axis.
        middle: DVec3,
        width: f64,
        tip: DVec3,
    }
    let shapes: BTreeMap<usize, Shape> = limbs
        .iter()
        .filter_map(|(&limb, record)| {
            let all: BTreeSet<u32> = record
                .segments
                .iter()
                .flatten()
                .flat_map(|&l| vertices_of(&cages.leaves[l]))
                .collect();
            let first: BTreeSet<u32> = record
                .segments
                .first()?
                .iter()
                .flat_map(|&l| vertices_of(&cages.leaves[l]))
                .collect();
            let others: BTreeSet<u32> = cages
                .leaves
                .iter()
                .enumerate()
                .filter(|(l, _)| !record.segments.iter().flatten().any(|m| m == l))
                .flat_map(|(_, leaf)| vertices_of(leaf))
                .collect();
            let ring: Vec<DVec3> = first.intersection(&others).map(point).collect();
            let ring = if ring.is_empty() {
                first.iter().map(point).collect()
            } else {
                ring
            };
            let root = centroid(ring.iter().copied())?;
            let middle = centroid(all.iter().map(point))?;
            let (lo, hi) = all
                .iter()
                .map(point)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p[lateral]), hi.max(p[lateral]))
                });
            // The tip: the limb's vertex farthest from its root.
            let tip = all
                .iter()
                .map(point)
                .max_by(|a, b| (*a - root).length().total_cmp(&(*b - root).length()))?;
            Some((
                limb,
                Shape {
                    root,
                    middle,
                    width: hi - lo,
                    tip,
                },
            ))
        })
        .collect();
    let height = mesh_extent.z.max(1e-12);
    // On the centre line where the limb straddles it (a tail, a neck: its middle within a
    // quarter of its own width of the plane); legs close together are each on one side.
    let side_of = |s: &Shape| {
        let offset = s.middle[lateral] - centre;
        if offset.abs() <= 0.25 * s.width {
            0.0
        } else {
            offset.signum()
        }
    };
    let is_leg = |s: &Shape| s.tip.z - mesh_lo.z < 0.2 * height && s.tip.z < s.root.z;
    // Which way a lying body faces: towards the limbs that reach well above it (a neck,
    // ears, horns; a quarter of its height), else towards a second thick region (its head), else −Y as in Blender.
    let forward = lying.then(|| {
        let axis = 1 - lateral;
        let raised = centroid(
            shapes
                .iter()
                .filter(|(limb, _)| !bodies.contains(limb))
                .map(|(_, s)| s)
                .filter(|s| s.tip.z > body_hi.z + 0.25 * body_extent.z && !is_leg(s))
                .map(|s| s.root),
        );
        // Else side limbs out from the body's upper half (a cow's ears on a head the body
        // holds); legs hang from its lower half.
        let upper = || {
            centroid(
                shapes
                    .iter()
                    .filter(|(limb, _)| !bodies.contains(limb))
                    .map(|(_, s)| s)
                    .filter(|s| !is_leg(s) && s.root.z > body_centre.z && side_of(s) != 0.0)
                    .map(|s| s.root),
            )
        };
        let head = raised.or(second_body).or_else(upper);
        let sign = head
            .map(|h| (h[axis] - body_centre[axis]).signum())
            .filter(|s| *s != 0.0)
            .unwrap_or(-1.0);
        (axis, sign)
    });
    let frame = Frame {
        left_sign: left_sign(lateral, forward),
        forward,
        body_lo,
        body_hi,
        mesh_lo,
        mesh_hi,
    };
    // Towards the head: the front half of a lying body, the upper half of a standing one.
    let headwards_of = |s: &Shape| match frame.forward {
        Some((axis, sign)) => (s.middle[axis] - body_centre[axis]) * sign > 0.0,
        None => s.middle.z >= body_centre.z,
    };
    let mut base: BTreeMap<usize, (String, Option<char>)> = BTreeMap::new();
    for (&limb, s) in &shapes {
        // A thick region of its own (a head, hips) is on the centre line when its middle is
        // within half its width of the plane (a head turned a little stays a head), or when it
        // stands above a lying body's top (a horse's head turned to a side).
        let raised_body = frame.forward.is_some() && s.middle.z > frame.body_hi.z;
        // A thick region grown from a limb is a head on its neck (a horse's turned head).
        let head_on_neck =
            bodies.contains(&limb) && limbs[&limb].parent.is_some_and(|p| !bodies.contains(&p));
        let carries_head = limbs
            .iter()
            .any(|(l, record)| record.parent == Some(limb) && bodies.contains(l))
            && !bodies.contains(&limb);
        let centred_body = bodies.contains(&limb)
            && ((s.middle[lateral] - centre).abs() <= 0.5 * s.width || raised_body);
        let side = if head_on_neck || carries_head || centred_body {
            0.0
        } else {
            side_of(s)
        };
        let side_letter = (side != 0.0).then_some(if side == frame.left_sign { 'L' } else { 'R' });
        let parent_is_head = limbs[&limb].parent.is_some_and(|p| {
            let Some(ps) = shapes.get(&p) else {
                return false;
            };
            if bodies.contains(&p) {
                // A thick region towards the head on the centre line, or on a neck.
                let centred = (ps.middle[lateral] - centre).abs() <= 0.5 * ps.width
                    || (frame.forward.is_some() && ps.middle.z > frame.body_hi.z);
                limbs[&p].parent.is_some_and(|q| !bodies.contains(&q))
                    || (centred && headwards_of(ps))
            } else {
                side_of(ps) == 0.0
                    && !is_leg(ps)
                    && (ps.tip.z > frame.body_hi.z
                        || matches!(centre_role(ps.root, ps.tip, &frame), "head" | "neck"))
            }
        });
        // Ears (horns) stand on top: a side limb rooted in the body's top fifth (or on a
        // head) that reaches above it.
        let body_height = frame.body_hi.z - frame.body_lo.z;
        let on_top = s.root.z > frame.body_hi.z - 0.2 * body_height && s.tip.z > frame.body_hi.z;
        let headwards = headwards_of(s);
        // A centre limb grows from it (a thick neck base carrying the neck and head).
        let carries_centre_limb = limbs.iter().any(|(l, record)| {
            record.parent == Some(limb)
                && shapes
                    .get(l)
                    .is_some_and(|c| (c.middle[lateral] - centre).abs() <= 0.25 * c.width)
        });
        // Ears and horns rise from where they grow (a muzzle, a leg do not).
        let rises = s.tip.z - s.root.z > 0.3 * (s.tip - s.root).length();
        let role = if head_on_neck {
            "head"
        } else if carries_head {
            "neck"
        } else if bodies.contains(&limb) {
            // A thick region of its own: a head on the centre line towards the head (a neck
            // where a centre limb grows from it), else hips; shoulders and hips at the sides.
            match (side == 0.0, headwards) {
                (true, true) if carries_centre_limb => "neck",
                (true, true) => "head",
                (true, false) => "hips",
                (false, true) => "shoulder",
                (false, false) => "hip",
            }
        } else if is_leg(s) {
            "leg"
        } else if side != 0.0 && ((parent_is_head && s.tip.z > s.root.z) || (on_top && rises)) {
            "ear"
        } else if side == 0.0 {
            centre_role(s.root, s.tip, &frame)
        } else if frame.forward.is_none() {
            "arm"
        } else if (rises && s.tip.z > frame.body_hi.z)
            || (headwards && s.root.z > body_centre.z && limbs[&limb].parent.is_none())
        {
            // On a lying body: rising above it, or out from the upper front (a cow's ears).
            "ear"
        } else {
            "limb"
        };
        base.insert(limb, (role.to_owned(), side_letter));
    }
    // A pair of like limbs from one place that both fall on one side of the plane (a bunny's
    // ears both leaning one way) are told apart by which lies further to the left.
    let mut groups: BTreeMap<(String, Option<usize>), Vec<usize>> = BTreeMap::new();
    for (&limb, (role, letter)) in &base {
        if letter.is_some() && role != "limb" {
            groups
                .entry((role.clone(), limbs[&limb].parent))
                .or_default()
                .push(limb);
        }
    }
    for ((role, _), pair) in groups {
        let [a, b] = pair[..] else { continue };
        let other_side_taken = base
            .iter()
            .any(|(l, (r, letter))| *r == role && *letter != base[&a].1 && *l != a && *l != b);
        if base[&a].1 != base[&b].1 || other_side_taken {
            continue;
        }
        let leftness = |l: usize| shapes[&l].middle[lateral] * frame.left_sign;
        let (left, right) = if leftness(a) >= leftness(b) {
            (a, b)
        } else {
            (b, a)
        };
        base.insert(left, (role.clone(), Some('L')));
        base.insert(right, (role, Some('R')));
    }
    // Quadrupeds: legs on a side in order along the body, front first.
    let mut names: BTreeMap<usize, String> = BTreeMap::new();
    for letter in [Some('L'), Some('R')] {
        let mut legs: Vec<usize> = base
            .iter()
            .filter(|(_, (r, s))| r == "leg" && *s == letter)
            .map(|(&l, _)| l)
            .collect();
        if legs.len() < 2 {
            continue;
        }
        let (axis, sign) = frame.forward.unwrap_or((1, -1.0));
        legs.sort_by(|a, b| {
            let along = |l: &usize| -sign * shapes[l].root[axis];
            along(a).total_cmp(&along(b))
        });
        let places: &[&str] = match legs.len() {
            2 => &["front", "back"],
            3 => &["front", "mid", "back"],
            _ => &[],
        };
        for (k, limb) in legs.iter().enumerate() {
            let place = places
                .get(k)
                .map(|p| (*p).to_owned())
                .unwrap_or_else(|| format!("{}", k + 1));
            if let Some(letter) = letter {
                names.insert(*limb, format!("leg.{place}.{letter}"));
            }
        }
    }
    let mut taken: BTreeMap<String, usize> = BTreeMap::new();
    let mut others = 0;
    for (&limb, (role, letter)) in &base {
        if names.contains_key(&limb) {
            continue;
        }
        let name = if role == "limb" {
            others += 1;
            format!("limb.{others}")
        } else {
            match letter {
                Some(l) => format!("{role}.{l}"),
                None => role.clone(),
            }
        };
        names.insert(limb, name);
    }
    // Names taken twice get Blender's numbered copies: `arm.L`, `arm.L.001`.
    let mut result = BTreeMap::new();
    for (limb, name) in names {
        let n = taken.entry(name.clone()).or_insert(0);
        *n += 1;
        let unique = if *n == 1 {
            name
        } else {
            format!("{name}.{:03}", *n - 1)
        };
        result.insert(limb, unique);
    }
    result
}

/// Which sign along the lateral axis is the figure's left: +X for an upright figure (facing
/// −Y, as Blender's), and left = up × forward for a lying one.
fn left_sign(lateral: usize, forward: Option<(usize, f64)>) -> f64 {
    match forward {
        Some((axis, sign)) => {
            let mut f = DVec3::ZERO;
            f[axis] = sign;
            DVec3::Z.cross(f)[lateral].signum()
        }
        None => 1.0,
    }
}

/// The role of a limb on the centre line: above a standing body a head (a neck with its head),
/// from its lower half a tail; at a lying body's front end a head (a neck where it rises above
/// the body), at its back end a tail; else an unnamed limb.
fn centre_role(root: DVec3, tip: DVec3, frame: &Frame) -> &'static str {
    let height = (frame.mesh_hi.z - frame.mesh_lo.z).max(1e-12);
    match frame.forward {
        None if tip.z > frame.body_hi.z - 0.05 * height => "head",
        // Hanging from a standing body's lower half and not reaching the ground: a tail.
        None if root.z < 0.5 * (frame.body_lo.z + frame.body_hi.z) => "tail",
        None => "limb",
        Some((axis, sign)) => {
            let body_mid = 0.5 * (frame.body_lo[axis] + frame.body_hi[axis]);
            if (root[axis] - body_mid) * sign > 0.0 {
                if tip.z > frame.body_hi.z {
                    "neck"
                } else {
                    "head"
                }
            } else if tip.z < frame.body_hi.z + 0.25 * height {
                "tail"
            } else {
                "limb"
            }
        }
    }
}

/// Renames the leaf cages of each limb `<limb>_<n>` (`leg.L_2`), n counting its segments from
/// the root as its controls do (a thick joint merged into a limb is one of them), pieces of
/// one segment lettered `leg.L_2b` as before.
pub(super) fn rename_limb_cages(
    cages: &mut CageSet,
    roles: &[Role],
    names: &BTreeMap<usize, String>,
) {
    let mut segments: BTreeMap<usize, BTreeSet<usize>> = BTreeMap::new();
    for role in roles {
        if let Role::Limb { limb, segment } = *role {
            segments.entry(limb).or_default().insert(segment);
        }
    }
    let mut taken: BTreeMap<String, usize> = BTreeMap::new();
    for (leaf, role) in cages.leaves.iter_mut().zip(roles) {
        if let Role::Limb { limb, segment } = *role
            && let Some(name) = names.get(&limb)
        {
            let ordinal = segments[&limb].range(..segment).count() + 1;
            let base = format!("{name}_{ordinal}");
            let n = taken.entry(base.clone()).or_insert(0);
            *n += 1;
            leaf.name = if *n == 1 {
                base
            } else {
                format!("{base}{}", char::from(b'a' + (*n as u8 - 1).min(25)))
            };
        }
    }
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
    let limb_vertices: BTreeMap<usize, BTreeSet<u32>> = limbs
        .iter()
        .map(|(&limb, record)| {
            let vertices = record
                .segments
                .iter()
                .flatten()
                .flat_map(|&l| vertices_of(&cages.leaves[l]))
                .collect();
            (limb, vertices)
        })
        .collect();
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
                None => Vec::new(),
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
    let owner_of: BTreeMap<u32, usize> = made
        .iter()
        .enumerate()
        .flat_map(|(i, c)| c.owns.iter().map(move |&v| (v, i)))
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
