//! Merging two neighbouring leaf cages into one.

use std::collections::BTreeSet;

use super::RigEditError;
use super::vocabulary::{drop_unused_vertices, face_key, leaf};
use crate::scene::Scene;

pub(crate) fn merge(scene: &mut Scene, first: &str, second: &str) -> Result<(), RigEditError> {
    let (a, b) = (leaf(scene, first)?, leaf(scene, second)?);
    if a == b {
        return Err(RigEditError::Value(format!(
            "merge {first} {second}: the same cage twice"
        )));
    }
    let shared: BTreeSet<Vec<u32>> = {
        let of_b: BTreeSet<Vec<u32>> = scene.cages.leaves[b]
            .faces
            .iter()
            .map(|f| face_key(f))
            .collect();
        scene.cages.leaves[a]
            .faces
            .iter()
            .map(|f| face_key(f))
            .filter(|k| of_b.contains(k))
            .collect()
    };
    if shared.is_empty() {
        return Err(RigEditError::Value(format!(
            "merge {first} {second}: they share no face; only neighbours can be merged"
        )));
    }
    let keep = |faces: &[Vec<u32>]| -> Vec<Vec<u32>> {
        faces
            .iter()
            .filter(|f| !shared.contains(&face_key(f)))
            .cloned()
            .collect()
    };
    let mut faces = keep(&scene.cages.leaves[a].faces);
    faces.extend(keep(&scene.cages.leaves[b].faces));
    scene.cages.leaves[a].faces = faces;
    scene.cages.leaves[a].border_h.remove(second);
    let gone = scene.cages.leaves.remove(b);
    for other in &mut scene.cages.leaves {
        other.border_h.remove(&gone.name);
    }
    // The vertices only the dissolved faces used (none for two boxes) go.
    drop_unused_vertices(scene, &gone.faces);
    Ok(())
}
