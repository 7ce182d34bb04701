//! Regressions of defects found by trying the editor: a second scene drawing the first one's
//! mesh, panics on stale selections after structural undo, the difference map binding on the
//! UI thread, and binds abandoned instead of cancelled.

use egui_kittest::kittest::Queryable as _;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::demo::demo_scene;
use starcages_editor::state::{InfluenceChoice, SelectMode};
use starcages_editor::ui::viewport_paint::uploaded_mesh;
use starcages_editor::{CageId, Command};
use starcages_io::save_scene;

use crate::common::{
    harness, harness_on, open_and_answer, press, scratch, send_and_settle, settle,
};

#[test]
fn opening_a_second_scene_draws_its_own_mesh() {
    let dir = scratch("two-scenes");
    let egg = dir.join("egg.json");
    let critter = dir.join("critter.json");
    save_scene(&demo_scene("egg", 0.5).unwrap(), &egg).unwrap();
    save_scene(&demo_scene("critter", 0.5).unwrap(), &critter).unwrap();
    let (mut harness, render_state) = harness_on(crate::common::document());
    let drawn = || uploaded_mesh(&render_state.renderer.read().callback_resources);
    for path in [&egg, &critter, &egg] {
        open_and_answer(
            harness.state_mut(),
            Command::Open(path.clone()),
            starcages_editor::commands::UnsavedAnswer::Discard,
        );
        settle(&mut harness);
        harness.run_steps(2);
        // kittest paints (and so runs the paint callback) when asked for an image.
        harness.render().unwrap();
        let state = &harness.state().state;
        assert_eq!(state.doc.path.as_deref(), Some(path.as_path()));
        let mesh = &state.doc.scene.mesh;
        let drawn = drawn().expect("the viewport holds a mesh");
        assert_eq!(drawn.key.document, state.document_id, "{}", path.display());
        assert_eq!(drawn.vertices, mesh.welded_positions().len());
        assert_eq!(drawn.triangles, mesh.welded_triangles().len());
        let (lo, hi) = mesh.bounds();
        assert!((drawn.bounds.0 - lo.as_vec3()).length() < 1e-4);
        assert!((drawn.bounds.1 - hi.as_vec3()).length() < 1e-4);
        // Posing deforms this mesh (the operator uploaded is this document's).
        let to = state.doc.scene.pose[0] + glam::DVec3::Z * 0.05;
        harness
            .state_mut()
            .run(Command::MoveVertices(vec![(0, to)]));
        harness.run_steps(2);
    }
}

#[test]
fn undoing_an_internal_cage_while_it_is_inspected_and_shift_dragging_after_do_not_panic() {
    let mut harness = harness();
    let head = harness
        .state()
        .state
        .doc
        .scene
        .cages
        .cage_vertices("head")
        .unwrap();
    let app = harness.state_mut();
    app.run(Command::Select {
        vertices: head,
        mode: SelectMode::Replace,
    });
    app.run(Command::AddInternalCage(CoordinateKind::MeanValue));
    settle(&mut harness);
    let added = CageId::Internal(2);
    harness.state_mut().run(Command::InspectCage(Some(added)));
    harness.run_steps(2);
    harness.get_by_label("internal_1 (mvc)");
    // Select everything, the new cage's vertices too, then undo the addition.
    press(&mut harness, egui::Key::A);
    let count = harness.state().state.doc.scene.cages.vertices.len();
    assert!(
        harness
            .state()
            .state
            .selection
            .vertices
            .contains(&(count as u32 - 1))
    );
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(3);
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.internals.len(), 2);
    assert_eq!(state.selection.cage(), None, "the inspected cage is gone");
    state.check_invariants().unwrap();
    assert!(
        state.selection.vertices.is_empty(),
        "vertices were removed, so their indices shifted: the vertex selection is cleared"
    );
    // Select everything again, then Shift-drag on a vertex and on empty space.
    press(&mut harness, egui::Key::A);
    let state = &harness.state().state;
    let v = *state.selection.vertices.iter().next().unwrap();
    let on_vertex = starcages_editor::ui::vertex_on_screen(state, v).unwrap();
    let viewport = state.view.viewport;
    let empty = egui::pos2(viewport.min.x + 5.0, viewport.min.y + 5.0);
    for start in [on_vertex, empty] {
        harness.event(egui::Event::ModifiersChanged(egui::Modifiers::SHIFT));
        harness.drag_at(start);
        harness.run_steps(1);
        harness.hover_at(start + egui::vec2(40.0, 30.0));
        harness.run_steps(1);
        harness.drop_at(start + egui::vec2(60.0, 40.0));
        harness.event(egui::Event::ModifiersChanged(egui::Modifiers::NONE));
        harness.run_steps(2);
        harness.state().state.check_invariants().unwrap();
    }
    // Undo everything back to the demo: still consistent.
    send_and_settle(&mut harness, Command::Undo);
    harness.state().state.check_invariants().unwrap();
}

#[test]
fn the_difference_map_binds_its_baseline_in_the_background() {
    let mut harness = harness();
    harness
        .state_mut()
        .run(Command::SetInfluence(InfluenceChoice::Difference(
            CoordinateKind::Green,
        )));
    // Choosing it returns at once: the baseline is a background job (a bind takes far longer
    // than spawning it), and the map says it is coming.
    let state = &harness.state().state;
    assert!(
        state.map.baseline_progress().is_some(),
        "the baseline binds off the UI thread"
    );
    assert!(state.map.values().is_none());
    assert!(
        state
            .map
            .note
            .as_deref()
            .unwrap_or_default()
            .contains("baseline")
    );
    harness.step();
    settle(&mut harness);
    let state = &harness.state().state;
    let values = state.map.values().expect("the map arrives");
    assert_eq!(values.values.len(), state.deformed().len());
    // At rest both deformations are the identity: said so, not noise stretched to red.
    assert!(values.title.contains("identical"), "{}", values.title);
    assert!(values.values.iter().all(|&v| v == 0.0));
    harness.get_by_label_contains("identical");
    // Posed, they differ.
    let pose = state.doc.scene.poses.keys().next().unwrap().clone();
    send_and_settle(&mut harness, Command::SwitchPose(Some(pose)));
    let values = harness.state().state.map.values().expect("the map").clone();
    assert!(!values.title.contains("identical"), "{}", values.title);
    assert!(values.values.iter().any(|&v| v > 0.5));
}

#[test]
fn replacing_the_document_cancels_its_running_bind() {
    let mut harness = harness();
    let mut settings = harness.state().state.doc.scene.settings;
    settings.harmonic.resolution = 128;
    harness.state_mut().run(Command::SetSettings {
        label: "HC grid".into(),
        settings,
    });
    let control = harness.state().state.bind_job.as_ref().unwrap().control();
    assert!(!control.is_cancelled());
    let dir = scratch("cancel-on-replace");
    let path = dir.join("bar.json");
    save_scene(&demo_scene("bar", 0.3).unwrap(), &path).unwrap();
    open_and_answer(
        harness.state_mut(),
        Command::Open(path),
        starcages_editor::commands::UnsavedAnswer::Discard,
    );
    assert!(control.is_cancelled(), "the old document's bind still runs");
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
}

/// A border h for two cages that share no face was accepted, left the rig invalid (the last
/// binding frozen) and every later move refused as "still being bound". Found by the model
/// test: removing an internal cage then re-checked the rig. The command now refuses it.
#[test]
fn a_border_h_for_cages_that_do_not_meet_is_refused_and_moves_still_land() {
    let doc = crate::common::document();
    let mut app = starcages_editor::EditorApp::new(doc, None, false);
    app.wait_for_jobs();
    let set = &app.state.doc.scene.cages;
    // head_1_1_0 and head_0_0_0 meet at an edge only.
    let leaf = set.leaf_index("head_1_1_0").unwrap();
    app.run(Command::SetBorderH {
        leaf,
        neighbour: "head_0_0_0".into(),
        h: Some(0.9),
    });
    let message = format!("{:?}", app.state.message);
    assert!(message.contains("share no face"), "{message}");
    assert!(app.state.rig_problems.is_empty());
    assert!(app.state.doc.scene.cages.leaves[leaf].border_h.is_empty());
    // Cages that do meet take it.
    app.run(Command::SetBorderH {
        leaf,
        neighbour: "head_0_1_0".into(),
        h: Some(0.9),
    });
    assert_eq!(app.state.doc.scene.cages.leaves[leaf].border_h.len(), 1);
    app.wait_for_jobs();
    assert!(app.state.rig_problems.is_empty());
    let v = app.state.doc.scene.cages.leaves[leaf].faces[0][0];
    let to = app.state.doc.scene.pose[v as usize] + glam::DVec3::splat(0.05);
    app.run(Command::MoveVertices(vec![(v, to)]));
    assert_eq!(app.state.doc.scene.pose[v as usize], to, "the move lands");
}
