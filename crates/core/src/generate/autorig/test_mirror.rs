//! Shapes for unit tests of the mirrored rig: ribbons of mesh near a mirror plane and a limb
//! part reaching that plane.

use glam::DVec3;

use super::parts::{Parts, Role};
use super::symmetry::MirrorPlane;
use super::voxels::Grid;
use crate::mesh::Mesh;

/// A ribbon 0.3 wide across y along the polyline through `corners` (points 0.1 apart); each
/// polyline of `polylines` its own piece of surface.
pub(super) fn ribbons(polylines: &[&[DVec3]]) -> Mesh {
    let mut positions: Vec<DVec3> = Vec::new();
    let mut triangles = Vec::new();
    for corners in polylines {
        let Some(&first) = corners.first() else {
            continue;
        };
        let mut path = vec![first];
        for pair in corners.windows(2) {
            let steps = ((pair[1] - pair[0]).length() / 0.1).round().max(1.0) as u32;
            path.extend(
                (1..=steps).map(|k| pair[0].lerp(pair[1], f64::from(k) / f64::from(steps))),
            );
        }
        let start = positions.len() as u32;
        let across = DVec3::new(0.0, 0.3, 0.0);
        positions.extend(path.iter().flat_map(|&p| [p, p + across]));
        for k in 0..path.len() as u32 - 1 {
            let a = start + 2 * k;
            triangles.push([a, a + 2, a + 1]);
            triangles.push([a + 1, a + 2, a + 3]);
        }
    }
    Mesh::new(positions, triangles, None, None).expect("a test ribbon is a valid mesh")
}

/// A grid over (0, 0, 0)–(4, 1, `height`) mirrored across x = 2, with a limb part holding
/// the low side's cells from x = 1 to the plane below `body_from` (a height), the body every
/// other cell.
pub(super) fn limb_at_the_plane(height: f64, body_from: f64) -> (Grid, MirrorPlane, Parts) {
    let grid = Grid::around(
        DVec3::ZERO,
        DVec3::new(4.0, 1.0, height),
        8,
        Some((0, 2.0)),
        &[],
        None,
    );
    let plane = MirrorPlane::of(&grid, 0);
    let body_from = grid.cell_at(DVec3::new(2.0, 0.5, body_from)).z;
    let limb_from = grid.cell_at(DVec3::new(1.0, 0.5, 1.0)).x;
    let parts = Parts::of_roles(
        (0..grid.len())
            .map(|i| {
                let c = grid.cell_of(i);
                let limb = c.z < body_from && c.x >= limb_from && plane.is_low_cell(c);
                Some(u32::from(limb))
            })
            .collect(),
        vec![
            Role::Body { body: 0, slab: 0 },
            Role::Limb {
                limb: 0,
                segment: 0,
            },
        ],
    );
    (grid, plane, parts)
}
