//! The scene model: a mesh, a set of leaf and internal cages over one vertex array, settings,
//! named poses, the current pose and the animation, and the model's own validation rules.
//! Editing rigs is [`crate::rig`]'s, generating them [`crate::generate`]'s, the engine's dry
//! runs [`crate::check`]'s; scene files and export are `starcages-io`'s.

mod cage_set;
mod containment;
mod locator;
mod pose_state;
mod pretty_json;
pub mod rig_names;
mod settings;
mod up_axis;
mod validate;

use std::collections::BTreeMap;
use std::path::PathBuf;

use glam::DVec3;

use crate::anim::Animation;
use crate::mesh::Mesh;

pub use cage_set::{
    Adjacency, CageSet, InternalCage, LeafCage, LocalCage, is_reversed, is_same_cycle,
};
pub(crate) use containment::ON_CAGE;
pub use containment::{Containment, leaf_containment};
pub use pose_state::{AnchorRecord, FollowRecord, HierarchyState, ReboundVertex};
pub use pretty_json::to_pretty as to_pretty_json;
pub use settings::{JoinPolicy, OutsidePolicy, SceneSettings, Smoothing};
pub use up_axis::UpAxis;
pub(crate) use validate::check_hierarchy;
pub use validate::{
    MAX_COORDINATE, ProblemElements, SceneProblem, ValidationReport, check_model, name_problem,
};

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
    /// The up axis of the mesh file (and of cage and pose files that go with it): the mesh is
    /// held turned to the scene's Z-up and turned back on export.
    pub mesh_up: UpAxis,
    /// The mesh, in scene coordinates (Z up).
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
    /// Keys over time (each names one of `poses`), frame rate and playback range.
    pub animation: Animation,
}

impl Scene {
    /// A scene in its rest pose, its mesh already in scene coordinates (`mesh_up` is Z: files
    /// are written as they are; set it for a mesh read from a Y-up file).
    pub fn new(
        mesh_source: MeshSource,
        mesh: Mesh,
        cages: CageSet,
        settings: SceneSettings,
    ) -> Self {
        let pose = cages.vertices.clone();
        Self {
            mesh_source,
            mesh_up: UpAxis::Z,
            mesh,
            cages,
            settings,
            poses: BTreeMap::new(),
            pose,
            pose_state: HierarchyState::default(),
            pose_states: BTreeMap::new(),
            animation: Animation::default(),
        }
    }

    /// A scene in its rest pose around a mesh read from the file `source` with up axis `up`
    /// (the mesh already turned to scene coordinates, as `starcages_io::read_mesh_as` gives it).
    pub fn from_mesh_file(
        source: PathBuf,
        up: UpAxis,
        mesh: Mesh,
        cages: CageSet,
        settings: SceneSettings,
    ) -> Self {
        let mut scene = Self::new(MeshSource::File(source), mesh, cages, settings);
        scene.mesh_up = up;
        scene
    }

    /// Replaces the whole rig by `cages` at rest (an auto rig): the poses, their hierarchy
    /// states and the animation's keys were of the old cage vertices, so they go with them
    /// (the playback range and frame rate stay). Returns how many poses and keys went.
    pub fn replace_rig(&mut self, cages: CageSet) -> (usize, usize) {
        let dropped = (self.poses.len(), self.animation.keys.len());
        self.pose = cages.vertices.clone();
        self.cages = cages;
        self.poses.clear();
        self.pose_state = HierarchyState::default();
        self.pose_states.clear();
        self.animation.keys.clear();
        dropped
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

    /// The up axis files written from this scene use (OBJ meshes and cages, point caches,
    /// points): the mesh file's, so that a round trip is the identity; for an embedded mesh,
    /// the axis the scene declares for it (`mesh_up_axis`: generated demos declare Y, the OBJ
    /// convention). glTF files are Y-up whatever this says (the format's rule).
    pub fn export_up(&self) -> UpAxis {
        self.mesh_up
    }

    /// Sets the h of the leaf cages named in `h` (a key's values); returns the indices of the
    /// cages whose h changed. Names that are not leaf cages are ignored (validation reports
    /// them).
    pub fn apply_keyed_h(&mut self, h: &BTreeMap<String, f64>) -> Vec<usize> {
        let mut changed = Vec::new();
        for (name, &value) in h {
            let Some(index) = self.cages.leaf_index(name) else {
                continue;
            };
            if self.cage_h(index) != value
                && let Some(leaf) = self.cages.leaves.get_mut(index)
            {
                leaf.h = Some(value);
                changed.push(index);
            }
        }
        changed
    }

    /// h of leaf cage `index`: its own or the scene default.
    pub fn cage_h(&self, index: usize) -> f64 {
        self.cages.leaves[index]
            .h
            .unwrap_or(self.settings.default_h)
    }
}
