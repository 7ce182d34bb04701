//! The 48 symmetries of a cube (turns by multiples of 90° and mirrors) as signed permutations
//! of the axes: the maps that take an axis-aligned box, and a grid centred on it, onto
//! themselves. Congruence classes of join cages and symmetric cages' harmonic solves use them.

use glam::{DVec3, UVec3};

/// A signed permutation of the axes: output axis `a` is input axis `perm[a]`, negated where
/// `negate[a]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CubeSymmetry {
    perm: [usize; 3],
    negate: [bool; 3],
}

impl CubeSymmetry {
    pub const IDENTITY: Self = Self {
        perm: [0, 1, 2],
        negate: [false; 3],
    };

    /// All 48, the identity first.
    pub fn all() -> impl Iterator<Item = Self> {
        const PERMS: [[usize; 3]; 6] = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        PERMS.into_iter().flat_map(|perm| {
            (0..8).map(move |bits| Self {
                perm,
                negate: [0, 1, 2].map(|a| bits >> a & 1 == 1),
            })
        })
    }

    /// `d` mapped.
    pub fn apply(&self, d: DVec3) -> DVec3 {
        let d = d.to_array();
        DVec3::from_array([0, 1, 2].map(|a| sign(self.negate[a]) * d[self.perm[a]]))
    }

    /// `d` mapped by the inverse.
    pub fn apply_inverse(&self, d: DVec3) -> DVec3 {
        let d = d.to_array();
        let mut out = [0.0; 3];
        for a in 0..3 {
            out[self.perm[a]] = sign(self.negate[a]) * d[a];
        }
        DVec3::from_array(out)
    }

    /// Whether a grid of `dims` maps onto itself (the axes it swaps have the same length).
    pub fn keeps_dims(&self, dims: UVec3) -> bool {
        (0..3).all(|a| dims[a] == dims[self.perm[a]])
    }

    /// Node `node` (linear index) of a grid of `dims`, mapped about the grid's centre (by the
    /// inverse where `inverse`); none when the map does not keep the grid.
    pub fn map_node(&self, dims: UVec3, node: usize, inverse: bool) -> Option<usize> {
        if !self.keeps_dims(dims) {
            return None;
        }
        let d = dims.to_array().map(i64::from);
        let n = i64::try_from(node).ok()?;
        let ijk = [n % d[0], (n / d[0]) % d[1], n / (d[0] * d[1])];
        // Doubled offsets from the centre, integers for odd and even sizes alike.
        let centred: [i64; 3] = [0, 1, 2].map(|a| 2 * ijk[a] - (d[a] - 1));
        let mut out = [0i64; 3];
        for a in 0..3 {
            let s = if self.negate[a] { -1 } else { 1 };
            if inverse {
                out[self.perm[a]] = s * centred[a];
            } else {
                out[a] = s * centred[self.perm[a]];
            }
        }
        let mut index = 0;
        for a in (0..3).rev() {
            let i = (out[a] + d[a] - 1) / 2;
            if !(0..d[a]).contains(&i) {
                return None;
            }
            index = index * d[a] + i;
        }
        usize::try_from(index).ok()
    }
}

fn sign(negate: bool) -> f64 {
    if negate { -1.0 } else { 1.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_maps_invert_each_other_and_match_the_point_map() {
        let dims = UVec3::new(5, 7, 5);
        let centre = (dims - UVec3::ONE).as_dvec3() * 0.5;
        for symmetry in CubeSymmetry::all() {
            for n in 0..(5 * 7 * 5) {
                let Some(m) = symmetry.map_node(dims, n, false) else {
                    assert!(!symmetry.keeps_dims(dims));
                    continue;
                };
                assert_eq!(symmetry.map_node(dims, m, true), Some(n));
                let at = |n: usize| {
                    let n = n as u32;
                    UVec3::new(n % 5, (n / 5) % 7, n / 35).as_dvec3() - centre
                };
                assert_eq!(symmetry.apply(at(n)), at(m));
                assert_eq!(symmetry.apply_inverse(at(m)), at(n));
            }
        }
        // The 8 mirrors, with and without the swap of the two axes of length 5.
        assert_eq!(
            CubeSymmetry::all().filter(|s| s.keeps_dims(dims)).count(),
            16
        );
    }
}
