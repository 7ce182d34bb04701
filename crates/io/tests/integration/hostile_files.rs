//! Hostile input, round three: nonsense that used to be accepted silently, and work a user could
//! multiply without bound.

use starcages_core::generate::demo::demo_scene;
use starcages_io::{load_scene, save_scene};

use starcages_test_support::Scratch;

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("hostile-{name}"))
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

/// A GLB whose header gives another length than the file's, a container version other than 2,
/// and a glTF 1.0 asset are refused saying which; our own GLB still reads.
#[test]
fn glb_lengths_container_versions_and_gltf_1_are_refused() {
    let dir = scratch("glb");
    let scene = demo_scene("bar", 0.3).unwrap();
    let good = dir.join("good.glb");
    starcages_io::write_mesh(&good, &scene.mesh, scene.mesh.positions()).unwrap();
    assert!(starcages_io::read_mesh(&good).is_ok());
    let bytes = std::fs::read(&good).unwrap();
    let refused = |name: &str, bytes: Vec<u8>, says: &str| {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let error = starcages_io::read_mesh(&path).unwrap_err().to_string();
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
    let error = starcages_io::read_mesh(&gltf).unwrap_err().to_string();
    assert!(error.contains("glTF 1.0 file"), "{error}");
}
