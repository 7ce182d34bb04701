//! `starcages-bench frame`: the editor's whole 3D frame as the viewport draws it — the
//! deformation, the shaded mesh, the cages, and in the richer variants the mesh file's look
//! (Textured shading) and ghosts of the animation, each ghost deformed again every frame as
//! in playback — timed end to end (recorded, submitted, waited for) on whatever adapter wgpu
//! picks. Variants are timed in the same run, so their ratios compare like with like:
//!
//! * `plain`: Solid shading, no look, no ghosts (the path every mesh takes);
//! * `plain_with_look`: Solid shading on a mesh whose look is uploaded (the look must cost
//!   the plain path nothing);
//! * `textured`: Textured shading (the gather into the file's layout, two materials, one with
//!   a 2048² image);
//! * `textured_ghosts`: Textured shading and four ghosts.

use clap::Args;
use glam::{DVec3, Vec2, Vec3};
use serde::Serialize;
use starcages_core::BindControl;
use starcages_core::generate::demo::demo_scene;
use starcages_core::mesh::look::{LoadedLook, Material, MeshLook, Rgba8Image, UvOrigin};
use starcages_core::star::StarBinding;
use starcages_viewport::framing_camera;
use starcages_viewport::gpu::{
    Ghost, GhostShape, GpuContext, Layers, OFFSCREEN_FORMAT, SceneRenderer, Shading, ViewTarget,
};

use starcages_cli::InputError;
use starcages_cli::progress::with_progress;

/// Arguments of `starcages-bench frame`.
#[derive(Debug, Args)]
pub struct BenchFrameArgs {
    /// The demo scene (`starcages-cli demo --list`); its first named pose is drawn.
    #[arg(long, default_value = "creature")]
    demo: String,
    /// Its detail (prism: 7 is about a million triangles).
    #[arg(long, default_value_t = 1.0)]
    detail: f64,
    /// Frames timed per variant (the median is reported).
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(i64).range(1..=10_000))]
    frames: i64,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1400, value_parser = clap::value_parser!(u32).range(16..=8192))]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 900, value_parser = clap::value_parser!(u32).range(16..=8192))]
    height: u32,
    /// Print JSON (otherwise lines of text).
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct Report {
    adapter: String,
    device_type: String,
    backend: String,
    demo: String,
    triangles: usize,
    vertices: usize,
    width: u32,
    height: u32,
    samples: u32,
    deforms_on_gpu: bool,
    ghosts: usize,
    /// Median milliseconds of a whole frame per variant.
    plain_ms: f64,
    plain_with_look_ms: f64,
    textured_ms: f64,
    textured_ghosts_ms: f64,
}

/// The median of `frames` runs after one run that warms the pipelines and buffers up.
fn median_ms(frames: usize, mut run: impl FnMut()) -> f64 {
    run();
    crate::bench_gpu::median_ms(frames, run)
}

/// A checker image `side` pixels wide, as an artist's base colour map stands in.
fn checker(side: u32) -> Rgba8Image {
    let mut pixels = Vec::with_capacity((side * side * 4) as usize);
    for y in 0..side {
        for x in 0..side {
            let light = ((x / 64) + (y / 64)) % 2 == 0;
            pixels.extend(if light {
                [235, 225, 210, 255]
            } else {
                [170, 60, 40, 255]
            });
        }
    }
    Rgba8Image {
        width: side,
        height: side,
        pixels,
    }
}

/// A look for a mesh without one: UVs by longitude and height around the mesh's centre (the
/// demo meshes have none), the upper half of the triangles wearing a 2048² image, the lower
/// half a plain colour.
fn synthetic_look(mesh: &starcages_core::mesh::Mesh) -> (starcages_core::mesh::Mesh, LoadedLook) {
    let (lo, hi) = mesh.bounds();
    let centre = (lo + hi) * 0.5;
    let uvs: Vec<Vec2> = mesh
        .positions()
        .iter()
        .map(|p| {
            let d = *p - centre;
            let u = (d.y.atan2(d.x) / std::f64::consts::TAU + 0.5) as f32;
            let v = ((p.z - lo.z) / (hi.z - lo.z).max(1e-12)) as f32;
            Vec2::new(u, v)
        })
        .collect();
    let with_uvs = starcages_core::mesh::Mesh::new(
        mesh.positions().to_vec(),
        mesh.triangles().to_vec(),
        None,
        Some(uvs),
    )
    .unwrap_or_else(|_| mesh.clone());
    let count = with_uvs.triangles().len();
    let look = MeshLook {
        materials: vec![
            Material {
                name: "skin".to_owned(),
                base_color: [1.0; 4],
                texture: None,
            },
            Material {
                name: "paint".to_owned(),
                base_color: [0.3, 0.5, 0.8, 1.0],
                texture: None,
            },
        ],
        triangle_materials: (0..count).map(|t| u32::from(t >= count / 2)).collect(),
        uv_origin: UvOrigin::TopLeft,
        notes: Vec::new(),
    };
    let loaded = LoadedLook {
        look,
        images: vec![Some(checker(2048)), None],
        problems: Vec::new(),
    };
    (with_uvs, loaded)
}

/// Runs the command.
pub fn run(args: &BenchFrameArgs) -> anyhow::Result<()> {
    let frames = usize::try_from(args.frames).unwrap_or(1);
    if !(0.1..=16.0).contains(&args.detail) {
        return Err(InputError(format!(
            "--detail {} is out of range; use 0.1 to 16",
            args.detail
        ))
        .into());
    }
    let scene = demo_scene(&args.demo, args.detail).ok_or_else(|| {
        InputError(format!(
            "no demo called '{}'; `starcages-cli demo --list` lists them",
            args.demo
        ))
    })?;
    let pose = scene
        .poses
        .values()
        .next()
        .cloned()
        .unwrap_or_else(|| scene.pose.clone());
    let control = BindControl::default();
    let binding = with_progress("binding", &control, || {
        StarBinding::bind_scene(&scene, &control)
    })
    .map_err(|e| InputError(e.to_string()))?;
    let rest = &scene.cages.vertices;
    let gpu = GpuContext::headless()?;
    let samples = if gpu.msaa4 { 4 } else { 1 };
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT, samples);
    let rest_mesh: Vec<Vec3> = scene.mesh.welded_positions_f32();
    let triangles = scene.mesh.welded_triangles();
    renderer.set_mesh(&gpu, &rest_mesh, triangles, Some(&binding.operator));
    let style = starcages_viewport::layers::CageStyle::default();
    renderer.set_lines(
        &gpu,
        &starcages_viewport::layers::cage_lines(&scene.cages, &pose, &style),
    );
    renderer.set_dots(
        &gpu,
        &starcages_viewport::layers::cage_dots(&scene.cages, &pose, &style),
    );
    let target = ViewTarget::new(&gpu, args.width, args.height, samples);
    let camera = framing_camera(&scene, &pose);
    let size = Vec2::new(args.width as f32, args.height as f32);
    let on_gpu = renderer.deforms_on_gpu();
    // The frame's pose and four ghosts between the rest and it, as shapes the renderer takes.
    let shape_of = |cages: &[DVec3]| {
        if on_gpu {
            binding.operator.dofs(rest, cages)
        } else {
            binding.deform(rest, cages)
        }
    };
    let ghost_poses: Vec<Vec<DVec3>> = [0.2, 0.4, 0.6, 0.8]
        .iter()
        .map(|t| {
            rest.iter()
                .zip(&pose)
                .map(|(a, b)| a.lerp(*b, *t))
                .collect()
        })
        .collect();
    // Shapes are computed once (the editor caches them per frame): a frame times the GPU's
    // work and the CPU's recording, not the pose evaluation.
    let shape = shape_of(&pose);
    let ghost_shapes: Vec<Vec<Vec3>> = ghost_poses.iter().map(|g| shape_of(g)).collect();
    let frame = |renderer: &mut SceneRenderer, layers: &Layers, ghosts: bool| {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        if !renderer.deform_on_gpu(&gpu, &mut encoder, &shape) {
            renderer.set_positions(&gpu, &shape);
        }
        if ghosts {
            let list: Vec<Ghost<'_>> = ghost_shapes
                .iter()
                .enumerate()
                .map(|(i, s)| Ghost {
                    shape: if on_gpu {
                        GhostShape::Dofs(s)
                    } else {
                        GhostShape::Positions(s)
                    },
                    tint: if i < 2 {
                        [0.95, 0.38, 0.28, 0.4]
                    } else {
                        [0.28, 0.55, 0.98, 0.4]
                    },
                })
                .collect();
            renderer.set_ghosts(&gpu, &mut encoder, &list);
        }
        renderer.set_camera(&gpu, &camera, size, layers);
        target.render(&mut encoder, renderer, layers);
        gpu.queue.submit([encoder.finish()]);
        gpu.wait().ok();
    };
    let solid = Layers::default();
    let textured = Layers {
        shading: Shading::Textured,
        ..Layers::default()
    };
    let plain_ms = median_ms(frames, || frame(&mut renderer, &solid, false));
    let (look_mesh, look) = synthetic_look(&scene.mesh);
    renderer
        .set_loaded_look(&gpu, &look_mesh, &look, &rest_mesh)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let plain_with_look_ms = median_ms(frames, || frame(&mut renderer, &solid, false));
    let textured_ms = median_ms(frames, || frame(&mut renderer, &textured, false));
    let textured_ghosts_ms = median_ms(frames, || frame(&mut renderer, &textured, true));
    let ghosts = renderer.ghost_count();
    let info = &gpu.adapter_info;
    let report = Report {
        adapter: info.name.clone(),
        device_type: format!("{:?}", info.device_type),
        backend: format!("{:?}", info.backend),
        demo: args.demo.clone(),
        triangles: triangles.len(),
        vertices: rest_mesh.len(),
        width: args.width,
        height: args.height,
        samples,
        deforms_on_gpu: on_gpu,
        ghosts,
        plain_ms,
        plain_with_look_ms,
        textured_ms,
        textured_ghosts_ms,
    };
    if args.json {
        starcages_cli::output::line(serde_json::to_string_pretty(&report)?)?;
    } else {
        starcages_cli::output::line(format_args!(
            "{} ({}, {}): {} {} triangles at {}×{} ({} samples), deform on GPU: {}\n\
             whole frame (median of {frames}): plain {:.2} ms, plain with a look {:.2} ms, \
             textured {:.2} ms, textured + {} ghosts {:.2} ms",
            report.adapter,
            report.device_type,
            report.backend,
            report.demo,
            report.triangles,
            report.width,
            report.height,
            report.samples,
            report.deforms_on_gpu,
            report.plain_ms,
            report.plain_with_look_ms,
            report.textured_ms,
            report.ghosts,
            report.textured_ghosts_ms,
        ))?;
    }
    Ok(())
}
