//! Removing an internal cage: what it owned becomes free (and stays where every pose put it),
//! its own vertices leave the cage vertex array, and every index is renumbered.

use std::collections::BTreeSet;

use thiserror::Error;

use crate::scene::{HierarchyState, Scene};

/// Why an internal cage could not be removed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RemoveInternalCageError {
    /// No internal cage has that index.
    #[error("there is no internal cage {index}; the scene has {count}")]
    NoSuchCage {
        /// The index asked for.
        index: usize,
        /// How many internal cages there are.
        count: usize,
    },
    /// A higher internal cage owns some of this cage's vertices.
    #[error(
        "internal cage '{cage}' is driven by internal cage '{parent}', which owns its vertices; \
         remove '{parent}' first"
    )]
    Driven {
        /// The cage to remove.
        cage: String,
        /// Its parent.
        parent: String,
    },
}

/// Removes internal cage `index` from `scene`. The vertices it owned keep their positions in
/// every pose and become free; its records in the pose states go. Its own vertices (those no
/// other cage uses) are removed from the rest positions and every pose, and all vertex indices
/// above them shift down. Adding an automatic internal cage and removing it gives back the
/// scene exactly.
pub fn remove_internal_cage(
    scene: &mut Scene,
    index: usize,
) -> Result<(), RemoveInternalCageError> {
    let set = &scene.cages;
    let Some(cage) = set.internals.get(index) else {
        return Err(RemoveInternalCageError::NoSuchCage {
            index,
            count: set.internals.len(),
        });
    };
    let own: BTreeSet<u32> = cage.faces.iter().flatten().copied().collect();
    if let Some(parent) = set
        .internals
        .iter()
        .find(|other| other.owns.iter().any(|v| own.contains(v)))
    {
        return Err(RemoveInternalCageError::Driven {
            cage: cage.name.clone(),
            parent: parent.name.clone(),
        });
    }
    let freed: BTreeSet<u32> = cage.owns.iter().copied().collect();
    let cage = scene.cages.internals.remove(index);
    let used_elsewhere = scene.cages.used_vertices();
    let removed: BTreeSet<u32> = cage
        .faces
        .iter()
        .flatten()
        .copied()
        .filter(|v| !used_elsewhere.contains(v))
        .collect();
    forget(&mut scene.pose_state, &freed);
    // A named pose's state that only held records of the freed vertices goes with them (an
    // absent state is the rest state), so that add-then-remove gives back the scene exactly.
    scene.pose_states.retain(|_, state| {
        let was_rest = state.is_rest();
        forget(state, &freed);
        was_rest || !state.is_rest()
    });
    renumber(scene, &removed);
    Ok(())
}

/// Drops the records of `vertices` (they lost their parent).
pub(crate) fn forget(state: &mut HierarchyState, vertices: &BTreeSet<u32>) {
    state.hand_moved.retain(|v| !vertices.contains(v));
    state.rebound.retain(|r| !vertices.contains(&r.vertex));
}

/// Removes the vertices `removed` (used by no cage) and shifts every index above them.
pub(crate) fn renumber(scene: &mut Scene, removed: &BTreeSet<u32>) {
    if removed.is_empty() {
        return;
    }
    let count = scene.cages.vertices.len();
    let mut new_index = vec![u32::MAX; count];
    let mut next = 0u32;
    for (old, slot) in new_index.iter_mut().enumerate() {
        if !removed.contains(&(old as u32)) {
            *slot = next;
            next += 1;
        }
    }
    let map = |v: &mut u32| {
        if let Some(&n) = new_index.get(*v as usize) {
            *v = n;
        }
    };
    let keep = |list: &mut Vec<glam::DVec3>| {
        let mut i = 0;
        list.retain(|_| {
            i += 1;
            !removed.contains(&(i as u32 - 1))
        });
    };
    keep(&mut scene.cages.vertices);
    keep(&mut scene.pose);
    scene.poses.values_mut().for_each(keep);
    let set = &mut scene.cages;
    for face in set.leaves.iter_mut().flat_map(|c| c.faces.iter_mut()) {
        face.iter_mut().for_each(map);
    }
    for cage in &mut set.internals {
        cage.faces.iter_mut().flatten().for_each(map);
        cage.owns.iter_mut().for_each(map);
        cage.joint.iter_mut().for_each(map);
    }
    for state in std::iter::once(&mut scene.pose_state).chain(scene.pose_states.values_mut()) {
        state.hand_moved.iter_mut().for_each(map);
        state.rebound.iter_mut().for_each(|r| map(&mut r.vertex));
    }
}
