//! StarCages' files: meshes (OBJ, glTF, GLB, FBX, PLY, STL, OFF) read and written, cage OBJ
//! files, point lists, point caches (PC2, MDD), baked glTF animation, scene files, deformed
//! mesh export and the binding cache; atomic saves. Apart from `starcages-core` so that the
//! maths builds without the C and C++ libraries the readers use (ufbx, meshoptimizer).
//!
//! Every error names the file, and for text formats the 1-based line, with the reason.

mod atomic;
mod bind_cache;
mod cage_set_obj;
mod export;
mod gltf_accessor;
mod gltf_animation;
mod gltf_meshopt;
mod gltf_skin;
mod mesh_fbx;
mod mesh_gltf;
mod mesh_look;
mod mesh_obj;
mod mesh_off;
mod mesh_ply;
mod mesh_stl;
mod mesh_write;
mod obj_cage;
mod obj_like_source;
mod obj_lint;
mod point_cache;
mod points;
pub mod sample_files;
mod scene_file;

use std::path::{Path, PathBuf};

use thiserror::Error;

use starcages_core::cage::CageError;
use starcages_core::mesh::{Mesh, MeshError};

pub use atomic::{AtomicWriter, is_same_file, remove_unfinished_saves, write_atomic};
pub use bind_cache::{CacheOutcome, bind_scene_cached, cache_path};
pub use cage_set_obj::{cage_set_obj_text, read_cage_set_obj, read_pose_obj};
pub use export::{ExportLayout, write_deformed_mesh};
pub use gltf_animation::{MAX_GLTF_BYTES, MAX_GLTF_FRAMES, MorphAnimation};
pub use mesh_fbx::parse_fbx;
pub use mesh_look::{MAX_TEXTURE_SIDE, load_look_images, load_texture};
pub use mesh_off::parse_off;
pub use mesh_ply::parse_ply;
pub use mesh_stl::parse_stl;
pub use mesh_write::{glb_bytes, glb_bytes_in_parts, obj_text, write_mesh};
pub use obj_cage::{ObjCageGroup, ObjCages, parse_obj_cages, read_cage_obj, read_obj_cages};
pub use obj_like_source::{ObjCopyReport, SourceVertex, source_vertex_list, write_obj_like_source};
pub use point_cache::{
    PointCache, PointCacheFormat, PointCacheWriter, parse_point_cache, read_point_cache,
};
pub use points::{parse_points, read_points};
pub use scene_file::{
    SCENE_FORMAT, SCENE_VERSION, SceneFileError, load_scene, save_scene, scene_to_json,
};

/// The mesh file types StarCages reads, by extension.
pub const MESH_EXTENSIONS: [&str; 7] = ["obj", "gltf", "glb", "fbx", "ply", "stl", "off"];
const MESH_EXTENSIONS_TEXT: &str = "obj, gltf, glb, fbx, ply, stl, off";

/// Whether the mesh file at `path` declares its own axes, so that StarCages reads it Y-up
/// whatever `--up` says: glTF (Y-up by specification) and FBX (turned to Y-up from the axes
/// its header declares).
pub fn declares_axes(path: &Path) -> bool {
    matches!(extension(path).as_str(), "gltf" | "glb" | "fbx")
}

/// Reads a mesh from an OBJ, glTF, GLB, FBX, PLY, STL or OFF file (by extension).
pub fn read_mesh(path: &Path) -> Result<Mesh, FileError> {
    match extension(path).as_str() {
        "obj" => mesh_obj::read_obj_mesh(path),
        "gltf" | "glb" => mesh_gltf::read_gltf_mesh(path),
        "fbx" => mesh_fbx::read_fbx_mesh(path),
        "ply" => mesh_ply::read_ply_mesh(path),
        "stl" => mesh_stl::read_stl_mesh(path),
        "off" => mesh_off::read_off_mesh(path),
        other => Err(FileError::Unsupported {
            path: path.to_path_buf(),
            extension: other.to_owned(),
            supported: MESH_EXTENSIONS_TEXT,
        }),
    }
}

/// Reads a mesh file and its look: the materials of glTF/GLB, OBJ (its MTL libraries) and FBX
/// files, each triangle's material and the UVs' origin (other formats: one plain material).
/// The mesh is the one [`read_mesh`] reads, except that an OBJ with `usemtl` may split its
/// vertices where materials change; triangles keep their order. Images are named, not decoded:
/// [`load_texture`] decodes each.
pub fn read_mesh_look(
    path: &Path,
) -> Result<(Mesh, starcages_core::mesh::look::MeshLook), FileError> {
    use starcages_core::mesh::look::{Material, MeshLook};
    let plain = |mesh: Mesh| {
        let look = MeshLook {
            materials: vec![Material::default()],
            triangle_materials: vec![0; mesh.triangles().len()],
            ..MeshLook::default()
        };
        (mesh, look)
    };
    match extension(path).as_str() {
        "obj" => {
            mesh_obj::read_obj(path, true).map(|(mesh, look)| (mesh, look.unwrap_or_default()))
        }
        "gltf" | "glb" => {
            mesh_gltf::read_gltf(path, true).map(|(mesh, look)| (mesh, look.unwrap_or_default()))
        }
        "fbx" => mesh_fbx::read_fbx(path),
        _ => read_mesh(path).map(plain),
    }
}

/// Reads a mesh file written with `up` as its up axis, in scene coordinates (Z up).
pub fn read_mesh_as(path: &Path, up: starcages_core::scene::UpAxis) -> Result<Mesh, FileError> {
    read_mesh(path).map(|mesh| up.mesh_to_scene(mesh))
}

/// A mesh read from `path`: validated and welded, problems reported against the file.
pub(crate) fn mesh_from_file(
    path: &Path,
    positions: Vec<glam::DVec3>,
    triangles: Vec<[u32; 3]>,
    normals: Option<Vec<glam::Vec3>>,
    uvs: Option<Vec<glam::Vec2>>,
) -> Result<Mesh, FileError> {
    Mesh::new(positions, triangles, normals, uvs).map_err(|problem| FileError::InvalidMesh {
        path: path.to_path_buf(),
        problem,
    })
}

/// Lower-case extension of a path ("" when none).
pub(crate) fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

/// A file could not be read as what was asked for.
#[derive(Debug, Error)]
pub enum FileError {
    /// The file could not be opened or read.
    #[error("{path}: cannot read: {error}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The system's reason (part of the message, so not a `source`).
        error: std::io::Error,
    },
    /// A line could not be parsed.
    #[error("{path}:{line}: {reason}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong and what was expected.
        reason: String,
    },
    /// The file's format is not one we read or write.
    #[error("{path}: unsupported file type '.{extension}'; use one of: {supported}")]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// Its extension.
        extension: String,
        /// What is supported.
        supported: &'static str,
    },
    /// The file could not be decoded (a reader library's reason).
    #[error("{path}: {reason}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// Refused to write a non-finite coordinate (an edit or pose blew up): nothing was written.
    #[error(
        "{path}: not written: vertex {vertex} has a non-finite coordinate; undo the edit or pose \
         that moved it so far (coordinates must stay within ±{}), the previous file, if any, is \
         unchanged",
        starcages_core::scene::MAX_COORDINATE
    )]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// The first offending vertex (0-based).
        vertex: usize,
    },
    /// The file parsed but its content is not a valid mesh.
    #[error("{path}: invalid mesh: {problem}")]
    InvalidMesh {
        /// The file.
        path: PathBuf,
        /// The mesh problem.
        problem: MeshError,
    },
    /// Writing failed; an existing file at `path` is untouched.
    #[error("{path}: cannot save: {error}; the previous file, if any, is unchanged")]
    Write {
        /// The file.
        path: PathBuf,
        /// The system's reason.
        error: std::io::Error,
    },
    /// The file parsed but its content is not a valid cage.
    #[error("{path}: invalid cage: {problem}")]
    InvalidCage {
        /// The file.
        path: PathBuf,
        /// The cage problem (element indices are 0-based, in file order).
        problem: CageError,
    },
}

impl FileError {
    pub(crate) fn format(path: &Path, reason: impl Into<String>) -> Self {
        Self::Format {
            path: path.to_path_buf(),
            reason: reason.into(),
        }
    }

    pub(crate) fn parse(path: &Path, line: usize, reason: impl Into<String>) -> Self {
        Self::Parse {
            path: path.to_path_buf(),
            line,
            reason: reason.into(),
        }
    }
}

/// The largest file StarCages reads (2 GiB): a mesh several times the size of any scan we
/// know. Checked against the file's size before reading, so a device such as `/dev/zero` or a
/// file growing while read cannot exhaust memory.
pub const MAX_FILE_BYTES: u64 = 2 << 30;

/// The bytes of the regular file at `path` (symbolic links followed), refusing devices, pipes
/// and folders, and files larger than [`MAX_FILE_BYTES`].
pub fn read_file_bytes(path: &Path) -> Result<Vec<u8>, FileError> {
    let io = |error| FileError::Io {
        path: path.to_path_buf(),
        error,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(FileError::format(
            path,
            "not a regular file (a folder, device or pipe); give the path of a file",
        ));
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(FileError::format(
            path,
            format!(
                "the file has {} bytes, more than the {MAX_FILE_BYTES}-byte limit for inputs",
                meta.len()
            ),
        ));
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::io::Read::read_to_end(
        &mut std::io::Read::take(file, MAX_FILE_BYTES + 1),
        &mut bytes,
    )
    .map_err(io)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(FileError::format(
            path,
            "the file grew past the input size limit while it was read",
        ));
    }
    Ok(bytes)
}

/// A text file as UTF-8, without a leading byte-order mark (which some editors write and which
/// would otherwise hide inside the first number or keyword: "x '\u{feff}0.5' is not a number").
pub fn read_text(path: &Path) -> Result<String, FileError> {
    let mut bytes = read_file_bytes(path)?;
    if bytes.starts_with(b"\xEF\xBB\xBF") {
        bytes.drain(..3);
    }
    String::from_utf8(bytes).map_err(|e| {
        let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        FileError::parse(path, line, "not UTF-8 text; is this really a text file?")
    })
}

/// The statements of OBJ text: (1-based line number, keyword, the remaining tokens) for every
/// line that is not blank or only a `#` comment.
pub(crate) fn obj_statements(
    text: &str,
) -> impl Iterator<Item = (usize, &str, std::str::SplitWhitespace<'_>)> {
    text.lines().enumerate().filter_map(|(index, raw)| {
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut tokens = line.split_whitespace();
        let keyword = tokens.next()?;
        Some((index + 1, keyword, tokens))
    })
}

/// Parses one finite float token, with a reason naming the token on failure.
pub(crate) fn parse_finite(token: &str, what: &str) -> Result<f64, String> {
    let value: f64 = token
        .parse()
        .map_err(|_| format!("{what} '{token}' is not a number"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("{what} '{token}' is not finite (NaN or infinity)"))
    }
}
