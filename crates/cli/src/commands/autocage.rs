//! `starcages-cli autocage`: a grid of box cages around any mesh, written as a scene.

use std::path::PathBuf;

use clap::Args;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::{AutocageOptions, DEFAULT_GRID, autocage};
use starcages_core::scene::{Scene, SceneSettings, UpAxis};

/// Arguments of `autocage`.
#[derive(Debug, Args)]
pub struct AutocageArgs {
    /// Mesh file (OBJ, glTF, GLB, FBX, PLY, STL or OFF; see docs/cli.md for axes).
    mesh: PathBuf,
    /// Cells along x, y and z.
    #[arg(long, num_args = 3, value_names = ["NX", "NY", "NZ"], default_values_t = DEFAULT_GRID,
        value_parser = clap::value_parser!(u32).range(1..=64))]
    grid: Vec<u32>,
    /// Up axis of an OBJ mesh file: y (the OBJ convention, turned to StarCages' Z-up) or z (read
    /// as is). glTF files are always Y-up.
    #[arg(long, value_parser = |s: &str| s.parse::<UpAxis>())]
    up: Option<UpAxis>,
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
    let grid = super::three_counts(&args.grid, "--grid", 64)?;
    super::check_padding(args.padding)?;
    super::check_output("--out", &args.out, &[&args.mesh], &["json"])?;
    let (mesh, up) = super::read_new_scene_mesh(&args.mesh, args.up)?;
    let cages = autocage(
        &mesh,
        &AutocageOptions {
            grid,
            padding: args.padding,
            kind: args.kind,
        },
    );
    let source = std::path::absolute(&args.mesh).unwrap_or_else(|_| args.mesh.clone());
    let scene = Scene::from_mesh_file(source, up, mesh, cages, SceneSettings::default());
    let summary = format!(
        "{} cages over {} cells",
        scene.cages.leaves.len(),
        grid.iter().product::<u32>()
    );
    super::save_new_scene(&scene, &args.out, &summary)
}
