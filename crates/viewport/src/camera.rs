//! The orbit camera, Z up as in Blender: orbit, pan, zoom towards the cursor, frame a box,
//! front / side / top views, projection of points and rays from pixels. Pure maths, no GPU.

use glam::{Mat4, Vec2, Vec3, Vec4Swizzles};

/// An orbit camera looking at `target` from `distance` away.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    /// The point orbited around.
    pub target: Vec3,
    /// Distance from the eye to the target.
    pub distance: f32,
    /// Turn about +Z, radians (0: the eye on +X).
    pub yaw: f32,
    /// Elevation above the XY plane, radians, within ±(π/2 − 0.001).
    pub pitch: f32,
    /// Vertical field of view, radians (in orthographic projection: the view shows what the
    /// perspective one shows at the target's depth).
    pub fov_y: f32,
    /// Orthographic projection instead of perspective (Blender's numpad 5).
    pub orthographic: bool,
}

/// Standard views, as on Blender's numpad (Ctrl gives the opposite ones).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// Looking along +Y (numpad 1).
    Front,
    /// Looking along −Y (Ctrl+numpad 1).
    Back,
    /// Looking along −X, from the right (numpad 3).
    Side,
    /// Looking along +X, from the left (Ctrl+numpad 3).
    Left,
    /// Looking down −Z (numpad 7).
    Top,
    /// Looking up +Z (Ctrl+numpad 7).
    Bottom,
}

impl View {
    /// The view looking at the target from the end of the world axis `axis` (0 x, 1 y, 2 z),
    /// on its positive side or not: what clicking an axis of the gizmo gives.
    pub fn from_axis(axis: usize, positive: bool) -> Self {
        match (axis, positive) {
            (0, true) => Self::Side,
            (0, false) => Self::Left,
            (1, true) => Self::Back,
            (1, false) => Self::Front,
            (_, true) => Self::Top,
            (_, false) => Self::Bottom,
        }
    }
}

const PITCH_LIMIT: f32 = std::f32::consts::FRAC_PI_2 - 0.001;

impl Default for OrbitCamera {
    fn default() -> Self {
        Self {
            target: Vec3::ZERO,
            distance: 5.0,
            yaw: -1.2,
            pitch: 0.45,
            fov_y: 40f32.to_radians(),
            orthographic: false,
        }
    }
}

impl OrbitCamera {
    /// Unit vector from the target to the eye.
    pub fn backward(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::new(cp * cy, cp * sy, sp)
    }

    /// The eye position.
    pub fn eye(&self) -> Vec3 {
        self.target + self.backward() * self.distance
    }

    /// Camera right and up vectors (world space).
    pub fn right_up(&self) -> (Vec3, Vec3) {
        let back = self.backward();
        let right = Vec3::Z.cross(back).try_normalize().unwrap_or(Vec3::X);
        (right, back.cross(right))
    }

    /// World → view.
    pub fn view(&self) -> Mat4 {
        let (_, up) = self.right_up();
        glam::camera::rh::view::look_at_mat4(self.eye(), self.target, up)
    }

    /// View → clip for a viewport of `aspect` = width / height (depth 0..1, as wgpu wants).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        if self.orthographic {
            // The box the perspective view shows at the target's depth; depth spans the scene
            // in front of and behind the target.
            let half_height = self.distance * (self.fov_y * 0.5).tan();
            let half_width = half_height * aspect.max(1e-6);
            return glam::camera::rh::proj::directx::orthographic(
                -half_width,
                half_width,
                -half_height,
                half_height,
                0.0,
                self.distance * 100.0 + 1.0,
            );
        }
        let near = (self.distance * 0.01).max(1e-4);
        // wgpu's clip space: y up, depth 0..1 (glam's DirectX convention).
        glam::camera::rh::proj::directx::perspective(
            self.fov_y,
            aspect.max(1e-6),
            near,
            self.distance * 100.0 + 1.0,
        )
    }

    /// World → clip for a viewport of `size` pixels.
    pub fn view_projection(&self, size: Vec2) -> Mat4 {
        self.projection(size.x / size.y.max(1.0)) * self.view()
    }

    /// Turns about the target by a mouse drag of `delta` pixels.
    pub fn orbit(&mut self, delta: Vec2) {
        self.yaw -= delta.x * 0.008;
        self.pitch = (self.pitch + delta.y * 0.008).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// World units per pixel at the target's depth, for a viewport `height` pixels tall.
    pub fn units_per_pixel(&self, height: f32) -> f32 {
        2.0 * self.distance * (self.fov_y * 0.5).tan() / height.max(1.0)
    }

    /// Moves target and eye so the scene follows a drag of `delta` pixels.
    pub fn pan(&mut self, delta: Vec2, height: f32) {
        let (right, up) = self.right_up();
        let scale = self.units_per_pixel(height);
        self.target += (-right * delta.x + up * delta.y) * scale;
    }

    /// Zooms by `steps` wheel notches (positive: closer), keeping the point under `cursor`
    /// (pixels, in a viewport of `size`) where it is on screen when given.
    pub fn zoom(&mut self, steps: f32, cursor: Option<Vec2>, size: Vec2) {
        let factor = 0.85f32.powf(steps);
        if let Some(cursor) = cursor {
            // The point under the cursor on the plane through the target facing the camera.
            let (origin, direction) = self.ray(cursor, size);
            let normal = self.backward();
            let denominator = direction.dot(normal);
            if denominator.abs() > 1e-6 {
                let t = (self.target - origin).dot(normal) / denominator;
                let under = origin + direction * t;
                self.target += (under - self.target) * (1.0 - factor);
            }
        }
        self.distance = (self.distance * factor).clamp(1e-4, 1e6);
    }

    /// Frames the box `min..max` so all of it is in view.
    pub fn frame(&mut self, min: Vec3, max: Vec3) {
        let radius = ((max - min).length() * 0.5).max(1e-3);
        self.target = (min + max) * 0.5;
        self.distance = radius / (self.fov_y * 0.5).sin() * 1.05;
    }

    /// Turns to a standard view, keeping target and distance.
    pub fn set_view(&mut self, view: View) {
        use std::f32::consts::{FRAC_PI_2, PI};
        let (yaw, pitch) = match view {
            View::Front => (-FRAC_PI_2, 0.0),
            View::Back => (FRAC_PI_2, 0.0),
            View::Side => (0.0, 0.0),
            View::Left => (PI, 0.0),
            View::Top => (-FRAC_PI_2, PITCH_LIMIT),
            View::Bottom => (-FRAC_PI_2, -PITCH_LIMIT),
        };
        self.yaw = yaw;
        self.pitch = pitch;
    }

    /// Pixel position (origin top left) and depth in 0..1 of `point`, or `None` behind the eye.
    pub fn project(&self, point: Vec3, size: Vec2) -> Option<(Vec2, f32)> {
        project_with(&self.view_projection(size), point, size)
    }

    /// The ray through pixel `pixel`: origin on the near plane and unit direction.
    pub fn ray(&self, pixel: Vec2, size: Vec2) -> (Vec3, Vec3) {
        let inverse = self.view_projection(size).inverse();
        let ndc = Vec2::new(
            2.0 * pixel.x / size.x.max(1.0) - 1.0,
            1.0 - 2.0 * pixel.y / size.y.max(1.0),
        );
        let near = inverse.project_point3(ndc.extend(0.0));
        let far = inverse.project_point3(ndc.extend(1.0));
        (near, (far - near).normalize_or(-self.backward()))
    }
}

/// Pixel position and depth of `point` under the world → clip matrix `view_projection`.
pub fn project_with(view_projection: &Mat4, point: Vec3, size: Vec2) -> Option<(Vec2, f32)> {
    let clip = *view_projection * point.extend(1.0);
    if clip.w <= 1e-6 {
        return None;
    }
    let ndc = clip.xyz() / clip.w;
    Some((
        Vec2::new((ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y),
        ndc.z,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIZE: Vec2 = Vec2::new(800.0, 600.0);

    #[test]
    fn the_target_projects_to_the_centre_and_rays_go_back_through_it() {
        let camera = OrbitCamera {
            target: Vec3::new(1.0, 2.0, 3.0),
            ..OrbitCamera::default()
        };
        let (pixel, depth) = camera.project(camera.target, SIZE).unwrap();
        assert!(pixel.distance(SIZE * 0.5) < 1e-3);
        assert!((0.0..1.0).contains(&depth));
        let p = Vec3::new(1.3, 1.8, 3.4);
        let (pixel, _) = camera.project(p, SIZE).unwrap();
        let (origin, direction) = camera.ray(pixel, SIZE);
        let closest = origin + direction * (p - origin).dot(direction);
        assert!(closest.distance(p) < 1e-4, "{closest} vs {p}");
    }

    #[test]
    fn pan_moves_the_scene_with_the_mouse() {
        let mut camera = OrbitCamera::default();
        let p = Vec3::ZERO;
        let before = camera.project(p, SIZE).unwrap().0;
        camera.pan(Vec2::new(40.0, -25.0), SIZE.y);
        let after = camera.project(p, SIZE).unwrap().0;
        assert!(
            (after - before).distance(Vec2::new(40.0, -25.0)) < 0.5,
            "{before} {after}"
        );
    }

    #[test]
    fn zoom_keeps_the_point_under_the_cursor() {
        let mut camera = OrbitCamera::default();
        let cursor = Vec2::new(600.0, 200.0);
        let (origin, direction) = camera.ray(cursor, SIZE);
        let normal = camera.backward();
        let t = (camera.target - origin).dot(normal) / direction.dot(normal);
        let under = origin + direction * t;
        camera.zoom(3.0, Some(cursor), SIZE);
        let (pixel, _) = camera.project(under, SIZE).unwrap();
        assert!(pixel.distance(cursor) < 0.5, "{pixel}");
        assert!(camera.distance < 5.0);
    }

    #[test]
    fn framing_puts_every_corner_on_screen() {
        let mut camera = OrbitCamera::default();
        let (min, max) = (Vec3::new(-3.0, -1.0, 0.0), Vec3::new(5.0, 2.0, 7.0));
        camera.frame(min, max);
        for view in [View::Front, View::Side, View::Top] {
            camera.set_view(view);
            for i in 0..8 {
                let corner = Vec3::new(
                    if i & 1 == 0 { min.x } else { max.x },
                    if i & 2 == 0 { min.y } else { max.y },
                    if i & 4 == 0 { min.z } else { max.z },
                );
                let (pixel, depth) = camera.project(corner, SIZE).unwrap();
                assert!(
                    pixel.cmpge(Vec2::ZERO).all() && pixel.cmple(SIZE).all(),
                    "{view:?} {pixel}"
                );
                assert!((0.0..1.0).contains(&depth));
            }
        }
    }

    #[test]
    fn standard_views_look_along_their_axes() {
        let mut camera = OrbitCamera::default();
        camera.set_view(View::Front);
        assert!(camera.backward().distance(-Vec3::Y) < 1e-5);
        camera.set_view(View::Side);
        assert!(camera.backward().distance(Vec3::X) < 1e-5);
        camera.set_view(View::Top);
        assert!(camera.backward().distance(Vec3::Z) < 1e-2);
        let mut orbit = OrbitCamera::default();
        orbit.orbit(Vec2::new(0.0, 1e6));
        assert!(orbit.pitch <= PITCH_LIMIT && orbit.view().is_finite());
    }

    #[test]
    fn orthographic_rays_are_parallel_and_keep_the_scale_at_the_target() {
        let mut camera = OrbitCamera::default();
        let offset = Vec3::new(0.0, 0.0, 0.5);
        let perspective = camera.project(camera.target + offset, SIZE).unwrap().0;
        camera.orthographic = true;
        let orthographic = camera.project(camera.target + offset, SIZE).unwrap().0;
        // At the target's depth both show the same size (within the perspective's depth skew).
        assert!(
            (perspective.y - orthographic.y).abs() < 8.0,
            "{perspective} vs {orthographic}"
        );
        let (_, a) = camera.ray(Vec2::new(10.0, 10.0), SIZE);
        let (_, b) = camera.ray(Vec2::new(700.0, 500.0), SIZE);
        assert!(a.distance(b) < 1e-4, "rays not parallel: {a} {b}");
        assert!(a.distance(-camera.backward()) < 1e-4);
        // A point behind the target projects without perspective: same pixel along the ray.
        let near = camera.project(camera.target, SIZE).unwrap().0;
        let far = camera
            .project(camera.target - camera.backward() * 2.0, SIZE)
            .unwrap()
            .0;
        assert!(near.distance(far) < 1e-2);
    }

    #[test]
    fn opposite_views_look_along_opposite_directions_and_axis_clicks_look_from_that_axis() {
        let mut camera = OrbitCamera::default();
        let mut look = |view| {
            camera.set_view(view);
            -camera.backward()
        };
        for (view, opposite) in [
            (View::Front, View::Back),
            (View::Side, View::Left),
            (View::Top, View::Bottom),
        ] {
            let (a, b) = (look(view), look(opposite));
            assert!((a + b).length() < 1e-2, "{view:?} {a} vs {opposite:?} {b}");
        }
        assert!(look(View::Front).distance(Vec3::Y) < 1e-5);
        assert!(look(View::Side).distance(-Vec3::X) < 1e-5);
        assert!(look(View::Top).distance(-Vec3::Z) < 1e-2);
        // Clicking the +X end of the gizmo looks from +X, along −X.
        for (axis, unit) in [(0, Vec3::X), (1, Vec3::Y), (2, Vec3::Z)] {
            for positive in [true, false] {
                let from = if positive { unit } else { -unit };
                let along = look(View::from_axis(axis, positive));
                assert!(
                    (along + from).length() < 1e-2,
                    "axis {axis} {positive}: {along}"
                );
            }
        }
    }
}
