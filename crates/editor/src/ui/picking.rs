//! Picking in the viewport: the cage vertex under the pointer (shown positions: the rest cages
//! in Rig mode, the pose in Pose mode), the one a grab snaps onto, and where a vertex is on
//! screen. Used by the viewport's mouse, the selection modes and the keys, none of which
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
    let mut pickable = state.view.pickable(&state.doc.scene.cages);
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
        &state.view.pickable(&state.doc.scene.cages),
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
