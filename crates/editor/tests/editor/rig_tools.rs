//! Rig mode's interactive tools through egui_kittest: the loop cut, face selection and E, I's
//! inset, G's snapping and welding, mesh selection and the Add menu.

use egui_kittest::SnapshotOptions;
use egui_kittest::kittest::Queryable as _;
use glam::DVec3;
use starcages_core::coords::CoordinateKind;
use starcages_editor::ui::vertex_on_screen;
use starcages_editor::{CageId, Command};

use crate::common::{leaf, press, press_with, send_and_settle, settle, undo};

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
    press_with(&mut harness, egui::Modifiers::COMMAND, egui::Key::R);
    harness.get_by_label_contains("Loop cut 'cage_0_0_0' across X");
    press(&mut harness, egui::Key::Escape);
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
    press(&mut harness, egui::Key::Enter);
    settle(&mut harness);
    let scene = &harness.state().state.doc.scene;
    assert_eq!(scene.cages.leaves.len(), 3);
    assert!(starcages_core::check::validate_scene(scene).is_valid());
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
    press(&mut harness, egui::Key::E);
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
    assert!(starcages_core::check::validate_scene(&scene).is_valid());
    assert_eq!(
        harness.state().state.selection.vertices.len(),
        6,
        "the two new caps are selected"
    );
    undo(&mut harness);
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
    press(&mut harness, egui::Key::E);
    assert!(harness.state().ui.tool.is_some(), "E starts G");
    press(&mut harness, egui::Key::Escape);
    settle(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 3);
    undo(&mut harness);
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
    press(&mut harness, egui::Key::E);
    let state = &harness.state().state;
    assert_eq!(state.doc.scene.cages.leaves.len(), 2);
    let message = format!("{:?}", state.message);
    assert!(message.contains("shared with a neighbour"), "{message}");
    // A selects every face in face select mode.
    press(&mut harness, egui::Key::A);
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
    press(&mut harness, egui::Key::I);
    assert!(harness.state().ui.inset.is_some(), "I starts sizing");
    harness.get_by_label_contains("Inset 1 face");
    harness.snapshot_options(
        "rig_mode_inset",
        &SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(1200),
    );
    press(&mut harness, egui::Key::Escape);
    assert!(harness.state().ui.inset.is_none());
    assert_eq!(
        harness.state().state.doc.scene.cages,
        before.cages,
        "Esc drops it"
    );
    press(&mut harness, egui::Key::I);
    harness.event(egui::Event::Text("0.05".into()));
    harness.run_steps(1);
    harness.get_by_label_contains("thickness 0.05");
    press(&mut harness, egui::Key::Enter);
    settle(&mut harness);
    let scene = harness.state().state.doc.scene.clone();
    assert_eq!(
        scene.cages.leaves[left].faces.len(),
        before.cages.leaves[left].faces.len() + 4,
        "{:?}",
        harness.state().state.message
    );
    assert_eq!(scene.cages.vertices.len(), before.cages.vertices.len() + 4);
    assert!(starcages_core::check::validate_scene(&scene).is_valid());
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
    press(&mut harness, egui::Key::E);
    press(&mut harness, egui::Key::Escape);
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
        undo(&mut harness);
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
    send_and_settle(
        &mut harness,
        Command::Rig(starcages_core::rig::RigOp::AddBox {
            name: "beyond".into(),
            min: DVec3::new(hi.x + gap, lo.y, lo.z),
            max: DVec3::new(hi.x + gap + 0.5, hi.y, hi.z),
            kind: CoordinateKind::MeanValue,
        }),
    );
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
    press(&mut harness, egui::Key::Escape);
    assert_eq!(harness.state().state.doc.scene.cages.vertices, rest);
    // Snapping on (the View panel's checkbox): the same move lands on the target.
    harness.get_by_label("Snap to vertices").click();
    harness.run_steps(1);
    grab_from_beside_to(&mut harness, target_on_screen);
    harness.get_by_label_contains(&format!("snapped to vertex {target}"));
    press(&mut harness, egui::Key::Enter);
    settle(&mut harness);
    let state = &harness.state().state;
    let scene = &state.doc.scene;
    assert_eq!(scene.cages.vertices.len(), 16, "{:?}", state.message);
    assert_eq!(
        scene.cages.adjacency().len(),
        2,
        "the box shares its face now"
    );
    assert!(starcages_core::check::validate_scene(scene).is_valid());
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
    undo(&mut harness);
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
    press_with(&mut harness, egui::Modifiers::SHIFT, egui::Key::A);
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
    undo(&mut harness);
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
    press_with(&mut harness, egui::Modifiers::SHIFT, egui::Key::A);
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
    press(&mut harness, egui::Key::A);
    let state = &harness.state().state;
    assert_eq!(state.selection.mesh_vertices.len(), count);
    // Esc closes the menu without adding anything.
    press_with(&mut harness, egui::Modifiers::SHIFT, egui::Key::A);
    press(&mut harness, egui::Key::Escape);
    assert!(harness.state().ui.add_menu.is_none());
    assert!(harness.query_by_label("Box at the pointer").is_none());
    assert_eq!(harness.state().state.doc.scene.cages.leaves.len(), 3);
}
