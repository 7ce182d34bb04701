//! `starcages.Scene`: a scene (mesh, leaf cages, controls, poses, keys) loaded, made or
//! generated, with its arrays in the mesh file's axes; posing by frame, named pose or edits;
//! `bind`.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Duration;

use glam::DVec3;
use numpy::{AllowTypeChange, PyArray2, PyArrayLike2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use starcages_core::BindControl;
use starcages_core::check::check_scene;
use starcages_core::posing::{PoseRequest, PoseSource};
use starcages_core::scene::Scene;
use starcages_core::star::StarBinding;

use crate::arrays::{points_in, points_out, triangles_out};
use crate::binding::PyBinding;
use crate::error;

/// A StarCages scene. Arrays are in the mesh file's axes (`up`), meshes welded.
#[pyclass(name = "Scene", module = "starcages")]
pub struct PyScene {
    pub(crate) scene: Scene,
}

impl PyScene {
    /// `scene` after the checks the CLI makes (the first problem as the error, `what` naming
    /// where the scene came from).
    pub(crate) fn checked(scene: Scene, what: &str) -> PyResult<Self> {
        let checked = check_scene(&scene);
        if let Some(problem) = checked.report.errors.first() {
            let more = match checked.report.errors.len() - 1 {
                0 => String::new(),
                n => format!(" (and {n} more)"),
            };
            return Err(error(format!("{what}: {problem}{more}")));
        }
        Ok(Self { scene })
    }

    fn file_points<'py>(
        &self,
        py: Python<'py>,
        points: &[DVec3],
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let up = self.scene.export_up();
        points_out(py, points.iter().map(|&p| up.from_scene(p)))
    }

    /// Cage positions given in the file's axes, in scene coordinates, one per cage vertex.
    pub(crate) fn cages_in(
        &self,
        cages: &PyArrayLike2<'_, f64, AllowTypeChange>,
    ) -> PyResult<Vec<DVec3>> {
        let points = points_in(cages, "cage positions")?;
        let count = self.scene.cages.vertices.len();
        if points.len() != count {
            return Err(error(format!(
                "cage positions: {} rows for the scene's {count} cage vertices",
                points.len()
            )));
        }
        let up = self.scene.export_up();
        Ok(points.into_iter().map(|p| up.to_scene(p)).collect())
    }
}

#[pymethods]
impl PyScene {
    /// Scene.load(path) -> Scene: a scene file (and the mesh file it names), checked.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let scene = py
            .detach(|| starcages_io::load_scene(&path))
            .map_err(error)?;
        Self::checked(scene, &path.display().to_string())
    }

    /// save(path): writes the scene file atomically.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        starcages_io::save_scene(&self.scene, &path).map_err(error)
    }

    /// The mesh file's up axis ("y" or "z"): the axes of every array.
    #[getter]
    fn up(&self) -> &'static str {
        self.scene.export_up().name()
    }

    /// The welded mesh vertices at rest, (n, 3) float64.
    #[getter]
    fn mesh_vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.file_points(py, self.scene.mesh.welded_positions())
    }

    /// The welded mesh triangles, (m, 3) uint32.
    #[getter]
    fn mesh_triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        triangles_out(py, self.scene.mesh.welded_triangles())
    }

    /// Every cage vertex (leaf and control cages) at rest, (k, 3) float64.
    #[getter]
    fn cage_vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.file_points(py, &self.scene.cages.vertices)
    }

    /// The current pose: every cage vertex, (k, 3) float64.
    #[getter]
    fn pose<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.file_points(py, &self.scene.pose)
    }

    /// The leaf cages: dicts of name, kind ("mvc", "hc", "gc"), h (None: the scene's), faces
    /// (lists of cage vertex indices).
    #[getter]
    fn leaf_cages<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for cage in &self.scene.cages.leaves {
            let d = PyDict::new(py);
            d.set_item("name", &cage.name)?;
            d.set_item("kind", cage.kind.to_string())?;
            d.set_item("h", cage.h)?;
            d.set_item("faces", &cage.faces)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The controls (internal cages): dicts of name, kind, faces, owns (the cage vertices it
    /// moves), pivot (its joint, or None) and joint (the vertices of its joint face).
    #[getter]
    fn controls<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let up = self.scene.export_up();
        let list = PyList::empty(py);
        for cage in &self.scene.cages.internals {
            let d = PyDict::new(py);
            d.set_item("name", &cage.name)?;
            d.set_item("kind", cage.kind.to_string())?;
            d.set_item("faces", &cage.faces)?;
            d.set_item("owns", &cage.owns)?;
            d.set_item("pivot", cage.pivot.map(|p| up.from_scene(p).to_array()))?;
            d.set_item("joint", &cage.joint)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The named poses: name -> (k, 3) float64 cage positions.
    #[getter]
    fn poses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, pose) in &self.scene.poses {
            d.set_item(name, self.file_points(py, pose)?)?;
        }
        Ok(d)
    }

    /// The animation keys: dicts of frame, pose (a pose name), interpolation and h (leaf cage
    /// name -> h at that key).
    #[getter]
    fn keys<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for key in &self.scene.animation.keys {
            let d = PyDict::new(py);
            d.set_item("frame", key.frame)?;
            d.set_item("pose", &key.pose)?;
            d.set_item(
                "interpolation",
                format!("{:?}", key.interpolation).to_lowercase(),
            )?;
            let h: BTreeMap<&str, f64> = key.h.iter().map(|(k, v)| (k.as_str(), *v)).collect();
            d.set_item("h", h)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// Frames per second of the animation.
    #[getter]
    fn fps(&self) -> f64 {
        self.scene.animation.fps
    }

    /// The animation's first and last frame.
    #[getter]
    fn frame_range(&self) -> (i64, i64) {
        (
            self.scene.animation.frame_start,
            self.scene.animation.frame_end,
        )
    }

    /// posed(edits=[], pose=None, frame=None) -> array
    ///
    /// Cage positions (k, 3) of a pose: the rest pose, a named `pose` or the animation at
    /// `frame`, with `edits` on top, propagated down the controls as the CLI's `--apply`
    /// does (e.g. "leg.L.2: rotate 1 0 0 60", "head: translate 0 0 0.1"), the joints as the
    /// mitre leaves them: `Binding.keep_joint_volumes` gives them their volume back as the
    /// CLI does once bound.
    #[pyo3(signature = (edits = Vec::new(), pose = None, frame = None))]
    fn posed<'py>(
        &self,
        py: Python<'py>,
        edits: Vec<String>,
        pose: Option<String>,
        frame: Option<f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let source = match (pose, frame) {
            (Some(_), Some(_)) => return Err(error("give a pose or a frame, not both")),
            (Some(name), None) => PoseSource::Named(Some(name)),
            (None, Some(f)) => PoseSource::Frame(f),
            (None, None) => PoseSource::Rest,
        };
        let edits = edits
            .iter()
            .map(|e| e.parse().map_err(|why| error(format!("edit '{e}': {why}"))))
            .collect::<PyResult<Vec<_>>>()?;
        let request = PoseRequest { source, edits };
        let resolved = request.resolve(&self.scene).map_err(error)?;
        self.file_points(py, &resolved.cages)
    }

    /// control_parents() -> dict[str, str | None]
    ///
    /// Each control's parent: the control that moves its cage vertices (None for a control
    /// no other moves), so that a tool can parent them body-out (Blender's empties).
    fn control_parents(&self) -> BTreeMap<String, Option<String>> {
        control_order(&self.scene)
            .into_iter()
            .map(|(i, parent)| {
                let internals = &self.scene.cages.internals;
                (
                    internals[i].name.clone(),
                    parent.map(|p| internals[p].name.clone()),
                )
            })
            .collect()
    }

    /// posed_by_controls(transforms, offsets=None) -> array
    ///
    /// Cage positions (k, 3) with each named control's cage moved rigidly by its 4×4
    /// transform (rest to posed, the file's axes; a control's transform includes its
    /// parents', as a parented object's world matrix does), parents first, every move
    /// propagated down the cage hierarchy to the leaf cage vertices. Controls left out stay
    /// where their parents take them. `offsets` ((k, 3)), hand moves of cage vertices on top
    /// of that pose, are applied last, a control's vertices carrying what they own.
    #[pyo3(signature = (transforms, offsets = None))]
    fn posed_by_controls<'py>(
        &self,
        py: Python<'py>,
        transforms: BTreeMap<String, PyArrayLike2<'py, f64, AllowTypeChange>>,
        offsets: Option<PyArrayLike2<'py, f64, AllowTypeChange>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let scene = &self.scene;
        let up = scene.export_up();
        let mut matrices = BTreeMap::new();
        for (name, matrix) in &transforms {
            let view = matrix.as_array();
            if view.shape() != [4, 4] || view.iter().any(|v| !v.is_finite()) {
                return Err(error(format!(
                    "control '{name}': a finite 4×4 matrix is expected, not shape {:?}",
                    view.shape()
                )));
            }
            if !scene.cages.internals.iter().any(|c| &c.name == name) {
                return Err(error(format!("no control named '{name}'")));
            }
            let columns: Vec<f64> = (0..4)
                .flat_map(|c| (0..4).map(move |r| (r, c)))
                .map(|(r, c)| view[[r, c]])
                .collect();
            matrices.insert(name.clone(), glam::DMat4::from_cols_slice(&columns));
        }
        let mut hierarchy =
            starcages_core::hierarchy::Hierarchy::bind_in_state(scene, &Default::default())
                .map_err(error)?;
        let mut cages = scene.cages.vertices.clone();
        for (i, _) in control_order(scene) {
            let control = &scene.cages.internals[i];
            let Some(matrix) = matrices.get(&control.name) else {
                continue;
            };
            let mut corners: Vec<u32> = control.faces.iter().flatten().copied().collect();
            corners.sort_unstable();
            corners.dedup();
            let moves: Vec<(u32, DVec3)> = corners
                .iter()
                .filter_map(|&v| {
                    let rest = *scene.cages.vertices.get(v as usize)?;
                    let moved = matrix.transform_point3(up.from_scene(rest));
                    Some((v, up.to_scene(moved)))
                })
                .collect();
            hierarchy.apply(&mut cages, &moves).map_err(error)?;
        }
        if let Some(offsets) = &offsets {
            let offsets = points_in(offsets, "offsets")?;
            if offsets.len() != cages.len() {
                return Err(error(format!(
                    "offsets: {} rows for the scene's {} cage vertices",
                    offsets.len(),
                    cages.len()
                )));
            }
            let moves: Vec<(u32, DVec3)> = offsets
                .iter()
                .enumerate()
                .filter(|(_, o)| **o != DVec3::ZERO)
                .map(|(v, &o)| (v as u32, cages[v] + up.to_scene(o)))
                .collect();
            hierarchy.apply(&mut cages, &moves).map_err(error)?;
        }
        self.file_points(py, &cages)
    }

    /// The scene's default h (each leaf cage without its own h blends with it).
    #[getter]
    fn default_h(&self) -> f64 {
        self.scene.settings.default_h
    }

    /// with_default_h(h) -> Scene: a copy with another default h (checked as a scene file's).
    fn with_default_h(&self, h: f64) -> PyResult<Self> {
        let mut scene = self.scene.clone();
        scene.settings.default_h = h;
        Self::checked(scene, "default h")
    }

    /// with_cage(name, kind=None, h=None, scene_h=False) -> Scene
    ///
    /// A copy in which leaf cage `name` uses coordinates `kind` ("mvc", "hc", "gc") and/or
    /// its own `h`, or the scene's default h again (`scene_h`); checked as a scene file's.
    #[pyo3(signature = (name, kind = None, h = None, scene_h = false))]
    fn with_cage(
        &self,
        name: &str,
        kind: Option<&str>,
        h: Option<f64>,
        scene_h: bool,
    ) -> PyResult<Self> {
        let mut scene = self.scene.clone();
        let index = scene
            .cages
            .leaf_index(name)
            .ok_or_else(|| error(format!("no leaf cage named '{name}'")))?;
        let cage = &mut scene.cages.leaves[index];
        if let Some(kind) = kind {
            cage.kind = kind
                .parse()
                .map_err(|e| error(format!("leaf cage '{name}': kind '{kind}': {e}")))?;
        }
        if scene_h {
            cage.h = None;
        } else if let Some(h) = h {
            cage.h = Some(h);
        }
        Self::checked(scene, &format!("leaf cage '{name}'"))
    }

    /// with_pose(cage_positions) -> Scene: a copy whose current pose is `cage_positions`
    /// (the file's axes), with the hierarchy state that gives it (a vertex moved apart from
    /// the control that owns it keeps its offset), as a scene file then carries it.
    fn with_pose(&self, cage_positions: PyArrayLike2<'_, f64, AllowTypeChange>) -> PyResult<Self> {
        let cages = self.cages_in(&cage_positions)?;
        let mut scene = self.scene.clone();
        let mut hierarchy =
            starcages_core::hierarchy::Hierarchy::bind_in_state(&scene, &Default::default())
                .map_err(error)?;
        let mut pose = scene.cages.vertices.clone();
        let moves: Vec<(u32, DVec3)> = cages
            .iter()
            .zip(&scene.cages.vertices)
            .enumerate()
            .filter(|(_, (now, rest))| now != rest)
            .map(|(v, (now, _))| (v as u32, *now))
            .collect();
        hierarchy.apply(&mut pose, &moves).map_err(error)?;
        scene.pose = cages;
        scene.pose_state = hierarchy.state();
        Ok(Self { scene })
    }

    /// to_scene_axes(points) -> array: points of the file's axes in StarCages' Z-up scene
    /// coordinates (the operator's).
    fn to_scene_axes<'py>(
        &self,
        py: Python<'py>,
        points: PyArrayLike2<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let up = self.scene.export_up();
        let points = points_in(&points, "points")?;
        points_out(py, points.into_iter().map(|p| up.to_scene(p)))
    }

    /// to_file_axes(points) -> array: scene coordinates back in the file's axes.
    fn to_file_axes<'py>(
        &self,
        py: Python<'py>,
        points: PyArrayLike2<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let points = points_in(&points, "points")?;
        self.file_points(py, &points)
    }

    /// bind(progress=None) -> Binding
    ///
    /// Binds the mesh to the cages. The GIL is released while the bind runs; `progress`,
    /// if given, is called with the fraction done (0 to 1) before it starts and about 20
    /// times a second from the calling thread; returning False (or raising) cancels the bind
    /// (a StarCagesError saying so, or the callback's exception).
    #[pyo3(signature = (progress = None))]
    fn bind(&self, py: Python<'_>, progress: Option<Bound<'_, PyAny>>) -> PyResult<PyBinding> {
        let checked = check_scene(&self.scene);
        let topology = checked
            .topology
            .ok_or_else(|| error("the scene's cages do not form a *Cages topology"))?;
        let control = BindControl::default();
        let scene = &self.scene;
        let mut callback_error = None;
        // Asks the callback; False or an exception cancels.
        let mut ask = |fraction: f64| {
            if let Some(callback) = &progress {
                match callback.call1((fraction,)) {
                    Ok(answer) if answer.is(pyo3::types::PyBool::new(py, false)) => {
                        control.cancel();
                    }
                    Ok(_) => {}
                    Err(e) => {
                        control.cancel();
                        callback_error.get_or_insert(e);
                    }
                }
            }
        };
        // Once before the work starts (a False there binds nothing), then while it runs.
        ask(0.0);
        let bound = std::thread::scope(|s| {
            let worker = s.spawn(|| StarBinding::bind_scene_with(scene, &topology, &control));
            while !worker.is_finished() {
                py.detach(|| std::thread::sleep(Duration::from_millis(50)));
                if !worker.is_finished() {
                    ask(control.progress());
                }
            }
            worker.join()
        });
        if let Some(e) = callback_error {
            return Err(e);
        }
        let binding = bound
            .map_err(|_| error("the bind stopped unexpectedly"))?
            .map_err(error)?;
        Ok(PyBinding::new(self.scene.clone(), binding))
    }

    fn __repr__(&self) -> String {
        format!(
            "<starcages.Scene: {} vertices, {} leaf cages, {} controls, {} poses, {} keys>",
            self.scene.mesh.welded_positions().len(),
            self.scene.cages.leaves.len(),
            self.scene.cages.internals.len(),
            self.scene.poses.len(),
            self.scene.animation.keys.len()
        )
    }
}

/// The controls (internal cages) parents first, each with its parent: the control that moves
/// one of its cage vertices (the deepest such, when several do).
fn control_order(scene: &Scene) -> Vec<(usize, Option<usize>)> {
    let internals = &scene.cages.internals;
    let corners: Vec<Vec<u32>> = internals
        .iter()
        .map(|c| c.faces.iter().flatten().copied().collect())
        .collect();
    let owners: Vec<Vec<usize>> = (0..internals.len())
        .map(|b| {
            (0..internals.len())
                .filter(|&a| a != b && corners[b].iter().any(|v| internals[a].owns.contains(v)))
                .collect()
        })
        .collect();
    // Depth by relaxation (the hierarchy is acyclic; at most one pass per control).
    let mut depth = vec![0usize; internals.len()];
    for _ in 0..internals.len() {
        for b in 0..internals.len() {
            let d = owners[b].iter().map(|&a| depth[a] + 1).max().unwrap_or(0);
            depth[b] = d.min(internals.len());
        }
    }
    let mut order: Vec<usize> = (0..internals.len()).collect();
    order.sort_by_key(|&i| (depth[i], i));
    order
        .into_iter()
        .map(|b| (b, owners[b].iter().copied().max_by_key(|&a| depth[a])))
        .collect()
}
