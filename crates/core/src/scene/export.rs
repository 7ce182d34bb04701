//! Writing the deformed mesh of a scene: in the mesh file's axes, and for a mesh read from an
//! OBJ file written to OBJ, as a copy of that file (same vertex list, texture coordinates,
//! groups and materials), so that it can serve as a shape key against the original.

use std::path::Path;

use glam::DVec3;

use super::{MeshSource, Scene};
use crate::io::{FileError, extension, write_mesh, write_obj_like_source};

/// Writes the scene's mesh deformed to `welded` (welded positions, scene coordinates) to
/// `path` (.obj or .glb), turned back to the mesh file's up axis ([`Scene::export_up`]). A
/// rest-pose export is the source file's positions to float precision.
pub fn write_deformed_mesh(path: &Path, scene: &Scene, welded: &[DVec3]) -> Result<(), FileError> {
    let up = scene.export_up();
    match &scene.mesh_source {
        MeshSource::File(source) if extension(path) == "obj" && extension(source) == "obj" => {
            write_obj_like_source(
                path,
                source,
                &scene.mesh,
                welded,
                |p| up.to_scene(p),
                |p| up.from_scene(p),
            )
            .map(|_| ())
        }
        _ => {
            let positions: Vec<DVec3> = scene
                .mesh
                .unweld(welded)
                .into_iter()
                .map(|p| up.from_scene(p))
                .collect();
            write_mesh(path, &scene.mesh, &positions)
        }
    }
}
