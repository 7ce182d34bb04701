//! A new mesh in the editor: New from mesh stands a Y-up file up, opens in the auto rig (or a
//! symmetric one), and Rig ▸ Auto rig asks for its settings and is one undo step.

use egui_kittest::kittest::Queryable as _;
use starcages_editor::{Command, Document};

use crate::common::{harness, scratch, send, send_and_settle, settle};

/// New from mesh reads an OBJ Y-up (the convention) and stands it up along Z; the dialog's
/// "Z up" reads it as it is.
#[test]
fn new_from_mesh_stands_a_y_up_obj_up() {
    use starcages_core::scene::UpAxis;
    use starcages_editor::state::NewMeshOptions;
    let dir = scratch("new-from-y-up");
    let mesh = dir.join("tall.obj");
    std::fs::write(
        &mesh,
        "v 0 0 0\nv 1 0 0\nv 0 4 0\nv 1 4 0\nv 0 0 1\nv 1 0 1\nv 0 4 1\nv 1 4 1\n\
         f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n",
    )
    .unwrap();
    let doc = Document {
        scene: starcages_core::generate::demo::demo_scene("bar", 0.3).unwrap(),
        path: None,
        dirty: false,
    };
    let mut app = starcages_editor::EditorApp::new(doc, None, false);
    app.wait_for_jobs();
    for (up, tall_axis) in [(UpAxis::Y, 2), (UpAxis::Z, 1)] {
        let options = NewMeshOptions {
            up,
            rig: starcages_editor::state::NewRig::Grid,
            ..NewMeshOptions::default()
        };
        crate::common::open_and_answer(
            &mut app,
            Command::NewFromMesh(mesh.clone(), options),
            starcages_editor::commands::UnsavedAnswer::Discard,
        );
        app.wait_for_jobs();
        let scene = &app.state.doc.scene;
        assert_eq!(scene.mesh_up, up);
        let (lo, hi) = scene.mesh.bounds();
        assert!(
            ((hi - lo)[tall_axis] - 4.0).abs() < 1e-9,
            "{up:?}: {:?}",
            hi - lo
        );
        // The default grid everywhere.
        assert!(scene.cages.leaves.len() <= 27 && scene.cages.leaves.len() > 8);
    }
}

/// New from mesh on `mesh` (discarding the open document), returning once the mesh is read
/// and installed, while its auto rig may still run.
fn open_mesh_until_read(app: &mut starcages_editor::EditorApp, mesh: &std::path::Path) {
    open_mesh_with_until_read(app, mesh, Default::default());
}

/// [`open_mesh_until_read`] with the dialog's `options`.
fn open_mesh_with_until_read(
    app: &mut starcages_editor::EditorApp,
    mesh: &std::path::Path,
    options: starcages_editor::state::NewMeshOptions,
) {
    crate::common::open_and_answer(
        app,
        Command::NewFromMesh(mesh.to_path_buf(), options),
        starcages_editor::commands::UnsavedAnswer::Discard,
    );
}

/// An editor on `scene` (not saved anywhere), its first bind done.
fn app_on(scene: starcages_core::scene::Scene) -> starcages_editor::EditorApp {
    let doc = Document {
        scene,
        path: None,
        dirty: false,
    };
    let mut app = starcages_editor::EditorApp::new(doc, None, false);
    app.wait_for_jobs();
    app
}

/// New from mesh gives the auto rig by default, on a worker; Rig ▸ Auto rig replaces a rig
/// with it as one undo step (poses of the old cages go, and come back with undo).
#[test]
fn the_auto_rig_is_the_default_for_a_new_mesh_and_one_undo_step_on_a_rig() {
    use starcages_core::check::validate_scene;
    let dir = scratch("auto-rig");
    let mesh = dir.join("bar.obj");
    let mut bar = starcages_core::generate::demo::demo_scene("bar", 0.3).unwrap();
    starcages_io::write_deformed_mesh(&mesh, &bar, bar.mesh.welded_positions()).unwrap();
    // An animation of the old rig's pose: its keys go with the rig (a key naming a pose the
    // scene no longer has left the scene invalid, the binding stuck on the old rig).
    bar.animation.keys.push(starcages_core::anim::Key {
        frame: 1.0,
        pose: "bend".into(),
        interpolation: Default::default(),
        h: Default::default(),
    });
    let old_animation = bar.animation.clone();
    let mut app = app_on(bar);
    let grid_cages = app.state.doc.scene.cages.clone();
    let grid_mesh_vertices = app.state.doc.scene.mesh.welded_positions().len();
    app.run(Command::AutoRig {
        detail: 2,
        controls: true,
        mirror: starcages_core::generate::Mirror::None,
    });
    assert!(app.state.autorig_job.is_some(), "runs on a worker");
    app.wait_for_jobs();
    let scene = &app.state.doc.scene;
    assert!(
        validate_scene(scene).is_valid(),
        "{:?}",
        validate_scene(scene).errors
    );
    assert!(scene.animation.keys.is_empty() && scene.poses.is_empty());
    assert!(
        app.state
            .message
            .as_ref()
            .is_some_and(|m| m.text.contains("1 animation key"))
    );
    assert_ne!(scene.cages, grid_cages);
    assert!(scene.cages.leaves.iter().all(|l| l.name.contains('_')));
    assert!(scene.cages.internals.iter().any(|c| c.name == "root"));
    assert!(app.state.rig.is_some(), "bound after the auto rig");
    app.run(Command::Undo);
    assert_eq!(app.state.doc.scene.cages, grid_cages, "one undo step back");
    assert_eq!(app.state.doc.scene.animation, old_animation);
    assert!(app.state.doc.scene.poses.contains_key("bend"));
    app.run(Command::Redo);
    assert_ne!(app.state.doc.scene.cages, grid_cages);
    // New from mesh: the auto rig by default. The mesh opens at once in the grid, the auto
    // rig follows on a worker and replaces it as one undo step.
    open_mesh_until_read(&mut app, &mesh);
    let opened = app.state.doc.scene.clone();
    assert_eq!(
        opened.mesh.welded_positions().len(),
        grid_mesh_vertices,
        "the mesh is open before its rig is made"
    );
    assert!(app.state.autorig_job.is_some(), "the auto rig runs after");
    assert!(
        app.state.bind_job.is_none(),
        "the grid is not bound meanwhile"
    );
    app.wait_for_jobs();
    let scene = &app.state.doc.scene;
    assert!(
        scene.cages.leaves.iter().all(|l| l.name.contains('_')),
        "{:?}",
        app.state.message
    );
    assert!(validate_scene(scene).is_valid());
    // Opening a mesh gives the posable rig: the bar has no limb, so its one control is the
    // root (the limbs' controls: posable_rig in the core's tests).
    assert!(
        scene
            .cages
            .internals
            .iter()
            .any(|c| c.name == "root" && c.pivot.is_some())
    );
    // The grid is one undo step away.
    app.run(Command::Undo);
    assert_eq!(app.state.doc.scene.cages, opened.cages);
    // Cancelling the auto rig keeps the grid, and binds it.
    open_mesh_until_read(&mut app, &mesh);
    app.run(Command::CancelAutoRig);
    app.wait_for_jobs();
    assert_eq!(app.state.doc.scene.cages, opened.cages);
    assert!(
        app.state.rig.is_some(),
        "the grid is bound after the cancel"
    );
}

/// Rig ▸ Auto rig… asks for the detail, internal cages and symmetry first; Cancel changes
/// nothing, Make rig starts the auto rig with what was chosen (no internal cages, symmetric
/// across x: every leaf vertex has the twin X mirror editing moves with it).
#[test]
fn rig_auto_rig_asks_for_detail_internal_cages_and_symmetry_first() {
    let mut harness = harness();
    let before = harness.state().state.doc.scene.cages.clone();
    harness.get_by_label("Rig").click();
    harness.run_steps(2);
    harness.get_by_label("Auto rig…").click();
    harness.run_steps(2);
    assert!(harness.state().ui.autorig_dialog.is_some());
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    assert!(harness.state().ui.autorig_dialog.is_none());
    assert!(harness.state().state.autorig_job.is_none());
    assert_eq!(harness.state().state.doc.scene.cages, before);
    harness.get_by_label("Rig").click();
    harness.run_steps(2);
    harness.get_by_label("Auto rig…").click();
    harness.run_steps(2);
    harness
        .state_mut()
        .ui
        .autorig_dialog
        .as_mut()
        .unwrap()
        .controls = false;
    harness.get_by_label("Symmetry").click();
    harness.run_steps(2);
    harness.get_by_label("Across x").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().ui.autorig_dialog.map(|d| d.mirror),
        Some(starcages_core::generate::Mirror::Axis(0))
    );
    harness.get_by_label("Make rig").click();
    harness.run_steps(2);
    settle(&mut harness);
    let scene = &harness.state().state.doc.scene;
    assert_ne!(scene.cages, before, "the auto rig replaced the rig");
    assert!(
        scene.cages.internals.is_empty(),
        "no internal cages, as chosen"
    );
    // X mirror editing finds every leaf vertex's twin (the mesh is centred on x = 0, so the
    // rig is symmetric across that plane, as mirror editing takes it).
    let partners = starcages_editor::state::mirror::partners(&scene.cages.vertices);
    assert!(
        scene
            .cages
            .leaves
            .iter()
            .flat_map(|l| l.faces.iter().flatten())
            .all(|&v| partners[v as usize].is_some()),
        "the rig is its own mirror image across x = 0"
    );
}

/// File ▸ New from mesh with Symmetry "Across x": the auto rig that follows the grid is its own
/// mirror image across x = 0, so X mirror editing finds every leaf vertex's twin.
#[test]
fn a_new_mesh_can_open_in_a_symmetric_auto_rig() {
    let dir = scratch("new-mesh-mirror");
    let mesh = dir.join("critter.obj");
    let critter = starcages_core::generate::demo::demo_scene("critter", 0.3).unwrap();
    starcages_io::write_deformed_mesh(&mesh, &critter, critter.mesh.welded_positions()).unwrap();
    let mut app = app_on(critter);
    let options = starcages_editor::state::NewMeshOptions {
        mirror: starcages_core::generate::Mirror::Axis(0),
        ..Default::default()
    };
    open_mesh_with_until_read(&mut app, &mesh, options);
    app.wait_for_jobs();
    let scene = &app.state.doc.scene;
    let names: Vec<&str> = scene.cages.leaves.iter().map(|l| l.name.as_str()).collect();
    assert!(
        names.contains(&"body_1"),
        "the auto rig replaced the grid: {names:?}"
    );
    let partners = starcages_editor::state::mirror::partners(&scene.cages.vertices);
    let lonely = scene
        .cages
        .leaves
        .iter()
        .flat_map(|l| l.faces.iter().flatten())
        .filter(|&&v| partners[v as usize].is_none())
        .count();
    assert_eq!(lonely, 0, "leaf vertices without a mirror twin");
}

/// The auto rig lands in the document it was made for or not at all: Ctrl+Z pressed while it
/// runs undoes the last edit and cancels the rig with a message (before, the rig landed on
/// top of the undone state, and the next Ctrl+Z took the rig away and kept nothing the artist
/// knew about); with nothing pressed it lands as one undo step.
#[test]
fn an_undo_while_the_auto_rig_runs_cancels_it_with_a_message() {
    let mut harness = crate::common::bar_harness(false);
    let grid = harness.state().state.doc.scene.cages.clone();
    let rest = harness.state().state.doc.scene.pose.clone();
    let moved = rest[0] + glam::DVec3::new(0.0, 0.0, 0.05);
    send(&mut harness, Command::MoveVertices(vec![(0, moved)]));
    assert_eq!(harness.state().state.doc.scene.pose[0], moved);
    harness.state_mut().run(Command::AutoRig {
        detail: 2,
        controls: true,
        mirror: starcages_core::generate::Mirror::None,
    });
    assert!(
        harness.state().state.autorig_job.is_some(),
        "runs on a worker"
    );
    // The undo while the job runs, with no frame between (a frame could land a job that
    // finished first, and the undo would then rightly undo the rig).
    send_and_settle(&mut harness, Command::Undo);
    let app = harness.state();
    assert!(app.state.autorig_job.is_none());
    assert_eq!(app.state.doc.scene.cages, grid, "the rig did not land");
    assert_eq!(app.state.doc.scene.pose[0], rest[0], "the move was undone");
    let message = app.state.message.as_ref().map(|m| m.text.clone());
    assert!(
        message
            .as_deref()
            .is_some_and(|m| m.contains("auto rig cancelled")),
        "{message:?}"
    );
    // Left alone, it lands as one step over the grid.
    send_and_settle(
        &mut harness,
        Command::AutoRig {
            detail: 2,
            controls: true,
            mirror: starcages_core::generate::Mirror::None,
        },
    );
    assert_ne!(harness.state().state.doc.scene.cages, grid);
    crate::common::undo(&mut harness);
    assert_eq!(harness.state().state.doc.scene.cages, grid);
}

/// R on a whole control (every vertex of an internal cage with a pivot, as the auto rig makes
/// them) turns it about its pivot, as Blender turns a bone about its head; another selection
/// turns about its median.
#[test]
fn r_on_a_control_turns_it_about_its_pivot() {
    // The neck: below the head's box, off its centre.
    let (mut harness, vertices, pivot) = critter_with_pivot("head", |lo, hi| {
        glam::DVec3::new(0.5 * (lo.x + hi.x), lo.y, lo.z)
    });
    let centre = harness.state().state.view.viewport.center();
    harness.hover_at(egui::pos2(centre.x, centre.y));
    let before = harness.state().state.doc.scene.pose.clone();
    send(
        &mut harness,
        Command::Select {
            vertices: vertices.clone(),
            mode: starcages_editor::state::SelectMode::Replace,
        },
    );
    harness.key_press(egui::Key::R);
    harness.run_steps(1);
    assert!(harness.state().ui.tool.is_some(), "R started a rotation");
    for text in ["z", "9", "0"] {
        harness.event(egui::Event::Text(text.into()));
        harness.run_steps(1);
    }
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
    let after = &harness.state().state.doc.scene.pose;
    let turn = glam::DQuat::from_axis_angle(glam::DVec3::Z, 90f64.to_radians());
    for &v in &vertices {
        let expected = pivot + turn * (before[v as usize] - pivot);
        let got = after[v as usize];
        assert!(
            (got - expected).length() < 1e-9,
            "vertex {v}: {got} instead of {expected} (turned about the pivot)"
        );
    }
}

/// The pivot point, chosen by its menu's accessibility label as in Blender's header, with a
/// control and three loose leaf-cage vertices selected (Rig mode, where every cage vertex is
/// the user's to move): Median Point (the default) turns everything about the mean of the
/// control's joint and the loose vertices, as Blender counts a bone by its head; Bounding Box
/// Center about the centre of their box; Individual Origins the control about its own joint and
/// the loose vertices about their centroid.
#[test]
fn the_pivot_point_menu_turns_about_joints_medians_or_individual_origins() {
    let (mut harness, head, joint) = critter_with_pivot("head", |lo, hi| {
        glam::DVec3::new(0.5 * (lo.x + hi.x), lo.y, lo.z)
    });
    harness
        .state_mut()
        .run(Command::SetMode(starcages_editor::state::EditMode::Rig));
    harness.run_steps(2);
    let set = &harness.state().state.doc.scene.cages;
    let in_internals: Vec<u32> = set
        .internals
        .iter()
        .flat_map(|c| set.cage_vertices(&c.name).unwrap())
        .collect();
    let loose: Vec<u32> = (0..set.vertices.len() as u32)
        .rev()
        .filter(|v| !in_internals.contains(v))
        .step_by(7)
        .take(3)
        .collect();
    assert_eq!(loose.len(), 3, "three loose vertices");
    let mut both: Vec<u32> = head.iter().chain(&loose).copied().collect();
    both.sort_unstable();
    let turn = glam::DQuat::from_axis_angle(glam::DVec3::Z, 90f64.to_radians());
    let centre = harness.state().state.view.viewport.center();
    for (choice, label) in [
        (None, "Median Point"),
        (Some("Individual Origins"), "Individual Origins"),
        (Some("Bounding Box Center"), "Bounding Box Center"),
    ] {
        if let Some(choice) = choice {
            harness.get_by_label("Pivot point").click();
            harness.run_steps(2);
            harness.get_by_label(choice).click();
            harness.run_steps(2);
        }
        assert_eq!(harness.state().state.view.pivot_point.label(), label);
        harness.hover_at(egui::pos2(centre.x, centre.y));
        let before = harness.state().state.doc.scene.cages.vertices.clone();
        send(
            &mut harness,
            Command::Select {
                vertices: both.clone(),
                mode: starcages_editor::state::SelectMode::Replace,
            },
        );
        rotate_z_90(&mut harness);
        let after = harness.state().state.doc.scene.cages.vertices.clone();
        let loose_points: Vec<glam::DVec3> = loose.iter().map(|&v| before[v as usize]).collect();
        let points: Vec<glam::DVec3> = std::iter::once(joint).chain(loose_points.clone()).collect();
        let together = match label {
            "Bounding Box Center" => {
                let lo = points.iter().fold(glam::DVec3::INFINITY, |a, &p| a.min(p));
                let hi = points
                    .iter()
                    .fold(glam::DVec3::NEG_INFINITY, |a, &p| a.max(p));
                (lo + hi) * 0.5
            }
            _ => points.iter().sum::<glam::DVec3>() / points.len() as f64,
        };
        let loose_centroid = loose_points.iter().sum::<glam::DVec3>() / 3.0;
        for (vertices, own) in [(&head, joint), (&loose, loose_centroid)] {
            let origin = if label == "Individual Origins" {
                own
            } else {
                together
            };
            for &v in vertices.iter() {
                let expected = origin + turn * (before[v as usize] - origin);
                let got = after[v as usize];
                assert!(
                    (got - expected).length() < 1e-6,
                    "{label}: vertex {v}: {got} instead of {expected}"
                );
            }
        }
        crate::common::undo(&mut harness);
        assert_eq!(
            harness.state().state.doc.scene.cages.vertices,
            before,
            "{label}: undone"
        );
    }
}

/// In Pose mode a click on the mesh, away from every cage vertex, selects the whole control
/// moving that part (here the critter's head cage, which owns the head's leaf vertices), ready
/// for R about its pivot; a click on empty space still clears the selection.
#[test]
fn clicking_the_mesh_in_pose_mode_selects_the_control_moving_it() {
    let mut harness = crate::common::harness();
    let head_vertices = harness
        .state()
        .state
        .doc
        .scene
        .cages
        .cage_vertices("head")
        .unwrap();
    // Framed on the head, so that the mesh shows between its cage vertices.
    let app = harness.state_mut();
    app.run(Command::Select {
        vertices: head_vertices.clone(),
        mode: starcages_editor::state::SelectMode::Replace,
    });
    app.run(Command::Camera(
        starcages_editor::commands::CameraChange::FrameSelection,
    ));
    app.run(Command::SelectNone);
    harness.run_steps(2);
    let app = harness.state();
    assert_eq!(app.state.mode, starcages_editor::state::EditMode::Pose);
    let set = &app.state.doc.scene.cages;
    let head = set.internals.iter().find(|c| c.name == "head").unwrap();
    let owned: std::collections::BTreeSet<u32> = head.owns.iter().copied().collect();
    let rect = app.state.view.viewport;
    let camera = app.state.view.camera;
    let on_screen = |p: glam::Vec3| {
        camera
            .project(p, rect.size)
            .map(|(pixel, _)| egui::pos2(rect.min.x + pixel.x, rect.min.y + pixel.y))
    };
    let cage_pixels: Vec<egui::Pos2> = app
        .state
        .shown_positions()
        .iter()
        .filter_map(|p| on_screen(p.as_vec3()))
        .collect();
    let pose = &app.state.doc.scene.pose;
    let mut leaf: Vec<u32> = set
        .leaves
        .iter()
        .flat_map(|l| l.faces.iter().flatten().copied())
        .collect();
    leaf.sort_unstable();
    leaf.dedup();
    // A mesh point whose nearest leaf cage vertices the head cage owns, clear of every cage
    // vertex on screen, in front of the rest of the mesh along the view.
    let deformed = app.state.deformed();
    let target = deformed
        .iter()
        .filter(|p| {
            let mut near = leaf.clone();
            near.sort_by(|&a, &b| {
                let d = |v: u32| pose[v as usize].distance(p.as_dvec3());
                d(a).total_cmp(&d(b))
            });
            near.iter().take(6).filter(|v| owned.contains(v)).count() >= 4
        })
        .filter_map(|&p| on_screen(p))
        .find(|&s| cage_pixels.iter().all(|c| c.distance(s) > 11.0))
        .expect("a head point clear of cage vertices");
    click_at(&mut harness, target);
    let selected: Vec<u32> = harness
        .state()
        .state
        .selection
        .vertices
        .iter()
        .copied()
        .collect();
    assert_eq!(selected, head_vertices, "the head cage is selected");
    // Empty space: nothing.
    click_at(
        &mut harness,
        egui::pos2(rect.min.x + 5.0, rect.min.y + rect.size.y - 5.0),
    );
    assert!(harness.state().state.selection.vertices.is_empty());
}

/// Pose mode draws a handle at each control's joint; a click on it selects the whole control
/// (before any cage vertex under it), and the handle shows selected.
#[test]
fn a_click_on_a_control_s_handle_selects_the_control() {
    // The joint at the middle of the ears cage's lowest face.
    let (mut harness, vertices, pivot) = critter_with_pivot("ears", |lo, hi| {
        glam::DVec3::new(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z)
    });
    let app = harness.state();
    let rect = app.state.view.viewport;
    let (pixel, _) = app
        .state
        .view
        .camera
        .project(pivot.as_vec3(), rect.size)
        .unwrap();
    click_at(
        &mut harness,
        egui::pos2(rect.min.x + pixel.x + 2.0, rect.min.y + pixel.y),
    );
    let selected: Vec<u32> = harness
        .state()
        .state
        .selection
        .vertices
        .iter()
        .copied()
        .collect();
    assert_eq!(
        selected, vertices,
        "the ears cage is selected by its handle"
    );
}

/// The critter with a pivot on its internal cage `name`, at `pivot_of(lo, hi)` of the cage's
/// rest bounds, in a harness; with the cage's vertices (sorted) and the pivot.
fn critter_with_pivot(
    name: &str,
    pivot_of: impl Fn(glam::DVec3, glam::DVec3) -> glam::DVec3,
) -> (
    egui_kittest::Harness<'static, starcages_editor::EditorApp>,
    Vec<u32>,
    glam::DVec3,
) {
    let mut scene = starcages_core::generate::demo::demo_scene("critter", 0.4).unwrap();
    let vertices = scene.cages.cage_vertices(name).unwrap();
    let (lo, hi) = vertices.iter().fold(
        (
            glam::DVec3::splat(f64::INFINITY),
            glam::DVec3::splat(f64::NEG_INFINITY),
        ),
        |(lo, hi), &v| {
            let p = scene.cages.vertices[v as usize];
            (lo.min(p), hi.max(p))
        },
    );
    let pivot = pivot_of(lo, hi);
    let cage = scene
        .cages
        .internals
        .iter_mut()
        .find(|c| c.name == name)
        .unwrap();
    cage.pivot = Some(pivot);
    let (harness, _) = crate::common::harness_on(Document {
        scene,
        path: None,
        dirty: false,
    });
    (harness, vertices, pivot)
}

/// A primary click at `at` (screen points), after hovering there, and two frames to land.
fn click_at(
    harness: &mut egui_kittest::Harness<'static, starcages_editor::EditorApp>,
    at: egui::Pos2,
) {
    harness.hover_at(at);
    harness.run_steps(1);
    for pressed in [true, false] {
        harness.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    harness.run_steps(2);
}

/// In Pose mode a rig's leaf vertices (under its controls) step back: small by default, and
/// when hidden they are neither drawn nor picked, while Rig mode picks them again.
#[test]
fn pose_mode_draws_leaf_vertices_small_or_hides_them_from_picking() {
    use starcages_editor::state::{LeafVertices, leaf_only_vertices};
    use starcages_editor::ui::{pick, vertex_on_screen};
    let mut harness = crate::common::harness();
    let state = &harness.state().state;
    assert_eq!(state.view.leaf_vertices, LeafVertices::Small);
    let leaf_only = leaf_only_vertices(&state.doc.scene.cages);
    assert!(
        !leaf_only.is_empty(),
        "the critter has leaf vertices under its controls"
    );
    // A leaf vertex whose screen position picks it while shown.
    let (v, at) = leaf_only
        .iter()
        .find_map(|&v| {
            let at = vertex_on_screen(state, v)?;
            let pointer = glam::Vec2::new(at.x, at.y);
            (pick(state, pointer) == Some(v)).then_some((v, pointer))
        })
        .expect("a leaf vertex picked where it is drawn");
    harness
        .state_mut()
        .run(Command::SetLeafVertices(LeafVertices::Hidden));
    harness.run_steps(1);
    let state = &harness.state().state;
    assert_ne!(
        pick(state, at),
        Some(v),
        "a hidden leaf vertex is not picked"
    );
    assert!(!state.pickable()[v as usize]);
    harness
        .state_mut()
        .run(Command::SetMode(starcages_editor::state::EditMode::Rig));
    harness.run_steps(1);
    assert!(
        harness.state().state.pickable()[v as usize],
        "Rig mode picks it again"
    );
    harness.get_by_label_contains("Leaf vertices in Pose mode");
}

/// Shift+right click on the mesh places the 3D cursor at the mesh point under the pointer, and
/// the 3D Cursor pivot turns the selection about it (R Z 90 in Rig mode).
#[test]
fn shift_right_click_places_the_3d_cursor_and_r_turns_about_it() {
    let mut harness = crate::common::harness();
    send(
        &mut harness,
        Command::SetMode(starcages_editor::state::EditMode::Rig),
    );
    // A rest mesh vertex in view, and where it is drawn.
    let (target, pointer) = {
        let state = &harness.state().state;
        let rect = state.view.viewport;
        let mesh = state.doc.scene.mesh.welded_positions();
        mesh.iter()
            .step_by(97)
            .find_map(|&p| {
                let (pixel, _) = state.view.camera.project(p.as_vec3(), rect.size)?;
                let pointer = rect.min + pixel;
                let under = starcages_editor::ui::mesh_point_under(state, pointer)?;
                (under == p).then_some((p, pointer))
            })
            .expect("a mesh vertex picked where it is drawn")
    };
    let pos = egui::pos2(pointer.x, pointer.y);
    harness.hover_at(pos);
    for pressed in [true, false] {
        harness.event_modifiers(
            egui::Event::PointerButton {
                pos,
                button: egui::PointerButton::Secondary,
                pressed,
                modifiers: egui::Modifiers::SHIFT,
            },
            egui::Modifiers::SHIFT,
        );
    }
    harness.run_steps(2);
    assert_eq!(harness.state().state.view.cursor, Some(target));
    // The 3D Cursor pivot from the menu; R Z 90 turns a vertex about the cursor.
    harness.get_by_label("Pivot point").click();
    harness.run_steps(2);
    harness.get_by_label("3D Cursor").click();
    harness.run_steps(2);
    let v = 0u32;
    let before = harness.state().state.doc.scene.cages.vertices[v as usize];
    send(
        &mut harness,
        Command::Select {
            vertices: vec![v],
            mode: starcages_editor::state::SelectMode::Replace,
        },
    );
    let centre = harness.state().state.view.viewport.center();
    harness.hover_at(egui::pos2(centre.x, centre.y));
    rotate_z_90(&mut harness);
    let after = harness.state().state.doc.scene.cages.vertices[v as usize];
    let turn = glam::DQuat::from_axis_angle(glam::DVec3::Z, 90f64.to_radians());
    let expected = target + turn * (before - target);
    assert!(after.distance(expected) < 1e-6, "{after} vs {expected}");
}

/// R, Z, 90 typed, Enter: the selection turned 90° about Z about the pivot.
fn rotate_z_90(harness: &mut egui_kittest::Harness<'static, starcages_editor::EditorApp>) {
    harness.key_press(egui::Key::R);
    harness.run_steps(1);
    for text in ["z", "9", "0"] {
        harness.event(egui::Event::Text(text.into()));
        harness.run_steps(1);
    }
    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
}

/// The Active Element pivot turns the selection about the last vertex picked (Shift adds it
/// and makes it active), as Blender's: the active vertex stays, the other turns about it.
#[test]
fn the_active_element_pivot_turns_about_the_last_vertex_picked() {
    use starcages_editor::state::SelectMode;
    let mut harness = crate::common::harness();
    send(
        &mut harness,
        Command::SetMode(starcages_editor::state::EditMode::Rig),
    );
    let (a, b) = (0u32, 5u32);
    send(
        &mut harness,
        Command::Select {
            vertices: vec![a],
            mode: SelectMode::Replace,
        },
    );
    send(
        &mut harness,
        Command::Select {
            vertices: vec![b],
            mode: SelectMode::Add,
        },
    );
    assert_eq!(harness.state().state.selection.active, Some(b));
    harness.get_by_label("Pivot point").click();
    harness.run_steps(2);
    harness.get_by_label("Active Element").click();
    harness.run_steps(2);
    let before = harness.state().state.doc.scene.cages.vertices.clone();
    let centre = harness.state().state.view.viewport.center();
    harness.hover_at(egui::pos2(centre.x, centre.y));
    rotate_z_90(&mut harness);
    let after = &harness.state().state.doc.scene.cages.vertices;
    let turn = glam::DQuat::from_axis_angle(glam::DVec3::Z, 90f64.to_radians());
    let pivot = before[b as usize];
    assert!(
        after[b as usize].distance(pivot) < 1e-9,
        "the active vertex stays"
    );
    let expected = pivot + turn * (before[a as usize] - pivot);
    assert!(after[a as usize].distance(expected) < 1e-6);
}

/// R on a control of an auto rig keeps the volume at its joint (the live rig settles the ring
/// the turn moved), and one Ctrl+Z gives the pose back as it was, ring included.
#[test]
fn r_on_a_control_keeps_the_volume_at_its_joint_and_undoes_in_one_step() {
    use glam::DVec3;
    use starcages_core::generate::{AutorigSettings, autorig, autorig_settings};
    use starcages_core::hierarchy::{CageEdit, Hierarchy};
    use starcages_core::mesh::Mesh;
    use starcages_core::scene::{MeshSource, Scene};
    // Two overlapping boxes: a body and an arm out along +X.
    let (mut positions, mut triangles) = (Vec::new(), Vec::new());
    for (lo, hi) in [
        (DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 1.0, 1.5)),
        (DVec3::new(0.8, 0.35, 0.6), DVec3::new(3.2, 0.65, 0.9)),
    ] {
        let b = positions.len() as u32;
        for c in 0..8 {
            let pick = |bit: u32, l: f64, h: f64| if c & bit == 0 { l } else { h };
            positions.push(DVec3::new(
                pick(1, lo.x, hi.x),
                pick(2, lo.y, hi.y),
                pick(4, lo.z, hi.z),
            ));
        }
        for face in starcages_core::cage::shapes::BOX_FACES {
            let [p, q, r, s] = face.map(|k| b + k as u32);
            triangles.push([p, q, r]);
            triangles.push([p, r, s]);
        }
    }
    let mesh = Mesh::new(positions, triangles, None, None).unwrap();
    let control = starcages_core::BindControl::default();
    let rig = autorig(&mesh, &AutorigSettings::default(), &control).unwrap();
    let scene = Scene::new(MeshSource::Embedded, mesh, rig.cages, autorig_settings());
    // The arm's sixth control (the arm lies on the body's plane of symmetry, front to back, so
    // it has no side: `limb.1.6`).
    let name = scene
        .cages
        .internals
        .iter()
        .map(|c| c.name.clone())
        .find(|n| n.ends_with(".6"))
        .unwrap();
    let vertices = scene.cages.cage_vertices(&name).unwrap();
    // The mitre alone, through the hierarchy: the volume the turn loses without the pass.
    let edit: CageEdit = format!("{name}: rotate 0 0 1 90").parse().unwrap();
    let mut mitred = scene.cages.vertices.clone();
    let moves = edit.moves(&scene.cages, &mitred).unwrap();
    Hierarchy::bind(&scene)
        .unwrap()
        .apply(&mut mitred, &moves)
        .unwrap();
    let (mut harness, _) = crate::common::harness_on(Document {
        scene,
        path: None,
        dirty: false,
    });
    settle(&mut harness);
    let welded = harness
        .state()
        .state
        .doc
        .scene
        .mesh
        .welded_triangles()
        .to_vec();
    let volume = |points: &[DVec3]| -> f64 {
        welded
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| points[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    };
    let deformed = |harness: &egui_kittest::Harness<'static, starcages_editor::EditorApp>| {
        let state = &harness.state().state;
        state
            .deformed()
            .iter()
            .map(|p| p.as_dvec3())
            .collect::<Vec<_>>()
    };
    let rest_volume = volume(&deformed(&harness));
    let mitred_mesh: Vec<DVec3> = {
        let rig = harness.state().state.rig.as_ref().unwrap();
        let rest = &harness.state().state.doc.scene.cages.vertices;
        rig.binding
            .deform(rest, &mitred)
            .iter()
            .map(|p| p.as_dvec3())
            .collect()
    };
    let mitred_change = volume(&mitred_mesh) / rest_volume - 1.0;
    let before = harness.state().state.doc.scene.pose.clone();
    let centre = harness.state().state.view.viewport.center();
    harness.hover_at(egui::pos2(centre.x, centre.y));
    send(
        &mut harness,
        Command::Select {
            vertices,
            mode: starcages_editor::state::SelectMode::Replace,
        },
    );
    rotate_z_90(&mut harness);
    let after = harness.state().state.doc.scene.pose.clone();
    assert_ne!(after, before, "the control turned");
    let kept_change = volume(&deformed(&harness)) / rest_volume - 1.0;
    // Issue 41's 2 %. The arm's mesh has no vertex near the joint, so its ring widens to the
    // bound of its scale and keeps only part of what the mitre lost (`joint_volume`).
    assert!(
        mitred_change.abs() > 0.01
            && kept_change.abs() < 0.02
            && kept_change.abs() < 0.5 * mitred_change.abs(),
        "the mesh's volume changed by {:.2} % (the mitre alone {:.2} %)",
        100.0 * kept_change,
        100.0 * mitred_change
    );
    crate::common::undo(&mut harness);
    assert_eq!(harness.state().state.doc.scene.pose, before);
}
