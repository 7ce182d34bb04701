//! `starcages.Binding`: a bound scene. Deforms to cage positions or animation frames (keyed h
//! re-binds only the cages whose h changed), gives the operator as CSR arrays, bakes point
//! caches.

use std::path::PathBuf;
use std::sync::OnceLock;

use numpy::ndarray::Array1;
use numpy::{AllowTypeChange, IntoPyArray as _, PyArray2, PyArrayLike2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use starcages_core::BindControl;
use starcages_core::bake::FrameDeformer;
use starcages_core::joint_volume::JointVolumes;
use starcages_core::posing::PoseRequest;
use starcages_core::scene::Scene;
use starcages_core::star::StarBinding;
use starcages_io::{ExportLayout, PointCacheFormat, PointCacheWriter};

use crate::arrays::{points_out, points_out_f32};
use crate::error;
use crate::scene::PyScene;

/// A scene bound: the mesh's coordinates in its cages, compiled into one sparse operator.
#[pyclass(name = "Binding", module = "starcages")]
pub struct PyBinding {
    scene: PyScene,
    deformer: FrameDeformer,
    /// The joints' regions in the bound mesh, built on the first `keep_joint_volumes` (a
    /// control drag calls it at every update) and dropped when a frame binds again.
    joint_volumes: OnceLock<JointVolumes>,
}

impl PyBinding {
    pub(crate) fn new(scene: Scene, binding: StarBinding) -> Self {
        Self {
            scene: PyScene {
                scene: scene.clone(),
            },
            deformer: FrameDeformer::new(scene, binding),
            joint_volumes: OnceLock::new(),
        }
    }
}

#[pymethods]
impl PyBinding {
    /// deform(cage_positions) -> array
    ///
    /// The welded mesh (n, 3) float64 for every cage vertex at `cage_positions` ((k, 3), the
    /// file's axes), with the binding's h.
    fn deform<'py>(
        &self,
        py: Python<'py>,
        cage_positions: PyArrayLike2<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let posed = self.scene.cages_in(&cage_positions)?;
        let binding = self.deformer.binding();
        let rest = &self.deformer.scene().cages.vertices;
        let deformed = py.detach(|| binding.deform(rest, &posed));
        let up = self.scene.scene.export_up();
        points_out(py, deformed.iter().map(|p| up.from_scene(p.as_dvec3())))
    }

    /// keep_joint_volumes(cage_positions, keep=None) -> array
    ///
    /// `cage_positions` ((k, 3), the file's axes) with every bent joint's ring scaled so that
    /// the mesh around the joint keeps its rest volume, as `starcages-cli deform --apply` and
    /// the editor pose (a pose of the controls, before hand moves of cage vertices). The
    /// cage vertices listed in `keep` (e.g. moved by hand) and the rings holding one are left
    /// alone.
    #[pyo3(signature = (cage_positions, keep = None))]
    fn keep_joint_volumes<'py>(
        &self,
        py: Python<'py>,
        cage_positions: PyArrayLike2<'py, f64, AllowTypeChange>,
        keep: Option<Vec<u32>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut posed = self.scene.cages_in(&cage_positions)?;
        let mut keep = keep.unwrap_or_default();
        keep.sort_unstable();
        let scene = self.deformer.scene();
        let binding = self.deformer.binding();
        let joint_volumes = &self.joint_volumes;
        py.detach(|| {
            let volumes = joint_volumes.get_or_init(|| {
                JointVolumes::new(
                    &scene.cages,
                    scene.mesh.welded_triangles(),
                    &binding.operator,
                )
            });
            volumes.settle(&binding.operator, &mut posed, None, &|v| {
                keep.binary_search(&v).is_ok()
            });
        });
        let up = self.scene.scene.export_up();
        points_out(py, posed.iter().map(|&p| up.from_scene(p)))
    }

    /// deform_frame(frame) -> array
    ///
    /// The welded mesh at animation `frame` (keys interpolated, keyed h applied: the cages
    /// whose h changed are bound again), as `starcages-cli deform --frame` gives it.
    fn deform_frame<'py>(
        &mut self,
        py: Python<'py>,
        frame: f64,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let pose = PoseRequest::frame(frame)
            .resolve(&self.scene.scene)
            .map_err(error)?;
        let control = BindControl::default();
        // Keyed h binds cages again: the joints' regions are built anew when next asked for.
        self.joint_volumes = OnceLock::new();
        let deformer = &mut self.deformer;
        let welded = py
            .detach(|| deformer.deform(&pose.cages, &pose.h, &control))
            .map_err(|e| error(format!("frame {frame}: {e}")))?;
        let up = self.scene.scene.export_up();
        points_out(py, welded.iter().map(|&p| up.from_scene(p)))
    }

    /// dofs(cage_positions) -> array
    ///
    /// The operator's degrees of freedom (float32, (dof_count, 3), scene axes) for cage
    /// positions in the file's axes: `S @ dofs + rest_offsets` is the deformed mesh in scene
    /// axes (`Scene.to_file_axes` turns it back).
    fn dofs<'py>(
        &self,
        py: Python<'py>,
        cage_positions: PyArrayLike2<'py, f64, AllowTypeChange>,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let posed = self.scene.cages_in(&cage_positions)?;
        let operator = &self.deformer.binding().operator;
        let dofs = operator.dofs(&self.deformer.scene().cages.vertices, &posed);
        points_out_f32(py, &dofs)
    }

    /// operator() -> dict
    ///
    /// The compiled operator S as CSR arrays that `scipy.sparse.csr_matrix((data, indices,
    /// indptr), shape=shape)` takes as they are: indptr (int64), indices (int32), data
    /// (float32), shape (vertices, dof_count), and rest_offsets ((vertices, 3) float32, scene
    /// axes): the mesh is `S @ dofs + rest_offsets`.
    fn operator<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let operator = &self.deformer.binding().operator;
        let (_, row_start, columns, values) = operator.parts();
        let d = PyDict::new(py);
        let indptr: Vec<i64> = row_start.iter().map(|&r| i64::from(r)).collect();
        let indices: Vec<i32> = columns
            .iter()
            .map(|&c| i32::try_from(c).map_err(|_| error("a column past 2^31")))
            .collect::<PyResult<_>>()?;
        d.set_item("indptr", Array1::from(indptr).into_pyarray(py))?;
        d.set_item("indices", Array1::from(indices).into_pyarray(py))?;
        d.set_item("data", Array1::from(values.to_vec()).into_pyarray(py))?;
        d.set_item("shape", (operator.row_count(), operator.dof_count()))?;
        d.set_item("rest_offsets", points_out_f32(py, operator.rest_offsets())?)?;
        Ok(d)
    }

    /// Welded mesh vertices the binding deforms.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.deformer.binding().operator.row_count()
    }

    /// Degrees of freedom (cage vertices, then Green face terms).
    #[getter]
    fn dof_count(&self) -> usize {
        self.deformer.binding().operator.dof_count()
    }

    /// Stored weights of the operator.
    #[getter]
    fn nonzeros(&self) -> usize {
        self.deformer.binding().operator.nonzeros()
    }

    /// bake(path, start=None, end=None) -> int
    ///
    /// Bakes the animation (every frame from `start` to `end`, by default the scene's range)
    /// into a PC2 or MDD point cache in the mesh file's vertex layout and axes, as
    /// `starcages-cli bake` does; returns the number of samples. Blender's Mesh Cache modifier
    /// reads it (set its Frame Start to the first frame).
    #[pyo3(signature = (path, start = None, end = None))]
    fn bake(
        &mut self,
        py: Python<'_>,
        path: PathBuf,
        start: Option<i64>,
        end: Option<i64>,
    ) -> PyResult<usize> {
        let scene = self.scene.scene.clone();
        let format = PointCacheFormat::of(&path).ok_or_else(|| {
            error(format!(
                "{}: bake writes point caches: name the file .pc2 or .mdd",
                path.display()
            ))
        })?;
        let range = match (start, end) {
            (None, None) => None,
            (s, e) => Some((
                s.unwrap_or(scene.animation.frame_start),
                e.unwrap_or(scene.animation.frame_end),
            )),
        };
        let (frames, times) =
            starcages_core::anim::sampling::animation_samples(&scene.animation, range, None)
                .map_err(error)?;
        let layout = ExportLayout::of(&scene).map_err(error)?;
        let mut writer =
            PointCacheWriter::create(&path, format, layout.len(&scene), frames.len(), times)
                .map_err(error)?;
        let control = BindControl::default();
        // Keyed h binds cages again: the joints' regions are built anew when next asked for.
        self.joint_volumes = OnceLock::new();
        let deformer = &mut self.deformer;
        py.detach(|| -> Result<(), String> {
            for &frame in &frames {
                let pose = PoseRequest::frame(frame)
                    .resolve(&scene)
                    .map_err(|e| format!("frame {frame}: {e}"))?;
                let welded = deformer
                    .deform(&pose.cages, &pose.h, &control)
                    .map_err(|e| format!("frame {frame}: {e}"))?;
                let positions: Vec<glam::Vec3> = layout
                    .positions(deformer.scene(), &welded)
                    .iter()
                    .map(|p| p.as_vec3())
                    .collect();
                writer.write_sample(&positions).map_err(|e| e.to_string())?;
            }
            writer.finish().map_err(|e| e.to_string())
        })
        .map_err(error)?;
        Ok(frames.len())
    }

    fn __repr__(&self) -> String {
        format!(
            "<starcages.Binding: {} vertices, {} degrees of freedom, {} weights>",
            self.vertex_count(),
            self.dof_count(),
            self.nonzeros()
        )
    }
}
