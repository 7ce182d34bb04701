//! `starcages-bench --drags SCENE`: what one update of a drag of each internal cage costs,
//! through core's `LiveRig`, the code the editor drives. Each internal cage's vertices are
//! turned about their centre in small steps through the hierarchy; per update it times the
//! hierarchy's propagation, the sparse path (`LiveRig::redeform_rows`: the moved columns'
//! DOFs, then the rows they touch, or the whole product when those hold most weights) and the
//! driver map (`LiveRig::redeform_drag`, its map built by the drag's first update), and checks
//! that both give the same mesh; and the editor's whole update (`LiveRig::move_vertices`: the
//! hierarchy, the bent joints' volume and the mesh).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use glam::{DQuat, DVec3};
use serde::Serialize;
use starcages_core::hierarchy::Hierarchy;
use starcages_core::live::LiveRig;
use starcages_core::scene::Scene;
use starcages_core::star::{DriverMap, StarBinding};

/// Updates timed per internal cage (the best is reported: this VM's timings are noisy).
const UPDATES: usize = 12;

/// One internal cage's drag.
#[derive(Serialize)]
struct Drag {
    cage: String,
    /// Its vertices, moved by hand.
    drivers: usize,
    /// Cage vertices that follow them through the hierarchy.
    followers: usize,
    /// Mesh rows that move.
    rows: usize,
    /// Per update: the hierarchy's propagation.
    hierarchy_ms: f64,
    /// Per update: the sparse path (`apply_after_move`) with the DOFs.
    sparse_ms: f64,
    /// Per update: the editor's whole update (`LiveRig::move_vertices` in a drag): the
    /// hierarchy, the bent joints' volume (`joint_volume`) and the mesh.
    update_ms: f64,
    /// Per update: the driver map with the DOFs; none where the drag has no map (a Green
    /// cage on the way).
    map_ms: Option<f64>,
    /// Building the map once, after the drag's first update.
    map_build_ms: Option<f64>,
    /// Largest distance between the two paths' meshes over the mesh's diagonal.
    map_error: Option<f64>,
}

#[derive(Serialize)]
struct Report {
    scene: String,
    mesh_vertices: usize,
    nonzeros: usize,
    bind_s: f64,
    drags: Vec<Drag>,
}

fn milliseconds(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// The moves that turn `drivers` (at `start`) by `angle` about z through their centre.
fn turned(drivers: &[u32], start: &[DVec3], angle: f64) -> Vec<(u32, DVec3)> {
    let centre = start.iter().sum::<DVec3>() / start.len().max(1) as f64;
    let turn = DQuat::from_rotation_z(angle);
    drivers
        .iter()
        .zip(start)
        .map(|(&d, &p)| (d, centre + turn * (p - centre)))
        .collect()
}

/// Times a drag of internal cage `index` through two live rigs, as the editor drives them: one
/// updating the rows the moves touch at every step, one following the drag's driver map.
fn bench_drag(
    scene: &Scene,
    binding: &Arc<StarBinding>,
    index: usize,
    diagonal: f64,
) -> anyhow::Result<Drag> {
    let bound_for = (scene.cages.clone(), scene.settings);
    let mut sparse = LiveRig::new(
        Arc::clone(binding),
        Hierarchy::bind(scene)?,
        bound_for.clone(),
        scene,
    );
    let mut through_map = LiveRig::new(
        Arc::clone(binding),
        Hierarchy::bind(scene)?,
        bound_for,
        scene,
    );
    let name = &scene.cages.internals[index].name;
    let drivers = scene.cages.cage_vertices(name).unwrap_or_default();
    let start: Vec<DVec3> = drivers.iter().map(|&d| scene.pose[d as usize]).collect();
    // The CPU mesh as something reads it (the editor's picking, maps, export; a viewport
    // without compute): read once, it is kept up to date move by move.
    sparse.deformed();
    through_map.deformed();
    let mut whole = LiveRig::new(
        Arc::clone(binding),
        Hierarchy::bind(scene)?,
        (scene.cages.clone(), scene.settings),
        scene,
    );
    whole.deformed();
    let mut whole_scene = scene.clone();
    let (mut sparse_scene, mut map_scene) = (scene.clone(), scene.clone());
    // The drag's first update, as the editor makes it: the map rig builds its map there.
    let first = turned(&drivers, &start, 0.01);
    sparse.move_vertices(&mut sparse_scene, &first, false)?;
    let changed = through_map.move_vertices(&mut map_scene, &first, true)?;
    whole.move_vertices(&mut whole_scene, &first, true)?;
    // The map's construction alone, timed apart (the rig built its own above).
    let build = Instant::now();
    let sensitivity = through_map.hierarchy.driver_sensitivity(&drivers);
    let built = sensitivity.as_ref().and_then(|s| {
        DriverMap::new(
            &binding.operator,
            &drivers,
            s,
            &map_scene.pose,
            through_map.deformed(),
        )
    });
    let map_build_ms = built.as_ref().map(|_| milliseconds(build));
    let has_map = through_map.drag_map().is_some();
    let (mut hierarchy_ms, mut sparse_ms, mut map_ms) = (f64::MAX, f64::MAX, f64::MAX);
    let mut update_ms = f64::MAX;
    let mut map_error: f64 = 0.0;
    for step in 1..=UPDATES {
        let moves = turned(&drivers, &start, 0.01 * (step + 1) as f64);
        let t = Instant::now();
        let changed = sparse.hierarchy.apply(&mut sparse_scene.pose, &moves)?;
        hierarchy_ms = hierarchy_ms.min(milliseconds(t));
        let t = Instant::now();
        sparse.redeform_rows(&sparse_scene, &changed);
        sparse_ms = sparse_ms.min(milliseconds(t));
        let t = Instant::now();
        whole.move_vertices(&mut whole_scene, &moves, true)?;
        update_ms = update_ms.min(milliseconds(t));
        if has_map {
            let changed = through_map.hierarchy.apply(&mut map_scene.pose, &moves)?;
            let t = Instant::now();
            through_map.redeform_drag(&map_scene, &drivers, &changed);
            map_ms = map_ms.min(milliseconds(t));
            if through_map.drag_map().is_none() {
                anyhow::bail!("the driver map does not describe step {step} of the drag");
            }
            let worst = sparse
                .deformed()
                .iter()
                .zip(through_map.deformed().iter())
                .map(|(a, b)| f64::from((*a - *b).length()))
                .fold(0.0, f64::max);
            map_error = map_error.max(worst / diagonal);
        }
    }
    Ok(Drag {
        cage: name.clone(),
        drivers: drivers.len(),
        followers: sensitivity.map_or(changed.len(), |s| s.len()),
        rows: through_map.drag_map().map_or(0, DriverMap::row_count),
        hierarchy_ms,
        sparse_ms,
        update_ms,
        map_ms: has_map.then_some(map_ms),
        map_build_ms,
        map_error: has_map.then_some(map_error),
    })
}

/// Runs the drag bench on the scene at `path`.
pub fn run(path: &Path, json: bool) -> anyhow::Result<()> {
    let scene = starcages_io::load_scene(path)?;
    if scene.cages.internals.is_empty() {
        return Err(starcages_cli::InputError(format!(
            "{}: the scene has no internal cages to drag; make a rig with \
             `autorig --internal` or add one with `internal-cage`",
            path.display()
        ))
        .into());
    }
    let name = path
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let t = Instant::now();
    let binding = Arc::new(starcages_cli::commands::deform::bind(
        &scene, None, path, false, &name,
    )?);
    let bind_s = t.elapsed().as_secs_f64();
    let (lo, hi) = scene.mesh.bounds();
    let diagonal = (hi - lo).length().max(f64::MIN_POSITIVE);
    let mut drags = Vec::new();
    for index in 0..scene.cages.internals.len() {
        drags.push(bench_drag(&scene, &binding, index, diagonal)?);
    }
    let report = Report {
        scene: name,
        mesh_vertices: binding.operator.row_count(),
        nonzeros: binding.operator.nonzeros(),
        bind_s,
        drags,
    };
    if json {
        return starcages_cli::output::line(serde_json::to_string_pretty(&report)?);
    }
    starcages_cli::output::line(format!(
        "{}: {} mesh vertices, {} weights, bound in {:.2} s; one drag update per internal cage (best of {UPDATES}):",
        report.scene, report.mesh_vertices, report.nonzeros, report.bind_s
    ))?;
    starcages_cli::output::line(format!(
        "{:<20} {:>7} {:>9} {:>9} {:>12} {:>10} {:>10} {:>8} {:>12} {:>10}",
        "cage",
        "drivers",
        "followers",
        "rows",
        "hierarchy ms",
        "sparse ms",
        "update ms",
        "map ms",
        "map build ms",
        "map error"
    ))?;
    let or_dash = |v: Option<f64>, digits: usize| v.map_or("-".into(), |v| format!("{v:.digits$}"));
    for d in &report.drags {
        starcages_cli::output::line(format!(
            "{:<20} {:>7} {:>9} {:>9} {:>12.2} {:>10.2} {:>10.2} {:>8} {:>12} {:>10}",
            d.cage,
            d.drivers,
            d.followers,
            d.rows,
            d.hierarchy_ms,
            d.sparse_ms,
            d.update_ms,
            or_dash(d.map_ms, 2),
            or_dash(d.map_build_ms, 1),
            d.map_error.map_or("-".into(), |e| format!("{e:.1e}")),
        ))?;
    }
    Ok(())
}
