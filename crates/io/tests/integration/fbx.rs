//! FBX, binary and ASCII: files written here (one node tree, both encodings) read with every
//! mesh node placed in world space — parents, non-uniform scale, a mirrored node turned
//! outward, one geometry under two nodes — in metres and turned from the declared up axis to
//! Y-up; a skinned mesh at its bind pose; forged and damaged files refused with the reason,
//! never a panic (proptest).

use std::path::Path;

use glam::{DAffine3, DMat3, DQuat, DVec3};
use proptest::prelude::*;
use starcages_core::mesh::Mesh;
use starcages_core::scene::UpAxis;
use starcages_io::{parse_fbx, read_mesh, read_mesh_as};

use starcages_test_support::Scratch;

/// One value of an FBX node's property list.
#[derive(Clone)]
enum Prop {
    Int(i32),
    Long(i64),
    Double(f64),
    Text(String),
    /// An object's name: "Class::name" in ASCII, "name\0\x01Class" in binary.
    Name(&'static str, String),
    Doubles(Vec<f64>),
    Ints(Vec<i32>),
}

/// A node of the FBX document tree.
#[derive(Clone)]
struct Node {
    name: &'static str,
    props: Vec<Prop>,
    children: Vec<Node>,
}

fn node(name: &'static str, props: Vec<Prop>, children: Vec<Node>) -> Node {
    Node {
        name,
        props,
        children,
    }
}

fn text(s: &str) -> Prop {
    Prop::Text(s.to_owned())
}

/// A `P:` entry of a Properties70 block.
fn p(name: &str, kind: &str, values: &[f64]) -> Node {
    let mut props = vec![text(name), text(kind), text(""), text("A")];
    props.extend(values.iter().map(|&v| Prop::Double(v)));
    node("P", props, vec![])
}

fn p_int(name: &str, value: i32) -> Node {
    node(
        "P",
        vec![
            text(name),
            text("int"),
            text("Integer"),
            text(""),
            Prop::Int(value),
        ],
        vec![],
    )
}

fn ascii(nodes: &[Node]) -> Vec<u8> {
    fn write(out: &mut String, n: &Node, depth: usize) {
        let indent = "\t".repeat(depth);
        let arrays = n
            .props
            .iter()
            .any(|p| matches!(p, Prop::Doubles(_) | Prop::Ints(_)));
        out.push_str(&format!("{indent}{}: ", n.name));
        if arrays {
            let (count, values) = match &n.props[0] {
                Prop::Doubles(v) => (v.len(), v.iter().map(|x| format!("{x:?}")).collect()),
                Prop::Ints(v) => (v.len(), v.iter().map(i32::to_string).collect::<Vec<_>>()),
                _ => unreachable!(),
            };
            out.push_str(&format!(
                "*{count} {{\n{indent}\ta: {}\n{indent}}}\n",
                values.join(",")
            ));
            return;
        }
        let props: Vec<String> = n
            .props
            .iter()
            .map(|p| match p {
                Prop::Int(v) => v.to_string(),
                Prop::Long(v) => v.to_string(),
                Prop::Double(v) => format!("{v:?}"),
                Prop::Text(s) => format!("\"{s}\""),
                Prop::Name(class, name) => format!("\"{class}::{name}\""),
                Prop::Doubles(_) | Prop::Ints(_) => unreachable!(),
            })
            .collect();
        out.push_str(&props.join(", "));
        if n.children.is_empty() {
            out.push('\n');
        } else {
            out.push_str(" {\n");
            for c in &n.children {
                write(out, c, depth + 1);
            }
            out.push_str(&format!("{indent}}}\n"));
        }
    }
    let mut out = String::from("; FBX 7.4.0 project file\n");
    for n in nodes {
        write(&mut out, n, 0);
    }
    out.into_bytes()
}

fn binary(nodes: &[Node]) -> Vec<u8> {
    fn props(n: &Node) -> Vec<u8> {
        let mut b = Vec::new();
        for p in &n.props {
            match p {
                Prop::Int(v) => {
                    b.push(b'I');
                    b.extend(v.to_le_bytes());
                }
                Prop::Long(v) => {
                    b.push(b'L');
                    b.extend(v.to_le_bytes());
                }
                Prop::Double(v) => {
                    b.push(b'D');
                    b.extend(v.to_le_bytes());
                }
                Prop::Text(s) => {
                    b.push(b'S');
                    b.extend((s.len() as u32).to_le_bytes());
                    b.extend(s.as_bytes());
                }
                Prop::Name(class, name) => {
                    let s = format!("{name}\0\x01{class}");
                    b.push(b'S');
                    b.extend((s.len() as u32).to_le_bytes());
                    b.extend(s.as_bytes());
                }
                Prop::Doubles(v) => {
                    b.push(b'd');
                    b.extend((v.len() as u32).to_le_bytes());
                    b.extend(0u32.to_le_bytes());
                    b.extend((v.len() as u32 * 8).to_le_bytes());
                    v.iter().for_each(|x| b.extend(x.to_le_bytes()));
                }
                Prop::Ints(v) => {
                    b.push(b'i');
                    b.extend((v.len() as u32).to_le_bytes());
                    b.extend(0u32.to_le_bytes());
                    b.extend((v.len() as u32 * 4).to_le_bytes());
                    v.iter().for_each(|x| b.extend(x.to_le_bytes()));
                }
            }
        }
        b
    }
    fn write(out: &mut Vec<u8>, n: &Node) {
        let start = out.len();
        let list = props(n);
        out.extend([0u8; 4]); // end offset, filled below
        out.extend((n.props.len() as u32).to_le_bytes());
        out.extend((list.len() as u32).to_le_bytes());
        out.push(n.name.len() as u8);
        out.extend(n.name.as_bytes());
        out.extend(list);
        if !n.children.is_empty() {
            for c in &n.children {
                write(out, c);
            }
            out.extend([0u8; 13]);
        }
        let end = out.len() as u32;
        out[start..start + 4].copy_from_slice(&end.to_le_bytes());
    }
    let mut out = b"Kaydara FBX Binary  \0\x1a\0".to_vec();
    out.extend(7400u32.to_le_bytes());
    for n in nodes {
        write(&mut out, n);
    }
    out.extend([0u8; 13]);
    out
}

/// The unit cube's corners and its six quads, outward, as FBX stores polygons (the last
/// corner of each one's index written as its bitwise complement).
fn cube_geometry(id: i64, name: &str) -> Node {
    let corners: Vec<f64> = (0..8)
        .flat_map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
        .collect();
    let indices: Vec<i32> = crate::mesh_formats::QUADS
        .iter()
        .flat_map(|q| q.map(|i| i as i32))
        .collect::<Vec<_>>()
        .chunks(4)
        .flat_map(|q| [q[0], q[1], q[2], !q[3]])
        .collect();
    node(
        "Geometry",
        vec![
            Prop::Long(id),
            Prop::Name("Geometry", name.into()),
            text("Mesh"),
        ],
        vec![
            node("Vertices", vec![Prop::Doubles(corners)], vec![]),
            node("PolygonVertexIndex", vec![Prop::Ints(indices)], vec![]),
            node("GeometryVersion", vec![Prop::Int(124)], vec![]),
        ],
    )
}

/// A mesh model (an FBX node) with a local translation, rotation (degrees, XYZ order) and
/// scale.
fn model(id: i64, name: &str, t: [f64; 3], r: [f64; 3], s: [f64; 3]) -> Node {
    node(
        "Model",
        vec![
            Prop::Long(id),
            Prop::Name("Model", name.into()),
            text("Mesh"),
        ],
        vec![
            node("Version", vec![Prop::Int(232)], vec![]),
            node(
                "Properties70",
                vec![],
                vec![
                    p("Lcl Translation", "Lcl Translation", &t),
                    p("Lcl Rotation", "Lcl Rotation", &r),
                    p("Lcl Scaling", "Lcl Scaling", &s),
                ],
            ),
        ],
    )
}

fn connect(child: i64, parent: i64) -> Node {
    node(
        "C",
        vec![text("OO"), Prop::Long(child), Prop::Long(parent)],
        vec![],
    )
}

/// A document: global settings (up axis as FBX numbers it, 1 = Y and 2 = Z; unit in
/// centimetres per unit), objects and their connections.
fn document(up: i32, unit_cm: f64, objects: Vec<Node>, connections: Vec<Node>) -> Vec<Node> {
    // Z-up files (Blender, 3ds Max) face -Y; Y-up ones (Maya) face +Z. X is right in both.
    let (front, front_sign) = if up == 2 { (1, -1) } else { (2, 1) };
    vec![
        node(
            "FBXHeaderExtension",
            vec![],
            vec![
                node("FBXHeaderVersion", vec![Prop::Int(1003)], vec![]),
                node("FBXVersion", vec![Prop::Int(7400)], vec![]),
            ],
        ),
        node(
            "GlobalSettings",
            vec![],
            vec![
                node("Version", vec![Prop::Int(1000)], vec![]),
                node(
                    "Properties70",
                    vec![],
                    vec![
                        p_int("UpAxis", up),
                        p_int("UpAxisSign", 1),
                        p_int("FrontAxis", front),
                        p_int("FrontAxisSign", front_sign),
                        p_int("CoordAxis", 0),
                        p_int("CoordAxisSign", 1),
                        node(
                            "P",
                            vec![
                                text("UnitScaleFactor"),
                                text("double"),
                                text("Number"),
                                text(""),
                                Prop::Double(unit_cm),
                            ],
                            vec![],
                        ),
                    ],
                ),
            ],
        ),
        node("Objects", vec![], objects),
        node("Connections", vec![], connections),
    ]
}

/// A parent turned 90° about its up axis and moved, a child under it stretched, a second
/// node sharing the child's geometry mirrored across x, all in a Z-up file whose unit is the
/// centimetre; returns the document and where each node's unit cube lies in metres, Z-up.
fn awkward_scene() -> (Vec<Node>, Vec<DAffine3>) {
    let objects = vec![
        cube_geometry(10, "box"),
        model(
            20,
            "parent",
            [100.0, 0.0, 50.0],
            [0.0, 0.0, 90.0],
            [1.0, 1.0, 1.0],
        ),
        model(
            21,
            "child",
            [0.0, 300.0, 0.0],
            [0.0, 0.0, 0.0],
            [2.0, 0.5, 1.0],
        ),
        model(
            22,
            "mirrored",
            [-400.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [-1.0, 1.0, 1.0],
        ),
    ];
    let connections = vec![
        connect(20, 0),
        connect(21, 20),
        connect(22, 0),
        connect(10, 21),
        connect(10, 22),
    ];
    let cm = DAffine3::from_scale(DVec3::splat(0.01));
    let parent = DAffine3::from_translation(DVec3::new(100.0, 0.0, 50.0))
        * DAffine3::from_quat(DQuat::from_rotation_z(90f64.to_radians()));
    let child = parent
        * DAffine3::from_translation(DVec3::new(0.0, 300.0, 0.0))
        * DAffine3::from_scale(DVec3::new(2.0, 0.5, 1.0));
    let mirrored = DAffine3::from_translation(DVec3::new(-400.0, 0.0, 0.0))
        * DAffine3::from_scale(DVec3::new(-1.0, 1.0, 1.0));
    (
        document(2, 1.0, objects, connections),
        vec![cm * child, cm * mirrored],
    )
}

/// The corners the reader should give: each placement's unit cube.
fn expected_corners(placements: &[DAffine3]) -> Vec<DVec3> {
    placements
        .iter()
        .flat_map(|a| {
            (0..8).map(move |i| {
                a.transform_point3(DVec3::new(
                    (i & 1) as f64,
                    ((i >> 1) & 1) as f64,
                    ((i >> 2) & 1) as f64,
                ))
            })
        })
        .collect()
}

fn signed_volume(mesh: &Mesh) -> f64 {
    let p = mesh.positions();
    mesh.triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| p[i as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

fn assert_placed(what: &str, mesh: &Mesh, placements: &[DAffine3]) {
    let expected = expected_corners(placements);
    assert_eq!(mesh.welded_positions().len(), expected.len(), "{what}");
    assert_eq!(mesh.triangles().len(), 12 * placements.len(), "{what}");
    for e in &expected {
        let nearest = mesh
            .welded_positions()
            .iter()
            .map(|p| p.distance(*e))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1e-9,
            "{what}: no vertex at {e} (nearest {nearest})"
        );
    }
    // Outward everywhere: each cube's volume counts positive, the mirrored one included.
    let volume: f64 = placements
        .iter()
        .map(|a| a.matrix3.determinant().abs())
        .sum();
    let read = signed_volume(mesh);
    assert!(
        (read - volume).abs() < 1e-9,
        "{what}: volume {read}, expected {volume}"
    );
}

/// `bytes` written to a file `name` in a fresh scratch folder, which is removed when the first
/// of the two is dropped.
fn scratch(name: &str, bytes: &[u8]) -> (Scratch, std::path::PathBuf) {
    let dir = Scratch::new("fbx");
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

#[test]
fn every_node_is_placed_in_world_space_in_metres_and_outward() {
    let (doc, placements) = awkward_scene();
    for (what, bytes) in [("binary", binary(&doc)), ("ascii", ascii(&doc))] {
        // The file is Z-up: read as the Y-up mesh StarCages takes FBX to be, then turned to
        // the scene's Z-up, the corners are where the file's own axes put them.
        let (_dir, path) = scratch(&format!("awkward-{what}.fbx"), &bytes);
        let mesh = read_mesh_as(&path, UpAxis::Y).unwrap();
        assert_placed(what, &mesh, &placements);
        // In the file axes StarCages reads FBX in (Y-up): the same corners, turned.
        let y_up = parse_fbx(&path, &bytes).unwrap();
        let turned: Vec<DAffine3> = placements
            .iter()
            .map(|a| DAffine3::from_mat3(DMat3::from_cols(DVec3::X, DVec3::NEG_Z, DVec3::Y)) * *a)
            .collect();
        assert_placed(&format!("{what}, Y-up"), &y_up, &turned);
    }
}

#[test]
fn y_up_files_and_units_are_read_as_declared() {
    // A Maya-like file: Y-up, in metres (100 cm per unit), one cube moved up by 2 units.
    let doc = document(
        1,
        100.0,
        vec![
            cube_geometry(10, "box"),
            model(20, "box", [0.0, 2.0, 0.0], [0.0; 3], [1.0; 3]),
        ],
        vec![connect(20, 0), connect(10, 20)],
    );
    let mesh = parse_fbx(Path::new("maya.fbx"), &binary(&doc)).unwrap();
    assert_placed(
        "Y-up, metres",
        &mesh,
        &[DAffine3::from_translation(DVec3::new(0.0, 2.0, 0.0))],
    );
    // The same in inches (2.54 cm): scaled to metres.
    let doc = document(
        1,
        2.54,
        vec![
            cube_geometry(10, "box"),
            model(20, "box", [0.0; 3], [0.0; 3], [1.0; 3]),
        ],
        vec![connect(20, 0), connect(10, 20)],
    );
    let mesh = parse_fbx(Path::new("inches.fbx"), &ascii(&doc)).unwrap();
    assert_placed(
        "inches",
        &mesh,
        &[DAffine3::from_scale(DVec3::splat(0.0254))],
    );
}

#[test]
fn a_skinned_mesh_rests_at_its_bind_pose() {
    // A cube skinned to one bone: the mesh node has since been moved (its current transform
    // is 5 units along x) and so has the bone (100 units up), but the cluster records the bone
    // 1 unit up when bound ("TransformLink", its world matrix then) and the geometry in the
    // bone's frame ("Transform": 1 unit below it), so the mesh was bound at the origin.
    let identity = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let (mut bone_at, mut mesh_in_bone) = (identity, identity);
    bone_at[13] = 1.0; // column-major: translation y
    mesh_in_bone[13] = -1.0;
    let objects = vec![
        cube_geometry(10, "box"),
        model(20, "box", [500.0, 0.0, 0.0], [0.0; 3], [1.0; 3]),
        node(
            "Model",
            vec![
                Prop::Long(30),
                Prop::Name("Model", "bone".into()),
                text("LimbNode"),
            ],
            vec![node(
                "Properties70",
                vec![],
                vec![p("Lcl Translation", "Lcl Translation", &[0.0, 100.0, 0.0])],
            )],
        ),
        node(
            "Deformer",
            vec![
                Prop::Long(40),
                Prop::Name("Deformer", "skin".into()),
                text("Skin"),
            ],
            vec![node("Version", vec![Prop::Int(101)], vec![])],
        ),
        node(
            "Deformer",
            vec![
                Prop::Long(41),
                Prop::Name("SubDeformer", "cluster".into()),
                text("Cluster"),
            ],
            vec![
                node("Version", vec![Prop::Int(100)], vec![]),
                node("Indexes", vec![Prop::Ints((0..8).collect())], vec![]),
                node("Weights", vec![Prop::Doubles(vec![1.0; 8])], vec![]),
                node(
                    "Transform",
                    vec![Prop::Doubles(mesh_in_bone.to_vec())],
                    vec![],
                ),
                node(
                    "TransformLink",
                    vec![Prop::Doubles(bone_at.to_vec())],
                    vec![],
                ),
            ],
        ),
    ];
    let connections = vec![
        connect(20, 0),
        connect(30, 0),
        connect(10, 20),
        connect(40, 10),
        connect(41, 40),
        connect(30, 41),
    ];
    // Y-up, unit = 1 cm: the bind pose puts the cube at the origin, at a hundredth of its size.
    let doc = document(1, 1.0, objects, connections);
    let mesh = parse_fbx(Path::new("skinned.fbx"), &binary(&doc)).unwrap();
    assert_placed(
        "skinned",
        &mesh,
        &[DAffine3::from_scale(DVec3::splat(0.01))],
    );
}

#[test]
fn the_one_entry_point_reads_fbx_and_refuses_what_it_cannot() {
    let (doc, placements) = awkward_scene();
    let (_dir, path) = scratch("cube.fbx", &binary(&doc));
    let mesh = read_mesh(&path).unwrap();
    assert_eq!(mesh.welded_positions().len(), 8 * placements.len());
    let says = |bytes: &[u8], text: &str| {
        let (_dir, path) = scratch("bad.fbx", bytes);
        let error = read_mesh(&path).unwrap_err().to_string();
        assert!(error.contains("bad.fbx"), "the file is named: {error}");
        assert!(error.contains(text), "{text:?} not in {error}");
    };
    let mut cut = binary(&doc);
    cut.truncate(cut.len() / 2);
    says(&cut, "not a readable FBX file");
    says(b"not an fbx file at all", "not a readable FBX file");
    // Only a camera: a readable file without a mesh says so.
    let camera = document(
        2,
        1.0,
        vec![node(
            "Model",
            vec![
                Prop::Long(20),
                Prop::Name("Model", "cam".into()),
                text("Camera"),
            ],
            vec![],
        )],
        vec![connect(20, 0)],
    );
    says(&binary(&camera), "has no mesh");
    // A node that flattens its mesh (scale 0) cannot be bound.
    let flat = document(
        2,
        1.0,
        vec![
            cube_geometry(10, "box"),
            model(20, "flat", [0.0; 3], [0.0; 3], [1.0, 0.0, 1.0]),
        ],
        vec![connect(20, 0), connect(10, 20)],
    );
    says(&ascii(&flat), "node 'flat'");
    // A node graph with a cycle (a parent of its own parent) is an error, not a hang.
    let cyclic = document(
        2,
        1.0,
        vec![
            cube_geometry(10, "box"),
            model(20, "a", [0.0; 3], [0.0; 3], [1.0; 3]),
            model(21, "b", [0.0; 3], [0.0; 3], [1.0; 3]),
        ],
        vec![connect(20, 21), connect(21, 20), connect(10, 20)],
    );
    let error = parse_fbx(Path::new("cyclic.fbx"), &binary(&cyclic))
        .unwrap_err()
        .to_string();
    assert!(error.contains("Cyclic node hierarchy"), "{error}");
}

/// What a lenient reader would read as another mesh, or blame on the wrong thing, is refused
/// naming the element (issue 42): a unit scale of zero (Blender's importer would scale the
/// mesh to nothing; ufbx falls back to another unit) or not finite, and a polygon corner past
/// the vertex count (ufbx's bare "Failed to load" before).
#[test]
fn a_zero_unit_scale_and_a_corner_past_the_vertices_are_named() {
    let cube = |unit: f64| {
        document(
            2,
            unit,
            vec![
                cube_geometry(10, "box"),
                model(20, "box", [0.0; 3], [0.0; 3], [1.0; 3]),
            ],
            vec![connect(20, 0), connect(10, 20)],
        )
    };
    assert!(parse_fbx(Path::new("ok.fbx"), &binary(&cube(100.0))).is_ok());
    for unit in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        for bytes in [binary(&cube(unit)), ascii(&cube(unit))] {
            let error = parse_fbx(Path::new("unit.fbx"), &bytes)
                .unwrap_err()
                .to_string();
            assert!(
                error.contains("unit.fbx: GlobalSettings: UnitScaleFactor is"),
                "{unit}: {error}"
            );
        }
    }
    // The last quad names corner 8 of 8 (0-based): past the vertex count.
    let mut past = cube(100.0);
    let geometry = past
        .iter_mut()
        .find(|n| n.name == "Objects")
        .and_then(|objects| objects.children.iter_mut().find(|n| n.name == "Geometry"))
        .unwrap();
    let indices = geometry
        .children
        .iter_mut()
        .find(|n| n.name == "PolygonVertexIndex")
        .unwrap();
    let Prop::Ints(values) = &mut indices.props[0] else {
        panic!("indices")
    };
    let last = values.len() - 2;
    values[last] = 8;
    for bytes in [binary(&past), ascii(&past)] {
        let error = parse_fbx(Path::new("past.fbx"), &bytes)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains(
                "past.fbx: the file's nodes read, but the geometry of mesh 'box' does not: a \
                 polygon names a vertex past the mesh's vertex list"
            ),
            "{error}"
        );
    }
}

#[test]
fn an_array_promising_gigabytes_is_refused_without_allocating_them() {
    // A binary array whose header claims a billion doubles in a file of a few hundred bytes.
    let (doc, _) = awkward_scene();
    let mut bytes = binary(&doc);
    let at = bytes
        .windows(9)
        .position(|w| w == b"Verticesd")
        .expect("the vertex array")
        + 9;
    bytes[at..at + 4].copy_from_slice(&1_000_000_000u32.to_le_bytes());
    let error = parse_fbx(Path::new("forged.fbx"), &bytes)
        .unwrap_err()
        .to_string();
    assert!(error.contains("not a readable FBX file"), "{error}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(crate::fuzz_readers::fuzz_cases()))]

    /// Random damage (bytes replaced, removed, the file cut) never panics or hangs.
    #[test]
    fn damaged_fbx_files_never_panic(cuts in prop::collection::vec((0usize..4096, any::<u8>()), 1..6)) {
        let (doc, _) = awkward_scene();
        let at = Path::new("fuzz.fbx");
        let _ = parse_fbx(at, &crate::fuzz_readers::damage(binary(&doc), &cuts));
        let _ = parse_fbx(at, &crate::fuzz_readers::damage(ascii(&doc), &cuts));
    }
}

/// A material: its diffuse colour, linear RGB.
fn material(id: i64, name: &str, diffuse: [f64; 3]) -> Node {
    node(
        "Material",
        vec![
            Prop::Long(id),
            Prop::Name("Material", name.into()),
            text(""),
        ],
        vec![
            node("Version", vec![Prop::Int(102)], vec![]),
            node("ShadingModel", vec![text("phong")], vec![]),
            node(
                "Properties70",
                vec![],
                vec![p("DiffuseColor", "Color", &diffuse)],
            ),
        ],
    )
}

/// An image file texture.
fn file_texture(id: i64, name: &str, file: &str) -> Node {
    node(
        "Texture",
        vec![Prop::Long(id), Prop::Name("Texture", name.into()), text("")],
        vec![
            node("Type", vec![text("TextureVideoClip")], vec![]),
            node(
                "FileName",
                vec![text(&format!("/elsewhere/{file}"))],
                vec![],
            ),
            node("RelativeFilename", vec![text(file)], vec![]),
        ],
    )
}

/// A connection of an object to a property of another (a texture to a material's colour).
fn connect_property(child: i64, parent: i64, property: &str) -> Node {
    node(
        "C",
        vec![
            text("OP"),
            Prop::Long(child),
            Prop::Long(parent),
            text(property),
        ],
        vec![],
    )
}

/// FBX materials through ufbx, in both encodings: a cube whose first three faces wear a red
/// material with an image beside the file (named relatively; the absolute name from the
/// artist's machine does not exist here) and whose last three a plain green one. The look has
/// both (colours encoded for display), each triangle its face's material, v counted from the
/// image's bottom; the image decodes. Read without the look, the same mesh.
#[test]
fn materials_per_face_with_their_colours_and_image_files() {
    let mut geometry = cube_geometry(10, "box");
    geometry.children.push(node(
        "LayerElementMaterial",
        vec![Prop::Int(0)],
        vec![
            node("Version", vec![Prop::Int(101)], vec![]),
            node("Name", vec![text("")], vec![]),
            node("MappingInformationType", vec![text("ByPolygon")], vec![]),
            node(
                "ReferenceInformationType",
                vec![text("IndexToDirect")],
                vec![],
            ),
            node(
                "Materials",
                vec![Prop::Ints(vec![0, 0, 0, 1, 1, 1])],
                vec![],
            ),
        ],
    ));
    let objects = vec![
        geometry,
        model(20, "box", [0.0; 3], [0.0; 3], [1.0; 3]),
        material(30, "red", [0.8, 0.05, 0.05]),
        material(31, "green", [0.05, 0.45, 0.08]),
        file_texture(40, "skin", "skin.png"),
    ];
    let connections = vec![
        connect(20, 0),
        connect(10, 20),
        connect(30, 20),
        connect(31, 20),
        connect_property(40, 30, "DiffuseColor"),
    ];
    let doc = document(2, 1.0, objects, connections);
    for (what, bytes) in [("binary", binary(&doc)), ("ascii", ascii(&doc))] {
        let (_dir, path) = scratch(&format!("materials-{what}.fbx"), &bytes);
        let png = path.with_file_name("skin.png");
        std::fs::write(&png, starcages_io::sample_files::checker_png()).unwrap();
        let (mesh, look) = starcages_io::read_mesh_look(&path).unwrap();
        assert_eq!(mesh, read_mesh(&path).unwrap(), "{what}");
        assert!(look.notes.is_empty(), "{what}: {:?}", look.notes);
        assert_eq!(
            look.uv_origin,
            starcages_core::mesh::look::UvOrigin::BottomLeft
        );
        let names: Vec<&str> = look.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["red", "green", "default"], "{what}");
        // Two triangles per quad face, in face order.
        assert_eq!(
            look.triangle_materials,
            [0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1],
            "{what}"
        );
        let red = &look.materials[0];
        assert!(
            (red.base_color[0] - 0.906).abs() < 0.01,
            "{what}: {:?}",
            red.base_color
        );
        assert_eq!(
            red.texture,
            Some(starcages_core::mesh::look::TextureSource::File(png.clone())),
            "{what}"
        );
        assert!(look.materials[1].texture.is_none());
        let image = starcages_io::load_texture(red.texture.as_ref().unwrap()).unwrap();
        assert_eq!((image.width, image.height), (64, 64));
    }
}
