//! The editor's state and the operations on it (open, save, bind, edit, undo), separate from
//! how they are drawn (`panels`) and driven by the mouse (`interaction`).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use glam::{DVec3, Vec3};
use starcages_core::coords::CoordinateKind;
use starcages_core::hierarchy::{AutoInternalCage, Hierarchy, add_auto_internal_cage};
use starcages_core::io::{cage_set_obj_text, write_atomic, write_mesh};
use starcages_core::scene::{AutocageOptions, CageSet, Scene, SceneSettings};
use starcages_core::star::{StarBinding, single_cage_scene};
use starcages_viewport::influence::{self, MapValues};
use starcages_viewport::layers::CageStyle;
use starcages_viewport::{Layers, OrbitCamera};

use crate::document::Document;
use crate::interaction::{Drag, TransformTool};
use crate::jobs::{BindJob, Poll, Scope};
use crate::undo::{Snapshot, UndoStack};

/// The bound scene: mesh operator, hierarchy and the deformed mesh.
#[derive(Debug)]
pub struct Rig {
    /// The mesh binding (weights, computed once per bind).
    pub binding: Arc<StarBinding>,
    /// Internal cages.
    pub hierarchy: Hierarchy,
    /// Deformed welded mesh positions, updated incrementally.
    pub deformed: Arc<Vec<Vec3>>,
    /// Degrees of freedom of the current pose (for GPU deformation).
    pub dofs: Arc<Vec<Vec3>>,
    /// The cages and settings this binding is for.
    pub bound_for: (CageSet, SceneSettings),
}

/// Which influence map is painted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InfluenceChoice {
    /// None: the studio mesh.
    #[default]
    None,
    /// b of the selected leaf cage.
    SelectedCage,
    /// b of every leaf cage.
    AllCages,
    /// W(v, p) of the selected cage vertex.
    JoinWeight,
    /// Difference to a single cage of this kind.
    Difference(CoordinateKind),
}

/// What the user sees and has selected.
#[derive(Debug, Clone)]
pub struct ViewState {
    /// The camera.
    pub camera: OrbitCamera,
    /// Layers and shading.
    pub layers: Layers,
    /// Hidden cages, selected and hovered vertices, level focus.
    pub style: CageStyle,
    /// The cage shown in the inspector (leaves, then internal cages).
    pub selected_cage: Option<usize>,
    /// The influence map.
    pub influence: InfluenceChoice,
    /// Moving a vertex moves its mirror partner across x = 0.
    pub mirror_x: bool,
    /// The viewport's rectangle last frame (points).
    pub viewport: egui::Rect,
}

/// A message in the status bar.
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    /// The text.
    pub text: String,
    /// An error (red) or information.
    pub error: bool,
}

/// Timings and sizes shown in the stats panel (the paper's Table II columns).
#[derive(Debug, Clone, Copy, Default)]
pub struct Stats {
    /// Seconds of the last bind.
    pub bind_seconds: f64,
    /// Milliseconds of the last deformation update (CPU, incremental).
    pub deform_ms: f64,
    /// Milliseconds between the last two frames.
    pub frame_ms: f64,
}

/// An action waiting for the user's answer about unsaved changes.
#[derive(Debug, Clone, PartialEq)]
pub enum Pending {
    /// Open this file.
    Open(PathBuf),
    /// Close the window.
    Close,
    /// Create a new scene around a mesh.
    NewFromMesh(PathBuf, AutocageOptions),
}

/// Change counters telling the viewport what to upload again.
#[derive(Debug, Clone, Copy, Default)]
pub struct Generations {
    /// The bound mesh.
    pub mesh: u64,
    /// The deformation.
    pub deformation: u64,
    /// The edit state (cages and settings), for stale bind results.
    pub edit: u64,
}

/// The editor.
pub struct EditorApp {
    /// The open document.
    pub doc: Document,
    /// Its binding, once bound.
    pub rig: Option<Rig>,
    /// A bind in progress.
    pub job: Option<BindJob>,
    /// A file being opened.
    pub load: Option<crate::jobs::LoadJob>,
    /// View and selection.
    pub view: ViewState,
    /// Undo and redo.
    pub undo: UndoStack,
    /// The status message.
    pub message: Option<Message>,
    /// A G / R / S transform in progress.
    pub tool: Option<TransformTool>,
    /// A mouse drag in the viewport.
    pub drag: Option<Drag>,
    /// Timings.
    pub stats: Stats,
    /// Change counters.
    pub generations: Generations,
    /// An action awaiting the unsaved-changes answer.
    pub pending: Option<Pending>,
    /// Recently opened or saved scenes, newest first.
    pub recent: Vec<PathBuf>,
    /// Where the recent list is kept (none in tests).
    pub recent_file: Option<PathBuf>,
    /// Name typed for a new pose.
    pub new_pose_name: String,
    /// Whether the 3D view can draw (wgpu available).
    pub gpu: bool,
    /// The window may close even with unsaved changes.
    pub allow_close: bool,
    /// Show measured times in the stats panel (off for reproducible snapshots).
    pub show_timings: bool,
    /// Wakes the UI from worker threads.
    pub(crate) repaint: Option<egui::Context>,
    pub(crate) last_frame: Option<Instant>,
    pub(crate) map_cache: MapCache,
    pub(crate) mesh_upload: Option<(u64, Arc<crate::viewport::MeshUpload>)>,
    /// The scene before a slider drag (one undo step per drag).
    pub(crate) drag_before: Option<Snapshot>,
    /// The automatic-cages dialog of File ▸ New from mesh, while open.
    pub new_mesh_dialog: Option<(PathBuf, AutocageOptions)>,
}

/// What an influence map depends on: the choice, the inspected cage, the single selected
/// vertex, the mesh generation and (for difference maps) the deformation generation.
pub(crate) type MapKey = (InfluenceChoice, Option<usize>, Option<u32>, u64, u64);

/// The painted influence map and what it was computed from.
#[derive(Default)]
pub(crate) struct MapCache {
    pub key: Option<MapKey>,
    pub values: Option<MapValues>,
    pub colors: Option<(u64, Arc<Vec<[u8; 4]>>)>,
    pub single: Option<(CoordinateKind, u64, Arc<StarBinding>)>,
}

impl EditorApp {
    /// An editor on `doc`, binding it in the background.
    pub fn new(doc: Document, repaint: Option<egui::Context>, gpu: bool) -> Self {
        let mut camera = OrbitCamera::default();
        let (lo, hi) = doc.scene.mesh.bounds();
        let (clo, chi) = starcages_core::cage::bounds_of(&doc.scene.pose);
        camera.frame(lo.min(clo).as_vec3(), hi.max(chi).as_vec3());
        let mut app = Self {
            doc,
            rig: None,
            job: None,
            load: None,
            view: ViewState {
                camera,
                layers: Layers::default(),
                style: CageStyle::default(),
                selected_cage: None,
                influence: InfluenceChoice::None,
                mirror_x: false,
                viewport: egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(800.0, 600.0)),
            },
            undo: UndoStack::default(),
            message: None,
            tool: None,
            drag: None,
            stats: Stats::default(),
            generations: Generations::default(),
            pending: None,
            recent: Vec::new(),
            recent_file: None,
            new_pose_name: String::new(),
            gpu,
            allow_close: false,
            show_timings: true,
            repaint,
            last_frame: None,
            map_cache: MapCache::default(),
            mesh_upload: None,
            drag_before: None,
            new_mesh_dialog: None,
        };
        app.start_bind("binding the scene");
        app
    }

    /// Starts binding the current scene on a worker thread, as much as changed since the
    /// current binding (the old binding stays in use meanwhile).
    pub fn start_bind(&mut self, label: &str) {
        if let Some(job) = self.job.take() {
            job.cancel();
        }
        let scope = self
            .rig
            .as_ref()
            .map_or(Scope::Full, |rig| rebind_scope(rig, &self.doc.scene));
        self.generations.edit += 1;
        let wake = self.repaint.clone();
        self.job = Some(BindJob::start(
            self.doc.scene.clone(),
            scope,
            self.generations.edit,
            label,
            move || {
                if let Some(ctx) = &wake {
                    ctx.request_repaint();
                }
            },
        ));
    }

    /// Takes a finished bind, if any; returns whether one was installed.
    pub fn poll_bind(&mut self) -> bool {
        let Some(job) = &self.job else {
            return false;
        };
        match job.poll() {
            Poll::Running(_) => false,
            Poll::Done(result) => {
                self.job = None;
                self.finish_bind(*result)
            }
        }
    }

    /// Blocks until the running bind ends and installs it (tests, headless use).
    pub fn wait_for_bind(&mut self) -> bool {
        match self.job.take() {
            Some(job) => {
                let result = job.wait();
                self.finish_bind(result)
            }
            None => false,
        }
    }

    fn finish_bind(&mut self, result: Result<crate::jobs::Bound, String>) -> bool {
        match result {
            Ok(bound) if bound.generation == self.generations.edit => {
                let mut hierarchy = bound.hierarchy;
                // The pose may have changed while binding: follow the current state.
                if let Err(e) = hierarchy.restore(&self.doc.scene.pose_state) {
                    self.error(format!("the pose's hierarchy state was reset: {e}"));
                    self.doc.scene.pose_state = hierarchy.state();
                }
                self.stats.bind_seconds = bound.seconds;
                let same_mesh = self
                    .rig
                    .as_ref()
                    .is_some_and(|rig| Arc::ptr_eq(&rig.binding, &bound.binding));
                self.rig = Some(Rig {
                    binding: bound.binding,
                    hierarchy,
                    deformed: Arc::new(Vec::new()),
                    dofs: Arc::new(Vec::new()),
                    bound_for: bound.bound_for,
                });
                if !same_mesh {
                    self.generations.mesh += 1;
                }
                self.redeform_all();
                self.map_cache = MapCache::default();
                true
            }
            Ok(_) => false, // a newer edit superseded it
            Err(e) => {
                self.error(format!(
                    "binding failed: {e}. The previous binding stays in use; undo (Ctrl+Z) the last change or fix the scene."
                ));
                false
            }
        }
    }

    /// Recomputes the whole deformed mesh from the current pose.
    pub fn redeform_all(&mut self) {
        let Some(rig) = &mut self.rig else {
            return;
        };
        let start = Instant::now();
        let scene = &self.doc.scene;
        rig.dofs = Arc::new(
            rig.binding
                .operator
                .dofs(&scene.cages.vertices, &scene.pose),
        );
        rig.deformed = Arc::new(rig.binding.deform(&scene.cages.vertices, &scene.pose));
        self.stats.deform_ms = start.elapsed().as_secs_f64() * 1e3;
        self.generations.deformation += 1;
    }

    /// Hand moves (vertex, new position), propagated down the hierarchy; the mesh follows
    /// incrementally (only the rows the moved vertices touch).
    pub fn apply_moves(&mut self, moves: &[(u32, DVec3)]) {
        let moves = self.with_mirror(moves);
        let Some(rig) = &mut self.rig else {
            self.error("the scene is still being bound; try again in a moment".into());
            return;
        };
        let scene = &mut self.doc.scene;
        let changed = match rig.hierarchy.apply(&mut scene.pose, &moves) {
            Ok(changed) => changed,
            Err(e) => {
                self.message = Some(Message {
                    text: e.to_string(),
                    error: true,
                });
                return;
            }
        };
        scene.pose_state = rig.hierarchy.state();
        self.doc.dirty = true;
        if changed.is_empty() {
            return;
        }
        let start = Instant::now();
        let operator = &rig.binding.operator;
        let dofs = operator.dofs(&scene.cages.vertices, &scene.pose);
        let rows = operator.rows_touched(&operator.columns_of_moved_vertices(&changed));
        let deformed = Arc::make_mut(&mut rig.deformed);
        if deformed.len() == operator.row_count() {
            operator.apply_rows(&rows, &dofs, deformed);
        }
        rig.dofs = Arc::new(dofs);
        self.stats.deform_ms = start.elapsed().as_secs_f64() * 1e3;
        self.generations.deformation += 1;
    }

    /// `moves` plus the mirror partners' moves when X mirroring is on.
    fn with_mirror(&self, moves: &[(u32, DVec3)]) -> Vec<(u32, DVec3)> {
        if !self.view.mirror_x {
            return moves.to_vec();
        }
        let partners = crate::mirror::partners(&self.doc.scene.cages.vertices);
        let moving: std::collections::BTreeSet<u32> = moves.iter().map(|m| m.0).collect();
        let mut out = moves.to_vec();
        for &(v, p) in moves {
            match partners.get(v as usize).copied().flatten() {
                Some(partner) if partner == v => {
                    // On the mirror plane: stays on it.
                    if let Some(last) = out.iter_mut().find(|m| m.0 == v) {
                        last.1.x = self.doc.scene.pose[v as usize].x;
                    }
                }
                Some(partner) if !moving.contains(&partner) => {
                    out.push((partner, DVec3::new(-p.x, p.y, p.z)));
                }
                _ => {}
            }
        }
        out
    }

    /// Records the state before an edit called `label` for undo.
    pub fn checkpoint(&mut self, label: &str) {
        self.undo.push(label, Snapshot::of(&self.doc.scene));
    }

    /// After the scene's state was replaced (an edit, undo, redo, cancel, pose switch): binds
    /// again what the change affects (see [`rebind_scope`]), else restores the hierarchy state
    /// and redeforms.
    pub fn state_replaced(&mut self) {
        self.doc.dirty = true;
        let changed = match &self.rig {
            Some(rig) => rig.bound_for != (self.doc.scene.cages.clone(), self.doc.scene.settings),
            None => true,
        };
        if changed || self.job.is_some() {
            self.start_bind("binding after the change");
            return;
        }
        if let Some(rig) = &mut self.rig
            && let Err(e) = rig.hierarchy.restore(&self.doc.scene.pose_state)
        {
            self.message = Some(Message {
                text: format!("hierarchy state could not be restored: {e}"),
                error: true,
            });
        }
        self.redeform_all();
    }

    /// Undoes the last edit.
    pub fn undo(&mut self) {
        self.tool = None;
        match self.undo.undo(&mut self.doc.scene) {
            Some(label) => {
                self.info(format!("undid: {label}"));
                self.state_replaced();
            }
            None => self.info("nothing to undo".into()),
        }
    }

    /// Redoes the last undone edit.
    pub fn redo(&mut self) {
        self.tool = None;
        match self.undo.redo(&mut self.doc.scene) {
            Some(label) => {
                self.info(format!("redid: {label}"));
                self.state_replaced();
            }
            None => self.info("nothing to redo".into()),
        }
    }

    /// Changes leaf or internal cage `cage`'s coordinates (an undoable edit that rebinds).
    pub fn set_cage_kind(&mut self, cage: usize, kind: CoordinateKind) {
        let leaves = self.doc.scene.cages.leaves.len();
        let current = if cage < leaves {
            self.doc.scene.cages.leaves[cage].kind
        } else {
            self.doc.scene.cages.internals[cage - leaves].kind
        };
        if current == kind {
            return;
        }
        self.checkpoint("change coordinates");
        if cage < leaves {
            self.doc.scene.cages.leaves[cage].kind = kind;
        } else {
            self.doc.scene.cages.internals[cage - leaves].kind = kind;
        }
        self.state_replaced();
    }

    /// Applies a settings change made by `change` as one undoable edit, then rebinds.
    pub fn edit_scene(&mut self, label: &str, change: impl FnOnce(&mut Scene)) {
        let before = Snapshot::of(&self.doc.scene);
        change(&mut self.doc.scene);
        if Snapshot::of(&self.doc.scene) != before {
            self.undo.push(label, before);
            self.state_replaced();
        }
    }

    /// Replaces the document (new or opened), keeping app-wide settings.
    pub fn replace_document(&mut self, doc: Document) {
        let gpu = self.gpu;
        let repaint = self.repaint.take();
        let recent = std::mem::take(&mut self.recent);
        let recent_file = self.recent_file.take();
        let (layers, viewport, show_timings) =
            (self.view.layers, self.view.viewport, self.show_timings);
        *self = Self::new(doc, repaint, gpu);
        self.recent = recent;
        self.recent_file = recent_file;
        self.view.layers = layers;
        self.view.viewport = viewport;
        self.show_timings = show_timings;
    }

    /// A new scene from the mesh at `path` in automatic grid cages.
    pub fn new_from_mesh(&mut self, path: &Path, options: &AutocageOptions) {
        match crate::document::scene_from_mesh(path, options) {
            Ok(scene) => {
                self.replace_document(Document {
                    scene,
                    path: None,
                    dirty: true,
                });
                self.info(format!("new scene around {}", path.display()));
            }
            Err(e) => self.error(format!("could not read the mesh: {e}")),
        }
    }

    /// Adds a box internal cage owning the selected vertices (an undoable hierarchy edit).
    pub fn add_internal_cage_around_selection(&mut self, kind: CoordinateKind) {
        let vertices: Vec<u32> = self.view.style.selected.iter().copied().collect();
        let taken: Vec<&str> = self.doc.scene.cages.cage_names();
        let name = (1..)
            .map(|i| format!("internal_{i}"))
            .find(|n| !taken.contains(&n.as_str()))
            .unwrap_or_default();
        let options = AutoInternalCage {
            name: name.clone(),
            kind,
            ..AutoInternalCage::default()
        };
        let mut result = Ok(0);
        self.edit_scene("add internal cage", |scene| {
            result = add_auto_internal_cage(scene, &options, &vertices);
        });
        match result {
            Ok(_) => self.info(format!(
                "added internal cage '{name}' owning {} vertices",
                vertices.len()
            )),
            Err(e) => self.error(e.to_string()),
        }
    }

    /// Starts opening a file (scene or mesh) on a worker thread; the current document stays
    /// until it has loaded, and stays for good if it fails.
    pub fn open(&mut self, path: &Path) {
        let wake = self.repaint.clone();
        self.load = Some(crate::jobs::LoadJob::start(path.to_path_buf(), move || {
            if let Some(ctx) = &wake {
                ctx.request_repaint();
            }
        }));
        self.info(format!("opening {}...", path.display()));
    }

    /// Takes a finished load, if any (`wait` blocks until it ends); returns whether a new
    /// document was installed.
    pub fn poll_load(&mut self, wait: bool) -> bool {
        let Some(job) = &self.load else {
            return false;
        };
        let result = if wait {
            self.load.take().map(crate::jobs::LoadJob::wait)
        } else {
            let result = job.poll();
            if result.is_some() {
                self.load = None;
            }
            result
        };
        let Some(result) = result else {
            return false;
        };
        match result {
            Ok(doc) => {
                let path = doc.path.clone();
                self.replace_document(doc);
                if let Some(path) = path {
                    self.remember(&path);
                    self.info(format!("opened {}", path.display()));
                }
                true
            }
            Err(e) => {
                self.error(format!(
                    "could not open {e}. The current scene is unchanged."
                ));
                false
            }
        }
    }

    /// Saves to `path` (atomically).
    pub fn save_as(&mut self, path: &Path) -> bool {
        match self.doc.save_as(path) {
            Ok(()) => {
                self.remember(path);
                self.info(format!("saved {}", path.display()));
                true
            }
            Err(e) => {
                self.error(format!("could not save: {e}. Nothing was overwritten."));
                false
            }
        }
    }

    /// Writes the deformed mesh (OBJ or GLB, normals recomputed).
    pub fn export_mesh(&mut self, path: &Path) {
        let Some(rig) = &self.rig else {
            self.error("nothing to export before the scene is bound".into());
            return;
        };
        let welded: Vec<DVec3> = rig.deformed.iter().map(|p| p.as_dvec3()).collect();
        let mesh = &self.doc.scene.mesh;
        match write_mesh(path, mesh, &mesh.unweld(&welded)) {
            Ok(()) => self.info(format!("exported {}", path.display())),
            Err(e) => self.error(e.to_string()),
        }
    }

    /// Writes the cages in the current pose as OBJ.
    pub fn export_cages(&mut self, path: &Path) {
        let text = cage_set_obj_text(&self.doc.scene.cages, &self.doc.scene.pose);
        match write_atomic(path, text.as_bytes()) {
            Ok(()) => self.info(format!("exported {}", path.display())),
            Err(e) => self.error(e.to_string()),
        }
    }

    fn remember(&mut self, path: &Path) {
        let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        self.recent.retain(|p| *p != path);
        self.recent.insert(0, path);
        self.recent.truncate(8);
        if let Some(file) = &self.recent_file {
            crate::recent::store(file, &self.recent);
        }
    }

    /// Shows an error in the status bar.
    pub fn error(&mut self, text: String) {
        self.message = Some(Message { text, error: true });
    }

    /// Shows information in the status bar.
    pub fn info(&mut self, text: String) {
        self.message = Some(Message { text, error: false });
    }

    /// The deformed welded mesh (empty before the first bind).
    pub fn deformed(&self) -> &[Vec3] {
        self.rig.as_ref().map_or(&[], |r| r.deformed.as_slice())
    }

    /// Per-vertex colours of the chosen influence map, recomputed only when its inputs change.
    pub(crate) fn map_colors(&mut self) -> Option<(u64, Arc<Vec<[u8; 4]>>)> {
        let rig = self.rig.as_ref()?;
        let selected_vertex = (self.view.style.selected.len() == 1)
            .then(|| self.view.style.selected.iter().next().copied())
            .flatten();
        let deformation = match self.view.influence {
            InfluenceChoice::Difference(_) => self.generations.deformation,
            _ => 0,
        };
        let key = (
            self.view.influence,
            self.view.selected_cage,
            selected_vertex,
            self.generations.mesh,
            deformation,
        );
        if self.map_cache.key == Some(key) {
            return self.map_cache.colors.clone();
        }
        let leaves = self.doc.scene.cages.leaves.len();
        let values = match self.view.influence {
            InfluenceChoice::None => None,
            InfluenceChoice::AllCages => Some(influence::boundary(&rig.binding, None)),
            InfluenceChoice::SelectedCage => self
                .view
                .selected_cage
                .filter(|&c| c < leaves)
                .map(|c| influence::boundary(&rig.binding, Some(c))),
            InfluenceChoice::JoinWeight => {
                selected_vertex.map(|v| influence::join_weight(&rig.binding, v))
            }
            InfluenceChoice::Difference(kind) => {
                let single = match &self.map_cache.single {
                    Some((k, g, b)) if *k == kind && *g == self.generations.mesh => Arc::clone(b),
                    _ => {
                        let scene = single_cage_scene(&self.doc.scene, kind);
                        match StarBinding::bind_scene(&scene, &Default::default()) {
                            Ok(b) => {
                                let b = Arc::new(b);
                                self.map_cache.single =
                                    Some((kind, self.generations.mesh, Arc::clone(&b)));
                                b
                            }
                            Err(e) => {
                                self.error(format!("single-cage baseline: {e}"));
                                return None;
                            }
                        }
                    }
                };
                let scene = &self.doc.scene;
                let other = single.deform(&scene.cages.vertices, &scene.pose);
                Some(influence::difference(self.deformed(), &other).0)
            }
        };
        let count = self.deformed().len();
        let colors = influence::vertex_colors(values.as_ref().map(|m| m.values.as_slice()), count);
        let generation = self.map_cache.colors.as_ref().map_or(0, |c| c.0 + 1);
        self.map_cache.key = Some(key);
        self.map_cache.values = values;
        self.map_cache.colors = Some((generation, Arc::new(colors)));
        self.map_cache.colors.clone()
    }

    /// The painted map's values and legend, if any.
    pub fn map_values(&self) -> Option<&MapValues> {
        self.map_cache.values.as_ref()
    }
}

/// How much of `rig` must be bound again for `scene`: nothing new is a full bind only when the
/// geometry, the hierarchy's structure or the settings changed; a leaf cage's kind, h or border
/// h changes only its own mesh rows; internal cages change only the hierarchy.
pub fn rebind_scope(rig: &Rig, scene: &Scene) -> Scope {
    let (bound, settings) = &rig.bound_for;
    let now = &scene.cages;
    if *settings != scene.settings
        || bound.vertices != now.vertices
        || bound.leaves.len() != now.leaves.len()
        || bound.internals.len() != now.internals.len()
    {
        return Scope::Full;
    }
    let mut leaves = Vec::new();
    for (i, (a, b)) in bound.leaves.iter().zip(&now.leaves).enumerate() {
        if a.faces != b.faces || a.name != b.name {
            return Scope::Full;
        }
        if a != b {
            leaves.push(i);
        }
    }
    if leaves.is_empty() {
        Scope::Hierarchy(Arc::clone(&rig.binding))
    } else {
        Scope::Leaves(Arc::clone(&rig.binding), leaves)
    }
}
