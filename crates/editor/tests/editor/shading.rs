//! Shading, the mesh file's materials and ghosts: the textured sphere (written by
//! `starcages_io::sample_files`) opens with its materials read on a worker, each shading mode
//! is one click away and drawn by the viewport's renderer, a broken image is a message naming
//! it while the mesh still opens, and ghosts of the animation follow their settings and keys.

use egui_kittest::kittest::Queryable as _;
use starcages_core::BindControl;
use starcages_editor::state::{GhostSettings, NewMeshOptions, NewRig};
use starcages_editor::ui::viewport_paint::drawn_extras;
use starcages_editor::{Command, Document};
use starcages_viewport::{Matcap, Shading};

use crate::common::{harness_on, scratch, send, settle};

/// The textured sphere's `file` (in `folder`) in a grid of cages.
fn sphere(folder: &std::path::Path, obj: bool) -> Document {
    let samples = starcages_io::sample_files::write_textured_samples(folder).unwrap();
    let path = if obj { samples.obj } else { samples.glb };
    let options = NewMeshOptions {
        rig: NewRig::Grid,
        ..NewMeshOptions::default()
    };
    let scene = starcages_editor::state::document::scene_from_mesh(
        &path,
        &options,
        &BindControl::default(),
    )
    .unwrap();
    Document {
        scene,
        path: None,
        dirty: true,
    }
}

/// A GLB with an embedded PNG opens with its two materials read off the UI thread and a
/// message saying how to see them; clicking Textured, MatCap (then Metal) and Solid sets the
/// shading, the renderer holds the look; a snapshot of the window in Textured shading.
#[test]
fn a_textured_mesh_opens_with_its_materials_and_each_shading_is_a_click_away() {
    let folder = scratch("textured-sphere");
    let (mut harness, render_state) = harness_on(sphere(&folder, false));
    settle(&mut harness);
    {
        let state = &harness.state().state;
        let look = state.look.as_ref().expect("the materials are read");
        assert_eq!(look.images.iter().flatten().count(), 1);
        assert!(look.problems.is_empty(), "{:?}", look.problems);
        let message = &state.message.as_ref().unwrap().text;
        assert!(message.contains("1 texture image read"), "{message}");
    }
    // kittest paints (and so runs the paint callback) when asked for an image.
    harness.render().unwrap();
    let extras = drawn_extras(&render_state.renderer.read().callback_resources);
    let extras = extras.unwrap();
    assert!(extras.look, "the renderer holds the look");
    assert_eq!(extras.ghosts, 0);
    harness.get_by_label("Textured").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.view.layers.shading, Shading::Textured);
    harness.snapshot_options(
        "textured_sphere",
        &egui_kittest::SnapshotOptions::new().threshold(4.0),
    );
    harness.get_by_label("MatCap").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.view.layers.shading,
        Shading::MatCap(Matcap::Clay)
    );
    harness.get_by_label("Metal").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.view.layers.shading,
        Shading::MatCap(Matcap::Metal)
    );
    harness.get_by_label("Solid").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.view.layers.shading, Shading::Solid);
}

/// An OBJ whose image is broken opens all the same: the status bar names the image and says
/// what to do; the material draws with its colour alone.
#[test]
fn a_broken_texture_is_a_message_naming_it_and_the_mesh_still_opens() {
    let folder = scratch("broken-texture");
    let doc = sphere(&folder, true);
    std::fs::write(folder.join("checker.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let (mut harness, _) = harness_on(doc);
    settle(&mut harness);
    let state = &harness.state().state;
    assert!(state.rig.is_some(), "the mesh binds");
    let look = state.look.as_ref().expect("the materials are read");
    assert!(look.images.iter().all(Option::is_none));
    let message = state.message.as_ref().unwrap();
    assert!(message.error);
    assert!(message.text.contains("checker.png"), "{}", message.text);
    assert!(message.text.contains("PNG or JPEG"), "{}", message.text);
}

/// Ghosts: on the critter (keys at 1, 12 and 24) at frame 12, View ▸ Ghosts' default of two
/// before and two after every three frames draws four, computed once while nothing changes and
/// again when a key is deleted; one before draws three; at frame 23 only those inside the range
/// are drawn; off draws none.
#[test]
fn ghosts_follow_their_settings_and_the_frame() {
    let (mut harness, render_state) = harness_on(crate::common::document());
    // kittest paints (and so runs the paint callback) when asked for an image.
    let extras = |harness: &mut egui_kittest::Harness<'_, starcages_editor::EditorApp>| {
        harness.render().unwrap();
        drawn_extras(&render_state.renderer.read().callback_resources).unwrap()
    };
    let drawn = |harness: &mut egui_kittest::Harness<'_, starcages_editor::EditorApp>| {
        Some(extras(harness).ghosts)
    };
    send(&mut harness, Command::SetFrame(12.0));
    assert_eq!(drawn(&mut harness), Some(0));
    harness.get_by_label("Ghosts").click();
    harness.run_steps(2);
    let ghosts = harness.state().state.view.ghosts;
    assert!(ghosts.shown);
    assert_eq!(
        ghosts.frames(12.0, (1.0, 24.0)),
        vec![(9.0, true), (6.0, true), (15.0, false), (18.0, false)]
    );
    assert_eq!(drawn(&mut harness), Some(4));
    // Computed once while nothing changes; again when a key changes.
    let first = extras(&mut harness).ghost_generation;
    harness.run_steps(2);
    assert_eq!(extras(&mut harness).ghost_generation, first);
    send(&mut harness, Command::DeleteKey(24.0));
    harness.run_steps(1);
    let after_edit = extras(&mut harness);
    assert_ne!(
        after_edit.ghost_generation, first,
        "a key edit recomputes the ghosts"
    );
    assert_eq!(after_edit.ghosts, 4);
    crate::common::undo(&mut harness);
    let fewer = GhostSettings {
        before: 1,
        ..ghosts
    };
    send(&mut harness, Command::SetGhosts(fewer));
    harness.run_steps(1);
    assert_eq!(drawn(&mut harness), Some(3));
    send(&mut harness, Command::SetFrame(23.0));
    harness.run_steps(1);
    // Frame 20 before; 26 and 29 lie past the end.
    assert_eq!(drawn(&mut harness), Some(1));
    send(&mut harness, Command::SetGhosts(GhostSettings::default()));
    harness.run_steps(1);
    assert_eq!(drawn(&mut harness), Some(0));
}
