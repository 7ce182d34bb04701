//! Writing meshes: OBJ (text) and GLB (binary glTF 2.0), with normals, saved atomically.

use std::fmt::Write as _;
use std::path::Path;

use glam::{DVec3, Vec2, Vec3};

use super::{FileError, extension, write_atomic};
use starcages_core::mesh::{Mesh, MeshPart};

/// Writes `mesh` with vertex `positions` (original layout) to an OBJ or GLB file, with normals
/// recomputed from those positions, atomically.
pub fn write_mesh(path: &Path, mesh: &Mesh, positions: &[DVec3]) -> Result<(), FileError> {
    if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
        return Err(FileError::NonFinite {
            path: path.to_path_buf(),
            vertex,
        });
    }
    let normals = mesh.recompute_normals(positions);
    let bytes = match extension(path).as_str() {
        "obj" => obj_text(positions, mesh.triangles(), Some(&normals), mesh.uvs()).into_bytes(),
        "glb" => glb_bytes_in_parts(
            positions,
            mesh.triangles(),
            &normals,
            mesh.uvs(),
            mesh.parts(),
        ),
        other => {
            return Err(FileError::Unsupported {
                path: path.to_path_buf(),
                extension: other.to_owned(),
                supported: "obj, glb",
            });
        }
    };
    write_atomic(path, &bytes)
}

/// OBJ text of a triangle mesh (1-based indices; `v/vt/vn` when present).
pub fn obj_text(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    normals: Option<&[Vec3]>,
    uvs: Option<&[Vec2]>,
) -> String {
    let mut s = String::with_capacity(positions.len() * 40 + triangles.len() * 30);
    s.push_str("# written by StarCages\n");
    for p in positions {
        writeln!(s, "v {} {} {}", p.x, p.y, p.z).ok();
    }
    for t in uvs.unwrap_or(&[]) {
        writeln!(s, "vt {} {}", t.x, t.y).ok();
    }
    for n in normals.unwrap_or(&[]) {
        writeln!(s, "vn {} {} {}", n.x, n.y, n.z).ok();
    }
    for tri in triangles {
        s.push('f');
        for &v in tri {
            let i = v + 1;
            match (uvs.is_some(), normals.is_some()) {
                (true, true) => write!(s, " {i}/{i}/{i}"),
                (true, false) => write!(s, " {i}/{i}"),
                (false, true) => write!(s, " {i}//{i}"),
                (false, false) => write!(s, " {i}"),
            }
            .ok();
        }
        s.push('\n');
    }
    s
}

/// A binary glTF 2.0 file of one triangle mesh: f32 positions and normals, optional UVs,
/// u32 indices.
pub fn glb_bytes(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    normals: &[Vec3],
    uvs: Option<&[Vec2]>,
) -> Vec<u8> {
    glb_bytes_in_parts(positions, triangles, normals, uvs, &[])
}

/// A binary glTF 2.0 file of a triangle mesh with one primitive per part (each with its own
/// vertices, in order, and local indices: a glTF source's primitives come back as they were),
/// or one primitive when `parts` is empty.
pub fn glb_bytes_in_parts(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    normals: &[Vec3],
    uvs: Option<&[Vec2]>,
    parts: &[MeshPart],
) -> Vec<u8> {
    let mut gltf = GltfBuilder::default();
    let primitives = gltf.mesh_primitives(positions, triangles, normals, uvs, parts);
    let document = gltf.document(serde_json::json!({"primitives": primitives}), None);
    glb_container(&document, &gltf.bin)
}

/// The binary buffer, buffer views and accessors of a glTF document being built.
#[derive(Default)]
pub(crate) struct GltfBuilder {
    /// The one buffer's bytes.
    pub bin: Vec<u8>,
    views: Vec<serde_json::Value>,
    accessors: Vec<serde_json::Value>,
}

/// glTF's `ARRAY_BUFFER` target (vertex attributes).
const ARRAY_BUFFER: u32 = 34962;
/// glTF's `ELEMENT_ARRAY_BUFFER` target (indices).
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

impl GltfBuilder {
    /// Appends `data` (4-byte aligned) as a buffer view; returns its index.
    pub fn view(&mut self, data: &[u8], target: Option<u32>, stride: Option<usize>) -> usize {
        let offset = self.bin.len();
        self.bin.extend_from_slice(data);
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view =
            serde_json::json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len()});
        if let Some(target) = target {
            view["target"] = serde_json::json!(target);
        }
        if let Some(stride) = stride {
            view["byteStride"] = serde_json::json!(stride);
        }
        self.views.push(view);
        self.views.len() - 1
    }

    /// A vertex attribute view of 3-vectors (stride 12, so parts can slice it).
    pub fn vec3_view(&mut self, values: &[Vec3]) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flat_map(|v| v.to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        self.view(&bytes, Some(ARRAY_BUFFER), Some(12))
    }

    /// Adds an accessor; returns its index.
    pub fn accessor(&mut self, accessor: serde_json::Value) -> usize {
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// A VEC3 float accessor of `values[range]` in `view`, with the bounds glTF requires for
    /// positions (and position morph targets).
    pub fn vec3_accessor(
        &mut self,
        view: usize,
        values: &[Vec3],
        range: std::ops::Range<usize>,
        bounds: bool,
    ) -> usize {
        let mut accessor = serde_json::json!({"bufferView": view, "byteOffset": range.start * 12,
            "componentType": 5126, "count": range.len(), "type": "VEC3"});
        if bounds {
            let (lo, hi) = values[range].iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            accessor["min"] = serde_json::json!(lo.to_array());
            accessor["max"] = serde_json::json!(hi.to_array());
        }
        self.accessor(accessor)
    }

    /// The primitives of a triangle mesh: one per part (one for all when `parts` is empty).
    pub fn mesh_primitives(
        &mut self,
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        normals: &[Vec3],
        uvs: Option<&[Vec2]>,
        parts: &[MeshPart],
    ) -> Vec<serde_json::Value> {
        let parts = whole_if_empty(parts, positions.len(), triangles.len());
        let pos32: Vec<Vec3> = positions.iter().map(|p| p.as_vec3()).collect();
        // Attribute views are shared (a stride makes them slicable); each part's accessors
        // start at its first vertex.
        let position_view = self.vec3_view(&pos32);
        let normal_view = self.vec3_view(normals);
        let uv_view = uvs.map(|uvs| {
            let bytes: Vec<u8> = uvs
                .iter()
                .flat_map(|t| t.to_array())
                .flat_map(f32::to_le_bytes)
                .collect();
            self.view(&bytes, Some(ARRAY_BUFFER), Some(8))
        });
        let index_bytes: Vec<u8> = parts
            .iter()
            .flat_map(|part| {
                triangles[part.triangles.start as usize..part.triangles.end as usize]
                    .iter()
                    .flatten()
                    .map(move |i| i - part.vertices.start)
            })
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let index_view = self.view(&index_bytes, Some(ELEMENT_ARRAY_BUFFER), None);
        let mut primitives = Vec::new();
        for part in &parts {
            let vertices = part.vertices.start as usize..part.vertices.end as usize;
            let position = self.vec3_accessor(position_view, &pos32, vertices.clone(), true);
            let normal = self.vec3_accessor(normal_view, normals, vertices.clone(), false);
            let first_index = 12 * part.triangles.start as usize;
            let index_count = 3 * (part.triangles.end - part.triangles.start) as usize;
            let indices = self.accessor(
                serde_json::json!({"bufferView": index_view, "byteOffset": first_index,
                "componentType": 5125, "count": index_count, "type": "SCALAR"}),
            );
            let mut attributes = serde_json::json!({"POSITION": position, "NORMAL": normal});
            if let Some(view) = uv_view {
                let uv = self.accessor(serde_json::json!({"bufferView": view,
                    "byteOffset": vertices.start * 8, "componentType": 5126,
                    "count": vertices.len(), "type": "VEC2"}));
                attributes["TEXCOORD_0"] = serde_json::json!(uv);
            }
            primitives
                .push(serde_json::json!({"attributes": attributes, "indices": indices, "mode": 4}));
        }
        primitives
    }

    /// The whole document: one node holding `mesh`, and `animations` when given.
    pub fn document(
        &self,
        mesh: serde_json::Value,
        animations: Option<serde_json::Value>,
    ) -> serde_json::Value {
        let mut document = serde_json::json!({
            "asset": {"version": "2.0", "generator": "StarCages"},
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "name": "deformed"}],
            "meshes": [mesh],
            "buffers": [{"byteLength": self.bin.len()}],
            "bufferViews": self.views,
            "accessors": self.accessors,
        });
        if let Some(animations) = animations {
            document["animations"] = animations;
        }
        document
    }
}

/// `parts`, or one part holding every vertex and triangle when it is empty.
pub(crate) fn whole_if_empty(
    parts: &[MeshPart],
    vertices: usize,
    triangles: usize,
) -> Vec<MeshPart> {
    if parts.is_empty() {
        vec![MeshPart {
            vertices: 0..vertices as u32,
            triangles: 0..triangles as u32,
        }]
    } else {
        parts.to_vec()
    }
}

/// A GLB container: the 12-byte header, the JSON chunk (space-padded) and the BIN chunk.
pub(crate) fn glb_container(document: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut json = document.to_string().into_bytes();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::read_mesh;

    fn quad() -> Mesh {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        Mesh::new(
            p,
            vec![[0, 1, 2], [0, 2, 3]],
            None,
            Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]),
        )
        .unwrap()
    }

    #[test]
    fn obj_and_glb_round_trip_through_our_readers() {
        let scratch = tempfile::tempdir().unwrap();
        let dir = scratch.path();
        let mesh = quad();
        let moved: Vec<DVec3> = mesh
            .positions()
            .iter()
            .map(|p| *p * 2.0 + DVec3::Z)
            .collect();
        for name in ["out.obj", "out.glb"] {
            let path = dir.join(name);
            write_mesh(&path, &mesh, &moved).unwrap();
            let back = read_mesh(&path).unwrap();
            assert_eq!(back.triangles(), mesh.triangles(), "{name}");
            for (a, b) in back.positions().iter().zip(&moved) {
                assert!((*a - *b).length() < 1e-6, "{name}: {a} vs {b}");
            }
            let normals = back.normals().expect("normals written");
            assert!(
                normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6),
                "{name}"
            );
            assert_eq!(back.uvs().map(<[Vec2]>::len), Some(4), "{name}");
        }
        let error = write_mesh(&dir.join("out.stl"), &mesh, mesh.positions()).unwrap_err();
        assert!(
            error.to_string().contains("unsupported file type '.stl'"),
            "{error}"
        );
    }
}
