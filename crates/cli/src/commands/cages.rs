//! `starcages-cli cages`: the cages of a scene, in a pose, as one OBJ with one `o` group per
//! leaf cage over the scene's shared vertex list (so it can come back as a pose file); or the
//! cage vertices over the animation's frames as a point cache (PC2, MDD) in that same order.

use std::path::PathBuf;

use clap::Args;
use glam::Vec3;
use starcages_core::posing::{PoseRequest, PoseSource};
use starcages_io::{PointCacheFormat, PointCacheWriter, cage_set_obj_text, write_atomic};

use super::frames::{SampleArgs, animation_samples};

/// Arguments of `cages`.
#[derive(Debug, Args)]
pub struct CagesArgs {
    /// Scene file.
    scene: PathBuf,
    /// A named pose of the scene (default: the current pose); OBJ output only.
    #[arg(long)]
    pose: Option<String>,
    /// File to write, in the mesh file's axes: .obj (the cages in one pose) or .pc2 / .mdd
    /// (every cage vertex, in the scene's order, over the animation's frames).
    #[arg(long)]
    out: PathBuf,
    /// Frames and rate of a point cache.
    #[command(flatten)]
    samples: SampleArgs,
}

/// Runs the command.
pub fn run(args: &CagesArgs) -> anyhow::Result<()> {
    const WRITES: [&str; 3] = ["obj", "pc2", "mdd"];
    super::check_output("--out", &args.out, &[&args.scene], &WRITES)?;
    let scene = super::load(&args.scene)?;
    let inputs: Vec<&std::path::Path> = super::mesh_file(&scene).into_iter().collect();
    super::check_output("--out", &args.out, &inputs, &WRITES)?;
    // In the mesh file's axes, so the cages line up with the mesh in other programs.
    let up = scene.export_up();
    match PointCacheFormat::of(&args.out) {
        None => {
            if args.samples.frames.is_some() || args.samples.fps.is_some() {
                return Err(crate::InputError(
                    "--frames and --fps apply to a point cache (.pc2, .mdd), not to .obj".into(),
                )
                .into());
            }
            let request = PoseRequest::new(PoseSource::Named(args.pose.clone()));
            let pose = super::pose::resolve(&scene, &request, &args.scene)?;
            let positions: Vec<_> = pose.cages.iter().map(|&p| up.from_scene(p)).collect();
            write_atomic(
                &args.out,
                cage_set_obj_text(&scene.cages, &positions).as_bytes(),
            )?;
        }
        Some(format) => {
            if args.pose.is_some() {
                return Err(crate::InputError(
                    "--pose applies to .obj; a point cache holds the animation's frames".into(),
                )
                .into());
            }
            let (frames, times) = animation_samples(&scene, args.samples.frames, args.samples.fps)?;
            let mut writer = PointCacheWriter::create(
                &args.out,
                format,
                scene.cages.vertices.len(),
                frames.len(),
                times,
            )?;
            for &frame in &frames {
                let pose = super::pose::resolve(&scene, &PoseRequest::frame(frame), &args.scene)?;
                let positions: Vec<Vec3> = pose
                    .cages
                    .iter()
                    .map(|&p| up.from_scene(p).as_vec3())
                    .collect();
                writer.write_sample(&positions)?;
            }
            writer.finish()?;
        }
    }
    crate::output::line(format_args!("{}", args.out.display()))?;
    Ok(())
}
