//! glTF and GLB meshes through the `gltf` crate: every triangle primitive of every mesh
//! instanced in the default scene (or every scene), with node transforms applied.
//!
//! Buffers are loaded here (the GLB blob, external files beside the document, base64 data
//! URIs) rather than through `gltf::import`, which would also decode every image.

use std::path::Path;

use base64::Engine as _;
use glam::{DAffine3, DMat4, DVec3, Vec2, Vec3};

use super::gltf_accessor::{check_accessor, read_elements};
use super::{FileError, extension};
use starcages_core::mesh::Mesh;

/// Reads a glTF or GLB file as one mesh.
pub(super) fn read_gltf_mesh(path: &Path) -> Result<Mesh, FileError> {
    read_gltf(path, false).map(|(mesh, _)| mesh)
}

/// Reads a glTF or GLB mesh and, when `with_look`, its materials
/// ([`super::mesh_look::gltf_look`]).
pub(super) fn read_gltf(
    path: &Path,
    with_look: bool,
) -> Result<(Mesh, Option<starcages_core::mesh::look::MeshLook>), FileError> {
    let bytes = super::read_file_bytes(path)?;
    let kind = if extension(path) == "glb" {
        "GLB"
    } else {
        "glTF"
    };
    // The JSON is parsed once for both checks (files whose JSON does not parse are left to the
    // gltf crate, which reports the syntax error).
    let root =
        json_of(&bytes).and_then(|json| serde_json::from_slice::<serde_json::Value>(json).ok());
    check_container(path, &bytes, root.as_ref())?;
    if let Some(root) = &root {
        check_required_extensions(path, root)?;
        check_primitive_references(path, root)?;
    }
    // The gltf crate's own validation indexes some arrays unchecked: a file that still trips it
    // is an error like any other, not a crash.
    let parsed = std::panic::catch_unwind(|| parse_validated(&bytes)).map_err(|_| {
        FileError::format(
            path,
            format!("not a readable {kind} file (its structure is inconsistent); re-export it"),
        )
    })?;
    let gltf =
        parsed.map_err(|e| FileError::format(path, format!("not a readable {kind} file ({e})")))?;
    let mut buffers = load_buffers(path, &gltf, root.as_ref(), bytes.len())?;
    if let Some(root) = &root {
        super::gltf_meshopt::decode_views(path, root, &mut buffers)?;
    }
    let mut out = Accumulator {
        quantized: gltf
            .extensions_used()
            .chain(gltf.extensions_required())
            .any(|e| e == QUANTIZATION),
        node_worlds: super::gltf_skin::node_worlds(&gltf),
        node_names: gltf
            .nodes()
            .map(|n| n.name().unwrap_or("unnamed").to_owned())
            .collect(),
        ..Accumulator::default()
    };
    let scenes: Vec<gltf::Scene> = match gltf.default_scene() {
        Some(scene) => vec![scene],
        None => gltf.scenes().collect(),
    };
    // Accessors are checked before the gltf crate reads them; should one still trip it, the
    // panic is an error about this file, not a crash.
    let walked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        scenes
            .into_iter()
            .try_for_each(|scene| walk(path, scene.nodes(), &buffers, &mut out))
    }));
    walked.map_err(|_| {
        FileError::format(
            path,
            format!("not a readable {kind} file (its data is inconsistent); re-export it"),
        )
    })??;
    if out.triangles.is_empty() {
        return Err(FileError::format(path, no_triangles_reason(&gltf)));
    }
    let Accumulator {
        positions,
        triangles,
        normals,
        uvs,
        all_normals,
        all_uvs,
        parts,
        part_materials,
        ..
    } = out;
    let look = with_look
        .then(|| super::mesh_look::gltf_look(path, &gltf, &buffers, &parts, &part_materials));
    let mesh = super::mesh_from_file(
        path,
        positions,
        triangles,
        all_normals.then_some(normals),
        all_uvs.then_some(uvs),
    )?;
    Ok((mesh.with_parts(parts), look))
}

/// Why a file that read without error gave no triangle: what it lacks, as precisely as the
/// document says (instead of "the mesh has no triangles" for every case).
fn no_triangles_reason(gltf: &gltf::Gltf) -> String {
    let meshes = gltf.meshes().len();
    let scenes = gltf.scenes().len();
    let placed = gltf.nodes().filter(|n| n.mesh().is_some()).count();
    if meshes == 0 {
        "the file has no mesh (only other content, such as cameras, lights or empty nodes); \
         export the model's geometry"
            .into()
    } else if scenes == 0 {
        format!(
            "the file has {meshes} mesh(es) but no scene to place them; export with a scene \
             (Blender: include the scene's objects)"
        )
    } else if placed == 0 {
        format!(
            "the file has {meshes} mesh(es) but no node uses one, so no scene shows them; \
             export the mesh objects, not only their data"
        )
    } else {
        "no node in the file's scene reaches a mesh with triangles (the meshes are in nodes \
         that no scene lists, or their primitives have no vertices); export the visible \
         objects of one scene"
            .into()
    }
}

/// The JSON of a glTF file: the whole file, or a GLB's JSON chunk (`None` when the GLB is too
/// short to hold one).
fn json_of(bytes: &[u8]) -> Option<&[u8]> {
    if bytes.starts_with(b"glTF") {
        // GLB: 12-byte header, then the JSON chunk (length, type, data).
        let length = bytes
            .get(12..16)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)?;
        bytes.get(20..20usize.saturating_add(length))
    } else {
        Some(bytes)
    }
}

/// A GLB's header must give version 2 and the file's own length (a shorter length hides bytes
/// the reader would ignore; a longer one is a truncated file), and the asset must be glTF 2.x:
/// glTF 1.0 is a different format, whose files only look alike.
fn check_container(
    path: &Path,
    bytes: &[u8],
    root: Option<&serde_json::Value>,
) -> Result<(), FileError> {
    if bytes.starts_with(b"glTF") {
        let word = |at: usize| {
            bytes
                .get(at..at + 4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        };
        let (Some(version), Some(length)) = (word(4), word(8)) else {
            return Err(FileError::format(
                path,
                "a GLB file has a 12-byte header; this one is cut short",
            ));
        };
        if version != 2 {
            return Err(FileError::format(
                path,
                format!(
                    "GLB container version {version}; only version 2 (glTF 2.0) is read: \
                     re-export it from a current tool"
                ),
            ));
        }
        if length as usize != bytes.len() {
            return Err(FileError::format(
                path,
                format!(
                    "the GLB header gives a length of {length} bytes, but the file has {}: it \
                     is truncated or has bytes after its end; re-export it",
                    bytes.len()
                ),
            ));
        }
    }
    let version = root.and_then(|root| root.get("asset")?.get("version")?.as_str());
    match version {
        Some(v) if !v.starts_with("2.") => Err(FileError::format(
            path,
            format!(
                "a glTF {v} file; only glTF 2.0 is read (1.0 is a different format): re-export \
                 it as glTF 2.0"
            ),
        )),
        _ => Ok(()),
    }
}

/// Checks that every mesh primitive of the document `root` names accessors that exist (the
/// gltf crate's validation indexes them unchecked and would panic).
fn check_primitive_references(path: &Path, root: &serde_json::Value) -> Result<(), FileError> {
    let accessors = root
        .get("accessors")
        .and_then(serde_json::Value::as_array)
        .map_or(0, Vec::len);
    let meshes = root.get("meshes").and_then(serde_json::Value::as_array);
    for (m, mesh) in meshes.into_iter().flatten().enumerate() {
        let primitives = mesh.get("primitives").and_then(serde_json::Value::as_array);
        for (p, primitive) in primitives.into_iter().flatten().enumerate() {
            let attributes = primitive
                .get("attributes")
                .and_then(serde_json::Value::as_object);
            let targets = primitive
                .get("targets")
                .and_then(serde_json::Value::as_array)
                .into_iter()
                .flatten()
                .filter_map(serde_json::Value::as_object)
                .flatten();
            let named = attributes
                .into_iter()
                .flatten()
                .chain(targets)
                .map(|(name, index)| (name.as_str(), index))
                .chain(primitive.get("indices").map(|i| ("indices", i)));
            for (name, index) in named {
                let valid = index.as_u64().is_some_and(|i| i < accessors as u64);
                if !valid {
                    return Err(FileError::format(
                        path,
                        format!(
                            "mesh {m}, primitive {p}: {name} names accessor {index}, but the \
                             file has {accessors} accessors; re-export the file"
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

fn load_buffers(
    path: &Path,
    gltf: &gltf::Gltf,
    root: Option<&serde_json::Value>,
    file_length: usize,
) -> Result<Vec<Vec<u8>>, FileError> {
    use super::gltf_meshopt::{fallback_bytes, is_fallback};
    gltf.buffers()
        .map(|buffer| {
            let data = match buffer.source() {
                // EXT_meshopt_compression: the decoded views fill it.
                gltf::buffer::Source::Bin
                    if root.is_some_and(|r| is_fallback(r, buffer.index())) =>
                {
                    fallback_bytes(path, buffer.index(), buffer.length(), file_length)?
                }
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
pub(super) fn percent_decode(text: &str) -> Option<String> {
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
    /// Each primitive (instance) read, in order.
    parts: Vec<starcages_core::mesh::MeshPart>,
    /// Each part's material (glTF material index; `None`: the default material).
    part_materials: Vec<Option<usize>>,
    /// The file uses KHR_mesh_quantization: vertex attributes may be integers.
    quantized: bool,
    /// World matrix of every node (skins place their meshes by their joints' worlds); `None`
    /// below a loop of parents.
    node_worlds: Vec<Option<DMat4>>,
    /// The glTF document's nodes' names, for messages.
    node_names: Vec<String>,
}

/// A file that requires an extension this reader does not handle (Draco or meshopt
/// compression, …) is refused naming it and saying how to export without it.
fn check_required_extensions(path: &Path, root: &serde_json::Value) -> Result<(), FileError> {
    let required = root
        .get("extensionsRequired")
        .and_then(serde_json::Value::as_array);
    let unread: Vec<&str> = required
        .into_iter()
        .flatten()
        .filter_map(serde_json::Value::as_str)
        .filter(|&e| e != QUANTIZATION && e != super::gltf_meshopt::MESHOPT)
        .collect();
    if unread.is_empty() {
        return Ok(());
    }
    Err(FileError::format(
        path,
        format!(
            "the file requires the glTF extension(s) {}, which StarCages does not read yet \
             (of the required extensions it reads {QUANTIZATION} and {}); export without \
             them (Blender: turn off mesh compression)",
            unread.join(", "),
            super::gltf_meshopt::MESHOPT
        ),
    ))
}

/// The extension that lets vertex attributes be 8- or 16-bit integers (gltfpack's default
/// output, which game and web pipelines ship); the node transforms dequantise them.
const QUANTIZATION: &str = "KHR_mesh_quantization";

/// The document parsed and validated as the `gltf` crate does, except that requiring
/// [`QUANTIZATION`] or `EXT_meshopt_compression`, which this reader handles itself, is not an
/// error.
fn parse_validated(bytes: &[u8]) -> Result<gltf::Gltf, gltf::Error> {
    use gltf::json::validation::{Error, Validate};
    let gltf = gltf::Gltf::from_slice_without_validation(bytes)?;
    let root = gltf.document.as_json();
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        errors.push((path(), error));
    });
    let handled = [QUANTIZATION, super::gltf_meshopt::MESHOPT].map(|e| format!("= \"{e}\""));
    errors.retain(|(path, error)| {
        !(matches!(error, Error::Unsupported)
            && path.as_str().starts_with("extensionsRequired")
            && handled.iter().any(|h| path.as_str().ends_with(h)))
    });
    if errors.is_empty() {
        Ok(gltf)
    } else {
        Err(gltf::Error::Validation(errors))
    }
}

/// Most node instances a file may expand to (a node graph that shares subtrees can describe
/// astronomically many paths in a few bytes).
const MAX_NODE_INSTANCES: usize = 1_000_000;

fn too_many_instances(path: &Path) -> FileError {
    FileError::format(
        path,
        format!(
            "the node graph expands to more than {MAX_NODE_INSTANCES} node instances \
             (subtrees shared many times over); re-export it as a plain tree"
        ),
    )
}

/// How many node instances the trees under `roots` expand to, counted once per node from its
/// children's counts (linear in the nodes and their links, without recursion), saturating
/// just past [`MAX_NODE_INSTANCES`]. None when a node is its own ancestor: [`walk`] names it.
fn instance_count(roots: &[gltf::Node<'_>]) -> Option<usize> {
    // Per node index: None not reached, Some(None) on the current path, Some(Some(n)) counted.
    let mut counted: Vec<Option<Option<usize>>> = Vec::new();
    let mut total = 0usize;
    for root in roots {
        let mut stack = vec![(root.clone(), false)];
        while let Some((node, children_done)) = stack.pop() {
            let index = node.index();
            if counted.len() <= index {
                counted.resize(index + 1, None);
            }
            if children_done {
                let count = node
                    .children()
                    .map(|c| counted.get(c.index()).copied().flatten().flatten())
                    .fold(1usize, |sum, c| sum.saturating_add(c.unwrap_or(0)))
                    .min(MAX_NODE_INSTANCES + 1);
                counted[index] = Some(Some(count));
                continue;
            }
            match counted[index] {
                Some(Some(_)) => continue,
                Some(None) => return None,
                None => {}
            }
            counted[index] = Some(None);
            stack.push((node.clone(), true));
            for child in node.children() {
                match counted.get(child.index()).copied().flatten() {
                    Some(None) => return None,
                    Some(Some(_)) => {}
                    None => stack.push((child, false)),
                }
            }
        }
        let count = counted.get(root.index()).copied().flatten().flatten();
        total = total.saturating_add(count.unwrap_or(0));
    }
    Some(total)
}

/// Visits the node trees under `roots` depth first without recursion (a deep chain cannot
/// overflow the stack), refusing cycles and graphs that expand past [`MAX_NODE_INSTANCES`].
fn walk<'a>(
    path: &Path,
    roots: impl Iterator<Item = gltf::Node<'a>>,
    buffers: &[Vec<u8>],
    out: &mut Accumulator,
) -> Result<(), FileError> {
    // (node, its parent's world transform, depth, the nearest node at or above it whose own
    // transform is not finite or flattens); `on_path[i]`: node i is an ancestor of the node
    // being visited, `path_nodes[d]`: the ancestor at depth d.
    let roots: Vec<gltf::Node<'a>> = roots.collect();
    // A graph sharing subtrees many times over is refused before its instances are visited.
    if instance_count(&roots).is_some_and(|n| n > MAX_NODE_INSTANCES) {
        return Err(too_many_instances(path));
    }
    let mut stack: Vec<(gltf::Node<'a>, DMat4, usize, Option<usize>)> = roots
        .into_iter()
        .map(|n| (n, DMat4::IDENTITY, 0, None))
        .collect();
    stack.reverse();
    let mut path_nodes: Vec<usize> = Vec::new();
    let mut on_path: Vec<bool> = Vec::new();
    let mut instances = 0usize;
    while let Some((node, parent, depth, flattened_by)) = stack.pop() {
        for gone in path_nodes.drain(depth.min(path_nodes.len())..) {
            if let Some(flag) = on_path.get_mut(gone) {
                *flag = false;
            }
        }
        let index = node.index();
        if on_path.len() <= index {
            on_path.resize(index + 1, false);
        }
        if on_path[index] {
            return Err(FileError::format(
                path,
                format!(
                    "node {index} is its own ancestor (the node graph has a cycle); a glTF node \
                     hierarchy must be a tree, re-export the file"
                ),
            ));
        }
        instances += 1;
        if instances > MAX_NODE_INSTANCES {
            return Err(too_many_instances(path));
        }
        on_path[index] = true;
        path_nodes.push(index);
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world = parent * local;
        let flattened_by = match super::gltf_skin::placement_problem(&local) {
            Some(_) if flattened_by.is_none() => Some(index),
            _ => flattened_by,
        };
        add_node_mesh(path, &node, world, flattened_by, buffers, out)?;
        let first_child = stack.len();
        stack.extend(
            node.children()
                .map(|child| (child, world, depth + 1, flattened_by)),
        );
        stack[first_child..].reverse();
    }
    Ok(())
}

/// Appends the triangles of `node`'s mesh (if any) placed by `world`; `flattened_by` is the
/// node at or above it whose own transform is not finite or flattens (scale 0), if any: a mesh
/// placed by its node there is refused naming that node (a skinned one is placed by its
/// joints, checked in [`super::gltf_skin`]).
fn add_node_mesh(
    path: &Path,
    node: &gltf::Node,
    world: DMat4,
    flattened_by: Option<usize>,
    buffers: &[Vec<u8>],
    out: &mut Accumulator,
) -> Result<(), FileError> {
    if let Some(mesh) = node.mesh() {
        let node_name = |i: usize| out.node_names.get(i).map_or("unnamed", String::as_str);
        if node.skin().is_none()
            && let Some(why) = super::gltf_skin::placement_problem(&world)
        {
            let culprit = flattened_by.unwrap_or(node.index());
            let at = if culprit == node.index() {
                String::new()
            } else {
                format!(
                    " (through its ancestor node {culprit} '{}')",
                    node_name(culprit)
                )
            };
            return Err(FileError::format(
                path,
                format!(
                    "node {} '{}' places mesh {} ('{}') by a transform that {why}{at}; give \
                     the node a non-zero scale and re-export",
                    node.index(),
                    node_name(node.index()),
                    mesh.index(),
                    mesh.name().unwrap_or("unnamed"),
                ),
            ));
        }
        let affine = DAffine3::from_mat4(world);
        let normal_matrix = affine.matrix3.inverse().transpose();
        for primitive in mesh.primitives() {
            let mesh_name = mesh.name().unwrap_or("unnamed");
            let (mesh_index, primitive_index) = (mesh.index(), primitive.index());
            let what = |attribute: &str| {
                format!(
                    "mesh {mesh_index} ('{mesh_name}'), primitive {primitive_index}, {attribute}"
                )
            };
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                return Err(FileError::format(
                    path,
                    format!(
                        "mesh {mesh_index} ('{mesh_name}'), primitive {primitive_index} is a \
                         {:?} primitive; only triangles are supported, triangulate on export",
                        primitive.mode()
                    ),
                ));
            }
            use gltf::accessor::{DataType as T, Dimensions as D};
            use gltf::mesh::Semantic;
            let position = primitive.get(&Semantic::Positions).ok_or_else(|| {
                FileError::format(
                    path,
                    format!(
                        "{} is missing; every primitive needs vertex positions",
                        what("POSITION")
                    ),
                )
            })?;
            // KHR_mesh_quantization allows 8- and 16-bit integer attributes.
            let (position_kinds, normal_kinds, uv_kinds): (&[_], &[_], &[_]) = if out.quantized {
                (
                    &[
                        (T::F32, D::Vec3),
                        (T::I8, D::Vec3),
                        (T::U8, D::Vec3),
                        (T::I16, D::Vec3),
                        (T::U16, D::Vec3),
                    ],
                    &[(T::F32, D::Vec3), (T::I8, D::Vec3), (T::I16, D::Vec3)],
                    &[
                        (T::F32, D::Vec2),
                        (T::I8, D::Vec2),
                        (T::U8, D::Vec2),
                        (T::I16, D::Vec2),
                        (T::U16, D::Vec2),
                    ],
                )
            } else {
                (
                    &[(T::F32, D::Vec3)],
                    &[(T::F32, D::Vec3)],
                    &[(T::F32, D::Vec2), (T::U8, D::Vec2), (T::U16, D::Vec2)],
                )
            };
            let count =
                check_accessor(path, &position, buffers, position_kinds, &what("POSITION"))?;
            if let Some(normal) = primitive.get(&Semantic::Normals) {
                let n = check_accessor(path, &normal, buffers, normal_kinds, &what("NORMAL"))?;
                if n != count {
                    return Err(FileError::format(
                        path,
                        format!(
                            "{} has {n} entries for {count} positions; re-export the file",
                            what("NORMAL")
                        ),
                    ));
                }
            }
            if let Some(uv) = primitive.get(&Semantic::TexCoords(0)) {
                let n = check_accessor(path, &uv, buffers, uv_kinds, &what("TEXCOORD_0"))?;
                if n != count {
                    return Err(FileError::format(
                        path,
                        format!(
                            "{} has {n} entries for {count} positions; re-export the file",
                            what("TEXCOORD_0")
                        ),
                    ));
                }
            }
            if let Some(indices) = primitive.indices() {
                let kinds = [(T::U8, D::Scalar), (T::U16, D::Scalar), (T::U32, D::Scalar)];
                check_accessor(path, &indices, buffers, &kinds, &what("indices"))?;
            }
            // A skinned mesh is placed by its joints (glTF 2.0 "Skins"), not by its node.
            let skinning = match node.skin() {
                Some(skin) => {
                    let joints = super::gltf_skin::joint_matrices(
                        path,
                        &out.node_names,
                        &skin,
                        buffers,
                        &out.node_worlds,
                    )?;
                    Some(super::gltf_skin::vertex_transforms(
                        path, &primitive, buffers, &joints, count, affine, &what,
                    )?)
                }
                None => None,
            };
            let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
            let positions = read_elements::<3>(&position, buffers, false);
            let first = out.positions.len();
            if first == 0 && out.triangles.is_empty() {
                out.all_normals = true;
                out.all_uvs = true;
            }
            let transform_of = |k: usize| skinning.as_ref().map_or(&affine, |t| &t[k]);
            out.positions.extend(
                positions
                    .iter()
                    .enumerate()
                    .map(|(k, &p)| transform_of(k).transform_point3(DVec3::from(p))),
            );
            let count = out.positions.len() - first;
            match primitive.get(&Semantic::Normals) {
                Some(normals) => out.normals.extend(
                    read_elements::<3>(&normals, buffers, false)
                        .iter()
                        .enumerate()
                        .map(|(k, &n)| {
                            let matrix = match &skinning {
                                Some(t) => t[k].matrix3.inverse().transpose(),
                                None => normal_matrix,
                            };
                            (matrix * DVec3::from(n)).normalize_or_zero().as_vec3()
                        }),
                ),
                None => out.all_normals = false,
            }
            match primitive.get(&Semantic::TexCoords(0)) {
                Some(uvs) => out.uvs.extend(
                    read_elements::<2>(&uvs, buffers, !out.quantized)
                        .iter()
                        .map(|&[u, v]| Vec2::new(u as f32, v as f32)),
                ),
                None => out.all_uvs = false,
            }
            let base = first as u32;
            let first_triangle = out.triangles.len() as u32;
            // Winding stays outward where the placement mirrors (per triangle for a skin: the
            // majority of its corners' transforms).
            let mirrored = |k: u32| transform_of(k as usize).matrix3.determinant() < 0.0;
            let mut push = |t: [u32; 3]| {
                let flip = t.iter().filter(|&&k| mirrored(k)).count() >= 2;
                let t = t.map(|v| v + base);
                out.triangles
                    .push(if flip { [t[0], t[2], t[1]] } else { t });
            };
            match reader.read_indices() {
                Some(indices) => {
                    let indices: Vec<u32> = indices.into_u32().collect();
                    if !indices.len().is_multiple_of(3) {
                        return Err(FileError::format(
                            path,
                            format!(
                                "{} holds {} indices, not a whole number of triangles; \
                                 re-export the file",
                                what("the index list"),
                                indices.len()
                            ),
                        ));
                    }
                    if let Some(k) = indices.iter().position(|&i| i as usize >= count) {
                        return Err(FileError::format(
                            path,
                            format!(
                                "{} names vertex {} at index {k}, but the primitive has \
                                 {count} vertices (numbered from 0); the file is damaged: \
                                 re-export it",
                                what("the index list"),
                                indices[k]
                            ),
                        ));
                    }
                    indices
                        .chunks_exact(3)
                        .for_each(|t| push([t[0], t[1], t[2]]));
                }
                None => {
                    if !count.is_multiple_of(3) {
                        return Err(FileError::format(
                            path,
                            format!(
                                "{} has {count} vertices and no index list, not a whole number \
                                 of triangles (3 vertices each); re-export the file",
                                what("POSITION")
                            ),
                        ));
                    }
                    (0..count as u32 / 3).for_each(|t| push([3 * t, 3 * t + 1, 3 * t + 2]))
                }
            }
            out.parts.push(starcages_core::mesh::MeshPart {
                vertices: base..out.positions.len() as u32,
                triangles: first_triangle..out.triangles.len() as u32,
            });
            out.part_materials.push(primitive.material().index());
        }
    }
    Ok(())
}
