//! The 3D viewport inside egui: each frame the app hands a [`FrameData`] to an egui-wgpu paint
//! callback, which renders the scene with the viewport crate into its own texture (depth,
//! MSAA) in `prepare` and copies it into egui's pass in `paint`.

use std::sync::Arc;

use egui_wgpu::{CallbackResources, CallbackTrait, RenderState, ScreenDescriptor};
use glam::Vec3;
use starcages_core::star::StarBinding;
use starcages_viewport::gpu::{Blit, GpuContext, Layers, SceneRenderer, ViewTarget};
use starcages_viewport::layers::{Dot, LineVertex};
use starcages_viewport::{OrbitCamera, gpu::OFFSCREEN_FORMAT};

/// A mesh to upload: welded rest positions, triangles, and the binding whose operator the GPU
/// deforms with.
#[derive(Debug)]
pub struct MeshUpload {
    /// Rest positions (welded).
    pub positions: Vec<Vec3>,
    /// Welded triangles.
    pub triangles: Vec<[u32; 3]>,
    /// The binding (operator) of this mesh.
    pub binding: Arc<StarBinding>,
}

/// A deformation to show: its generation, the degrees of freedom (GPU path) and the deformed
/// positions (CPU path).
pub type Deformation = (u64, Arc<Vec<Vec3>>, Arc<Vec<Vec3>>);

/// Everything the viewport draws this frame.
#[derive(Debug, Clone)]
pub struct FrameData {
    /// The camera.
    pub camera: OrbitCamera,
    /// Layers and shading.
    pub layers: Layers,
    /// Cage edges.
    pub lines: Arc<Vec<LineVertex>>,
    /// Cage vertices.
    pub dots: Arc<Vec<Dot>>,
    /// The mesh and its generation (uploaded when the generation changes).
    pub mesh: Option<(u64, Arc<MeshUpload>)>,
    /// This frame's degrees of freedom (GPU deformation) and the deformed positions (CPU path),
    /// with their generation.
    pub deformation: Option<Deformation>,
    /// Vertex colours and their generation.
    pub colors: Option<(u64, Arc<Vec<[u8; 4]>>)>,
}

/// GPU state kept across frames in egui-wgpu's callback resources.
struct Resources {
    gpu: GpuContext,
    renderer: SceneRenderer,
    target: Option<ViewTarget>,
    blit: Blit,
    samples: u32,
    mesh_generation: u64,
    deformation_generation: u64,
    color_generation: u64,
}

/// Installs the viewport's GPU resources into eframe's renderer. Returns false without wgpu.
pub fn install(render_state: &RenderState) -> bool {
    let gpu = GpuContext::from_device(
        &render_state.adapter,
        render_state.device.clone(),
        render_state.queue.clone(),
    );
    let samples = if gpu.msaa4 { 4 } else { 1 };
    let resources = Resources {
        renderer: SceneRenderer::new(&gpu, OFFSCREEN_FORMAT, samples),
        blit: Blit::new(&gpu, render_state.target_format),
        target: None,
        samples,
        mesh_generation: u64::MAX,
        deformation_generation: u64::MAX,
        color_generation: u64::MAX,
        gpu,
    };
    render_state
        .renderer
        .write()
        .callback_resources
        .insert(resources);
    true
}

/// The paint callback of one frame.
pub struct ViewportCallback {
    /// What to draw.
    pub data: FrameData,
    /// The viewport's size in points.
    pub size_points: egui::Vec2,
}

impl CallbackTrait for ViewportCallback {
    fn prepare(
        &self,
        _device: &wgpu::Device,
        _queue: &wgpu::Queue,
        screen: &ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        let Some(r) = resources.get_mut::<Resources>() else {
            return Vec::new();
        };
        let data = &self.data;
        if let Some((generation, mesh)) = &data.mesh
            && *generation != r.mesh_generation
        {
            r.renderer.set_mesh(
                &r.gpu,
                &mesh.positions,
                &mesh.triangles,
                Some(&mesh.binding.operator),
            );
            r.mesh_generation = *generation;
            r.deformation_generation = u64::MAX;
            r.color_generation = u64::MAX;
        }
        if let Some((generation, dofs, positions)) = &data.deformation
            && *generation != r.deformation_generation
        {
            if !r.renderer.deform_on_gpu(&r.gpu, encoder, dofs) {
                r.renderer.set_positions(&r.gpu, positions);
            }
            r.deformation_generation = *generation;
        }
        if let Some((generation, colors)) = &data.colors
            && *generation != r.color_generation
        {
            r.renderer.set_colors(&r.gpu, colors);
            r.color_generation = *generation;
        }
        r.renderer.set_lines(&r.gpu, &data.lines);
        r.renderer.set_dots(&r.gpu, &data.dots);
        let width = (self.size_points.x * screen.pixels_per_point)
            .round()
            .max(1.0) as u32;
        let height = (self.size_points.y * screen.pixels_per_point)
            .round()
            .max(1.0) as u32;
        if !r
            .target
            .as_ref()
            .is_some_and(|t| t.fits(width, height, r.samples))
        {
            let target = ViewTarget::new(&r.gpu, width, height, r.samples);
            r.blit.set_source(&r.gpu, &target);
            r.target = Some(target);
        }
        if let Some(target) = &r.target {
            r.renderer
                .set_camera(&r.gpu, &data.camera, target.size(), &data.layers);
            target.render(encoder, &r.renderer, &data.layers);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        render_pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        if let Some(r) = resources.get::<Resources>() {
            r.blit.draw(render_pass);
        }
    }
}
