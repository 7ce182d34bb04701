//! The auto rig's limbs as a tree before they are named: every body but the main one as a
//! limb (a head, hips, a thick knee), parents resolved, the pieces the cutting leaves of one
//! limb joined (a neck found as two halves, a thick joint inside a limb, a leg's hip piece),
//! so that each limb is one chain from the body out.

use std::collections::{BTreeMap, BTreeSet};

use super::controls::{body_vertices, limbs_of, main_body, vertices_of};
use super::parts::Role;
use crate::scene::CageSet;

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
    lateral: Option<usize>,
    heads: &BTreeSet<usize>,
) -> (Vec<Role>, BTreeMap<usize, usize>, BTreeSet<usize>) {
    let roles = separate_bodies(cages, roles);
    let parent_limb = present_parents(&roles, parent_limb);
    let (roles, parent_limb) = join_limbs_between_bodies(cages, &roles, &parent_limb, heads);
    attach_bodies(cages, &roles, &parent_limb, lateral, heads)
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
    heads: &BTreeSet<usize>,
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
    let Some(main) = main_body(&body_vertices, heads) else {
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
    lateral: Option<usize>,
    heads: &BTreeSet<usize>,
) -> (Vec<Role>, BTreeMap<usize, usize>, BTreeSet<usize>) {
    let body_vertices = body_vertices(cages, roles);
    let Some(main) = main_body(&body_vertices, heads) else {
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
            continue;
        }
        // A body touching neither the main body nor a limb grows from the body it shares most
        // with (a crown on a head larger than the torso, `head_over_legs`).
        let on_body = body_vertices
            .iter()
            .filter(|(b, _)| **b != main && **b != body)
            .map(|(&b, v)| (shared(vertices, v), std::cmp::Reverse(b)))
            .max()
            .filter(|(n, _)| *n > 0);
        if with_main == 0
            && best.is_none_or(|(n, _)| n == 0)
            && let Some((_, std::cmp::Reverse(other))) = on_body
        {
            parents.insert(pseudo(body), pseudo(other));
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
    // A thick thigh on the torso carrying one leg to the ground is the leg's first segment; a
    // thick shoulder off the centre line carrying one limb, the limb's (the mirrored beast's
    // mirrored solid is thick at the shoulders, whose bodies were `shoulder.L` carrying a
    // two-segment `arm.L`; a head carrying a long muzzle stays a body).
    let off_centre: BTreeSet<usize> = lateral
        .map(|axis| off_centre_bodies(cages, &body_vertices, main, axis))
        .unwrap_or_default()
        .into_iter()
        .map(pseudo)
        .collect();
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
        let [child] = children[..] else { continue };
        if bodies.contains(&child) {
            continue;
        }
        if reaches_ground(&roles, child) {
            append_limb(&mut roles, &mut parents, body, child, 2);
            bodies.remove(&body);
        } else if off_centre.contains(&body)
            && append_limb(&mut roles, &mut parents, body, child, 2)
        {
            bodies.remove(&body);
        }
    }
    legs_from_hip_pieces(cages, &mut roles, &mut parents, &bodies, &reaches_ground);
    (roles, parents, bodies)
}

/// The bodies other than `main` off the centre line: a body's middle further from the main
/// body's centre along the `lateral` axis than a quarter of the body's own width there (a
/// shoulder; not a head, nor a head turned a little).
fn off_centre_bodies(
    cages: &CageSet,
    body_vertices: &BTreeMap<usize, BTreeSet<u32>>,
    main: usize,
    lateral: usize,
) -> BTreeSet<usize> {
    let along = |vertices: &BTreeSet<u32>| {
        let values: Vec<f64> = vertices
            .iter()
            .filter_map(|&v| cages.vertices.get(v as usize).map(|p| p[lateral]))
            .collect();
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
        (lo, hi, mean)
    };
    let Some(main_vertices) = body_vertices.get(&main) else {
        return BTreeSet::new();
    };
    let (main_lo, main_hi, _) = along(main_vertices);
    let centre = 0.5 * (main_lo + main_hi);
    body_vertices
        .iter()
        .filter(|(b, vertices)| {
            let (lo, hi, middle) = along(vertices);
            **b != main && (middle - centre).abs() > 0.25 * (hi - lo)
        })
        .map(|(b, _)| *b)
        .collect()
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

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::test_cages::point_cages;
    use super::*;

    /// Leaf cages as boxes (one polygon over their 8 corners: the limb tree reads only which
    /// vertices the cages share and where they are), corners shared by position.
    fn boxes(extents: &[(DVec3, DVec3)]) -> CageSet {
        let corners: Vec<Vec<DVec3>> = extents
            .iter()
            .map(|&(lo, hi)| {
                (0..8)
                    .map(|corner| {
                        let pick =
                            |bit: usize, a: f64, b: f64| if corner & bit == 0 { a } else { b };
                        DVec3::new(
                            pick(1, lo.x, hi.x),
                            pick(2, lo.y, hi.y),
                            pick(4, lo.z, hi.z),
                        )
                    })
                    .collect()
            })
            .collect();
        point_cages(&corners)
    }

    /// A torso, a thick body beside it at `x` carrying a limb of two segments hanging from it
    /// above the ground.
    fn torso_with_a_body_at(x: f64) -> (CageSet, Vec<Role>) {
        let (a, b) = (x - 0.3, x + 0.3);
        let cages = boxes(&[
            (DVec3::new(-1.0, -0.5, -2.0), DVec3::new(1.0, 0.5, 2.0)),
            (DVec3::new(a, -0.5, 2.0), DVec3::new(b, 0.5, 2.6)),
            (DVec3::new(a, -0.5, 2.6), DVec3::new(b, 0.5, 3.2)),
            (DVec3::new(a, -0.5, 3.2), DVec3::new(b, 0.5, 3.8)),
        ]);
        let roles = vec![
            Role::Body { body: 0, slab: 0 },
            Role::Body { body: 1, slab: 0 },
            Role::Limb {
                limb: 0,
                segment: 0,
            },
            Role::Limb {
                limb: 0,
                segment: 1,
            },
        ];
        (cages, roles)
    }

    #[test]
    fn a_thick_shoulder_off_the_centre_line_is_its_arm_s_first_segment() {
        // On top of the torso's side (x 1.3, a quarter of its 0.6 width is 0.15 from the
        // centre): the body and the limb become one chain of three segments from the torso.
        let (cages, roles) = torso_with_a_body_at(1.3);
        let (roles, parents, bodies) =
            bodies_as_limbs(&cages, &roles, &BTreeMap::new(), Some(0), &BTreeSet::new());
        assert!(bodies.is_empty(), "{bodies:?}");
        let Role::Limb { limb, segment: 0 } = roles[1] else {
            panic!("the shoulder is {:?}", roles[1]);
        };
        assert_eq!(roles[2], Role::Limb { limb, segment: 1 });
        assert_eq!(roles[3], Role::Limb { limb, segment: 2 });
        assert!(!parents.contains_key(&limb), "{parents:?}");
        // Negative controls: with no lateral axis known, or on the centre line (a head with a
        // long muzzle), the body stays a body carrying the limb.
        for (x, lateral) in [(1.3, None), (0.05, Some(0))] {
            let (cages, roles) = torso_with_a_body_at(x);
            let (roles, parents, bodies) =
                bodies_as_limbs(&cages, &roles, &BTreeMap::new(), lateral, &BTreeSet::new());
            let Role::Limb { limb: body, .. } = roles[1] else {
                panic!("{:?}", roles[1]);
            };
            assert!(bodies.contains(&body), "x {x}: {bodies:?}");
            let Role::Limb { limb: arm, .. } = roles[2] else {
                panic!("{:?}", roles[2]);
            };
            assert_eq!(parents.get(&arm), Some(&body), "x {x}");
        }
    }
}
