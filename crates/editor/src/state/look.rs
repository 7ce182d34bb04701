//! The mesh file's look (materials and images) for Textured shading: read and decoded on a
//! worker when a document opens, so a large image never stalls the UI; a missing or broken
//! image is a status message naming the file, and the mesh draws without it.

use std::path::PathBuf;
use std::sync::Arc;

use starcages_core::mesh::look::LoadedLook;
use starcages_core::scene::MeshSource;

use super::EditorState;
use super::jobs::{Job, Waker};

/// Reads the look of the mesh file `path` (whose mesh has `triangle_count` triangles) and
/// decodes its images, on a worker. A file that cannot be read, or no longer has that many
/// triangles, gives a look-less result with the reason as its problem.
pub fn load_look(path: PathBuf, triangle_count: usize, wake: Option<Waker>) -> Job<LoadedLook> {
    let label = format!("reading the materials of {}", path.display());
    Job::spawn(
        "materials",
        label,
        wake,
        move |_control| match starcages_io::read_mesh_look(&path) {
            Ok((mesh, _)) if mesh.triangles().len() != triangle_count => LoadedLook {
                problems: vec![format!(
                    "{}: the file changed since the scene was made ({} triangles, the scene's \
                     mesh has {triangle_count}); its materials are not shown",
                    path.display(),
                    mesh.triangles().len()
                )],
                ..LoadedLook::default()
            },
            Ok((_, look)) => starcages_io::load_look_images(look),
            Err(e) => LoadedLook {
                problems: vec![format!("materials not read: {e}")],
                ..LoadedLook::default()
            },
        },
    )
}

impl EditorState {
    /// Starts reading the look of the document's mesh file (none for a generated mesh).
    pub(super) fn start_look(&mut self) {
        self.look = None;
        self.look_job = match &self.doc.scene.mesh_source {
            MeshSource::File(path) => Some(load_look(
                path.clone(),
                self.doc.scene.mesh.triangles().len(),
                self.waker.clone(),
            )),
            MeshSource::Embedded => None,
        };
    }

    /// Takes the look once read: it draws in Textured shading; its problems go to the status
    /// bar (the first, and how many more).
    pub(super) fn poll_look(&mut self, wait: bool) {
        let Some(job) = &self.look_job else {
            return;
        };
        let result = if wait { Some(job.wait()) } else { job.poll() };
        let Some(result) = result else {
            return;
        };
        self.look_job = None;
        match result {
            Ok(loaded) => {
                let problems = loaded.problems.clone();
                let images = loaded.images.iter().flatten().count();
                let plain = loaded.look.is_plain();
                self.look = (!plain).then(|| Arc::new(loaded));
                self.generations.look += 1;
                if let Some(first) = problems.first() {
                    let more = match problems.len() - 1 {
                        0 => String::new(),
                        n => format!(" (and {n} more)"),
                    };
                    self.message = Some(super::Message::new(format!("{first}{more}"), true));
                } else if images > 0 {
                    self.info(format!(
                        "{images} texture image{} read: Textured shading (View menu, Shading) shows them",
                        if images == 1 { "" } else { "s" }
                    ));
                }
            }
            Err(e) => self.error(e),
        }
    }
}
