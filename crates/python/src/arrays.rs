//! numpy arrays in and out: points (n, 3) float64, triangles (m, 3) uint32, checked on the
//! way in (shape, finite values, vertex indices in range) with a message naming what is wrong.

use glam::{DVec3, Vec3};
use numpy::ndarray::Array2;
use numpy::{AllowTypeChange, IntoPyArray as _, PyArray2, PyArrayLike2};
use pyo3::prelude::*;

use crate::error;

/// Points from an (n, 3) array (any real dtype, or nested lists), every coordinate finite.
pub fn points_in(
    array: &PyArrayLike2<'_, f64, AllowTypeChange>,
    what: &str,
) -> PyResult<Vec<DVec3>> {
    let view = array.as_array();
    if view.ncols() != 3 {
        return Err(error(format!(
            "{what}: an array of shape (n, 3) is expected, not {:?}",
            view.shape()
        )));
    }
    view.rows()
        .into_iter()
        .enumerate()
        .map(|(i, row)| {
            let p = DVec3::new(row[0], row[1], row[2]);
            if p.is_finite() {
                Ok(p)
            } else {
                Err(error(format!("{what}: row {i} is not finite ({p})")))
            }
        })
        .collect()
}

/// Triangles from an (m, 3) integer array, every index below `vertices`.
pub fn triangles_in(
    array: &PyArrayLike2<'_, i64, AllowTypeChange>,
    vertices: usize,
) -> PyResult<Vec<[u32; 3]>> {
    let view = array.as_array();
    if view.ncols() != 3 {
        return Err(error(format!(
            "triangles: an array of shape (m, 3) is expected, not {:?}",
            view.shape()
        )));
    }
    view.rows()
        .into_iter()
        .enumerate()
        .map(|(i, row)| {
            let mut t = [0u32; 3];
            for (k, &v) in row.iter().enumerate() {
                t[k] = u32::try_from(v)
                    .ok()
                    .filter(|&v| (v as usize) < vertices)
                    .ok_or_else(|| {
                        error(format!(
                            "triangles: row {i} names vertex {v}, but there are {vertices} \
                             (numbered from 0)"
                        ))
                    })?;
            }
            Ok(t)
        })
        .collect()
}

/// An (n, 3) float64 array of `points`.
pub fn points_out<'py>(
    py: Python<'py>,
    points: impl ExactSizeIterator<Item = DVec3>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = points.len();
    let flat: Vec<f64> = points.flat_map(|p| p.to_array()).collect();
    Array2::from_shape_vec((n, 3), flat)
        .map(|a| a.into_pyarray(py))
        .map_err(error)
}

/// An (n, 3) float32 array of `points`.
pub fn points_out_f32<'py>(
    py: Python<'py>,
    points: &[Vec3],
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let flat: Vec<f32> = points.iter().flat_map(|p| p.to_array()).collect();
    Array2::from_shape_vec((points.len(), 3), flat)
        .map(|a| a.into_pyarray(py))
        .map_err(error)
}

/// An (m, 3) uint32 array of `triangles`.
pub fn triangles_out<'py>(
    py: Python<'py>,
    triangles: &[[u32; 3]],
) -> PyResult<Bound<'py, PyArray2<u32>>> {
    let flat: Vec<u32> = triangles.iter().flatten().copied().collect();
    Array2::from_shape_vec((triangles.len(), 3), flat)
        .map(|a| a.into_pyarray(py))
        .map_err(error)
}
