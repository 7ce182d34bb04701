//! What the viewport draws in the warning colour while the rig is invalid: the leaf cages, cage
//! vertices and mesh vertices that the validation problems name, each with the first problem
//! that names it (shown when the pointer is over it).

use std::collections::BTreeMap;

use starcages_core::scene::{Scene, SceneProblem};
use starcages_viewport::layers::CageStyle;

/// At most this many mesh vertices are marked (the count is in the problem's text).
const MARKED_MESH_VERTICES: usize = 20_000;

/// The elements of an invalid rig, with the reason for each.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RigWarnings {
    /// Leaf cages (by index) and the first problem naming each.
    pub cages: BTreeMap<usize, String>,
    /// Cage vertices and the first problem naming each.
    pub vertices: BTreeMap<u32, String>,
    /// Mesh vertices (welded indices) a problem names: outside every cage, or in two.
    pub mesh_vertices: Vec<usize>,
}

impl RigWarnings {
    /// The warnings for `problems` of `scene` (empty for a valid rig).
    pub fn from_problems(scene: &Scene, problems: &[SceneProblem]) -> Self {
        let mut warnings = Self::default();
        for problem in problems {
            let elements = problem.elements(&scene.cages);
            let text = problem.to_string();
            for c in elements.leaf_cages {
                warnings.cages.entry(c).or_insert_with(|| text.clone());
            }
            for v in elements.cage_vertices {
                warnings.vertices.entry(v).or_insert_with(|| text.clone());
            }
            let room = MARKED_MESH_VERTICES.saturating_sub(warnings.mesh_vertices.len());
            warnings
                .mesh_vertices
                .extend(elements.mesh_vertices.into_iter().take(room));
        }
        warnings
    }

    /// Why cage vertex `v` is drawn as a problem: its own problem, or that of a warned cage
    /// it belongs to.
    pub fn reason_at_vertex(&self, scene: &Scene, v: u32) -> Option<&str> {
        if let Some(reason) = self.vertices.get(&v) {
            return Some(reason);
        }
        self.cages.iter().find_map(|(&c, reason)| {
            let cage = scene.cages.leaves.get(c)?;
            cage.faces
                .iter()
                .flatten()
                .any(|&u| u == v)
                .then_some(reason.as_str())
        })
    }

    /// Marks the warned cages and vertices in `style`, and the warned mesh vertices at their
    /// rest positions.
    pub fn mark(&self, scene: &Scene, style: &mut CageStyle) {
        style.warning_cages = self.cages.keys().copied().collect();
        style.warning_vertices = self.vertices.keys().copied().collect();
        let positions = scene.mesh.welded_positions();
        style.warning_points = self
            .mesh_vertices
            .iter()
            .filter_map(|&v| positions.get(v))
            .map(|p| p.as_vec3())
            .collect();
    }
}
