//! Automatic grid cages: a grid of box cages around a mesh, empty cells dropped, neighbouring
//! cells sharing their faces exactly (same vertices, opposite orientation).

use std::collections::BTreeMap;

use glam::{DVec3, UVec3};

use super::{CageSet, LeafCage};
use crate::cage::shapes::box_faces;
use crate::coords::CoordinateKind;
use crate::mesh::Mesh;

/// Options of [`autocage`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AutocageOptions {
    /// Cells along x, y and z (each at least 1).
    pub grid: [u32; 3],
    /// Margin around the mesh's bounding box, as a fraction of its largest side.
    pub padding: f64,
    /// Coordinate kind of every cage.
    pub kind: CoordinateKind,
}

impl Default for AutocageOptions {
    fn default() -> Self {
        Self {
            grid: [2, 2, 2],
            padding: 0.05,
            kind: CoordinateKind::MeanValue,
        }
    }
}

/// A grid of box cages around the mesh's vertices; cells holding no mesh vertex are dropped.
pub fn autocage(mesh: &Mesh, options: &AutocageOptions) -> CageSet {
    let grid = UVec3::from_array(options.grid).max(UVec3::ONE);
    let (lo, hi) = mesh.bounds();
    let margin = (hi - lo).max_element().max(f64::MIN_POSITIVE) * options.padding.max(1e-6);
    let (lo, hi) = (lo - DVec3::splat(margin), hi + DVec3::splat(margin));
    let cell = (hi - lo) / grid.as_dvec3();
    let node = |i: UVec3| {
        // Exactly lo and hi on the outer nodes; every shared node computed the same way.
        let t = i.as_dvec3() / grid.as_dvec3();
        lo + (hi - lo) * t
    };
    let mut occupied = vec![false; (grid.x * grid.y * grid.z) as usize];
    for p in mesh.welded_positions() {
        let c = ((*p - lo) / cell).floor().as_uvec3().min(grid - UVec3::ONE);
        occupied[(c.x + grid.x * (c.y + grid.y * c.z)) as usize] = true;
    }
    let mut index: BTreeMap<(u32, u32, u32), u32> = BTreeMap::new();
    let mut set = CageSet::default();
    for k in 0..grid.z {
        for j in 0..grid.y {
            for i in 0..grid.x {
                if !occupied[(i + grid.x * (j + grid.y * k)) as usize] {
                    continue;
                }
                let corners: [u32; 8] = std::array::from_fn(|c| {
                    let c = c as u32;
                    {
                        let at = UVec3::new(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
                        *index.entry((at.z, at.y, at.x)).or_insert_with(|| {
                            set.vertices.push(node(at));
                            set.vertices.len() as u32 - 1
                        })
                    }
                });
                set.leaves.push(LeafCage {
                    name: format!("cell_{i}_{j}_{k}"),
                    kind: options.kind,
                    h: None,
                    border_h: BTreeMap::new(),
                    faces: box_faces(corners),
                });
            }
        }
    }
    set
}
