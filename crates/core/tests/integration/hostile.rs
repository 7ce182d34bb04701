//! Hostile input, round three: nonsense that used to be accepted silently, and work a user could
//! multiply without bound.

use starcages_core::check::validate_scene;
use starcages_core::generate::demo::demo_scene;
use starcages_core::rig::{MAX_SUBDIVIDED_VERTICES, RigOp, apply_rig_op};
use starcages_core::scene::SceneProblem;

#[test]
fn empty_names_control_characters_and_states_of_missing_poses_fail_validation() {
    let mut scene = demo_scene("bar", 0.3).unwrap();
    scene.cages.leaves[0].name = "left\nerror: fake".into();
    scene.cages.leaves[1].name = " ".into();
    scene
        .pose_states
        .insert("nowhere".into(), Default::default());
    let errors = validate_scene(&scene).errors;
    let names: Vec<&String> = errors
        .iter()
        .filter_map(|e| match e {
            SceneProblem::BadName { name, .. } => Some(name),
            _ => None,
        })
        .collect();
    assert_eq!(names.len(), 2, "{errors:?}");
    let shown: Vec<String> = errors.iter().map(ToString::to_string).collect();
    assert!(
        shown.iter().all(|m| !m.contains('\n')),
        "a message holds a line break: {shown:?}"
    );
    assert!(
        shown
            .iter()
            .any(|m| m.contains("'nowhere'") && m.contains("no pose")),
        "{shown:?}"
    );
    // Rig operations refuse such names too.
    let mut scene = demo_scene("bar", 0.3).unwrap();
    let op = RigOp::parse("add-box x 5 5 5 6 6 6").unwrap();
    let RigOp::AddBox { min, max, kind, .. } = op else {
        panic!("add-box parses")
    };
    let error = apply_rig_op(
        &mut scene,
        &RigOp::AddBox {
            name: "a\tb".into(),
            min,
            max,
            kind,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("control characters"), "{error}");
}

/// Each subdivision multiplies the cage vertices by about four: past the limit it is refused
/// before anything is made.
#[test]
fn subdivide_refuses_to_grow_a_rig_past_its_limit() {
    let mut scene = demo_scene("bar", 0.3).unwrap();
    // Unused vertices bring the rig close to the limit cheaply.
    let filler = MAX_SUBDIVIDED_VERTICES - scene.cages.vertices.len() - 10;
    for k in 0..filler {
        let p = glam::DVec3::new(50.0 + k as f64, 0.0, 0.0);
        scene.cages.vertices.push(p);
        scene.pose.push(p);
        for pose in scene.poses.values_mut() {
            pose.push(p);
        }
    }
    let before = scene.cages.vertices.len();
    let error = apply_rig_op(&mut scene, &RigOp::Subdivide)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains(&MAX_SUBDIVIDED_VERTICES.to_string()),
        "{error}"
    );
    assert_eq!(scene.cages.vertices.len(), before, "nothing was made");
}

/// A vertex listed twice by one internal cage says so, not "owned by both 'ic' and 'ic'".
#[test]
fn a_vertex_listed_twice_by_one_internal_cage_is_named_as_such() {
    let mut scene = demo_scene("critter", 0.3).unwrap();
    let v = scene.cages.internals[0].owns[0];
    scene.cages.internals[0].owns.push(v);
    let errors = validate_scene(&scene).errors;
    let cage = scene.cages.internals[0].name.clone();
    assert!(
        errors.iter().any(|e| matches!(
            e,
            SceneProblem::ListedTwice { cage: c, vertex } if *c == cage && *vertex == v as usize
        )),
        "{errors:?}"
    );
    assert!(
        !errors
            .iter()
            .any(|e| matches!(e, SceneProblem::OwnedTwice { .. })),
        "{errors:?}"
    );
}
