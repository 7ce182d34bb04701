//! `starcages-cli eval`: deformed positions of arbitrary points, so other objects can follow
//! the cages. Points in (one `x y z` per line), JSON out: `{"points": [[x, y, z], ...]}`, both
//! in the mesh file's axes, as every file `deform` and `cages` read and write.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;
use starcages_core::BindControl;
use starcages_core::star::{StarBinding, evaluate_points};
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
    let (mut posed, edited) = args.pose.positions(&scene, &args.scene)?;
    let scene = args.pose.method_scene(scene);
    // Edits that bend a joint keep its volume as `deform` does, which takes the mesh's binding.
    if let Some(hand_moved) = &edited
        && scene.cages.internals.iter().any(|c| !c.joint.is_empty())
    {
        let binding = StarBinding::bind_scene(&scene, &BindControl::default())
            .map_err(|e| InputError(format!("{}: {e}", args.scene.display())))?;
        super::pose::keep_joint_volumes(&scene, &binding, &mut posed, hand_moved);
    }
    let out = evaluate_points(&scene, &points, &posed, &BindControl::default())
        .map_err(|e| InputError(format!("{}: {e}", args.points.display())))?;
    let json = serde_json::to_string(&Output {
        points: out.iter().map(|&p| up.from_scene(p).to_array()).collect(),
    })?;
    crate::output::line(json)?;
    Ok(())
}
