//! Baking: the mesh at a run of frames through one compiled operator. Cage positions change
//! per frame at the cost of one sparse product; a frame whose keyed h differs from the
//! operator's re-binds only the cages whose h changed (h shapes their rows of S, eq. 11).

use std::collections::BTreeMap;

use glam::DVec3;

use crate::coords::BindControl;
use crate::scene::Scene;
use crate::star::{StarBinding, StarError};

/// A scene's mesh deformed frame after frame by one binding.
pub struct FrameDeformer {
    scene: Scene,
    binding: StarBinding,
}

impl FrameDeformer {
    /// Deforms `scene`'s mesh with `binding` (a binding of that scene).
    pub fn new(scene: Scene, binding: StarBinding) -> Self {
        Self { scene, binding }
    }

    /// The scene as bound now (its h as the last frame keyed it).
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The binding as it stands now.
    pub fn binding(&self) -> &StarBinding {
        &self.binding
    }

    /// The welded mesh, in scene coordinates, for cage vertices at `cage_positions` and the
    /// keyed h values `h` (re-binding the cages whose h changed since the last frame).
    pub fn deform(
        &mut self,
        cage_positions: &[DVec3],
        h: &BTreeMap<String, f64>,
        control: &BindControl,
    ) -> Result<Vec<DVec3>, StarError> {
        let changed = self.scene.apply_keyed_h(h);
        if !changed.is_empty() {
            self.binding = self.binding.rebind_leaves(&self.scene, &changed, control)?;
        }
        Ok(self
            .binding
            .deform(&self.scene.cages.vertices, cage_positions)
            .iter()
            .map(|p| p.as_dvec3())
            .collect())
    }
}
