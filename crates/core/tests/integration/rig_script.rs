//! Rig scripts and the operations they added (faces by direction, kind, h, subdivide), the
//! surface-nets mesher, and the `creature` demo built by a script.

use std::collections::BTreeMap;

use glam::DVec3;
use starcages_core::BindControl;
use starcages_core::check::validate_scene;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::creature::{CREATURE_RIG, apply_rig_script, creature};
use starcages_core::rig::{RigEditError, RigOp, apply_rig_op, parse_rig_script};
use starcages_core::star::StarBinding;
use starcages_core::surface_nets::surface_nets;

use crate::common::empty_scene;

#[test]
fn a_script_skips_comments_and_names_the_line_of_a_bad_operation() {
    let ops =
        parse_rig_script("# a rig\n\nadd-box a 0 0 0 1 1 1  # the body\nsubdivide\n").unwrap();
    assert_eq!(ops.len(), 2);
    assert_eq!(ops[0].0, 3);
    assert_eq!(ops[1], (4, RigOp::Subdivide));
    let error = parse_rig_script("add-box a 0 0 0 1 1 1\nextrude a up 1\n").unwrap_err();
    assert!(
        matches!(error, RigEditError::AtLine { line: 2, .. }),
        "{error}"
    );
    assert!(
        error
            .to_string()
            .contains("neither a face number nor a direction")
    );
    // An operation that cannot apply names its line and changes nothing.
    let mut scene = empty_scene();
    let before = scene.clone();
    let error =
        apply_rig_script(&mut scene, "add-box a 0 0 0 1 1 2\nextrude b +z 1\n").unwrap_err();
    assert!(
        error
            .to_string()
            .starts_with("line 2: there is no leaf cage 'b'"),
        "{error}"
    );
    assert_eq!(scene, before);
    // A script of more operations than the limit is refused before anything runs.
    let long = "subdivide\n".repeat(starcages_core::rig::MAX_RIG_SCRIPT_OPS + 1);
    assert!(
        parse_rig_script(&long)
            .unwrap_err()
            .to_string()
            .contains("at most")
    );
}

#[test]
fn a_face_named_by_its_direction_is_the_face_with_that_outward_normal() {
    let mut by_direction = empty_scene();
    apply_rig_script(
        &mut by_direction,
        "add-box a 0 0 0 1 1 2\nextrude a -x 0.5 b\nkind b gc\nh b 0.3\nh all 0.7",
    )
    .unwrap();
    let new = &by_direction.cages.leaves[1];
    assert_eq!(new.kind, CoordinateKind::Green);
    assert_eq!(new.h, Some(0.3));
    assert_eq!(by_direction.settings.default_h, 0.7);
    let xs: Vec<f64> = new
        .faces
        .iter()
        .flatten()
        .map(|&v| by_direction.cages.vertices[v as usize].x)
        .collect();
    assert!(xs.iter().all(|&x| x == 0.0 || x == -0.5), "{xs:?}");
    // The same face by index gives the same rig.
    let mut by_index = empty_scene();
    apply_rig_op(
        &mut by_index,
        &RigOp::parse("add-box a 0 0 0 1 1 2").unwrap(),
    )
    .unwrap();
    let index = by_index.cages.leaves[0]
        .faces
        .iter()
        .position(|f| {
            f.iter()
                .all(|&v| by_index.cages.vertices[v as usize].x == 0.0)
        })
        .unwrap();
    apply_rig_op(
        &mut by_index,
        &RigOp::parse(&format!("extrude a {index} 0.5 b")).unwrap(),
    )
    .unwrap();
    assert_eq!(by_index.cages, {
        let mut c = by_direction.cages.clone();
        c.leaves[1].kind = CoordinateKind::MeanValue;
        c.leaves[1].h = None;
        c
    });
    // h out of range and a kind of a missing cage are refused.
    for bad in ["h a 0", "h a 1.5", "kind nope gc"] {
        let mut scene = by_index.clone();
        assert!(
            apply_rig_op(&mut scene, &RigOp::parse(bad).unwrap()).is_err(),
            "{bad}"
        );
        assert_eq!(scene, by_index);
    }
}

#[test]
fn subdivide_keeps_the_rig_valid_shared_and_the_deformation_at_rest() {
    let mut scene = empty_scene();
    apply_rig_script(
        &mut scene,
        "add-box body 0 0 0 1 1 1\nextrude body +z 1 neck\n",
    )
    .unwrap();
    // A pose: the neck's top moved; the subdivided pose has the midpoints of the posed cage.
    let top: Vec<u32> = (0..scene.cages.vertices.len() as u32)
        .filter(|&v| scene.cages.vertices[v as usize].z == 2.0)
        .collect();
    for &v in &top {
        scene.pose[v as usize] += DVec3::new(0.3, 0.0, 0.1);
    }
    scene.poses.insert("bent".into(), scene.pose.clone());
    let before = scene.clone();
    let binding = StarBinding::bind_scene(&before, &BindControl::default()).unwrap();
    let deformed_before = binding.deform(&before.cages.vertices, &before.cages.vertices);
    apply_rig_op(&mut scene, &RigOp::Subdivide).unwrap();
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    // Two boxes sharing a face: 12 corners, 20 edges (one shared) and 11 faces (one shared).
    assert_eq!(scene.cages.vertices.len(), 12 + 20 + 11);
    for cage in &scene.cages.leaves {
        assert_eq!(cage.faces.len(), 24);
    }
    let adjacency = scene.cages.adjacency();
    assert_eq!(adjacency.len(), 1);
    assert_eq!(
        adjacency[0].faces.len(),
        4,
        "the shared face is cut the same on both sides"
    );
    // Old vertices keep their places; the pose's new vertices are the pose subdivided (the
    // same midpoints and centres of the posed cage).
    let old = before.cages.vertices.len();
    assert_eq!(&scene.cages.vertices[..old], &before.cages.vertices[..]);
    assert_eq!(&scene.pose[..old], &before.pose[..]);
    let mut posed_as_rest = before.clone();
    posed_as_rest.cages.vertices = before.pose.clone();
    apply_rig_op(&mut posed_as_rest, &RigOp::Subdivide).unwrap();
    assert_eq!(posed_as_rest.cages.vertices, scene.pose);
    assert_eq!(scene.poses["bent"], scene.pose);
    assert!(
        (old..scene.pose.len()).any(|v| scene.pose[v] != scene.cages.vertices[v]),
        "the pose's new vertices follow the posed cage"
    );
    // At rest the mesh stays where it is: subdivision does not change the rest shape.
    let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
    let deformed = binding.deform(&scene.cages.vertices, &scene.cages.vertices);
    let worst = deformed
        .iter()
        .zip(&deformed_before)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    assert!(worst < 1e-5, "{worst}");
}

#[test]
fn subdivide_is_refused_while_internal_cages_drive_leaf_vertices() {
    let mut scene = starcages_core::generate::demo::demo_scene("critter", 0.3).unwrap();
    let before = scene.clone();
    let error = apply_rig_op(&mut scene, &RigOp::Subdivide).unwrap_err();
    assert!(error.to_string().contains("internal cages"), "{error}");
    assert_eq!(scene, before);
}

/// Signed volume of a closed triangle mesh (positive when its triangles face outwards).
fn signed_volume(positions: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[test]
fn surface_nets_close_a_sphere_facing_outwards() {
    let radius = 0.8;
    let (positions, triangles) = surface_nets(
        |p| p.length() - radius,
        DVec3::splat(-1.0),
        DVec3::splat(1.0),
        0.05,
    );
    // Closed and consistently oriented: every directed edge appears once, and its reverse once.
    let mut edges: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for t in &triangles {
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    assert!(
        edges.values().all(|&n| n == 1),
        "an edge is used twice the same way"
    );
    assert!(
        edges.keys().all(|&(a, b)| edges.contains_key(&(b, a))),
        "an open edge"
    );
    let volume = signed_volume(&positions, &triangles);
    let exact = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
    assert!(
        (volume / exact - 1.0).abs() < 0.02,
        "{volume} against {exact}"
    );
    assert!(positions.iter().all(|p| (p.length() - radius).abs() < 0.05));
    // A negative control: the field flipped (positive inside) turns every triangle inside out.
    let (flipped_positions, flipped) = surface_nets(
        |p| radius - p.length(),
        DVec3::splat(-1.0),
        DVec3::splat(1.0),
        0.05,
    );
    // (The outside is now "inside": the same sphere, its triangles facing inwards.)
    assert!(signed_volume(&flipped_positions, &flipped) < 0.0);
    // Degenerate requests give nothing instead of a huge allocation.
    assert!(
        surface_nets(|p| p.length() - 1.0, DVec3::ZERO, DVec3::ONE, 0.0)
            .1
            .is_empty()
    );
    assert!(
        surface_nets(|p| p.length() - 1.0, DVec3::ZERO, DVec3::ONE, 1e-5)
            .1
            .is_empty()
    );
}

#[test]
fn the_creature_is_a_valid_rig_of_eighteen_chained_cages_around_65k_triangles() {
    let scene = creature(1.0);
    let triangles = scene.mesh.triangles().len();
    assert!(
        (60_000..=70_000).contains(&triangles),
        "{triangles} triangles"
    );
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    let leaves = &scene.cages.leaves;
    assert_eq!(leaves.len(), 18);
    let kinds: Vec<CoordinateKind> = leaves.iter().map(|c| c.kind).collect();
    for kind in [
        CoordinateKind::MeanValue,
        CoordinateKind::Green,
        CoordinateKind::Harmonic,
    ] {
        assert!(kinds.contains(&kind), "{kind:?} is used");
    }
    // Low adjacency: chains along the limbs, no cage with more than four neighbours.
    let mut neighbours = vec![0; leaves.len()];
    for pair in scene.cages.adjacency() {
        neighbours[pair.first] += 1;
        neighbours[pair.second] += 1;
    }
    assert!(
        neighbours.iter().all(|&n| (1..=4).contains(&n)),
        "{neighbours:?}"
    );
    // Limbs leave the body through inset faces: a thigh shares vertices with its body box
    // and its shin only, so it joins no other cage's join cages.
    let vertices_of = |c: usize| -> std::collections::BTreeSet<u32> {
        leaves[c].faces.iter().flatten().copied().collect()
    };
    for (c, cage) in leaves.iter().enumerate() {
        if !cage.name.starts_with("thigh_") {
            continue;
        }
        let mine = vertices_of(c);
        let touching: Vec<&str> = (0..leaves.len())
            .filter(|&o| o != c && !vertices_of(o).is_disjoint(&mine))
            .map(|o| leaves[o].name.as_str())
            .collect();
        assert_eq!(touching.len(), 2, "{}: {touching:?}", cage.name);
        assert!(
            touching.iter().any(|n| n.starts_with("body_"))
                && touching.iter().any(|n| n.starts_with("shin_")),
            "{}: {touching:?}",
            cage.name
        );
    }
    let shins = leaves
        .iter()
        .filter(|c| c.name.starts_with("shin_"))
        .count();
    assert_eq!(shins, 4, "four legs in two segments");
    // The mesh is closed (a surface-nets mesh of the creature's field).
    let closed = &scene.mesh;
    let mut edges: BTreeMap<(u32, u32), i32> = BTreeMap::new();
    for t in closed.triangles() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    assert!(edges.values().all(|&n| n == 2));
    // The script in the repository is the one the demo ran.
    assert!(CREATURE_RIG.contains("inset chest +z"));
}

#[test]
fn problems_name_the_cages_and_vertices_they_are_about() {
    let mut scene = empty_scene();
    apply_rig_script(
        &mut scene,
        "add-box a 0 0 0 1 1 1\nadd-box b 0.5 0.05 0.05 1.5 0.95 2.0\n",
    )
    .unwrap();
    let report = validate_scene(&scene);
    assert!(!report.is_valid());
    let mut cages = std::collections::BTreeSet::new();
    let mut vertices = 0;
    for problem in &report.errors {
        let elements = problem.elements(&scene.cages);
        cages.extend(elements.leaf_cages);
        vertices += elements.cage_vertices.len() + elements.mesh_vertices.len();
    }
    assert_eq!(cages, [0, 1].into(), "{:?}", report.errors);
    assert!(vertices > 0);
    // A valid rig names nothing.
    let mut valid = empty_scene();
    apply_rig_script(&mut valid, "add-box a 0 0 0 1 1 2\n").unwrap();
    assert!(validate_scene(&valid).errors.is_empty());
}
