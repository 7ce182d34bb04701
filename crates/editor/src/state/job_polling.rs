//! The editor's background jobs seen from its state: starting a bind, a load, a new document
//! from a mesh or an auto rig, polling them once per frame (or waiting, in tests), and what a
//! finished job changes; an edit while the auto rig runs cancels it.

use std::path::PathBuf;
use std::sync::Arc;

use super::jobs::{self, Job, Scope};
use super::{
    Document, EditorError, EditorState, LiveRig, NewMeshOptions, NewRig, Pending, Selection,
};

impl EditorState {
    /// Starts binding the current scene on a worker, as much as changed since the binding in
    /// use (which stays in use meanwhile). A bind already running is stale: it is cancelled.
    pub fn start_bind(&mut self, label: &str) {
        self.bind_after_gesture = false;
        let scope = self
            .rig
            .as_ref()
            .map_or(Scope::Preview, |rig| rig.rebind_scope(&self.doc.scene));
        self.generations.edit += 1;
        self.spawn_bind(label, scope);
    }

    /// Starts the full bind that replaces a preview binding, unless a bind is running already.
    pub fn refine_preview(&mut self) {
        let Some(rig) = self.rig.as_ref().filter(|rig| rig.preview) else {
            return;
        };
        if self.bind_job.is_none() {
            let (label, scope) = refinement(rig);
            self.spawn_bind(label, scope);
        }
    }

    /// Starts a bind of `scope` for the current edit generation, replacing (cancelling) the
    /// one running.
    pub(super) fn spawn_bind(&mut self, label: &str, scope: Scope) {
        let generation = self.generations.edit;
        let scene = self.doc.scene.clone();
        let (topology, hierarchy) = self
            .checked_topology
            .as_ref()
            .and_then(|t| t.of(&scene))
            .unzip();
        self.bind_job = Some(Job::spawn("binding", label, self.waker.clone(), move |c| {
            let checked = jobs::Checked {
                topology: topology.as_deref(),
                hierarchy: hierarchy.flatten(),
            };
            jobs::bind(&scene, checked, scope, generation, c)
        }));
    }

    /// Takes finished jobs (bind, load, baseline) and refreshes the influence map; `wait`
    /// blocks until every running job has ended (tests and headless use).
    pub fn poll_jobs(&mut self, wait: bool) {
        loop {
            self.poll_load(wait);
            self.poll_autorig(wait);
            self.poll_bind(wait);
            self.poll_baseline(wait);
            self.poll_look(wait);
            self.refresh_map();
            let busy = self.load_job.is_some()
                || self.look_job.is_some()
                || self.autorig_job.is_some()
                || self.bind_job.is_some()
                || self.map.baseline_progress().is_some();
            if !wait || !busy {
                return;
            }
        }
    }

    fn poll_bind(&mut self, wait: bool) {
        let Some(job) = &self.bind_job else {
            return;
        };
        let result = if wait { Some(job.wait()) } else { job.poll() };
        let Some(result) = result else {
            return;
        };
        self.bind_job = None;
        match result.and_then(|r| r) {
            Ok(bound) if bound.generation == self.generations.edit => {
                let mut hierarchy = bound.hierarchy;
                // The pose may have changed while binding: follow the current state.
                if let Err(e) = hierarchy.restore(&self.doc.scene.pose_state) {
                    self.error(EditorError::Hierarchy(e));
                    self.doc.scene.pose_state = hierarchy.state();
                }
                self.stats.bind_seconds = bound.seconds;
                let same_mesh = self
                    .rig
                    .as_ref()
                    .is_some_and(|rig| Arc::ptr_eq(&rig.binding, &bound.binding));
                let preview = bound.preview;
                let mut rig =
                    LiveRig::new(bound.binding, hierarchy, bound.bound_for, &self.doc.scene);
                rig.preview = preview;
                rig.coarse_leaves = bound.coarse_leaves;
                if let Some(volumes) = bound.joint_volumes {
                    rig.set_joint_volumes(volumes);
                }
                self.rig = Some(rig);
                if !same_mesh {
                    self.generations.mesh += 1;
                }
                self.generations.deformation += 1;
                if let Some(rig) = self.rig.as_ref().filter(|rig| rig.preview) {
                    // Deformable now; the full resolution follows in the background.
                    let (label, scope) = refinement(rig);
                    self.spawn_bind(label, scope);
                }
            }
            Ok(_) => {} // a newer edit superseded it
            Err(e) => self.error(e),
        }
    }

    fn poll_load(&mut self, wait: bool) {
        let Some(job) = &self.load_job else {
            return;
        };
        let result = if wait { Some(job.wait()) } else { job.poll() };
        let Some(result) = result else {
            return;
        };
        self.load_job = None;
        match result.and_then(|r| r) {
            // Unsaved work (kept or made while the file was read) is asked about now that the
            // file has opened: a broken one is refused without a question.
            Ok(doc) if self.doc.dirty => {
                self.info(format!(
                    "{} is read; {} has unsaved changes",
                    doc.source_name(),
                    self.doc.name()
                ));
                self.loaded = Some(Box::new(doc));
                self.pending = Some(Pending::Install);
            }
            Ok(doc) => self.install_loaded(doc),
            Err(e) => {
                self.pending_autorig = None;
                self.error(e);
            }
        }
    }

    /// Puts a document a worker has read in place of the current one, and starts the auto
    /// rig New from mesh asked for.
    fn install_loaded(&mut self, doc: Document) {
        let path = doc.path.clone();
        // Taken first: installing the document starts a fresh state.
        let autorig = self.pending_autorig.take();
        self.install_document(doc);
        if let Some(path) = path {
            self.remember(&path);
            self.info(format!("opened {}", path.display()));
        }
        if let Some(settings) = autorig {
            // The grid is not bound meanwhile: the auto rig gets every core, and its rig is
            // bound when it arrives (the grid is, should it not).
            self.bind_job = None;
            self.start_autorig(settings);
        }
    }

    /// The answer to the unsaved-changes question about a document read meanwhile: install
    /// it, or (`install` false: cancelled, or the save failed) drop it and keep the work.
    pub fn finish_pending_install(&mut self, install: bool) {
        let loaded = self.loaded.take();
        match loaded {
            Some(doc) if install => self.install_loaded(*doc),
            _ => self.pending_autorig = None,
        }
    }

    /// Takes the auto rig's cages once they are made: they replace the rig as one undo step
    /// (poses and animation keys are of the old cages, so they go; undo brings them back), with
    /// mean value join cages as [`starcages_core::generate::autorig_settings`] says.
    ///
    /// It lands in the document it was asked for or not at all: an edit, undo or redo while
    /// it runs cancels it ([`Self::cancel_autorig_for_edit`]), and it waits for a gesture in
    /// progress (a grab begun on the old cages) to end.
    fn poll_autorig(&mut self, wait: bool) {
        let Some(job) = &self.autorig_job else {
            return;
        };
        if self.gesture.is_some() && !wait {
            return;
        }
        let result = if wait { Some(job.wait()) } else { job.poll() };
        let Some(result) = result else {
            return;
        };
        self.autorig_job = None;
        match result.and_then(|r| r) {
            Ok(cages) => {
                let (leaves, vertices) = (cages.leaves.len(), cages.vertices.len());
                self.selection = Selection::default();
                let mut dropped = (0, 0);
                self.edit_scene("auto rig", |scene| {
                    scene.settings.join_coordinates =
                        starcages_core::generate::autorig_settings().join_coordinates;
                    dropped = scene.replace_rig(cages);
                });
                let went = match dropped {
                    (0, 0) => String::new(),
                    (poses, keys) => format!(
                        "; the old rig's {poses} pose(s) and {keys} animation key(s) went with it"
                    ),
                };
                self.info(format!(
                    "auto rig: {leaves} leaf cages, {vertices} cage vertices{went} (Ctrl+Z brings the old rig back)"
                ));
            }
            Err(e) => {
                self.error(e);
                self.bind_if_unbound();
            }
        }
    }

    /// Binds the scene if nothing is bound or binding (a mesh whose auto rig did not come:
    /// its grid was left unbound while the auto rig ran).
    pub fn bind_if_unbound(&mut self) {
        if self.rig.is_none() && self.bind_job.is_none() {
            self.start_bind("binding the scene");
        }
    }

    /// Starts the auto rig of the current mesh on a worker, with the scene's settings kept.
    pub fn start_autorig(&mut self, settings: starcages_core::generate::AutorigSettings) {
        self.info("auto rig…");
        self.autorig_job = Some(jobs::autorig(
            self.doc.scene.mesh.clone(),
            settings,
            self.waker.clone(),
        ));
    }

    /// Starts reading a mesh and rigging it on a worker, as [`Self::start_load`]. With the auto
    /// rig, the mesh opens at once in the automatic grid and the auto rig follows in the
    /// background, replacing the grid as one undo step (Ctrl+Z brings the grid back; Cancel or
    /// a mesh the auto rig cannot rig keeps it): a million-triangle mesh shows while its rig is
    /// made.
    pub fn start_new_from_mesh(&mut self, path: PathBuf, mut options: NewMeshOptions) {
        self.info(format!("reading {}…", path.display()));
        self.pending_autorig = match options.rig {
            NewRig::Auto => {
                options.rig = NewRig::Grid;
                Some(starcages_core::generate::AutorigSettings {
                    detail: options.detail,
                    mirror: options.mirror,
                    ..starcages_core::generate::AutorigSettings::default()
                })
            }
            NewRig::Grid => None,
        };
        self.load_job = Some(jobs::new_from_mesh(path, options, self.waker.clone()));
    }

    /// Starts opening `path` on a worker; the current document stays until it has loaded,
    /// and for good if it fails. A mesh (not a `.json` scene) opens as File ▸ New from mesh
    /// does: at once in the grid, its auto rig following.
    pub fn start_load(&mut self, path: PathBuf) {
        let scene = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        if !scene {
            return self.start_new_from_mesh(path, NewMeshOptions::default());
        }
        self.info(format!("opening {}…", path.display()));
        self.load_job = Some(jobs::load(path, self.waker.clone()));
    }

    /// Starts generating the demo `name` on a worker, as [`Self::start_load`].
    pub fn start_load_demo(&mut self, name: String) {
        self.info(format!("generating the {name} demo…"));
        self.load_job = Some(jobs::load_demo(name, self.waker.clone()));
    }

    /// An edit, undo or redo changed the document while the auto rig was being made for it:
    /// the rig would land on another document (on top of an undone step, or over a stray
    /// move), so it is cancelled, with a message saying how to make it again.
    pub(super) fn cancel_autorig_for_edit(&mut self) {
        if self.autorig_job.take().is_some() {
            self.info(
                "auto rig cancelled: the rig changed while it was being made (the Rig menu's \
                 Auto rig makes it again)",
            );
        }
    }
}

/// The bind that refines the preview `rig`: its coarse leaf cages' rows at full resolution,
/// or everything with harmonic join cages.
fn refinement(rig: &LiveRig) -> (&'static str, Scope) {
    if rig.coarse_leaves.is_empty() {
        ("refining: harmonic join cages", Scope::Full)
    } else {
        (
            "refining: harmonic leaf cages",
            Scope::Leaves(Arc::clone(&rig.binding), rig.coarse_leaves.clone(), false),
        )
    }
}
