//! How a mesh looks in its file: its materials (a base colour factor and an optional base
//! colour image), which material each triangle wears, and which way its UVs run. Nothing here
//! deforms; the viewport draws it and the readers fill it. Images are named here and decoded by
//! the io crate into [`Rgba8Image`]s.

use std::path::PathBuf;
use std::sync::Arc;

/// Where a base colour image lives.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TextureSource {
    /// A file on disk (already resolved against the mesh file's folder).
    File(PathBuf),
    /// Bytes inside the mesh file (a GLB buffer view, a data URI, an FBX embedded texture),
    /// with a name for messages (`image 0 'skin'`).
    Embedded {
        /// How messages name it.
        name: String,
        /// The encoded image (PNG, JPEG).
        bytes: Arc<Vec<u8>>,
    },
}

impl TextureSource {
    /// How messages name this image: its path, or its name inside the mesh file.
    pub fn describe(&self) -> String {
        match self {
            Self::File(path) => path.display().to_string(),
            Self::Embedded { name, .. } => format!("{name} (embedded)"),
        }
    }
}

/// One material: a base colour factor times an optional base colour image.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Its name in the file (or `material N`).
    pub name: String,
    /// The base colour factor, RGBA in display (sRGB-encoded) values in [0, 1]. The readers
    /// encode the files' linear factors (glTF `baseColorFactor`, MTL `Kd`, FBX base colour).
    pub base_color: [f32; 4],
    /// The base colour image, multiplied by the factor.
    pub texture: Option<TextureSource>,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".to_owned(),
            base_color: [1.0; 4],
            texture: None,
        }
    }
}

/// Where a file's UV origin is: glTF's images start at the top row, OBJ's and FBX's at the
/// bottom.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UvOrigin {
    /// v = 0 is the image's top row (glTF).
    #[default]
    TopLeft,
    /// v = 0 is the image's bottom row (OBJ, FBX).
    BottomLeft,
}

/// A mesh file's look: materials and the material of each triangle of the mesh's original
/// layout ([`super::Mesh::triangles`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshLook {
    /// The materials (index 0 may be the default one for triangles without a material).
    pub materials: Vec<Material>,
    /// Per original triangle, its material (an index into `materials`).
    pub triangle_materials: Vec<u32>,
    /// The UVs' origin.
    pub uv_origin: UvOrigin,
    /// What the reader could not use, one line each, naming the file and the element (an MTL
    /// library that is missing, a texture on a second UV set).
    pub notes: Vec<String>,
}

impl MeshLook {
    /// Whether any material has an image.
    pub fn has_textures(&self) -> bool {
        self.materials.iter().any(|m| m.texture.is_some())
    }

    /// Whether this look says anything beyond a plain mesh: a material with an image or a
    /// colour other than white, or more than one material.
    pub fn is_plain(&self) -> bool {
        self.materials.len() <= 1
            && self
                .materials
                .iter()
                .all(|m| m.texture.is_none() && m.base_color == [1.0; 4])
    }

    /// The material of each triangle, checked against `triangle_count` triangles: a look read
    /// for another layout (a file changed since) gives `None`. An index past the materials
    /// reads as material 0 of a look that has one.
    pub fn materials_of(&self, triangle_count: usize) -> Option<Vec<u32>> {
        if self.triangle_materials.len() != triangle_count || self.materials.is_empty() {
            return None;
        }
        let count = self.materials.len() as u32;
        Some(
            self.triangle_materials
                .iter()
                .map(|&m| if m < count { m } else { 0 })
                .collect(),
        )
    }
}

/// A decoded image, 8-bit RGBA rows from the top, as the file stores it (display values).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rgba8Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub pixels: Vec<u8>,
}

/// A look with its images decoded (index for index with its materials; `None` where a
/// material has no image or its image could not be read), and what could not be used.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LoadedLook {
    /// The look.
    pub look: MeshLook,
    /// Each material's decoded image.
    pub images: Vec<Option<Rgba8Image>>,
    /// The look's notes and each image that failed, one line each naming the file.
    pub problems: Vec<String>,
}

/// The display (sRGB-encoded) value of a linear colour channel in [0, 1] (IEC 61966-2-1).
pub fn srgb_from_linear(linear: f32) -> f32 {
    let c = linear.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// A linear RGBA factor as display values (alpha stays linear).
pub fn display_color(linear: [f32; 4]) -> [f32; 4] {
    let [r, g, b, a] = linear;
    [
        srgb_from_linear(r),
        srgb_from_linear(g),
        srgb_from_linear(b),
        a.clamp(0.0, 1.0),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_encoding_keeps_black_white_and_mid_grey_where_the_standard_puts_them() {
        assert_eq!(srgb_from_linear(0.0), 0.0);
        assert!((srgb_from_linear(1.0) - 1.0).abs() < 1e-6);
        // Linear 0.2140 is sRGB 0.5 (128/255).
        assert!((srgb_from_linear(0.214) - 0.5).abs() < 2e-3);
        assert_eq!(srgb_from_linear(f32::NAN.max(-1.0)), 0.0);
    }

    #[test]
    fn a_look_for_another_layout_gives_no_triangle_materials() {
        let look = MeshLook {
            materials: vec![Material::default(), Material::default()],
            triangle_materials: vec![0, 1, 7],
            ..MeshLook::default()
        };
        assert_eq!(look.materials_of(3), Some(vec![0, 1, 0]));
        assert_eq!(look.materials_of(4), None);
        assert!(!look.is_plain());
        assert!(MeshLook::default().is_plain());
    }
}
