//! Storing a named pose of a generated demo from text edits (shared by the demos and the
//! creature, which each build theirs).

use crate::scene::Scene;

/// Stores the pose `name`: the rest pose with `edits` ("CAGE: rotate …", as `--apply` takes
/// them) applied in order through the cage hierarchy, with its hierarchy state when it is not
/// the rest state. The edits are the demo's own and known to apply.
pub(super) fn store_pose(scene: &mut Scene, name: &str, edits: &[&str]) {
    use crate::hierarchy::{CageEdit, Hierarchy};
    let mut hierarchy =
        Hierarchy::bind(scene).unwrap_or_else(|e| unreachable!("{name} hierarchy: {e}"));
    let mut pose = scene.pose.clone();
    for edit in edits {
        let edit: CageEdit = edit.parse().unwrap_or_else(|e| unreachable!("{e}"));
        let moves = edit
            .moves(&scene.cages, &pose)
            .unwrap_or_else(|e| unreachable!("{e}"));
        hierarchy
            .apply(&mut pose, &moves)
            .unwrap_or_else(|e| unreachable!("{name} pose: {e}"));
    }
    scene.poses.insert(name.into(), pose);
    let state = hierarchy.state();
    if !state.is_rest() {
        scene.pose_states.insert(name.into(), state);
    }
}

/// Keys the stored poses `keys` (frame, pose name) with smooth interpolation, at 24 fps, the
/// playback range from the first key to frame `last_frame`.
pub(super) fn set_keys(scene: &mut Scene, last_frame: i64, keys: &[(f64, &str)]) {
    use crate::anim::{Interpolation, Key};
    scene.animation.fps = 24.0;
    scene.animation.frame_start = keys.first().map_or(1, |k| k.0 as i64);
    scene.animation.frame_end = last_frame;
    scene.animation.keys = keys
        .iter()
        .map(|&(frame, pose)| Key {
            frame,
            pose: pose.into(),
            interpolation: Interpolation::Bezier,
            h: Default::default(),
        })
        .collect();
}
