//! The editor's tests, one binary: the real app driven with egui_kittest on the software Vulkan
//! driver (`app`), regressions of defects found by trying it (`regressions`), and a
//! model-based test driving the state through long random command sequences (`model`).
#![allow(clippy::unwrap_used)]

mod app;
mod common;
mod layering;
mod model;
mod regressions;
mod timeline;
