//! Undo and redo of every edit: snapshots of the editable part of the scene (cages, settings,
//! poses and their hierarchy states; never the mesh), one per edit, a whole drag being one.

use std::collections::BTreeMap;

use glam::DVec3;
use starcages_core::anim::Animation;
use starcages_core::scene::{CageSet, HierarchyState, Scene, SceneSettings};

/// The editable state of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    cages: CageSet,
    settings: SceneSettings,
    poses: BTreeMap<String, Vec<DVec3>>,
    pose: Vec<DVec3>,
    pose_state: HierarchyState,
    pose_states: BTreeMap<String, HierarchyState>,
    animation: Animation,
}

impl Snapshot {
    /// The editable state of `scene`.
    pub fn of(scene: &Scene) -> Self {
        Self {
            cages: scene.cages.clone(),
            settings: scene.settings,
            poses: scene.poses.clone(),
            pose: scene.pose.clone(),
            pose_state: scene.pose_state.clone(),
            pose_states: scene.pose_states.clone(),
            animation: scene.animation.clone(),
        }
    }

    /// Puts this state back into `scene`.
    pub fn restore(self, scene: &mut Scene) {
        scene.cages = self.cages;
        scene.settings = self.settings;
        scene.poses = self.poses;
        scene.pose = self.pose;
        scene.pose_state = self.pose_state;
        scene.pose_states = self.pose_states;
        scene.animation = self.animation;
    }
}

/// The undo and redo stacks.
#[derive(Debug, Default)]
pub struct UndoStack {
    undo: Vec<(String, Snapshot)>,
    redo: Vec<(String, Snapshot)>,
}

const LIMIT: usize = 200;

impl UndoStack {
    /// Records that `label` is about to change the scene whose state was `before`.
    pub fn push(&mut self, label: &str, before: Snapshot) {
        self.undo.push((label.to_owned(), before));
        if self.undo.len() > LIMIT {
            self.undo.remove(0);
        }
        self.redo.clear();
    }

    /// Undoes the last edit of `scene`; returns its label.
    pub fn undo(&mut self, scene: &mut Scene) -> Option<String> {
        let (label, before) = self.undo.pop()?;
        self.redo.push((label.clone(), Snapshot::of(scene)));
        before.restore(scene);
        Some(label)
    }

    /// Redoes the last undone edit; returns its label.
    pub fn redo(&mut self, scene: &mut Scene) -> Option<String> {
        let (label, after) = self.redo.pop()?;
        self.undo.push((label.clone(), Snapshot::of(scene)));
        after.restore(scene);
        Some(label)
    }

    /// How many edits Ctrl+Z can undo.
    pub fn depth(&self) -> usize {
        self.undo.len()
    }

    /// Takes back the last edit's record (to fold it into a gesture that continues it).
    pub fn take_last(&mut self) -> Option<(String, Snapshot)> {
        self.undo.pop()
    }

    /// Label of the edit Ctrl+Z would undo.
    pub fn undo_label(&self) -> Option<&str> {
        self.undo.last().map(|(l, _)| l.as_str())
    }

    /// Label of the edit Ctrl+Shift+Z would redo.
    pub fn redo_label(&self) -> Option<&str> {
        self.redo.last().map(|(l, _)| l.as_str())
    }

    /// Forgets everything (a new document).
    pub fn clear(&mut self) {
        self.undo.clear();
        self.redo.clear();
    }
}
