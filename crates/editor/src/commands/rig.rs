//! Rig operations on the rest cages: rig ops, rest moves, kinds, h, settings, internal cages, the mode.

use starcages_core::hierarchy::{AutoInternalCage, add_auto_internal_cage, remove_internal_cage};

use super::{Command, Effect};
use crate::state::{CageId, EditorError, EditorState, SelectMode};

/// Carries out a command of this domain (others are not its to apply, and do nothing here).
pub fn apply_rig(state: &mut EditorState, command: Command, effects: &mut Vec<Effect>) {
    match command {
        Command::SetMode(crate::state::EditMode::Pose) if !state.rig_problems.is_empty() => {
            state.error(EditorError::Rig(format!(
                "fix the rig before posing ({} problem(s)): {}",
                state.rig_problems.len(),
                state.rig_problems[0]
            )));
        }
        Command::SetMode(mode) => {
            state.mode = mode;
            state.info(match mode {
                crate::state::EditMode::Rig => {
                    "Rig mode: moving vertices edits the rest cages (poses follow); E extrudes \
                     and I insets the selected faces, Ctrl+R loop-cuts and X deletes the \
                     inspected cage, Shift+A adds a box; Tab: back to Pose mode"
                }
                crate::state::EditMode::Pose => "Pose mode: moving vertices poses the mesh",
            });
        }
        Command::Rig(op) => apply_rig_ops(state, vec![op], effects),
        Command::RigOps(ops) => apply_rig_ops(state, ops, effects),
        Command::MoveRestVertices(moves) => move_rest_vertices(state, &moves, false),
        Command::SetCageKind(cage, kind)
            if cage.kind(&state.doc.scene.cages).is_some_and(|k| k != kind) =>
        {
            state.edit_scene("change coordinates", |scene| match cage {
                CageId::Leaf(i) => scene.cages.leaves[i].kind = kind,
                CageId::Internal(i) => scene.cages.internals[i].kind = kind,
            });
        }
        Command::SetCageH { leaf, h } if leaf < state.doc.scene.cages.leaves.len() => {
            let h = h.map(|h| h.clamp(0.01, 1.0));
            state.edit_scene("change h", |scene| scene.cages.leaves[leaf].h = h);
        }
        Command::SetBorderH { leaf, neighbour, h } => {
            let set = &state.doc.scene.cages;
            let adjacent = set.leaf_index(&neighbour).is_some_and(|other| {
                set.adjacency().iter().any(|a| {
                    (a.first, a.second) == (leaf.min(other), leaf.max(other)) && leaf != other
                })
            });
            if h.is_some() && !adjacent {
                // An override for cages that do not meet would make the rig invalid.
                let name = set.leaves.get(leaf).map_or("?", |c| c.name.as_str());
                state.error(EditorError::Rig(format!(
                    "border h: '{name}' and '{neighbour}' share no face; a border's h applies \
                     where two cages meet"
                )));
            } else if leaf < state.doc.scene.cages.leaves.len() {
                state.edit_scene("change border h", |scene| {
                    let borders = &mut scene.cages.leaves[leaf].border_h;
                    match h {
                        Some(h) => borders.insert(neighbour, h.clamp(0.01, 1.0)),
                        None => borders.remove(&neighbour),
                    };
                });
            }
        }
        Command::SetSettings { label, settings } => {
            state.edit_scene(&label, |scene| scene.settings = settings);
        }
        Command::AddInternalCage(kind) => add_internal_cage(state, kind),
        Command::RemoveInternalCage(index) => {
            let name = CageId::Internal(index)
                .name(&state.doc.scene.cages)
                .unwrap_or_default()
                .to_owned();
            let result = state.edit_scene("remove internal cage", |scene| {
                remove_internal_cage(scene, index)
            });
            match result {
                Ok(()) => state.info(format!("removed internal cage '{name}'")),
                Err(e) => state.error(EditorError::RemoveInternalCage(e)),
            }
        }
        _ => {}
    }
}

/// Moves rest positions (and every pose by the same amount): the N panel's rest fields (`to`
/// is the new rest position), and every move in Rig mode (`to` is where the vertex is dragged
/// in the current pose, `posed`).
pub(super) fn move_rest_vertices(
    state: &mut EditorState,
    moves: &[(u32, glam::DVec3)],
    posed: bool,
) {
    state.edit_scene("move rest positions", |scene| {
        for &(v, to) in moves {
            let Some(rest) = scene.cages.vertices.get_mut(v as usize) else {
                continue;
            };
            let from = if posed {
                scene.pose.get(v as usize).copied().unwrap_or(*rest)
            } else {
                *rest
            };
            let delta = to - from;
            *rest += delta;
            for pose in std::iter::once(&mut scene.pose).chain(scene.poses.values_mut()) {
                if let Some(p) = pose.get_mut(v as usize) {
                    *p += delta;
                }
            }
        }
    });
}

/// At the end of a move in Rig mode: selected vertices that landed on other cage vertices
/// (snapped; to within rounding, 1e-9 of the rig's size) become those vertices, so the cages
/// meeting there share their border (part of the move's undo step). The selection follows the
/// renumbering.
pub(super) fn weld_snapped_vertices(state: &mut EditorState) {
    let moved = state.selection.vertices.clone();
    let rest = &state.doc.scene.cages.vertices;
    let (lo, hi) = starcages_core::cage::bounds_of(rest);
    let tolerance = 1e-9 * (hi - lo).length().max(1.0);
    let landed = moved.iter().any(|&v| {
        rest.get(v as usize).is_some_and(|p| {
            rest.iter()
                .enumerate()
                .any(|(u, q)| q.distance(*p) <= tolerance && !moved.contains(&(u as u32)))
        })
    });
    if !landed {
        return;
    }
    let result = state.edit_scene("weld", |scene| {
        starcages_core::rig::weld_vertices(scene, tolerance, Some(&moved))
    });
    match result {
        Ok(report) => {
            let selected: Vec<u32> = moved
                .iter()
                .filter_map(|&v| report.new_index.get(v as usize).copied())
                .collect();
            state.selection.select(selected, SelectMode::Replace);
            state.info(format!(
                "merged {} vertex(es) onto the vertices they were snapped to: the cages share \
                 that border now",
                report.merged
            ));
        }
        Err(e) => state.error(EditorError::Rig(format!(
            "the snapped vertices stay separate: {e}"
        ))),
    }
}

/// Rig operations as one undo step, applied whole or not at all; after extrusions the new caps
/// are selected (and one cap starts G along its normal), after insets the inner faces.
fn apply_rig_ops(
    state: &mut EditorState,
    ops: Vec<starcages_core::rig::RigOp>,
    effects: &mut Vec<Effect>,
) {
    let label = match ops.as_slice() {
        [op] => format!("rig: {}", rig_op_label(op)),
        _ => format!("rig: {} operations", ops.len()),
    };
    let leaves_before = state.doc.scene.cages.leaves.len();
    let result = state.edit_scene(&label, |scene| {
        let mut edited = scene.clone();
        for op in &ops {
            starcages_core::rig::apply_rig_op(&mut edited, op)?;
        }
        *scene = edited;
        Ok::<(), starcages_core::rig::RigEditError>(())
    });
    match result {
        Ok(()) => {
            state.info(label);
            let extruded = ops
                .iter()
                .filter(|op| matches!(op, starcages_core::rig::RigOp::Extrude { .. }))
                .count();
            let inset: Vec<(usize, usize)> = ops
                .iter()
                .filter_map(|op| match op {
                    starcages_core::rig::RigOp::Inset {
                        cage,
                        face: starcages_core::rig::FaceRef::Index(f),
                        ..
                    } => Some((state.doc.scene.cages.leaf_index(cage)?, *f)),
                    _ => None,
                })
                .collect();
            if !inset.is_empty() {
                // The inner faces stay selected, as Blender's inset leaves them: E goes on.
                let set = &state.doc.scene.cages;
                state
                    .selection
                    .select_faces(inset, SelectMode::Replace, set);
            } else if extruded == 1 && ops.len() == 1 {
                effects.extend(select_extruded_cap(state, leaves_before));
            } else if extruded > 0 {
                let caps: Vec<u32> = state.doc.scene.cages.leaves[leaves_before..]
                    .iter()
                    .filter_map(|cage| cage.faces.get(1))
                    .flatten()
                    .copied()
                    .collect();
                state.selection.select(caps, SelectMode::Replace);
            }
        }
        Err(e) => state.error(EditorError::Rig(e.to_string())),
    }
}

/// After an extrusion: selects the new cap (the new cage's vertices that are new) and asks the
/// UI to start G along the axis most aligned with the cap's offset.
fn select_extruded_cap(state: &mut EditorState, leaves_before: usize) -> Option<Effect> {
    let scene = &state.doc.scene;
    let cage = scene.cages.leaves.get(leaves_before)?;
    // Faces 0 and 1 of an extruded cage are its base (the shared face) and its cap.
    let (base, cap) = (cage.faces.first()?, cage.faces.get(1)?);
    let centre = |face: &[u32]| {
        face.iter()
            .filter_map(|&v| scene.cages.vertices.get(v as usize))
            .sum::<glam::DVec3>()
            / face.len().max(1) as f64
    };
    let offset = centre(cap) - centre(base);
    let cap = cap.clone();
    let axis = (0..3).fold(0, |best, k| {
        if offset[k].abs() > offset[best].abs() {
            k
        } else {
            best
        }
    });
    state.selection.vertices = cap.into_iter().collect();
    state.gesture_continues = Some(state.undo.depth());
    Some(Effect::GrabAlong(axis))
}

/// A short name of a rig operation for the undo history.
fn rig_op_label(op: &starcages_core::rig::RigOp) -> String {
    use starcages_core::rig::RigOp;
    match op {
        RigOp::AddBox { name, .. } => format!("add box '{name}'"),
        RigOp::Extrude { cage, name, .. } => format!("extrude '{cage}' into '{name}'"),
        RigOp::Inset { cage, face, .. } => format!("inset face {face} of '{cage}'"),
        RigOp::Delete { cage } => format!("delete '{cage}'"),
        RigOp::Merge { first, second } => format!("merge '{second}' into '{first}'"),
        RigOp::Split { cage, name, .. } => format!("loop cut '{cage}' ('{name}')"),
        RigOp::Mirror { cage, name } => format!("mirror '{cage}' as '{name}'"),
        RigOp::Fit { cage, .. } => format!("fit '{cage}'"),
        RigOp::Rest { cage, .. } => format!("move rest of '{cage}'"),
        RigOp::Kind { cage, kind } => format!("'{cage}' to {kind}"),
        RigOp::H { cage, h } => format!("h of '{cage}' to {h}"),
        RigOp::Subdivide => "subdivide the leaf cages".into(),
        RigOp::Weld { distance } => format!("weld vertices within {distance}"),
    }
}

fn add_internal_cage(state: &mut EditorState, kind: starcages_core::coords::CoordinateKind) {
    let vertices: Vec<u32> = state.selection.vertices.iter().copied().collect();
    let taken = state.doc.scene.cages.cage_names();
    let name = (1..)
        .map(|i| format!("internal_{i}"))
        .find(|n| !taken.contains(&n.as_str()))
        .unwrap_or_default();
    let options = AutoInternalCage {
        name: name.clone(),
        kind,
        ..AutoInternalCage::default()
    };
    let result = state.edit_scene("add internal cage", |scene| {
        add_auto_internal_cage(scene, &options, &vertices)
    });
    match result {
        Ok(index) => {
            let set = &state.doc.scene.cages;
            state.selection.inspect(Some(CageId::Internal(index)), set);
            state.info(format!(
                "added internal cage '{name}' owning {} vertices",
                vertices.len()
            ));
        }
        Err(e) => state.error(EditorError::AddInternalCage(e)),
    }
}
