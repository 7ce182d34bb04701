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

use crate::common::{cage, harness, leaf, scratch, settle};

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
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert_eq!(harness.state().state.doc.scene.pose, before_pose);
    assert_eq!(harness.state().state.undo.undo_label(), None);
    let restored = harness.state().state.deformed().to_vec();
    let worst = restored
        .iter()
        .zip(&before_mesh)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    assert!(worst < 1e-5, "{worst}");
    harness.key_press_modifiers(
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    harness.run_steps(2);
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
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    settle(&mut harness);
    assert_eq!(kind(&harness), CoordinateKind::MeanValue);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Y);
    harness.run_steps(2);
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
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert_eq!(harness.state().state.doc.scene.cages.leaves[head].h, None);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Y);
    harness.run_steps(2);
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
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
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
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
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
    harness.key_press(egui::Key::A);
    harness.run_steps(2);
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

/// New from mesh reads an OBJ Y-up (the convention) and stands it up along Z; the dialog's
/// "Z up" reads it as it is.
#[test]
fn new_from_mesh_stands_a_y_up_obj_up() {
    use starcages_core::scene::UpAxis;
    use starcages_editor::state::NewMeshOptions;
    let dir = scratch("new-from-y-up");
    let mesh = dir.join("tall.obj");
    std::fs::write(
        &mesh,
        "v 0 0 0\nv 1 0 0\nv 0 4 0\nv 1 4 0\nv 0 0 1\nv 1 0 1\nv 0 4 1\nv 1 4 1\n\
         f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n",
    )
    .unwrap();
    let doc = Document {
        scene: starcages_core::generate::demo::demo_scene("bar", 0.3).unwrap(),
        path: None,
        dirty: false,
    };
    let mut app = starcages_editor::EditorApp::new(doc, None, false);
    app.wait_for_jobs();
    for (up, tall_axis) in [(UpAxis::Y, 2), (UpAxis::Z, 1)] {
        let options = NewMeshOptions {
            up,
            rig: starcages_editor::state::NewRig::Grid,
            ..NewMeshOptions::default()
        };
        app.run(Command::NewFromMesh(mesh.clone(), options));
        app.run(Command::AnswerUnsaved(
            starcages_editor::commands::UnsavedAnswer::Discard,
        ));
        app.wait_for_jobs();
        let scene = &app.state.doc.scene;
        assert_eq!(scene.mesh_up, up);
        let (lo, hi) = scene.mesh.bounds();
        assert!(
            ((hi - lo)[tall_axis] - 4.0).abs() < 1e-9,
            "{up:?}: {:?}",
            hi - lo
        );
        // The default grid everywhere.
        assert!(scene.cages.leaves.len() <= 27 && scene.cages.leaves.len() > 8);
    }
}

/// New from mesh on `mesh` (discarding the open document), returning once the mesh is read
/// and installed, while its auto rig may still run.
fn open_mesh_until_read(app: &mut starcages_editor::EditorApp, mesh: &std::path::Path) {
    open_mesh_with_until_read(app, mesh, Default::default());
}

/// [`open_mesh_until_read`] with the dialog's `options`.
fn open_mesh_with_until_read(
    app: &mut starcages_editor::EditorApp,
    mesh: &std::path::Path,
    options: starcages_editor::state::NewMeshOptions,
) {
    app.run(Command::NewFromMesh(mesh.to_path_buf(), options));
    app.run(Command::AnswerUnsaved(
        starcages_editor::commands::UnsavedAnswer::Discard,
    ));
    while app.state.load_job.is_some() {
        app.state.poll_jobs(false);
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

/// An editor on `scene` (not saved anywhere), its first bind done.
fn app_on(scene: starcages_core::scene::Scene) -> starcages_editor::EditorApp {
    let doc = Document {
        scene,
        path: None,
        dirty: false,
    };
    let mut app = starcages_editor::EditorApp::new(doc, None, false);
    app.wait_for_jobs();
    app
}

/// New from mesh gives the auto rig by default, on a worker; Rig ▸ Auto rig replaces a rig
/// with it as one undo step (poses of the old cages go, and come back with undo).
#[test]
fn the_auto_rig_is_the_default_for_a_new_mesh_and_one_undo_step_on_a_rig() {
    use starcages_core::scene::validate_scene;
    let dir = scratch("auto-rig");
    let mesh = dir.join("bar.obj");
    let mut bar = starcages_core::generate::demo::demo_scene("bar", 0.3).unwrap();
    starcages_core::scene::write_deformed_mesh(&mesh, &bar, bar.mesh.welded_positions()).unwrap();
    // An animation of the old rig's pose: its keys go with the rig (a key naming a pose the
    // scene no longer has left the scene invalid, the binding stuck on the old rig).
    bar.animation.keys.push(starcages_core::anim::Key {
        frame: 1.0,
        pose: "bend".into(),
        interpolation: Default::default(),
        h: Default::default(),
    });
    let old_animation = bar.animation.clone();
    let mut app = app_on(bar);
    let grid_cages = app.state.doc.scene.cages.clone();
    let grid_mesh_vertices = app.state.doc.scene.mesh.welded_positions().len();
    app.run(Command::AutoRig {
        detail: 2,
        internal: true,
        mirror: starcages_core::generate::Mirror::None,
    });
    assert!(app.state.autorig_job.is_some(), "runs on a worker");
    app.wait_for_jobs();
    let scene = &app.state.doc.scene;
    assert!(
        validate_scene(scene).is_valid(),
        "{:?}",
        validate_scene(scene).errors
    );
    assert!(scene.animation.keys.is_empty() && scene.poses.is_empty());
    assert!(
        app.state
            .message
            .as_ref()
            .is_some_and(|m| m.text.contains("1 animation key"))
    );
    assert_ne!(scene.cages, grid_cages);
    assert!(
        scene
            .cages
            .leaves
            .iter()
            .all(|l| l.name.starts_with("body") || l.name.starts_with("limb"))
    );
    assert!(scene.cages.internals.iter().any(|c| c.name == "rig_ctrl"));
    assert!(app.state.rig.is_some(), "bound after the auto rig");
    app.run(Command::Undo);
    assert_eq!(app.state.doc.scene.cages, grid_cages, "one undo step back");
    assert_eq!(app.state.doc.scene.animation, old_animation);
    assert!(app.state.doc.scene.poses.contains_key("bend"));
    app.run(Command::Redo);
    assert_ne!(app.state.doc.scene.cages, grid_cages);
    // New from mesh: the auto rig by default. The mesh opens at once in the grid, the auto
    // rig follows on a worker and replaces it as one undo step.
    open_mesh_until_read(&mut app, &mesh);
    let opened = app.state.doc.scene.clone();
    assert_eq!(
        opened.mesh.welded_positions().len(),
        grid_mesh_vertices,
        "the mesh is open before its rig is made"
    );
    assert!(app.state.autorig_job.is_some(), "the auto rig runs after");
    assert!(
        app.state.bind_job.is_none(),
        "the grid is not bound meanwhile"
    );
    app.wait_for_jobs();
    let scene = &app.state.doc.scene;
    assert!(
        scene
            .cages
            .leaves
            .iter()
            .all(|l| l.name.starts_with("body") || l.name.starts_with("limb")),
        "{:?}",
        app.state.message
    );
    assert!(validate_scene(scene).is_valid());
    // The grid is one undo step away.
    app.run(Command::Undo);
    assert_eq!(app.state.doc.scene.cages, opened.cages);
    // Cancelling the auto rig keeps the grid, and binds it.
    open_mesh_until_read(&mut app, &mesh);
    app.run(Command::CancelAutoRig);
    app.wait_for_jobs();
    assert_eq!(app.state.doc.scene.cages, opened.cages);
    assert!(
        app.state.rig.is_some(),
        "the grid is bound after the cancel"
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
    starcages_core::scene::save_scene(
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
    harness.key_press(egui::Key::Num5);
    harness.run_steps(2);
    assert!(harness.state().state.view.camera.orthographic);
    harness.get_by_role_and_label(Role::Button, "View").click();
    harness.run_steps(2);
    harness.get_by_label_contains("(now orthographic)");
    harness.key_press(egui::Key::Escape);
    harness.key_press(egui::Key::Num5);
    harness.run_steps(2);
    assert!(!harness.state().state.view.camera.orthographic);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Num1);
    harness.run_steps(2);
    assert!(
        looking(&harness).distance(-Vec3::Y) < 1e-3,
        "Ctrl+1 looks along -Y"
    );
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Num7);
    harness.run_steps(2);
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
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
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
        harness.key_press_modifiers(modifiers, key);
        harness.run_steps(2);
        let message = harness.state().state.message.clone().unwrap();
        assert!(
            message.text.contains("Rig mode only") && message.text.contains("Tab"),
            "{key:?}: {}",
            message.text
        );
    }
    // Tab switches to Rig mode and back; the status bar says which.
    harness.get_by_label("Pose mode");
    harness.key_press(egui::Key::Tab);
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.mode,
        starcages_editor::state::EditMode::Rig
    );
    harness.get_by_label("Rig mode");
    harness.key_press(egui::Key::Tab);
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.mode,
        starcages_editor::state::EditMode::Pose
    );
    harness.key_press(egui::Key::A);
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::A);
    harness.run_steps(2);
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
    harness.key_press(egui::Key::N);
    harness.run_steps(2);
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
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
    let after = harness.state().state.doc.scene.pose[v as usize];
    assert!(
        (after - before - DVec3::new(0.0, 0.0, 0.125)).length() < 1e-9,
        "{before} -> {after}"
    );
    harness.state_mut().run(Command::Undo);
    assert_eq!(harness.state().state.doc.scene.pose[v as usize], before);
    // F1: every action with its keys, and the cage colours.
    harness.key_press(egui::Key::F1);
    harness.run_steps(2);
    assert!(harness.state().ui.show_shortcuts);
    // The window's title and its own row.
    assert!(harness.query_all_by_label("Keyboard shortcuts").count() >= 2);
    harness.get_by_label_contains("Switch between perspective and orthographic");
    harness.get_by_label_contains("GC leaf cage");
    harness.get_by_label_contains("border: a face shared by two leaf cages");
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
    harness.key_press(egui::Key::N);
    harness.run_steps(2);
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
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
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
    starcages_core::scene::save_scene(
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

/// Rig mode: Tab enters it; E extrudes the selected face into a new cage sharing it; X
/// deletes the inspected cage and undo brings it back; Ctrl+R cuts a cage; moving vertices
/// edits the rest cages (the poses follow); the binding follows every change.
#[test]
fn rig_mode_extrudes_cuts_deletes_and_moves_rest_cages() {
    let mut harness = crate::common::bar_harness(true);
    // The +x face of the right cage.
    let app = harness.state_mut();
    let scene = &app.state.doc.scene;
    let right = scene.cages.leaf_index("cage_1_0_0").unwrap();
    let face: Vec<u32> = scene.cages.leaves[right]
        .faces
        .iter()
        .find(|f| f.iter().all(|&v| scene.cages.vertices[v as usize].x > 1.0))
        .unwrap()
        .clone();
    app.run(Command::Select {
        vertices: face.clone(),
        mode: starcages_editor::state::SelectMode::Replace,
    });
    harness.key_press(egui::Key::E);
    harness.run_steps(2);
    // E continues as G along the face's normal (x here) on the new cap, as Blender's extrude.
    assert!(harness.state().ui.tool.is_some(), "E starts G");
    let state = &harness.state().state;
    let cap: Vec<u32> = state.selection.vertices.iter().copied().collect();
    assert_eq!(cap.len(), 4, "the new cap is selected");
    assert!(cap.iter().all(|v| !face.contains(v)));
    let cap_before: Vec<DVec3> = cap
        .iter()
        .map(|&v| state.doc.scene.cages.vertices[v as usize])
        .collect();
    for text in ["0", ".", "2", "5"] {
        harness.event(egui::Event::Text(text.into()));
        harness.run_steps(1);
    }
    harness.get_by_label_contains("Grab along X: 0.250");
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    assert!(harness.state().ui.tool.is_none());
    for (&v, before) in cap.iter().zip(&cap_before) {
        let moved = state.doc.scene.cages.vertices[v as usize] - *before;
        assert!(
            (moved - DVec3::new(0.25, 0.0, 0.0)).length() < 1e-12,
            "the cap moves along x in the rest cages: {moved}"
        );
    }
    assert_eq!(state.doc.scene.cages.leaves.len(), 3, "{:?}", state.message);
    assert_eq!(state.doc.scene.cages.adjacency().len(), 2);
    assert!(starcages_core::scene::validate_scene(&state.doc.scene).is_valid());
    assert_eq!(
        state.rig.as_ref().unwrap().bound_for.0.leaves.len(),
        3,
        "the binding follows"
    );
    // E and its grab are one undo step (Blender's "extrude and move"); redo brings both back.
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
    harness.key_press_modifiers(
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.leaves.len(), 3);
    for (&v, before) in cap.iter().zip(&cap_before) {
        let moved = state.doc.scene.cages.vertices[v as usize] - *before;
        assert!((moved - DVec3::new(0.25, 0.0, 0.0)).length() < 1e-12);
    }
    // X deletes the inspected (new) cage; undo brings it back.
    let new_cage = CageId::Leaf(2);
    harness
        .state_mut()
        .run(Command::InspectCage(Some(new_cage)));
    harness.key_press(egui::Key::X);
    harness.run_steps(2);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 3);
    // Ctrl+R places a cut across the inspected cage's longest side; Enter makes it.
    harness
        .state_mut()
        .run(Command::InspectCage(Some(CageId::Leaf(0))));
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::R);
    harness.run_steps(2);
    assert!(
        harness.state().ui.loop_cut.is_some(),
        "the cut is being placed"
    );
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
    settle(&mut harness);
    let scene = harness.state().state.doc.scene.clone();
    assert_eq!(
        scene.cages.leaves.len(),
        4,
        "{:?}",
        harness.state().state.message
    );
    assert!(starcages_core::scene::validate_scene(&scene).is_valid());
    // Moving a vertex in Rig mode moves its rest position; the poses follow.
    let v = face[0];
    let before_rest = scene.cages.vertices[v as usize];
    let before_pose = scene.pose[v as usize];
    let to = before_pose + DVec3::new(0.1, 0.0, 0.0);
    harness
        .state_mut()
        .run(Command::MoveVertices(vec![(v, to)]));
    settle(&mut harness);
    let scene = &harness.state().state.doc.scene;
    assert!(
        (scene.cages.vertices[v as usize] - before_rest - DVec3::new(0.1, 0.0, 0.0)).length()
            < 1e-12
    );
    assert!((scene.pose[v as usize] - to).length() < 1e-12);
}

/// An invalid rig (a box overlapping the cages) shows a banner with the first problem, keeps
/// the last valid binding and refuses Pose mode until it is fixed (here by undo).
#[test]
fn an_invalid_rig_shows_its_problems_and_refuses_pose_mode() {
    let mut harness = crate::common::bar_harness(false);
    let binding = std::sync::Arc::clone(&harness.state().state.rig.as_ref().unwrap().binding);
    let centre = harness.state().state.view.viewport.center();
    harness.hover_at(egui::pos2(centre.x, centre.y));
    harness.key_press(egui::Key::Tab);
    harness.run_steps(1);
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::A);
    harness.run_steps(2);
    harness.get_by_label("Box around the whole mesh").click();
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.leaves.len(), 3);
    assert!(
        !state.rig_problems.is_empty(),
        "a box over the cages overlaps them"
    );
    harness.get_by_label_contains("The rig has");
    assert!(
        std::sync::Arc::ptr_eq(
            &binding,
            &harness.state().state.rig.as_ref().unwrap().binding
        ),
        "the last valid binding stays"
    );
    harness.key_press(egui::Key::Tab);
    harness.run_steps(2);
    let state = &harness.state().state;
    assert_eq!(state.mode, starcages_editor::state::EditMode::Rig);
    assert!(
        state
            .message
            .as_ref()
            .unwrap()
            .text
            .contains("fix the rig before posing")
    );
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert!(harness.state().state.rig_problems.is_empty());
    assert!(harness.query_by_label_contains("The rig has").is_none());
    harness.key_press(egui::Key::Tab);
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.mode,
        starcages_editor::state::EditMode::Pose
    );
}

/// File > Import cages adds an OBJ's cages to the rig, in the mesh file's axes, sharing the
/// faces where they meet the rig; undo removes them.
#[test]
fn importing_cages_adds_them_to_the_rig_sharing_faces() {
    let mut harness = crate::common::bar_harness(false);
    // A box beside the bar's +x face, written Y-up (OBJ convention); the bar is symmetric in
    // y and z, so the box is the same in both axes.
    let path = box_obj(
        "import-cages",
        "tip",
        [1.1, -0.35, -0.35],
        [2.0, 0.35, 0.35],
    );
    harness.state_mut().run(Command::ImportCages(path));
    settle(&mut harness);
    let state = &harness.state().state;
    let scene = &state.doc.scene;
    assert_eq!(scene.cages.leaves.len(), 3, "{:?}", state.message);
    assert_eq!(scene.cages.leaves[2].name, "tip");
    assert_eq!(
        scene.cages.adjacency().len(),
        2,
        "the tip shares the bar's end face"
    );
    assert!(state.rig_problems.is_empty(), "{:?}", state.rig_problems);
    harness.state_mut().run(Command::Undo);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
}

/// An OBJ holding one box group called `name` from `lo` to `hi`, in a scratch folder.
fn box_obj(folder: &str, name: &str, lo: [f64; 3], hi: [f64; 3]) -> std::path::PathBuf {
    let corners: Vec<String> = (0..8)
        .map(|c: usize| {
            let at = |axis: usize| {
                if c >> axis & 1 == 0 {
                    lo[axis]
                } else {
                    hi[axis]
                }
            };
            format!("v {} {} {}", at(0), at(1), at(2))
        })
        .collect();
    let faces = starcages_core::cage::shapes::box_faces(std::array::from_fn(|c| c as u32 + 1));
    let mut text = corners.join("\n") + &format!("\no {name}\n");
    for f in faces {
        let corners: Vec<String> = f.iter().map(|v| v.to_string()).collect();
        text += &format!("f {}\n", corners.join(" "));
    }
    let path = scratch(folder).join(format!("{name}.obj"));
    std::fs::write(&path, text).unwrap();
    path
}

/// File ▸ Import internal cages: a box around the bar's right cage becomes its parent (an
/// internal cage driving its eight corners), in one undo step; one holding nothing free is
/// refused with the reason.
#[test]
fn importing_internal_cages_drives_the_cage_vertices_inside_them() {
    let mut harness = crate::common::bar_harness(false);
    // The bar's right cage spans x 0..1.1 and y, z -0.35..0.35 at this detail (symmetric in y
    // and z, so the same Y-up or Z-up).
    let path = box_obj(
        "import-internal",
        "driver",
        [-0.1, -0.5, -0.5],
        [1.3, 0.5, 0.5],
    );
    harness
        .state_mut()
        .run(Command::ImportInternalCages(path.clone()));
    settle(&mut harness);
    let state = &harness.state().state;
    let set = &state.doc.scene.cages;
    assert_eq!(set.internals.len(), 1, "{:?}", state.message);
    assert_eq!(set.internals[0].name, "driver");
    let right = leaf(harness.state(), "cage_1_0_0");
    let corners: std::collections::BTreeSet<u32> =
        set.leaves[right].faces.iter().flatten().copied().collect();
    let owned: std::collections::BTreeSet<u32> = set.internals[0].owns.iter().copied().collect();
    assert_eq!(owned, corners, "it drives the right cage's corners");
    assert!(
        state
            .rig
            .as_ref()
            .unwrap()
            .hierarchy
            .parent_of(*corners.first().unwrap())
            .is_some()
    );
    assert_eq!(
        state.selection.cage(),
        Some(CageId::Internal(0)),
        "shown in the inspector"
    );
    // Again: nothing inside is free any more.
    harness.state_mut().run(Command::ImportInternalCages(path));
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.internals.len(), 1);
    let message = format!("{:?}", state.message);
    assert!(
        message.contains("holds no cage vertex without a parent"),
        "{message}"
    );
    harness.state_mut().run(Command::Undo);
    settle(&mut harness);
    assert!(harness.state().state.doc.scene.cages.internals.is_empty());
}

/// Rig mode's merge (M), mirror (Ctrl+M) and Fit to mesh work on the inspected cage.
#[test]
fn rig_mode_merges_mirrors_and_fits_the_inspected_cage() {
    let mut harness = crate::common::bar_harness(true);
    // Fit the left cage: it shrinks toward the bar, its shared face stays.
    harness
        .state_mut()
        .run(Command::InspectCage(Some(CageId::Leaf(0))));
    let before = harness.state().state.doc.scene.clone();
    harness.state_mut().ui.show_shortcuts = false;
    harness.get_by_role_and_label(Role::Button, "Rig").click();
    harness.run_steps(2);
    harness.get_by_label_contains("Fit to mesh").click();
    harness.run_steps(2);
    let scene = harness.state().state.doc.scene.clone();
    assert_ne!(
        scene.cages.vertices,
        before.cages.vertices,
        "{:?}",
        harness.state().state.message
    );
    assert!(
        harness.state().state.rig_problems.is_empty(),
        "{:?}",
        harness.state().state.rig_problems
    );
    // M merges the two cages (the left one has one neighbour).
    harness.key_press(egui::Key::M);
    harness.run_steps(2);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 1);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
    // Ctrl+M mirrors the inspected cage across x = 0: a copy that overlaps the other half of
    // the bar, which the live validation reports.
    harness
        .state_mut()
        .run(Command::InspectCage(Some(CageId::Leaf(1))));
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::M);
    harness.run_steps(2);
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.leaves.len(), 3, "{:?}", state.message);
    assert!(state.doc.scene.cages.leaves[2].name.contains("mirror"));
    assert!(
        !state.rig_problems.is_empty(),
        "a mirror over the other half overlaps it"
    );
}

/// Rig mode shows, picks and moves the rest cages even while a pose is active; Pose mode shows
/// the pose again.
#[test]
fn rig_mode_shows_the_rest_cages_while_a_pose_is_active() {
    let mut harness = crate::common::bar_harness(false);
    let pose = harness
        .state()
        .state
        .doc
        .scene
        .poses
        .keys()
        .next()
        .unwrap()
        .clone();
    harness.state_mut().run(Command::SwitchPose(Some(pose)));
    settle(&mut harness);
    let scene = harness.state().state.doc.scene.clone();
    let v = (0..scene.pose.len())
        .find(|&v| scene.pose[v] != scene.cages.vertices[v])
        .expect("the pose moves some vertex") as u32;
    let on_screen = |h: &egui_kittest::Harness<'static, starcages_editor::EditorApp>| {
        vertex_on_screen(&h.state().state, v).unwrap()
    };
    let posed_at = on_screen(&harness);
    harness.key_press(egui::Key::Tab);
    harness.run_steps(2);
    let state = &harness.state().state;
    assert_eq!(state.shown_positions(), &scene.cages.vertices[..]);
    let rest_at = on_screen(&harness);
    assert!(rest_at.distance(posed_at) > 1.0, "the rest cage is shown");
    // Picking in Rig mode finds the vertex where its rest position is drawn.
    harness.hover_at(rest_at);
    harness.run_steps(2);
    assert_eq!(harness.state().state.selection.hovered, Some(v));
    // The pose is ghosted over the rest cages: faint lines in the ghost colour.
    let ghost_pixels = |h: &mut egui_kittest::Harness<'static, starcages_editor::EditorApp>| {
        let [r, g, b, _] = starcages_viewport::colors::to_u8(starcages_viewport::colors::GHOST);
        h.render()
            .unwrap()
            .pixels()
            .filter(|p| p.0[0].abs_diff(r) < 6 && p.0[1].abs_diff(g) < 6 && p.0[2].abs_diff(b) < 6)
            .count()
    };
    let in_rig_mode = ghost_pixels(&mut harness);
    harness.key_press(egui::Key::Tab);
    harness.run_steps(2);
    assert!(on_screen(&harness).distance(posed_at) < 1e-3);
    let in_pose_mode = ghost_pixels(&mut harness);
    assert!(
        in_rig_mode > in_pose_mode + 100,
        "ghost pixels: {in_rig_mode} in Rig mode, {in_pose_mode} in Pose mode"
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

/// Rig ▸ Subdivide cuts every face of every leaf cage into quads in one undo step; the rig
/// stays valid and bound, and undo gives back the cages.
#[test]
fn rig_menu_subdivides_every_cage_in_one_undo_step() {
    use egui::accesskit::Role;
    let mut harness = crate::common::bar_harness(true);
    let before = harness.state().state.doc.scene.clone();
    harness.get_by_role_and_label(Role::Button, "Rig").click();
    harness.run_steps(2);
    harness.get_by_label_contains("Subdivide").click();
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    let scene = &state.doc.scene;
    assert!(scene.cages.leaves.iter().all(|c| c.faces.len() == 24));
    assert!(starcages_core::scene::validate_scene(scene).is_valid());
    assert_eq!(
        state.rig.as_ref().unwrap().bound_for.0.vertices.len(),
        scene.cages.vertices.len(),
        "the binding follows"
    );
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert_eq!(harness.state().state.doc.scene.cages, before.cages);
}

/// Live validation draws what is wrong: a box added over the bar's cages overlaps them, so it
/// (and the cages it overlaps) are drawn in the warning colour, the offending vertices as large
/// warning dots, and the pointer over one of them says why.
#[test]
fn an_invalid_rig_draws_its_problem_cages_in_the_warning_colour_with_the_reason_on_hover() {
    let mut harness = crate::common::bar_harness(true);
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::A);
    harness.run_steps(2);
    harness.get_by_label("Box around the whole mesh").click();
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    assert!(!state.rig_problems.is_empty());
    let added = state.doc.scene.cages.leaves.len() - 1;
    assert!(
        state.rig_warnings.cages.contains_key(&added),
        "the new box is warned: {:?}",
        state.rig_warnings
    );
    // The pointer over a vertex of the warned box: the reason next to it.
    let v = state.doc.scene.cages.leaves[added].faces[0][0];
    let rect = state.view.viewport;
    let at = state.shown_positions()[v as usize].as_vec3();
    let (pixel, _) = state.view.camera.project(at, rect.size).unwrap();
    let pointer = rect.min + pixel;
    harness.hover_at(egui::pos2(pointer.x, pointer.y));
    harness.run_steps(3);
    assert!(harness.state().state.selection.hovered.is_some());
    harness.get_by_label_contains("Problem here: ");
    // The warning colour is on screen.
    let image = harness.render().unwrap();
    let [r, g, b, _] = starcages_viewport::colors::to_u8(starcages_viewport::colors::WARNING);
    let warned = image
        .pixels()
        .filter(|p| p.0[0].abs_diff(r) < 30 && p.0[1].abs_diff(g) < 30 && p.0[2].abs_diff(b) < 40)
        .count();
    assert!(warned > 100, "{warned} warning-coloured pixels");
    harness.snapshot_options(
        "rig_mode_warnings",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
    // Undo: the rig is valid again and nothing is warned.
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.rig_warnings,
        starcages_editor::state::rig_warnings::RigWarnings::default()
    );
}

/// Ctrl+R's cut slides with the mouse before it is made: the preview follows the pointer along
/// the cage, a typed fraction overrides it, Esc drops the cut and Enter makes it there.
#[test]
fn the_loop_cut_slides_with_the_mouse_and_a_typed_fraction_places_it() {
    let mut harness = crate::common::bar_harness(true);
    harness
        .state_mut()
        .run(Command::InspectCage(Some(CageId::Leaf(0))));
    let rect = harness.state().state.view.viewport;
    let centre = rect.center();
    // Esc drops the cut: nothing changes.
    harness.hover_at(egui::pos2(centre.x, centre.y));
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::R);
    harness.run_steps(2);
    harness.get_by_label_contains("Loop cut 'cage_0_0_0' across X");
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    assert!(harness.state().ui.loop_cut.is_none());
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
    // The pointer at either side of the view slides the cut to different places.
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::R);
    let mut fractions = Vec::new();
    for x in [
        rect.min.x + 0.2 * rect.size.x,
        rect.min.x + 0.8 * rect.size.x,
    ] {
        harness.hover_at(egui::pos2(x, centre.y));
        harness.run_steps(2);
        fractions.push(harness.state().ui.loop_cut.as_ref().unwrap().t);
    }
    assert!(
        (fractions[0] - fractions[1]).abs() > 0.05,
        "the cut follows the pointer: {fractions:?}"
    );
    harness.snapshot_options(
        "rig_mode_loop_cut",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
    // A typed fraction wins; Enter cuts there.
    for text in ["0", ".", "2", "5"] {
        harness.event(egui::Event::Text(text.into()));
        harness.run_steps(1);
    }
    harness.get_by_label_contains("0.25 of the way  [typed 0.25]");
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
    settle(&mut harness);
    let scene = &harness.state().state.doc.scene;
    assert_eq!(scene.cages.leaves.len(), 3);
    assert!(starcages_core::scene::validate_scene(scene).is_valid());
    // The left cage spans x in [-1.1, 0] in the bar demo at this detail: the cut's vertices
    // sit a quarter of the way along it.
    let xs: Vec<f64> = scene.cages.vertices.iter().map(|p| p.x).collect();
    let (lo, hi) = (-1.1_f64, 0.0_f64);
    let expected = lo + 0.25 * (hi - lo);
    assert!(
        xs.iter().any(|x| (x - expected).abs() < 1e-9)
            || xs
                .iter()
                .any(|x| (x - (hi - 0.25 * (hi - lo))).abs() < 1e-9),
        "{xs:?}"
    );
}

/// The screen position of a leaf-cage face's centre, and the face of `cage` that looks most
/// toward the camera.
fn front_face_on_screen(
    state: &starcages_editor::state::EditorState,
    cage: usize,
) -> (usize, egui::Pos2) {
    let set = &state.doc.scene.cages;
    let eye = state.view.camera.eye().as_dvec3();
    let rest = &set.vertices;
    let (f, face) = set.leaves[cage]
        .faces
        .iter()
        .enumerate()
        .max_by(|(_, a), (_, b)| {
            let facing = |face: &Vec<u32>| {
                let p: Vec<DVec3> = face.iter().map(|&v| rest[v as usize]).collect();
                let centre = p.iter().sum::<DVec3>() / p.len() as f64;
                let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                normal.dot((eye - centre).normalize())
            };
            facing(a).total_cmp(&facing(b))
        })
        .unwrap();
    let corners: Vec<egui::Pos2> = face
        .iter()
        .map(|&v| vertex_on_screen(state, v).unwrap())
        .collect();
    let centre = corners
        .iter()
        .fold(egui::Vec2::ZERO, |sum, p| sum + p.to_vec2())
        / corners.len() as f32;
    (f, centre.to_pos2())
}

/// Face select mode: a click picks a leaf-cage face, Shift+click adds one, E extrudes every
/// selected face into its own cage in one undo step; a face shared with a neighbour is refused.
#[test]
fn face_select_mode_picks_faces_and_e_extrudes_each_into_a_cage_in_one_step() {
    let mut harness = crate::common::bar_harness(true);
    harness.run_steps(2);
    harness.get_by_label("Face select").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.view.select_element,
        starcages_editor::state::SelectElement::CageFaces
    );
    let (left, right) = {
        let app = harness.state();
        (leaf(app, "cage_0_0_0"), leaf(app, "cage_1_0_0"))
    };
    let (left_face, left_at) = front_face_on_screen(&harness.state().state, left);
    let (right_face, right_at) = front_face_on_screen(&harness.state().state, right);
    harness.hover_at(left_at);
    harness.run_steps(1);
    harness.drag_at(left_at);
    harness.run_steps(1);
    harness.drop_at(left_at);
    harness.run_steps(2);
    let picked = harness
        .state()
        .state
        .selection
        .face_indices(&harness.state().state.doc.scene.cages);
    assert_eq!(
        picked,
        vec![(left, left_face)],
        "a click picks the face under it"
    );
    let shift = egui::Modifiers::SHIFT;
    harness.hover_at(right_at);
    harness.run_steps(1);
    for pressed in [true, false] {
        harness.event_modifiers(
            egui::Event::PointerButton {
                pos: right_at,
                button: egui::PointerButton::Primary,
                pressed,
                modifiers: shift,
            },
            shift,
        );
        harness.run_steps(1);
    }
    harness.run_steps(1);
    let state = &harness.state().state;
    let mut picked = state.selection.face_indices(&state.doc.scene.cages);
    picked.sort_unstable();
    assert_eq!(
        picked,
        vec![(left, left_face), (right, right_face)],
        "Shift adds"
    );
    assert_eq!(
        state.selection.vertices.len(),
        6,
        "their corners (one edge shared) are selected"
    );
    harness.snapshot_options(
        "rig_mode_face_select",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
    // E: one new cage per face, each sharing its face with its parent, as one undo step.
    harness.key_press(egui::Key::E);
    harness.run_steps(2);
    settle(&mut harness);
    let scene = harness.state().state.doc.scene.clone();
    assert_eq!(
        scene.cages.leaves.len(),
        4,
        "{:?}",
        harness.state().state.message
    );
    // Each new cage shares its face with its parent; the two new cages, pushed out of
    // neighbouring faces by the same distance, share the wall between them (as Blender's region
    // extrude keeps the common edge joined).
    assert_eq!(scene.cages.adjacency().len(), 4);
    assert!(starcages_core::scene::validate_scene(&scene).is_valid());
    assert_eq!(
        harness.state().state.selection.vertices.len(),
        6,
        "the two new caps are selected"
    );
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    settle(&mut harness);
    assert_eq!(
        harness.state().state.doc.scene.cages.leaves.len(),
        2,
        "one step"
    );
    // One face: E goes on as G; Esc keeps the extrusion at its default depth, as its own
    // undo step.
    harness.state_mut().run(Command::SelectFaces {
        faces: vec![(right, right_face)],
        mode: starcages_editor::state::SelectMode::Replace,
    });
    harness.key_press(egui::Key::E);
    harness.run_steps(2);
    assert!(harness.state().ui.tool.is_some(), "E starts G");
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 3);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
    // The face the two cages share cannot be extruded.
    let state = &harness.state().state;
    let set = &state.doc.scene.cages;
    let shared = set.leaves[left]
        .faces
        .iter()
        .position(|face| {
            let mut key = face.clone();
            key.sort_unstable();
            set.faces_by_vertex_set()
                .get(&key)
                .is_some_and(|cages| cages.len() > 1)
        })
        .unwrap();
    harness.state_mut().run(Command::SelectFaces {
        faces: vec![(left, shared)],
        mode: starcages_editor::state::SelectMode::Replace,
    });
    harness.key_press(egui::Key::E);
    harness.run_steps(2);
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.leaves.len(), 2);
    let message = format!("{:?}", state.message);
    assert!(message.contains("shared with a neighbour"), "{message}");
    // A selects every face in face select mode.
    harness.key_press(egui::Key::A);
    harness.run_steps(2);
    let state = &harness.state().state;
    let total: usize = state
        .doc
        .scene
        .cages
        .leaves
        .iter()
        .map(|c| c.faces.len())
        .sum();
    assert_eq!(
        state.selection.face_indices(&state.doc.scene.cages).len(),
        total
    );
}

/// I starts sizing an inset of the selected faces: the header says how thick, Esc drops it, a
/// typed thickness sets it exactly, Enter makes it (one undo step); the inner face stays
/// selected, so E then grows a cage that shares only the inner face's corners with its parent
/// (Blender's I then E).
#[test]
fn i_insets_the_selected_face_and_e_extrudes_the_inner_face() {
    let mut harness = crate::common::bar_harness(true);
    harness.run_steps(2);
    let left = leaf(harness.state(), "cage_0_0_0");
    let (face, _) = front_face_on_screen(&harness.state().state, left);
    let before = harness.state().state.doc.scene.clone();
    harness.state_mut().run(Command::SetSelectElement(
        starcages_editor::state::SelectElement::CageFaces,
    ));
    harness.state_mut().run(Command::SelectFaces {
        faces: vec![(left, face)],
        mode: starcages_editor::state::SelectMode::Replace,
    });
    harness.key_press(egui::Key::I);
    harness.run_steps(2);
    assert!(harness.state().ui.inset.is_some(), "I starts sizing");
    harness.get_by_label_contains("Inset 1 face");
    harness.snapshot_options(
        "rig_mode_inset",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    assert!(harness.state().ui.inset.is_none());
    assert_eq!(
        harness.state().state.doc.scene.cages,
        before.cages,
        "Esc drops it"
    );
    harness.key_press(egui::Key::I);
    harness.run_steps(2);
    harness.event(egui::Event::Text("0.05".into()));
    harness.run_steps(1);
    harness.get_by_label_contains("thickness 0.05");
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
    settle(&mut harness);
    let scene = harness.state().state.doc.scene.clone();
    assert_eq!(
        scene.cages.leaves[left].faces.len(),
        before.cages.leaves[left].faces.len() + 4,
        "{:?}",
        harness.state().state.message
    );
    assert_eq!(scene.cages.vertices.len(), before.cages.vertices.len() + 4);
    assert!(starcages_core::scene::validate_scene(&scene).is_valid());
    let inner: std::collections::BTreeSet<u32> = scene.cages.leaves[left].faces[face]
        .iter()
        .copied()
        .collect();
    assert!(
        inner
            .iter()
            .all(|&v| v as usize >= before.cages.vertices.len())
    );
    // Each inner corner lies 0.05 inside both edges at its corner: 0.05·√2 from it on a
    // rectangle.
    let outer = &before.cages.leaves[left].faces[face];
    for (k, &v) in scene.cages.leaves[left].faces[face].iter().enumerate() {
        let from = before.cages.vertices[outer[k] as usize];
        let distance = scene.cages.vertices[v as usize].distance(from);
        assert!(
            (distance - 0.05 * 2f64.sqrt()).abs() < 1e-9,
            "corner {k}: {distance}"
        );
    }
    harness.key_press(egui::Key::E);
    harness.run_steps(2);
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    settle(&mut harness);
    let scene = harness.state().state.doc.scene.clone();
    assert_eq!(
        scene.cages.leaves.len(),
        before.cages.leaves.len() + 1,
        "{:?}",
        harness.state().state.message
    );
    let grown: std::collections::BTreeSet<u32> = scene
        .cages
        .leaves
        .last()
        .unwrap()
        .faces
        .iter()
        .flatten()
        .copied()
        .collect();
    let others: std::collections::BTreeSet<u32> = scene.cages.leaves
        [..scene.cages.leaves.len() - 1]
        .iter()
        .flat_map(|c| c.faces.iter().flatten().copied())
        .collect();
    assert_eq!(
        grown
            .intersection(&others)
            .copied()
            .collect::<std::collections::BTreeSet<u32>>(),
        inner,
        "the new cage touches its parent at the inner face only"
    );
    // Two undo steps: the extrusion, then the inset.
    for _ in 0..2 {
        harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
        harness.run_steps(2);
        settle(&mut harness);
    }
    assert_eq!(harness.state().state.doc.scene.cages, before.cages);
}

/// G with the pointer 40 points right of `to`, then the pointer moved onto `to`.
fn grab_from_beside_to(
    harness: &mut egui_kittest::Harness<'static, starcages_editor::EditorApp>,
    to: egui::Pos2,
) {
    harness.hover_at(to + egui::vec2(40.0, 0.0));
    harness.run_steps(1);
    harness.key_press(egui::Key::G);
    harness.run_steps(1);
    harness.hover_at(to);
    harness.run_steps(2);
}

/// Snapping: with "Snap to vertices" on, G puts the selection's nearest vertex exactly on the
/// cage vertex under the pointer; confirming in Rig mode merges the vertices that landed on
/// others, so a box moved against a cage shares its face (one undo step with the move).
#[test]
fn g_snaps_to_a_cage_vertex_and_rig_mode_welds_the_border_in_one_undo_step() {
    let mut harness = crate::common::bar_harness(true);
    let set = harness.state().state.doc.scene.cages.clone();
    let right = leaf(harness.state(), "cage_1_0_0");
    let corners: Vec<DVec3> = set.leaves[right]
        .faces
        .iter()
        .flatten()
        .map(|&v| set.vertices[v as usize])
        .collect();
    let (lo, hi) = starcages_core::cage::bounds_of(&corners);
    // A box a little beyond the right cage's +x face, as tall and deep.
    let gap = 0.3;
    harness
        .state_mut()
        .run(Command::Rig(starcages_core::rig::RigOp::AddBox {
            name: "beyond".into(),
            min: DVec3::new(hi.x + gap, lo.y, lo.z),
            max: DVec3::new(hi.x + gap + 0.5, hi.y, hi.z),
            kind: CoordinateKind::MeanValue,
        }));
    settle(&mut harness);
    let rest = harness.state().state.doc.scene.cages.vertices.clone();
    assert_eq!(rest.len(), 20);
    let near_face: Vec<u32> = (0..rest.len() as u32)
        .filter(|&v| rest[v as usize].x == hi.x + gap)
        .collect();
    assert_eq!(near_face.len(), 4);
    // The right cage's corner facing the box's first near corner: the snap target.
    let first = rest[near_face[0] as usize];
    let target = (0..rest.len() as u32)
        .find(|&v| rest[v as usize] == DVec3::new(hi.x, first.y, first.z))
        .unwrap();
    // Everything in view (the box reaches past the bar).
    harness.state_mut().run(Command::Camera(
        starcages_editor::commands::CameraChange::FrameAll,
    ));
    harness.run_steps(2);
    let target_on_screen = vertex_on_screen(&harness.state().state, target).unwrap();
    harness.state_mut().run(Command::Select {
        vertices: near_face.clone(),
        mode: starcages_editor::state::SelectMode::Replace,
    });
    // Snapping off: the pointer over the target moves the box freely (no snap).
    grab_from_beside_to(&mut harness, target_on_screen);
    assert!(
        harness
            .query_by_label_contains("snapped to vertex")
            .is_none()
    );
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    assert_eq!(harness.state().state.doc.scene.cages.vertices, rest);
    // Snapping on (the View panel's checkbox): the same move lands on the target.
    harness.get_by_label("Snap to vertices").click();
    harness.run_steps(1);
    grab_from_beside_to(&mut harness, target_on_screen);
    harness.get_by_label_contains(&format!("snapped to vertex {target}"));
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    let scene = &state.doc.scene;
    assert_eq!(scene.cages.vertices.len(), 16, "{:?}", state.message);
    assert_eq!(
        scene.cages.adjacency().len(),
        2,
        "the box shares its face now"
    );
    assert!(starcages_core::scene::validate_scene(scene).is_valid());
    assert_eq!(
        state.selection.vertices.len(),
        4,
        "the selection follows the weld"
    );
    assert!(
        state
            .selection
            .vertices
            .iter()
            .all(|&v| scene.cages.vertices[v as usize].x == hi.x),
        "the box's near face is the cage's far face"
    );
    // One undo step takes back the move and the weld.
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.vertices, rest);
    // A mouse drag of the selection snaps and welds the same way.
    harness.state_mut().run(Command::Select {
        vertices: near_face.clone(),
        mode: starcages_editor::state::SelectMode::Replace,
    });
    let grabbed = vertex_on_screen(&harness.state().state, near_face[0]).unwrap();
    harness.hover_at(grabbed);
    harness.run_steps(2);
    harness.drag_at(grabbed);
    harness.run_steps(1);
    for step in 1..=4 {
        let t = step as f32 / 4.0;
        harness.hover_at(grabbed + (target_on_screen - grabbed) * t);
        harness.run_steps(1);
    }
    harness.drop_at(target_on_screen);
    harness.run_steps(2);
    settle(&mut harness);
    let scene = &harness.state().state.doc.scene;
    assert_eq!(scene.cages.vertices.len(), 16);
    assert_eq!(scene.cages.adjacency().len(), 2);
}

/// Where mesh vertex `v` (welded, at rest) is drawn.
fn mesh_vertex_on_screen(state: &starcages_editor::state::EditorState, v: usize) -> egui::Pos2 {
    let rect = state.view.viewport;
    let p = state.doc.scene.mesh.welded_positions()[v].as_vec3();
    let (pixel, _) = state.view.camera.project(p, rect.size).unwrap();
    let at = rect.min + pixel;
    egui::pos2(at.x, at.y)
}

/// Drags from `from` to `to` in five steps with `modifiers` held.
fn drag_with(
    harness: &mut egui_kittest::Harness<'static, starcages_editor::EditorApp>,
    from: egui::Pos2,
    to: egui::Pos2,
    modifiers: egui::Modifiers,
    via: &[egui::Pos2],
) {
    let press = |harness: &mut egui_kittest::Harness<'static, starcages_editor::EditorApp>,
                 pos: egui::Pos2,
                 pressed: bool| {
        harness.event_modifiers(
            egui::Event::PointerButton {
                pos,
                button: egui::PointerButton::Primary,
                pressed,
                modifiers,
            },
            modifiers,
        );
        harness.run_steps(1);
    };
    harness.hover_at(from);
    harness.run_steps(1);
    press(harness, from, true);
    for &p in via.iter().chain([&to]) {
        harness.event_modifiers(egui::Event::PointerMoved(p), modifiers);
        harness.run_steps(1);
    }
    press(harness, to, false);
    harness.run_steps(1);
}

/// Mesh select mode picks a region of the mesh with a rectangle or a Ctrl lasso; Shift+A's
/// menu puts a box around it (undoable), or a cube in the part of the mesh under the pointer.
#[test]
fn mesh_select_and_the_add_menu_box_a_region_of_the_mesh() {
    let mut harness = crate::common::bar_harness(true);
    harness.run_steps(2);
    harness.get_by_label("Mesh select").click();
    harness.run_steps(2);
    let state = &harness.state().state;
    let count = state.doc.scene.mesh.welded_positions().len();
    let on_screen: Vec<egui::Pos2> = (0..count)
        .map(|v| mesh_vertex_on_screen(state, v))
        .collect();
    let (lo, hi) = on_screen.iter().fold(
        (
            egui::pos2(f32::INFINITY, f32::INFINITY),
            egui::pos2(0.0, 0.0),
        ),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    // A rectangle over the left third of the drawn mesh.
    let a = lo - egui::vec2(5.0, 5.0);
    let b = egui::pos2(lo.x + (hi.x - lo.x) / 3.0, hi.y + 5.0);
    drag_with(&mut harness, a, b, egui::Modifiers::NONE, &[]);
    let state = &harness.state().state;
    let inside = |p: &egui::Pos2| p.x >= a.x && p.x <= b.x && p.y >= a.y && p.y <= b.y;
    let expected: std::collections::BTreeSet<u32> = (0..count as u32)
        .filter(|&v| inside(&on_screen[v as usize]))
        .collect();
    assert!(!expected.is_empty() && expected.len() < count);
    assert_eq!(
        state.selection.mesh_vertices, expected,
        "the rectangle's vertices"
    );
    assert!(
        state.selection.vertices.is_empty(),
        "no cage vertex was picked"
    );
    harness.get_by_label_contains(&format!("Mesh select ({})", expected.len()));
    harness.snapshot_options(
        "rig_mode_mesh_select",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
    // Shift+A ▸ Box around the selected mesh vertices: a cage holding exactly that region.
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::A);
    harness.run_steps(2);
    harness.snapshot_options(
        "rig_mode_add_menu",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
    harness
        .get_by_label("Box around the selected mesh vertices")
        .click();
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    let scene = &state.doc.scene;
    assert_eq!(scene.cages.leaves.len(), 3, "{:?}", state.message);
    assert!(harness.state().ui.add_menu.is_none(), "the menu closed");
    let boxed: Vec<DVec3> = scene.cages.leaves[2]
        .faces
        .iter()
        .flatten()
        .map(|&v| scene.cages.vertices[v as usize])
        .collect();
    let (box_lo, box_hi) = starcages_core::cage::bounds_of(&boxed);
    let rest = scene.mesh.welded_positions();
    for &v in &expected {
        let p = rest[v as usize];
        assert!(
            p.cmpge(box_lo).all() && p.cmple(box_hi).all(),
            "{p} outside the box"
        );
    }
    let (mesh_lo, mesh_hi) = scene.mesh.bounds();
    assert!(
        box_hi.x < mesh_hi.x,
        "the box holds a region, not the whole mesh"
    );
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
    // A Ctrl lasso (a triangle) replaces the mesh selection with what it encloses.
    let centre = egui::pos2(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y));
    let corners = [
        centre + egui::vec2(-60.0, 40.0),
        centre + egui::vec2(0.0, -60.0),
        centre + egui::vec2(60.0, 40.0),
    ];
    drag_with(
        &mut harness,
        corners[0],
        corners[0] + egui::vec2(1.0, 0.0),
        egui::Modifiers::COMMAND,
        &[corners[1], corners[2]],
    );
    let state = &harness.state().state;
    let lassoed = &state.selection.mesh_vertices;
    assert!(!lassoed.is_empty());
    for &v in lassoed {
        let p = on_screen[v as usize];
        assert!(
            p.x >= corners[0].x
                && p.x <= corners[2].x
                && p.y >= corners[1].y
                && p.y <= corners[0].y,
            "{p:?} outside the lasso's bounds"
        );
    }
    // Shift+A ▸ Box at the pointer, over the middle of the bar: a cube inside its extent.
    harness.hover_at(centre);
    harness.run_steps(1);
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::A);
    harness.run_steps(2);
    harness.get_by_label("Box at the pointer").click();
    harness.run_steps(2);
    settle(&mut harness);
    let scene = &harness.state().state.doc.scene;
    assert_eq!(scene.cages.leaves.len(), 3);
    let cube: Vec<DVec3> = scene.cages.leaves[2]
        .faces
        .iter()
        .flatten()
        .map(|&v| scene.cages.vertices[v as usize])
        .collect();
    let (cube_lo, cube_hi) = starcages_core::cage::bounds_of(&cube);
    let middle = 0.5 * (cube_lo + cube_hi);
    assert!(
        middle.cmpge(mesh_lo).all() && middle.cmple(mesh_hi).all(),
        "the cube sits in the mesh: {middle}"
    );
    let edge = cube_hi - cube_lo;
    assert!((edge.x - edge.y).abs() < 1e-9 && (edge.x - edge.z).abs() < 1e-9);
    assert!(edge.x < (mesh_hi - mesh_lo).length() * 0.5);
    // A selects every mesh vertex in mesh select mode.
    harness.key_press(egui::Key::A);
    harness.run_steps(2);
    let state = &harness.state().state;
    assert_eq!(state.selection.mesh_vertices.len(), count);
    // Esc closes the menu without adding anything.
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::A);
    harness.run_steps(2);
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    assert!(harness.state().ui.add_menu.is_none());
    assert!(harness.query_by_label("Box at the pointer").is_none());
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 3);
}

/// Rig ▸ Auto rig… asks for the detail, internal cages and symmetry first; Cancel changes
/// nothing, Make rig starts the auto rig with what was chosen (no internal cages, symmetric
/// across x: every leaf vertex has the twin X mirror editing moves with it).
#[test]
fn rig_auto_rig_asks_for_detail_internal_cages_and_symmetry_first() {
    let mut harness = harness();
    let before = harness.state().state.doc.scene.cages.clone();
    harness.get_by_label("Rig").click();
    harness.run_steps(2);
    harness.get_by_label("Auto rig…").click();
    harness.run_steps(2);
    assert!(harness.state().ui.autorig_dialog.is_some());
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    assert!(harness.state().ui.autorig_dialog.is_none());
    assert!(harness.state().state.autorig_job.is_none());
    assert_eq!(harness.state().state.doc.scene.cages, before);
    harness.get_by_label("Rig").click();
    harness.run_steps(2);
    harness.get_by_label("Auto rig…").click();
    harness.run_steps(2);
    harness
        .state_mut()
        .ui
        .autorig_dialog
        .as_mut()
        .unwrap()
        .internal = false;
    harness.get_by_label("Symmetry").click();
    harness.run_steps(2);
    harness.get_by_label("Across x").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().ui.autorig_dialog.map(|d| d.mirror),
        Some(starcages_core::generate::Mirror::Axis(0))
    );
    harness.get_by_label("Make rig").click();
    harness.run_steps(2);
    settle(&mut harness);
    let scene = &harness.state().state.doc.scene;
    assert_ne!(scene.cages, before, "the auto rig replaced the rig");
    assert!(
        scene.cages.internals.is_empty(),
        "no internal cages, as chosen"
    );
    // X mirror editing finds every leaf vertex's twin (the mesh is centred on x = 0, so the
    // rig is symmetric across that plane, as mirror editing takes it).
    let partners = starcages_editor::state::mirror::partners(&scene.cages.vertices);
    assert!(
        scene
            .cages
            .leaves
            .iter()
            .flat_map(|l| l.faces.iter().flatten())
            .all(|&v| partners[v as usize].is_some()),
        "the rig is its own mirror image across x = 0"
    );
}

/// File ▸ New from mesh with Symmetry "Across x": the auto rig that follows the grid is its own
/// mirror image across x = 0, so X mirror editing finds every leaf vertex's twin.
#[test]
fn a_new_mesh_can_open_in_a_symmetric_auto_rig() {
    let dir = scratch("new-mesh-mirror");
    let mesh = dir.join("critter.obj");
    let critter = starcages_core::generate::demo::demo_scene("critter", 0.3).unwrap();
    starcages_core::scene::write_deformed_mesh(&mesh, &critter, critter.mesh.welded_positions())
        .unwrap();
    let mut app = app_on(critter);
    let options = starcages_editor::state::NewMeshOptions {
        mirror: starcages_core::generate::Mirror::Axis(0),
        ..Default::default()
    };
    open_mesh_with_until_read(&mut app, &mesh, options);
    app.wait_for_jobs();
    let scene = &app.state.doc.scene;
    let names: Vec<&str> = scene.cages.leaves.iter().map(|l| l.name.as_str()).collect();
    assert!(
        names.contains(&"body_1"),
        "the auto rig replaced the grid: {names:?}"
    );
    let partners = starcages_editor::state::mirror::partners(&scene.cages.vertices);
    let lonely = scene
        .cages
        .leaves
        .iter()
        .flat_map(|l| l.faces.iter().flatten())
        .filter(|&&v| partners[v as usize].is_none())
        .count();
    assert_eq!(lonely, 0, "leaf vertices without a mirror twin");
}
