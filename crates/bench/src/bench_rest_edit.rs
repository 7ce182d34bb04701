//! `starcages-bench --rest-edits SCENE`: one-vertex rest edits spread over the rig. For up
//! to 64 leaf-cage vertices (all of them, or spread evenly over their indices) it moves the
//! vertex's rest position by 1 % of its shortest edge and re-binds what that can change
//! (`StarBinding::rebind_rest_edit`, as the editor does), and reports per vertex the cages that
//! hold it, the share of mesh rows bound again and the time against a full bind from scratch,
//! split into binding the rows and the rest (topology, finding the rows, splicing).
//! The rows an edit reaches follow from eqs. 4 and 8: the rows of the cages holding the vertex
//! and, where b < 1, the rows of every cage with a border vertex whose join cage holds it.

use std::path::Path;
use std::time::Instant;

use glam::DVec3;
use serde::Serialize;
use starcages_core::BindControl;
use starcages_core::scene::Scene;
use starcages_core::star::StarBinding;

/// Most vertices edited.
const SAMPLES: usize = 64;

/// One vertex's rest edit.
#[derive(Serialize)]
struct Edit {
    vertex: u32,
    /// The leaf cages holding it.
    cages: Vec<String>,
    /// Share of the mesh rows bound again.
    rows: f64,
    /// Seconds of the re-bind.
    seconds: f64,
    /// `seconds` over a full bind's.
    share_of_bind: f64,
    /// Of `seconds`, binding the rows (placing them included).
    rows_bind_s: f64,
    /// Of `seconds`, the rest: the topology of the edited cages, finding the rows, splicing
    /// them into the operator and the join weights. An edit pays it whatever rows it reaches.
    other_s: f64,
}

#[derive(Serialize)]
struct Report {
    scene: String,
    mesh_vertices: usize,
    full_bind_s: f64,
    edits: Vec<Edit>,
    /// Share of the edited vertices whose re-bind took at most a tenth of a full bind.
    within_a_tenth: f64,
    /// Median share of rows, and of a full bind's time.
    median_rows: f64,
    median_share_of_bind: f64,
    /// Median of the costs an edit pays whatever rows it reaches (`other_s`), and its share
    /// of a full bind's time.
    median_other_s: f64,
    median_other_share_of_bind: f64,
}

/// The leaf-cage vertices edited: all, or `SAMPLES` spread evenly over them.
fn samples(scene: &Scene) -> Vec<u32> {
    let mut used: Vec<u32> = scene
        .cages
        .leaves
        .iter()
        .flat_map(|c| c.faces.iter().flatten().copied())
        .collect();
    used.sort_unstable();
    used.dedup();
    if used.len() <= SAMPLES {
        return used;
    }
    (0..SAMPLES)
        .filter_map(|k| used.get(k * used.len() / SAMPLES).copied())
        .collect()
}

/// `scene` with `vertex`'s rest position moved by 1 % of its shortest leaf-cage edge.
pub(super) fn edited(scene: &Scene, vertex: u32) -> Scene {
    let rest = &scene.cages.vertices;
    let shortest = scene
        .cages
        .leaves
        .iter()
        .flat_map(|c| &c.faces)
        .flat_map(|f| (0..f.len()).map(move |k| (f[k], f[(k + 1) % f.len()])))
        .filter(|&(a, b)| a == vertex || b == vertex)
        .map(|(a, b)| rest[a as usize].distance(rest[b as usize]))
        .fold(f64::INFINITY, f64::min);
    let mut edited = scene.clone();
    edited.cages.vertices[vertex as usize] += DVec3::new(0.6, 0.48, 0.64) * 0.01 * shortest;
    edited
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Runs the rest-edit bench on the scene at `path`.
pub fn run(path: &Path, json: bool) -> anyhow::Result<()> {
    let scene = starcages_io::load_scene(path)?;
    let name = path
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let binding = starcages_cli::commands::deform::bind(&scene, None, path, false, &name)?;
    let control = BindControl::default();
    // A full bind from scratch (no harmonic solve kept), the yardstick.
    starcages_core::coords::clear_harmonic_cache();
    let t = Instant::now();
    StarBinding::bind_scene(&scene, &control)?;
    let full_bind_s = t.elapsed().as_secs_f64();
    let rows_total = binding.operator.row_count().max(1) as f64;
    let mut edits = Vec::new();
    for vertex in samples(&scene) {
        let edited = edited(&scene, vertex);
        let rows = binding.rows_affected_by_rest_edit(&edited, &[vertex])?;
        // The unchanged harmonic cages' solves are in the cache from the full bind, as in the
        // editor; an edited harmonic cage is solved again.
        let t = Instant::now();
        let rebound = binding.rebind_rest_edit(&edited, &[vertex], &control)?;
        let seconds = t.elapsed().as_secs_f64();
        let rows_bind_s = rebound.stats.seconds_total - rebound.stats.seconds_splice;
        edits.push(Edit {
            vertex,
            cages: scene
                .cages
                .leaves
                .iter()
                .filter(|c| c.faces.iter().flatten().any(|&v| v == vertex))
                .map(|c| c.name.clone())
                .collect(),
            rows: rows.len() as f64 / rows_total,
            seconds,
            share_of_bind: seconds / full_bind_s,
            rows_bind_s,
            other_s: seconds - rows_bind_s,
        });
    }
    let count = edits.len().max(1) as f64;
    let report = Report {
        scene: name,
        mesh_vertices: binding.operator.row_count(),
        full_bind_s,
        within_a_tenth: edits.iter().filter(|e| e.share_of_bind <= 0.1).count() as f64 / count,
        median_rows: median(edits.iter().map(|e| e.rows).collect()),
        median_share_of_bind: median(edits.iter().map(|e| e.share_of_bind).collect()),
        median_other_s: median(edits.iter().map(|e| e.other_s).collect()),
        median_other_share_of_bind: median(edits.iter().map(|e| e.other_s / full_bind_s).collect()),
        edits,
    };
    if json {
        return starcages_cli::output::line(serde_json::to_string_pretty(&report)?);
    }
    starcages_cli::output::line(format!(
        "{}: {} mesh vertices, a full bind in {:.3} s; one-vertex rest edits:",
        report.scene, report.mesh_vertices, report.full_bind_s
    ))?;
    starcages_cli::output::line(format!(
        "{:>7} {:>7} {:>9} {:>9} {:>9}  cages",
        "vertex", "rows %", "seconds", "of bind %", "other s"
    ))?;
    for e in &report.edits {
        starcages_cli::output::line(format!(
            "{:>7} {:>7.1} {:>9.3} {:>9.1} {:>9.3}  {}",
            e.vertex,
            100.0 * e.rows,
            e.seconds,
            100.0 * e.share_of_bind,
            e.other_s,
            e.cages.join(", ")
        ))?;
    }
    starcages_cli::output::line(format!(
        "median: {:.0} % of the rows in {:.0} % of a full bind; {:.0} % of the edited vertices re-bind within a tenth of a full bind",
        100.0 * report.median_rows,
        100.0 * report.median_share_of_bind,
        100.0 * report.within_a_tenth
    ))?;
    starcages_cli::output::line(format!(
        "an edit's costs besides binding its rows (topology, finding the rows, splicing): median {:.1} ms, {:.0} % of a full bind",
        1e3 * report.median_other_s,
        100.0 * report.median_other_share_of_bind
    ))
}
