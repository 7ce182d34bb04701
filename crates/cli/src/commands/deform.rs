//! `starcages-cli deform`: bind a scene, deform its mesh into a pose, write OBJ or GLB.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use starcages_core::BindControl;
use starcages_core::star::StarBinding;
use starcages_io::CacheOutcome;
use starcages_io::write_deformed_mesh;

use super::pose::PoseArgs;
use crate::InputError;
use crate::progress::with_progress;

/// Arguments of `deform`.
#[derive(Debug, Args)]
pub struct DeformArgs {
    /// Scene file.
    scene: PathBuf,
    #[command(flatten)]
    pose: PoseArgs,
    /// Deformed mesh to write: .obj or .glb (normals recomputed).
    #[arg(long)]
    out: PathBuf,
    /// Print memory and times to standard error.
    #[arg(long)]
    stats: bool,
    /// Keep the binding in a cache beside the scene (SCENE.json.bind) and reuse it while the
    /// mesh, cages and settings are unchanged.
    #[arg(long, conflicts_with = "single_cage")]
    cache: bool,
}

/// Runs the command.
pub fn run(args: &DeformArgs) -> anyhow::Result<()> {
    let inputs: Vec<&std::path::Path> = std::iter::once(args.scene.as_path())
        .chain(args.pose.pose_file())
        .collect();
    super::check_output("--out", &args.out, &inputs, &["obj", "glb"])?;
    let super::pose::PosedScene {
        scene,
        cages: mut posed,
        label,
        topology,
        edited,
    } = args.pose.load_posed(&args.scene)?;
    let mesh: Vec<&std::path::Path> = super::mesh_file(&scene).into_iter().collect();
    super::check_output("--out", &args.out, &mesh, &["obj", "glb"])?;
    let binding = bind(&scene, topology.as_deref(), &args.scene, args.cache, &label)?;
    if let Some(hand_moved) = &edited {
        super::pose::keep_joint_volumes(&scene, &binding, &mut posed, hand_moved);
    }
    let start = Instant::now();
    let welded = binding.deform(&scene.cages.vertices, &posed);
    let seconds_frame = start.elapsed().as_secs_f64();
    let welded: Vec<glam::DVec3> = welded.iter().map(|p| p.as_dvec3()).collect();
    // In the mesh file's axes, an OBJ as a copy of its source: a rest-pose export is the
    // source file.
    write_deformed_mesh(&args.out, &scene, &welded)?;
    if args.stats {
        let s = binding.stats;
        crate::note!(
            "bind: {:.3} s (cage coordinates {:.3} s, join cages {:.3} s; the MVC/GC kernels \
             evaluated {:.2} million point·triangle pairs, the bind's floor); weights: {:.2} MB in \
             {} non-zeros (+{:.2} MB transpose); frame: {:.4} s",
            s.seconds_total,
            s.seconds_cage_coordinates,
            s.seconds_join_cages,
            s.kernel_pairs as f64 / 1e6,
            s.operator_bytes as f64 / 1e6,
            s.nonzeros,
            s.transpose_bytes as f64 / 1e6,
            seconds_frame
        );
        print_leaf_breakdown(&scene, &binding);
    }
    crate::output::line(args.out.display())?;
    Ok(())
}

/// Binds `scene` (read from `scene_path`) with a progress line, through the binding cache
/// beside the scene when `cache` is set; with `topology` where validation built it.
pub fn bind(
    scene: &starcages_core::scene::Scene,
    topology: Option<&starcages_core::star::Topology>,
    scene_path: &std::path::Path,
    cache: bool,
    label: &str,
) -> anyhow::Result<StarBinding> {
    let control = BindControl::default();
    let binding = with_progress("binding", &control, || {
        if !cache {
            return match topology {
                Some(topology) => StarBinding::bind_scene_with(scene, topology, &control),
                None => StarBinding::bind_scene(scene, &control),
            };
        }
        let (binding, outcome) = starcages_io::bind_scene_cached(scene, scene_path, &control)?;
        match outcome {
            CacheOutcome::Hit => crate::note!("{label}: binding read from its cache"),
            CacheOutcome::Written => {}
            CacheOutcome::Replaced(why) | CacheOutcome::NotWritten(why) => {
                crate::note!("warning: {why}")
            }
        }
        Ok(binding)
    })
    .map_err(|e| InputError(format!("{label}: {e}")))?;
    Ok(binding)
}

/// Per leaf cage: the mesh vertices bound to it, how many of them blend with join cages
/// (b < 1, eq. 11), their mean non-zeros per row and the leaf's share of all non-zeros; where
/// the operator's memory goes.
fn print_leaf_breakdown(scene: &starcages_core::scene::Scene, binding: &StarBinding) {
    #[derive(Default, Clone, Copy)]
    struct Leaf {
        points: usize,
        blended: usize,
        nonzeros: usize,
    }
    let mut leaves = vec![Leaf::default(); scene.cages.leaves.len()];
    let (_, row_start, _, _) = binding.operator.parts();
    for (row, &cage) in binding.cage_of.iter().enumerate() {
        let (Some(leaf), Some(start), Some(end)) = (
            leaves.get_mut(cage as usize),
            row_start.get(row),
            row_start.get(row + 1),
        ) else {
            continue;
        };
        leaf.points += 1;
        leaf.nonzeros += end.saturating_sub(*start) as usize;
        if binding.boundary_weight.get(row).is_some_and(|&b| b < 1.0) {
            leaf.blended += 1;
        }
    }
    let total = binding.operator.nonzeros().max(1) as f64;
    crate::note!(
        "{:<20} {:>4} {:>8} {:>9} {:>10} {:>10}",
        "leaf cage",
        "kind",
        "points",
        "b < 1 %",
        "nnz / row",
        "nnz share"
    );
    for (cage, leaf) in scene.cages.leaves.iter().zip(&leaves) {
        crate::note!(
            "{:<20} {:>4} {:>8} {:>9.1} {:>10.1} {:>9.1}%",
            cage.name,
            cage.kind.to_string(),
            leaf.points,
            100.0 * leaf.blended as f64 / leaf.points.max(1) as f64,
            leaf.nonzeros as f64 / leaf.points.max(1) as f64,
            100.0 * leaf.nonzeros as f64 / total,
        );
    }
}
