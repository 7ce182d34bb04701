//! The WGSL sources in `shaders/`, with the shared uniform block prepended.

const COMMON: &str = include_str!("../../../../shaders/common.wgsl");

/// The shader modules: name and source as written in `shaders/`.
pub const SOURCES: [(&str, &str); 8] = [
    ("gather", include_str!("../../../../shaders/gather.wgsl")),
    ("ghost", include_str!("../../../../shaders/ghost.wgsl")),
    ("mesh", include_str!("../../../../shaders/mesh.wgsl")),
    ("lines", include_str!("../../../../shaders/lines.wgsl")),
    ("dots", include_str!("../../../../shaders/dots.wgsl")),
    (
        "background",
        include_str!("../../../../shaders/background.wgsl"),
    ),
    ("deform", include_str!("../../../../shaders/deform.wgsl")),
    ("blit", include_str!("../../../../shaders/blit.wgsl")),
];

/// The full source of shader `name`: scene draw shaders get the per-frame uniform block first.
pub fn source(name: &str) -> String {
    let body = SOURCES
        .iter()
        .find(|(n, _)| *n == name)
        .map_or("", |(_, s)| s);
    if matches!(name, "deform" | "blit" | "gather") {
        body.to_owned()
    } else {
        format!("{COMMON}\n{body}")
    }
}

/// Compiles shader `name` on `device`.
pub fn module(device: &wgpu::Device, name: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(name),
        source: wgpu::ShaderSource::Wgsl(source(name).into()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every shader parses and validates with naga, without a GPU.
    #[test]
    fn every_shader_validates() {
        for (name, _) in SOURCES {
            let module = naga::front::wgsl::parse_str(&source(name))
                .unwrap_or_else(|e| panic!("{name}.wgsl: {}", e.emit_to_string(&source(name))));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::empty(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}.wgsl: {e:?}"));
        }
    }
}
