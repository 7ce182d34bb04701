//! A head at the end of a neck that the cut did not find as a thick region of its own: the
//! camel's head is hardly thicker than its neck, so it was the neck's last segment, and the
//! rig had no `head` control. The segments from where the neck stops rising and runs level
//! (a head held forward on a raised neck) become a limb of their own, `head`, hanging from the
//! neck, whose control nods the head alone.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;

use super::controls::{centroid, limbs_of, new_limb_id, vertices_of};
use super::parts::Role;
use crate::scene::CageSet;

/// Splits the head off the rig's `neck` (see the module) where no limb is a head yet: the
/// neck must rise (its tip above its root by more than 0.3 of their distance: a bust's neck,
/// hanging to its cut, does not) and keep at least one segment. Where the rig has a `head`
/// chain and no neck, a neck is split off its first segments where the head hangs from them
/// ([`first_hanging_segment`], [`second_of_a_long_chain`]: TOSCA's horse, whose muzzle hangs
/// below its back, so its whole chain was named `head`). Updates the leaves' roles, the limbs'
/// parents (a branch rooted on the head hangs from it) and the names.
pub(super) fn head_off_neck(
    cages: &CageSet,
    roles: &mut [Role],
    parent_limb: &mut BTreeMap<usize, usize>,
    names: &mut BTreeMap<usize, String>,
) {
    let named = |n: &str| {
        names
            .iter()
            .find(|(_, name)| name.as_str() == n)
            .map(|(&l, _)| l)
    };
    if names.values().any(|n| n == "neck") {
        if names
            .values()
            .any(|n| n == "head" || n.starts_with("head."))
        {
            return;
        }
        if let Some(neck) = named("neck") {
            split_head_off(cages, roles, parent_limb, names, neck, first_level_segment);
        }
    } else if let Some(head) = named("head")
        && !parent_limb.contains_key(&head)
    {
        let four_legged = names.values().any(|n| n.starts_with("leg.front"));
        let split = split_head_off(
            cages,
            roles,
            parent_limb,
            names,
            head,
            first_hanging_segment,
        ) || (four_legged
            && split_head_off(
                cages,
                roles,
                parent_limb,
                names,
                head,
                second_of_a_long_chain,
            ));
        if split {
            names.insert(head, "neck".to_owned());
        }
    }
}

/// Which of a chain's segments is its head's first, from the cages, the leaves' roles, the
/// chain's limb and its segments' vertices.
type FirstHeadSegment = fn(&CageSet, &[Role], usize, &[BTreeSet<u32>]) -> Option<usize>;

/// Where `first_head` (over the chain's segments' vertices) finds a segment, makes the chain
/// `neck`'s segments from it a new limb named `head`, hanging from `neck`. Returns whether it did.
fn split_head_off(
    cages: &CageSet,
    roles: &mut [Role],
    parent_limb: &mut BTreeMap<usize, usize>,
    names: &mut BTreeMap<usize, String>,
    neck: usize,
    first_head: FirstHeadSegment,
) -> bool {
    let limbs = limbs_of(roles, parent_limb);
    let Some(record) = limbs.get(&neck) else {
        return false;
    };
    let segment_vertices: Vec<BTreeSet<u32>> = record
        .segments
        .iter()
        .map(|leaves| {
            leaves
                .iter()
                .flat_map(|&l| vertices_of(&cages.leaves[l]))
                .collect()
        })
        .collect();
    let Some(first_level) = first_head(cages, roles, neck, &segment_vertices) else {
        return false;
    };
    let head = new_limb_id(roles, parent_limb, names);
    let head_vertices: BTreeSet<u32> = segment_vertices[first_level..]
        .iter()
        .flatten()
        .copied()
        .collect();
    let neck_vertices: BTreeSet<u32> = segment_vertices[..first_level]
        .iter()
        .flatten()
        .copied()
        .collect();
    // The neck's segment numbers in order (merges may have left gaps): `record.segments`' order.
    let numbers: Vec<usize> = roles
        .iter()
        .filter_map(|r| match *r {
            Role::Limb { limb, segment } if limb == neck => Some(segment),
            _ => None,
        })
        .collect::<BTreeSet<usize>>()
        .into_iter()
        .collect();
    for role in roles.iter_mut() {
        if let Role::Limb { limb, segment } = *role
            && limb == neck
            && let Ok(index) = numbers.binary_search(&segment)
            && index >= first_level
        {
            *role = Role::Limb {
                limb: head,
                segment: index - first_level,
            };
        }
    }
    // Branches rooted on the head (ears, horns) hang from it.
    for (&child, child_record) in &limbs {
        if parent_limb.get(&child) != Some(&neck) {
            continue;
        }
        let Some(first) = child_record.segments.first() else {
            continue;
        };
        let root: BTreeSet<u32> = first
            .iter()
            .flat_map(|&l| vertices_of(&cages.leaves[l]))
            .collect();
        if root.intersection(&head_vertices).count() > root.intersection(&neck_vertices).count() {
            parent_limb.insert(child, head);
        }
    }
    parent_limb.insert(head, neck);
    names.insert(head, "head".to_owned());
    true
}

/// The first segment after the neck's first whose direction (its pivot to the next one's, the
/// last to its tip) is within 45° of level, where the neck as a whole or its first segment
/// rises (TOSCA's jumping horse10 raises its neck steeply to a head that points down, its
/// muzzle as low as the neck's root); None where neither rises (a bust's neck, hanging to its
/// cut), the neck has one segment, or never runs level.
fn first_level_segment(
    cages: &CageSet,
    roles: &[Role],
    neck: usize,
    segment_vertices: &[BTreeSet<u32>],
) -> Option<usize> {
    let (pivots, tip) = pivots_and_tip(cages, roles, neck, segment_vertices)?;
    let rises = |d: DVec3| d.z > RISING * d.length();
    if !rises(tip - pivots[0]) && !rises(pivots[1] - pivots[0]) {
        return None;
    }
    let level = |d: DVec3| d.z.abs() < d.truncate().length();
    (1..pivots.len()).find(|&k| {
        let next = pivots.get(k + 1).copied().unwrap_or(tip);
        level(next - pivots[k])
    })
}

/// Where a head chain carries a neck: the first segment after the chain's first that does not
/// rise (its direction within 0.3 of its length above level, or falling) where the first
/// rises (a head hanging from a raised neck). None where the chain has one segment, its first
/// does not rise, or all rise (a standing figure's neck and head).
fn first_hanging_segment(
    cages: &CageSet,
    roles: &[Role],
    chain: usize,
    segment_vertices: &[BTreeSet<u32>],
) -> Option<usize> {
    let (pivots, tip) = pivots_and_tip(cages, roles, chain, segment_vertices)?;
    let direction = |k: usize| pivots.get(k + 1).copied().unwrap_or(tip) - pivots[k];
    let rises = |d: DVec3| d.z > RISING * d.length();
    if !rises(direction(0)) {
        return None;
    }
    (1..pivots.len()).find(|&k| !rises(direction(k)))
}

/// On a four-legged figure, a head chain reaching at least [`LONGEST_HEAD_SHARE`] of the
/// figure's height from where it leaves the body carries a neck: its second segment starts
/// the head (a neck held level to a head that hangs: TOSCA's horse). None for a chain of one
/// segment or a shorter one (a dog's head). Not on other figures: a star lying flat, whose
/// height is small, has arms "reaching" several heights.
fn second_of_a_long_chain(
    cages: &CageSet,
    roles: &[Role],
    chain: usize,
    segment_vertices: &[BTreeSet<u32>],
) -> Option<usize> {
    let (pivots, _) = pivots_and_tip(cages, roles, chain, segment_vertices)?;
    let heights = cages.vertices.iter().map(|p| p.z);
    let height = heights.clone().fold(f64::MIN, f64::max) - heights.fold(f64::MAX, f64::min);
    let reach = (segment_vertices.iter().flatten())
        .map(|&v| (cages.vertices[v as usize] - pivots[0]).length())
        .fold(0.0, f64::max);
    (reach >= LONGEST_HEAD_SHARE * height).then_some(1)
}

/// The farthest a head alone reaches from where it leaves the body, as a share of the figure's
/// height (from its lowest to its highest cage vertex). Measured at the default detail: heads
/// of one segment reach 0.11–0.31 (spot 0.31, TOSCA's cat 0.28), TOSCA's wolf's head of two
/// 0.30; TOSCA's horse's neck and head 0.34 (0.37 mirrored).
const LONGEST_HEAD_SHARE: f64 = 0.33;

/// How much of its length a neck rises by, at least.
const RISING: f64 = 0.3;

/// Each segment's pivot of a chain of at least two (the centroid of the ring it shares with
/// what comes before it) and its tip (the last segment's vertex farthest from its pivot).
fn pivots_and_tip(
    cages: &CageSet,
    roles: &[Role],
    chain: usize,
    segment_vertices: &[BTreeSet<u32>],
) -> Option<(Vec<DVec3>, DVec3)> {
    if segment_vertices.len() < 2 {
        return None;
    }
    let point = |v: &u32| cages.vertices[*v as usize];
    let outside: BTreeSet<u32> = cages
        .leaves
        .iter()
        .zip(roles)
        .filter(|(_, r)| !matches!(r, Role::Limb { limb, .. } if *limb == chain))
        .flat_map(|(leaf, _)| vertices_of(leaf))
        .collect();
    let mut pivots: Vec<DVec3> = Vec::with_capacity(segment_vertices.len());
    for (k, vertices) in segment_vertices.iter().enumerate() {
        let before = if k == 0 {
            &outside
        } else {
            &segment_vertices[k - 1]
        };
        pivots.push(centroid(vertices.intersection(before).map(point))?);
    }
    let last = *pivots.last()?;
    let tip = segment_vertices
        .last()?
        .iter()
        .map(point)
        .max_by(|a, b| (*a - last).length().total_cmp(&(*b - last).length()))?;
    Some((pivots, tip))
}

#[cfg(test)]
mod tests {
    use super::super::test_cages::point_cages;
    use super::*;

    /// Four corners of a square of half side 0.1 around `centre`, level.
    fn ring(centre: DVec3) -> Vec<DVec3> {
        [(-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1)]
            .iter()
            .map(|&(dx, dy)| centre + DVec3::new(dx, dy, 0.0))
            .collect()
    }

    /// A body and a neck of three segments through `joints` (the body's ring first, the tip
    /// last): the leaves' roles, the neck limb 0 and the body last.
    fn neck_rig(joints: &[DVec3]) -> (CageSet, Vec<Role>) {
        let mut body = vec![
            DVec3::new(-0.4, -1.0, 0.0),
            DVec3::new(0.4, -1.0, 0.0),
            DVec3::new(0.4, 1.0, 0.8),
            DVec3::new(-0.4, 1.0, 0.8),
        ];
        body.extend(ring(joints[0]));
        let mut cages: Vec<Vec<DVec3>> = joints
            .windows(2)
            .map(|pair| [ring(pair[0]), ring(pair[1])].concat())
            .collect();
        cages.push(body);
        let mut roles: Vec<Role> = (0..joints.len() - 1)
            .map(|segment| Role::Limb { limb: 0, segment })
            .collect();
        roles.push(Role::Body { body: 0, slab: 0 });
        (point_cages(&cages), roles)
    }

    fn split(
        cages: &CageSet,
        roles: &[Role],
        name: &str,
    ) -> (Vec<Role>, BTreeMap<usize, usize>, BTreeMap<usize, String>) {
        split_with(cages, roles, &[name])
    }

    /// [`split`] with more limb names (limbs 0, 1, … named in order; limb 0 the chain).
    fn split_with(
        cages: &CageSet,
        roles: &[Role],
        limb_names: &[&str],
    ) -> (Vec<Role>, BTreeMap<usize, usize>, BTreeMap<usize, String>) {
        let mut roles = roles.to_vec();
        let mut parents = BTreeMap::new();
        let mut names: BTreeMap<usize, String> = (limb_names.iter().enumerate())
            .map(|(l, n)| (l, (*n).to_owned()))
            .collect();
        head_off_neck(cages, &mut roles, &mut parents, &mut names);
        (roles, parents, names)
    }

    /// A neck that rises from the body's front and then runs level (the camel's head held
    /// forward; or rises steeply, then runs forward and down) gives its level segment to a
    /// `head` hanging from it; a neck rising straight
    /// up to its tip, one hanging down (a bust's), and a rig that has a head keep theirs.
    #[test]
    fn the_level_end_of_a_raised_neck_is_its_head() {
        // Joints on the centre plane, as (y, z).
        let joints = |yz: &[(f64, f64)]| -> Vec<DVec3> {
            yz.iter().map(|&(y, z)| DVec3::new(0.0, y, z)).collect()
        };
        let raised = joints(&[(0.9, 0.6), (1.1, 1.2), (1.2, 1.6), (1.7, 1.7)]);
        let (cages, roles) = neck_rig(&raised);
        let (after, parents, names) = split(&cages, &roles, "neck");
        let limb_segments: Vec<(usize, usize)> = after
            .iter()
            .filter_map(|r| match *r {
                Role::Limb { limb, segment } => Some((limb, segment)),
                Role::Body { .. } => None,
            })
            .collect();
        assert_eq!(limb_segments, [(0, 0), (0, 1), (1, 0)], "{after:?}");
        assert_eq!(parents.get(&1), Some(&0));
        assert_eq!(names.get(&1).map(String::as_str), Some("head"));

        // Raised steeply to a head pointing forward and down, its muzzle about as low as the
        // neck's root (TOSCA's jumping horse): the chain as a whole hardly rises, its first
        // segment does.
        let steep = joints(&[(0.9, 0.6), (1.1, 1.4), (1.9, 0.75)]);
        let (cages, roles) = neck_rig(&steep);
        let (after, parents, names) = split(&cages, &roles, "neck");
        assert_eq!(
            after[1],
            Role::Limb {
                limb: 1,
                segment: 0
            },
            "{after:?}"
        );
        assert_eq!(parents.get(&1), Some(&0));
        assert_eq!(names.get(&1).map(String::as_str), Some("head"));

        let straight_up = joints(&[(0.9, 0.6), (1.0, 1.2), (1.1, 1.6), (1.2, 2.0)]);
        let (cages, roles) = neck_rig(&straight_up);
        assert_eq!(split(&cages, &roles, "neck").0, roles);

        let hanging: Vec<DVec3> = raised.iter().map(|p| DVec3::new(p.x, p.y, -p.z)).collect();
        let (cages, roles) = neck_rig(&hanging);
        assert_eq!(split(&cages, &roles, "neck").0, roles);

        let (cages, roles) = neck_rig(&raised);
        let mut roles_with_head = roles.clone();
        let mut parents = BTreeMap::new();
        let mut names = BTreeMap::from([(0, "neck".to_owned()), (5, "head".to_owned())]);
        head_off_neck(&cages, &mut roles_with_head, &mut parents, &mut names);
        assert_eq!(roles_with_head, roles);
    }

    /// A chain named `head` whose head hangs: from a rising first segment (a raised neck), or,
    /// on a four-legged figure, from a level one reaching far from the body (TOSCA's horse),
    /// its first segment becomes the `neck` and the rest the `head` hanging from it. A short
    /// head held level (a dog's), a head whose segments all rise (a standing figure's) and a
    /// long level chain on a figure without legs (an arm of a star lying flat) stay `head`.
    #[test]
    fn a_head_hanging_from_its_chains_first_segment_gets_a_neck() {
        let joints = |yz: &[(f64, f64)]| -> Vec<DVec3> {
            yz.iter().map(|&(y, z)| DVec3::new(0.0, y, z)).collect()
        };
        let head_segments = |after: &[Role]| -> Vec<(usize, usize)> {
            after
                .iter()
                .filter_map(|r| match *r {
                    Role::Limb { limb, segment } => Some((limb, segment)),
                    Role::Body { .. } => None,
                })
                .collect()
        };
        let raised = joints(&[(0.9, 0.6), (1.1, 1.2), (1.5, 1.3), (1.7, 0.9)]);
        let level = joints(&[(0.9, 0.6), (1.9, 0.6), (2.2, 0.2)]);
        for (hanging, limb_names) in [
            (&raised, &["head"][..]),
            (&level, &["head", "leg.front.L"][..]),
        ] {
            let (cages, roles) = neck_rig(hanging);
            let (after, parents, names) = split_with(&cages, &roles, limb_names);
            let new_limb = limb_names.len();
            let mut expected = vec![(0, 0)];
            expected.extend((1..hanging.len() - 1).map(|k| (new_limb, k - 1)));
            assert_eq!(head_segments(&after), expected, "{hanging:?}");
            assert_eq!(parents.get(&new_limb), Some(&0));
            assert_eq!(names.get(&0).map(String::as_str), Some("neck"));
            assert_eq!(names.get(&new_limb).map(String::as_str), Some("head"));
        }
        let (cages, roles) = neck_rig(&level);
        assert_eq!(split(&cages, &roles, "head").0, roles);
        for kept in [
            joints(&[(0.9, 0.6), (0.95, 0.6), (1.0, 0.55)]),
            joints(&[(0.9, 0.6), (1.0, 1.2), (1.1, 1.6), (1.2, 2.0)]),
        ] {
            let (cages, roles) = neck_rig(&kept);
            let (after, _, names) = split(&cages, &roles, "head");
            assert_eq!(after, roles, "{kept:?}");
            assert_eq!(names.get(&0).map(String::as_str), Some("head"));
        }
    }
}
