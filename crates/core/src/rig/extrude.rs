//! Extruding a free face of a leaf cage into a new cage that shares it.

use glam::DVec3;

use super::vocabulary::{face_normal, free_face, free_name, leaf, vertex_at};
use super::{FaceRef, RigEditError};
use crate::scene::{LeafCage, Scene};

pub(crate) fn extrude(
    scene: &mut Scene,
    cage: &str,
    face: FaceRef,
    distance: f64,
    name: &str,
) -> Result<(), RigEditError> {
    free_name(scene, name)?;
    let c = leaf(scene, cage)?;
    let face = free_face(scene, c, face)?;
    let corners = scene.cages.leaves[c].faces[face].clone();
    if distance.is_nan() || distance <= 0.0 {
        return Err(RigEditError::Value(format!(
            "extrude {cage} {face}: the distance {distance} must be positive"
        )));
    }
    let points: Vec<DVec3> = corners
        .iter()
        .map(|&v| scene.cages.vertices[v as usize])
        .collect();
    let normal = face_normal(scene, &corners);
    if normal == DVec3::ZERO {
        return Err(RigEditError::Value(format!(
            "face {face} of '{cage}' has no area to extrude"
        )));
    }
    let cap: Vec<u32> = points
        .iter()
        .map(|p| vertex_at(scene, *p + normal * distance))
        .collect();
    // The base is the shared face run the other way; the cap keeps the face's orientation
    // (it faces outwards, away from the old cage); the sides join edge (a, b) to (a', b').
    let mut new_faces = vec![
        corners.iter().rev().copied().collect::<Vec<u32>>(),
        cap.clone(),
    ];
    let k = corners.len();
    for i in 0..k {
        let j = (i + 1) % k;
        new_faces.push(vec![corners[i], corners[j], cap[j], cap[i]]);
    }
    let kind = scene.cages.leaves[c].kind;
    scene.cages.leaves.push(LeafCage {
        name: name.to_owned(),
        kind,
        h: None,
        border_h: Default::default(),
        faces: new_faces,
    });
    Ok(())
}
