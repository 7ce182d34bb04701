//! Posing: hand moves (in Rig mode, rest moves), stored poses.

use super::Command;
use crate::state::{EditorError, EditorState};

/// Carries out a command of this domain (others are not its to apply, and do nothing here).
pub fn apply_pose(state: &mut EditorState, command: Command) {
    match command {
        Command::MoveVertices(moves) if state.mode == crate::state::EditMode::Rig => {
            // Rig mode shows and moves the rest cages.
            super::rig::move_rest_vertices(state, &moves, false)
        }
        Command::MoveVertices(moves) => move_vertices(state, &moves),
        Command::StorePose(name) => store_pose(state, name.trim()),
        Command::SwitchPose(name) => {
            let known = name
                .as_ref()
                .is_none_or(|n| state.doc.scene.poses.contains_key(n));
            if known {
                state.edit_scene("switch pose", |scene| match &name {
                    Some(n) => {
                        if let Some(pose) = scene.poses.get(n) {
                            scene.pose = pose.clone();
                            scene.pose_state =
                                scene.pose_states.get(n).cloned().unwrap_or_default();
                        }
                    }
                    None => {
                        scene.pose = scene.cages.vertices.clone();
                        scene.pose_state = Default::default();
                    }
                });
            }
        }
        Command::DeletePose(name)
            if state
                .doc
                .scene
                .animation
                .keys
                .iter()
                .any(|k| k.pose == name) =>
        {
            state.error(EditorError::Pose(format!(
                "pose '{name}' is keyed on the timeline; delete its keys first (X on a key)"
            )));
        }
        Command::DeletePose(name) => {
            state.edit_scene("delete pose", |scene| {
                scene.poses.remove(&name);
                scene.pose_states.remove(&name);
            });
        }
        _ => {}
    }
}

/// A pose move (and the animation key it edits), one undo step like every other edit; the
/// rig's pose moves need no rebind, so not through `edit_scene`.
fn move_vertices(state: &mut EditorState, moves: &[(u32, glam::DVec3)]) {
    let (moved, _) = state.undo_step("move vertices", |state| {
        let moved = state.move_vertices(moves);
        if moved.is_ok() {
            super::animation::key_after_edit(state);
        }
        moved
    });
    if let Err(e) = moved {
        state.error(e);
    }
}

fn store_pose(state: &mut EditorState, name: &str) {
    if name.is_empty() {
        state.error(EditorError::Pose(
            "type a name for the pose first, then Store pose".into(),
        ));
        return;
    }
    state.edit_scene("store pose", |scene| {
        scene.poses.insert(name.to_owned(), scene.pose.clone());
        scene
            .pose_states
            .insert(name.to_owned(), scene.pose_state.clone());
    });
    state.info(format!("stored pose '{name}'"));
}
