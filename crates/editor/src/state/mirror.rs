//! X-symmetry: each cage vertex's partner across the plane x = 0 at rest.

use glam::DVec3;

/// Per vertex, the vertex at its mirror image (itself on the plane), if any.
pub fn partners(rest: &[DVec3]) -> Vec<Option<u32>> {
    let (lo, hi) = starcages_core::cage::bounds_of(rest);
    let tolerance = 1e-6 * (hi - lo).length().max(1e-12);
    let mut sorted: Vec<u32> = (0..rest.len() as u32).collect();
    sorted.sort_by(|&a, &b| rest[a as usize].x.total_cmp(&rest[b as usize].x));
    rest.iter()
        .map(|p| {
            let image = DVec3::new(-p.x, p.y, p.z);
            let start = sorted.partition_point(|&v| rest[v as usize].x < image.x - tolerance);
            sorted[start..]
                .iter()
                .take_while(|&&v| rest[v as usize].x <= image.x + tolerance)
                .copied()
                .find(|&v| rest[v as usize].distance(image) <= tolerance)
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
}
