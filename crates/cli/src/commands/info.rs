//! `starcages-cli info`: the mesh's counts and bounds, per cage its name, kind, h, level,
//! parent and vertex/face counts, and per control its limb, side, parent and pivot.

use std::collections::BTreeSet;
use std::path::PathBuf;

use clap::Args;
use serde::Serialize;
use starcages_core::coords::CoordinateKind;
use starcages_core::scene::{MeshSource, Scene, rig_names};

/// Arguments of `info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Scene file.
    scene: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct MeshInfo {
    source: String,
    /// Up axis of the mesh file ("y": turned to the scene's Z-up; "z": read as is).
    up_axis: &'static str,
    vertices: usize,
    welded_vertices: usize,
    triangles: usize,
    bounds_min: [f64; 3],
    bounds_max: [f64; 3],
}

#[derive(Serialize)]
struct CageInfo {
    name: String,
    kind: CoordinateKind,
    h: Option<f64>,
    level: &'static str,
    depth: usize,
    parent: Option<String>,
    vertices: usize,
    faces: usize,
}

/// A control: an internal cage with a pivot (the auto rig's `<limb>.<n>` and `root`).
#[derive(Serialize)]
struct ControlInfo {
    name: String,
    /// The limb it belongs to (its name without the segment number); none for `root`.
    limb: Option<String>,
    /// "L" or "R" (Blender's `.L` on +X), none on the centre line.
    side: Option<&'static str>,
    /// The internal cage carrying it (forward kinematics).
    parent: Option<String>,
    /// The joint it turns about, at rest, in the scene's Z-up frame (as `--apply` takes axes).
    pivot: [f64; 3],
    /// Leaf vertices of its joint ring (they turn half as far, as a mitre).
    joint_vertices: usize,
}

#[derive(Serialize)]
struct Info {
    mesh: MeshInfo,
    cage_vertices: usize,
    cages: Vec<CageInfo>,
    controls: Vec<ControlInfo>,
    poses: Vec<String>,
}

/// The limb and side a control's name says: `leg.L.2` is segment 2 of limb `leg.L`, on the
/// left.
fn limb_and_side(name: &str) -> (Option<String>, Option<&'static str>) {
    let Some(limb) = rig_names::limb_of_control(name) else {
        return (None, None);
    };
    let side = match rig_names::role_and_side(limb).1 {
        Some("L") => Some("L"),
        Some("R") => Some("R"),
        _ => None,
    };
    (Some(limb.to_owned()), side)
}

fn info(scene: &Scene) -> Info {
    let (lo, hi) = scene.mesh.bounds();
    let set = &scene.cages;
    let vertex_sets: Vec<BTreeSet<u32>> = set
        .leaves
        .iter()
        .map(|c| &c.faces)
        .chain(set.internals.iter().map(|c| &c.faces))
        .map(|faces| faces.iter().flatten().copied().collect())
        .collect();
    let leaves = set.leaves.len();
    // The parent of a cage: the first internal cage owning one of its vertices.
    let parent = |cage: usize| {
        set.internals
            .iter()
            .find(|i| i.owns.iter().any(|v| vertex_sets[cage].contains(v)))
            .map(|i| i.name.clone())
    };
    // Depth: 0 for leaves; an internal cage is one above the deepest cage it drives.
    let mut depth = vec![0usize; vertex_sets.len()];
    for _ in 0..set.internals.len() {
        for (k, internal) in set.internals.iter().enumerate() {
            let driven = (0..vertex_sets.len())
                .filter(|&c| {
                    c != leaves + k && internal.owns.iter().any(|v| vertex_sets[c].contains(v))
                })
                .map(|c| depth[c])
                .max();
            depth[leaves + k] = driven.map_or(1, |d| d + 1).min(set.internals.len() + 1);
        }
    }
    let mut cages: Vec<CageInfo> = set
        .leaves
        .iter()
        .enumerate()
        .map(|(c, cage)| CageInfo {
            name: cage.name.clone(),
            kind: cage.kind,
            h: Some(scene.cage_h(c)),
            level: "leaf",
            depth: 0,
            parent: parent(c),
            vertices: vertex_sets[c].len(),
            faces: cage.faces.len(),
        })
        .collect();
    cages.extend(set.internals.iter().enumerate().map(|(k, cage)| CageInfo {
        name: cage.name.clone(),
        kind: cage.kind,
        h: None,
        level: "internal",
        depth: depth[leaves + k],
        parent: parent(leaves + k),
        vertices: vertex_sets[leaves + k].len(),
        faces: cage.faces.len(),
    }));
    let controls = set
        .internals
        .iter()
        .enumerate()
        .filter_map(|(k, cage)| {
            let pivot = cage.pivot?;
            let (limb, side) = limb_and_side(&cage.name);
            Some(ControlInfo {
                name: cage.name.clone(),
                limb,
                side,
                parent: parent(leaves + k),
                pivot: pivot.to_array(),
                joint_vertices: cage.joint.len(),
            })
        })
        .collect();
    Info {
        mesh: MeshInfo {
            source: match &scene.mesh_source {
                MeshSource::File(path) => path.display().to_string(),
                MeshSource::Embedded => "embedded".into(),
            },
            up_axis: scene.mesh_up.name(),
            vertices: scene.mesh.positions().len(),
            welded_vertices: scene.mesh.welded_positions().len(),
            triangles: scene.mesh.triangles().len(),
            bounds_min: lo.to_array(),
            bounds_max: hi.to_array(),
        },
        cage_vertices: set.vertices.len(),
        cages,
        controls,
        poses: scene.poses.keys().cloned().collect(),
    }
}

/// Runs the command.
pub fn run(args: &InfoArgs) -> anyhow::Result<()> {
    let scene = super::load(&args.scene)?;
    let info = info(&scene);
    if args.json {
        crate::output::line(starcages_core::scene::to_pretty_json(
            &serde_json::to_value(&info)?,
        ))?;
        return Ok(());
    }
    let m = &info.mesh;
    crate::output::line(format_args!(
        "mesh: {} ({} vertices, {} welded, {} triangles; file {}-up)",
        m.source,
        m.vertices,
        m.welded_vertices,
        m.triangles,
        m.up_axis.to_uppercase()
    ))?;
    crate::output::line(format_args!(
        "bounds: {:?} .. {:?}",
        m.bounds_min, m.bounds_max
    ))?;
    crate::output::line(format_args!(
        "cage vertices: {}; poses: {}",
        info.cage_vertices,
        info.poses.join(", ")
    ))?;
    crate::output::line(format_args!(
        "{:<20} {:<4} {:>5} {:<9} {:<16} {:>8} {:>6}",
        "cage", "kind", "h", "level", "parent", "vertices", "faces"
    ))?;
    for c in &info.cages {
        let h = c.h.map_or("-".to_owned(), |h| format!("{h:.3}"));
        let level = if c.level == "leaf" {
            "leaf".to_owned()
        } else {
            format!("internal{}", c.depth)
        };
        crate::output::line(format_args!(
            "{:<20} {:<4} {:>5} {:<9} {:<16} {:>8} {:>6}",
            c.name,
            c.kind.short_name(),
            h,
            level,
            c.parent.as_deref().unwrap_or("-"),
            c.vertices,
            c.faces
        ))?;
    }
    if !info.controls.is_empty() {
        crate::output::line(format_args!(
            "{:<20} {:<16} {:<4} {:<16} {}",
            "control", "limb", "side", "parent", "pivot (Z-up)"
        ))?;
    }
    for c in &info.controls {
        crate::output::line(format_args!(
            "{:<20} {:<16} {:<4} {:<16} {:.4} {:.4} {:.4}",
            c.name,
            c.limb.as_deref().unwrap_or("-"),
            c.side.unwrap_or("-"),
            c.parent.as_deref().unwrap_or("-"),
            c.pivot[0],
            c.pivot[1],
            c.pivot[2]
        ))?;
    }
    Ok(())
}
