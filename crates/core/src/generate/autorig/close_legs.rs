//! Legs standing closer together than a grid cell: when the rig found them, and how fine a grid
//! must be to find them.
//!
//! Cells that hold both legs' inner surfaces join the legs into one solid as thick as the body,
//! so one leg, or none, is found. [`super::autorig`] then rigs a figure that stands on separate
//! feet and is symmetric across a horizontal plane again, on a grid with that plane through the
//! middle of a column of cells; where the gap is narrower than a cell, on a grid whose cells fit
//! in it ([`cells_to_part_legs`]).

use super::Autorig;
use super::surface::SurfaceMesh;
use crate::mesh::Mesh;
use std::collections::BTreeSet;

/// How many limbs of `rig` are legs with a side (`leg.L`, `leg.front.R` …), by its leaf
/// cages' names.
pub(super) fn sided_legs(rig: &Autorig) -> usize {
    let limbs: BTreeSet<&str> = rig
        .cages
        .leaves
        .iter()
        .filter_map(|leaf| leaf.name.split_once('_').map(|(limb, _)| limb))
        .filter(|limb| limb.starts_with("leg.") && (limb.ends_with(".L") || limb.ends_with(".R")))
        .collect();
    limbs.len()
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

/// Cells along the mesh's longest side of a grid whose cells fit between the legs, measured
/// across the plane `axis = centre` (a vertical plane the figure is symmetric across): the
/// crotch is the lowest point of the surface that crosses the plane; in the lower
/// [`LEG_SPAN_MEASURED`] of the height below it, the gap between the legs is twice the least
/// distance of a mesh vertex from the plane (no triangle there crosses it, so its nearest point
/// is a corner). The cells are [`CELL_IN_GAP`] of that gap, so that a column centred on the
/// plane holds no surface. None where the plane crosses no triangle (the halves are not joined),
/// the crotch is lower than [`LEAST_LEG_SHARE`] of the height, or the legs touch below it.
pub(super) fn cells_to_part_legs(mesh: &Mesh, axis: usize, centre: f64) -> Option<u32> {
    let positions = mesh.welded_positions();
    let (lo, hi) = mesh.bounds();
    let height = hi.z - lo.z;
    let longest = (hi - lo).max_element();
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
    let cell = CELL_IN_GAP * 2.0 * half_gap;
    if cell.is_nan() || cell <= 0.0 {
        return None;
    }
    let cells = (longest / cell).ceil();
    (cells.is_finite() && cells <= f64::from(u32::MAX)).then_some(cells as u32)
}

/// The share of the legs' height, from the ground up to the crotch, over which
/// [`cells_to_part_legs`] measures the gap between them (above it the thighs curve into the
/// crotch).
const LEG_SPAN_MEASURED: f64 = 0.75;

/// A grid cell's share of the gap between the legs in [`cells_to_part_legs`]: below 1, so that
/// the surface sampled at [0.45 cells](super::voxels::solid_cells) stays out of the column.
const CELL_IN_GAP: f64 = 0.8;

/// The least height of a crotch, as a share of the figure's, for [`cells_to_part_legs`] to see
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
    fn the_cells_fit_in_the_gap_between_the_legs() {
        let mesh = two_legs(0.05);
        let cells = cells_to_part_legs(&mesh, 0, 0.0).unwrap();
        let cell = 2.0 / f64::from(cells);
        assert!(cell < 0.05 && cell > 0.7 * 0.05, "cell {cell}");
        // A twice wider gap: cells twice as large, their count rounded up (so 2 × ⌈n / 2⌉ ≤ n + 2).
        let wide = cells_to_part_legs(&two_legs(0.1), 0, 0.0).unwrap();
        assert!(wide * 2 <= cells + 2, "{wide} against {cells}");
    }

    #[test]
    fn no_legs_no_gap() {
        // Legs that touch.
        assert_eq!(cells_to_part_legs(&two_legs(0.0), 0, 0.0), None);
        // Across the other horizontal plane, the "legs" are one solid from the ground up.
        assert_eq!(cells_to_part_legs(&two_legs(0.05), 1, 0.0), None);
    }
}
