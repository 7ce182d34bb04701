//! Congruence classes of join cages: two join cages whose triangulated surfaces are the same
//! up to a translation and one of the 48 symmetries of the cube (turns by multiples of 90°
//! and mirrors, as a box grid has) have the same harmonic coordinates, mapped through the
//! symmetry, so one solve serves the whole class. Harmonic coordinates depend only on the
//! triangles (the hat functions) and the domain, not on their orientation, and the solver's
//! grid is centred on the cage's box, so it maps onto itself as well.

use glam::DVec3;

use crate::cage::Cage;
use crate::cage::cube_symmetry::CubeSymmetry;

/// A class's key: the vertices' quantised positions in the canonical frame, in canonical
/// order, and the triangles over that order (corners sorted, triangles sorted).
pub(super) type ShapeKey = (Vec<[i64; 3]>, Vec<[u32; 3]>);

/// How one join cage sits in its class's canonical frame.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Placement {
    /// Canonical rank of each local vertex.
    pub rank: Vec<usize>,
    centre: DVec3,
    symmetry: CubeSymmetry,
}

impl Placement {
    /// `p` (this join cage's frame) in the canonical frame.
    pub fn canonical_from_join(&self, p: DVec3) -> DVec3 {
        self.symmetry.apply(p - self.centre)
    }

    /// `q` (canonical frame) in this join cage's frame.
    pub fn join_from_canonical(&self, q: DVec3) -> DVec3 {
        self.centre + self.symmetry.apply_inverse(q)
    }
}

/// The class of `cage` (its key, smallest over the 48 symmetries) and how it sits in it.
pub(super) fn shape_class(cage: &Cage) -> (ShapeKey, Placement) {
    let positions = cage.positions();
    let (lo, hi) = cage.bounds();
    let centre = 0.5 * (lo + hi);
    let quantum = 1e-9 * cage.diagonal().max(f64::MIN_POSITIVE);
    let mut best: Option<(ShapeKey, Placement)> = None;
    for symmetry in CubeSymmetry::all() {
        let quantised: Vec<[i64; 3]> = positions
            .iter()
            .map(|&p| {
                let q = symmetry.apply(p - centre) / quantum;
                [q.x.round() as i64, q.y.round() as i64, q.z.round() as i64]
            })
            .collect();
        let mut order: Vec<usize> = (0..positions.len()).collect();
        order.sort_by_key(|&k| quantised[k]);
        let mut rank = vec![0usize; order.len()];
        for (r, &k) in order.iter().enumerate() {
            rank[k] = r;
        }
        let mut triangles: Vec<[u32; 3]> = cage
            .triangles()
            .iter()
            .map(|t| {
                let mut corners = t.map(|v| rank[v as usize] as u32);
                corners.sort_unstable();
                corners
            })
            .collect();
        triangles.sort_unstable();
        let key = (order.iter().map(|&k| quantised[k]).collect(), triangles);
        if best.as_ref().is_none_or(|(b, _)| key < *b) {
            best = Some((
                key,
                Placement {
                    rank,
                    centre,
                    symmetry,
                },
            ));
        }
    }
    // `all` is never empty.
    best.unwrap_or_else(|| ((Vec::new(), Vec::new()), Placement::identity(centre)))
}

impl Placement {
    /// Whether `other` sits in the class turned or mirrored relative to this one (not just
    /// moved).
    #[cfg(test)]
    pub fn turned_or_mirrored_from(&self, other: &Self) -> bool {
        self.symmetry != other.symmetry
    }

    fn identity(centre: DVec3) -> Self {
        Self {
            rank: Vec::new(),
            centre,
            symmetry: CubeSymmetry::IDENTITY,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::shapes;

    /// `cage` with its vertices moved by `map` and the same polygons (flipped for a mirror, so
    /// it stays outward), as a join cage built from mapped cells would be.
    fn mapped(cage: &Cage, map: impl Fn(DVec3) -> DVec3, mirror: bool) -> Cage {
        let positions = cage.positions().iter().map(|&p| map(p)).collect();
        let faces: Vec<Vec<u32>> = cage.polygons().iter().map(|f| f.vertices.clone()).collect();
        let faces = if mirror {
            Cage::flipped_faces(&faces)
        } else {
            faces
        };
        Cage::from_polygons(positions, faces).unwrap()
    }

    #[test]
    fn turned_mirrored_and_moved_copies_share_a_class_and_map_points_back() {
        let base = shapes::l_prism();
        let (key, placement) = shape_class(&base);
        let p = DVec3::new(0.3, 1.2, 0.5);
        let shift = DVec3::new(5.0, -1.0, 2.0);
        type Map = Box<dyn Fn(DVec3) -> DVec3>;
        let copies: [(Map, bool); 3] = [
            // Turned 90° about z and moved.
            (
                Box::new(move |q: DVec3| DVec3::new(-q.y, q.x, q.z) + shift),
                false,
            ),
            // Mirrored across x and moved.
            (
                Box::new(move |q: DVec3| DVec3::new(-q.x, q.y, q.z) + shift),
                true,
            ),
            // Stood up: z and y swapped (a mirror), then moved.
            (
                Box::new(move |q: DVec3| DVec3::new(q.x, q.z, q.y) + shift),
                true,
            ),
        ];
        for (map, mirror) in copies {
            let copy = mapped(&base, &map, mirror);
            let (copy_key, copy_placement) = shape_class(&copy);
            assert_eq!(key, copy_key);
            // The copy maps onto the base vertex for vertex (by canonical rank), so the
            // affine map between the frames carries the copy's points to the base's.
            let to_base =
                |q: DVec3| placement.join_from_canonical(copy_placement.canonical_from_join(q));
            for (k, &r) in copy_placement.rank.iter().enumerate() {
                let partner = placement.rank.iter().position(|&s| s == r).unwrap();
                let there = to_base(copy.positions()[k]);
                assert!(there.distance(base.positions()[partner]) < 1e-12, "{there}");
            }
            let q = to_base(map(p));
            assert!(base.winding_number(q) > 0.5, "{q} is inside");
            assert!(
                copy_placement
                    .join_from_canonical(copy_placement.canonical_from_join(p))
                    .distance(p)
                    < 1e-12
            );
        }
        // Negative control: a stretched copy is another class.
        let stretched = mapped(&base, |q| DVec3::new(q.x, q.y, 1.1 * q.z), false);
        assert_ne!(shape_class(&stretched).0, key);
    }
}
