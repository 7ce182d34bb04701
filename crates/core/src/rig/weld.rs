//! Welding cage vertices: vertices that meet (snapped onto each other in the editor, or within
//! a distance in a script) become one, so cages that touch there share their border exactly,
//! as the *Cages join transformations need (a border is a face both cages index).

use std::collections::BTreeSet;

use super::vocabulary::RigEditError;
use crate::scene::Scene;

/// What a weld did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WeldReport {
    /// How many vertices were merged into others (and removed).
    pub merged: usize,
    /// For every vertex index before the weld, its index after (a merged vertex maps to the
    /// vertex it became).
    pub new_index: Vec<u32>,
}

/// Merges cage vertices no farther apart than `distance` (rest positions; 0: exactly equal).
/// With `moved`, only pairs with at least one vertex of `moved` count, and the other vertex
/// stays (it is what `moved` was snapped onto); otherwise the lower index stays. The vertex
/// that stays keeps its rest and pose positions. Refused, with the scene unchanged, while
/// internal cages exist (they record the leaf vertices they drive by index) or when a face
/// would lose a corner (two of its corners would become one).
pub fn weld_vertices(
    scene: &mut Scene,
    distance: f64,
    moved: Option<&BTreeSet<u32>>,
) -> Result<WeldReport, RigEditError> {
    if !(distance >= 0.0 && distance.is_finite()) {
        return Err(RigEditError::Value(format!(
            "weld {distance}: the distance must be a finite number ≥ 0"
        )));
    }
    if !scene.cages.internals.is_empty() {
        return Err(RigEditError::Value(
            "weld: internal cages record the leaf vertices they drive by index; remove the \
             internal cages first (or weld before adding them)"
                .into(),
        ));
    }
    let count = scene.cages.vertices.len();
    let is_moved = |v: usize| moved.is_none_or(|m| m.contains(&(v as u32)));
    // Which vertex each one becomes: sweep the vertices in order of x, so only pairs within
    // `distance` in x are compared.
    let positions = &scene.cages.vertices;
    let mut order: Vec<usize> = (0..count).collect();
    order.sort_by(|&a, &b| positions[a].x.total_cmp(&positions[b].x));
    let mut target: Vec<usize> = (0..count).collect();
    for (i, &a) in order.iter().enumerate() {
        for &b in &order[i + 1..] {
            if positions[b].x - positions[a].x > distance {
                break;
            }
            if positions[a].distance(positions[b]) > distance || !(is_moved(a) || is_moved(b)) {
                continue;
            }
            // The stationary vertex stays (it is the snap target); else the lower index.
            let (stays, goes) = match (is_moved(a), is_moved(b)) {
                (true, false) => (b, a),
                (false, true) => (a, b),
                _ => (a.min(b), a.max(b)),
            };
            let (stays, goes) = (root(&target, stays), root(&target, goes));
            if stays != goes {
                target[goes] = stays;
            }
        }
    }
    let becomes: Vec<u32> = (0..count).map(|v| root(&target, v) as u32).collect();
    let removed: BTreeSet<u32> = (0..count as u32)
        .filter(|&v| becomes[v as usize] != v)
        .collect();
    let mut faces: Vec<Vec<Vec<u32>>> = Vec::with_capacity(scene.cages.leaves.len());
    for cage in &scene.cages.leaves {
        let mut welded_faces = Vec::with_capacity(cage.faces.len());
        for (f, face) in cage.faces.iter().enumerate() {
            let welded: Vec<u32> = face
                .iter()
                .map(|&v| becomes.get(v as usize).copied().unwrap_or(v))
                .collect();
            if welded.iter().collect::<BTreeSet<_>>().len() < welded.len() {
                return Err(RigEditError::Value(format!(
                    "weld: face {f} of '{}' would lose a corner (two of its corners would become \
                     one); move them apart first",
                    cage.name
                )));
            }
            welded_faces.push(welded);
        }
        faces.push(welded_faces);
    }
    for (cage, faces) in scene.cages.leaves.iter_mut().zip(faces) {
        cage.faces = faces;
    }
    // Index after removal: the kept vertices close ranks.
    let mut compact = vec![0u32; count];
    let mut next = 0u32;
    for (v, slot) in compact.iter_mut().enumerate() {
        *slot = next;
        if !removed.contains(&(v as u32)) {
            next += 1;
        }
    }
    let new_index = becomes.iter().map(|&b| compact[b as usize]).collect();
    for state in std::iter::once(&mut scene.pose_state).chain(scene.pose_states.values_mut()) {
        crate::hierarchy::forget(state, &removed);
    }
    crate::hierarchy::renumber(scene, &removed);
    Ok(WeldReport {
        merged: removed.len(),
        new_index,
    })
}

/// The vertex `v` finally becomes (follows the chain of merges).
fn root(target: &[usize], mut v: usize) -> usize {
    while target[v] != v {
        v = target[v];
    }
    v
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::check::validate_scene;
    use crate::rig::{RigOp, apply_rig_op};

    /// Two boxes 1e-3 apart along x: their facing faces do not share vertices.
    fn two_boxes_apart(gap: f64) -> Scene {
        let mut scene = crate::generate::demo::demo_scene("bar", 0.3).unwrap();
        scene.cages.leaves.clear();
        scene.cages.vertices.clear();
        scene.pose.clear();
        scene.poses.clear();
        let lo = scene.mesh.bounds().0 - DVec3::splat(0.1);
        let hi = scene.mesh.bounds().1 + DVec3::splat(0.1);
        let mid = 0.5 * (lo.x + hi.x);
        for (name, min, max) in [
            ("left", lo, DVec3::new(mid, hi.y, hi.z)),
            ("right", DVec3::new(mid + gap, lo.y, lo.z), hi),
        ] {
            let op = RigOp::AddBox {
                name: name.into(),
                min,
                max,
                kind: crate::coords::CoordinateKind::MeanValue,
            };
            apply_rig_op(&mut scene, &op).unwrap();
        }
        scene
    }

    #[test]
    fn welding_a_gap_makes_the_boxes_share_a_face_and_keeps_the_stationary_vertices() {
        let mut scene = two_boxes_apart(1e-3);
        assert_eq!(scene.cages.vertices.len(), 16);
        assert!(scene.cages.adjacency().is_empty(), "no shared face yet");
        // Too small a distance: nothing happens.
        let mut unchanged = scene.clone();
        let report = weld_vertices(&mut unchanged, 1e-4, None).unwrap();
        assert_eq!(report.merged, 0);
        assert_eq!(unchanged, scene);
        // The right box's vertices moved: the left box's stay where they are.
        let right = scene.cages.leaf_index("right").unwrap();
        let moved: BTreeSet<u32> = scene.cages.leaves[right]
            .faces
            .iter()
            .flatten()
            .copied()
            .collect();
        let left_before = scene.cages.vertices[..8].to_vec();
        let report = weld_vertices(&mut scene, 2e-3, Some(&moved)).unwrap();
        assert_eq!(report.merged, 4);
        assert_eq!(scene.cages.vertices.len(), 12);
        assert_eq!(scene.pose.len(), 12);
        assert_eq!(
            scene.cages.vertices[..8],
            left_before[..],
            "the targets stay"
        );
        assert_eq!(scene.cages.adjacency().len(), 1, "one shared face");
        assert!(validate_scene(&scene).is_valid());
        // Every old index maps to a vertex at (about) its old position.
        for (old, &new) in report.new_index.iter().enumerate() {
            let was = two_boxes_apart(1e-3).cages.vertices[old];
            assert!(scene.cages.vertices[new as usize].distance(was) <= 2e-3);
        }
    }

    #[test]
    fn the_weld_operation_of_scripts_welds_the_whole_rig() {
        assert_eq!(RigOp::parse("weld").unwrap(), RigOp::Weld { distance: 0.0 });
        let op = RigOp::parse("weld 0.002").unwrap();
        assert_eq!(op, RigOp::Weld { distance: 0.002 });
        assert!(RigOp::parse("weld near").is_err());
        let mut scene = two_boxes_apart(1e-3);
        apply_rig_op(&mut scene, &op).unwrap();
        assert_eq!(scene.cages.vertices.len(), 12);
        assert_eq!(scene.cages.adjacency().len(), 1);
    }

    #[test]
    fn welding_refuses_to_collapse_a_face_and_leaves_the_scene_unchanged() {
        let mut scene = two_boxes_apart(1e-3);
        let before = scene.clone();
        // A distance as large as the boxes would merge the corners of one face.
        let error = weld_vertices(&mut scene, 10.0, None).unwrap_err();
        assert!(error.to_string().contains("would lose a corner"), "{error}");
        assert_eq!(scene, before);
        // Negative control for the distance check.
        assert!(weld_vertices(&mut scene, f64::NAN, None).is_err());
        assert!(weld_vertices(&mut scene, -1.0, None).is_err());
    }

    #[test]
    fn welding_only_pairs_with_a_moved_vertex() {
        let mut scene = two_boxes_apart(1e-3);
        // Nothing of the gap moved: the pairs across it are not welded.
        let far = (0..scene.cages.vertices.len() as u32)
            .find(|&v| scene.cages.vertices[v as usize].x < 0.0)
            .unwrap();
        let report = weld_vertices(&mut scene, 2e-3, Some(&BTreeSet::from([far]))).unwrap();
        assert_eq!(report.merged, 0);
        let mut exact = two_boxes_apart(0.0);
        assert_eq!(
            exact.cages.vertices.len(),
            12,
            "add-box reuses exact corners"
        );
        assert_eq!(weld_vertices(&mut exact, 0.0, None).unwrap().merged, 0);
    }
}
