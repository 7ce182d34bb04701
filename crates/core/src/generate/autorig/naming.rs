//! Limb names by role and side, Blender's way (`leg.L`, `leg.front.R`, `neck`, `head`,
//! `ear.L`, `limb.N`), from the shape of each limb in the rig's Z-up frame; the leaf cages
//! renamed after their limbs.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;

use super::controls::{
    body_vertices, centroid, limb_vertex_sets, limbs_of, main_body, vertices_of,
};
use super::parts::Role;
use crate::scene::CageSet;

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
/// the rig's lateral axis (`mirror` where given, else the horizontal axis the mesh is clearly
/// symmetric across, `symmetric`, where two limbs mirror each other across it), `.L` on +X as
/// in Blender (a figure facing −Y has its left on +X).
pub(super) fn limb_names(
    cages: &CageSet,
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
    bodies: &BTreeSet<usize>,
    mirror: Option<(usize, f64)>,
    symmetric: Option<usize>,
    heads: &BTreeSet<usize>,
) -> BTreeMap<usize, String> {
    let limbs = limbs_of(roles, parent_limb);
    let point = |v: &u32| cages.vertices[*v as usize];
    let (mesh_lo, mesh_hi) = crate::cage::bounds_of(&cages.vertices);
    let body_sizes = body_vertices(cages, roles);
    let main_key = main_body(&body_sizes, heads);
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
    // A body is lying where it is longer than tall across its middle plane: with a known
    // left-right axis (the mirror's or the symmetry's), along the other horizontal axis only,
    // so that a standing torso broad across its shoulders (the mirrored beast's, its head
    // split off) is not taken for a lying one.
    let known_lateral = mirror
        .map(|(axis, _)| axis)
        .or(symmetric)
        .filter(|&axis| axis < 2);
    let lying = match known_lateral {
        Some(axis) => body_extent[1 - axis] > body_extent.z,
        None => body_extent.x.max(body_extent.y) > body_extent.z,
    };
    let mesh_extent = mesh_hi - mesh_lo;
    // Each limb's leaf vertices, and their middle for the pairs that say which axis is left to
    // right.
    let limb_vertices = limb_vertex_sets(cages, &limbs);
    let middles: Vec<DVec3> = limb_vertices
        .values()
        .filter_map(|all| centroid(all.iter().map(point)))
        .collect();
    let body_centre = 0.5 * (body_lo + body_hi);
    let legs_apart = (!lying)
        .then(|| two_legs_apart(&limbs, &limb_vertices, cages, mesh_lo.z, mesh_extent.z))
        .flatten();
    let longer_side = if mesh_extent.y > mesh_extent.x { 1 } else { 0 };
    let (lateral, lateral_from_legs) = match (mirror, symmetric) {
        (Some((axis, _)), _) if axis < 2 => (axis, false),
        (None, Some(axis)) if axis < 2 && has_mirrored_pair(&middles, axis, body_centre) => {
            (axis, false)
        }
        // No pair either way (a bust whose nose, chin and neck lie on its plane): the symmetry
        // still says which axis runs from left to right.
        (None, Some(axis)) if axis < 2 && !has_mirrored_pair(&middles, 1 - axis, body_centre) => {
            (axis, false)
        }
        _ if lying && body_extent.x >= body_extent.y => (1, false),
        _ if lying => (0, false),
        _ if let Some(axis) = legs_apart => (axis, true),
        _ => (longer_side, false),
    };
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
        /// The height of the limb's lowest vertex.
        bottom: f64,
        /// The height of the limb's highest vertex.
        top: f64,
    }
    let shapes: BTreeMap<usize, Shape> = limbs
        .iter()
        .filter_map(|(&limb, record)| {
            let all = limb_vertices.get(&limb)?;
            let segment_vertices = |segment: &Vec<usize>| -> BTreeSet<u32> {
                segment
                    .iter()
                    .flat_map(|&l| vertices_of(&cages.leaves[l]))
                    .collect()
            };
            let first = segment_vertices(record.segments.first()?);
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
            // The tip: the vertex of the limb's last segment farthest from its root (a leg
            // whose first segment reaches up the flank above its root, spot's back leg at
            // detail 4, had its tip there and was no leg).
            let tip = segment_vertices(record.segments.last()?)
                .iter()
                .map(point)
                .max_by(|a, b| (*a - root).length().total_cmp(&(*b - root).length()))?;
            let bottom = all.iter().map(|v| point(v).z).fold(f64::INFINITY, f64::min);
            let top = all
                .iter()
                .map(|v| point(v).z)
                .fold(f64::NEG_INFINITY, f64::max);
            Some((
                limb,
                Shape {
                    root,
                    middle,
                    width: hi - lo,
                    tip,
                    bottom,
                    top,
                },
            ))
        })
        .collect();
    let height = mesh_extent.z.max(1e-12);
    // How far a limb reaches from its root to its tip.
    let length = |s: &Shape| (s.tip - s.root).length();
    // A leg ends near the ground (its tip in the figure's lowest fifth) and reaches down to it
    // (its lowest vertex in the lowest tenth; the shared meshes' legs in their lowest 5 %),
    // below where it starts. Short arms hanging to a fifth of the height (Cheburashka's, their
    // lowest vertex at 16-19 %) do not; a foot whose toe rises above its ankle does.
    let is_leg = |s: &Shape| {
        s.tip.z - mesh_lo.z < 0.2 * height
            && s.bottom - mesh_lo.z < 0.1 * height
            && s.bottom < s.root.z
    };
    // Halfway between the roots of the two legs that gave the lateral axis across the box's
    // longer side. Where the longer side already runs across the legs, the box's middle
    // stays the centre and the legs keep their sides by their middles (the armadillo at
    // detail 1: one leg's first cage reaches round to its tail, and the middle between the
    // legs' roots took an ear for its head; a generated figure with its arms raised had a
    // leg without a side, which sent it to the grid centred on its plane, where its arms are
    // arms, not ears).
    let legs_between = (lateral_from_legs && lateral != longer_side)
        .then(|| {
            let roots: Vec<f64> = shapes
                .iter()
                .filter(|(l, s)| limbs[*l].parent.is_none() && is_leg(s))
                .map(|(_, s)| s.root[lateral])
                .collect();
            match roots[..] {
                [a, b] => Some(0.5 * (a + b)),
                _ => None,
            }
        })
        .flatten();
    // Under a lying body without a mirror plane across the lateral axis, the middle between
    // the legs where they stand on both sides of the body's box (the mean of their middles on
    // each side, halfway between): a posed body's box is lopsided. TOSCA's prancing horse:
    // its raised foreleg moved the box's middle 3.2 from its tail's middle, more than a
    // quarter of the tail's width, and the tail was `limb.1`. By their middles, not their
    // roots: the jumping horse10's hind legs' roots lie 4 off their middles' centre, which
    // took its tail for a side limb. Not under a standing body (but where its legs gave the
    // lateral axis, above): the armadillo's legs stand off its torso's middle, and pieces of
    // its shoulders at details 1 and 5 changed sides.
    let centre = match mirror {
        Some((axis, _)) if axis == lateral => centre,
        // Halfway between the roots of two legs that gave the lateral axis (their hips:
        // TOSCA's standing cat's upper body turns, and its box's middle lay 2.1 from one
        // leg's middle, which left it without a side).
        _ if let Some(between) = legs_between => between,
        _ if !lying => centre,
        _ => {
            let side_mean = |left: bool| {
                let middles: Vec<f64> = shapes
                    .values()
                    .filter(|s| is_leg(s) && (s.middle[lateral] > centre) == left)
                    .map(|s| s.middle[lateral])
                    .collect();
                (!middles.is_empty()).then(|| middles.iter().sum::<f64>() / middles.len() as f64)
            };
            match (side_mean(true), side_mean(false)) {
                (Some(a), Some(b)) => 0.5 * (a + b),
                _ => centre,
            }
        }
    };
    // On the centre line where the limb straddles it (a tail, a neck: its middle within a
    // quarter of its own width of the plane); legs close together are each on one side.
    // Where two legs gave the lateral axis, each is on its root's side of the middle
    // between their roots (a sitting dog's hind leg folded across under it, TOSCA's dog7, has
    // its middle near the centre).
    let side_of = |s: &Shape| {
        if let Some(between) = legs_between
            && is_leg(s)
        {
            return (s.root[lateral] - between).signum();
        }
        let offset = s.middle[lateral] - centre;
        if offset.abs() <= 0.25 * s.width {
            0.0
        } else {
            offset.signum()
        }
    };
    // Which way a lying body faces: towards the limbs that reach well above it (a neck,
    // ears, horns; a quarter of its height), else towards a second thick region (its head), else −Y as in Blender.
    // A limb reaches as high as its highest vertex, not its tip: a neck raised to a head
    // hanging below the back (a grazing horse's) had its tip low, and was named `tail`.
    let forward = lying.then(|| {
        let axis = 1 - lateral;
        let raised = centroid(
            shapes
                .iter()
                .filter(|(limb, _)| !bodies.contains(limb))
                .map(|(_, s)| s)
                .filter(|s| s.top > body_hi.z + 0.25 * body_extent.z && !is_leg(s))
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
    // A bust: a standing figure with no limb off its centre line (no arm, leg or ear pair);
    // the one limb it rests on is its neck, not a leg.
    let bust = frame.forward.is_none() && shapes.values().all(|s| side_of(s) == 0.0);
    // Standing on a leg either side of the plane.
    let legs_either_side = [1.0, -1.0]
        .iter()
        .all(|&sign| shapes.values().any(|s| is_leg(s) && side_of(s) == sign));
    // A limb from which a pair of legs grows, one either side of the plane.
    let carries_leg_pair = |limb: usize| {
        let legs: Vec<&Shape> = limbs
            .iter()
            .filter(|(l, record)| record.parent == Some(limb) && !bodies.contains(l))
            .filter_map(|(l, _)| shapes.get(l))
            .filter(|c| is_leg(c))
            .collect();
        legs.iter().enumerate().any(|(i, a)| {
            legs[i + 1..]
                .iter()
                .any(|b| mirror_each_other(a.middle, b.middle, lateral, centre))
        })
    };
    // A stem: a short side limb out from the body whose one child, a side limb longer than
    // itself, is the rest of an arm or a leg (a shoulder, a hip the grid cut off as a limb of
    // its own). TOSCA's gorilla, mirrored, arms raised: its shoulders were `ear.L` and
    // `ear.R`, its arms `horn.L` and `horn.R` hanging from them. A limb carrying more than one
    // is no stem (a pelvis piece carrying both legs and the tail).
    let stem_of: BTreeMap<usize, usize> = shapes
        .iter()
        .filter_map(|(&child, c)| {
            let stem = limbs[&child].parent?;
            let s = shapes.get(&stem)?;
            let siblings = limbs.values().filter(|r| r.parent == Some(stem)).count();
            let stem_like = !bodies.contains(&stem)
                && !bodies.contains(&child)
                && limbs[&stem].parent.is_none()
                && siblings == 1
                && side_of(s) != 0.0
                && side_of(c) == side_of(s)
                && length(c) > length(s);
            stem_like.then_some((child, stem))
        })
        .collect();
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
        // A long limb off a lying body's side, not on a head (a fifth of the figure's height
        // long), reaching well above the body (a quarter of its height above its top) or out
        // beyond its front end, is a neck or a head turned to a side: the horse's neck and
        // head at detail 2 were `ear.L`, and a head at the end of a neck the body's slabs
        // climb, `ear.L`. Ears are shorter (spot's 0.12-0.15 of its height) or grow from a
        // head. `centre_role` then tells neck from head. A neck grows from the body's upper
        // half: a front leg raised forward beyond the front (TOSCA's prancing horse) hangs
        // from its lower half, and was named `neck` and `head`.
        let beyond_front = frame.forward.is_some_and(|(axis, sign)| {
            let front = if sign > 0.0 {
                frame.body_hi[axis]
            } else {
                frame.body_lo[axis]
            };
            (s.tip[axis] - front) * sign > 0.0
        });
        let turned_neck = frame.forward.is_some()
            && !bodies.contains(&limb)
            && !parent_is_head
            && !is_leg(s)
            && s.root.z > 0.5 * (frame.body_lo.z + frame.body_hi.z)
            && length(s) > 0.2 * height
            && (s.tip.z > frame.body_hi.z + 0.25 * (frame.body_hi.z - frame.body_lo.z)
                || beyond_front);
        // A limb from a lying body's back end on its centre line (its root in the body's last
        // eighth along it, within a tenth of the body's width of the plane) is on the centre
        // line even where it leans to a side: TOSCA's horse17 holds its tail up and aside, and
        // it was `ear.L`.
        // A limb straight out from the body that is no leg and no thick region.
        let free_limb = !bodies.contains(&limb) && !is_leg(s) && limbs[&limb].parent.is_none();
        let back_centre = free_limb
            && frame.forward.is_some_and(|(axis, sign)| {
                let half_length = 0.5 * (frame.body_hi[axis] - frame.body_lo[axis]);
                let width = frame.body_hi[lateral] - frame.body_lo[lateral];
                (s.root[axis] - body_centre[axis]) * sign < -BACK_END_SHARE * half_length
                    && (s.root[lateral] - centre).abs() < 0.1 * width
            });
        // A limb from a standing body's lower half rooted on its centre line (within a tenth
        // of the body's width of the plane) is on it even where it curls to a side: a tail
        // (TOSCA's cat standing up, its tail curled aside, was `arm.L`). So is one rooted at
        // the body's front or back end, as under a lying body ([`BACK_END_SHARE`]): TOSCA's
        // sitting dog's tail, curled to a side, was `arm.L`.
        let low_limb = free_limb && frame.forward.is_none() && s.root.z < body_centre.z;
        let at_end = low_limb && {
            let along = 1 - lateral;
            let half_length = 0.5 * (frame.body_hi[along] - frame.body_lo[along]);
            (s.root[along] - body_centre[along]).abs() > BACK_END_SHARE * half_length
        };
        let low_centre = at_end
            || (low_limb && {
                let width = frame.body_hi[lateral] - frame.body_lo[lateral];
                (s.root[lateral] - centre).abs() < 0.1 * width
            });
        let side = if head_on_neck
            || carries_head
            || centred_body
            || turned_neck
            || back_centre
            || low_centre
        {
            0.0
        } else {
            side_of(s)
        };
        let side_letter = (side != 0.0).then_some(if side == frame.left_sign { 'L' } else { 'R' });
        // Ears (horns) stand on top: a side limb rooted in the body's top fifth (or on a
        // head) that reaches above it.
        let body_height = frame.body_hi.z - frame.body_lo.z;
        // Not where a centre limb rising from the body (a head, a neck) starts well above
        // the limb's root: the body's top is then a neck's base, and a side limb from below
        // it is an arm raised (TOSCA's gorilla: its left arm, rooted a fifth of the body's
        // height below its head, was `ear.L` beside `arm.R`).
        // A pair's lower root stands for both: decimation may keep a vertex that lifts one
        // side's root ring (the gorilla-like figure's left arm, 1.21 -> 1.33 with a ring of
        // four kept at a joint, while its right arm stayed).
        let pair_root_z = shapes
            .iter()
            .filter(|(l, c)| {
                **l != limb
                    && !bodies.contains(*l)
                    && mirror_each_other(s.middle, c.middle, lateral, centre)
            })
            .map(|(_, c)| c.root.z)
            .fold(s.root.z, f64::min);
        let below_a_head = limbs.iter().any(|(&l, record)| {
            l != limb
                && record.parent.is_none()
                && shapes.get(&l).is_some_and(|c| {
                    side_of(c) == 0.0
                        && !is_leg(c)
                        && c.tip.z >= c.root.z
                        && c.root.z > pair_root_z + HEAD_ABOVE_ARM_SHARE * body_height
                })
        });
        // An ear grows from the body or a head, not from the end of a stem (an arm raised
        // from its shoulder).
        let on_top = s.root.z > frame.body_hi.z - 0.2 * body_height
            && s.tip.z > frame.body_hi.z
            && !below_a_head
            && !stem_of.contains_key(&limb);
        let headwards = headwards_of(s);
        // A centre limb longer than itself rises from it (a thick neck base carrying the
        // neck and head; not a head's crown between its ears, spot's at detail 5, which made
        // its head `neck`, nor an elephant's trunk hanging from its head).
        let carries_centre_limb = limbs.iter().any(|(l, record)| {
            record.parent == Some(limb)
                && shapes.get(l).is_some_and(|c| {
                    (c.middle[lateral] - centre).abs() <= 0.25 * c.width
                        && length(c) > length(s)
                        && c.tip.z > c.root.z
                })
        });
        // Ears and horns rise from where they grow (a muzzle, a leg do not).
        let rises = s.tip.z - s.root.z > 0.3 * length(s);
        // On a head, ears may stand out sideways and a little down (spot's fall 15°); a side
        // limb hanging from it more steeply than 30° is not one.
        let droops = s.root.z - s.tip.z > 0.5 * length(s);
        // A thick region on another that is not the main body (a crown on a head larger
        // than the torso, `head_over_legs`) is part of it, as a crown on a head is.
        let on_body =
            bodies.contains(&limb) && limbs[&limb].parent.is_some_and(|p| bodies.contains(&p));
        let role = if on_body {
            "limb"
        } else if head_on_neck {
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
            // On a bust the one limb reaching its bottom is its neck.
            if bust { "neck" } else { "leg" }
        } else if side != 0.0 && ((parent_is_head && !droops) || (on_top && rises)) {
            "ear"
        } else if side == 0.0
            && parent_is_head
            && limbs[&limb].parent.is_some_and(|p| bodies.contains(&p))
        {
            // A centre limb on a head of its own (spot's crown between its ears at detail 5)
            // is no neck; where it makes that thick region a neck (`carries_centre_limb`:
            // longer than it and rising, TOSCA's rearing horse15 with its head held up
            // from the top of its neck), it is the head.
            let makes_neck = limbs[&limb]
                .parent
                .and_then(|p| shapes.get(&p))
                .is_some_and(|ps| {
                    (s.middle[lateral] - centre).abs() <= 0.25 * s.width
                        && length(s) > length(ps)
                        && s.tip.z > s.root.z
                });
            if makes_neck { "head" } else { "limb" }
        } else if side == 0.0 && carries_leg_pair(limb) {
            // Two legs joined along the plane from the body down to where they part (the
            // camel's, touching under its chest): their common stem, which turns both.
            match frame.forward {
                Some(_) if headwards => "leg.front",
                Some(_) => "leg.back",
                None => "leg",
            }
        } else if side == 0.0 {
            // Low at a standing body's end, a tail shorter than a fifth of the height: a
            // rearing horse is tall (TOSCA's horse15's tail, 0.13 of it, was `limb.1`). Only
            // on a figure standing on a leg either side: a bust's chin is no tail (QMVC's
            // ManHead mirrored at detail 4, its neck an unsided `leg`, had its chin `tail`).
            match centre_role(s.root, s.tip, &frame) {
                "limb"
                    if at_end
                        && legs_either_side
                        && length(s) >= SHORTEST_END_TAIL_SHARE * height =>
                {
                    "tail"
                }
                role => role,
            }
        } else if frame.forward.is_none() {
            "arm"
        } else if rises && s.tip.z > frame.body_hi.z {
            // On a lying body: rising above it.
            "ear"
        } else if headwards && s.root.z > body_centre.z && limbs[&limb].parent.is_none() {
            // Out from the upper front: a cow's ears (an eighth of its height), a centaur's
            // arms (a third).
            if length(s) < LONGEST_EAR_SHARE * height {
                "ear"
            } else {
                "arm"
            }
        } else {
            "limb"
        };
        base.insert(limb, (role.to_owned(), side_letter));
    }
    // Two limbs that mirror each other across the plane have one role: a leg needs both to
    // reach the ground. Cheburashka's short arms hang to a fifth of his height, and the one
    // whose tip was lower was `leg.R` beside `arm.L`.
    let keys: Vec<usize> = base.keys().copied().collect();
    for (i, &a) in keys.iter().enumerate() {
        for &b in &keys[i + 1..] {
            let (Some(sa), Some(sb)) = (shapes.get(&a), shapes.get(&b)) else {
                continue;
            };
            let roles = (base[&a].0.as_str(), base[&b].0.as_str());
            let one_leg = matches!(roles, ("leg", "arm") | ("arm", "leg"));
            if one_leg && mirror_each_other(sa.middle, sb.middle, lateral, centre) {
                let arm = if roles.0 == "leg" { a } else { b };
                if let Some(entry) = base.get_mut(&arm) {
                    entry.0 = "arm".to_owned();
                }
            }
        }
    }
    // A leg lifted off the ground (a horse stepping, prancing or jumping, TOSCA's horse5,
    // horse7 and horse10: its hoof at a tenth to a half of the height) does not reach down as
    // its twin does. A side limb straight off the body, hanging from its lower half (arms, ears
    // and tails grow higher) with its tip below its root, and half a leg long or more (knees
    // bent), is the leg missing where it grows: under a lying body, at its end (front or back
    // half) on its side where no leg stands; under a standing one, on a side with fewer legs
    // than the other.
    let leg_lengths: Vec<f64> = base
        .iter()
        .filter(|(_, (role, _))| role == "leg")
        .filter_map(|(l, _)| shapes.get(l).map(length))
        .collect();
    if !leg_lengths.is_empty() {
        let mean_leg = leg_lengths.iter().sum::<f64>() / leg_lengths.len() as f64;
        // Whether a leg is missing where `limb` (with side `letter`) grows, given the roles.
        let missing_at =
            |limb: usize, letter: char, base: &BTreeMap<usize, (String, Option<char>)>| {
                let legs_on = |side: char| {
                    base.iter()
                        .filter(|(_, (role, l))| role == "leg" && *l == Some(side))
                        .filter_map(|(l, _)| shapes.get(l))
                        .collect::<Vec<_>>()
                };
                let other = if letter == 'L' { 'R' } else { 'L' };
                let Some(s) = shapes.get(&limb) else {
                    return false;
                };
                match frame.forward {
                    Some((axis, sign)) => {
                        let front = |c: &Shape| (c.root[axis] - body_centre[axis]) * sign > 0.0;
                        !legs_on(letter).iter().any(|c| front(c) == front(s))
                    }
                    None => legs_on(letter).len() < legs_on(other).len(),
                }
            };
        let mut lifted: Vec<(usize, f64)> = shapes
            .iter()
            .filter(|(limb, s)| {
                let Some((role, Some(letter))) = base.get(limb) else {
                    return false;
                };
                role == "limb"
                    && limbs[limb].parent.is_none()
                    && !bodies.contains(limb)
                    && s.root.z < body_centre.z
                    && s.tip.z < s.root.z
                    && length(s) >= LIFTED_LEG_SHARE * mean_leg
                    && missing_at(**limb, *letter, &base)
            })
            .map(|(&limb, s)| (limb, length(s)))
            .collect();
        // The longest first, one per missing leg.
        lifted.sort_by(|a, b| b.1.total_cmp(&a.1));
        for (limb, _) in lifted {
            let Some(letter) = base.get(&limb).and_then(|(_, l)| *l) else {
                continue;
            };
            if missing_at(limb, letter, &base)
                && let Some(entry) = base.get_mut(&limb)
            {
                entry.0 = "leg".to_owned();
            }
        }
    }
    // A stem is named for what it carries: the shoulder of an arm, the hip of a leg.
    for (&child, &stem) in &stem_of {
        let base_role = match base.get(&child).map(|(role, _)| role.as_str()) {
            Some("arm") => "shoulder",
            Some("leg") => "hip",
            _ => continue,
        };
        if let Some(entry) = base.get_mut(&stem) {
            entry.0 = base_role.to_owned();
        }
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
    // Two ears on one side (spot's ear and horn): the one that rises least is the ear, the
    // steeper ones horns.
    for letter in [Some('L'), Some('R')] {
        let mut ears: Vec<(usize, f64)> = base
            .iter()
            .filter(|(_, (r, s))| r == "ear" && *s == letter)
            .filter_map(|(&l, _)| {
                let s = shapes.get(&l)?;
                Some((l, (s.tip.z - s.root.z) / length(s).max(1e-12)))
            })
            .collect();
        if ears.len() < 2 {
            continue;
        }
        ears.sort_by(|a, b| a.1.total_cmp(&b.1));
        for &(limb, _) in &ears[1..] {
            base.insert(limb, ("horn".to_owned(), letter));
        }
    }
    // Four legs under a lying body: the front two and the back two are pairs, and a pair whose
    // legs stand side by side has one on each side, told apart by which lies further left,
    // where the plane through the body's middle left one or both without a side (TOSCA's
    // wolf, its head and body turned: its left legs were `leg` and `leg.001`).
    if let Some((axis, sign)) = frame.forward {
        let mut legs: Vec<usize> = base
            .iter()
            .filter(|(l, (r, _))| r == "leg" && shapes.contains_key(l))
            .map(|(&l, _)| l)
            .collect();
        if legs.len() == 4 {
            legs.sort_by(|a, b| {
                let along = |l: &usize| -sign * shapes[l].root[axis];
                along(a).total_cmp(&along(b))
            });
            for pair in legs.chunks(2) {
                let [a, b] = pair[..] else { continue };
                let sides = (base[&a].1, base[&b].1);
                if sides.0.is_some() && sides.1.is_some() && sides.0 != sides.1 {
                    continue;
                }
                let (sa, sb) = (&shapes[&a], &shapes[&b]);
                let apart = (sa.middle[lateral] - sb.middle[lateral]).abs();
                // Side by side: further apart than a quarter of their mean width.
                if apart <= 0.25 * (sa.width + sb.width) {
                    continue;
                }
                let a_left = (sa.middle[lateral] - sb.middle[lateral]) * frame.left_sign > 0.0;
                let (left, right) = if a_left { (a, b) } else { (b, a) };
                for (limb, letter) in [(left, 'L'), (right, 'R')] {
                    if let Some(entry) = base.get_mut(&limb) {
                        entry.1 = Some(letter);
                    }
                }
            }
        }
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
    // A lone leg on a side whose other side's legs are named by place takes the place of the
    // one its root is level with along the body: clearly nearer it (within half the distance
    // to the next). TOSCA's gorilla on its right knuckles, its left hand at its mouth, had
    // `leg.L` beside `leg.front.R` and `leg.back.R`; a lone leg between the other side's two
    // (two legs joined into one, spot's at detail 1) keeps `leg.L`.
    for (letter, other) in [('L', 'R'), ('R', 'L')] {
        let lone: Vec<usize> = base
            .iter()
            .filter(|(_, (r, s))| r == "leg" && *s == Some(letter))
            .map(|(&l, _)| l)
            .collect();
        let [leg] = lone[..] else { continue };
        let suffix = format!(".{other}");
        let (axis, _) = frame.forward.unwrap_or((1, -1.0));
        let mut placed: Vec<(f64, &str)> = names
            .iter()
            .filter_map(|(l, name)| {
                let place = name.strip_prefix("leg.")?.strip_suffix(suffix.as_str())?;
                let apart = (shapes.get(l)?.root[axis] - shapes.get(&leg)?.root[axis]).abs();
                Some((apart, place))
            })
            .collect();
        placed.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let [(nearest, place), (next, _), ..] = placed[..]
            && nearest < 0.5 * next
        {
            names.insert(leg, format!("leg.{place}.{letter}"));
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

/// How far above a side limb's root a centre limb rising from the body must start, as a share
/// of the body's height, for the side limb to be an arm below a head, not an ear on top.
const HEAD_ABOVE_ARM_SHARE: f64 = 0.1;

/// The shortest lifted leg, root to tip, as a share of the mean length of the figure's legs
/// that reach the ground: TOSCA's horses' lifted legs are 0.84-1.1 of it, 0.58-0.60 with the
/// knees folded under a jump (horse10); their tails 0.3-0.45.
const LIFTED_LEG_SHARE: f64 = 0.5;

/// Where a lying body's back end starts, as a share of its half length from its middle: its
/// last eighth. The tails of TOSCA's animals and posed horses grow from 0.80-1.0 of it; hind
/// legs from 0.47-0.83, off the centre line.
const BACK_END_SHARE: f64 = 0.75;

/// The longest ear out from a lying body's upper front, root to tip, as a share of the
/// figure's height: spot's and the cow's ears reach 0.08-0.2, a centaur's arms 0.34-0.40.
const LONGEST_EAR_SHARE: f64 = 0.25;

/// The shortest neck rising above a lying body's front, root to tip, as a share of the
/// figure's height: a neck carrying its head there is long (the camel's: 0.37-0.42); a
/// shorter centre limb rising above the body is a head on it (TOSCA's centaur: the man's
/// head on his torso, 0.16, was `neck`).
const SHORTEST_NECK_SHARE: f64 = 0.25;

/// Whether two limbs' middles are mirror images across the plane through `centre` across
/// `axis` (on opposite sides at about the same distance, level with each other): a pair of
/// legs, arms or ears, which a mesh symmetric across that axis has when the axis runs from
/// its left to its right.
fn has_mirrored_pair(middles: &[DVec3], axis: usize, centre: DVec3) -> bool {
    middles.iter().enumerate().any(|(i, a)| {
        middles[i + 1..]
            .iter()
            .any(|b| mirror_each_other(*a, *b, axis, centre[axis]))
    })
}

/// Whether points `a` and `b` are mirror images across the plane at `centre` across `axis`:
/// on opposite sides at about the same distance, level with each other (within a quarter of
/// their distance apart).
fn mirror_each_other(a: DVec3, b: DVec3, axis: usize, centre: f64) -> bool {
    let (da, db) = (a[axis] - centre, b[axis] - centre);
    let apart = (da - db).abs();
    let mut off = a - b;
    off[axis] = 0.0;
    da * db < 0.0 && (da + db).abs() <= 0.25 * apart && off.length() <= 0.25 * apart
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

/// The least length of a tail low at a standing body's end, as a share of the figure's
/// height (a fifth elsewhere, [`centre_role`]): TOSCA's rearing horse15's is 0.13.
const SHORTEST_END_TAIL_SHARE: f64 = 0.1;

/// The share of a standing body's height, from its top, in which a head growing from it is
/// rooted ([`centre_role`]).
const HEAD_ROOT_SHARE: f64 = 0.15;

/// The horizontal axis along which a standing figure's two legs stand apart, where its limbs
/// reaching the ground from the body are two and stand apart along one axis at least
/// [`LEGS_APART_RATIO`] times as far as along the other. A figure
/// standing up on its hind legs (TOSCA's rearing cat and horse) has no mirror plane and
/// its raised forelegs or tail reach further out across its front than its arms do across its
/// width: the longer horizontal side of its box ran from front to back, and its legs, paws and
/// tail were named as if it faced sideways (two `arm.R`, `leg.L` beside an unsided `leg`).
/// Legs here are limbs out from the body whose lowest cage vertex is in the figure's lowest
/// tenth, compared by their centroids.
fn two_legs_apart(
    limbs: &BTreeMap<usize, super::controls::Limb>,
    limb_vertices: &BTreeMap<usize, BTreeSet<u32>>,
    cages: &CageSet,
    ground: f64,
    height: f64,
) -> Option<usize> {
    let point = |v: &u32| cages.vertices.get(*v as usize).copied();
    let legs: Vec<DVec3> = limbs
        .iter()
        .filter(|(_, record)| record.parent.is_none())
        .filter_map(|(limb, _)| limb_vertices.get(limb))
        .filter(|all| {
            all.iter()
                .filter_map(point)
                .any(|p| p.z - ground < 0.1 * height)
        })
        .filter_map(|all| centroid(all.iter().filter_map(point)))
        .collect();
    let [a, b] = legs.as_slice() else {
        return None;
    };
    let apart = (*a - *b).abs();
    let axis = if apart.x >= apart.y { 0 } else { 1 };
    (apart[axis] >= LEGS_APART_RATIO * apart[1 - axis]).then_some(axis)
}

/// How many times further apart along one horizontal axis than along the other two legs
/// must stand for [`two_legs_apart`] to take that axis as left to right: TOSCA's rearing cat
/// 2.4, horse 7.6; a walking figure's stride (TOSCA's michael1: its feet 7.4 apart across,
/// 8 along) says nothing.
const LEGS_APART_RATIO: f64 = 2.0;

/// The role of a limb on the centre line: above a standing body a head (a neck with its head),
/// from its lower half a tail (when a fifth of the height long); at a lying body's front end a
/// head (a neck where it rises above the body and is long enough to carry one), at its back
/// end a tail; else an unnamed limb.
fn centre_role(root: DVec3, tip: DVec3, frame: &Frame) -> &'static str {
    let height = (frame.mesh_hi.z - frame.mesh_lo.z).max(1e-12);
    let body_height = frame.body_hi.z - frame.body_lo.z;
    match frame.forward {
        // Rooted in the body's top (a paw held to the mouth of a cat standing up, TOSCA's
        // cat4, rises from its chest a quarter of the body's height below its top).
        None if tip.z > frame.body_hi.z - 0.05 * height
            && root.z > frame.body_hi.z - HEAD_ROOT_SHARE * body_height =>
        {
            "head"
        }
        // Hanging from a standing body's lower half, not reaching the ground and a fifth of
        // the figure's height long: a tail (the armadillo's: a quarter); a nose or a chin on a
        // bust is shorter (ManHead's: a tenth).
        None if root.z < 0.5 * (frame.body_lo.z + frame.body_hi.z)
            && (tip - root).length() >= 0.2 * height =>
        {
            "tail"
        }
        None => "limb",
        Some((axis, sign)) => {
            let body_mid = 0.5 * (frame.body_lo[axis] + frame.body_hi[axis]);
            if (root[axis] - body_mid) * sign > 0.0 {
                if tip.z > frame.body_hi.z && (tip - root).length() >= SHORTEST_NECK_SHARE * height
                {
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

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};

    use glam::DVec3;

    use super::super::test_cages::point_cages;
    use super::*;

    /// Four corners of a square of half side `r` around (x, y) at height z.
    fn ring(x: f64, y: f64, z: f64, r: f64) -> Vec<DVec3> {
        [(-r, -r), (r, -r), (r, r), (-r, r)]
            .iter()
            .map(|(dx, dy)| DVec3::new(x + dx, y + dy, z))
            .collect()
    }

    /// The eight corners of a lying body 0.8 wide, 2 long (along Y) and 0.8 tall.
    fn lying_body() -> Vec<DVec3> {
        let mut body = Vec::new();
        for x in [-0.4, 0.4] {
            for y in [-1.0, 1.0] {
                for z in [0.0, 0.8] {
                    body.push(DVec3::new(x, y, z));
                }
            }
        }
        body
    }

    /// The names of a quadruped facing +Y: `body`'s corners, four legs of two segments at
    /// (±0.25, ±0.7) (limbs 0–3: front right, front left, back right, back left), their
    /// thighs also holding a piece of the flank above the hip where `flank`, and a neck
    /// rising from the front at x = `neck_x` (limb 4).
    fn quadruped_names(body: Vec<DVec3>, flank: bool, neck_x: f64) -> BTreeMap<usize, String> {
        let legs = [(0.25, 0.7), (-0.25, 0.7), (0.25, -0.7), (-0.25, -0.7)];
        legged_names(body, &legs, flank, neck_x)
    }

    /// [`quadruped_names`] with legs at `legs` (limbs `0..legs.len()`, the neck the next).
    fn legged_names(
        mut body: Vec<DVec3>,
        legs: &[(f64, f64)],
        flank: bool,
        neck_x: f64,
    ) -> BTreeMap<usize, String> {
        let mut cages = Vec::new();
        for &(x, y) in legs {
            body.extend(ring(x, y, 0.0, 0.08));
            let mut thigh = ring(x, y, 0.0, 0.08);
            thigh.extend(ring(x, y, -0.25, 0.08));
            if flank {
                thigh.extend([
                    DVec3::new(x - 0.08, y + 0.3, 0.7),
                    DVec3::new(x + 0.08, y + 0.3, 0.7),
                ]);
            }
            let mut shin = ring(x, y, -0.25, 0.08);
            shin.extend(ring(x, y, -0.5, 0.08));
            cages.push(thigh);
            cages.push(shin);
        }
        body.extend(ring(neck_x, 0.9, 0.6, 0.1));
        let mut neck = ring(neck_x, 0.9, 0.6, 0.1);
        neck.extend(ring(neck_x, 1.3, 1.4, 0.1));
        cages.push(neck);
        cages.push(body);
        names_of(&cages, legs.len(), legs.len() + 1, &[])
    }

    /// The names of `cages`' limbs: limbs `0..two_segment` have two cages each, the rest up to
    /// `limbs` one, in that order, then the one body; `parents` as (child, parent) limbs.
    fn names_of(
        cages: &[Vec<DVec3>],
        two_segment: usize,
        limbs: usize,
        parents: &[(usize, usize)],
    ) -> BTreeMap<usize, String> {
        let mut roles: Vec<Role> = (0..two_segment)
            .flat_map(|limb| (0..2).map(move |segment| Role::Limb { limb, segment }))
            .collect();
        roles.extend((two_segment..limbs).map(|limb| Role::Limb { limb, segment: 0 }));
        roles.push(Role::Body { body: 0, slab: 0 });
        limb_names(
            &point_cages(cages),
            &roles,
            &parents.iter().copied().collect(),
            &BTreeSet::new(),
            None,
            None,
            &BTreeSet::new(),
        )
    }

    /// The eight corners of the box from `lo` to `hi`.
    fn box_corners(lo: DVec3, hi: DVec3) -> Vec<DVec3> {
        let mut corners = Vec::new();
        for x in [lo.x, hi.x] {
            for y in [lo.y, hi.y] {
                for z in [lo.z, hi.z] {
                    corners.push(DVec3::new(x, y, z));
                }
            }
        }
        corners
    }

    /// Two legs at x = ∓`x` (right, then left), each a thigh and a shin from the heights
    /// `[hip, knee, foot]`, their hip rings added to `body`: the legs' four cages.
    fn standing_legs(
        body: &mut Vec<DVec3>,
        x: f64,
        [hip, knee, foot]: [f64; 3],
    ) -> Vec<Vec<DVec3>> {
        let mut cages = Vec::new();
        for x in [-x, x] {
            body.extend(ring(x, 0.0, hip, 0.08));
            let mut thigh = ring(x, 0.0, hip, 0.08);
            thigh.extend(ring(x, 0.0, knee, 0.08));
            let mut shin = ring(x, 0.0, knee, 0.08);
            shin.extend(ring(x, 0.0, foot, 0.08));
            cages.push(thigh);
            cages.push(shin);
        }
        cages
    }

    /// The names of a figure standing on two legs of two segments (limbs 0 and 1, at
    /// x = ±0.15) under a body 0.6 wide and 1.2 tall, with a thick region on its top (limb 2,
    /// a body of its own, from z 1.2 to 1.5) carrying a centre limb rising from it to
    /// `muzzle_top` (limb 3).
    fn thick_head_names(muzzle_top: f64) -> BTreeMap<usize, String> {
        let mut body = box_corners(DVec3::new(-0.3, -0.3, 0.0), DVec3::new(0.3, 0.3, 1.2));
        let mut cages = standing_legs(&mut body, 0.15, [0.0, -0.25, -0.5]);
        body.extend(ring(0.0, 0.0, 1.2, 0.15));
        let mut head = ring(0.0, 0.0, 1.2, 0.15);
        head.extend(ring(0.0, 0.0, 1.5, 0.15));
        head.extend(ring(0.0, -0.02, 1.5, 0.05));
        cages.push(head);
        let mut muzzle = ring(0.0, -0.02, 1.5, 0.05);
        muzzle.extend(ring(0.0, -0.1, muzzle_top, 0.05));
        cages.push(muzzle);
        cages.push(body);
        let mut roles: Vec<Role> = (0..2)
            .flat_map(|limb| (0..2).map(move |segment| Role::Limb { limb, segment }))
            .collect();
        roles.extend((2..4).map(|limb| Role::Limb { limb, segment: 0 }));
        roles.push(Role::Body { body: 0, slab: 0 });
        limb_names(
            &point_cages(&cages),
            &roles,
            &BTreeMap::from([(3, 2)]),
            &BTreeSet::from([2]),
            None,
            None,
            &BTreeSet::new(),
        )
    }

    #[test]
    fn a_muzzle_rising_from_a_thick_head_is_the_head_on_its_neck() {
        // TOSCA's rearing horse15 holds its head up, its muzzle to the sky: the thick back
        // of its head is a body of its own, which the muzzle rising from it (longer than it)
        // makes a neck; the muzzle was `limb.1` on it.
        let names = thick_head_names(2.0);
        assert_eq!(names.get(&2).map(String::as_str), Some("neck"), "{names:?}");
        assert_eq!(names.get(&3).map(String::as_str), Some("head"), "{names:?}");
        // A crown shorter than the head it stands on stays a limb of that head.
        let names = thick_head_names(1.65);
        assert_eq!(names.get(&2).map(String::as_str), Some("head"), "{names:?}");
        assert!(
            names.get(&3).is_some_and(|n| n.starts_with("limb")),
            "{names:?}"
        );
    }

    #[test]
    fn a_leg_whose_first_segment_reaches_up_the_flank_is_a_leg() {
        // A quadruped facing +Y (its neck rises at the front) whose legs' first segments also
        // hold a piece of the flank above the hip, reaching farther from the hip than the
        // hoof does, as spot's back leg at detail 4: the leg's tip was on the flank, above
        // its root, and the leg was `limb.1`.
        let names = quadruped_names(lying_body(), true, 0.0);
        let legs: BTreeSet<&str> = (0..4)
            .filter_map(|limb| names.get(&limb).map(String::as_str))
            .collect();
        // Facing +Y, the left side is −X.
        let expected: BTreeSet<&str> =
            BTreeSet::from(["leg.front.L", "leg.front.R", "leg.back.L", "leg.back.R"]);
        assert_eq!(legs, expected, "{names:?}");
    }

    #[test]
    fn a_lone_leg_takes_the_place_it_stands_level_with() {
        // A quadruped facing +Y with its back left leg missing (inside the body, or a hand
        // held at the mouth: TOSCA's gorilla on its right knuckles): the lone left leg stands
        // level with the front right one and was `leg.L`.
        let legs = [(0.25, 0.7), (-0.25, 0.7), (0.25, -0.7)];
        let names = legged_names(lying_body(), &legs, false, 0.0);
        let name = |limb: usize| names.get(&limb).map(String::as_str);
        assert_eq!(
            [name(0), name(1), name(2)],
            [Some("leg.front.R"), Some("leg.front.L"), Some("leg.back.R")],
            "{names:?}"
        );
        // Halfway between the other side's two (two legs joined into one), it keeps `leg.L`.
        let legs = [(0.25, 0.7), (-0.25, 0.05), (0.25, -0.7)];
        let names = legged_names(lying_body(), &legs, false, 0.0);
        assert_eq!(
            names.get(&1).map(String::as_str),
            Some("leg.L"),
            "{names:?}"
        );
    }

    #[test]
    fn four_legs_under_a_lying_body_are_two_pairs_of_sides() {
        // A quadruped facing +Y whose body reaches far out to its left (a wolf's body and
        // head turned): the plane through the body's middle runs through its left legs,
        // which had no side (`leg`, `leg.001`).
        let mut body = Vec::new();
        for x in [-0.9, 0.4] {
            for y in [-1.0, 1.0] {
                for z in [0.0, 0.8] {
                    body.push(DVec3::new(x, y, z));
                }
            }
        }
        let names = quadruped_names(body, false, -0.25);
        // Facing +Y, the left side is −X.
        let name = |limb: usize| names.get(&limb).map(String::as_str);
        assert_eq!(
            [name(0), name(1), name(2), name(3)],
            [
                Some("leg.front.R"),
                Some("leg.front.L"),
                Some("leg.back.R"),
                Some("leg.back.L")
            ],
            "{names:?}"
        );
    }

    #[test]
    fn legs_joined_down_to_where_they_part_grow_from_their_stem() {
        // A quadruped facing +Y whose front legs touch from the chest down to where they part
        // (the camel's): one centre limb from the body, carrying the two legs. The stem was a
        // `head` (a centre limb at the front end not rising above the body) carrying
        // `leg.front.L` and `leg.front.R`.
        let mut body = lying_body();
        let mut cages = Vec::new();
        for x in [0.25, -0.25] {
            body.extend(ring(x, -0.7, 0.0, 0.08));
            let mut thigh = ring(x, -0.7, 0.0, 0.08);
            thigh.extend(ring(x, -0.7, -0.25, 0.08));
            let mut shin = ring(x, -0.7, -0.25, 0.08);
            shin.extend(ring(x, -0.7, -0.5, 0.08));
            cages.push(thigh);
            cages.push(shin);
        }
        body.extend(ring(0.0, 0.7, 0.0, 0.15));
        let mut stem = ring(0.0, 0.7, 0.0, 0.15);
        for x in [0.08, -0.08] {
            stem.extend(ring(x, 0.7, -0.2, 0.06));
            let mut leg = ring(x, 0.7, -0.2, 0.06);
            leg.extend(ring(x, 0.7, -0.5, 0.06));
            cages.push(leg);
        }
        cages.insert(4, stem);
        body.extend(ring(0.0, 0.9, 0.6, 0.1));
        let mut neck = ring(0.0, 0.9, 0.6, 0.1);
        neck.extend(ring(0.0, 1.3, 1.4, 0.1));
        cages.push(neck);
        cages.push(body);
        // Back legs 0 and 1 (two segments each), the stem 2, front legs 3 and 4, the neck 5.
        let names = names_of(&cages, 2, 6, &[(3, 2), (4, 2)]);
        let name = |limb: usize| names.get(&limb).map(String::as_str);
        assert_eq!(name(2), Some("leg.front"), "{names:?}");
        let front: BTreeSet<_> = [name(3), name(4)].into_iter().flatten().collect();
        assert_eq!(
            front,
            BTreeSet::from(["leg.front.L", "leg.front.R"]),
            "{names:?}"
        );
        let back: BTreeSet<_> = [name(0), name(1)].into_iter().flatten().collect();
        assert_eq!(
            back,
            BTreeSet::from(["leg.back.L", "leg.back.R"]),
            "{names:?}"
        );
        assert_eq!(name(5), Some("neck"), "{names:?}");
    }

    #[test]
    fn an_arm_raised_from_a_shoulder_cut_off_as_a_limb_is_an_arm() {
        // A standing figure whose shoulders the grid cut off as short limbs of their own, the
        // arms raised above the head from their ends (TOSCA's gorilla, mirrored, whose
        // shoulders were `ear.L` and `ear.R`, its arms `horn.L` and `horn.R`). Without the
        // stem rule these shoulders are `arm.*` and the arms `ear.*`.
        let mut body = box_corners(DVec3::new(-0.4, -0.2, 1.0), DVec3::new(0.4, 0.2, 2.0));
        // Legs (limbs 0 and 1, two segments each), right then left.
        let mut cages = standing_legs(&mut body, 0.2, [1.0, 0.5, 0.0]);
        // The head (limb 2) on top.
        body.extend(ring(0.0, 0.0, 2.0, 0.1));
        let mut head = ring(0.0, 0.0, 2.0, 0.1);
        head.extend(ring(0.0, 0.0, 2.4, 0.1));
        cages.push(head);
        // Shoulders (limbs 3 and 4) out from the body's top, arms (5 and 6) raised from them.
        let mut arms = Vec::new();
        for side in [-1.0, 1.0] {
            body.extend(ring(0.4 * side, 0.0, 1.92, 0.06));
            let mut shoulder = ring(0.4 * side, 0.0, 1.92, 0.06);
            shoulder.extend(ring(0.6 * side, 0.0, 2.05, 0.06));
            cages.push(shoulder);
            let mut arm = ring(0.6 * side, 0.0, 2.05, 0.06);
            arm.extend(ring(0.7 * side, 0.0, 2.7, 0.05));
            arms.push(arm);
        }
        cages.extend(arms);
        cages.push(body);
        let names = names_of(&cages, 2, 7, &[(5, 3), (6, 4)]);
        let name = |limb: usize| names.get(&limb).map(String::as_str);
        assert_eq!(
            [name(0), name(1), name(2)],
            [Some("leg.R"), Some("leg.L"), Some("head")],
            "{names:?}"
        );
        assert_eq!(
            [name(3), name(4), name(5), name(6)],
            [
                Some("shoulder.R"),
                Some("shoulder.L"),
                Some("arm.R"),
                Some("arm.L")
            ],
            "{names:?}"
        );
    }
}
