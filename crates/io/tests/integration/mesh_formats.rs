//! PLY (ASCII, binary in both byte orders), STL (ASCII, binary) and OFF: the same cube read
//! from each, with the file's layout kept and coincident corners welded; extra properties and
//! elements skipped; forged and truncated files refused with the reason; random damage never
//! panics (proptest).

use std::path::Path;

use glam::DVec3;
use proptest::prelude::*;
use starcages_io::{parse_off, parse_ply, parse_stl, read_mesh};

/// The unit cube's corners and its six quads, outward.
const CORNERS: [[f64; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [1.0, 1.0, 1.0],
];
pub(crate) const QUADS: [[u32; 4]; 6] = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 4, 6, 2],
    [1, 3, 7, 5],
];

fn ascii_ply() -> String {
    let mut s = String::from(
        "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 8\nproperty float x\n\
         property float y\nproperty float z\nproperty uchar red\nproperty float u\nproperty float v\n\
         element face 6\nproperty list uchar int vertex_indices\nproperty uchar flags\n\
         element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n",
    );
    for c in CORNERS {
        s += &format!("{} {} {} 200 {} {}\n", c[0], c[1], c[2], c[0], c[1]);
    }
    for q in QUADS {
        s += &format!("4 {} {} {} {} 7\n", q[0], q[1], q[2], q[3]);
    }
    s + "0 1\n"
}

fn binary_ply(big: bool) -> Vec<u8> {
    let order = if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut out = format!(
        "ply\nformat {order} 1.0\nelement vertex 8\nproperty double x\nproperty double y\n\
         property double z\nproperty short extra\nelement face 6\n\
         property list uchar uint vertex_indices\nend_header\n"
    )
    .into_bytes();
    let put = |out: &mut Vec<u8>, le: &[u8]| {
        let mut b = le.to_vec();
        if big {
            b.reverse();
        }
        out.extend(b);
    };
    for c in CORNERS {
        for x in c {
            put(&mut out, &x.to_le_bytes());
        }
        put(&mut out, &(-3i16).to_le_bytes());
    }
    for q in QUADS {
        out.push(4);
        for i in q {
            put(&mut out, &i.to_le_bytes());
        }
    }
    out
}

fn triangles() -> Vec<[usize; 3]> {
    QUADS
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]].map(|t| t.map(|i| i as usize)))
        .collect()
}

fn ascii_stl() -> String {
    let mut s = String::from("solid cube\n");
    for t in triangles() {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for i in t {
            let c = CORNERS[i];
            s += &format!("      vertex {} {} {}\n", c[0], c[1], c[2]);
        }
        s += "    endloop\n  endfacet\n";
    }
    s + "endsolid cube\n"
}

fn binary_stl() -> Vec<u8> {
    let mut out = vec![b' '; 80];
    out.extend(12u32.to_le_bytes());
    for t in triangles() {
        out.extend([0u8; 12]);
        for i in t {
            for x in CORNERS[i] {
                out.extend((x as f32).to_le_bytes());
            }
        }
        out.extend([0u8; 2]);
    }
    out
}

fn off() -> String {
    let mut s = String::from("COFF\n# a cube\n8 6 12\n");
    for c in CORNERS {
        s += &format!("{} {} {} 255 0 0 255\n", c[0], c[1], c[2]);
    }
    for q in QUADS {
        s += &format!("4 {} {} {} {}  0.5 0.5 0.5\n", q[0], q[1], q[2], q[3]);
    }
    s
}

fn assert_cube(what: &str, mesh: &starcages_core::mesh::Mesh, layout: usize) {
    assert_eq!(mesh.positions().len(), layout, "{what}: the file's layout");
    assert_eq!(mesh.welded_positions().len(), 8, "{what}: welded corners");
    assert_eq!(mesh.triangles().len(), 12, "{what}");
    for c in CORNERS {
        assert!(
            mesh.welded_positions().contains(&DVec3::from_array(c)),
            "{what}: {c:?}"
        );
    }
    // Outward: the signed volume of the closed surface is +1.
    let p = mesh.positions();
    let volume: f64 = mesh
        .triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| p[i as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    assert!((volume - 1.0).abs() < 1e-12, "{what}: volume {volume}");
}

#[test]
fn the_same_cube_reads_from_every_format() {
    let at = Path::new("cube");
    let ply = parse_ply(at, ascii_ply().as_bytes()).unwrap();
    assert_cube("ascii ply", &ply, 8);
    assert_eq!(ply.uvs().map(<[glam::Vec2]>::len), Some(8), "u v read");
    assert_cube(
        "little-endian ply",
        &parse_ply(at, &binary_ply(false)).unwrap(),
        8,
    );
    assert_cube(
        "big-endian ply",
        &parse_ply(at, &binary_ply(true)).unwrap(),
        8,
    );
    assert_cube(
        "ascii stl",
        &parse_stl(at, ascii_stl().as_bytes()).unwrap(),
        36,
    );
    assert_cube("binary stl", &parse_stl(at, &binary_stl()).unwrap(), 36);
    assert_cube("off", &parse_off(at, &off()).unwrap(), 8);
    // By extension, through the one entry point every command and the editor use.
    let dir = starcages_test_support::Scratch::new("formats");
    for (name, bytes) in [
        ("cube.ply", binary_ply(false)),
        ("cube.stl", binary_stl()),
        ("cube.off", off().into_bytes()),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        assert_eq!(
            read_mesh(&path).unwrap().welded_positions().len(),
            8,
            "{name}"
        );
    }
    let error = read_mesh(&dir.join("cube.3ds")).unwrap_err().to_string();
    assert!(error.contains("fbx, ply, stl, off"), "{error}");
}

#[test]
fn forged_and_broken_files_are_refused_with_the_reason() {
    let at = Path::new("bad");
    let says = |result: Result<starcages_core::mesh::Mesh, starcages_io::FileError>, text: &str| {
        let error = result.unwrap_err().to_string();
        assert!(error.contains(text), "{text:?} not in {error}");
    };
    // PLY: a vertex count no file this size can hold, before anything is allocated.
    says(
        parse_ply(
            at,
            ascii_ply()
                .replace("vertex 8", "vertex 4000000000")
                .as_bytes(),
        ),
        "announces",
    );
    says(
        parse_ply(at, ascii_ply().replace("4 0 2 3 1", "4 0 2 3 9").as_bytes()),
        "names vertex 9, but there are 8 vertices (numbered from 0); the file is damaged: export \
         it again",
    );
    says(
        parse_ply(at, ascii_ply().replacen(" 200 ", " 2x0 ", 1).as_bytes()),
        "'2x0' is not a number",
    );
    let mut cut = binary_ply(false);
    cut.truncate(cut.len() - 3);
    says(parse_ply(at, &cut), "truncated");
    says(
        parse_ply(at, ascii_ply().replace("end_header", "end_head").as_bytes()),
        "end_header",
    );
    says(
        parse_ply(
            at,
            ascii_ply().replace("0 0 0 200", "nan 0 0 200").as_bytes(),
        ),
        "vertex 0 has a coordinate that is not finite (NaN or infinity); fix or remove it and \
         export again",
    );
    let points = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                  property float z\nend_header\n0 0 0\n";
    says(parse_ply(at, points.as_bytes()), "point cloud");
    // STL: a binary count that does not match the length; a facet cut short.
    let mut stl = binary_stl();
    stl.truncate(stl.len() - 10);
    says(parse_stl(at, &stl), "84 + 50 per triangle");
    says(
        parse_stl(
            at,
            ascii_stl()
                .replacen("      vertex 0 0 0\n", "", 1)
                .as_bytes(),
        ),
        "3",
    );
    says(
        parse_stl(
            at,
            ascii_stl()
                .replacen("vertex 0 0 0", "vertex 0 inf 0", 1)
                .as_bytes(),
        ),
        "bad:4: y 'inf' is not finite",
    );
    // Binary: the second triangle's first corner (84-byte header, 50 bytes a facet, the
    // normal's 12 first) has a NaN y.
    let mut stl = binary_stl();
    stl[84 + 50 + 12 + 4..84 + 50 + 12 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    says(
        parse_stl(at, &stl),
        "triangle 1 has a corner that is not finite (NaN or infinity); fix or remove it and \
         export again",
    );
    // OFF: counts beyond the file, a corner out of range, not an OFF file.
    says(
        parse_off(at, &off().replace("8 6 12", "80000000 6 12")),
        "truncated",
    );
    says(
        parse_off(at, &off().replace("4 0 2 3 1", "4 0 2 3 8")),
        "face 0",
    );
    says(parse_off(at, "PLY\n"), "not an OFF file");
}

/// Files that a lenient reader would read as another mesh (a flat one, one of two vertex
/// sets, 4-D points cut to 3-D) are refused, naming the element; and files of another kind
/// than their first bytes suggest are refused for what they are (issue 42, classes 1 and 3).
#[test]
fn nonsense_is_refused_not_read_as_another_mesh() {
    let at = Path::new("bad");
    let says = |result: Result<starcages_core::mesh::Mesh, starcages_io::FileError>, text: &str| {
        let error = result.unwrap_err().to_string();
        assert!(error.contains(text), "{text:?} not in {error}");
    };
    // PLY: a second vertex element (which set is the mesh's?), a coordinate declared as a list
    // (read as 0 before: a flat mesh), a property declared twice.
    let second = ascii_ply().replace(
        "element face 6",
        "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 6",
    );
    says(
        parse_ply(at, second.as_bytes()),
        "bad:11: a second 'vertex' element (the first is on line 4)",
    );
    let listed = ascii_ply().replace("property float z", "property list uchar float z");
    says(
        parse_ply(at, listed.as_bytes()),
        "vertex property 'z' is declared as a list",
    );
    let twice = ascii_ply().replace("property float u", "property float y");
    says(
        parse_ply(at, twice.as_bytes()),
        "property 'y' is declared twice",
    );
    // Counts smaller than the data (the last vertices or faces would be dropped without a
    // word): refused, in PLY (text and binary) and OFF.
    says(
        parse_ply(
            at,
            ascii_ply()
                .replace("element edge 1", "element edge 0")
                .as_bytes(),
        ),
        "line 32 still holds data ('0') after the last element the header announces",
    );
    let mut longer = binary_ply(false);
    longer.extend([0u8; 12]);
    says(
        parse_ply(at, &longer),
        "12 bytes of data remain after the last element",
    );
    says(
        parse_off(at, &off().replace("8 6 12", "8 5 12")),
        "bad:17: data after the 8 vertices and 5 faces the counts announce",
    );
    // OFF: 4-D vertices, by either spelling; nOFF of dimension 3 is a plain OFF.
    let plain = off().replacen("COFF", "OFF", 1);
    says(
        parse_off(at, &plain.replacen("OFF", "4OFF", 1)),
        "'4OFF' announces 4-D vertices",
    );
    says(
        parse_off(at, &plain.replacen("OFF", "nOFF\n4", 1)),
        "bad:2: 'nOFF' announces 4-D vertices",
    );
    let three = parse_off(at, &plain.replacen("OFF", "nOFF 3", 1)).unwrap();
    assert_cube("nOFF 3", &three, 8);
    says(
        parse_off(at, &plain.replacen("OFF", "XOFF", 1)),
        "not an OFF file",
    );
    // A binary OFF says so, from the text and from a file (not "not UTF-8 text").
    says(parse_off(at, "OFF BINARY\n"), "binary OFF");
    let dir = starcages_test_support::Scratch::new("off-binary");
    let file = dir.join("cube.off");
    let mut bytes = b"OFF BINARY\n".to_vec();
    bytes.extend([0x00, 0x00, 0x00, 0x08, 0xff, 0xfe, 0x80, 0x81]);
    std::fs::write(&file, &bytes).unwrap();
    says(read_mesh(&file), "a binary OFF file ('OFF BINARY')");
    // STL: a binary file whose header starts with "solid" and whose count lies is a binary
    // file with a wrong count, not "an ASCII STL file that is not text".
    let mut stl = binary_stl();
    stl[..11].copy_from_slice(b"solid cube ");
    stl[80..84].copy_from_slice(&13u32.to_le_bytes());
    says(
        parse_stl(at, &stl),
        "a binary STL file (its header starts with 'solid' as an ASCII STL does, but the rest \
         is binary) announcing 13 triangles",
    );
    // ... and with a true count it reads, "solid" or not.
    stl[80..84].copy_from_slice(&12u32.to_le_bytes());
    assert_cube(
        "binary STL with a solid header",
        &parse_stl(at, &stl).unwrap(),
        36,
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(crate::fuzz_readers::fuzz_cases()))]

    /// Random damage (bytes replaced, removed, the file cut) never panics.
    #[test]
    fn damaged_files_never_panic(cuts in prop::collection::vec((0usize..4096, any::<u8>()), 1..6)) {
        let damage = |bytes: Vec<u8>| crate::fuzz_readers::damage(bytes, &cuts);
        let at = Path::new("fuzz");
        let _ = parse_ply(at, &damage(ascii_ply().into_bytes()));
        let _ = parse_ply(at, &damage(binary_ply(false)));
        let _ = parse_ply(at, &damage(binary_ply(true)));
        let _ = parse_stl(at, &damage(ascii_stl().into_bytes()));
        let _ = parse_stl(at, &damage(binary_stl()));
        if let Ok(text) = String::from_utf8(damage(off().into_bytes())) {
            let _ = parse_off(at, &text);
        }
    }
}
