//! `starcages-cli new`: assemble a scene from a mesh and an artist's cage OBJ file.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use starcages_core::coords::CoordinateKind;
use starcages_core::scene::{OutsidePolicy, Scene, SceneSettings, UpAxis};
use starcages_io::read_cage_set_obj;

/// `--outside` values.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum Outside {
    /// Mesh vertices outside every cage are an error.
    Error,
    /// They follow the nearest cage.
    Nearest,
}

/// Arguments of `new`.
#[derive(Debug, Args)]
pub struct NewArgs {
    /// Mesh file (OBJ, glTF, GLB, FBX, PLY, STL or OFF; see docs/cli.md for axes).
    mesh: PathBuf,
    /// Cage OBJ file: each `o`/`g` group is one leaf cage; shared positions are welded.
    #[arg(long)]
    cages: PathBuf,
    /// Coordinates of every cage: mvc, hc or gc.
    #[arg(long, default_value = "mvc", value_parser = |s: &str| s.parse::<CoordinateKind>())]
    kind: CoordinateKind,
    /// What to do with mesh vertices outside every cage.
    #[arg(long, value_enum, default_value = "error")]
    outside: Outside,
    /// Up axis of OBJ mesh and cage files: y (the OBJ convention, turned to StarCages' Z-up) or
    /// z (read as is). glTF meshes are always Y-up; the cage file follows the same axis.
    #[arg(long, value_parser = |s: &str| s.parse::<UpAxis>())]
    up: Option<UpAxis>,
    /// Scene file to write.
    #[arg(long)]
    out: PathBuf,
}

/// Runs the command.
pub fn run(args: &NewArgs) -> anyhow::Result<()> {
    super::check_output("--out", &args.out, &[&args.mesh, &args.cages], &["json"])?;
    let (mesh, up) = super::read_new_scene_mesh(&args.mesh, args.up)?;
    let mut cages = read_cage_set_obj(&args.cages, args.kind)?;
    for v in &mut cages.vertices {
        *v = up.to_scene(*v);
    }
    let settings = SceneSettings {
        outside: match args.outside {
            Outside::Error => OutsidePolicy::Error,
            Outside::Nearest => OutsidePolicy::Nearest,
        },
        ..Default::default()
    };
    let source = std::path::absolute(&args.mesh).unwrap_or_else(|_| args.mesh.clone());
    let scene = Scene::from_mesh_file(source, up, mesh, cages, settings);
    let summary = format!("{} cages", scene.cages.leaves.len());
    super::save_new_scene(&scene, &args.out, &summary)
}
