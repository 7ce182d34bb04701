//! Plain `limb.N` names for a shape that is no figure: where naming by role gave two limbs
//! alike in reach one role and side that a figure has one of, the shape is a hand's fingers
//! or an octopus's arms, not a figure's head, arms and ears.
//!
//! It reads the rig [`super::autorig`] chose, not each grid's: the rigs of one mesh are
//! compared by how their names look (`name_defects`), and a rig renamed here would always
//! look clean (the elephant's first rig, whose ears are a second `arm.L` and `arm.R`, would
//! have beaten the mirrored one that names them ears).

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;

use super::Autorig;
use crate::geometry::{dominant_eigenvector, scatter_about};
use crate::scene::rig_names::{limb_of_control, limb_of_leaf, role_and_side, segment_of_leaf};

/// The roles a figure has one of (on the centre line) or one of a side: a head, a neck, a
/// tail, hips; an arm, an ear, a horn, a shoulder, a hip. Legs are not among them: a
/// quadruped has two a side, an insect three.
const ONE_EACH: [&str; 9] = [
    "head", "neck", "tail", "hips", "arm", "ear", "horn", "shoulder", "hip",
];

/// Renames every limb of `rig` `limb.N` (N counting limbs by place, [`in_order_of_place`]:
/// its leaf cages `limb.N_K`, its controls `limb.N.K`) where its names are no figure's. Without a pair
/// of legs under it, one either side, a shape is none where two limbs alike in reach take one
/// role and side ([`alike_twice`]: `arm.L` and `arm.L.001`, a hand's fingers) or a side has an
/// ear and a horn that grow from no head (two fingers on top of a palm). On a pair of legs,
/// the same among whole limbs out from the body each reaching half as far as its longest leg
/// (an octopus standing on two of its arms).
pub(super) fn limbs_unless_a_figure(rig: &mut Autorig) {
    let reach = limb_reaches(rig);
    // Only limbs with leaf cages: the merges in naming leave names behind.
    let limbs: Vec<&(String, Option<String>)> = (rig.report.limb_parents.iter())
        .filter(|(name, _)| reach.contains_key(name.as_str()))
        .collect();
    let parsed: Vec<(&str, Option<&str>)> = limbs.iter().map(|(n, _)| role_and_side(n)).collect();
    let legs_paired = ["L", "R"].iter().all(|side| {
        parsed
            .iter()
            .any(|(role, s)| *role == "leg" && *s == Some(*side))
    });
    let reach_of = |k: usize| {
        limbs
            .get(k)
            .and_then(|(name, _)| reach.get(name.as_str()))
            .copied()
            .unwrap_or(0.0)
    };
    let keyed = |k: usize| (parsed[k], reach_of(k));
    let no_figure = if legs_paired {
        let longest_leg = (0..parsed.len())
            .filter(|&k| parsed[k].0 == "leg")
            .map(reach_of)
            .fold(0.0, f64::max);
        // A whole limb out from the body: not on a head (Cheburashka's ears, `arm.R.001` at
        // detail 1), carrying no limb (the armadillo's hip, `arm.L` carrying `leg.L` at
        // detail 4), and long.
        let whole = |k: usize| {
            let name = limbs[k].0.as_str();
            limbs[k].1.is_none()
                && !limbs.iter().any(|(_, p)| p.as_deref() == Some(name))
                && reach_of(k) >= 0.5 * longest_leg
        };
        alike_twice((0..parsed.len()).filter(|&k| whole(k)).map(keyed))
    } else {
        let headless_horn = limbs
            .iter()
            .zip(&parsed)
            .any(|((_, parent), (role, side))| {
                let on_a_head = parent
                    .as_deref()
                    .is_some_and(|p| role_and_side(p).0 == "head");
                *role == "horn"
                    && side.is_some()
                    && !on_a_head
                    && parsed.iter().any(|(r, s)| *r == "ear" && s == side)
            });
        headless_horn || alike_twice((0..parsed.len()).map(keyed))
    };
    if no_figure {
        let names: Vec<String> = limbs.iter().map(|(name, _)| name.clone()).collect();
        let names = in_order_of_place(rig, names);
        rename(rig, &names);
    }
}

/// `limbs` in the order of where they grow from (so that `limb.1` … `limb.N` run across a
/// hand from one side to the other, or round an octopus): by their roots' place along the
/// roots' longest spread where they lie near a line, by their angle round the roots' middle in
/// the plane of their two longest spreads, starting after the widest gap, where they lie round
/// it. A limb's root is the middle of its first segment's leaf cages. The spreads' directions
/// point each to where its largest coordinate grows, so the order is the same wherever the
/// shape lies. Limbs whose roots are unknown keep their order, after the others.
fn in_order_of_place(rig: &Autorig, limbs: Vec<String>) -> Vec<String> {
    let roots: Vec<Option<DVec3>> = limbs.iter().map(|l| limb_root(rig, l)).collect();
    let known: Vec<DVec3> = roots.iter().flatten().copied().collect();
    let Some(spreads) = Spreads::of(&known) else {
        return limbs;
    };
    let along_a_line = spreads.second < LINE_SPREAD * spreads.first;
    let key = |root: DVec3| -> f64 {
        let d = root - spreads.middle;
        if along_a_line {
            d.dot(spreads.longest)
        } else {
            d.dot(spreads.next).atan2(d.dot(spreads.longest))
        }
    };
    let mut keyed: Vec<(f64, String)> = Vec::new();
    let mut unknown: Vec<String> = Vec::new();
    for (limb, root) in limbs.into_iter().zip(roots) {
        match root {
            Some(root) => keyed.push((key(root), limb)),
            None => unknown.push(limb),
        }
    }
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    if !along_a_line && keyed.len() > 1 {
        // Round the middle: start after the widest gap between neighbouring angles.
        let n = keyed.len();
        let gap = |k: usize| {
            let next = keyed[(k + 1) % n].0
                + if k + 1 == n {
                    std::f64::consts::TAU
                } else {
                    0.0
                };
            next - keyed[k].0
        };
        let widest = (0..n)
            .max_by(|&a, &b| gap(a).total_cmp(&gap(b)))
            .unwrap_or(n - 1);
        keyed.rotate_left((widest + 1) % n);
    }
    keyed
        .into_iter()
        .map(|(_, limb)| limb)
        .chain(unknown)
        .collect()
}

/// How much smaller the roots' second spread (variance) must be than their first for them to
/// lie along a line rather than round a middle: a hand's four fingers and thumb lie along its
/// knuckles, an octopus's arms round its mantle.
const LINE_SPREAD: f64 = 0.25;

/// The middle of a limb's first segment: its leaf cages `<limb>_<K>…` of the lowest K.
fn limb_root(rig: &Autorig, limb: &str) -> Option<DVec3> {
    let segment_of =
        |name: &str| segment_of_leaf(name).filter(|_| limb_of_leaf(name) == Some(limb));
    let first = rig
        .cages
        .leaves
        .iter()
        .filter_map(|l| segment_of(&l.name))
        .min()?;
    let vertices: BTreeSet<u32> = (rig.cages.leaves.iter())
        .filter(|l| segment_of(&l.name) == Some(first))
        .flat_map(|l| l.faces.iter().flatten().copied())
        .collect();
    let points: Vec<DVec3> = (vertices.iter())
        .filter_map(|&v| rig.cages.vertices.get(v as usize).copied())
        .collect();
    (!points.is_empty()).then(|| points.iter().sum::<DVec3>() / points.len() as f64)
}

/// Points' middle and their two longest spreads: the directions and sizes of their scatter's
/// ([`scatter_about`]) two largest eigenvalues.
struct Spreads {
    middle: DVec3,
    longest: DVec3,
    first: f64,
    next: DVec3,
    second: f64,
}

impl Spreads {
    /// None for fewer than two points or points all in one place.
    fn of(points: &[DVec3]) -> Option<Self> {
        if points.len() < 2 {
            return None;
        }
        let middle = points.iter().sum::<DVec3>() / points.len() as f64;
        let scatter = scatter_about(points.iter().copied(), middle);
        let (longest, first) = dominant_eigenvector(scatter)?;
        let rest = scatter
            - glam::DMat3::from_cols(
                longest * longest.x,
                longest * longest.y,
                longest * longest.z,
            ) * first;
        let (next, second) =
            dominant_eigenvector(rest).unwrap_or((longest.any_orthonormal_vector(), 0.0));
        Some(Self {
            middle,
            longest,
            first,
            next,
            second,
        })
    }
}

/// Whether two of `limbs` (role and side, reach) alike in reach (the shorter at least
/// [`ALIKE`] of the longer) take one role a figure has one of (a side): two fingers, not an
/// arm and a piece of it (QMVC's ManHead at detail 4: an `arm.R.001` 0.38 of its `arm.R`).
fn alike_twice<'a>(limbs: impl Iterator<Item = ((&'a str, Option<&'a str>), f64)>) -> bool {
    let mut by_role: BTreeMap<(&str, Option<&str>), Vec<f64>> = BTreeMap::new();
    for (key, reach) in limbs.filter(|((role, _), _)| ONE_EACH.contains(role)) {
        by_role.entry(key).or_default().push(reach);
    }
    by_role.values().any(|reaches| {
        reaches.iter().enumerate().any(|(i, a)| {
            reaches[i + 1..]
                .iter()
                .any(|b| a.min(*b) >= ALIKE * a.max(*b))
        })
    })
}

/// How alike two limbs' reaches are to be taken for two of a kind, the shorter's share of the
/// longer: libigl's hand's two `arm.L` fingers 0.87, its octopus's two short `head`s 0.91;
/// the armadillo's left hip, `arm.L.001` beside its left arm at detail 5, 0.69.
const ALIKE: f64 = 0.75;

/// How far each limb reaches, by name: the diagonal of its leaf cages' vertices' box.
fn limb_reaches(rig: &Autorig) -> BTreeMap<&str, f64> {
    let mut vertices: BTreeMap<&str, BTreeSet<u32>> = BTreeMap::new();
    for leaf in &rig.cages.leaves {
        if let Some(limb) = limb_of_leaf(&leaf.name) {
            let set = vertices.entry(limb).or_default();
            set.extend(leaf.faces.iter().flatten().copied());
        }
    }
    vertices
        .into_iter()
        .filter(|(_, set)| !set.is_empty())
        .map(|(limb, set)| {
            let points: Vec<DVec3> = set
                .iter()
                .filter_map(|&v| rig.cages.vertices.get(v as usize).copied())
                .collect();
            let (lo, hi) = crate::cage::bounds_of(&points);
            (limb, (hi - lo).length())
        })
        .collect()
}

/// Renames each of `limbs` `limb.N`, N its place among them, in the report, its leaf cages
/// and its controls.
fn rename(rig: &mut Autorig, limbs: &[String]) {
    let new_names: BTreeMap<&str, String> = (limbs.iter().enumerate())
        .map(|(k, name)| (name.as_str(), format!("limb.{}", k + 1)))
        .collect();
    let renamed = |name: &str| new_names.get(name).cloned();
    for (name, parent) in &mut rig.report.limb_parents {
        if let Some(new) = renamed(name) {
            *name = new;
        }
        if let Some(new) = parent.as_deref().and_then(renamed) {
            *parent = Some(new);
        }
    }
    for leaf in &mut rig.cages.leaves {
        if let Some((limb, rest)) = leaf.name.rsplit_once('_')
            && let Some(new) = renamed(limb)
        {
            leaf.name = format!("{new}_{rest}");
        }
    }
    for control in &mut rig.cages.internals {
        if let Some(limb) = limb_of_control(&control.name)
            && let Some(new) = renamed(limb)
            && let Some((_, segment)) = control.name.rsplit_once('.')
        {
            control.name = format!("{new}.{segment}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::AutorigReport;
    use super::super::test_cages::point_cages;
    use super::*;
    use crate::scene::InternalCage;

    /// A rig whose limb k (named `names[k]`, hanging from `parents[k]`) has one leaf cage, a
    /// triangle `reaches[k]` long along X at height k, and one control.
    fn rig(names: &[&str], parents: &[Option<&str>], reaches: &[f64]) -> Autorig {
        let triangles: Vec<Vec<DVec3>> = reaches
            .iter()
            .enumerate()
            .map(|(k, &reach)| {
                let z = k as f64;
                vec![
                    DVec3::new(0.0, 0.0, z),
                    DVec3::new(reach, 0.0, z),
                    DVec3::new(0.0, 0.1, z),
                ]
            })
            .collect();
        let mut cages = point_cages(&triangles);
        for (leaf, name) in cages.leaves.iter_mut().zip(names) {
            leaf.name = format!("{name}_1");
        }
        cages.internals = names
            .iter()
            .map(|name| InternalCage {
                name: format!("{name}.1"),
                kind: crate::coords::CoordinateKind::MeanValue,
                faces: Vec::new(),
                owns: Vec::new(),
                pivot: None,
                joint: Vec::new(),
            })
            .collect();
        let report = AutorigReport {
            limb_parents: names
                .iter()
                .zip(parents)
                .map(|(n, p)| ((*n).to_owned(), p.map(str::to_owned)))
                .collect(),
            ..AutorigReport::default()
        };
        Autorig { cages, report }
    }

    /// A rig of limbs `names`, none on another, each one leaf cage: a triangle at `roots[k]`,
    /// pointing up, and its second segment's above it.
    fn rig_with_roots(names: &[&str], roots: &[DVec3]) -> Autorig {
        let triangle = |at: DVec3| vec![at, at + DVec3::X * 0.1, at + DVec3::Z * 0.1];
        let leaves: Vec<Vec<DVec3>> = (roots.iter())
            .flat_map(|&root| [triangle(root + DVec3::Z), triangle(root)])
            .collect();
        let mut cages = point_cages(&leaves);
        for (k, name) in names.iter().enumerate() {
            cages.leaves[2 * k].name = format!("{name}_2");
            cages.leaves[2 * k + 1].name = format!("{name}_1b");
        }
        let report = AutorigReport {
            limb_parents: names.iter().map(|n| ((*n).to_owned(), None)).collect(),
            ..AutorigReport::default()
        };
        Autorig { cages, report }
    }

    /// The number `limb.N` each of `rig`'s leaf cages named `<limb>_1b` took, in the rig's order.
    fn numbers_of_first_segments(rig: &Autorig) -> Vec<usize> {
        (rig.cages.leaves.iter())
            .filter_map(|l| {
                l.name
                    .strip_suffix("_1b")?
                    .strip_prefix("limb.")?
                    .parse()
                    .ok()
            })
            .collect()
    }

    #[test]
    fn fingers_are_numbered_across_the_hand_and_arms_round_the_octopus() {
        // A hand's four fingers along its knuckles (X) and a thumb below the first, listed out
        // of order, as the rig's order of limbs can be.
        let names = ["arm.L", "arm.L.001", "arm.R", "ear.R", "head"];
        let roots = [
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(-0.3, 0.0, -1.0),
            DVec3::new(3.0, 0.0, 0.1),
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.1),
        ];
        let mut hand = rig_with_roots(&names, &roots);
        limbs_unless_a_figure(&mut hand);
        // Along the knuckles, the way X grows: the thumb first here, last in the mirror image.
        assert_eq!(numbers_of_first_segments(&hand), [4, 1, 5, 2, 3]);
        let mut mirrored = rig_with_roots(&names, &roots.map(|r| DVec3::new(-r.x, r.y, r.z)));
        limbs_unless_a_figure(&mut mirrored);
        assert_eq!(numbers_of_first_segments(&mirrored), [2, 5, 1, 4, 3]);
        // Eight arms round a mantle, listed out of order: numbered round it, each next to the
        // one before.
        let names = [
            "head", "head.001", "neck", "tail", "leg.R", "ear.L", "ear.R", "head.002",
        ];
        let angles = [0, 3, 6, 1, 4, 7, 2, 5];
        let roots: Vec<DVec3> = (angles.iter())
            .map(|&k| {
                let a = k as f64 * std::f64::consts::TAU / 8.0;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let mut octopus = rig_with_roots(&names, &roots);
        limbs_unless_a_figure(&mut octopus);
        let numbers = numbers_of_first_segments(&octopus);
        let mut by_number = [0usize; 8];
        for (k, &n) in numbers.iter().enumerate() {
            by_number[n - 1] = angles[k];
        }
        for n in 0..8 {
            let step = (by_number[(n + 1) % 8] + 8 - by_number[n]) % 8;
            assert!(
                step == 1 || step == 7,
                "arms {by_number:?} out of order round the mantle"
            );
        }
        // Every leaf and limb renamed alike.
        assert!(leaf_names(&octopus).iter().all(|n| n.starts_with("limb.")));
    }

    fn leaf_names(rig: &Autorig) -> Vec<&str> {
        rig.cages.leaves.iter().map(|l| l.name.as_str()).collect()
    }

    #[test]
    fn a_hand_s_fingers_become_limbs_with_their_cages_and_controls() {
        let names = ["arm.L", "arm.L.001", "arm.R", "ear.R", "head"];
        let mut hand = rig(&names, &[None; 5], &[1.0; 5]);
        limbs_unless_a_figure(&mut hand);
        assert_eq!(
            leaf_names(&hand),
            ["limb.1_1", "limb.2_1", "limb.3_1", "limb.4_1", "limb.5_1"]
        );
        assert_eq!(hand.cages.internals[1].name, "limb.2.1");
        assert_eq!(hand.report.limb_parents[4], ("limb.5".to_owned(), None));
    }

    #[test]
    fn a_piece_of_an_arm_is_no_second_arm() {
        // QMVC's ManHead at detail 4: a bust with a chunk of its right shoulder apart.
        let names = ["leg", "arm.R", "arm.L", "arm.R.001"];
        let mut bust = rig(&names, &[None; 4], &[1.8, 0.46, 0.42, 0.17]);
        limbs_unless_a_figure(&mut bust);
        assert_eq!(leaf_names(&bust)[3], "arm.R.001_1");
    }

    #[test]
    fn a_figure_on_a_pair_of_legs_keeps_a_short_second_arm_but_not_a_long_one() {
        let names = ["arm.L", "arm.L.001", "arm.R", "head", "leg.L", "leg.R"];
        // The second left arm a piece of one (a hand come apart): a fifth of a leg.
        let mut figure = rig(&names, &[None; 6], &[2.0, 0.4, 2.0, 0.5, 2.0, 2.0]);
        limbs_unless_a_figure(&mut figure);
        assert_eq!(
            leaf_names(&figure),
            [
                "arm.L_1",
                "arm.L.001_1",
                "arm.R_1",
                "head_1",
                "leg.L_1",
                "leg.R_1"
            ]
        );
        // As long as the first: an octopus standing on two of its arms.
        let mut octopus = rig(&names, &[None; 6], &[2.0, 1.5, 2.0, 0.5, 2.0, 2.0]);
        limbs_unless_a_figure(&mut octopus);
        assert!(leaf_names(&octopus).iter().all(|n| n.starts_with("limb.")));
        // As long, but on the head (Cheburashka's ear), or carrying a leg (a hip): kept.
        let long = [2.0, 1.5, 2.0, 0.5, 2.0, 2.0];
        for parents in [
            [None, Some("head"), None, None, None, None],
            [None, None, None, None, Some("arm.L.001"), None],
        ] {
            let mut figure = rig(&names, &parents, &long);
            limbs_unless_a_figure(&mut figure);
            assert_eq!(leaf_names(&figure)[1], "arm.L.001_1", "{parents:?}");
        }
    }

    #[test]
    fn an_ear_and_a_horn_on_a_head_are_a_figure_s_but_not_on_a_palm() {
        // spot's head carries an ear and a horn a side; the parent's name is renamed too.
        let names = ["head", "ear.L", "horn.L", "ear.R", "horn.R"];
        let parents = [None, Some("head"), Some("head"), Some("head"), Some("head")];
        let mut spot = rig(&names, &parents, &[1.0; 5]);
        limbs_unless_a_figure(&mut spot);
        assert_eq!(leaf_names(&spot)[2], "horn.L_1");
        // The same on top of the body: four fingers and a thumb.
        let names = ["arm.R", "ear.L", "horn.L", "ear.R", "horn.R"];
        let mut hand = rig(&names, &[None; 5], &[1.0; 5]);
        limbs_unless_a_figure(&mut hand);
        assert!(leaf_names(&hand).iter().all(|n| n.starts_with("limb.")));
        // A renamed parent is renamed where a limb hangs from it.
        let names = ["head", "head.001", "ear.L"];
        let parents = [None, None, Some("head.001")];
        let mut octopus = rig(&names, &parents, &[1.0; 3]);
        limbs_unless_a_figure(&mut octopus);
        assert_eq!(
            octopus.report.limb_parents[2],
            ("limb.3".to_owned(), Some("limb.2".to_owned()))
        );
    }
}
