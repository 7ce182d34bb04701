//! Binding in the editor: in the background with Cancel, previews refined, internal cages as
//! hierarchy-only edits, rest edits in the item panel.

use egui::accesskit::Role;
use egui_kittest::kittest::Queryable as _;
use glam::DVec3;
use starcages_core::coords::CoordinateKind;
use starcages_editor::{CageId, Command, Document};

use crate::common::{cage, harness, leaf, press, scratch, send_and_settle, settle};

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
    let dir = scratch("cancelled-refinement");
    let path = dir.join("deformed.obj");
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
    send_and_settle(&mut harness, Command::Undo);
    assert_eq!(harness.state().state.doc.scene.cages.internals.len(), 3);
    send_and_settle(&mut harness, Command::Undo);
    assert_eq!(harness.state().state.doc.scene.cages.internals.len(), 2);
}

#[test]
fn an_internal_cage_kind_change_rebinds_the_hierarchy_only() {
    let mut harness = harness();
    let old = std::sync::Arc::clone(&harness.state().state.rig.as_ref().unwrap().binding);
    let ears = cage(harness.state(), "ears");
    send_and_settle(
        &mut harness,
        Command::SetCageKind(ears, CoordinateKind::MeanValue),
    );
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
    assert!(!first.deformed().is_empty(), "the preview deforms the mesh");
    let mut quick = scene.clone();
    quick.settings.join_coordinates = starcages_core::scene::JoinPolicy::Mvc;
    let expected =
        StarBinding::bind_scene(&quick, &starcages_core::BindControl::default()).unwrap();
    assert_eq!(first.binding.operator, expected.operator);
    // Export waits for the full binding.
    let dir = scratch("preview-export");
    let path = dir.join("deformed.obj");
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
    send_and_settle(&mut harness, Command::Undo);
    let scene = &harness.state().state.doc.scene;
    assert_eq!(scene.cages.vertices, before.cages.vertices);
    assert_eq!(scene.poses, before.poses);
}

/// Validation keeps the topology it built, and a bind of the same cages and join policy takes
/// it; another policy or other cages do not.
#[test]
fn the_bind_takes_the_topology_validation_built_for_the_same_cages_only() {
    use starcages_core::scene::JoinPolicy;
    let harness = crate::common::harness();
    let state = &harness.state().state;
    let checked = state
        .checked_topology
        .as_ref()
        .expect("validation kept its topology");
    assert!(checked.of(&state.doc.scene).is_some());
    let mut other_policy = state.doc.scene.clone();
    other_policy.settings.join_coordinates = match other_policy.settings.join_coordinates {
        JoinPolicy::Mvc => JoinPolicy::Hc,
        _ => JoinPolicy::Mvc,
    };
    assert!(checked.of(&other_policy).is_none());
    let mut other_cages = state.doc.scene.clone();
    other_cages.cages.vertices[0].z += 0.01;
    assert!(checked.of(&other_cages).is_none());
}
