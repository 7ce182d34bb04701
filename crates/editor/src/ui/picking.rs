//! Picking in the viewport: the cage vertex under the pointer (shown positions: the rest cages
//! in Rig mode, the pose in Pose mode), the one a grab snaps onto, where a vertex is on
//! screen, and in Pose mode the control moving the part of the mesh under the pointer. Used by the viewport's mouse, the selection modes and the keys, none of which
//! import each other for it.

use glam::Vec2;
use starcages_viewport::picking::pick_nearest;

use crate::state::EditorState;

/// Pick radius in points.
const PICK_RADIUS: f32 = 10.0;
/// How near (points) the pointer must come to a cage vertex for a grab to snap onto it.
pub(super) const SNAP_RADIUS: f32 = 16.0;

fn pose_f32(state: &EditorState) -> Vec<glam::Vec3> {
    state
        .shown_positions()
        .iter()
        .map(|p| p.as_vec3())
        .collect()
}

/// The cage vertex under `pointer` (screen points) that a grab snaps onto, among those not
/// being moved: its index and position.
pub fn snap_target(
    state: &EditorState,
    pointer: Vec2,
    moving: &std::collections::BTreeSet<u32>,
) -> Option<(u32, glam::DVec3)> {
    let rect = state.view.viewport;
    let mut pickable = state.pickable();
    for &v in moving {
        if let Some(slot) = pickable.get_mut(v as usize) {
            *slot = false;
        }
    }
    let v = pick_nearest(
        &state.view.camera,
        rect.size,
        &pose_f32(state),
        &pickable,
        rect.local(pointer),
        SNAP_RADIUS,
    )?;
    Some((v as u32, *state.shown_positions().get(v)?))
}

/// The cage vertex under `pointer` (screen points), if any.
pub fn pick(state: &EditorState, pointer: Vec2) -> Option<u32> {
    let rect = state.view.viewport;
    pick_nearest(
        &state.view.camera,
        rect.size,
        &pose_f32(state),
        &state.pickable(),
        rect.local(pointer),
        PICK_RADIUS,
    )
    .map(|i| i as u32)
}

/// The screen position (points) of cage vertex `v` in the current view.
pub fn vertex_on_screen(state: &EditorState, v: u32) -> Option<egui::Pos2> {
    let rect = state.view.viewport;
    let p = state.shown_positions().get(v as usize)?.as_vec3();
    let (pixel, _) = state.view.camera.project(p, rect.size)?;
    let at = rect.min + pixel;
    Some(egui::pos2(at.x, at.y))
}

/// How near (points) the pointer must come to the deformed mesh for a click to pick the control
/// moving it.
const MESH_PICK_RADIUS: f32 = 8.0;

/// Leaf cage vertices that vote for the control of a picked mesh point.
const VOTERS: usize = 6;

/// The mesh vertex nearest `pointer` (screen points) where the mesh is drawn, as the mesh
/// stands in the viewport: deformed in Pose mode, at rest in Rig mode. None off the mesh.
pub fn mesh_point_under(state: &EditorState, pointer: Vec2) -> Option<glam::DVec3> {
    let rect = state.view.viewport;
    let rest: Vec<glam::Vec3>;
    let mesh: &[glam::Vec3] = match state.mode {
        crate::state::EditMode::Pose => state.deformed(),
        crate::state::EditMode::Rig => {
            rest = (state.doc.scene.mesh.welded_positions().iter())
                .map(|p| p.as_vec3())
                .collect();
            &rest
        }
    };
    let picked = pick_nearest(
        &state.view.camera,
        rect.size,
        mesh,
        &[],
        rect.local(pointer),
        MESH_PICK_RADIUS,
    )?;
    Some(mesh.get(picked)?.as_dvec3())
}

/// Pose mode: the internal cage (the auto rig's control) moving the part of the deformed mesh
/// under `pointer`: among the leaf cage vertices nearest the picked mesh point in the current
/// pose, the internal cage owning most of them. Its vertices (sorted), so that R and S turn
/// it about its pivot; None off the mesh or where no internal cage owns that part.
pub fn control_under(state: &EditorState, pointer: Vec2) -> Option<Vec<u32>> {
    let at = mesh_point_under(state, pointer)?;
    let set = &state.doc.scene.cages;
    let mut owner: Vec<Option<usize>> = vec![None; set.vertices.len()];
    for (i, internal) in set.internals.iter().enumerate() {
        for &v in &internal.owns {
            if let Some(slot) = owner.get_mut(v as usize) {
                *slot = Some(i);
            }
        }
    }
    let pose = &state.doc.scene.pose;
    let mut leaf_vertices: Vec<u32> = set
        .leaves
        .iter()
        .flat_map(|l| l.faces.iter().flatten().copied())
        .collect();
    leaf_vertices.sort_unstable();
    leaf_vertices.dedup();
    let distance = |v: u32| {
        pose.get(v as usize)
            .map_or(f64::INFINITY, |p| p.distance(at))
    };
    // The nearest few, unordered among themselves: they only vote.
    let nearest = VOTERS.min(leaf_vertices.len());
    if nearest < leaf_vertices.len() {
        leaf_vertices.select_nth_unstable_by(nearest, |&a, &b| distance(a).total_cmp(&distance(b)));
    }
    let mut votes: std::collections::BTreeMap<usize, usize> = std::collections::BTreeMap::new();
    for v in &leaf_vertices[..nearest] {
        if let Some(Some(cage)) = owner.get(*v as usize) {
            *votes.entry(*cage).or_insert(0) += 1;
        }
    }
    let cage = votes
        .into_iter()
        .max_by_key(|&(c, n)| (n, std::cmp::Reverse(c)))?
        .0;
    set.cage_vertices(&set.internals.get(cage)?.name)
}
