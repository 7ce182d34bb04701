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
use super::name_defects::is_second_of_its_kind;

/// The roles a figure has one of (on the centre line) or one of a side: a head, a neck, a
/// tail, hips; an arm, an ear, a horn, a shoulder, a hip. Legs are not among them: a
/// quadruped has two a side, an insect three.
const ONE_EACH: [&str; 9] = [
    "head", "neck", "tail", "hips", "arm", "ear", "horn", "shoulder", "hip",
];

/// Renames every limb of `rig` `limb.N` (N counting limbs in the report's order: its leaf
/// cages `limb.N_K`, its controls `limb.N.K`) where its names are no figure's. Without a pair
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
        rename(rig, &names);
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

/// The limb a leaf cage belongs to, from its name (`leg.L_2b` is `leg.L`'s; `body_3` is a
/// body's, which no limb is named).
fn limb_of_leaf(name: &str) -> Option<&str> {
    name.rsplit_once('_').map(|(limb, _)| limb)
}

/// The limb a control turns, from its name (`leg.L.2` turns `leg.L`; `root` none).
fn limb_of_control(name: &str) -> Option<&str> {
    name.rsplit_once('.')
        .filter(|(_, n)| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
        .map(|(limb, _)| limb)
}

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

/// A limb's role and side from its name: `leg.front.L.001` is `("leg", Some("L"))`, `tail`
/// is `("tail", None)`.
fn role_and_side(name: &str) -> (&str, Option<&str>) {
    // Blender's numbered copy of a name taken twice is the name's.
    let name = match name.rsplit_once('.') {
        Some((first, _)) if is_second_of_its_kind(name) => first,
        _ => name,
    };
    let parts: Vec<&str> = name.split('.').collect();
    let role = parts.first().copied().unwrap_or("");
    let side = parts
        .last()
        .copied()
        .filter(|s| parts.len() > 1 && (*s == "L" || *s == "R"));
    (role, side)
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

    fn leaf_names(rig: &Autorig) -> Vec<&str> {
        rig.cages.leaves.iter().map(|l| l.name.as_str()).collect()
    }

    #[test]
    fn roles_and_sides_are_read_from_blender_names() {
        assert_eq!(role_and_side("leg.front.L.001"), ("leg", Some("L")));
        assert_eq!(role_and_side("arm.R"), ("arm", Some("R")));
        assert_eq!(role_and_side("head.002"), ("head", None));
        assert_eq!(role_and_side("tail"), ("tail", None));
        assert_eq!(role_and_side("limb.12"), ("limb", None));
        assert_eq!(
            limb_of_control("leg.front.L.001.3"),
            Some("leg.front.L.001")
        );
        assert_eq!(limb_of_control("root"), None);
        assert_eq!(limb_of_leaf("ear.L_2b"), Some("ear.L"));
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
