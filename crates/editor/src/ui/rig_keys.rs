//! Rig mode's keys turned into rig operations from what is selected and inspected: E extrudes
//! the selected face, Shift+A adds a box (`BoxPlacement`: around the selected mesh or cage
//! vertices, the mesh, or in the part under the pointer), X / Delete
//! deletes the inspected cage. Each gives the operation, or why there is none. (Ctrl+R's loop
//! cut and I's inset are sized with the mouse first: `loop_cut_tool`, `inset_tool`.)

use glam::DVec3;
use starcages_core::rig::RigOp;

use crate::state::{CageId, EditorState};

/// A name `stem_N` no cage has.
fn fresh_name(state: &EditorState, stem: &str) -> String {
    let taken = state.doc.scene.cages.cage_names();
    (1..)
        .map(|i| format!("{stem}_{i}"))
        .find(|n| !taken.contains(&n.as_str()))
        .unwrap_or_default()
}

/// A selected leaf-cage face: its cage, its index there and its corners.
pub(super) type SelectedFace<'a> = (usize, usize, &'a [u32]);

/// The selected leaf-cage faces, or why `key` cannot take them: none selected, or one shared
/// with a neighbour (only the rig's outer faces can grow).
pub(super) fn free_selected_faces<'a>(
    state: &'a EditorState,
    key: &str,
) -> Result<Vec<SelectedFace<'a>>, String> {
    let set = &state.doc.scene.cages;
    let shared = set.faces_by_vertex_set();
    let mut faces = Vec::new();
    for (c, f) in state.selection.face_indices(set) {
        let cage = &set.leaves[c];
        let Some(face) = cage.faces.get(f) else {
            continue;
        };
        let mut corners = face.clone();
        corners.sort_unstable();
        if shared.get(&corners).is_some_and(|s| s.len() > 1) {
            return Err(format!(
                "{key}: face {f} of '{}' is shared with a neighbour already; select free faces",
                cage.name
            ));
        }
        faces.push((c, f, face.as_slice()));
    }
    if faces.is_empty() {
        return Err(format!(
            "{key}: select faces first (click them in face select mode)"
        ));
    }
    Ok(faces)
}

/// E in face select mode: every selected face pushed out by half its longest edge into a new
/// cage (one undo step); a face shared with a neighbour already cannot be extruded.
pub fn extrude_faces(state: &EditorState) -> Result<Vec<RigOp>, String> {
    let scene = &state.doc.scene;
    let set = &scene.cages;
    let mut taken: Vec<String> = set.cage_names().iter().map(|n| (*n).to_owned()).collect();
    let mut ops = Vec::new();
    for (c, f, face) in free_selected_faces(state, "E (extrude)")? {
        let cage = &set.leaves[c];
        let name = (1..)
            .map(|i| format!("{}_{i}", cage.name))
            .find(|n| !taken.contains(n))
            .unwrap_or_default();
        taken.push(name.clone());
        ops.push(RigOp::Extrude {
            cage: cage.name.clone(),
            face: starcages_core::rig::FaceRef::Index(f),
            distance: 0.5 * longest_edge(scene, face),
            name,
        });
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
                    face: starcages_core::rig::FaceRef::Index(f),
                    distance: 0.5 * longest_edge(scene, face),
                    name: fresh_name(state, &cage.name),
                });
            }
        }
    }
    Err("E (extrude): select every corner of one face of a leaf cage first".into())
}

/// Where Shift+A's box goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BoxPlacement {
    /// Around the selected mesh vertices (mesh select mode), 5 % of their size larger.
    AroundMeshSelection,
    /// Around the selected cage vertices, 5 % larger.
    AroundCageSelection,
    /// Around the whole mesh, 5 % larger.
    AroundMesh,
    /// A cube in the part of the mesh under this screen point (points): centred between where
    /// the ray through it enters the mesh and where it leaves, about as wide as that; where the
    /// ray misses the mesh, a cube of a tenth of its size on the ray, level with its centre.
    At(glam::Vec2),
}

impl BoxPlacement {
    /// The add menu's label.
    pub fn label(self) -> &'static str {
        match self {
            Self::AroundMeshSelection => "Box around the selected mesh vertices",
            Self::AroundCageSelection => "Box around the selected cage vertices",
            Self::AroundMesh => "Box around the whole mesh",
            Self::At(_) => "Box at the pointer",
        }
    }
}

/// Shift+A: a box cage placed as `placement` says.
pub fn add_box(state: &EditorState, placement: BoxPlacement) -> Result<RigOp, String> {
    let scene = &state.doc.scene;
    let mesh = scene.mesh.welded_positions();
    let padded = |points: &[DVec3], what: &str| -> Result<(DVec3, DVec3), String> {
        if points.len() < 2 {
            return Err(format!(
                "Shift+A (add box): select {what} first (at least two, spanning a volume)"
            ));
        }
        let (lo, hi) = starcages_core::cage::bounds_of(points);
        let pad = 0.05 * (hi - lo).length();
        Ok((lo - DVec3::splat(pad), hi + DVec3::splat(pad)))
    };
    let (lo, hi) = match placement {
        BoxPlacement::AroundMeshSelection => {
            let points: Vec<DVec3> = (state.selection.mesh_vertices.iter())
                .filter_map(|&v| mesh.get(v as usize).copied())
                .collect();
            padded(
                &points,
                "mesh vertices (Mesh select, then drag a rectangle or Ctrl+drag a lasso)",
            )?
        }
        BoxPlacement::AroundCageSelection => {
            let points: Vec<DVec3> = (state.selection.vertices.iter())
                .filter_map(|&v| scene.cages.vertices.get(v as usize).copied())
                .collect();
            padded(&points, "cage vertices")?
        }
        BoxPlacement::AroundMesh => padded(mesh, "a mesh with vertices")?,
        BoxPlacement::At(pointer) => box_at(state, pointer),
    };
    if (hi - lo).min_element() <= 0.0 || !(hi - lo).is_finite() {
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

/// The cube of [`BoxPlacement::At`]: (min, max).
fn box_at(state: &EditorState, pointer: glam::Vec2) -> (DVec3, DVec3) {
    let scene = &state.doc.scene;
    let rect = state.view.viewport;
    let (origin, direction) = state.view.camera.ray(rect.local(pointer), rect.size);
    let positions = scene.mesh.welded_positions_f32();
    let hits = starcages_viewport::picking::ray_mesh_hits(
        origin,
        direction,
        &positions,
        scene.mesh.welded_triangles(),
    );
    let (lo, hi) = scene.mesh.bounds();
    let diagonal = (hi - lo).length().max(1e-9);
    let on_ray = |t: f32| (origin + direction * t).as_dvec3();
    let (centre, edge) = match hits.as_slice() {
        [enter, leave, ..] => {
            let depth = f64::from(leave - enter);
            (
                0.5 * (on_ray(*enter) + on_ray(*leave)),
                (1.2 * depth).clamp(0.02 * diagonal, 0.5 * diagonal),
            )
        }
        [surface] => (on_ray(*surface), 0.1 * diagonal),
        [] => {
            // Level with the mesh's centre: the point of the ray nearest it.
            let centre = (0.5 * (lo + hi)).as_vec3();
            let t = (centre - origin).dot(direction).max(0.0);
            (on_ray(t), 0.1 * diagonal)
        }
    };
    let half = DVec3::splat(0.5 * edge);
    (centre - half, centre + half)
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
