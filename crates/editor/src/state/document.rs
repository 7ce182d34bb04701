//! The open document: a scene, where it lives on disk, and whether it has unsaved changes.
//! Opening accepts scene files and bare meshes (which get the auto rig).

use std::path::{Path, PathBuf};

use starcages_core::BindControl;
use starcages_core::check::validate_scene;
use starcages_core::generate::demo::demo_scene;
use starcages_core::generate::{AutocageOptions, autocage};
use starcages_core::generate::{AutorigSettings, Mirror, autorig, autorig_settings};
use starcages_core::scene::{Scene, SceneSettings, UpAxis};
use starcages_io::{declares_axes, read_mesh_as};
use starcages_io::{load_scene, save_scene};

use super::EditorError;

/// The demo scene `cargo run --release` opens.
pub const DEMO: &str = "critter";

/// A scene being edited.
#[derive(Debug, Clone)]
pub struct Document {
    /// The scene.
    pub scene: Scene,
    /// Its file, once saved or opened.
    pub path: Option<PathBuf>,
    /// Changed since the last save.
    pub dirty: bool,
}

/// Whether `path` is a file the editor can open: a mesh of a type the readers know, or (with
/// `scenes`) a scene file (`.json`). Checked before any prompt about unsaved
/// work, so that no one confirms losing work for a file that is then refused.
pub fn check_openable(path: &Path, scenes: bool) -> Result<(), EditorError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let mesh = starcages_io::MESH_EXTENSIONS.contains(&extension.as_str());
    let known = mesh || (scenes && extension == "json");
    let cannot = |why: String| EditorError::CannotOpen {
        path: path.to_path_buf(),
        why,
    };
    if !known {
        let what = if extension.is_empty() {
            "a file without an extension".to_owned()
        } else {
            format!("a .{extension} file")
        };
        let wanted = starcages_io::MESH_EXTENSIONS.join(", ");
        return Err(cannot(if scenes {
            format!("{what} is neither a scene (.json) nor a mesh ({wanted})")
        } else {
            format!("{what} is not a mesh ({wanted})")
        }));
    }
    if !path.is_file() {
        return Err(cannot(if path.exists() {
            "it is not a file".into()
        } else {
            "there is no such file".into()
        }));
    }
    Ok(())
}

impl Document {
    /// The built-in demo scene (generated, nothing read from disk).
    pub fn demo() -> Self {
        let scene = demo_scene(DEMO, 1.0).unwrap_or_else(|| unreachable!("the demo exists"));
        Self {
            scene,
            path: None,
            dirty: false,
        }
    }

    /// The generated demo scene `name` (see `starcages-cli demo --list`), unsaved.
    pub fn demo_named(name: &str) -> Result<Self, EditorError> {
        let scene =
            demo_scene(name, 1.0).ok_or_else(|| EditorError::UnknownDemo(name.to_owned()))?;
        Ok(Self {
            scene,
            path: None,
            dirty: false,
        })
    }

    /// Opens a scene (`.json`) or a mesh (any format `read_mesh` reads: OBJ, glTF, GLB, FBX,
    /// PLY, STL, OFF; boxed in automatic grid cages). The error names the file, what is wrong and what to do.
    pub fn open(path: &Path, control: &BindControl) -> Result<Self, EditorError> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        if extension == "json" {
            let scene = load_scene(path).map_err(EditorError::OpenScene)?;
            let report = validate_scene(&scene);
            if let Some(problem) = report.errors.first() {
                return Err(EditorError::InvalidScene {
                    path: path.to_path_buf(),
                    problem: problem.to_string(),
                    count: report.errors.len(),
                });
            }
            return Ok(Self {
                scene,
                path: Some(path.to_path_buf()),
                dirty: false,
            });
        }
        Ok(Self {
            scene: scene_from_mesh(path, &NewMeshOptions::default(), control)?,
            path: None,
            dirty: true,
        })
    }

    /// Saves atomically to `path` and remembers it.
    pub fn save_as(&mut self, path: &Path) -> Result<(), EditorError> {
        save_scene(&self.scene, path).map_err(EditorError::Save)?;
        self.path = Some(path.to_path_buf());
        self.dirty = false;
        Ok(())
    }

    /// The file name, or "untitled".
    pub fn name(&self) -> String {
        self.path.as_ref().and_then(|p| p.file_name()).map_or_else(
            || "untitled".to_owned(),
            |n| n.to_string_lossy().into_owned(),
        )
    }

    /// What it was read from, for a message: the scene file, else the mesh file (a new scene
    /// around a mesh), else "untitled" (a demo).
    pub fn source_name(&self) -> String {
        match (&self.path, &self.scene.mesh_source) {
            (None, starcages_core::scene::MeshSource::File(mesh)) => mesh
                .file_name()
                .map_or_else(|| self.name(), |n| n.to_string_lossy().into_owned()),
            _ => self.name(),
        }
    }

    /// The window title: file name and an unsaved-changes marker.
    pub fn title(&self) -> String {
        format!(
            "{}{} — StarCages",
            if self.dirty { "● " } else { "" },
            self.name()
        )
    }
}

/// Which cages File ▸ New from mesh (and opening a mesh) puts around the mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NewRig {
    /// The auto rig: chains of cages along the limbs, a few across the body.
    #[default]
    Auto,
    /// A grid of box cages.
    Grid,
}

/// How File ▸ New from mesh builds a scene: the auto rig or the automatic grid, and the mesh
/// file's up axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewMeshOptions {
    /// Auto rig or grid.
    pub rig: NewRig,
    /// The auto rig's detail (1 to 5).
    pub detail: u32,
    /// The automatic grid of box cages.
    pub cages: AutocageOptions,
    /// Up axis of an OBJ file (glTF is always Y-up).
    pub up: UpAxis,
    /// A plane the auto rig is a mirror image of itself across (scene axes).
    pub mirror: Mirror,
}

impl Default for NewMeshOptions {
    fn default() -> Self {
        Self {
            rig: NewRig::Auto,
            detail: AutorigSettings::default().detail,
            cages: AutocageOptions::default(),
            up: UpAxis::Y,
            mirror: Mirror::None,
        }
    }
}

/// A new scene around the mesh at `path`, turned to Z-up, in the auto rig or a grid of box
/// cages (`control` reports the auto rig's progress and cancels it).
pub fn scene_from_mesh(
    path: &Path,
    options: &NewMeshOptions,
    control: &BindControl,
) -> Result<Scene, EditorError> {
    let up = if declares_axes(path) {
        UpAxis::Y
    } else {
        options.up
    };
    let mesh = read_mesh_as(path, up).map_err(EditorError::OpenMesh)?;
    let (cages, settings) = match options.rig {
        NewRig::Auto => {
            let settings = AutorigSettings {
                detail: options.detail,
                mirror: options.mirror,
                ..AutorigSettings::default()
            };
            let cages = autorig(&mesh, &settings, control)
                .map_err(EditorError::AutoRig)?
                .cages;
            (cages, autorig_settings())
        }
        NewRig::Grid => (autocage(&mesh, &options.cages), SceneSettings::default()),
    };
    let source = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    Ok(Scene::from_mesh_file(source, up, mesh, cages, settings))
}
