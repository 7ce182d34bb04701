// The drawn layout of a textured mesh: each of its file's vertices (split at UV seams) takes
// the position and normal of the welded vertex it belongs to, after each deformation.

struct Params {
    count: u32,
    // Invocations per row of the dispatch grid (x × 64), for grids taller than one row.
    stride: u32,
    _pad0: u32,
    _pad1: u32,
};

@group(0) @binding(0) var<uniform> params: Params;
// Per drawn vertex, its welded vertex.
@group(0) @binding(1) var<storage, read> welded_of: array<u32>;
@group(0) @binding(2) var<storage, read> welded_positions: array<f32>;
@group(0) @binding(3) var<storage, read> welded_normals: array<f32>;
@group(0) @binding(4) var<storage, read_write> positions: array<f32>;
@group(0) @binding(5) var<storage, read_write> normals: array<f32>;

@compute @workgroup_size(64)
fn gather(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = id.x + id.y * params.stride;
    if (v >= params.count) {
        return;
    }
    let w = welded_of[v];
    for (var k = 0u; k < 3u; k = k + 1u) {
        positions[3u * v + k] = welded_positions[3u * w + k];
        normals[3u * v + k] = welded_normals[3u * w + k];
    }
}
