//! StarCages viewport: the wgpu renderer of meshes, cages and influence maps, GPU deformation
//! and offscreen images.
//!
//! Not built yet: this crate arrives with the viewport issue. It exists so that the workspace
//! has its final shape and the dependency direction (viewport → core) is fixed from the start.

/// Name of the crate, for diagnostics until the renderer lands.
pub const CRATE_NAME: &str = "starcages-viewport";
