// The deformed mesh: smooth (per-vertex normals) or flat (screen-space derivatives) shading,
// two-sided. Solid: lit by a key, a fill and a rim light for a neutral studio look. MatCap:
// the matcap image at the view-space normal. Textured: the material's base colour (factor ×
// image at the UV) under the studio light. Vertex colours (an influence map) replace the
// material's colour where `frame.shading.y` says so.

// The matcap (group 1) and the material (group 2).
@group(1) @binding(0) var matcap_image: texture_2d<f32>;
@group(1) @binding(1) var matcap_sampler: sampler;

struct Material {
    // Base colour factor (display values).
    base_color: vec4<f32>,
    // x: has an image (1) or not (0); y: UV origin at the bottom (1, OBJ/FBX) or top (0).
    flags: vec4<f32>,
};

@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_image: texture_2d<f32>;
@group(2) @binding(2) var base_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

struct TexturedIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) uv: vec2<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) uv: vec2<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.color = v.color;
    out.uv = vec2<f32>(0.0);
    return out;
}

@vertex
fn vs_textured(v: TexturedIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.color = v.color;
    out.uv = v.uv;
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

fn view_normal(in: VertexOut, view: vec3<f32>) -> vec3<f32> {
    var n = normalize(in.normal + vec3<f32>(0.0, 0.0, 1e-12));
    if (frame.viewport.z > 0.5) {
        n = normalize(cross(dpdxFine(in.world), dpdyFine(in.world)));
    }
    // Two-sided: the side facing the eye.
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    return n;
}

// Solid: the vertex colour (light grey, or an influence map) under the studio light. No
// texture is read: the plain path costs what it did before the other modes existed.
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

// MatCap: the matcap at the view-space normal; an influence map keeps its light and shade.
@fragment
fn fs_matcap(in: VertexOut) -> @location(0) vec4<f32> {
    let view = normalize(frame.eye.xyz - in.world);
    let n = view_normal(in, view);
    let in_view = vec2<f32>(dot(n, frame.camera_right.xyz), dot(n, frame.camera_up.xyz));
    let matcap = textureSampleLevel(
        matcap_image, matcap_sampler, vec2<f32>(0.5 + 0.49 * in_view.x, 0.5 - 0.49 * in_view.y), 0.0
    ).rgb;
    if (frame.shading.y > 0.5) {
        let shade = dot(matcap, vec3<f32>(0.299, 0.587, 0.114));
        return vec4<f32>(in.color.rgb * (0.35 + 0.9 * shade), frame.opacity.x);
    }
    return vec4<f32>(matcap, frame.opacity.x);
}

// Textured: the material's base colour factor × its image at the UV (OBJ and FBX count v from
// the image's bottom row) under the studio light; an influence map replaces it.
@fragment
fn fs_textured(in: VertexOut) -> @location(0) vec4<f32> {
    var uv = in.uv;
    if (material.flags.y > 0.5) {
        uv.y = 1.0 - uv.y;
    }
    // Sampled in uniform control flow, before anything depends on the fragment.
    let texel = textureSample(base_image, base_sampler, uv);
    let view = normalize(frame.eye.xyz - in.world);
    let n = view_normal(in, view);
    var base = material.base_color.rgb;
    if (material.flags.x > 0.5) {
        base = base * texel.rgb;
    }
    if (frame.shading.y > 0.5) {
        base = in.color.rgb;
    }
    return vec4<f32>(light(n, view, base), frame.opacity.x);
}
