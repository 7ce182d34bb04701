//! Leaf cages from labelled cells: each part's surface is the cell faces between it and any
//! other label, merged into as few rectangles as the labels allow. A rectangle between two
//! parts is one face of both (run in opposite directions), so neighbouring cages share their
//! borders exactly; a grid vertex where rectangles meet is a corner of every rectangle whose
//! edge passes through it (no T-junctions).

use std::collections::{BTreeMap, BTreeSet};

use glam::IVec3;

use super::parts::Parts;
use super::symmetry::{MirrorPlane, partners};
use super::voxels::Grid;

/// A face polygon over grid vertices, counter-clockwise seen from the side of `front`.
#[derive(Debug, Clone)]
pub(super) struct GridFace {
    /// Corners (grid vertices), counter-clockwise seen from the part `front` is outward for.
    pub corners: Vec<IVec3>,
    /// The part the face bounds from behind (its outward side faces away from this part).
    pub front: Option<u32>,
    /// The part on the other side (None: outside).
    pub back: Option<u32>,
}

/// The merged rectangles of every boundary between two labels, as polygons with the grid
/// vertices that other rectangles put on their edges. Polygons whose fan from the first corner
/// would hold a degenerate triangle are split. With a `mirror` plane, the faces on the high side
/// are the images of those on the low side (no rectangle crosses the plane).
pub(super) fn boundary_faces(
    grid: &Grid,
    parts: &Parts,
    mirror: Option<&MirrorPlane>,
) -> Vec<GridFace> {
    let mut rectangles = Vec::new();
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let d = grid.dims;
        for plane in 0..=d[axis] {
            // Labels on either side of each unit face of this plane.
            let side = |a: i32, b: i32, w: i32| -> Option<u32> {
                let mut c = IVec3::ZERO;
                c[axis] = w;
                c[u] = a;
                c[v] = b;
                grid.index(c).and_then(|i| parts.label[i])
            };
            let (nu, nv) = (d[u], d[v]);
            // With a mirror, the side of the mirror plane is part of the key: no rectangle
            // crosses it.
            let high = |a: i32, b: i32| match mirror {
                Some(m) if m.axis == u => a >= m.half,
                Some(m) if m.axis == v => b >= m.half,
                _ => false,
            };
            let key = |a: i32, b: i32| -> Option<(Option<u32>, Option<u32>, bool)> {
                let (below, above) = (side(a, b, plane - 1), side(a, b, plane));
                (below != above).then_some((below, above, high(a, b)))
            };
            let mut used = vec![false; (nu * nv) as usize];
            for b in 0..nv {
                for a in 0..nu {
                    if used[(a + nu * b) as usize] {
                        continue;
                    }
                    let Some(k) = key(a, b) else { continue };
                    // Greedy: widen along u, then grow along v while the whole row matches.
                    let mut a1 = a + 1;
                    while a1 < nu && !used[(a1 + nu * b) as usize] && key(a1, b) == Some(k) {
                        a1 += 1;
                    }
                    let mut b1 = b + 1;
                    'grow: while b1 < nv {
                        for x in a..a1 {
                            if used[(x + nu * b1) as usize] || key(x, b1) != Some(k) {
                                break 'grow;
                            }
                        }
                        b1 += 1;
                    }
                    for y in b..b1 {
                        for x in a..a1 {
                            used[(x + nu * y) as usize] = true;
                        }
                    }
                    let corner = |x: i32, y: i32| {
                        let mut c = IVec3::ZERO;
                        c[axis] = plane;
                        c[u] = x;
                        c[v] = y;
                        c
                    };
                    // Counter-clockwise seen from +axis (u × v = axis).
                    let ring = [corner(a, b), corner(a1, b), corner(a1, b1), corner(a, b1)];
                    let low = match mirror {
                        Some(m) if m.axis == axis => plane <= m.half,
                        Some(_) => !k.2,
                        None => true,
                    };
                    if low {
                        rectangles.push((ring, k.0, k.1));
                    }
                }
            }
        }
    }
    let corners: BTreeSet<(i32, i32, i32)> = rectangles
        .iter()
        .flat_map(|(ring, _, _)| ring.iter())
        .flat_map(|&c| [Some(c), mirror.map(|m| m.vertex(c))])
        .flatten()
        .map(|c| (c.x, c.y, c.z))
        .collect();
    let mut faces = Vec::with_capacity(rectangles.len());
    for (ring, below, above) in rectangles {
        // Every corner of another rectangle on an edge becomes a corner of this one.
        let mut polygon = Vec::new();
        for k in 0..4 {
            let (from, to) = (ring[k], ring[(k + 1) % 4]);
            let step = (to - from).signum();
            let mut at = from;
            while at != to {
                if at == from || corners.contains(&(at.x, at.y, at.z)) {
                    polygon.push(at);
                }
                at += step;
            }
        }
        for piece in fan_safe_pieces(polygon) {
            // Outward for the part below (normal +axis); the part above gets it reversed.
            faces.push(GridFace {
                corners: piece,
                front: below,
                back: above,
            });
        }
    }
    if let Some(m) = mirror {
        // The images: corners mirrored, turned (keeping the first, so the fan from it is the
        // mirror image of the original's), each side's part its partner.
        let partner = partners(grid, m, parts);
        let image_of = |p: Option<u32>| p.map(|p| partner.get(p as usize).copied().unwrap_or(p));
        // A face on the plane itself (between a part and its image: a slab halved there
        // between two legs) is its own image.
        let images: Vec<GridFace> = faces
            .iter()
            .filter(|f| !f.corners.iter().all(|c| c[m.axis] == m.half))
            .map(|f| {
                let mut corners: Vec<IVec3> = f.corners.iter().map(|&c| m.vertex(c)).collect();
                corners[1..].reverse();
                GridFace {
                    corners,
                    front: image_of(f.front),
                    back: image_of(f.back),
                }
            })
            .collect();
        faces.extend(images);
    }
    faces
}

/// Splits a convex polygon whose corners may include points along its edges into polygons
/// that fan from their first corner without a degenerate triangle: the whole polygon when a
/// rotation of it fans cleanly, otherwise triangles clipped from corners that keep the rest
/// non-degenerate.
fn fan_safe_pieces(polygon: Vec<IVec3>) -> Vec<Vec<IVec3>> {
    let n = polygon.len();
    for start in 0..n {
        let rotated: Vec<IVec3> = (0..n).map(|k| polygon[(start + k) % n]).collect();
        if (1..n - 1).all(|k| !collinear(rotated[0], rotated[k], rotated[k + 1])) {
            return vec![rotated];
        }
    }
    let mut rest = polygon;
    let mut pieces = Vec::new();
    while rest.len() > 3 {
        let m = rest.len();
        let ear = (0..m).find(|&k| {
            let (prev, here, next) = (rest[(k + m - 1) % m], rest[k], rest[(k + 1) % m]);
            if collinear(prev, here, next) {
                return false;
            }
            // The rest must keep some area.
            let remaining: Vec<IVec3> = (0..m).filter(|&j| j != k).map(|j| rest[j]).collect();
            (1..remaining.len() - 1)
                .any(|j| !collinear(remaining[0], remaining[j], remaining[j + 1]))
                || remaining.len() == 3 && !collinear(remaining[0], remaining[1], remaining[2])
        });
        let Some(k) = ear else { break };
        let m = rest.len();
        pieces.push(vec![rest[(k + m - 1) % m], rest[k], rest[(k + 1) % m]]);
        rest.remove(k);
    }
    pieces.push(rest);
    pieces
}

fn collinear(a: IVec3, b: IVec3, c: IVec3) -> bool {
    (b - a).cross(c - a) == IVec3::ZERO
}

/// The faces over one numbered vertex list: (grid vertex of each vertex, per face its corners,
/// the part it bounds and the part behind it).
pub(super) type IndexedFaces = (Vec<IVec3>, Vec<(Vec<u32>, Option<u32>, Option<u32>)>);

/// Numbers the faces' corners (see [`IndexedFaces`]).
pub(super) fn indexed_faces(faces: &[GridFace]) -> IndexedFaces {
    let mut index: BTreeMap<(i32, i32, i32), u32> = BTreeMap::new();
    let mut vertices = Vec::new();
    let indexed = faces
        .iter()
        .map(|face| {
            let ids = face
                .corners
                .iter()
                .map(|c| {
                    *index.entry((c.x, c.y, c.z)).or_insert_with(|| {
                        vertices.push(*c);
                        vertices.len() as u32 - 1
                    })
                })
                .collect();
            (ids, face.front, face.back)
        })
        .collect();
    (vertices, indexed)
}

/// Each part's faces, outward, from faces that each bound `front` and (reversed) `back`; the
/// vertices renumbered to those used: (grid vertex of each vertex, per part its faces).
pub(super) fn part_faces(
    vertices: &[IVec3],
    faces: &[(Vec<u32>, Option<u32>, Option<u32>)],
    parts: usize,
) -> (Vec<IVec3>, Vec<Vec<Vec<u32>>>) {
    let mut renumber: BTreeMap<u32, u32> = BTreeMap::new();
    let mut used = Vec::new();
    let mut per_part: Vec<Vec<Vec<u32>>> = vec![Vec::new(); parts];
    for (corners, front, back) in faces {
        let ids: Vec<u32> = corners
            .iter()
            .map(|&c| {
                *renumber.entry(c).or_insert_with(|| {
                    used.push(vertices[c as usize]);
                    used.len() as u32 - 1
                })
            })
            .collect();
        if let Some(p) = front {
            per_part[*p as usize].push(ids.clone());
        }
        if let Some(p) = back {
            // Reversed, keeping the first corner (the fan's apex) first.
            let mut reversed = vec![ids[0]];
            reversed.extend(ids[1..].iter().rev());
            per_part[*p as usize].push(reversed);
        }
    }
    (used, per_part)
}
