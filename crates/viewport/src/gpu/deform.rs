//! GPU deformation: the compiled operator uploaded once; per frame only the degrees of freedom
//! (posed cage vertices and Green face terms) go up, and a compute pass writes positions and
//! normals straight into the mesh's vertex buffers. `cpu_normals` is the CPU path's twin.

use glam::Vec3;
use rayon::prelude::*;
use starcages_core::star::StarOperator;
use wgpu::util::DeviceExt as _;

use super::context::GpuContext;
use super::shaders;

const WORKGROUP: u32 = 64;

/// The operator and mesh topology on the GPU, uploaded once; each [`DeformTarget`] (the
/// drawn mesh, each ghost of the animation) has its own degrees of freedom and output buffers
/// and shares them.
#[derive(Debug)]
pub struct GpuDeformer {
    operator: [wgpu::Buffer; 4],
    topology: [wgpu::Buffer; 3],
    params: wgpu::Buffer,
    product_layout: wgpu::BindGroupLayout,
    normals_layout: wgpu::BindGroupLayout,
    deform: wgpu::ComputePipeline,
    normals: wgpu::ComputePipeline,
    dof_count: usize,
    rows: usize,
    groups: (u32, u32),
    /// Bytes uploaded once (operator and topology).
    pub resident_bytes: u64,
}

/// Where one deformation goes: its degrees of freedom and the position and normal buffers it
/// writes (3 floats per welded vertex, usage STORAGE).
#[derive(Debug)]
pub struct DeformTarget {
    dofs: wgpu::Buffer,
    product_group: wgpu::BindGroup,
    normals_group: wgpu::BindGroup,
}

fn storage(device: &wgpu::Device, label: &str, contents: &[u8]) -> wgpu::Buffer {
    // Empty bindings are not allowed: pad to one word.
    let padded: &[u8] = if contents.is_empty() {
        &[0; 4]
    } else {
        contents
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: padded,
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// Bytes of the largest storage buffer a [`GpuDeformer`] of `operator` over `triangle_count`
/// triangles creates (the operator's columns or values, the triangle lists, the rest offsets or
/// the DOFs).
pub fn largest_buffer_bytes(operator: &StarOperator, triangle_count: usize) -> u64 {
    let rows = operator.row_count() as u64;
    [
        operator.nonzeros() as u64 * 4,
        (rows + 1) * 4,
        rows * 12,
        triangle_count as u64 * 12,
        operator.dof_count() as u64 * 12,
    ]
    .into_iter()
    .max()
    .unwrap_or(0)
}

/// Whether a [`GpuDeformer`] of `operator` fits the device's limits: every storage buffer
/// within both the largest buffer and the largest storage binding. A larger operator (a
/// million-triangle mesh in a fine rig: 390 MB of columns against lavapipe's 256 MiB, or
/// wgpu's default 128 MiB binding) deforms on the CPU instead of failing to create.
pub fn deformer_fits(
    limits: &wgpu::Limits,
    operator: &StarOperator,
    triangle_count: usize,
) -> bool {
    let bound = limits
        .max_buffer_size
        .min(limits.max_storage_buffer_binding_size);
    largest_buffer_bytes(operator, triangle_count) <= bound
}

/// Incident triangles of each vertex, CSR: (start per vertex + 1, triangle indices).
pub fn vertex_triangles(vertex_count: usize, triangles: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; vertex_count + 1];
    for t in triangles {
        for &v in t {
            start[v as usize + 1] += 1;
        }
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut fill = start.clone();
    let mut list = vec![0u32; start[vertex_count] as usize];
    for (i, t) in triangles.iter().enumerate() {
        for &v in t {
            list[fill[v as usize] as usize] = i as u32;
            fill[v as usize] += 1;
        }
    }
    (start, list)
}

/// Area-weighted vertex normals, as the GPU computes them.
pub fn cpu_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let (start, list) = vertex_triangles(positions.len(), triangles);
    (0..positions.len())
        .into_par_iter()
        .map(|v| {
            let n: Vec3 = list[start[v] as usize..start[v + 1] as usize]
                .iter()
                .map(|&t| {
                    let [a, b, c] = triangles[t as usize].map(|i| positions[i as usize]);
                    (b - a).cross(c - a)
                })
                .sum();
            n.try_normalize().unwrap_or(Vec3::Z)
        })
        .collect()
}

fn compute_entry(binding: u32, read_only: bool, uniform: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: if uniform {
                wgpu::BufferBindingType::Uniform
            } else {
                wgpu::BufferBindingType::Storage { read_only }
            },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The bindings of the product pass (binding, read-only, uniform) and of the normals pass.
/// Two passes, two bind groups: each stays within the default limit of 8 storage buffers per
/// stage (the product: 6; the normals: 5).
const PRODUCT_BINDINGS: [(u32, bool, bool); 7] = [
    (0, true, true),
    (1, true, false),
    (2, true, false),
    (3, true, false),
    (4, true, false),
    (5, false, false),
    (10, true, false),
];
const NORMALS_BINDINGS: [(u32, bool, bool); 6] = [
    (0, true, true),
    (5, false, false),
    (6, true, false),
    (7, true, false),
    (8, true, false),
    (9, false, false),
];

fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    bindings: &[(u32, bool, bool)],
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let resources: Vec<wgpu::BindGroupEntry<'_>> = bindings
        .iter()
        .zip(buffers)
        .map(|(&(b, _, _), buffer)| wgpu::BindGroupEntry {
            binding: b,
            resource: buffer.as_entire_binding(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &resources,
    })
}

impl GpuDeformer {
    /// Uploads `operator` and the mesh's (welded) `triangles`.
    pub fn new(gpu: &GpuContext, operator: &StarOperator, triangles: &[[u32; 3]]) -> Self {
        let device = &gpu.device;
        let (_, row_start, columns, values) = operator.parts();
        let rows = operator.row_count();
        let (vt_start, vt_list) = vertex_triangles(rows, triangles);
        let flat_triangles: Vec<u32> = triangles.iter().flatten().copied().collect();
        let rest_offsets: Vec<f32> = operator
            .rest_offsets()
            .iter()
            .flat_map(|o| o.to_array())
            .collect();
        let operator_buffers = [
            storage(device, "row starts", bytemuck::cast_slice(row_start)),
            storage(device, "columns", bytemuck::cast_slice(columns)),
            storage(device, "values", bytemuck::cast_slice(values)),
            storage(device, "rest offsets", bytemuck::cast_slice(&rest_offsets)),
        ];
        let topology = [
            storage(
                device,
                "vertex triangle starts",
                bytemuck::cast_slice(&vt_start),
            ),
            storage(device, "vertex triangles", bytemuck::cast_slice(&vt_list)),
            storage(device, "triangles", bytemuck::cast_slice(&flat_triangles)),
        ];
        let workgroups = (rows as u32).div_ceil(WORKGROUP).max(1);
        let max = device.limits().max_compute_workgroups_per_dimension.max(1);
        let groups = (workgroups.min(max), workgroups.div_ceil(max));
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("deform params"),
            contents: bytemuck::cast_slice(&[rows as u32, groups.0 * WORKGROUP, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let layout = |label: &str, bindings: &[(u32, bool, bool)]| {
            let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
                .iter()
                .map(|&(b, read_only, uniform)| compute_entry(b, read_only, uniform))
                .collect();
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            })
        };
        let product_layout = layout("deform product", &PRODUCT_BINDINGS);
        let normals_layout = layout("deform normals", &NORMALS_BINDINGS);
        let module = shaders::module(device, "deform");
        let pipeline = |entry: &str, layout: &wgpu::BindGroupLayout| {
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry),
                bind_group_layouts: &[Some(layout)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let resident_bytes = operator_buffers
            .iter()
            .chain(&topology)
            .map(wgpu::Buffer::size)
            .sum();
        Self {
            deform: pipeline("deform", &product_layout),
            normals: pipeline("vertex_normals", &normals_layout),
            operator: operator_buffers,
            topology,
            params,
            product_layout,
            normals_layout,
            dof_count: operator.dof_count(),
            rows,
            groups,
            resident_bytes,
        }
    }

    /// Welded vertices written per deformation.
    pub fn vertex_count(&self) -> usize {
        self.rows
    }

    /// A target writing into `positions` and `normals` (3 floats per welded vertex, usage
    /// STORAGE), with its own degrees of freedom.
    pub fn target(
        &self,
        gpu: &GpuContext,
        positions: &wgpu::Buffer,
        normals: &wgpu::Buffer,
    ) -> DeformTarget {
        let device = &gpu.device;
        let dofs = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dofs"),
            size: (self.dof_count.max(1) * 12) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let [row_start, columns, values, rest] = &self.operator;
        let product_group = bind_group(
            device,
            "deform product",
            &self.product_layout,
            &PRODUCT_BINDINGS,
            &[
                &self.params,
                row_start,
                columns,
                values,
                &dofs,
                positions,
                rest,
            ],
        );
        let [vt_start, vt_list, triangles] = &self.topology;
        let normals_group = bind_group(
            device,
            "deform normals",
            &self.normals_layout,
            &NORMALS_BINDINGS,
            &[
                &self.params,
                positions,
                vt_start,
                vt_list,
                triangles,
                normals,
            ],
        );
        DeformTarget {
            dofs,
            product_group,
            normals_group,
        }
    }

    /// Uploads a frame's degrees of freedom into `target` and records its deformation and
    /// normals.
    pub fn record(
        &self,
        gpu: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        target: &DeformTarget,
        dofs: &[Vec3],
    ) {
        let n = dofs.len().min(self.dof_count);
        if n > 0 {
            gpu.queue
                .write_buffer(&target.dofs, 0, bytemuck::cast_slice(&dofs[..n]));
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("deform"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &target.product_group, &[]);
        pass.set_pipeline(&self.deform);
        pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
        pass.set_bind_group(0, &target.normals_group, &[]);
        pass.set_pipeline(&self.normals);
        pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use starcages_core::BindControl;
    use starcages_core::generate::demo::demo_scene;
    use starcages_core::star::StarBinding;

    /// An operator whose largest buffer passes a device's buffer or binding limit does not get
    /// a GPU deformer (the CPU path draws it); within both limits it does.
    #[test]
    fn an_operator_past_the_device_s_buffer_limits_deforms_on_the_cpu() {
        let scene = demo_scene("bar", 1.0).unwrap();
        let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
        let triangles = scene.mesh.welded_triangles().len();
        let largest = largest_buffer_bytes(&binding.operator, triangles);
        assert_eq!(largest, binding.operator.nonzeros() as u64 * 4);
        let limits = |buffer: u64, binding: u64| wgpu::Limits {
            max_buffer_size: buffer,
            max_storage_buffer_binding_size: binding,
            ..wgpu::Limits::default()
        };
        let fits = |l: wgpu::Limits| deformer_fits(&l, &binding.operator, triangles);
        let exact = largest;
        assert!(fits(limits(largest, exact)));
        assert!(!fits(limits(largest - 1, exact)));
        assert!(!fits(limits(largest, exact - 1)));
    }
}
