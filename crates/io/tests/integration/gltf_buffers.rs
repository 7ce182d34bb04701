//! External glTF buffers: only relative paths to regular files inside the glTF file's folder
//! are read; absolute paths, `..` escapes (also %-encoded), URI schemes, devices and symlinks
//! leading outside are refused with a message naming the URI.

use std::path::{Path, PathBuf};

use starcages_io::read_mesh;

use starcages_test_support::Scratch;

fn scratch(name: &str) -> Scratch {
    let dir = Scratch::new(&format!("gltf-{name}"));
    std::fs::create_dir_all(dir.join("models").join("sub")).unwrap();
    dir
}

/// Three float positions: one triangle.
fn triangle_bytes() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect()
}

/// A glTF document whose one buffer is `uri` (36 bytes: a triangle).
fn gltf_with_buffer(folder: &Path, uri: &str) -> PathBuf {
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
"bufferViews":[{{"buffer":0,"byteLength":36}}],
"buffers":[{{"uri":"{uri}","byteLength":36}}]}}"#
    );
    let path = folder.join("models").join("scene.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn buffers_inside_the_folder_are_read() {
    let dir = scratch("inside");
    std::fs::write(dir.join("models").join("tri.bin"), triangle_bytes()).unwrap();
    std::fs::write(
        dir.join("models").join("sub").join("tri.bin"),
        triangle_bytes(),
    )
    .unwrap();
    for uri in ["tri.bin", "./tri.bin", "sub/tri.bin", "sub%2Ftri.bin"] {
        let mesh = read_mesh(&gltf_with_buffer(&dir, uri)).unwrap();
        assert_eq!(mesh.welded_triangles().len(), 1, "{uri}");
    }
}

#[test]
fn buffers_outside_the_folder_are_refused() {
    let dir = scratch("outside");
    // A file just outside the folder, as an attacker would aim at.
    std::fs::write(dir.join("secret.bin"), triangle_bytes()).unwrap();
    std::fs::create_dir_all(dir.join("models").join("folder.bin")).unwrap();
    let mut cases = vec![
        ("../secret.bin", "leaves the folder"),
        ("sub/../../secret.bin", "leaves the folder"),
        ("%2e%2e/secret.bin", "leaves the folder"),
        ("..%5Csecret.bin", "leaves the folder"),
        ("/etc/passwd", "absolute path"),
        ("/dev/zero", "absolute path"),
        ("file:///etc/passwd", "URI scheme"),
        ("https://example.invalid/x.bin", "URI scheme"),
        ("folder.bin", "not a regular file"),
        ("%zz.bin", "broken %-escape"),
    ];
    #[cfg(unix)]
    {
        let link = dir.join("models").join("link.bin");
        std::os::unix::fs::symlink(dir.join("secret.bin"), link).unwrap();
        cases.push(("link.bin", "symbolic link"));
    }
    for (uri, why) in cases {
        let path = gltf_with_buffer(&dir, uri);
        let error = read_mesh(&path).unwrap_err().to_string();
        assert!(
            error.contains("scene.gltf") && error.contains(uri) && error.contains(why),
            "{uri}: {error}"
        );
    }
}
