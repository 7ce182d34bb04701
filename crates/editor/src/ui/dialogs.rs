//! Native file dialogs (rfd). Each returns the chosen path, or `None` when the user cancelled.

use std::path::PathBuf;

/// A scene or mesh to open.
pub fn open_file() -> Option<PathBuf> {
    rfd::FileDialog::new()
        .add_filter("scene or mesh", &["json", "obj", "gltf", "glb"])
        .pick_file()
}

/// A mesh to box in automatic cages.
pub fn mesh_file() -> Option<PathBuf> {
    rfd::FileDialog::new()
        .add_filter("mesh", &["obj", "gltf", "glb"])
        .pick_file()
}

/// Where to save the scene.
pub fn scene_destination() -> Option<PathBuf> {
    rfd::FileDialog::new()
        .add_filter("StarCages scene", &["json"])
        .set_file_name("scene.json")
        .save_file()
}

/// Where to write the deformed mesh.
pub fn mesh_destination() -> Option<PathBuf> {
    rfd::FileDialog::new()
        .add_filter("mesh", &["obj", "glb"])
        .set_file_name("deformed.obj")
        .save_file()
}

/// Where to write the cages.
pub fn cages_destination() -> Option<PathBuf> {
    rfd::FileDialog::new()
        .add_filter("OBJ", &["obj"])
        .set_file_name("cages.obj")
        .save_file()
}
