//! Scene files: JSON with a `format` name and an integer `version`, written atomically and
//! human-readably. Mesh paths are stored relative to the scene file; generated demos embed
//! their mesh. Files from a newer version are refused; older ones are migrated.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec2, Vec3};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use thiserror::Error;

use crate::{FileError, read_mesh_as, write_atomic};
use starcages_core::anim::Animation;
use starcages_core::mesh::{Mesh, MeshError};
use starcages_core::scene::UpAxis;
use starcages_core::scene::{
    CageSet, HierarchyState, InternalCage, LeafCage, MeshSource, Scene, SceneSettings,
};

/// The `format` name of scene files.
pub const SCENE_FORMAT: &str = "starcages-scene";
/// The scene file version this build writes (and the newest it reads).
pub const SCENE_VERSION: u32 = 3;

/// Why a scene file could not be read or written.
#[derive(Debug, Error)]
pub enum SceneFileError {
    /// Reading or writing the file itself, or the mesh file it names.
    #[error(transparent)]
    File(#[from] FileError),
    /// Not JSON, or JSON of the wrong shape (with line and column).
    #[error("{path}: not a valid scene file: {reason}")]
    Syntax {
        /// The scene file.
        path: PathBuf,
        /// serde_json's reason, with line and column.
        reason: String,
    },
    /// JSON of the wrong shape: a field missing, of the wrong type or unknown.
    #[error("{path}:{line}:{column}: field '{field}': {reason}")]
    Shape {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The field's path in the document (`cages[0].faces`; `.` for the top level).
        field: String,
        /// What is wrong and what to write instead.
        reason: String,
    },
    /// JSON, but not a StarCages scene.
    #[error(
        "{path}: not a StarCages scene (its \"format\" is {found}, expected \"{SCENE_FORMAT}\")"
    )]
    WrongFormat {
        /// The file.
        path: PathBuf,
        /// What its format field says.
        found: String,
    },
    /// Written by a newer StarCages.
    #[error(
        "{path}: written by a newer StarCages (scene version {version}); this build reads versions up to \
         {SCENE_VERSION}: update StarCages to open it"
    )]
    NewerVersion {
        /// The file.
        path: PathBuf,
        /// Its version.
        version: u64,
    },
    /// The embedded mesh is invalid.
    #[error("{path}: the embedded mesh is invalid: {problem}")]
    EmbeddedMesh {
        /// The scene file.
        path: PathBuf,
        /// What is wrong.
        problem: MeshError,
    },
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct EmbeddedMesh {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    normals: Option<Vec<Vec3>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    uvs: Option<Vec<Vec2>>,
}

#[derive(Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
enum MeshRef {
    Path(PathBuf),
    Embedded(EmbeddedMesh),
}

/// The scene file (version [`SCENE_VERSION`]; older versions are migrated to it first).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    format: String,
    version: u32,
    #[serde(default)]
    settings: SceneSettings,
    cage_vertices: Vec<DVec3>,
    cages: Vec<LeafCage>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    internal_cages: Vec<InternalCage>,
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    poses: BTreeMap<String, Vec<DVec3>>,
    /// Hierarchy state of named poses (absent: rest state).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pose_hierarchy: BTreeMap<String, HierarchyState>,
    /// Absent when the current pose is the rest pose.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    current_pose: Option<Vec<DVec3>>,
    /// Hierarchy state of the current pose (absent: rest state).
    #[serde(default, skip_serializing_if = "HierarchyState::is_rest")]
    current_hierarchy: HierarchyState,
    /// The mesh file's up axis (version 2; version 1 files read meshes as they are: "z").
    #[serde(default)]
    mesh_up_axis: UpAxis,
    /// Keys, frame rate and range (version 3; absent: no keys, 24 fps, frames 1..48).
    #[serde(default, skip_serializing_if = "Animation::is_default")]
    animation: Animation,
    /// Last, since an embedded mesh can be long.
    mesh: MeshRef,
}

/// serde_json's reason without its own "at line L column C" (the error names them), with the
/// fix spelled out for the common cases.
fn shape_reason(error: &serde_json::Error) -> String {
    let text = error.to_string();
    let text = match text.rfind(" at line ") {
        Some(at) => text[..at].to_owned(),
        None => text,
    };
    if let Some(field) = text.strip_prefix("missing field ") {
        format!(
            "the field {field} is missing here; add it (docs/scene-format.md lists every field)"
        )
    } else if text.starts_with("invalid type") || text.starts_with("invalid value") {
        format!("{text}; write a value of the expected kind")
    } else if text.starts_with("unknown field") || text.starts_with("unknown variant") {
        format!("{text}; check the spelling")
    } else if text == "expected value" {
        // The text parsed as JSON before: this is a number, list, object or null where a name
        // (one of a field's words, such as a cage's kind) belongs.
        "expected a name in quotes here (such as \"mvc\"; docs/scene-format.md lists each \
         field's names), found a number, a list, an object or null; write the name as a string"
            .into()
    } else {
        text
    }
}

/// Migrations from each older version to the next, applied in order on the raw JSON.
fn migrate(mut value: Value, version: u64) -> Value {
    debug_assert!(version <= u64::from(SCENE_VERSION));
    if version < 2 {
        // Version 1 read mesh files as they are (Z up); version 2 turns Y-up files, so a
        // version-1 scene says "z" to keep its mesh where its cages are.
        if let Value::Object(map) = &mut value {
            map.insert("mesh_up_axis".into(), Value::String("z".into()));
            map.insert("version".into(), Value::from(2));
        }
    }
    if version < 3 {
        // Version 3 added "animation"; a version-2 scene has none, which is the default.
        if let Value::Object(map) = &mut value {
            map.insert("version".into(), Value::from(3));
        }
    }
    value
}

/// The first field that must be an object (named fields) but is not, with what it is. serde
/// would read a struct from an array by position, which silently accepts nonsense.
fn misplaced_array(value: &Value) -> Option<(String, &'static str)> {
    let kind = |v: &Value| match v {
        Value::Array(_) => "an array",
        Value::String(_) => "a string",
        Value::Number(_) => "a number",
        Value::Bool(_) => "a boolean",
        Value::Null => "null",
        Value::Object(_) => "an object",
    };
    let mut wrong = None;
    let mut check = |field: String, v: &Value| {
        if wrong.is_none() && !v.is_object() {
            wrong = Some((field, kind(v)));
        }
    };
    for field in [
        "settings",
        "animation",
        "current_hierarchy",
        "mesh",
        "pose_hierarchy",
    ] {
        if let Some(v) = value.get(field) {
            check(field.to_owned(), v);
        }
    }
    if let Some(harmonic) = value.get("settings").and_then(|s| s.get("harmonic")) {
        check("settings.harmonic".to_owned(), harmonic);
    }
    for list in ["cages", "internal_cages"] {
        for (i, cage) in value
            .get(list)
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
            .enumerate()
        {
            check(format!("{list}[{i}]"), cage);
        }
    }
    let keys = value.get("animation").and_then(|a| a.get("keys"));
    for (i, key) in keys
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .enumerate()
    {
        check(format!("animation.keys[{i}]"), key);
    }
    if let Some(states) = value.get("pose_hierarchy").and_then(Value::as_object) {
        for (name, state) in states {
            check(format!("pose_hierarchy.{name}"), state);
        }
    }
    wrong
}

/// Reads a scene file and the mesh it names.
pub fn load_scene(path: &Path) -> Result<Scene, SceneFileError> {
    let text = crate::read_text(path)?;
    let syntax = |e: serde_json::Error| SceneFileError::Syntax {
        path: path.to_path_buf(),
        reason: e.to_string(),
    };
    let value: Value = serde_json::from_str(&text).map_err(syntax)?;
    let format = value.get("format");
    if format.and_then(Value::as_str) != Some(SCENE_FORMAT) {
        return Err(SceneFileError::WrongFormat {
            path: path.to_path_buf(),
            found: format.map_or_else(|| "missing".to_owned(), Value::to_string),
        });
    }
    let version = value
        .get("version")
        .and_then(Value::as_u64)
        .ok_or_else(|| SceneFileError::Syntax {
            path: path.to_path_buf(),
            reason: "\"version\" is missing or not a non-negative integer".to_owned(),
        })?;
    if version == 0 {
        return Err(SceneFileError::Syntax {
            path: path.to_path_buf(),
            reason: "\"version\" is 0, which never existed; scene versions start at 1".to_owned(),
        });
    }
    if version > u64::from(SCENE_VERSION) {
        return Err(SceneFileError::NewerVersion {
            path: path.to_path_buf(),
            version,
        });
    }
    let value = migrate(value, version);
    if let Some((field, found)) = misplaced_array(&value) {
        return Err(SceneFileError::Syntax {
            path: path.to_path_buf(),
            reason: format!(
                "\"{field}\" is {found}, but it is a set of named fields: write it as an object \
                 {{\"name\": value, …}} (docs/scene-format.md lists them); values are never \
                 read by position"
            ),
        });
    }
    // Parse the text itself so that shape errors carry the line, the column and the field's
    // path (`cages[0].faces`); a migrated older file is parsed from its migrated value.
    let file: SceneFile = if version == u64::from(SCENE_VERSION) {
        let mut deserializer = serde_json::Deserializer::from_str(&text);
        serde_path_to_error::deserialize(&mut deserializer).map_err(|e| {
            let field = e.path().to_string();
            let inner = e.into_inner();
            SceneFileError::Shape {
                path: path.to_path_buf(),
                line: inner.line(),
                column: inner.column(),
                field,
                reason: shape_reason(&inner),
            }
        })?
    } else {
        serde_json::from_value(value).map_err(syntax)?
    };
    let folder = path.parent().unwrap_or(Path::new("."));
    let (mesh_source, mesh) = match file.mesh {
        MeshRef::Path(relative) => {
            let full = folder.join(&relative);
            let mesh = read_mesh_as(&full, file.mesh_up_axis)?;
            (MeshSource::File(full), mesh)
        }
        MeshRef::Embedded(m) => {
            let mesh =
                Mesh::new(m.positions, m.triangles, m.normals, m.uvs).map_err(|problem| {
                    SceneFileError::EmbeddedMesh {
                        path: path.to_path_buf(),
                        problem,
                    }
                })?;
            (MeshSource::Embedded, mesh)
        }
    };
    let cages = CageSet {
        vertices: file.cage_vertices,
        leaves: file.cages,
        internals: file.internal_cages,
    };
    let pose = file.current_pose.unwrap_or_else(|| cages.vertices.clone());
    Ok(Scene {
        mesh_source,
        mesh_up: file.mesh_up_axis,
        mesh,
        cages,
        settings: file.settings,
        poses: file.poses,
        pose,
        pose_state: file.current_hierarchy,
        pose_states: file.pose_hierarchy,
        animation: file.animation,
    })
}

/// The scene as JSON text, with the mesh path relative to `scene_path`'s folder.
pub fn scene_to_json(scene: &Scene, scene_path: &Path) -> String {
    let mesh = match &scene.mesh_source {
        MeshSource::File(path) => MeshRef::Path(relative_to(
            path,
            scene_path.parent().unwrap_or(Path::new(".")),
        )),
        MeshSource::Embedded => MeshRef::Embedded(EmbeddedMesh {
            positions: scene.mesh.positions().to_vec(),
            triangles: scene.mesh.triangles().to_vec(),
            normals: scene.mesh.normals().map(<[Vec3]>::to_vec),
            uvs: scene.mesh.uvs().map(<[Vec2]>::to_vec),
        }),
    };
    let file = SceneFile {
        format: SCENE_FORMAT.to_owned(),
        version: SCENE_VERSION,
        settings: scene.settings,
        cage_vertices: scene.cages.vertices.clone(),
        cages: scene.cages.leaves.clone(),
        internal_cages: scene.cages.internals.clone(),
        poses: scene.poses.clone(),
        pose_hierarchy: scene
            .pose_states
            .iter()
            .filter(|(_, s)| !s.is_rest())
            .map(|(n, s)| (n.clone(), s.clone()))
            .collect(),
        current_pose: (scene.pose != scene.cages.vertices).then(|| scene.pose.clone()),
        current_hierarchy: scene.pose_state.clone(),
        mesh_up_axis: scene.mesh_up,
        animation: scene.animation.clone(),
        mesh,
    };
    // Serialising plain data to a Value cannot fail (no maps with non-string keys).
    let value = serde_json::to_value(&file).unwrap_or(Value::Null);
    starcages_core::scene::to_pretty_json(&value)
}

/// Saves the scene atomically: a failed save leaves the previous file intact and says why.
pub fn save_scene(scene: &Scene, path: &Path) -> Result<(), SceneFileError> {
    write_atomic(path, scene_to_json(scene, path).as_bytes())?;
    Ok(())
}

/// `path` relative to `base` when it lies below it (or beside it via `..`), else absolute.
fn relative_to(path: &Path, base: &Path) -> PathBuf {
    let absolute = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let (path, base) = (absolute(path), absolute(base));
    let common = path
        .components()
        .zip(base.components())
        .take_while(|(a, b)| a == b)
        .count();
    if common == 0 {
        return path;
    }
    let mut relative = PathBuf::new();
    for _ in base.components().skip(common) {
        relative.push("..");
    }
    for part in path.components().skip(common) {
        relative.push(part);
    }
    relative
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths() {
        assert_eq!(
            relative_to(Path::new("/a/b/mesh.obj"), Path::new("/a/b")),
            PathBuf::from("mesh.obj")
        );
        assert_eq!(
            relative_to(Path::new("/a/m/mesh.obj"), Path::new("/a/b")),
            PathBuf::from("../m/mesh.obj")
        );
    }
}
