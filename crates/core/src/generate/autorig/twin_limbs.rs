//! One limb cut into two side by side. Where a thick limb leaves its body along a long ring,
//! the cut can start it twice: the cartoon elephant's arm at the default detail was `arm.L`, a
//! one-segment piece of the shoulder, and `arm.L.001`, the lower half of the shoulder and the
//! rest of the arm, both rooted on the torso and touching along the arm. Each got a control,
//! and neither turned the whole arm. A one-segment limb named as another (the same role and
//! side: `arm.L` and `arm.L.001`), growing from the same place, carrying nothing and touching
//! it along a good share of its cages, joins that limb's first segment.

use std::collections::BTreeMap;

use super::controls::{limb_vertex_sets, limbs_of};
use super::parts::Role;
use crate::scene::CageSet;
use crate::scene::rig_names::without_copy_number;

/// The least share of the one-segment limb's cage vertices the two limbs share: the
/// elephant's shoulder piece shares 10 of its 25 with its arm; two legs touching at a crotch
/// (the Ogre's at detail 1, `leg` and `leg.001`) share a few.
const TWIN_SHARE: f64 = 0.25;

/// Merges each one-segment twin into its limb (see the module): its leaves become part of the
/// limb's first segment, its name goes, and the limb takes the plain name where the twin had
/// it. Returns how many twins were merged.
pub(super) fn merge_twin_limbs(
    cages: &CageSet,
    roles: &mut [Role],
    parent_limb: &mut BTreeMap<usize, usize>,
    names: &mut BTreeMap<usize, String>,
) -> usize {
    let mut merged = 0;
    // One merge at a time: each changes the limbs.
    while let Some((twin, into)) = next_twin(cages, roles, parent_limb, names) {
        let first_segment = roles
            .iter()
            .filter_map(|r| match *r {
                Role::Limb { limb, segment } if limb == into => Some(segment),
                _ => None,
            })
            .min()
            .unwrap_or(0);
        for role in roles.iter_mut() {
            if matches!(*role, Role::Limb { limb, .. } if limb == twin) {
                *role = Role::Limb {
                    limb: into,
                    segment: first_segment,
                };
            }
        }
        parent_limb.remove(&twin);
        if let Some(twin_name) = names.remove(&twin)
            && let Some(name) = names.get_mut(&into)
            && twin_name == without_copy_number(name)
        {
            *name = twin_name;
        }
        merged += 1;
    }
    merged
}

/// The first twin and the limb it joins, if any.
fn next_twin(
    cages: &CageSet,
    roles: &[Role],
    parent_limb: &BTreeMap<usize, usize>,
    names: &BTreeMap<usize, String>,
) -> Option<(usize, usize)> {
    let limbs = limbs_of(roles, parent_limb);
    let vertices = limb_vertex_sets(cages, &limbs);
    let carries = |limb: usize| limbs.values().any(|r| r.parent == Some(limb));
    for (&twin, record) in &limbs {
        let Some(twin_name) = names.get(&twin) else {
            continue;
        };
        if record.segments.len() != 1 || carries(twin) {
            continue;
        }
        let twin_vertices = &vertices[&twin];
        let into = limbs
            .iter()
            .filter(|&(&other, other_record)| {
                other != twin
                    && other_record.parent == record.parent
                    && names
                        .get(&other)
                        .is_some_and(|n| without_copy_number(n) == without_copy_number(twin_name))
            })
            .map(|(&other, other_record)| {
                let shared = twin_vertices.intersection(&vertices[&other]).count();
                (
                    shared,
                    other_record.segments.len(),
                    vertices[&other].len(),
                    other,
                )
            })
            .filter(|&(shared, ..)| shared as f64 >= TWIN_SHARE * twin_vertices.len() as f64)
            // Of two one-segment twins, the smaller joins the larger.
            .filter(|&(_, segments, size, _)| segments > 1 || size > twin_vertices.len())
            .max()
            .map(|(.., other)| other);
        if let Some(into) = into {
            return Some((twin, into));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::test_cages::point_cages;
    use super::*;

    fn p(x: f64, z: f64) -> DVec3 {
        DVec3::new(x, 0.0, z)
    }

    /// A body (leaf 0); an arm of two segments (limb 1: leaves 1, 2); a one-segment piece
    /// (limb 2, leaf 3) on the body above the arm's first segment, touching its second along
    /// `touching` points; a leg (limb 3, leaf 4) touching nothing but the body.
    fn shoulder(touching: usize) -> (CageSet, Vec<Role>) {
        let body = vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 2.0),
            p(1.0, 1.75),
            p(1.0, 1.5),
            p(1.0, 1.0),
        ];
        let arm_1 = vec![p(1.0, 1.0), p(1.0, 1.5), p(1.5, 1.0), p(1.5, 1.5)];
        let mut arm_2 = vec![p(1.5, 1.0), p(1.5, 1.5), p(2.5, 1.0), p(2.5, 1.5)];
        let mut piece = vec![p(1.0, 1.75), p(1.0, 2.0), p(1.2, 2.0), p(1.3, 1.9)];
        for k in 0..touching {
            let q = p(1.6 + 0.1 * k as f64, 1.6);
            arm_2.push(q);
            piece.push(q);
        }
        let leg = vec![p(0.0, 0.0), p(0.2, -1.0), p(0.3, -1.0)];
        let cages = point_cages(&[body, arm_1, arm_2, piece, leg]);
        let roles = vec![
            Role::Body { body: 0, slab: 0 },
            Role::Limb {
                limb: 1,
                segment: 0,
            },
            Role::Limb {
                limb: 1,
                segment: 1,
            },
            Role::Limb {
                limb: 2,
                segment: 0,
            },
            Role::Limb {
                limb: 3,
                segment: 0,
            },
        ];
        (cages, roles)
    }

    /// The shoulder piece touching the arm along four points of its eight joins the arm's
    /// first segment, and the arm takes the plain name; touching it at none, or named as
    /// another limb, it stays.
    #[test]
    fn a_one_segment_twin_touching_its_limb_joins_its_first_segment() {
        let named = |piece: &str| {
            BTreeMap::from([
                (1, "arm.L.001".to_owned()),
                (2, piece.to_owned()),
                (3, "leg.L".to_owned()),
            ])
        };
        let (cages, roles) = shoulder(4);
        let mut after = roles.clone();
        let mut parents = BTreeMap::new();
        let mut names = named("arm.L");
        assert_eq!(
            merge_twin_limbs(&cages, &mut after, &mut parents, &mut names),
            1
        );
        assert_eq!(
            after[3],
            Role::Limb {
                limb: 1,
                segment: 0
            }
        );
        assert_eq!(
            after[4],
            Role::Limb {
                limb: 3,
                segment: 0
            }
        );
        assert_eq!(
            names,
            BTreeMap::from([(1, "arm.L".to_owned()), (3, "leg.L".to_owned())])
        );
        // Negative controls: not touching, and not named alike.
        let (cages, roles) = shoulder(0);
        let mut after = roles.clone();
        let mut names = named("arm.L");
        assert_eq!(
            merge_twin_limbs(&cages, &mut after, &mut parents, &mut names),
            0
        );
        assert_eq!(after, roles);
        let (cages, roles) = shoulder(4);
        let mut after = roles.clone();
        let mut names = named("ear.L");
        assert_eq!(
            merge_twin_limbs(&cages, &mut after, &mut parents, &mut names),
            0
        );
        assert_eq!(names.len(), 3);
    }
}
