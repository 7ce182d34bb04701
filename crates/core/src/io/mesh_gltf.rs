//! glTF and GLB meshes through the `gltf` crate: every triangle primitive of every mesh
//! instanced in the default scene (or every scene), with node transforms applied.
//!
//! Buffers are loaded here (the GLB blob, external files beside the document, base64 data
//! URIs) rather than through `gltf::import`, which would also decode every image.

use std::path::Path;

use base64::Engine as _;
use glam::{DAffine3, DMat4, DVec3, Vec2, Vec3};

use super::{FileError, extension};
use crate::mesh::Mesh;

/// Reads a glTF or GLB file as one mesh.
pub(super) fn read_gltf_mesh(path: &Path) -> Result<Mesh, FileError> {
    let bytes = std::fs::read(path).map_err(|error| FileError::Io {
        path: path.to_path_buf(),
        error,
    })?;
    let gltf = gltf::Gltf::from_slice(&bytes).map_err(|e| {
        let kind = if extension(path) == "glb" {
            "GLB"
        } else {
            "glTF"
        };
        FileError::format(path, format!("not a readable {kind} file ({e})"))
    })?;
    let buffers = load_buffers(path, &gltf)?;
    let mut out = Accumulator::default();
    let scenes: Vec<gltf::Scene> = match gltf.default_scene() {
        Some(scene) => vec![scene],
        None => gltf.scenes().collect(),
    };
    for scene in scenes {
        for node in scene.nodes() {
            visit(path, &node, DMat4::IDENTITY, &buffers, &mut out)?;
        }
    }
    let Accumulator {
        positions,
        triangles,
        normals,
        uvs,
        all_normals,
        all_uvs,
    } = out;
    super::mesh_from_file(
        path,
        positions,
        triangles,
        all_normals.then_some(normals),
        all_uvs.then_some(uvs),
    )
}

fn load_buffers(path: &Path, gltf: &gltf::Gltf) -> Result<Vec<Vec<u8>>, FileError> {
    gltf.buffers()
        .map(|buffer| {
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                    FileError::format(path, "the GLB has no binary chunk for its buffer")
                })?,
                gltf::buffer::Source::Uri(uri) => {
                    if let Some(rest) = uri.strip_prefix("data:") {
                        let encoded =
                            rest.split_once(";base64,").map(|(_, d)| d).ok_or_else(|| {
                                FileError::format(
                                    path,
                                    "a buffer's data URI is not base64; re-export the file",
                                )
                            })?;
                        base64::engine::general_purpose::STANDARD
                            .decode(encoded)
                            .map_err(|e| {
                                FileError::format(
                                    path,
                                    format!("a buffer's base64 data is corrupt ({e})"),
                                )
                            })?
                    } else {
                        read_external_buffer(path, uri, buffer.length())?
                    }
                }
            };
            if data.len() < buffer.length() {
                return Err(FileError::format(
                    path,
                    format!(
                        "buffer {} holds {} bytes, {} expected",
                        buffer.index(),
                        data.len(),
                        buffer.length()
                    ),
                ));
            }
            Ok(data)
        })
        .collect()
}

/// Reads an external buffer named by `uri`, which must be a relative reference to a regular
/// file inside the glTF file's folder: absolute paths, `..` escapes, URI schemes and symlinks
/// leading outside are refused (a downloaded file must not read `/etc/passwd` or `/dev/zero`
/// into vertex positions). At most `length` bytes (the declared length) are read.
fn read_external_buffer(path: &Path, uri: &str, length: usize) -> Result<Vec<u8>, FileError> {
    let refuse = |why: &str| {
        FileError::format(
            path,
            format!(
                "buffer URI '{uri}' {why}; external buffers must be files in the glTF file's \
                 folder (or a subfolder), named by a relative path"
            ),
        )
    };
    let decoded = percent_decode(uri).ok_or_else(|| refuse("has a broken %-escape"))?;
    let relative = Path::new(&decoded);
    let has_scheme = decoded
        .split_once(':')
        .is_some_and(|(scheme, _)| !scheme.is_empty() && !scheme.contains(['/', '\\']));
    if has_scheme {
        return Err(refuse("names a URI scheme"));
    }
    if relative.is_absolute() || decoded.starts_with(['/', '\\']) {
        return Err(refuse("is an absolute path"));
    }
    let escapes = relative.components().any(|c| {
        !matches!(
            c,
            std::path::Component::Normal(_) | std::path::Component::CurDir
        )
    });
    if escapes || decoded.contains('\\') {
        return Err(refuse("leaves the folder ('..', a drive or a backslash)"));
    }
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let file = folder.join(relative);
    let io = |error| FileError::Io {
        path: file.clone(),
        error,
    };
    // Symlinks are resolved: the real file must still be inside the real folder.
    let real_folder = folder.canonicalize().map_err(io)?;
    let real_file = file.canonicalize().map_err(io)?;
    if !real_file.starts_with(&real_folder) {
        return Err(refuse("leads outside the folder through a symbolic link"));
    }
    if !real_file.metadata().map_err(io)?.is_file() {
        return Err(refuse("is not a regular file"));
    }
    let mut data = Vec::new();
    std::io::Read::read_to_end(
        &mut std::io::Read::take(std::fs::File::open(&real_file).map_err(io)?, length as u64),
        &mut data,
    )
    .map_err(io)?;
    Ok(data)
}

/// `text` with %XX escapes decoded (URIs in glTF are percent-encoded); `None` for a broken
/// escape or bytes that are not UTF-8.
fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while let Some(&b) = bytes.get(i) {
        if b == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[derive(Default)]
struct Accumulator {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    all_normals: bool,
    all_uvs: bool,
}

fn visit(
    path: &Path,
    node: &gltf::Node,
    parent: DMat4,
    buffers: &[Vec<u8>],
    out: &mut Accumulator,
) -> Result<(), FileError> {
    let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
    let world = parent * local;
    if let Some(mesh) = node.mesh() {
        let affine = DAffine3::from_mat4(world);
        let normal_matrix = affine.matrix3.inverse().transpose();
        for primitive in mesh.primitives() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                return Err(FileError::format(
                    path,
                    format!(
                        "mesh '{}' has a {:?} primitive; only triangles are supported, triangulate on export",
                        mesh.name().unwrap_or("unnamed"),
                        primitive.mode()
                    ),
                ));
            }
            let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
            let Some(positions) = reader.read_positions() else {
                continue;
            };
            let first = out.positions.len();
            if first == 0 && out.triangles.is_empty() {
                out.all_normals = true;
                out.all_uvs = true;
            }
            out.positions
                .extend(positions.map(|p| affine.transform_point3(DVec3::from(p.map(f64::from)))));
            let count = out.positions.len() - first;
            match reader.read_normals() {
                Some(normals) => out.normals.extend(normals.map(|n| {
                    (normal_matrix * DVec3::from(n.map(f64::from)))
                        .normalize_or_zero()
                        .as_vec3()
                })),
                None => out.all_normals = false,
            }
            match reader.read_tex_coords(0) {
                Some(uvs) => out.uvs.extend(uvs.into_f32().map(Vec2::from)),
                None => out.all_uvs = false,
            }
            let base = first as u32;
            let flip = affine.matrix3.determinant() < 0.0;
            let mut push = |t: [u32; 3]| {
                let t = t.map(|v| v + base);
                out.triangles
                    .push(if flip { [t[0], t[2], t[1]] } else { t });
            };
            match reader.read_indices() {
                Some(indices) => {
                    let indices: Vec<u32> = indices.into_u32().collect();
                    if !indices.len().is_multiple_of(3)
                        || indices.iter().any(|&i| i as usize >= count)
                    {
                        return Err(FileError::format(
                            path,
                            "a primitive's indices are out of range or not triangles",
                        ));
                    }
                    indices
                        .chunks_exact(3)
                        .for_each(|t| push([t[0], t[1], t[2]]));
                }
                None => (0..count as u32 / 3).for_each(|t| push([3 * t, 3 * t + 1, 3 * t + 2])),
            }
        }
    }
    for child in node.children() {
        visit(path, &child, world, buffers, out)?;
    }
    Ok(())
}
