//! Internal cages read from a file: each imported cage becomes the parent of the cage vertices
//! inside it that have no parent yet (so a modelled cage around the ears drives the ear cages).

use std::collections::BTreeSet;

use super::auto::{AutoInternalCageError, attach_internal_cage};
use crate::cage::Cage;
use crate::coords::CoordinateKind;
use crate::scene::{CageSet, Scene};

/// Adds the leaf cages of `imported` (positions in scene coordinates) as internal cages of
/// `kind`, each owning the cage vertices strictly inside it (generalised winding number above
/// ½, at rest) that no internal cage owns yet; names already taken get a number. Whole or not
/// at all: the scene is unchanged on an error. Returns the new cages' indices among the
/// internal cages.
pub fn import_internal_cages(
    scene: &mut Scene,
    imported: &CageSet,
    kind: CoordinateKind,
) -> Result<Vec<usize>, AutoInternalCageError> {
    let mut edited = scene.clone();
    let mut added = Vec::new();
    for cage in &imported.leaves {
        // The cage's own vertices, renumbered from 0.
        let used: BTreeSet<u32> = cage.faces.iter().flatten().copied().collect();
        let used: Vec<u32> = used.into_iter().collect();
        let local = |v: u32| used.binary_search(&v).map(|i| i as u32).unwrap_or(0);
        let positions: Vec<_> = used
            .iter()
            .filter_map(|&v| imported.vertices.get(v as usize).copied())
            .collect();
        let faces: Vec<Vec<u32>> = cage
            .faces
            .iter()
            .map(|f| f.iter().map(|&v| local(v)).collect())
            .collect();
        let shape = Cage::from_polygons(positions.clone(), faces.clone()).map_err(|e| {
            AutoInternalCageError::InvalidCage {
                name: cage.name.clone(),
                reason: e.to_string(),
            }
        })?;
        let set = &edited.cages;
        let parented: BTreeSet<u32> = set.internals.iter().flat_map(|c| c.owns.clone()).collect();
        let owned: Vec<u32> = (0..set.vertices.len() as u32)
            .filter(|v| !parented.contains(v))
            .filter(|&v| shape.winding_number(set.vertices[v as usize]) > 0.5)
            .collect();
        if owned.is_empty() {
            return Err(AutoInternalCageError::HoldsNothing {
                name: cage.name.clone(),
            });
        }
        let taken = set.cage_names();
        let name = (1..)
            .map(|k| match k {
                1 => cage.name.clone(),
                k => format!("{}_{k}", cage.name),
            })
            .find(|n| !taken.contains(&n.as_str()))
            .unwrap_or_default();
        added.push(attach_internal_cage(
            &mut edited,
            &name,
            kind,
            &positions,
            faces,
            owned,
        ));
    }
    *scene = edited;
    Ok(added)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::cage::shapes;
    use crate::generate::demo::demo_scene;

    /// A cage set holding one box from `lo` to `hi` called `name`.
    fn box_set(name: &str, lo: DVec3, hi: DVec3) -> CageSet {
        let cuboid = shapes::cuboid(lo, hi);
        let mut set = CageSet {
            vertices: cuboid.positions().to_vec(),
            ..Default::default()
        };
        set.leaves.push(crate::scene::LeafCage {
            name: name.into(),
            kind: CoordinateKind::MeanValue,
            h: None,
            border_h: Default::default(),
            faces: cuboid
                .polygons()
                .iter()
                .map(|p| p.vertices.clone())
                .collect(),
        });
        set
    }

    #[test]
    fn an_imported_box_owns_the_free_vertices_inside_it_and_the_hierarchy_binds() {
        let mut scene = demo_scene("bar", 0.3).unwrap();
        let right = scene.cages.leaf_index("cage_1_0_0").unwrap();
        let corners: Vec<DVec3> = scene.cages.leaves[right]
            .faces
            .iter()
            .flatten()
            .map(|&v| scene.cages.vertices[v as usize])
            .collect();
        let (lo, hi) = crate::cage::bounds_of(&corners);
        let pad = DVec3::splat(0.1);
        let before = scene.cages.vertices.len();
        let added = import_internal_cages(
            &mut scene,
            &box_set("right_driver", lo - pad, hi + pad),
            CoordinateKind::Harmonic,
        )
        .unwrap();
        assert_eq!(added, vec![0]);
        let internal = &scene.cages.internals[0];
        assert_eq!(internal.name, "right_driver");
        assert_eq!(internal.kind, CoordinateKind::Harmonic);
        // The right cage's eight corners, the four it shares with the left cage included.
        assert_eq!(internal.owns.len(), 8);
        assert_eq!(scene.cages.vertices.len(), before + 8);
        assert!(crate::check::validate_scene(&scene).is_valid());
        assert!(crate::hierarchy::Hierarchy::bind(&scene).is_ok());
        // A second import of the same box: nothing left without a parent, and the scene stays.
        let unchanged = scene.clone();
        let error = import_internal_cages(
            &mut scene,
            &box_set("again", lo - pad, hi + pad),
            CoordinateKind::MeanValue,
        )
        .unwrap_err();
        assert!(matches!(error, AutoInternalCageError::HoldsNothing { .. }));
        assert_eq!(scene, unchanged);
    }

    #[test]
    fn an_open_imported_cage_is_refused_with_the_reason() {
        let mut scene = demo_scene("bar", 0.3).unwrap();
        let mut open = box_set("lid_off", DVec3::splat(-2.0), DVec3::splat(2.0));
        open.leaves[0].faces.pop();
        let unchanged = scene.clone();
        let error =
            import_internal_cages(&mut scene, &open, CoordinateKind::MeanValue).unwrap_err();
        assert!(
            matches!(error, AutoInternalCageError::InvalidCage { .. }),
            "{error}"
        );
        assert_eq!(scene, unchanged);
    }
}
