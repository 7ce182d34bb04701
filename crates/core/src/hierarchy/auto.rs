//! The automatic internal cage: a box (8 vertices, or a finer box grid) around chosen
//! lower-level vertices, padded, added to the scene as their parent.

use std::collections::BTreeMap;

use glam::{DVec3, UVec3};
use thiserror::Error;

use crate::cage::bounds_of;
use crate::coords::CoordinateKind;
use crate::scene::{InternalCage, Scene};

/// Options of [`add_auto_internal_cage`].
#[derive(Debug, Clone, PartialEq)]
pub struct AutoInternalCage {
    /// Name of the new cage (unique among all cages).
    pub name: String,
    /// Its coordinates.
    pub kind: CoordinateKind,
    /// Margin around the vertices' bounding box, as a fraction of its largest side.
    pub padding: f64,
    /// Quads along x, y and z on each side of the box (1 1 1: the 8-vertex box).
    pub cells: [u32; 3],
}

impl Default for AutoInternalCage {
    fn default() -> Self {
        Self {
            name: "internal".into(),
            kind: CoordinateKind::MeanValue,
            padding: 0.1,
            cells: [1, 1, 1],
        }
    }
}

/// Why the automatic internal cage could not be added.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AutoInternalCageError {
    /// Nothing to own.
    #[error(
        "no vertices were chosen for internal cage '{name}'; choose the vertices it should own"
    )]
    NoVertices {
        /// The cage's name.
        name: String,
    },
    /// The name is taken.
    #[error("a cage named '{name}' already exists; pick another name")]
    NameTaken {
        /// The name.
        name: String,
    },
    /// A vertex index past the end.
    #[error("vertex {vertex} does not exist; the scene has {count} cage vertices")]
    NoSuchVertex {
        /// The vertex.
        vertex: u32,
        /// The count.
        count: usize,
    },
    /// An imported internal cage is not a closed, consistently oriented surface.
    #[error("the imported cage '{name}' cannot be an internal cage: {reason}")]
    InvalidCage {
        /// Its name.
        name: String,
        /// What is wrong with it.
        reason: String,
    },
    /// An imported internal cage encloses no cage vertex it could drive.
    #[error(
        "the imported cage '{name}' holds no cage vertex without a parent; place it around the \
         vertices it should drive"
    )]
    HoldsNothing {
        /// Its name.
        name: String,
    },
    /// A vertex already has a parent.
    #[error(
        "vertex {vertex} is already owned by internal cage '{parent}'; a vertex has at most one \
         parent: leave it out, or choose the vertices of '{parent}' instead"
    )]
    AlreadyOwned {
        /// The vertex.
        vertex: u32,
        /// Its parent.
        parent: String,
    },
}

/// Adds a box cage around the rest positions of `vertices`, owning them, and returns its
/// index among the scene's internal cages. Its vertices are appended to the cage vertex array
/// (at rest in every pose). Where a pose already moved an owned vertex away from rest, that
/// vertex counts as moved by hand in that pose, so the new parent carries the edit along.
pub fn add_auto_internal_cage(
    scene: &mut Scene,
    options: &AutoInternalCage,
    vertices: &[u32],
) -> Result<usize, AutoInternalCageError> {
    let set = &scene.cages;
    let mut owned: Vec<u32> = vertices.to_vec();
    owned.sort_unstable();
    owned.dedup();
    if owned.is_empty() {
        return Err(AutoInternalCageError::NoVertices {
            name: options.name.clone(),
        });
    }
    if set.cage_names().contains(&options.name.as_str()) {
        return Err(AutoInternalCageError::NameTaken {
            name: options.name.clone(),
        });
    }
    let count = set.vertices.len();
    for &v in &owned {
        if v as usize >= count {
            return Err(AutoInternalCageError::NoSuchVertex { vertex: v, count });
        }
        if let Some(parent) = set.internals.iter().find(|c| c.owns.contains(&v)) {
            return Err(AutoInternalCageError::AlreadyOwned {
                vertex: v,
                parent: parent.name.clone(),
            });
        }
    }
    let points: Vec<DVec3> = owned.iter().map(|&v| set.vertices[v as usize]).collect();
    let (lo, hi) = bounds_of(&points);
    let (all_lo, all_hi) = bounds_of(&set.vertices);
    let side = (hi - lo).max_element();
    let margin = (options.padding.max(0.0) * side).max(1e-3 * (all_hi - all_lo).length());
    let (positions, faces) = box_grid(
        lo - DVec3::splat(margin),
        hi + DVec3::splat(margin),
        options.cells,
    );
    Ok(attach_internal_cage(
        scene,
        &options.name,
        options.kind,
        &positions,
        faces,
        owned,
    ))
}

/// Appends an internal cage (its own new vertices `positions`, `faces` over them, at rest in
/// every pose) owning `owned`; returns its index among the internal cages. Where a pose already
/// moved an owned vertex away from rest, that vertex counts as moved by hand in that pose.
pub(super) fn attach_internal_cage(
    scene: &mut Scene,
    name: &str,
    kind: CoordinateKind,
    positions: &[DVec3],
    faces: Vec<Vec<u32>>,
    owned: Vec<u32>,
) -> usize {
    let base = scene.cages.vertices.len() as u32;
    scene.cages.vertices.extend(positions);
    scene.pose.extend(positions);
    for pose in scene.poses.values_mut() {
        pose.extend(positions);
    }
    scene.cages.internals.push(InternalCage {
        name: name.to_owned(),
        kind,
        faces: faces
            .into_iter()
            .map(|f| f.into_iter().map(|v| v + base).collect())
            .collect(),
        owns: owned.clone(),
        pivot: None,
        joint: Vec::new(),
    });
    let rest = &scene.cages.vertices;
    let moved = |pose: &[DVec3]| -> Vec<u32> {
        owned
            .iter()
            .copied()
            .filter(|&v| pose[v as usize] != rest[v as usize])
            .collect()
    };
    let current = moved(&scene.pose);
    mark_hand_moved(&mut scene.pose_state.hand_moved, current);
    for (name, pose) in &scene.poses {
        let moved = moved(pose);
        if !moved.is_empty() {
            let state = scene.pose_states.entry(name.clone()).or_default();
            mark_hand_moved(&mut state.hand_moved, moved);
        }
    }
    scene.cages.internals.len() - 1
}

fn mark_hand_moved(list: &mut Vec<u32>, more: Vec<u32>) {
    list.extend(more);
    list.sort_unstable();
    list.dedup();
}

/// The surface of a box from `min` to `max` with `cells` quads along each axis, welded, quads
/// counter-clockwise seen from outside.
pub fn box_grid(min: DVec3, max: DVec3, cells: [u32; 3]) -> (Vec<DVec3>, Vec<Vec<u32>>) {
    let n = UVec3::from_array(cells).max(UVec3::ONE);
    let mut index: BTreeMap<[u32; 3], u32> = BTreeMap::new();
    let mut positions = Vec::new();
    let mut vertex = |i: [u32; 3]| -> u32 {
        *index.entry(i).or_insert_with(|| {
            let t = UVec3::from_array(i).as_dvec3() / n.as_dvec3();
            positions.push(min + (max - min) * t);
            positions.len() as u32 - 1
        })
    };
    let mut faces = Vec::new();
    for axis in 0..3 {
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, n[axis]] {
            for j in 0..n[b] {
                for i in 0..n[a] {
                    let corner = |di: u32, dj: u32| {
                        let mut c = [0; 3];
                        c[axis] = side;
                        c[a] = i + di;
                        c[b] = j + dj;
                        c
                    };
                    // (a, b, axis) is right-handed: counter-clockwise in (a, b) faces +axis.
                    let mut quad = vec![
                        vertex(corner(0, 0)),
                        vertex(corner(1, 0)),
                        vertex(corner(1, 1)),
                        vertex(corner(0, 1)),
                    ];
                    if side == 0 {
                        quad.reverse();
                    }
                    faces.push(quad);
                }
            }
        }
    }
    (positions, faces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::Cage;

    #[test]
    fn box_grids_are_valid_cages() {
        for cells in [[1, 1, 1], [2, 3, 1], [3, 3, 3]] {
            let (positions, faces) = box_grid(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0), cells);
            let cage = Cage::from_polygons(positions, faces).unwrap();
            assert!((cage.volume() - 6.0).abs() < 1e-12);
            let [x, y, z] = cells.map(|c| c as usize);
            let expected = (x + 1) * (y + 1) * (z + 1) - (x - 1) * (y - 1) * (z - 1);
            assert_eq!(cage.vertex_count(), expected, "{cells:?}");
        }
    }
}
