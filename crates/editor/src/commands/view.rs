//! The view: hidden cages, layers, the influence map, mirroring, snapping, pivot, camera, messages.

use super::{CameraChange, Command};
use crate::state::EditorState;

/// Carries out a command of this domain (others are not its to apply, and do nothing here).
pub fn apply_view(state: &mut EditorState, command: Command) {
    match command {
        Command::SetCageHidden(cage, hidden) => {
            state.view.set_hidden(cage, hidden, &state.doc.scene.cages);
        }
        Command::SetLayers(layers) => state.view.layers = layers,
        Command::SetGhosts(ghosts) => state.view.ghosts = ghosts,
        Command::SetInfluence(choice) => state.view.influence = choice,
        Command::SetMirrorX(on) => state.view.mirror_x = on,
        Command::SetSnapToVertices(on) => state.view.snap_to_vertices = on,
        Command::SetPivotPoint(pivot) => state.view.pivot_point = pivot,
        Command::SetLeafVertices(shown) => state.view.leaf_vertices = shown,
        Command::SetCursor(at) if at.is_finite() => state.view.cursor = Some(at),
        Command::Camera(change) => camera(state, change),
        Command::SetViewport(rect) => state.view.viewport = rect,
        Command::Info(text) => state.info(text),
        _ => {}
    }
}

fn camera(state: &mut EditorState, change: CameraChange) {
    let size = state.view.viewport.size;
    let camera = &mut state.view.camera;
    match change {
        CameraChange::Orbit(delta) => camera.orbit(delta),
        CameraChange::Pan(delta) => camera.pan(delta, size.y),
        CameraChange::Zoom {
            steps,
            cursor_in_viewport,
        } => camera.zoom(steps, cursor_in_viewport, size),
        CameraChange::View(view) => camera.set_view(view),
        CameraChange::ToggleOrthographic => camera.orthographic = !camera.orthographic,
        CameraChange::FrameAll => state.frame(false),
        CameraChange::FrameSelection => state.frame(true),
    }
}
