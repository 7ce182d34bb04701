//! Everything a user can do, as values: the UI sends [`Command`]s, and [`apply`] — the one
//! place that changes the editor's state — carries them out once per frame. [`UiCommand`] is
//! the table of menu and keyboard actions (label, tooltip, shortcut).

mod animation;
mod apply;
mod files;
mod history;
mod jobs;
mod pose;
mod rig;
mod selection;
mod table;
mod view;

use std::path::PathBuf;

use glam::{DVec3, Vec2};
use starcages_core::coords::CoordinateKind;
use starcages_core::scene::SceneSettings;
use starcages_viewport::{Layers, View};

use crate::state::{CageId, GestureId, InfluenceChoice, NewMeshOptions, ScreenRect, SelectMode};

pub use apply::{apply, apply_all};

/// What applying a command asks of the UI, returned by [`apply`]: the state holds no UI
/// tools, so a command that continues as one (E, then its grab) says so here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    /// Start G on the selection, locked to this world axis (0, 1, 2): E's extrusion continues
    /// as a grab along the face's normal, as in Blender.
    GrabAlong(usize),
}
pub use table::{ToolKey, UiCommand};

/// The answer to "unsaved changes: save first?".
#[derive(Debug, Clone, PartialEq)]
pub enum UnsavedAnswer {
    /// Save (to this file, or to the document's own), then go on.
    Save(Option<PathBuf>),
    /// Go on without saving.
    Discard,
    /// Do nothing.
    Cancel,
}

/// A change of the camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CameraChange {
    /// Orbit by a pointer move (points).
    Orbit(Vec2),
    /// Pan by a pointer move (points).
    Pan(Vec2),
    /// Zoom by wheel steps towards the cursor (in viewport points), if any.
    Zoom {
        /// Wheel steps (positive: closer).
        steps: f32,
        /// The cursor in the viewport.
        cursor_in_viewport: Option<Vec2>,
    },
    /// A standard view (front, side, top and their opposites).
    View(View),
    /// Perspective ↔ orthographic projection.
    ToggleOrthographic,
    /// Frame everything.
    FrameAll,
    /// Frame the selected vertices.
    FrameSelection,
}

/// One thing a user does.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Open a scene or a mesh (asks first when there are unsaved changes).
    Open(PathBuf),
    /// Open a generated demo scene by name (asks first when there are unsaved changes).
    OpenDemo(String),
    /// A new scene around a mesh in the auto rig or a grid of cages, made on a worker (asks
    /// first over unsaved changes).
    NewFromMesh(PathBuf, NewMeshOptions),
    /// Rig ▸ Auto rig: replace the rig with the auto rig of the mesh (on a worker; one undo
    /// step when it arrives).
    AutoRig {
        /// How fine, 1 to 5.
        detail: u32,
        /// Also the controls: one per limb segment, turning about its joint, and `root`.
        controls: bool,
        /// A plane the rig is a mirror image of itself across (scene axes, Z-up).
        mirror: starcages_core::generate::Mirror,
    },
    /// Stop the auto rig in progress.
    CancelAutoRig,
    /// Save to the document's file (the UI asks for one with [`Command::SaveAs`] when there is
    /// none).
    Save,
    /// Save to this file.
    SaveAs(PathBuf),
    /// Write the deformed mesh (OBJ or GLB).
    ExportMesh(PathBuf),
    /// Write the posed cages (OBJ).
    ExportCages(PathBuf),
    /// Add the cages of an OBJ file (one leaf cage per `o`/`g` group, in the mesh file's axes)
    /// to the rig.
    ImportCages(PathBuf),
    /// Add the cages of an OBJ file as internal cages (each drives the free cage vertices
    /// inside it), one undo step.
    ImportInternalCages(PathBuf),
    /// The answer to the unsaved-changes prompt.
    AnswerUnsaved(UnsavedAnswer),
    /// The window wants to close (asks first over unsaved changes).
    RequestClose,
    /// Stop opening a file.
    CancelLoad,
    /// Stop the bind in progress (the binding in use stays).
    CancelBind,
    /// Stop binding the difference map's baseline.
    CancelBaseline,
    /// Undo the last edit (a gesture in progress is cancelled instead).
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Start a gesture: what follows until [`Command::EndGesture`] is one undo step.
    BeginGesture {
        /// Its id, chosen by the UI.
        id: GestureId,
        /// The undo label.
        label: String,
    },
    /// End the gesture, keeping its changes or going back.
    EndGesture {
        /// Keep (one undo step) or revert.
        keep: bool,
    },
    /// Move cage vertices to new positions (a hand edit, propagated down the hierarchy).
    MoveVertices(Vec<(u32, DVec3)>),
    /// Move cage vertices' rest positions (the binding): the current pose and every stored
    /// pose move them by the same amount, so poses keep their displacement from rest. Only
    /// the rows the edit can change are bound again.
    MoveRestVertices(Vec<(u32, DVec3)>),
    /// Change a cage's coordinates.
    SetCageKind(CageId, CoordinateKind),
    /// Set a leaf cage's h (`None`: the scene's default).
    SetCageH {
        /// The leaf cage.
        leaf: usize,
        /// Its h.
        h: Option<f64>,
    },
    /// Set (or remove, with `None`) a leaf cage's h on its border with a neighbour.
    SetBorderH {
        /// The leaf cage.
        leaf: usize,
        /// The neighbour's name.
        neighbour: String,
        /// The border's h.
        h: Option<f64>,
    },
    /// Change the scene settings.
    SetSettings {
        /// The undo label.
        label: String,
        /// The new settings.
        settings: SceneSettings,
    },
    /// Add a box internal cage around the selected vertices.
    AddInternalCage(CoordinateKind),
    /// Remove an internal cage (what it owned becomes free).
    RemoveInternalCage(usize),
    /// Store the current pose under a name.
    StorePose(String),
    /// Switch to a stored pose, or to rest with `None`.
    SwitchPose(Option<String>),
    /// Delete a stored pose.
    DeletePose(String),
    /// Go to a frame of the animation (not an undo step).
    SetFrame(f64),
    /// Start or stop playback.
    SetPlaying(bool),
    /// Key the current pose at the current frame (updating the key there, if any).
    InsertKey,
    /// Delete the key at this frame.
    DeleteKey(f64),
    /// Move the key at `from` to `to` (retime).
    MoveKey {
        /// Its frame now.
        from: f64,
        /// Its new frame.
        to: f64,
    },
    /// How the key at `frame` moves on to the next one.
    SetKeyInterpolation {
        /// The key's frame.
        frame: f64,
        /// Its interpolation.
        interpolation: starcages_core::anim::Interpolation,
    },
    /// Frame rate and playback range.
    SetAnimationRange {
        /// Frames per second.
        fps: f64,
        /// First frame.
        start: i64,
        /// Last frame.
        end: i64,
    },
    /// Auto-key on or off.
    SetAutoKey(bool),
    /// Turn a cage point cache (PC2 or MDD from another tool, in the order and axes of
    /// Export cages) into keys, one per sample (one undo step).
    ImportCageAnimation(PathBuf),
    /// Select vertices.
    Select {
        /// The picked vertices.
        vertices: Vec<u32>,
        /// How they combine with the selection.
        mode: SelectMode,
    },
    /// Select every vertex of a drawn cage.
    SelectAll,
    /// Clear the selection.
    SelectNone,
    /// Show a cage in the inspector and select its vertices (`None`: inspect nothing).
    InspectCage(Option<CageId>),
    /// The vertex under the cursor.
    Hover(Option<u32>),
    /// Hide or show a cage.
    SetCageHidden(CageId, bool),
    /// Layers and shading.
    SetLayers(Layers),
    /// Ghosts of the animation.
    SetGhosts(crate::state::GhostSettings),
    /// The influence map.
    SetInfluence(InfluenceChoice),
    /// X mirror editing on or off.
    SetMirrorX(bool),
    /// Snapping to cage vertices while moving on or off.
    SetSnapToVertices(bool),
    /// What R and S turn and scale about (a tool setting: not an undo step, as in Blender).
    SetPivotPoint(crate::state::PivotPoint),
    /// Places the 3D cursor (scene coordinates).
    SetCursor(DVec3),
    /// How Pose mode draws the leaf vertices of a rig with controls.
    SetLeafVertices(crate::state::LeafVertices),
    /// Move the camera.
    Camera(CameraChange),
    /// Where the viewport is on screen.
    SetViewport(ScreenRect),
    /// Show a message in the status bar (why a key did nothing, say).
    Info(String),
    /// Switch between Pose mode and Rig mode.
    SetMode(crate::state::EditMode),
    /// A rig operation on the rest cages (one undo step).
    Rig(starcages_core::rig::RigOp),
    /// Several rig operations applied whole or not at all, as one undo step (E on several
    /// faces).
    RigOps(Vec<starcages_core::rig::RigOp>),
    /// Select leaf-cage faces (cage index, face index): their corners join the vertex
    /// selection.
    SelectFaces {
        /// The faces.
        faces: Vec<(usize, usize)>,
        /// How they combine with the selection.
        mode: crate::state::SelectMode,
    },
    /// What clicks and region drags select in Rig mode.
    SetSelectElement(crate::state::SelectElement),
    /// Select mesh vertices (mesh select mode).
    SelectMeshVertices {
        /// Their indices (welded mesh vertices).
        vertices: Vec<u32>,
        /// How they combine with the mesh selection.
        mode: crate::state::SelectMode,
    },
}

/// Collects the commands the UI sends during a frame.
#[derive(Debug, Default)]
pub struct CommandSender {
    queue: Vec<Command>,
}

impl CommandSender {
    /// Queues `command` for the end of the frame.
    pub fn send(&mut self, command: Command) {
        self.queue.push(command);
    }

    /// Takes the queued commands.
    pub fn take(&mut self) -> Vec<Command> {
        std::mem::take(&mut self.queue)
    }

    /// Whether nothing is queued.
    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }
}
