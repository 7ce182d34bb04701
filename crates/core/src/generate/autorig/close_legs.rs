//! Legs standing closer together than a grid cell: when the rig found them, and how wide the
//! gap between them is.
//!
//! Cells that hold both legs' inner surfaces join the legs into one solid as thick as the body,
//! so one leg, or none, is found. [`super::autorig`] then rigs a figure that stands on separate
//! feet and is symmetric across a horizontal plane again, on a grid with that plane through the
//! middle of a column of cells; where the gap is narrower than a cell, on a grid whose column
//! there is thinner than the gap ([`gap_between_legs`], [`super::voxels::Band`]), every other
//! cell as the detail's. It does so too where the legs it found reach little of the height
//! ([`leg_reach`]): thighs pressed together over thinner shins leave only the feet as legs.

use super::Autorig;
use super::name_defects::{is_leg, is_leg_without_side};
use super::surface::SurfaceMesh;
use crate::mesh::Mesh;
use std::collections::BTreeSet;

/// How many limbs of `rig` are legs with a side (`leg.L`, `leg.front.R` …), by its leaf
/// cages' names.
pub(super) fn sided_legs(rig: &Autorig) -> usize {
    leg_limbs(rig)
        .filter(|limb| limb.ends_with(".L") || limb.ends_with(".R"))
        .count()
}

/// Whether `rig` has more legs on one side than on the other (`leg.front.R` and `leg.back.R`
/// but only `leg.L`): on a figure symmetric across a horizontal plane, two legs the grid
/// joined where their feet touch (one chain down one leg and up the other) or a leg left in
/// the body.
pub(super) fn unpaired_legs(rig: &Autorig) -> bool {
    let on = |side: &str| leg_limbs(rig).filter(|limb| limb.ends_with(side)).count();
    on(".L") != on(".R")
}

/// How many limbs of `rig` are legs without a side (`leg`, `leg.front`): two legs the grid
/// joined along the symmetry plane (the camel's front legs, a cell apart) are one such limb.
pub(super) fn unsided_legs(rig: &Autorig) -> usize {
    leg_limbs(rig)
        .filter(|limb| is_leg_without_side(limb))
        .count()
}

/// How high the legs of `rig` reach: the top of their leaf cages (sided legs and the stems
/// carrying them) above the lowest cage vertex, as a share of the cages' height (0 with no
/// leg). Legs a cell apart that the grid joined above the ankles leave only the feet as legs
/// (TOSCA's Victoria at the default detail: two feet under body slabs holding both legs,
/// 0.08).
pub(super) fn leg_reach(rig: &Autorig) -> f64 {
    let cages = &rig.cages;
    let (lo, hi) = crate::cage::bounds_of(&cages.vertices);
    let height = hi.z - lo.z;
    let top = (cages.leaves.iter())
        .filter(|leaf| {
            leaf.name
                .split_once('_')
                .is_some_and(|(limb, _)| is_leg(limb))
        })
        .flat_map(|leaf| leaf.faces.iter().flatten())
        .filter_map(|&v| cages.vertices.get(v as usize))
        .map(|p| p.z)
        .max_by(f64::total_cmp);
    match top {
        Some(top) if height > 0.0 => ((top - lo.z) / height).clamp(0.0, 1.0),
        _ => 0.0,
    }
}

/// How many limbs of `rig` other than legs have a side (arms, ears …), by its leaf cages'
/// names: a retry that parts the legs must keep them.
pub(super) fn sided_other_limbs(rig: &Autorig) -> usize {
    limbs_of_rig(rig)
        .into_iter()
        .filter(|limb| !is_leg(limb) && (limb.ends_with(".L") || limb.ends_with(".R")))
        .count()
}

/// Whether `rig` has a head: a limb named `head` (or a numbered copy, `head.001`), by its
/// leaf cages' names. A retry that parts the legs must keep it.
pub(super) fn has_head(rig: &Autorig) -> bool {
    limbs_of_rig(rig)
        .into_iter()
        .any(|limb| limb == "head" || limb.starts_with("head."))
}

/// Legs reaching less than this share of the figure's height ([`leg_reach`]) are
/// feet the grid parted under legs it joined: a quadruped's legs reach a third of it or more
/// (spot's, the shortest of the shared meshes', 0.3–0.35).
pub(super) const SHORT_LEG_REACH: f64 = 0.3;

/// [`SHORT_LEG_REACH`] for a figure on two legs (`leg.L` and `leg.R`, no front or back
/// pair): a person's legs reach about half of the height, so legs reaching a third of it
/// are shins under thighs the grid joined (TOSCA's Michael, his thighs pressed together
/// down to the knees: his legs' cages reached 0.33 and his hips turned at his knees, 23 %
/// up). The beast's legs at detail 1, its thickest, reach 0.41.
pub(super) const SHORT_BIPED_LEG_REACH: f64 = 0.4;

/// Whether `rig` stands on two legs: it has sided legs and all of them are `leg.L` or
/// `leg.R` (a quadruped's are `leg.front.L` …).
pub(super) fn on_two_legs(rig: &Autorig) -> bool {
    let mut sided = leg_limbs(rig)
        .filter(|limb| limb.ends_with(".L") || limb.ends_with(".R"))
        .peekable();
    sided.peek().is_some() && sided.all(|limb| limb == "leg.L" || limb == "leg.R")
}

/// How much higher a retry's legs must reach to be kept over the detail's rig with as many
/// sided legs.
pub(super) const BETTER_LEG_REACH: f64 = 0.05;

/// The names of the limbs of `rig` that are legs, once each, by its leaf cages' names.
fn leg_limbs(rig: &Autorig) -> impl Iterator<Item = &str> {
    limbs_of_rig(rig).into_iter().filter(|limb| is_leg(limb))
}

/// The names of the limbs of `rig`, once each: its limb leaf cages are named
/// `<limb>_<segment>` (body cages `body_<slab>`, which this lists as `body`).
fn limbs_of_rig(rig: &Autorig) -> BTreeSet<&str> {
    (rig.cages.leaves.iter())
        .filter_map(|leaf| leaf.name.split_once('_').map(|(limb, _)| limb))
        .collect()
}

/// Whether the figure stands on separate feet: the welded mesh vertices in its lowest
/// [`FEET_SHARE`] of height fall in two pieces or more joined by its surface (legs the grid may
/// have joined; a ball, a bust or a body on one base is one piece).
pub(super) fn stands_on_separate_feet(surface: &SurfaceMesh) -> bool {
    let points = surface.mesh.welded_positions();
    let (lo, hi) = surface.mesh.bounds();
    let floor = lo.z + FEET_SHARE * (hi.z - lo.z);
    let low: Vec<bool> = points.iter().map(|p| p.z <= floor).collect();
    let mut seen = vec![false; points.len()];
    let mut pieces = 0;
    for start in 0..points.len() {
        if !low[start] || seen[start] {
            continue;
        }
        pieces += 1;
        if pieces >= 2 {
            return true;
        }
        seen[start] = true;
        let mut stack = vec![start];
        while let Some(v) = stack.pop() {
            for &n in surface.neighbours.get(v).into_iter().flatten() {
                let n = n as usize;
                if low.get(n) == Some(&true) && !seen[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            }
        }
    }
    false
}

/// The share of the figure's height, from the bottom, in which [`stands_on_separate_feet`]
/// looks for feet.
const FEET_SHARE: f64 = 0.05;

/// The gap between the legs across the plane `axis = centre` (a vertical plane the figure is
/// symmetric across): the crotch is the lowest point of the surface that crosses the plane; in
/// the lower [`LEG_SPAN_MEASURED`] of the height below it, the gap is twice the least distance
/// of a mesh vertex from the plane (no triangle there crosses it, so its nearest point is a
/// corner). None where the plane crosses no triangle (the halves are not joined), the crotch is
/// lower than [`LEAST_LEG_SHARE`] of the height, or the legs touch below it.
pub(super) fn gap_between_legs(mesh: &Mesh, axis: usize, centre: f64) -> Option<f64> {
    let positions = mesh.welded_positions();
    let (lo, hi) = mesh.bounds();
    let height = hi.z - lo.z;
    if axis > 1 || height.is_nan() || height <= 0.0 {
        return None;
    }
    let crotch = mesh
        .welded_triangles()
        .iter()
        .filter_map(|t| {
            let corners = t.map(|k| positions.get(k as usize).copied());
            let [Some(a), Some(b), Some(c)] = corners else {
                return None;
            };
            let low = a[axis].min(b[axis]).min(c[axis]);
            let high = a[axis].max(b[axis]).max(c[axis]);
            (low <= centre && centre <= high).then_some(a.z.min(b.z).min(c.z))
        })
        .min_by(f64::total_cmp)?;
    if crotch - lo.z < LEAST_LEG_SHARE * height {
        return None;
    }
    let top = lo.z + LEG_SPAN_MEASURED * (crotch - lo.z);
    let half_gap = positions
        .iter()
        .filter(|p| p.z <= top)
        .map(|p| (p[axis] - centre).abs())
        .min_by(f64::total_cmp)?;
    let gap = 2.0 * half_gap;
    (gap.is_finite() && gap > 0.0).then_some(gap)
}

/// The share of the legs' height, from the ground up to the crotch, over which
/// [`gap_between_legs`] measures it (above it the thighs curve into the
/// crotch).
const LEG_SPAN_MEASURED: f64 = 0.75;

/// The width of the thin cells between legs ([`super::voxels::Band`]) as a share of the gap
/// between them: below 1, so that no surface passes through them.
pub(super) const CELL_IN_GAP: f64 = 0.8;

/// The least height of a crotch, as a share of the figure's, for [`gap_between_legs`] to see
/// legs below it.
const LEAST_LEG_SHARE: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::demo::box_mesh;
    use glam::DVec3;

    /// Two boxes `gap` apart under a box across them: legs under a pelvis.
    fn two_legs(gap: f64) -> Mesh {
        let half = 0.5 * gap;
        let boxes = [
            (
                DVec3::new(-0.3 - half, -0.15, 0.0),
                DVec3::new(-half, 0.15, 1.0),
            ),
            (
                DVec3::new(half, -0.15, 0.0),
                DVec3::new(0.3 + half, 0.15, 1.0),
            ),
            (DVec3::new(-0.35, -0.2, 0.9), DVec3::new(0.35, 0.2, 2.0)),
        ];
        let (mut positions, mut triangles) = (Vec::new(), Vec::new());
        for (lo, hi) in boxes {
            let part = box_mesh(lo, hi, [1, 1, 1]);
            let base = positions.len() as u32;
            positions.extend_from_slice(part.welded_positions());
            triangles.extend(part.welded_triangles().iter().map(|t| t.map(|k| k + base)));
        }
        Mesh::new(positions, triangles, None, None).unwrap()
    }

    #[test]
    fn the_gap_between_the_legs_is_measured_below_the_crotch() {
        for gap in [0.05, 0.1] {
            let measured = gap_between_legs(&two_legs(gap), 0, 0.0).unwrap();
            assert!((measured - gap).abs() < 1e-12, "{measured} against {gap}");
        }
    }

    #[test]
    fn no_legs_no_gap() {
        // Legs that touch.
        assert_eq!(gap_between_legs(&two_legs(0.0), 0, 0.0), None);
        // Across the other horizontal plane, the "legs" are one solid from the ground up.
        assert_eq!(gap_between_legs(&two_legs(0.05), 1, 0.0), None);
    }
}
