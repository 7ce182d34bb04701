// Cage edges and the mesh wireframe: coloured line segments, pulled slightly towards the eye so
// they win depth ties with the surface they lie on.

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) color: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    let clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.clip = vec4<f32>(clip.xy, clip.z - 2e-4 * clip.w, clip.w);
    out.color = v.color;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return in.color;
}

// Cage edges: their colour at the cages' opacity.
@fragment
fn fs_cage(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.color.rgb, in.color.a * frame.opacity.y);
}

// The mesh wireframe: positions straight from the mesh's vertex buffer, one dark colour.
@vertex
fn vs_wire(@location(0) position: vec3<f32>) -> VertexOut {
    var out: VertexOut;
    let clip = frame.view_proj * vec4<f32>(position, 1.0);
    out.clip = vec4<f32>(clip.xy, clip.z - 2e-4 * clip.w, clip.w);
    out.color = vec4<f32>(0.06, 0.06, 0.07, 0.55);
    return out;
}
