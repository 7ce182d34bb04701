//! Hostile input, round three: nonsense that used to be accepted silently, and work a user could
//! multiply without bound.

use std::path::PathBuf;

use starcages_core::generate::demo::demo_scene;
use starcages_core::rig::{MAX_SUBDIVIDED_VERTICES, RigOp, apply_rig_op};
use starcages_core::scene::{SceneProblem, load_scene, save_scene, validate_scene};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("starcages-hostile-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// serde reads a struct from an array by position; a scene file's named-field objects may not
/// be arrays (or anything else).
#[test]
fn object_fields_written_as_arrays_are_refused_naming_the_field() {
    let dir = scratch("arrays");
    let path = dir.join("scene.json");
    save_scene(&demo_scene("critter", 0.3).unwrap(), &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    for (field, value) in [
        (
            "settings",
            serde_json::json!([0.5, "sine", "auto", "error"]),
        ),
        ("animation", serde_json::json!([24, 1, 24, []])),
    ] {
        let mut broken = json.clone();
        broken[field] = value;
        std::fs::write(&path, broken.to_string()).unwrap();
        let error = load_scene(&path).unwrap_err().to_string();
        assert!(
            error.contains(&format!("\"{field}\" is an array")) && error.contains("object"),
            "{error}"
        );
    }
    json["animation"]["keys"][0] = serde_json::json!([1, "ears_up"]);
    std::fs::write(&path, json.to_string()).unwrap();
    let error = load_scene(&path).unwrap_err().to_string();
    assert!(error.contains("animation.keys[0]"), "{error}");
}

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

/// A GLB whose header gives another length than the file's, a container version other than 2,
/// and a glTF 1.0 asset are refused saying which; our own GLB still reads.
#[test]
fn glb_lengths_container_versions_and_gltf_1_are_refused() {
    let dir = scratch("glb");
    let scene = demo_scene("bar", 0.3).unwrap();
    let good = dir.join("good.glb");
    starcages_core::io::write_mesh(&good, &scene.mesh, scene.mesh.positions()).unwrap();
    assert!(starcages_core::io::read_mesh(&good).is_ok());
    let bytes = std::fs::read(&good).unwrap();
    let refused = |name: &str, bytes: Vec<u8>, says: &str| {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let error = starcages_core::io::read_mesh(&path)
            .unwrap_err()
            .to_string();
        assert!(error.contains(says), "{name}: {says:?} not in {error}");
    };
    let mut longer = bytes.clone();
    longer.extend([0u8; 16]);
    refused("longer.glb", longer, "bytes after its end");
    let mut version = bytes.clone();
    version[4..8].copy_from_slice(&1u32.to_le_bytes());
    refused("version.glb", version, "container version 1");
    let gltf = dir.join("old.gltf");
    std::fs::write(
        &gltf,
        r#"{"asset": {"version": "1.0"}, "meshes": {}, "accessors": {}}"#,
    )
    .unwrap();
    let error = starcages_core::io::read_mesh(&gltf)
        .unwrap_err()
        .to_string();
    assert!(error.contains("glTF 1.0 file"), "{error}");
}
