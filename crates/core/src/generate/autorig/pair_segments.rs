//! A pair of limbs keeps as many segments on both sides. The two limbs of a pair are cut into
//! as many segments (`parts::paired_segment_counts`), but on a figure that is not exactly
//! symmetric a repair can merge a segment of one and not of the other: the beast's right foot
//! holds two pieces of surface its cut cannot part, so it joins the shin, while the left foot
//! stays a segment of its own. The left leg then has a control more than the right, and
//! `leg.L.4` is a foot where `leg.R.4` is a shin. Here the other limb's segment that was merged
//! joins the same neighbour, or a body where the first one's joined one (the horse's right
//! thigh, its haunch, at detail 2), so both legs bend at the same joints.

use std::collections::BTreeMap;

use super::parts::{Parts, Role, contacts_of};
use super::voxels::Grid;

/// For each pair of limbs (`parts.pairs`) whose segment counts differ, merges into each other
/// the longer limb's segments whose counterparts in the shorter limb were merged since the
/// cut: the cells of segment k of the shorter limb (by `cut_roles`, each cell's role when it
/// was cut) now mostly in its segment j (or in a body), the longer limb's segment k joins its
/// segment j (or the body part it touches), part by part into the one it shares most faces
/// with. Returns how many parts were merged.
pub(super) fn equal_pair_segments(
    grid: &Grid,
    parts: &mut Parts,
    cut_roles: &[Option<Role>],
) -> usize {
    let mut merges = 0;
    for &(a, b) in &parts.pairs.clone() {
        let mut by_limb = parts.limb_segments();
        let mut segments_of = |limb| by_limb.remove(&limb).unwrap_or_default();
        let (now_a, now_b) = (segments_of(a), segments_of(b));
        let (short, now_short, now_long) = match now_a.len().cmp(&now_b.len()) {
            std::cmp::Ordering::Less => (a, now_a, now_b),
            std::cmp::Ordering::Greater => (b, now_b, now_a),
            std::cmp::Ordering::Equal => continue,
        };
        // Where the cells of each segment of the short limb went: per cut segment, the cells
        // now in each of its current segments or in a body.
        let mut went: BTreeMap<usize, BTreeMap<Destination, usize>> = BTreeMap::new();
        for (role, label) in cut_roles.iter().zip(&parts.label) {
            if let (Some(Role::Limb { limb, segment }), Some(l)) = (role, label)
                && *limb == short
            {
                let destination = match parts.roles.get(*l as usize) {
                    Some(Role::Limb { limb: now, segment }) if *now == short => {
                        Destination::Segment(*segment)
                    }
                    Some(Role::Body { .. }) => Destination::Body,
                    _ => continue,
                };
                *went
                    .entry(*segment)
                    .or_default()
                    .entry(destination)
                    .or_default() += 1;
            }
        }
        let mut into: BTreeMap<u32, u32> = BTreeMap::new();
        let mut left = now_long.len();
        for (&k, destinations) in &went {
            if left <= now_short.len() || now_short.contains_key(&k) {
                continue;
            }
            let Some((&destination, _)) = destinations
                .iter()
                .max_by_key(|&(d, n)| (n, std::cmp::Reverse(*d)))
            else {
                continue;
            };
            let Some(from) = now_long.get(&k) else {
                continue;
            };
            let joins = |q: u32| match destination {
                Destination::Segment(j) => now_long.get(&j).is_some_and(|to| to.contains(&q)),
                Destination::Body => {
                    matches!(parts.roles.get(q as usize), Some(Role::Body { .. }))
                }
            };
            let mut joined = false;
            for &p in from {
                let contacts = contacts_of(grid, &parts.label, p);
                if let Some((&q, _)) = contacts
                    .iter()
                    .filter(|(q, _)| joins(**q))
                    .max_by_key(|&(q, n)| (n, std::cmp::Reverse(q)))
                {
                    into.insert(p, q);
                    joined = true;
                }
            }
            if joined {
                left -= 1;
            }
        }
        if into.is_empty() {
            continue;
        }
        merges += into.len();
        parts.merge_into(&into);
    }
    merges
}

/// Where the cells of a limb segment went since the cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Destination {
    /// Into another segment of the same limb.
    Segment(usize),
    /// Into a body (a thigh into the haunch it could not be parted from).
    Body,
}

#[cfg(test)]
mod tests {

    use glam::DVec3;

    use super::super::parts::compact;
    use super::*;

    /// Two limbs of three segments each, three cells per segment, on either side of a body
    /// along one row of cells: limb 0 over x 0–8 (its segment 0 at x 6–8), the body over
    /// x 9–19, limb 1 over x 20–28 (its segment 0 at x 20–22). `merged` moves limb 0's segment
    /// `from` into its segment `into`, or into the body where `into` is None (a repair's
    /// merge). Returns the grid, the parts, the cut roles and the cell index of each x.
    fn pair(
        merged: Option<(usize, Option<usize>)>,
    ) -> (Grid, Parts, Vec<Option<Role>>, Vec<usize>) {
        let grid = Grid::around(DVec3::ZERO, DVec3::new(30.0, 1.0, 1.0), 30, None, &[], None);
        let at: Vec<usize> = (0..30)
            .filter_map(|x| grid.index(grid.cell_at(DVec3::new(f64::from(x) + 0.5, 0.5, 0.5))))
            .collect();
        assert_eq!(at.len(), 30);
        let mut label = vec![None; grid.len()];
        let mut cut_roles = vec![None; grid.len()];
        // Parts 0–2: limb 0's segments; 3–5: limb 1's; 6: the body.
        let mut roles: Vec<Role> = (0..2)
            .flat_map(|limb| (0..3).map(move |segment| Role::Limb { limb, segment }))
            .collect();
        roles.push(Role::Body { body: 0, slab: 0 });
        for x in 9..20 {
            label[at[x]] = Some(6);
            cut_roles[at[x]] = Some(roles[6]);
        }
        for (limb, first) in [(0, 8), (1, 20)] {
            for k in 0..9 {
                let x = if limb == 0 { first - k } else { first + k };
                let segment = k / 3;
                cut_roles[at[x]] = Some(Role::Limb { limb, segment });
                let part = match merged {
                    Some((from, Some(into))) if limb == 0 && segment == from => into,
                    Some((from, None)) if limb == 0 && segment == from => 6,
                    _ => 3 * limb + segment,
                };
                label[at[x]] = Some(part as u32);
            }
        }
        let mut parts = Parts {
            pairs: vec![(0, 1)],
            ..Parts::of_roles(label, roles)
        };
        compact(&mut parts);
        (grid, parts, cut_roles, at)
    }

    /// Limb 1's segment at each x in 20–28 (None: a body's cell).
    fn segments_of_limb_1(parts: &Parts, at: &[usize]) -> Vec<Option<usize>> {
        (20..29)
            .map(
                |x| match parts.label[at[x]].map(|l| parts.roles[l as usize]) {
                    Some(Role::Limb { limb: 1, segment }) => Some(segment),
                    Some(Role::Body { .. }) => None,
                    other => panic!("x = {x}: {other:?}"),
                },
            )
            .collect()
    }

    #[test]
    fn the_other_limb_s_tip_joins_the_segment_the_first_limb_s_tip_joined() {
        let (grid, mut parts, cut_roles, at) = pair(Some((2, Some(1))));
        assert_eq!(equal_pair_segments(&grid, &mut parts, &cut_roles), 1);
        let expected = [0, 0, 0, 1, 1, 1, 1, 1, 1].map(Some);
        assert_eq!(segments_of_limb_1(&parts, &at), expected);
    }

    #[test]
    fn a_middle_segment_merged_into_the_first_is_mirrored_as_such() {
        // Negative control for the tip: here the middle segment went the other way.
        let (grid, mut parts, cut_roles, at) = pair(Some((1, Some(0))));
        assert_eq!(equal_pair_segments(&grid, &mut parts, &cut_roles), 1);
        let expected = [0, 0, 0, 0, 0, 0, 2, 2, 2].map(Some);
        assert_eq!(segments_of_limb_1(&parts, &at), expected);
    }

    #[test]
    fn a_first_segment_merged_into_the_body_is_mirrored_on_the_other_limb() {
        // The horse's thigh at detail 2, which joined its haunch on one side only.
        let (grid, mut parts, cut_roles, at) = pair(Some((0, None)));
        assert_eq!(equal_pair_segments(&grid, &mut parts, &cut_roles), 1);
        let expected = [
            None,
            None,
            None,
            Some(1),
            Some(1),
            Some(1),
            Some(2),
            Some(2),
            Some(2),
        ];
        assert_eq!(segments_of_limb_1(&parts, &at), expected);
    }

    #[test]
    fn limbs_with_as_many_segments_are_left_alone() {
        let (grid, mut parts, cut_roles, at) = pair(None);
        let before = parts.clone();
        assert_eq!(equal_pair_segments(&grid, &mut parts, &cut_roles), 0);
        assert_eq!(parts.label, before.label);
        let expected = [0, 0, 0, 1, 1, 1, 2, 2, 2].map(Some);
        assert_eq!(segments_of_limb_1(&parts, &at), expected);
        // A pair not listed is not made equal.
        let (grid, mut parts, cut_roles, _) = pair(Some((2, Some(1))));
        parts.pairs.clear();
        assert_eq!(equal_pair_segments(&grid, &mut parts, &cut_roles), 0);
    }
}
