//! `starcages-cli cages`: the leaf cages of a scene, in a pose, as one OBJ with one `o` group
//! per cage over the scene's shared vertex list (so it can come back as a pose file).

use std::path::PathBuf;

use clap::Args;
use starcages_core::io::{cage_set_obj_text, write_atomic};

/// Arguments of `cages`.
#[derive(Debug, Args)]
pub struct CagesArgs {
    /// Scene file.
    scene: PathBuf,
    /// A named pose of the scene (default: the current pose).
    #[arg(long)]
    pose: Option<String>,
    /// OBJ file to write.
    #[arg(long)]
    out: PathBuf,
}

/// Runs the command.
pub fn run(args: &CagesArgs) -> anyhow::Result<()> {
    super::check_output("--out", &args.out, &[&args.scene], &["obj"])?;
    let scene = super::load(&args.scene)?;
    let inputs: Vec<&std::path::Path> = super::mesh_file(&scene).into_iter().collect();
    super::check_output("--out", &args.out, &inputs, &["obj"])?;
    let positions = super::pose::named_pose(&scene, args.pose.as_deref(), &args.scene)?;
    // In the mesh file's axes, so the cages line up with the mesh in other programs.
    let up = scene.export_up();
    let positions: Vec<_> = positions.iter().map(|&p| up.from_scene(p)).collect();
    write_atomic(
        &args.out,
        cage_set_obj_text(&scene.cages, &positions).as_bytes(),
    )?;
    crate::output::line(format_args!("{}", args.out.display()))?;
    Ok(())
}
