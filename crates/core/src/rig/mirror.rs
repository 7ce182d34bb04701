//! A copy of a leaf cage mirrored across x = 0.

use glam::DVec3;

use super::RigEditError;
use super::vocabulary::{free_name, leaf, vertex_at};
use crate::scene::{LeafCage, Scene};

pub(crate) fn mirror(scene: &mut Scene, cage: &str, name: &str) -> Result<(), RigEditError> {
    free_name(scene, name)?;
    let c = leaf(scene, cage)?;
    let source = scene.cages.leaves[c].clone();
    let mut map = std::collections::BTreeMap::new();
    for &v in source.faces.iter().flatten() {
        if map.contains_key(&v) {
            continue;
        }
        let p = scene.cages.vertices[v as usize];
        let mirrored = DVec3::new(-p.x, p.y, p.z);
        map.insert(v, vertex_at(scene, mirrored));
    }
    // A reflection turns orientation inside out: run every face the other way.
    let faces = source
        .faces
        .iter()
        .map(|f| f.iter().rev().map(|v| map[v]).collect())
        .collect();
    scene.cages.leaves.push(LeafCage {
        name: name.to_owned(),
        faces,
        border_h: Default::default(),
        ..source
    });
    Ok(())
}
