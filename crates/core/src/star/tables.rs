//! What a bind's phases share: where points are placed, sparse rows, per-cage coordinate
//! tables and the per-join-cage data of Ω (eqs. 6, 7) and L_v (eqs. 9, 10).

use std::sync::Arc;

use glam::DVec3;

use super::StarError;
use super::topology::JoinCage;
use crate::coords::{BindControl, BindSettings, CageWeights, CoordinateKind, bind};
use crate::scene::{LocalCage, Smoothing};

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

/// Coordinates of a set of points in one cage.
pub(super) struct Table {
    /// The points, in the order of their rows (what the tests bind again alone).
    #[cfg_attr(not(test), allow(dead_code))]
    pub points: Vec<usize>,
    pub weights: CageWeights,
    /// Per point index, its row (`u32::MAX`: none): a point's rows are read in every table
    /// of its cage's join cages, where a binary search each was a twentieth of a bind.
    row_of: Vec<u32>,
}

impl Table {
    /// The table of `points` (distinct, in any order) with their coordinates `weights`, row by
    /// row.
    pub(super) fn new(points: Vec<usize>, weights: CageWeights) -> Self {
        let mut row_of = vec![u32::MAX; points.iter().max().map_or(0, |&i| i + 1)];
        for (k, &i) in points.iter().enumerate() {
            row_of[i] = k as u32;
        }
        Self {
            points,
            weights,
            row_of,
        }
    }

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
        Ok(Self::new(points, weights))
    }

    /// (vertex weights, Green ψ) of point `i`, if the table has it.
    pub(super) fn get(&self, i: usize) -> Option<(&[f64], Option<&[f64]>)> {
        let k = *self.row_of.get(i)? as usize;
        if k == u32::MAX as usize {
            return None;
        }
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
    /// For interior v: 1 / d(t, v) per far face, and per far face the least d(t, p) at which
    /// f(d(t, p) / d(t, v)) is exactly 1 (both empty for a boundary vertex of its join cage).
    pub inverse_normaliser: Vec<f64>,
    pub one_from: Vec<f64>,
}

impl JoinData<'_> {
    /// [`JoinData::inverse_normaliser`] and [`JoinData::one_from`] of `normaliser`.
    pub(super) fn interior_factors(normaliser: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let inverse: Vec<f64> = normaliser.iter().map(|&d| 1.0 / d).collect();
        let one_from = inverse.iter().map(|&x| least_argument_to_one(x)).collect();
        (inverse, one_from)
    }
}

/// The least d with fl(d · inverse) ≥ 1, so that f(d · inverse) = 1 exactly (the product is
/// rounded, so d ≥ 1 / inverse is not enough near it); +∞ where no d qualifies for certain (a
/// normaliser that is not positive and finite).
fn least_argument_to_one(inverse: f64) -> f64 {
    if !(inverse > 0.0 && inverse.is_finite()) {
        return f64::INFINITY;
    }
    let mut d = 1.0 / inverse;
    // Rounding is monotone in d: step up to the first d that reaches 1, then down while the
    // one below still does.
    while d * inverse < 1.0 {
        d = d.next_up();
    }
    while d.next_down() * inverse >= 1.0 {
        d = d.next_down();
    }
    d
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
        smoothing.product_of_unit(xs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The least argument at which a factor is exactly 1: there the rounded product
        /// reaches 1 and one step below it does not (d ≥ 1 / inverse alone fails: checked).
        #[test]
        fn the_least_argument_to_one_is_exact(normaliser in 1e-6f64..1.0) {
            let inverse = 1.0 / normaliser;
            let d = least_argument_to_one(inverse);
            prop_assert!(d * inverse >= 1.0);
            prop_assert!(d.next_down() * inverse < 1.0);
            prop_assert_eq!(Smoothing::Sine.eval(d * inverse, 1.0), 1.0);
        }
    }

    #[test]
    fn no_least_argument_without_a_positive_finite_normaliser() {
        for inverse in [0.0, -2.0, f64::INFINITY, f64::NAN] {
            assert_eq!(least_argument_to_one(inverse), f64::INFINITY);
        }
    }
}
