// Cage vertices: round dots of constant pixel size with a dark outline, one instance each,
// expanded from six corners in clip space and pulled towards the eye.

struct DotIn {
    @location(0) position: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) size: f32,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
    @location(1) offset: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) corner: u32, dot: DotIn) -> VertexOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let c = corners[corner];
    let clip = frame.view_proj * vec4<f32>(dot.position, 1.0);
    let pixels = c * 0.5 * (dot.size + 2.0);
    let shift = pixels * 2.0 / frame.viewport.xy * clip.w;
    var out: VertexOut;
    out.clip = vec4<f32>(clip.xy + shift, clip.z - 1e-3 * clip.w, clip.w);
    out.color = dot.color;
    out.offset = c * (dot.size + 2.0) / dot.size;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let r = length(in.offset);
    if (r > 1.0 + 2.0 / 9.0) {
        discard;
    }
    if (r > 1.0) {
        return vec4<f32>(0.02, 0.02, 0.03, frame.opacity.y);
    }
    return vec4<f32>(in.color.rgb, in.color.a * frame.opacity.y);
}
