//! Inset (Blender's Inset Faces): the cage keeps its shape, the inner face sits exactly the
//! thickness inside every edge, an extrusion of it touches no vertex of the face's edges, poses
//! follow affinely, and what cannot apply is refused with the scene unchanged.

use std::collections::BTreeSet;

use glam::DVec3;
use starcages_core::check::validate_scene;
use starcages_core::rig::{RigEditError, RigOp, apply_rig_op};

use crate::common::empty_scene;

fn op(text: &str) -> RigOp {
    RigOp::parse(text).unwrap()
}

/// Signed volume of a closed cage (divergence theorem over its fan-triangulated faces).
fn volume(positions: &[DVec3], faces: &[Vec<u32>]) -> f64 {
    faces
        .iter()
        .flat_map(|f| (1..f.len() - 1).map(move |k| [f[0], f[k], f[k + 1]]))
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[test]
fn an_inset_keeps_the_cage_and_an_extrusion_of_it_touches_no_edge_of_the_face() {
    let mut scene = empty_scene();
    apply_rig_op(&mut scene, &op("add-box body 0 0 0 1 1 1")).unwrap();
    // A pose that moves the body affinely: the inset must follow it exactly.
    let affine = |p: DVec3| DVec3::new(2.0 * p.x + 0.3 * p.z, p.y - 0.1, 1.5 * p.z + 0.2);
    scene.pose = scene.cages.vertices.iter().map(|&p| affine(p)).collect();
    apply_rig_op(&mut scene, &op("inset body +z 0.05")).unwrap();
    let body = &scene.cages.leaves[0];
    assert_eq!(
        body.faces.len(),
        10,
        "the top became an inner face and a ring of four"
    );
    assert_eq!(scene.cages.vertices.len(), 12);
    let volume_after = volume(&scene.cages.vertices, &body.faces);
    assert!((volume_after - 1.0).abs() < 1e-12, "{volume_after}");
    // The inner face: 0.05 inside each edge of the top, in its plane.
    let inner: Vec<DVec3> = (8..12).map(|v| scene.cages.vertices[v]).collect();
    for p in &inner {
        assert!((p.z - 1.0).abs() < 1e-12, "{p}");
        for c in [p.x, p.y] {
            assert!((c - 0.05).abs() < 1e-12 || (c - 0.95).abs() < 1e-12, "{p}");
        }
    }
    for (v, rest) in inner.iter().enumerate() {
        let posed = scene.pose[8 + v];
        assert!(posed.distance(affine(*rest)) < 1e-12, "{posed} {rest}");
    }
    // `+z` now names the inner face (coplanar faces: the first listed), and the neck grown
    // from it shares its four corners with the body and nothing else.
    apply_rig_op(&mut scene, &op("extrude body +z 1 neck")).unwrap();
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    let vertices_of = |c: usize| -> BTreeSet<u32> {
        scene.cages.leaves[c]
            .faces
            .iter()
            .flatten()
            .copied()
            .collect()
    };
    let shared: BTreeSet<u32> = vertices_of(0)
        .intersection(&vertices_of(1))
        .copied()
        .collect();
    assert_eq!(shared, (8..12).collect());
    let adjacency = scene.cages.adjacency();
    assert_eq!(adjacency.len(), 1);
    assert_eq!(adjacency[0].faces.len(), 1);
}

#[test]
fn an_inset_that_cannot_apply_is_refused_and_changes_nothing() {
    let mut scene = empty_scene();
    apply_rig_op(&mut scene, &op("add-box body 0 0 0 1 1 1")).unwrap();
    apply_rig_op(&mut scene, &op("extrude body +z 1 neck")).unwrap();
    let before = scene.clone();
    for (text, expected) in [
        ("inset body +z 0.1", "shared with another cage"),
        ("inset body -z 0.5", "does not fit the face"),
        ("inset body -z 0.7", "does not fit the face"),
        ("inset body -z 1e308", "does not fit the face"),
        ("inset body -z 1e-300", "does not fit the face"),
        ("inset body -z 0", "must be positive"),
        ("inset body -z -0.1", "must be positive"),
        ("inset nobody -z 0.1", "no leaf cage 'nobody'"),
        ("inset body 99 0.1", "face 99 does not exist"),
    ] {
        let error = apply_rig_op(&mut scene, &op(text)).unwrap_err();
        assert!(error.to_string().contains(expected), "{text}: {error}");
        assert_eq!(scene, before, "{text} changed the scene");
    }
    let syntax = RigOp::parse("inset body up 0.1").unwrap_err();
    assert!(matches!(syntax, RigEditError::Syntax { .. }), "{syntax}");
}
