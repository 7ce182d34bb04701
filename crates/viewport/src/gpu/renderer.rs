//! The scene renderer: background, shaded mesh, wireframe, cage lines and vertex dots into a
//! colour target (optionally multisampled) with a depth buffer. Independent of any window: the
//! editor renders through it into a texture, the CLI into an image.

use glam::{Mat4, Vec2, Vec3};
use wgpu::util::DeviceExt as _;

use super::context::GpuContext;
use super::deform::{DeformTarget, GpuDeformer, cpu_normals};
use super::ghosts::{Ghost, GhostBuffers, GhostMesh, MAX_GHOSTS, ghost_layout};
use super::look::{LookBuffers, LookError, LookMaterial, MaterialLayout, RenderLook};
use super::shaders;
use crate::camera::OrbitCamera;
use crate::colors;
use crate::layers::{Dot, LineVertex, mesh_edges};
use crate::matcap::Matcap;

/// The depth format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The per-frame uniform block (`shaders/common.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniforms {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    viewport: [f32; 4],
    background_top: [f32; 4],
    background_bottom: [f32; 4],
    opacity: [f32; 4],
    camera_right: [f32; 4],
    camera_up: [f32; 4],
    shading: [f32; 4],
}

/// How the mesh is shaded (Blender's viewport shading popover).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Shading {
    /// Studio light on the mesh's colour (light grey, or an influence map).
    #[default]
    Solid,
    /// A built-in matcap at the view-space normal.
    MatCap(Matcap),
    /// The file's materials: base colour factor × image, under the studio light.
    Textured,
}

/// Which layers to draw and how.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layers {
    /// The shaded mesh.
    pub mesh: bool,
    /// Flat instead of smooth shading.
    pub flat: bool,
    /// The mesh's edges over it.
    pub wireframe: bool,
    /// Cage edges.
    pub cages: bool,
    /// Cage vertices.
    pub vertices: bool,
    /// The ground grid and the X and Y axis lines (set by [`SceneRenderer::set_guides`]).
    pub ground: bool,
    /// X-ray: the mesh drawn translucent at [`Layers::xray_opacity`] and the cages over it,
    /// seen and picked through it.
    pub xray: bool,
    /// The mesh's opacity in X-ray, in [0.05, 1].
    pub xray_opacity: f32,
    /// The cages' opacity (edges and vertices), in [0.05, 1].
    pub cage_opacity: f32,
    /// Solid, MatCap or Textured.
    pub shading: Shading,
    /// The vertex colours ([`SceneRenderer::set_colors`]: an influence map) replace the
    /// material's colour, over any shading.
    pub vertex_colors: bool,
}

impl Default for Layers {
    fn default() -> Self {
        Self {
            mesh: true,
            flat: false,
            wireframe: false,
            cages: true,
            vertices: true,
            ground: false,
            xray: false,
            xray_opacity: 0.5,
            cage_opacity: 1.0,
            shading: Shading::Solid,
            vertex_colors: false,
        }
    }
}

struct MeshBuffers {
    positions: wgpu::Buffer,
    normals: wgpu::Buffer,
    colors: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    edges: wgpu::Buffer,
    edge_count: u32,
    vertex_count: usize,
    /// The rest mesh's bounding-box diagonal.
    diagonal: f32,
    triangles: Vec<[u32; 3]>,
    deformer: Option<GpuDeformer>,
    /// The drawn mesh's deformation target (with `deformer`).
    target: Option<DeformTarget>,
    /// The file's layout and materials, for Textured shading.
    look: Option<LookBuffers>,
}

/// A growable vertex buffer for lines and dots.
struct Dynamic {
    buffer: Option<wgpu::Buffer>,
    count: u32,
}

impl Dynamic {
    fn upload(&mut self, gpu: &GpuContext, label: &str, bytes: &[u8], count: usize) {
        self.count = count as u32;
        if bytes.is_empty() {
            return;
        }
        match &self.buffer {
            Some(b) if b.size() >= bytes.len() as u64 => gpu.queue.write_buffer(b, 0, bytes),
            _ => {
                self.buffer = Some(gpu.device.create_buffer_init(
                    &wgpu::util::BufferInitDescriptor {
                        label: Some(label),
                        contents: bytes,
                        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                    },
                ));
            }
        }
    }
}

/// The renderer's pipelines and the scene's GPU buffers.
pub struct SceneRenderer {
    sample_count: u32,
    frame: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    background: wgpu::RenderPipeline,
    /// Solid and MatCap over the welded mesh, and Textured over the file's layout; each
    /// opaque and in X-ray (translucent, no depth written).
    solid_pipelines: [wgpu::RenderPipeline; 2],
    matcap_pipelines: [wgpu::RenderPipeline; 2],
    textured_pipelines: [wgpu::RenderPipeline; 2],
    ghost_pipeline: wgpu::RenderPipeline,
    ghost_layout: wgpu::BindGroupLayout,
    ghosts: Vec<GhostBuffers>,
    ghost_count: usize,
    matcap_layout: wgpu::BindGroupLayout,
    matcap_group: wgpu::BindGroup,
    matcap: Matcap,
    material_layout: MaterialLayout,
    default_material: wgpu::BindGroup,
    wire_pipeline: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    cage_line_pipeline: wgpu::RenderPipeline,
    cage_line_xray_pipeline: wgpu::RenderPipeline,
    dot_pipeline: wgpu::RenderPipeline,
    dot_xray_pipeline: wgpu::RenderPipeline,
    mesh: Option<MeshBuffers>,
    lines: Dynamic,
    guides: Dynamic,
    dots: Dynamic,
}

impl std::fmt::Debug for SceneRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SceneRenderer")
            .field("sample_count", &self.sample_count)
            .field("mesh_vertices", &self.mesh.as_ref().map(|m| m.vertex_count))
            .finish_non_exhaustive()
    }
}

const POSITION: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![0 => Float32x3];
const NORMAL: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![1 => Float32x3];
const COLOR: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![2 => Unorm8x4];
const UV: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![3 => Float32x2];
const LINE: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Unorm8x4];
const DOT: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Unorm8x4, 2 => Float32];

fn layout(
    stride: u64,
    step: wgpu::VertexStepMode,
    attributes: &[wgpu::VertexAttribute],
) -> wgpu::VertexBufferLayout<'_> {
    wgpu::VertexBufferLayout {
        array_stride: stride,
        step_mode: step,
        attributes,
    }
}

impl SceneRenderer {
    /// Pipelines for colour targets of `format` with `sample_count` samples.
    pub fn new(gpu: &GpuContext, format: wgpu::TextureFormat, sample_count: u32) -> Self {
        let device = &gpu.device;
        let frame = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
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
        });
        let frame_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &frame_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame.as_entire_binding(),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&frame_layout)],
            immediate_size: 0,
        });
        let matcap_layout = super::bindings::image_layout(device, "matcap");
        let material_layout = MaterialLayout::new(device);
        let mesh_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("mesh"),
            bind_group_layouts: &[
                Some(&frame_layout),
                Some(&matcap_layout),
                Some(&material_layout.layout),
            ],
            immediate_size: 0,
        });
        let ghost_bind_layout = ghost_layout(device);
        let ghost_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("ghost"),
                bind_group_layouts: &[Some(&frame_layout), Some(&ghost_bind_layout)],
                immediate_size: 0,
            });
        let pipeline_in = |layout: &wgpu::PipelineLayout,
                           name: &str,
                           vertex_entry: &str,
                           buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
                           topology: wgpu::PrimitiveTopology,
                           fragment_entry: &str,
                           depth_write: bool,
                           depth_compare: wgpu::CompareFunction| {
            let module = shaders::module(device, name);
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(name),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vertex_entry),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(depth_compare),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: sample_count,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment_entry),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let pipeline = |name: &str,
                        vertex_entry: &str,
                        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
                        topology: wgpu::PrimitiveTopology,
                        fragment_entry: &str,
                        depth_write: bool,
                        depth_compare: wgpu::CompareFunction| {
            pipeline_in(
                &pipeline_layout,
                name,
                vertex_entry,
                buffers,
                topology,
                fragment_entry,
                depth_write,
                depth_compare,
            )
        };
        let vertex = wgpu::VertexStepMode::Vertex;
        let less = wgpu::CompareFunction::Less;
        let background = pipeline(
            "background",
            "vs_main",
            &[],
            wgpu::PrimitiveTopology::TriangleList,
            "fs_main",
            false,
            wgpu::CompareFunction::Always,
        );
        let mesh_buffers = [
            Some(layout(12, vertex, &POSITION)),
            Some(layout(12, vertex, &NORMAL)),
            Some(layout(4, vertex, &COLOR)),
        ];
        let triangles = wgpu::PrimitiveTopology::TriangleList;
        let textured_buffers = [
            Some(layout(12, vertex, &POSITION)),
            Some(layout(12, vertex, &NORMAL)),
            Some(layout(4, vertex, &COLOR)),
            Some(layout(8, vertex, &UV)),
        ];
        // X-ray: translucent, writing no depth, so the cages behind show through.
        let mesh_pipelines = |vertex_entry: &str,
                              buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
                              fragment: &str| {
            [true, false].map(|depth_write| {
                pipeline_in(
                    &mesh_layout,
                    "mesh",
                    vertex_entry,
                    buffers,
                    triangles,
                    fragment,
                    depth_write,
                    less,
                )
            })
        };
        let solid_pipelines = mesh_pipelines("vs_main", &mesh_buffers, "fs_main");
        let matcap_pipelines = mesh_pipelines("vs_main", &mesh_buffers, "fs_matcap");
        let textured_pipelines = mesh_pipelines("vs_textured", &textured_buffers, "fs_textured");
        let ghost_pipeline = pipeline_in(
            &ghost_pipeline_layout,
            "ghost",
            "vs_main",
            &[
                Some(layout(12, vertex, &POSITION)),
                Some(layout(12, vertex, &NORMAL)),
            ],
            triangles,
            "fs_main",
            false,
            less,
        );
        let matcap = Matcap::default();
        let matcap_group = matcap_group(gpu, &matcap_layout, matcap);
        let default_material = material_layout.group(
            gpu,
            &LookMaterial {
                base_color: [1.0; 4],
                image: None,
            },
            Default::default(),
        );
        let wire_pipeline = pipeline(
            "lines",
            "vs_wire",
            &[Some(layout(12, vertex, &POSITION))],
            wgpu::PrimitiveTopology::LineList,
            "fs_main",
            false,
            wgpu::CompareFunction::LessEqual,
        );
        let line_buffers = [Some(layout(16, vertex, &LINE))];
        let lines = wgpu::PrimitiveTopology::LineList;
        let less_equal = wgpu::CompareFunction::LessEqual;
        let always = wgpu::CompareFunction::Always;
        let line_pipeline = pipeline(
            "lines",
            "vs_main",
            &line_buffers,
            lines,
            "fs_main",
            true,
            less_equal,
        );
        let cage_line_pipeline = pipeline(
            "lines",
            "vs_main",
            &line_buffers,
            lines,
            "fs_cage",
            true,
            less_equal,
        );
        let cage_line_xray_pipeline = pipeline(
            "lines",
            "vs_main",
            &line_buffers,
            lines,
            "fs_cage",
            false,
            always,
        );
        let dot_buffers = [Some(layout(20, wgpu::VertexStepMode::Instance, &DOT))];
        let dot_pipeline = pipeline(
            "dots",
            "vs_main",
            &dot_buffers,
            triangles,
            "fs_main",
            true,
            less_equal,
        );
        let dot_xray_pipeline = pipeline(
            "dots",
            "vs_main",
            &dot_buffers,
            triangles,
            "fs_main",
            false,
            always,
        );
        Self {
            sample_count,
            frame,
            frame_group,
            background,
            solid_pipelines,
            matcap_pipelines,
            textured_pipelines,
            ghost_pipeline,
            ghost_layout: ghost_bind_layout,
            ghosts: Vec::new(),
            ghost_count: 0,
            matcap_layout,
            matcap_group,
            matcap,
            material_layout,
            default_material,
            wire_pipeline,
            line_pipeline,
            cage_line_pipeline,
            cage_line_xray_pipeline,
            dot_pipeline,
            dot_xray_pipeline,
            mesh: None,
            lines: Dynamic {
                buffer: None,
                count: 0,
            },
            guides: Dynamic {
                buffer: None,
                count: 0,
            },
            dots: Dynamic {
                buffer: None,
                count: 0,
            },
        }
    }

    /// Samples per pixel of the colour targets this renderer draws into.
    pub fn sample_count(&self) -> usize {
        self.sample_count as usize
    }

    /// Uploads a mesh (welded positions and triangles) at its rest shape, and, when compute
    /// shaders are available and `operator` is given, the operator for GPU deformation.
    pub fn set_mesh(
        &mut self,
        gpu: &GpuContext,
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        operator: Option<&starcages_core::star::StarOperator>,
    ) {
        let device = &gpu.device;
        let geometry = wgpu::BufferUsages::VERTEX
            | wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC;
        let normals = cpu_normals(positions, triangles);
        let init = |label: &str, contents: &[u8], usage| {
            super::bindings::buffer_with(device, label, contents, usage)
        };
        let positions_buffer = init("positions", bytemuck::cast_slice(positions), geometry);
        let normals_buffer = init("normals", bytemuck::cast_slice(&normals), geometry);
        let colours = vec![colors::to_u8(colors::MESH); positions.len()];
        let colors_buffer = init(
            "colours",
            bytemuck::cast_slice(&colours),
            wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        );
        let flat: Vec<u32> = triangles.iter().flatten().copied().collect();
        let indices = init(
            "indices",
            bytemuck::cast_slice(&flat),
            wgpu::BufferUsages::INDEX,
        );
        let edge_list = mesh_edges(triangles);
        let edges = init(
            "edges",
            bytemuck::cast_slice(&edge_list),
            wgpu::BufferUsages::INDEX,
        );
        let deformer = operator
            .filter(|_| gpu.compute)
            .filter(|op| super::deform::deformer_fits(&device.limits(), op, triangles.len()))
            .map(|op| GpuDeformer::new(gpu, op, triangles));
        let target = deformer
            .as_ref()
            .map(|d| d.target(gpu, &positions_buffer, &normals_buffer));
        self.ghosts.clear();
        self.ghost_count = 0;
        self.mesh = Some(MeshBuffers {
            positions: positions_buffer,
            normals: normals_buffer,
            colors: colors_buffer,
            indices,
            index_count: flat.len() as u32,
            edges,
            edge_count: edge_list.len() as u32,
            vertex_count: positions.len(),
            diagonal: {
                let (lo, hi) = positions.iter().fold(
                    (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                    |(lo, hi), p| (lo.min(*p), hi.max(*p)),
                );
                if positions.is_empty() {
                    0.0
                } else {
                    (hi - lo).length()
                }
            },
            triangles: triangles.to_vec(),
            deformer,
            target,
            look: None,
        });
    }

    /// Uploads the mesh's look (its file's layout, UVs and materials) for Textured shading,
    /// at the rest `positions` given to [`SceneRenderer::set_mesh`]; `None` drops it. A look
    /// that does not fit the mesh is refused (the mesh draws without it).
    pub fn set_look(
        &mut self,
        gpu: &GpuContext,
        look: Option<&RenderLook<'_>>,
        rest: &[Vec3],
    ) -> Result<(), LookError> {
        let Some(mesh) = &mut self.mesh else {
            return Ok(());
        };
        mesh.look = None;
        let Some(look) = look else {
            return Ok(());
        };
        let buffers = LookBuffers::new(
            gpu,
            &self.material_layout,
            look,
            mesh.vertex_count,
            (&mesh.positions, &mesh.normals),
        )?;
        if rest.len() == mesh.vertex_count {
            buffers.write_gathered(gpu, rest, &cpu_normals(rest, &mesh.triangles));
        }
        mesh.look = Some(buffers);
        Ok(())
    }

    /// Uploads a loaded look over `mesh` (the mesh [`SceneRenderer::set_mesh`] was given, in
    /// its welded form): its original layout, UVs and the look's materials and images.
    pub fn set_loaded_look(
        &mut self,
        gpu: &GpuContext,
        mesh: &starcages_core::mesh::Mesh,
        loaded: &starcages_core::mesh::look::LoadedLook,
        rest: &[Vec3],
    ) -> Result<(), LookError> {
        let triangle_materials = loaded
            .look
            .materials_of(mesh.triangles().len())
            .ok_or(LookError::Mismatch("a look read for another mesh"))?;
        let materials: Vec<LookMaterial<'_>> = loaded
            .look
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| LookMaterial {
                base_color: m.base_color,
                image: loaded.images.get(i).and_then(Option::as_ref),
            })
            .collect();
        let look = RenderLook {
            welded_of: mesh.weld_map(),
            triangles: mesh.triangles(),
            uvs: mesh.uvs(),
            triangle_materials: &triangle_materials,
            materials: &materials,
            uv_origin: loaded.look.uv_origin,
        };
        self.set_look(gpu, Some(&look), rest)
    }

    /// How many ghosts are drawn.
    pub fn ghost_count(&self) -> usize {
        self.ghost_count
    }

    /// Whether a look is uploaded.
    pub fn has_look(&self) -> bool {
        self.mesh.as_ref().is_some_and(|m| m.look.is_some())
    }

    /// The matcap MatCap shading uses.
    pub fn set_matcap(&mut self, gpu: &GpuContext, matcap: Matcap) {
        if matcap != self.matcap {
            self.matcap_group = matcap_group(gpu, &self.matcap_layout, matcap);
            self.matcap = matcap;
        }
    }

    /// Shapes the ghosts drawn from now on (at most [`MAX_GHOSTS`]; an empty list hides
    /// them): degrees of freedom are deformed on the GPU, positions uploaded. Returns how many
    /// will be drawn.
    pub fn set_ghosts(
        &mut self,
        gpu: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        ghosts: &[Ghost<'_>],
    ) -> usize {
        self.ghost_count = 0;
        let Some(mesh) = &self.mesh else {
            return 0;
        };
        for ghost in ghosts.iter().take(MAX_GHOSTS) {
            if self.ghosts.len() <= self.ghost_count {
                self.ghosts.push(GhostBuffers::new(
                    gpu,
                    &self.ghost_layout,
                    mesh.vertex_count,
                    mesh.deformer.as_ref(),
                ));
            }
            let buffers = &self.ghosts[self.ghost_count];
            let shared = GhostMesh {
                deformer: mesh.deformer.as_ref(),
                triangles: &mesh.triangles,
                vertex_count: mesh.vertex_count,
                push: 0.01 * mesh.diagonal,
            };
            if buffers.shape(gpu, encoder, &shared, ghost) {
                self.ghost_count += 1;
            }
        }
        self.ghost_count
    }

    /// Whether deformation runs on the GPU (a mesh with an operator, compute available).
    pub fn deforms_on_gpu(&self) -> bool {
        self.mesh.as_ref().is_some_and(|m| m.deformer.is_some())
    }

    /// Records the GPU deformation for this frame's degrees of freedom
    /// ([`StarOperator::dofs`](starcages_core::star::StarOperator::dofs)). Returns false when
    /// there is no GPU deformer (use [`SceneRenderer::set_positions`]).
    pub fn deform_on_gpu(
        &self,
        gpu: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        dofs: &[Vec3],
    ) -> bool {
        let Some(mesh) = &self.mesh else {
            return false;
        };
        match (&mesh.deformer, &mesh.target) {
            (Some(deformer), Some(target)) => {
                deformer.record(gpu, encoder, target, dofs);
                match &mesh.look {
                    Some(look) if look.gathers_on_gpu() => look.record_gather(encoder),
                    Some(look) => {
                        // No compute for the gather cannot happen with a GPU deformer, but
                        // should it, the textured layout keeps its rest shape.
                        let _ = look;
                    }
                    None => {}
                }
                true
            }
            _ => false,
        }
    }

    /// The CPU path: uploads deformed positions and recomputes normals.
    pub fn set_positions(&self, gpu: &GpuContext, positions: &[Vec3]) {
        if let Some(mesh) = &self.mesh
            && positions.len() == mesh.vertex_count
        {
            let normals = cpu_normals(positions, &mesh.triangles);
            gpu.queue
                .write_buffer(&mesh.positions, 0, bytemuck::cast_slice(positions));
            gpu.queue
                .write_buffer(&mesh.normals, 0, bytemuck::cast_slice(&normals));
            if let Some(look) = &mesh.look {
                look.write_gathered(gpu, positions, &normals);
            }
        }
    }

    /// Per-vertex colours of the mesh (an influence map, or the studio colour).
    pub fn set_colors(&self, gpu: &GpuContext, colours: &[[u8; 4]]) {
        if let Some(mesh) = &self.mesh
            && colours.len() == mesh.vertex_count
        {
            gpu.queue
                .write_buffer(&mesh.colors, 0, bytemuck::cast_slice(colours));
            if let Some(look) = &mesh.look {
                look.write_colors(gpu, colours);
            }
        }
    }

    /// Cage edges to draw.
    pub fn set_lines(&mut self, gpu: &GpuContext, lines: &[LineVertex]) {
        self.lines
            .upload(gpu, "cage lines", bytemuck::cast_slice(lines), lines.len());
    }

    /// Uploads the ground grid's lines (drawn when [`Layers::ground`] is on).
    pub fn set_guides(&mut self, gpu: &GpuContext, lines: &[LineVertex]) {
        self.guides
            .upload(gpu, "ground grid", bytemuck::cast_slice(lines), lines.len());
    }

    /// Cage vertices to draw.
    pub fn set_dots(&mut self, gpu: &GpuContext, dots: &[Dot]) {
        self.dots
            .upload(gpu, "cage dots", bytemuck::cast_slice(dots), dots.len());
    }

    /// The mesh's position buffer (for reading GPU results back in tests and benchmarks).
    pub fn position_buffer(&self) -> Option<&wgpu::Buffer> {
        self.mesh.as_ref().map(|m| &m.positions)
    }

    /// Writes the camera for a target of `size` pixels.
    pub fn set_camera(&self, gpu: &GpuContext, camera: &OrbitCamera, size: Vec2, layers: &Layers) {
        let view_proj: Mat4 = camera.view_projection(size);
        let (right, up) = camera.right_up();
        let uniforms = FrameUniforms {
            view_proj: view_proj.to_cols_array_2d(),
            eye: camera.eye().extend(1.0).to_array(),
            viewport: [size.x, size.y, if layers.flat { 1.0 } else { 0.0 }, 0.0],
            background_top: colors::BACKGROUND_TOP,
            background_bottom: colors::BACKGROUND_BOTTOM,
            opacity: [
                if layers.xray {
                    layers.xray_opacity.clamp(0.05, 1.0)
                } else {
                    1.0
                },
                layers.cage_opacity.clamp(0.05, 1.0),
                0.0,
                0.0,
            ],
            camera_right: right.extend(0.0).to_array(),
            camera_up: up.extend(0.0).to_array(),
            shading: [0.0, if layers.vertex_colors { 1.0 } else { 0.0 }, 0.0, 0.0],
        };
        gpu.queue
            .write_buffer(&self.frame, 0, bytemuck::bytes_of(&uniforms));
    }

    /// Draws every enabled layer into an open render pass (colour and depth attached, cleared
    /// or not).
    pub fn draw<'pass>(&'pass self, pass: &mut wgpu::RenderPass<'pass>, layers: &Layers) {
        pass.set_bind_group(0, &self.frame_group, &[]);
        pass.set_pipeline(&self.background);
        pass.draw(0..3, 0..1);
        if let Some(mesh) = &self.mesh {
            let textured = (layers.shading == Shading::Textured)
                .then_some(mesh.look.as_ref())
                .flatten();
            if layers.mesh && mesh.index_count > 0 {
                pass.set_bind_group(1, &self.matcap_group, &[]);
                let xray = usize::from(layers.xray);
                match textured {
                    Some(look) => {
                        pass.set_pipeline(&self.textured_pipelines[xray]);
                        pass.set_vertex_buffer(0, look.positions.slice(..));
                        pass.set_vertex_buffer(1, look.normals.slice(..));
                        pass.set_vertex_buffer(2, look.colors.slice(..));
                        pass.set_vertex_buffer(3, look.uvs.slice(..));
                        pass.set_index_buffer(look.indices.slice(..), wgpu::IndexFormat::Uint32);
                        for (range, material) in &look.draws {
                            let group = look.materials.get(*material);
                            pass.set_bind_group(2, group.unwrap_or(&self.default_material), &[]);
                            pass.draw_indexed(range.clone(), 0, 0..1);
                        }
                    }
                    None => {
                        // Textured without a look draws as Solid.
                        pass.set_pipeline(match layers.shading {
                            Shading::MatCap(_) => &self.matcap_pipelines[xray],
                            Shading::Solid | Shading::Textured => &self.solid_pipelines[xray],
                        });
                        pass.set_bind_group(2, &self.default_material, &[]);
                        pass.set_vertex_buffer(0, mesh.positions.slice(..));
                        pass.set_vertex_buffer(1, mesh.normals.slice(..));
                        pass.set_vertex_buffer(2, mesh.colors.slice(..));
                        pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                        pass.draw_indexed(0..mesh.index_count, 0, 0..1);
                    }
                }
            }
            // Ghosts over the mesh, translucent, writing no depth, pushed back from the eye by 1 %
            // of the diagonal: where a ghost nearly coincides with the mesh the mesh shows clean;
            // where the motion brings it in front it tints the mesh; beyond the silhouette it
            // shows.
            if self.ghost_count > 0 && mesh.index_count > 0 {
                pass.set_pipeline(&self.ghost_pipeline);
                pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                for ghost in &self.ghosts[..self.ghost_count] {
                    pass.set_bind_group(1, &ghost.group, &[]);
                    pass.set_vertex_buffer(0, ghost.positions.slice(..));
                    pass.set_vertex_buffer(1, ghost.normals.slice(..));
                    pass.draw_indexed(0..mesh.index_count, 0, 0..1);
                }
            }
            if layers.wireframe && mesh.edge_count > 0 {
                pass.set_pipeline(&self.wire_pipeline);
                pass.set_vertex_buffer(0, mesh.positions.slice(..));
                pass.set_index_buffer(mesh.edges.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..mesh.edge_count, 0, 0..1);
            }
        }
        if layers.ground
            && self.guides.count > 0
            && let Some(buffer) = &self.guides.buffer
        {
            pass.set_pipeline(&self.line_pipeline);
            pass.set_vertex_buffer(0, buffer.slice(..));
            pass.draw(0..self.guides.count, 0..1);
        }
        if layers.cages
            && self.lines.count > 0
            && let Some(buffer) = &self.lines.buffer
        {
            pass.set_pipeline(if layers.xray {
                &self.cage_line_xray_pipeline
            } else {
                &self.cage_line_pipeline
            });
            pass.set_vertex_buffer(0, buffer.slice(..));
            pass.draw(0..self.lines.count, 0..1);
        }
        if layers.vertices
            && self.dots.count > 0
            && let Some(buffer) = &self.dots.buffer
        {
            pass.set_pipeline(if layers.xray {
                &self.dot_xray_pipeline
            } else {
                &self.dot_pipeline
            });
            pass.set_vertex_buffer(0, buffer.slice(..));
            pass.draw(0..6, 0..self.dots.count);
        }
    }
}

/// The matcap bind group for `matcap`.
fn matcap_group(
    gpu: &GpuContext,
    layout: &wgpu::BindGroupLayout,
    matcap: Matcap,
) -> wgpu::BindGroup {
    let image = matcap.image(256);
    let view = super::look::upload_image(gpu, "matcap", &image, 256)
        .create_view(&wgpu::TextureViewDescriptor::default());
    let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("matcap"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    super::bindings::image_group(&gpu.device, "matcap", layout, &view, &sampler)
}
