//! The scene model: a mesh, a set of leaf and internal cages over one vertex array, settings,
//! named poses and the current pose; validation of the whole; JSON scene files; demo scenes
//! and automatic grid cages.

mod autocage;
mod cage_set;
mod containment;
pub mod demo;
mod file;
mod pose_state;
mod pretty_json;
mod settings;
mod validate;

use std::collections::BTreeMap;
use std::path::PathBuf;

use glam::DVec3;

use crate::mesh::Mesh;

pub use autocage::{AutocageOptions, autocage};
pub use cage_set::{
    Adjacency, CageSet, InternalCage, LeafCage, LocalCage, is_reversed, is_same_cycle,
};
pub(crate) use containment::ON_CAGE;
pub use containment::{Containment, leaf_containment};
pub use file::{
    SCENE_FORMAT, SCENE_VERSION, SceneFileError, load_scene, save_scene, scene_to_json,
};
pub use pose_state::{AnchorRecord, FollowRecord, HierarchyState, ReboundVertex};
pub use pretty_json::to_pretty as to_pretty_json;
pub use settings::{JoinPolicy, OutsidePolicy, SceneSettings, Smoothing};
pub(crate) use validate::check_hierarchy;
pub use validate::{MAX_COORDINATE, SceneProblem, ValidationReport, validate_scene};

/// Where the scene's mesh comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshSource {
    /// A mesh file (absolute once loaded; saved relative to the scene file).
    File(PathBuf),
    /// Stored inside the scene file (generated demos).
    Embedded,
}

/// A whole scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Where the mesh comes from.
    pub mesh_source: MeshSource,
    /// The mesh.
    pub mesh: Mesh,
    /// Cages with their rest positions.
    pub cages: CageSet,
    /// Scene-wide settings.
    pub settings: SceneSettings,
    /// Named poses: positions of every cage vertex.
    pub poses: BTreeMap<String, Vec<DVec3>>,
    /// Current positions of every cage vertex.
    pub pose: Vec<DVec3>,
    /// The hierarchy's state in the current pose (section 3.4).
    pub pose_state: HierarchyState,
    /// The hierarchy's state in each named pose (rest state where absent).
    pub pose_states: BTreeMap<String, HierarchyState>,
}

impl Scene {
    /// A scene in its rest pose.
    pub fn new(
        mesh_source: MeshSource,
        mesh: Mesh,
        cages: CageSet,
        settings: SceneSettings,
    ) -> Self {
        let pose = cages.vertices.clone();
        Self {
            mesh_source,
            mesh,
            cages,
            settings,
            poses: BTreeMap::new(),
            pose,
            pose_state: HierarchyState::default(),
            pose_states: BTreeMap::new(),
        }
    }

    /// The positions of a named pose, or the current pose for `None`.
    pub fn pose_named(&self, name: Option<&str>) -> Option<&[DVec3]> {
        match name {
            None => Some(&self.pose),
            Some(n) => self.poses.get(n).map(Vec::as_slice),
        }
    }

    /// The hierarchy state of a named pose, or of the current pose for `None`.
    pub fn pose_state_named(&self, name: Option<&str>) -> HierarchyState {
        match name {
            None => self.pose_state.clone(),
            Some(n) => self.pose_states.get(n).cloned().unwrap_or_default(),
        }
    }

    /// h of leaf cage `index`: its own or the scene default.
    pub fn cage_h(&self, index: usize) -> f64 {
        self.cages.leaves[index]
            .h
            .unwrap_or(self.settings.default_h)
    }
}
