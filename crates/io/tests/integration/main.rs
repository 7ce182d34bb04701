//! The io crate's integration tests in one binary: every reader against specifications and
//! forged files, every writer read back (by our readers and the `gltf` crate), scene files and
//! point caches.
#![allow(clippy::unwrap_used)]

mod fbx;
mod fuzz_readers;
mod gltf_buffers;
mod gltf_files;
mod hostile_files;
mod mesh_formats;
mod point_caches;
mod scene_files;
mod written_files;
