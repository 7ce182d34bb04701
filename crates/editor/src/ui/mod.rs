//! The UI: panels, the viewport's input and drawing, keyboard shortcuts, prompts. It reads
//! [`EditorState`] and sends [`Command`]s; it never changes the document. What is transient
//! input — a drag in progress, the G / R / S tool, text being typed — lives here in
//! [`UiState`].

mod actions;
mod add_menu;
pub mod axis_gizmo;
mod control_handles;
pub mod file_dialog;
mod help;
mod inset_tool;
mod inspector;
mod item_panel;
mod keyboard;
mod loop_cut_tool;
mod menu;
mod outliner;
mod panels;
mod picking;
pub mod prompts;
mod rig_keys;
mod select_modes;
mod shading;
mod status_bar;
mod timeline;
mod transform_tool;
mod viewport_input;
pub mod viewport_paint;

use std::path::PathBuf;
use std::time::Instant;

use egui::Panel;

use crate::commands::{Command, CommandSender};
use crate::state::{EditorState, GestureId, NewMeshOptions};

pub use picking::{mesh_point_under, pick, vertex_on_screen};
pub use transform_tool::{Axis, Mode, TransformTool};
pub use viewport_input::Drag;

/// Transient UI state: input in progress and what is typed, never the document.
#[derive(Debug)]
pub struct UiState {
    /// A mouse drag in the viewport.
    pub drag: Option<Drag>,
    /// A G / R / S transform in progress.
    pub tool: Option<TransformTool>,
    /// Ctrl+R's loop cut while it is being placed.
    pub loop_cut: Option<loop_cut_tool::LoopCutTool>,
    /// I's inset being sized, if any.
    pub inset: Option<inset_tool::InsetTool>,
    /// Shift+A's add menu, open at this screen point (points).
    pub add_menu: Option<glam::Vec2>,
    /// The name typed for a new pose.
    pub new_pose_name: String,
    /// File dialogs: native on a worker, or in-app where no native one can be shown.
    pub files: file_dialog::FileDialogs,
    /// The automatic-cages dialog of File ▸ New from mesh, while open.
    pub new_mesh_dialog: Option<(PathBuf, NewMeshOptions)>,
    /// A slider drag in progress (one undo step).
    pub slider_gesture: Option<GestureId>,
    /// The Item panel (N) is shown.
    pub show_item_panel: bool,
    /// The left panel (the outliner) is wanted (T); a narrow window may still hide it.
    pub show_outliner: bool,
    /// The right panel (properties) is wanted (Shift+T); a narrow window may still hide it.
    pub show_properties: bool,
    /// The keyboard shortcuts window (F1) is shown.
    pub show_shortcuts: bool,
    /// Give up the keyboard focus egui moved on Tab (next frame).
    drop_focus: bool,
    /// A question about poses, while open.
    pub pose_prompt: Option<panels::PosePrompt>,
    /// What the last commands asked of the UI (E's grab), carried out next frame.
    pub effects: Vec<crate::commands::Effect>,
    /// The influence map shown before an h slider drag switched to the cage's b map.
    pub influence_before_h_drag: Option<crate::state::InfluenceChoice>,
    /// Rig ▸ Auto rig's dialog, while open.
    pub autorig_dialog: Option<prompts::AutorigDialog>,
    /// The key picked on the timeline (its frame), if any.
    pub selected_key: Option<f64>,
    /// A key being dragged along the timeline.
    pub key_drag: Option<timeline::KeyDrag>,
    /// Show measured times in the stats panel (off for reproducible snapshots).
    pub show_timings: bool,
    /// Whether the 3D view can draw (wgpu available).
    pub gpu: bool,
    /// Milliseconds between the last two frames.
    pub frame_ms: f64,
    last_frame: Option<Instant>,
    next_gesture: u64,
    mesh_upload: viewport_paint::MeshUploadCache,
    /// The ghosts drawn last.
    ghosts: viewport_paint::GhostCache,
    /// The mesh the look was uploaded over.
    look_upload: viewport_paint::LookUploadCache,
}

impl UiState {
    /// Whether a dialog is open (a file dialog, New from mesh, Auto rig, a question about poses
    /// or unsaved changes): the editor's shortcuts wait until it is answered.
    pub fn dialog_open(&self, state: &EditorState) -> bool {
        self.files.is_open()
            || self.new_mesh_dialog.is_some()
            || self.autorig_dialog.is_some()
            || self.pose_prompt.is_some()
            || state.pending.is_some()
    }

    /// A UI with nothing in progress; `gpu`: whether the 3D view can draw.
    pub fn new(gpu: bool) -> Self {
        Self {
            drag: None,
            tool: None,
            loop_cut: None,
            inset: None,
            add_menu: None,
            new_pose_name: String::new(),
            files: file_dialog::FileDialogs::from_env(),
            new_mesh_dialog: None,
            slider_gesture: None,
            show_item_panel: false,
            show_outliner: true,
            show_properties: true,
            show_shortcuts: false,
            drop_focus: false,
            pose_prompt: None,
            influence_before_h_drag: None,
            effects: Vec::new(),
            autorig_dialog: None,
            selected_key: None,
            key_drag: None,
            show_timings: true,
            gpu,
            frame_ms: 0.0,
            last_frame: None,
            next_gesture: 1,
            mesh_upload: viewport_paint::MeshUploadCache::default(),
            ghosts: viewport_paint::GhostCache::default(),
            look_upload: viewport_paint::LookUploadCache::default(),
        }
    }

    /// A new gesture id.
    pub fn new_gesture(&mut self) -> GestureId {
        self.next_gesture += 1;
        GestureId(self.next_gesture)
    }

    /// Drops input in progress whose gesture the state no longer has (it was cancelled by an
    /// undo, or the document was replaced).
    fn revalidate(&mut self, state: &EditorState) {
        let live = state.gesture_id();
        // A loop cut is placed on a cage of Rig mode; another mode or a cage gone ends it.
        if self.loop_cut.as_ref().is_some_and(|cut| {
            state.mode != crate::state::EditMode::Rig
                || state.doc.scene.cages.leaf_index(&cut.cage).is_none()
        }) {
            self.loop_cut = None;
        }
        // So is an inset; an undo may also have taken its faces away.
        if self.inset.as_ref().is_some_and(|inset| {
            state.mode != crate::state::EditMode::Rig || !inset.is_valid_for(state)
        }) {
            self.inset = None;
        }
        if self.tool.as_ref().is_some_and(|t| Some(t.gesture) != live) {
            self.tool = None;
        }
        if let Some(Drag::Move { gesture, .. }) = &self.drag
            && Some(*gesture) != live
        {
            self.drag = None;
        }
        if self.slider_gesture.is_some_and(|g| Some(g) != live) {
            self.slider_gesture = None;
        }
    }
}

/// One frame of the whole window: reads `state`, sends commands to `sender`.
pub fn frame_ui(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    let now = Instant::now();
    if let Some(last) = ui_state.last_frame.replace(now) {
        ui_state.frame_ms = (now - last).as_secs_f64() * 1e3;
    }
    ui_state.revalidate(state);
    let ctx = ui.ctx().clone();
    dropped_files(&ctx, sender);
    keyboard::shortcuts(state, ui_state, &ctx, sender);
    for effect in std::mem::take(&mut ui_state.effects) {
        match effect {
            // Extrude continues as G along the face's normal, as in Blender.
            crate::commands::Effect::GrabAlong(axis) => {
                let pointer = ctx
                    .input(|i| i.pointer.latest_pos())
                    .map_or(state.view.viewport.center(), |p| glam::Vec2::new(p.x, p.y));
                actions::grab_along(state, ui_state, pointer, axis, sender);
            }
        }
    }
    Panel::top("menu").show(ui, |ui| menu::menu_bar(state, ui_state, ui, sender));
    Panel::bottom("status").show(ui, |ui| status_bar::status_bar(state, ui_state, ui, sender));
    let layout = SidePanels::for_width(
        ui.max_rect().width(),
        ui_state.show_outliner,
        ui_state.show_properties,
    );
    if let Some(max) = layout.outliner {
        Panel::left("outliner")
            .default_size(220.0_f32.min(max))
            .max_size(max)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| outliner::outliner(state, ui, sender));
            });
    }
    let Some(properties_max) = layout.properties else {
        return frame_rest(state, ui_state, ui, sender, &ctx);
    };
    Panel::right("inspector")
        .default_size(280.0_f32.min(properties_max))
        .max_size(properties_max)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                if ui_state.show_item_panel {
                    item_panel::item_panel(state, ui_state, ui, sender);
                }
                inspector::inspector(state, ui_state, ui, sender);
                panels::view_options(state, ui, sender);
                panels::stats(state, ui_state, ui);
                panels::poses(state, ui_state, ui, sender);
            });
        });
    frame_rest(state, ui_state, ui, sender, &ctx);
}

/// Which side panels show at a window width, and how wide each may grow: the outliner up to a
/// fifth of the window and the properties up to three tenths, so that the viewport keeps at
/// least half; a panel that would be narrower than it can be read collapses instead (the
/// outliner first).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SidePanels {
    /// The outliner's greatest width, or `None` when hidden.
    pub outliner: Option<f32>,
    /// The properties panel's greatest width, or `None` when hidden.
    pub properties: Option<f32>,
}

impl SidePanels {
    /// The narrowest outliner worth showing, in points.
    const OUTLINER_MIN: f32 = 150.0;
    /// The narrowest properties panel worth showing, in points.
    const PROPERTIES_MIN: f32 = 200.0;

    /// The panels for a window `width` points wide, each where wanted.
    pub fn for_width(width: f32, outliner: bool, properties: bool) -> Self {
        let (outliner_max, properties_max) = (0.2 * width, 0.3 * width);
        Self {
            outliner: (outliner && outliner_max >= Self::OUTLINER_MIN).then_some(outliner_max),
            properties: (properties && properties_max >= Self::PROPERTIES_MIN)
                .then_some(properties_max),
        }
    }
}

/// The rest of the frame after the side panels: the timeline, the viewport and the dialogs.
fn frame_rest(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
    ctx: &egui::Context,
) {
    let ctx = ctx.clone();
    // Under the viewport only, between the side panels (as Blender's timeline).
    Panel::bottom("timeline").show(ui, |ui| timeline::timeline(state, ui_state, ui, sender));
    egui::CentralPanel::default()
        .frame(egui::Frame::NONE)
        .show(ui, |ui| {
            viewport_input::viewport(state, ui_state, ui, sender)
        });
    prompts::unsaved_prompt(state, ui_state, &ctx, sender);
    if let Some((purpose, path)) = ui_state.files.poll(&ctx) {
        actions::file_chosen(purpose, path, ui_state, sender);
    }
    prompts::new_mesh_dialog(ui_state, &ctx, sender);
    prompts::autorig_dialog(ui_state, &ctx, sender);
    help::shortcuts_window(ui_state, &ctx);
    panels::pose_prompt(state, ui_state, &ctx, sender);
    add_menu::popup(state, ui_state, &ctx, sender);
}

fn dropped_files(ctx: &egui::Context, sender: &mut CommandSender) {
    let dropped = ctx.input(|i| i.raw.dropped_files.clone());
    if let Some(path) = dropped
        .iter()
        .map(|f| f.path().to_path_buf())
        .find(|p| !p.as_os_str().is_empty())
    {
        sender.send(Command::Open(path));
    }
}

#[cfg(test)]
mod tests {
    use super::SidePanels;

    #[test]
    fn side_panels_leave_half_the_width_and_collapse_the_outliner_first() {
        let wide = SidePanels::for_width(1400.0, true, true);
        assert_eq!(wide.outliner, Some(280.0));
        assert!(wide.properties.is_some_and(|w| (w - 420.0).abs() < 1e-3));
        let middle = SidePanels::for_width(700.0, true, true);
        assert_eq!(middle.outliner, None, "a 140-point outliner collapses");
        assert!(middle.properties.is_some_and(|w| (w - 210.0).abs() < 1e-3));
        let small = SidePanels::for_width(640.0, true, true);
        assert_eq!((small.outliner, small.properties), (None, None));
        let unwanted = SidePanels::for_width(1400.0, false, true);
        assert_eq!(unwanted.outliner, None);
        for width in [300.0, 640.0, 900.0, 1280.0, 3000.0] {
            let panels = SidePanels::for_width(width, true, true);
            let taken = panels.outliner.unwrap_or(0.0) + panels.properties.unwrap_or(0.0);
            assert!(taken <= 0.5 * width, "{width}");
        }
    }
}
