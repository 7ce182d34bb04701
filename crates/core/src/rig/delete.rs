//! Deleting a leaf cage (its vertices no other cage uses go too).

use super::RigEditError;
use super::vocabulary::{drop_unused_vertices, leaf};
use crate::scene::Scene;

pub(crate) fn delete(scene: &mut Scene, cage: &str) -> Result<(), RigEditError> {
    let c = leaf(scene, cage)?;
    let gone = scene.cages.leaves.remove(c);
    // Neighbours' per-border h for the gone cage go too.
    for other in &mut scene.cages.leaves {
        other.border_h.remove(cage);
    }
    drop_unused_vertices(scene, &gone.faces);
    Ok(())
}
