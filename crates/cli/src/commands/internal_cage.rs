//! `starcages-cli internal-cage`: add a box internal cage (section 3.4) around chosen cage
//! vertices, as their parent, or the cages of an OBJ file as internal cages, and write the
//! scene.

use std::path::PathBuf;

use clap::Args;
use starcages_core::coords::CoordinateKind;
use starcages_core::hierarchy::{AutoInternalCage, add_auto_internal_cage, import_internal_cages};

use crate::InputError;

/// Arguments of `internal-cage`.
#[derive(Debug, Args)]
pub struct InternalCageArgs {
    /// Scene file.
    scene: PathBuf,
    /// Name of the new cage.
    #[arg(long, required_unless_present = "from")]
    name: Option<String>,
    /// Own the vertices of these cages (leaf or internal) that have no parent yet.
    #[arg(long, value_delimiter = ',', required_unless_present_any = ["vertices", "from"])]
    cages: Vec<String>,
    /// Instead of a box: every cage (o/g group) of this OBJ file becomes an internal cage,
    /// named after its group, owning the cage vertices inside it that have no parent yet. The
    /// file's axes follow the scene's mesh file (Y-up OBJ turned to Z-up).
    #[arg(long, value_name = "CAGES.obj", conflicts_with_all = ["cages", "vertices", "name"])]
    from: Option<PathBuf>,
    /// Own these cage vertices (indices into the scene's cage vertex array).
    #[arg(long, value_delimiter = ',', value_parser = clap::value_parser!(u32).range(0..))]
    vertices: Vec<u32>,
    /// Coordinates of the new cage: mvc, hc or gc.
    #[arg(long, default_value = "mvc", value_parser = |s: &str| s.parse::<CoordinateKind>())]
    kind: CoordinateKind,
    /// Margin around the owned vertices, as a fraction of their bounding box's largest side.
    #[arg(long, default_value_t = 0.1)]
    padding: f64,
    /// Quads along x, y and z on each side of the box (1 1 1: 8 vertices).
    #[arg(long, num_args = 3, value_names = ["NX", "NY", "NZ"], default_values_t = [1, 1, 1],
        value_parser = clap::value_parser!(u32).range(1..=16))]
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
    if let Some(from) = &args.from {
        return import(args, from, scene);
    }
    let name = args.name.clone().unwrap_or_default();
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
        name: name.clone(),
        kind: args.kind,
        padding: args.padding,
        cells,
    };
    let index = add_auto_internal_cage(&mut scene, &options, &vertices)
        .map_err(|e| InputError(format!("{label}: {e}")))?;
    let summary = format!(
        "internal cage '{name}' owns {} vertices",
        scene.cages.internals[index].owns.len()
    );
    super::save_new_scene(&scene, &args.out, &summary)
}

/// `--from`: the OBJ's cages as internal cages.
fn import(
    args: &InternalCageArgs,
    from: &std::path::Path,
    mut scene: starcages_core::scene::Scene,
) -> anyhow::Result<()> {
    super::check_output("--out", &args.out, &[from], &["json"])?;
    let mut set =
        starcages_io::read_cage_set_obj(from, args.kind).map_err(|e| InputError(e.to_string()))?;
    let up = scene.export_up();
    for p in &mut set.vertices {
        *p = up.to_scene(*p);
    }
    let added = import_internal_cages(&mut scene, &set, args.kind)
        .map_err(|e| InputError(format!("{}: {e}", from.display())))?;
    let names: Vec<String> = added
        .iter()
        .filter_map(|&i| scene.cages.internals.get(i))
        .map(|c| format!("'{}' owns {} vertices", c.name, c.owns.len()))
        .collect();
    let summary = format!(
        "internal cage(s) from {}: {}",
        from.display(),
        names.join(", ")
    );
    super::save_new_scene(&scene, &args.out, &summary)
}
