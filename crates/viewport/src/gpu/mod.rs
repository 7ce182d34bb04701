//! Everything that touches wgpu: the device, the WGSL shaders, the scene renderer and GPU
//! deformation.

mod bindings;
mod context;
pub mod deform;
pub mod ghosts;
pub mod look;
pub mod renderer;
pub mod shaders;
mod target;

pub use context::{GpuContext, GpuError, OFFSCREEN_FORMAT};
pub use deform::{DeformTarget, GpuDeformer, cpu_normals};
pub use ghosts::{Ghost, GhostShape, MAX_GHOSTS};
pub use look::{LookError, LookMaterial, RenderLook};
pub use renderer::{Layers, SceneRenderer, Shading};
pub use target::{Blit, ViewTarget};
