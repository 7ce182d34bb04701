//! The posing engine: what each source gives (cages, hierarchy state, keyed h), edits on top
//! propagating through the hierarchy from the source's state, and refusals by name.

use std::collections::BTreeMap;

use glam::DVec3;
use starcages_core::generate::demo::demo_scene;
use starcages_core::hierarchy::{CageEdit, Hierarchy};
use starcages_core::posing::{PoseError, PoseRequest, PoseSource};
use starcages_core::scene::Scene;

fn critter() -> Scene {
    demo_scene("critter", 1.0).expect("the critter demo")
}

fn edit(text: &str) -> CageEdit {
    text.parse().expect("an edit")
}

fn largest_difference(a: &[DVec3], b: &[DVec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).abs().max_element())
        .fold(0.0, f64::max)
}

#[test]
fn a_keyed_frame_is_its_key_pose_with_its_hierarchy_state_and_between_keys_starts_from_rest() {
    let scene = critter();
    let key = &scene.animation.keys[1];
    assert_eq!((key.frame, key.pose.as_str()), (12.0, "ears_back"));
    let stored_state = &scene.pose_states["ears_back"];
    assert!(
        !stored_state.is_rest(),
        "the key's pose carries a hierarchy state"
    );
    let at_key = PoseRequest::frame(12.0).resolve(&scene).expect("frame 12");
    assert_eq!(at_key.cages, scene.poses["ears_back"]);
    assert_eq!(&at_key.state, stored_state);
    let between = PoseRequest::frame(6.5).resolve(&scene).expect("frame 6.5");
    assert!(between.state.is_rest());
    assert_eq!(
        Some(between.cages),
        scene.animation.pose_at(&scene.poses, 6.5)
    );
    // Keyed h comes with a frame, and only with a frame.
    assert_eq!(at_key.h, scene.animation.h_at(12.0));
    let named = PoseRequest::new(PoseSource::Named(Some("ears_back".into())));
    assert_eq!(named.resolve(&scene).expect("named").h, BTreeMap::new());
}

#[test]
fn edits_at_a_keyed_frame_go_on_from_the_key_state_as_at_its_named_pose() {
    let scene = critter();
    let edits = vec![edit("head: rotate 0 0 1 10")];
    let at_frame = PoseRequest {
        source: PoseSource::Frame(12.0),
        edits: edits.clone(),
    };
    let at_name = PoseRequest {
        source: PoseSource::Named(Some("ears_back".into())),
        edits: edits.clone(),
    };
    let from_frame = at_frame.resolve(&scene).expect("frame 12 with an edit");
    let from_name = at_name
        .resolve(&scene)
        .expect("the key's pose with an edit");
    assert_eq!(from_frame.cages, from_name.cages);
    assert_eq!(from_frame.state, from_name.state);
    // Negative control: the same edit from the rest state moves the ears elsewhere, so the
    // state is what made the two agree.
    let mut hierarchy = Hierarchy::bind_in_state(&scene, &Default::default()).expect("bind");
    let mut from_rest = scene.poses["ears_back"].clone();
    let moves = edits[0].moves(&scene.cages, &from_rest).expect("moves");
    hierarchy.apply(&mut from_rest, &moves).expect("apply");
    assert!(largest_difference(&from_rest, &from_frame.cages) > 1e-3);
    // The edit moved the head: the returned state is the state after it.
    assert_ne!(from_frame.cages, scene.poses["ears_back"]);
    assert_eq!(
        from_frame.state,
        hierarchy_state_after(&scene, &from_frame.cages)
    );
}

/// The state a hierarchy bound in the key's state has after the head edit.
fn hierarchy_state_after(
    scene: &Scene,
    expected: &[DVec3],
) -> starcages_core::scene::HierarchyState {
    let mut hierarchy =
        Hierarchy::bind_in_state(scene, &scene.pose_states["ears_back"]).expect("bind");
    let mut pose = scene.poses["ears_back"].clone();
    let moves = edit("head: rotate 0 0 1 10")
        .moves(&scene.cages, &pose)
        .expect("moves");
    hierarchy.apply(&mut pose, &moves).expect("apply");
    assert_eq!(pose, expected);
    hierarchy.state()
}

#[test]
fn rest_named_and_outside_positions_start_where_they_say() {
    let scene = critter();
    let rest = PoseRequest::new(PoseSource::Rest)
        .resolve(&scene)
        .expect("rest");
    assert_eq!(rest.cages, scene.cages.vertices);
    assert!(rest.state.is_rest());
    let current = PoseRequest::new(PoseSource::Named(None))
        .resolve(&scene)
        .expect("current");
    assert_eq!(current.cages, scene.pose);
    assert_eq!(current.state, scene.pose_state);
    let moved: Vec<DVec3> = scene.cages.vertices.iter().map(|p| *p + DVec3::X).collect();
    let outside = PoseRequest::new(PoseSource::Positions(moved.clone()))
        .resolve(&scene)
        .expect("positions");
    assert_eq!(outside.cages, moved);
    assert!(outside.state.is_rest());
}

#[test]
fn requests_that_give_no_pose_are_refused_by_name() {
    let scene = critter();
    let refused = |source: PoseSource, edits: Vec<CageEdit>| {
        PoseRequest { source, edits }
            .resolve(&scene)
            .expect_err("refused")
    };
    let unknown = refused(PoseSource::Named(Some("nope".into())), vec![]);
    assert!(matches!(&unknown, PoseError::UnknownPose { name, known }
        if name == "nope" && known.contains("ears_back")));
    assert_eq!(
        refused(PoseSource::Frame(f64::NAN), vec![]).to_string(),
        "frame NaN: give a finite frame number"
    );
    let short = refused(PoseSource::Positions(vec![DVec3::ZERO; 3]), vec![]);
    assert!(matches!(short, PoseError::VertexCount { found: 3, .. }));
    let far = refused(PoseSource::Rest, vec![edit("head: scale 1e12")]);
    assert!(
        matches!(far, PoseError::Far { by_edits: true, .. }),
        "{far}"
    );
    let no_cage = refused(PoseSource::Rest, vec![edit("nobody: scale 2")]);
    assert!(matches!(no_cage, PoseError::Edit(_)));
    let mut unkeyed = scene.clone();
    unkeyed.animation.keys.clear();
    let no_keys = PoseRequest::frame(1.0)
        .resolve(&unkeyed)
        .expect_err("no keys");
    assert_eq!(no_keys, PoseError::NoKeys);
}

/// Posing through the hierarchy validation bound (a copy restored to the source's state) gives
/// what a new bind gives, from every source the critter has.
#[test]
fn posing_through_validation_s_hierarchy_equals_a_new_bind() {
    let scene = critter();
    let checked = starcages_core::check::check_scene(&scene);
    let bound = checked
        .hierarchy
        .as_ref()
        .expect("the dry run kept its hierarchy");
    let edits = vec![
        edit("head: rotate 0 0 1 10"),
        edit("ears: rotate 1 0 0 -15"),
    ];
    let sources = [
        PoseSource::Frame(12.0),
        PoseSource::Frame(6.5),
        PoseSource::Named(Some("fig13".into())),
        PoseSource::Named(None),
        PoseSource::Rest,
    ];
    for source in sources {
        let request = PoseRequest {
            source: source.clone(),
            edits: edits.clone(),
        };
        let fresh = request.resolve(&scene).expect("a new bind");
        let reused = request
            .resolve_with(&scene, Some(bound))
            .expect("validation's");
        assert_eq!(fresh, reused, "{source:?}");
    }
}
