//! What every rig operation shares: its error, the key that finds a face in any cage, and a
//! rest move that the poses follow. The operations (`rig_edit`, `fit`, `inset`, `subdivide`,
//! `weld`) import from here, never from each other's dispatcher.

use glam::DVec3;
use thiserror::Error;

use super::Scene;

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
pub(super) fn face_key(face: &[u32]) -> Vec<u32> {
    let mut key = face.to_vec();
    key.sort_unstable();
    key
}

/// Moves cage vertex `v` at rest to `to`; every pose moves it by the same displacement.
pub(super) fn move_rest_vertex(scene: &mut Scene, v: u32, to: DVec3) {
    let delta = to - scene.cages.vertices[v as usize];
    scene.cages.vertices[v as usize] = to;
    for pose in std::iter::once(&mut scene.pose).chain(scene.poses.values_mut()) {
        if let Some(p) = pose.get_mut(v as usize) {
            *p += delta;
        }
    }
}
