//! The editor's files through egui_kittest: save and reopen, a broken file, the unsaved-changes
//! prompt on open, close and save, export refusing the scene's own mesh, the in-app file dialog,
//! the demos.

use egui::accesskit::Role;
use egui_kittest::SnapshotOptions;
use egui_kittest::kittest::Queryable as _;
use glam::DVec3;
use starcages_editor::{Command, Document};

use crate::common::{harness, leaf, press, scratch, send_and_settle, settle};

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
    send_and_settle(&mut harness, Command::Open(broken));
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

/// Opening over unsaved work reads the file first and asks once it has opened: Cancel keeps
/// the work and drops what was read, Don't save puts it in place.
#[test]
fn opening_over_unsaved_work_asks_once_the_file_is_read() {
    let mut harness = harness();
    let dir = scratch("prompt");
    let path = dir.join("saved.json");
    harness.state_mut().run(Command::SaveAs(path.clone()));
    let edited = {
        let app = harness.state_mut();
        let to = app.state.doc.scene.pose[0] + DVec3::Z * 0.2;
        app.run(Command::MoveVertices(vec![(0, to)]));
        assert!(app.state.doc.dirty);
        app.state.doc.scene.clone()
    };
    send_and_settle(&mut harness, Command::Open(path.clone()));
    {
        let state = &harness.state().state;
        assert_eq!(state.pending, Some(starcages_editor::Pending::Install));
        assert!(state.loaded.is_some(), "read before the question");
        assert!(
            state.doc.dirty && state.doc.scene == edited,
            "the work stays until the answer"
        );
    }
    harness.get_by_label_contains("saved.json is read and opens in its place");
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    {
        let state = &harness.state().state;
        assert!(state.pending.is_none() && state.loaded.is_none());
        assert!(state.doc.dirty && state.doc.scene == edited);
    }
    send_and_settle(&mut harness, Command::Open(path.clone()));
    harness.get_by_label("Don't save").click();
    harness.run_steps(2);
    settle(&mut harness);
    let state = &harness.state().state;
    assert!(!state.doc.dirty);
    assert_eq!(state.doc.path.as_deref(), Some(path.as_path()));
    assert_ne!(state.doc.scene, edited);
}

/// A scene file that fails to read (here truncated) over unsaved work is refused with its
/// reason and no question: the artist is not asked to give up work for a file that does not
/// open. Before, the prompt came first and the failure after the answer.
#[test]
fn a_broken_scene_over_unsaved_work_is_refused_without_asking() {
    let mut harness = harness();
    let dir = scratch("broken-over-work");
    let broken = dir.join("broken.json");
    std::fs::write(
        &broken,
        "{ \"format\": \"starcages-scene\", \"version\": 1, ",
    )
    .unwrap();
    let edited = {
        let app = harness.state_mut();
        let to = app.state.doc.scene.pose[0] + DVec3::Z * 0.2;
        app.run(Command::MoveVertices(vec![(0, to)]));
        app.state.doc.scene.clone()
    };
    send_and_settle(&mut harness, Command::Open(broken));
    let state = &harness.state().state;
    assert!(
        state.pending.is_none(),
        "no unsaved prompt for a broken file"
    );
    assert!(state.loaded.is_none());
    let message = state.message.clone().unwrap();
    assert!(
        message.error && message.text.contains("broken.json") && message.text.contains("EOF"),
        "{}",
        message.text
    );
    assert!(
        state.doc.dirty && state.doc.scene == edited,
        "the work is kept"
    );
    assert!(harness.query_by_label("Don't save").is_none());
}

/// A dropped or opened file that cannot be opened (a type no reader knows, a file that is
/// not there) is refused at once, naming it: no one is asked about unsaved work first.
#[test]
fn a_file_that_cannot_be_opened_is_refused_before_the_unsaved_prompt() {
    let mut harness = harness();
    let folder = scratch("refused");
    let notes = folder.join("notes.txt");
    std::fs::write(&notes, "not a mesh").unwrap();
    {
        let app = harness.state_mut();
        let to = app.state.doc.scene.pose[0] + DVec3::Z * 0.2;
        app.run(Command::MoveVertices(vec![(0, to)]));
        assert!(app.state.doc.dirty);
    }
    for (path, why) in [
        (notes, "a .txt file is neither a scene (.json) nor a mesh"),
        (folder.join("gone.json"), "there is no such file"),
        (folder.to_path_buf(), "a file without an extension"),
    ] {
        harness.state_mut().run(Command::Open(path.clone()));
        harness.run_steps(2);
        let state = &harness.state().state;
        assert!(
            state.pending.is_none(),
            "{}: no unsaved prompt",
            path.display()
        );
        assert!(state.load_job.is_none());
        let message = state
            .message
            .as_ref()
            .map(|m| m.text.clone())
            .unwrap_or_default();
        assert!(
            message.contains(&path.display().to_string()) && message.contains(why),
            "{message}"
        );
        assert!(state.doc.dirty, "the work is kept");
    }
    // New from mesh refuses a scene file the same way.
    harness.state_mut().run(Command::NewFromMesh(
        folder.join("scene.json"),
        Default::default(),
    ));
    harness.run_steps(2);
    let state = &harness.state().state;
    assert!(state.pending.is_none());
    let message = state
        .message
        .as_ref()
        .map(|m| m.text.clone())
        .unwrap_or_default();
    assert!(message.contains("is not a mesh"), "{message}");
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
fn exporting_over_the_scene_s_own_mesh_is_refused() {
    let mut harness = harness();
    let dir = scratch("export-over-mesh");
    let mesh = dir.join("box.obj");
    let text = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
                f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::fs::write(&mesh, text).unwrap();
    let options = starcages_editor::state::NewMeshOptions::default();
    send_and_settle(&mut harness, Command::NewFromMesh(mesh.clone(), options));
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
        dialog.enter(dir.to_path_buf());
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

/// Save from the unsaved-changes prompt of a scene without a file opens the file dialog on
/// top (the prompt steps aside), and choosing a file saves and carries on.
#[test]
fn saving_from_the_unsaved_prompt_goes_through_the_file_dialog() {
    let mut harness = harness();
    harness.state_mut().ui.files.in_app_only = true;
    let dir = scratch("save-from-prompt");
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
    settle(&mut harness);
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
        dialog.enter(dir.to_path_buf());
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

/// File ▸ Save as… proposes the mesh's name for a scene never saved, and Export the mesh's
/// name with what is exported.
#[test]
fn save_as_proposes_the_mesh_s_name() {
    let mut harness = harness();
    {
        let app = harness.state_mut();
        app.ui.files.in_app_only = true;
        app.state.doc.scene.mesh_source =
            starcages_core::scene::MeshSource::File("/models/armadillo.obj".into());
    }
    for (item, proposed) in [
        ("Save as…", "armadillo.json"),
        ("Export deformed mesh…", "armadillo_deformed.obj"),
    ] {
        harness.get_by_label("File").click();
        harness.run_steps(2);
        harness.get_by_label_contains(item).click();
        harness.run_steps(2);
        let app = harness.state_mut();
        let dialog = app
            .ui
            .files
            .in_app
            .take()
            .expect("the in-app dialog is open");
        assert_eq!(dialog.name, proposed, "{item}");
        harness.run_steps(1);
    }
}
