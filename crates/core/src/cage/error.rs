//! Problems a cage can have, each naming the element at fault and the fix.

use thiserror::Error;

/// Why a polygon soup is not a valid cage. Indices are 0-based, in input order: vertices as
/// given, faces as the input polygons (before triangulation).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CageError {
    /// Fewer than four vertices cannot enclose a volume.
    #[error("cage has {count} vertices; a closed cage needs at least 4")]
    TooFewVertices {
        /// Number of vertices given.
        count: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error(
        "vertex {vertex} has a non-finite coordinate ({x}, {y}, {z}); fix or remove that vertex"
    )]
    NonFiniteVertex {
        /// Offending vertex.
        vertex: usize,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
        /// z coordinate.
        z: f64,
    },
    /// A vertex coordinate beyond [`super::MAX_COORDINATE`].
    #[error(
        "vertex {vertex} has a coordinate of magnitude {value:e}, beyond ±{max:e} (the \
         deformation is computed in 32-bit floats); fix that vertex or scale the cage down",
        max = super::MAX_COORDINATE
    )]
    CoordinateTooLarge {
        /// Offending vertex.
        vertex: usize,
        /// Its largest absolute coordinate.
        value: f64,
    },
    /// A face has fewer than three corners.
    #[error("face {face} has {corners} corners; a face needs at least 3")]
    TooFewCorners {
        /// Offending face.
        face: usize,
        /// Number of corners.
        corners: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but the cage has only {count} vertices")]
    VertexOutOfRange {
        /// Offending face.
        face: usize,
        /// The missing vertex index.
        vertex: usize,
        /// Number of vertices.
        count: usize,
    },
    /// A face uses the same vertex twice.
    #[error("face {face} uses vertex {vertex} twice; remove the repeated corner")]
    RepeatedCorner {
        /// Offending face.
        face: usize,
        /// Repeated vertex.
        vertex: usize,
    },
    /// A face (or one triangle of a polygon's fan) has (almost) zero area.
    #[error("face {face} is degenerate (area {area:.3e}); merge or remove it")]
    DegenerateFace {
        /// Offending face.
        face: usize,
        /// Its area (of the offending fan triangle for polygons).
        area: f64,
    },
    /// Two vertices sit at the same position.
    #[error(
        "vertices {first} and {second} sit at the same position; move one away, or weld them \
         into one if they are the same corner"
    )]
    DuplicateVertex {
        /// Lower index.
        first: usize,
        /// Higher index.
        second: usize,
    },
    /// A vertex is used by no face.
    #[error("vertex {vertex} is used by no face; remove it")]
    UnusedVertex {
        /// Offending vertex.
        vertex: usize,
    },
    /// An edge has a single face: the cage has a hole.
    #[error(
        "cage is not closed: edge ({a}, {b}) has only face {face}; close the hole along that edge"
    )]
    OpenEdge {
        /// First vertex of the edge.
        a: usize,
        /// Second vertex of the edge.
        b: usize,
        /// The one face on it.
        face: usize,
    },
    /// An edge has more than two faces.
    #[error("edge ({a}, {b}) is non-manifold: {faces} faces share it; split the cage there")]
    NonManifoldEdge {
        /// First vertex of the edge.
        a: usize,
        /// Second vertex of the edge.
        b: usize,
        /// Number of faces on it.
        faces: usize,
    },
    /// Two neighbouring faces run their shared edge in the same direction.
    #[error(
        "faces {first} and {second} have inconsistent orientation along edge ({a}, {b}); flip face {second}"
    )]
    InconsistentOrientation {
        /// A face using the directed edge.
        first: usize,
        /// Another face using it in the same direction.
        second: usize,
        /// Edge start.
        a: usize,
        /// Edge end.
        b: usize,
    },
    /// The faces are consistent but their normals point inwards.
    #[error(
        "cage is oriented inwards (signed volume {volume:.3e}); flip all faces so normals point out"
    )]
    InwardOrientation {
        /// Signed volume (negative).
        volume: f64,
    },
    /// An edge passes through a face of the same cage.
    #[error(
        "cage passes through itself: edge ({a}, {b}) crosses face {face}; move the vertices \
         that were pushed through so that the surface no longer folds over itself"
    )]
    SelfIntersecting {
        /// First vertex of the edge.
        a: usize,
        /// Second vertex of the edge.
        b: usize,
        /// The face it crosses.
        face: usize,
    },
}
