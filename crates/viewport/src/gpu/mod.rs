//! Everything that touches wgpu: the device, the WGSL shaders, the scene renderer and GPU
//! deformation.

mod context;
pub mod deform;
pub mod renderer;
pub mod shaders;
mod target;

pub use context::{GpuContext, GpuError, OFFSCREEN_FORMAT};
pub use deform::{GpuDeformer, cpu_normals};
pub use renderer::{Layers, SceneRenderer};
pub use target::{Blit, ViewTarget};
