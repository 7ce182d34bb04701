//! Malformed glTF files get a clear error, never a panic, an abort or a silently wrong mesh:
//! accessors of the wrong type, short strides, sparse storage, missing positions, node graphs
//! with cycles or astronomically many paths; a very deep (valid) node chain reads fine.

use base64::Engine as _;
use starcages_io::read_mesh;

use starcages_test_support::Scratch;

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("gltf-files-{name}"))
}

/// 48 bytes: three float positions (36) then three u32 indices (12).
fn buffer_uri() -> String {
    let mut bytes: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    bytes.extend([0u32, 1, 2].iter().flat_map(|x| x.to_le_bytes()));
    format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    )
}

/// A glTF document from its parts (JSON fragments), one 48-byte buffer.
fn document(nodes: &str, primitive: &str, accessors: &str, views: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":{nodes},
"meshes":[{{"name":"tri","primitives":[{primitive}]}}],"accessors":{accessors},"bufferViews":{views},
"buffers":[{{"uri":"{}","byteLength":48}}]}}"#,
        buffer_uri()
    )
}

const VIEWS: &str =
    r#"[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":12}]"#;
const POSITION: &str =
    r#"{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}"#;
const INDICES: &str = r#"{"bufferView":1,"componentType":5125,"count":3,"type":"SCALAR"}"#;
const PRIMITIVE: &str = r#"{"attributes":{"POSITION":0},"indices":1}"#;
const ONE_NODE: &str = r#"[{"mesh":0}]"#;

fn read(dir: &std::path::Path, name: &str, json: &str) -> Result<usize, String> {
    let path = dir.join(name);
    std::fs::write(&path, json).unwrap();
    read_mesh(&path)
        .map(|m| m.welded_triangles().len())
        .map_err(|e| e.to_string())
}

#[test]
fn a_well_formed_triangle_reads() {
    let dir = scratch("good");
    let json = document(
        ONE_NODE,
        PRIMITIVE,
        &format!("[{POSITION},{INDICES}]"),
        VIEWS,
    );
    assert_eq!(read(&dir, "good.gltf", &json), Ok(1));
}

#[test]
fn malformed_accessors_are_refused_with_the_reason() {
    let dir = scratch("accessors");
    let float_indices = INDICES.replace("5125", "5126");
    let byte_positions = POSITION.replace("5126", "5121");
    let scalar_positions = POSITION.replace("VEC3", "SCALAR");
    let too_many = POSITION.replace("\"count\":3", "\"count\":4");
    let short_stride_views = VIEWS.replacen(
        "\"byteLength\":36}",
        "\"byteLength\":36,\"byteStride\":4}",
        1,
    );
    let sparse = POSITION.replace(
        "\"type\":\"VEC3\"",
        "\"type\":\"VEC3\",\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":1,\"componentType\":5125},\"values\":{\"bufferView\":0}}",
    );
    let cases = [
        (
            "float-indices",
            PRIMITIVE,
            format!("[{POSITION},{float_indices}]"),
            VIEWS.to_owned(),
            "expected Scalar of U8",
        ),
        (
            "byte-positions",
            PRIMITIVE,
            format!("[{byte_positions},{INDICES}]"),
            VIEWS.to_owned(),
            "expected Vec3 of F32",
        ),
        (
            "scalar-positions",
            PRIMITIVE,
            format!("[{scalar_positions},{INDICES}]"),
            VIEWS.to_owned(),
            "holds Scalar",
        ),
        (
            "past-the-view",
            PRIMITIVE,
            format!("[{too_many},{INDICES}]"),
            VIEWS.to_owned(),
            "need 48 bytes",
        ),
        (
            "short-stride",
            PRIMITIVE,
            format!("[{POSITION},{INDICES}]"),
            short_stride_views,
            "byteStride 4",
        ),
        (
            "sparse",
            PRIMITIVE,
            format!("[{sparse},{INDICES}]"),
            VIEWS.to_owned(),
            "sparse",
        ),
        (
            "no-position",
            r#"{"attributes":{"NORMAL":0},"indices":1}"#,
            format!("[{POSITION},{INDICES}]"),
            VIEWS.to_owned(),
            "POSITION",
        ),
        (
            "two-indices",
            PRIMITIVE,
            format!(
                "[{POSITION},{}]",
                INDICES.replace("\"count\":3", "\"count\":2")
            ),
            VIEWS.to_owned(),
            "mesh 0 ('tri'), primitive 0, the index list holds 2 indices, not a whole number of triangles; \
             re-export",
        ),
        (
            "index-past-the-vertices",
            PRIMITIVE,
            format!(
                "[{},{INDICES}]",
                POSITION.replace("\"count\":3", "\"count\":2")
            ),
            VIEWS.to_owned(),
            "mesh 0 ('tri'), primitive 0, the index list names vertex 2 at index 2, but the primitive has 2 \
             vertices (numbered from 0); the file is damaged: re-export it",
        ),
    ];
    for (name, primitive, accessors, views, why) in cases {
        let json = document(ONE_NODE, primitive, &accessors, &views);
        let error = read(&dir, &format!("{name}.gltf"), &json).unwrap_err();
        assert!(
            error.contains(&format!("{name}.gltf")) && error.contains(why),
            "{name}: {error}"
        );
    }
}

#[test]
fn node_graphs_with_cycles_or_too_many_paths_are_refused_and_deep_chains_read() {
    let dir = scratch("nodes");
    let accessors = format!("[{POSITION},{INDICES}]");
    let cycle = r#"[{"children":[1]},{"children":[0],"mesh":0}]"#;
    let error = read(
        &dir,
        "cycle.gltf",
        &document(cycle, PRIMITIVE, &accessors, VIEWS),
    )
    .unwrap_err();
    assert!(error.contains("cycle"), "{error}");
    let self_child = r#"[{"children":[0],"mesh":0}]"#;
    let error = read(
        &dir,
        "self.gltf",
        &document(self_child, PRIMITIVE, &accessors, VIEWS),
    )
    .unwrap_err();
    assert!(error.contains("cycle"), "{error}");
    // 41 nodes, each with both children the next one: 2^40 paths to the last.
    let dag: Vec<String> = (0..41)
        .map(|i| {
            if i == 40 {
                r#"{"mesh":0}"#.to_owned()
            } else {
                format!(r#"{{"children":[{0},{0}]}}"#, i + 1)
            }
        })
        .collect();
    let dag = format!("[{}]", dag.join(","));
    let error = read(
        &dir,
        "dag.gltf",
        &document(&dag, PRIMITIVE, &accessors, VIEWS),
    )
    .unwrap_err();
    assert!(error.contains("node instances"), "{error}");
    // A valid 200,000-deep chain: read, not a stack overflow.
    let depth = 200_000;
    let chain: Vec<String> = (0..depth)
        .map(|i| {
            if i == depth - 1 {
                r#"{"mesh":0}"#.to_owned()
            } else {
                format!(r#"{{"children":[{}]}}"#, i + 1)
            }
        })
        .collect();
    let chain = format!("[{}]", chain.join(","));
    assert_eq!(
        read(
            &dir,
            "chain.gltf",
            &document(&chain, PRIMITIVE, &accessors, VIEWS)
        ),
        Ok(1)
    );
}

#[test]
fn empty_accessors_are_refused() {
    // Found by scripts/fuzz.sh: a count of 0 made the gltf crate subtract below zero.
    let dir = scratch("empty");
    let empty = INDICES.replace("\"count\":3", "\"count\":0");
    let json = document(ONE_NODE, PRIMITIVE, &format!("[{POSITION},{empty}]"), VIEWS);
    let error = read(&dir, "empty.gltf", &json).unwrap_err();
    assert!(
        error.contains("indices") && error.contains("no elements"),
        "{error}"
    );
}

/// A file that reads but gives no triangle says what it lacks: no mesh, no scene, no node
/// using a mesh, or a scene that does not reach one.
#[test]
fn files_without_triangles_say_what_they_lack() {
    let dir = scratch("no-triangles");
    let accessors = format!("[{POSITION},{INDICES}]");
    let good = document(ONE_NODE, PRIMITIVE, &accessors, VIEWS);
    let cases = [
        (
            "no-mesh.gltf",
            r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"name":"camera holder"}]}"#.to_owned(),
            "has no mesh",
        ),
        (
            "no-scene.gltf",
            good.replace(r#""scene":0,"scenes":[{"nodes":[0]}],"#, ""),
            "no scene to place them",
        ),
        (
            "no-node-uses-it.gltf",
            good.replace(r#""nodes":[{"mesh":0}]"#, r#""nodes":[{"name":"empty"}]"#),
            "no node uses one",
        ),
        (
            "unlisted-node.gltf",
            good.replace(
                r#""nodes":[{"mesh":0}]"#,
                r#""nodes":[{"name":"empty"},{"mesh":0}]"#,
            ),
            "no node in the file's scene reaches a mesh",
        ),
    ];
    for (name, json, expected) in cases {
        let error = read(&dir, name, &json).expect_err(name);
        assert!(error.contains(expected), "{name}: {error}");
        assert!(
            !error.contains("the mesh has no triangles"),
            "{name}: {error}"
        );
    }
}

/// A glTF file with two primitives is read as two parts and written back as two primitives,
/// each with its own vertices in the source's order.
#[test]
fn primitives_come_back_as_primitives_in_order() {
    let dir = scratch("two-primitives");
    // Two triangles' worth of data: primitive 0 uses vertices 0..3, primitive 1 a second copy.
    let json = document(
        r#"[{"mesh":0},{"mesh":0,"translation":[2,0,0]}]"#,
        PRIMITIVE,
        &format!("[{POSITION},{INDICES}]"),
        VIEWS,
    )
    .replace(r#""nodes":[0]"#, r#""nodes":[0,1]"#);
    let path = dir.join("two.gltf");
    std::fs::write(&path, &json).unwrap();
    let mesh = read_mesh(&path).unwrap();
    assert_eq!(mesh.parts().len(), 2, "two primitive instances");
    assert_eq!(mesh.parts()[1].vertices, 3..6);
    let out = dir.join("back.glb");
    starcages_io::write_mesh(&out, &mesh, mesh.positions()).unwrap();
    let back = read_mesh(&out).unwrap();
    assert_eq!(back.parts(), mesh.parts());
    assert_eq!(back.positions(), mesh.positions());
    assert_eq!(back.triangles(), mesh.triangles());
    // The written file has two primitives with three vertices each.
    let bytes = std::fs::read(&out).unwrap();
    let json_length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let document: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_length]).unwrap();
    let primitives = document["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(primitives.len(), 2);
    for p in primitives {
        let position = p["attributes"]["POSITION"].as_u64().unwrap() as usize;
        assert_eq!(document["accessors"][position]["count"], 3);
    }
}

/// gltfpack's default output (KHR_mesh_quantization): 16-bit integer positions dequantised by
/// the node's scale and offset, 8-bit normalised normals. It reads as the float triangle does;
/// integer positions without the extension are refused.
#[test]
fn quantized_attributes_read_as_their_float_values() {
    let dir = scratch("quantized");
    // Positions (u16, not normalised): (0,0,0), (65535,0,0), (0,65535,0), 2 bytes of padding;
    // normals (i8, normalised): (0,0,127) three times, 1 byte of padding each (stride 4);
    // indices (u32).
    let mut bytes: Vec<u8> = [0u16, 0, 0, 65535, 0, 0, 0, 65535, 0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    bytes.extend([0, 0]);
    for _ in 0..3 {
        bytes.extend([0u8, 0, 127, 0]);
    }
    bytes.extend([0u32, 1, 2].iter().flat_map(|x| x.to_le_bytes()));
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    );
    let json = |extensions: &str| {
        format!(
            r#"{{"asset":{{"version":"2.0"}},{extensions}"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"mesh":0,"scale":[{s},{s},{s}],"translation":[2,0,0]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2}}]}}],
"accessors":[{{"bufferView":0,"componentType":5123,"count":3,"type":"VEC3","min":[0,0,0],"max":[65535,65535,0]}},
{{"bufferView":1,"componentType":5120,"normalized":true,"count":3,"type":"VEC3"}},
{{"bufferView":2,"componentType":5125,"count":3,"type":"SCALAR"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":18}},{{"buffer":0,"byteOffset":20,"byteLength":12,"byteStride":4}},
{{"buffer":0,"byteOffset":32,"byteLength":12}}],
"buffers":[{{"uri":"{uri}","byteLength":{}}}]}}"#,
            bytes.len(),
            s = 1.0 / 65535.0
        )
    };
    let quantized = dir.join("quantized.gltf");
    std::fs::write(
        &quantized,
        json(r#""extensionsUsed":["KHR_mesh_quantization"],"extensionsRequired":["KHR_mesh_quantization"],"#),
    )
    .unwrap();
    let mesh = read_mesh(&quantized).unwrap();
    let expected = [[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, 1.0, 0.0]];
    for (p, e) in mesh.positions().iter().zip(expected) {
        assert!(
            (p.to_array().iter().zip(e).map(|(a, b)| (a - b).abs())).all(|d| d < 1e-9),
            "{p}"
        );
    }
    for n in mesh.normals().unwrap() {
        assert!((n.z - 1.0).abs() < 1e-6 && n.x == 0.0 && n.y == 0.0, "{n}");
    }
    // Without the extension, integer positions are not glTF: refused naming the accessor.
    let plain = dir.join("plain.gltf");
    std::fs::write(&plain, json("")).unwrap();
    let error = read_mesh(&plain).unwrap_err().to_string();
    assert!(
        error.contains("POSITION") && error.contains("accessor 0"),
        "{error}"
    );
    // An extension this reader does not handle is named, with the way out.
    let draco = dir.join("draco.gltf");
    std::fs::write(
        &draco,
        json(r#""extensionsRequired":["KHR_mesh_quantization","KHR_draco_mesh_compression"],"#),
    )
    .unwrap();
    let error = read_mesh(&draco).unwrap_err().to_string();
    assert!(
        error.contains("KHR_draco_mesh_compression") && error.contains("export without"),
        "{error}"
    );
}

/// A skinned triangle under a transformed armature: placed by its joints (world × inverse
/// bind, glTF 2.0 "Skins"), the mesh node's own transform ignored; a moved joint carries its
/// vertex; a mirrored armature keeps the winding outward; a joint index past the skin's joints
/// is refused naming the attribute.
#[test]
fn skinned_meshes_are_placed_by_their_joints_not_their_node() {
    let dir = scratch("skinned");
    // Positions (36 bytes), JOINTS_0 u8 (12), WEIGHTS_0 f32 (48), two inverse bind matrices
    // (128), indices u32 (12).
    let mut bytes: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let joints = |last: u8| [0u8, 0, 0, 0, 0, 0, 0, 0, last, 0, 0, 0];
    bytes.extend(joints(1));
    for _ in 0..3 {
        bytes.extend([1.0f32, 0.0, 0.0, 0.0].iter().flat_map(|x| x.to_le_bytes()));
    }
    // Joint 0 binds at the armature's origin, joint 1 at z = 5 (its inverse: z − 5).
    let identity = glam::Mat4::IDENTITY.to_cols_array();
    let down = glam::Mat4::from_translation(glam::Vec3::new(0.0, 0.0, -5.0)).to_cols_array();
    bytes.extend(identity.iter().chain(&down).flat_map(|x| x.to_le_bytes()));
    bytes.extend([0u32, 1, 2].iter().flat_map(|x| x.to_le_bytes()));
    let write_under = |name: &str,
                       armature_scale: &str,
                       joint_z: f64,
                       joint_bytes: [u8; 12],
                       chain: usize| {
        let mut bytes = bytes.clone();
        bytes[36..48].copy_from_slice(&joint_bytes);
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&bytes)
        );
        // `chain` plain nodes above the armature (nodes 4, 5, …, the last holding node 0).
        let chain_nodes: String = (0..chain)
            .map(|k| {
                let child = if k + 1 == chain { 0 } else { 5 + k };
                format!(r#",{{"children":[{child}]}}"#)
            })
            .collect();
        let roots = if chain == 0 { "0,3" } else { "4,3" };
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{roots}]}}],
"nodes":[{{"name":"armature","translation":[10,0,0],"scale":{armature_scale},"children":[1,2]}},
{{"name":"root"}},{{"name":"tip","translation":[0,0,{joint_z}]}},
{{"name":"limb","mesh":0,"skin":0,"translation":[100,100,100],"scale":[3,3,3]}}{chain_nodes}],
"skins":[{{"joints":[1,2],"inverseBindMatrices":3}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"JOINTS_0":1,"WEIGHTS_0":2}},"indices":4}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
{{"bufferView":1,"componentType":5121,"count":3,"type":"VEC4"}},
{{"bufferView":2,"componentType":5126,"count":3,"type":"VEC4"}},
{{"bufferView":3,"componentType":5126,"count":2,"type":"MAT4"}},
{{"bufferView":4,"componentType":5125,"count":3,"type":"SCALAR"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":12}},
{{"buffer":0,"byteOffset":48,"byteLength":48}},{{"buffer":0,"byteOffset":96,"byteLength":128}},
{{"buffer":0,"byteOffset":224,"byteLength":12}}],
"buffers":[{{"uri":"{uri}","byteLength":{}}}]}}"#,
            bytes.len()
        );
        let path = dir.join(name);
        std::fs::write(&path, json).unwrap();
        read_mesh(&path)
    };
    let write = |name: &str, armature_scale: &str, joint_z: f64, joint_bytes: [u8; 12]| {
        write_under(name, armature_scale, joint_z, joint_bytes, 0)
    };
    let close = |mesh: &starcages_core::mesh::Mesh, expected: [[f64; 3]; 3]| {
        for (p, e) in mesh.positions().iter().zip(expected) {
            let d = (*p - glam::DVec3::from(e)).length();
            assert!(d < 1e-6, "{p} against {e:?}");
        }
    };
    // At the bind pose every joint matrix is the armature's: translate 10 in x, scale 2.
    let rest = write("rest.gltf", "[2,2,2]", 5.0, joints(1)).unwrap();
    close(
        &rest,
        [[10.0, 0.0, 0.0], [12.0, 0.0, 0.0], [10.0, 2.0, 0.0]],
    );
    // The tip joint raised by 1 (2 after the armature's scale) carries the vertex it weighs.
    let posed = write("posed.gltf", "[2,2,2]", 6.0, joints(1)).unwrap();
    close(
        &posed,
        [[10.0, 0.0, 0.0], [12.0, 0.0, 0.0], [10.0, 2.0, 2.0]],
    );
    // A mirrored armature (scale −2 in x): positions mirrored, the winding kept outward (the
    // triangle's geometric normal is +z before and after).
    let mirrored = write("mirrored.gltf", "[-2,2,2]", 5.0, joints(1)).unwrap();
    close(
        &mirrored,
        [[10.0, 0.0, 0.0], [8.0, 0.0, 0.0], [10.0, 2.0, 0.0]],
    );
    let normal = |mesh: &starcages_core::mesh::Mesh| {
        let p = mesh.positions();
        let t = mesh.triangles()[0].map(|i| p[i as usize]);
        (t[1] - t[0]).cross(t[2] - t[0]).z
    };
    assert!(normal(&rest) > 0.0 && normal(&mirrored) > 0.0);
    // Under a chain of 100,000 plain nodes: the joints' worlds are found in linear time
    // (walking each node's ancestors anew was quadratic: minutes).
    let deep = write_under("deep.gltf", "[2,2,2]", 5.0, joints(1), 100_000).unwrap();
    close(
        &deep,
        [[10.0, 0.0, 0.0], [12.0, 0.0, 0.0], [10.0, 2.0, 0.0]],
    );
    // Joint 7 of a two-joint skin: refused, naming the attribute and the vertex.
    let error = write("bad.gltf", "[2,2,2]", 5.0, joints(7))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("JOINTS_0") && error.contains("joint 7") && error.contains("vertex 2"),
        "{error}"
    );
}

/// A triangle whose positions and indices are `EXT_meshopt_compression` streams (encoded here
/// with the same library's encoder), in a fallback buffer without data, as gltfpack's `-cc`
/// writes: it reads as the plain triangle. A corrupt stream, a stream that does not fit its
/// view and a fallback claiming gigabytes are refused naming the buffer view or buffer.
#[test]
fn meshopt_compressed_views_decode_into_their_fallback_buffer() {
    let dir = scratch("meshopt");
    let positions: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 3.0, 0.0]];
    let vertices = meshopt::encode_vertex_buffer(&positions).unwrap();
    let indices = meshopt::encode_index_buffer(&[0, 1, 2], 3).unwrap();
    let document = |vertex_stream: &[u8], fallback_length: usize, view_length: usize| {
        let mut bytes = vertex_stream.to_vec();
        let index_offset = bytes.len();
        bytes.extend(&indices);
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&bytes)
        );
        format!(
            r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["EXT_meshopt_compression"],
"extensionsRequired":["EXT_meshopt_compression"],"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[2,3,0]}},
{{"bufferView":1,"componentType":5125,"count":3,"type":"SCALAR"}}],
"bufferViews":[{{"buffer":1,"byteOffset":0,"byteLength":{view_length},"byteStride":12,
"extensions":{{"EXT_meshopt_compression":{{"buffer":0,"byteOffset":0,"byteLength":{},"byteStride":12,"mode":"ATTRIBUTES","count":3}}}}}},
{{"buffer":1,"byteOffset":36,"byteLength":12,
"extensions":{{"EXT_meshopt_compression":{{"buffer":0,"byteOffset":{index_offset},"byteLength":{},"byteStride":4,"mode":"TRIANGLES","count":3}}}}}}],
"buffers":[{{"uri":"{uri}","byteLength":{}}},
{{"byteLength":{fallback_length},"extensions":{{"EXT_meshopt_compression":{{"fallback":true}}}}}}]}}"#,
            vertex_stream.len(),
            indices.len(),
            bytes.len()
        )
    };
    let read_doc = |name: &str, json: String| {
        let path = dir.join(name);
        std::fs::write(&path, json).unwrap();
        read_mesh(&path)
    };
    let mesh = read_doc("good.gltf", document(&vertices, 48, 36)).unwrap();
    let expected = positions.map(|p| glam::DVec3::new(p[0].into(), p[1].into(), p[2].into()));
    assert_eq!(mesh.positions(), expected.as_slice());
    assert_eq!(mesh.triangles(), [[0, 1, 2]].as_slice());
    // A damaged vertex stream (its header byte) does not decode.
    let mut damaged = vertices.clone();
    damaged[0] ^= 0xff;
    let error = read_doc("damaged.gltf", document(&damaged, 48, 36))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("buffer view 0") && error.contains("EXT_meshopt_compression"),
        "{error}"
    );
    // The fallback buffer too small for the decoded views.
    let error = read_doc("small.gltf", document(&vertices, 40, 36))
        .unwrap_err()
        .to_string();
    assert!(error.contains("do not fit buffer 1"), "{error}");
    // A fallback claiming 4 GB from a file of a few hundred bytes.
    let error = read_doc("huge.gltf", document(&vertices, 4_000_000_000, 36))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("buffer 1") && error.contains("fallback"),
        "{error}"
    );
}

/// A placement that cannot place a mesh is refused naming the node (or the skin, joint and
/// node) that breaks it, not blamed on a mesh vertex afterwards: a node or ancestor of scale
/// zero, a skin's joint of scale zero, an inverse bind matrix of NaN or zero, joints whose
/// parents form a loop outside the scene. Index lists and vertex runs that are not whole
/// triangles name the mesh and primitive by index (issue 42, classes 1 and 3).
#[test]
fn placements_that_cannot_place_are_refused_naming_the_node() {
    let dir = scratch("placements");
    let says = |name: &str, json: &str, text: &str| {
        let error = read(&dir, name, json).unwrap_err();
        assert!(error.contains(text), "{name}: {text:?} not in {error}");
    };
    says(
        "flat.gltf",
        &document(
            r#"[{"mesh":0,"scale":[1,0,1]}]"#,
            PRIMITIVE,
            &format!("[{POSITION},{INDICES}]"),
            VIEWS,
        ),
        "node 0 'unnamed' places mesh 0 ('tri') by a transform that flattens the mesh (a scale of zero); give the node a non-zero scale",
    );
    says(
        "ancestor.gltf",
        &document(
            r#"[{"name":"group","scale":[0,0,0],"children":[1]},{"name":"leaf","mesh":0}]"#,
            PRIMITIVE,
            &format!("[{POSITION},{INDICES}]"),
            VIEWS,
        ),
        "node 1 'leaf' places mesh 0 ('tri') by a transform that flattens the mesh (a scale of zero) (through its ancestor node 0 'group')",
    );
    let two_indices = INDICES.replace(r#""count":3"#, r#""count":2"#);
    says(
        "indices.gltf",
        &document(
            ONE_NODE,
            PRIMITIVE,
            &format!("[{POSITION},{two_indices}]"),
            VIEWS,
        ),
        "mesh 0 ('tri'), primitive 0, the index list holds 2 indices",
    );
    let two_vertices = POSITION.replace(r#""count":3"#, r#""count":2"#);
    says(
        "run.gltf",
        &document(
            ONE_NODE,
            r#"{"attributes":{"POSITION":0}}"#,
            &format!("[{two_vertices}]"),
            VIEWS,
        ),
        "mesh 0 ('tri'), primitive 0, POSITION has 2 vertices and no index list",
    );

    // Skins: the triangle weighted to joint 0 (nodes named in `nodes`, joints `joints`), with
    // inverse bind matrix 0 as given.
    let skinned = |nodes: &str, joints: &str, inverse_bind: [f32; 16]| {
        let mut bytes: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        bytes.extend([0u8; 12]);
        for _ in 0..3 {
            bytes.extend([1.0f32, 0.0, 0.0, 0.0].iter().flat_map(|x| x.to_le_bytes()));
        }
        let identity = glam::Mat4::IDENTITY.to_cols_array();
        bytes.extend(
            inverse_bind
                .iter()
                .chain(&identity)
                .flat_map(|x| x.to_le_bytes()),
        );
        bytes.extend([0u32, 1, 2].iter().flat_map(|x| x.to_le_bytes()));
        let uri = base64::engine::general_purpose::STANDARD.encode(&bytes);
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"name":"limb","mesh":0,"skin":0}},{nodes}],
"skins":[{{"joints":{joints},"inverseBindMatrices":3}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"JOINTS_0":1,"WEIGHTS_0":2}},"indices":4}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
{{"bufferView":1,"componentType":5121,"count":3,"type":"VEC4"}},
{{"bufferView":2,"componentType":5126,"count":3,"type":"VEC4"}},
{{"bufferView":3,"componentType":5126,"count":2,"type":"MAT4"}},
{{"bufferView":4,"componentType":5125,"count":3,"type":"SCALAR"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":12}},
{{"buffer":0,"byteOffset":48,"byteLength":48}},{{"buffer":0,"byteOffset":96,"byteLength":128}},
{{"buffer":0,"byteOffset":224,"byteLength":12}}],
"buffers":[{{"uri":"data:application/octet-stream;base64,{uri}","byteLength":{}}}]}}"#,
            bytes.len()
        )
    };
    let identity = glam::Mat4::IDENTITY.to_cols_array();
    let bones = r#"{"name":"hip"},{"name":"knee"}"#;
    assert_eq!(
        read(&dir, "skin.gltf", &skinned(bones, "[1,2]", identity)),
        Ok(1)
    );
    says(
        "zero-joint.gltf",
        &skinned(
            r#"{"name":"hip","scale":[0,0,0]},{"name":"knee"}"#,
            "[1,2]",
            identity,
        ),
        "skin 0 ('unnamed'), joint 0 (node 1 'hip') stands where its transform (with its parents') flattens the mesh",
    );
    says(
        "nan-ibm.gltf",
        &skinned(bones, "[1,2]", [f32::NAN; 16]),
        "skin 0 ('unnamed'), joint 0 (node 1 'hip') has an inverse bind matrix that is not finite",
    );
    says(
        "zero-ibm.gltf",
        &skinned(bones, "[1,2]", [0.0; 16]),
        "skin 0 ('unnamed'), joint 0 (node 1 'hip') has an inverse bind matrix that flattens the mesh",
    );
    // Joints outside the scene whose parents form a loop (the walk of the scene never meets
    // them): the mesh was placed one unit off before.
    says(
        "loop.gltf",
        &skinned(
            r#"{"name":"hip","translation":[1,0,0],"children":[2]},{"name":"knee","children":[1]}"#,
            "[1,2]",
            identity,
        ),
        "skin 0 ('unnamed'), joint 0 (node 1 'hip') hangs from a loop of parents",
    );
}
