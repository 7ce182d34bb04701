//! What every rig operation shares: its error, the key that finds a face in any cage, a rest
//! move that the poses follow, and the lookups (a leaf by name, a face by index or direction, a
//! free name, the vertex at a position). The operations import from here, never from each
//! other or from the dispatcher.

use std::collections::BTreeSet;

use glam::DVec3;
use thiserror::Error;

use super::FaceRef;
use crate::scene::Scene;

/// Why a rig operation could not apply.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RigEditError {
    /// No leaf cage of that name.
    #[error("there is no leaf cage '{0}'; check the name (starcages-cli info lists them)")]
    NoSuchCage(String),
    /// The name is taken.
    #[error("a cage called '{0}' exists already; choose another name")]
    NameTaken(String),
    /// No such face.
    #[error("cage '{cage}' has {count} faces; face {face} does not exist (faces count from 0)")]
    NoSuchFace {
        /// The cage.
        cage: String,
        /// The face asked for.
        face: usize,
        /// How many it has.
        count: usize,
    },
    /// The face already borders another cage.
    #[error(
        "face {face} of '{cage}' is shared with another cage already; extrude or inset a free face"
    )]
    FaceShared {
        /// The cage.
        cage: String,
        /// The face.
        face: usize,
    },
    /// A number out of range.
    #[error("{0}")]
    Value(String),
    /// An operation of a script failed.
    #[error("line {line}: {problem}")]
    AtLine {
        /// The script's line, from 1.
        line: usize,
        /// What went wrong there.
        problem: Box<RigEditError>,
    },
    /// The operation text could not be read.
    #[error("'{op}': {why}")]
    Syntax {
        /// The text.
        op: String,
        /// What is wrong.
        why: String,
    },
}

/// A face's key: its vertices sorted (the same face in two cages has the same key).
pub(crate) fn face_key(face: &[u32]) -> Vec<u32> {
    let mut key = face.to_vec();
    key.sort_unstable();
    key
}

/// Moves cage vertex `v` at rest to `to`; every pose moves it by the same displacement.
pub(crate) fn move_rest_vertex(scene: &mut Scene, v: u32, to: DVec3) {
    let delta = to - scene.cages.vertices[v as usize];
    scene.cages.vertices[v as usize] = to;
    for pose in std::iter::once(&mut scene.pose).chain(scene.poses.values_mut()) {
        if let Some(p) = pose.get_mut(v as usize) {
            *p += delta;
        }
    }
}

/// The operations index vertices through the faces and the poses: a scene read from a file
/// that `validate` would refuse on those grounds is refused here rather than indexed.
pub(crate) fn check_structure(scene: &Scene) -> Result<(), RigEditError> {
    let count = scene.cages.vertices.len();
    let set = &scene.cages;
    let faces = set
        .leaves
        .iter()
        .map(|c| (&c.name, &c.faces))
        .chain(set.internals.iter().map(|c| (&c.name, &c.faces)));
    for (name, faces) in faces {
        if let Some(v) = faces.iter().flatten().find(|&&v| v as usize >= count) {
            return Err(RigEditError::Value(format!(
                "cage '{name}' refers to vertex {v}, but there are {count}; fix the scene first \
                 (starcages-cli validate lists its problems)"
            )));
        }
    }
    let poses = std::iter::once(&scene.pose).chain(scene.poses.values());
    if poses.into_iter().any(|p| p.len() != count) {
        return Err(RigEditError::Value(
            "a pose has another vertex count than the cages; fix the scene first (starcages-cli \
             validate lists its problems)"
                .into(),
        ));
    }
    Ok(())
}

pub(crate) fn leaf(scene: &Scene, name: &str) -> Result<usize, RigEditError> {
    scene
        .cages
        .leaf_index(name)
        .ok_or_else(|| RigEditError::NoSuchCage(name.to_owned()))
}

pub(crate) fn free_name(scene: &Scene, name: &str) -> Result<(), RigEditError> {
    let set = &scene.cages;
    let taken =
        set.leaves.iter().any(|c| c.name == name) || set.internals.iter().any(|c| c.name == name);
    if taken {
        Err(RigEditError::NameTaken(name.to_owned()))
    } else if let Some(why) = crate::scene::name_problem(name) {
        Err(RigEditError::Value(format!("cage name {name:?}: {why}")))
    } else {
        Ok(())
    }
}

/// The vertex at exactly `p` (rest), or a new one there (at rest in every pose).
pub(crate) fn vertex_at(scene: &mut Scene, p: DVec3) -> u32 {
    if let Some(v) = scene.cages.vertices.iter().position(|q| *q == p) {
        return v as u32;
    }
    scene.cages.vertices.push(p);
    scene.pose.push(p);
    for pose in scene.poses.values_mut() {
        pose.push(p);
    }
    scene.cages.vertices.len() as u32 - 1
}

/// The index of the face `face` names in leaf cage `c`.
pub(crate) fn face_index(scene: &Scene, c: usize, face: FaceRef) -> Result<usize, RigEditError> {
    let cage = &scene.cages.leaves[c];
    match face {
        FaceRef::Index(i) => Ok(i),
        FaceRef::Facing { axis, positive } => {
            let mut toward = DVec3::ZERO;
            toward[axis.min(2)] = if positive { 1.0 } else { -1.0 };
            cage.faces
                .iter()
                .enumerate()
                .map(|(i, f)| (i, face_normal(scene, f).dot(toward)))
                .filter(|(_, alignment)| *alignment > 0.5)
                // Coplanar faces tie (an inset's ring around its inner face, a subdivided
                // face's quads): the lowest index wins, which after an inset is the inner face.
                .fold(
                    None,
                    |best: Option<(usize, f64)>, (i, alignment)| match best {
                        Some((_, b)) if alignment <= b + 1e-9 => best,
                        _ => Some((i, alignment)),
                    },
                )
                .map(|(i, _)| i)
                .ok_or_else(|| {
                    RigEditError::Value(format!(
                        "cage '{}' has no face facing {face}; name the face by its number",
                        cage.name
                    ))
                })
        }
    }
}

/// The index of the face `face` names in leaf cage `c`, checked to exist and to be shared
/// with no other leaf cage (extrude and inset work on the rig's outer surface).
pub(crate) fn free_face(scene: &Scene, c: usize, face: FaceRef) -> Result<usize, RigEditError> {
    let face = face_index(scene, c, face)?;
    let cage = &scene.cages.leaves[c];
    let Some(corners) = cage.faces.get(face) else {
        return Err(RigEditError::NoSuchFace {
            cage: cage.name.clone(),
            face,
            count: cage.faces.len(),
        });
    };
    let key = face_key(corners);
    let shared = scene
        .cages
        .leaves
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != c)
        .flat_map(|(_, l)| &l.faces)
        .any(|f| face_key(f) == key);
    if shared {
        return Err(RigEditError::FaceShared {
            cage: cage.name.clone(),
            face,
        });
    }
    Ok(face)
}

/// A face's unit outward normal (Newell's method: counter-clockwise seen from outside), zero
/// for a face without area.
pub(crate) fn face_normal(scene: &Scene, face: &[u32]) -> DVec3 {
    let points: Vec<DVec3> = face
        .iter()
        .filter_map(|&v| scene.cages.vertices.get(v as usize).copied())
        .collect();
    points
        .iter()
        .zip(points.iter().cycle().skip(1))
        .map(|(a, b)| a.cross(*b))
        .sum::<DVec3>()
        .normalize_or_zero()
}

/// Removes the vertices of `gone` (a removed cage's faces) that no cage uses any more, with
/// their ownership and hierarchy records, renumbering every index.
pub(crate) fn drop_unused_vertices(scene: &mut Scene, gone: &[Vec<u32>]) {
    let used = scene.cages.used_vertices();
    let removed: BTreeSet<u32> = gone
        .iter()
        .flatten()
        .copied()
        .filter(|v| !used.contains(v))
        .collect();
    for internal in &mut scene.cages.internals {
        internal.owns.retain(|v| !removed.contains(v));
        internal.joint.retain(|v| !removed.contains(v));
    }
    for state in std::iter::once(&mut scene.pose_state).chain(scene.pose_states.values_mut()) {
        crate::hierarchy::forget(state, &removed);
    }
    crate::hierarchy::renumber(scene, &removed);
}
