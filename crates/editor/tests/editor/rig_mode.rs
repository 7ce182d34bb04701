//! Rig mode through egui_kittest: extrude, delete, merge, mirror, fit, subdivide, imported
//! leaf and internal cages, the rest cages shown while a pose is active, and how an invalid rig
//! is shown (the interactive tools are `rig_tools`).

use egui::accesskit::Role;
use egui_kittest::SnapshotOptions;
use egui_kittest::kittest::Queryable as _;
use glam::DVec3;
use starcages_editor::ui::vertex_on_screen;
use starcages_editor::{CageId, Command};

use crate::common::{leaf, press, press_with, scratch, send_and_settle, settle, undo};

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
    press(&mut harness, egui::Key::E);
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
    press(&mut harness, egui::Key::Enter);
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
    assert!(starcages_core::check::validate_scene(&state.doc.scene).is_valid());
    assert_eq!(
        state.rig.as_ref().unwrap().bound_for.0.leaves.len(),
        3,
        "the binding follows"
    );
    // E and its grab are one undo step (Blender's "extrude and move"); redo brings both back.
    undo(&mut harness);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
    press_with(
        &mut harness,
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
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
    press(&mut harness, egui::Key::X);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
    undo(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 3);
    // Ctrl+R places a cut across the inspected cage's longest side; Enter makes it.
    harness
        .state_mut()
        .run(Command::InspectCage(Some(CageId::Leaf(0))));
    press_with(&mut harness, egui::Modifiers::COMMAND, egui::Key::R);
    assert!(
        harness.state().ui.loop_cut.is_some(),
        "the cut is being placed"
    );
    press(&mut harness, egui::Key::Enter);
    settle(&mut harness);
    let scene = harness.state().state.doc.scene.clone();
    assert_eq!(
        scene.cages.leaves.len(),
        4,
        "{:?}",
        harness.state().state.message
    );
    assert!(starcages_core::check::validate_scene(&scene).is_valid());
    // Moving a vertex in Rig mode moves its rest position; the poses follow.
    let v = face[0];
    let before_rest = scene.cages.vertices[v as usize];
    let before_pose = scene.pose[v as usize];
    let to = before_pose + DVec3::new(0.1, 0.0, 0.0);
    send_and_settle(&mut harness, Command::MoveVertices(vec![(v, to)]));
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
    press_with(&mut harness, egui::Modifiers::SHIFT, egui::Key::A);
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
    press(&mut harness, egui::Key::Tab);
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
    undo(&mut harness);
    assert!(harness.state().state.rig_problems.is_empty());
    assert!(harness.query_by_label_contains("The rig has").is_none());
    press(&mut harness, egui::Key::Tab);
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
    let dir = scratch("import-cages");
    let path = box_obj(&dir, "tip", [1.1, -0.35, -0.35], [2.0, 0.35, 0.35]);
    send_and_settle(&mut harness, Command::ImportCages(path));
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

/// An OBJ holding one box group called `name` from `lo` to `hi`, in folder `dir`.
fn box_obj(dir: &std::path::Path, name: &str, lo: [f64; 3], hi: [f64; 3]) -> std::path::PathBuf {
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
    let path = dir.join(format!("{name}.obj"));
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
    let dir = scratch("import-internal");
    let path = box_obj(&dir, "driver", [-0.1, -0.5, -0.5], [1.3, 0.5, 0.5]);
    send_and_settle(&mut harness, Command::ImportInternalCages(path.clone()));
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
    send_and_settle(&mut harness, Command::Undo);
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
    press(&mut harness, egui::Key::M);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 1);
    undo(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 2);
    // Ctrl+M mirrors the inspected cage across x = 0: a copy that overlaps the other half of
    // the bar, which the live validation reports.
    harness
        .state_mut()
        .run(Command::InspectCage(Some(CageId::Leaf(1))));
    press_with(&mut harness, egui::Modifiers::COMMAND, egui::Key::M);
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
    send_and_settle(&mut harness, Command::SwitchPose(Some(pose)));
    let scene = harness.state().state.doc.scene.clone();
    let v = (0..scene.pose.len())
        .find(|&v| scene.pose[v] != scene.cages.vertices[v])
        .expect("the pose moves some vertex") as u32;
    let on_screen = |h: &egui_kittest::Harness<'static, starcages_editor::EditorApp>| {
        vertex_on_screen(&h.state().state, v).unwrap()
    };
    let posed_at = on_screen(&harness);
    press(&mut harness, egui::Key::Tab);
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
    press(&mut harness, egui::Key::Tab);
    assert!(on_screen(&harness).distance(posed_at) < 1e-3);
    let in_pose_mode = ghost_pixels(&mut harness);
    assert!(
        in_rig_mode > in_pose_mode + 100,
        "ghost pixels: {in_rig_mode} in Rig mode, {in_pose_mode} in Pose mode"
    );
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
    assert!(starcages_core::check::validate_scene(scene).is_valid());
    assert_eq!(
        state.rig.as_ref().unwrap().bound_for.0.vertices.len(),
        scene.cages.vertices.len(),
        "the binding follows"
    );
    undo(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages, before.cages);
}

/// Live validation draws what is wrong: a box added over the bar's cages overlaps them, so it
/// (and the cages it overlaps) are drawn in the warning colour, the offending vertices as large
/// warning dots, and the pointer over one of them says why.
#[test]
fn an_invalid_rig_draws_its_problem_cages_in_the_warning_colour_with_the_reason_on_hover() {
    let mut harness = crate::common::bar_harness(true);
    press_with(&mut harness, egui::Modifiers::SHIFT, egui::Key::A);
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
    undo(&mut harness);
    assert_eq!(
        harness.state().state.rig_warnings,
        starcages_editor::state::rig_warnings::RigWarnings::default()
    );
}
