//! What a rig's limb names say the grid got wrong, counted so that two rigs of one mesh can be
//! compared ([`super::autorig`] rigs a symmetric figure again mirrored where its first rig has
//! some).
//!
//! Three signs, each a limb:
//! - **a second limb of one role and side** (`arm.L.001`): the namer found more arms on a side
//!   than a figure has, usually pieces of one part or a part it could not place (the
//!   elephant's ears were `arm.L` and `arm.R.002`, its arms `arm.L.001` and `arm.R.001`, its
//!   head a `neck`);
//! - **a leg without a side** (`leg`, `leg.front`, `leg.back`): two legs the grid joined along
//!   the plane of symmetry (the camel's front legs, a cell apart);
//! - **a leg growing from a limb other than a leg** (the camel's hind legs hanging from a `tail`
//!   that is their two thighs joined).

use super::AutorigReport;
use crate::scene::rig_names::is_numbered_copy;

/// How many limbs of the rig `report` describes show one of the signs above.
pub(super) fn name_defects(report: &AutorigReport) -> usize {
    report
        .limb_parents
        .iter()
        .filter(|(name, parent)| is_defect(name, parent.as_deref()))
        .count()
}

/// Whether the rig `report` describes names its limbs better than the rig `than` does: more
/// limbs free of the signs above, or as many and fewer with a sign. A rig that names fewer
/// limbs cleanly is not better for naming none of them wrongly (Cheburashka's arms at detail 1,
/// lost on the mirrored grid).
pub(super) fn names_better(report: &AutorigReport, than: &AutorigReport) -> bool {
    let score = |r: &AutorigReport| {
        let defects = name_defects(r);
        (r.limb_parents.len() - defects, defects)
    };
    let ((clean, defects), (clean_than, defects_than)) = (score(report), score(than));
    clean > clean_than || (clean == clean_than && defects < defects_than)
}

fn is_defect(name: &str, parent: Option<&str>) -> bool {
    is_numbered_copy(name)
        || is_leg_without_side(name)
        || (is_leg(name) && parent.is_some_and(|p| !is_leg(p)))
}

/// Whether a limb's name is a leg's (`leg`, `leg.L`, `leg.front.R` …).
pub(super) fn is_leg(name: &str) -> bool {
    name == "leg" || name.starts_with("leg.")
}

/// Whether a limb's name is a leg's without a side.
pub(super) fn is_leg_without_side(name: &str) -> bool {
    matches!(name, "leg" | "leg.front" | "leg.back")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(limbs: &[(&str, Option<&str>)]) -> AutorigReport {
        AutorigReport {
            grid: [1, 1, 1],
            solid_cells: 0,
            limbs: limbs.len(),
            leaf_cages: 0,
            leaf_vertices: 0,
            merges: 0,
            mirror_axis: None,
            refinements: 0,
            shared_cages: Vec::new(),
            limb_parents: limbs
                .iter()
                .map(|(n, p)| (n.to_string(), p.map(str::to_string)))
                .collect(),
        }
    }

    /// A quadruped named as it should be shows none; each sign counts once per limb, and a
    /// limb numbered
    /// by the namer's count (`limb.1`) is not one.
    #[test]
    fn each_sign_counts_once_per_limb() {
        let clean = report(&[
            ("leg.front.L", None),
            ("leg.front.R", None),
            ("leg.back.L", None),
            ("leg.back.R", None),
            ("neck", None),
            ("head", Some("neck")),
            ("ear.L", Some("head")),
            ("tail", None),
            ("limb.1", None),
        ]);
        assert_eq!(name_defects(&clean), 0);
        let camel = report(&[
            ("leg", None),
            ("tail", None),
            ("leg.L", Some("tail")),
            ("leg.R", Some("tail")),
            ("neck", None),
        ]);
        assert_eq!(name_defects(&camel), 3);
        let elephant = report(&[
            ("arm.L", None),
            ("arm.L.001", None),
            ("arm.R.002", None),
            ("neck", None),
        ]);
        assert_eq!(name_defects(&elephant), 2);
        // The elephant's mirrored rig: ears, head and trunk named, none numbered.
        let mirrored = report(&[
            ("ear.L", Some("head")),
            ("ear.R", Some("head")),
            ("head", None),
            ("limb.1", Some("head")),
        ]);
        assert!(names_better(&mirrored, &elephant));
        assert!(!names_better(&elephant, &mirrored));
        // Fewer signs, but fewer limbs named cleanly too: not better.
        let lost_arms = report(&[("head", None), ("ear.L", Some("head"))]);
        let with_arms = report(&[
            ("head", None),
            ("ear.L", Some("head")),
            ("arm.L", None),
            ("arm.R.001", Some("head")),
        ]);
        assert!(!names_better(&lost_arms, &with_arms));
        assert!(names_better(&with_arms, &lost_arms));
    }
}
