//! What a bind's phases share: where points are placed, sparse rows, per-cage coordinate
//! tables and the per-join-cage data of Ω (eqs. 6, 7) and L_v (eqs. 9, 10).

use std::sync::Arc;

use glam::DVec3;

use super::StarError;
use super::topology::JoinCage;
use crate::coords::{BindControl, BindSettings, CageWeights, CoordinateKind, bind};
use crate::scene::{LocalCage, Smoothing, product_of};

/// Where a point is bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Placement {
    /// Inside (or on) this leaf cage.
    Cage(usize),
    /// Outside every cage, following this nearest cage (the scene's `nearest` policy).
    Nearest(usize),
}

/// A sparse row over the operator's columns: cage vertices, then Green DOFs.
pub(crate) type Row = Vec<(u32, f64)>;

/// Coordinates of a sorted set of points in one cage.
pub(super) struct Table {
    pub points: Vec<usize>,
    pub weights: CageWeights,
}

impl Table {
    pub(super) fn compute(
        kind: CoordinateKind,
        cage: &LocalCage,
        all: &[DVec3],
        points: Vec<usize>,
        settings: &BindSettings,
        control: &BindControl,
        what: &str,
    ) -> Result<Self, StarError> {
        let positions: Vec<DVec3> = points.iter().map(|&i| all[i]).collect();
        let weights = bind(kind, &cage.cage, &positions, settings, control).map_err(|source| {
            StarError::Coordinates {
                what: what.to_owned(),
                source,
            }
        })?;
        Ok(Self { points, weights })
    }

    /// (vertex weights, Green ψ) of point `i`, if the table has it.
    pub(super) fn get(&self, i: usize) -> Option<(&[f64], Option<&[f64]>)> {
        let k = self.points.binary_search(&i).ok()?;
        Some(match &self.weights {
            CageWeights::Vertex { weights, .. } => (weights.row(k), None),
            CageWeights::Green(g) => (g.phi_row(k), Some(g.psi_row(k))),
        })
    }
}

/// Adds `scale` × a coordinate row of `cage` (local vertices, optional ψ over its triangles).
pub(super) fn add_row(
    out: &mut Row,
    scale: f64,
    (w, psi): (&[f64], Option<&[f64]>),
    cage: &LocalCage,
    dofs: &[u32],
    vertex_count: u32,
) {
    for (k, &x) in w.iter().enumerate() {
        if x != 0.0 {
            out.push((cage.global[k], scale * x));
        }
    }
    if let Some(psi) = psi {
        for (t, &x) in psi.iter().enumerate() {
            if x != 0.0 {
                out.push((vertex_count + dofs[t], scale * x));
            }
        }
    }
}

/// Sorts a row by column and sums duplicates, in place (no second allocation per row).
pub(super) fn merge(mut row: Row) -> Row {
    row.sort_unstable_by_key(|&(c, _)| c);
    let mut kept = 0;
    for read in 0..row.len() {
        let (c, w) = row[read];
        if kept > 0 && row[kept - 1].0 == c {
            row[kept - 1].1 += w;
        } else {
            row[kept] = (c, w);
            kept += 1;
        }
    }
    row.truncate(kept);
    row
}

/// Per join cage: Ω's faces and normalisers, and the special points' coordinates.
pub(super) struct JoinData<'a> {
    pub join: &'a JoinCage,
    /// Faces of jc(v) not incident to v, as local vertex lists (F(jc(v), v) in eq. 6).
    pub far_faces: Arc<Vec<Vec<usize>>>,
    /// d_{jc(v)}(t, v) per far face (1 for non-interior v).
    pub normaliser: Vec<f64>,
    /// Interpolating coordinates (MVC/HC) of the points that need Ω(v, ·).
    pub interp: Option<Arc<Table>>,
    /// Coordinates of kind `join.kind` of the points that need L_v.
    pub transform: Option<Arc<Table>>,
    /// For interior v: row of T_{jc(v)}(v) (eq. 10).
    pub vertex_row: Row,
    pub dofs: Vec<u32>,
}

impl JoinData<'_> {
    /// Ω(v, p) (eq. 6) from p's interpolating weights in jc(v).
    pub(super) fn omega(&self, w: &[f64], smoothing: Smoothing) -> f64 {
        self.omega_with(w, smoothing, &mut Vec::new())
    }

    /// [`JoinData::omega`] with a scratch list of the factors.
    pub(super) fn omega_with(&self, w: &[f64], smoothing: Smoothing, xs: &mut Vec<f64>) -> f64 {
        xs.clear();
        // d_{jc(v)}(t, p) = 1 − Σ_{u ∈ V(t)} w(u, p)   (eq. 7), over d_{jc(v)}(t, v)
        xs.extend(
            self.far_faces
                .iter()
                .zip(&self.normaliser)
                .map(|(face, &dv)| (1.0 - face.iter().map(|&k| w[k]).sum::<f64>()) / dv),
        );
        // Ω(v, p) = Π_{t ∈ F(jc(v), v)} f(d(t, p) / d(t, v))   (eq. 6)
        smoothing.eval_unit_in_place(xs);
        product_of(xs)
    }
}
