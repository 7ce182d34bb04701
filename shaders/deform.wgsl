// GPU deformation: the compiled *Cages operator (CSR, f32) times the frame's degrees of freedom
// (posed cage vertices, then Green face terms), written straight into the vertex buffer; then
// area-weighted vertex normals from the incident triangles.

struct Params {
    rows: u32,
    // Invocations per row of the dispatch grid (x × 64), for grids taller than one row.
    stride: u32,
    _pad0: u32,
    _pad1: u32,
};

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> row_start: array<u32>;
@group(0) @binding(2) var<storage, read> columns: array<u32>;
@group(0) @binding(3) var<storage, read> values: array<f32>;
// Three floats per degree of freedom.
@group(0) @binding(4) var<storage, read> dofs: array<f32>;
// Three floats per mesh vertex: the position vertex buffer.
@group(0) @binding(5) var<storage, read_write> positions: array<f32>;
// Incident triangles per vertex (CSR) and the triangles' corners.
@group(0) @binding(6) var<storage, read> vertex_triangle_start: array<u32>;
@group(0) @binding(7) var<storage, read> vertex_triangles: array<u32>;
@group(0) @binding(8) var<storage, read> triangles: array<u32>;
// Three floats per mesh vertex: the normal vertex buffer.
@group(0) @binding(9) var<storage, read_write> normals: array<f32>;
// Three floats per mesh vertex: p − S(rest), the row's rest offset (displacement form).
@group(0) @binding(10) var<storage, read> rest_offsets: array<f32>;

fn position(v: u32) -> vec3<f32> {
    return vec3<f32>(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u]);
}

// S(p) = Σ_j w_j x_j   (eq. 3 as one sparse row), plus p − S(rest) (docs/math.md)
@compute @workgroup_size(64)
fn deform(@builtin(global_invocation_id) id: vec3<u32>) {
    let row = id.x + id.y * params.stride;
    if (row >= params.rows) {
        return;
    }
    var sum = vec3<f32>(rest_offsets[3u * row], rest_offsets[3u * row + 1u], rest_offsets[3u * row + 2u]);
    for (var k = row_start[row]; k < row_start[row + 1u]; k = k + 1u) {
        let c = columns[k];
        sum = sum + values[k] * vec3<f32>(dofs[3u * c], dofs[3u * c + 1u], dofs[3u * c + 2u]);
    }
    positions[3u * row] = sum.x;
    positions[3u * row + 1u] = sum.y;
    positions[3u * row + 2u] = sum.z;
}

@compute @workgroup_size(64)
fn vertex_normals(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = id.x + id.y * params.stride;
    if (v >= params.rows) {
        return;
    }
    var n = vec3<f32>(0.0);
    for (var k = vertex_triangle_start[v]; k < vertex_triangle_start[v + 1u]; k = k + 1u) {
        let t = vertex_triangles[k];
        let a = position(triangles[3u * t]);
        let b = position(triangles[3u * t + 1u]);
        let c = position(triangles[3u * t + 2u]);
        n = n + cross(b - a, c - a);
    }
    let len = length(n);
    if (len > 0.0) {
        n = n / len;
    } else {
        n = vec3<f32>(0.0, 0.0, 1.0);
    }
    normals[3u * v] = n.x;
    normals[3u * v + 1u] = n.y;
    normals[3u * v + 2u] = n.z;
}
