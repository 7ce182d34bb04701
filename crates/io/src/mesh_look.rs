//! A mesh file's look ([`MeshLook`]): glTF materials (base colour factor and texture, embedded
//! or beside the file), OBJ's MTL (`Kd`, `map_Kd`), FBX materials (in [`super::mesh_fbx`]); and
//! the decoding of their images through the `image` crate. What cannot be used becomes a note
//! naming the file and the element, never an error: the mesh still opens.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use base64::Engine as _;
use starcages_core::mesh::look::{
    LoadedLook, Material, MeshLook, Rgba8Image, TextureSource, UvOrigin, display_color,
};

/// The largest image side decoded (16k, as GPUs' largest 2D textures).
pub const MAX_TEXTURE_SIDE: u32 = 16_384;
/// The largest image file read.
const MAX_TEXTURE_FILE_BYTES: u64 = 256 << 20;

/// The look of a glTF file: one material per glTF material (in order), plus a default one for
/// primitives without, and each part's triangles given its primitive's material.
pub(super) fn gltf_look(
    path: &Path,
    gltf: &gltf::Gltf,
    buffers: &[Vec<u8>],
    parts: &[starcages_core::mesh::MeshPart],
    part_materials: &[Option<usize>],
) -> MeshLook {
    let mut notes = Vec::new();
    let mut materials: Vec<Material> = gltf
        .materials()
        .map(|material| {
            let index = material.index().unwrap_or(0);
            let name = material
                .name()
                .map_or_else(|| format!("material {index}"), str::to_owned);
            let pbr = material.pbr_metallic_roughness();
            let texture = pbr.base_color_texture().and_then(|info| {
                if info.tex_coord() != 0 {
                    notes.push(format!(
                        "{}: material {index} '{name}' maps its base colour through UV set {}; \
                         only the first (TEXCOORD_0) is read, so it is drawn without its image",
                        path.display(),
                        info.tex_coord()
                    ));
                    return None;
                }
                let image = info.texture().source();
                let label = format!(
                    "image {} '{}' of {}",
                    image.index(),
                    image.name().unwrap_or("unnamed"),
                    path.display()
                );
                match image.source() {
                    gltf::image::Source::View { view, .. } => {
                        let bytes = buffers.get(view.buffer().index()).and_then(|b| {
                            b.get(view.offset()..view.offset().checked_add(view.length())?)
                        });
                        match bytes {
                            Some(bytes) => Some(TextureSource::Embedded {
                                name: label,
                                bytes: Arc::new(bytes.to_vec()),
                            }),
                            None => {
                                notes.push(format!(
                                    "{label}: its buffer view lies outside its buffer; \
                                     re-export the file"
                                ));
                                None
                            }
                        }
                    }
                    gltf::image::Source::Uri { uri, .. } => match uri_source(path, uri, &label) {
                        Ok(source) => Some(source),
                        Err(note) => {
                            notes.push(note);
                            None
                        }
                    },
                }
            });
            Material {
                name,
                base_color: display_color(pbr.base_color_factor()),
                texture,
            }
        })
        .collect();
    let default = materials.len() as u32;
    materials.push(Material::default());
    let mut triangle_materials = Vec::new();
    for (part, material) in parts.iter().zip(part_materials) {
        let m = material.map_or(default, |m| m as u32);
        let count = part.triangles.end.saturating_sub(part.triangles.start) as usize;
        triangle_materials.extend(std::iter::repeat_n(m, count));
    }
    MeshLook {
        materials,
        triangle_materials,
        uv_origin: UvOrigin::TopLeft,
        notes,
    }
}

/// The image a glTF URI names: a base64 data URI, or a relative path inside the file's folder
/// (as buffers are read: no scheme, no absolute path, no `..`).
fn uri_source(path: &Path, uri: &str, label: &str) -> Result<TextureSource, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let encoded = rest
            .split_once(";base64,")
            .map(|(_, d)| d)
            .ok_or_else(|| format!("{label}: its data URI is not base64; re-export the file"))?;
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(encoded)
            .map_err(|e| {
                format!("{label}: its base64 data is corrupt ({e}); re-export the file")
            })?;
        return Ok(TextureSource::Embedded {
            name: label.to_owned(),
            bytes: Arc::new(bytes),
        });
    }
    let decoded = super::mesh_gltf::percent_decode(uri)
        .ok_or_else(|| format!("{label}: URI '{uri}' has a broken %-escape"))?;
    let relative = Path::new(&decoded);
    let inside = !relative.is_absolute()
        && !decoded.contains(':')
        && !decoded.contains('\\')
        && relative.components().all(|c| {
            matches!(
                c,
                std::path::Component::Normal(_) | std::path::Component::CurDir
            )
        });
    if !inside {
        return Err(format!(
            "{label}: URI '{uri}' is not a relative path inside the glTF file's folder; \
             put the image beside the file and name it relatively"
        ));
    }
    Ok(TextureSource::File(folder_of(path).join(relative)))
}

fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The look of an OBJ file from tobj's models (in the order their triangles were read) and
/// materials: a material per MTL material plus a default one, each model's triangles given
/// its `usemtl` material.
pub(super) fn obj_look(
    path: &Path,
    models: &[tobj::Model],
    materials: Result<Vec<tobj::Material>, String>,
) -> MeshLook {
    let mut notes = Vec::new();
    let folder = folder_of(path);
    let read = match materials {
        Ok(m) => m,
        Err(why) => {
            notes.push(why);
            Vec::new()
        }
    };
    let mut out: Vec<Material> = read
        .iter()
        .map(|m| {
            let [r, g, b] = m.diffuse.map_or([1.0; 3], |d| d.map(|c| c as f32));
            let alpha = m.dissolve.map_or(1.0, |d| d as f32);
            Material {
                name: m.name.clone(),
                base_color: display_color([r, g, b, alpha]),
                texture: m
                    .diffuse_texture
                    .as_deref()
                    .and_then(map_file_name)
                    .map(|file| TextureSource::File(resolve_beside(&folder, &file))),
            }
        })
        .collect();
    let default = out.len() as u32;
    out.push(Material::default());
    let mut triangle_materials = Vec::new();
    for model in models {
        let m = model
            .mesh
            .material_id
            .filter(|&m| m < read.len())
            .map_or(default, |m| m as u32);
        triangle_materials.extend(std::iter::repeat_n(m, model.mesh.indices.len() / 3));
    }
    MeshLook {
        materials: out,
        triangle_materials,
        uv_origin: UvOrigin::BottomLeft,
        notes,
    }
}

/// The file an MTL `map_Kd` names, past its options (`-s 1 1 1 skin.png`: the last word; a
/// name without options may contain spaces).
fn map_file_name(value: &str) -> Option<String> {
    let value = value.trim();
    if value.is_empty() {
        return None;
    }
    if value.starts_with('-') {
        value.split_whitespace().last().map(str::to_owned)
    } else {
        Some(value.to_owned())
    }
}

/// A path written in a material file, relative to `folder` unless absolute; Windows
/// separators read as folders.
pub(super) fn resolve_beside(folder: &Path, written: &str) -> PathBuf {
    let written = written.replace('\\', "/");
    let path = Path::new(&written);
    if path.is_absolute() {
        path.to_path_buf()
    } else {
        folder.join(path)
    }
}

/// Decodes every material's image (in parallel); each failure is a problem naming the image,
/// and that material draws with its factor alone.
pub fn load_look_images(look: MeshLook) -> LoadedLook {
    use rayon::prelude::*;
    let results: Vec<Option<Result<Rgba8Image, String>>> = look
        .materials
        .par_iter()
        .map(|m| m.texture.as_ref().map(load_texture))
        .collect();
    let mut problems = look.notes.clone();
    let images = results
        .into_iter()
        .map(|r| match r {
            Some(Ok(image)) => Some(image),
            Some(Err(why)) => {
                problems.push(why);
                None
            }
            None => None,
        })
        .collect();
    LoadedLook {
        look,
        images,
        problems,
    }
}

/// Decodes a material's image (PNG or JPEG, by its content) into RGBA rows from the top. The
/// error is one line naming the image and what to do.
pub fn load_texture(source: &TextureSource) -> Result<Rgba8Image, String> {
    let described = source.describe();
    let bytes: Arc<Vec<u8>> = match source {
        TextureSource::File(path) => {
            let metadata = std::fs::metadata(path).map_err(|e| {
                format!(
                    "{described}: cannot read the image ({e}); put it where the material names it"
                )
            })?;
            if !metadata.is_file() {
                return Err(format!("{described}: not a regular file"));
            }
            if metadata.len() > MAX_TEXTURE_FILE_BYTES {
                return Err(format!(
                    "{described}: {} MiB, past the {} MiB read for an image; scale it down",
                    metadata.len() >> 20,
                    MAX_TEXTURE_FILE_BYTES >> 20
                ));
            }
            Arc::new(
                std::fs::read(path)
                    .map_err(|e| format!("{described}: cannot read the image ({e})"))?,
            )
        }
        TextureSource::Embedded { bytes, .. } => Arc::clone(bytes),
    };
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes.as_slice()))
        .with_guessed_format()
        .map_err(|e| format!("{described}: cannot read the image ({e})"))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    limits.max_alloc = Some(1 << 30);
    reader.limits(limits);
    if reader.format().is_none() {
        return Err(format!(
            "{described}: not a PNG or JPEG image; save it as PNG or JPEG"
        ));
    }
    let decoded = reader.decode().map_err(|e| {
        format!("{described}: a broken or unsupported image ({e}); save it again as PNG or JPEG")
    })?;
    let rgba = decoded.into_rgba8();
    Ok(Rgba8Image {
        width: rgba.width(),
        height: rgba.height(),
        pixels: rgba.into_raw(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_kd_options_are_skipped_and_names_with_spaces_kept() {
        assert_eq!(map_file_name("skin.png").as_deref(), Some("skin.png"));
        assert_eq!(map_file_name("my skin.png").as_deref(), Some("my skin.png"));
        assert_eq!(
            map_file_name("-s 1 1 1 -bm 0.5 skin.png").as_deref(),
            Some("skin.png")
        );
        assert_eq!(map_file_name("  "), None);
    }

    #[test]
    fn image_uris_outside_the_folder_are_notes() {
        let at = Path::new("/models/a.gltf");
        for uri in [
            "../secret.png",
            "/etc/passwd",
            "http://x/y.png",
            "c:\\x.png",
        ] {
            let note = uri_source(at, uri, "image 0").unwrap_err();
            assert!(note.contains("relative path inside"), "{uri}: {note}");
        }
        assert_eq!(
            uri_source(at, "tex/skin%20a.png", "image 0"),
            Ok(TextureSource::File(PathBuf::from("/models/tex/skin a.png")))
        );
    }

    /// An image declaring sides past the limit (a forged PNG header: 40,000 × 40,000 pixels,
    /// 6.4 GB decoded) is refused before anything of that size is allocated.
    #[test]
    fn an_image_promising_gigabytes_is_refused() {
        let mut png = crate::sample_files::checker_png();
        // IHDR: 8-byte signature, 4-byte length, "IHDR", width, height (big-endian), then the
        // rest and a CRC over type and data.
        png[16..20].copy_from_slice(&40_000u32.to_be_bytes());
        png[20..24].copy_from_slice(&40_000u32.to_be_bytes());
        let crc = crc32(&png[12..29]);
        png[29..33].copy_from_slice(&crc.to_be_bytes());
        let forged = TextureSource::Embedded {
            name: "image 0".to_owned(),
            bytes: Arc::new(png),
        };
        let why = load_texture(&forged).unwrap_err();
        assert!(
            why.starts_with("image 0 (embedded): a broken or unsupported image"),
            "{why}"
        );
    }

    /// CRC-32 (IEEE), as PNG chunks carry it.
    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = 0xFFFF_FFFFu32;
        for &b in bytes {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 == 1 {
                    (crc >> 1) ^ 0xEDB8_8320
                } else {
                    crc >> 1
                };
            }
        }
        !crc
    }

    #[test]
    fn a_broken_image_is_a_message_naming_it() {
        let broken = TextureSource::Embedded {
            name: "image 0 'skin'".to_owned(),
            bytes: Arc::new(b"\x89PNG\r\n\x1a\n broken".to_vec()),
        };
        let why = load_texture(&broken).unwrap_err();
        assert!(
            why.starts_with("image 0 'skin' (embedded): a broken"),
            "{why}"
        );
        let text = TextureSource::Embedded {
            name: "image 1".to_owned(),
            bytes: Arc::new(b"hello".to_vec()),
        };
        assert!(
            load_texture(&text)
                .unwrap_err()
                .contains("not a PNG or JPEG")
        );
        let missing = TextureSource::File(PathBuf::from("/nonexistent/skin.png"));
        assert!(
            load_texture(&missing)
                .unwrap_err()
                .starts_with("/nonexistent/skin.png: cannot read")
        );
    }
}
