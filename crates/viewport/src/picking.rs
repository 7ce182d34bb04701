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
    let corners = [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
    select_in_lasso(camera, size, points, pickable, &corners)
}

/// Indices of the points (where `pickable`, or all when it is empty) whose projection lies
/// inside the screen polygon `lasso` (pixels; closed implicitly, even-odd rule, so a lasso
/// crossing itself selects what it encloses an odd number of times).
pub fn select_in_lasso(
    camera: &OrbitCamera,
    size: Vec2,
    points: &[Vec3],
    pickable: &[bool],
    lasso: &[Vec2],
) -> Vec<usize> {
    if lasso.len() < 3 {
        return Vec::new();
    }
    let (lo, hi) = lasso.iter().fold(
        (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let view_projection = camera.view_projection(size);
    points
        .iter()
        .enumerate()
        .filter(|(i, _)| pickable.is_empty() || pickable.get(*i).copied().unwrap_or(false))
        .filter_map(|(i, p)| {
            let (pixel, _) = project_with(&view_projection, *p, size)?;
            let in_bounds = pixel.cmpge(lo).all() && pixel.cmple(hi).all();
            (in_bounds && inside_polygon(lasso, pixel)).then_some(i)
        })
        .collect()
}

/// Whether `point` is inside the closed polygon `polygon` (even-odd crossings of a ray to +x).
fn inside_polygon(polygon: &[Vec2], point: Vec2) -> bool {
    let mut inside = false;
    let mut previous = polygon[polygon.len() - 1];
    for &current in polygon {
        if (current.y > point.y) != (previous.y > point.y) {
            let x = previous.x
                + (point.y - previous.y) / (current.y - previous.y) * (current.x - previous.x);
            if point.x < x {
                inside = !inside;
            }
        }
        previous = current;
    }
    inside
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

/// Distances along the ray (`origin`, unit `direction`) to every triangle of a mesh it
/// crosses, nearest first: entries and exits alternate on a closed mesh.
pub fn ray_mesh_hits(
    origin: Vec3,
    direction: Vec3,
    positions: &[Vec3],
    triangles: &[[u32; 3]],
) -> Vec<f32> {
    let mut hits: Vec<f32> = triangles
        .iter()
        .filter_map(|t| {
            let corners = t.map(|v| positions.get(v as usize).copied());
            match corners {
                [Some(a), Some(b), Some(c)] => ray_triangle(origin, direction, [a, b, c]),
                _ => None,
            }
        })
        .collect();
    hits.sort_by(f32::total_cmp);
    hits
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

    #[test]
    fn a_ray_through_a_cube_enters_and_leaves_it() {
        // The unit cube's 12 triangles.
        let positions: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let triangles: Vec<[u32; 3]> = starcages_core::cage::shapes::BOX_FACES
            .iter()
            .map(|q| q.map(|v| v as u32))
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        let hits = ray_mesh_hits(Vec3::new(0.3, 0.4, -2.0), Vec3::Z, &positions, &triangles);
        assert_eq!(hits.len(), 2, "{hits:?}");
        assert!((hits[0] - 2.0).abs() < 1e-5 && (hits[1] - 3.0).abs() < 1e-5);
        // Beside the cube: no hit (negative control).
        let beside = ray_mesh_hits(Vec3::new(1.5, 0.4, -2.0), Vec3::Z, &positions, &triangles);
        assert!(beside.is_empty());
    }

    #[test]
    fn a_lasso_selects_the_points_it_encloses_and_not_those_in_its_notch() {
        let camera = OrbitCamera {
            distance: 8.0,
            ..OrbitCamera::default()
        };
        let points = grid();
        let pixels: Vec<Vec2> = points
            .iter()
            .map(|p| camera.project(*p, SIZE).unwrap().0)
            .collect();
        let (lo, hi) = pixels.iter().fold(
            (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let pad = Vec2::splat(5.0);
        let (lo, hi) = (lo - pad, hi + pad);
        // A square around everything: all points.
        let square = [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
        assert_eq!(
            select_in_lasso(&camera, SIZE, &points, &[], &square).len(),
            27
        );
        // The same square with a rectangular notch cut from its top edge down to its centre:
        // exactly the points drawn in the notch are outside (the even-odd test's negative
        // control).
        let centre = 0.5 * (lo + hi);
        let w = 0.15 * (hi.x - lo.x);
        let notched = [
            lo,
            Vec2::new(centre.x - w, lo.y),
            Vec2::new(centre.x - w, centre.y),
            Vec2::new(centre.x + w, centre.y),
            Vec2::new(centre.x + w, lo.y),
            Vec2::new(hi.x, lo.y),
            hi,
            Vec2::new(lo.x, hi.y),
        ];
        let inside = select_in_lasso(&camera, SIZE, &points, &[], &notched);
        let in_notch: Vec<usize> = (0..27)
            .filter(|&i| (pixels[i].x - centre.x).abs() < w && pixels[i].y < centre.y)
            .collect();
        assert!(!in_notch.is_empty());
        for i in 0..27 {
            assert_eq!(inside.contains(&i), !in_notch.contains(&i), "point {i}");
        }
        // Too few corners: nothing.
        assert!(select_in_lasso(&camera, SIZE, &points, &[], &square[..2]).is_empty());
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
