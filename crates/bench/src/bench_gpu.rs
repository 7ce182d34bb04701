//! `starcages-bench gpu`: per-frame cost of GPU deformation and rendering against the CPU
//! operator on the prism demo (about 200k triangles at detail 3, a million at detail 7), on
//! whatever adapter wgpu picks (a discrete GPU when there is one).

use std::time::Instant;

use clap::Args;
use glam::{Vec2, Vec3};
use serde::Serialize;
use starcages_core::BindControl;
use starcages_core::generate::demo::demo_scene;
use starcages_core::star::StarBinding;
use starcages_viewport::framing_camera;
use starcages_viewport::gpu::cpu_normals;
use starcages_viewport::gpu::{GpuContext, Layers, OFFSCREEN_FORMAT, SceneRenderer, ViewTarget};

use starcages_cli::InputError;
use starcages_cli::progress::with_progress;

/// Arguments of `starcages-bench gpu`.
#[derive(Debug, Args)]
pub struct BenchGpuArgs {
    /// Tessellation of the prism demo (3: about 200k triangles; 7: about a million).
    #[arg(long, default_value_t = 3.0)]
    detail: f64,
    /// Frames timed per measurement (the median is reported).
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(i64).range(1..=10_000))]
    frames: i64,
    /// Rendered image size for the draw timing.
    #[arg(long, default_value_t = 1920, value_parser = clap::value_parser!(u32).range(16..=8192))]
    width: u32,
    /// Print JSON (otherwise lines of text).
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct Report {
    adapter: String,
    device_type: String,
    backend: String,
    compute: bool,
    /// Whether the operator fit the device's buffer limits and deformed on the GPU; when not,
    /// `gpu_deform_ms` times the CPU path's upload.
    deforms_on_gpu: bool,
    triangles: usize,
    vertices: usize,
    nonzeros: usize,
    bind_s: f64,
    cpu_deform_ms: f64,
    cpu_normals_ms: f64,
    gpu_deform_ms: f64,
    gpu_draw_ms: f64,
    gpu_frame_fps: f64,
    cpu_to_gpu_deform_ratio: f64,
}

/// Median milliseconds of `frames` runs of `run`.
pub(crate) fn median_ms(frames: usize, mut run: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..frames.max(1))
        .map(|_| {
            let start = Instant::now();
            run();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Runs the command.
pub fn run(args: &BenchGpuArgs) -> anyhow::Result<()> {
    // In 1..=10000 (clap's range).
    let frames = usize::try_from(args.frames).unwrap_or(1);
    // Triangles grow with the square of the detail: 16 gives about 5.3 million (the big-mesh
    // issue's 5M frame).
    if !(0.1..=16.0).contains(&args.detail) {
        return Err(InputError(format!(
            "--detail {} is out of range; use 0.1 to 16 (16: about 5.3 million triangles)",
            args.detail
        ))
        .into());
    }
    let scene = demo_scene("prism", args.detail)
        .ok_or_else(|| InputError("the prism demo is missing".into()))?;
    let pose = scene
        .poses
        .get("twist")
        .cloned()
        .unwrap_or_else(|| scene.pose.clone());
    let control = BindControl::default();
    let start = Instant::now();
    let binding = with_progress("binding", &control, || {
        StarBinding::bind_scene(&scene, &control)
    })
    .map_err(|e| InputError(e.to_string()))?;
    let bind_s = start.elapsed().as_secs_f64();
    let rest = &scene.cages.vertices;
    let triangles = scene.mesh.welded_triangles();
    let mut deformed = Vec::new();
    let cpu_deform_ms = median_ms(frames, || deformed = binding.deform(rest, &pose));
    let cpu_normals_ms = median_ms(frames, || {
        std::hint::black_box(cpu_normals(&deformed, triangles));
    });
    let gpu = GpuContext::headless()?;
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT, 1);
    let rest_mesh: Vec<Vec3> = scene.mesh.welded_positions_f32();
    renderer.set_mesh(&gpu, &rest_mesh, triangles, Some(&binding.operator));
    let dofs = binding.operator.dofs(rest, &pose);
    let gpu_deform_ms = median_ms(frames, || {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        if !renderer.deform_on_gpu(&gpu, &mut encoder, &dofs) {
            renderer.set_positions(&gpu, &deformed);
        }
        gpu.queue.submit([encoder.finish()]);
        gpu.wait().ok();
    });
    let height = args.width * 9 / 16;
    let target = ViewTarget::new(&gpu, args.width, height, 1);
    let camera = framing_camera(&scene, &pose);
    let layers = Layers::default();
    renderer.set_camera(
        &gpu,
        &camera,
        Vec2::new(args.width as f32, height as f32),
        &layers,
    );
    let gpu_draw_ms = median_ms(frames, || {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        target.render(&mut encoder, &renderer, &layers);
        gpu.queue.submit([encoder.finish()]);
        gpu.wait().ok();
    });
    let info = &gpu.adapter_info;
    let report = Report {
        adapter: info.name.clone(),
        device_type: format!("{:?}", info.device_type),
        backend: format!("{:?}", info.backend),
        compute: gpu.compute,
        deforms_on_gpu: renderer.deforms_on_gpu(),
        triangles: triangles.len(),
        vertices: rest_mesh.len(),
        nonzeros: binding.operator.nonzeros(),
        bind_s,
        cpu_deform_ms,
        cpu_normals_ms,
        gpu_deform_ms,
        gpu_draw_ms,
        gpu_frame_fps: 1e3 / (gpu_deform_ms + gpu_draw_ms).max(1e-6),
        cpu_to_gpu_deform_ratio: (cpu_deform_ms + cpu_normals_ms) / gpu_deform_ms.max(1e-9),
    };
    if !report.deforms_on_gpu {
        starcages_cli::note!(
            "the operator does not fit this device's buffer limits (or it has no compute): \
             the GPU deformation column times the CPU path's upload"
        );
    }
    if args.json {
        starcages_cli::output::line(serde_json::to_string_pretty(&report)?)?;
    } else {
        starcages_cli::output::line(format_args!(
            "{} ({}, {}): {} triangles, {} non-zeros; bind {:.2} s\n\
             CPU deform {:.2} ms + normals {:.2} ms; GPU deform+normals {:.2} ms, draw {:.2} ms \
             ({:.0} fps); CPU/GPU deformation {:.1}×",
            report.adapter,
            report.device_type,
            report.backend,
            report.triangles,
            report.nonzeros,
            report.bind_s,
            report.cpu_deform_ms,
            report.cpu_normals_ms,
            report.gpu_deform_ms,
            report.gpu_draw_ms,
            report.gpu_frame_fps,
            report.cpu_to_gpu_deform_ratio
        ))?;
    }
    Ok(())
}
