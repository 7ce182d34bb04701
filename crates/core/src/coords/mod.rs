//! Cage coordinates: one API over Mean Value, Harmonic and Green coordinates.
//!
//! [`bind`] computes the coordinates of a batch of points with respect to a cage, in parallel,
//! in f64, and returns [`CageWeights`]: dense rows (one per point) that the sparse deformation
//! operator consumes. [`CageWeights::deform`] applies eq. 2 of *Cages (T_c(p) = Σ w_c(v,p) v'),
//! or Lipman et al.'s f(p) = Σ φ_i v'_i + Σ ψ_j s_j n'_j for Green coordinates.
//!
//! Conventions (also in `docs/coordinates.md`): weights are over the cage's vertices in input
//! order; Green ψ are over the cage's triangles in input order after triangulation (fan order
//! for polygons).

mod control;
mod green;
mod harmonic;
pub(crate) mod lanes;
mod mvc;
mod mvc_pool;
pub(crate) use mvc_pool::bind_mean_value_pooled;

use std::fmt;
use std::str::FromStr;

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::cage::Cage;

pub use control::BindControl;
pub use green::green_stretch;
pub(crate) use green::triangle_stretch;
pub use harmonic::{HarmonicSettings, clear_harmonic_cache};
#[cfg(test)]
pub(crate) use harmonic::{functions_solved_of, solves_of};
pub use lanes::{SIMD_ENV, lane_backend};

/// The coordinate systems a cage can use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum CoordinateKind {
    /// Mean Value Coordinates (Ju et al. 2005): defined everywhere, may be negative.
    #[serde(rename = "mvc")]
    MeanValue,
    /// Harmonic Coordinates (Joshi et al. 2007): non-negative, inside the cage only.
    #[serde(rename = "hc")]
    Harmonic,
    /// Green Coordinates (Lipman et al. 2008): shape preserving, vertex and face terms.
    #[serde(rename = "gc")]
    Green,
}

impl CoordinateKind {
    /// Every kind, in menu order.
    pub const ALL: [Self; 3] = [Self::MeanValue, Self::Harmonic, Self::Green];

    /// Short name used in files and on the command line: `mvc`, `hc`, `gc`.
    pub fn short_name(self) -> &'static str {
        match self {
            Self::MeanValue => "mvc",
            Self::Harmonic => "hc",
            Self::Green => "gc",
        }
    }
}

impl fmt::Display for CoordinateKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.short_name())
    }
}

impl FromStr for CoordinateKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "mvc" | "mean-value" | "meanvalue" => Ok(Self::MeanValue),
            "hc" | "harmonic" => Ok(Self::Harmonic),
            "gc" | "green" => Ok(Self::Green),
            other => Err(format!(
                "unknown coordinate kind '{other}'; use mvc, hc or gc"
            )),
        }
    }
}

/// Settings of a bind.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct BindSettings {
    /// Discretisation of harmonic coordinates.
    pub harmonic: HarmonicSettings,
}

/// Why coordinates could not be computed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CoordError {
    /// A point has a NaN or infinite coordinate.
    #[error("point {index} has a non-finite coordinate; fix the input point")]
    NonFinitePoint {
        /// The point's index.
        index: usize,
    },
    /// Harmonic coordinates are undefined outside the cage.
    #[error(
        "{count} point(s) lie outside the cage, where harmonic coordinates are undefined \
         (points {listed}); enlarge the cage or use mvc or gc"
    )]
    OutsideCage {
        /// Indices of the outside points (all of them).
        points: Vec<usize>,
        /// Their number.
        count: usize,
        /// The first few, formatted.
        listed: String,
    },
    /// Mean value coordinates were asked for points too far from the cage to be accurate.
    #[error(
        "{count} point(s) lie more than {MVC_RANGE_IN_DIAGONALS} cage diagonals from the cage's \
         centre (points {listed}), where mean value coordinates lose their accuracy (the weights \
         of faces seen from both sides cancel); use gc, which stays accurate at any distance, \
         or a cage closer to the points"
    )]
    TooFarForMeanValue {
        /// Indices of the far points (all of them).
        points: Vec<usize>,
        /// Their number.
        count: usize,
        /// The first few, formatted.
        listed: String,
    },
    /// A posed cage has another vertex count than the bound one.
    #[error("posed cage has {got} vertices but the weights were bound to {expected}")]
    PoseMismatch {
        /// Vertices bound.
        expected: usize,
        /// Vertices given.
        got: usize,
    },
    /// The harmonic solver hit its iteration cap (a degenerate cage or too low a cap).
    #[error(
        "harmonic coordinates did not converge in {iterations} iterations; raise max_iterations or check the cage"
    )]
    NotConverged {
        /// Iterations run.
        iterations: usize,
    },
    /// The bind was cancelled through its [`BindControl`].
    #[error("binding was cancelled")]
    Cancelled,
    /// Settings outside their limits (the message names the value and the range).
    #[error("{0}")]
    Settings(String),
}

impl CoordError {
    fn outside(points: Vec<usize>) -> Self {
        let listed = crate::messages::list_first(&points, 10);
        Self::OutsideCage {
            count: points.len(),
            points,
            listed,
        }
    }
}

/// Dense per-point weights over the cage vertices: `#points × #vertices`, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct VertexWeights {
    /// Number of cage vertices (row length).
    pub vertex_count: usize,
    /// Row-major weights.
    pub weights: Vec<f64>,
}

impl VertexWeights {
    /// Number of points (rows).
    pub fn point_count(&self) -> usize {
        self.weights
            .len()
            .checked_div(self.vertex_count)
            .unwrap_or(0)
    }

    /// Weights of point `i` over the cage vertices.
    pub fn row(&self, i: usize) -> &[f64] {
        &self.weights[i * self.vertex_count..(i + 1) * self.vertex_count]
    }
}

/// Green coordinates: φ over vertices (`#points × #vertices`) and ψ over triangles
/// (`#points × #triangles`), both row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct GreenWeights {
    /// Number of cage vertices.
    pub vertex_count: usize,
    /// Number of cage triangles.
    pub face_count: usize,
    /// Vertex coordinates φ.
    pub phi: Vec<f64>,
    /// Face coordinates ψ.
    pub psi: Vec<f64>,
}

impl GreenWeights {
    /// φ of point `i`.
    pub fn phi_row(&self, i: usize) -> &[f64] {
        &self.phi[i * self.vertex_count..(i + 1) * self.vertex_count]
    }

    /// ψ of point `i`.
    pub fn psi_row(&self, i: usize) -> &[f64] {
        &self.psi[i * self.face_count..(i + 1) * self.face_count]
    }
}

/// Coordinates of a batch of points with respect to one cage.
#[derive(Debug, Clone, PartialEq)]
pub enum CageWeights {
    /// MVC or HC: one weight per cage vertex.
    Vertex {
        /// Which kind produced them.
        kind: CoordinateKind,
        /// The weights.
        weights: VertexWeights,
    },
    /// GC: φ per vertex and ψ per face.
    Green(GreenWeights),
}

impl CageWeights {
    /// The kind that produced these weights.
    pub fn kind(&self) -> CoordinateKind {
        match self {
            Self::Vertex { kind, .. } => *kind,
            Self::Green(_) => CoordinateKind::Green,
        }
    }

    /// Number of points bound.
    pub fn point_count(&self) -> usize {
        match self {
            Self::Vertex { weights, .. } => weights.point_count(),
            Self::Green(g) => g.phi.len().checked_div(g.vertex_count).unwrap_or(0),
        }
    }

    /// The weights of point `i` alone.
    pub fn row(&self, i: usize) -> CageWeights {
        match self {
            Self::Vertex { kind, weights } => Self::Vertex {
                kind: *kind,
                weights: VertexWeights {
                    vertex_count: weights.vertex_count,
                    weights: weights.row(i).to_vec(),
                },
            },
            Self::Green(g) => Self::Green(GreenWeights {
                vertex_count: g.vertex_count,
                face_count: g.face_count,
                phi: g.phi_row(i).to_vec(),
                psi: g.psi_row(i).to_vec(),
            }),
        }
    }

    /// Bytes of weights stored.
    pub fn byte_size(&self) -> usize {
        match self {
            Self::Vertex { weights, .. } => weights.weights.len() * 8,
            Self::Green(g) => (g.phi.len() + g.psi.len()) * 8,
        }
    }

    /// Positions of the bound points under the posed cage `posed` (same vertex order as the
    /// rest cage `cage` they were bound to): eq. 2 of *Cages, or Lipman et al.'s GC map.
    pub fn deform(&self, cage: &Cage, posed: &[DVec3]) -> Result<Vec<DVec3>, CoordError> {
        if posed.len() != cage.vertex_count() {
            return Err(CoordError::PoseMismatch {
                expected: cage.vertex_count(),
                got: posed.len(),
            });
        }
        Ok(match self {
            Self::Vertex { weights, .. } => (0..weights.point_count())
                .into_par_iter()
                .map(|i| weights.row(i).iter().zip(posed).map(|(&w, &v)| w * v).sum())
                .collect(),
            Self::Green(g) => {
                let stretch = green_stretch(cage, posed);
                let scaled_normals: Vec<DVec3> = cage
                    .triangle_normals_at(posed)
                    .iter()
                    .zip(&stretch)
                    .map(|(n, s)| *n * *s)
                    .collect();
                (0..self.point_count())
                    .into_par_iter()
                    .map(|i| {
                        let vertex_part: DVec3 =
                            g.phi_row(i).iter().zip(posed).map(|(&w, &v)| w * v).sum();
                        let face_part: DVec3 = g
                            .psi_row(i)
                            .iter()
                            .zip(&scaled_normals)
                            .map(|(&w, &n)| w * n)
                            .sum();
                        vertex_part + face_part
                    })
                    .collect()
            }
        })
    }
}

/// How far from a cage (in cage diagonals, from the centre of its bounding box) mean value
/// coordinates are computed. Outside a cage the weights of the faces seen from the front and from
/// the back cancel, so the error relative to the distance grows with about its square: measured
/// on random affine images of an icosahedron it is 1e-10 at 100 diagonals, 1e-8 at 1000 and
/// 1e-6 at 10 000 (`docs/math.md`, "Mean value coordinates far from the cage"). Within this range
/// they reproduce points to 1e-6 of their distance, with a margin.
pub const MVC_RANGE_IN_DIAGONALS: f64 = 1000.0;

/// Refuses points beyond [`MVC_RANGE_IN_DIAGONALS`] rather than returning weights that do not
/// reproduce them.
fn check_mean_value_range(cage: &Cage, points: &[DVec3]) -> Result<(), CoordError> {
    let (lo, hi) = cage.bounds();
    let centre = 0.5 * (lo + hi);
    let limit = MVC_RANGE_IN_DIAGONALS * cage.diagonal();
    let far: Vec<usize> = points
        .iter()
        .enumerate()
        .filter(|(_, p)| p.distance(centre) > limit)
        .map(|(i, _)| i)
        .collect();
    if far.is_empty() {
        return Ok(());
    }
    Err(CoordError::TooFarForMeanValue {
        listed: crate::messages::list_first(&far, 10),
        count: far.len(),
        points: far,
    })
}

/// Computes coordinates of `points` with respect to `cage`, in parallel.
///
/// GC are defined everywhere; MVC within [`MVC_RANGE_IN_DIAGONALS`] of the cage (beyond it
/// they fail with [`CoordError::TooFarForMeanValue`]); HC only inside (and on) the cage, and
/// fail with [`CoordError::OutsideCage`] naming every outside point. `control` reports progress and can
/// cancel the work from another thread.
pub fn bind(
    kind: CoordinateKind,
    cage: &Cage,
    points: &[DVec3],
    settings: &BindSettings,
    control: &BindControl,
) -> Result<CageWeights, CoordError> {
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(CoordError::NonFinitePoint { index });
    }
    let n = cage.vertex_count();
    Ok(match kind {
        CoordinateKind::MeanValue => {
            check_mean_value_range(cage, points)?;
            control.add_kernel_pairs(points.len() as u64 * cage.triangles().len() as u64);
            let mut weights = vec![0.0; points.len() * n];
            control.set_total(points.len().div_ceil(CHUNK));
            weights
                .par_chunks_mut(CHUNK * n.max(1))
                .zip(points.par_chunks(CHUNK))
                .try_for_each(|(rows, points)| {
                    control.check()?;
                    lanes::run_kernel(mvc::MvcRows { cage, points, rows });
                    control.advance();
                    Ok::<(), CoordError>(())
                })?;
            CageWeights::Vertex {
                kind,
                weights: VertexWeights {
                    vertex_count: n,
                    weights,
                },
            }
        }
        CoordinateKind::Harmonic => CageWeights::Vertex {
            kind,
            weights: VertexWeights {
                vertex_count: n,
                weights: harmonic::harmonic_bind(cage, points, &settings.harmonic, control)?,
            },
        },
        CoordinateKind::Green => {
            let gc = green::GreenCage::new(cage);
            let f = cage.triangles().len();
            control.add_kernel_pairs(points.len() as u64 * f as u64);
            let mut phi = vec![0.0; points.len() * n];
            let mut psi = vec![0.0; points.len() * f];
            control.set_total(points.len().div_ceil(CHUNK));
            phi.par_chunks_mut(CHUNK * n.max(1))
                .zip(psi.par_chunks_mut(CHUNK * f.max(1)))
                .zip(points.par_chunks(CHUNK))
                .try_for_each(|((phi, psi), points)| {
                    control.check()?;
                    let gc = &gc;
                    lanes::run_kernel(green::GreenRows {
                        cage,
                        gc,
                        points,
                        phi,
                        psi,
                    });
                    control.advance();
                    Ok::<(), CoordError>(())
                })?;
            CageWeights::Green(GreenWeights {
                vertex_count: n,
                face_count: f,
                phi,
                psi,
            })
        }
    })
}

/// Points per parallel work item (and per progress step).
const CHUNK: usize = 64;
