//! Limb segments that hold almost none of the mesh: where a cut between two segments runs
//! through a hand or a foot, the cells past it can be a piece or two that hold a handful of
//! mesh vertices (the Ogre's `arm.L.3` turned 15 of its arm's 3,758). Each would get a
//! control that moves nothing an artist can see, and it shifts the numbering of the joints
//! after it between a limb and its pair. Such a segment's parts join the segments of the same
//! limb beside them.

use std::collections::BTreeMap;

use super::parts::{Parts, contacts_of};
use super::surface::SurfaceMesh;
use super::surface_pieces::Surface;
use super::voxels::Grid;

/// A segment holding fewer mesh vertices than this share of its limb's mean segment is a
/// crumb. In the default rigs of the shared meshes, Homer, Cheburashka and the cow (vertices
/// counted by cell, as here), the crumbs hold 1–9 % of their limb's mean; the smallest segment
/// kept, 17 % (the beast's right hand); the next, 37 % and more. A quarter changed 16 of the
/// 100 regression rigs and left as many `.L`/`.R` pairs unequal as before (the Ogre's arms at
/// detail 4, five segments each, became three and four).
const CRUMB_SHARE: f64 = 0.1;

/// The fewest mesh vertices a limb's segments must hold on average for their counts to tell
/// a crumb: the limbs of the regression meshes' default rigs hold about 70 (the cow's legs)
/// to 1,250 (the Ogre's arms) per segment; the tests' box arm, 8 in 6 segments.
const DENSE_SEGMENT: f64 = 40.0;

/// Merges every crumb segment's parts into the other segments of its limb (each part into the
/// one its mesh vertices share the most surface edges with, else the most cell faces), in limbs
/// whose segments hold [`DENSE_SEGMENT`] vertices or more on average. Returns how many parts
/// were merged.
pub(super) fn merge_crumb_segments(grid: &Grid, parts: &mut Parts, surface: &SurfaceMesh) -> usize {
    let cells = Surface::new(grid, surface);
    let held = cells.vertices_by_part(parts);
    let count = |p: u32| held.get(&p).map_or(0, Vec::len);
    // Per limb, per segment: its parts and the mesh vertices they hold.
    let limbs: Vec<BTreeMap<usize, (Vec<u32>, usize)>> = (parts.limb_segments().into_values())
        .map(|segments| {
            (segments.into_iter())
                .map(|(segment, members)| {
                    let held = members.iter().map(|&p| count(p)).sum();
                    (segment, (members, held))
                })
                .collect()
        })
        .collect();
    let mut into: BTreeMap<u32, u32> = BTreeMap::new();
    for segments in &limbs {
        if segments.len() < 2 {
            continue;
        }
        let total: usize = segments.values().map(|(_, n)| n).sum();
        let mean = total as f64 / segments.len() as f64;
        // A coarse mesh's vertices say little of where its surface is (a box's arm has them at
        // its ends only, its segments between hold none).
        if mean < DENSE_SEGMENT {
            continue;
        }
        let least = CRUMB_SHARE * mean;
        let is_crumb = |n: usize| (n as f64) < least;
        // The parts a crumb may join: those of the limb's other segments that are no crumbs.
        let kept: Vec<u32> = segments
            .values()
            .filter(|(_, n)| !is_crumb(*n))
            .flat_map(|(members, _)| members.iter().copied())
            .collect();
        for (members, _) in segments.values().filter(|(_, n)| is_crumb(*n)) {
            for &p in members {
                let own = held.get(&p).map_or(&[][..], Vec::as_slice);
                if let Some(target) = joining(grid, parts, &cells, own, p, &kept) {
                    into.insert(p, target);
                }
            }
        }
    }
    if into.is_empty() {
        return 0;
    }
    parts.merge_into(&into);
    into.len()
}

/// The part of `kept` that part `p` (holding the mesh vertices `own`) joins: the one its
/// vertices share the most surface edges with (so the merged part's surface stays one piece),
/// else the one it shares the most cell faces with; None where it touches none.
fn joining(
    grid: &Grid,
    parts: &Parts,
    cells: &Surface,
    own: &[usize],
    p: u32,
    kept: &[u32],
) -> Option<u32> {
    let best = |counts: BTreeMap<u32, usize>| {
        counts
            .into_iter()
            .filter(|(q, n)| *n > 0 && kept.contains(q))
            .max_by_key(|&(q, n)| (n, std::cmp::Reverse(q)))
            .map(|(q, _)| q)
    };
    let part_of = |v: usize| {
        cells
            .cell_of
            .get(v)
            .copied()
            .flatten()
            .and_then(|c| parts.label[c])
    };
    let mut edges: BTreeMap<u32, usize> = BTreeMap::new();
    for &i in own {
        for &j in cells.neighbours.get(i).into_iter().flatten() {
            if let Some(q) = part_of(j as usize)
                && q != p
            {
                *edges.entry(q).or_insert(0) += 1;
            }
        }
    }
    best(edges).or_else(|| best(contacts_of(grid, &parts.label, p)))
}

#[cfg(test)]
mod tests {

    use glam::DVec3;

    use super::super::parts::Role;
    use super::*;
    use crate::mesh::Mesh;

    /// A ribbon along x from 0.05 to `end`, one pair of vertices every `step`.
    fn ribbon(end: f64, step: f64) -> Mesh {
        let columns = ((end - 0.05) / step).round() as u32 + 1;
        let positions: Vec<DVec3> = (0..columns)
            .flat_map(|k| {
                let x = 0.05 + step * f64::from(k);
                [DVec3::new(x, 0.3, 0.5), DVec3::new(x, 0.6, 0.5)]
            })
            .collect();
        let triangles = (0..columns - 1)
            .flat_map(|k| {
                [
                    [2 * k, 2 * k + 2, 2 * k + 1],
                    [2 * k + 1, 2 * k + 2, 2 * k + 3],
                ]
            })
            .collect();
        Mesh::new(positions, triangles, None, None).unwrap()
    }

    /// Cells by their x: a body up to x = 1, then a limb's three segments, the last from x = 9.
    fn body_and_limb(grid: &Grid) -> Parts {
        let column = |x: f64| grid.cell_at(DVec3::new(x, 0.5, 0.5)).x;
        let (one, five, nine) = (column(1.0), column(5.0), column(9.0));
        Parts::of_roles(
            (0..grid.len())
                .map(|i| {
                    let x = grid.cell_of(i).x;
                    Some(match () {
                        _ if x < one => 0,
                        _ if x < five => 1,
                        _ if x < nine => 2,
                        _ => 3,
                    })
                })
                .collect(),
            std::iter::once(Role::Body { body: 0, slab: 0 })
                .chain((0..3).map(|segment| Role::Limb { limb: 0, segment }))
                .collect(),
        )
    }

    #[test]
    fn a_limb_s_last_segment_holding_a_few_vertices_joins_the_segment_before_it() {
        let grid = Grid::around(DVec3::ZERO, DVec3::new(12.0, 1.0, 1.0), 12, None, &[], None);
        // The ribbon ends just past the last segment's first face: a pair or two of its
        // vertices there, against about 80 in each of the two segments before.
        let mesh = ribbon(8.85, 0.1);
        let before = body_and_limb(&grid);
        let tip = |parts: &Parts| {
            let points = mesh.welded_positions();
            points
                .iter()
                .filter(|&&p| parts.part_at(&grid, p) == Some(3))
                .count()
        };
        assert!((1..=4).contains(&tip(&before)), "{}", tip(&before));
        let mut parts = before.clone();
        assert_eq!(
            merge_crumb_segments(&grid, &mut parts, &SurfaceMesh::new(&mesh)),
            1
        );
        assert_eq!(parts.roles, before.roles[..3]);
        for (i, label) in before.label.iter().enumerate() {
            let expected = if *label == Some(3) { Some(2) } else { *label };
            assert_eq!(parts.label[i], expected);
        }
    }

    #[test]
    fn a_short_last_segment_and_the_body_stay_parts_of_their_own() {
        let grid = Grid::around(DVec3::ZERO, DVec3::new(12.0, 1.0, 1.0), 12, None, &[], None);
        // The last segment holds about 20 columns of the ribbon (a quarter of the others'
        // mean: short, not a crumb); the body about 8, a tenth, but bodies are never crumbs.
        let mesh = ribbon(11.0, 0.1);
        let mut parts = body_and_limb(&grid);
        let before = parts.clone();
        assert_eq!(
            merge_crumb_segments(&grid, &mut parts, &SurfaceMesh::new(&mesh)),
            0
        );
        assert_eq!(parts.label, before.label);
        assert_eq!(parts.roles, before.roles);
    }

    #[test]
    fn on_a_coarse_mesh_a_segment_holding_no_vertex_is_no_crumb() {
        let grid = Grid::around(DVec3::ZERO, DVec3::new(12.0, 1.0, 1.0), 12, None, &[], None);
        // One pair of vertices every 1.3, the last at x = 7.85: six in each of the first two
        // segments, none in the last. Counted so coarsely, vertices do not say where the
        // surface is (the ribbon could be one long quad).
        let mesh = ribbon(7.85, 1.3);
        let mut parts = body_and_limb(&grid);
        let before = parts.clone();
        assert_eq!(
            merge_crumb_segments(&grid, &mut parts, &SurfaceMesh::new(&mesh)),
            0
        );
        assert_eq!(parts.label, before.label);
    }
}
