//! Writing the deformed mesh of a scene: in the mesh file's axes, and for a mesh read from an
//! OBJ file written to OBJ, as a copy of that file (same vertex list, texture coordinates,
//! groups and materials), so that it can serve as a shape key against the original.

use std::path::Path;

use glam::DVec3;

use crate::{
    FileError, SourceVertex, extension, read_text, source_vertex_list, write_mesh,
    write_obj_like_source,
};
use starcages_core::scene::{MeshSource, Scene, UpAxis};

/// Writes the scene's mesh deformed to `welded` (welded positions, scene coordinates) to
/// `path` (.obj or .glb), turned back to the mesh file's up axis ([`Scene::export_up`]). A
/// rest-pose export is the source file's positions to float precision.
pub fn write_deformed_mesh(path: &Path, scene: &Scene, welded: &[DVec3]) -> Result<(), FileError> {
    // glTF is Y-up by the format's rule; every other file in the mesh file's axes.
    let up = if extension(path) == "glb" {
        UpAxis::Y
    } else {
        scene.export_up()
    };
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

/// The vertex list `write_deformed_mesh` gives a `.obj` file, which point caches (PC2, MDD)
/// follow so that they play on that file: for a mesh read from an OBJ file, the source's `v`
/// lines in file order (a line no face uses keeps its position); otherwise the mesh's original
/// layout.
#[derive(Debug, Clone)]
pub struct ExportLayout {
    /// The source's `v` lines, for a mesh read from OBJ.
    source: Option<Vec<SourceVertex>>,
}

impl ExportLayout {
    /// The layout of `scene`'s OBJ export (reads the source OBJ file, if the mesh came from one).
    pub fn of(scene: &Scene) -> Result<Self, FileError> {
        let source = match &scene.mesh_source {
            MeshSource::File(source) if extension(source) == "obj" => {
                let up = scene.export_up();
                let text = read_text(source)?;
                Some(source_vertex_list(&text, source, &scene.mesh, |p| {
                    up.to_scene(p)
                })?)
            }
            _ => None,
        };
        Ok(Self { source })
    }

    /// How many vertices the export holds.
    pub fn len(&self, scene: &Scene) -> usize {
        match &self.source {
            Some(list) => list.len(),
            None => scene.mesh.positions().len(),
        }
    }

    /// True when the export holds no vertex.
    pub fn is_empty(&self, scene: &Scene) -> bool {
        self.len(scene) == 0
    }

    /// The exported positions, in the mesh file's axes, of the mesh deformed to `welded`
    /// (welded positions, scene coordinates).
    pub fn positions(&self, scene: &Scene, welded: &[DVec3]) -> Vec<DVec3> {
        let up = scene.export_up();
        match &self.source {
            Some(list) => list
                .iter()
                .map(|v| match v.welded.and_then(|w| welded.get(w)) {
                    Some(p) => up.from_scene(*p),
                    None => v.in_file,
                })
                .collect(),
            None => scene
                .mesh
                .unweld(welded)
                .into_iter()
                .map(|p| up.from_scene(p))
                .collect(),
        }
    }
}
