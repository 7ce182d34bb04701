//! Drags of internal cages: after their first update they go through a driver map (a few
//! weights per mesh row instead of the sparse product), show what the full product shows, and
//! end exact.

use glam::{DQuat, DVec3, Vec3};
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::demo::demo_scene;
use starcages_core::scene::Scene;
use starcages_editor::state::GestureId;
use starcages_editor::{Command, Document, EditorApp};

/// The largest distance between two meshes' vertices.
fn farthest(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.distance(*y))
        .fold(0.0, f32::max)
}

/// The app on `scene` (a critter), a gesture begun, the head cage's vertices and where they
/// start.
fn head_drag(scene: Scene) -> (EditorApp, Vec<u32>, Vec<DVec3>) {
    let doc = Document {
        scene,
        path: None,
        dirty: false,
    };
    let mut app = EditorApp::new(doc, None, false);
    app.wait_for_jobs();
    let drivers = app.state.doc.scene.cages.cage_vertices("head").unwrap();
    let start: Vec<DVec3> = drivers
        .iter()
        .map(|&d| app.state.doc.scene.pose[d as usize])
        .collect();
    app.run(Command::BeginGesture {
        id: GestureId(1),
        label: "drag".into(),
    });
    (app, drivers, start)
}

/// Turning the critter's head cage (every leaf follows it) in steps, as R does: from the
/// second step the rig holds a driver map and the mesh is the full product's to f32 rounding;
/// when the gesture ends the map is gone and the mesh is the full product's bit for bit.
#[test]
fn an_internal_cage_drag_goes_through_a_driver_map_and_ends_exact() {
    let mut scene = demo_scene("critter", 0.4).unwrap();
    for leaf in &mut scene.cages.leaves {
        leaf.kind = CoordinateKind::MeanValue; // its right ear is Green: no map over it
    }
    let (mut app, drivers, start) = head_drag(scene);
    let centre = start.iter().sum::<DVec3>() / start.len() as f64;
    for step in 1..=4 {
        let turn = DQuat::from_rotation_z(0.15 * f64::from(step));
        let moves = drivers
            .iter()
            .zip(&start)
            .map(|(&d, &p)| (d, centre + turn * (p - centre)))
            .collect();
        app.run(Command::MoveVertices(moves));
        let rig = app.state.rig.as_ref().unwrap();
        assert!(
            rig.drag_map().is_some(),
            "step {step}: a map after the first update"
        );
        let scene = &app.state.doc.scene;
        let full = rig.binding.deform(&scene.cages.vertices, &scene.pose);
        let (lo, hi) = scene.mesh.bounds();
        let size = (hi - lo).length() as f32;
        let error = farthest(&full, rig.deformed());
        assert!(error <= 1e-5 * size, "step {step}: {error}");
        let moved = farthest(&full, rig.rest_view().positions());
        assert!(
            moved > 1e-2 * size,
            "step {step}: the head turned by {moved}"
        );
    }
    app.run(Command::EndGesture { keep: true });
    let rig = app.state.rig.as_ref().unwrap();
    assert!(rig.drag_map().is_none());
    let scene = &app.state.doc.scene;
    assert_eq!(
        **rig.deformed(),
        rig.binding.deform(&scene.cages.vertices, &scene.pose)
    );
}

/// Over the critter's Green right ear the head's drag has no map: the first update finds so
/// and later ones do not try again; every update is the full product's, and the gesture's end
/// forgets it.
#[test]
fn a_drag_over_a_green_cage_tries_for_a_map_once() {
    let (mut app, drivers, start) = head_drag(demo_scene("critter", 0.4).unwrap());
    for step in 1..=3 {
        let offset = DVec3::new(0.02, 0.0, 0.01) * f64::from(step);
        let moves = drivers
            .iter()
            .zip(&start)
            .map(|(&d, &p)| (d, p + offset))
            .collect();
        app.run(Command::MoveVertices(moves));
        let rig = app.state.rig.as_ref().unwrap();
        assert!(rig.drag_map().is_none(), "step {step}");
        assert_eq!(rig.drag_without_map(), Some(&drivers[..]), "step {step}");
        let scene = &app.state.doc.scene;
        let full = rig.binding.deform(&scene.cages.vertices, &scene.pose);
        assert_eq!(**rig.deformed(), full, "step {step}");
    }
    app.run(Command::EndGesture { keep: true });
    assert!(app.state.rig.as_ref().unwrap().drag_without_map().is_none());
}
