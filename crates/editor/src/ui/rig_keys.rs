//! Rig mode's keys turned into rig operations from what is selected and inspected: E extrudes
//! the selected face, Ctrl+R cuts the inspected cage across its longest side, Shift+A adds a
//! box around the selection (or the mesh), X / Delete deletes the inspected cage. Each gives
//! the operation, or why there is none.

use glam::DVec3;
use starcages_core::scene::RigOp;

use crate::state::{CageId, EditorState};

/// A name `stem_N` no cage has.
fn fresh_name(state: &EditorState, stem: &str) -> String {
    let taken = state.doc.scene.cages.cage_names();
    (1..)
        .map(|i| format!("{stem}_{i}"))
        .find(|n| !taken.contains(&n.as_str()))
        .unwrap_or_default()
}

/// E: the face of a leaf cage whose corners are all selected, pushed out by half its longest
/// edge into a new cage.
pub fn extrude(state: &EditorState) -> Result<RigOp, String> {
    let scene = &state.doc.scene;
    let selected = &state.selection.vertices;
    let inspected = match state.selection.cage() {
        Some(CageId::Leaf(c)) => Some(c),
        _ => None,
    };
    let mut candidates: Vec<usize> = inspected.into_iter().collect();
    candidates.extend((0..scene.cages.leaves.len()).filter(|c| Some(*c) != inspected));
    for c in candidates {
        let cage = &scene.cages.leaves[c];
        for (f, face) in cage.faces.iter().enumerate() {
            if face.iter().all(|v| selected.contains(v)) {
                let longest = (0..face.len())
                    .map(|k| {
                        let (a, b) = (face[k], face[(k + 1) % face.len()]);
                        scene.cages.vertices[a as usize].distance(scene.cages.vertices[b as usize])
                    })
                    .fold(0.0, f64::max);
                return Ok(RigOp::Extrude {
                    cage: cage.name.clone(),
                    face: f,
                    distance: 0.5 * longest,
                    name: fresh_name(state, &cage.name),
                });
            }
        }
    }
    Err("E (extrude): select every corner of one face of a leaf cage first".into())
}

/// Ctrl+R: the inspected leaf cage cut in half across its longest side.
pub fn loop_cut(state: &EditorState) -> Result<RigOp, String> {
    let Some(CageId::Leaf(c)) = state.selection.cage() else {
        return Err(
            "Ctrl+R (loop cut): inspect a leaf cage first (click it in the outliner)".into(),
        );
    };
    let scene = &state.doc.scene;
    let cage = &scene.cages.leaves[c];
    let points: Vec<DVec3> = cage
        .faces
        .iter()
        .flatten()
        .map(|&v| scene.cages.vertices[v as usize])
        .collect();
    let (lo, hi) = starcages_core::cage::bounds_of(&points);
    let extent = hi - lo;
    let axis = (0..3).fold(0, |best, k| if extent[k] > extent[best] { k } else { best });
    Ok(RigOp::Split {
        cage: cage.name.clone(),
        axis,
        t: 0.5,
        name: fresh_name(state, &cage.name),
    })
}

/// Shift+A: a box around the selected vertices (5 % larger), or around the mesh.
pub fn add_box(state: &EditorState) -> Result<RigOp, String> {
    let scene = &state.doc.scene;
    let selected: Vec<DVec3> = state
        .selection
        .vertices
        .iter()
        .filter_map(|&v| scene.cages.vertices.get(v as usize).copied())
        .collect();
    let (lo, hi) = if selected.len() >= 2 {
        starcages_core::cage::bounds_of(&selected)
    } else {
        scene.mesh.bounds()
    };
    let pad = 0.05 * (hi - lo).length();
    let (lo, hi) = (lo - DVec3::splat(pad), hi + DVec3::splat(pad));
    if (hi - lo).min_element() <= 0.0 {
        return Err(
            "Shift+A (add box): the selection is flat; select vertices spanning a volume".into(),
        );
    }
    Ok(RigOp::AddBox {
        name: fresh_name(state, "box"),
        min: lo,
        max: hi,
        kind: starcages_core::coords::CoordinateKind::MeanValue,
    })
}

/// X / Delete: the inspected leaf cage.
pub fn delete(state: &EditorState) -> Result<RigOp, String> {
    match state.selection.cage() {
        Some(CageId::Leaf(c)) => Ok(RigOp::Delete {
            cage: state.doc.scene.cages.leaves[c].name.clone(),
        }),
        _ => Err("X / Delete: inspect the leaf cage to delete (click it in the outliner)".into()),
    }
}
