//! Adding the leaf cages of another cage set (a cage OBJ file) to a rig.

use super::vocabulary::{free_name, vertex_at};
use crate::scene::{CageSet, LeafCage, Scene};

/// Adds the leaf cages of `imported` (positions in scene coordinates) to `scene`: vertices at
/// the exact positions of existing ones are reused, so imported cages that meet the rig share
/// its faces; new vertices start at rest in every pose. Names already taken get a number.
pub fn import_leaf_cages(scene: &mut Scene, imported: &CageSet) {
    let map: Vec<u32> = imported
        .vertices
        .iter()
        .map(|&p| vertex_at(scene, p))
        .collect();
    for cage in &imported.leaves {
        let name = (1..)
            .map(|k| {
                if k == 1 {
                    cage.name.clone()
                } else {
                    format!("{}_{k}", cage.name)
                }
            })
            .find(|n| free_name(scene, n).is_ok())
            .unwrap_or_default();
        scene.cages.leaves.push(LeafCage {
            name,
            faces: cage
                .faces
                .iter()
                .map(|f| f.iter().map(|&v| map[v as usize]).collect())
                .collect(),
            ..cage.clone()
        });
    }
}
