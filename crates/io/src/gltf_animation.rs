//! Baked animation as glTF 2.0 (`.glb`, or `.gltf` with its buffer embedded as a data URI):
//! the mesh at rest with its normals and UVs, one morph target per frame (position and normal
//! offsets from rest) and one animation whose weights switch from each frame's target to the
//! next's (`LINEAR`: at a frame's time exactly its target has weight 1, all others 0). That is
//! what game engines, web viewers and Blender's glTF importer (shape keys) play; a morph target
//! per key would not do, since smooth keys interpolate each coordinate on its own curve.

use std::path::{Path, PathBuf};

use base64::Engine as _;
use glam::{DVec3, Vec3};

use super::mesh_write::{GltfBuilder, glb_container, whole_if_empty};
use super::{FileError, extension, write_atomic};
use starcages_core::mesh::Mesh;

/// The most frames one glTF bake holds: its weights grow as frames², and engines load every
/// target (bake longer animations to PC2 or MDD, or in ranges with `--frames`).
pub const MAX_GLTF_FRAMES: usize = 4096;
/// The most bytes of offsets one glTF bake holds (GLB counts bytes in 32 bits).
pub const MAX_GLTF_BYTES: usize = 1 << 30;

/// A baked animation collected frame by frame, then written as glTF.
pub struct MorphAnimation {
    path: PathBuf,
    rest: Vec<DVec3>,
    rest_normals: Vec<Vec3>,
    position_offsets: Vec<Vec3>,
    normal_offsets: Vec<Vec3>,
    seconds: Vec<f32>,
    names: Vec<String>,
}

impl MorphAnimation {
    /// Starts an animation of `mesh` (its original layout) at rest at `rest`, to be written
    /// to `path` (.glb or .gltf).
    pub fn new(path: &Path, mesh: &Mesh, rest: Vec<DVec3>) -> Result<Self, FileError> {
        if !matches!(extension(path).as_str(), "glb" | "gltf") {
            return Err(FileError::Unsupported {
                path: path.to_path_buf(),
                extension: extension(path),
                supported: "glb, gltf",
            });
        }
        let rest_normals = mesh.recompute_normals(&rest);
        Ok(Self {
            path: path.to_path_buf(),
            rest,
            rest_normals,
            position_offsets: Vec::new(),
            normal_offsets: Vec::new(),
            seconds: Vec::new(),
            names: Vec::new(),
        })
    }

    /// Adds a frame: the mesh at `positions` (original layout), shown at `seconds`, its morph
    /// target called `name`.
    pub fn push_frame(
        &mut self,
        mesh: &Mesh,
        positions: &[DVec3],
        seconds: f64,
        name: String,
    ) -> Result<(), FileError> {
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(FileError::NonFinite {
                path: self.path.clone(),
                vertex,
            });
        }
        let bytes = (self.position_offsets.len() + positions.len()) * 24;
        if self.seconds.len() >= MAX_GLTF_FRAMES || bytes > MAX_GLTF_BYTES {
            return Err(FileError::format(
                &self.path,
                format!(
                    "not written: a glTF bake holds at most {MAX_GLTF_FRAMES} frames and \
                     {MAX_GLTF_BYTES} bytes of offsets (one morph target per frame); bake this \
                     one to .pc2 or .mdd, or in ranges with --frames"
                ),
            ));
        }
        let normals = mesh.recompute_normals(positions);
        self.position_offsets.extend(
            positions
                .iter()
                .zip(&self.rest)
                .map(|(p, r)| (*p - *r).as_vec3()),
        );
        self.normal_offsets
            .extend(normals.iter().zip(&self.rest_normals).map(|(n, r)| *n - *r));
        self.seconds.push(seconds as f32);
        self.names.push(name);
        Ok(())
    }

    /// Writes the file atomically.
    pub fn write(&self, mesh: &Mesh) -> Result<(), FileError> {
        let frames = self.seconds.len();
        let bad_time = self.seconds.iter().any(|t| !t.is_finite() || *t < 0.0);
        if frames == 0 || bad_time || self.seconds.windows(2).any(|w| w[1] <= w[0]) {
            return Err(FileError::format(
                &self.path,
                "not written: a glTF animation needs at least one frame, at finite, \
                 non-negative and increasing times (32-bit seconds); bake fewer frames or \
                 frames nearer 0",
            ));
        }
        let vertex_count = self.rest.len();
        let mut gltf = GltfBuilder::default();
        let mut primitives = gltf.mesh_primitives(
            &self.rest,
            mesh.triangles(),
            &self.rest_normals,
            mesh.uvs(),
            mesh.parts(),
        );
        let position_view = gltf.vec3_view(&self.position_offsets);
        let normal_view = gltf.vec3_view(&self.normal_offsets);
        let parts = whole_if_empty(mesh.parts(), vertex_count, mesh.triangles().len());
        for (primitive, part) in primitives.iter_mut().zip(&parts) {
            let targets: Vec<serde_json::Value> = (0..frames)
                .map(|f| {
                    let range = f * vertex_count + part.vertices.start as usize
                        ..f * vertex_count + part.vertices.end as usize;
                    let position = gltf.vec3_accessor(
                        position_view,
                        &self.position_offsets,
                        range.clone(),
                        true,
                    );
                    let normal =
                        gltf.vec3_accessor(normal_view, &self.normal_offsets, range, false);
                    serde_json::json!({"POSITION": position, "NORMAL": normal})
                })
                .collect();
            primitive["targets"] = serde_json::json!(targets);
        }
        // Times, and per time a weight per target: 1 for its own frame's.
        let time_bytes: Vec<u8> = self.seconds.iter().flat_map(|t| t.to_le_bytes()).collect();
        let time_view = gltf.view(&time_bytes, None, None);
        let time_accessor = gltf.accessor(serde_json::json!({"bufferView": time_view,
            "componentType": 5126, "count": frames, "type": "SCALAR",
            "min": [self.seconds[0]], "max": [self.seconds[frames - 1]]}));
        let mut weight_bytes = Vec::with_capacity(frames * frames * 4);
        for f in 0..frames {
            for target in 0..frames {
                let w: f32 = if target == f { 1.0 } else { 0.0 };
                weight_bytes.extend_from_slice(&w.to_le_bytes());
            }
        }
        let weight_view = gltf.view(&weight_bytes, None, None);
        let weight_accessor = gltf.accessor(serde_json::json!({"bufferView": weight_view,
            "componentType": 5126, "count": frames * frames, "type": "SCALAR"}));
        let mesh_json = serde_json::json!({
            "name": "deformed",
            "primitives": primitives,
            "weights": vec![0.0; frames],
            "extras": {"targetNames": self.names},
        });
        let animations = serde_json::json!([{
            "name": "StarCages bake",
            "samplers": [{"input": time_accessor, "output": weight_accessor,
                          "interpolation": "LINEAR"}],
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}],
        }]);
        let mut document = gltf.document(mesh_json, Some(animations));
        let bytes = if extension(&self.path) == "glb" {
            glb_container(&document, &gltf.bin)
        } else {
            let data = base64::engine::general_purpose::STANDARD.encode(&gltf.bin);
            document["buffers"][0]["uri"] =
                serde_json::json!(format!("data:application/octet-stream;base64,{data}"));
            document.to_string().into_bytes()
        };
        write_atomic(&self.path, &bytes)
    }
}
