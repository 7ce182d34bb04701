//! `starcages-cli edit`: build or change a rig with a script of operations, applied in order to
//! a scene (or to an empty scene around a mesh), validated and saved atomically. An operation
//! that cannot apply is an error naming it, and nothing is written.

use std::path::PathBuf;

use clap::Args;
use starcages_core::rig::{RigOp, apply_rig_op, parse_rig_script};
use starcages_core::scene::{CageSet, Scene, SceneSettings, UpAxis};
use starcages_io::load_scene;

/// Arguments of `edit`.
#[derive(Debug, Args)]
pub struct EditArgs {
    /// A scene (.json), or a mesh (.obj, .gltf, .glb, .ply, .stl, .off) to start a rig from nothing around it.
    input: PathBuf,
    /// Scene file to write (never the input).
    #[arg(long)]
    out: PathBuf,
    /// An operation, repeatable, applied in order (KIND and NAME at the end are optional):
    /// "add-box NAME X0 Y0 Z0 X1 Y1 Z1 KIND" (KIND: mvc, hc or gc);
    /// "extrude CAGE FACE DIST NAME" (FACE 0-based in the cage's face list, or the direction it
    /// faces: +x, -x, +y, -y, +z, -z; pushed out DIST along its outward normal; the new cage
    /// shares that face);
    /// "inset CAGE FACE THICKNESS" (a free face becomes a smaller face THICKNESS inside its
    /// edges and a ring of quads; extrude the inner face, which keeps FACE, to grow a cage
    /// that touches no other);
    /// "split CAGE x|y|z T NAME" (loop cut across the ring of quads at fraction T);
    /// "delete CAGE"; "merge A B"; "mirror CAGE NAME" (across x = 0);
    /// "fit CAGE MARGIN" (pull free vertices in to the mesh, MARGIN × its diagonal away);
    /// "rest CAGE: translate X Y Z" | "rest CAGE: rotate AX AY AZ DEG" | "rest CAGE: scale S"
    /// (about the cage's centroid; poses move along);
    /// "kind CAGE mvc|hc|gc" (its coordinates); "h CAGE|all H" (blending parameter of a cage,
    /// or the scene's default);
    /// "subdivide" (every face of every leaf cage cut into quads through its edge midpoints
    /// and centre);
    /// "weld DIST" (cage vertices within DIST become one, so cages that meet there share
    /// their border; without DIST only exactly equal ones).
    #[arg(long = "op", value_name = "OP", required_unless_present = "script")]
    ops: Vec<String>,
    /// A file of operations, one per line as --op takes them (`#` starts a comment), run before
    /// the --op ones (assets/creature/rig.ops is an example).
    #[arg(long, value_name = "FILE")]
    script: Option<PathBuf>,
    /// Up axis of an OBJ mesh given as the input (glTF is always Y-up).
    #[arg(long, value_parser = |s: &str| s.parse::<UpAxis>())]
    up: Option<UpAxis>,
}

/// Runs the command.
pub fn run(args: &EditArgs) -> anyhow::Result<()> {
    let is_scene = args
        .input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let mut inputs: Vec<&std::path::Path> = vec![&args.input];
    super::check_output("--out", &args.out, &inputs, &["json"])?;
    let mut scene = if is_scene {
        load_scene(&args.input)?
    } else {
        let (mesh, up) = super::read_new_scene_mesh(&args.input, args.up)?;
        let source = std::path::absolute(&args.input).unwrap_or_else(|_| args.input.clone());
        Scene::from_mesh_file(
            source,
            up,
            mesh,
            CageSet::default(),
            SceneSettings::default(),
        )
    };
    let mesh = super::mesh_file(&scene).map(std::path::Path::to_path_buf);
    inputs.extend(mesh.as_deref());
    super::check_output("--out", &args.out, &inputs, &["json"])?;
    // Read every operation first: a typo in the last one writes nothing. Each is named by
    // where it came from ("rig.ops line 12", "--op 2") in errors.
    let mut ops: Vec<(String, String, RigOp)> = Vec::new();
    if let Some(script) = &args.script {
        let text = starcages_io::read_text(script)?;
        let parsed = parse_rig_script(&text)
            .map_err(|e| crate::InputError(format!("{}: {e}", script.display())))?;
        let lines: Vec<&str> = text.lines().collect();
        for (line, op) in parsed {
            let source = lines.get(line - 1).map_or("", |l| l.trim()).to_owned();
            ops.push((format!("{} line {line}", script.display()), source, op));
        }
    }
    for (i, text) in args.ops.iter().enumerate() {
        let op =
            RigOp::parse(text).map_err(|e| crate::InputError(format!("--op {}: {e}", i + 1)))?;
        ops.push((format!("--op {}", i + 1), text.clone(), op));
    }
    for (place, text, op) in &ops {
        apply_rig_op(&mut scene, op).map_err(|e| {
            crate::InputError(format!("{place} '{text}': {e}; nothing was written"))
        })?;
    }
    let summary = format!(
        "{} leaf cages after {} operation(s)",
        scene.cages.leaves.len(),
        ops.len()
    );
    super::save_new_scene(&scene, &args.out, &summary)
}
