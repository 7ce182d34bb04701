//! Selection: vertices, faces, mesh vertices, the inspected cage, hover.

use super::Command;
use crate::state::{EditorState, SelectMode};

/// Carries out a command of this domain (others are not its to apply, and do nothing here).
pub fn apply_selection(state: &mut EditorState, command: Command) {
    match command {
        Command::SelectFaces { faces, mode } => {
            let set = &state.doc.scene.cages;
            state.selection.select_faces(faces, mode, set);
        }
        Command::SetSelectElement(element) => state.view.select_element = element,
        Command::SelectMeshVertices { vertices, mode } => {
            let count = state.doc.scene.mesh.welded_positions().len();
            state.selection.select_mesh_vertices(vertices, mode, count);
        }
        Command::Select { vertices, mode } => {
            let count = state.doc.scene.cages.vertices.len();
            let valid = vertices.into_iter().filter(|&v| (v as usize) < count);
            state.selection.select(valid, mode);
            // Faces that lost a corner are no longer selected.
            state.selection.revalidate(&state.doc.scene.cages);
        }
        Command::SelectAll => select_all(state),
        Command::SelectNone => {
            state.selection.select([], SelectMode::Replace);
            state.selection.mesh_vertices.clear();
        }
        Command::InspectCage(cage) => {
            let set = &state.doc.scene.cages;
            let cage = cage.filter(|c| c.exists(set));
            state.selection.inspect(cage, set);
            if let Some(faces) = cage.and_then(|c| c.faces(set)) {
                let vertices = faces.iter().flatten().copied();
                state.selection.select(vertices, SelectMode::Replace);
            }
        }
        Command::Hover(vertex) => {
            let count = state.doc.scene.cages.vertices.len();
            state.selection.hovered = vertex.filter(|&v| (v as usize) < count);
        }
        _ => {}
    }
}

/// A: everything the current select mode picks (Blender's select all): the shown cage
/// vertices, the shown leaf cages' faces, or every mesh vertex.
fn select_all(state: &mut EditorState) {
    let set = &state.doc.scene.cages;
    match state.select_element() {
        crate::state::SelectElement::CageVertices => {
            let pickable = state.pickable();
            let all = (0..pickable.len() as u32).filter(|&v| pickable[v as usize]);
            state.selection.select(all, SelectMode::Replace);
        }
        crate::state::SelectElement::CageFaces => {
            let hidden = state.view.cage_style(&state.selection, set).hidden;
            let faces: Vec<(usize, usize)> = (set.leaves.iter().enumerate())
                .filter(|(c, _)| !hidden.contains(c))
                .flat_map(|(c, cage)| (0..cage.faces.len()).map(move |f| (c, f)))
                .collect();
            state
                .selection
                .select_faces(faces, SelectMode::Replace, set);
        }
        crate::state::SelectElement::MeshVertices => {
            let count = state.doc.scene.mesh.welded_positions().len();
            let all = 0..count as u32;
            state
                .selection
                .select_mesh_vertices(all, SelectMode::Replace, count);
        }
    }
}
