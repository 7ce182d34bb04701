//! `starcages-cli internal-cage`: add a box internal cage (section 3.4) around chosen cage
//! vertices, as their parent, and write the scene.

use std::path::PathBuf;

use clap::Args;
use starcages_core::coords::CoordinateKind;
use starcages_core::hierarchy::{AutoInternalCage, add_auto_internal_cage};

use crate::InputError;

/// Arguments of `internal-cage`.
#[derive(Debug, Args)]
pub struct InternalCageArgs {
    /// Scene file.
    scene: PathBuf,
    /// Name of the new cage.
    #[arg(long)]
    name: String,
    /// Own the vertices of these cages (leaf or internal) that have no parent yet.
    #[arg(long, value_delimiter = ',', required_unless_present = "vertices")]
    cages: Vec<String>,
    /// Own these cage vertices (indices into the scene's cage vertex array).
    #[arg(long, value_delimiter = ',')]
    vertices: Vec<u32>,
    /// Coordinates of the new cage: mvc, hc or gc.
    #[arg(long, default_value = "mvc", value_parser = |s: &str| s.parse::<CoordinateKind>())]
    kind: CoordinateKind,
    /// Margin around the owned vertices, as a fraction of their bounding box's largest side.
    #[arg(long, default_value_t = 0.1)]
    padding: f64,
    /// Quads along x, y and z on each side of the box (1 1 1: 8 vertices).
    #[arg(long, num_args = 3, value_names = ["NX", "NY", "NZ"], default_values_t = [1, 1, 1])]
    cells: Vec<u32>,
    /// Scene file to write (may be the input).
    #[arg(long)]
    out: PathBuf,
}

/// Runs the command.
pub fn run(args: &InternalCageArgs) -> anyhow::Result<()> {
    // Writing over the scene itself is an in-place edit (atomic); its mesh is off limits.
    super::check_output("--out", &args.out, &[], &["json"])?;
    let mut scene = super::load(&args.scene)?;
    let mesh: Vec<&std::path::Path> = super::mesh_file(&scene).into_iter().collect();
    super::check_output("--out", &args.out, &mesh, &["json"])?;
    let label = args.scene.display();
    let cells = super::three_counts(&args.cells, "--cells", 16)?;
    super::check_padding(args.padding)?;
    let mut vertices = args.vertices.clone();
    for cage in &args.cages {
        let owned = scene.cages.cage_vertices(cage).ok_or_else(|| {
            InputError(format!(
                "{label}: no cage named '{cage}'; the cages are: {}",
                scene.cages.cage_names().join(", ")
            ))
        })?;
        let has_parent = |v: &u32| scene.cages.internals.iter().any(|c| c.owns.contains(v));
        vertices.extend(owned.iter().filter(|v| !has_parent(v)));
    }
    let options = AutoInternalCage {
        name: args.name.clone(),
        kind: args.kind,
        padding: args.padding,
        cells,
    };
    let index = add_auto_internal_cage(&mut scene, &options, &vertices)
        .map_err(|e| InputError(format!("{label}: {e}")))?;
    let summary = format!(
        "internal cage '{}' owns {} vertices",
        args.name,
        scene.cages.internals[index].owns.len()
    );
    super::save_new_scene(&scene, &args.out, &summary)
}
