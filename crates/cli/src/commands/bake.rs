//! `starcages-cli bake`: the scene's animation (or cage positions per frame from another
//! tool's point cache) through one binding into a point cache (PC2, MDD) or an animated glTF.

use starcages_core::anim::SampleTimes;
use std::io::{IsTerminal as _, Write as _};
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use glam::{DVec3, Vec3};
use starcages_core::BindControl;
use starcages_core::bake::FrameDeformer;
use starcages_core::posing::PoseRequest;
use starcages_core::scene::{Scene, UpAxis};
use starcages_io::ExportLayout;
use starcages_io::{MorphAnimation, PointCacheFormat, PointCacheWriter, read_point_cache};

use super::frames::{SampleArgs, animation_samples};
use crate::InputError;

/// Arguments of `bake`.
#[derive(Debug, Args)]
pub struct BakeArgs {
    /// Scene file.
    scene: PathBuf,
    /// File to write: .pc2 or .mdd (the vertices of `deform --out x.obj`, in its order and the
    /// mesh file's axes), or .glb / .gltf (the mesh with one morph target per frame).
    #[arg(long)]
    out: PathBuf,
    #[command(flatten)]
    samples: SampleArgs,
    /// Cage vertex positions per frame from another tool (PC2 or MDD in the vertex order and
    /// axes `starcages-cli cages` writes) drive the rig instead of the scene's animation.
    #[arg(long, value_name = "CAGES.pc2|.mdd")]
    cage_cache: Option<PathBuf>,
    /// Keep the binding in a cache beside the scene (SCENE.json.bind).
    #[arg(long, conflicts_with = "single_cage")]
    cache: bool,
    /// Bake with one cage (the union of the leaf cages) of this kind instead of *Cages: the
    /// single-cage baseline, for comparing bake rates.
    #[arg(long, value_parser = |s: &str| s.parse::<starcages_core::coords::CoordinateKind>())]
    single_cage: Option<starcages_core::coords::CoordinateKind>,
    /// Print the bake's frames per second and the file's size to standard error.
    #[arg(long)]
    stats: bool,
}

/// Cage positions and h per sample.
struct Samples {
    /// Scene frame of each sample.
    frames: Vec<f64>,
    /// Cage positions per sample, scene coordinates; `None`: from the animation.
    cages: Option<Vec<Vec<DVec3>>>,
    /// When the samples fall (cache headers).
    times: SampleTimes,
}

/// Where the baked frames go.
enum Output {
    Cache(PointCacheWriter, ExportLayout),
    Gltf(MorphAnimation),
}

/// Runs the command.
pub fn run(args: &BakeArgs) -> anyhow::Result<()> {
    const WRITES: [&str; 4] = ["pc2", "mdd", "glb", "gltf"];
    let inputs: Vec<&Path> = std::iter::once(args.scene.as_path())
        .chain(args.cage_cache.as_deref())
        .collect();
    super::check_output("--out", &args.out, &inputs, &WRITES)?;
    let scene = super::load(&args.scene)?;
    let label = args.scene.display().to_string();
    let checked = super::report(&scene, &label);
    if !checked.is_valid() {
        return Err(InputError(format!(
            "{label}: the scene does not validate; see the problems above"
        ))
        .into());
    }
    let mesh: Vec<&Path> = super::mesh_file(&scene).into_iter().collect();
    super::check_output("--out", &args.out, &mesh, &WRITES)?;
    let samples = samples(args, &scene, &label)?;
    let scene = match args.single_cage {
        Some(kind) => starcages_core::star::single_cage_scene(&scene, kind),
        None => scene,
    };
    // The topology validation built, unless the bind takes the single-cage baseline.
    let topology = checked.topology.filter(|_| args.single_cage.is_none());
    let binding =
        super::deform::bind(&scene, topology.as_deref(), &args.scene, args.cache, &label)?;
    let mut output = match PointCacheFormat::of(&args.out) {
        Some(format) => {
            let layout = ExportLayout::of(&scene)?;
            let writer = PointCacheWriter::create(
                &args.out,
                format,
                layout.len(&scene),
                samples.frames.len(),
                samples.times,
            )?;
            Output::Cache(writer, layout)
        }
        None => {
            // Animated glTF: Y-up by the format's rule, whatever the mesh file's axes.
            let up = UpAxis::Y;
            let rest: Vec<DVec3> = scene
                .mesh
                .positions()
                .iter()
                .map(|&p| up.from_scene(p))
                .collect();
            Output::Gltf(MorphAnimation::new(&args.out, &scene.mesh, rest)?)
        }
    };
    let seconds = starcages_core::anim::sampling::gltf_seconds(&samples.frames, samples.times.fps);
    let mut deformer = FrameDeformer::new(scene.clone(), binding);
    let control = BindControl::default();
    let start = Instant::now();
    let mut seconds_deform = 0.0;
    let progress = std::io::stderr().is_terminal();
    let count = samples.frames.len();
    for (k, &frame) in samples.frames.iter().enumerate() {
        let (cages, h) = match &samples.cages {
            Some(cages) => (cages[k].clone(), Default::default()),
            None => {
                let request = PoseRequest::frame(frame);
                let pose = super::pose::resolve(&scene, &request, &args.scene)?;
                (pose.cages, pose.h)
            }
        };
        let deform_start = Instant::now();
        let welded = deformer
            .deform(&cages, &h, &control)
            .map_err(|e| InputError(format!("{label}: frame {frame}: {e}")))?;
        seconds_deform += deform_start.elapsed().as_secs_f64();
        match &mut output {
            Output::Cache(writer, layout) => {
                let positions: Vec<Vec3> = layout
                    .positions(deformer.scene(), &welded)
                    .iter()
                    .map(|p| p.as_vec3())
                    .collect();
                writer.write_sample(&positions)?;
            }
            Output::Gltf(animation) => {
                let up = UpAxis::Y;
                let positions: Vec<DVec3> = scene
                    .mesh
                    .unweld(&welded)
                    .into_iter()
                    .map(|p| up.from_scene(p))
                    .collect();
                let seconds = seconds.get(k).copied().unwrap_or(f64::NAN);
                animation.push_frame(&scene.mesh, &positions, seconds, format!("frame {frame}"))?;
            }
        }
        if progress {
            crate::note_inline!("\rbaking: frame {frame} ({}/{count})", k + 1);
            std::io::stderr().flush().ok();
        }
    }
    match output {
        Output::Cache(writer, _) => {
            writer.finish()?;
            let first = samples.times.start_frame;
            if first != 0.0 {
                // Blender's Mesh Cache plays sample 0 at its own Frame Start (0 by default).
                crate::note!(
                    "note: in Blender's Mesh Cache modifier set Frame Start to {first} (it starts \
                     at its own Frame Start, 0 by default, not at the file's first frame), so \
                     that frame N shows frame N"
                );
            }
        }
        Output::Gltf(animation) => animation.write(&scene.mesh)?,
    }
    if progress {
        crate::note!();
    }
    if args.stats {
        let seconds = start.elapsed().as_secs_f64();
        let bytes = std::fs::metadata(&args.out).map(|m| m.len()).unwrap_or(0);
        crate::note!(
            "bake: {count} frames in {seconds:.3} s ({:.1} frames/s written; deformation alone \
             {:.1} frames/s); {} bytes ({:.2} MB)",
            count as f64 / seconds.max(1e-9),
            count as f64 / seconds_deform.max(1e-9),
            bytes,
            bytes as f64 / 1e6
        );
    }
    crate::output::line(args.out.display())?;
    Ok(())
}

/// The samples to bake: the animation's frames, or the cage cache's samples.
fn samples(args: &BakeArgs, scene: &Scene, label: &str) -> anyhow::Result<Samples> {
    let Some(path) = &args.cage_cache else {
        if scene.animation.is_empty() {
            return Err(InputError(format!(
                "{label}: the scene has no animation keys to bake; key poses in the editor, or \
                 drive the rig with --cage-cache CAGES.pc2"
            ))
            .into());
        }
        let (frames, times) = animation_samples(scene, args.samples.frames, args.samples.fps)?;
        return Ok(Samples {
            frames,
            cages: None,
            times,
        });
    };
    if args.samples.fps.is_some() {
        return Err(InputError(
            "--fps does not apply with --cage-cache: the cache's own samples are baked".into(),
        )
        .into());
    }
    let cache = read_point_cache(path, Some(scene.cages.vertices.len()), scene.animation.fps)?;
    cache.check_as_cage_animation(path)?;
    let up = scene.export_up();
    let mut frames = Vec::new();
    let mut cages = Vec::new();
    for (k, sample) in cache.samples.iter().enumerate() {
        let frame = cache.start_frame + k as f64 * cache.frame_step;
        if let Some(range) = args.samples.frames
            && !(frame >= range.first as f64 - 1e-6 && frame <= range.last as f64 + 1e-6)
        {
            continue;
        }
        frames.push(frame);
        cages.push(
            sample
                .iter()
                .map(|p| up.to_scene(p.as_dvec3()))
                .collect::<Vec<_>>(),
        );
    }
    let Some(&first) = frames.first() else {
        return Err(InputError(format!(
            "{}: no sample falls in --frames (its samples run from frame {} every {} frames)",
            path.display(),
            cache.start_frame,
            cache.frame_step
        ))
        .into());
    };
    Ok(Samples {
        frames,
        cages: Some(cages),
        times: SampleTimes {
            start_frame: first,
            frame_step: cache.frame_step,
            fps: scene.animation.fps,
        },
    })
}
