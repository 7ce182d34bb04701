//! The real editor driven with egui_kittest on the software Vulkan driver: picking and dragging
//! a cage vertex, the coordinates combo, the h slider, undo and redo, save and reopen, a broken
//! file, and a snapshot of the main window.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use egui::accesskit::Role;
use egui_kittest::kittest::Queryable as _;
use egui_kittest::{Harness, SnapshotOptions};
use glam::Vec3;
use starcages_core::coords::CoordinateKind;
use starcages_core::scene::demo::demo_scene;
use starcages_editor::app::InfluenceChoice;
use starcages_editor::{Document, EditorApp};

fn document() -> Document {
    Document {
        scene: demo_scene("critter", 0.6).unwrap(),
        path: None,
        dirty: false,
    }
}

fn harness() -> Harness<'static, EditorApp> {
    let mut harness = Harness::builder()
        .with_size(egui::vec2(1280.0, 800.0))
        .wgpu()
        .build_eframe(|cc| {
            let mut app = starcages_editor::create(cc, document());
            app.show_timings = false;
            assert!(app.wait_for_bind(), "the demo binds");
            app
        });
    harness.run_steps(3);
    harness
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("starcages-editor-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Waits for a background bind to finish and lets the UI take it.
fn settle(harness: &mut Harness<'static, EditorApp>) {
    harness.state_mut().wait_for_bind();
    harness.run_steps(2);
}

fn leaf(app: &EditorApp, name: &str) -> usize {
    app.doc.scene.cages.leaf_index(name).unwrap()
}

#[test]
fn dragging_a_picked_vertex_moves_the_mesh_near_its_cage_only_and_undoes_in_one_step() {
    let mut harness = harness();
    let app = harness.state();
    // A corner of the lower front-left head cage: belongs to that cage only.
    let v = app.doc.scene.cages.leaves[leaf(app, "head_0_0_0")].faces[0][0];
    let before_pose = app.doc.scene.pose.clone();
    let before_mesh: Vec<Vec3> = app.deformed().to_vec();
    let start = app.vertex_on_screen(v).unwrap();
    harness.hover_at(start);
    harness.run_steps(2);
    assert_eq!(
        harness.state().view.style.hovered,
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
    let app = harness.state();
    assert!(app.view.style.selected.contains(&v));
    let moved = app.doc.scene.pose[v as usize].distance(before_pose[v as usize]);
    assert!(moved > 0.05, "the vertex moved {moved}");
    let others_still = (0..before_pose.len())
        .filter(|&u| u != v as usize)
        .all(|u| app.doc.scene.pose[u] == before_pose[u]);
    assert!(
        others_still,
        "only the dragged vertex moved (it has no children)"
    );
    // The mesh moved near the cage, and not at all far from it (the ears).
    let after_mesh = app.deformed();
    let changed = |i: usize| after_mesh[i] != before_mesh[i];
    assert!((0..after_mesh.len()).any(changed));
    let ear = leaf(app, "ear_right") as u32;
    let rig = app.rig.as_ref().unwrap();
    let ear_vertices: Vec<usize> = (0..after_mesh.len())
        .filter(|&i| rig.binding.cage_of[i] == ear)
        .collect();
    assert!(!ear_vertices.is_empty());
    assert!(
        ear_vertices.iter().all(|&i| !changed(i)),
        "the far ear moved"
    );
    // One undo step for the whole drag, and redo brings it back.
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert_eq!(harness.state().doc.scene.pose, before_pose);
    let restored = harness.state().deformed().to_vec();
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
    assert!(harness.state().doc.scene.pose[v as usize].distance(before_pose[v as usize]) > 0.05);
    assert!(harness.state().doc.dirty);
    assert!(harness.state().doc.title().starts_with('●'));
}

#[test]
fn the_coordinates_combo_changes_a_cage_kind_and_undo_restores_it() {
    let mut harness = harness();
    harness.get_by_label("ear_left (mvc)").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().view.selected_cage,
        Some(leaf(harness.state(), "ear_left"))
    );
    harness.get_by_label("Coordinates").click();
    harness.run_steps(2);
    harness.get_by_label("Green (GC)").click();
    harness.run_steps(2);
    settle(&mut harness);
    let app = harness.state();
    assert_eq!(
        app.doc.scene.cages.leaves[leaf(app, "ear_left")].kind,
        CoordinateKind::Green
    );
    assert!(app.rig.is_some());
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    settle(&mut harness);
    let app = harness.state();
    assert_eq!(
        app.doc.scene.cages.leaves[leaf(app, "ear_left")].kind,
        CoordinateKind::MeanValue
    );
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Y);
    harness.run_steps(2);
    let app = harness.state();
    assert_eq!(
        app.doc.scene.cages.leaves[leaf(app, "ear_left")].kind,
        CoordinateKind::Green
    );
}

#[test]
fn the_h_slider_changes_the_influence_map() {
    let mut harness = harness();
    harness.get_by_label("head_0_0_0 (mvc)").click();
    harness.run_steps(2);
    harness.state_mut().view.influence = InfluenceChoice::SelectedCage;
    harness.run_steps(2);
    let before = harness.state().map_values().unwrap().values.clone();
    harness
        .get_by_role_and_label(Role::Slider, "h")
        .set_value_accesskit(0.15);
    harness.run_steps(2);
    settle(&mut harness);
    let app = harness.state();
    let cage = leaf(app, "head_0_0_0");
    assert_eq!(app.doc.scene.cages.leaves[cage].h, Some(0.15));
    let after = app.map_values().unwrap().values.clone();
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
    let app = harness.state();
    assert_eq!(app.doc.scene.cages.leaves[leaf(app, "head_0_0_0")].h, None);
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Y);
    harness.run_steps(2);
    let app = harness.state();
    assert_eq!(
        app.doc.scene.cages.leaves[leaf(app, "head_0_0_0")].h,
        Some(0.15)
    );
}

#[test]
fn grab_with_an_axis_lock_and_a_typed_distance_then_cancel_a_rotation() {
    let mut harness = harness();
    let app = harness.state_mut();
    let v = app.doc.scene.cages.leaves[leaf(app, "head_1_0_0")].faces[0][0];
    app.select_vertex(v, false);
    let start = app.doc.scene.pose[v as usize];
    let centre = app.view.viewport.center();
    harness.hover_at(centre);
    harness.key_press(egui::Key::G);
    harness.run_steps(1);
    assert!(harness.state().tool.is_some());
    for text in ["z", "0", ".", "2", "5"] {
        harness.event(egui::Event::Text(text.into()));
        harness.run_steps(1);
    }
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
    let app = harness.state();
    assert!(app.tool.is_none());
    let moved = app.doc.scene.pose[v as usize] - start;
    assert!(
        (moved - glam::DVec3::new(0.0, 0.0, 0.25)).length() < 1e-12,
        "{moved}"
    );
    // R, move the mouse, Esc: nothing changes and nothing is recorded.
    let after_grab = app.doc.scene.pose.clone();
    harness.key_press(egui::Key::R);
    harness.run_steps(1);
    harness.hover_at(centre + egui::vec2(80.0, 40.0));
    harness.run_steps(2);
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    assert_eq!(harness.state().doc.scene.pose, after_grab);
    assert_eq!(harness.state().undo.undo_label(), Some("grab"));
}

#[test]
fn save_and_reopen_gives_the_same_scene_and_a_broken_file_leaves_the_app_usable() {
    let mut harness = harness();
    let dir = scratch("save");
    let path = dir.join("critter.json");
    {
        let app = harness.state_mut();
        app.apply_moves(&[(0, app.doc.scene.pose[0] + glam::DVec3::new(0.1, 0.0, 0.0))]);
        assert!(app.doc.dirty);
        assert!(app.save_as(&path));
        assert!(!app.doc.dirty);
    }
    let reopened = Document::open(&path).unwrap();
    assert_eq!(reopened.scene, harness.state().doc.scene);
    // And through the app: open (on a worker), the same scene, clean, bound again.
    let saved = harness.state().doc.scene.clone();
    harness.state_mut().open(&path);
    assert!(harness.state_mut().poll_load(true));
    settle(&mut harness);
    assert_eq!(harness.state().doc.scene, saved);
    assert!(!harness.state().doc.dirty);
    assert!(harness.state().rig.is_some());
    // A broken file: an error in the status bar, the scene untouched.
    let broken = dir.join("broken.json");
    std::fs::write(
        &broken,
        "{ \"format\": \"starcages-scene\", \"version\": 1, ",
    )
    .unwrap();
    let scene_before = harness.state().doc.scene.clone();
    harness.state_mut().open(&broken);
    assert!(
        harness.state().load.is_some(),
        "opening runs in the background"
    );
    assert!(!harness.state_mut().poll_load(true));
    harness.run_steps(2);
    let app = harness.state();
    let message = app.message.clone().unwrap();
    assert!(
        message.error && message.text.contains("broken.json"),
        "{}",
        message.text
    );
    assert_eq!(app.doc.scene, scene_before);
    harness.get_by_label_contains("broken.json");
    // Still usable: the selection and an edit work.
    harness.key_press(egui::Key::A);
    harness.run_steps(2);
    assert!(!harness.state().view.style.selected.is_empty());
    let _ = Path::new("unused");
}

#[test]
fn main_window_snapshot() {
    let mut harness = harness();
    harness.state_mut().view.influence = InfluenceChoice::AllCages;
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
fn a_bind_runs_in_the_background_and_cancel_keeps_the_previous_binding() {
    let mut harness = harness();
    let old = std::sync::Arc::clone(&harness.state().rig.as_ref().unwrap().binding);
    // A fine HC grid makes the ears cage's bind slow enough to cancel.
    harness
        .state_mut()
        .edit_scene("HC grid", |scene| scene.settings.harmonic.resolution = 128);
    assert!(harness.state().job.is_some());
    let mut frames = Vec::new();
    for _ in 0..5 {
        let start = std::time::Instant::now();
        harness.step();
        frames.push(start.elapsed().as_secs_f64() * 1e3);
    }
    frames.sort_by(f64::total_cmp);
    assert!(frames[2] < 50.0, "UI frames while binding: {frames:?} ms");
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    let app = harness.state_mut();
    assert!(!app.wait_for_bind(), "the cancelled bind was installed");
    let message = app.message.clone().unwrap();
    assert!(
        message.error && message.text.contains("cancelled"),
        "{}",
        message.text
    );
    assert!(std::sync::Arc::ptr_eq(
        &old,
        &app.rig.as_ref().unwrap().binding
    ));
}

#[test]
fn adding_an_internal_cage_around_the_selection_is_an_undoable_hierarchy_edit() {
    let mut harness = harness();
    let ears = harness
        .state()
        .doc
        .scene
        .cages
        .cage_vertices("ear_left")
        .unwrap();
    // The ear's lower vertices belong to the head cage; its top ones to the ears cage.
    let app = harness.state_mut();
    app.view.style.selected = ears.iter().copied().collect();
    app.add_internal_cage_around_selection(CoordinateKind::MeanValue);
    let message = app.message.clone().unwrap();
    assert!(
        message.error && message.text.contains("already owned"),
        "{}",
        message.text
    );
    assert_eq!(app.doc.scene.cages.internals.len(), 2);
    // Unowned vertices: a new top-level cage over the head cage's own vertices.
    let head = app.doc.scene.cages.cage_vertices("head").unwrap();
    app.view.style.selected = head.iter().copied().collect();
    app.add_internal_cage_around_selection(CoordinateKind::Harmonic);
    settle(&mut harness);
    let app = harness.state_mut();
    assert_eq!(app.doc.scene.cages.internals.len(), 3);
    assert!(
        app.rig
            .as_ref()
            .unwrap()
            .hierarchy
            .parent_of(head[0])
            .is_some()
    );
    app.undo();
    settle(&mut harness);
    assert_eq!(harness.state().doc.scene.cages.internals.len(), 2);
}

#[test]
fn an_internal_cage_kind_change_rebinds_the_hierarchy_only() {
    let mut harness = harness();
    let old = std::sync::Arc::clone(&harness.state().rig.as_ref().unwrap().binding);
    let leaves = harness.state().doc.scene.cages.leaves.len();
    harness
        .state_mut()
        .set_cage_kind(leaves, CoordinateKind::MeanValue); // the ears cage
    settle(&mut harness);
    let app = harness.state();
    assert_eq!(
        app.doc.scene.cages.internals[0].kind,
        CoordinateKind::MeanValue
    );
    assert!(
        std::sync::Arc::ptr_eq(&old, &app.rig.as_ref().unwrap().binding),
        "the mesh was rebound"
    );
}

#[test]
fn x_mirror_editing_moves_the_partner_vertex() {
    let mut harness = harness();
    let app = harness.state_mut();
    app.view.mirror_x = true;
    let rest = app.doc.scene.cages.vertices.clone();
    let v = (0..rest.len()).find(|&i| rest[i].x < -1.0).unwrap() as u32;
    let partner = (0..rest.len())
        .find(|&i| {
            (rest[i]
                - glam::DVec3::new(-rest[v as usize].x, rest[v as usize].y, rest[v as usize].z))
            .length()
                < 1e-9
        })
        .unwrap();
    let target = rest[v as usize] + glam::DVec3::new(-0.2, 0.1, 0.3);
    app.apply_moves(&[(v, target)]);
    let moved = app.doc.scene.pose[partner];
    assert!(
        (moved - glam::DVec3::new(-target.x, target.y, target.z)).length() < 1e-12,
        "{moved}"
    );
}

#[test]
fn opening_over_unsaved_work_asks_first() {
    let mut harness = harness();
    let path = scratch("prompt").join("saved.json");
    assert!(harness.state_mut().save_as(&path));
    {
        let app = harness.state_mut();
        app.apply_moves(&[(0, app.doc.scene.pose[0] + glam::DVec3::Z * 0.2)]);
        assert!(app.doc.dirty);
        starcages_editor::panels::request_open(app, path.clone());
        assert!(app.load.is_none(), "nothing opens before the answer");
    }
    harness.run_steps(2);
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    assert!(harness.state().pending.is_none() && harness.state().doc.dirty);
    starcages_editor::panels::request_open(harness.state_mut(), path.clone());
    harness.run_steps(2);
    harness.get_by_label("Don't save").click();
    harness.run_steps(2);
    let app = harness.state_mut();
    assert!(app.poll_load(true));
    assert!(!app.doc.dirty);
    assert_eq!(app.doc.path.as_deref(), Some(path.as_path()));
}
