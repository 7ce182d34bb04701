//! `starcages-cli autorig`: a shape-following rig of leaf cages around any mesh (chains of
//! cages along limbs, a few across each body), written as a scene.

use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use starcages_core::BindControl;
use starcages_core::generate::{AutorigError, AutorigSettings, Mirror, autorig, autorig_settings};
use starcages_core::scene::{Scene, UpAxis};

use crate::InputError;
use crate::progress::with_progress;

/// Arguments of `autorig`.
#[derive(Debug, Args)]
pub struct AutorigArgs {
    /// Mesh file (OBJ, glTF, GLB, FBX, PLY, STL or OFF; see docs/cli.md for axes).
    mesh: PathBuf,
    /// How fine the rig is: 1 (few, coarse cages) to 5 (many, tight ones).
    #[arg(long, default_value_t = 3,
        value_parser = clap::value_parser!(u32).range(1..=i64::from(starcages_core::generate::MAX_DETAIL)))]
    detail: u32,
    /// Least distance from the mesh to the cages' outer surface, as a fraction of the mesh's
    /// bounding-box diagonal (0: as tight as the detail's grid allows).
    #[arg(long, default_value_t = 0.0)]
    margin: f64,
    /// Make the rig its own mirror image across this axis of the mesh file (x, y or z), or the
    /// most symmetric one (auto): across the plane through the origin where the mesh is centred
    /// on it (within 1 % of its width), else through the mesh's centre.
    #[arg(long, value_name = "x|y|z|auto")]
    mirror: Option<String>,
    /// Leaf cages whose name starts with one of these (comma-separated, e.g. body_3,limb2) get
    /// Green coordinates: they keep their shape.
    #[arg(long, value_delimiter = ',')]
    keep_shape: Vec<String>,
    /// Leave out the controls (the bare leaf rig): by default every limb segment gets a
    /// control `<limb>.<n>` that turns about its joint and carries the segments after it, and
    /// `root` carries the whole rig.
    #[arg(long)]
    no_controls: bool,
    /// Kept for scripts written before controls were the default: controls are made unless
    /// --no-controls is given.
    #[arg(long, hide = true)]
    internal: bool,
    /// Up axis of an OBJ mesh file: y (the OBJ convention, turned to StarCages' Z-up) or z (read
    /// as is). glTF files are always Y-up.
    #[arg(long, value_parser = |s: &str| s.parse::<UpAxis>())]
    up: Option<UpAxis>,
    /// Scene file to write.
    #[arg(long)]
    out: PathBuf,
}

/// Runs the command.
pub fn run(args: &AutorigArgs) -> anyhow::Result<()> {
    super::check_output("--out", &args.out, &[&args.mesh], &["json"])?;
    let (mesh, up) = super::read_new_scene_mesh(&args.mesh, args.up)?;
    let mirror = match args.mirror.as_deref() {
        None => Mirror::None,
        Some(name) => {
            Mirror::named(name, up).map_err(|why| InputError(format!("--mirror {why}")))?
        }
    };
    let settings = AutorigSettings {
        detail: args.detail,
        margin: args.margin,
        mirror,
        keep_shape: args.keep_shape.clone(),
        controls: !args.no_controls,
        ..AutorigSettings::default()
    };
    let control = BindControl::default();
    let rig = with_progress("auto rig", &control, || autorig(&mesh, &settings, &control));
    let rig = match rig {
        Ok(rig) => rig,
        Err(e @ (AutorigError::Setting(_) | AutorigError::NoVolume | AutorigError::Invalid(_))) => {
            return Err(InputError(format!("{}: {e}", args.mesh.display())).into());
        }
        Err(e) => return Err(e).context("auto rig"),
    };
    let source = std::path::absolute(&args.mesh).unwrap_or_else(|_| args.mesh.clone());
    let report = rig.report.clone();
    let scene = Scene::from_mesh_file(source, up, mesh, rig.cages, autorig_settings());
    let summary = format!(
        "{} leaf cages ({} vertices) along {} limbs{}{}{}",
        report.leaf_cages,
        report.leaf_vertices,
        report.limbs,
        if scene.cages.internals.is_empty() {
            String::new()
        } else {
            format!(", {} internal cages", scene.cages.internals.len())
        },
        report
            .mirror_axis
            // In the mesh file's axes, as the option takes it (the swap is its own inverse).
            .map(|a| format!(", symmetric across {}", ["x", "y", "z"][scene_axis(a, up)]))
            .unwrap_or_default(),
        match report.refinements {
            0 => String::new(),
            n => format!(
                ", on a grid refined {n}× (by a quarter each) to give separate parts closer \
                 than a cell cages of their own"
            ),
        },
    );
    let shared: Vec<&str> = report
        .shared_cages
        .iter()
        .filter_map(|&l| scene.cages.leaves.get(l))
        .map(|l| l.name.as_str())
        .collect();
    if !shared.is_empty() {
        crate::note!(
            "note: {} cages hold more than one piece of the surface ({}); a higher --detail \
             separates parts that lie close together",
            shared.len(),
            shared.join(", ")
        );
    }
    super::save_new_scene(&scene, &args.out, &summary)
}

/// The scene axis (Z-up) of an axis of the mesh file: a Y-up file's y is the scene's z and its
/// z the scene's -y.
fn scene_axis(file_axis: usize, up: UpAxis) -> usize {
    match (up, file_axis) {
        (UpAxis::Y, 1) => 2,
        (UpAxis::Y, 2) => 1,
        (_, a) => a,
    }
}
