//! A render target for the scene: colour (multisampled or not), a resolved single-sample
//! colour texture that can be sampled or copied, and depth. `Blit` draws a target's image
//! into someone else's render pass (egui's, in the editor).

use glam::Vec2;

use super::context::{GpuContext, OFFSCREEN_FORMAT};
use super::renderer::{DEPTH_FORMAT, Layers, SceneRenderer};
use super::shaders;

/// Colour, resolve and depth textures of one size.
#[derive(Debug)]
pub struct ViewTarget {
    width: u32,
    height: u32,
    samples: u32,
    color: wgpu::Texture,
    resolve: Option<wgpu::Texture>,
    depth: wgpu::Texture,
}

impl ViewTarget {
    /// Textures of `width` × `height` pixels (clamped to 1..=8192) with `samples` samples.
    pub fn new(gpu: &GpuContext, width: u32, height: u32, samples: u32) -> Self {
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
        let readable = wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::TEXTURE_BINDING;
        let (color, resolve) = if samples > 1 {
            (
                texture("colour (MSAA)", OFFSCREEN_FORMAT, samples, attach),
                Some(texture("colour", OFFSCREEN_FORMAT, 1, attach | readable)),
            )
        } else {
            (
                texture("colour", OFFSCREEN_FORMAT, 1, attach | readable),
                None,
            )
        };
        let depth = texture("depth", DEPTH_FORMAT, samples, attach);
        Self {
            width,
            height,
            samples,
            color,
            resolve,
            depth,
        }
    }

    /// Size in pixels.
    pub fn size(&self) -> Vec2 {
        Vec2::new(self.width as f32, self.height as f32)
    }

    /// Whether this target has `width` × `height` pixels and `samples` samples.
    pub fn fits(&self, width: u32, height: u32, samples: u32) -> bool {
        (self.width, self.height, self.samples)
            == (width.clamp(1, 8192), height.clamp(1, 8192), samples)
    }

    /// The single-sample image (resolved when multisampled).
    pub fn image(&self) -> &wgpu::Texture {
        self.resolve.as_ref().unwrap_or(&self.color)
    }

    /// Records a render pass drawing `renderer`'s scene into this target.
    pub fn render(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        layers: &Layers,
    ) {
        let view = |t: &wgpu::Texture| t.create_view(&wgpu::TextureViewDescriptor::default());
        let color_view = view(&self.color);
        let resolve_view = self.resolve.as_ref().map(view);
        let depth_view = view(&self.depth);
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
}

/// Draws a [`ViewTarget`]'s image over the current viewport of another render pass.
#[derive(Debug)]
pub struct Blit {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    group: Option<wgpu::BindGroup>,
}

impl Blit {
    /// A blit into colour targets of `format` (single-sampled).
    pub fn new(gpu: &GpuContext, format: wgpu::TextureFormat) -> Self {
        let device = &gpu.device;
        let layout = super::bindings::image_layout(device, "blit");
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("blit"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = shaders::module(device, "blit");
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("blit"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("blit"),
            ..Default::default()
        });
        Self {
            pipeline,
            layout,
            sampler,
            group: None,
        }
    }

    /// Points the blit at `target`'s image (after the target changed).
    pub fn set_source(&mut self, gpu: &GpuContext, target: &ViewTarget) {
        let view = target
            .image()
            .create_view(&wgpu::TextureViewDescriptor::default());
        self.group = Some(super::bindings::image_group(
            &gpu.device,
            "blit",
            &self.layout,
            &view,
            &self.sampler,
        ));
    }

    /// Draws the image into `pass` over its current viewport.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if let Some(group) = &self.group {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.draw(0..3, 0..1);
        }
    }
}
