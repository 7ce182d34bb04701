//! StarCages for Python (`import starcages`): read meshes, auto-rig them, load and save scenes,
//! bind (the GIL released, progress and cancel through a callback), deform to cage positions
//! or animation frames, hand the compiled operator to scipy as CSR arrays, and bake point
//! caches — numpy arrays in and out.
//!
//! Frames: every array is in the mesh file's axes (a Y-up OBJ's points are Y-up), as every
//! file StarCages writes is; `Scene.to_scene_axes` turns them into StarCages'
//! Z-up scene coordinates, which the operator works in. Meshes are the welded view (vertices
//! at the same position are one), as StarCages binds and deforms them.
//!
//! Errors are `starcages.StarCagesError` with the same one-line messages as the CLI's.

use std::path::PathBuf;

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

mod arrays;
mod binding;
mod scene;

create_exception!(
    starcages,
    StarCagesError,
    PyException,
    "A StarCages error: the message names the file, element and reason, as the CLI's do."
);

/// A `StarCagesError` carrying `message`.
pub(crate) fn error(message: impl std::fmt::Display) -> PyErr {
    StarCagesError::new_err(message.to_string())
}

/// Vertices (n, 3) float64 and triangles (m, 3) uint32.
type MeshArrays<'py> = (
    Bound<'py, numpy::PyArray2<f64>>,
    Bound<'py, numpy::PyArray2<u32>>,
);

/// read_mesh(path) -> (vertices, triangles)
///
/// Reads a mesh file (OBJ, glTF, GLB, FBX, PLY, STL, OFF) as StarCages binds it: the welded
/// vertices (float64, shape (n, 3), in the file's axes) and triangles (uint32, shape (m, 3)).
#[pyfunction]
fn read_mesh<'py>(py: Python<'py>, path: PathBuf) -> PyResult<MeshArrays<'py>> {
    let mesh = py
        .detach(|| starcages_io::read_mesh(&path))
        .map_err(error)?;
    Ok((
        arrays::points_out(py, mesh.welded_positions().iter().copied())?,
        arrays::triangles_out(py, mesh.welded_triangles())?,
    ))
}

/// demo(name, detail=1.0) -> Scene
///
/// One of the generated demo scenes (`demo_names()`), at `detail` (1 = default tessellation).
#[pyfunction]
#[pyo3(signature = (name, detail = 1.0))]
fn demo(name: &str, detail: f64) -> PyResult<scene::PyScene> {
    if !(detail.is_finite() && detail > 0.0 && detail <= 16.0) {
        return Err(error(format!(
            "detail {detail} is out of range; use a number above 0, at most 16"
        )));
    }
    let scene = starcages_core::generate::demo::demo_scene(name, detail).ok_or_else(|| {
        error(format!(
            "no demo called '{name}'; one of: {}",
            demo_names().join(", ")
        ))
    })?;
    scene::PyScene::checked(scene, "demo")
}

/// demo_names() -> list[str]
///
/// The names `demo` takes.
#[pyfunction]
fn demo_names() -> Vec<String> {
    starcages_core::generate::demo::DEMOS
        .iter()
        .map(|(name, _)| (*name).to_owned())
        .collect()
}

/// autorig(vertices, triangles, detail=3, mirror=None, controls=True, up="z") -> Scene
///
/// The auto rig of a mesh given as arrays (`up`: the arrays' up axis, "z" or "y"): chains of
/// leaf cages along its limbs and a control per segment (`controls`), symmetric across
/// `mirror` ("x", "y", "z" in the arrays' axes, or "auto"). The GIL is released meanwhile.
#[pyfunction]
#[pyo3(signature = (vertices, triangles, detail = 3, mirror = None, controls = true, up = "z"))]
fn autorig(
    py: Python<'_>,
    vertices: numpy::PyArrayLike2<'_, f64, numpy::AllowTypeChange>,
    triangles: numpy::PyArrayLike2<'_, i64, numpy::AllowTypeChange>,
    detail: u32,
    mirror: Option<&str>,
    controls: bool,
    up: &str,
) -> PyResult<scene::PyScene> {
    use starcages_core::generate::{AutorigSettings, Mirror, autorig, autorig_settings};
    let up: starcages_core::scene::UpAxis =
        up.parse().map_err(|e| error(format!("up '{up}': {e}")))?;
    let points = arrays::points_in(&vertices, "vertices")?;
    let faces = arrays::triangles_in(&triangles, points.len())?;
    let mesh = starcages_core::mesh::Mesh::new(points, faces, None, None).map_err(error)?;
    let mesh = up.mesh_to_scene(mesh);
    let mirror = match mirror {
        None => Mirror::None,
        Some(name) => Mirror::named(name, up).map_err(|why| error(format!("mirror {why}")))?,
    };
    let settings = AutorigSettings {
        detail,
        mirror,
        controls,
        ..AutorigSettings::default()
    };
    let control = starcages_core::BindControl::default();
    let rig = py
        .detach(|| autorig(&mesh, &settings, &control))
        .map_err(|e| error(format!("auto rig: {e}")))?;
    let mut scene = starcages_core::scene::Scene::new(
        starcages_core::scene::MeshSource::Embedded,
        mesh,
        rig.cages,
        autorig_settings(),
    );
    scene.mesh_up = up;
    scene::PyScene::checked(scene, "auto rig")
}

/// StarCages: *Cages deformation, numpy in and out.
#[pymodule]
fn starcages(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("StarCagesError", m.py().get_type::<StarCagesError>())?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<binding::PyBinding>()?;
    m.add_function(wrap_pyfunction!(read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(demo, m)?)?;
    m.add_function(wrap_pyfunction!(demo_names, m)?)?;
    m.add_function(wrap_pyfunction!(autorig, m)?)?;
    Ok(())
}
