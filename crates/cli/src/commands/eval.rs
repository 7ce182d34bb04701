//! `starcages-cli eval`: deformed positions of arbitrary points, so other objects can follow
//! the cages. Points in (one `x y z` per line), JSON out: `{"points": [[x, y, z], ...]}`, both
//! in the mesh file's axes, as every file `deform` and `cages` read and write.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;
use starcages_core::BindControl;
use starcages_core::star::evaluate_points;
use starcages_io::read_points;

use super::pose::PoseArgs;
use crate::InputError;

/// Arguments of `eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Scene file.
    scene: PathBuf,
    /// Points file: one `x y z` per line (rest positions, in the mesh file's axes, as the output);
    /// blank lines and `#` comments allowed.
    #[arg(long)]
    points: PathBuf,
    #[command(flatten)]
    pose: PoseArgs,
}

#[derive(Serialize)]
struct Output {
    points: Vec<[f64; 3]>,
}

/// Runs the command.
pub fn run(args: &EvalArgs) -> anyhow::Result<()> {
    let scene = super::load(&args.scene)?;
    let up = scene.export_up();
    let points: Vec<_> = read_points(&args.points)?
        .into_iter()
        .map(|p| up.to_scene(p))
        .collect();
    let posed = args.pose.positions(&scene, &args.scene)?;
    let scene = args.pose.method_scene(scene);
    let out = evaluate_points(&scene, &points, &posed, &BindControl::default())
        .map_err(|e| InputError(format!("{}: {e}", args.points.display())))?;
    let json = serde_json::to_string(&Output {
        points: out.iter().map(|&p| up.from_scene(p).to_array()).collect(),
    })?;
    crate::output::line(json)?;
    Ok(())
}
