//! A quadruped's head that the cut left in its body. A cat's head grows from its chest through
//! a neck nearly as thick as both, so the body narrows nowhere and has no saddle deep enough to
//! split (TOSCA's cat, an unseen mesh: its head was body slabs at every detail, its ears hung
//! from the root, and nothing turned the head). On a figure with front and back legs, the body
//! slabs well in front of the front legs' roots are its neck and head: they become a limb
//! `head`, one segment per slab from the shoulders out, carrying what grows from them.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;

use super::controls::{centroid, limbs_of, new_limb_id, vertices_of};
use super::parts::Role;
use crate::scene::CageSet;

/// How far in front of the front legs' roots a slab's middle must lie to be part of the head,
/// as a share of the distance from the back legs' roots to the front legs'.
const HEAD_REACH_SHARE: f64 = 0.25;

/// Makes the body slabs in front of the front legs a limb `head` (see the module) where the
/// rig has no head or neck and has both `leg.front` and `leg.back` legs; at least one slab
/// stays the body. Updates the leaves' roles, the limbs' parents (a limb rooted on the head,
/// an ear, hangs from it) and the names.
pub(super) fn head_out_of_body(
    cages: &CageSet,
    roles: &mut [Role],
    parent_limb: &mut BTreeMap<usize, usize>,
    names: &mut BTreeMap<usize, String>,
) {
    let has = |prefix: &str| {
        names
            .values()
            .any(|n| n == prefix || n.starts_with(&format!("{prefix}.")))
    };
    if has("head") || has("neck") {
        return;
    }
    let limbs = limbs_of(roles, parent_limb);
    let point = |v: &u32| cages.vertices.get(*v as usize).copied();
    let leaf_vertices = |leaves: &mut dyn Iterator<Item = usize>| -> BTreeSet<u32> {
        leaves
            .filter_map(|l| cages.leaves.get(l))
            .flat_map(vertices_of)
            .collect()
    };
    let body_leaves: Vec<usize> = roles
        .iter()
        .enumerate()
        .filter(|(_, r)| matches!(r, Role::Body { .. }))
        .map(|(l, _)| l)
        .collect();
    let body = leaf_vertices(&mut body_leaves.iter().copied());
    // Where the legs of one end meet the body: the middle of their first segments' rings.
    let roots_of = |end: &str| {
        let rings: Vec<DVec3> = names
            .iter()
            .filter(|(_, n)| n.starts_with(&format!("leg.{end}.")))
            .filter_map(|(limb, _)| limbs.get(limb))
            .filter(|record| record.parent.is_none())
            .filter_map(|record| record.segments.first())
            .flat_map(|first| leaf_vertices(&mut first.iter().copied()))
            .filter(|v| body.contains(v))
            .filter_map(|v| point(&v))
            .collect();
        centroid(rings.into_iter())
    };
    let (Some(front), Some(back)) = (roots_of("front"), roots_of("back")) else {
        return;
    };
    let along = DVec3::new(front.x - back.x, front.y - back.y, 0.0);
    let spacing = along.length();
    if spacing <= 0.0 {
        return;
    }
    let forward = along / spacing;
    // Each slab's leaves and how far its middle lies in front of the front legs.
    let mut slabs: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    for &leaf in &body_leaves {
        if let Some(&Role::Body { body, slab }) = roles.get(leaf) {
            slabs.entry((body, slab)).or_default().push(leaf);
        }
    }
    let mut ahead: Vec<(f64, Vec<usize>)> = slabs
        .into_values()
        .filter_map(|leaves| {
            let middle = centroid(
                leaf_vertices(&mut leaves.iter().copied())
                    .iter()
                    .filter_map(point),
            )?;
            let reach = (middle - front).dot(forward);
            (reach > HEAD_REACH_SHARE * spacing).then_some((reach, leaves))
        })
        .collect();
    if ahead.is_empty() || ahead.iter().map(|(_, l)| l.len()).sum::<usize>() >= body_leaves.len() {
        return;
    }
    ahead.sort_by(|a, b| a.0.total_cmp(&b.0));
    let head = new_limb_id(roles, parent_limb, names);
    let head_leaves: Vec<usize> = ahead.iter().flat_map(|(_, l)| l.iter().copied()).collect();
    for (segment, (_, leaves)) in ahead.iter().enumerate() {
        for &leaf in leaves {
            if let Some(role) = roles.get_mut(leaf) {
                *role = Role::Limb {
                    limb: head,
                    segment,
                };
            }
        }
    }
    let head_vertices = leaf_vertices(&mut head_leaves.iter().copied());
    let rest: Vec<usize> = body_leaves
        .iter()
        .copied()
        .filter(|l| !head_leaves.contains(l))
        .collect();
    let rest_vertices = leaf_vertices(&mut rest.iter().copied());
    // Limbs rooted on the head's slabs (ears) hang from it; legs never do.
    for (&limb, record) in &limbs {
        if record.parent.is_some() || names.get(&limb).is_some_and(|n| n.starts_with("leg")) {
            continue;
        }
        let Some(first) = record.segments.first() else {
            continue;
        };
        let root = leaf_vertices(&mut first.iter().copied());
        if root.intersection(&head_vertices).count() > root.intersection(&rest_vertices).count() {
            parent_limb.insert(limb, head);
        }
    }
    names.insert(head, "head".to_owned());
}
