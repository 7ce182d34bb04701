//! A textured mesh on the GPU: the file's own vertex layout (split at UV seams) with its UVs,
//! its triangles grouped by material, one bind group per material (base colour factor and
//! image with its mip chain), and the gather that copies each deformation from the welded
//! vertices into that layout (a compute pass, or on the CPU where compute is missing).

use std::ops::Range;

use glam::{Vec2, Vec3};
use starcages_core::mesh::look::{Rgba8Image, UvOrigin};
use wgpu::util::DeviceExt as _;

use super::context::GpuContext;
use super::shaders;

const WORKGROUP: u32 = 64;

/// One material to draw: its base colour factor (display values) and image.
#[derive(Debug, Clone, Copy)]
pub struct LookMaterial<'a> {
    /// Base colour factor, RGBA.
    pub base_color: [f32; 4],
    /// The decoded base colour image, if any (a missing or broken one is drawn without).
    pub image: Option<&'a Rgba8Image>,
}

/// A mesh's look to upload, over the mesh's original layout.
#[derive(Debug, Clone, Copy)]
pub struct RenderLook<'a> {
    /// Per original vertex, its welded vertex ([`starcages_core::mesh::Mesh::weld_map`]).
    pub welded_of: &'a [u32],
    /// The original triangles.
    pub triangles: &'a [[u32; 3]],
    /// Per original vertex, its UV (absent: every vertex at (0, 0)).
    pub uvs: Option<&'a [Vec2]>,
    /// Per triangle, its material.
    pub triangle_materials: &'a [u32],
    /// The materials.
    pub materials: &'a [LookMaterial<'a>],
    /// Where the UVs' origin is.
    pub uv_origin: UvOrigin,
}

/// Why a look cannot be drawn over a mesh.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LookError {
    /// Its arrays do not match each other or the mesh.
    #[error("the look does not match the mesh ({0}); it is drawn without its materials")]
    Mismatch(&'static str),
}

/// The layouts of the material bind group and the sampler every material uses.
#[derive(Debug)]
pub(super) struct MaterialLayout {
    pub layout: wgpu::BindGroupLayout,
    pub sampler: wgpu::Sampler,
}

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct MaterialUniforms {
    base_color: [f32; 4],
    flags: [f32; 4],
}

impl MaterialLayout {
    pub(super) fn new(device: &wgpu::Device) -> Self {
        let texture = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("material"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                texture(1),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("material"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        Self { layout, sampler }
    }

    /// A material's bind group: its factor, and its image (a white pixel when it has none).
    pub(super) fn group(
        &self,
        gpu: &GpuContext,
        material: &LookMaterial<'_>,
        uv_origin: UvOrigin,
    ) -> wgpu::BindGroup {
        let device = &gpu.device;
        let white = Rgba8Image {
            width: 1,
            height: 1,
            pixels: vec![255; 4],
        };
        let image = material.image.unwrap_or(&white);
        let max_side = device.limits().max_texture_dimension_2d;
        let view = upload_image(gpu, "base colour", image, max_side)
            .create_view(&wgpu::TextureViewDescriptor::default());
        let uniforms = MaterialUniforms {
            base_color: material.base_color,
            flags: [
                if material.image.is_some() { 1.0 } else { 0.0 },
                if uv_origin == UvOrigin::BottomLeft {
                    1.0
                } else {
                    0.0
                },
                0.0,
                0.0,
            ],
        };
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("material"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("material"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
            ],
        })
    }
}

/// Halves an image by 2×2 box filtering (an odd side keeps its last row or column out).
fn half(image: &Rgba8Image) -> Rgba8Image {
    let (w, h) = ((image.width / 2).max(1), (image.height / 2).max(1));
    let at = |x: u32, y: u32, c: u32| {
        let x = x.min(image.width - 1);
        let y = y.min(image.height - 1);
        u32::from(image.pixels[((y * image.width + x) * 4 + c) as usize])
    };
    let mut pixels = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            for c in 0..4 {
                let sum = at(2 * x, 2 * y, c)
                    + at(2 * x + 1, 2 * y, c)
                    + at(2 * x, 2 * y + 1, c)
                    + at(2 * x + 1, 2 * y + 1, c);
                pixels.push(((sum + 2) / 4) as u8);
            }
        }
    }
    Rgba8Image {
        width: w,
        height: h,
        pixels,
    }
}

/// The image and its mip chain down to one pixel, without the levels past `max_side` (a
/// texture larger than the device takes is drawn at the largest level it takes).
pub fn mip_chain(image: &Rgba8Image, max_side: u32) -> Vec<Rgba8Image> {
    let mut levels = Vec::new();
    let valid = image.width > 0
        && image.height > 0
        && image.pixels.len() == (image.width as usize) * (image.height as usize) * 4;
    let mut level = if valid {
        image.clone()
    } else {
        Rgba8Image {
            width: 1,
            height: 1,
            pixels: vec![255; 4],
        }
    };
    loop {
        let last = level.width == 1 && level.height == 1;
        let next = (!last).then(|| half(&level));
        if level.width <= max_side && level.height <= max_side {
            levels.push(level);
        }
        match next {
            Some(n) => level = n,
            None => break,
        }
    }
    levels
}

/// Uploads `image` with its mip chain as an RGBA8 texture (display values, sampled as they
/// are: the renderer lights in display values).
pub(super) fn upload_image(
    gpu: &GpuContext,
    label: &str,
    image: &Rgba8Image,
    max_side: u32,
) -> wgpu::Texture {
    let levels = mip_chain(image, max_side.max(1));
    let (width, height) = levels.first().map_or((1, 1), |l| (l.width, l.height));
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels.len().max(1) as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (mip, level) in levels.iter().enumerate() {
        gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: mip as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &level.pixels,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(level.width * 4),
                rows_per_image: Some(level.height),
            },
            wgpu::Extent3d {
                width: level.width,
                height: level.height,
                depth_or_array_layers: 1,
            },
        );
    }
    texture
}

/// The gather pass from the welded buffers into the drawn layout.
#[derive(Debug)]
struct Gather {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    groups: (u32, u32),
}

/// The textured mesh's buffers.
#[derive(Debug)]
pub(super) struct LookBuffers {
    pub positions: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    pub colors: wgpu::Buffer,
    pub uvs: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    /// Index ranges and the material bind group each is drawn with.
    pub draws: Vec<(Range<u32>, usize)>,
    pub materials: Vec<wgpu::BindGroup>,
    welded_of: Vec<u32>,
    gather: Option<Gather>,
}

impl LookBuffers {
    /// Checks `look` against a mesh of `welded_count` welded vertices and uploads it; the
    /// welded buffers are those the deformation writes (gathered from on the GPU when compute
    /// is available).
    pub(super) fn new(
        gpu: &GpuContext,
        materials: &MaterialLayout,
        look: &RenderLook<'_>,
        welded_count: usize,
        welded: (&wgpu::Buffer, &wgpu::Buffer),
    ) -> Result<Self, LookError> {
        let vertices = look.welded_of.len();
        if look.welded_of.iter().any(|&w| w as usize >= welded_count) {
            return Err(LookError::Mismatch("a vertex outside the welded mesh"));
        }
        if look.uvs.is_some_and(|uvs| uvs.len() != vertices) {
            return Err(LookError::Mismatch("UVs"));
        }
        if look.triangle_materials.len() != look.triangles.len() {
            return Err(LookError::Mismatch("triangle materials"));
        }
        if look
            .triangles
            .iter()
            .flatten()
            .any(|&v| v as usize >= vertices)
        {
            return Err(LookError::Mismatch("a triangle outside the vertices"));
        }
        if look.materials.is_empty() {
            return Err(LookError::Mismatch("no material"));
        }
        let device = &gpu.device;
        // Triangles grouped by material (stable: each group keeps the file's order).
        let mut order: Vec<u32> = (0..look.triangles.len() as u32).collect();
        let material_of = |t: u32| {
            let m = look.triangle_materials[t as usize] as usize;
            if m < look.materials.len() { m } else { 0 }
        };
        order.sort_by_key(|&t| material_of(t));
        let mut indices = Vec::with_capacity(order.len() * 3);
        let mut draws: Vec<(Range<u32>, usize)> = Vec::new();
        for &t in &order {
            let m = material_of(t);
            let start = indices.len() as u32;
            indices.extend_from_slice(&look.triangles[t as usize]);
            match draws.last_mut() {
                Some((range, last)) if *last == m => range.end = start + 3,
                _ => draws.push((start..start + 3, m)),
            }
        }
        let init = |label: &str, contents: &[u8], usage| {
            super::bindings::buffer_with(device, label, contents, usage)
        };
        let geometry =
            wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        let zeros = vec![Vec3::ZERO; vertices];
        let positions = init("look positions", bytemuck::cast_slice(&zeros), geometry);
        let normals = init("look normals", bytemuck::cast_slice(&zeros), geometry);
        let colours = vec![crate::colors::to_u8(crate::colors::MESH); vertices];
        let colors = init(
            "look colours",
            bytemuck::cast_slice(&colours),
            wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        );
        let uv_list: Vec<Vec2> = look
            .uvs
            .map_or_else(|| vec![Vec2::ZERO; vertices], <[Vec2]>::to_vec);
        let uvs = init(
            "look uvs",
            bytemuck::cast_slice(&uv_list),
            wgpu::BufferUsages::VERTEX,
        );
        let index_buffer = init(
            "look indices",
            bytemuck::cast_slice(&indices),
            wgpu::BufferUsages::INDEX,
        );
        let material_groups = look
            .materials
            .iter()
            .map(|m| materials.group(gpu, m, look.uv_origin))
            .collect();
        let gather = gpu
            .compute
            .then(|| Gather::new(gpu, look.welded_of, welded, (&positions, &normals)));
        Ok(Self {
            positions,
            normals,
            colors,
            uvs,
            indices: index_buffer,
            draws,
            materials: material_groups,
            welded_of: look.welded_of.to_vec(),
            gather,
        })
    }

    /// Whether the welded buffers are gathered on the GPU.
    pub(super) fn gathers_on_gpu(&self) -> bool {
        self.gather.is_some()
    }

    /// Records the gather of the welded buffers into this layout.
    pub(super) fn record_gather(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(gather) = &self.gather {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("gather"),
                timestamp_writes: None,
            });
            pass.set_bind_group(0, &gather.group, &[]);
            pass.set_pipeline(&gather.pipeline);
            pass.dispatch_workgroups(gather.groups.0, gather.groups.1, 1);
        }
    }

    /// The CPU gather: welded positions and normals into this layout.
    pub(super) fn write_gathered(&self, gpu: &GpuContext, positions: &[Vec3], normals: &[Vec3]) {
        let pick = |from: &[Vec3]| -> Vec<Vec3> {
            self.welded_of
                .iter()
                .map(|&w| from.get(w as usize).copied().unwrap_or(Vec3::ZERO))
                .collect()
        };
        gpu.queue
            .write_buffer(&self.positions, 0, bytemuck::cast_slice(&pick(positions)));
        gpu.queue
            .write_buffer(&self.normals, 0, bytemuck::cast_slice(&pick(normals)));
    }

    /// Welded vertex colours into this layout.
    pub(super) fn write_colors(&self, gpu: &GpuContext, welded: &[[u8; 4]]) {
        let colours: Vec<[u8; 4]> = self
            .welded_of
            .iter()
            .map(|&w| {
                welded
                    .get(w as usize)
                    .copied()
                    .unwrap_or([200, 200, 200, 255])
            })
            .collect();
        gpu.queue
            .write_buffer(&self.colors, 0, bytemuck::cast_slice(&colours));
    }
}

impl Gather {
    fn new(
        gpu: &GpuContext,
        welded_of: &[u32],
        welded: (&wgpu::Buffer, &wgpu::Buffer),
        drawn: (&wgpu::Buffer, &wgpu::Buffer),
    ) -> Self {
        let device = &gpu.device;
        let count = welded_of.len() as u32;
        let workgroups = count.div_ceil(WORKGROUP).max(1);
        let max = device.limits().max_compute_workgroups_per_dimension.max(1);
        let groups = (workgroups.min(max), workgroups.div_ceil(max));
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("gather params"),
            contents: bytemuck::cast_slice(&[count, groups.0 * WORKGROUP, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let padded: &[u32] = if welded_of.is_empty() {
            &[0]
        } else {
            welded_of
        };
        let map = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("welded of"),
            contents: bytemuck::cast_slice(padded),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let entry = |binding: u32, kind: wgpu::BufferBindingType| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: kind,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let read = wgpu::BufferBindingType::Storage { read_only: true };
        let write = wgpu::BufferBindingType::Storage { read_only: false };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gather"),
            entries: &[
                entry(0, wgpu::BufferBindingType::Uniform),
                entry(1, read),
                entry(2, read),
                entry(3, read),
                entry(4, write),
                entry(5, write),
            ],
        });
        let buffers = [&params, &map, welded.0, welded.1, drawn.0, drawn.1];
        let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .iter()
            .enumerate()
            .map(|(b, buffer)| wgpu::BindGroupEntry {
                binding: b as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gather"),
            layout: &layout,
            entries: &entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gather"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("gather"),
            layout: Some(&pipeline_layout),
            module: &shaders::module(device, "gather"),
            entry_point: Some("gather"),
            compilation_options: Default::default(),
            cache: None,
        });
        Self {
            pipeline,
            group,
            groups,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mip_chain_halves_down_to_one_pixel_and_averages() {
        let image = Rgba8Image {
            width: 4,
            height: 2,
            pixels: [[0, 0, 0, 255], [255, 255, 255, 255]]
                .into_iter()
                .cycle()
                .take(8)
                .flatten()
                .collect(),
        };
        let chain = mip_chain(&image, 16);
        let sides: Vec<(u32, u32)> = chain.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sides, [(4, 2), (2, 1), (1, 1)]);
        // Black and white columns average to mid grey.
        assert_eq!(chain[1].pixels[0], 128);
        // A device that takes 2 pixels drops the larger level.
        assert_eq!(mip_chain(&image, 2).len(), 2);
        // A malformed image becomes one white pixel rather than a panic.
        let broken = Rgba8Image {
            width: 3,
            height: 3,
            pixels: vec![0; 5],
        };
        assert_eq!(mip_chain(&broken, 16)[0].pixels, vec![255; 4]);
    }
}
