//! Subdivision of the leaf cages: every face becomes quads through a vertex at the midpoint of
//! each of its edges and one at its centre (linear: the rest shape does not change). An edge or
//! a face that several cages share gets one new vertex, so borders stay exactly shared.

use std::collections::BTreeMap;

use glam::DVec3;

use super::vocabulary::RigEditError;
use crate::scene::Scene;

/// The most cage vertices a subdivision may make: each one multiplies the vertices by about four,
/// and a rig of this many already takes seconds to validate and bind (repeating `subdivide`
/// would otherwise grow without bound).
pub const MAX_SUBDIVIDED_VERTICES: usize = 100_000;

/// Subdivides every leaf cage's faces; every pose gets the same midpoints and centres of its
/// own positions. Refused while the scene has internal cages, or when the result would pass
/// [`MAX_SUBDIVIDED_VERTICES`].
pub fn subdivide_leaf_cages(scene: &mut Scene) -> Result<(), RigEditError> {
    // New vertices: at most one per face and one per face corner (each edge's midpoint, shared
    // edges counted once per side): an upper bound, checked before anything is made.
    let corners: usize = scene
        .cages
        .leaves
        .iter()
        .flat_map(|c| &c.faces)
        .map(|f| f.len() + 1)
        .sum();
    let most = scene.cages.vertices.len() + corners;
    if most > MAX_SUBDIVIDED_VERTICES {
        let estimate = scene.cages.vertices.len() + corners / 2;
        return Err(RigEditError::Value(format!(
            "subdivide: the rig has {} cage vertices and would get about {estimate}, more than \
             the {MAX_SUBDIVIDED_VERTICES} a rig may have; subdivide only the cages that need \
             it, or start from a coarser rig",
            scene.cages.vertices.len()
        )));
    }
    if !scene.cages.internals.is_empty() {
        return Err(RigEditError::Value(
            "subdivide: internal cages drive leaf vertices, and the new vertices would have no \
             driver; remove the internal cages first (or subdivide before adding them)"
                .into(),
        ));
    }
    // A new vertex is the mean of some old ones: keyed by their sorted indices.
    let mut made: BTreeMap<Vec<u32>, u32> = BTreeMap::new();
    let mut means: Vec<Vec<u32>> = Vec::new();
    let first_new = scene.cages.vertices.len() as u32;
    let mut mean_of = |mut of: Vec<u32>| -> u32 {
        of.sort_unstable();
        *made.entry(of.clone()).or_insert_with(|| {
            means.push(of);
            first_new + means.len() as u32 - 1
        })
    };
    let mut new_faces: Vec<Vec<Vec<u32>>> = Vec::with_capacity(scene.cages.leaves.len());
    for cage in &scene.cages.leaves {
        let mut faces = Vec::new();
        for face in &cage.faces {
            let k = face.len();
            if k < 3 {
                faces.push(face.clone());
                continue;
            }
            let centre = mean_of(face.clone());
            let mids: Vec<u32> = (0..k)
                .map(|i| mean_of(vec![face[i], face[(i + 1) % k]]))
                .collect();
            // Corner i's quad: the corner, the midpoint after it, the centre, the midpoint before
            // it (the face's own orientation).
            for i in 0..k {
                faces.push(vec![face[i], mids[i], centre, mids[(i + k - 1) % k]]);
            }
        }
        new_faces.push(faces);
    }
    let mean = |positions: &[DVec3], of: &[u32]| -> DVec3 {
        of.iter()
            .filter_map(|&v| positions.get(v as usize))
            .sum::<DVec3>()
            / of.len().max(1) as f64
    };
    let extend = |positions: &mut Vec<DVec3>| {
        let added: Vec<DVec3> = means.iter().map(|of| mean(positions, of)).collect();
        positions.extend(added);
    };
    extend(&mut scene.cages.vertices);
    extend(&mut scene.pose);
    for pose in scene.poses.values_mut() {
        extend(pose);
    }
    for (cage, faces) in scene.cages.leaves.iter_mut().zip(new_faces) {
        cage.faces = faces;
    }
    Ok(())
}
