//! The StarCages editor: an egui/eframe app over the core (scene, binding, hierarchy) and the
//! viewport (rendering through an egui-wgpu paint callback). A library so tests can drive the
//! real app with egui_kittest; the binary `starcages` is a thin `main`.
//!
//! * [`app`]: state and operations (open, save, bind in the background, edits, undo).
//! * `interaction`: viewport mouse and keys, the G / R / S tool.
//! * `panels`: menu, outliner, inspector, view options, stats, poses, status bar, prompts.
//! * `viewport`: the paint callback.

pub mod app;
pub mod document;
pub mod interaction;
mod jobs;
mod mirror;
pub mod panels;
pub mod recent;
pub mod undo;
mod viewport;

pub use app::EditorApp;
pub use document::Document;

/// Builds the app inside eframe: installs the viewport's GPU resources when wgpu is there.
pub fn create(cc: &eframe::CreationContext<'_>, doc: Document) -> EditorApp {
    let gpu = cc.wgpu_render_state.as_ref().is_some_and(viewport::install);
    EditorApp::new(doc, Some(cc.egui_ctx.clone()), gpu)
}
