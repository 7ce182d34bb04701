//! `starcages-cli autocage`: a grid of box cages around any mesh, written as a scene.

use std::path::PathBuf;

use clap::Args;
use starcages_core::coords::CoordinateKind;
use starcages_core::io::read_mesh;
use starcages_core::scene::{
    AutocageOptions, MeshSource, Scene, SceneSettings, autocage, save_scene,
};

use crate::InputError;

/// Arguments of `autocage`.
#[derive(Debug, Args)]
pub struct AutocageArgs {
    /// Mesh file (OBJ, glTF or GLB).
    mesh: PathBuf,
    /// Cells along x, y and z.
    #[arg(long, num_args = 3, value_names = ["NX", "NY", "NZ"])]
    grid: Vec<u32>,
    /// Margin around the mesh, as a fraction of its largest side.
    #[arg(long, default_value_t = 0.05)]
    padding: f64,
    /// Coordinates of every cage: mvc, hc or gc.
    #[arg(long, default_value = "mvc", value_parser = |s: &str| s.parse::<CoordinateKind>())]
    kind: CoordinateKind,
    /// Scene file to write.
    #[arg(long)]
    out: PathBuf,
}

/// Runs the command.
pub fn run(args: &AutocageArgs) -> anyhow::Result<()> {
    let grid: [u32; 3] = args
        .grid
        .clone()
        .try_into()
        .map_err(|_| InputError("--grid needs three numbers: NX NY NZ".into()))?;
    if grid.iter().any(|&n| n == 0 || n > 64) {
        return Err(InputError(format!(
            "--grid {grid:?}: each count must be between 1 and 64"
        ))
        .into());
    }
    if !(0.0..=10.0).contains(&args.padding) {
        return Err(InputError(format!(
            "--padding {} is out of range; use a value in [0, 10]",
            args.padding
        ))
        .into());
    }
    let mesh = read_mesh(&args.mesh)?;
    let cages = autocage(
        &mesh,
        &AutocageOptions {
            grid,
            padding: args.padding,
            kind: args.kind,
        },
    );
    let source = std::path::absolute(&args.mesh).unwrap_or_else(|_| args.mesh.clone());
    let scene = Scene::new(
        MeshSource::File(source),
        mesh,
        cages,
        SceneSettings::default(),
    );
    save_scene(&scene, &args.out)?;
    let report = super::report(&scene, &args.out.display().to_string());
    crate::output::line(format_args!(
        "{}: {} cages over {} cells",
        args.out.display(),
        scene.cages.leaves.len(),
        grid.iter().product::<u32>()
    ))?;
    if report.is_valid() {
        Ok(())
    } else {
        Err(InputError(
            "the scene was written but does not validate; see the problems above".into(),
        )
        .into())
    }
}
