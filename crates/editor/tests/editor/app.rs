//! The real editor through egui_kittest: picking and dragging a cage vertex, the coordinates
//! combo, the h slider, G with an axis lock, undo and redo, save and reopen, a broken file,
//! background binds with Cancel, internal cages, X mirroring, the unsaved-changes prompt, and a
//! snapshot of the main window.

use egui::accesskit::Role;
use egui_kittest::SnapshotOptions;
use egui_kittest::kittest::Queryable as _;
use glam::{DVec3, Vec3};
use starcages_core::coords::CoordinateKind;
use starcages_editor::state::InfluenceChoice;
use starcages_editor::ui::vertex_on_screen;
use starcages_editor::{CageId, Command, Document};

use crate::common::{cage, harness, leaf, press, press_with, scratch, settle, undo};

#[test]
fn dragging_a_picked_vertex_moves_the_mesh_near_its_cage_only_and_undoes_in_one_step() {
    let mut harness = harness();
    let app = harness.state();
    // A corner of the lower front-left head cage: belongs to that cage only.
    let v = app.state.doc.scene.cages.leaves[leaf(app, "head_0_0_0")].faces[0][0];
    let before_pose = app.state.doc.scene.pose.clone();
    let before_mesh: Vec<Vec3> = app.state.deformed().to_vec();
    let start = vertex_on_screen(&app.state, v).unwrap();
    harness.hover_at(start);
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.selection.hovered,
        Some(v),
        "hover highlight"
    );
    harness.drag_at(start);
    harness.run_steps(1);
    for step in 1..=5 {
        harness.hover_at(start + egui::vec2(6.0 * step as f32, -4.0 * step as f32));
        harness.run_steps(1);
    }
    harness.drop_at(start + egui::vec2(30.0, -20.0));
    harness.run_steps(2);
    let state = &harness.state().state;
    assert!(state.selection.vertices.contains(&v));
    assert!(state.gesture.is_none(), "the drag's gesture ended");
    let moved = state.doc.scene.pose[v as usize].distance(before_pose[v as usize]);
    assert!(moved > 0.05, "the vertex moved {moved}");
    let others_still = (0..before_pose.len())
        .filter(|&u| u != v as usize)
        .all(|u| state.doc.scene.pose[u] == before_pose[u]);
    assert!(
        others_still,
        "only the dragged vertex moved (it has no children)"
    );
    // The mesh moved near the cage, and not at all far from it (the ears).
    let after_mesh = state.deformed();
    let changed = |i: usize| after_mesh[i] != before_mesh[i];
    assert!((0..after_mesh.len()).any(changed));
    let ear = leaf(harness.state(), "ear_right") as u32;
    let rig = state.rig.as_ref().unwrap();
    let ear_vertices: Vec<usize> = (0..after_mesh.len())
        .filter(|&i| rig.binding.cage_of[i] == ear)
        .collect();
    assert!(!ear_vertices.is_empty());
    assert!(
        ear_vertices.iter().all(|&i| !changed(i)),
        "the far ear moved"
    );
    // One undo step for the whole drag, and redo brings it back.
    assert_eq!(state.undo.undo_label(), Some("move vertices"));
    undo(&mut harness);
    assert_eq!(harness.state().state.doc.scene.pose, before_pose);
    assert_eq!(harness.state().state.undo.undo_label(), None);
    let restored = harness.state().state.deformed().to_vec();
    let worst = restored
        .iter()
        .zip(&before_mesh)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    assert!(worst < 1e-5, "{worst}");
    press_with(
        &mut harness,
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    let state = &harness.state().state;
    assert!(state.doc.scene.pose[v as usize].distance(before_pose[v as usize]) > 0.05);
    assert!(state.doc.dirty);
    assert!(state.doc.title().starts_with('●'));
}

#[test]
fn the_coordinates_combo_changes_a_cage_kind_and_undo_restores_it() {
    let mut harness = harness();
    harness.get_by_label("ear_left (mvc)").click();
    harness.run_steps(2);
    let ear = cage(harness.state(), "ear_left");
    assert_eq!(harness.state().state.selection.cage(), Some(ear));
    harness.get_by_label("Coordinates").click();
    harness.run_steps(2);
    harness.get_by_label("Green (GC)").click();
    harness.run_steps(2);
    settle(&mut harness);
    let kind = |h: &egui_kittest::Harness<'static, starcages_editor::EditorApp>| {
        ear.kind(&h.state().state.doc.scene.cages).unwrap()
    };
    assert_eq!(kind(&harness), CoordinateKind::Green);
    assert!(
        harness
            .state()
            .state
            .rig
            .as_ref()
            .unwrap()
            .is_current_for(&harness.state().state.doc.scene)
    );
    undo(&mut harness);
    settle(&mut harness);
    assert_eq!(kind(&harness), CoordinateKind::MeanValue);
    press_with(&mut harness, egui::Modifiers::COMMAND, egui::Key::Y);
    assert_eq!(kind(&harness), CoordinateKind::Green);
}

#[test]
fn the_h_slider_changes_the_influence_map() {
    let mut harness = harness();
    harness.get_by_label("head_0_0_0 (mvc)").click();
    harness.run_steps(2);
    harness
        .state_mut()
        .run(Command::SetInfluence(InfluenceChoice::SelectedCage));
    harness.run_steps(2);
    let before = harness.state().state.map.values().unwrap().values.clone();
    harness
        .get_by_role_and_label(Role::Slider, "h")
        .set_value_accesskit(0.15);
    harness.run_steps(2);
    settle(&mut harness);
    let head = leaf(harness.state(), "head_0_0_0");
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.leaves[head].h, Some(0.15));
    let after = state.map.values().unwrap().values.clone();
    let differing = before
        .iter()
        .zip(&after)
        .filter(|(a, b)| (*a - *b).abs() > 1e-3)
        .count();
    assert!(
        differing > 10,
        "the b map did not change ({differing} vertices)"
    );
    undo(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves[head].h, None);
    press_with(&mut harness, egui::Modifiers::COMMAND, egui::Key::Y);
    assert_eq!(
        harness.state().state.doc.scene.cages.leaves[head].h,
        Some(0.15)
    );
}

#[test]
fn grab_with_an_axis_lock_and_a_typed_distance_then_cancel_a_rotation() {
    let mut harness = harness();
    let app = harness.state_mut();
    let v = app.state.doc.scene.cages.leaves[leaf(app, "head_1_0_0")].faces[0][0];
    app.run(Command::Select {
        vertices: vec![v],
        mode: starcages_editor::state::SelectMode::Replace,
    });
    let start = app.state.doc.scene.pose[v as usize];
    let centre = app.state.view.viewport.center();
    let centre = egui::pos2(centre.x, centre.y);
    harness.hover_at(centre);
    harness.key_press(egui::Key::G);
    harness.run_steps(1);
    assert!(harness.state().ui.tool.is_some());
    assert!(harness.state().state.gesture.is_some());
    for text in ["z", "0", ".", "2", "5"] {
        harness.event(egui::Event::Text(text.into()));
        harness.run_steps(1);
    }
    // The header over the viewport and the status bar's hint.
    harness.get_by_label_contains("Grab along Z: 0.250  [typed 0.25]");
    harness.get_by_label_contains("Grab along Z: 0.25 — X/Y/Z lock");
    press(&mut harness, egui::Key::Enter);
    let state = &harness.state().state;
    assert!(harness.state().ui.tool.is_none() && state.gesture.is_none());
    let moved = state.doc.scene.pose[v as usize] - start;
    assert!(
        (moved - DVec3::new(0.0, 0.0, 0.25)).length() < 1e-12,
        "{moved}"
    );
    // R on everything, move the mouse, Esc: nothing changes and nothing is recorded.
    let after_grab = state.doc.scene.pose.clone();
    harness.key_press(egui::Key::A);
    harness.run_steps(1);
    harness.key_press(egui::Key::R);
    harness.run_steps(1);
    harness.hover_at(centre + egui::vec2(80.0, 40.0));
    harness.run_steps(2);
    assert_ne!(
        harness.state().state.doc.scene.pose,
        after_grab,
        "R follows the mouse"
    );
    press(&mut harness, egui::Key::Escape);
    assert_eq!(harness.state().state.doc.scene.pose, after_grab);
    assert_eq!(harness.state().state.undo.undo_label(), Some("grab"));
}

#[test]
fn save_and_reopen_gives_the_same_scene_and_a_broken_file_leaves_the_app_usable() {
    let mut harness = harness();
    let dir = scratch("save");
    let path = dir.join("critter.json");
    {
        let app = harness.state_mut();
        let to = app.state.doc.scene.pose[0] + DVec3::new(0.1, 0.0, 0.0);
        app.run(Command::MoveVertices(vec![(0, to)]));
        assert!(app.state.doc.dirty);
        app.run(Command::SaveAs(path.clone()));
        assert!(!app.state.doc.dirty, "{:?}", app.state.message);
    }
    let reopened = Document::open(&path, &starcages_core::BindControl::default()).unwrap();
    assert_eq!(reopened.scene, harness.state().state.doc.scene);
    // And through the app: open (on a worker), the same scene, clean, bound again.
    let saved = harness.state().state.doc.scene.clone();
    harness.state_mut().run(Command::Open(path.clone()));
    assert!(
        harness.state().state.load_job.is_some(),
        "opening runs in the background"
    );
    settle(&mut harness);
    let state = &harness.state().state;
    assert_eq!(state.doc.scene, saved);
    assert!(!state.doc.dirty);
    assert!(state.rig.is_some());
    assert_eq!(
        state.recent.first(),
        Some(&std::path::absolute(&path).unwrap())
    );
    // A broken file: an error in the status bar, the scene untouched.
    let broken = dir.join("broken.json");
    std::fs::write(
        &broken,
        "{ \"format\": \"starcages-scene\", \"version\": 1, ",
    )
    .unwrap();
    let document_before = state.document_id;
    harness.state_mut().run(Command::Open(broken));
    settle(&mut harness);
    let state = &harness.state().state;
    let message = state.message.clone().unwrap();
    assert!(
        message.error && message.text.contains("broken.json"),
        "{}",
        message.text
    );
    assert!(message.text.contains("unchanged"), "{}", message.text);
    assert_eq!(state.doc.scene, saved);
    assert_eq!(state.document_id, document_before);
    harness.get_by_label_contains("broken.json");
    // Still usable: the selection works.
    press(&mut harness, egui::Key::A);
    assert!(!harness.state().state.selection.vertices.is_empty());
}

#[test]
fn main_window_snapshot() {
    let mut harness = harness();
    harness
        .state_mut()
        .run(Command::SetInfluence(InfluenceChoice::AllCages));
    harness.run_steps(3);
    let image = harness.render().unwrap();
    // The viewport shows both ends of the b map: red and blue pixels.
    let red = image
        .pixels()
        .filter(|p| p.0[0] > 150 && p.0[2] < 90 && p.0[1] < 120)
        .count();
    let blue = image
        .pixels()
        .filter(|p| p.0[2] > 150 && p.0[0] < 90)
        .count();
    assert!(red > 200 && blue > 200, "red {red}, blue {blue}");
    harness.snapshot_options(
        "main_window",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
}

#[test]
fn a_bind_runs_in_the_background_the_ui_keeps_drawing_and_cancel_keeps_the_previous_binding() {
    let mut harness = harness();
    let old = std::sync::Arc::clone(&harness.state().state.rig.as_ref().unwrap().binding);
    // Harmonic join cages on a fine HC grid are slow enough to cancel. A quick preview with
    // mean value join cages comes first and is installed; the refinement is what runs long.
    let mut settings = harness.state().state.doc.scene.settings;
    settings.join_coordinates = starcages_core::scene::JoinPolicy::Auto;
    settings.harmonic.resolution = 128;
    harness.state_mut().run(Command::SetSettings {
        label: "HC grid".into(),
        settings,
    });
    assert!(harness.state().state.bind_job.is_some());
    // Frames keep coming while it binds, and show its progress.
    let mut frames = 0;
    while !harness
        .state()
        .state
        .rig
        .as_ref()
        .is_some_and(|rig| rig.preview)
    {
        harness.step();
        frames += 1;
        std::thread::sleep(std::time::Duration::from_millis(5));
        assert!(frames < 2000, "the preview never arrived");
    }
    for _ in 0..3 {
        harness.step();
    }
    harness.get_by_label("refining: harmonic join cages");
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    assert!(state.bind_job.is_none());
    let message = state.message.clone().unwrap();
    assert!(
        message.error && message.text.contains("cancelled"),
        "{}",
        message.text
    );
    // The binding in use when Cancel was pressed stays: the preview, still marked as one (so
    // export waits for a full bind), not the binding before the change.
    let rig = state.rig.as_ref().unwrap();
    assert!(rig.preview);
    assert!(!std::sync::Arc::ptr_eq(&old, &rig.binding));
    // Export says why it cannot write the preview and starts the refinement again.
    let path = scratch("cancelled-refinement").join("deformed.obj");
    harness.state_mut().run(Command::ExportMesh(path.clone()));
    let state = &harness.state().state;
    assert!(!path.exists());
    assert!(
        state.bind_job.is_some(),
        "the refinement did not start again"
    );
    assert!(
        state
            .message
            .as_ref()
            .unwrap()
            .text
            .contains("quick preview"),
        "{:?}",
        state.message
    );
}

#[test]
fn adding_and_removing_internal_cages_are_undoable_hierarchy_edits() {
    let mut harness = harness();
    let app = harness.state_mut();
    let ears = app.state.doc.scene.cages.cage_vertices("ear_left").unwrap();
    // The ear's lower vertices belong to the head cage; its top ones to the ears cage.
    app.run(Command::Select {
        vertices: ears,
        mode: starcages_editor::state::SelectMode::Replace,
    });
    app.run(Command::AddInternalCage(CoordinateKind::MeanValue));
    let message = app.state.message.clone().unwrap();
    assert!(
        message.error && message.text.contains("already owned"),
        "{}",
        message.text
    );
    assert_eq!(app.state.doc.scene.cages.internals.len(), 2);
    // Unowned vertices: a new top-level cage over the head cage's own vertices.
    let head = app.state.doc.scene.cages.cage_vertices("head").unwrap();
    app.run(Command::Select {
        vertices: head.clone(),
        mode: starcages_editor::state::SelectMode::Replace,
    });
    app.run(Command::AddInternalCage(CoordinateKind::Harmonic));
    settle(&mut harness);
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.internals.len(), 3);
    assert_eq!(state.selection.cage(), Some(CageId::Internal(2)));
    assert!(
        state
            .rig
            .as_ref()
            .unwrap()
            .hierarchy
            .parent_of(head[0])
            .is_some()
    );
    // Remove it from the inspector, then undo the removal and the addition.
    harness.get_by_label("Remove internal cage").click();
    harness.run_steps(2);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.internals.len(), 2);
    assert_eq!(harness.state().state.selection.cage(), None);
    harness.state_mut().run(Command::Undo);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.internals.len(), 3);
    harness.state_mut().run(Command::Undo);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.internals.len(), 2);
}

#[test]
fn an_internal_cage_kind_change_rebinds_the_hierarchy_only() {
    let mut harness = harness();
    let old = std::sync::Arc::clone(&harness.state().state.rig.as_ref().unwrap().binding);
    let ears = cage(harness.state(), "ears");
    harness
        .state_mut()
        .run(Command::SetCageKind(ears, CoordinateKind::MeanValue));
    settle(&mut harness);
    let state = &harness.state().state;
    assert_eq!(
        ears.kind(&state.doc.scene.cages),
        Some(CoordinateKind::MeanValue)
    );
    assert!(
        std::sync::Arc::ptr_eq(&old, &state.rig.as_ref().unwrap().binding),
        "the mesh was rebound"
    );
}

#[test]
fn x_mirror_editing_moves_the_partner_vertex() {
    let mut harness = harness();
    let app = harness.state_mut();
    app.run(Command::SetMirrorX(true));
    let rest = app.state.doc.scene.cages.vertices.clone();
    let v = (0..rest.len()).find(|&i| rest[i].x < -1.0).unwrap() as u32;
    let image = |p: DVec3| DVec3::new(-p.x, p.y, p.z);
    let partner = (0..rest.len())
        .find(|&i| (rest[i] - image(rest[v as usize])).length() < 1e-9)
        .unwrap();
    let target = rest[v as usize] + DVec3::new(-0.2, 0.1, 0.3);
    app.run(Command::MoveVertices(vec![(v, target)]));
    let moved = app.state.doc.scene.pose[partner];
    assert!((moved - image(target)).length() < 1e-12, "{moved}");
}

#[test]
fn opening_over_unsaved_work_asks_first() {
    let mut harness = harness();
    let path = scratch("prompt").join("saved.json");
    harness.state_mut().run(Command::SaveAs(path.clone()));
    {
        let app = harness.state_mut();
        let to = app.state.doc.scene.pose[0] + DVec3::Z * 0.2;
        app.run(Command::MoveVertices(vec![(0, to)]));
        assert!(app.state.doc.dirty);
        app.run(Command::Open(path.clone()));
        assert!(
            app.state.load_job.is_none(),
            "nothing opens before the answer"
        );
    }
    harness.run_steps(2);
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    assert!(harness.state().state.pending.is_none() && harness.state().state.doc.dirty);
    harness.state_mut().run(Command::Open(path.clone()));
    harness.run_steps(2);
    harness.get_by_label("Don't save").click();
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    assert!(!state.doc.dirty);
    assert_eq!(state.doc.path.as_deref(), Some(path.as_path()));
}

/// The window's close button goes through the same command as every other action: a saved
/// document closes at once, unsaved work asks first and the window stays until the answer.
#[test]
fn closing_the_window_asks_over_unsaved_work_and_closes_a_saved_one() {
    let close = |harness: &mut egui_kittest::Harness<'static, starcages_editor::EditorApp>| {
        harness
            .input_mut()
            .viewports
            .entry(egui::ViewportId::ROOT)
            .or_default()
            .events
            .push(egui::ViewportEvent::Close);
        harness.run_steps(1);
    };
    let mut harness = harness();
    close(&mut harness);
    assert!(
        harness.state().state.close_confirmed,
        "a saved document closes"
    );
    let mut harness = self::harness();
    {
        let app = harness.state_mut();
        let to = app.state.doc.scene.pose[0] + DVec3::Z * 0.2;
        app.run(Command::MoveVertices(vec![(0, to)]));
    }
    close(&mut harness);
    harness.run_steps(2);
    let state = &harness.state().state;
    assert!(
        !state.close_confirmed && state.pending.is_some(),
        "unsaved work asks"
    );
    harness.get_by_label("Don't save");
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    let state = &harness.state().state;
    assert!(!state.close_confirmed && state.pending.is_none() && state.doc.dirty);
}

#[test]
fn menus_show_the_table_labels_and_shortcuts() {
    let mut harness = harness();
    harness.get_by_label("Edit").click();
    harness.run_steps(2);
    // "Undo" is disabled with nothing to undo but present, with its shortcut text.
    harness.get_by_label_contains("Undo");
    harness.get_by_label_contains("Ctrl+Z");
    harness.key_press(egui::Key::Escape);
    harness.run_steps(1);
    harness.get_by_role_and_label(Role::Button, "View").click();
    harness.run_steps(2);
    harness.get_by_label_contains("Frame all").click();
    harness.run_steps(2);
    assert!(
        harness.state().state.message.is_none()
            || !harness.state().state.message.as_ref().unwrap().error
    );
}

#[test]
fn exporting_over_the_scene_s_own_mesh_is_refused() {
    let mut harness = harness();
    let dir = scratch("export-over-mesh");
    let mesh = dir.join("box.obj");
    let text = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
                f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::fs::write(&mesh, text).unwrap();
    let options = starcages_editor::state::NewMeshOptions::default();
    harness
        .state_mut()
        .run(Command::NewFromMesh(mesh.clone(), options));
    settle(&mut harness);
    harness.state_mut().run(Command::ExportMesh(mesh.clone()));
    let message = harness.state().state.message.clone().unwrap();
    assert!(
        message.error && message.text.contains("would destroy it"),
        "{}",
        message.text
    );
    assert_eq!(std::fs::read_to_string(&mesh).unwrap(), text);
    // Elsewhere it exports.
    let out = dir.join("deformed.obj");
    harness.state_mut().run(Command::ExportMesh(out.clone()));
    assert!(out.exists(), "{:?}", harness.state().state.message);
}

/// A scene whose join cages use harmonic coordinates is deformable from a quick preview bind
/// (mean value join cages), which a full bind then replaces; export waits for the full one.
#[test]
fn harmonic_join_cages_arrive_after_a_deformable_preview() {
    use starcages_core::star::StarBinding;
    let mut scene = starcages_core::generate::demo::demo_scene("critter", 0.3).unwrap();
    scene.settings.join_coordinates = starcages_core::scene::JoinPolicy::Auto;
    let doc = Document {
        scene,
        path: None,
        dirty: false,
    };
    let scene = doc.scene.clone();
    let mut app = starcages_editor::EditorApp::new(doc, None, false);
    // The first binding installed is the preview (the full bind starts only then).
    while app.state.rig.is_none() {
        app.state.poll_jobs(false);
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let first = app.state.rig.as_ref().unwrap();
    assert!(
        first.preview,
        "critter has harmonic join cages: a preview comes first"
    );
    assert!(!first.deformed.is_empty(), "the preview deforms the mesh");
    let mut quick = scene.clone();
    quick.settings.join_coordinates = starcages_core::scene::JoinPolicy::Mvc;
    let expected =
        StarBinding::bind_scene(&quick, &starcages_core::BindControl::default()).unwrap();
    assert_eq!(first.binding.operator, expected.operator);
    // Export waits for the full binding.
    let path = scratch("preview-export").join("deformed.obj");
    app.run(Command::ExportMesh(path.clone()));
    if app.state.rig.as_ref().unwrap().preview {
        assert!(!path.exists(), "a preview binding was exported");
    }
    // Installed, it starts the full bind; waiting for every job ends with the full binding.
    app.wait_for_jobs();
    let rig = app.state.rig.as_ref().unwrap();
    assert!(!rig.preview);
    let full = StarBinding::bind_scene(&scene, &starcages_core::BindControl::default()).unwrap();
    assert_eq!(rig.binding.operator, full.operator);
    assert_ne!(
        full.operator, expected.operator,
        "negative control: the join cages differ"
    );
}

/// A leaf cage switched to harmonic coordinates is bound at the preview resolution first (so
/// the change shows at once), then refined in the background to what a full bind gives.
#[test]
fn a_leaf_switched_to_harmonic_is_previewed_coarsely_then_refined() {
    use starcages_core::star::StarBinding;
    let mut app = starcages_editor::EditorApp::new(crate::common::document(), None, false);
    app.wait_for_jobs();
    assert!(!app.state.rig.as_ref().unwrap().preview);
    let before = std::sync::Arc::clone(&app.state.rig.as_ref().unwrap().binding);
    let head = CageId::by_name(&app.state.doc.scene.cages, "head_0_0_0").unwrap();
    app.run(Command::SetCageKind(head, CoordinateKind::Harmonic));
    // The first binding installed after the change is the coarse preview.
    loop {
        app.state.poll_jobs(false);
        let rig = app.state.rig.as_ref().unwrap();
        if !std::sync::Arc::ptr_eq(&rig.binding, &before) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let scene = app.state.doc.scene.clone();
    let c = scene.cages.leaf_index("head_0_0_0").unwrap();
    let rig = app.state.rig.as_ref().unwrap();
    assert!(rig.preview, "a coarse preview comes first");
    assert_eq!(rig.coarse_leaves, vec![c]);
    let mut coarse = scene.clone();
    coarse.settings.harmonic = coarse.settings.harmonic.preview();
    let control = starcages_core::BindControl::default();
    let expected = before.rebind_leaves(&coarse, &[c], &control).unwrap();
    assert_eq!(rig.binding.operator, expected.operator);
    // Waiting for every job ends with the full resolution, equal to a full bind's rows.
    app.wait_for_jobs();
    let rig = app.state.rig.as_ref().unwrap();
    assert!(!rig.preview && rig.coarse_leaves.is_empty());
    let full = StarBinding::bind_scene(&scene, &control).unwrap();
    let (a, b) = (
        rig.binding.deform(&scene.cages.vertices, &scene.pose),
        full.deform(&scene.cages.vertices, &scene.pose),
    );
    let worst = a
        .iter()
        .zip(&b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max);
    assert!(worst < 1e-5, "refined = full bind: {worst}");
    assert_ne!(
        expected.operator, full.operator,
        "negative control: the coarse rows differ"
    );
}

/// Where no native file dialog can be shown, File ▸ Open… opens the in-app one, and choosing a
/// scene in it opens the scene: the action never silently vanishes.
#[test]
fn the_in_app_file_dialog_opens_a_scene_when_no_native_dialog_can_be_shown() {
    let mut harness = harness();
    // A fixed folder name: the snapshot shows it.
    let dir = std::env::temp_dir().join("starcages-in-app-dialog");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    let path = dir.join("bar.json");
    starcages_io::save_scene(
        &starcages_core::generate::demo::demo_scene("bar", 0.3).unwrap(),
        &path,
    )
    .unwrap();
    harness.state_mut().ui.files.in_app_only = true;
    harness.get_by_label("File").click();
    harness.run_steps(2);
    harness.get_by_label_contains("Open…").click();
    harness.run_steps(2);
    {
        let dialog = harness.state_mut().ui.files.in_app.as_mut();
        let dialog = dialog.expect("the in-app dialog is open");
        dialog.enter(dir.clone());
        dialog.name = "bar.json".into();
    }
    harness.run_steps(2);
    harness.get_by_label("File name");
    harness.snapshot_options(
        "in_app_file_dialog",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
    harness.get_by_role_and_label(Role::Button, "Open").click();
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    assert!(
        harness.state().ui.files.in_app.is_none(),
        "the dialog closed"
    );
    assert_eq!(state.doc.path.as_deref(), Some(path.as_path()));
    assert_eq!(state.doc.scene.cages.leaves.len(), 2);
}

/// While a dialog is open its keys are not the editor's: typing a file name after a click
/// that missed the name field (found trying the release editor: "arm_rig.json" selected every
/// vertex and started a rotation) leaves the rig alone. Closed, R rotates again.
#[test]
fn shortcuts_wait_while_a_dialog_is_open() {
    use starcages_editor::ui::file_dialog::FilePurpose;
    let mut harness = harness();
    let centre = harness.state().state.view.viewport.center();
    let centre = egui::pos2(centre.x, centre.y);
    let app = harness.state_mut();
    let v = app.state.doc.scene.cages.leaves[leaf(app, "head_1_0_0")].faces[0][0];
    app.run(Command::Select {
        vertices: vec![v],
        mode: starcages_editor::state::SelectMode::Replace,
    });
    app.ui.files.in_app_only = true;
    app.ui.files.request(FilePurpose::SaveScene, None);
    harness.run_steps(2);
    // Nothing in the dialog has the keyboard, as after a click beside its name field.
    harness
        .ctx
        .memory_mut(|m| m.focused().map(|id| m.surrender_focus(id)));
    harness.hover_at(centre);
    press(&mut harness, egui::Key::R);
    assert!(harness.state().ui.tool.is_none(), "R started a rotation");
    harness.state_mut().ui.files.in_app = None;
    harness.run_steps(1);
    harness.hover_at(centre);
    harness.key_press(egui::Key::R);
    harness.run_steps(1);
    assert!(
        harness.state().ui.tool.is_some(),
        "R rotates once the dialog is closed"
    );
}

/// Blender's viewport aids: numpad 5 toggles orthographic, Ctrl+numpad gives the opposite
/// views, clicking an end of the axis gizmo looks along that axis, and G shows a header with
/// the live amount and the locked axis drawn through the pivot (snapshot with the ground grid).
#[test]
fn orthographic_toggle_opposite_views_axis_gizmo_and_the_transform_header() {
    use starcages_editor::ui::axis_gizmo;
    use starcages_viewport::View;
    let mut harness = harness();
    let looking = |harness: &egui_kittest::Harness<'static, starcages_editor::EditorApp>| {
        -harness.state().state.view.camera.backward()
    };
    let centre = harness.state().state.view.viewport.center();
    harness.hover_at(egui::pos2(centre.x, centre.y));
    press(&mut harness, egui::Key::Num5);
    assert!(harness.state().state.view.camera.orthographic);
    harness.get_by_role_and_label(Role::Button, "View").click();
    harness.run_steps(2);
    harness.get_by_label_contains("(now orthographic)");
    harness.key_press(egui::Key::Escape);
    press(&mut harness, egui::Key::Num5);
    assert!(!harness.state().state.view.camera.orthographic);
    press_with(&mut harness, egui::Modifiers::COMMAND, egui::Key::Num1);
    assert!(
        looking(&harness).distance(-Vec3::Y) < 1e-3,
        "Ctrl+1 looks along -Y"
    );
    press_with(&mut harness, egui::Modifiers::COMMAND, egui::Key::Num7);
    assert!(
        looking(&harness).distance(Vec3::Z) < 1e-2,
        "Ctrl+7 looks up +Z"
    );
    // The gizmo: click the +X end, then the +Z end.
    let rect = {
        let v = harness.state().state.view.viewport;
        egui::Rect::from_min_size(egui::pos2(v.min.x, v.min.y), egui::vec2(v.size.x, v.size.y))
    };
    for (axis, expected) in [(0, View::Side), (2, View::Top)] {
        let camera = harness.state().state.view.camera;
        let at = axis_gizmo::end_position(rect, &camera, axis, true);
        harness.hover_at(at);
        harness.run_steps(1);
        harness.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed: true,
            modifiers: egui::Modifiers::NONE,
        });
        harness.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed: false,
            modifiers: egui::Modifiers::NONE,
        });
        harness.run_steps(2);
        let mut reference = starcages_viewport::OrbitCamera::default();
        reference.set_view(expected);
        assert!(
            looking(&harness).distance(-reference.backward()) < 1e-3,
            "gizmo axis {axis}: {}",
            looking(&harness)
        );
        assert!(
            harness.state().state.selection.vertices.is_empty(),
            "the click picked"
        );
    }
    // G with a Z lock: the header shows the live value.
    harness.state_mut().run(Command::Camera(
        starcages_editor::commands::CameraChange::View(View::Front),
    ));
    let app = harness.state_mut();
    let v = app.state.doc.scene.cages.leaves[leaf(app, "head_1_0_0")].faces[0][0];
    app.run(Command::Select {
        vertices: vec![v],
        mode: starcages_editor::state::SelectMode::Replace,
    });
    harness.hover_at(egui::pos2(centre.x, centre.y));
    harness.key_press(egui::Key::G);
    harness.run_steps(1);
    harness.event(egui::Event::Text("z".into()));
    harness.run_steps(1);
    harness.hover_at(egui::pos2(centre.x + 30.0, centre.y - 60.0));
    harness.run_steps(2);
    let header = harness.get_by_label_contains("Grab along Z: ");
    let text = {
        use egui_kittest::kittest::NodeT as _;
        let node = header.accesskit_node();
        node.label().or_else(|| node.value()).unwrap_or_default()
    };
    let value: f64 = text
        .trim_start_matches("Grab along Z: ")
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(value > 0.0, "moving up gives a positive Z: {text}");
    harness.snapshot_options(
        "transform_header_axis_and_grid",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1500),
    );
    press(&mut harness, egui::Key::Escape);
    assert!(harness.state().ui.tool.is_none());
}

/// Keys a Blender user reaches for either act or say why not; N shows the selection's
/// coordinates and editing them moves the selection (undoable); F1 lists the shortcuts with
/// the cage colour legend; status messages fade.
#[test]
fn blender_keys_answer_the_item_panel_edits_and_f1_lists_the_shortcuts() {
    let mut harness = harness();
    let centre = harness.state().state.view.viewport.center();
    harness.hover_at(egui::pos2(centre.x, centre.y));
    // Rig operations in Pose mode say how to reach them (X and I are the timeline's there).
    for (key, modifiers) in [
        (egui::Key::Delete, egui::Modifiers::NONE),
        (egui::Key::E, egui::Modifiers::NONE),
        (egui::Key::A, egui::Modifiers::SHIFT),
        (egui::Key::R, egui::Modifiers::COMMAND),
    ] {
        press_with(&mut harness, modifiers, key);
        let message = harness.state().state.message.clone().unwrap();
        assert!(
            message.text.contains("Rig mode only") && message.text.contains("Tab"),
            "{key:?}: {}",
            message.text
        );
    }
    // Tab switches to Rig mode and back; the status bar says which.
    harness.get_by_label("Pose mode");
    press(&mut harness, egui::Key::Tab);
    assert_eq!(
        harness.state().state.mode,
        starcages_editor::state::EditMode::Rig
    );
    harness.get_by_label("Rig mode");
    press(&mut harness, egui::Key::Tab);
    assert_eq!(
        harness.state().state.mode,
        starcages_editor::state::EditMode::Pose
    );
    harness.key_press(egui::Key::A);
    press_with(&mut harness, egui::Modifiers::SHIFT, egui::Key::A);
    // Messages fade: an old one is no longer in the status bar (but kept in the state).
    harness.state_mut().state.message.as_mut().unwrap().shown =
        std::time::Instant::now() - starcages_editor::state::Message::LIFETIME * 2;
    harness.run_steps(2);
    assert!(harness.query_by_label_contains("Rig mode only").is_none());
    // N: the Item panel, with the selected vertex's coordinates; typing a value moves it.
    let app = harness.state_mut();
    let v = app.state.doc.scene.cages.leaves[leaf(app, "head_1_0_0")].faces[0][0];
    app.run(Command::Select {
        vertices: vec![v],
        mode: starcages_editor::state::SelectMode::Replace,
    });
    let before = app.state.doc.scene.pose[v as usize];
    press(&mut harness, egui::Key::N);
    assert!(harness.state().ui.show_item_panel);
    harness.get_by_label(&format!("vertex {v}"));
    harness.get_by_label("Rest");
    let z_field = || {
        harness
            .query_all_by_role(Role::SpinButton)
            .nth(2)
            .expect("three coordinate fields")
    };
    z_field().click();
    harness.run_steps(1);
    harness
        .query_all_by_role(Role::SpinButton)
        .nth(2)
        .expect("the Z field")
        .type_text(&format!("{}", before.z + 0.125));
    harness.run_steps(1);
    press(&mut harness, egui::Key::Enter);
    let after = harness.state().state.doc.scene.pose[v as usize];
    assert!(
        (after - before - DVec3::new(0.0, 0.0, 0.125)).length() < 1e-9,
        "{before} -> {after}"
    );
    harness.state_mut().run(Command::Undo);
    assert_eq!(harness.state().state.doc.scene.pose[v as usize], before);
    // F1: every action with its keys, and the cage colours.
    press(&mut harness, egui::Key::F1);
    assert!(harness.state().ui.show_shortcuts);
    // The window's title and its own row.
    assert!(harness.query_all_by_label("Keyboard shortcuts").count() >= 2);
    harness.get_by_label_contains("Switch between perspective and orthographic");
    harness.get_by_label_contains("GC leaf cage");
    harness.get_by_label_contains("border: a face shared by two leaf cages");
    // The keys of the modal tools, from their table.
    harness.get_by_label("Lock to X (again: free)");
    assert!(
        harness
            .query_all_by_label_contains("while G / R / S, loop cut, inset runs")
            .count()
            >= 4
    );
    harness.snapshot_options(
        "shortcuts_window_and_item_panel",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1500),
    );
}

/// Poses: the active one is shown; switching away from edits not stored asks (keep them as a
/// pose, discard, cancel); storing over an existing name asks before overwriting.
#[test]
fn poses_show_the_active_one_and_ask_before_losing_or_overwriting() {
    let mut harness = harness();
    let stored: Vec<String> = harness
        .state()
        .state
        .doc
        .scene
        .poses
        .keys()
        .cloned()
        .collect();
    let first = stored
        .first()
        .expect("the critter has a stored pose")
        .clone();
    // Away from the timeline's keys (an edit at a keyed frame goes into that key's pose).
    harness.state_mut().run(Command::SetFrame(5.0));
    harness.state_mut().run(Command::SwitchPose(None));
    harness.run_steps(2);
    harness.get_by_label("current: the rest pose");
    let app = harness.state_mut();
    let v = app.state.doc.scene.cages.leaves[leaf(app, "head_1_0_0")].faces[0][0];
    let moved = app.state.doc.scene.pose[v as usize] + DVec3::new(0.0, 0.0, 0.1);
    app.run(Command::MoveVertices(vec![(v, moved)]));
    harness.run_steps(2);
    harness.get_by_label("current: edited, not stored");
    // Switching asks; keeping stores the edits as 'unsaved' and switches.
    harness.get_by_label(&first).click();
    harness.run_steps(2);
    harness.get_by_label("Edits not stored");
    harness.get_by_label("Keep them as 'unsaved'").click();
    harness.run_steps(3);
    let scene = &harness.state().state.doc.scene;
    assert_eq!(
        scene.poses.get("unsaved").map(|p| p[v as usize]),
        Some(moved)
    );
    assert_eq!(&scene.pose, &scene.poses[&first]);
    harness.get_by_label(&format!("current: '{first}'"));
    // Storing over an existing name asks; Cancel leaves it, Overwrite replaces it.
    harness
        .state_mut()
        .run(Command::MoveVertices(vec![(v, moved * 1.5)]));
    harness.run_steps(1);
    harness.state_mut().ui.new_pose_name = first.clone();
    harness.get_by_label("Store pose").click();
    harness.run_steps(2);
    harness.get_by_label("Overwrite pose?");
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    assert_ne!(
        harness.state().state.doc.scene.poses[&first][v as usize],
        moved * 1.5
    );
    harness.get_by_label("Store pose").click();
    harness.run_steps(2);
    harness.get_by_label("Overwrite").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.doc.scene.poses[&first][v as usize],
        moved * 1.5
    );
}

/// Dragging h shows the cage's b map while dragging (then the map chosen before); the W map
/// with several vertices selected follows the vertex under the cursor, or says what to do.
#[test]
fn dragging_h_shows_the_b_map_and_the_w_map_follows_the_hovered_vertex() {
    let mut harness = harness();
    harness.get_by_label("head_0_0_0 (mvc)").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.view.influence, InfluenceChoice::None);
    let slider = harness.get_by_role_and_label(Role::Slider, "h");
    let at = slider.rect().center();
    harness.event(egui::Event::PointerMoved(at));
    harness.event(egui::Event::PointerButton {
        pos: at,
        button: egui::PointerButton::Primary,
        pressed: true,
        modifiers: egui::Modifiers::NONE,
    });
    harness.run_steps(1);
    harness.event(egui::Event::PointerMoved(at + egui::vec2(-40.0, 0.0)));
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.view.influence,
        InfluenceChoice::SelectedCage,
        "the b map is shown while dragging h"
    );
    harness.event(egui::Event::PointerButton {
        pos: at + egui::vec2(-40.0, 0.0),
        button: egui::PointerButton::Primary,
        pressed: false,
        modifiers: egui::Modifiers::NONE,
    });
    harness.run_steps(2);
    assert_eq!(harness.state().state.view.influence, InfluenceChoice::None);
    let head = leaf(harness.state(), "head_0_0_0");
    assert_ne!(harness.state().state.doc.scene.cages.leaves[head].h, None);
    // W with the whole head cage selected: a note, then the hovered vertex's map.
    harness
        .state_mut()
        .run(Command::SetInfluence(InfluenceChoice::JoinWeight));
    settle(&mut harness);
    let note = harness.state().state.map.note.clone().unwrap_or_default();
    assert!(note.contains("are selected"), "{note}");
    let v = harness.state().state.doc.scene.cages.leaves[head].faces[0][0];
    let on_screen = vertex_on_screen(&harness.state().state, v).unwrap();
    harness.hover_at(on_screen);
    harness.run_steps(3);
    assert_eq!(harness.state().state.selection.hovered, Some(v));
    assert!(
        harness.state().state.map.values().is_some(),
        "W of the hovered vertex"
    );
}

/// Every control says in plain words what it does: the b / W / h maps, red and blue, the join
/// policy and the HC grid among them.
#[test]
fn controls_explain_themselves_in_tooltips() {
    let mut harness = harness();
    // Tooltips at once (a person rests the pointer a moment first).
    harness
        .ctx
        .all_styles_mut(|style| style.interaction.tooltip_delay = 0.0);
    harness.get_by_label("head_0_0_0 (mvc)").click();
    harness.run_steps(2);
    harness.get_by_label("Scene settings").click();
    harness.run_steps(2);
    for (label, words) in [
        ("h", "how far into this cage its neighbours blend in"),
        ("HC grid", "Harmonic coordinates are solved on a grid"),
        ("Join cages", "blend neighbouring cages smoothly"),
        ("Influence map", "The mesh in its own colour"),
        ("Ground grid", "X axis in red"),
        ("Coordinates", "How this cage's vertices move the mesh"),
    ] {
        let node = harness
            .query_all_by_label(label)
            .next()
            .unwrap_or_else(|| panic!("no control called {label}"));
        node.hover();
        harness.run_steps(3);
        let found = harness.query_by_label_contains(words).is_some();
        assert!(found, "no tooltip for {label} containing '{words}'");
        harness.hover_at(egui::pos2(5.0, 790.0));
        harness.run_steps(2);
    }
    // b's colours are explained where the map is chosen.
    harness
        .state_mut()
        .run(Command::SetInfluence(InfluenceChoice::AllCages));
    harness.run_steps(2);
    harness
        .query_all_by_label("Influence map")
        .next()
        .unwrap()
        .hover();
    harness.run_steps(3);
    harness.get_by_label_contains("Red (b = 1): only this cage's own");
}

/// The Item panel edits rest positions too: the poses keep their displacement from rest, only
/// the rows the edit reaches are bound again, and the result is the full bind's; undo restores.
#[test]
fn editing_rest_positions_in_the_item_panel_rebinds_and_moves_the_poses_along() {
    use starcages_core::star::StarBinding;
    let mut harness = harness();
    let app = harness.state_mut();
    let v = app.state.doc.scene.cages.leaves[leaf(app, "head_1_0_0")].faces[0][0];
    app.run(Command::Select {
        vertices: vec![v],
        mode: starcages_editor::state::SelectMode::Replace,
    });
    let before = app.state.doc.scene.clone();
    press(&mut harness, egui::Key::N);
    harness.get_by_label("Rest");
    // The rest Z field: the sixth coordinate field (posed X Y Z, then rest X Y Z).
    let target = before.cages.vertices[v as usize].z - 0.05;
    harness
        .query_all_by_role(Role::SpinButton)
        .nth(5)
        .expect("the rest Z field")
        .click();
    harness.run_steps(1);
    harness
        .query_all_by_role(Role::SpinButton)
        .nth(5)
        .expect("the rest Z field")
        .type_text(&format!("{target}"));
    harness.run_steps(1);
    press(&mut harness, egui::Key::Enter);
    settle(&mut harness);
    let state = &harness.state().state;
    let scene = &state.doc.scene;
    let delta = DVec3::new(0.0, 0.0, -0.05);
    assert!(
        (scene.cages.vertices[v as usize] - before.cages.vertices[v as usize] - delta).length()
            < 1e-9
    );
    assert!((scene.pose[v as usize] - before.pose[v as usize] - delta).length() < 1e-9);
    for (name, pose) in &scene.poses {
        let moved = pose[v as usize] - before.poses[name][v as usize];
        assert!(
            (moved - delta).length() < 1e-9,
            "pose {name} did not follow"
        );
    }
    // The incremental binding deforms as a full bind of the edited scene does.
    let rig = state.rig.as_ref().unwrap();
    assert_eq!(rig.bound_for.0.vertices, scene.cages.vertices);
    let full = StarBinding::bind_scene(scene, &starcages_core::BindControl::default()).unwrap();
    let (a, b) = (
        rig.binding.deform(&scene.cages.vertices, &scene.pose),
        full.deform(&scene.cages.vertices, &scene.pose),
    );
    let worst = a
        .iter()
        .zip(&b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max);
    assert!(
        worst < 1e-4,
        "incremental differs from a full bind by {worst}"
    );
    harness.state_mut().run(Command::Undo);
    settle(&mut harness);
    let scene = &harness.state().state.doc.scene;
    assert_eq!(scene.cages.vertices, before.cages.vertices);
    assert_eq!(scene.poses, before.poses);
}

/// Save from the unsaved-changes prompt of a scene without a file opens the file dialog on
/// top (the prompt steps aside), and choosing a file saves and carries on.
#[test]
fn saving_from_the_unsaved_prompt_goes_through_the_file_dialog() {
    let mut harness = harness();
    harness.state_mut().ui.files.in_app_only = true;
    let dir =
        std::env::temp_dir().join(format!("starcages-save-from-prompt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let other = dir.join("bar.json");
    starcages_io::save_scene(
        &starcages_core::generate::demo::demo_scene("bar", 0.3).unwrap(),
        &other,
    )
    .unwrap();
    // An edit, then Open: the prompt asks.
    let app = harness.state_mut();
    let v = app.state.doc.scene.cages.leaves[leaf(app, "head_1_0_0")].faces[0][0];
    let moved = app.state.doc.scene.pose[v as usize] + DVec3::Z * 0.1;
    app.run(Command::MoveVertices(vec![(v, moved)]));
    app.run(Command::Open(other.clone()));
    harness.run_steps(2);
    harness.get_by_label("Unsaved changes");
    harness.get_by_role_and_label(Role::Button, "Save").click();
    harness.run_steps(2);
    assert!(
        harness.query_by_label("Unsaved changes").is_none(),
        "the prompt covers the dialog"
    );
    {
        let dialog = harness
            .state_mut()
            .ui
            .files
            .in_app
            .as_mut()
            .expect("the save dialog");
        dialog.enter(dir.clone());
        dialog.name = "critter-edited.json".into();
    }
    harness.run_steps(2);
    harness.get_by_role_and_label(Role::Button, "Save").click();
    harness.run_steps(2);
    settle(&mut harness);
    assert!(dir.join("critter-edited.json").exists(), "not saved");
    assert_eq!(
        harness.state().state.doc.path.as_deref(),
        Some(other.as_path())
    );
}

/// File ▸ Open demo lists every generated demo (the creature among them) and opens one on a
/// worker, clean and bound.
#[test]
fn file_open_demo_lists_the_demos_and_opens_one() {
    let mut harness = harness();
    harness.get_by_label("File").click();
    harness.run_steps(2);
    harness.get_by_label("Open demo").click();
    harness.run_steps(2);
    for (name, _) in starcages_core::generate::demo::DEMOS {
        harness.get_by_label(name);
    }
    // The command starts a worker and returns: the document is not replaced yet (checked on
    // the command itself; a frame later the worker may have finished already).
    let mut probe = starcages_editor::EditorState::new(crate::common::document(), None);
    starcages_editor::commands::apply(&mut probe, Command::OpenDemo("bumpy".into()));
    assert!(
        probe.load_job.is_some() && probe.doc.scene.cages.leaves.len() == 10,
        "the demo is generated in the background"
    );
    harness.get_by_label("bumpy").click();
    harness.run_steps(1);
    settle(&mut harness);
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.leaves.len(), 3);
    assert!(!state.doc.dirty && state.doc.path.is_none());
    assert!(state.rig.is_some(), "bound");
}

/// A message longer than the status bar ends in "…" at the window's edge, and hovering it
/// shows the whole text (the fix at its end included) in a tooltip.
#[test]
fn a_long_status_message_is_cut_and_shown_whole_on_hover() {
    let mut harness = harness();
    let fix = "write the name as a string. The current scene is unchanged";
    let text = format!(
        "could not open scene.json:1:36375: field 'cages[0].kind': expected a name in quotes \
         here (such as \"mvc\"; docs/scene-format.md lists each field's names), found a number, \
         a list, an object or null; {fix}"
    );
    harness.state_mut().state.message =
        Some(starcages_editor::state::Message::new(text.clone(), true));
    harness.set_size(egui::vec2(900.0, 600.0));
    harness.run_steps(2);
    let whole = |harness: &egui_kittest::Harness<'_, starcages_editor::EditorApp>| {
        harness.query_all_by_label_contains(fix).count()
    };
    let before = whole(&harness);
    harness
        .get_by_label_contains("could not open scene.json")
        .hover();
    // Past egui's tooltip delay (half a second).
    for _ in 0..10 {
        harness.step();
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    assert!(
        whole(&harness) > before,
        "no tooltip with the whole message on hover ({before} nodes with its end before)"
    );
}
