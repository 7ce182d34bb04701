//! The one place that changes the editor's state: each command records its undo point (one per
//! gesture), changes the document or the view, revalidates what depends on the document, and
//! schedules binds in the background.

use std::path::Path;

use starcages_core::hierarchy::{AutoInternalCage, add_auto_internal_cage, remove_internal_cage};
use starcages_io::{cage_set_obj_text, write_atomic};

use super::{CameraChange, Command, Effect, UnsavedAnswer};
use crate::state::NewMeshOptions;
use crate::state::{CageId, EditorError, EditorState, Pending, SelectMode};

/// Carries out `commands` in order.
pub fn apply_all(state: &mut EditorState, commands: Vec<Command>) -> Vec<Effect> {
    commands
        .into_iter()
        .flat_map(|command| apply(state, command))
        .collect()
}

/// Carries out one command; returns what it asks of the UI (E's grab).
pub fn apply(state: &mut EditorState, command: Command) -> Vec<Effect> {
    let mut effects = Vec::new();
    apply_to(state, command, &mut effects);
    effects
}

/// [`apply`], the effects pushed onto `effects`.
fn apply_to(state: &mut EditorState, command: Command, effects: &mut Vec<Effect>) {
    match command {
        command @ (Command::SetFrame(_)
        | Command::SetPlaying(_)
        | Command::InsertKey
        | Command::DeleteKey(_)
        | Command::MoveKey { .. }
        | Command::SetKeyInterpolation { .. }
        | Command::SetAnimationRange { .. }
        | Command::SetAutoKey(_)
        | Command::ImportCageAnimation(_)) => super::animation::apply_animation(state, command),
        Command::Open(path) => {
            if state.doc.dirty {
                state.pending = Some(Pending::Open(path));
            } else {
                state.start_load(path);
            }
        }
        Command::OpenDemo(name) => {
            if state.doc.dirty {
                state.pending = Some(Pending::OpenDemo(name));
            } else {
                state.start_load_demo(name);
            }
        }
        Command::NewFromMesh(path, options) => {
            if state.doc.dirty {
                state.pending = Some(Pending::NewFromMesh(path, options));
            } else {
                new_from_mesh(state, &path, &options);
            }
        }
        Command::Save => match state.doc.path.clone() {
            Some(path) => {
                save_as(state, &path);
            }
            None => state.error(EditorError::NoFile),
        },
        Command::SaveAs(path) => {
            save_as(state, &path);
        }
        Command::ExportMesh(path) => export_mesh(state, &path),
        Command::ExportCages(path) => {
            let scene = &state.doc.scene;
            let inputs = [
                state.doc.path.clone(),
                match &scene.mesh_source {
                    starcages_core::scene::MeshSource::File(p) => Some(p.clone()),
                    starcages_core::scene::MeshSource::Embedded => None,
                },
            ];
            if inputs
                .iter()
                .flatten()
                .any(|p| starcages_io::is_same_file(&path, p))
            {
                state.error(EditorError::OutputIsInput(path));
                return;
            }
            // In the mesh file's axes, to line up with the mesh in other programs.
            let up = scene.export_up();
            let posed: Vec<glam::DVec3> = scene.pose.iter().map(|&p| up.from_scene(p)).collect();
            let text = cage_set_obj_text(&scene.cages, &posed);
            match write_atomic(&path, text.as_bytes()) {
                Ok(()) => state.info(format!("exported {}", path.display())),
                Err(e) => state.error(EditorError::Export(e)),
            }
        }
        Command::ImportCages(path) => {
            let up = state.doc.scene.export_up();
            match starcages_io::read_cage_set_obj(
                &path,
                starcages_core::coords::CoordinateKind::MeanValue,
            ) {
                Ok(mut set) => {
                    for p in &mut set.vertices {
                        *p = up.to_scene(*p);
                    }
                    let count = set.leaves.len();
                    state.edit_scene("import cages", |scene| {
                        starcages_core::rig::import_leaf_cages(scene, &set)
                    });
                    state.info(format!("imported {count} cage(s) from {}", path.display()));
                }
                Err(e) => state.error(EditorError::Rig(e.to_string())),
            }
        }
        Command::ImportInternalCages(path) => import_internal(state, &path),
        Command::AnswerUnsaved(answer) => answer_unsaved(state, answer),
        Command::RequestClose => {
            if state.doc.dirty {
                state.pending = Some(Pending::Close);
            } else {
                state.close_confirmed = true;
            }
        }
        Command::AutoRig {
            detail,
            controls,
            mirror,
        } => {
            state.start_autorig(starcages_core::generate::AutorigSettings {
                detail,
                controls,
                mirror,
                ..Default::default()
            });
        }
        Command::CancelAutoRig => {
            if state.autorig_job.take().is_some() {
                state.info("auto rig cancelled; the rig is unchanged");
                state.bind_if_unbound();
            }
        }
        Command::CancelLoad => {
            if state.load_job.take().is_some() {
                state.info("opening cancelled; the current scene is unchanged");
            }
        }
        Command::CancelBind => {
            if let Some(job) = &state.bind_job {
                job.cancel();
            }
        }
        Command::CancelBaseline => state.map.cancel_baseline(),
        Command::Undo => {
            if state.gesture.is_some() {
                state.end_gesture(false);
                state.info("cancelled the edit in progress");
                return;
            }
            match state.undo.undo(&mut state.doc.scene) {
                Some(label) => {
                    state.info(format!("undid: {label}"));
                    state.document_changed();
                }
                None => state.info("nothing to undo"),
            }
        }
        Command::Redo => {
            state.end_gesture(true);
            match state.undo.redo(&mut state.doc.scene) {
                Some(label) => {
                    state.info(format!("redid: {label}"));
                    state.document_changed();
                }
                None => state.info("nothing to redo"),
            }
        }
        Command::BeginGesture { id, label } => state.begin_gesture(id, &label),
        Command::EndGesture { keep } => {
            if keep && state.mode == crate::state::EditMode::Rig {
                weld_snapped_vertices(state);
            }
            state.end_gesture(keep);
        }
        Command::MoveVertices(moves) if state.mode == crate::state::EditMode::Rig => {
            // Rig mode shows and moves the rest cages.
            move_rest_vertices(state, &moves, false)
        }
        Command::MoveVertices(moves) => move_vertices(state, &moves),
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
        Command::SelectFaces { faces, mode } => {
            let set = &state.doc.scene.cages;
            state.selection.select_faces(faces, mode, set);
        }
        Command::SetSelectElement(element) => state.view.select_element = element,
        Command::SelectMeshVertices { vertices, mode } => {
            let count = state.doc.scene.mesh.welded_positions().len();
            state.selection.select_mesh_vertices(vertices, mode, count);
        }
        Command::MoveRestVertices(moves) => move_rest_vertices(state, &moves, false),
        Command::SetCageKind(cage, kind) => {
            if cage.kind(&state.doc.scene.cages).is_some_and(|k| k != kind) {
                state.edit_scene("change coordinates", |scene| match cage {
                    CageId::Leaf(i) => scene.cages.leaves[i].kind = kind,
                    CageId::Internal(i) => scene.cages.internals[i].kind = kind,
                });
            }
        }
        Command::SetCageH { leaf, h } => {
            if leaf < state.doc.scene.cages.leaves.len() {
                let h = h.map(|h| h.clamp(0.01, 1.0));
                state.edit_scene("change h", |scene| scene.cages.leaves[leaf].h = h);
            }
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
        Command::Select { vertices, mode } => {
            let count = state.doc.scene.cages.vertices.len();
            let valid = vertices.into_iter().filter(|&v| (v as usize) < count);
            state.selection.select(valid, mode);
            // Faces that lost a corner are no longer selected.
            state.selection.revalidate(&state.doc.scene.cages);
        }
        Command::SelectAll => select_all(state),
        Command::SelectNone => {
            state.selection.select([], SelectMode::Replace);
            state.selection.mesh_vertices.clear();
        }
        Command::InspectCage(cage) => {
            let set = &state.doc.scene.cages;
            let cage = cage.filter(|c| c.exists(set));
            state.selection.inspect(cage, set);
            if let Some(faces) = cage.and_then(|c| c.faces(set)) {
                let vertices = faces.iter().flatten().copied();
                state.selection.select(vertices, SelectMode::Replace);
            }
        }
        Command::Hover(vertex) => {
            let count = state.doc.scene.cages.vertices.len();
            state.selection.hovered = vertex.filter(|&v| (v as usize) < count);
        }
        Command::SetCageHidden(cage, hidden) => {
            state.view.set_hidden(cage, hidden, &state.doc.scene.cages);
        }
        Command::SetLayers(layers) => state.view.layers = layers,
        Command::SetInfluence(choice) => state.view.influence = choice,
        Command::SetMirrorX(on) => state.view.mirror_x = on,
        Command::SetSnapToVertices(on) => state.view.snap_to_vertices = on,
        Command::SetPivotPoint(pivot) => state.view.pivot_point = pivot,
        Command::Camera(change) => camera(state, change),
        Command::SetViewport(rect) => state.view.viewport = rect,
        Command::Info(text) => state.info(text),
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

/// Moves rest positions (and every pose by the same amount): the N panel's rest fields (`to`
/// is the new rest position), and every move in Rig mode (`to` is where the vertex is dragged
/// in the current pose, `posed`).
fn move_rest_vertices(state: &mut EditorState, moves: &[(u32, glam::DVec3)], posed: bool) {
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

/// A: everything the current select mode picks (Blender's select all): the shown cage
/// vertices, the shown leaf cages' faces, or every mesh vertex.
fn select_all(state: &mut EditorState) {
    let set = &state.doc.scene.cages;
    match state.select_element() {
        crate::state::SelectElement::CageVertices => {
            let pickable = state.view.pickable(set);
            let all = (0..pickable.len() as u32).filter(|&v| pickable[v as usize]);
            state.selection.select(all, SelectMode::Replace);
        }
        crate::state::SelectElement::CageFaces => {
            let hidden = state.view.cage_style(&state.selection, set).hidden;
            let faces: Vec<(usize, usize)> = (set.leaves.iter().enumerate())
                .filter(|(c, _)| !hidden.contains(c))
                .flat_map(|(c, cage)| (0..cage.faces.len()).map(move |f| (c, f)))
                .collect();
            state
                .selection
                .select_faces(faces, SelectMode::Replace, set);
        }
        crate::state::SelectElement::MeshVertices => {
            let count = state.doc.scene.mesh.welded_positions().len();
            let all = 0..count as u32;
            state
                .selection
                .select_mesh_vertices(all, SelectMode::Replace, count);
        }
    }
}

/// At the end of a move in Rig mode: selected vertices that landed on other cage vertices
/// (snapped; to within rounding, 1e-9 of the rig's size) become those vertices, so the cages
/// meeting there share their border (part of the move's undo step). The selection follows the
/// renumbering.
fn weld_snapped_vertices(state: &mut EditorState) {
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

/// File ▸ Import internal cages: every cage of the OBJ becomes an internal cage driving the
/// free cage vertices inside it (one undo step, all or none).
fn import_internal(state: &mut EditorState, path: &Path) {
    let up = state.doc.scene.export_up();
    let kind = starcages_core::coords::CoordinateKind::MeanValue;
    let mut set = match starcages_io::read_cage_set_obj(path, kind) {
        Ok(set) => set,
        Err(e) => return state.error(EditorError::Rig(e.to_string())),
    };
    for p in &mut set.vertices {
        *p = up.to_scene(*p);
    }
    let result = state.edit_scene("import internal cages", |scene| {
        starcages_core::hierarchy::import_internal_cages(scene, &set, kind)
    });
    match result {
        Ok(added) => {
            let set = &state.doc.scene.cages;
            let named: Vec<String> = added
                .iter()
                .filter_map(|&i| set.internals.get(i))
                .map(|c| format!("'{}' ({} vertices)", c.name, c.owns.len()))
                .collect();
            if let Some(&last) = added.last() {
                state.selection.inspect(Some(CageId::Internal(last)), set);
            }
            state.info(format!(
                "imported internal cage(s) {} from {}",
                named.join(", "),
                path.display()
            ));
        }
        Err(e) => state.error(EditorError::AddInternalCage(e)),
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

fn new_from_mesh(state: &mut EditorState, path: &Path, options: &NewMeshOptions) {
    state.start_new_from_mesh(path.to_path_buf(), *options);
}

fn save_as(state: &mut EditorState, path: &Path) -> bool {
    match state.doc.save_as(path) {
        Ok(()) => {
            state.remember(path);
            state.info(format!("saved {}", path.display()));
            true
        }
        Err(e) => {
            state.error(e);
            false
        }
    }
}

fn export_mesh(state: &mut EditorState, path: &Path) {
    let Some(rig) = &state.rig else {
        state.error(EditorError::NotBound);
        return;
    };
    if rig.preview {
        // A preview (mean value join cages) is for interaction, not for files. Its refinement
        // may have been cancelled: start it again.
        state.refine_preview();
        state.error(EditorError::PreviewOnly);
        return;
    }
    if let starcages_core::scene::MeshSource::File(source) = &state.doc.scene.mesh_source
        && starcages_io::is_same_file(path, source)
    {
        state.error(EditorError::OutputIsInput(path.to_path_buf()));
        return;
    }
    let welded: Vec<glam::DVec3> = rig.deformed.iter().map(|p| p.as_dvec3()).collect();
    // In the mesh file's axes, an OBJ as a copy of its source (same vertex list and order).
    match starcages_io::write_deformed_mesh(path, &state.doc.scene, &welded) {
        Ok(()) => state.info(format!("exported {}", path.display())),
        Err(e) => state.error(EditorError::Export(e)),
    }
}

fn answer_unsaved(state: &mut EditorState, answer: UnsavedAnswer) {
    let Some(pending) = state.pending.take() else {
        return;
    };
    match answer {
        UnsavedAnswer::Cancel => return,
        UnsavedAnswer::Discard => {}
        UnsavedAnswer::Save(path) => {
            let Some(path) = path.or_else(|| state.doc.path.clone()) else {
                state.error(EditorError::NoFile);
                return;
            };
            if !save_as(state, &path) {
                return; // not saved: keep the work
            }
        }
    }
    match pending {
        Pending::Open(path) => state.start_load(path),
        Pending::OpenDemo(name) => state.start_load_demo(name),
        Pending::NewFromMesh(path, options) => new_from_mesh(state, &path, &options),
        Pending::Close => state.close_confirmed = true,
    }
}
