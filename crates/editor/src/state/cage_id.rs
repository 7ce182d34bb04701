//! [`CageId`]: a typed address of a cage in a [`CageSet`], instead of a flat "leaves then
//! internal cages" index.

use starcages_core::coords::CoordinateKind;
use starcages_core::scene::CageSet;

/// A cage of the scene: a leaf cage (it deforms the mesh) or an internal cage (it drives cage
/// vertices below it). An id can outlive its cage (after an undo, say): every accessor returns
/// `None` for a cage that is not there, and [`crate::state::EditorState`] drops stale ids after
/// each change of the document.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CageId {
    /// `CageSet::leaves[i]`.
    Leaf(usize),
    /// `CageSet::internals[i]`.
    Internal(usize),
}

impl CageId {
    /// Every cage of `set`: leaves first, then internal cages.
    pub fn all(set: &CageSet) -> impl Iterator<Item = Self> + use<> {
        let leaves = (0..set.leaves.len()).map(Self::Leaf);
        let internals = (0..set.internals.len()).map(Self::Internal);
        leaves.chain(internals)
    }

    /// Whether the cage exists in `set`.
    pub fn exists(self, set: &CageSet) -> bool {
        match self {
            Self::Leaf(i) => i < set.leaves.len(),
            Self::Internal(i) => i < set.internals.len(),
        }
    }

    /// The cage's name.
    pub fn name(self, set: &CageSet) -> Option<&str> {
        match self {
            Self::Leaf(i) => set.leaves.get(i).map(|c| c.name.as_str()),
            Self::Internal(i) => set.internals.get(i).map(|c| c.name.as_str()),
        }
    }

    /// The cage's coordinates.
    pub fn kind(self, set: &CageSet) -> Option<CoordinateKind> {
        match self {
            Self::Leaf(i) => set.leaves.get(i).map(|c| c.kind),
            Self::Internal(i) => set.internals.get(i).map(|c| c.kind),
        }
    }

    /// The cage's polygon faces (indices into `set.vertices`).
    pub fn faces(self, set: &CageSet) -> Option<&[Vec<u32>]> {
        match self {
            Self::Leaf(i) => set.leaves.get(i).map(|c| c.faces.as_slice()),
            Self::Internal(i) => set.internals.get(i).map(|c| c.faces.as_slice()),
        }
    }

    /// The cage's index in the viewport crate's per-cage lists (leaves, then internal cages).
    /// Used only where the editor hands data to `starcages_viewport`.
    pub fn layer_index(self, set: &CageSet) -> usize {
        match self {
            Self::Leaf(i) => i,
            Self::Internal(i) => set.leaves.len() + i,
        }
    }

    /// The cage with `name`.
    pub fn by_name(set: &CageSet, name: &str) -> Option<Self> {
        Self::all(set).find(|id| id.name(set) == Some(name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use starcages_core::generate::demo::demo_scene;

    #[test]
    fn ids_resolve_while_their_cage_exists() {
        let Some(scene) = demo_scene("critter", 0.3) else {
            panic!("the critter demo exists");
        };
        let set = &scene.cages;
        let all: Vec<CageId> = CageId::all(set).collect();
        assert_eq!(all.len(), set.leaves.len() + set.internals.len());
        for (flat, id) in all.iter().enumerate() {
            assert!(id.exists(set));
            assert_eq!(id.layer_index(set), flat);
            let name = id.name(set).unwrap_or_default();
            assert_eq!(CageId::by_name(set, name), Some(*id));
        }
        let gone = CageId::Internal(set.internals.len());
        assert!(!gone.exists(set));
        assert_eq!(gone.name(set), None);
        assert_eq!(gone.faces(set), None);
    }
}
