//! Shared helpers: the harness on the critter demo, scratch folders, waiting for jobs.

use std::sync::{Arc, Mutex};

use egui_kittest::Harness;
use starcages_core::generate::demo::demo_scene;
use starcages_editor::commands::UnsavedAnswer;
use starcages_editor::{CageId, Command, Document, EditorApp};

/// The critter demo at a reduced detail.
pub fn document() -> Document {
    Document {
        scene: demo_scene("critter", 0.6).unwrap(),
        path: None,
        dirty: false,
    }
}

/// The real app on `doc` in a 1280×800 window rendered by wgpu, its first bind done; also
/// hands back egui-wgpu's render state (the viewport's GPU resources live in it).
pub fn harness_on(doc: Document) -> (Harness<'static, EditorApp>, egui_wgpu::RenderState) {
    harness_sized(doc, egui::vec2(1280.0, 800.0))
}

/// [`harness_on`] in a window of `size` points.
pub fn harness_sized(
    doc: Document,
    size: egui::Vec2,
) -> (Harness<'static, EditorApp>, egui_wgpu::RenderState) {
    let render_state = Arc::new(Mutex::new(None));
    let keep = Arc::clone(&render_state);
    let mut harness = Harness::builder()
        .with_size(size)
        .wgpu()
        .build_eframe(move |cc| {
            *keep.lock().unwrap() = cc.wgpu_render_state.clone();
            let mut app = starcages_editor::create(cc, doc);
            app.ui.show_timings = false;
            app.wait_for_jobs();
            assert!(app.state.rig.is_some(), "the scene binds");
            app
        });
    harness.run_steps(3);
    let render_state = render_state.lock().unwrap().take();
    (
        harness,
        render_state.expect("kittest gives eframe a wgpu render state"),
    )
}

/// The app on the critter demo.
pub fn harness() -> Harness<'static, EditorApp> {
    harness_on(document()).0
}

/// A fresh scratch folder for this test, removed when dropped.
pub fn scratch(name: &str) -> starcages_test_support::Scratch {
    starcages_test_support::Scratch::new(&format!("editor-{name}"))
}

/// Sends `command` as the UI would, then runs one frame for it to show.
pub fn send(harness: &mut Harness<'static, EditorApp>, command: Command) {
    harness.state_mut().run(command);
    harness.run_steps(1);
}

/// Sends `command`, then waits for the jobs it starts and lets the UI take them.
pub fn send_and_settle(harness: &mut Harness<'static, EditorApp>, command: Command) {
    harness.state_mut().run(command);
    settle(harness);
}

/// Waits for background jobs to finish and lets the UI take them.
pub fn settle(harness: &mut Harness<'static, EditorApp>) {
    harness.state_mut().wait_for_jobs();
    harness.run_steps(2);
}

/// The leaf cage called `name`.
pub fn leaf(app: &EditorApp, name: &str) -> usize {
    app.state.doc.scene.cages.leaf_index(name).unwrap()
}

/// The cage called `name`.
pub fn cage(app: &EditorApp, name: &str) -> CageId {
    CageId::by_name(&app.state.doc.scene.cages, name).unwrap()
}

/// The app on the bar demo (two cages side by side), the pointer over the viewport, in Rig
/// mode when `rig_mode`.
pub fn bar_harness(rig_mode: bool) -> Harness<'static, EditorApp> {
    let doc = Document {
        scene: demo_scene("bar", 0.3).unwrap(),
        path: None,
        dirty: false,
    };
    let (mut harness, _) = harness_on(doc);
    let centre = harness.state().state.view.viewport.center();
    harness.hover_at(egui::pos2(centre.x, centre.y));
    if rig_mode {
        harness.key_press(egui::Key::Tab);
        harness.run_steps(1);
    }
    harness
}

/// Ctrl+Z, and two frames for it to land.
pub fn undo(harness: &mut Harness<'static, EditorApp>) {
    press_with(harness, egui::Modifiers::COMMAND, egui::Key::Z);
}

/// `key`, and two frames for it to land.
pub fn press(harness: &mut Harness<'static, EditorApp>, key: egui::Key) {
    harness.key_press(key);
    harness.run_steps(2);
}

/// `key` with `modifiers`, and two frames for it to land.
pub fn press_with(
    harness: &mut Harness<'static, EditorApp>,
    modifiers: egui::Modifiers,
    key: egui::Key,
) {
    harness.key_press_modifiers(modifiers, key);
    harness.run_steps(2);
}

/// Runs `command` (an open, a new from mesh, a demo) and waits until the file is read
/// (binds may go on), then answers the unsaved-changes question if it is asked: the editor
/// asks only once the file has opened.
pub fn open_and_answer(app: &mut EditorApp, command: Command, answer: UnsavedAnswer) {
    app.run(command);
    while app.state.load_job.is_some() {
        app.state.poll_jobs(false);
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    if app.state.pending.is_some() {
        app.run(Command::AnswerUnsaved(answer));
    }
}
