//! The rig operations as values: what each changes, and the faces they name.

use glam::DVec3;

use crate::coords::CoordinateKind;

/// One rig operation.
#[derive(Debug, Clone, PartialEq)]
pub enum RigOp {
    /// A new axis-aligned box leaf cage from `min` to `max` (corners at positions of existing
    /// vertices reuse them, so a box beside a cage shares its face).
    AddBox {
        /// Its name.
        name: String,
        /// One corner.
        min: DVec3,
        /// The opposite corner.
        max: DVec3,
        /// Its coordinates.
        kind: CoordinateKind,
    },
    /// A new leaf cage on a face of `cage`, pushed out `distance` along its outward normal; the
    /// new cage shares that face with `cage`.
    Extrude {
        /// The cage.
        cage: String,
        /// The face: by index or by the direction it faces.
        face: FaceRef,
        /// How far.
        distance: f64,
        /// The new cage's name.
        name: String,
    },
    /// Inset a face no other cage shares (Blender's Inset Faces): a smaller copy of it,
    /// `thickness` inside each of its edges in its plane, joined to its edges by a ring of
    /// quads. The cage keeps its shape; the inner face can then be extruded, so the new cage
    /// touches no vertex of the face's edges (and no cage beyond them).
    Inset {
        /// The cage.
        cage: String,
        /// The face: by index or by the direction it faces.
        face: FaceRef,
        /// Distance from each edge to the inner face's edge, in scene units.
        thickness: f64,
    },
    /// Remove a leaf cage; vertices no other cage uses go.
    Delete {
        /// The cage.
        cage: String,
    },
    /// A copy of `cage` mirrored across x = 0 (vertices on the plane are shared).
    Mirror {
        /// The cage.
        cage: String,
        /// The copy's name.
        name: String,
    },
    /// Join two neighbouring cages into the first (the faces they share dissolve).
    Merge {
        /// The cage that stays.
        first: String,
        /// The cage merged into it.
        second: String,
    },
    /// Loop cut: split a cage whose faces are two ends and a ring of quads between them (a box,
    /// an extruded cage) across the ring, at fraction `t` from the end facing −`axis`; the
    /// two parts share the new face.
    Split {
        /// The cage.
        cage: String,
        /// The world axis the cut goes across (0 x, 1 y, 2 z): the ends are the faces whose
        /// normals are most aligned with it.
        axis: usize,
        /// Where, in (0, 1).
        t: f64,
        /// The new part's name (the part beyond the cut).
        name: String,
    },
    /// Fit to mesh (a shrink-wrap): pull each of the cage's vertices that no other leaf cage
    /// shares toward the mesh vertex nearest to it, as far as keeps every mesh vertex it holds
    /// inside with `margin` (a fraction of the mesh's bounding box diagonal) between them and
    /// the cage; a mesh vertex already closer than that keeps the distance it has.
    Fit {
        /// The cage.
        cage: String,
        /// The margin, as a fraction of the mesh's diagonal.
        margin: f64,
    },
    /// Give a leaf cage other coordinates.
    Kind {
        /// The cage.
        cage: String,
        /// Its new coordinates.
        kind: CoordinateKind,
    },
    /// Set the blending parameter h (eq. 11) of one leaf cage, or with `cage` = `all` the
    /// scene's default h (cages without their own h use it).
    H {
        /// The cage, or `all`.
        cage: String,
        /// h in (0, 1].
        h: f64,
    },
    /// Subdivide every face of every leaf cage into quads (a vertex at each edge's midpoint and
    /// at each face's centre, Blender's Subdivide). Shared faces and edges are cut the same way
    /// on both sides, so the rig stays watertight; poses get the same midpoints of their own
    /// positions. Refused while internal cages drive leaf vertices (the new vertices would
    /// have no driver).
    Subdivide,
    /// Weld: merge cage vertices no farther apart than `distance` (0: only those at exactly
    /// the same position), so cages that touch there share their border (see `weld_vertices`).
    Weld {
        /// The distance, in scene units.
        distance: f64,
    },
    /// Move a cage's rest vertices (and every pose by the same amount).
    Rest {
        /// The cage.
        cage: String,
        /// How.
        transform: RestTransform,
    },
}

/// A face of a cage, named by its index in the cage's face list (0-based, as in the scene
/// file) or by the direction it faces (`+x`, `-z`, …: the face whose outward normal is most
/// aligned with that axis, so a script reads as what it builds; among coplanar faces the one
/// listed first, which after an inset is the inner face).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaceRef {
    /// By index.
    Index(usize),
    /// By direction: the axis (0 x, 1 y, 2 z) and whether it is the positive one.
    Facing {
        /// The world axis.
        axis: usize,
        /// Towards +axis (true) or −axis.
        positive: bool,
    },
}

impl FaceRef {
    /// Reads a face number or a direction (`+x`, `-z`, …).
    pub fn parse(text: &str) -> Result<Self, String> {
        let direction = |axis: usize| match text.as_bytes().first() {
            Some(b'+') => Some(Self::Facing {
                axis,
                positive: true,
            }),
            Some(b'-') => Some(Self::Facing {
                axis,
                positive: false,
            }),
            _ => None,
        };
        match text.get(1..) {
            Some("x" | "X") => direction(0),
            Some("y" | "Y") => direction(1),
            Some("z" | "Z") => direction(2),
            _ => None,
        }
        .or_else(|| text.parse().ok().map(Self::Index))
        .ok_or_else(|| {
            format!(
                "face '{text}' is neither a face number nor a direction (+x, -x, +y, -y, +z, -z)"
            )
        })
    }
}

impl std::fmt::Display for FaceRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Index(i) => write!(f, "{i}"),
            Self::Facing { axis, positive } => write!(
                f,
                "{}{}",
                if *positive { '+' } else { '-' },
                ['x', 'y', 'z'][(*axis).min(2)]
            ),
        }
    }
}

/// A change of a cage's rest positions, about the centroid of its vertices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RestTransform {
    /// Move by this vector.
    Translate(DVec3),
    /// Turn about this axis by degrees.
    Rotate(DVec3, f64),
    /// Scale by this factor.
    Scale(f64),
}
