//! Limbs no control can hold. A limb whose leaf cages add no vertex of their own (every one of
//! their vertices is also a vertex of a cage outside it) gets no control: each vertex already
//! belongs to the body or to another limb's segment. It still had a name and blocked what reads
//! names: TOSCA's walking horse had a `head` of two small cages under its poll (12 vertices,
//! all shared with the neck), so no head was split off its neck, and the rig had `neck.1`–
//! `neck.3` and no `head` control. Such a limb, carrying no other, joins the segment (or body
//! slab) its cages share the most vertices with, and its name goes.

use std::collections::{BTreeMap, BTreeSet};

use super::controls::{limbs_of, vertices_of};
use super::parts::Role;
use crate::scene::CageSet;

/// Folds every ownerless limb that carries no other into the role (limb segment or body slab)
/// its cages share the most vertices with (see the module); a limb touching nothing stays.
/// Leaves joining a body slab take its cages' name with a letter (`body_3b`); those joining a
/// limb are renamed with it later. Returns how many limbs were folded.
pub(super) fn fold_ownerless_limbs(
    cages: &mut CageSet,
    roles: &mut [Role],
    parent_limb: &mut BTreeMap<usize, usize>,
    names: &mut BTreeMap<usize, String>,
) -> usize {
    let mut folded = 0;
    // One fold at a time: each changes which vertices the others share.
    while let Some((limb, into)) = next_ownerless(cages, roles, parent_limb) {
        let slab_name = roles
            .iter()
            .zip(&cages.leaves)
            .find(|(role, _)| **role == into)
            .map(|(_, leaf)| leaf.name.trim_end_matches(|c: char| c.is_ascii_lowercase()))
            .map(str::to_owned);
        for (leaf, role) in cages.leaves.iter_mut().zip(roles.iter_mut()) {
            if matches!(*role, Role::Limb { limb: l, .. } if l == limb) {
                *role = into;
                if let (Role::Body { .. }, Some(base)) = (into, &slab_name) {
                    leaf.name = base.clone();
                }
            }
        }
        if let Role::Body { .. } = into {
            letter_duplicate_names(cages);
        }
        parent_limb.remove(&limb);
        names.remove(&limb);
        folded += 1;
    }
    folded
}

/// Gives each leaf whose name an earlier leaf has the first letter after it that makes a name
/// no leaf has (`body_3b`); names held once stay as they are.
fn letter_duplicate_names(cages: &mut CageSet) {
    let mut used: BTreeSet<String> = cages.leaves.iter().map(|l| l.name.clone()).collect();
    let mut seen: BTreeSet<String> = BTreeSet::new();
    for leaf in &mut cages.leaves {
        if seen.insert(leaf.name.clone()) {
            continue;
        }
        let base = leaf.name.clone();
        if let Some(free) = (b'b'..=b'z')
            .map(|c| format!("{base}{}", char::from(c)))
            .find(|n| !used.contains(n))
        {
            used.insert(free.clone());
            seen.insert(free.clone());
            leaf.name = free;
        }
    }
}

/// The first ownerless limb carrying no other and the role it joins.
fn next_ownerless(
    cages: &CageSet,
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
) -> Option<(usize, Role)> {
    let limbs = limbs_of(roles, parent_limb);
    let carriers: BTreeSet<usize> = limbs.values().filter_map(|r| r.parent).collect();
    limbs
        .iter()
        .filter(|(limb, _)| !carriers.contains(limb))
        .find_map(|(&limb, record)| {
            let own: BTreeSet<usize> = record.segments.iter().flatten().copied().collect();
            let vertices: BTreeSet<u32> = own
                .iter()
                .filter_map(|&l| cages.leaves.get(l))
                .flat_map(vertices_of)
                .collect();
            // How many of the limb's vertices each outside role's cages hold.
            let mut shared: BTreeMap<Role, usize> = BTreeMap::new();
            let mut outside: BTreeSet<u32> = BTreeSet::new();
            for (leaf, (cage, role)) in cages.leaves.iter().zip(roles).enumerate() {
                if own.contains(&leaf) {
                    continue;
                }
                let held: BTreeSet<u32> = vertices_of(cage)
                    .into_iter()
                    .filter(|v| vertices.contains(v))
                    .collect();
                if held.is_empty() {
                    continue;
                }
                *shared.entry(*role).or_insert(0) += held.len();
                outside.extend(held);
            }
            if vertices.is_empty() || outside.len() < vertices.len() {
                return None;
            }
            let into = shared
                .into_iter()
                .max_by_key(|&(role, n)| (n, std::cmp::Reverse(role)))
                .map(|(role, _)| role)?;
            Some((limb, into))
        })
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::test_cages::point_cages;
    use super::*;

    fn p(x: f64, z: f64) -> DVec3 {
        DVec3::new(x, 0.0, z)
    }

    fn limb(limb: usize, segment: usize) -> Role {
        Role::Limb { limb, segment }
    }

    /// A body (leaf 0); a neck of two segments (limb 1: leaves 1, 2); a small piece (limb 2,
    /// leaf 3) between the neck's segments whose points all lie on them, three on the second
    /// and one on the first, plus `own` points of its own.
    fn neck_with_piece(own: usize) -> (CageSet, Vec<Role>) {
        let body = vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
        let neck_1 = vec![
            p(0.0, 1.0),
            p(1.0, 1.0),
            p(1.0, 2.0),
            p(0.0, 2.0),
            p(-0.5, 1.5),
        ];
        let neck_2 = vec![
            p(1.0, 2.0),
            p(0.0, 2.0),
            p(0.0, 3.0),
            p(1.0, 3.0),
            p(0.5, 2.5),
            p(0.6, 2.6),
        ];
        let mut piece = vec![p(1.0, 2.0), p(0.5, 2.5), p(0.6, 2.6), p(0.0, 1.0)];
        for k in 0..own {
            piece.push(p(1.5 + 0.1 * k as f64, 2.5));
        }
        let cages = point_cages(&[body, neck_1, neck_2, piece]);
        let roles = vec![
            Role::Body { body: 0, slab: 0 },
            limb(1, 0),
            limb(1, 1),
            limb(2, 0),
        ];
        (cages, roles)
    }

    /// The piece all of whose points its neighbours hold joins the neck's second segment,
    /// which holds most of them, and its name goes; with one point of its own it stays.
    #[test]
    fn a_limb_with_no_vertex_of_its_own_joins_the_segment_sharing_most() {
        let names = || BTreeMap::from([(1, "neck".to_owned()), (2, "head".to_owned())]);
        let (mut cages, mut roles) = neck_with_piece(0);
        let (mut parents, mut named) = (BTreeMap::new(), names());
        assert_eq!(
            fold_ownerless_limbs(&mut cages, &mut roles, &mut parents, &mut named),
            1
        );
        assert_eq!(roles[3], limb(1, 1));
        assert_eq!(named, BTreeMap::from([(1, "neck".to_owned())]));

        let (mut cages, mut roles) = neck_with_piece(1);
        let (mut parents, mut named) = (BTreeMap::new(), names());
        assert_eq!(
            fold_ownerless_limbs(&mut cages, &mut roles, &mut parents, &mut named),
            0
        );
        assert_eq!(roles[3], limb(2, 0));
        assert_eq!(named, names());
    }

    /// A piece lying on the body joins the body's slab and takes its cages' name with a
    /// letter.
    #[test]
    fn a_limb_on_the_body_joins_its_slab_and_name() {
        let body = vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
        let arm = vec![p(1.0, 0.0), p(1.0, 1.0), p(2.0, 0.0), p(2.0, 1.0)];
        let piece = vec![p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0), p(1.0, 1.0)];
        let leg = vec![p(0.0, 0.0), p(0.0, -1.0), p(0.5, -1.0)];
        let mut cages = point_cages(&[body, arm, piece, leg]);
        // A later cage already has the first lettered name: it keeps it.
        cages.leaves[3].name = "cage0b".to_owned();
        let mut roles = vec![
            Role::Body { body: 0, slab: 0 },
            limb(1, 0),
            limb(2, 0),
            limb(3, 0),
        ];
        let mut named = BTreeMap::from([(1, "arm.L".to_owned()), (2, "arm.L.001".to_owned())]);
        let folded = fold_ownerless_limbs(&mut cages, &mut roles, &mut BTreeMap::new(), &mut named);
        assert_eq!(folded, 1);
        assert_eq!(roles[2], Role::Body { body: 0, slab: 0 });
        assert_eq!(cages.leaves[2].name, "cage0c");
        assert_eq!(cages.leaves[3].name, "cage0b");
        assert_eq!(named, BTreeMap::from([(1, "arm.L".to_owned())]));
    }

    /// A limb carrying another stays even where it owns nothing: its child hangs from it.
    #[test]
    fn a_limb_carrying_another_stays() {
        let (mut cages, mut roles) = neck_with_piece(0);
        // The neck's second segment is a limb of its own hanging from the piece.
        roles[2] = limb(3, 0);
        let mut parents = BTreeMap::from([(3, 2)]);
        let mut named = BTreeMap::from([(1, "neck".to_owned()), (2, "head".to_owned())]);
        fold_ownerless_limbs(&mut cages, &mut roles, &mut parents, &mut named);
        assert_eq!(roles[3], limb(2, 0));
        assert!(named.contains_key(&2));
    }
}
