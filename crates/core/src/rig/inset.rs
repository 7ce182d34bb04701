//! Inset of one face of a leaf cage (Blender's Inset Faces): the face becomes a smaller copy of
//! itself, a fixed distance inside each of its edges, joined to its edges by a ring of quads.
//! The cage's shape does not change. Extruding the inner face then gives a neighbour that
//! shares none of the face's edge vertices, so it joins no other cage's join cages.

use glam::DVec3;

use super::vocabulary::RigEditError;
use crate::scene::Scene;

/// The thinnest inset, as a fraction of the face's shortest side: thinner, the ring's quads
/// would be slivers and the inner corners all but on the face's.
const MIN_THICKNESS: f64 = 1e-4;

/// The inner face of a polygon inset by a thickness: per corner i the affine combination
/// inner_i = p_i + α (p_{i−1} − p_i) + β (p_{i+1} − p_i), so that any placement of the polygon
/// (a pose) places its inner face the same way.
#[derive(Debug, Clone, PartialEq)]
pub struct InsetCorners {
    /// (α, β) per corner.
    combinations: Vec<(f64, f64)>,
}

impl InsetCorners {
    /// The inset of the polygon `corners` (counter-clockwise seen from outside) by `thickness`,
    /// measured in its plane from each edge; or why it cannot be: a thickness outside
    /// (1e-4, ½) of the shortest side, a corner where the polygon folds back or runs straight
    /// on, or an inner face that would turn round.
    pub fn new(corners: &[DVec3], thickness: f64) -> Result<Self, String> {
        let k = corners.len();
        let normal = corners
            .iter()
            .zip(corners.iter().cycle().skip(1))
            .map(|(a, b)| a.cross(*b))
            .sum::<DVec3>()
            .normalize_or_zero();
        if normal == DVec3::ZERO || k < 3 {
            return Err("the face has no area".into());
        }
        if thickness.is_nan() || thickness <= 0.0 {
            return Err(format!("the thickness {thickness:?} must be positive"));
        }
        let smallest_side = (0..k)
            .map(|i| corners[i].distance(corners[(i + 1) % k]))
            .fold(f64::INFINITY, f64::min);
        // Less than half the shortest side (more folds a rectangle's inner face), and enough
        // to keep the inner corners apart from the face's corners.
        if thickness >= 0.5 * smallest_side || thickness < MIN_THICKNESS * smallest_side {
            return Err(format!(
                "a thickness of {thickness:?} does not fit the face (its shortest side is \
                 {smallest_side:.4}); use between {:.2e} and half of that",
                MIN_THICKNESS * smallest_side
            ));
        }
        let mut combinations = Vec::with_capacity(k);
        for i in 0..k {
            let (previous, here, next) =
                (corners[(i + k - 1) % k], corners[i], corners[(i + 1) % k]);
            // Inward normals of the edges into and out of the corner, in the face's plane
            // (counter-clockwise seen from outside, so normal × edge points inside).
            let inward_in = normal.cross(here - previous).normalize_or_zero();
            let inward_out = normal.cross(next - here).normalize_or_zero();
            let denominator = 1.0 + inward_in.dot(inward_out);
            if inward_in == DVec3::ZERO || inward_out == DVec3::ZERO || denominator < 1e-6 {
                return Err(format!(
                    "corner {i} has a zero-length edge or folds back; fix the face first"
                ));
            }
            // The point `thickness` inside both edges' lines.
            let offset = (inward_in + inward_out) * (thickness / denominator);
            let (a, b) = (previous - here, next - here);
            let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
            let determinant = aa * bb - ab * ab;
            if determinant <= 1e-12 * aa * bb {
                return Err(format!(
                    "the edges at corner {i} are in line; dissolve that corner first"
                ));
            }
            let (oa, ob) = (offset.dot(a), offset.dot(b));
            combinations.push((
                (oa * bb - ob * ab) / determinant,
                (ob * aa - oa * ab) / determinant,
            ));
        }
        let inset = Self { combinations };
        // The inner face must run the same way as the face, edge by edge, with room to spare
        // (a sharp corner folds it sooner than half the shortest side).
        let inner = inset.place(corners);
        if inner.iter().any(|p| !p.is_finite()) {
            return Err(
                "the inner face's corners would not be finite numbers; use a smaller thickness"
                    .into(),
            );
        }
        for i in 0..k {
            let (outer, inner) = (
                corners[(i + 1) % k] - corners[i],
                inner[(i + 1) % k] - inner[i],
            );
            if inner.dot(outer) <= 1e-3 * smallest_side * outer.length() {
                return Err(format!(
                    "a thickness of {thickness:?} folds the inner face (its shortest side is \
                     {smallest_side:.4}); use less"
                ));
            }
        }
        Ok(inset)
    }

    /// The inner corners for the polygon's corners placed at `corners` (the rest positions
    /// the inset was made for, or a pose of them).
    pub fn place(&self, corners: &[DVec3]) -> Vec<DVec3> {
        let k = corners.len();
        self.combinations
            .iter()
            .enumerate()
            .map(|(i, &(alpha, beta))| {
                let at = |j: usize| corners.get(j % k.max(1)).copied().unwrap_or(DVec3::ZERO);
                at(i) + (at(i + k - 1) - at(i)) * alpha + (at(i + 1) - at(i)) * beta
            })
            .collect()
    }
}

/// Insets face `face` of leaf cage `c` by `thickness` (scene units, measured in the face's
/// plane from each edge; see [`InsetCorners`]). Every pose gets the same affine combination of
/// its own positions: a pose that moves the face rigidly or affinely moves the inset with it.
/// Refused for a face another cage shares (checked by the caller), a thickness that does not
/// fit, and while internal cages exist (the new vertices would have no driver).
pub fn inset_face(
    scene: &mut Scene,
    c: usize,
    face: usize,
    thickness: f64,
) -> Result<(), RigEditError> {
    let name = scene.cages.leaves[c].name.clone();
    if !scene.cages.internals.is_empty() {
        return Err(RigEditError::Value(format!(
            "inset {name} {face}: internal cages drive leaf vertices, and the new vertices would \
             have no driver; inset before adding internal cages"
        )));
    }
    let corners = scene.cages.leaves[c].faces[face].clone();
    let positions_of = |positions: &[DVec3]| -> Vec<DVec3> {
        corners
            .iter()
            .map(|&v| positions.get(v as usize).copied().unwrap_or(DVec3::ZERO))
            .collect()
    };
    let rest = positions_of(&scene.cages.vertices);
    let inset = InsetCorners::new(&rest, thickness)
        .map_err(|why| RigEditError::Value(format!("inset {name} {face}: {why}")))?;
    let k = corners.len();
    let first_new = scene.cages.vertices.len() as u32;
    let inner: Vec<u32> = (0..k as u32).map(|i| first_new + i).collect();
    let posed = inset.place(&positions_of(&scene.pose));
    scene.pose.extend(posed);
    for pose in scene.poses.values_mut() {
        let moved = inset.place(&positions_of(pose));
        pose.extend(moved);
    }
    scene.cages.vertices.extend(inset.place(&rest));
    // The inner face keeps the face's orientation; each ring quad runs along its outer edge
    // the same way and back along the inner one.
    let cage = &mut scene.cages.leaves[c];
    cage.faces[face] = inner.clone();
    for i in 0..k {
        let j = (i + 1) % k;
        cage.faces
            .push(vec![corners[i], corners[j], inner[j], inner[i]]);
    }
    Ok(())
}
