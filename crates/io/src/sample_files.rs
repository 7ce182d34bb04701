//! Small textured files written by our own code, for the tests and for trying the viewport's
//! shading: a UV sphere (Y up, as both formats' files) whose northern half wears a checker image
//! (red and white in the image's top half, blue and white in its bottom half: the image's
//! orientation shows) and whose southern half a plain green material — as a GLB with the PNG
//! embedded, and as an OBJ with its MTL library and the PNG beside it.

use std::path::{Path, PathBuf};

use super::FileError;

/// Rings from pole to pole and segments around.
const RINGS: u32 = 24;
const SEGMENTS: u32 = 48;
/// The plain material's colour, linear RGB (glTF's factor and MTL's `Kd` alike).
const GREEN: [f32; 3] = [0.05, 0.45, 0.08];

/// The checker image, 64 × 64 PNG bytes.
pub fn checker_png() -> Vec<u8> {
    let size = 64u32;
    let image = image::RgbaImage::from_fn(size, size, |x, y| {
        let light = ((x / 8) + (y / 8)) % 2 == 0;
        match (y < size / 2, light) {
            (_, true) => image::Rgba([245, 245, 245, 255]),
            (true, false) => image::Rgba([220, 30, 30, 255]),
            (false, false) => image::Rgba([30, 60, 220, 255]),
        }
    });
    let mut bytes = Vec::new();
    // Encoding an in-memory image cannot fail for lack of space.
    let _ = image.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    );
    bytes
}

/// Positions, UVs, triangles and how many of the triangles are northern (they come first).
type Sphere = (Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<[u32; 3]>, usize);

/// The sphere: positions (Y up, radius 1), UVs with v = 0 at the north pole (glTF's image
/// top), and triangles, northern ones first.
fn sphere() -> Sphere {
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for ring in 0..=RINGS {
        let v = ring as f32 / RINGS as f32;
        let polar = v * std::f32::consts::PI;
        for segment in 0..=SEGMENTS {
            let u = segment as f32 / SEGMENTS as f32;
            let azimuth = u * std::f32::consts::TAU;
            positions.push([
                polar.sin() * azimuth.cos(),
                polar.cos(),
                -polar.sin() * azimuth.sin(),
            ]);
            uvs.push([u, v]);
        }
    }
    let at = |ring: u32, segment: u32| ring * (SEGMENTS + 1) + segment;
    let mut triangles = Vec::new();
    for ring in 0..RINGS {
        for segment in 0..SEGMENTS {
            let (a, b) = (at(ring, segment), at(ring, segment + 1));
            let (c, d) = (at(ring + 1, segment), at(ring + 1, segment + 1));
            if ring > 0 {
                triangles.push([a, c, b]);
            }
            if ring + 1 < RINGS {
                triangles.push([b, c, d]);
            }
        }
    }
    let northern = triangles
        .iter()
        .filter(|t| t.iter().all(|&v| v / (SEGMENTS + 1) <= RINGS / 2))
        .count();
    // Northern triangles first (they are: rings run from the north pole).
    (positions, uvs, triangles, northern)
}

/// The paths [`write_textured_samples`] writes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TexturedSamples {
    /// `sphere.glb`, its image embedded.
    pub glb: PathBuf,
    /// `sphere.obj`, with `sphere.mtl` and `checker.png` beside it.
    pub obj: PathBuf,
    /// `checker.png`.
    pub png: PathBuf,
}

/// Writes the textured sphere into `folder` as GLB and as OBJ + MTL + PNG.
pub fn write_textured_samples(folder: &Path) -> Result<TexturedSamples, FileError> {
    let (positions, uvs, triangles, northern) = sphere();
    let png = checker_png();
    let write = |name: &str, bytes: &[u8]| -> Result<PathBuf, FileError> {
        let path = folder.join(name);
        super::write_atomic(&path, bytes)?;
        Ok(path)
    };
    let glb = write(
        "sphere.glb",
        &sphere_glb(&positions, &uvs, &triangles, northern, &png),
    )?;
    let png_path = write("checker.png", &png)?;
    let mut obj = String::from("# StarCages textured sample\nmtllib sphere.mtl\no sphere\n");
    for p in &positions {
        obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    // OBJ counts v from the image's bottom row.
    for t in &uvs {
        obj += &format!("vt {} {}\n", t[0], 1.0 - t[1]);
    }
    for (k, t) in triangles.iter().enumerate() {
        if k == 0 {
            obj += "usemtl skin\n";
        } else if k == northern {
            obj += "usemtl paint\n";
        }
        let [a, b, c] = t.map(|v| v + 1);
        obj += &format!("f {a}/{a} {b}/{b} {c}/{c}\n");
    }
    let obj_path = write("sphere.obj", obj.as_bytes())?;
    let [r, g, b] = GREEN;
    let mtl =
        format!("newmtl skin\nKd 1 1 1\nmap_Kd checker.png\n\nnewmtl paint\nKd {r} {g} {b}\n");
    write("sphere.mtl", mtl.as_bytes())?;
    Ok(TexturedSamples {
        glb,
        obj: obj_path,
        png: png_path,
    })
}

/// The sphere as GLB: two primitives (the northern half with the checker, the southern half
/// green) over one vertex list, the PNG in the binary chunk.
fn sphere_glb(
    positions: &[[f32; 3]],
    uvs: &[[f32; 2]],
    triangles: &[[u32; 3]],
    northern: usize,
    png: &[u8],
) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut push = |bytes: &[u8], target: Option<u32>| {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let mut view =
            serde_json::json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()});
        if let Some(target) = target {
            view["target"] = target.into();
        }
        bin.extend_from_slice(bytes);
        views.push(view);
        views.len() - 1
    };
    let position_bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    let uv_bytes: Vec<u8> = uvs.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
    let index_bytes = |ts: &[[u32; 3]]| -> Vec<u8> {
        ts.iter().flatten().flat_map(|i| i.to_le_bytes()).collect()
    };
    let (north, south) = triangles.split_at(northern);
    let position_view = push(&position_bytes, Some(34962));
    let uv_view = push(&uv_bytes, Some(34962));
    let north_view = push(&index_bytes(north), Some(34963));
    let south_view = push(&index_bytes(south), Some(34963));
    let image_view = push(png, None);
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let (lo, hi) = positions
        .iter()
        .fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        });
    let [r, g, b] = GREEN;
    let json = serde_json::json!({
        "asset": {"version": "2.0", "generator": "StarCages sample files"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "sphere"}],
        "meshes": [{"name": "sphere", "primitives": [
            {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0},
            {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 3, "material": 1},
        ]}],
        "materials": [
            {"name": "skin", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}},
            {"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [r, g, b, 1.0], "metallicFactor": 0.0}},
        ],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987}],
        "images": [{"bufferView": image_view, "mimeType": "image/png", "name": "checker"}],
        "accessors": [
            {"bufferView": position_view, "componentType": 5126, "count": positions.len(), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": uv_view, "componentType": 5126, "count": uvs.len(), "type": "VEC2"},
            {"bufferView": north_view, "componentType": 5125, "count": north.len() * 3, "type": "SCALAR"},
            {"bufferView": south_view, "componentType": 5125, "count": south.len() * 3, "type": "SCALAR"},
        ],
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}],
    });
    super::mesh_write::glb_container(&json, &bin)
}

#[cfg(test)]
mod tests {
    use super::*;
    use starcages_core::mesh::look::{TextureSource, UvOrigin};

    /// Both samples read back with their two materials (the checker image, the green factor
    /// encoded for display), each triangle's material, and their UVs' origins; the images
    /// decode to the checker (red at the top row's dark squares).
    #[test]
    fn the_textured_samples_read_back_with_their_materials() {
        let folder = tempfile::tempdir().unwrap();
        let samples = write_textured_samples(folder.path()).unwrap();
        let (_, _, triangles, northern) = sphere();
        for (path, origin) in [
            (&samples.glb, UvOrigin::TopLeft),
            (&samples.obj, UvOrigin::BottomLeft),
        ] {
            let (mesh, look) = crate::read_mesh_look(path).unwrap();
            assert_eq!(mesh.triangles().len(), triangles.len());
            assert_eq!(look.uv_origin, origin, "{}", path.display());
            assert!(look.notes.is_empty(), "{:?}", look.notes);
            let materials = look.materials_of(triangles.len()).unwrap();
            let skin = materials[0] as usize;
            let paint = materials[northern] as usize;
            assert!(materials[..northern].iter().all(|&m| m as usize == skin));
            assert!(materials[northern..].iter().all(|&m| m as usize == paint));
            assert_eq!(look.materials[skin].name, "skin");
            let texture = look.materials[skin].texture.as_ref().unwrap();
            if let TextureSource::File(file) = texture {
                assert_eq!(file, &samples.png);
            }
            let image = crate::load_texture(texture).unwrap();
            assert_eq!((image.width, image.height), (64, 64));
            assert_eq!(&image.pixels[8 * 4..8 * 4 + 3], &[220, 30, 30]);
            let green = look.materials[paint].base_color;
            assert!(look.materials[paint].texture.is_none());
            assert!((green[1] - 0.70).abs() < 0.02, "{green:?}");
            // The plain mesh read is the same shape.
            let plain = crate::read_mesh(path).unwrap();
            assert_eq!(plain.triangles().len(), mesh.triangles().len());
        }
    }

    /// An OBJ whose MTL library is missing opens, with a note naming the library.
    #[test]
    fn a_missing_material_library_is_a_note_and_the_mesh_opens() {
        let folder = tempfile::tempdir().unwrap();
        let samples = write_textured_samples(folder.path()).unwrap();
        std::fs::remove_file(folder.path().join("sphere.mtl")).unwrap();
        let (mesh, look) = crate::read_mesh_look(&samples.obj).unwrap();
        assert!(!mesh.triangles().is_empty());
        assert_eq!(look.notes.len(), 1, "{:?}", look.notes);
        assert!(look.notes[0].contains("sphere.mtl"), "{}", look.notes[0]);
        assert!(!look.has_textures());
    }
}
