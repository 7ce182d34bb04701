//! The built-in matcaps: images of a lit sphere, looked up by the view-space normal (as
//! Blender's MatCap shading). Computed here from small lighting models, so no image file ships.

use glam::Vec3;
use starcages_core::mesh::look::Rgba8Image;

/// A built-in matcap.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Matcap {
    /// Warm grey clay, soft key light: reads forms without distraction.
    #[default]
    Clay,
    /// Green jade: wrapped light and a sharp highlight.
    Jade,
    /// Chrome: a sky, a horizon and a floor reflected; shows curvature and kinks.
    Metal,
    /// Three flat tones and a rim: reads silhouettes.
    Toon,
}

impl Matcap {
    /// Every matcap, in menu order.
    pub const ALL: [Self; 4] = [Self::Clay, Self::Jade, Self::Metal, Self::Toon];

    /// The menu's name.
    pub fn label(self) -> &'static str {
        match self {
            Self::Clay => "Clay",
            Self::Jade => "Jade",
            Self::Metal => "Metal",
            Self::Toon => "Toon",
        }
    }

    /// The colour of the sphere point with view-space normal `n` (x right, y up, z toward
    /// the eye), display values in [0, 1].
    pub fn shade(self, n: Vec3) -> Vec3 {
        let key = Vec3::new(-0.45, 0.6, 0.66).normalize();
        let lambert = n.dot(key).max(0.0);
        let rim = (1.0 - n.z.max(0.0)).powi(3);
        let half = (key + Vec3::Z).normalize();
        let specular = |power: i32| n.dot(half).max(0.0).powi(power);
        match self {
            Self::Clay => {
                let base = Vec3::new(0.80, 0.70, 0.62);
                base * (0.28 + 0.72 * lambert) + Vec3::splat(0.12 * rim + 0.06 * specular(12))
            }
            Self::Jade => {
                let wrap = ((n.dot(key) + 0.5) / 1.5).max(0.0);
                let base = Vec3::new(0.32, 0.70, 0.48);
                base * (0.25 + 0.75 * wrap)
                    + Vec3::new(0.2, 0.35, 0.25) * rim
                    + Vec3::splat(0.55 * specular(60))
            }
            Self::Metal => {
                // The view direction reflected about n, looked up in a studio: bright sky,
                // dark band at the horizon, grey floor.
                let r = 2.0 * n.z * n - Vec3::Z;
                let up = r.y;
                let sky = Vec3::new(0.92, 0.94, 0.98) * (0.55 + 0.45 * up.max(0.0));
                let floor = Vec3::new(0.30, 0.28, 0.26) * (0.6 + 0.4 * (-up).max(0.0));
                let band = (-(up * 9.0).powi(2)).exp();
                let env = if up > 0.0 { sky } else { floor };
                env * (1.0 - 0.85 * band) + Vec3::splat(0.5 * specular(80))
            }
            Self::Toon => {
                let base = Vec3::new(0.86, 0.62, 0.45);
                let tone = if lambert > 0.6 {
                    1.0
                } else if lambert > 0.2 {
                    0.7
                } else {
                    0.45
                };
                let edge = if n.z < 0.28 { 0.35 } else { 1.0 };
                base * tone * edge
            }
        }
    }

    /// The matcap as a square image `size` pixels wide; outside the sphere, the colour of its
    /// rim (so filtering at the edge stays clean).
    pub fn image(self, size: u32) -> Rgba8Image {
        let size = size.max(2);
        let mut pixels = Vec::with_capacity((size * size * 4) as usize);
        for row in 0..size {
            for column in 0..size {
                let x = (column as f32 + 0.5) / size as f32 * 2.0 - 1.0;
                let y = 1.0 - (row as f32 + 0.5) / size as f32 * 2.0;
                let planar = glam::Vec2::new(x, y);
                let planar = if planar.length() > 0.999 {
                    planar.normalize() * 0.999
                } else {
                    planar
                };
                let z = (1.0 - planar.length_squared()).max(0.0).sqrt();
                let colour = self.shade(Vec3::new(planar.x, planar.y, z));
                let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
                pixels.extend([byte(colour.x), byte(colour.y), byte(colour.z), 255]);
            }
        }
        Rgba8Image {
            width: size,
            height: size,
            pixels,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each matcap lights the side toward its key light brighter than the side away from it,
    /// and its centre differs from its lower edge (a flat image would fail).
    #[test]
    fn matcaps_are_lit_from_the_upper_left() {
        for matcap in Matcap::ALL {
            let image = matcap.image(64);
            assert_eq!(image.pixels.len(), 64 * 64 * 4);
            let at = |x: usize, y: usize| {
                let i = (y * 64 + x) * 4;
                image.pixels[i..i + 3]
                    .iter()
                    .map(|&b| b as u32)
                    .sum::<u32>()
            };
            // Upper left (toward the key) against lower right.
            if matcap != Matcap::Metal {
                assert!(at(20, 20) > at(44, 44), "{matcap:?}");
            }
            assert_ne!(at(32, 32), at(32, 62), "{matcap:?}");
        }
    }
}
