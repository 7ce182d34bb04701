//! What a rig's names say, in Blender's conventions as the auto rig writes them: a control
//! `<limb>.<n>` turns segment `n` of limb `<limb>` (`leg.L.2`, the left knee); a leaf cage
//! `<limb>_<n>` is part of segment `n`, with a letter where a segment has several
//! (`leg.L_2b`); a limb's side is its last word, `L` or `R` (`leg.front.L`); a second limb of
//! one role and side is numbered `.001` (`arm.L.001`). Other names (`root`, `body_3`, a
//! hand-made rig's) are no limb's.

/// Whether `name` ends in Blender's copy number, a dot and three digits (`arm.L.001`).
pub fn is_numbered_copy(name: &str) -> bool {
    name.rsplit_once('.')
        .is_some_and(|(_, last)| last.len() == 3 && last.bytes().all(|b| b.is_ascii_digit()))
}

/// `name` without its copy number (`arm.L.001` is `arm.L`).
pub fn without_copy_number(name: &str) -> &str {
    match name.rsplit_once('.') {
        Some((base, _)) if is_numbered_copy(name) => base,
        _ => name,
    }
}

/// The limb a control turns: `leg.L.2` turns `leg.L`, `limb.3.1` turns `limb.3`; `root` none.
pub fn limb_of_control(name: &str) -> Option<&str> {
    name.rsplit_once('.')
        .filter(|(limb, n)| {
            !limb.is_empty() && !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit())
        })
        .map(|(limb, _)| limb)
}

/// The limb a leaf cage is part of: `leg.L_2b` is `leg.L`'s; `body_3` is a body's, which no
/// limb is named (the caller tells them apart).
pub fn limb_of_leaf(name: &str) -> Option<&str> {
    name.rsplit_once('_').map(|(limb, _)| limb)
}

/// The segment a leaf cage is part of: `leg.L_2b` is segment 2's.
pub fn segment_of_leaf(name: &str) -> Option<u32> {
    let (_, rest) = name.rsplit_once('_')?;
    let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    rest.get(..digits)?.parse().ok()
}

/// A limb's role and side: `leg.front.L.001` is `("leg", Some("L"))`, `tail` is
/// `("tail", None)`, `limb.12` is `("limb", None)`.
pub fn role_and_side(limb: &str) -> (&str, Option<&str>) {
    let name = without_copy_number(limb);
    let role = name.split('.').next().unwrap_or("");
    let side = name
        .rsplit_once('.')
        .map(|(_, last)| last)
        .filter(|s| *s == "L" || *s == "R");
    (role, side)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limbs_sides_and_copies_are_read_from_blender_names() {
        assert!(is_numbered_copy("arm.L.001"));
        assert!(!is_numbered_copy("limb.12") && !is_numbered_copy("leg.L.2"));
        assert_eq!(without_copy_number("leg.front.R.002"), "leg.front.R");
        assert_eq!(without_copy_number("limb.3"), "limb.3");
        assert_eq!(without_copy_number("tail.0a1"), "tail.0a1");
        assert_eq!(
            limb_of_control("leg.front.L.001.3"),
            Some("leg.front.L.001")
        );
        assert_eq!(limb_of_control("limb.3.1"), Some("limb.3"));
        for no_limb in ["root", "leg.L.", ".2", "leg.L.x2"] {
            assert_eq!(limb_of_control(no_limb), None, "{no_limb}");
        }
        assert_eq!(limb_of_leaf("ear.L_2b"), Some("ear.L"));
        assert_eq!(segment_of_leaf("ear.L_12b"), Some(12));
        assert_eq!(segment_of_leaf("ear.L_b"), None);
        assert_eq!(role_and_side("leg.front.L.001"), ("leg", Some("L")));
        assert_eq!(role_and_side("arm.R"), ("arm", Some("R")));
        assert_eq!(role_and_side("head.002"), ("head", None));
        assert_eq!(role_and_side("tail"), ("tail", None));
        assert_eq!(role_and_side("limb.12"), ("limb", None));
    }
}
