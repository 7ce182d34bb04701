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
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

/// Standard views, as on Blender's numpad.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// Looking along +Y (numpad 1).
    Front,
    /// Looking along −X (numpad 3).
    Side,
    /// Looking down −Z (numpad 7).
    Top,
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
        let (yaw, pitch) = match view {
            View::Front => (-std::f32::consts::FRAC_PI_2, 0.0),
            View::Side => (0.0, 0.0),
            View::Top => (-std::f32::consts::FRAC_PI_2, PITCH_LIMIT),
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
}
