//! `starcages-bench --scale MESH`: the bind's scaling with mesh size. The mesh is
//! subdivided uniformly (`--segments`, each edge cut into n parts: n² × the triangles), put in
//! the automatic 3×3×3 grid with default settings, and bound by *Cages and by the single MVC
//! cage; per size it prints the bind time split by phase, the bind's peak heap (measured by the
//! counting allocator of this binary), the mesh's and the stored binding's bytes and the time
//! to follow one cage-vertex move, and the default auto rig's open + rig + bind. With `--blender PYTHON` (Blender 5 as the `bpy` package)
//! Blender's Mesh Deform binds the same mesh in the rig's union cage, side by side
//! (`scripts/blender_mesh_deform_bind.py`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::{DVec3, Vec3};
use peakmem_alloc::PeakMemAllocTrait as _;
use serde::Serialize;
use starcages_core::BindControl;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::{
    AutocageOptions, AutorigSettings, autocage, autorig, autorig_settings,
};
use starcages_core::scene::{Scene, SceneSettings};
use starcages_core::star::{StarBinding, single_cage_scene};

/// Most triangles a size of the series may have (about 5 million vertices: a bind of those
/// needs about 4 GB).
const MAX_SCALE_TRIANGLES: u64 = 10_000_000;

/// One bind of one size.
#[derive(Serialize)]
struct Bind {
    seconds: f64,
    seconds_cage_coordinates: f64,
    seconds_join_cages: f64,
    /// Placement, Ω at cage vertices, row assembly and packing: the rest of `seconds`.
    seconds_other: f64,
    /// Most heap bytes held at once during the bind, above what was held before it.
    peak_mb: f64,
    /// Bytes the binding keeps (operator, its transpose, join weights, per-point b and cage).
    stored_mb: f64,
    /// Seconds to follow one cage-vertex move (incremental), mean over 16 vertices.
    move_s: f64,
}

/// Blender's Mesh Deform on the same mesh and union cage.
#[derive(Serialize, serde::Deserialize)]
struct Blender {
    bind_seconds: f64,
    move_seconds: f64,
    /// Peak resident memory of the whole Blender process (MB).
    #[serde(default)]
    peak_rss_mb: f64,
    /// The part of it the bind added (MB).
    #[serde(default)]
    bind_rss_mb: f64,
}

/// The default auto rig of the same mesh, as an artist meets it: the mesh file read, rigged
/// (controls included) and bound.
#[derive(Serialize)]
struct AutoRig {
    /// Reading the mesh as an OBJ file (written by this benchmark).
    open_seconds: f64,
    rig_seconds: f64,
    leaf_cages: usize,
    cage_vertices: usize,
    bind: Bind,
    /// Opening, rigging and binding together.
    total_seconds: f64,
}

#[derive(Serialize)]
struct Size {
    segments: u32,
    mesh_vertices: usize,
    mesh_triangles: usize,
    mesh_mb: f64,
    stars: Bind,
    single_mvc: Bind,
    /// Peak over (mesh + stored operator): the bound is 2.
    stars_peak_over_kept: f64,
    stars_seconds_per_million_vertices: f64,
    auto_rig: AutoRig,
    #[serde(skip_serializing_if = "Option::is_none")]
    blender: Option<Blender>,
}

/// Opens `mesh` from an OBJ file, auto-rigs it and binds the rig (see [`AutoRig`]).
fn auto_rig(mesh: &starcages_core::mesh::Mesh, mesh_path: &Path) -> anyhow::Result<AutoRig> {
    let dir = tempfile::tempdir()?;
    let obj = dir.path().join("mesh.obj");
    let triangles: Vec<Vec<u32>> = mesh.welded_triangles().iter().map(|t| t.to_vec()).collect();
    write_plain_obj(&obj, mesh.welded_positions(), &triangles)?;
    let start = Instant::now();
    let (opened, up) = starcages_cli::commands::read_new_scene_mesh(&obj, None)?;
    let open_seconds = start.elapsed().as_secs_f64();
    let control = BindControl::default();
    let start = Instant::now();
    let rig = starcages_cli::progress::with_progress("auto rig", &control, || {
        autorig(&opened, &AutorigSettings::default(), &control)
    })
    .map_err(|e| anyhow::anyhow!("auto rig of {}: {e}", mesh_path.display()))?;
    let rig_seconds = start.elapsed().as_secs_f64();
    let (leaf_cages, cage_vertices) = (rig.cages.leaves.len(), rig.cages.vertices.len());
    let scene = Scene::from_mesh_file(obj, up, opened, rig.cages, autorig_settings());
    let bind = bind(&scene, "auto rig bind")?;
    Ok(AutoRig {
        open_seconds,
        rig_seconds,
        leaf_cages,
        cage_vertices,
        total_seconds: open_seconds + rig_seconds + bind.seconds,
        bind,
    })
}

/// Binds `scene` from scratch and measures it.
fn bind(scene: &Scene, what: &str) -> anyhow::Result<Bind> {
    starcages_core::coords::clear_harmonic_cache();
    let control = BindControl::default();
    crate::ALLOCATOR.reset_peak_memory();
    let start = Instant::now();
    let binding = starcages_cli::progress::with_progress(what, &control, || {
        StarBinding::bind_scene(scene, &control)
    })
    .map_err(|e| anyhow::anyhow!("{what}: {e}"))?;
    let seconds = start.elapsed().as_secs_f64();
    let peak = crate::ALLOCATOR.get_peak_memory();
    let stats = binding.stats;
    let operator = &binding.operator;
    let rest = &scene.cages.vertices;
    let mut out = vec![Vec3::ZERO; operator.row_count()];
    let mut moved = rest.clone();
    let mut x = operator.dofs(rest, &moved);
    operator.apply(&x, &mut out);
    let samples: Vec<u32> = (0..16).map(|i| (i * rest.len() / 16) as u32).collect();
    let start = Instant::now();
    for &v in &samples {
        moved[v as usize] += DVec3::splat(0.01);
        operator.update_dofs(rest, &moved, &[v], &mut x);
        let rows = operator.rows_touched(&operator.columns_of_moved_vertices(&[v]));
        operator.apply_rows(&rows, &x, &mut out);
    }
    let move_s = start.elapsed().as_secs_f64() / samples.len() as f64;
    Ok(Bind {
        seconds,
        seconds_cage_coordinates: stats.seconds_cage_coordinates,
        seconds_join_cages: stats.seconds_join_cages,
        seconds_other: (seconds - stats.seconds_cage_coordinates - stats.seconds_join_cages)
            .max(0.0),
        peak_mb: peak as f64 / 1e6,
        stored_mb: binding.byte_size() as f64 / 1e6,
        move_s,
    })
}

/// Writes `positions` and `triangles` (0-based) as a plain OBJ for the Blender script.
fn write_plain_obj(path: &Path, positions: &[DVec3], faces: &[Vec<u32>]) -> anyhow::Result<()> {
    use std::io::Write as _;
    let file = std::fs::File::create(path)
        .map_err(|e| anyhow::anyhow!("{}: cannot create: {e}", path.display()))?;
    let mut out = std::io::BufWriter::new(file);
    for p in positions {
        writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
    }
    for f in faces {
        write!(out, "f")?;
        for v in f {
            write!(out, " {}", v + 1)?;
        }
        writeln!(out)?;
    }
    out.flush()?;
    Ok(())
}

/// Blender's Mesh Deform bind (precision 5) of `scene`'s mesh in its leaf cages' union.
fn blender(python: &Path, script: &Path, scene: &Scene) -> anyhow::Result<Blender> {
    let dir = tempfile::tempdir()?;
    let mesh_path = dir.path().join("mesh.obj");
    let cage_path = dir.path().join("cages.obj");
    let mesh = &scene.mesh;
    let triangles: Vec<Vec<u32>> = mesh.welded_triangles().iter().map(|t| t.to_vec()).collect();
    write_plain_obj(&mesh_path, mesh.welded_positions(), &triangles)?;
    let cage_faces: Vec<Vec<u32>> = scene
        .cages
        .leaves
        .iter()
        .flat_map(|leaf| leaf.faces.iter().map(|f| f.to_vec()))
        .collect();
    write_plain_obj(&cage_path, &scene.cages.vertices, &cage_faces)?;
    let output = std::process::Command::new(python)
        .arg(script)
        .arg(&mesh_path)
        .arg(&cage_path)
        .arg("5")
        .output()
        .map_err(|e| anyhow::anyhow!("{}: cannot run: {e}", python.display()))?;
    if !output.status.success() {
        anyhow::bail!(
            "{} {} failed: {}",
            python.display(),
            script.display(),
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line = stdout
        .lines()
        .rev()
        .find(|l| l.starts_with('{'))
        .ok_or_else(|| anyhow::anyhow!("{}: no JSON line in its output", script.display()))?;
    Ok(serde_json::from_str(line)?)
}

/// Runs the scale series of `mesh_path` at each of `segments`.
pub fn run(
    mesh_path: &Path,
    segments: &[u32],
    blender_python: Option<&PathBuf>,
    json: bool,
) -> anyhow::Result<()> {
    let script = PathBuf::from("scripts/blender_mesh_deform_bind.py");
    if blender_python.is_some() && !script.is_file() {
        return Err(starcages_cli::InputError(format!(
            "--blender needs {} (run from the repository's root)",
            script.display()
        ))
        .into());
    }
    let limit = starcages_core::mesh::MAX_SUBDIVISION_SEGMENTS;
    if let Some(n) = segments.iter().find(|&&n| n == 0 || n > limit) {
        return Err(starcages_cli::InputError(format!(
            "--segments {n}: each must be 1 to {limit} (edge cuts; 10 gives 100× the triangles)"
        ))
        .into());
    }
    let (base, up) = starcages_cli::commands::read_new_scene_mesh(mesh_path, None)?;
    // Refused before any work: each size must fit this machine (a 25k-vertex mesh at 64 cuts
    // would be 200 million triangles).
    for &n in segments {
        let triangles = base.welded_triangles().len() as u64 * u64::from(n) * u64::from(n);
        if triangles > MAX_SCALE_TRIANGLES {
            return Err(starcages_cli::InputError(format!(
                "--segments {n} would make {triangles} triangles of {}'s {}, past the {} this \
                 benchmark allows; use fewer cuts",
                mesh_path.display(),
                base.welded_triangles().len(),
                MAX_SCALE_TRIANGLES
            ))
            .into());
        }
    }
    let mut sizes = Vec::new();
    for &n in segments {
        let mesh = base.subdivided(n)?;
        starcages_cli::note!(
            "{} × {n}²: {} vertices",
            mesh_path.display(),
            mesh.welded_positions().len()
        );
        let auto_rig = auto_rig(&mesh, mesh_path)?;
        let cages = autocage(&mesh, &AutocageOptions::default());
        let mesh_mb = mesh.byte_size() as f64 / 1e6;
        let (vertices, triangles) = (mesh.welded_positions().len(), mesh.welded_triangles().len());
        let scene = Scene::from_mesh_file(
            mesh_path.to_owned(),
            up,
            mesh,
            cages,
            SceneSettings::default(),
        );
        let stars = bind(&scene, "*Cages bind")?;
        let single = single_cage_scene(&scene, CoordinateKind::MeanValue);
        let single_mvc = bind(&single, "single MVC bind")?;
        let blender = match blender_python {
            Some(python) => {
                starcages_cli::note!("Blender Mesh Deform bind …");
                Some(blender(python, &script, &scene)?)
            }
            None => None,
        };
        sizes.push(Size {
            segments: n,
            mesh_vertices: vertices,
            mesh_triangles: triangles,
            mesh_mb,
            stars_peak_over_kept: stars.peak_mb / (mesh_mb + stars.stored_mb),
            stars_seconds_per_million_vertices: stars.seconds / vertices as f64 * 1e6,
            stars,
            single_mvc,
            auto_rig,
            blender,
        });
    }
    if json {
        return starcages_cli::output::line(serde_json::to_string_pretty(&sizes)?);
    }
    let mut table = String::from(
        "| vertices | *Cages bind (cage / join / other) s | s per 1M vertices | peak MB | mesh + kept MB | peak / kept | single MVC bind s (peak MB) | auto rig: open + rig + bind = total s (leaf cages) | Blender bind s (peak RSS MB) | move ms: *Cages / single MVC / Blender |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for s in &sizes {
        let b = &s.stars;
        let blender = s.blender.as_ref();
        table.push_str(&format!(
            "| {} | {:.2} ({:.2} / {:.2} / {:.2}) | {:.2} | {:.0} | {:.0} | {:.2} | {:.2} ({:.0}) | {:.2} + {:.2} + {:.2} = {:.2} ({}) | {} | {:.2} / {:.2} / {} |\n",
            s.mesh_vertices,
            b.seconds,
            b.seconds_cage_coordinates,
            b.seconds_join_cages,
            b.seconds_other,
            s.stars_seconds_per_million_vertices,
            b.peak_mb,
            s.mesh_mb + b.stored_mb,
            s.stars_peak_over_kept,
            s.single_mvc.seconds,
            s.single_mvc.peak_mb,
            s.auto_rig.open_seconds,
            s.auto_rig.rig_seconds,
            s.auto_rig.bind.seconds,
            s.auto_rig.total_seconds,
            s.auto_rig.leaf_cages,
            blender.map_or("–".into(), |x| format!("{:.2} ({:.0})", x.bind_seconds, x.peak_rss_mb)),
            b.move_s * 1e3,
            s.single_mvc.move_s * 1e3,
            blender.map_or("–".into(), |x| format!("{:.2}", x.move_seconds * 1e3)),
        ));
    }
    starcages_cli::output::line(table.trim_end())
}
