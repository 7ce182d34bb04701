//! Ghosts of the animation: the mesh deformed at frames around the current one, each into its
//! own position and normal buffers (through the one resident operator where the GPU deforms,
//! from CPU positions elsewhere), drawn translucent over the welded triangles.

use glam::Vec3;
use wgpu::util::DeviceExt as _;

use super::context::GpuContext;
use super::deform::{DeformTarget, GpuDeformer, cpu_normals};

/// The most ghosts drawn at once.
pub const MAX_GHOSTS: usize = 16;

/// The shape of one ghost.
#[derive(Debug, Clone, Copy)]
pub enum GhostShape<'a> {
    /// The frame's degrees of freedom, deformed on the GPU (where the renderer has a GPU
    /// deformer; otherwise the ghost is not drawn).
    Dofs(&'a [Vec3]),
    /// Deformed welded positions, computed on the CPU.
    Positions(&'a [Vec3]),
}

/// One ghost to draw: its shape and its tint (RGB, opacity).
#[derive(Debug, Clone, Copy)]
pub struct Ghost<'a> {
    /// Its shape.
    pub shape: GhostShape<'a>,
    /// Tint and opacity.
    pub tint: [f32; 4],
}

/// What every ghost of a mesh shares: its GPU deformer, welded triangles and vertex count,
/// and how far ghosts are pushed from the eye (world units).
#[derive(Debug, Clone, Copy)]
pub(super) struct GhostMesh<'a> {
    pub deformer: Option<&'a GpuDeformer>,
    pub triangles: &'a [[u32; 3]],
    pub vertex_count: usize,
    pub push: f32,
}

/// One ghost's buffers.
#[derive(Debug)]
pub(super) struct GhostBuffers {
    pub positions: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    target: Option<DeformTarget>,
    tint: wgpu::Buffer,
    pub group: wgpu::BindGroup,
}

/// The ghost bind group's layout (group 1 of the ghost pipeline: its tint).
pub(super) fn ghost_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("ghost"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    })
}

impl GhostBuffers {
    pub(super) fn new(
        gpu: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        vertex_count: usize,
        deformer: Option<&GpuDeformer>,
    ) -> Self {
        let device = &gpu.device;
        let size = (vertex_count.max(1) * 12) as u64;
        let buffer = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::VERTEX
                    | wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let positions = buffer("ghost positions");
        let normals = buffer("ghost normals");
        let target = deformer.map(|d| d.target(gpu, &positions, &normals));
        let tint = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ghost tint"),
            contents: bytemuck::cast_slice(&[0f32; 8]),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ghost"),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: tint.as_entire_binding(),
            }],
        });
        Self {
            positions,
            normals,
            target,
            tint,
            group,
        }
    }

    /// Shapes this ghost: records its deformation, or uploads CPU positions with their
    /// normals. Returns false when it cannot be shaped (degrees of freedom without a GPU
    /// deformer, or positions of another mesh).
    pub(super) fn shape(
        &self,
        gpu: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        mesh: &GhostMesh<'_>,
        ghost: &Ghost<'_>,
    ) -> bool {
        let GhostMesh {
            deformer,
            triangles,
            vertex_count,
            push,
        } = *mesh;
        let [r, g, b, a] = ghost.tint;
        gpu.queue.write_buffer(
            &self.tint,
            0,
            bytemuck::cast_slice(&[r, g, b, a, push, 0.0, 0.0, 0.0]),
        );
        match ghost.shape {
            GhostShape::Dofs(dofs) => match (deformer, &self.target) {
                (Some(deformer), Some(target)) => {
                    deformer.record(gpu, encoder, target, dofs);
                    true
                }
                _ => false,
            },
            GhostShape::Positions(positions) if positions.len() == vertex_count => {
                let normals = cpu_normals(positions, triangles);
                gpu.queue
                    .write_buffer(&self.positions, 0, bytemuck::cast_slice(positions));
                gpu.queue
                    .write_buffer(&self.normals, 0, bytemuck::cast_slice(&normals));
                true
            }
            GhostShape::Positions(_) => false,
        }
    }
}
