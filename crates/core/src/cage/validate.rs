//! Validation of a polygon soup as a cage: every problem, in a stable order.

use std::collections::BTreeMap;

use glam::DVec3;

use super::{CageError, MAX_COORDINATE, bounds_of, crossing, signed_volume};
use crate::geometry::triangle_area_vector;

/// Relative tolerance (to the bounding-box diagonal) under which two vertices coincide.
const DUPLICATE_TOLERANCE: f64 = 1e-12;
/// Relative tolerance (to the squared diagonal) under which a triangle is degenerate.
const DEGENERATE_AREA_TOLERANCE: f64 = 1e-14;

/// Every problem of `faces` over `positions` as a cage; empty when it is a valid cage.
/// Structural problems (counts, indices, NaN) stop the check early, since later checks need
/// them resolved.
pub(super) fn check(positions: &[DVec3], faces: &[Vec<u32>]) -> Vec<CageError> {
    let mut problems = Vec::new();
    if positions.len() < 4 {
        problems.push(CageError::TooFewVertices {
            count: positions.len(),
        });
    }
    for (i, p) in positions.iter().enumerate() {
        if !p.is_finite() {
            problems.push(CageError::NonFiniteVertex {
                vertex: i,
                x: p.x,
                y: p.y,
                z: p.z,
            });
        } else if p.abs().max_element() > MAX_COORDINATE {
            // Checked before any size-relative tolerance: such a coordinate makes the
            // diagonal huge and every other test meaningless.
            problems.push(CageError::CoordinateTooLarge {
                vertex: i,
                value: p.abs().max_element(),
            });
        }
    }
    for (f, face) in faces.iter().enumerate() {
        if face.len() < 3 {
            problems.push(CageError::TooFewCorners {
                face: f,
                corners: face.len(),
            });
        }
        for &v in face {
            if v as usize >= positions.len() {
                problems.push(CageError::VertexOutOfRange {
                    face: f,
                    vertex: v as usize,
                    count: positions.len(),
                });
            }
        }
        let mut sorted = face.clone();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            problems.push(CageError::RepeatedCorner {
                face: f,
                vertex: w[0] as usize,
            });
        }
    }
    if !problems.is_empty() {
        return problems;
    }
    // Coincident vertices first: they also open edges, and "weld" is the fix for both.
    check_duplicates(positions, &mut problems);
    check_topology(positions.len(), faces, &mut problems);
    check_degenerate_faces(positions, faces, &mut problems);
    if problems.is_empty() {
        let triangles = fan(faces);
        // A cage through itself has a meaningless signed volume: report the crossing, not
        // an orientation to flip.
        if let Some(crossing) = crossing::self_crossing(positions, &triangles) {
            problems.push(CageError::SelfIntersecting {
                a: crossing.edge[0] as usize,
                b: crossing.edge[1] as usize,
                face: fan_polygon(faces, crossing.triangle),
            });
            return problems;
        }
        let volume = signed_volume(positions, &triangles);
        if volume <= 0.0 {
            problems.push(CageError::InwardOrientation { volume });
        }
    }
    problems
}

/// The polygon whose fan holds triangle `triangle` of [`fan`]`(faces)`.
fn fan_polygon(faces: &[Vec<u32>], triangle: usize) -> usize {
    let mut first = 0;
    for (f, face) in faces.iter().enumerate() {
        first += face.len() - 2;
        if triangle < first {
            return f;
        }
    }
    faces.len().saturating_sub(1)
}

fn fan(faces: &[Vec<u32>]) -> Vec<[u32; 3]> {
    faces
        .iter()
        .flat_map(|f| (1..f.len() - 1).map(move |k| [f[0], f[k], f[k + 1]]))
        .collect()
}

fn check_topology(vertex_count: usize, faces: &[Vec<u32>], problems: &mut Vec<CageError>) {
    let mut used = vec![false; vertex_count];
    // Directed edge -> faces running it in that direction.
    let mut directed: BTreeMap<(u32, u32), Vec<usize>> = BTreeMap::new();
    for (f, face) in faces.iter().enumerate() {
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            used[a as usize] = true;
            directed.entry((a, b)).or_default().push(f);
        }
    }
    for (&(a, b), fwd) in &directed {
        if a > b && directed.contains_key(&(b, a)) {
            continue; // reported from the (b, a) side
        }
        let back = directed.get(&(b, a)).map_or(0, Vec::len);
        let total = fwd.len() + back;
        let (lo, hi) = (a.min(b) as usize, a.max(b) as usize);
        if total == 1 {
            problems.push(CageError::OpenEdge {
                a: a as usize,
                b: b as usize,
                face: fwd[0],
            });
        } else if total > 2 {
            problems.push(CageError::NonManifoldEdge {
                a: lo,
                b: hi,
                faces: total,
            });
        } else if fwd.len() == 2 {
            problems.push(CageError::InconsistentOrientation {
                first: fwd[0],
                second: fwd[1],
                a: a as usize,
                b: b as usize,
            });
        }
    }
    for (v, _) in used.iter().enumerate().filter(|(_, u)| !**u) {
        problems.push(CageError::UnusedVertex { vertex: v });
    }
}

fn check_degenerate_faces(positions: &[DVec3], faces: &[Vec<u32>], problems: &mut Vec<CageError>) {
    let (lo, hi) = bounds_of(positions);
    let diagonal = (hi - lo).length();
    let area_tolerance = DEGENERATE_AREA_TOLERANCE * diagonal * diagonal;
    for (f, face) in faces.iter().enumerate() {
        let p = |k: usize| positions[face[k] as usize];
        let smallest = (1..face.len() - 1)
            .map(|k| 0.5 * triangle_area_vector(p(0), p(k), p(k + 1)).length())
            .fold(f64::INFINITY, f64::min);
        if smallest <= area_tolerance {
            problems.push(CageError::DegenerateFace {
                face: f,
                area: smallest,
            });
        }
    }
}

/// Each vertex that coincides with an earlier one is named once, with the first vertex of its
/// cluster: linear in the vertices however many share a position (listing every coincident
/// pair was quadratic: 30,000 copies of one point aborted the process).
fn check_duplicates(positions: &[DVec3], problems: &mut Vec<CageError>) {
    let (lo, hi) = bounds_of(positions);
    let diagonal = (hi - lo).length();
    // Sort by x, compare within the tolerance window.
    let tolerance = DUPLICATE_TOLERANCE * diagonal.max(f64::MIN_POSITIVE);
    let mut order: Vec<usize> = (0..positions.len()).collect();
    order.sort_by(|&i, &j| positions[i].x.total_cmp(&positions[j].x).then(i.cmp(&j)));
    // The first vertex (lowest index) each vertex was found to coincide with.
    let mut first_of: Vec<Option<usize>> = vec![None; positions.len()];
    for (k, &i) in order.iter().enumerate() {
        if first_of[i].is_some() {
            continue; // already named with its cluster's first vertex
        }
        let mut cluster = vec![i];
        for &j in &order[k + 1..] {
            if positions[j].x - positions[i].x > tolerance {
                break;
            }
            if first_of[j].is_none() && positions[i].distance(positions[j]) <= tolerance {
                cluster.push(j);
            }
        }
        if let Some(&first) = cluster.iter().min() {
            for &j in cluster.iter().filter(|&&j| j != first) {
                first_of[j] = Some(first);
            }
        }
    }
    for (second, first) in first_of.iter().enumerate() {
        if let Some(first) = *first {
            problems.push(CageError::DuplicateVertex { first, second });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::{Cage, shapes};

    fn cube_soup() -> (Vec<DVec3>, Vec<Vec<u32>>) {
        let c = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
        let faces = c.polygons().iter().map(|p| p.vertices.clone()).collect();
        (c.positions().to_vec(), faces)
    }

    /// Many copies of one position are named once each, with the first copy, in linear time
    /// and memory (every pair was listed before: quadratic).
    #[test]
    fn many_coincident_vertices_are_named_once_each() {
        let (mut p, f) = cube_soup();
        let copies = 30_000;
        p.extend(std::iter::repeat_n(p[0], copies));
        let problems = check(&p, &f);
        let duplicates: Vec<_> = problems
            .iter()
            .filter_map(|e| match e {
                CageError::DuplicateVertex { first, second } => Some((*first, *second)),
                _ => None,
            })
            .collect();
        assert_eq!(duplicates.len(), copies);
        assert!(
            duplicates
                .iter()
                .all(|&(first, second)| first == 0 && second >= 8)
        );
    }

    #[test]
    fn valid_cube_has_no_problem() {
        let (p, f) = cube_soup();
        assert!(check(&p, &f).is_empty());
    }

    #[test]
    fn each_problem_is_named() {
        let (p, mut f) = cube_soup();
        f.pop();
        let e = Cage::from_polygons(p.clone(), f).unwrap_err();
        assert!(matches!(e, CageError::OpenEdge { .. }), "{e}");
        assert!(e.to_string().contains("not closed"));

        let (p2, mut f2) = cube_soup();
        f2[0].reverse();
        let e = Cage::from_polygons(p2, f2).unwrap_err();
        assert!(
            matches!(e, CageError::InconsistentOrientation { .. }),
            "{e}"
        );
        assert!(e.to_string().contains("flip face"));

        let (p3, f3) = cube_soup();
        let e = Cage::from_polygons(p3, Cage::flipped_faces(&f3)).unwrap_err();
        assert!(matches!(e, CageError::InwardOrientation { .. }), "{e}");

        let (mut p4, f4) = cube_soup();
        p4[3].y = f64::NAN;
        let e = Cage::from_polygons(p4, f4).unwrap_err();
        assert_eq!(e.to_string().split(' ').nth(1), Some("3"));

        let (mut p5, f5) = cube_soup();
        p5.push(p5[2]);
        let probs = check(&p5, &f5);
        assert!(probs.contains(&CageError::UnusedVertex { vertex: 8 }));
        assert!(probs.contains(&CageError::DuplicateVertex {
            first: 2,
            second: 8
        }));

        let (p6, mut f6) = cube_soup();
        f6.push(vec![0, 1, 2]);
        assert!(
            check(&p6, &f6)
                .iter()
                .any(|e| matches!(e, CageError::NonManifoldEdge { .. }))
        );

        let (mut p7, f7) = cube_soup();
        p7[7] = p7[3]; // collapse the top-right edge: degenerate faces and a duplicate
        assert!(
            check(&p7, &f7)
                .iter()
                .any(|e| matches!(e, CageError::DegenerateFace { .. }))
        );

        assert!(matches!(
            Cage::from_polygons(p.clone()[..3].to_vec(), vec![vec![0, 1, 2], vec![0, 2, 1]]),
            Err(CageError::TooFewVertices { count: 3 })
        ));
        assert!(matches!(
            Cage::from_polygons(p.clone(), vec![vec![0, 1, 99]]),
            Err(CageError::VertexOutOfRange { vertex: 99, .. })
        ));
        assert!(matches!(
            Cage::from_polygons(p, vec![vec![0, 1, 1]]),
            Err(CageError::RepeatedCorner { vertex: 1, .. })
        ));
    }
}
