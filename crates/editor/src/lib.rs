//! The StarCages editor: an egui/eframe app over the core (scene, binding, hierarchy) and the
//! viewport (rendering through an egui-wgpu paint callback). A library so tests can drive the
//! real app with egui_kittest; the binary `starcages` is a thin `main`.
//!
//! Dependencies point one way: [`state`] (no egui types) ← [`commands`] (what a user can do,
//! and the one [`commands::apply`]) ← [`ui`] (reads the state, sends commands) ← [`app`]
//! (runs a frame: poll jobs, draw, apply).

pub mod app;
pub mod commands;
pub mod launch;
pub mod state;
pub mod ui;

pub use app::EditorApp;
pub use commands::{Command, UiCommand};
pub use state::{CageId, Document, EditorState, Pending};

/// Builds the app inside eframe: installs the viewport's GPU resources when wgpu is there.
pub fn create(cc: &eframe::CreationContext<'_>, doc: Document) -> EditorApp {
    let gpu = cc
        .wgpu_render_state
        .as_ref()
        .is_some_and(ui::viewport_paint::install);
    EditorApp::new(doc, Some(cc.egui_ctx.clone()), gpu)
}
