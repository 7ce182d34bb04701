//! Offscreen rendering: a scene in a pose, seen by a camera, as an RGBA image, without a
//! window (the CLI's `render`, snapshot tests, thumbnails).

use glam::{DVec3, Vec2, Vec3};
use image::RgbaImage;
use starcages_core::scene::Scene;
use starcages_core::star::StarBinding;

use crate::camera::OrbitCamera;
use crate::gpu::{GpuContext, GpuError, Layers, OFFSCREEN_FORMAT, SceneRenderer, renderer};
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
    let rest: Vec<Vec3> = scene
        .mesh
        .welded_positions()
        .iter()
        .map(|p| p.as_vec3())
        .collect();
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
    let values = options.map.as_ref().map(|m| m.values.as_slice());
    renderer.set_colors(gpu, &vertex_colors(values, rest.len()));
    renderer.set_lines(gpu, &cage_lines(&scene.cages, pose, &options.style));
    renderer.set_dots(gpu, &cage_dots(&scene.cages, pose, &options.style));
    let target = Target::new(gpu, options.width, options.height, samples);
    renderer.set_camera(gpu, camera, target.size(), &options.layers);
    target.render(gpu, &renderer, encoder, &options.layers)
}

/// Colour (multisampled or not), resolve and depth textures of one image.
struct Target {
    width: u32,
    height: u32,
    color: wgpu::Texture,
    resolve: Option<wgpu::Texture>,
    depth: wgpu::Texture,
}

impl Target {
    fn new(gpu: &GpuContext, width: u32, height: u32, samples: u32) -> Self {
        let (width, height) = (width.clamp(1, 8192), height.clamp(1, 8192));
        let texture = |label, format, samples, usage| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let copy = wgpu::TextureUsages::COPY_SRC;
        let (color, resolve) = if samples > 1 {
            (
                texture("colour (MSAA)", OFFSCREEN_FORMAT, samples, attach),
                Some(texture("colour", OFFSCREEN_FORMAT, 1, attach | copy)),
            )
        } else {
            (texture("colour", OFFSCREEN_FORMAT, 1, attach | copy), None)
        };
        let depth = texture("depth", renderer::DEPTH_FORMAT, samples, attach);
        Self {
            width,
            height,
            color,
            resolve,
            depth,
        }
    }

    fn size(&self) -> Vec2 {
        Vec2::new(self.width as f32, self.height as f32)
    }

    fn render(
        &self,
        gpu: &GpuContext,
        renderer: &SceneRenderer,
        mut encoder: wgpu::CommandEncoder,
        layers: &Layers,
    ) -> Result<RgbaImage, GpuError> {
        let view = |t: &wgpu::Texture| t.create_view(&wgpu::TextureViewDescriptor::default());
        let color_view = view(&self.color);
        let resolve_view = self.resolve.as_ref().map(view);
        let depth_view = view(&self.depth);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    depth_slice: None,
                    resolve_target: resolve_view.as_ref(),
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            renderer.draw(&mut pass, layers);
        }
        let source = self.resolve.as_ref().unwrap_or(&self.color);
        let bytes_per_row = (self.width * 4).div_ceil(256) * 256;
        let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(bytes_per_row) * u64::from(self.height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_texture_to_buffer(
            source.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(bytes_per_row),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
        gpu.queue.submit([encoder.finish()]);
        let bytes = read_buffer(gpu, &readback)?;
        let mut image = RgbaImage::new(self.width, self.height);
        let row = (self.width * 4) as usize;
        for (y, chunk) in bytes.chunks(bytes_per_row as usize).enumerate() {
            let start = y * row;
            image.as_mut()[start..start + row].copy_from_slice(&chunk[..row]);
        }
        Ok(image)
    }
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
