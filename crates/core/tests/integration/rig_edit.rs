//! Rig operations: extrude gives two cages sharing exactly one face, delete and add undo each
//! other exactly, mirror is exact, rest edits move the poses along and re-bind incrementally
//! to what a full bind gives, and bad operations are refused with the scene unchanged.

use glam::DVec3;
use starcages_core::BindControl;
use starcages_core::check::validate_scene;
use starcages_core::rig::{RigEditError, RigOp, apply_rig_op};
use starcages_core::scene::{OutsidePolicy, Scene};
use starcages_core::star::StarBinding;

use crate::common::empty_scene;

fn op(text: &str) -> RigOp {
    RigOp::parse(text).unwrap()
}

/// The volume of leaf cage `c` of `scene`.
fn leaf_volume(scene: &Scene, c: usize) -> f64 {
    starcages_core::scene::LocalCage::new(&scene.cages.vertices, &scene.cages.leaves[c].faces)
        .unwrap()
        .cage
        .volume()
}

#[test]
fn a_box_and_an_extrusion_build_a_valid_two_cage_rig_sharing_one_face() {
    let mut scene = empty_scene();
    apply_rig_op(&mut scene, &op("add-box body 0 0 0 1 1 1")).unwrap();
    // Face 1 of a box is its top (z = max), counter-clockwise from outside.
    let top = scene.cages.leaves[0]
        .faces
        .iter()
        .position(|f| f.iter().all(|&v| scene.cages.vertices[v as usize].z == 1.0))
        .unwrap();
    apply_rig_op(&mut scene, &op(&format!("extrude body {top} 1 neck"))).unwrap();
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    let adjacency = scene.cages.adjacency();
    assert_eq!(adjacency.len(), 1);
    assert_eq!(adjacency[0].faces.len(), 1, "exactly one shared face");
    assert_eq!(scene.cages.vertices.len(), 12);
    assert_eq!(
        scene.pose.len(),
        12,
        "new vertices start at rest in the pose"
    );
    // It binds and deforms; a rest edit re-binds incrementally to the full bind.
    let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
    let mut edited = scene.clone();
    apply_rig_op(&mut edited, &op("rest neck: scale 1.2")).unwrap();
    let moved: Vec<u32> = (0..edited.cages.vertices.len() as u32)
        .filter(|&v| edited.cages.vertices[v as usize] != scene.cages.vertices[v as usize])
        .collect();
    assert!(!moved.is_empty());
    let incremental = binding
        .rebind_rest_edit(&edited, &moved, &BindControl::default())
        .unwrap();
    let full = StarBinding::bind_scene(&edited, &BindControl::default()).unwrap();
    let (a, b) = (
        incremental.deform(&edited.cages.vertices, &edited.pose),
        full.deform(&edited.cages.vertices, &edited.pose),
    );
    let worst = a
        .iter()
        .zip(&b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max);
    assert!(worst < 1e-5, "{worst}");
}

#[test]
fn adding_then_deleting_gives_back_the_scene_and_mirror_is_exact() {
    let mut scene = empty_scene();
    scene.settings.outside = OutsidePolicy::Nearest;
    apply_rig_op(&mut scene, &op("add-box right 0 0 0 1 1 2")).unwrap();
    let before = scene.clone();
    apply_rig_op(&mut scene, &op("add-box extra 1 0 0 2 1 2 gc")).unwrap();
    assert_eq!(
        scene.cages.vertices.len(),
        12,
        "the shared face's corners are reused"
    );
    apply_rig_op(&mut scene, &op("delete extra")).unwrap();
    assert_eq!(scene, before, "delete undoes add exactly");
    // Mirror across x = 0: the x = 0 face is shared, every other vertex mirrored exactly.
    apply_rig_op(&mut scene, &op("mirror right left")).unwrap();
    let left = scene.cages.leaf_index("left").unwrap();
    for face in &scene.cages.leaves[left].faces {
        for &v in face {
            let p = scene.cages.vertices[v as usize];
            let mirror = DVec3::new(-p.x, p.y, p.z);
            assert!(scene.cages.vertices.contains(&mirror));
        }
    }
    assert_eq!(scene.cages.vertices.len(), 12);
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    assert_eq!(scene.cages.adjacency().len(), 1);
}

#[test]
fn bad_operations_are_refused_and_leave_the_scene_unchanged() {
    let mut scene = empty_scene();
    apply_rig_op(&mut scene, &op("add-box a 0 0 0 1 1 1")).unwrap();
    apply_rig_op(&mut scene, &op("extrude a 1 0.5 b")).unwrap();
    let before = scene.clone();
    let shared = scene.cages.leaves[0]
        .faces
        .iter()
        .position(|f| {
            let mut k = f.clone();
            k.sort_unstable();
            scene.cages.leaves[1].faces.iter().any(|g| {
                let mut h = g.clone();
                h.sort_unstable();
                h == k
            })
        })
        .unwrap();
    for (text, expected) in [
        (
            format!("extrude a {shared} 1 c"),
            "shared with another cage",
        ),
        ("extrude a 99 1 c".to_owned(), "face 99 does not exist"),
        ("extrude nobody 0 1 c".to_owned(), "no leaf cage 'nobody'"),
        ("add-box a 0 0 0 1 1 1".to_owned(), "exists already"),
        ("add-box flat 0 0 0 1 1 0".to_owned(), "flat"),
        ("rest a: scale -1".to_owned(), "must be positive"),
    ] {
        let error = apply_rig_op(&mut scene, &op(&text))
            .unwrap_err()
            .to_string();
        assert!(error.contains(expected), "{text}: {error}");
        assert_eq!(scene, before, "{text} changed the scene");
    }
    for text in [
        "extrude a one 1",
        "spin a",
        "add-box x 0 0 0 1 1 z",
        "rest a: twist 3",
    ] {
        assert!(
            matches!(RigOp::parse(text), Err(RigEditError::Syntax { .. })),
            "{text}"
        );
    }
}

#[test]
fn a_loop_cut_gives_two_cages_sharing_the_new_face_and_merge_dissolves_it() {
    let mut scene = empty_scene();
    apply_rig_op(&mut scene, &op("add-box tall 0 0 0 1 1 2")).unwrap();
    let before = scene.clone();
    apply_rig_op(&mut scene, &op("split tall z 0.25 upper")).unwrap();
    assert_eq!(scene.cages.leaves.len(), 2);
    assert_eq!(scene.cages.vertices.len(), 12);
    let cut: Vec<f64> = scene.cages.vertices[8..].iter().map(|p| p.z).collect();
    assert!(cut.iter().all(|&z| (z - 0.5).abs() < 1e-12), "{cut:?}");
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    let adjacency = scene.cages.adjacency();
    assert_eq!(adjacency.len(), 1);
    assert_eq!(adjacency[0].faces.len(), 1);
    // It binds; merge gives back one cage over the same volume.
    StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
    apply_rig_op(&mut scene, &op("merge tall upper")).unwrap();
    assert_eq!(scene.cages.leaves.len(), 1);
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    assert!((leaf_volume(&scene, 0) - leaf_volume(&before, 0)).abs() < 1e-12);
    // Refusals: not neighbours, a cut out of range, a ring face shared with a neighbour.
    apply_rig_op(&mut scene, &op("add-box far 3 0 0 4 1 1")).unwrap();
    let error = apply_rig_op(&mut scene, &op("merge tall far"))
        .unwrap_err()
        .to_string();
    assert!(error.contains("share no face"), "{error}");
    let error = apply_rig_op(&mut scene, &op("split tall z 1.5"))
        .unwrap_err()
        .to_string();
    assert!(error.contains("inside (0, 1)"), "{error}");
    let mut pair = empty_scene();
    apply_rig_op(&mut pair, &op("add-box a 0 0 0 1 1 2")).unwrap();
    apply_rig_op(&mut pair, &op("add-box side 1 0 0 2 1 2")).unwrap();
    let error = apply_rig_op(&mut pair, &op("split a z 0.5"))
        .unwrap_err()
        .to_string();
    assert!(error.contains("T-junction"), "{error}");
    // Across x, the shared face is an end: that cut is fine.
    apply_rig_op(&mut pair, &op("split a x 0.5")).unwrap();
    assert_eq!(pair.cages.adjacency().len(), 2);
}

/// Fit pulls a loose box in to the mesh: every mesh vertex stays inside with the margin, the
/// cage gets smaller, and vertices shared with a neighbour stay where they are.
#[test]
fn fit_pulls_a_cage_to_the_mesh_keeping_the_margin_and_shared_vertices() {
    let mut scene = empty_scene();
    // The mesh spans (0.1, 0.1, 0.1) .. (0.9, 0.9, 1.8); a loose box around its lower part
    // and a neighbour above.
    apply_rig_op(&mut scene, &op("add-box low -0.5 -0.5 -0.5 1.5 1.5 1")).unwrap();
    apply_rig_op(&mut scene, &op("add-box high -0.5 -0.5 1 1.5 1.5 2.5")).unwrap();
    let before = scene.clone();
    apply_rig_op(&mut scene, &op("fit low 0.01")).unwrap();
    assert!(
        leaf_volume(&scene, 0) < 0.8 * leaf_volume(&before, 0),
        "the cage did not shrink"
    );
    // The shared face (z = 1) did not move.
    for face in &before.cages.leaves[1].faces {
        for &v in face {
            assert_eq!(
                scene.cages.vertices[v as usize],
                before.cages.vertices[v as usize]
            );
        }
    }
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    let local =
        starcages_core::scene::LocalCage::new(&scene.cages.vertices, &scene.cages.leaves[0].faces)
            .unwrap();
    let (lo, hi) = scene.mesh.bounds();
    let gap = 0.01 * (hi - lo).length();
    let low: Vec<&DVec3> = scene
        .mesh
        .welded_positions()
        .iter()
        .filter(|p| p.z < 1.0)
        .collect();
    assert!(
        !low.is_empty(),
        "the mesh has vertices below z = 1 for the fitted cage"
    );
    for p in low {
        assert!(local.cage.winding_number(*p) > 0.5);
        assert!(
            local.cage.closest_point(*p).2 >= gap * 0.999,
            "{p} too close"
        );
    }
    assert!(
        apply_rig_op(&mut scene, &op("fit low 2")).is_err(),
        "a margin out of range"
    );
}

/// A mesh vertex that starts closer to a face than the margin keeps its distance but does not
/// freeze the fit: the cage's other vertices still close in on the mesh, and the rig stays
/// valid (no vertices crowded together).
#[test]
fn fit_works_around_a_vertex_already_inside_the_margin() {
    let mut scene = empty_scene();
    // The mesh's x = 0.1 side is 0.01 from this box's x = 0.09 face: inside the 2 % margin.
    apply_rig_op(&mut scene, &op("add-box low 0.09 -0.5 -0.5 1.5 1.5 1")).unwrap();
    apply_rig_op(&mut scene, &op("add-box high 0.09 -0.5 1 1.5 1.5 2.5")).unwrap();
    let before = scene.clone();
    apply_rig_op(&mut scene, &op("fit low 0.02")).unwrap();
    assert!(
        leaf_volume(&scene, 0) < 0.8 * leaf_volume(&before, 0),
        "{} against {}",
        leaf_volume(&scene, 0),
        leaf_volume(&before, 0)
    );
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
}

/// A scene whose faces name missing vertices (read from a broken file) is refused, not
/// indexed.
#[test]
fn a_structurally_broken_scene_is_refused_not_indexed() {
    let mut scene = empty_scene();
    apply_rig_op(&mut scene, &op("add-box a 0 0 0 1 1 1")).unwrap();
    scene.cages.leaves[0].faces[0][0] = 999;
    for text in [
        "extrude a 1 0.5 b",
        "split a z 0.5",
        "mirror a",
        "fit a 0.01",
        "rest a: scale 2",
        "delete a",
    ] {
        let error = apply_rig_op(&mut scene, &op(text)).unwrap_err().to_string();
        assert!(error.contains("refers to vertex 999"), "{text}: {error}");
    }
}
