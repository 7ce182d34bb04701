//! X-mirrored moves for the live rig (`starcages_core::live::LiveRig`).

use glam::DVec3;

/// `moves` plus their mirror partners' moves across x = 0 (`partners` from
/// [`super::mirror::partners`]); a vertex on the plane stays on it.
pub fn with_mirror(
    moves: &[(u32, DVec3)],
    partners: &[Option<u32>],
    pose: &[DVec3],
) -> Vec<(u32, DVec3)> {
    let moving: std::collections::BTreeSet<u32> = moves.iter().map(|m| m.0).collect();
    let mut out = moves.to_vec();
    for &(v, p) in moves {
        match partners.get(v as usize).copied().flatten() {
            Some(partner) if partner == v => {
                if let (Some(last), Some(at)) =
                    (out.iter_mut().find(|m| m.0 == v), pose.get(v as usize))
                {
                    last.1.x = at.x;
                }
            }
            Some(partner) if !moving.contains(&partner) => {
                out.push((partner, DVec3::new(-p.x, p.y, p.z)));
            }
            _ => {}
        }
    }
    out
}
