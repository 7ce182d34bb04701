//! The 3D viewport inside egui: each frame the UI hands a [`FrameData`] to an egui-wgpu paint
//! callback, which renders the scene with the viewport crate into its own texture (depth,
//! MSAA) in `prepare` and copies it into egui's pass in `paint`. Uploads are keyed by the
//! document's identity as well as its generations, so a newly opened scene always draws its
//! own mesh.

use starcages_core::live::DeformedMesh;
use std::sync::Arc;

use egui_wgpu::{CallbackResources, CallbackTrait, RenderState, ScreenDescriptor};
use glam::Vec3;
use starcages_core::star::StarBinding;
use starcages_viewport::gpu::{
    Blit, Ghost, GhostShape, GpuContext, Layers, SceneRenderer, ViewTarget,
};
use starcages_viewport::layers::{
    Dot, LineVertex, cage_dots, cage_lines, ghost_lines, ground_grid,
};
use starcages_viewport::{OrbitCamera, gpu::OFFSCREEN_FORMAT};

use super::UiState;
use crate::state::EditorState;

/// Which mesh an upload is: the document's identity and its mesh generation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshKey {
    /// `EditorState::document_id`.
    pub document: u64,
    /// `Generations::mesh`.
    pub generation: u64,
}

/// The last mesh upload, reused while its key holds.
#[derive(Debug, Default)]
pub struct MeshUploadCache(Option<(MeshKey, Arc<MeshUpload>)>);

/// What the renderer holds: the mesh uploaded last, as the paint callback saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UploadedMesh {
    /// Which document and binding it came from.
    pub key: MeshKey,
    /// Welded vertices.
    pub vertices: usize,
    /// Triangles.
    pub triangles: usize,
    /// Rest-position bounds (min, max).
    pub bounds: (Vec3, Vec3),
}

/// The mesh the viewport's renderer holds now (tests read it back through egui-wgpu's
/// callback resources).
pub fn uploaded_mesh(resources: &CallbackResources) -> Option<UploadedMesh> {
    resources.get::<Resources>()?.uploaded
}

/// The ghosts drawn last, reused while their key holds (the same document, binding, frame,
/// settings and keys).
#[derive(Debug, Default)]
pub struct GhostCache(Option<(GhostKey, Ghosts)>);

/// What the ghosts depend on.
#[derive(Debug, Clone, PartialEq)]
struct GhostKey {
    document: u64,
    binding: usize,
    frame: f64,
    settings: crate::state::GhostSettings,
    animation: starcages_core::anim::Animation,
}

/// Each ghost's degrees of freedom and tint, with their generation.
pub type Ghosts = (u64, Arc<Vec<(Vec<Vec3>, [f32; 4])>>);

static NEXT_GHOSTS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// The ghosts of the current frame: in Pose mode with keys and ghosts shown, the degrees of
/// freedom of the poses at the frames around it, deformed through the current binding.
/// Computed again only when what they depend on changes.
fn ghosts_of(state: &EditorState, cache: &mut GhostCache) -> Option<Ghosts> {
    let scene = &state.doc.scene;
    let rig = state.rig.as_ref()?;
    let settings = state.view.ghosts;
    if !settings.shown
        || state.mode != crate::state::EditMode::Pose
        || scene.animation.keys.is_empty()
    {
        return None;
    }
    let key = GhostKey {
        document: state.document_id,
        binding: Arc::as_ptr(&rig.binding) as usize,
        frame: state.timeline.frame,
        settings,
        animation: scene.animation.clone(),
    };
    if let Some((k, ghosts)) = &cache.0
        && *k == key
    {
        return Some(ghosts.clone());
    }
    let range = (
        scene.animation.frame_start as f64,
        scene.animation.frame_end as f64,
    );
    let step = f64::from(settings.step.max(1));
    let frames = settings.frames(state.timeline.frame, range);
    let ghosts: Vec<(Vec<Vec3>, [f32; 4])> = frames
        .iter()
        .filter_map(|&(frame, before)| {
            let pose = starcages_core::posing::PoseRequest::frame(frame)
                .resolve(scene)
                .ok()?;
            let distance = ((frame - state.timeline.frame).abs() / step).round() as u32;
            let dofs = rig
                .binding
                .operator
                .dofs(&scene.cages.vertices, &pose.cages);
            Some((dofs, crate::state::GhostSettings::tint(before, distance)))
        })
        .collect();
    let ghosts = (
        NEXT_GHOSTS.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        Arc::new(ghosts),
    );
    cache.0 = Some((key, ghosts.clone()));
    Some(ghosts)
}

/// The look to draw over the current mesh, its generation following the document, the mesh
/// and the look (the mesh is copied for it only when one of those changes).
fn look_upload(state: &EditorState, cache: &mut LookUploadCache) -> LookUpload {
    let key = (
        state.document_id,
        state.generations.mesh,
        state.generations.look,
    );
    let Some(look) = &state.look else {
        cache.0 = None;
        return (key, None);
    };
    let mesh = match &cache.0 {
        Some((k, mesh)) if *k == key => Arc::clone(mesh),
        _ => {
            let mesh = Arc::new(state.doc.scene.mesh.clone());
            cache.0 = Some((key, Arc::clone(&mesh)));
            mesh
        }
    };
    (key, Some((Arc::clone(look), mesh)))
}

/// What the viewport's renderer draws besides the mesh, as the paint callback left it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DrawnExtras {
    /// It holds the mesh file's look.
    pub look: bool,
    /// Ghosts drawn.
    pub ghosts: usize,
    /// The generation of the ghosts' shapes (a new one each time they are computed).
    pub ghost_generation: u64,
}

/// [`DrawnExtras`] of the viewport's renderer (tests read it through egui-wgpu's callback
/// resources).
pub fn drawn_extras(resources: &CallbackResources) -> Option<DrawnExtras> {
    let r = resources.get::<Resources>()?;
    Some(DrawnExtras {
        look: r.renderer.has_look(),
        ghosts: r.renderer.ghost_count(),
        ghost_generation: r.ghost_generation,
    })
}

/// A mesh to upload: welded rest positions, triangles, and the binding whose operator the GPU
/// deforms with.
#[derive(Debug)]
pub struct MeshUpload {
    /// Rest positions (welded).
    pub positions: Vec<Vec3>,
    /// Welded triangles.
    pub triangles: Vec<[u32; 3]>,
    /// The binding (operator) of this mesh; `None` while the first bind runs (the rest shape
    /// is drawn meanwhile).
    pub binding: Option<Arc<StarBinding>>,
}

/// A look to upload: its generation, the look, and the mesh it is drawn over (its file
/// layout and UVs).
pub type LookUpload = (
    LookKey,
    Option<(
        Arc<starcages_core::mesh::look::LoadedLook>,
        Arc<starcages_core::mesh::Mesh>,
    )>,
);

/// Which look an upload is: the document, its mesh generation and its look generation.
pub type LookKey = (u64, u64, u64);

/// The mesh the look was last uploaded over, shared while the document, mesh and look stay.
#[derive(Debug, Default)]
pub struct LookUploadCache(Option<(LookKey, Arc<starcages_core::mesh::Mesh>)>);

/// A deformation to show: its generation, and the degrees of freedom (GPU path) with the
/// deformed positions (CPU path, computed only where the GPU cannot deform).
pub type Deformation = (u64, Arc<DeformedMesh>);

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
    /// The ground grid.
    pub guides: Arc<Vec<LineVertex>>,
    /// The mesh and its key (uploaded when the key changes).
    pub mesh: Option<(MeshKey, Arc<MeshUpload>)>,
    /// This frame's degrees of freedom (GPU deformation) and the deformed positions (CPU path),
    /// with their generation.
    pub deformation: Option<Deformation>,
    /// Vertex colours and their generation.
    pub colors: Option<(u64, Arc<Vec<[u8; 4]>>)>,
    /// The mesh file's look over its mesh, and its generation.
    pub look: LookUpload,
    /// Ghosts of the animation.
    pub ghosts: Option<Ghosts>,
}

/// GPU state kept across frames in egui-wgpu's callback resources.
struct Resources {
    gpu: GpuContext,
    renderer: SceneRenderer,
    target: Option<ViewTarget>,
    blit: Blit,
    samples: u32,
    mesh_key: Option<MeshKey>,
    uploaded: Option<UploadedMesh>,
    deformation_generation: u64,
    color_generation: u64,
    look_key: Option<LookKey>,
    ghost_generation: u64,
    /// Whether the renderer drew ghosts last frame.
    ghosts_shown: bool,
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
        mesh_key: None,
        uploaded: None,
        deformation_generation: u64::MAX,
        color_generation: u64::MAX,
        look_key: None,
        ghost_generation: u64::MAX,
        ghosts_shown: false,
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
        if let Some((key, mesh)) = &data.mesh
            && Some(*key) != r.mesh_key
        {
            r.renderer.set_mesh(
                &r.gpu,
                &mesh.positions,
                &mesh.triangles,
                mesh.binding.as_deref().map(|b| &b.operator),
            );
            r.mesh_key = Some(*key);
            let bounds = mesh.positions.iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            r.uploaded = Some(UploadedMesh {
                key: *key,
                vertices: mesh.positions.len(),
                triangles: mesh.triangles.len(),
                bounds,
            });
            r.deformation_generation = u64::MAX;
            r.color_generation = u64::MAX;
            r.look_key = None;
            r.ghost_generation = u64::MAX;
        }
        if let Some((_, upload)) = &data.mesh
            && Some(data.look.0) != r.look_key
        {
            // A look that does not fit the mesh (a file changed since) draws it without.
            let _ = match &data.look.1 {
                // The rest shape until the next deformation is gathered into the layout.
                Some((look, mesh)) => {
                    r.renderer
                        .set_loaded_look(&r.gpu, mesh, look, &upload.positions)
                }
                None => r.renderer.set_look(&r.gpu, None, &[]),
            };
            r.look_key = Some(data.look.0);
            r.deformation_generation = u64::MAX;
            r.color_generation = u64::MAX;
        }
        if let starcages_viewport::Shading::MatCap(matcap) = data.layers.shading {
            r.renderer.set_matcap(&r.gpu, matcap);
        }
        if let Some((generation, mesh)) = &data.deformation
            && *generation != r.deformation_generation
        {
            if !r.renderer.deform_on_gpu(&r.gpu, encoder, &mesh.dofs) {
                r.renderer.set_positions(&r.gpu, mesh.positions());
            }
            r.deformation_generation = *generation;
        }
        if let Some((generation, colors)) = &data.colors
            && *generation != r.color_generation
        {
            r.renderer.set_colors(&r.gpu, colors);
            r.color_generation = *generation;
        }
        match &data.ghosts {
            Some((generation, ghosts)) if *generation != r.ghost_generation => {
                let binding = data.mesh.as_ref().and_then(|(_, m)| m.binding.clone());
                let on_gpu = r.renderer.deforms_on_gpu();
                // Where the GPU cannot deform, each ghost is deformed here on the CPU.
                let positions: Vec<Vec<Vec3>> = match (&binding, on_gpu) {
                    (Some(binding), false) => ghosts
                        .iter()
                        .map(|(dofs, _)| {
                            let mut out = vec![Vec3::ZERO; binding.operator.row_count()];
                            binding.operator.apply(dofs, &mut out);
                            out
                        })
                        .collect(),
                    _ => Vec::new(),
                };
                let shapes: Vec<Ghost<'_>> = ghosts
                    .iter()
                    .enumerate()
                    .map(|(i, (dofs, tint))| Ghost {
                        shape: match positions.get(i) {
                            Some(p) => GhostShape::Positions(p),
                            None => GhostShape::Dofs(dofs),
                        },
                        tint: *tint,
                    })
                    .collect();
                r.renderer.set_ghosts(&r.gpu, encoder, &shapes);
                r.ghost_generation = *generation;
                r.ghosts_shown = true;
            }
            Some(_) => {}
            None if r.ghosts_shown => {
                r.renderer.set_ghosts(&r.gpu, encoder, &[]);
                r.ghosts_shown = false;
                r.ghost_generation = u64::MAX;
            }
            None => {}
        }
        r.renderer.set_lines(&r.gpu, &data.lines);
        r.renderer.set_guides(&r.gpu, &data.guides);
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

/// Hands this frame's scene to the paint callback (or draws a note without wgpu).
pub fn paint(state: &EditorState, ui_state: &mut UiState, ui: &mut egui::Ui, rect: egui::Rect) {
    if !ui_state.gpu {
        ui.painter()
            .rect_filled(rect, 0.0, egui::Color32::from_gray(40));
        ui.painter().text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "3D view unavailable: no wgpu device",
            egui::FontId::proportional(16.0),
            egui::Color32::LIGHT_GRAY,
        );
        return;
    }
    let scene = &state.doc.scene;
    let mut style = state.view.cage_style(&state.selection, &scene.cages);
    state.rig_warnings.mark(scene, &mut style);
    // The 3D cursor, once placed or while it is the pivot.
    let cursor_shown =
        state.view.cursor.is_some() || state.view.pivot_point == crate::state::PivotPoint::Cursor;
    if cursor_shown {
        style.cursor = Some(state.view.cursor.unwrap_or_default().as_vec3());
    }
    if state.posing_controls() {
        // Pose mode poses the controls: the leaf vertices under them step back.
        use crate::state::{LeafVertices, leaf_only_vertices};
        match state.view.leaf_vertices {
            LeafVertices::Shown => {}
            LeafVertices::Small => style.quiet_vertices = leaf_only_vertices(&scene.cages),
            LeafVertices::Hidden => style.hidden_vertices = leaf_only_vertices(&scene.cages),
        }
    }
    if state.mode == crate::state::EditMode::Rig {
        let rest = scene.mesh.welded_positions();
        style.selected_points = (state.selection.mesh_vertices.iter())
            .filter_map(|&v| rest.get(v as usize))
            .map(|p| p.as_vec3())
            .collect();
    }
    let shown = state.shown_positions();
    let mut lines = cage_lines(&scene.cages, shown, &style);
    // Rig mode edits the rest cages; the current pose, where it differs, is ghosted over them.
    if state.mode == crate::state::EditMode::Rig && scene.pose != scene.cages.vertices {
        lines.extend(ghost_lines(
            &scene.cages,
            &scene.pose,
            &scene.cages.vertices,
            &style.hidden,
        ));
    }
    let lines = Arc::new(lines);
    let dots = Arc::new(cage_dots(&scene.cages, shown, &style));
    let (lo, hi) = scene.mesh.bounds();
    let guides = Arc::new(ground_grid(lo.as_vec3(), hi.as_vec3()));
    let key = MeshKey {
        document: state.document_id,
        generation: state.generations.mesh,
    };
    let mesh = match &ui_state.mesh_upload.0 {
        Some((k, m)) if *k == key => (key, Arc::clone(m)),
        _ => {
            let upload = Arc::new(MeshUpload {
                positions: scene.mesh.welded_positions_f32(),
                triangles: scene.mesh.welded_triangles().to_vec(),
                binding: state.rig.as_ref().map(|rig| Arc::clone(&rig.binding)),
            });
            ui_state.mesh_upload.0 = Some((key, Arc::clone(&upload)));
            (key, upload)
        }
    };
    let deformation = state.rig.as_ref().map(|rig| match state.mode {
        // Rig mode shows the mesh at rest: the binding's own rest positions (for the rest
        // cages it was made for), under a generation of their own.
        crate::state::EditMode::Rig => (u64::MAX - 1, rig.rest_view()),
        crate::state::EditMode::Pose => (state.generations.deformation, rig.mesh()),
    });
    let mut layers = state.view.layers;
    // An influence map shows over any shading.
    layers.vertex_colors = state.view.influence != crate::state::InfluenceChoice::None;
    let ghosts = ghosts_of(state, &mut ui_state.ghosts);
    let data = FrameData {
        camera: state.view.camera,
        layers,
        lines,
        dots,
        guides,
        mesh: Some(mesh),
        deformation,
        colors: state.map.colors(),
        look: look_upload(state, &mut ui_state.look_upload),
        ghosts,
    };
    ui.painter().add(egui_wgpu::Callback::new_paint_callback(
        rect,
        ViewportCallback {
            data,
            size_points: rect.size(),
        },
    ));
}
