//! Storing a named pose of a generated demo from text edits (shared by the demos and the
//! creature, which each build theirs).

use super::Scene;

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
