//! Multi-level deformation (section 3.4 of *Cages): internal cages drive the lower-level cage
//! vertices they own, at any depth. Edits propagate downwards only: moving a vertex updates what
//! it owns (and so on down to the leaf cages), never its parent. When a parent moves later, a
//! vertex moved by hand since gets coordinates recomputed from its current position (the
//! λ·ΔU scheme where the parent's coordinates are undefined there); every other vertex reuses
//! its cached coordinates. Mesh weights are never touched: the hierarchy only moves cage
//! vertices, and the leaf cages' compiled operator turns them into the mesh.

mod auto;
mod edit;
mod follow;
mod import;
mod joint;
mod remove;
mod restore;
mod spread;

use std::collections::BTreeMap;
use std::sync::Arc;

use glam::{DAffine3, DVec3};
use thiserror::Error;

use crate::cage::{Cage, CageError};
use crate::coords::{BindSettings, CoordError, CoordinateKind};
use crate::scene::{
    HierarchyState, LocalCage, ReboundVertex, Scene, SceneProblem, check_hierarchy,
};

pub use auto::{AutoInternalCage, AutoInternalCageError, add_auto_internal_cage, box_grid};
pub use edit::{CageEdit, CageTransform, EditError, posed_pivot};
use follow::{Follow, RebindRequest, anchor_points, rebind};
pub use import::import_internal_cages;
pub use joint::{JointFrame, affine_fit};
pub use remove::{RemoveInternalCageError, remove_internal_cage};
pub(crate) use remove::{forget, renumber};

/// Why the hierarchy could not be bound or an edit applied.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum HierarchyError {
    /// The hierarchy itself is malformed (a cycle, a vertex with two parents, ...).
    #[error("{0}")]
    Structure(SceneProblem),
    /// An internal cage is not a closed, consistently oriented cage.
    #[error("internal cage '{cage}': {problem}")]
    Cage {
        /// The cage.
        cage: String,
        /// What is wrong.
        problem: CageError,
    },
    /// An HC internal cage owns a vertex outside it at rest.
    #[error(
        "internal cage '{cage}' uses harmonic coordinates but owns vertex {vertex}, which lies \
         outside it at rest where they are undefined; enlarge the cage or switch it to mvc or gc"
    )]
    OwnedOutside {
        /// The cage.
        cage: String,
        /// The vertex.
        vertex: u32,
    },
    /// Coordinates of owned vertices failed.
    #[error("internal cage '{cage}': {source}")]
    Coordinates {
        /// The cage.
        cage: String,
        /// Why.
        #[source]
        source: CoordError,
    },
    /// An edit names a vertex that does not exist.
    #[error("vertex {vertex} does not exist; the scene has {count} cage vertices")]
    NoSuchVertex {
        /// The vertex.
        vertex: u32,
        /// The number of cage vertices.
        count: usize,
    },
    /// An edit moves a vertex to a NaN or infinite position.
    #[error("vertex {vertex} was given a non-finite position; the edit was not applied")]
    NonFinite {
        /// The vertex.
        vertex: u32,
    },
    /// A pose of the wrong length.
    #[error("the pose has {got} vertices but the scene has {expected}")]
    PoseLength {
        /// Its length.
        got: usize,
        /// The scene's vertex count.
        expected: usize,
    },
    /// A saved hierarchy state does not fit the scene.
    #[error("hierarchy state: vertex {vertex}: {reason}; remove it from the pose's state")]
    BadState {
        /// The vertex.
        vertex: u32,
        /// What does not fit.
        reason: String,
    },
}

/// The most drivers [`Hierarchy::driver_sensitivity`] takes: a drag of one internal cage's
/// vertices (a box has 8), or a few dozen leaf vertices.
pub const MAX_DRIVERS: usize = 64;

/// Counters of the work the hierarchy did (none of it touches mesh weights).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HierarchyStats {
    /// Owned vertices bound to their parent at rest, once, in [`Hierarchy::bind`].
    pub bound_at_rest: usize,
    /// Coordinates recomputed for hand-moved vertices when their parent moved.
    pub rebound: usize,
    /// Owned-vertex positions re-evaluated because their parent moved.
    pub propagated: usize,
}

/// One internal cage, bound.
#[derive(Debug, Clone)]
struct Level {
    name: String,
    kind: CoordinateKind,
    /// Faces over the local vertices.
    faces: Vec<Vec<u32>>,
    /// Local vertex → shared vertex.
    global: Vec<u32>,
    /// Owned shared vertices.
    owns: Vec<u32>,
    /// How each owned vertex follows, now.
    follow: Vec<Follow>,
    /// How each owned vertex follows in the rest state.
    rest_follow: Vec<Follow>,
}

impl Level {
    fn shape(&self, pose: &[DVec3]) -> Vec<DVec3> {
        self.global.iter().map(|&v| pose[v as usize]).collect()
    }
}

/// A control's joint, bound: its ring turns half as far as the control does relative to
/// its parent (`joint`).
#[derive(Debug, Clone)]
struct Joint {
    /// The control's level.
    control: usize,
    /// The level owning the control's vertices (and the ring's).
    parent: usize,
    /// Rest shapes of the control and its parent, for their motions.
    control_rest: Vec<DVec3>,
    parent_rest: Vec<DVec3>,
    frame: JointFrame,
    /// Ring vertices with their slot in the parent's `owns`.
    ring: Vec<(u32, usize)>,
    /// What the ring takes back of its parent control's own joint's swing, where it reaches
    /// into the stretch over which that swing spreads (`spread`).
    ring_back: Option<spread::RingBack>,
}

/// The bound hierarchy of a scene's internal cages, with its edit state.
#[derive(Debug, Clone)]
pub struct Hierarchy {
    levels: Vec<Level>,
    joints: Vec<Joint>,
    /// Controls beside a joint, along which its twist and its swing spread.
    segments: Vec<spread::Segment>,
    /// Internal cages, every driver before the cages it drives.
    order: Vec<usize>,
    /// Per shared vertex: (level, slot in its `owns`).
    parent: Vec<Option<(usize, usize)>>,
    /// Per shared vertex: moved by hand since its parent last moved.
    hand_moved: Vec<bool>,
    settings: BindSettings,
    stats: HierarchyStats,
}

impl Hierarchy {
    /// Binds every owned vertex to its parent at rest, then restores the scene's current
    /// hierarchy state.
    pub fn bind(scene: &Scene) -> Result<Self, HierarchyError> {
        Self::bind_in_state(scene, &scene.pose_state)
    }

    /// Binds every owned vertex to its parent at rest, then restores `state` (a stored pose's
    /// or key's hierarchy state rather than the current one).
    pub fn bind_in_state(scene: &Scene, state: &HierarchyState) -> Result<Self, HierarchyError> {
        let mut problems = Vec::new();
        check_hierarchy(scene, &mut problems);
        if let Some(problem) = problems.into_iter().next() {
            return Err(HierarchyError::Structure(problem));
        }
        let set = &scene.cages;
        let settings = BindSettings {
            harmonic: scene.settings.harmonic,
        };
        let mut parent = vec![None; set.vertices.len()];
        let mut levels = Vec::with_capacity(set.internals.len());
        let mut bound_at_rest = 0;
        for (l, cage) in set.internals.iter().enumerate() {
            let local = LocalCage::new(&set.vertices, &cage.faces).map_err(|problem| {
                HierarchyError::Cage {
                    cage: cage.name.clone(),
                    problem,
                }
            })?;
            let points: Vec<DVec3> = cage
                .owns
                .iter()
                .map(|&v| set.vertices[v as usize])
                .collect();
            let faces = local.cage.polygons().iter().map(|p| p.vertices.clone());
            let faces: Vec<Vec<u32>> = faces.collect();
            let rest = Arc::new(local.cage);
            let follow: Vec<Follow> = anchor_points(cage.kind, &rest, &points, &settings)
                .map_err(|source| match source {
                    CoordError::OutsideCage { points, .. } => HierarchyError::OwnedOutside {
                        cage: cage.name.clone(),
                        vertex: cage.owns[points[0]],
                    },
                    source => HierarchyError::Coordinates {
                        cage: cage.name.clone(),
                        source,
                    },
                })?
                .into_iter()
                .map(Follow::Coordinates)
                .collect();
            bound_at_rest += follow.len();
            for (k, &v) in cage.owns.iter().enumerate() {
                parent[v as usize] = Some((l, k));
            }
            levels.push(Level {
                name: cage.name.clone(),
                kind: cage.kind,
                faces,
                global: local.global,
                owns: cage.owns.clone(),
                rest_follow: follow.clone(),
                follow,
            });
        }
        let order = drivers_first(&levels);
        let mut joints = bind_joints(scene, &levels, &parent);
        let segments = spread::bind_segments(scene, &levels, &joints);
        spread::bind_ring_backs(&mut joints, &segments, &set.vertices);
        let mut hierarchy = Self {
            levels,
            joints,
            segments,
            order,
            parent,
            hand_moved: vec![false; set.vertices.len()],
            settings,
            stats: HierarchyStats {
                bound_at_rest,
                ..HierarchyStats::default()
            },
        };
        hierarchy.restore(state)?;
        Ok(hierarchy)
    }

    /// Whether the scene has no internal cages.
    pub fn is_empty(&self) -> bool {
        self.levels.is_empty()
    }

    /// Work counters since [`Hierarchy::bind`].
    pub fn stats(&self) -> HierarchyStats {
        self.stats
    }

    /// The internal cage owning vertex `v`, by name.
    pub fn parent_of(&self, v: u32) -> Option<&str> {
        self.parent
            .get(v as usize)
            .copied()
            .flatten()
            .map(|(l, _)| self.levels[l].name.as_str())
    }

    /// Whether vertex `v` was moved by hand since its parent last moved.
    pub fn is_hand_moved(&self, v: u32) -> bool {
        self.hand_moved.get(v as usize).copied().unwrap_or(false)
    }

    /// Every vertex that moves when any vertex of internal cage `internal` (an index into the
    /// scene's internal cages) moves: its owned vertices, and theirs through the cages they
    /// belong to, down to the leaf cages. Sorted.
    pub fn reach(&self, internal: usize) -> Vec<u32> {
        let mut reached = vec![false; self.parent.len()];
        let mut stack = vec![internal];
        let mut visited = vec![false; self.levels.len()];
        while let Some(l) = stack.pop() {
            if std::mem::replace(&mut visited[l], true) {
                continue;
            }
            for &v in &self.levels[l].owns {
                reached[v as usize] = true;
                stack
                    .extend((0..self.levels.len()).filter(|&m| self.levels[m].global.contains(&v)));
            }
        }
        (0..reached.len() as u32)
            .filter(|&v| reached[v as usize])
            .collect()
    }

    /// Applies hand edits `moves` (vertex, new position) to `pose` and propagates them
    /// downwards. A vertex moved by hand keeps its hand position even when its parent moves in
    /// the same edit. Returns the vertices whose position changed, sorted. On error `pose` and
    /// the hierarchy are left as they were.
    pub fn apply(
        &mut self,
        pose: &mut [DVec3],
        moves: &[(u32, DVec3)],
    ) -> Result<Vec<u32>, HierarchyError> {
        let n = self.parent.len();
        if pose.len() != n {
            return Err(HierarchyError::PoseLength {
                got: pose.len(),
                expected: n,
            });
        }
        let mut by_hand = vec![false; n];
        let mut new = pose.to_vec();
        for &(v, p) in moves {
            if v as usize >= n {
                return Err(HierarchyError::NoSuchVertex {
                    vertex: v,
                    count: n,
                });
            }
            if !p.is_finite() {
                return Err(HierarchyError::NonFinite { vertex: v });
            }
            new[v as usize] = p;
            by_hand[v as usize] = true;
        }
        let old: &[DVec3] = pose;
        let mut changed: Vec<bool> = (0..n).map(|v| new[v] != old[v]).collect();
        let mut updates: Vec<(usize, usize, Follow)> = Vec::new();
        let mut propagated = 0;
        for &l in &self.order {
            let level = &self.levels[l];
            if !level.global.iter().any(|&v| changed[v as usize]) {
                continue;
            }
            let (before, after) = (level.shape(old), level.shape(&new));
            // The paper's rule: hand-moved vertices get coordinates from where they are now,
            // with respect to the parent as it was before this move.
            let slots: Vec<usize> = (0..level.owns.len())
                .filter(|&k| {
                    let v = level.owns[k] as usize;
                    !by_hand[v] && self.hand_moved[v]
                })
                .collect();
            let requests: Vec<RebindRequest<'_>> = slots
                .iter()
                .map(|&k| RebindRequest {
                    point: old[level.owns[k] as usize],
                    current: &level.follow[k],
                })
                .collect();
            let fresh = rebind(level.kind, &level.faces, &before, &requests, &self.settings)
                .map_err(|source| HierarchyError::Coordinates {
                    cage: level.name.clone(),
                    source,
                })?;
            let mut fresh: BTreeMap<usize, Follow> = slots.into_iter().zip(fresh).collect();
            for (k, &v) in level.owns.iter().enumerate() {
                let v = v as usize;
                if by_hand[v] {
                    continue;
                }
                let follow = fresh.remove(&k);
                let p = follow.as_ref().unwrap_or(&level.follow[k]).position(&after);
                propagated += 1;
                if let Some(follow) = follow {
                    updates.push((l, k, follow));
                }
                if p != new[v] {
                    new[v] = p;
                    changed[v] = true;
                }
            }
        }
        self.stats.rebound += updates.len();
        self.stats.propagated += propagated;
        for (l, k, follow) in updates {
            self.hand_moved[self.levels[l].owns[k] as usize] = false;
            self.levels[l].follow[k] = follow;
        }
        let mut turns = spread::JointTurns::new(self.joints.len());
        self.spread_segments(&mut new, &mut changed, &by_hand, &mut turns);
        self.bend_joints(&mut new, &mut changed, &by_hand, &mut turns);
        for ((flag, hand), parent) in self.hand_moved.iter_mut().zip(&by_hand).zip(&self.parent) {
            if *hand && parent.is_some() {
                *flag = true;
            }
        }
        pose.copy_from_slice(&new);
        Ok((0..n as u32).filter(|&v| changed[v as usize]).collect())
    }

    /// How every vertex that follows `drivers` (vertices moved by hand, at most
    /// [`MAX_DRIVERS`]) moves per unit move of each: the derivative ∂v/∂d_m, the same along x, y
    /// and z, as (vertex, one value per driver), sorted by vertex; a driver's own row is the
    /// unit row. Exact while the follows stay as they are, which [`Hierarchy::apply`] changes
    /// only the first time a parent moves under a vertex moved by hand before
    /// ([`HierarchyStats::rebound`] says when). None when a Green internal cage is on the way
    /// (its normals make the map nonlinear) or there are too many drivers.
    pub fn driver_sensitivity(&self, drivers: &[u32]) -> Option<Vec<(u32, Vec<f64>)>> {
        let n = self.parent.len();
        let m = drivers.len();
        if m == 0 || m > MAX_DRIVERS || drivers.iter().any(|&d| d as usize >= n) {
            return None;
        }
        let mut sensitivity: Vec<Option<Vec<f64>>> = vec![None; n];
        for (k, &d) in drivers.iter().enumerate() {
            let mut unit = vec![0.0; m];
            unit[k] = 1.0;
            sensitivity[d as usize] = Some(unit);
        }
        for &l in &self.order {
            let level = &self.levels[l];
            if level
                .global
                .iter()
                .all(|&v| sensitivity[v as usize].is_none())
            {
                continue;
            }
            for (k, &v) in level.owns.iter().enumerate() {
                if drivers.contains(&v) {
                    continue; // a hand move keeps its hand position
                }
                let weights = level.follow[k].linear_weights()?;
                let mut row = vec![0.0; m];
                for (&u, &w) in level.global.iter().zip(&weights) {
                    if let Some(s) = &sensitivity[u as usize] {
                        row.iter_mut().zip(s).for_each(|(r, s)| *r += w * s);
                    }
                }
                sensitivity[v as usize] = Some(row);
            }
        }
        let reached: Vec<bool> = sensitivity.iter().map(Option::is_some).collect();
        if self.reaches_joint(&reached) {
            return None;
        }
        Some(
            sensitivity
                .into_iter()
                .enumerate()
                .filter_map(|(v, s)| Some((v as u32, s?)))
                .collect(),
        )
    }

    /// Puts every joint ring whose control or parent moved at its mitred place: the place
    /// its parent gives it, taken through half the control's turn relative to the parent
    /// ([`JointFrame::mitre`]), and, where the ring reaches into the stretch over which the
    /// parent's own joint spreads its swing, back by the share a segment vertex as far from
    /// that joint takes (`spread`): an ankle ring reaching up a short shin bends with the knee
    /// as the shin's own vertices do, not rigidly with the shin. Vertices moved by hand keep
    /// their place.
    fn bend_joints(
        &self,
        pose: &mut [DVec3],
        changed: &mut [bool],
        by_hand: &[bool],
        turns: &mut spread::JointTurns,
    ) {
        for joint in &self.joints {
            let (control, parent) = (&self.levels[joint.control], &self.levels[joint.parent]);
            let moved = |level: &Level| level.global.iter().any(|&v| changed[v as usize]);
            if !moved(control) && !moved(parent) {
                continue;
            }
            let parent_shape = parent.shape(pose);
            let Some((control_motion, parent_motion)) = self.joint_motions(joint, pose) else {
                continue;
            };
            let parent_inverse = parent_motion.inverse();
            let mitre = joint.frame.mitre(&(parent_inverse * control_motion));
            let ring_back = self.ring_back_in_pose(joint, turns, pose);
            for (k, &(v, slot)) in joint.ring.iter().enumerate() {
                let v = v as usize;
                if by_hand[v] || self.hand_moved[v] {
                    continue;
                }
                // Into the parent's rest frame, through the mitre and what the ring takes back
                // of the parent's own joint, and back.
                let q =
                    parent_inverse.transform_point3(parent.follow[slot].position(&parent_shape));
                let mitred = mitre.transform_point3(q);
                let mitred = ring_back
                    .as_ref()
                    .map_or(mitred, |back| back.apply(k, mitred));
                let p = parent_motion.transform_point3(mitred);
                if p.is_finite() && p != pose[v] {
                    pose[v] = p;
                    changed[v] = true;
                }
            }
        }
    }

    /// A joint's control and parent motions in `pose` (least-squares affine fits of their
    /// vertices from rest); None where either shape is flat.
    fn joint_motions(&self, joint: &Joint, pose: &[DVec3]) -> Option<(DAffine3, DAffine3)> {
        let fit = |rest: &[DVec3], level: usize| affine_fit(rest, &self.levels[level].shape(pose));
        Some((
            fit(&joint.control_rest, joint.control)?,
            fit(&joint.parent_rest, joint.parent)?,
        ))
    }

    /// Whether a move of `vertices` reaches a joint (its control or its parent moves), where
    /// the ring's place is not linear in the moved vertices.
    fn reaches_joint(&self, reached: &[bool]) -> bool {
        self.joints.iter().any(|j| {
            [j.control, j.parent]
                .iter()
                .any(|&l| self.levels[l].global.iter().any(|&v| reached[v as usize]))
        })
    }

    /// The edit state, to store with a pose.
    pub fn state(&self) -> HierarchyState {
        let hand_moved = (0..self.hand_moved.len() as u32)
            .filter(|&v| self.hand_moved[v as usize])
            .collect();
        let mut rebound = Vec::new();
        for level in &self.levels {
            for (k, follow) in level.follow.iter().enumerate() {
                let at_rest = matches!(
                    (follow, &level.rest_follow[k]),
                    (Follow::Coordinates(a), Follow::Coordinates(r))
                        if Arc::ptr_eq(&a.reference, &r.reference) && a.point == r.point
                );
                if !at_rest {
                    rebound.push(ReboundVertex {
                        vertex: level.owns[k],
                        follow: follow.record(),
                    });
                }
            }
        }
        rebound.sort_by_key(|r| r.vertex);
        HierarchyState {
            hand_moved,
            rebound,
        }
    }

    /// Resets to the rest state, then restores `state` (a pose's stored state).
    pub fn restore(&mut self, state: &HierarchyState) -> Result<(), HierarchyError> {
        let mut follow: Vec<Vec<Follow>> =
            self.levels.iter().map(|l| l.rest_follow.clone()).collect();
        let mut hand_moved = vec![false; self.hand_moved.len()];
        for &v in &state.hand_moved {
            self.slot_of(v)?;
            hand_moved[v as usize] = true;
        }
        let slots = state
            .rebound
            .iter()
            .map(|r| self.slot_of(r.vertex))
            .collect::<Result<Vec<_>, _>>()?;
        // One record per vertex: which of two would it follow?
        let mut listed: Vec<u32> = state.rebound.iter().map(|r| r.vertex).collect();
        listed.sort_unstable();
        if let Some(twice) = listed.windows(2).find(|w| w[0] == w[1]) {
            return Err(HierarchyError::BadState {
                vertex: twice[0],
                reason: "it is listed twice in \"rebound\"".into(),
            });
        }
        let restored = restore::follows(&self.levels, &slots, &state.rebound, &self.settings)?;
        for ((l, k), f) in slots.into_iter().zip(restored) {
            follow[l][k] = f;
        }
        for (level, follow) in self.levels.iter_mut().zip(follow) {
            level.follow = follow;
        }
        self.hand_moved = hand_moved;
        Ok(())
    }

    fn slot_of(&self, v: u32) -> Result<(usize, usize), HierarchyError> {
        self.parent
            .get(v as usize)
            .copied()
            .flatten()
            .ok_or_else(|| HierarchyError::BadState {
                vertex: v,
                reason: "it has no parent cage".into(),
            })
    }
}

/// The joints of the scene's controls: an internal cage with a pivot and a ring, owned by
/// one parent cage that owns the ring too (validation checks it). The limb's direction at the
/// joint runs from the pivot to the control's centroid.
fn bind_joints(scene: &Scene, levels: &[Level], parent: &[Option<(usize, usize)>]) -> Vec<Joint> {
    let set = &scene.cages;
    let mut joints = Vec::new();
    for (l, cage) in set.internals.iter().enumerate() {
        let (Some(pivot), false) = (cage.pivot, cage.joint.is_empty()) else {
            continue;
        };
        let level = &levels[l];
        let Some(parent_level) = level
            .global
            .iter()
            .find_map(|&v| parent.get(v as usize).copied().flatten())
            .map(|(p, _)| p)
        else {
            continue;
        };
        let ring: Option<Vec<(u32, usize)>> = cage
            .joint
            .iter()
            .map(|&v| match parent.get(v as usize).copied().flatten() {
                Some((p, slot)) if p == parent_level => Some((v, slot)),
                _ => None,
            })
            .collect();
        let control_rest = level.shape(&set.vertices);
        let centroid = control_rest.iter().sum::<DVec3>() / control_rest.len().max(1) as f64;
        let (Some(ring), Some(axis)) = (ring, (centroid - pivot).try_normalize()) else {
            continue;
        };
        joints.push(Joint {
            control: l,
            parent: parent_level,
            control_rest,
            parent_rest: levels[parent_level].shape(&set.vertices),
            frame: JointFrame { pivot, axis },
            ring,
            ring_back: None,
        });
    }
    joints
}

/// Internal cages ordered so that a cage comes after every cage owning one of its vertices
/// (Kahn's algorithm; the hierarchy was checked to be acyclic).
fn drivers_first(levels: &[Level]) -> Vec<usize> {
    let drives =
        |i: usize, j: usize| i != j && levels[i].owns.iter().any(|v| levels[j].global.contains(v));
    let n = levels.len();
    let mut indegree: Vec<usize> = (0..n)
        .map(|j| (0..n).filter(|&i| drives(i, j)).count())
        .collect();
    let mut ready: Vec<usize> = (0..n).filter(|&j| indegree[j] == 0).rev().collect();
    let mut order = Vec::with_capacity(n);
    while let Some(i) = ready.pop() {
        order.push(i);
        for (j, count) in indegree.iter_mut().enumerate() {
            if drives(i, j) {
                *count -= 1;
                if *count == 0 {
                    ready.push(j);
                }
            }
        }
    }
    order
}

/// The parent cage at `shape` as a validated cage (for restoring saved states).
fn cage_at(level: &Level, shape: &[DVec3]) -> Result<Cage, CageError> {
    Cage::from_polygons(shape.to_vec(), level.faces.clone())
}
