//! `starcages-bench`: the paper's Table II in one run: *Cages against single-cage MVC, GC
//! and HC on the demo scenes (and optionally real meshes in an automatic grid, 3×3×3 unless
//! `--grid` says otherwise): memory, bind time (cage coordinates / total), time per full frame
//! and per single cage-vertex move, plus a plain array read for the machine's memory bandwidth.
//! `--h 1.0,0.6,0.2` benches *Cages at each h (the paper's Table I); ratios include the bind.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use glam::{DVec3, Vec3};
use serde::Serialize;
use starcages_core::BindControl;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::demo::demo_scene;
use starcages_core::generate::{AutocageOptions, DEFAULT_GRID, autocage};
use starcages_core::scene::{Scene, SceneSettings};
use starcages_core::star::{StarBinding, single_cage_scene};

/// Arguments of `bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Print JSON (otherwise a table).
    #[arg(long)]
    json: bool,
    /// Tessellation of the prism demo (3 gives about 200k triangles).
    #[arg(long, default_value_t = 3.0)]
    prism_detail: f64,
    /// Also bench every OBJ in this folder with an automatic grid (e.g. ../shared/meshes).
    #[arg(long)]
    meshes: Option<PathBuf>,
    /// Cells of the automatic grid along x, y and z for `--meshes` (the paper-style tables in
    /// docs/performance.md use 4 4 4).
    #[arg(long, num_args = 3, value_names = ["NX", "NY", "NZ"], default_values_t = DEFAULT_GRID,
        value_parser = clap::value_parser!(u32).range(1..=32))]
    grid: Vec<u32>,
    /// Also bench these scene files (repeatable; named by their file stem), e.g. a rig built
    /// with `edit`.
    #[arg(long, value_name = "SCENE")]
    scene: Vec<PathBuf>,
    /// Only these scenes (names as in the output).
    #[arg(long)]
    only: Vec<String>,
    /// Skip the single-cage HC baseline (its bind is the slowest).
    #[arg(long)]
    no_hc: bool,
    /// *Cages at each of these blending parameters h (the paper's Table I), e.g. 1.0,0.6,0.2:
    /// every cage's h is set to it (per-cage and per-border overrides cleared). Default: the
    /// scenes' own h.
    #[arg(long, value_delimiter = ',', value_name = "H,H,...")]
    h: Vec<f64>,
    /// Also the paper's Table II pairs: *Cages with every leaf cage MVC against the single MVC
    /// cage, and every leaf cage GC against the single GC cage (the scene's h and join
    /// cages), with memory, bind and the time to follow one cage-vertex move (Table II's
    /// "Deform").
    #[arg(long)]
    table2: bool,
    /// Instead of the tables above, the bind's scaling on this mesh: subdivided at each of
    /// `--segments`, in the automatic 3×3×3 grid; bind time by phase, peak memory, single MVC,
    /// the default auto rig's open + rig + bind, and (with `--blender`) Blender's Mesh Deform
    /// per size (docs/performance.md).
    #[arg(long, value_name = "MESH")]
    scale: Option<PathBuf>,
    /// Edge cuts of each `--scale` size: n gives n² × the triangles (the armadillo's 25k
    /// vertices: 1, 5, 10 give 25k, 625k and 2.5M).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1,2,5,10",
        value_name = "N,N,..."
    )]
    segments: Vec<u32>,
    /// Instead of the tables above, one drag update per internal cage of this scene (an
    /// `autorig --internal` rig, say): the hierarchy's propagation, the sparse update and the
    /// driver map the editor's drags use, per update (docs/performance.md).
    #[arg(long, value_name = "SCENE", conflicts_with = "scale")]
    drags: Option<PathBuf>,
    /// Instead of the tables above, one-vertex rest edits of up to 64 leaf-cage vertices spread
    /// over this scene's rig: per vertex, its cages, the share of rows bound again and the
    /// re-bind's time against a full bind (docs/performance.md).
    #[arg(long, value_name = "SCENE", conflicts_with_all = ["scale", "drags"])]
    rest_edits: Option<PathBuf>,
    /// Python with Blender 5's `bpy` (a throw-away venv): `--scale` also times Mesh Deform
    /// (precision 5) on each size, through scripts/blender_mesh_deform_bind.py.
    #[arg(long, value_name = "PYTHON")]
    blender: Option<PathBuf>,
}

/// One pair of the paper's Table II: *Cages with every leaf cage of one kind against the single
/// cage of that kind.
#[derive(Serialize)]
struct TableTwo {
    scene: String,
    /// "mvc" or "gc".
    kind: String,
    memory_ratio: f64,
    bind_ratio: f64,
    /// Single-cage time over *Cages time to follow one cage-vertex move (Table II, column 4).
    move_ratio: f64,
    /// The same for the weights a move reads (`Row::move_nonzeros`): the ratio the timing
    /// measures, without its noise.
    move_work_ratio: f64,
    frame_ratio: f64,
}

#[derive(Serialize)]
struct Row {
    scene: String,
    method: String,
    mesh_vertices: usize,
    cages: usize,
    memory_mb: f64,
    /// Stored weights per mesh vertex: memory and frame time follow it.
    nonzeros_per_row: f64,
    /// The share of mesh vertices with b < 1 (eq. 11), which read join cages: where h decides
    /// memory and frame time.
    blended_share: f64,
    bind_cage_s: f64,
    bind_total_s: f64,
    /// Point·triangle pairs the MVC/GC kernels evaluated in the bind: its physical floor.
    kernel_pairs: u64,
    frame_s: f64,
    move_s: f64,
    /// Mean stored weights read to follow one cage-vertex move (the rows it touches, whole):
    /// the move's work, free of timing noise.
    move_nonzeros: f64,
    stream_gb_s: f64,
    /// *Cages only: seconds to re-bind after a rest-pose edit of one central cage vertex
    /// (`StarBinding::rebind_rest_edit`), and the share of rows it bound again.
    #[serde(skip_serializing_if = "Option::is_none")]
    rest_edit_s: Option<f64>,
    /// The same edit bound in full, for comparison (the edit can change join kinds).
    #[serde(skip_serializing_if = "Option::is_none")]
    rest_edit_full_s: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    rest_edit_rows: Option<f64>,
    /// *Cages only: seconds to re-bind after a leaf cage switches to harmonic coordinates (to
    /// mean value when it is harmonic already), as the editor's coordinates combo does
    /// (`StarBinding::rebind_leaves`): the slowest leaf of a small rig, else the largest
    /// (`bench_kind_switch`).
    #[serde(skip_serializing_if = "Option::is_none")]
    kind_switch_s: Option<f64>,
    /// The same switch bound at the harmonic preview resolution, as the editor shows it first
    /// (`HarmonicSettings::preview`).
    #[serde(skip_serializing_if = "Option::is_none")]
    kind_switch_preview_s: Option<f64>,
}

#[derive(Serialize)]
struct Ratios {
    scene: String,
    /// The *Cages method row these ratios are for ("stars", or "stars h=0.6").
    method: String,
    bind_vs_mvc: f64,
    /// Single MVC's kernel pairs over *Cages': the bind ratio the coordinate kernels alone
    /// would allow (the floor; harmonic solves not counted).
    kernel_floor_vs_mvc: f64,
    frame_vs_mvc: f64,
    frame_vs_gc: f64,
    move_vs_mvc: f64,
    move_vs_gc: f64,
    memory_vs_mvc: f64,
    memory_vs_gc: f64,
    /// Re-bind after a one-vertex rest edit as a share of a full bind of the edited scene.
    rest_edit_vs_bind: f64,
    /// Share of the rows that edit bound again.
    rest_edit_rows: f64,
    /// Seconds to re-bind after a leaf cage switches to HC (`Row::kind_switch_s`).
    kind_switch_s: f64,
    /// The same at the preview resolution (`Row::kind_switch_preview_s`).
    kind_switch_preview_s: f64,
}

#[derive(Serialize)]
struct Report {
    threads: usize,
    /// The SIMD backend of the MVC and GC kernels (binding time depends on it).
    simd: &'static str,
    array_read_gb_s: f64,
    rows: Vec<Row>,
    ratios: Vec<Ratios>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    table2: Vec<TableTwo>,
}

/// Best of `n` timings of `f`, in seconds.
fn best_of(n: usize, mut f: impl FnMut()) -> f64 {
    (0..n)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// GB/s of reading a 256 MB array (parallel), best of 5: 32-bit integer sums in sixteen
/// independent lanes per chunk, which compile to SIMD adds, so memory is the bound, not the
/// latency of one chain of additions.
fn array_read_bandwidth() -> f64 {
    use rayon::prelude::*;
    let data = vec![1u32; 64 << 20];
    let seconds = best_of(5, || {
        let s: u32 = data
            .par_chunks(1 << 16)
            .map(|c| {
                let mut lanes = [0u32; 16];
                for block in c.chunks_exact(16) {
                    for (acc, &v) in lanes.iter_mut().zip(block) {
                        *acc = acc.wrapping_add(v);
                    }
                }
                lanes.iter().fold(0u32, |a, &b| a.wrapping_add(b))
            })
            .reduce(|| 0, u32::wrapping_add);
        std::hint::black_box(s);
    });
    (data.len() * 4) as f64 / seconds / 1e9
}

fn bench_method(name: &str, method: &str, scene: &Scene, pose: &[DVec3]) -> anyhow::Result<Row> {
    let control = BindControl::default();
    // Every bind timed from scratch: no harmonic solve kept from an earlier run or scene.
    starcages_core::coords::clear_harmonic_cache();
    let binding = StarBinding::bind_scene(scene, &control)
        .map_err(|e| anyhow::anyhow!("{name} ({method}): {e}"))?;
    let rest = &scene.cages.vertices;
    let operator = &binding.operator;
    let mut out = vec![Vec3::ZERO; operator.row_count()];
    let x = operator.dofs(rest, pose);
    // Best of many repetitions: the fastest run is the one least disturbed by other work on
    // the machine (timings of shared virtual machines are noisy).
    let frame_s = best_of(30, || {
        let x = operator.dofs(rest, pose);
        operator.apply(&x, &mut out);
    });
    let apply_s = best_of(30, || operator.apply(&x, &mut out));
    // A single cage-vertex move (Table II's "average of the times needed for the deformation
    // of a cage vertex"): every vertex in turn, or 64 spread evenly over the whole index range
    // of a larger cage, incremental update; the mean over them, best of 5 rounds.
    let samples = move_samples(rest.len());
    let mut moved = pose.to_vec();
    let mut moved_x = operator.dofs(rest, &moved);
    let move_s = best_of(5, || {
        for &v in &samples {
            moved[v as usize] += DVec3::splat(0.01);
            operator.update_dofs(rest, &moved, &[v], &mut moved_x);
            let rows = operator.rows_touched(&operator.columns_of_moved_vertices(&[v]));
            operator.apply_rows(&rows, &moved_x, &mut out);
        }
    }) / samples.len() as f64;
    let (_, row_start, _, _) = operator.parts();
    let move_nonzeros = samples
        .iter()
        .map(|&v| {
            operator
                .rows_touched(&operator.columns_of_moved_vertices(&[v]))
                .iter()
                .map(|&r| (row_start[r as usize + 1] - row_start[r as usize]) as usize)
                .sum::<usize>()
        })
        .sum::<usize>() as f64
        / samples.len().max(1) as f64;
    let streamed = operator.byte_size() + operator.row_count() * 12 + x.len() * 12;
    let (rest_edit_s, rest_edit_full_s, rest_edit_rows) = if method.starts_with("stars") {
        match bench_rest_edit(scene, &binding) {
            Ok((seconds, full, share)) => (Some(seconds), Some(full), Some(share)),
            Err(e) => {
                // The small move can push mesh vertices that touch a cage outside it: the
                // scene's other figures stand, this one is left out.
                starcages_cli::note!("{name} ({method}): no rest-edit figure: {e}");
                (None, None, None)
            }
        }
    } else {
        (None, None, None)
    };
    let (kind_switch_s, kind_switch_preview_s) = if method.starts_with("stars") {
        let switch = |scene: &Scene| {
            bench_kind_switch(scene, &binding)
                .map_err(|e| anyhow::anyhow!("{name} ({method}), kind switch: {e}"))
        };
        let mut coarse = scene.clone();
        coarse.settings.harmonic = coarse.settings.harmonic.preview();
        (Some(switch(scene)?), Some(switch(&coarse)?))
    } else {
        (None, None)
    };
    Ok(Row {
        scene: name.to_owned(),
        method: method.to_owned(),
        mesh_vertices: scene.mesh.welded_positions().len(),
        cages: scene.cages.leaves.len(),
        memory_mb: binding.stats.operator_bytes as f64 / 1e6,
        nonzeros_per_row: operator.nonzeros() as f64 / operator.row_count().max(1) as f64,
        blended_share: binding.boundary_weight.iter().filter(|&&b| b < 1.0).count() as f64
            / binding.boundary_weight.len().max(1) as f64,
        bind_cage_s: binding.stats.seconds_cage_coordinates,
        bind_total_s: binding.stats.seconds_total,
        kernel_pairs: binding.stats.kernel_pairs,
        frame_s,
        move_s,
        move_nonzeros,
        stream_gb_s: streamed as f64 / apply_s / 1e9,
        rest_edit_s,
        rest_edit_full_s,
        rest_edit_rows,
        kind_switch_s,
        kind_switch_preview_s,
    })
}

/// The cage vertices whose moves are timed: all of them up to 256, else 64 spread evenly over
/// the index range (rigs number vertices part by part, so a prefix would time one part).
fn move_samples(vertex_count: usize) -> Vec<u32> {
    const ALL_UP_TO: usize = 256;
    const SPREAD: usize = 64;
    if vertex_count <= ALL_UP_TO {
        return (0..vertex_count as u32).collect();
    }
    (0..SPREAD)
        .map(|i| (i * vertex_count / SPREAD) as u32)
        .collect()
}

/// Seconds to re-bind after one leaf cage switches to HC (or to MVC when it is HC), best of
/// three: the slowest leaf of a rig of at most 16 leaf cages of at most 16 vertices each, else
/// the leaf holding the most mesh vertices.
fn bench_kind_switch(
    scene: &Scene,
    binding: &StarBinding,
) -> Result<f64, starcages_core::star::StarError> {
    // Every leaf of a small rig (each switch is one grid solve per eight cage vertices, so a
    // large rig would take minutes); else the leaf holding the most mesh vertices.
    let small = scene.cages.leaves.len() <= 16
        && scene.cages.leaves.iter().all(|cage| {
            let corners: std::collections::BTreeSet<u32> =
                cage.faces.iter().flatten().copied().collect();
            corners.len() <= 16
        });
    let leaves: Vec<usize> = if small {
        (0..scene.cages.leaves.len()).collect()
    } else {
        let mut held = vec![0usize; scene.cages.leaves.len()];
        for &c in &binding.cage_of {
            if let Some(count) = held.get_mut(c as usize) {
                *count += 1;
            }
        }
        (held.iter().enumerate())
            .max_by_key(|&(_, count)| *count)
            .map(|(c, _)| c)
            .into_iter()
            .collect()
    };
    let control = BindControl::default();
    let mut slowest: f64 = 0.0;
    for leaf in leaves {
        let mut switched = scene.clone();
        let cage = &mut switched.cages.leaves[leaf];
        cage.kind = if cage.kind == CoordinateKind::Harmonic {
            CoordinateKind::MeanValue
        } else {
            CoordinateKind::Harmonic
        };
        let mut best = f64::INFINITY;
        for _ in 0..3 {
            let start = Instant::now();
            binding.rebind_leaves(&switched, &[leaf], &control)?;
            best = best.min(start.elapsed().as_secs_f64());
        }
        slowest = slowest.max(best);
    }
    Ok(slowest)
}

/// Re-binds after moving the cage vertex nearest the centre of all cage vertices by 1 % of the
/// shortest cage edge at it (small enough to keep the rig valid): (seconds incremental, seconds
/// of a full bind of the edited scene, share of rows re-bound).
fn bench_rest_edit(
    scene: &Scene,
    binding: &StarBinding,
) -> Result<(f64, f64, f64), starcages_core::star::StarError> {
    let rest = &scene.cages.vertices;
    let centre = rest.iter().sum::<DVec3>() / rest.len().max(1) as f64;
    let used: Vec<u32> = scene
        .cages
        .leaves
        .iter()
        .flat_map(|c| c.faces.iter().flatten().copied())
        .collect();
    let Some(&vertex) = used.iter().min_by(|&&a, &&b| {
        rest[a as usize]
            .distance(centre)
            .total_cmp(&rest[b as usize].distance(centre))
    }) else {
        return Ok((0.0, 0.0, 0.0));
    };
    let edited = crate::bench_rest_edit::edited(scene, vertex);
    let control = BindControl::default();
    let rows = binding.rows_affected_by_rest_edit(&edited, &[vertex])?;
    let start = Instant::now();
    binding.rebind_rest_edit(&edited, &[vertex], &control)?;
    let seconds = start.elapsed().as_secs_f64();
    // The re-bind above found the unchanged cages' harmonic solves kept from the scene's
    // bind, as the editor does; the full bind is timed from scratch.
    starcages_core::coords::clear_harmonic_cache();
    let start = Instant::now();
    StarBinding::bind_scene(&edited, &control)?;
    let full = start.elapsed().as_secs_f64();
    Ok((
        seconds,
        full,
        rows.len() as f64 / binding.operator.row_count().max(1) as f64,
    ))
}

/// A smooth test pose: every cage vertex moved by a wave.
fn wave(scene: &Scene) -> Vec<DVec3> {
    scene
        .cages
        .vertices
        .iter()
        .map(|p| {
            *p + DVec3::new(
                0.05 * (2.0 * p.y).sin(),
                0.05 * (2.0 * p.z).sin(),
                0.05 * (2.0 * p.x).sin(),
            )
        })
        .collect()
}

/// Runs the command.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    if let Some(scene) = &args.rest_edits {
        return crate::bench_rest_edit::run(scene, args.json);
    }
    if let Some(scene) = &args.drags {
        return crate::bench_drag::run(scene, args.json);
    }
    if let Some(mesh) = &args.scale {
        return crate::bench_scale::run(mesh, &args.segments, args.blender.as_ref(), args.json);
    }
    if !(0.1..=6.0).contains(&args.prism_detail) {
        return Err(starcages_cli::InputError(format!(
            "--prism-detail {} is out of range; use 0.1 to 6 (6: about 2 million triangles)",
            args.prism_detail
        ))
        .into());
    }
    let grid = starcages_cli::commands::three_counts(&args.grid, "--grid", 32)?;
    if let Some(h) = args.h.iter().find(|h| !(**h > 0.0 && **h <= 1.0)) {
        return Err(starcages_cli::InputError(format!("--h {h}: each h must be in (0, 1]")).into());
    }
    // Scenes left out by `--only` are not built (the prism alone is 200k triangles).
    let mut names = Vec::new();
    let mut wanted = |name: &str| {
        names.push(name.to_owned());
        args.only.is_empty() || args.only.iter().any(|n| n == name)
    };
    let mut scenes: Vec<(String, Scene)> = Vec::new();
    for (name, detail) in [
        ("bar", 1.0),
        ("egg", 1.0),
        ("bumpy", 1.0),
        ("prism", args.prism_detail),
        ("creature", 1.0),
    ] {
        if !wanted(name) {
            continue;
        }
        if let Some(scene) = demo_scene(name, detail) {
            scenes.push((name.to_owned(), scene));
        }
    }
    if let Some(folder) = &args.meshes {
        let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
            .map_err(|e| {
                starcages_cli::InputError(format!("{}: cannot list: {e}", folder.display()))
            })?
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "obj"))
            .collect();
        files.sort();
        for file in files {
            let stem = file
                .file_stem()
                .map_or("mesh".into(), |s| s.to_string_lossy().into_owned());
            let name = format!("{stem}-{}x{}x{}", grid[0], grid[1], grid[2]);
            if !wanted(&name) {
                continue;
            }
            // Y-up as every OBJ: turned to Z-up, as `autocage` and the editor do.
            let (mesh, up) = starcages_cli::commands::read_new_scene_mesh(&file, None)?;
            let cages = autocage(
                &mesh,
                &AutocageOptions {
                    grid,
                    ..Default::default()
                },
            );
            let scene = Scene::from_mesh_file(file, up, mesh, cages, SceneSettings::default());
            scenes.push((name, scene));
        }
    }
    for file in &args.scene {
        let name = file
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        if wanted(&name) {
            scenes.push((name, starcages_io::load_scene(file)?));
        }
    }
    if let Some(unknown) = args.only.iter().find(|n| !names.contains(n)) {
        return Err(starcages_cli::InputError(format!(
            "--only {unknown}: no such scene; the scenes are {}",
            names.join(", ")
        ))
        .into());
    }
    let mut rows = Vec::new();
    let mut ratios = Vec::new();
    let mut table2 = Vec::new();
    for (name, scene) in &scenes {
        let pose = wave(scene);
        let mut stars = Vec::new();
        if args.h.is_empty() {
            stars.push(bench_method(name, "stars", scene, &pose)?);
        }
        for &h in &args.h {
            let mut at_h = scene.clone();
            at_h.settings.default_h = h;
            for cage in &mut at_h.cages.leaves {
                cage.h = None;
                cage.border_h.clear();
            }
            stars.push(bench_method(name, &format!("stars h={h}"), &at_h, &pose)?);
        }
        let mvc = bench_method(
            name,
            "single-mvc",
            &single_cage_scene(scene, CoordinateKind::MeanValue),
            &pose,
        )?;
        let gc = bench_method(
            name,
            "single-gc",
            &single_cage_scene(scene, CoordinateKind::Green),
            &pose,
        )?;
        for star in &stars {
            ratios.push(Ratios {
                scene: name.clone(),
                method: star.method.clone(),
                bind_vs_mvc: mvc.bind_total_s / star.bind_total_s,
                kernel_floor_vs_mvc: mvc.kernel_pairs as f64 / star.kernel_pairs.max(1) as f64,
                frame_vs_mvc: mvc.frame_s / star.frame_s,
                frame_vs_gc: gc.frame_s / star.frame_s,
                move_vs_mvc: mvc.move_s / star.move_s,
                move_vs_gc: gc.move_s / star.move_s,
                memory_vs_mvc: mvc.memory_mb / star.memory_mb,
                memory_vs_gc: gc.memory_mb / star.memory_mb,
                rest_edit_vs_bind: star.rest_edit_s.unwrap_or(f64::NAN)
                    / star.rest_edit_full_s.unwrap_or(f64::NAN),
                rest_edit_rows: star.rest_edit_rows.unwrap_or(f64::NAN),
                kind_switch_s: star.kind_switch_s.unwrap_or(f64::NAN),
                kind_switch_preview_s: star.kind_switch_preview_s.unwrap_or(f64::NAN),
            });
        }
        rows.extend(stars);
        if args.table2 {
            for (kind, single) in [
                (CoordinateKind::MeanValue, &mvc),
                (CoordinateKind::Green, &gc),
            ] {
                let mut uniform = scene.clone();
                for cage in &mut uniform.cages.leaves {
                    cage.kind = kind;
                }
                let star = bench_method(name, &format!("stars all-{kind}"), &uniform, &pose)?;
                table2.push(TableTwo {
                    scene: name.clone(),
                    kind: kind.to_string(),
                    memory_ratio: single.memory_mb / star.memory_mb,
                    bind_ratio: single.bind_total_s / star.bind_total_s,
                    move_ratio: single.move_s / star.move_s,
                    move_work_ratio: single.move_nonzeros / star.move_nonzeros.max(1.0),
                    frame_ratio: single.frame_s / star.frame_s,
                });
                rows.push(star);
            }
        }
        rows.extend([mvc, gc]);
        if !args.no_hc {
            rows.push(bench_method(
                name,
                "single-hc",
                &single_cage_scene(scene, CoordinateKind::Harmonic),
                &pose,
            )?);
        }
        if !args.json {
            starcages_cli::note!("benched {name}");
        }
    }
    let report = Report {
        threads: rayon::current_num_threads(),
        simd: starcages_core::coords::lane_backend(),
        array_read_gb_s: array_read_bandwidth(),
        rows,
        ratios,
        table2,
    };
    if args.json {
        starcages_cli::output::line(starcages_core::scene::to_pretty_json(
            &serde_json::to_value(&report)?,
        ))?;
        return Ok(());
    }
    starcages_cli::output::line(format_args!(
        "threads: {}; SIMD: {}; plain array read: {:.1} GB/s",
        report.threads, report.simd, report.array_read_gb_s
    ))?;
    starcages_cli::output::line(format_args!(
        "{:<16} {:<13} {:>8} {:>5} {:>9} {:>7} {:>7} {:>9} {:>9} {:>10} {:>10} {:>8}",
        "scene",
        "method",
        "vertices",
        "cages",
        "MB",
        "nnz/row",
        "b<1 %",
        "bind cc",
        "bind s",
        "frame s",
        "move s",
        "GB/s"
    ))?;
    for r in &report.rows {
        starcages_cli::output::line(format_args!(
            "{:<16} {:<13} {:>8} {:>5} {:>9.2} {:>7.1} {:>7.1} {:>9.3} {:>9.3} {:>10.5} {:>10.6} {:>8.1}",
            r.scene,
            r.method,
            r.mesh_vertices,
            r.cages,
            r.memory_mb,
            r.nonzeros_per_row,
            100.0 * r.blended_share,
            r.bind_cage_s,
            r.bind_total_s,
            r.frame_s,
            r.move_s,
            r.stream_gb_s
        ))?;
    }
    for q in &report.ratios {
        starcages_cli::output::line(format_args!(
            "{:<16} {} vs single MVC: bind {:.2}x (kernel floor {:.2}x), frame {:.1}x, move {:.1}x, memory {:.1}x; vs single GC: frame {:.1}x, move {:.1}x, memory {:.1}x; a one-vertex rest edit re-binds {:.0} % of the rows in {:.0} % of a full bind's time; a leaf's switch to HC re-binds in {:.0} ms at most, its preview in {:.0} ms",
            q.scene,
            q.method,
            q.bind_vs_mvc,
            q.kernel_floor_vs_mvc,
            q.frame_vs_mvc,
            q.move_vs_mvc,
            q.memory_vs_mvc,
            q.frame_vs_gc,
            q.move_vs_gc,
            q.memory_vs_gc,
            100.0 * q.rest_edit_rows,
            100.0 * q.rest_edit_vs_bind,
            1e3 * q.kind_switch_s,
            1e3 * q.kind_switch_preview_s
        ))?;
    }
    for t in &report.table2 {
        starcages_cli::output::line(format_args!(
            "{:<16} Table II, every leaf {} against the single {} cage: memory {:.1}x less, bind {:.2}x, one cage-vertex move {:.1}x faster ({:.1}x fewer weights read), whole frame {:.1}x faster",
            t.scene,
            t.kind,
            t.kind,
            t.memory_ratio,
            t.bind_ratio,
            t.move_ratio,
            t.move_work_ratio,
            t.frame_ratio
        ))?;
    }
    Ok(())
}
