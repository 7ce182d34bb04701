// Per-frame uniforms shared by every StarCages draw pipeline (prepended to each shader).
struct Frame {
    view_proj: mat4x4<f32>,
    // xyz: eye position.
    eye: vec4<f32>,
    // x, y: viewport size in pixels; z: flat shading (1) or smooth (0); w: unused.
    viewport: vec4<f32>,
    // Background gradient, top and bottom.
    background_top: vec4<f32>,
    background_bottom: vec4<f32>,
    // x: the mesh's opacity (below 1 in X-ray); y: the cages' opacity; z, w: unused.
    opacity: vec4<f32>,
    // The camera's right and up directions (xyz), for matcap lookups.
    camera_right: vec4<f32>,
    camera_up: vec4<f32>,
    // x: unused (the shading mode picks the mesh's fragment entry point); y: vertex colours
    // (an influence map) replace the material's colour (1) or not (0); z, w: unused.
    shading: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
