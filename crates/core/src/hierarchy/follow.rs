//! How an owned vertex follows its parent cage (section 3.4): coordinates computed at some
//! shape of the parent, or the λ·ΔU scheme where the parent's coordinates are undefined.

use std::sync::Arc;

use glam::DVec3;

use crate::cage::Cage;
use crate::coords::{BindControl, BindSettings, CageWeights, CoordError, CoordinateKind, bind};
use crate::scene::{AnchorRecord, FollowRecord};

/// Coordinates of one point with respect to the parent cage at a reference shape.
#[derive(Debug, Clone)]
pub(crate) struct Anchored {
    /// The parent at the shape the coordinates were computed for.
    pub reference: Arc<Cage>,
    /// The point, at that shape.
    pub point: DVec3,
    /// Its coordinates (one row).
    pub weights: CageWeights,
}

impl Anchored {
    /// T_c(point) for the parent's vertices now at `parent` (eq. 2; Lipman's map for GC).
    pub fn position(&self, parent: &[DVec3]) -> DVec3 {
        // The reference and `parent` come from the same cage, so the counts always agree.
        self.weights
            .deform(&self.reference, parent)
            .ok()
            .and_then(|p| p.first().copied())
            .unwrap_or(self.point)
    }

    /// The serialisable form.
    pub fn record(&self) -> AnchorRecord {
        AnchorRecord {
            point: self.point,
            parent_shape: self.reference.positions().to_vec(),
        }
    }
}

/// How an owned vertex follows its parent.
#[derive(Debug, Clone)]
pub(crate) enum Follow {
    /// v = T_c(v): coordinates of the vertex itself.
    Coordinates(Anchored),
    /// v'' = T'_c(a) + λ (T'_c(Δv) − T'_c(a)) (section 3.4), for HC parents the vertex was
    /// dragged out of (or close to the surface of).
    Lambda {
        /// a = T_c(v) before the hand edit.
        anchor: Anchored,
        /// Δv = a + ΔU, inside the parent.
        delta: Anchored,
        /// λ with U = λ ΔU.
        lambda: f64,
    },
    /// The parent's shape was not a valid cage at the re-bind: v = T'_c(a) + U.
    Offset {
        /// a = T_c(v) before the hand edit.
        anchor: Anchored,
        /// U.
        offset: DVec3,
    },
}

impl Follow {
    /// The vertex's position for the parent's vertices at `parent`.
    pub fn position(&self, parent: &[DVec3]) -> DVec3 {
        match self {
            Self::Coordinates(c) => c.position(parent),
            Self::Lambda {
                anchor,
                delta,
                lambda,
            } => {
                let a = anchor.position(parent);
                a + (delta.position(parent) - a) * *lambda
            }
            Self::Offset { anchor, offset } => anchor.position(parent) + *offset,
        }
    }

    /// The vertex's position as a linear combination of the parent's vertices, when it is one:
    /// the weights of MVC and HC coordinates (eq. 2), blended by λ for [`Follow::Lambda`]
    /// (an [`Follow::Offset`] adds a constant). None for Green coordinates, whose face normals
    /// make the position nonlinear in the parent's vertices.
    pub fn linear_weights(&self) -> Option<Vec<f64>> {
        let of = |a: &Anchored| match &a.weights {
            CageWeights::Vertex { weights, .. } if weights.point_count() == 1 => {
                Some(weights.row(0).to_vec())
            }
            _ => None,
        };
        match self {
            Self::Coordinates(a) | Self::Offset { anchor: a, .. } => of(a),
            Self::Lambda {
                anchor,
                delta,
                lambda,
            } => {
                let (a, d) = (of(anchor)?, of(delta)?);
                (a.len() == d.len()).then(|| {
                    a.iter()
                        .zip(&d)
                        .map(|(a, d)| (1.0 - lambda) * a + lambda * d)
                        .collect()
                })
            }
        }
    }

    /// Where the parent alone puts the vertex: T_c(v) before any hand edit.
    pub fn anchor(&self) -> &Anchored {
        match self {
            Self::Coordinates(a)
            | Self::Lambda { anchor: a, .. }
            | Self::Offset { anchor: a, .. } => a,
        }
    }

    /// The serialisable form.
    pub fn record(&self) -> FollowRecord {
        match self {
            Self::Coordinates(a) => FollowRecord::Coordinates(a.record()),
            Self::Lambda {
                anchor,
                delta,
                lambda,
            } => FollowRecord::Lambda {
                anchor: anchor.record(),
                delta: delta.record(),
                lambda: *lambda,
            },
            Self::Offset { anchor, offset } => FollowRecord::Offset {
                anchor: anchor.record(),
                offset: *offset,
            },
        }
    }
}

/// Coordinates of `points` with respect to `cage`, one [`Anchored`] each.
pub(crate) fn anchor_points(
    kind: CoordinateKind,
    cage: &Arc<Cage>,
    points: &[DVec3],
    settings: &BindSettings,
) -> Result<Vec<Anchored>, CoordError> {
    if points.is_empty() {
        return Ok(Vec::new());
    }
    let weights = bind(kind, cage, points, settings, &BindControl::default())?;
    Ok(points
        .iter()
        .enumerate()
        .map(|(i, &point)| Anchored {
            reference: Arc::clone(cage),
            point,
            weights: weights.row(i),
        })
        .collect())
}

/// A vertex moved by hand, to re-bind: its position and how it followed so far.
pub(crate) struct RebindRequest<'a> {
    /// Its position now (set by hand).
    pub point: DVec3,
    /// How it followed the parent until now.
    pub current: &'a Follow,
}

/// New followers for vertices moved by hand, against the parent's shape `shape` (the paper's
/// rule: coordinates recomputed from the current position). Where `kind` has no coordinates
/// outside the cage (HC), a vertex out of (or near the surface of) the parent gets the λ·ΔU
/// scheme: Δv = a + U/λ lies at most halfway from the anchor a to the surface along U, with
/// λ = max(1, 2 / t*) for the exit parameter t* of the ray a + tU, so λ and the response vary
/// continuously with the drag.
pub(crate) fn rebind(
    kind: CoordinateKind,
    faces: &[Vec<u32>],
    shape: &[DVec3],
    requests: &[RebindRequest<'_>],
    settings: &BindSettings,
) -> Result<Vec<Follow>, CoordError> {
    let Ok(cage) = Cage::from_polygons(shape.to_vec(), faces.to_vec()) else {
        return Ok(requests.iter().map(|r| offset(r, shape)).collect());
    };
    let cage = Arc::new(cage);
    if kind != CoordinateKind::Harmonic {
        let points: Vec<DVec3> = requests.iter().map(|r| r.point).collect();
        return Ok(anchor_points(kind, &cage, &points, settings)?
            .into_iter()
            .map(Follow::Coordinates)
            .collect());
    }
    // Plan each request: coordinates of the vertex itself, or of Δv with its λ.
    enum Plan {
        Direct,
        Lambda { anchor: Anchored, lambda: f64 },
        Offset,
    }
    let mut points = Vec::new();
    let plans: Vec<Plan> = requests
        .iter()
        .map(|r| {
            let anchor = r.current.anchor().clone();
            let a = anchor.position(shape);
            let u = r.point - a;
            if cage.winding_number(a) <= 0.5 {
                return Plan::Offset;
            }
            let exit = if u.length_squared() > 0.0 {
                cage.ray_exit(a, u)
            } else {
                f64::INFINITY
            };
            let lambda = (2.0 / exit).max(1.0);
            if lambda == 1.0 {
                points.push(r.point);
                Plan::Direct
            } else {
                points.push(a + u / lambda);
                Plan::Lambda { anchor, lambda }
            }
        })
        .collect();
    let mut bound = anchor_points(kind, &cage, &points, settings)?.into_iter();
    Ok(plans
        .into_iter()
        .zip(requests)
        .map(|(plan, r)| {
            match plan {
                Plan::Direct => bound.next().map(Follow::Coordinates),
                Plan::Lambda { anchor, lambda } => bound.next().map(|delta| Follow::Lambda {
                    anchor,
                    delta,
                    lambda,
                }),
                Plan::Offset => None,
            }
            .unwrap_or_else(|| offset(r, shape))
        })
        .collect())
}

/// The fallback follower: the anchor plus the hand displacement, for a parent shape that is not
/// a valid cage or an anchor that left the parent.
fn offset(request: &RebindRequest<'_>, shape: &[DVec3]) -> Follow {
    let anchor = request.current.anchor().clone();
    Follow::Offset {
        offset: request.point - anchor.position(shape),
        anchor,
    }
}
