//! Cutting a leaf cage in two across an axis (the editor's loop cut): the ring of edges cut,
//! and the cut.

use std::collections::BTreeSet;

use super::RigEditError;
use super::vocabulary::{face_key, face_normal, free_name, leaf, vertex_at};
use crate::scene::{LeafCage, Scene};

/// The ring a loop cut of leaf cage `cage` across world axis `axis` (0 x, 1 y, 2 z) goes
/// around: the cage's two ends (the faces most against and most along the axis) and, for each
/// corner of the start end in its order, the corner of the far end its side edge leads to. A cut
/// at fraction t puts a vertex on each of those edges at t from the start. Refused where the
/// cage is not two ends joined by a ring of quads, or a ring face is shared with a neighbour
/// (the cut would leave it a T-junction).
pub fn loop_cut_ring(scene: &Scene, cage: &str, axis: usize) -> Result<LoopCutRing, RigEditError> {
    let c = leaf(scene, cage)?;
    let faces = &scene.cages.leaves[c].faces;
    let axis = axis.min(2);
    let along = |f: &[u32]| face_normal(scene, f)[axis];
    let not_a_ring = || {
        RigEditError::Value(format!(
            "split {cage}: it is not two ends joined by a ring of quads across that axis (a box or an \
         extruded cage is); cut another cage or along another axis"
        ))
    };
    if faces.is_empty() {
        return Err(not_a_ring());
    }
    // The ends: the faces most against and most along the axis.
    let (low, high) = (0..faces.len()).fold((0, 0), |(lo, hi), f| {
        (
            if along(&faces[f]) < along(&faces[lo]) {
                f
            } else {
                lo
            },
            if along(&faces[f]) > along(&faces[hi]) {
                f
            } else {
                hi
            },
        )
    });
    let (start, end) = (&faces[low], &faces[high]);
    let k = start.len();
    if low == high || end.len() != k || faces.len() != k + 2 {
        return Err(not_a_ring());
    }
    // Each start vertex's partner on the end face: the other end of its side edge.
    let end_set: BTreeSet<u32> = end.iter().copied().collect();
    let mut partner = std::collections::BTreeMap::new();
    for (f, side) in faces.iter().enumerate() {
        if f == low || f == high {
            continue;
        }
        if side.len() != 4 {
            return Err(not_a_ring());
        }
        for i in 0..4 {
            let (a, b) = (side[i], side[(i + 1) % 4]);
            if start.contains(&a) && end_set.contains(&b) {
                partner.insert(a, b);
            } else if start.contains(&b) && end_set.contains(&a) {
                partner.insert(b, a);
            }
        }
    }
    if partner.len() != k {
        return Err(not_a_ring());
    }
    // A ring face shared with a neighbour would be cut on one side only (a T-junction).
    for (f, side) in faces.iter().enumerate() {
        if f == low || f == high {
            continue;
        }
        let key = face_key(side);
        if let Some(other) = scene
            .cages
            .leaves
            .iter()
            .enumerate()
            .find(|(i, l)| *i != c && l.faces.iter().any(|g| face_key(g) == key))
        {
            return Err(RigEditError::Value(format!(
                "split {cage}: ring face {f} is shared with '{}', which the cut would leave \
                 with a T-junction; cut along another axis",
                other.1.name
            )));
        }
    }
    Ok(LoopCutRing {
        start_face: low,
        end_face: high,
        edges: start.iter().map(|&a| (a, partner[&a])).collect(),
    })
}

/// Where a loop cut goes: see [`loop_cut_ring`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LoopCutRing {
    /// The end the cut fraction is measured from (index in the cage's faces).
    pub start_face: usize,
    /// The other end.
    pub end_face: usize,
    /// The side edges, (start corner, far corner), in the start face's order.
    pub edges: Vec<(u32, u32)>,
}

pub(crate) fn split(
    scene: &mut Scene,
    cage: &str,
    axis: usize,
    t: f64,
    name: &str,
) -> Result<(), RigEditError> {
    free_name(scene, name)?;
    let c = leaf(scene, cage)?;
    if !(t > 0.0 && t < 1.0) {
        return Err(RigEditError::Value(format!(
            "split {cage}: t = {t} must be inside (0, 1)"
        )));
    }
    let ring = loop_cut_ring(scene, cage, axis)?;
    let faces = scene.cages.leaves[c].faces.clone();
    let (low, high) = (ring.start_face, ring.end_face);
    let (start, end) = (&faces[low], &faces[high]);
    let end_set: BTreeSet<u32> = end.iter().copied().collect();
    let partner: std::collections::BTreeMap<u32, u32> = ring.edges.iter().copied().collect();
    // New vertices on the side edges, at t from the start end.
    let mut cut = std::collections::BTreeMap::new();
    for (&a, &b) in &partner {
        let (pa, pb) = (
            scene.cages.vertices[a as usize],
            scene.cages.vertices[b as usize],
        );
        cut.insert(a, vertex_at(scene, pa + (pb - pa) * t));
        // The end vertex maps to the same cut vertex.
        cut.insert(b, cut[&a]);
    }
    // The start part keeps the start face and the start halves of the sides; the far part
    // gets the end face and the far halves. A side quad's start-side corners stay, its
    // end-side corners become cut vertices (and the other way round for the far part).
    let mut near = vec![start.clone()];
    let mut far = vec![end.clone()];
    for (f, side) in faces.iter().enumerate() {
        if f == low || f == high {
            continue;
        }
        near.push(
            side.iter()
                .map(|v| if end_set.contains(v) { cut[v] } else { *v })
                .collect(),
        );
        far.push(
            side.iter()
                .map(|v| if end_set.contains(v) { *v } else { cut[v] })
                .collect(),
        );
    }
    // The new face: the start face moved to the cut, facing the far part from the near one
    // (its orientation is the end face's), and reversed for the far part.
    let cut_face: Vec<u32> = start.iter().rev().map(|v| cut[v]).collect();
    near.push(cut_face.clone());
    far.push(cut_face.iter().rev().copied().collect());
    let original = scene.cages.leaves[c].clone();
    scene.cages.leaves[c].faces = near;
    scene.cages.leaves.push(LeafCage {
        name: name.to_owned(),
        faces: far,
        border_h: Default::default(),
        ..original
    });
    Ok(())
}
