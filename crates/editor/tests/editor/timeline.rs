//! The timeline through egui_kittest, with Blender's keys: Up/Down to the next and previous
//! key, Shift+Left/Right to the ends, Space to play and stop, I to key the pose, Alt+I and X to
//! delete a key; edits at a keyed frame update its key, auto-key adds keys; every key edit is
//! one undo step; a cage point cache imports as keys.

use egui::{Key, Modifiers};
use egui_kittest::SnapshotOptions;
use egui_kittest::kittest::Queryable as _;
use glam::{DVec3, Vec3};
use starcages_editor::{Command, EditorApp};

use crate::common::{harness, leaf, press_with, scratch, send};

type Harness = egui_kittest::Harness<'static, EditorApp>;

fn frame(harness: &Harness) -> f64 {
    harness.state().state.timeline.frame
}

fn key_frames(harness: &Harness) -> Vec<f64> {
    let keys = &harness.state().state.doc.scene.animation.keys;
    keys.iter().map(|k| k.frame).collect()
}

#[test]
fn keys_navigate_play_insert_and_delete_as_in_blender_and_undo_one_step_each() {
    let mut harness = harness();
    harness.get_by_label("Timeline");
    // The critter ships keys at 1, 12 and 24; the timeline starts at the first frame.
    assert_eq!(key_frames(&harness), vec![1.0, 12.0, 24.0]);
    assert_eq!(frame(&harness), 1.0);
    press_with(&mut harness, Modifiers::NONE, Key::ArrowUp);
    assert_eq!(frame(&harness), 12.0);
    // At a key the cages stand in its pose, and the mesh follows.
    let app = harness.state();
    let scene = &app.state.doc.scene;
    assert_eq!(scene.pose, scene.poses["ears_back"]);
    let deformed_at_key = app.state.rig.as_ref().unwrap().deformed().clone();
    press_with(&mut harness, Modifiers::SHIFT, Key::ArrowRight);
    assert_eq!(frame(&harness), 24.0);
    let rest_again = harness
        .state()
        .state
        .rig
        .as_ref()
        .unwrap()
        .deformed()
        .clone();
    assert_ne!(deformed_at_key, rest_again, "the mesh moved with the frame");
    press_with(&mut harness, Modifiers::NONE, Key::ArrowDown);
    assert_eq!(frame(&harness), 12.0);
    press_with(&mut harness, Modifiers::SHIFT, Key::ArrowLeft);
    assert_eq!(frame(&harness), 1.0);
    // Space plays in real time and stops.
    press_with(&mut harness, Modifiers::NONE, Key::Space);
    assert!(harness.state().state.timeline.playing.is_some());
    std::thread::sleep(std::time::Duration::from_millis(200));
    harness.run_steps(2);
    assert!(frame(&harness) > 1.0, "playback advanced");
    press_with(&mut harness, Modifiers::NONE, Key::Space);
    assert!(harness.state().state.timeline.playing.is_none());
    // Frame 5 has no key: a move without auto-key makes none; I keys the pose.
    harness.state_mut().run(Command::SetFrame(5.0));
    let app = harness.state_mut();
    let v = app.state.doc.scene.cages.leaves[leaf(app, "ear_left")].faces[0][0];
    let moved = app.state.doc.scene.pose[v as usize] + DVec3::new(0.0, 0.0, 0.2);
    app.run(Command::MoveVertices(vec![(v, moved)]));
    harness.run_steps(1);
    assert_eq!(key_frames(&harness), vec![1.0, 12.0, 24.0]);
    press_with(&mut harness, Modifiers::NONE, Key::I);
    assert_eq!(key_frames(&harness), vec![1.0, 5.0, 12.0, 24.0]);
    let key_pose = |harness: &Harness| {
        let scene = &harness.state().state.doc.scene;
        let k = scene.animation.key_at(5.0).unwrap();
        scene.poses[&scene.animation.keys[k].pose][v as usize]
    };
    assert_eq!(key_pose(&harness), moved);
    // At a keyed frame an edit updates the key, in the edit's own undo step.
    let further = moved + DVec3::new(0.1, 0.0, 0.0);
    send(&mut harness, Command::MoveVertices(vec![(v, further)]));
    assert_eq!(key_pose(&harness), further);
    press_with(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(key_pose(&harness), moved);
    press_with(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(key_frames(&harness), vec![1.0, 12.0, 24.0], "I undone");
    press_with(&mut harness, Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    assert_eq!(key_frames(&harness), vec![1.0, 5.0, 12.0, 24.0], "I redone");
    // Alt+I deletes the key at the current frame; X the key selected on the timeline.
    press_with(&mut harness, Modifiers::ALT, Key::I);
    assert_eq!(key_frames(&harness), vec![1.0, 12.0, 24.0]);
    harness.state_mut().ui.selected_key = Some(24.0);
    press_with(&mut harness, Modifiers::NONE, Key::X);
    assert_eq!(key_frames(&harness), vec![1.0, 12.0]);
    press_with(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(key_frames(&harness), vec![1.0, 12.0, 24.0]);
    // Auto-key: an edit at a frame without a key inserts one.
    harness.get_by_label("Auto-key").click();
    harness.run_steps(2);
    assert!(harness.state().state.timeline.auto_key);
    harness.state_mut().run(Command::SetFrame(8.0));
    send(&mut harness, Command::MoveVertices(vec![(v, further)]));
    assert_eq!(key_frames(&harness), vec![1.0, 8.0, 12.0, 24.0]);
    // Retiming keeps the order; a frame with a key already is refused.
    harness.state_mut().run(Command::MoveKey {
        from: 8.0,
        to: 16.0,
    });
    assert_eq!(key_frames(&harness), vec![1.0, 12.0, 16.0, 24.0]);
    harness.state_mut().run(Command::MoveKey {
        from: 16.0,
        to: 24.0,
    });
    assert_eq!(key_frames(&harness), vec![1.0, 12.0, 16.0, 24.0]);
    harness.run_steps(2);
    let message = harness.state().state.message.clone().unwrap();
    assert!(
        message.error && message.text.contains("has a key"),
        "{message:?}"
    );
}

#[test]
fn a_cage_point_cache_imports_as_keys_and_the_timeline_draws_them() {
    let mut harness = harness();
    let dir = scratch("cage-cache");
    let path = dir.join("wave.pc2");
    let app = harness.state();
    let scene = &app.state.doc.scene;
    let up = scene.export_up();
    let samples: Vec<Vec<Vec3>> = (0..3)
        .map(|k| {
            scene
                .cages
                .vertices
                .iter()
                .map(|p| {
                    up.from_scene(*p + DVec3::new(0.0, 0.0, 0.1 * k as f64))
                        .as_vec3()
                })
                .collect()
        })
        .collect();
    let times = starcages_core::anim::SampleTimes {
        start_frame: 30.0,
        frame_step: 1.0,
        fps: 24.0,
    };
    let count = scene.cages.vertices.len();
    let mut writer = starcages_io::PointCacheWriter::create(
        &path,
        starcages_io::PointCacheFormat::Pc2,
        count,
        3,
        times,
    )
    .unwrap();
    for sample in &samples {
        writer.write_sample(sample).unwrap();
    }
    writer.finish().unwrap();
    harness
        .state_mut()
        .run(Command::ImportCageAnimation(path.clone()));
    assert_eq!(
        key_frames(&harness),
        vec![1.0, 12.0, 24.0, 30.0, 31.0, 32.0]
    );
    assert_eq!(harness.state().state.doc.scene.animation.frame_end, 32);
    harness.state_mut().run(Command::SetFrame(31.0));
    let scene = &harness.state().state.doc.scene;
    let lifted = scene.pose[0] - scene.cages.vertices[0];
    assert!(
        (lifted - DVec3::new(0.0, 0.0, 0.1)).length() < 1e-6,
        "{lifted}"
    );
    // One undo step takes the whole import back.
    press_with(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(key_frames(&harness), vec![1.0, 12.0, 24.0]);
    // A cache of another vertex count is refused, saying why.
    let wrong = dir.join("wrong.pc2");
    let mut writer = starcages_io::PointCacheWriter::create(
        &wrong,
        starcages_io::PointCacheFormat::Pc2,
        3,
        1,
        times,
    )
    .unwrap();
    writer.write_sample(&[Vec3::ZERO; 3]).unwrap();
    writer.finish().unwrap();
    harness.state_mut().run(Command::ImportCageAnimation(wrong));
    harness.run_steps(2);
    let message = harness.state().state.message.clone().unwrap();
    assert!(message.text.contains("are needed here"), "{message:?}");
    // The message names a scratch folder with the process id: not in the snapshot.
    harness.state_mut().state.message = None;
    harness.state_mut().run(Command::SetFrame(12.0));
    harness.run_steps(3);
    harness.snapshot_options(
        "timeline",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
}

#[test]
fn dragging_on_the_timeline_scrubs_and_dragging_a_key_retimes_it() {
    let mut harness = harness();
    let rect = harness.get_by_label("Timeline").rect();
    // The critter's range is 1..24, drawn 14 points in from each end.
    let x = |frame: f32| rect.left() + 14.0 + (rect.width() - 28.0) * (frame - 1.0) / 23.0;
    let ticks_row = rect.top() + 10.0;
    harness.hover_at(egui::pos2(x(6.0), ticks_row));
    harness.run_steps(1);
    harness.drag_at(egui::pos2(x(6.0), ticks_row));
    harness.run_steps(1);
    harness.hover_at(egui::pos2(x(12.0), ticks_row));
    harness.run_steps(1);
    harness.drop_at(egui::pos2(x(18.0), ticks_row));
    harness.run_steps(2);
    assert_eq!(frame(&harness), 18.0);
    // The key at 12, by its diamond, to 16; one undo step puts it back.
    let diamonds = rect.bottom() - 8.5;
    harness.hover_at(egui::pos2(x(12.0), diamonds));
    harness.run_steps(1);
    harness.drag_at(egui::pos2(x(12.0), diamonds));
    harness.run_steps(1);
    harness.hover_at(egui::pos2(x(14.0), diamonds));
    harness.run_steps(1);
    harness.drop_at(egui::pos2(x(16.0), diamonds));
    harness.run_steps(2);
    assert_eq!(key_frames(&harness), vec![1.0, 16.0, 24.0]);
    assert_eq!(frame(&harness), 18.0, "retiming a key does not scrub");
    press_with(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(key_frames(&harness), vec![1.0, 12.0, 24.0]);
}

/// The editor poses a frame with core's posing engine, as the CLI and the bake do: at a keyed
/// frame an edit goes on from the key's hierarchy state and gives the cages
/// `deform --frame 12 --apply "head: rotate 0 0 1 10"` poses.
#[test]
fn an_edit_at_a_keyed_frame_gives_the_cages_the_cli_poses() {
    use starcages_core::hierarchy::CageEdit;
    use starcages_core::posing::{PoseRequest, PoseSource};
    let mut harness = harness();
    let edit: CageEdit = "head: rotate 0 0 1 10".parse().unwrap();
    let expected = PoseRequest {
        source: PoseSource::Frame(12.0),
        edits: vec![edit.clone()],
    }
    .resolve(&harness.state().state.doc.scene)
    .unwrap();
    send(&mut harness, Command::SetFrame(12.0));
    let app = harness.state_mut();
    let scene = &app.state.doc.scene;
    assert_eq!(scene.pose, scene.poses["ears_back"]);
    let moves = edit.moves(&scene.cages, &scene.pose).unwrap();
    app.run(Command::MoveVertices(moves));
    harness.run_steps(1);
    let scene = &harness.state().state.doc.scene;
    assert_eq!(scene.pose, expected.cages);
    assert_eq!(scene.pose_state, expected.state);
}
