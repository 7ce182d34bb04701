//! Rig mode's keys turned into rig operations from what is selected and inspected: E extrudes
//! the selected face, Shift+A adds a box around the selection (or the mesh), X / Delete
//! deletes the inspected cage. Each gives the operation, or why there is none. (Ctrl+R's loop
//! cut is placed with the mouse first: `loop_cut_tool`.)

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

/// E in face select mode: every selected face pushed out by half its longest edge into a new
/// cage (one undo step); a face shared with a neighbour already cannot be extruded.
pub fn extrude_faces(state: &EditorState) -> Result<Vec<RigOp>, String> {
    let scene = &state.doc.scene;
    let set = &scene.cages;
    let shared = set.faces_by_vertex_set();
    let mut taken: Vec<String> = set.cage_names().iter().map(|n| (*n).to_owned()).collect();
    let mut ops = Vec::new();
    for (c, f) in state.selection.face_indices(set) {
        let cage = &set.leaves[c];
        let Some(face) = cage.faces.get(f) else {
            continue;
        };
        let mut key = face.clone();
        key.sort_unstable();
        if shared.get(&key).is_some_and(|s| s.len() > 1) {
            return Err(format!(
                "E (extrude): face {f} of '{}' is shared with a neighbour already; select free faces",
                cage.name
            ));
        }
        let name = (1..)
            .map(|i| format!("{}_{i}", cage.name))
            .find(|n| !taken.contains(n))
            .unwrap_or_default();
        taken.push(name.clone());
        ops.push(RigOp::Extrude {
            cage: cage.name.clone(),
            face: starcages_core::scene::FaceRef::Index(f),
            distance: 0.5 * longest_edge(scene, face),
            name,
        });
    }
    if ops.is_empty() {
        return Err("E (extrude): select faces first (click them in face select mode)".into());
    }
    Ok(ops)
}

/// The longest edge of a polygon face (rest positions).
fn longest_edge(scene: &starcages_core::scene::Scene, face: &[u32]) -> f64 {
    (0..face.len())
        .map(|k| {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            scene.cages.vertices[a as usize].distance(scene.cages.vertices[b as usize])
        })
        .fold(0.0, f64::max)
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
                return Ok(RigOp::Extrude {
                    cage: cage.name.clone(),
                    face: starcages_core::scene::FaceRef::Index(f),
                    distance: 0.5 * longest_edge(scene, face),
                    name: fresh_name(state, &cage.name),
                });
            }
        }
    }
    Err("E (extrude): select every corner of one face of a leaf cage first".into())
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

/// The inspected leaf cage's index and name, or why there is none.
fn inspected_leaf(state: &EditorState, what: &str) -> Result<(usize, String), String> {
    match state.selection.cage() {
        Some(CageId::Leaf(c)) => Ok((c, state.doc.scene.cages.leaves[c].name.clone())),
        _ => Err(format!(
            "{what}: inspect a leaf cage first (click it in the outliner)"
        )),
    }
}

/// M: the inspected cage and the neighbour whose shared face is selected (or its only one).
pub fn merge(state: &EditorState) -> Result<RigOp, String> {
    let (c, name) = inspected_leaf(state, "M (merge)")?;
    let set = &state.doc.scene.cages;
    let key = |f: &[u32]| {
        let mut k = f.to_vec();
        k.sort_unstable();
        k
    };
    let own: Vec<Vec<u32>> = set.leaves[c].faces.iter().map(|f| key(f)).collect();
    // Each neighbour with the faces it shares with the inspected cage.
    let neighbours: Vec<(usize, Vec<Vec<u32>>)> = (0..set.leaves.len())
        .filter(|&n| n != c)
        .map(|n| {
            let shared = set.leaves[n]
                .faces
                .iter()
                .map(|f| key(f))
                .filter(|k| own.contains(k))
                .collect::<Vec<_>>();
            (n, shared)
        })
        .filter(|(_, shared)| !shared.is_empty())
        .collect();
    let selected = &state.selection.vertices;
    let chosen = neighbours
        .iter()
        .find(|(_, shared)| {
            shared
                .iter()
                .any(|f| f.iter().all(|v| selected.contains(v)))
        })
        .or_else(|| (neighbours.len() == 1).then(|| &neighbours[0]));
    match chosen {
        Some((n, _)) => Ok(RigOp::Merge {
            first: name,
            second: set.leaves[*n].name.clone(),
        }),
        None => Err(format!(
            "M (merge): '{name}' has {} neighbours; select the face it shares with the one to merge",
            neighbours.len()
        )),
    }
}

/// Ctrl+M: a mirrored copy of the inspected cage.
pub fn mirror(state: &EditorState) -> Result<RigOp, String> {
    let (_, name) = inspected_leaf(state, "Ctrl+M (mirror)")?;
    Ok(RigOp::Mirror {
        name: fresh_name(state, &format!("{name}_mirror")),
        cage: name,
    })
}

/// Fit the inspected cage to the mesh with a 2 % margin.
pub fn fit(state: &EditorState) -> Result<RigOp, String> {
    let (_, name) = inspected_leaf(state, "Fit to mesh")?;
    Ok(RigOp::Fit {
        cage: name,
        margin: 0.02,
    })
}
