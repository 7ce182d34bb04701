//! The real editor through egui_kittest: picking and dragging a cage vertex, the coordinates
//! combo, the h slider, G with an axis lock, X mirroring, menus, keys, tooltips, poses, the
//! main window's snapshot.

use egui::accesskit::Role;
use egui_kittest::SnapshotOptions;
use egui_kittest::kittest::Queryable as _;
use glam::{DVec3, Vec3};
use starcages_core::coords::CoordinateKind;
use starcages_editor::Command;
use starcages_editor::state::InfluenceChoice;
use starcages_editor::ui::vertex_on_screen;

use crate::common::{cage, harness, leaf, press, press_with, send, send_and_settle, settle, undo};

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
    app.ui
        .files
        .request(FilePurpose::SaveScene, "scene.json".into(), None);
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
    send(&mut harness, Command::MoveVertices(vec![(v, moved * 1.5)]));
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
    send_and_settle(
        &mut harness,
        Command::SetInfluence(InfluenceChoice::JoinWeight),
    );
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

/// T and Shift+T (View ▸ Outliner, View ▸ Properties panel) hide and show the side panels; N's
/// Item panel brings the right panel back.
#[test]
fn t_and_shift_t_hide_the_side_panels_and_the_view_menu_names_them() {
    let mut harness = harness();
    let viewport_width = |harness: &egui_kittest::Harness<'static, starcages_editor::EditorApp>| {
        harness.state().state.view.viewport.size.x
    };
    let full = viewport_width(&harness);
    harness.get_by_label("Outliner");
    press(&mut harness, egui::Key::T);
    assert!(
        harness.query_by_label("Outliner").is_none(),
        "T hid the outliner"
    );
    let without_outliner = viewport_width(&harness);
    assert!(
        without_outliner > full + 100.0,
        "{full} -> {without_outliner}"
    );
    press_with(&mut harness, egui::Modifiers::SHIFT, egui::Key::T);
    assert!(
        harness.query_by_label("Scene settings").is_none(),
        "Shift+T hid the properties"
    );
    assert!(viewport_width(&harness) > without_outliner + 100.0);
    press(&mut harness, egui::Key::N);
    harness.get_by_label("Item");
    harness.get_by_label("Scene settings");
    press(&mut harness, egui::Key::T);
    harness.get_by_label("Outliner");
    harness
        .get_all_by_label("View")
        .next()
        .expect("the View menu")
        .click();
    harness.run_steps(2);
    harness.get_by_label_contains("Properties panel");
}

/// In a small window the side panels give way first: the viewport keeps at least half the
/// window's width, and the panels come back when the window is wide again.
#[test]
fn a_small_window_keeps_half_of_its_width_for_the_viewport() {
    for (width, height) in [(640.0, 420.0), (420.0, 300.0), (900.0, 600.0)] {
        let (mut harness, _) =
            crate::common::harness_sized(crate::common::document(), egui::vec2(width, height));
        harness.run_steps(2);
        let viewport = harness.state().state.view.viewport.size.x;
        assert!(
            viewport >= 0.5 * width - 1.0,
            "{width}×{height}: viewport {viewport}"
        );
    }
}

/// Alt+Z (View ▸ X-ray) turns X-ray on and off; its mesh opacity slider shows while it is on,
/// the cage opacity slider always.
#[test]
fn alt_z_toggles_x_ray_and_its_opacity_slider() {
    let mut harness = harness();
    assert!(harness.query_all_by_label_contains("Cage opacity").count() > 0);
    assert!(harness.query_by_label_contains("Mesh opacity").is_none());
    press_with(&mut harness, egui::Modifiers::ALT, egui::Key::Z);
    assert!(harness.state().state.view.layers.xray);
    assert!(harness.query_all_by_label_contains("Mesh opacity").count() > 0);
    press_with(&mut harness, egui::Modifiers::ALT, egui::Key::Z);
    assert!(!harness.state().state.view.layers.xray);
}
