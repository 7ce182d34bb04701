//! Files: open, demos, new from a mesh, save, export, import, the unsaved-changes answer, close.

use std::path::Path;

use starcages_io::{cage_set_obj_text, write_atomic};

use super::{Command, UnsavedAnswer};
use crate::state::NewMeshOptions;
use crate::state::{CageId, EditorError, EditorState, Pending};

/// Carries out a command of this domain (others are not its to apply, and do nothing here).
pub fn apply_files(state: &mut EditorState, command: Command) {
    match command {
        // Read on a worker first: unsaved work is asked about once the file has opened
        // (`Pending::Install`), never for a file that then fails.
        Command::Open(path) => {
            if let Err(e) = crate::state::document::check_openable(&path, true) {
                state.error(e);
            } else {
                state.start_load(path);
            }
        }
        Command::OpenDemo(name) => state.start_load_demo(name),
        Command::NewFromMesh(path, options) => {
            if let Err(e) = crate::state::document::check_openable(&path, false) {
                state.error(e);
            } else {
                new_from_mesh(state, &path, &options);
            }
        }
        Command::Save => match state.doc.path.clone() {
            Some(path) => {
                save_as(state, &path);
            }
            None => state.error(EditorError::NoFile),
        },
        Command::SaveAs(path) => {
            save_as(state, &path);
        }
        Command::ExportMesh(path) => export_mesh(state, &path),
        Command::ExportCages(path) => {
            let scene = &state.doc.scene;
            let inputs = [
                state.doc.path.clone(),
                match &scene.mesh_source {
                    starcages_core::scene::MeshSource::File(p) => Some(p.clone()),
                    starcages_core::scene::MeshSource::Embedded => None,
                },
            ];
            if inputs
                .iter()
                .flatten()
                .any(|p| starcages_io::is_same_file(&path, p))
            {
                state.error(EditorError::OutputIsInput(path));
                return;
            }
            // In the mesh file's axes, to line up with the mesh in other programs.
            let up = scene.export_up();
            let posed: Vec<glam::DVec3> = scene.pose.iter().map(|&p| up.from_scene(p)).collect();
            let text = cage_set_obj_text(&scene.cages, &posed);
            match write_atomic(&path, text.as_bytes()) {
                Ok(()) => state.info(format!("exported {}", path.display())),
                Err(e) => state.error(EditorError::Export(e)),
            }
        }
        Command::ImportCages(path) => {
            let up = state.doc.scene.export_up();
            match starcages_io::read_cage_set_obj(
                &path,
                starcages_core::coords::CoordinateKind::MeanValue,
            ) {
                Ok(mut set) => {
                    for p in &mut set.vertices {
                        *p = up.to_scene(*p);
                    }
                    let count = set.leaves.len();
                    state.edit_scene("import cages", |scene| {
                        starcages_core::rig::import_leaf_cages(scene, &set)
                    });
                    state.info(format!("imported {count} cage(s) from {}", path.display()));
                }
                Err(e) => state.error(EditorError::Rig(e.to_string())),
            }
        }
        Command::ImportInternalCages(path) => import_internal(state, &path),
        Command::AnswerUnsaved(answer) => answer_unsaved(state, answer),
        Command::RequestClose => {
            if state.doc.dirty {
                // A file read meanwhile and waiting to open is dropped: the window closes.
                state.finish_pending_install(false);
                state.pending = Some(Pending::Close);
            } else {
                state.close_confirmed = true;
            }
        }
        _ => {}
    }
}

/// File ▸ Import internal cages: every cage of the OBJ becomes an internal cage driving the
/// free cage vertices inside it (one undo step, all or none).
fn import_internal(state: &mut EditorState, path: &Path) {
    let up = state.doc.scene.export_up();
    let kind = starcages_core::coords::CoordinateKind::MeanValue;
    let mut set = match starcages_io::read_cage_set_obj(path, kind) {
        Ok(set) => set,
        Err(e) => return state.error(EditorError::Rig(e.to_string())),
    };
    for p in &mut set.vertices {
        *p = up.to_scene(*p);
    }
    let result = state.edit_scene("import internal cages", |scene| {
        starcages_core::hierarchy::import_internal_cages(scene, &set, kind)
    });
    match result {
        Ok(added) => {
            let set = &state.doc.scene.cages;
            let named: Vec<String> = added
                .iter()
                .filter_map(|&i| set.internals.get(i))
                .map(|c| format!("'{}' ({} vertices)", c.name, c.owns.len()))
                .collect();
            if let Some(&last) = added.last() {
                state.selection.inspect(Some(CageId::Internal(last)), set);
            }
            state.info(format!(
                "imported internal cage(s) {} from {}",
                named.join(", "),
                path.display()
            ));
        }
        Err(e) => state.error(EditorError::AddInternalCage(e)),
    }
}

pub(super) fn new_from_mesh(state: &mut EditorState, path: &Path, options: &NewMeshOptions) {
    state.start_new_from_mesh(path.to_path_buf(), *options);
}

fn save_as(state: &mut EditorState, path: &Path) -> bool {
    match state.doc.save_as(path) {
        Ok(()) => {
            state.remember(path);
            state.info(format!("saved {}", path.display()));
            true
        }
        Err(e) => {
            state.error(e);
            false
        }
    }
}

fn export_mesh(state: &mut EditorState, path: &Path) {
    let Some(rig) = &state.rig else {
        state.error(EditorError::NotBound);
        return;
    };
    if rig.preview {
        // A preview (mean value join cages) is for interaction, not for files. Its refinement
        // may have been cancelled: start it again.
        state.refine_preview();
        state.error(EditorError::PreviewOnly);
        return;
    }
    if let starcages_core::scene::MeshSource::File(source) = &state.doc.scene.mesh_source
        && starcages_io::is_same_file(path, source)
    {
        state.error(EditorError::OutputIsInput(path.to_path_buf()));
        return;
    }
    let welded: Vec<glam::DVec3> = rig.deformed().iter().map(|p| p.as_dvec3()).collect();
    // In the mesh file's axes, an OBJ as a copy of its source (same vertex list and order).
    match starcages_io::write_deformed_mesh(path, &state.doc.scene, &welded) {
        Ok(()) => state.info(format!("exported {}", path.display())),
        Err(e) => state.error(EditorError::Export(e)),
    }
}

fn answer_unsaved(state: &mut EditorState, answer: UnsavedAnswer) {
    let Some(pending) = state.pending.take() else {
        return;
    };
    let go_on = match answer {
        UnsavedAnswer::Cancel => false,
        UnsavedAnswer::Discard => true,
        UnsavedAnswer::Save(path) => match path.or_else(|| state.doc.path.clone()) {
            // Not saved: keep the work.
            Some(path) => save_as(state, &path),
            None => {
                state.error(EditorError::NoFile);
                false
            }
        },
    };
    match pending {
        Pending::Install => state.finish_pending_install(go_on),
        Pending::Close => state.close_confirmed = go_on,
    }
}
