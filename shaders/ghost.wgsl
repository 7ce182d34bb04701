// A ghost of the animation: the mesh deformed at another frame, drawn translucent in one
// tint (frames before and after the current one get their own), lit softly so its form reads.

struct Ghost {
    // rgb: tint; a: opacity.
    tint: vec4<f32>,
    // x: how far the ghost is pushed away from the eye (world units, ~1 % of the mesh's
    // diagonal): parts that nearly coincide with the current pose stay under it instead of
    // flickering through.
    push: vec4<f32>,
};

@group(1) @binding(0) var<uniform> ghost: Ghost;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    let away = normalize(v.position - frame.eye.xyz + vec3<f32>(1e-12, 0.0, 0.0));
    out.clip = frame.view_proj * vec4<f32>(v.position + ghost.push.x * away, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let view = normalize(frame.eye.xyz - in.world);
    var n = normalize(in.normal + vec3<f32>(0.0, 0.0, 1e-12));
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    // Facing the eye: the tint, lit; toward the silhouette: more opaque, so outlines read.
    let facing = max(dot(n, view), 0.0);
    let colour = ghost.tint.rgb * (0.6 + 0.4 * facing);
    return vec4<f32>(colour, ghost.tint.a * (0.6 + 0.4 * (1.0 - facing)));
}
