//! A head larger than the torso it sits on. The main body is the largest body, and a head the
//! cut splits off above the shoulders is never it (`Parts::heads`). A head the cut finds as a
//! thick region of its own (split at a narrowing, or apart from the torso's thick cells) is
//! not known as a head: a cartoon elephant's head,
//! larger than its torso, became the main body, the torso a limb named `head` carrying the
//! legs and arms, the arms `ear.L` and `ear.R`. The body the legs grow from is the torso: the
//! largest body carrying no leg, right above a body that carries one, is a head.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;

use super::controls::{
    body_vertices, centroid, limb_vertex_sets, limbs_of, main_body, segment_vertex_sets,
};
use super::parts::Role;
use crate::scene::CageSet;

/// A leg reaches the figure's lowest tenth (naming's test of a leg, at the tree's level).
const LEG_BOTTOM_SHARE: f64 = 0.1;

/// How far below a head the top of the torso under it may lie, as a share of the head's
/// height.
const TORSO_GAP_SHARE: f64 = 0.1;

/// `heads` without the bodies a leg grows from (a torso whose rounded top the cut took for a
/// crown), and with the largest body where no leg grows from it while one grows from a body
/// right under it (see the module). A leg is a limb rooted on the body
/// (its first segment shares cage vertices with it) that reaches the figure's lowest tenth,
/// itself or through the limbs growing from it (legs on a stem).
pub(super) fn heads_over_legs(
    cages: &CageSet,
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
    heads: &BTreeSet<usize>,
) -> BTreeSet<usize> {
    let bodies = body_vertices(cages, roles);
    let limbs = limbs_of(roles, parent_limb);
    let point = |v: &u32| cages.vertices.get(*v as usize).copied();
    let (mesh_lo, mesh_hi) = crate::cage::bounds_of(&cages.vertices);
    let ground = mesh_lo.z + LEG_BOTTOM_SHARE * (mesh_hi.z - mesh_lo.z);
    let limb_vertices = limb_vertex_sets(cages, &limbs);
    let first_segment_vertices = segment_vertex_sets(cages, &limbs, 1);
    // Whether a limb, or one growing from it (legs on a stem), reaches the lowest tenth.
    let reaches_ground = |root: usize| {
        let mut stack = vec![root];
        let mut seen = BTreeSet::new();
        while let Some(limb) = stack.pop() {
            if !seen.insert(limb) {
                continue;
            }
            let Some(vertices) = limb_vertices.get(&limb) else {
                continue;
            };
            if vertices.iter().filter_map(point).any(|p| p.z < ground) {
                return true;
            }
            stack.extend(
                limbs
                    .iter()
                    .filter(|(_, r)| r.parent == Some(limb))
                    .map(|(&child, _)| child),
            );
        }
        false
    };
    let carries_leg = |body: &BTreeSet<u32>| {
        limbs.iter().any(|(&limb, record)| {
            record.parent.is_none()
                && first_segment_vertices
                    .get(&limb)
                    .is_some_and(|first| !first.is_disjoint(body))
                && reaches_ground(limb)
        })
    };
    // A body the legs grow from is the torso, never a head (a torso whose top the cut took
    // for a crown).
    let legs_bodies: BTreeSet<usize> = bodies
        .iter()
        .filter(|(_, vertices)| carries_leg(vertices))
        .map(|(&body, _)| body)
        .collect();
    let mut heads: BTreeSet<usize> = heads.difference(&legs_bodies).copied().collect();
    let Some(largest) = main_body(&bodies, &heads) else {
        return heads;
    };
    let points = |body: usize| -> Vec<DVec3> {
        bodies
            .get(&body)
            .map(|vertices| vertices.iter().filter_map(point).collect())
            .unwrap_or_default()
    };
    let largest_points = points(largest);
    let Some(largest_middle) = centroid(largest_points.iter().copied()) else {
        return heads;
    };
    let (largest_lo, largest_hi) = crate::cage::bounds_of(&largest_points);
    let gap = TORSO_GAP_SHARE * (largest_hi.z - largest_lo.z);
    // Right under it: its middle below the largest body's, its top within a tenth of the
    // largest body's height of its bottom (a thick knee far down a leg is no torso).
    let torso_below = legs_bodies.iter().any(|&body| {
        let body_points = points(body);
        let (_, hi) = crate::cage::bounds_of(&body_points);
        centroid(body_points.into_iter()).is_some_and(|m| m.z < largest_middle.z)
            && hi.z >= largest_lo.z - gap
    });
    if !legs_bodies.contains(&largest) && torso_below {
        heads.insert(largest);
    }
    heads
}
