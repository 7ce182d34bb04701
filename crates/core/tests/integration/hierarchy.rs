//! Multi-level deformation (section 3.4): internal cages drive lower-level cage vertices,
//! edits propagate downwards only, hand edits survive parent moves, mesh weights are bound once.
#![allow(clippy::unwrap_used)]

use glam::{DMat3, DQuat, DVec3};
use proptest::prelude::*;
use starcages_core::BindControl;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::demo::demo_scene;
use starcages_core::hierarchy::{
    AutoInternalCage, AutoInternalCageError, CageEdit, Hierarchy, HierarchyError,
    RemoveInternalCageError, add_auto_internal_cage, remove_internal_cage,
};
use starcages_core::scene::{FollowRecord, Scene, SceneProblem};
use starcages_core::star::StarBinding;

/// Adds the parent's moves for the pose it is given.
type ParentMove<'a> = &'a dyn Fn(&mut Vec<(u32, DVec3)>, &[DVec3]);

fn critter() -> Scene {
    demo_scene("critter", 0.4).unwrap()
}

fn internal(scene: &Scene, name: &str) -> usize {
    scene
        .cages
        .internals
        .iter()
        .position(|c| c.name == name)
        .unwrap()
}

/// Applies a whole-cage edit written as text.
fn edit(scene: &Scene, hierarchy: &mut Hierarchy, pose: &mut [DVec3], text: &str) -> Vec<u32> {
    let edit: CageEdit = text.parse().unwrap();
    let moves = edit.moves(&scene.cages, pose).unwrap();
    hierarchy.apply(pose, &moves).unwrap()
}

fn leaf_vertices(scene: &Scene) -> Vec<u32> {
    let mut v: Vec<u32> = scene
        .cages
        .leaves
        .iter()
        .flat_map(|c| c.faces.iter().flatten().copied())
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

fn max_distance(a: &[DVec3], b: &[DVec3], only: &[u32]) -> f64 {
    only.iter()
        .map(|&v| a[v as usize].distance(b[v as usize]))
        .fold(0.0, f64::max)
}

#[test]
fn the_root_reaches_every_leaf_vertex_and_the_middle_cage_some() {
    let scene = critter();
    let h = Hierarchy::bind(&scene).unwrap();
    let head = h.reach(internal(&scene, "head"));
    for v in leaf_vertices(&scene) {
        assert!(head.contains(&v), "the root misses leaf vertex {v}");
    }
    let ears = h.reach(internal(&scene, "ears"));
    assert_eq!(ears.len(), 6);
    assert_eq!(h.parent_of(ears[0]), Some("ears"));
    assert_eq!(h.stats().bound_at_rest, 6 + 27 + 8);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]

    /// An affine map of the MVC root moves everything it reaches, and the mesh, by that map.
    #[test]
    fn an_affine_map_of_the_root_moves_everything_by_that_map(
        m in prop::array::uniform9(-0.3f64..0.3),
        t in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let mut scene = critter();
        // GC leaves reproduce similarities only: make every leaf MVC for a general affine map.
        for leaf in &mut scene.cages.leaves {
            leaf.kind = CoordinateKind::MeanValue;
        }
        let map = DMat3::IDENTITY + DMat3::from_cols_array(&m);
        let affine = |p: DVec3| map * p + DVec3::from_array(t);
        let mut h = Hierarchy::bind(&scene).unwrap();
        let head = internal(&scene, "head");
        let head_vertices = scene.cages.cage_vertices("head").unwrap();
        let mut pose = scene.pose.clone();
        let moves: Vec<(u32, DVec3)> =
            head_vertices.iter().map(|&v| (v, affine(pose[v as usize]))).collect();
        h.apply(&mut pose, &moves).unwrap();
        let expected: Vec<DVec3> = scene.pose.iter().map(|&p| affine(p)).collect();
        // The ears cage is HC: linear precision holds to its solver tolerance.
        prop_assert!(max_distance(&pose, &expected, &h.reach(head)) < 1e-6);
        let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
        let mesh = binding.deform(&scene.cages.vertices, &pose);
        let worst = scene
            .mesh
            .welded_positions()
            .iter()
            .zip(&mesh)
            .map(|(p, q)| affine(*p).distance(q.as_dvec3()))
            .fold(0.0, f64::max);
        prop_assert!(worst < 1e-4, "mesh off the affine image by {worst}");
    }

    /// A similarity of a GC internal cage moves what it reaches by that similarity.
    #[test]
    fn a_similarity_of_a_green_internal_cage_is_reproduced(
        axis in prop::array::uniform3(-1.0f64..1.0),
        angle in -1.5f64..1.5,
        scale in 0.5f64..2.0,
        t in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let axis = DVec3::from_array(axis).try_normalize().unwrap_or(DVec3::Z);
        let mut scene = critter();
        let ears = internal(&scene, "ears");
        scene.cages.internals[ears].kind = CoordinateKind::Green;
        let similarity = |p: DVec3| DQuat::from_axis_angle(axis, angle) * p * scale + DVec3::from_array(t);
        let mut h = Hierarchy::bind(&scene).unwrap();
        let mut pose = scene.pose.clone();
        let moves: Vec<(u32, DVec3)> = scene
            .cages
            .cage_vertices("ears")
            .unwrap()
            .iter()
            .map(|&v| (v, similarity(pose[v as usize])))
            .collect();
        h.apply(&mut pose, &moves).unwrap();
        let expected: Vec<DVec3> = scene.pose.iter().map(|&p| similarity(p)).collect();
        prop_assert!(max_distance(&pose, &expected, &h.reach(ears)) < 1e-8);
    }
}

/// Fig. 13: a leaf, its parent, the grandparent, then a leaf again. Hand edits are carried
/// along by later parent moves, neither lost nor doubled; the parent of a moved vertex never
/// moves; mesh weights are bound exactly once.
#[test]
fn the_fig13_sequence_carries_hand_edits_along() {
    let scene = critter();
    let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
    let mesh_binds = 1;
    let mut h = Hierarchy::bind(&scene).unwrap();
    let mut pose = scene.pose.clone();
    let rest = pose.clone();
    let ears_cage = scene.cages.cage_vertices("ears").unwrap();
    let head_cage = scene.cages.cage_vertices("head").unwrap();

    // (b) Leaf: scale the left ear. Only its own vertices move: parents are not affected.
    let changed = edit(&scene, &mut h, &mut pose, "ear_left: scale 1.3");
    assert_eq!(changed, scene.cages.cage_vertices("ear_left").unwrap());
    let after_leaf = pose.clone();
    assert!(
        ears_cage
            .iter()
            .all(|&v| pose[v as usize] == rest[v as usize])
    );

    // (c) Parent: turn the ears cage. Every vertex it owns turns with it, the scaled left ear
    // included: the hand edit is carried along.
    let centre = ears_cage.iter().map(|&v| pose[v as usize]).sum::<DVec3>() / 8.0;
    let turn = DQuat::from_axis_angle(DVec3::X, (-25f64).to_radians());
    edit(&scene, &mut h, &mut pose, "ears: rotate 1 0 0 -25");
    let ears_reach = h.reach(internal(&scene, "ears"));
    for &v in &ears_reach {
        let expected = centre + turn * (after_leaf[v as usize] - centre);
        assert!(pose[v as usize].distance(expected) < 1e-7, "vertex {v}");
    }
    // The left ear's lower vertices belong to the head, which did not move.
    let ear_left = scene.cages.cage_vertices("ear_left").unwrap();
    let lower: Vec<u32> = ear_left
        .iter()
        .copied()
        .filter(|v| !ears_reach.contains(v))
        .collect();
    assert!(
        !lower.is_empty(),
        "the left ear has vertices the ears' cage does not reach"
    );
    for &v in &lower {
        assert_eq!(pose[v as usize], after_leaf[v as usize]);
    }
    let after_parent = pose.clone();
    let mesh_after_parent = binding.deform(&scene.cages.vertices, &pose);

    // (d) Grandparent: turn the head. Everything turns rigidly with it, both earlier edits
    // included, and the mesh with it.
    let centre = head_cage.iter().map(|&v| pose[v as usize]).sum::<DVec3>() / 8.0;
    let turn = DQuat::from_axis_angle(DVec3::Z, 20f64.to_radians());
    edit(&scene, &mut h, &mut pose, "head: rotate 0 0 1 20");
    let rigid = |p: DVec3| centre + turn * (p - centre);
    let all = h.reach(internal(&scene, "head"));
    let worst = all
        .iter()
        .map(|&v| pose[v as usize].distance(rigid(after_parent[v as usize])))
        .fold(0.0, f64::max);
    assert!(worst < 1e-7, "grandparent move off rigid by {worst}");
    let mesh = binding.deform(&scene.cages.vertices, &pose);
    let worst = mesh
        .iter()
        .zip(&mesh_after_parent)
        .map(|(q, p)| q.as_dvec3().distance(rigid(p.as_dvec3())))
        .fold(0.0, f64::max);
    assert!(worst < 1e-4, "mesh off rigid by {worst}");
    let after_grandparent = pose.clone();

    // (e) Leaf again: only the face cage's vertices move.
    let changed = edit(
        &scene,
        &mut h,
        &mut pose,
        "head_1_0_1: translate 0.15 -0.2 0",
    );
    assert_eq!(changed, scene.cages.cage_vertices("head_1_0_1").unwrap());

    // And the grandparent again: the face edit travels with it, once.
    edit(&scene, &mut h, &mut pose, "head: translate 0 0 0.5");
    let face = scene.cages.cage_vertices("head_1_0_1").unwrap();
    for &v in &face {
        let hand = after_grandparent[v as usize] + DVec3::new(0.15, -0.2, 0.0);
        assert!(
            pose[v as usize].distance(hand + DVec3::new(0.0, 0.0, 0.5)) < 1e-9,
            "vertex {v}: the hand edit was lost or doubled"
        );
    }
    // Coordinates were recomputed only for owned vertices moved by hand; the mesh was never
    // rebound: the one binding still reproduces an independent f64 evaluation from rest.
    let stats = h.stats();
    assert_eq!(stats.bound_at_rest, 41);
    // (c) the ear's 4 hand-moved tops; (d) its 4 lower vertices and the ears cage's 8;
    // the last head move: the face cage's 8.
    assert_eq!(stats.rebound, 4 + (4 + 8) + 8, "{stats:?}");
    assert_eq!(mesh_binds, 1);
    let mesh = binding.deform(&scene.cages.vertices, &pose);
    let reference = starcages_core::star::evaluate_points(
        &scene,
        scene.mesh.welded_positions(),
        &pose,
        &BindControl::default(),
    )
    .unwrap();
    let worst = mesh
        .iter()
        .zip(&reference)
        .map(|(a, b)| a.as_dvec3().distance(*b))
        .fold(0.0, f64::max);
    assert!(worst < 1e-4, "{worst}");
}

#[test]
fn internal_edits_leave_mesh_vertices_beyond_their_reach_bit_for_bit() {
    let scene = critter();
    let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
    let mut h = Hierarchy::bind(&scene).unwrap();
    let mut pose = scene.pose.clone();
    let before = binding.deform(&scene.cages.vertices, &pose);
    let changed = edit(&scene, &mut h, &mut pose, "ears: rotate 0 1 0 30");
    let ears = internal(&scene, "ears");
    let reach = h.reach(ears);
    let ears_vertices = scene.cages.cage_vertices("ears").unwrap();
    assert!(
        changed
            .iter()
            .all(|v| reach.contains(v) || ears_vertices.contains(v))
    );
    let after = binding.deform(&scene.cages.vertices, &pose);
    let columns = binding.operator.columns_of_moved_vertices(&reach);
    let touched = binding.operator.rows_touched(&columns);
    let mut unchanged = 0;
    for (i, (a, b)) in before.iter().zip(&after).enumerate() {
        if touched.binary_search(&(i as u32)).is_err() {
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits)
            );
            unchanged += 1;
        }
    }
    // The ears move, the rest of the head does not.
    assert!(
        unchanged > before.len() / 2,
        "{unchanged} of {}",
        before.len()
    );
    assert!(
        before
            .iter()
            .zip(&after)
            .any(|(a, b)| a.distance(*b) > 0.05)
    );
}

/// The λ·ΔU scheme: an owned vertex dragged out of its HC parent keeps following it, without
/// NaN, continuously in how far it was dragged, and exactly under affine parent moves.
#[test]
fn hc_parent_follows_a_vertex_dragged_outside_it() {
    let scene = critter();
    let ears = internal(&scene, "ears");
    let ears_vertices = scene.cages.cage_vertices("ears").unwrap();
    let owned = scene.cages.internals[ears].owns[0];
    let top = ears_vertices
        .iter()
        .map(|&v| scene.pose[v as usize].z)
        .fold(f64::MIN, f64::max);
    let start = scene.pose[owned as usize];
    let corner = ears_vertices[7];
    let response = |s: f64, parent_move: ParentMove<'_>| {
        let mut h = Hierarchy::bind(&scene).unwrap();
        let mut pose = scene.pose.clone();
        let target = DVec3::new(start.x, start.y, start.z + s * (top - start.z));
        h.apply(&mut pose, &[(owned, target)]).unwrap();
        let mut moves = Vec::new();
        parent_move(&mut moves, &pose);
        h.apply(&mut pose, &moves).unwrap();
        (pose[owned as usize], h.state())
    };
    // A non-affine parent move: one corner of the ears cage pulled up and out.
    let pull = |moves: &mut Vec<(u32, DVec3)>, pose: &[DVec3]| {
        moves.push((corner, pose[corner as usize] + DVec3::new(0.3, 0.2, 0.6)));
    };
    let steps = 60;
    let samples: Vec<(f64, DVec3)> = (0..=steps)
        .map(|i| {
            let s = 2.0 * f64::from(i) / f64::from(steps);
            (s, response(s, &pull).0)
        })
        .collect();
    let ds = 2.0 * (top - start.z) / f64::from(steps);
    for pair in samples.windows(2) {
        let ((s0, a), (_, b)) = (pair[0], pair[1]);
        assert!(a.is_finite() && b.is_finite(), "NaN at s = {s0}");
        assert!(
            a.distance(b) < 5.0 * ds,
            "jump of {} at s = {s0}",
            a.distance(b)
        );
    }
    // Outside the parent, the state records the λ scheme with λ > 1.
    let (_, state) = response(1.5, &pull);
    let record = state.rebound.iter().find(|r| r.vertex == owned).unwrap();
    match &record.follow {
        FollowRecord::Lambda { lambda, delta, .. } => {
            assert!(*lambda > 1.0);
            assert!(delta.point.z < top, "Δv lies inside the parent");
        }
        other => panic!("expected the λ scheme, got {other:?}"),
    }
    // Under an affine parent move the dragged vertex moves by exactly that map.
    let shift = |p: DVec3| DMat3::from_diagonal(DVec3::new(1.2, 0.9, 1.1)) * p + DVec3::X;
    let (moved, _) = response(1.5, &|moves, pose| {
        moves.extend(ears_vertices.iter().map(|&v| (v, shift(pose[v as usize]))));
    });
    let dragged = DVec3::new(start.x, start.y, start.z + 1.5 * (top - start.z));
    assert!(
        moved.distance(shift(dragged)) < 1e-6,
        "{moved} vs {}",
        shift(dragged)
    );
}

#[test]
fn malformed_hierarchies_are_refused_with_the_culprit_named() {
    let mut scene = critter();
    let ears = internal(&scene, "ears");
    let head = internal(&scene, "head");
    // A cycle: the ears cage owns a vertex of the head cage, which owns the ears cage.
    let head_vertex = scene.cages.internals[head].faces[0][0];
    scene.cages.internals[ears].owns.push(head_vertex);
    let error = Hierarchy::bind(&scene).unwrap_err();
    assert!(
        matches!(
            error,
            HierarchyError::Structure(SceneProblem::HierarchyCycle { .. })
        ),
        "{error}"
    );
    // Two parents.
    let mut scene = critter();
    let shared = scene.cages.internals[ears].owns[0];
    scene.cages.internals[head].owns.push(shared);
    let error = Hierarchy::bind(&scene).unwrap_err();
    assert!(error.to_string().contains("at most one parent"), "{error}");
    // An HC parent owning a vertex outside it at rest.
    let mut scene = critter();
    scene.cages.internals[head].owns.retain(|&v| v != 0);
    scene.cages.internals[ears].owns.push(0);
    let error = Hierarchy::bind(&scene).unwrap_err();
    assert!(
        matches!(error, HierarchyError::OwnedOutside { vertex: 0, .. }),
        "{error}"
    );
    assert!(error.to_string().contains("enlarge the cage"));
}

#[test]
fn the_auto_internal_cage_boxes_the_chosen_vertices() {
    let mut scene = demo_scene("bar", 0.3).unwrap();
    let right: Vec<u32> = (0..scene.cages.vertices.len() as u32)
        .filter(|&v| scene.cages.vertices[v as usize].x > 1.0)
        .collect();
    let options = AutoInternalCage {
        name: "end".into(),
        kind: CoordinateKind::Harmonic,
        padding: 0.2,
        cells: [1, 2, 2],
    };
    scene.pose[right[0] as usize] += DVec3::Y * 0.1;
    let index = add_auto_internal_cage(&mut scene, &options, &right).unwrap();
    assert_eq!(scene.cages.internals[index].owns, right);
    assert_eq!(scene.pose_state.hand_moved, vec![right[0]]);
    assert!(starcages_core::check::validate_scene(&scene).is_valid());
    let mut h = Hierarchy::bind(&scene).unwrap();
    // Scaling the new cage scales the bar's end about the box's centre.
    let mut pose = scene.pose.clone();
    let start = pose.clone();
    edit(&scene, &mut h, &mut pose, "end: translate 0 0 1");
    for &v in &right[1..] {
        // HC reproduces translations to its solver tolerance.
        let off = pose[v as usize].distance(start[v as usize] + DVec3::Z);
        assert!(off < 1e-6, "vertex {v} off by {off}");
    }
    assert!(matches!(
        add_auto_internal_cage(&mut scene, &options, &right),
        Err(AutoInternalCageError::NameTaken { .. })
    ));
    let other = AutoInternalCage {
        name: "again".into(),
        ..options
    };
    let error = add_auto_internal_cage(&mut scene, &other, &right).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("already owned by internal cage 'end'")
    );
}

#[test]
fn edits_of_unknown_cages_name_the_known_ones() {
    let scene = critter();
    let edit: CageEdit = "nose: scale 2".parse().unwrap();
    let error = edit.moves(&scene.cages, &scene.pose).unwrap_err();
    assert!(error.to_string().contains("ears, head"), "{error}");
}

#[test]
fn removing_an_internal_cage_undoes_adding_it_and_frees_what_it_owned() {
    let mut scene = critter();
    scene.pose[0] += DVec3::X * 0.05;
    scene.poses.insert("nudged".into(), scene.pose.clone());
    let original = scene.clone();
    // Every leaf vertex has a parent in the critter; the top cage's own vertices have none.
    let free: Vec<u32> = ["ears", "head"]
        .into_iter()
        .flat_map(|name| scene.cages.cage_vertices(name).unwrap())
        .filter(|v| scene.cages.internals.iter().all(|c| !c.owns.contains(v)))
        .collect();
    assert!(
        !free.is_empty(),
        "the critter's top cage has unowned vertices"
    );
    let options = AutoInternalCage {
        name: "extra".into(),
        ..AutoInternalCage::default()
    };
    let index = add_auto_internal_cage(&mut scene, &options, &free).unwrap();
    assert_ne!(scene, original);
    remove_internal_cage(&mut scene, index).unwrap();
    assert_eq!(scene, original, "add then remove is the identity");

    // A cage driven by another is refused, naming the parent; its parent can go.
    let ears = internal(&scene, "ears");
    let head = internal(&scene, "head");
    let driven = [ears, head].into_iter().find(|&c| {
        let own: Vec<u32> = scene.cages.internals[c]
            .faces
            .iter()
            .flatten()
            .copied()
            .collect();
        scene
            .cages
            .internals
            .iter()
            .any(|p| p.owns.iter().any(|v| own.contains(v)))
    });
    // The critter's ears cage owns vertices its head cage drives: one of the two is driven.
    let child = driven.expect("one internal cage owns vertices another drives");
    let error = remove_internal_cage(&mut scene.clone(), child).unwrap_err();
    assert!(error.to_string().contains("remove '"), "{error}");
    let top = [ears, head]
        .into_iter()
        .find(|&c| Some(c) != driven)
        .unwrap();
    let top_name = scene.cages.internals[top].name.clone();
    let owned = scene.cages.internals[top].owns.clone();
    let positions: Vec<DVec3> = owned.iter().map(|&v| scene.pose[v as usize]).collect();
    let own_vertices: std::collections::BTreeSet<u32> = scene.cages.internals[top]
        .faces
        .iter()
        .flatten()
        .copied()
        .collect();
    remove_internal_cage(&mut scene, top).unwrap();
    assert!(scene.cages.cage_vertices(&top_name).is_none());
    assert!(starcages_core::check::validate_scene(&scene).is_valid());
    // Freed vertices keep their posed positions, at indices shifted past the removed ones.
    for (v, p) in owned.iter().zip(&positions) {
        let shift = own_vertices.range(..*v).count() as u32;
        assert_eq!(scene.pose[(*v - shift) as usize], *p);
    }
    assert!(Hierarchy::bind(&scene).is_ok());
    assert!(matches!(
        remove_internal_cage(&mut scene, 99),
        Err(RemoveInternalCageError::NoSuchCage { index: 99, .. })
    ));
}

#[test]
fn validate_reports_pose_states_that_deform_would_refuse() {
    let scene = critter();
    assert!(starcages_core::check::validate_scene(&scene).is_valid());
    // A record naming a vertex that does not exist.
    let mut bad = scene.clone();
    bad.pose_state.hand_moved.push(99_999);
    let errors = starcages_core::check::validate_scene(&bad).errors;
    assert!(
        errors.iter().any(
            |e| matches!(e, SceneProblem::PoseState { pose, .. } if pose == "the current pose")
        ),
        "{errors:?}"
    );
    // A re-bound vertex whose recorded parent shape has one vertex.
    let mut bad = scene.clone();
    let state = bad.pose_states.get_mut("fig13").unwrap();
    let FollowRecord::Coordinates(anchor) = &mut state.rebound[0].follow else {
        panic!("the fig13 pose has a re-bound vertex with coordinates");
    };
    anchor.parent_shape.truncate(1);
    let errors = starcages_core::check::validate_scene(&bad).errors;
    let text = errors
        .iter()
        .find(|e| matches!(e, SceneProblem::PoseState { .. }))
        .map(ToString::to_string)
        .unwrap_or_else(|| panic!("not reported: {errors:?}"));
    assert!(
        text.contains("pose 'fig13'") && text.contains("pose_states"),
        "{text}"
    );
    // A re-bound vertex listed twice (which record would it follow?).
    let mut bad = scene.clone();
    let state = bad.pose_states.get_mut("fig13").unwrap();
    let first = state.rebound[0].clone();
    state.rebound.push(first.clone());
    let errors = starcages_core::check::validate_scene(&bad).errors;
    let text = errors
        .iter()
        .find(|e| matches!(e, SceneProblem::PoseState { .. }))
        .map(ToString::to_string)
        .unwrap_or_else(|| panic!("not reported: {errors:?}"));
    assert!(
        text.contains("pose 'fig13'")
            && text.contains(&format!(
                "vertex {}: it is listed twice in \"rebound\"",
                first.vertex
            )),
        "{text}"
    );
}
