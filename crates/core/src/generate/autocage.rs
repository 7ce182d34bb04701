//! Automatic grid cages: a grid of box cages around a mesh, cells outside it dropped,
//! neighbouring cells sharing their faces exactly (same vertices, opposite orientation).

use std::collections::BTreeMap;

use glam::{DVec3, UVec3};
use rayon::prelude::*;

use crate::cage::shapes::box_faces;
use crate::coords::CoordinateKind;
use crate::geometry::{block_face_connected, winding_number};
use crate::mesh::Mesh;
use crate::scene::{CageSet, LeafCage};

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
            grid: DEFAULT_GRID,
            padding: 0.05,
            kind: CoordinateKind::MeanValue,
        }
    }
}

/// The automatic grid's cells along x, y and z wherever none is given (the command line, New
/// from mesh, `autocage`, `bench`).
pub const DEFAULT_GRID: [u32; 3] = [3, 3, 3];

/// A grid of box cages around the mesh: a cell is kept when it holds a mesh vertex or when its
/// centre lies inside the mesh's volume (generalised winding number above ½), so the union of
/// the cells has no cavities where the mesh is thick; the other cells are dropped.
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
    fill_inside(&mut occupied, grid, mesh, |c| {
        lo + (c.as_dvec3() + 0.5) * cell
    });
    make_manifold(&mut occupied, grid);
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

/// Marks the empty cells whose centre (`centre` of a cell index) lies inside the mesh.
/// Without these, the cells inside a thick mesh hold no vertex and leave a cavity, and every
/// join cage around it is concave (and so harmonic under the automatic policy).
fn fill_inside(
    occupied: &mut [bool],
    grid: UVec3,
    mesh: &Mesh,
    centre: impl Fn(UVec3) -> DVec3 + Sync,
) {
    let positions = mesh.welded_positions();
    let triangles = mesh.welded_triangles();
    let inside: Vec<usize> = (0..occupied.len())
        .into_par_iter()
        .filter(|&index| !occupied[index])
        .filter(|&index| {
            let i = index as u32;
            let c = UVec3::new(i % grid.x, (i / grid.x) % grid.y, i / (grid.x * grid.y));
            winding_number(positions, triangles, centre(c)) > 0.5
        })
        .collect();
    for index in inside {
        occupied[index] = true;
    }
}

/// Adds cells until the union of the occupied cells is a manifold: around every grid vertex,
/// the occupied cells of its 2×2×2 block and the empty ones must each be face-connected
/// (otherwise cells meet only along an edge or at a vertex, and the *Cages join cage there is
/// not a valid cage). Offending blocks are filled whole; cells are only ever added, so this
/// terminates.
fn make_manifold(occupied: &mut [bool], grid: UVec3) {
    let cell = |i: i64, j: i64, k: i64| -> Option<usize> {
        let g = grid.as_i64vec3();
        (i >= 0 && j >= 0 && k >= 0 && i < g.x && j < g.y && k < g.z)
            .then(|| (i + g.x * (j + g.y * k)) as usize)
    };
    loop {
        let mut changed = false;
        for k in 0..=i64::from(grid.z) {
            for j in 0..=i64::from(grid.y) {
                for i in 0..=i64::from(grid.x) {
                    // The 8 cells around grid vertex (i, j, k); bit c = (dx, dy, dz).
                    let cells: [Option<usize>; 8] = std::array::from_fn(|c| {
                        cell(
                            i - 1 + (c as i64 & 1),
                            j - 1 + ((c as i64 >> 1) & 1),
                            k - 1 + (c as i64 >> 2),
                        )
                    });
                    let mask: u8 = (0..8)
                        .filter(|&c| cells[c].is_some_and(|x| occupied[x]))
                        .fold(0, |m, c| m | 1 << c);
                    if block_face_connected(mask) && block_face_connected(!mask) {
                        continue;
                    }
                    for x in cells.into_iter().flatten() {
                        changed |= !occupied[x];
                        occupied[x] = true;
                    }
                }
            }
        }
        if !changed {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::validate_scene;
    use crate::scene::{JoinPolicy, MeshSource, Scene, SceneSettings};
    use crate::star::Topology;

    #[test]
    fn cells_inside_a_thick_mesh_are_kept() {
        // A closed box mesh 3 cells wide on a 3x3x3 grid: vertices lie only on its surface
        // (in the outer ring of cells), yet the centre cell is inside and must stay.
        let mesh =
            crate::generate::demo::box_mesh(DVec3::splat(-1.5), DVec3::splat(1.5), [1, 1, 1]);
        let options = AutocageOptions {
            grid: [3, 3, 3],
            padding: 0.0,
            ..Default::default()
        };
        let set = autocage(&mesh, &options);
        assert_eq!(set.leaves.len(), 27, "no cavity at the centre");
        assert!(set.leaves.iter().any(|c| c.name == "cell_1_1_1"));
        // The winding number itself: 1 inside, 0 outside.
        let (p, t) = (mesh.welded_positions(), mesh.welded_triangles());
        assert!((winding_number(p, t, DVec3::ZERO) - 1.0).abs() < 1e-9);
        assert!(winding_number(p, t, DVec3::splat(3.0)).abs() < 1e-9);
    }

    #[test]
    fn face_connectivity_of_blocks() {
        assert!(block_face_connected(0));
        assert!(block_face_connected(0b0000_0011));
        assert!(!block_face_connected(0b0000_1001)); // cells 0 and 3 share an edge only
        assert!(!block_face_connected(0b1000_0001)); // cells 0 and 7 share a vertex only
    }

    #[test]
    fn diagonal_cells_get_filled_so_join_cages_are_valid() {
        // Mesh vertices only near two diagonally opposite cells of a 2x2x1 grid.
        let positions = vec![
            DVec3::new(0.1, 0.1, 0.1),
            DVec3::new(0.2, 0.1, 0.1),
            DVec3::new(0.1, 0.2, 0.1),
            DVec3::new(1.9, 1.9, 0.9),
            DVec3::new(1.8, 1.9, 0.9),
            DVec3::new(1.9, 1.8, 0.9),
        ];
        let mesh = Mesh::new(positions, vec![[0, 1, 2], [3, 4, 5]], None, None).unwrap();
        let set = autocage(
            &mesh,
            &AutocageOptions {
                grid: [2, 2, 1],
                padding: 0.0,
                ..Default::default()
            },
        );
        assert_eq!(set.leaves.len(), 4, "the diagonal pair was completed");
        assert!(Topology::new(&set, JoinPolicy::Auto).is_ok());
        let scene = Scene::new(MeshSource::Embedded, mesh, set, SceneSettings::default());
        assert!(validate_scene(&scene).is_valid());
    }
}
