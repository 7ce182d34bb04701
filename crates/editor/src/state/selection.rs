//! What the user has picked: cage vertices, the inspected cage, the hovered vertex.

use std::collections::BTreeSet;

use starcages_core::scene::CageSet;

use super::CageId;

/// The selection. Indices always resolve in the current document: [`Selection::revalidate`]
/// runs after every change of it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Selection {
    /// Selected cage vertices (indices into `CageSet::vertices`).
    pub vertices: BTreeSet<u32>,
    /// The cage shown in the inspector, with its name: the name follows the cage when an
    /// edit renumbers the cages (an internal cage removed before it, say).
    cage: Option<(CageId, String)>,
    /// The cage vertex under the cursor.
    pub hovered: Option<u32>,
    /// The vertex count the vertex indices were picked in.
    vertex_count: usize,
    /// Selected leaf-cage faces (face select mode), by cage name and face index; their corners
    /// are in `vertices` too. A face goes when one of its corners is deselected.
    pub faces: BTreeSet<(String, usize)>,
    /// Selected mesh vertices (mesh select mode in Rig mode; indices into the welded mesh
    /// vertices): the region Shift+A can put a box around.
    pub mesh_vertices: BTreeSet<u32>,
    /// The active element, as Blender's: the first vertex of the last pick that selected
    /// something (the vertex clicked; for a control, its first vertex). Always selected.
    pub active: Option<u32>,
}

/// How a picked set of vertices combines with the selection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SelectMode {
    /// The picked vertices become the selection.
    Replace,
    /// The picked vertices join the selection.
    Add,
    /// Each picked vertex flips between selected and not.
    Toggle,
}

impl Selection {
    /// Combines `picked` into the selection.
    pub fn select(&mut self, picked: impl IntoIterator<Item = u32>, mode: SelectMode) {
        if mode == SelectMode::Replace {
            self.vertices.clear();
            self.faces.clear();
        }
        let mut first_selected = None;
        for v in picked {
            if mode == SelectMode::Toggle && self.vertices.contains(&v) {
                self.vertices.remove(&v);
            } else {
                self.vertices.insert(v);
                first_selected.get_or_insert(v);
            }
        }
        self.active = first_selected
            .or(self.active)
            .filter(|v| self.vertices.contains(v));
    }

    /// Combines leaf-cage faces `picked` (cage index, face index in `set`) into the selection,
    /// with their corners; faces `set` does not have are ignored.
    pub fn select_faces(&mut self, picked: Vec<(usize, usize)>, mode: SelectMode, set: &CageSet) {
        if mode == SelectMode::Replace {
            self.vertices.clear();
            self.faces.clear();
        }
        for (c, f) in picked {
            let Some((cage, face)) = set
                .leaves
                .get(c)
                .and_then(|cage| Some((cage, cage.faces.get(f)?)))
            else {
                continue;
            };
            let key = (cage.name.clone(), f);
            if mode == SelectMode::Toggle && self.faces.remove(&key) {
                // Its corners go, except those of other selected faces.
                let kept: BTreeSet<u32> = self
                    .faces
                    .iter()
                    .filter_map(|(name, g)| set.leaves.get(set.leaf_index(name)?)?.faces.get(*g))
                    .flatten()
                    .copied()
                    .collect();
                self.vertices
                    .retain(|v| !face.contains(v) || kept.contains(v));
            } else {
                self.faces.insert(key);
                self.vertices.extend(face.iter().copied());
            }
        }
    }

    /// Combines mesh vertices `picked` into the mesh selection; indices of `count` or more are
    /// ignored.
    pub fn select_mesh_vertices(
        &mut self,
        picked: impl IntoIterator<Item = u32>,
        mode: SelectMode,
        count: usize,
    ) {
        if mode == SelectMode::Replace {
            self.mesh_vertices.clear();
        }
        for v in picked.into_iter().filter(|&v| (v as usize) < count) {
            if mode == SelectMode::Toggle && self.mesh_vertices.contains(&v) {
                self.mesh_vertices.remove(&v);
            } else {
                self.mesh_vertices.insert(v);
            }
        }
    }

    /// The selected faces as (cage index, face index) in `set`.
    pub fn face_indices(&self, set: &CageSet) -> Vec<(usize, usize)> {
        self.faces
            .iter()
            .filter_map(|(name, f)| Some((set.leaf_index(name)?, *f)))
            .collect()
    }

    /// The cage shown in the inspector.
    pub fn cage(&self) -> Option<CageId> {
        self.cage.as_ref().map(|(id, _)| *id)
    }

    /// Shows `cage` in the inspector (nothing for a cage `set` does not have).
    pub fn inspect(&mut self, cage: Option<CageId>, set: &CageSet) {
        self.cage = cage.and_then(|id| Some((id, id.name(set)?.to_owned())));
    }

    /// Brings the selection in line with `set` after a change of the document: the inspected
    /// cage is found again by name (or dropped); vertex indices out of range go, and when
    /// vertices were removed (indices shifted) the vertex selection is cleared rather than
    /// left pointing at other vertices.
    pub fn revalidate(&mut self, set: &CageSet) {
        let count = set.vertices.len();
        if count < self.vertex_count {
            self.vertices.clear();
            self.hovered = None;
        }
        self.vertex_count = count;
        self.vertices.retain(|&v| (v as usize) < count);
        let vertices = &self.vertices;
        self.faces.retain(|(name, f)| {
            set.leaf_index(name)
                .and_then(|c| set.leaves[c].faces.get(*f))
                .is_some_and(|face| face.iter().all(|v| vertices.contains(v)))
        });
        self.hovered = self.hovered.filter(|&v| (v as usize) < count);
        self.active = self.active.filter(|v| self.vertices.contains(v));
        self.cage = self.cage.take().and_then(|(id, name)| {
            let id = match id.name(set) {
                Some(now) if now == name => id,
                _ => CageId::by_name(set, &name)?,
            };
            Some((id, name))
        });
    }

    /// Whether every index resolves in `set` (the invariant `revalidate` keeps).
    pub fn is_valid_for(&self, set: &CageSet) -> bool {
        let count = set.vertices.len();
        self.vertices.iter().all(|&v| (v as usize) < count)
            && self.hovered.is_none_or(|v| (v as usize) < count)
            && self.active.is_none_or(|v| self.vertices.contains(&v))
            && self
                .cage
                .as_ref()
                .is_none_or(|(id, name)| id.name(set) == Some(name.as_str()))
    }

    /// The one selected vertex, if exactly one is selected.
    pub fn single_vertex(&self) -> Option<u32> {
        match self.vertices.len() {
            1 => self.vertices.first().copied(),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_active_vertex_is_the_first_of_the_last_pick_and_always_selected() {
        let mut selection = Selection::default();
        selection.select([4, 7], SelectMode::Replace);
        assert_eq!(selection.active, Some(4));
        selection.select([9], SelectMode::Add);
        assert_eq!(selection.active, Some(9));
        // Toggling the active vertex off leaves nothing active; toggling another off keeps it.
        selection.select([4], SelectMode::Toggle);
        assert_eq!(selection.active, Some(9));
        selection.select([9], SelectMode::Toggle);
        assert_eq!(selection.active, None);
        selection.select([], SelectMode::Replace);
        assert_eq!(selection.active, None);
    }

    #[test]
    fn modes_combine_as_blender_does() {
        let mut s = Selection::default();
        s.select([1, 2], SelectMode::Replace);
        s.select([2, 3], SelectMode::Toggle);
        assert_eq!(s.vertices, BTreeSet::from([1, 3]));
        s.select([4], SelectMode::Add);
        assert_eq!(s.vertices, BTreeSet::from([1, 3, 4]));
        s.select([5], SelectMode::Replace);
        assert_eq!(s.single_vertex(), Some(5));
    }

    #[test]
    fn the_inspected_cage_follows_its_name_and_removed_vertices_clear_the_selection() {
        use starcages_core::hierarchy::{
            AutoInternalCage, add_auto_internal_cage, remove_internal_cage,
        };
        let Some(mut scene) = starcages_core::generate::demo::demo_scene("critter", 0.3) else {
            panic!("the critter demo exists");
        };
        // Two more top-level cages over halves of the head cage's own (free) vertices.
        let free = scene.cages.cage_vertices("head").unwrap_or_default();
        let (a, b) = free.split_at(free.len() / 2);
        for (name, vertices) in [("extra_a", a), ("extra_b", b)] {
            let options = AutoInternalCage {
                name: name.into(),
                ..AutoInternalCage::default()
            };
            assert!(add_auto_internal_cage(&mut scene, &options, vertices).is_ok());
        }
        let set = &scene.cages;
        let extra_b = CageId::by_name(set, "extra_b");
        let mut s = Selection::default();
        s.revalidate(set);
        s.inspect(extra_b, set);
        s.select([0, 1], SelectMode::Replace);
        let Some(CageId::Internal(b_index)) = extra_b else {
            panic!("extra_b is an internal cage");
        };
        assert!(
            remove_internal_cage(&mut scene, b_index - 1).is_ok(),
            "extra_a goes"
        );
        let set = &scene.cages;
        s.revalidate(set);
        assert_eq!(
            s.cage(),
            Some(CageId::Internal(b_index - 1)),
            "it follows extra_b"
        );
        assert_eq!(s.cage().and_then(|c| c.name(set)), Some("extra_b"));
        assert!(
            s.vertices.is_empty(),
            "indices shifted: the vertex selection is cleared"
        );
        assert!(s.is_valid_for(set));
        // A cage that is gone is dropped.
        s.inspect(Some(CageId::Internal(99)), set);
        assert_eq!(s.cage(), None);
    }
}
