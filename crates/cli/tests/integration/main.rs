//! End-to-end tests of `starcages-cli` in one binary: scenes, weights, deform and eval,
//! render.
#![allow(clippy::unwrap_used)]

mod animation;
mod common;
mod deform;
mod hostile;
mod outputs;
mod render;
mod scenes;
mod weights;
