//! Screen-space picking of cage vertices: the nearest one under the cursor within a radius,
//! and rectangle selection. Pure functions over projected points, no GPU.

use glam::{Vec2, Vec3};

use crate::camera::{OrbitCamera, project_with};

/// The point nearest to `cursor` on screen within `radius` pixels, among those with
/// `pickable[i]` (all when empty); ties go to the one nearer the eye.
pub fn pick_nearest(
    camera: &OrbitCamera,
    size: Vec2,
    points: &[Vec3],
    pickable: &[bool],
    cursor: Vec2,
    radius: f32,
) -> Option<usize> {
    let view_projection = camera.view_projection(size);
    let mut best: Option<(usize, f32, f32)> = None;
    for (i, p) in points.iter().enumerate() {
        if !pickable.is_empty() && !pickable.get(i).copied().unwrap_or(false) {
            continue;
        }
        let Some((pixel, depth)) = project_with(&view_projection, *p, size) else {
            continue;
        };
        let distance = pixel.distance(cursor);
        if distance > radius {
            continue;
        }
        let better = best.is_none_or(|(_, d, z)| {
            distance < d - 0.5 || ((distance - d).abs() <= 0.5 && depth < z)
        });
        if better {
            best = Some((i, distance, depth));
        }
    }
    best.map(|(i, _, _)| i)
}

/// Every point projecting inside the screen rectangle with corners `a` and `b` (any order),
/// among the pickable ones, in index order.
pub fn select_in_rectangle(
    camera: &OrbitCamera,
    size: Vec2,
    points: &[Vec3],
    pickable: &[bool],
    a: Vec2,
    b: Vec2,
) -> Vec<usize> {
    let (lo, hi) = (a.min(b), a.max(b));
    let view_projection = camera.view_projection(size);
    points
        .iter()
        .enumerate()
        .filter(|(i, _)| pickable.is_empty() || pickable.get(*i).copied().unwrap_or(false))
        .filter_map(|(i, p)| {
            let (pixel, _) = project_with(&view_projection, *p, size)?;
            (pixel.cmpge(lo).all() && pixel.cmple(hi).all()).then_some(i)
        })
        .collect()
}

/// The polygon (an index into `polygons`, corners indexing `positions`) the ray through pixel
/// `cursor_in_viewport` meets first, if any. Polygons are fan-triangulated from their first
/// corner; either side counts.
pub fn pick_polygon(
    camera: &OrbitCamera,
    viewport_size: Vec2,
    positions: &[Vec3],
    polygons: &[&[u32]],
    cursor_in_viewport: Vec2,
) -> Option<usize> {
    let (origin, direction) = camera.ray(cursor_in_viewport, viewport_size);
    let mut best: Option<(f32, usize)> = None;
    for (i, polygon) in polygons.iter().enumerate() {
        let corners: Vec<Vec3> = polygon
            .iter()
            .filter_map(|&v| positions.get(v as usize).copied())
            .collect();
        if corners.len() < 3 || corners.len() != polygon.len() {
            continue;
        }
        for k in 1..corners.len() - 1 {
            if let Some(t) =
                ray_triangle(origin, direction, [corners[0], corners[k], corners[k + 1]])
                && best.is_none_or(|(b, _)| t < b)
            {
                best = Some((t, i));
            }
        }
    }
    best.map(|(_, i)| i)
}

/// Distance along the ray to triangle `tri` (Möller–Trumbore), either side facing.
fn ray_triangle(origin: Vec3, direction: Vec3, tri: [Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inverse = 1.0 / det;
    let s = origin - tri[0];
    let u = s.dot(p) * inverse;
    let q = s.cross(e1);
    let v = direction.dot(q) * inverse;
    let t = e2.dot(q) * inverse;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const SIZE: Vec2 = Vec2::new(640.0, 480.0);

    fn grid() -> Vec<Vec3> {
        (0..27)
            .map(|i| Vec3::new((i % 3) as f32, ((i / 3) % 3) as f32, (i / 9) as f32) - 1.0)
            .collect()
    }

    proptest! {
        /// Clicking at a vertex's projection picks that vertex or one drawn at the same spot
        /// nearer the eye.
        #[test]
        fn clicking_a_projected_vertex_picks_it(yaw in -3.0f32..3.0, pitch in -1.4f32..1.4, k in 0usize..27) {
            let camera = OrbitCamera { yaw, pitch, distance: 8.0, ..OrbitCamera::default() };
            let points = grid();
            let (pixel, depth) = camera.project(points[k], SIZE).unwrap();
            let picked = pick_nearest(&camera, SIZE, &points, &[], pixel, 6.0).unwrap();
            let (other, other_depth) = camera.project(points[picked], SIZE).unwrap();
            prop_assert!(other.distance(pixel) <= 0.5 + 1e-3);
            prop_assert!(picked == k || other_depth <= depth);
        }
    }

    #[test]
    fn nothing_is_picked_far_from_every_vertex_or_when_unpickable() {
        let camera = OrbitCamera::default();
        let points = grid();
        assert_eq!(
            pick_nearest(&camera, SIZE, &points, &[], Vec2::new(2.0, 2.0), 8.0),
            None
        );
        let (pixel, _) = camera.project(points[13], SIZE).unwrap();
        let mut pickable = vec![true; 27];
        pickable[13] = false;
        let picked = pick_nearest(&camera, SIZE, &points, &pickable, pixel, 3.0);
        assert_ne!(picked, Some(13));
    }

    #[test]
    fn the_rectangle_selects_what_projects_inside_it() {
        let mut camera = OrbitCamera::default();
        camera.set_view(crate::camera::View::Front);
        let points = grid();
        let all = select_in_rectangle(&camera, SIZE, &points, &[], Vec2::ZERO, SIZE);
        assert_eq!(all.len(), 27);
        // The left half of the screen holds the x = −1 column (and not x = +1).
        let left = select_in_rectangle(
            &camera,
            SIZE,
            &points,
            &[],
            Vec2::ZERO,
            Vec2::new(300.0, 480.0),
        );
        assert!(left.iter().all(|&i| points[i].x < 0.0));
        assert_eq!(left.len(), 9);
        let swapped = select_in_rectangle(
            &camera,
            SIZE,
            &points,
            &[],
            Vec2::new(300.0, 480.0),
            Vec2::ZERO,
        );
        assert_eq!(left, swapped);
    }

    #[test]
    fn a_polygon_is_picked_where_the_ray_meets_it_first() {
        let camera = OrbitCamera::default();
        let size = Vec2::new(400.0, 300.0);
        // Two squares facing the eye along its view direction, one behind the other.
        let eye_dir = -camera.backward();
        let (u, w) = eye_dir.any_orthonormal_pair();
        let square = |centre: Vec3| -> Vec<Vec3> {
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(a, b)| centre + u * a + w * b)
                .to_vec()
        };
        let near = camera.target;
        let far = camera.target + eye_dir * 2.0;
        let mut positions = square(far);
        positions.extend(square(near));
        let polygons: [&[u32]; 2] = [&[0, 1, 2, 3], &[4, 5, 6, 7]];
        let centre = size / 2.0;
        assert_eq!(
            pick_polygon(&camera, size, &positions, &polygons, centre),
            Some(1),
            "the nearer square"
        );
        assert_eq!(
            pick_polygon(&camera, size, &positions, &polygons, Vec2::new(1.0, 1.0)),
            None,
            "a corner of the view misses both"
        );
    }
}
