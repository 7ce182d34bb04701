//! The editor's state, with no egui types: the document, the selection, the view, undo, the
//! binding in use and the background jobs. Only [`crate::commands::apply`] changes it; the UI
//! reads it. After every change of the document the selection, the hidden cages and any
//! gesture in progress are revalidated, so every index the UI reads resolves.

mod cage_id;
pub mod document;
mod error;
mod influence_map;
mod job_polling;
pub mod jobs;
mod look;
pub mod mirror;
pub mod recent;
mod rig;
pub mod rig_warnings;
mod selection;
pub mod timeline;
pub mod undo;
mod view;

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use glam::{DVec3, Vec3};
use starcages_core::posing::PoseRequest;

pub use cage_id::CageId;
pub use document::{Document, NewMeshOptions, NewRig};
pub use error::EditorError;
pub use influence_map::InfluenceMap;
pub use jobs::{Job, Waker};
pub use selection::{SelectMode, Selection};
pub use starcages_core::live::LiveRig;
pub use view::{
    GhostSettings, InfluenceChoice, LeafVertices, PivotPoint, ScreenRect, SelectElement, ViewState,
    leaf_only_vertices,
};

use jobs::{BindResult, LoadResult};
use undo::{Snapshot, UndoStack};

/// A message in the status bar.
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    /// The text.
    pub text: String,
    /// An error (red) or information.
    pub error: bool,
    /// When it was shown (it fades after [`Message::LIFETIME`]).
    pub shown: Instant,
}

impl Message {
    /// How long information stays in the status bar; errors stay twice as long. The last
    /// second of it fades out.
    pub const LIFETIME: std::time::Duration = std::time::Duration::from_secs(6);

    /// A message shown now.
    pub fn new(text: impl Into<String>, error: bool) -> Self {
        Self {
            text: text.into(),
            error,
            shown: Instant::now(),
        }
    }

    /// Its opacity now: 1 while fresh, falling to 0 over the last second of its lifetime.
    pub fn opacity(&self) -> f32 {
        let lifetime = if self.error {
            2 * Self::LIFETIME
        } else {
            Self::LIFETIME
        };
        let left = lifetime.saturating_sub(self.shown.elapsed()).as_secs_f32();
        left.min(1.0)
    }
}

/// Timings and sizes shown in the stats panel (the paper's Table II columns).
#[derive(Debug, Clone, Copy, Default)]
pub struct Stats {
    /// Seconds of the last bind.
    pub bind_seconds: f64,
    /// Milliseconds of the last deformation update (CPU, incremental).
    pub deform_ms: f64,
}

/// An action waiting for the user's answer about unsaved changes.
#[derive(Debug, Clone, PartialEq)]
pub enum Pending {
    /// Put in place the document a worker has read ([`EditorState::loaded`]: a scene, a mesh
    /// in its first cages, a demo). Asked only once it is read, so that no one confirms losing
    /// work for a file that then fails to open.
    Install,
    /// Close the window.
    Close,
}

/// Change counters: what the viewport must upload again and which results are stale.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Generations {
    /// The bound mesh (a new binding).
    pub mesh: u64,
    /// The deformation.
    pub deformation: u64,
    /// The edit state (cages and settings), for stale bind results.
    pub edit: u64,
    /// The mesh's look (read after the document opened).
    pub look: u64,
}

/// Identifies a gesture: a drag, a G / R / S tool or a slider drag, one undo step however
/// many moves it makes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GestureId(pub u64);

/// A gesture in progress: the document before it, to record one undo step or to go back.
#[derive(Debug)]
pub struct Gesture {
    /// Its id (the UI's transient tool holds the same one).
    pub id: GestureId,
    /// The undo label ("grab", "move vertices", "change h").
    pub label: String,
    /// The editable scene when it began.
    pub before: Snapshot,
    /// The edit this gesture continues (E's extrusion before its grab), taken off the undo
    /// stack: kept, the two are one undo step; cancelled, the edit's own step comes back.
    pub continues: Option<(String, Snapshot)>,
}

/// Every document installed gets a new id, never reused: GPU uploads and caches key on it.
static NEXT_DOCUMENT_ID: AtomicU64 = AtomicU64::new(1);

/// What moving cage vertices does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EditMode {
    /// Moving cage vertices poses the mesh; the rest cages and the binding stay.
    #[default]
    Pose,
    /// Moving cage vertices edits the rest cages (the binding); poses move along. Rig
    /// operations (extrude, loop cut, add, delete) are on keys.
    Rig,
}

/// The whole editor state.
pub struct EditorState {
    /// The open document.
    pub doc: Document,
    /// The document's identity: new for every document installed, never reused.
    pub document_id: u64,
    /// Selected and hovered vertices, the inspected cage.
    pub selection: Selection,
    /// Camera, layers, hidden cages, influence map, mirroring.
    pub view: ViewState,
    /// Pose mode or Rig mode.
    pub mode: EditMode,
    /// The undo depth right after an edit that the next gesture continues (E, then its
    /// grab): that gesture folds the edit's undo step into its own.
    pub gesture_continues: Option<usize>,
    /// What is wrong with the rig, found after every change of the document (empty: valid).
    /// The last valid binding stays in use meanwhile; Pose mode waits for a valid rig.
    pub rig_problems: Vec<String>,
    /// The cages and vertices those problems name, drawn in the warning colour.
    pub rig_warnings: rig_warnings::RigWarnings,
    /// The *Cages topology the last validation built, with the cages and join policy it is of:
    /// a full bind of those takes it instead of building it again.
    pub checked_topology: Option<CheckedTopology>,
    /// Undo and redo.
    pub undo: UndoStack,
    /// A gesture in progress.
    pub gesture: Option<Gesture>,
    /// The binding in use, once bound.
    pub rig: Option<LiveRig>,
    /// A bind in progress (dropping it cancels it).
    pub bind_job: Option<Job<BindResult>>,
    /// A file being opened.
    pub load_job: Option<Job<LoadResult>>,
    /// Rig ▸ Auto rig running on the current mesh (dropping it cancels it).
    pub autorig_job: Option<Job<Result<starcages_core::scene::CageSet, EditorError>>>,
    /// The auto rig New from mesh asked for: started once the mesh (in the grid, at once) is
    /// open.
    pending_autorig: Option<starcages_core::generate::AutorigSettings>,
    /// The influence map.
    pub map: InfluenceMap,
    /// The status message.
    pub message: Option<Message>,
    /// Timings.
    pub stats: Stats,
    /// Change counters.
    pub generations: Generations,
    /// An action awaiting the unsaved-changes answer.
    pub pending: Option<Pending>,
    /// A document read while the current one had unsaved changes, waiting for the answer
    /// ([`Pending::Install`]).
    pub loaded: Option<Box<Document>>,
    /// Recently opened or saved scenes, newest first.
    pub recent: Vec<PathBuf>,
    /// Where the recent list is kept (none in tests).
    pub recent_file: Option<PathBuf>,
    /// The user chose to close the window (after the unsaved-changes prompt).
    pub close_confirmed: bool,
    /// The current frame, playback and auto-key.
    pub timeline: timeline::Timeline,
    /// The mesh file's materials and images, once read (none for a plain or generated mesh).
    pub look: Option<Arc<starcages_core::mesh::look::LoadedLook>>,
    /// Reading them.
    pub look_job: Option<Job<starcages_core::mesh::look::LoadedLook>>,
    /// Settings changed inside a gesture: bind when it ends.
    bind_after_gesture: bool,
    waker: Option<Waker>,
}

/// The topology and hierarchy validation built, and what they are of.
#[derive(Debug, Clone)]
pub struct CheckedTopology {
    /// The cages they were built for.
    pub cages: starcages_core::scene::CageSet,
    /// The settings they were built with.
    pub settings: starcages_core::scene::SceneSettings,
    /// The topology.
    pub topology: Arc<starcages_core::star::Topology>,
    /// The hierarchy bound by the dry run (where the scene has internal cages).
    pub hierarchy: Option<starcages_core::hierarchy::Hierarchy>,
}

impl CheckedTopology {
    /// The topology and hierarchy when they are `scene`'s (its cages and settings).
    pub fn of(
        &self,
        scene: &starcages_core::scene::Scene,
    ) -> Option<(
        Arc<starcages_core::star::Topology>,
        Option<starcages_core::hierarchy::Hierarchy>,
    )> {
        (self.cages == scene.cages && self.settings == scene.settings)
            .then(|| (Arc::clone(&self.topology), self.hierarchy.clone()))
    }
}

impl std::fmt::Debug for EditorState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EditorState")
            .field("document", &self.doc.name())
            .field("document_id", &self.document_id)
            .field("selection", &self.selection)
            .field("gesture", &self.gesture)
            .field("generations", &self.generations)
            .finish_non_exhaustive()
    }
}

impl EditorState {
    /// A state on `doc`, binding it in the background; `waker` is called when a job finishes.
    pub fn new(doc: Document, waker: Option<Waker>) -> Self {
        let mut state = Self {
            doc,
            document_id: NEXT_DOCUMENT_ID.fetch_add(1, Ordering::Relaxed),
            selection: Selection::default(),
            view: ViewState::default(),
            mode: EditMode::Pose,
            rig_problems: Vec::new(),
            rig_warnings: rig_warnings::RigWarnings::default(),
            checked_topology: None,
            gesture_continues: None,
            undo: UndoStack::default(),
            gesture: None,
            rig: None,
            bind_job: None,
            load_job: None,
            autorig_job: None,
            pending_autorig: None,
            map: InfluenceMap::default(),
            message: None,
            stats: Stats::default(),
            generations: Generations::default(),
            pending: None,
            loaded: None,
            recent: Vec::new(),
            recent_file: None,
            close_confirmed: false,
            timeline: timeline::Timeline::default(),
            look: None,
            look_job: None,
            bind_after_gesture: false,
            waker,
        };
        // A scene with keys opens at its first frame, posed as the animation says there.
        let start = state.doc.scene.animation.frame_start as f64;
        state.show_frame(start);
        // Posing at a frame is not an edit: the document is as it was read.
        state.doc.dirty = false;
        // The editor shows the ground grid (off by default in the viewport crate's offscreen
        // images).
        state.view.layers.ground = true;
        state.revalidate();
        state.check_rig();
        state.frame(false);
        state.start_bind("binding the scene");
        state.start_look();
        state
    }

    /// Replaces the document (opened or new): a new identity, a fresh selection, undo and
    /// binding; running jobs of the old document are cancelled. The view's layers and the
    /// app-wide settings stay.
    pub fn install_document(&mut self, doc: Document) {
        let keep_view = (
            self.view.layers,
            self.view.viewport,
            self.view.mirror_x,
            self.view.snap_to_vertices,
            self.view.pivot_point,
            self.view.ghosts,
        );
        let recent = std::mem::take(&mut self.recent);
        let recent_file = self.recent_file.take();
        let waker = self.waker.take();
        // Dropping the old state drops its jobs, which cancels them.
        *self = Self::new(doc, waker);
        (
            self.view.layers,
            self.view.viewport,
            self.view.mirror_x,
            self.view.snap_to_vertices,
            self.view.pivot_point,
            self.view.ghosts,
        ) = keep_view;
        self.recent = recent;
        self.recent_file = recent_file;
    }

    /// Drops whatever the current document no longer has from the selection and the view.
    pub fn revalidate(&mut self) {
        let set = &self.doc.scene.cages;
        self.selection.revalidate(set);
        self.view.revalidate(set);
    }

    /// Hand moves (vertex, new position), mirrored when X mirroring is on, propagated down the
    /// hierarchy; the mesh follows incrementally.
    pub fn move_vertices(&mut self, moves: &[(u32, DVec3)]) -> Result<(), EditorError> {
        let moves = if self.view.mirror_x {
            let partners = mirror::partners(&self.doc.scene.cages.vertices);
            rig::with_mirror(moves, &partners, &self.doc.scene.pose)
        } else {
            moves.to_vec()
        };
        let scene = &mut self.doc.scene;
        let Some(rig) = self.rig.as_mut().filter(|rig| rig.can_pose(scene)) else {
            // An invalid rig is not bound at all: say so rather than "still being bound".
            return Err(match self.rig_problems.first() {
                Some(first) => EditorError::Rig(format!(
                    "the rig has {} problem(s) and is not bound; fix them first: {first}",
                    self.rig_problems.len()
                )),
                None => EditorError::NotBound,
            });
        };
        let start = Instant::now();
        let changed = rig
            .move_vertices(scene, &moves, self.gesture.is_some())
            .map_err(EditorError::Move)?;
        self.doc.dirty = true;
        if changed.is_empty() {
            return Ok(());
        }
        self.stats.deform_ms = start.elapsed().as_secs_f64() * 1e3;
        self.generations.deformation += 1;
        Ok(())
    }

    /// Goes to `frame`: with keys, the cages take the animation's pose there (and keyed h,
    /// which re-binds the cages whose h changed). Not an edit of the document: no undo step.
    pub fn show_frame(&mut self, frame: f64) {
        if !frame.is_finite() {
            return;
        }
        // A key can only be set where a scene may hold one.
        let limit = starcages_core::anim::MAX_FRAME as f64;
        let frame = frame.clamp(-limit, limit);
        self.timeline.frame = frame;
        let scene = &mut self.doc.scene;
        if scene.animation.is_empty() || self.gesture.is_some() {
            return;
        }
        // The posing engine the CLI and the bake use: on a key its pose's hierarchy state comes
        // back (hand moves go on from there); between keys the interpolated pose starts from
        // the rest state.
        let Ok(pose) = PoseRequest::frame(frame).resolve(scene) else {
            return;
        };
        scene.pose = pose.cages;
        scene.pose_state = pose.state;
        let h = pose.h;
        if !scene.apply_keyed_h(&h).is_empty() {
            // Keyed h shapes the operator: bind the cages whose h changed.
            self.document_changed();
            return;
        }
        if let Some(rig) = self.rig.as_mut().filter(|rig| rig.can_pose(scene)) {
            if let Err(e) = rig.hierarchy.restore(&scene.pose_state) {
                self.message = Some(Message::new(EditorError::Hierarchy(e).to_string(), true));
            }
            let start = Instant::now();
            rig.redeform_all(scene);
            self.stats.deform_ms = start.elapsed().as_secs_f64() * 1e3;
            self.generations.deformation += 1;
        }
    }

    /// While playing: shows the frame due now. Returns whether playback runs (the UI then
    /// asks for the next repaint at once).
    pub fn advance_playback(&mut self) -> bool {
        let now = Instant::now();
        if let Some(frame) = self.timeline.playback_frame(&self.doc.scene.animation, now) {
            self.show_frame(frame);
        }
        self.timeline.playing.is_some()
    }

    /// Validates the scene: its problems, and the elements they name for the viewport.
    fn check_rig(&mut self) {
        let checked = starcages_core::check::check_scene(&self.doc.scene);
        let scene = &self.doc.scene;
        let hierarchy = checked.hierarchy;
        self.checked_topology = checked.topology.map(|topology| CheckedTopology {
            cages: scene.cages.clone(),
            settings: scene.settings,
            topology,
            hierarchy,
        });
        let report = checked.report;
        self.rig_warnings =
            rig_warnings::RigWarnings::from_problems(&self.doc.scene, &report.errors);
        self.rig_problems = report.errors.iter().map(ToString::to_string).collect();
    }

    /// After the document's editable state was replaced (an edit, undo, redo, a cancelled
    /// gesture, a pose switch): revalidates, then binds again what the change affects, or
    /// restores the hierarchy state and redeforms.
    pub fn document_changed(&mut self) {
        self.cancel_autorig_for_edit();
        self.doc.dirty = true;
        self.revalidate();
        self.check_rig();
        if !self.rig_problems.is_empty() {
            // An invalid rig is not bound: the last valid binding stays in use (a bind of the
            // old state still running is stale: dropping it cancels it).
            self.bind_job = None;
            self.bind_after_gesture = false;
            return;
        }
        let stale = self
            .rig
            .as_ref()
            .is_none_or(|rig| !rig.is_current_for(&self.doc.scene));
        if stale || self.bind_job.is_some() {
            if self.gesture.is_some() {
                self.bind_after_gesture = true;
            } else {
                self.start_bind("binding after the change");
            }
            return;
        }
        if let Some(rig) = &mut self.rig {
            if let Err(e) = rig.hierarchy.restore(&self.doc.scene.pose_state) {
                self.message = Some(Message::new(EditorError::Hierarchy(e).to_string(), true));
            }
            let start = Instant::now();
            rig.redeform_all(&self.doc.scene);
            self.stats.deform_ms = start.elapsed().as_secs_f64() * 1e3;
            self.generations.deformation += 1;
        }
    }

    /// Starts a gesture: later changes are one undo step, recorded when it ends. A gesture
    /// already running is kept (its changes) first.
    pub fn begin_gesture(&mut self, id: GestureId, label: &str) {
        self.end_gesture(true);
        // The grab E asks for continues the extrusion, as Blender's "extrude and move".
        let continues = match self.gesture_continues.take() {
            Some(depth) if depth == self.undo.depth() => self.undo.take_last(),
            _ => None,
        };
        let label = match &continues {
            Some((edit, _)) => format!("{edit} and {label}"),
            None => label.to_owned(),
        };
        self.gesture = Some(Gesture {
            id,
            label,
            before: Snapshot::of(&self.doc.scene),
            continues,
        });
    }

    /// Ends the gesture: `keep` records one undo step (if anything changed), otherwise the
    /// document goes back to where it began.
    pub fn end_gesture(&mut self, keep: bool) {
        let Some(gesture) = self.gesture.take() else {
            return;
        };
        if let Some(rig) = self.rig.as_mut() {
            rig.end_drag(&self.doc.scene);
        }
        if keep {
            match gesture.continues {
                // One step back to before the edit the gesture continued.
                Some((_, before_edit)) => self.undo.push(&gesture.label, before_edit),
                None if gesture.before != Snapshot::of(&self.doc.scene) => {
                    self.undo.push(&gesture.label, gesture.before);
                }
                None => {}
            }
            if self.bind_after_gesture {
                self.start_bind("binding after the change");
            }
        } else {
            self.bind_after_gesture = false;
            if let Some((edit, before_edit)) = gesture.continues {
                self.undo.push(&edit, before_edit);
            }
            gesture.before.restore(&mut self.doc.scene);
            self.document_changed();
        }
    }

    /// Applies `change` to the scene as one undoable edit called `label` (part of the gesture
    /// in progress, if any); nothing is recorded when nothing changed.
    pub fn edit_scene<T>(
        &mut self,
        label: &str,
        change: impl FnOnce(&mut starcages_core::scene::Scene) -> T,
    ) -> T {
        let (out, changed) = self.undo_step(label, |state| change(&mut state.doc.scene));
        if changed {
            self.document_changed();
        }
        out
    }

    /// One undo step around `change`, the path every edit takes (scene edits through
    /// [`Self::edit_scene`], pose moves directly): the editable state before it is pushed under
    /// `label` when `change` altered it, unless a gesture runs (a gesture is one step, recorded
    /// when it ends). Returns what `change` returned and whether the state changed.
    pub fn undo_step<T>(&mut self, label: &str, change: impl FnOnce(&mut Self) -> T) -> (T, bool) {
        let before = Snapshot::of(&self.doc.scene);
        let out = change(self);
        let changed = Snapshot::of(&self.doc.scene) != before;
        if changed && self.gesture.is_none() {
            self.undo.push(label, before);
        }
        if changed {
            self.cancel_autorig_for_edit();
        }
        (out, changed)
    }

    /// What clicks and region drags select: the view's choice in Rig mode, cage vertices in
    /// Pose mode.
    pub fn select_element(&self) -> SelectElement {
        match self.mode {
            EditMode::Rig => self.view.select_element,
            EditMode::Pose => SelectElement::CageVertices,
        }
    }

    /// The cage vertex positions shown, picked and moved: the rest cages in Rig mode, the
    /// current pose in Pose mode.
    pub fn shown_positions(&self) -> &[DVec3] {
        match self.mode {
            EditMode::Rig => &self.doc.scene.cages.vertices,
            EditMode::Pose => &self.doc.scene.pose,
        }
    }

    /// Frames everything, or the selection.
    pub fn frame(&mut self, selection_only: bool) {
        let pose = self.shown_positions();
        let points: Vec<DVec3> = if selection_only && !self.selection.vertices.is_empty() {
            let selected = self.selection.vertices.iter();
            selected
                .filter_map(|&v| pose.get(v as usize).copied())
                .collect()
        } else {
            let mut all = pose.to_vec();
            let (lo, hi) = self.doc.scene.mesh.bounds();
            all.extend([lo, hi]);
            all.extend(self.deformed().iter().map(|p| p.as_dvec3()));
            all
        };
        let (lo, hi) = starcages_core::cage::bounds_of(&points);
        let pad = if selection_only { 0.2 } else { 0.0 };
        self.view
            .camera
            .frame(lo.as_vec3() - pad, hi.as_vec3() + pad);
    }

    /// Adds `path` to the recent files (and stores the list).
    pub fn remember(&mut self, path: &std::path::Path) {
        let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        self.recent.retain(|p| *p != path);
        self.recent.insert(0, path);
        self.recent.truncate(8);
        if let Some(file) = &self.recent_file {
            recent::store(file, &self.recent);
        }
    }

    /// Shows an error in the status bar.
    pub fn error(&mut self, error: EditorError) {
        self.message = Some(Message::new(error.to_string(), true));
    }

    /// Shows information in the status bar.
    pub fn info(&mut self, text: impl Into<String>) {
        self.message = Some(Message::new(text, false));
    }

    /// The deformed welded mesh (empty before the first bind).
    pub fn deformed(&self) -> &[Vec3] {
        self.rig.as_ref().map_or(&[], |r| r.deformed().as_slice())
    }

    /// The id of the gesture in progress.
    pub fn gesture_id(&self) -> Option<GestureId> {
        self.gesture.as_ref().map(|g| g.id)
    }

    /// Whether Pose mode is posing a rig with controls (internal cages): then the leaf
    /// vertices are drawn and picked as [`ViewState::leaf_vertices`] says.
    pub fn posing_controls(&self) -> bool {
        self.mode == EditMode::Pose && !self.doc.scene.cages.internals.is_empty()
    }

    /// Per cage vertex: whether clicks, regions and snapping may pick it (visible cages; in
    /// Pose mode with controls, not the leaf vertices when they are hidden).
    pub fn pickable(&self) -> Vec<bool> {
        let set = &self.doc.scene.cages;
        let mut pickable = self.view.pickable(set);
        if self.posing_controls() && self.view.leaf_vertices == view::LeafVertices::Hidden {
            for v in view::leaf_only_vertices(set) {
                if let Some(slot) = pickable.get_mut(v as usize) {
                    *slot = false;
                }
            }
        }
        pickable
    }

    /// Checks the invariants the UI relies on; the first broken one, described.
    pub fn check_invariants(&self) -> Result<(), String> {
        let scene = &self.doc.scene;
        let set = &scene.cages;
        let count = set.vertices.len();
        if !self.selection.is_valid_for(set) {
            return Err(format!("stale selection {:?}", self.selection));
        }
        if !self.view.is_valid_for(set) {
            return Err("a hidden cage does not resolve".into());
        }
        if scene.pose.len() != count {
            return Err(format!("pose has {} of {count} vertices", scene.pose.len()));
        }
        if let Some((name, _)) = scene.poses.iter().find(|(_, p)| p.len() != count) {
            return Err(format!("stored pose '{name}' has the wrong length"));
        }
        if let Some(name) = scene
            .pose_states
            .keys()
            .find(|n| !scene.poses.contains_key(*n))
        {
            return Err(format!("pose state '{name}' has no pose"));
        }
        for id in CageId::all(set) {
            let faces = id.faces(set).unwrap_or_default();
            if faces.iter().flatten().any(|&v| v as usize >= count) {
                return Err(format!("cage {id:?} names a vertex past the end"));
            }
        }
        if let Some(rig) = &self.rig {
            // Settled (no bind on its way, bound for these cages): the incremental DOFs and
            // mesh are a full deformation's.
            let settled = self.bind_job.is_none() && rig.is_current_for(scene);
            if settled && !rig.is_up_to_date(scene) {
                return Err("the live rig's DOFs or mesh differ from a full deformation".into());
            }
        }
        Ok(())
    }
}
