//! Offscreen rendering: a scene in a pose, seen by a camera, as an RGBA image, without a
//! window (the CLI's `render`, snapshot tests, thumbnails).

use glam::{DVec3, Vec3};
use image::RgbaImage;
use starcages_core::mesh::look::LoadedLook;
use starcages_core::scene::Scene;
use starcages_core::star::StarBinding;

use crate::camera::OrbitCamera;
use crate::gpu::{GpuContext, GpuError, Layers, OFFSCREEN_FORMAT, SceneRenderer, ViewTarget};
use crate::influence::{MapValues, vertex_colors};
use crate::layers::{CageStyle, cage_dots, cage_lines};

/// What to draw and at which size.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Layers and shading.
    pub layers: Layers,
    /// Cage visibility, selection, hover and level focus.
    pub style: CageStyle,
    /// An influence map painted on the mesh.
    pub map: Option<MapValues>,
    /// 4× multisampling where the adapter supports it (off for pixel-exact tests).
    pub msaa: bool,
    /// The mesh file's look, for Textured shading.
    pub look: Option<std::sync::Arc<LoadedLook>>,
    /// Ghosts: other poses of the cages, each with its tint and opacity.
    pub ghosts: Vec<(Vec<DVec3>, [f32; 4])>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            layers: Layers::default(),
            style: CageStyle::default(),
            map: None,
            msaa: true,
            look: None,
            ghosts: Vec::new(),
        }
    }
}

/// A camera framing the scene's cages in `pose` from the default direction.
pub fn framing_camera(scene: &Scene, pose: &[DVec3]) -> OrbitCamera {
    let (lo, hi) = starcages_core::cage::bounds_of(pose);
    let (mlo, mhi) = scene.mesh.bounds();
    let mut camera = OrbitCamera::default();
    camera.frame(lo.min(mlo).as_vec3(), hi.max(mhi).as_vec3());
    camera
}

/// Renders `scene` (bound as `binding`) in `pose` through `camera`.
pub fn render_to_image(
    gpu: &GpuContext,
    scene: &Scene,
    binding: &StarBinding,
    pose: &[DVec3],
    camera: &OrbitCamera,
    options: &RenderOptions,
) -> Result<RgbaImage, GpuError> {
    let samples = if options.msaa && gpu.msaa4 { 4 } else { 1 };
    let mut renderer = SceneRenderer::new(gpu, OFFSCREEN_FORMAT, samples);
    let rest: Vec<Vec3> = scene.mesh.welded_positions_f32();
    let triangles = scene.mesh.welded_triangles();
    renderer.set_mesh(gpu, &rest, triangles, Some(&binding.operator));
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("offscreen"),
        });
    let dofs = binding.operator.dofs(&scene.cages.vertices, pose);
    if !renderer.deform_on_gpu(gpu, &mut encoder, &dofs) {
        renderer.set_positions(gpu, &binding.deform(&scene.cages.vertices, pose));
    }
    if let Some(look) = &options.look {
        // A look that does not fit draws the mesh without it, as the editor does.
        let _ = renderer.set_loaded_look(gpu, &scene.mesh, look, &rest);
    }
    if let crate::gpu::Shading::MatCap(matcap) = options.layers.shading {
        renderer.set_matcap(gpu, matcap);
    }
    let ghost_shapes: Vec<Vec<Vec3>> = options
        .ghosts
        .iter()
        .map(|(ghost_pose, _)| {
            if renderer.deforms_on_gpu() {
                binding.operator.dofs(&scene.cages.vertices, ghost_pose)
            } else {
                binding.deform(&scene.cages.vertices, ghost_pose)
            }
        })
        .collect();
    let ghosts: Vec<crate::gpu::Ghost<'_>> = ghost_shapes
        .iter()
        .zip(&options.ghosts)
        .map(|(shape, (_, tint))| crate::gpu::Ghost {
            shape: if renderer.deforms_on_gpu() {
                crate::gpu::GhostShape::Dofs(shape)
            } else {
                crate::gpu::GhostShape::Positions(shape)
            },
            tint: *tint,
        })
        .collect();
    renderer.set_ghosts(gpu, &mut encoder, &ghosts);
    let values = options.map.as_ref().map(|m| m.values.as_slice());
    renderer.set_colors(gpu, &vertex_colors(values, rest.len()));
    renderer.set_lines(gpu, &cage_lines(&scene.cages, pose, &options.style));
    renderer.set_dots(gpu, &cage_dots(&scene.cages, pose, &options.style));
    let target = ViewTarget::new(gpu, options.width, options.height, samples);
    renderer.set_camera(gpu, camera, target.size(), &options.layers);
    render_and_read(gpu, &renderer, &target, encoder, &options.layers)
}

/// Renders into `target` and reads the image back.
fn render_and_read(
    gpu: &GpuContext,
    renderer: &SceneRenderer,
    target: &ViewTarget,
    mut encoder: wgpu::CommandEncoder,
    layers: &Layers,
) -> Result<RgbaImage, GpuError> {
    target.render(&mut encoder, renderer, layers);
    let size = target.size();
    let (width, height) = (size.x as u32, size.y as u32);
    let bytes_per_row = (width * 4).div_ceil(256) * 256;
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(bytes_per_row) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        target.image().as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(bytes_per_row),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    gpu.queue.submit([encoder.finish()]);
    let bytes = read_buffer(gpu, &readback)?;
    let mut image = RgbaImage::new(width, height);
    let row = (width * 4) as usize;
    for (y, chunk) in bytes.chunks(bytes_per_row as usize).enumerate() {
        let start = y * row;
        image.as_mut()[start..start + row].copy_from_slice(&chunk[..row]);
    }
    Ok(image)
}

/// Maps `buffer` (MAP_READ) and copies its bytes out.
pub fn read_buffer(gpu: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        sender.send(result).ok();
    });
    gpu.wait()?;
    receiver
        .recv()
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let bytes = buffer
        .get_mapped_range(..)
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// Copies a GPU buffer (COPY_SRC) back to the CPU.
pub fn download(gpu: &GpuContext, source: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("download"),
        size: source.size(),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("download"),
        });
    encoder.copy_buffer_to_buffer(source, 0, &staging, 0, source.size());
    gpu.queue.submit([encoder.finish()]);
    read_buffer(gpu, &staging)
}

/// The image as PNG bytes.
pub fn encode_png(image: &RgbaImage) -> Vec<u8> {
    let mut bytes = Vec::new();
    // Encoding into memory only fails on an invalid image size, which RgbaImage rules out.
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .ok();
    bytes
}
