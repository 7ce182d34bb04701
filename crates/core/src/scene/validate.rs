//! Validation of a whole scene: every problem as a typed error naming the cage, the element
//! and the fix.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;
use rayon::prelude::*;
use thiserror::Error;

use super::cage_set::{LocalCage, is_same_cycle};
use super::containment::{ON_CAGE, leaf_containment};
use super::{OutsidePolicy, Scene};
use crate::cage::CageError;

pub use crate::cage::MAX_COORDINATE;

/// One problem of a scene. Vertex indices are 0-based: cage vertices in the scene's shared
/// array, mesh vertices in the welded mesh.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SceneProblem {
    /// A stored hierarchy state cannot be restored (or the hierarchy cannot be bound).
    #[error(
        "the internal-cage state of {pose} cannot be restored: {why}; delete its \"pose_states\" \
         entry (or \"pose_state\") to start that pose from the rest state"
    )]
    PoseState {
        /// "the current pose" or "pose 'NAME'".
        pose: String,
        /// Why.
        why: String,
    },
    /// A cage vertex coordinate is not finite or beyond [`MAX_COORDINATE`].
    #[error(
        "cage vertex {vertex} in {pose} has a coordinate that is not finite or beyond \
         ±{MAX_COORDINATE:e}; move it back (the deformation is computed in 32-bit floats)"
    )]
    CoordinateOutOfRange {
        /// "rest position", "the current pose" or "pose 'NAME'".
        pose: String,
        /// The first such vertex.
        vertex: u32,
    },
    /// A scene setting is outside its limits.
    #[error("settings: {why}")]
    Settings {
        /// Which value, and its range.
        why: String,
    },
    /// The scene has no leaf cage.
    #[error("the scene has no leaf cage; add cages (e.g. with `starcages-cli autocage`)")]
    NoLeafCages,
    /// Two cages share a name.
    #[error("two cages are called '{name}'; rename one")]
    DuplicateName {
        /// The name.
        name: String,
    },
    /// A cage name that is empty or holds control characters (a newline would print as a line
    /// of its own in every message naming the cage).
    #[error("cage name {name:?}: {why}; rename it")]
    BadName {
        /// The name, quoted and escaped when shown.
        name: String,
        /// What is wrong with it.
        why: &'static str,
    },
    /// A cage is not a valid closed, outward-oriented cage.
    #[error("cage '{cage}': {problem}")]
    Cage {
        /// The cage.
        cage: String,
        /// What is wrong with it.
        problem: CageError,
    },
    /// An h outside (0, 1].
    #[error("cage '{cage}': h = {h:?} is outside (0, 1]; choose a value in that range")]
    InvalidH {
        /// The cage.
        cage: String,
        /// The value.
        h: f64,
    },
    /// A border h override names a cage that is not a neighbour.
    #[error(
        "cage '{cage}': border h for '{neighbour}', which is not an adjacent cage; remove the override"
    )]
    UnknownBorder {
        /// The cage.
        cage: String,
        /// The named neighbour.
        neighbour: String,
    },
    /// Two cages share a face with the same orientation: one is inside-out or they overlap.
    #[error(
        "cages '{first}' and '{second}' share face {face} of '{first}' with the same orientation; \
         neighbouring cages must run shared faces in opposite directions (flip one cage, or fix the overlap)"
    )]
    SharedFaceSameOrientation {
        /// One cage.
        first: String,
        /// The other.
        second: String,
        /// The face, in the first cage's list.
        face: usize,
    },
    /// More than two cages have the same face.
    #[error(
        "face {face} of cage '{cage}' is shared by {count} cages; a face borders at most two cages"
    )]
    FaceSharedByMany {
        /// A cage with the face.
        cage: String,
        /// The face in its list.
        face: usize,
        /// How many cages have it.
        count: usize,
    },
    /// A mesh vertex is strictly inside two leaf cages: the cages overlap.
    #[error(
        "mesh vertex {vertex} is inside both '{first}' and '{second}': those cages overlap; make them meet at shared faces"
    )]
    MeshVertexInTwoCages {
        /// The mesh vertex.
        vertex: usize,
        /// One cage.
        first: String,
        /// The other.
        second: String,
    },
    /// A cage vertex is strictly inside another leaf cage.
    #[error(
        "cage vertex {vertex} lies inside cage '{cage}': cages overlap; move the vertex onto or outside '{cage}'"
    )]
    CageVertexInsideCage {
        /// The cage vertex.
        vertex: usize,
        /// The cage containing it.
        cage: String,
    },
    /// Two leaf cages pass through each other (no vertex of either need be inside the other).
    #[error(
        "cages '{first}' and '{second}' pass through each other: edge ({a}, {b}) of '{first}' \
         crosses face {face} of '{second}'; neighbouring cages may only meet at shared faces, so \
         move the cages apart or make them share the face between them"
    )]
    CagesCross {
        /// The cage whose edge crosses.
        first: String,
        /// The cage whose face is crossed.
        second: String,
        /// First vertex of the edge (shared array).
        a: usize,
        /// Second vertex of the edge.
        b: usize,
        /// The face, in the second cage's list.
        face: usize,
    },
    /// A leaf cage vertex lies on another leaf cage's surface without being its vertex.
    #[error(
        "cage vertex {vertex} lies on face {face} of cage '{cage}' but is not one of its vertices \
         (a T-junction, or a copy of a shared vertex): neighbouring cages must share whole faces; \
         split that face of '{cage}' at the vertex, or weld the vertex to the one of '{cage}' \
         at the same place"
    )]
    VertexOnCageSurface {
        /// The cage vertex.
        vertex: usize,
        /// The cage whose surface it touches.
        cage: String,
        /// The face it lies on, in that cage's list.
        face: usize,
    },
    /// Mesh vertices outside every cage, too far from their nearest (MVC) cage to follow it.
    #[error(
        "{count} mesh vertices lie outside every cage and more than {range} cage diagonals from \
         their nearest cage (first: vertex {vertex}, nearest '{cage}'), where its mean value \
         coordinates are not accurate; enlarge the cages to hold them, or make that cage gc",
        range = crate::coords::MVC_RANGE_IN_DIAGONALS
    )]
    FarFromNearestCage {
        /// How many.
        count: usize,
        /// The first.
        vertex: usize,
        /// Its nearest cage.
        cage: String,
    },
    /// Mesh vertices outside every leaf cage.
    #[error(
        "{count} mesh vertices lie outside every leaf cage (first: {listed}; within {min:?} .. {max:?}); \
         enlarge the cages, or set the scene's outside policy to 'nearest'"
    )]
    MeshOutside {
        /// How many.
        count: usize,
        /// Their indices (all).
        vertices: Vec<usize>,
        /// The first few, formatted.
        listed: String,
        /// Bounding box minimum of those vertices.
        min: [f64; 3],
        /// Bounding box maximum of those vertices.
        max: [f64; 3],
    },
    /// A pose has the wrong number of vertices.
    #[error(
        "pose '{pose}' has {got} vertices but the cages have {expected}; re-export the pose from this scene"
    )]
    PoseLength {
        /// The pose ("current" for the current one).
        pose: String,
        /// Its vertex count.
        got: usize,
        /// The cage vertex count.
        expected: usize,
    },
    /// A pose has a NaN or infinite coordinate.
    #[error("pose '{pose}': cage vertex {vertex} has a non-finite coordinate")]
    PoseNonFinite {
        /// The pose.
        pose: String,
        /// The vertex.
        vertex: usize,
    },
    /// The leaf cages' *Cages topology is unusable (e.g. a non-manifold join cage).
    #[error("{0}")]
    Topology(String),
    /// The animation cannot be played.
    #[error(transparent)]
    Animation(#[from] crate::anim::AnimationProblem),
    /// An internal cage owns a vertex that does not exist or is its own.
    #[error(
        "internal cage '{cage}' owns vertex {vertex}, which {reason}; remove it from its owned list"
    )]
    BadOwnedVertex {
        /// The internal cage.
        cage: String,
        /// The vertex.
        vertex: usize,
        /// Why it cannot be owned.
        reason: &'static str,
    },
    /// A vertex owned by two internal cages.
    #[error(
        "vertex {vertex} is owned by both '{first}' and '{second}'; a vertex has at most one parent"
    )]
    OwnedTwice {
        /// The vertex.
        vertex: usize,
        /// One owner.
        first: String,
        /// The other.
        second: String,
    },
    /// An internal cage lists a vertex twice in its `owns`.
    #[error("internal cage '{cage}' lists vertex {vertex} twice in \"owns\"; remove the repeat")]
    ListedTwice {
        /// The internal cage.
        cage: String,
        /// The vertex.
        vertex: usize,
    },
    /// The ownership hierarchy has a cycle.
    #[error(
        "internal cage '{cage}' ends up owning one of its own vertices through the hierarchy; break the cycle"
    )]
    HierarchyCycle {
        /// A cage on the cycle.
        cage: String,
    },
    /// A control's pivot is not a finite position within the coordinate range.
    #[error(
        "internal cage '{cage}' has its pivot at a non-finite position or beyond \
         ±{MAX_COORDINATE:e}; put it at the joint the control turns about, or remove \"pivot\""
    )]
    BadPivot {
        /// The internal cage.
        cage: String,
    },
    /// A joint ring lists a vertex that cannot bend with the control.
    #[error(
        "internal cage '{cage}' lists vertex {vertex} in its \"joint\" ring, which {reason}; \
         remove it from the ring"
    )]
    BadJointVertex {
        /// The internal cage.
        cage: String,
        /// The vertex.
        vertex: usize,
        /// Why it cannot be in the ring.
        reason: &'static str,
    },
}

/// Result of validating a scene.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ValidationReport {
    /// Problems that make the scene unusable.
    pub errors: Vec<SceneProblem>,
    /// Things worth knowing that do not stop deformation.
    pub warnings: Vec<String>,
}

/// The elements a problem is about, so an editor can draw them in a warning colour: leaf cages
/// (by index), cage vertices and mesh vertices.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ProblemElements {
    /// Leaf cages, by index in the scene's list.
    pub leaf_cages: Vec<usize>,
    /// Cage vertices (the shared array).
    pub cage_vertices: Vec<u32>,
    /// Mesh vertices.
    pub mesh_vertices: Vec<usize>,
}

impl SceneProblem {
    /// The leaf cages, cage vertices and mesh vertices this problem names (leaf cages by their
    /// index in `set`; names that are not leaf cages are left out).
    pub fn elements(&self, set: &super::CageSet) -> ProblemElements {
        let leaf = |name: &str| set.leaf_index(name);
        let mut out = ProblemElements::default();
        let mut cages = |names: &[&String]| {
            out.leaf_cages
                .extend(names.iter().filter_map(|n| leaf(n.as_str())));
        };
        match self {
            Self::DuplicateName { name } => cages(&[name]),
            Self::Cage { cage, .. }
            | Self::InvalidH { cage, .. }
            | Self::UnknownBorder { cage, .. }
            | Self::FaceSharedByMany { cage, .. } => cages(&[cage]),
            Self::SharedFaceSameOrientation { first, second, .. } => cages(&[first, second]),
            Self::MeshVertexInTwoCages {
                vertex,
                first,
                second,
            } => {
                cages(&[first, second]);
                out.mesh_vertices.push(*vertex);
            }
            Self::CageVertexInsideCage { vertex, cage }
            | Self::VertexOnCageSurface { vertex, cage, .. } => {
                cages(&[cage]);
                out.cage_vertices.push(*vertex as u32);
            }
            Self::CagesCross {
                first,
                second,
                a,
                b,
                ..
            } => {
                cages(&[first, second]);
                out.cage_vertices.extend([*a as u32, *b as u32]);
            }
            Self::FarFromNearestCage { vertex, cage, .. } => {
                cages(&[cage]);
                out.mesh_vertices.push(*vertex);
            }
            Self::MeshOutside { vertices, .. } => out.mesh_vertices.extend(vertices),
            _ => {}
        }
        out
    }
}

impl ValidationReport {
    /// Whether the scene is usable.
    pub fn is_valid(&self) -> bool {
        self.errors.is_empty()
    }
}

/// What is wrong with a cage name, if anything: empty, or holding a control character.
pub fn name_problem(name: &str) -> Option<&'static str> {
    if name.trim().is_empty() {
        Some("a cage needs a name that is not empty or only spaces")
    } else if name.chars().any(char::is_control) {
        Some("a name may not hold control characters such as a newline or a tab")
    } else {
        None
    }
}

/// The model's own rules: names, coordinates, settings, closed and oriented cages, shared
/// faces, the hierarchy's structure, poses, the animation, overlaps and coverage of the mesh.
/// [`crate::check::validate_scene`] adds the dry runs of the engine (topology, hierarchy
/// states) on top.
pub fn check_model(scene: &Scene) -> ValidationReport {
    let mut report = ValidationReport::default();
    let errors = &mut report.errors;
    let set = &scene.cages;
    if set.leaves.is_empty() {
        errors.push(SceneProblem::NoLeafCages);
    }
    let mut names = BTreeSet::new();
    for name in set
        .leaves
        .iter()
        .map(|c| &c.name)
        .chain(set.internals.iter().map(|c| &c.name))
    {
        if !names.insert(name) {
            errors.push(SceneProblem::DuplicateName { name: name.clone() });
        }
        if let Some(why) = name_problem(name) {
            errors.push(SceneProblem::BadName {
                name: name.clone(),
                why,
            });
        }
    }
    let named = scene.poses.iter().map(|(n, p)| (format!("pose '{n}'"), p));
    for (what, positions) in [("rest position".to_owned(), &set.vertices)]
        .into_iter()
        .chain(std::iter::once((
            "the current pose".to_owned(),
            &scene.pose,
        )))
        .chain(named)
    {
        let far = positions
            .iter()
            .position(|p| !(p.is_finite() && p.abs().max_element() <= MAX_COORDINATE));
        if let Some(vertex) = far {
            errors.push(SceneProblem::CoordinateOutOfRange {
                pose: what,
                vertex: vertex as u32,
            });
        }
    }
    if let Err(why) = scene.settings.harmonic.check() {
        errors.push(SceneProblem::Settings { why });
    }
    let h = scene.settings.default_h;
    if !(h > 0.0 && h <= 1.0) {
        errors.push(SceneProblem::Settings {
            why: format!(
                "default_h = {h:?} is outside (0, 1]; choose a value in that range (0.5 is the \
                 default)"
            ),
        });
    }
    // Each cage closed and outward-oriented.
    let mut leaves: Vec<Option<LocalCage>> = Vec::new();
    for cage in &set.leaves {
        match LocalCage::new(&set.vertices, &cage.faces) {
            Ok(local) => leaves.push(Some(local)),
            Err(problem) => {
                errors.push(SceneProblem::Cage {
                    cage: cage.name.clone(),
                    problem,
                });
                leaves.push(None);
            }
        }
        for h in cage.h.iter().chain(cage.border_h.values()) {
            if !(*h > 0.0 && *h <= 1.0) {
                errors.push(SceneProblem::InvalidH {
                    cage: cage.name.clone(),
                    h: *h,
                });
            }
        }
    }
    for cage in &set.internals {
        if let Err(problem) = LocalCage::new(&set.vertices, &cage.faces) {
            errors.push(SceneProblem::Cage {
                cage: cage.name.clone(),
                problem,
            });
        }
    }
    check_shared_faces(scene, errors);
    check_hierarchy(scene, errors);
    check_poses(scene, errors);
    // A hierarchy state stored for a pose that does not exist belongs to nothing.
    for name in scene.pose_states.keys() {
        if !scene.poses.contains_key(name) {
            errors.push(SceneProblem::PoseState {
                pose: format!("pose '{name}'"),
                why: "there is no pose of that name (its state is stored, its positions are \
                      not)"
                    .into(),
            });
        }
    }
    errors.extend(
        scene
            .animation
            .problems(&scene.poses, set.leaves.iter().map(|c| c.name.as_str()))
            .into_iter()
            .map(SceneProblem::Animation),
    );
    if leaves.iter().all(Option::is_some) && !leaves.is_empty() {
        let leaves: Vec<LocalCage> = leaves.into_iter().flatten().collect();
        check_overlaps_and_coverage(scene, &leaves, &mut report);
    }
    report
}

fn check_shared_faces(scene: &Scene, errors: &mut Vec<SceneProblem>) {
    let set = &scene.cages;
    for sharing in set.faces_by_vertex_set().values() {
        match sharing[..] {
            [_] => {}
            [(ci, fi), (cj, fj)]
                if ci != cj
                    && is_same_cycle(&set.leaves[ci].faces[fi], &set.leaves[cj].faces[fj]) =>
            {
                errors.push(SceneProblem::SharedFaceSameOrientation {
                    first: set.leaves[ci].name.clone(),
                    second: set.leaves[cj].name.clone(),
                    face: fi,
                });
            }
            [(ci, fi), ..] if sharing.len() > 2 => errors.push(SceneProblem::FaceSharedByMany {
                cage: set.leaves[ci].name.clone(),
                face: fi,
                count: sharing.len(),
            }),
            _ => {} // the same face twice in one cage: reported by that cage's own check
        }
    }
    let adjacency = set.adjacency();
    for (c, cage) in set.leaves.iter().enumerate() {
        for neighbour in cage.border_h.keys() {
            let adjacent = set.leaf_index(neighbour).is_some_and(|n| {
                adjacency
                    .iter()
                    .any(|a| (a.first, a.second) == (c.min(n), c.max(n)))
            });
            if !adjacent {
                errors.push(SceneProblem::UnknownBorder {
                    cage: cage.name.clone(),
                    neighbour: neighbour.clone(),
                });
            }
        }
    }
}

pub(crate) fn check_hierarchy(scene: &Scene, errors: &mut Vec<SceneProblem>) {
    let set = &scene.cages;
    let n = set.vertices.len();
    let mut parent: BTreeMap<u32, usize> = BTreeMap::new();
    let own_vertices: Vec<BTreeSet<u32>> = set
        .internals
        .iter()
        .map(|c| c.faces.iter().flatten().copied().collect())
        .collect();
    for (i, cage) in set.internals.iter().enumerate() {
        for &v in &cage.owns {
            let reason = if v as usize >= n {
                Some("does not exist")
            } else if own_vertices[i].contains(&v) {
                Some("is one of its own vertices")
            } else {
                None
            };
            if let Some(reason) = reason {
                errors.push(SceneProblem::BadOwnedVertex {
                    cage: cage.name.clone(),
                    vertex: v as usize,
                    reason,
                });
                continue;
            }
            if parent.get(&v) == Some(&i) {
                errors.push(SceneProblem::ListedTwice {
                    cage: cage.name.clone(),
                    vertex: v as usize,
                });
            } else if let Some(&other) = parent.get(&v) {
                errors.push(SceneProblem::OwnedTwice {
                    vertex: v as usize,
                    first: set.internals[other].name.clone(),
                    second: cage.name.clone(),
                });
            } else {
                parent.insert(v, i);
            }
        }
    }
    check_joints(set, &parent, &own_vertices, errors);
    // Internal cage i drives internal cage j when it owns one of j's vertices; a cycle in
    // that graph means a cage drives itself.
    let drives: Vec<BTreeSet<usize>> = set
        .internals
        .iter()
        .map(|c| {
            (0..set.internals.len())
                .filter(|&j| c.owns.iter().any(|v| own_vertices[j].contains(v)))
                .collect()
        })
        .collect();
    for start in 0..set.internals.len() {
        let mut stack: Vec<usize> = drives[start].iter().copied().collect();
        let mut seen = BTreeSet::new();
        while let Some(j) = stack.pop() {
            if j == start {
                errors.push(SceneProblem::HierarchyCycle {
                    cage: set.internals[start].name.clone(),
                });
                break;
            }
            if seen.insert(j) {
                stack.extend(drives[j].iter().copied());
            }
        }
    }
}

/// Pivots are finite, in range; a joint ring's vertices are owned by the cage that owns the
/// control's own vertices (its parent control), each in one ring, none of them the control's.
fn check_joints(
    set: &super::CageSet,
    parent: &BTreeMap<u32, usize>,
    own_vertices: &[BTreeSet<u32>],
    errors: &mut Vec<SceneProblem>,
) {
    let mut in_ring: BTreeSet<u32> = BTreeSet::new();
    for (i, cage) in set.internals.iter().enumerate() {
        if let Some(p) = cage.pivot
            && !(p.is_finite() && p.abs().max_element() <= MAX_COORDINATE)
        {
            errors.push(SceneProblem::BadPivot {
                cage: cage.name.clone(),
            });
        }
        // The control's parent: the cage owning its vertices (the first one owned).
        let control_parent = own_vertices[i].iter().find_map(|v| parent.get(v)).copied();
        for &v in &cage.joint {
            let reason = if v as usize >= set.vertices.len() {
                Some("does not exist")
            } else if own_vertices[i].contains(&v) {
                Some("is one of the control's own vertices")
            } else if parent.get(&v).copied() != control_parent {
                Some("is not owned by the cage that owns the control")
            } else if !in_ring.insert(v) {
                Some("is in another ring already (or listed twice)")
            } else {
                None
            };
            if let Some(reason) = reason {
                errors.push(SceneProblem::BadJointVertex {
                    cage: cage.name.clone(),
                    vertex: v as usize,
                    reason,
                });
            }
        }
    }
}

fn check_poses(scene: &Scene, errors: &mut Vec<SceneProblem>) {
    let expected = scene.cages.vertices.len();
    let poses = scene
        .poses
        .iter()
        .map(|(n, p)| (n.as_str(), p))
        .chain([("current", &scene.pose)]);
    for (name, pose) in poses {
        if pose.len() != expected {
            errors.push(SceneProblem::PoseLength {
                pose: name.to_owned(),
                got: pose.len(),
                expected,
            });
        } else if let Some(vertex) = pose.iter().position(|p| !p.is_finite()) {
            errors.push(SceneProblem::PoseNonFinite {
                pose: name.to_owned(),
                vertex,
            });
        }
    }
}

fn check_overlaps_and_coverage(scene: &Scene, leaves: &[LocalCage], report: &mut ValidationReport) {
    let set = &scene.cages;
    let name = |c: usize| set.leaves[c].name.clone();
    let mesh_points = scene.mesh.welded_positions();
    let containment = leaf_containment(leaves, mesh_points);
    let mut outside = Vec::new();
    for (v, c) in containment.iter().enumerate() {
        if c.inside.len() >= 2 {
            report.errors.push(SceneProblem::MeshVertexInTwoCages {
                vertex: v,
                first: name(c.inside[0]),
                second: name(c.inside[1]),
            });
        }
        if !c.is_covered() {
            outside.push(v);
        }
    }
    // Report each overlapping pair once, not once per vertex.
    dedup_overlaps(&mut report.errors);
    if scene.settings.outside == OutsidePolicy::Nearest {
        check_far_from_nearest_cage(scene, leaves, &outside, &mut report.errors);
    }
    if !outside.is_empty() {
        let (lo, hi) =
            crate::cage::bounds_of(&outside.iter().map(|&v| mesh_points[v]).collect::<Vec<_>>());
        let listed = crate::messages::list_first(&outside, 8);
        let problem = SceneProblem::MeshOutside {
            count: outside.len(),
            vertices: outside,
            listed,
            min: lo.to_array(),
            max: hi.to_array(),
        };
        match scene.settings.outside {
            OutsidePolicy::Error => report.errors.push(problem),
            OutsidePolicy::Nearest => report
                .warnings
                .push(format!("{problem} (they follow the nearest cage)")),
        }
    }
    check_cage_vertices_against_cages(scene, leaves, &mut report.errors);
    check_cages_crossing(set, leaves, &mut report.errors);
}

/// Leaf-cage vertices strictly inside another leaf cage (overlap), or on its surface without
/// being its vertex (a T-junction). A vertex at exactly the place of one of the other cage's
/// vertices is a contact: two cages may touch without sharing where no mesh edge passes
/// between them (the auto rig parts two paws side by side so; docs/math.md, *Cages: "Two
/// leaf cages may touch"); where one does, the mesh would tear there and the copy is refused
/// as before.
fn check_cage_vertices_against_cages(
    scene: &Scene,
    leaves: &[LocalCage],
    errors: &mut Vec<SceneProblem>,
) {
    let set = &scene.cages;
    let mut is_leaf_vertex = vec![false; set.vertices.len()];
    for &v in set.leaves.iter().flat_map(|l| l.faces.iter().flatten()) {
        if let Some(slot) = is_leaf_vertex.get_mut(v as usize) {
            *slot = true;
        }
    }
    // Internal cages' vertices may lie anywhere: only leaf vertices matter here.
    let found: Vec<(SceneProblem, Option<u32>)> = leaves
        .par_iter()
        .enumerate()
        .flat_map_iter(|(c, local)| {
            let tol = ON_CAGE * local.cage.diagonal();
            let (lo, hi) = local.cage.bounds();
            let (lo, hi) = (lo - tol, hi + tol);
            let is_leaf_vertex = &is_leaf_vertex;
            set.vertices
                .iter()
                .enumerate()
                .filter(move |(v, p)| {
                    is_leaf_vertex[*v]
                        && local.global.binary_search(&(*v as u32)).is_err()
                        && p.cmpge(lo).all()
                        && p.cmple(hi).all()
                })
                .filter_map(move |(vertex, p)| {
                    let (triangle, _, distance) = local.cage.closest_point(*p);
                    if distance <= tol {
                        let touched = local.cage.positions().iter().position(|q| q == p);
                        let problem = SceneProblem::VertexOnCageSurface {
                            vertex,
                            cage: set.leaves[c].name.clone(),
                            face: local.cage.triangle_polygon()[triangle] as usize,
                        };
                        Some((problem, touched.map(|k| local.global[k])))
                    } else if local.cage.winding_number(*p) > 0.5 {
                        let problem = SceneProblem::CageVertexInsideCage {
                            vertex,
                            cage: set.leaves[c].name.clone(),
                        };
                        Some((problem, None))
                    } else {
                        None
                    }
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let touched: BTreeSet<u32> = found.iter().filter_map(|(_, t)| *t).collect();
    let torn = faces_the_mesh_crosses(scene, &touched);
    errors.extend(
        found
            .into_iter()
            .filter_map(|(problem, touched)| match touched {
                Some(at) if !torn.contains(&at) => None,
                _ => Some(problem),
            }),
    );
}

/// Of the `touched` leaf vertices (each at the place of another cage's vertex), those on a
/// face of theirs whose corners are all touched (a face two cages both have, unshared) that a
/// mesh edge meets.
fn faces_the_mesh_crosses(scene: &Scene, touched: &BTreeSet<u32>) -> BTreeSet<u32> {
    let set = &scene.cages;
    let touching: Vec<[DVec3; 3]> = set
        .leaves
        .iter()
        .flat_map(|l| &l.faces)
        .filter(|f| f.len() >= 3 && f.iter().all(|v| touched.contains(v)))
        .flat_map(|f| (1..f.len() - 1).map(move |i| [f[0], f[i], f[i + 1]]))
        .filter_map(|t| {
            let at = |v: u32| set.vertices.get(v as usize).copied();
            Some([at(t[0])?, at(t[1])?, at(t[2])?])
        })
        .collect();
    let mut torn = BTreeSet::new();
    if touching.is_empty() {
        return torn;
    }
    let points = scene.mesh.welded_positions();
    let crossed: Vec<bool> = touching
        .par_iter()
        .map(|t| {
            let (lo, hi) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
            scene.mesh.welded_triangles().iter().any(|tri| {
                let corner = |k: usize| points.get(tri[k] as usize).copied();
                (0..3).any(|k| {
                    let (Some(p), Some(q)) = (corner(k), corner((k + 1) % 3)) else {
                        return false;
                    };
                    p.min(q).cmple(hi).all()
                        && p.max(q).cmpge(lo).all()
                        && crate::geometry::segment_meets_triangle(p, q, *t)
                })
            })
        })
        .collect();
    for (t, crossed) in touching.iter().zip(crossed) {
        if crossed {
            torn.extend(
                set.vertices
                    .iter()
                    .enumerate()
                    .filter(|(v, p)| touched.contains(&(*v as u32)) && t.contains(p))
                    .map(|(v, _)| v as u32),
            );
        }
    }
    torn
}

/// Pairs of leaf cages whose surfaces cross: they overlap even where no vertex of either lies
/// inside the other (two boxes in a plus sign).
fn check_cages_crossing(
    set: &super::CageSet,
    leaves: &[LocalCage],
    errors: &mut Vec<SceneProblem>,
) {
    let pairs: Vec<(usize, usize)> = (0..leaves.len())
        .flat_map(|i| (i + 1..leaves.len()).map(move |j| (i, j)))
        .collect();
    let found: Vec<SceneProblem> = pairs
        .par_iter()
        .filter_map(|&(i, j)| {
            let (a, b) = (&leaves[i], &leaves[j]);
            let (forward, crossing) = crate::cage::cages_crossing(
                (a.cage.positions(), a.cage.triangles()),
                (b.cage.positions(), b.cage.triangles()),
            )?;
            let (edge_cage, face_cage) = if forward { (i, j) } else { (j, i) };
            let global = |v: u32| leaves[edge_cage].global[v as usize] as usize;
            Some(SceneProblem::CagesCross {
                first: set.leaves[edge_cage].name.clone(),
                second: set.leaves[face_cage].name.clone(),
                a: global(crossing.edge[0]),
                b: global(crossing.edge[1]),
                face: leaves[face_cage].cage.triangle_polygon()[crossing.triangle] as usize,
            })
        })
        .collect();
    errors.extend(found);
}

/// Under the `nearest` policy an outside mesh vertex follows its nearest cage through that
/// cage's coordinates; mean value coordinates refuse points beyond their accurate range, so a
/// bind would fail there: report it here, as `deform` would.
fn check_far_from_nearest_cage(
    scene: &Scene,
    leaves: &[LocalCage],
    outside: &[usize],
    errors: &mut Vec<SceneProblem>,
) {
    use crate::coords::{CoordinateKind, MVC_RANGE_IN_DIAGONALS};
    let points = scene.mesh.welded_positions();
    let far: Vec<(usize, usize)> = outside
        .par_iter()
        .filter_map(|&v| {
            let p = points[v];
            let nearest = leaves
                .iter()
                .enumerate()
                .map(|(c, l)| (c, l.cage.closest_point(p).2))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(c, _)| c)?;
            let cage = &leaves[nearest].cage;
            let (lo, hi) = cage.bounds();
            let beyond = p.distance(0.5 * (lo + hi)) > MVC_RANGE_IN_DIAGONALS * cage.diagonal();
            (scene.cages.leaves[nearest].kind == CoordinateKind::MeanValue && beyond)
                .then_some((v, nearest))
        })
        .collect();
    if let Some(&(vertex, cage)) = far.first() {
        errors.push(SceneProblem::FarFromNearestCage {
            count: far.len(),
            vertex,
            cage: scene.cages.leaves[cage].name.clone(),
        });
    }
}

fn dedup_overlaps(errors: &mut Vec<SceneProblem>) {
    let mut seen = BTreeSet::new();
    errors.retain(|e| match e {
        SceneProblem::MeshVertexInTwoCages { first, second, .. } => {
            seen.insert((first.clone(), second.clone()))
        }
        _ => true,
    });
}
