//! *Cages (section 3 of the paper): leaf cages glued C1-smoothly by join transformations,
//! compiled into one sparse linear operator.
//!
//! * [`topology`]: adjacency, borders, boundaries, join cages, interior vertices.
//! * `bind`: the rows of S (eq. 3) for a set of points, coordinates in batches.
//! * `operator`: the f32 CSR operator ([`StarOperator`]), its transpose, full and incremental
//!   application.
//! * `green_dofs`: Green face degrees of freedom.
//! * `cache`: the binding cache beside a scene file.

mod assemble;
mod bind;
mod cache;
mod drag;
mod green_dofs;
mod operator;
mod partial;
mod pooled_joins;
mod shape_class;
mod splice_rows;
mod splice_transpose;
mod tables;
pub mod topology;

use std::time::Instant;

use glam::{DVec3, Vec3};
use thiserror::Error;

pub use bind::Placement;
pub use cache::{binding_key, decode_binding_cache, encode_binding_cache};
pub use drag::DriverMap;
pub use green_dofs::GreenDofs;
pub use operator::StarOperator;
pub use topology::{Border, JoinCage, Topology, TopologyError};

use crate::coords::{BindControl, CoordError, CoordinateKind};
use crate::scene::{CageSet, LeafCage, OutsidePolicy, Scene, leaf_containment};

/// Why a scene could not be bound.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum StarError {
    /// The cage topology is unusable.
    #[error(transparent)]
    Topology(#[from] TopologyError),
    /// Coordinates failed in one cage.
    #[error("{what}: {source}")]
    Coordinates {
        /// Which cage.
        what: String,
        /// Why.
        source: CoordError,
    },
    /// Points outside every leaf cage under the `error` outside policy.
    #[error(
        "{count} point(s) lie outside every leaf cage (first: {listed}); enlarge the cages or set the \
         scene's outside policy to 'nearest'"
    )]
    Outside {
        /// How many.
        count: usize,
        /// The first few, formatted.
        listed: String,
    },
    /// Cancelled through the [`BindControl`].
    #[error("binding was cancelled")]
    Cancelled,
    /// Eq. 8 would take too long: the interior vertices of a border (a finely subdivided
    /// shared face) each weigh every point and every other such vertex over all the faces of
    /// their join cage.
    #[error(
        "binding would take about {estimate}: the border of cages {cages} holds {interior} \
         vertices inside it (not on its edges), and eq. 8 weighs each of them at every point and \
         every other such vertex over all {faces} faces of its join cage; use fewer subdivisions \
         on the shared faces (dissolve or weld vertices there), or split the cages so that each \
         border is smaller"
    )]
    TooMuchWork {
        /// The leaf cages of the worst border, named.
        cages: String,
        /// Interior vertices on it.
        interior: usize,
        /// Faces of its join cage.
        faces: usize,
        /// The time it would take, in words.
        estimate: String,
    },
    /// A partial re-bind was asked of a binding made for another mesh.
    #[error(
        "the binding has {rows} rows but the mesh has {vertices} vertices; bind the scene again"
    )]
    StaleBinding {
        /// Rows of the binding.
        rows: usize,
        /// Welded mesh vertices.
        vertices: usize,
    },
}

/// Timings and sizes of a bind (the paper's Table I/II columns).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BindStats {
    /// Seconds spent on leaf-cage coordinates.
    pub seconds_cage_coordinates: f64,
    /// Seconds spent on join cages (coordinates and Ω normalisers).
    pub seconds_join_cages: f64,
    /// Total seconds, placement and packing included.
    pub seconds_total: f64,
    /// Of `seconds_total`, the seconds a partial re-bind spent splicing its rows into the
    /// operator and the join weights (0 for a full bind).
    pub seconds_splice: f64,
    /// Bytes of the CSR operator.
    pub operator_bytes: usize,
    /// Bytes of the transpose (for incremental updates).
    pub transpose_bytes: usize,
    /// Stored non-zero weights.
    pub nonzeros: usize,
    /// Point·triangle pairs the MVC and GC kernels evaluated for this bind
    /// ([`BindControl::kernel_pairs`]): its physical floor, the time the coordinates alone
    /// need, in kernel evaluations (harmonic solves not counted). 0 when read from a cache.
    pub kernel_pairs: u64,
}

/// A bound scene (or point set): the compiled operator and per-point data.
#[derive(Debug, Clone, PartialEq)]
pub struct StarBinding {
    /// The compiled operator (rows: the bound points).
    pub operator: StarOperator,
    /// b_{c_i}(p) per point (eq. 11): 1 where T is fully applied, 0 on borders.
    pub boundary_weight: Vec<f32>,
    /// The leaf cage each point was bound to.
    pub cage_of: Vec<u32>,
    /// W_n(v, p) (eq. 4): each point's normalised join weights over its cage's boundary
    /// vertices, for influence maps.
    pub join_weights: JoinWeights,
    /// Timings and sizes.
    pub stats: BindStats,
}

/// Sparse per-point join weights W_n(v, p) (eq. 4), CSR: points with b = 1 have none.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JoinWeights {
    /// Start of each point's entries (points + 1).
    pub row_start: Vec<u32>,
    /// Boundary vertex of each entry.
    pub vertex: Vec<u32>,
    /// W_n(v, p) of each entry.
    pub weight: Vec<f32>,
}

impl JoinWeights {
    /// The points' vertices and weights.
    fn csr_rows(&self) -> splice_rows::CsrRows<'_, u32, f32> {
        splice_rows::CsrRows {
            start: &self.row_start,
            a: &self.vertex,
            b: &self.weight,
        }
    }

    /// These weights with the points `rows` (increasing, in range) replaced, in order, by the
    /// points of `part`; every other point's entries copied as they are.
    fn splice(&self, rows: &[usize], part: &JoinWeights) -> Self {
        let (row_start, vertex, weight, _) =
            splice_rows::splice_rows(&self.csr_rows(), &part.csr_rows(), rows, |v| v);
        Self {
            row_start,
            vertex,
            weight,
        }
    }

    /// The weights packed by `rows`.
    fn from_appender(rows: operator::RowAppender) -> Self {
        let (row_start, vertex, weight) = rows.finish();
        Self {
            row_start,
            vertex,
            weight,
        }
    }

    /// W_n(`vertex`, p) for every point p (0 where `vertex` has no say).
    pub fn of_vertex(&self, vertex: u32) -> Vec<f32> {
        self.row_start
            .windows(2)
            .map(|r| {
                (r[0] as usize..r[1] as usize)
                    .find(|&k| self.vertex[k] == vertex)
                    .map_or(0.0, |k| self.weight[k])
            })
            .collect()
    }

    /// Bytes stored.
    pub fn byte_size(&self) -> usize {
        (self.row_start.len() + self.vertex.len() + self.weight.len()) * 4
    }
}

impl StarBinding {
    /// Binds the scene's (welded) mesh vertices.
    pub fn bind_scene(scene: &Scene, control: &BindControl) -> Result<Self, StarError> {
        Self::bind_points(scene, scene.mesh.welded_positions(), control)
    }

    /// Binds the scene's (welded) mesh vertices with `topology`, the scene's topology built
    /// by the caller (validation keeps the one it built).
    pub fn bind_scene_with(
        scene: &Scene,
        topology: &Topology,
        control: &BindControl,
    ) -> Result<Self, StarError> {
        Self::bind_points_with(scene, topology, scene.mesh.welded_positions(), control)
    }

    /// Binds arbitrary points (at rest) to the scene's leaf cages.
    pub fn bind_points(
        scene: &Scene,
        points: &[DVec3],
        control: &BindControl,
    ) -> Result<Self, StarError> {
        Self::bind_points_in_chunks(scene, points, control, bind_chunk_points(points.len()))
    }

    /// [`StarBinding::bind_points`] with `scene`'s topology, built by the caller.
    pub(crate) fn bind_points_with(
        scene: &Scene,
        topology: &Topology,
        points: &[DVec3],
        control: &BindControl,
    ) -> Result<Self, StarError> {
        let chunk = bind_chunk_points(points.len());
        Self::bind_points_in_chunks_with(scene, topology, points, control, chunk)
    }

    /// [`StarBinding::bind_points`], `chunk` points at a time.
    fn bind_points_in_chunks(
        scene: &Scene,
        points: &[DVec3],
        control: &BindControl,
        chunk: usize,
    ) -> Result<Self, StarError> {
        let topology = Topology::new(&scene.cages, scene.settings.join_coordinates)?;
        Self::bind_points_in_chunks_with(scene, &topology, points, control, chunk)
    }

    /// [`StarBinding::bind_points_in_chunks`] with `scene`'s topology.
    fn bind_points_in_chunks_with(
        scene: &Scene,
        topology: &Topology,
        points: &[DVec3],
        control: &BindControl,
        chunk: usize,
    ) -> Result<Self, StarError> {
        let start = Instant::now();
        let pairs_before = control.kernel_pairs();
        let placement = place(scene, topology, points)?;
        // Streamed: each chunk's rows (dense coordinate tables, unpacked rows) are packed into
        // the CSR arrays and freed before the next, so the bind's transient memory is one
        // chunk's, whatever the mesh size (issue 29).
        let (chunk, chunks) = even_chunks(points.len(), chunk);
        let mut operator_rows = operator::RowAppender::default();
        let mut join_weights = operator::RowAppender::default();
        let mut boundary_weight = Vec::with_capacity(points.len());
        let (mut seconds_cage, mut seconds_join) = (0.0, 0.0);
        let mut green = GreenDofs::default();
        let stages = control.stages(chunks);
        let mut memo = bind::JoinMemo::default();
        for k in 0..chunks {
            let range = k * chunk..((k + 1) * chunk).min(points.len());
            stages.enter(k);
            let rows = bind::bind_rows(
                &scene.cages,
                topology,
                &scene.settings,
                &points[range.clone()],
                &placement[range],
                control,
                &mut memo,
            )?;
            if k == 0 {
                // The whole bind's size from its first chunk's.
                let factor = points.len() as f64 / rows.rows.len().max(1) as f64;
                operator_rows.reserve(&rows.rows, factor);
                join_weights.reserve(&rows.join_weights, factor);
            }
            operator_rows.push(&rows.rows);
            join_weights.push(&rows.join_weights);
            boundary_weight.extend(rows.boundary_weight.iter().map(|&b| b as f32));
            seconds_cage += rows.seconds_cage;
            seconds_join += rows.seconds_join;
            // Green DOFs are numbered from the cages alone: every chunk's are the same.
            green = rows.green;
        }
        drop(stages);
        let mut operator = operator_rows.into_operator(scene.cages.vertices.len(), green);
        operator.set_rest_offsets(points, &scene.cages.vertices);
        let stats = BindStats {
            seconds_cage_coordinates: seconds_cage,
            seconds_join_cages: seconds_join,
            seconds_total: start.elapsed().as_secs_f64(),
            seconds_splice: 0.0,
            operator_bytes: operator.byte_size(),
            transpose_bytes: operator.transpose_byte_size(),
            nonzeros: operator.nonzeros(),
            kernel_pairs: control.kernel_pairs() - pairs_before,
        };
        Ok(Self {
            operator,
            boundary_weight,
            join_weights: JoinWeights::from_appender(join_weights),
            cage_of: placement
                .iter()
                .map(|p| match p {
                    Placement::Cage(c) | Placement::Nearest(c) => *c as u32,
                })
                .collect(),
            stats,
        })
    }

    /// Bytes the binding keeps: the operator and its transpose, the join weights, b and the
    /// cage of each point.
    pub fn byte_size(&self) -> usize {
        self.stats.operator_bytes
            + self.stats.transpose_bytes
            + self.join_weights.byte_size()
            + self.boundary_weight.len() * 4
            + self.cage_of.len() * 4
    }

    /// Deformed positions of the bound points for the posed cage vertices `posed`.
    pub fn deform(&self, rest: &[DVec3], posed: &[DVec3]) -> Vec<Vec3> {
        let x = self.operator.dofs(rest, posed);
        let mut out = vec![Vec3::ZERO; self.operator.row_count()];
        self.operator.apply(&x, &mut out);
        out
    }
}

/// Deformed positions of `points` for the posed cage `posed`, evaluated in f64 from the
/// unpacked rows of S (eq. 3): the reference the f32 operator is tested against, and the
/// evaluation for arbitrary points (`starcages-cli eval`).
pub fn evaluate_points(
    scene: &Scene,
    points: &[DVec3],
    posed: &[DVec3],
    control: &BindControl,
) -> Result<Vec<DVec3>, StarError> {
    let (_, rows) = bound_rows(scene, points, control)?;
    let rest = &scene.cages.vertices;
    let dofs = |cage: &[DVec3]| {
        let mut x: Vec<DVec3> = cage.to_vec();
        x.extend(rows.green.values(rest, cage));
        x
    };
    let (x, x_rest) = (dofs(posed), dofs(rest));
    let apply = |row: &[(u32, f64)], x: &[DVec3]| -> DVec3 {
        row.iter().map(|&(c, w)| x[c as usize] * w).sum()
    };
    // S(posed) + p − S(rest): the displacement form (docs/math.md).
    Ok(rows
        .rows
        .iter()
        .zip(points)
        .map(|(row, p)| apply(row, &x) + (*p - apply(row, &x_rest)))
        .collect())
}

/// Topology, placement and the unpacked rows of S for `points`.
fn bound_rows(
    scene: &Scene,
    points: &[DVec3],
    control: &BindControl,
) -> Result<(Vec<Placement>, bind::BoundRows), StarError> {
    let topology = Topology::new(&scene.cages, scene.settings.join_coordinates)?;
    let placement = place(scene, &topology, points)?;
    let rows = bind::bind_rows(
        &scene.cages,
        &topology,
        &scene.settings,
        points,
        &placement,
        control,
        &mut bind::JoinMemo::default(),
    )?;
    Ok((placement, rows))
}

/// Points placed at a time (the containment lists are per point).
const PLACE_CHUNK_POINTS: usize = 1 << 16;

/// Points bound at a time by [`StarBinding::bind_points`]: an eighth of the points (so the
/// transient tables stay a fraction of what the binding keeps), at least 4096 (each chunk
/// plans its cages' rows and gathers its join cages' points again) and at most 32768.
fn bind_chunk_points(points: usize) -> usize {
    (points / 8).clamp(4096, 32768)
}

/// `points` split into chunks of about `chunk` (at least one point): the number of chunks
/// rounded to the nearest (at least 1), the points spread evenly over them. Each chunk has a
/// fixed cost (its cages' row plans, its join cages' point lists), so a last sliver of a chunk
/// would cost as much as a whole one; chunks hold at most 1.5 times `chunk`. Returns the chunk
/// size and count.
fn even_chunks(points: usize, chunk: usize) -> (usize, usize) {
    let chunk = chunk.max(1);
    let chunks = ((points + chunk / 2) / chunk).max(1);
    let size = points.div_ceil(chunks).max(1);
    (size, points.div_ceil(size).max(1))
}

/// Places each point in the first leaf cage containing it (inside or on its surface), or in the
/// nearest one under the `nearest` policy.
fn place(
    scene: &Scene,
    topology: &Topology,
    points: &[DVec3],
) -> Result<Vec<Placement>, StarError> {
    let mut outside = Vec::new();
    let mut placement = Vec::with_capacity(points.len());
    // In chunks: the containment lists are per point.
    for (k, part) in points.chunks(PLACE_CHUNK_POINTS).enumerate() {
        let first = k * PLACE_CHUNK_POINTS;
        let containment = leaf_containment(&topology.leaves, part);
        placement.extend(containment.iter().enumerate().map(|(j, c)| {
            let i = first + j;
            match (c.inside.first(), c.on_surface.first()) {
                (Some(&cage), _) | (None, Some(&cage)) => Placement::Cage(cage),
                (None, None) => {
                    outside.push(i);
                    let nearest = topology
                        .leaves
                        .iter()
                        .enumerate()
                        .map(|(c, l)| (c, l.cage.closest_point(points[i]).2))
                        .min_by(|a, b| a.1.total_cmp(&b.1))
                        .map_or(0, |(c, _)| c);
                    Placement::Nearest(nearest)
                }
            }
        }));
    }
    if !outside.is_empty() && scene.settings.outside == OutsidePolicy::Error {
        let listed = crate::messages::list_first(&outside, 8);
        return Err(StarError::Outside {
            count: outside.len(),
            listed,
        });
    }
    Ok(placement)
}

/// The single-cage baseline of a scene: the union of all its leaf cages (shared faces
/// removed) as one cage of `kind`, over the same vertex array so poses apply unchanged.
pub fn single_cage_scene(scene: &Scene, kind: CoordinateKind) -> Scene {
    let mut count = std::collections::BTreeMap::<Vec<u32>, usize>::new();
    for face in scene.cages.leaves.iter().flat_map(|c| &c.faces) {
        let mut key = face.clone();
        key.sort_unstable();
        *count.entry(key).or_default() += 1;
    }
    let faces: Vec<Vec<u32>> = scene
        .cages
        .leaves
        .iter()
        .flat_map(|c| c.faces.iter())
        .filter(|f| {
            let mut key = (*f).clone();
            key.sort_unstable();
            count[&key] == 1
        })
        .cloned()
        .collect();
    let mut single = scene.clone();
    single.cages = CageSet {
        vertices: scene.cages.vertices.clone(),
        leaves: vec![LeafCage {
            name: "single".into(),
            kind,
            h: None,
            border_h: Default::default(),
            faces,
        }],
        internals: Vec::new(),
    };
    single
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::demo::demo_scene;

    /// A bind streamed chunk by chunk is the bind of all points at once: the same rows, rest
    /// offsets, b, join weights, cages and Green DOFs, and the same kernel work: the join
    /// cages' data at the cage vertices is computed once and read by the later chunks
    /// (`bind::JoinMemo`), not bound again per chunk. The egg's rig has interior join vertices
    /// (eq. 10) and, with one leaf made Green, Green DOFs.
    #[test]
    fn a_bind_streamed_in_chunks_equals_the_bind_of_all_points_at_once() {
        let mut scene = demo_scene("egg", 0.5).unwrap();
        scene.cages.leaves[0].kind = CoordinateKind::Green;
        let points = scene.mesh.welded_positions();
        let control = BindControl::default();
        let whole =
            StarBinding::bind_points_in_chunks(&scene, points, &control, points.len()).unwrap();
        let chunk = points.len() / 5 + 1;
        let streamed = StarBinding::bind_points_in_chunks(&scene, points, &control, chunk).unwrap();
        assert_eq!(
            whole.stats.kernel_pairs, streamed.stats.kernel_pairs,
            "point·triangle pairs of the whole bind and of the streamed one"
        );
        let (a, b) = (whole.operator.parts(), streamed.operator.parts());
        assert_eq!(a.3, b.3, "weights");
        assert_eq!(a.0, b.0, "Green DOFs");
        assert_eq!(a.1, b.1, "row starts");
        assert_eq!(a.2, b.2, "columns");
        let largest =
            a.3.iter()
                .zip(b.3)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f32::max);
        assert!(largest <= 1e-6, "weights differ by {largest}");
        assert!(!whole.operator.green_dofs().is_empty());
        assert_eq!(whole.cage_of, streamed.cage_of);
        assert_eq!(
            whole.join_weights.row_start,
            streamed.join_weights.row_start
        );
        assert_eq!(whole.join_weights.vertex, streamed.join_weights.vertex);
        assert!(
            whole.join_weights.vertex.len() > 100,
            "few points weigh joins"
        );
        for (x, y) in whole.boundary_weight.iter().zip(&streamed.boundary_weight) {
            assert!((x - y).abs() <= 1e-6);
        }
        for (x, y) in whole
            .operator
            .rest_offsets()
            .iter()
            .zip(streamed.operator.rest_offsets())
        {
            assert!((*x - *y).length() <= 1e-5);
        }
    }

    /// Chunks are even and never a sliver: the count rounds to the nearest, every point is in
    /// one chunk, and a chunk holds at most 1.5 times the size asked for.
    #[test]
    fn points_are_split_into_even_chunks_without_a_sliver() {
        assert_eq!(even_chunks(25_002, 4096), (4167, 6));
        assert_eq!(even_chunks(31_800, 4096), (3975, 8));
        assert_eq!(even_chunks(100, 4096), (100, 1));
        assert_eq!(even_chunks(0, 4096), (1, 1));
        for points in [1, 7, 4095, 4096, 6143, 6144, 6145, 1_000_003] {
            for chunk in [1, 3, 4096] {
                let (size, count) = even_chunks(points, chunk);
                assert!(size * count >= points, "{points} in {count} of {size}");
                assert!(
                    size * (count - 1) < points.max(1),
                    "{points}: an empty chunk"
                );
                assert!(
                    2 * size <= 3 * chunk + 2,
                    "{points}: chunks of {size} for {chunk}"
                );
            }
        }
    }

    /// A streamed bind solves each class of congruent harmonic leaves once, in its first
    /// cage's frame: a chunk holding no point of a harmonic cage solves nothing for it, and a
    /// chunk holding points of only the class's second cage still reads the first's solve.
    /// (The creature's four thighs are two mirrored pairs; the resolution is one no other test
    /// uses, so the solve count is this test's alone.)
    #[test]
    fn a_streamed_bind_solves_each_class_of_congruent_harmonic_leaves_once() {
        let mut scene = demo_scene("creature", 0.2).unwrap();
        scene.settings.harmonic.resolution = 13;
        let points = scene.mesh.welded_positions();
        let topology = Topology::new(&scene.cages, scene.settings.join_coordinates).unwrap();
        let thighs: Vec<usize> = (0..scene.cages.leaves.len())
            .filter(|&c| scene.cages.leaves[c].kind == CoordinateKind::Harmonic)
            .collect();
        assert_eq!(thighs.len(), 4);
        let chunk = points.len() / 40 + 1;
        StarBinding::bind_points_in_chunks(&scene, points, &BindControl::default(), chunk).unwrap();
        let solves: Vec<usize> = thighs
            .iter()
            .map(|&c| crate::coords::solves_of(&topology.leaves[c].cage, &scene.settings.harmonic))
            .collect();
        assert_eq!(
            solves.iter().sum::<usize>(),
            2,
            "solves per thigh: {solves:?}"
        );
        assert!(
            solves.iter().all(|&n| n <= 1),
            "solves per thigh: {solves:?}"
        );
        // Each thigh is mirror-symmetric front to back and side to side: a solve computes 17
        // of its 42 functions and maps the others (coords::harmonic::symmetry).
        let functions: Vec<Option<usize>> = thighs
            .iter()
            .map(|&c| {
                let cage = &topology.leaves[c].cage;
                crate::coords::functions_solved_of(cage, &scene.settings.harmonic)
                    .map(|solved| cage.vertex_count() / solved.max(1))
            })
            .collect();
        assert_eq!(
            functions.iter().flatten().count(),
            2,
            "thighs solved: {functions:?}"
        );
        assert!(
            functions.iter().flatten().all(|&ratio| ratio >= 2),
            "vertices per function solved, by thigh: {functions:?}"
        );
    }

    /// The same for harmonic join cages: a class of congruent join cages is solved in its
    /// frame only, whichever of its members a chunk's points need.
    #[test]
    fn a_streamed_bind_solves_each_class_of_congruent_harmonic_join_cages_once() {
        let mut scene = demo_scene("egg", 0.5).unwrap();
        scene.settings.join_coordinates = crate::scene::JoinPolicy::Hc;
        scene.settings.harmonic.resolution = 11;
        let points = scene.mesh.welded_positions();
        let topology = Topology::new(&scene.cages, scene.settings.join_coordinates).unwrap();
        let everything: bind::Needs = topology
            .joins
            .keys()
            .map(|&v| (v, (0..points.len()).collect()))
            .collect();
        let classes = bind::harmonic_classes(&topology, &everything);
        let chunk = points.len() / 10 + 1;
        StarBinding::bind_points_in_chunks(&scene, points, &BindControl::default(), chunk).unwrap();
        let solves_of = |v: u32| {
            crate::coords::solves_of(&topology.joins[&v].local.cage, &scene.settings.harmonic)
        };
        let mut members = 0;
        for class in &classes {
            assert!(solves_of(class.frame.0) <= 1, "frame {}", class.frame.0);
            for (v, _) in class.members.iter().filter(|(v, _)| *v != class.frame.0) {
                assert_eq!(solves_of(*v), 0, "join cage of {v} solved alone");
                members += 1;
            }
        }
        assert!(members >= 2, "{members} members beside their frames");
    }

    /// The progress of a streamed bind covers all its chunks: it ends the bind near 1 and never
    /// above, and the stages are forgotten afterwards.
    #[test]
    fn a_streamed_bind_s_progress_spans_its_chunks() {
        let scene = demo_scene("bar", 1.0).unwrap();
        let points = scene.mesh.welded_positions();
        let control = BindControl::default();
        StarBinding::bind_points_in_chunks(&scene, points, &control, points.len() / 4 + 1).unwrap();
        let stages = control.stages(4);
        stages.enter(3);
        assert!(control.progress() >= 0.75 && control.progress() <= 1.0);
        drop(stages);
        assert!(control.progress() <= 1.0);
    }
}
