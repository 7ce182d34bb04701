// The deformed mesh: smooth (per-vertex normals) or flat (screen-space derivatives) shading,
// two-sided, lit by a key, a fill and a rim light for a neutral studio look.

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.color = v.color;
    return out;
}

fn light(n: vec3<f32>, view: vec3<f32>, base: vec3<f32>) -> vec3<f32> {
    // Lights fixed to the camera so the model reads the same from every side.
    let right = normalize(cross(vec3<f32>(0.0, 0.0, 1.0), view) + vec3<f32>(1e-6, 0.0, 0.0));
    let up = cross(view, right);
    let key = normalize(view + 0.6 * right + 0.8 * up);
    let fill = normalize(view - 0.8 * right - 0.2 * up);
    let diffuse = 0.75 * max(dot(n, key), 0.0) + 0.3 * max(dot(n, fill), 0.0);
    let rim = 0.25 * pow(1.0 - max(dot(n, view), 0.0), 3.0);
    let half_key = normalize(key + view);
    let specular = 0.18 * pow(max(dot(n, half_key), 0.0), 40.0);
    return base * (0.22 + diffuse) + vec3<f32>(rim + specular);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let view = normalize(frame.eye.xyz - in.world);
    let faceted = cross(dpdxFine(in.world), dpdyFine(in.world));
    var n = normalize(in.normal + vec3<f32>(0.0, 0.0, 1e-12));
    if (frame.viewport.z > 0.5) {
        n = normalize(faceted);
    }
    // Two-sided: light the side facing the eye.
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    return vec4<f32>(light(n, view, in.color.rgb), frame.opacity.x);
}
