//! X-symmetry: each cage vertex's partner across the plane x = 0 at rest.

use glam::DVec3;

/// Per vertex, the vertex at its mirror image (itself on the plane), if any. Two cages that
/// touch on the plane without sharing (the auto rig's two paws side by side) each have a copy
/// of the vertices there: each copy's partner is the other, so that a mirrored move carries
/// the other side's copy instead of pinning the vertex to the plane.
pub fn partners(rest: &[DVec3]) -> Vec<Option<u32>> {
    let (lo, hi) = starcages_core::cage::bounds_of(rest);
    let tolerance = 1e-6 * (hi - lo).length().max(1e-12);
    let mut sorted: Vec<u32> = (0..rest.len() as u32).collect();
    sorted.sort_by(|&a, &b| rest[a as usize].x.total_cmp(&rest[b as usize].x));
    rest.iter()
        .enumerate()
        .map(|(own, p)| {
            let image = DVec3::new(-p.x, p.y, p.z);
            let start = sorted.partition_point(|&v| rest[v as usize].x < image.x - tolerance);
            let mut at_image = sorted[start..]
                .iter()
                .take_while(|&&v| rest[v as usize].x <= image.x + tolerance)
                .copied()
                .filter(|&v| rest[v as usize].distance(image) <= tolerance);
            let first = at_image.next()?;
            if first as usize != own {
                return Some(first);
            }
            Some(at_image.next().unwrap_or(first))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partners_are_mirror_images() {
        let rest = vec![
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.5, 2.0, 0.0),
        ];
        assert_eq!(partners(&rest), vec![Some(1), Some(0), Some(2), None]);
    }

    #[test]
    fn copies_on_the_plane_are_each_others_partners() {
        let rest = vec![
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        assert_eq!(partners(&rest), vec![Some(2), Some(1), Some(0)]);
    }
}
