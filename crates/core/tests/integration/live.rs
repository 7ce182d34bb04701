//! The live rig: moves and drags keep the DOFs (updated column by column) and the mesh equal
//! to a full deformation of the pose, with a negative control; what a change of the scene
//! makes stale.

use std::sync::Arc;

use glam::DVec3;
use starcages_core::BindControl;
use starcages_core::generate::demo::demo_scene;
use starcages_core::hierarchy::{CageEdit, Hierarchy};
use starcages_core::live::{LiveRig, RebindScope};
use starcages_core::scene::Scene;
use starcages_core::star::StarBinding;

fn live(scene: &Scene) -> LiveRig {
    let binding = StarBinding::bind_scene(scene, &BindControl::default()).unwrap();
    let hierarchy = Hierarchy::bind(scene).unwrap();
    let bound_for = (scene.cages.clone(), scene.settings);
    LiveRig::new(Arc::new(binding), hierarchy, bound_for, scene)
}

fn moves(scene: &Scene, edit: &str) -> Vec<(u32, DVec3)> {
    let edit: CageEdit = edit.parse().unwrap();
    edit.moves(&scene.cages, &scene.pose).unwrap()
}

#[test]
fn moves_and_drags_keep_dofs_and_mesh_those_of_a_full_deformation() {
    let mut scene = demo_scene("critter", 0.3).unwrap();
    // Mean value cages only: a drag through them has a driver map (a Green cage has none).
    use starcages_core::coords::CoordinateKind;
    for cage in &mut scene.cages.internals {
        cage.kind = CoordinateKind::MeanValue;
    }
    for cage in &mut scene.cages.leaves {
        if cage.kind == CoordinateKind::Green {
            cage.kind = CoordinateKind::MeanValue;
        }
    }
    let mut rig = live(&scene);
    assert!(rig.is_up_to_date(&scene));
    // The CPU mesh read, as picking or a viewport without compute reads it: kept up to date
    // move by move from here on.
    let _ = rig.deformed();
    // Single moves of a leaf cage and of an internal cage (whose leaf cages follow).
    for edit in ["ear_left: translate 0 0 0.1", "head: rotate 0 0 1 10"] {
        let m = moves(&scene, edit);
        let changed = rig.move_vertices(&mut scene, &m, false).unwrap();
        assert!(!changed.is_empty());
        assert!(rig.is_up_to_date(&scene), "after {edit}");
        assert_eq!(scene.pose_state, rig.hierarchy.state());
    }
    // A drag of the ears' internal cage: steps through the driver map, exact at its end.
    for step in 1..=4 {
        let m = moves(&scene, &format!("ears: rotate 1 0 0 {}", -2 * step));
        rig.move_vertices(&mut scene, &m, true).unwrap();
        let full = rig
            .binding
            .operator
            .dofs(&scene.cages.vertices, &scene.pose);
        assert_eq!(
            **rig.dofs(),
            full,
            "step {step}: the DOFs follow column by column"
        );
        assert!(
            rig.drag_map().is_some(),
            "step {step}: the first update builds the map"
        );
    }
    rig.end_drag(&scene);
    assert!(rig.is_up_to_date(&scene));
    // Negative control: a pose changed behind the rig's back is caught.
    scene.pose[0] += DVec3::new(0.0, 0.0, 0.05);
    assert!(!rig.is_up_to_date(&scene));
}

#[test]
fn a_scene_change_makes_stale_only_what_it_touches() {
    let scene = demo_scene("bar", 0.3).unwrap();
    let rig = live(&scene);
    assert!(matches!(
        rig.rebind_scope(&scene),
        RebindScope::Hierarchy(_)
    ));
    let mut h = scene.clone();
    h.cages.leaves[1].h = Some(0.3);
    assert!(matches!(rig.rebind_scope(&h), RebindScope::Leaves(_, leaves, true) if leaves == [1]));
    let mut rest = scene.clone();
    rest.cages.vertices[3] += DVec3::new(0.0, 0.0, 0.01);
    assert!(matches!(rig.rebind_scope(&rest), RebindScope::RestEdit(_, moved) if moved == [3]));
    let mut settings = scene.clone();
    settings.settings.default_h = 0.25;
    assert!(matches!(rig.rebind_scope(&settings), RebindScope::Preview));
}

/// The CPU mesh is computed only when something reads it: moves and drags without a reader
/// update the DOFs alone (and build no driver map); a read then gives the full product.
#[test]
fn the_cpu_mesh_is_computed_only_when_read() {
    let mut scene = demo_scene("critter", 0.3).unwrap();
    let mut rig = live(&scene);
    assert!(
        rig.mesh().computed_positions().is_none(),
        "nothing read it yet"
    );
    for step in 1..=3 {
        let m = moves(&scene, &format!("ears: rotate 1 0 0 {}", -3 * step));
        rig.move_vertices(&mut scene, &m, true).unwrap();
        assert!(rig.mesh().computed_positions().is_none(), "step {step}");
        assert!(rig.drag_map().is_none(), "no map without a reader");
    }
    rig.end_drag(&scene);
    assert!(rig.is_up_to_date(&scene));
    let full = rig.binding.deform(&scene.cages.vertices, &scene.pose);
    assert_eq!(**rig.deformed(), full, "a read gives the full product");
    assert!(rig.mesh().computed_positions().is_some());
}
