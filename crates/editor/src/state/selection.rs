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
    /// The cage shown in the inspector.
    pub cage: Option<CageId>,
    /// The cage vertex under the cursor.
    pub hovered: Option<u32>,
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
        }
        for v in picked {
            if mode == SelectMode::Toggle && self.vertices.contains(&v) {
                self.vertices.remove(&v);
            } else {
                self.vertices.insert(v);
            }
        }
    }

    /// Drops whatever no longer exists in `set`.
    pub fn revalidate(&mut self, set: &CageSet) {
        let count = set.vertices.len();
        self.vertices.retain(|&v| (v as usize) < count);
        self.hovered = self.hovered.filter(|&v| (v as usize) < count);
        self.cage = self.cage.filter(|c| c.exists(set));
    }

    /// Whether every index resolves in `set` (the invariant `revalidate` keeps).
    pub fn is_valid_for(&self, set: &CageSet) -> bool {
        let count = set.vertices.len();
        self.vertices.iter().all(|&v| (v as usize) < count)
            && self.hovered.is_none_or(|v| (v as usize) < count)
            && self.cage.is_none_or(|c| c.exists(set))
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
}
