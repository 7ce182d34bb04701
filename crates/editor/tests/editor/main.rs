//! The editor's tests, one binary: the real app driven with egui_kittest on the software Vulkan
//! driver, by feature (`app`: picking, dragging, undo, files, binds, poses, views and prompts;
//! `rig_mode`: Rig mode's operations and selections; `auto_rig`: new meshes and the auto rig;
//! `timeline`: keys and playback; `drag`: internal-cage drags; `layering`: the crate's layers),
//! regressions of defects found by trying it (`regressions`), and a model-based test driving the
//! state through long random command sequences (`model`), over the helpers of `common`.
#![allow(clippy::unwrap_used)]

mod app;
mod auto_rig;
mod binding;
mod common;
mod drag;
mod files;
mod layering;
mod model;
mod regressions;
mod rig_mode;
mod rig_tools;
mod shading;
mod timeline;
