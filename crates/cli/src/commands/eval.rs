//! `starcages-cli eval`: deformed positions of arbitrary points, so other objects can follow
//! the cages. Points in (one `x y z` per line), JSON out: `{"points": [[x, y, z], ...]}`.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;
use starcages_core::BindControl;
use starcages_core::io::read_points;
use starcages_core::star::evaluate_points;

use super::pose::PoseArgs;
use crate::InputError;

/// Arguments of `eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Scene file.
    scene: PathBuf,
    /// Points file: one `x y z` per line (rest positions); blank lines and `#` comments allowed.
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
    let points = read_points(&args.points)?;
    let posed = args.pose.positions(&scene, &args.scene)?;
    let scene = args.pose.method_scene(scene);
    let out = evaluate_points(&scene, &points, &posed, &BindControl::default())
        .map_err(|e| InputError(format!("{}: {e}", args.points.display())))?;
    let json = serde_json::to_string(&Output {
        points: out.iter().map(|p| p.to_array()).collect(),
    })?;
    crate::output::line(json)?;
    Ok(())
}
