//! No panic, hang or runaway allocation on arbitrary input: the scene (with its animation),
//! mesh OBJ, PLY, STL and OFF (in `mesh_formats`), glTF/GLB, cage OBJ, point and point-cache
//! readers on random bytes, on randomly damaged valid files, and (glTF) on
//! structure-aware mutations of a valid document: numbers swapped for extreme values, type
//! names swapped, array entries dropped, node cycles; and the binding cache, damaged and crafted
//! (words replaced, checksum recomputed). A proptest harness; `scripts/fuzz.sh`
//! runs it for as long as asked and counts the inputs tried.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use proptest::prelude::*;
use serde_json::Value;
use starcages_core::generate::demo::demo_scene;
use starcages_core::star::{StarBinding, decode_binding_cache, encode_binding_cache};
use starcages_io::{glb_bytes, parse_obj_cages, parse_points, read_cage_obj, read_mesh};
use starcages_io::{load_scene, save_scene};

use starcages_test_support::Scratch;

/// Cases per property: 64 in the test suite, more from `scripts/fuzz.sh`
/// (`STARCAGES_FUZZ_CASES`).
pub fn fuzz_cases() -> u32 {
    std::env::var("STARCAGES_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(64)
}

fn scratch() -> Scratch {
    Scratch::new("fuzz")
}

/// A small valid scene with poses and animation keys (so damage reaches every section).
fn valid_scene_text() -> String {
    let dir = scratch();
    let path = dir.join("valid.json");
    let mut scene = demo_scene("bar", 0.2).unwrap();
    let lifted: Vec<glam::DVec3> = scene.pose.iter().map(|p| *p + glam::DVec3::Z).collect();
    scene.poses.insert("up".into(), lifted);
    scene
        .poses
        .insert("rest".into(), scene.cages.vertices.clone());
    for (frame, pose) in [(1.0, "rest"), (12.0, "up")] {
        scene.animation.keys.push(starcages_core::anim::Key {
            frame,
            pose: pose.into(),
            interpolation: starcages_core::anim::Interpolation::Bezier,
            h: [(scene.cages.leaves[0].name.clone(), 0.4)]
                .into_iter()
                .collect(),
        });
    }
    save_scene(&scene, &path).unwrap();
    std::fs::read_to_string(path).unwrap()
}

const CUBE_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\no a\n\
f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

/// `text` with bytes replaced, removed, or the rest cut off, as `cuts` say.
pub fn damage(text: impl AsRef<[u8]>, cuts: &[(usize, u8)]) -> Vec<u8> {
    let mut bytes = text.as_ref().to_vec();
    for &(at, b) in cuts {
        if bytes.is_empty() {
            break;
        }
        let i = at % bytes.len();
        match b % 3 {
            0 => bytes[i] = b,
            1 => {
                bytes.remove(i);
            }
            _ => bytes.truncate(i),
        }
    }
    bytes
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(fuzz_cases()))]

    #[test]
    fn scene_reader_never_panics(cuts in prop::collection::vec((any::<usize>(), any::<u8>()), 1..6), raw in prop::collection::vec(any::<u8>(), 0..200)) {
        let dir = scratch();
        let text = valid_scene_text();
        for (name, bytes) in [("damaged.json", damage(&text, &cuts)), ("raw.json", raw)] {
            let path = dir.join(format!("{}-{name}", std::process::id()));
            std::fs::write(&path, &bytes).unwrap();
            // What loads is validated and played: a damaged animation never panics either.
            if let Ok(scene) = load_scene(&path) {
                let _ = starcages_core::check::validate_scene(&scene);
                for frame in [-1.0, 1.0, 6.5, 12.0, 1e300] {
                    let _ = scene.animation.pose_at(&scene.poses, frame);
                    let _ = scene.animation.h_at(frame);
                }
            }
        }
    }

    /// Point caches (PC2, MDD) damaged or made of random bytes are refused or read, never a
    /// panic or an allocation the file's length does not back.
    #[test]
    fn point_cache_readers_never_panic(cuts in prop::collection::vec((any::<usize>(), any::<u8>()), 1..6), raw in prop::collection::vec(any::<u8>(), 0..200)) {
        use starcages_core::anim::SampleTimes;
        use starcages_io::{PointCacheFormat, PointCacheWriter, parse_point_cache};
        let dir = scratch();
        for format in [PointCacheFormat::Pc2, PointCacheFormat::Mdd] {
            let path = dir.join(format!("{}-valid-{format:?}", std::process::id()));
            let times = SampleTimes { start_frame: 1.0, frame_step: 1.0, fps: 24.0 };
            let mut writer = PointCacheWriter::create(&path, format, 4, 3, times).unwrap();
            for k in 0..3 {
                writer.write_sample(&[glam::Vec3::splat(k as f32); 4]).unwrap();
            }
            writer.finish().unwrap();
            let valid = std::fs::read(&path).unwrap();
            for bytes in [damage(&valid, &cuts), raw.clone()] {
                let _ = parse_point_cache(&path, format, &bytes, None, 24.0);
                let _ = parse_point_cache(&path, format, &bytes, Some(4), 24.0);
            }
        }
    }

    #[test]
    fn obj_readers_never_panic(cuts in prop::collection::vec((any::<usize>(), any::<u8>()), 1..6), raw in prop::collection::vec(any::<u8>(), 0..200)) {
        let dir = scratch();
        for (name, bytes) in [("damaged.obj", damage(CUBE_OBJ, &cuts)), ("raw.obj", raw)] {
            let path = dir.join(name);
            std::fs::write(&path, &bytes).unwrap();
            let _ = read_mesh(&path);
            let _ = read_cage_obj(&path);
            let text = String::from_utf8_lossy(&bytes);
            let _ = parse_obj_cages(&text, &path);
            let _ = parse_points(&text, &path);
        }
    }
}

/// A valid glTF document: one triangle, positions and indices in a base64 buffer.
fn valid_gltf() -> Value {
    use base64::Engine as _;
    let mut bytes: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    bytes.extend([0u32, 1, 2].iter().flat_map(|x| x.to_le_bytes()));
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    );
    serde_json::json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "children": [1]}, {"mesh": 0, "translation": [1, 0, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36, "byteStride": 12},
            {"buffer": 0, "byteOffset": 36, "byteLength": 12}
        ],
        "buffers": [{"uri": uri, "byteLength": 48}]
    })
}

/// [`valid_gltf`]'s triangle skinned to two joints under a transformed armature node (JOINTS_0,
/// WEIGHTS_0, inverse bind matrices), so mutations reach the skin reader.
fn valid_skinned_gltf() -> Value {
    use base64::Engine as _;
    let mut bytes: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    bytes.extend([0u32, 1, 2].iter().flat_map(|x| x.to_le_bytes()));
    bytes.extend([0u8, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0]);
    for w in [
        [0.5f32, 0.5, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
    ] {
        bytes.extend(w.iter().flat_map(|x| x.to_le_bytes()));
    }
    let identity = glam::Mat4::IDENTITY.to_cols_array();
    bytes.extend(
        identity
            .iter()
            .chain(&identity)
            .flat_map(|x| x.to_le_bytes()),
    );
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    );
    serde_json::json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 3]}],
        "nodes": [{"children": [1, 2], "scale": [2, 1, 1]}, {}, {"translation": [0, 1, 0]},
                  {"mesh": 0, "skin": 0}],
        "skins": [{"joints": [1, 2], "inverseBindMatrices": 4}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "JOINTS_0": 2,
                                                    "WEIGHTS_0": 3}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5121, "count": 3, "type": "VEC4"},
            {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5126, "count": 2, "type": "MAT4"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 12},
            {"buffer": 0, "byteOffset": 48, "byteLength": 12},
            {"buffer": 0, "byteOffset": 60, "byteLength": 48},
            {"buffer": 0, "byteOffset": 108, "byteLength": 128}
        ],
        "buffers": [{"uri": uri, "byteLength": bytes.len()}]
    })
}

/// [`valid_gltf`]'s triangle as `EXT_meshopt_compression` streams in a fallback buffer
/// (gltfpack's `-cc` layout), so mutations reach the decoder and the fallback handling.
fn valid_compressed_gltf() -> Value {
    use base64::Engine as _;
    let positions: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let mut bytes = meshopt::encode_vertex_buffer(&positions).unwrap();
    let vertex_length = bytes.len();
    bytes.extend(meshopt::encode_index_buffer(&[0, 1, 2], 3).unwrap());
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    );
    let ext = |offset: usize, length: usize, stride: usize, mode: &str| {
        serde_json::json!({"EXT_meshopt_compression": {"buffer": 0, "byteOffset": offset,
            "byteLength": length, "byteStride": stride, "mode": mode, "count": 3}})
    };
    let mut document = valid_gltf();
    document["extensionsUsed"] = serde_json::json!(["EXT_meshopt_compression"]);
    document["extensionsRequired"] = serde_json::json!(["EXT_meshopt_compression"]);
    document["bufferViews"] = serde_json::json!([
        {"buffer": 1, "byteOffset": 0, "byteLength": 36, "byteStride": 12,
         "extensions": ext(0, vertex_length, 12, "ATTRIBUTES")},
        {"buffer": 1, "byteOffset": 36, "byteLength": 12,
         "extensions": ext(vertex_length, bytes.len() - vertex_length, 4, "TRIANGLES")}
    ]);
    document["buffers"] = serde_json::json!([
        {"uri": uri, "byteLength": bytes.len()},
        {"byteLength": 48, "extensions": {"EXT_meshopt_compression": {"fallback": true}}}
    ]);
    document
}

/// Extreme and awkward replacements for a number.
const NUMBERS: [f64; 13] = [
    0.0,
    -1.0,
    1.0,
    2.0,
    3.0,
    4.0,
    4294967295.0,
    1e300,
    5126.0,
    5121.0,
    5120.0,
    5122.0,
    5123.0,
];
/// Replacements for a string (glTF type and semantic names, URIs).
const STRINGS: [&str; 7] = [
    "SCALAR",
    "VEC2",
    "MAT4",
    "../x.bin",
    "/dev/zero",
    "data:,",
    "",
];

/// Applies mutation `what` (a choice and a position) to the `n`-th node of `value` in document
/// order: numbers and strings replaced, array entries dropped or duplicated as cycles.
fn mutate(value: &mut Value, n: &mut usize, what: (u8, u8)) -> bool {
    let hit = *n == 0;
    *n = n.wrapping_sub(1);
    match value {
        Value::Number(_) if hit => {
            let x = NUMBERS[what.1 as usize % NUMBERS.len()];
            *value = serde_json::json!(x);
            true
        }
        Value::String(_) if hit => {
            *value = Value::String(STRINGS[what.1 as usize % STRINGS.len()].to_owned());
            true
        }
        Value::Array(items) if hit && !items.is_empty() => {
            let i = what.1 as usize % items.len();
            if what.0.is_multiple_of(2) {
                items.remove(i);
            } else {
                // A child list pointing back up the node graph (cycles) or a duplicate entry.
                let copy = items[i].clone();
                items.push(copy);
                items.push(serde_json::json!(0));
            }
            true
        }
        Value::Array(items) => items.iter_mut().any(|v| mutate(v, n, what)),
        Value::Object(map) => map.values_mut().any(|v| mutate(v, n, what)),
        _ => false,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(fuzz_cases()))]

    #[test]
    fn gltf_and_glb_readers_never_panic(
        mutations in prop::collection::vec((0usize..200, any::<u8>(), any::<u8>()), 1..5),
        cuts in prop::collection::vec((any::<usize>(), any::<u8>()), 1..4),
        quantized in any::<bool>(),
        variant in 0u8..3,
    ) {
        let dir = scratch();
        let mut document = match variant {
            0 => valid_gltf(),
            1 => valid_skinned_gltf(),
            _ => valid_compressed_gltf(),
        };
        if quantized {
            // KHR_mesh_quantization: integer component types become legal attributes.
            document["extensionsUsed"] = serde_json::json!(["KHR_mesh_quantization"]);
            document["extensionsRequired"] = serde_json::json!(["KHR_mesh_quantization"]);
        }
        for (at, a, b) in mutations {
            let mut n = at;
            mutate(&mut document, &mut n, (a, b));
        }
        let path = dir.join(format!("{}-mutated.gltf", std::process::id()));
        std::fs::write(&path, document.to_string()).unwrap();
        if let Ok(mesh) = read_mesh(&path) {
            prop_assert!(mesh.positions().iter().all(|p| p.is_finite()));
        }
        // A valid GLB, damaged byte-wise.
        let positions = [glam::DVec3::ZERO, glam::DVec3::X, glam::DVec3::Y];
        let normals = [glam::Vec3::Z; 3];
        let glb = glb_bytes(&positions, &[[0, 1, 2]], &normals, None);
        let mut damaged = glb;
        for &(at, byte) in &cuts {
            if damaged.is_empty() {
                break;
            }
            let i = at % damaged.len();
            damaged[i] = byte;
        }
        let path = dir.join(format!("{}-damaged.glb", std::process::id()));
        std::fs::write(&path, &damaged).unwrap();
        let _ = read_mesh(&path);
    }
}

/// The bar demo, its binding and the binding's cache bytes, computed once.
fn cache_fixture() -> &'static (starcages_core::scene::Scene, Vec<u8>) {
    static FIXTURE: std::sync::OnceLock<(starcages_core::scene::Scene, Vec<u8>)> =
        std::sync::OnceLock::new();
    FIXTURE.get_or_init(|| {
        let scene = demo_scene("bar", 0.2).unwrap();
        let binding =
            StarBinding::bind_scene(&scene, &starcages_core::BindControl::default()).unwrap();
        let bytes = encode_binding_cache(&scene, &binding);
        (scene, bytes)
    })
}

/// FNV-1a over `bytes`: the cache's checksum, recomputed so that mutated content passes it (a
/// crafted file, not a damaged one).
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Extreme and awkward replacements for a 32-bit word of the cache: counts, indices, f32 bits.
const WORDS: [u32; 9] = [
    0,
    1,
    u32::MAX,
    0xFFFF_FFF0,
    0x7FC0_0000, // NaN
    0x7F80_0000, // +inf
    0x7F7F_FFFF, // f32::MAX
    0xBF80_0000, // -1.0
    0x3F80_0000, // 1.0
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(fuzz_cases()))]

    /// Damaged caches fail their checksum; crafted ones (content changed, checksum recomputed)
    /// are refused or, when accepted, deform without a panic and within the scene's cages.
    #[test]
    fn binding_cache_reader_never_panics(
        words in prop::collection::vec((any::<usize>(), any::<u8>(), any::<u32>()), 1..5),
        cuts in prop::collection::vec((any::<usize>(), any::<u8>()), 1..4),
    ) {
        let (scene, valid) = cache_fixture();
        let damaged = damage(String::from_utf8_lossy(valid).as_bytes(), &cuts);
        let _ = decode_binding_cache(&damaged, scene);
        let mut crafted = valid.clone();
        let payload_words = (crafted.len() - 24) / 4;
        for &(at, choice, random) in &words {
            let word = if choice % 4 == 0 { random } else { WORDS[choice as usize % WORDS.len()] };
            let offset = 24 + 4 * (at % payload_words);
            crafted[offset..offset + 4].copy_from_slice(&word.to_le_bytes());
        }
        if words.iter().any(|w| w.1 % 7 == 0) {
            crafted.truncate(24 + 4 * (words[0].0 % payload_words));
        }
        let checksum = fnv(&crafted[24..]);
        crafted[16..24].copy_from_slice(&checksum.to_le_bytes());
        if let Ok(binding) = decode_binding_cache(&crafted, scene) {
            prop_assert!(binding.cage_of.iter().all(|&c| (c as usize) < scene.cages.leaves.len()));
            prop_assert!(binding.boundary_weight.iter().all(|b| (0.0..=1.0).contains(b)));
            let _ = binding.deform(&scene.cages.vertices, &scene.pose);
        }
    }
}

/// The compressed fixture reads as the plain triangle (so the fuzz starts from a valid file).
#[test]
fn the_compressed_fuzz_fixture_reads() {
    let dir = scratch();
    let path = dir.join(format!("{}-compressed.gltf", std::process::id()));
    std::fs::write(&path, valid_compressed_gltf().to_string()).unwrap();
    let mesh = read_mesh(&path).unwrap();
    assert_eq!(mesh.positions()[1], glam::DVec3::X);
    // valid_gltf's two instances of the triangle.
    assert_eq!(mesh.triangles(), [[0, 1, 2], [3, 4, 5]].as_slice());
}

/// The skinned fixture reads (so the fuzz starts from a valid skin): its first vertex weighs
/// both joints half and half, the others the first joint, all under the armature's x scale.
#[test]
fn the_skinned_fuzz_fixture_reads_by_its_joints() {
    let dir = scratch();
    let path = dir.join(format!("{}-skinned.gltf", std::process::id()));
    std::fs::write(&path, valid_skinned_gltf().to_string()).unwrap();
    let mesh = read_mesh(&path).unwrap();
    let p = mesh.positions();
    assert!(
        (p[0] - glam::DVec3::new(0.0, 0.5, 0.0)).length() < 1e-9,
        "{}",
        p[0]
    );
    assert!(
        (p[1] - glam::DVec3::new(2.0, 0.0, 0.0)).length() < 1e-9,
        "{}",
        p[1]
    );
}
